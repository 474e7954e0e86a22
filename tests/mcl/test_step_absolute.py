"""MC_StepAbsolute and the absolute measuring system (:class:`mcl.AbsoluteEncoder`).

The sensor on its own (word, wrap, Gray code, known at power-on); the block on a pure-Python
simulated axis (Done in the cycle it starts, Ref, no motion, the coordinate = the sensor's
reading + Offset; the refusals: no absolute sensor, NaN Offset, Disabled, ErrorStop, Stopping,
a moving axis with Aborting); and from the physics of the MuJoCo gantry: after power-on at an
arbitrary joint position, and after a power cycle, the coordinate equals the joint coordinate
[mm] within one count.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from typing import Any

import pytest

import mcl
import scenes
from mcl import AbsoluteEncoder, AxisState, ErrorID
from mcl import faults as flt
from scenes.machines import gantry
from scenes.machines.press import RAM_SSI
from scenes.scene import Scene
from tests.helpers import make_machine, tick

COUNT = 0.001
"""One incremental count of the simulated axis and of the gantry [mm]."""
SSI = AbsoluteEncoder.ssi(resolution=1.0e-6, bits=24, offset=0.0)
"""An SSI linear transducer: 1 µm, 24 bit binary, zero at the physical zero."""
START = 0.3023417
"""The simulated axis' start (physical, off the 1 µm grid) [m]."""


def absolute_axis(
    absolute: AbsoluteEncoder | None = SSI, start: float = START
) -> tuple[mcl.SimMachine, mcl.Axis]:
    """The powered, unreferenced axis X at ``start`` with the absolute sensor ``absolute``."""
    sensors = replace(mcl.IDEAL_SENSORS, absolute=absolute)
    machine = make_machine({"X": mcl.SimAxisParams(start=start, sensors=sensors)}, referenced=False)
    X = machine.axes["X"]
    assert X.state == AxisState.StandStill and not X.Ref
    return machine, X


def run_block(machine: mcl.SimMachine, fb: Any, cycles: int = 50, **inputs: Any) -> int:
    """Call ``fb`` with Execute=TRUE every scan until Done or Error; the scans it took."""
    X = machine.axes["X"]
    for n in range(1, cycles + 1):
        fb(Axis=X, Execute=True, **inputs)
        if fb.Done or fb.Error:
            return n
        tick(machine)
    raise AssertionError(f"{type(fb).__name__} neither Done nor Error in {cycles} scans")


def move_done(machine: mcl.Machine, X: mcl.Axis, move: Any, **inputs: float) -> None:
    """The move block ``move`` with ``inputs`` reaches its target within 5 s."""
    machine.run(
        lambda: move(Axis=X, Execute=True, **inputs),
        until=lambda: move.Done or move.Error,
        timeout=5.0,
    )
    assert move.Done


# ---------------------------------------------------------------------- the sensor
def test_ssi_word_is_the_position_in_counts_and_wraps_after_its_word_length() -> None:
    enc = AbsoluteEncoder.ssi(resolution=5.0e-6, bits=25, offset=-0.1)
    assert enc.span == pytest.approx(5.0e-6 * 2**25)
    assert enc.word(-0.1) == 0
    assert enc.word(0.2500037) == math.floor((0.2500037 + 0.1) / 5.0e-6)
    assert enc.position(enc.word(0.2500037)) == pytest.approx(0.2500037, abs=5.0e-6)
    assert enc.word(-0.1 + enc.span + 1.0e-5) == 2  # past the word length it starts again
    assert enc.word(-0.1 - 5.0e-6) == 2**25 - 1


def test_gray_coded_word_decodes_to_the_binary_count() -> None:
    gray = AbsoluteEncoder.ssi(resolution=1.0e-6, bits=24, gray=True)
    binary = AbsoluteEncoder.ssi(resolution=1.0e-6, bits=24)
    for x in (0.0, 1.0e-6, 0.123456, 16.7):
        assert gray.count(gray.word(x)) == binary.word(x)
        assert gray.position(gray.word(x)) == binary.position(binary.word(x))
    words = [gray.word(k * 1.0e-6) for k in range(64)]
    assert all(bin(a ^ b).count("1") == 1 for a, b in itertools.pairwise(words))


def test_multi_turn_rotary_encoder_counts_17_bits_per_turn_and_4096_turns() -> None:
    enc = AbsoluteEncoder.rotary(travel_per_rev=0.02, single_turn=17, multi_turn=12)
    assert enc.bits == 29
    assert enc.resolution == pytest.approx(0.02 / 131072)
    assert enc.span == pytest.approx(0.02 * 4096)
    assert enc.word(0.02 * 3 + 0.005) == 3 * 131072 + 131072 // 4


def test_bad_sensor_settings_are_refused() -> None:
    bad: dict[str, Any]
    for bad in ({"resolution": 0.0}, {"resolution": math.nan}, {"bits": 0}, {"offset": math.inf}):
        with pytest.raises(ValueError, match="AbsoluteEncoder"):
            kwargs: dict[str, Any] = {"resolution": 1.0e-6, **bad}
            AbsoluteEncoder(**kwargs)


def test_the_absolute_reading_is_known_at_power_on_unlike_the_incremental_counter() -> None:
    machine, _ = absolute_axis()
    io = machine.axes["X"].io
    assert io.counts == 0  # the incremental counter starts at 0 where the axis stands
    reading = io.absolute_position()
    assert reading is not None
    assert reading == pytest.approx(START, abs=1.0e-6) and reading <= START


def test_channel_snapshot_restores_the_reading_and_its_frame_state() -> None:
    channel = mcl.AxisChannel("A", 1.0e-6, 1000, sensors=replace(mcl.IDEAL_SENSORS, absolute=SSI))
    channel.sample(0.001, 0.1, 0.1, 0.1, 0.1)
    snap = channel.snapshot()
    channel.set_fault(flt.AbsoluteFrameError())
    channel.sample(0.002, 0.2, 0.2, 0.2, 0.2)
    assert channel.absolute_position() is None
    channel.restore(snap)
    assert channel.absolute_ok
    assert channel.absolute_position() == pytest.approx(0.1, abs=1.0e-6)


# ---------------------------------------------------------------------- the block
def test_step_absolute_sets_the_coordinate_from_the_sensor_ref_standstill_no_motion() -> None:
    machine, X = absolute_axis()
    x0 = machine.sims["X"].x
    fb = mcl.MC_StepAbsolute()
    scans = run_block(machine, fb)
    assert scans <= 2, "no search: the step ends in the cycle it starts, or the next"
    assert fb.Done and not fb.Error and not fb.Busy and not fb.CommandAborted
    tick(machine, 50)
    assert X.state == AxisState.StandStill and X.Ref and X.AxErrorID == 0
    assert machine.sims["X"].x == pytest.approx(x0, abs=2.0e-6), "the axis moved"
    joint_mm = machine.sims["X"].x * 1000.0
    assert pytest.approx(joint_mm, abs=2 * COUNT) == X.POS
    fb(Axis=X, Execute=False)
    assert not (fb.Done or fb.Busy or fb.Error), "outputs fall with Execute"


def test_offset_shifts_the_coordinate() -> None:
    machine, X = absolute_axis()
    fb = mcl.MC_StepAbsolute()
    run_block(machine, fb, Offset=-250.0)
    assert fb.Done
    assert pytest.approx(machine.sims["X"].x * 1000.0 - 250.0, abs=2 * COUNT) == X.POS


def test_sensor_offset_is_the_physical_zero_of_the_reading() -> None:
    """An SSI transducer mounted with its zero 0.1 m below the physical zero: the reading is
    the position again (offset + count · resolution)."""
    machine, X = absolute_axis(AbsoluteEncoder.ssi(resolution=5.0e-6, bits=25, offset=-0.1))
    fb = mcl.MC_StepAbsolute()
    run_block(machine, fb)
    assert fb.Done
    assert pytest.approx(machine.sims["X"].x * 1000.0, abs=0.005 + COUNT) == X.POS


def test_homing_again_gives_the_same_coordinate_after_a_move() -> None:
    """Homed, moved 37.5 mm, homed again: the coordinate does not jump (the sensor and the
    coordinate agree)."""
    machine, X = absolute_axis()
    run_block(machine, mcl.MC_StepAbsolute())
    move_done(machine, X, mcl.MC_MoveRelative(), Distance=37.5, Velocity=50.0)
    tick(machine, 50)
    before = X.POS
    fb = mcl.MC_StepAbsolute()
    run_block(machine, fb)
    assert fb.Done and X.Ref
    assert pytest.approx(before, abs=2 * COUNT) == X.POS
    assert pytest.approx(machine.sims["X"].x * 1000.0, abs=2 * COUNT) == X.POS


def test_no_absolute_sensor_is_an_error_and_leaves_the_axis_alone() -> None:
    machine, X = absolute_axis(None)
    pos, state = X.POS, X.state
    fb = mcl.MC_StepAbsolute()
    fb(Axis=X, Execute=True)
    assert fb.Error and fb.ErrorID == ErrorID.ENoAbsolute == 21 and not fb.Busy
    assert mcl.error_text(fb.ErrorID) == "axis has no absolute encoder"
    tick(machine, 20)
    assert pytest.approx(pos, abs=COUNT) == X.POS and X.state == state and not X.Ref
    assert X.AxErrorID == 0


def assert_refused(X: mcl.Axis, error: ErrorID, **inputs: float) -> None:
    """MC_StepAbsolute (Execute with ``inputs``) reports ``error``; the axis stays unreferenced."""
    fb = mcl.MC_StepAbsolute()
    fb(Axis=X, Execute=True, **inputs)
    assert fb.Error and fb.ErrorID == error and not X.Ref


@pytest.mark.parametrize("offset", [math.nan, math.inf, -math.inf])
def test_offset_not_finite_is_eparam(offset: float) -> None:
    _, X = absolute_axis()
    assert_refused(X, ErrorID.EParam, Offset=offset)


def test_refused_when_disabled() -> None:
    machine, X = absolute_axis()
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=X, Enable=False), timeout=0.01)
    assert_refused(X, ErrorID.Epower)


def test_refused_in_errorstop_and_stopping() -> None:
    machine, X = absolute_axis()
    stop = mcl.MC_Stop()
    machine.run(lambda: stop(Axis=X, Execute=True, Deceleration=100.0), timeout=0.05)
    assert X.state == AxisState.Stopping
    assert_refused(X, ErrorID.EAxStop)
    machine.run(lambda: stop(Axis=X, Execute=False), timeout=0.05)
    X.fault(ErrorID.ERRPOS)
    tick(machine, 5)
    assert X.state == AxisState.ErrorStop
    assert_refused(X, ErrorID.Eerrstop)


def test_aborting_a_moving_axis_is_refused() -> None:
    machine, X = absolute_axis()
    move = mcl.MC_MoveVelocity()
    machine.run(lambda: move(Axis=X, Execute=True, Velocity=20.0), timeout=0.3)
    assert X.moving
    assert_refused(X, ErrorID.EParam)


# ---------------------------------------------------------------------- from the physics
LEADS = {"X": 0.020, "Y": 0.020, "Z": 0.010}
"""The gantry's ball-screw leads [m] (models/gantry.xml)."""


def absolute_gantry(start: dict[str, float]) -> Scene:
    """The MuJoCo gantry with a 17-bit × 12-bit multi-turn absolute encoder on each motor, its
    zero 1 m below the joint zero (the travel lies inside the 4096 turns), other sensors
    default (noisy incremental encoder, real switches)."""
    axes = {
        name: replace(
            axis,
            sensors=replace(
                axis.sensors or mcl.Sensors(),
                absolute=AbsoluteEncoder.rotary(LEADS[name], 17, 12, offset=-1.0),
            ),
        )
        for name, axis in gantry.MACHINE.axes.items()
    }
    return Scene([replace(gantry.MACHINE, axes=axes)], start=start, trace_every=0)


def home_absolute(scene: Scene) -> dict[str, mcl.MC_StepAbsolute]:
    """Power every axis, then MC_StepAbsolute on each; Done within 0.1 s."""
    powers = {name: mcl.MC_Power() for name in scene.axes}
    steps = {name: mcl.MC_StepAbsolute() for name in scene.axes}

    def program() -> None:
        for name, axis in scene.axes.items():
            powers[name](Axis=axis, Enable=True)
            steps[name](Axis=axis, Execute=powers[name].Status)

    scene.run(program, until=lambda: all(s.Done or s.Error for s in steps.values()), timeout=1.0)
    scene.run(program, timeout=0.1)
    for name, step in steps.items():
        assert step.Done and not step.Error, (name, step.ErrorID)
    return steps


def joint_mm(scene: Scene, name: str) -> float:
    """The joint coordinate of axis ``name`` now [mm]."""
    return float(scene.data.qpos[scene.io(name).qpos_adr]) * 1000.0


def assert_coordinate_is_the_joint(scene: Scene) -> None:
    """Each axis' actual position [mm] = its joint coordinate within one count (the absolute
    encoder's 0.15 µm on X/Y plus the incremental encoder's 1 µm and its noise)."""
    for name, axis in scene.axes.items():
        assert axis.Ref and axis.state == AxisState.StandStill, name
        error = axis.actual - joint_mm(scene, name)
        assert abs(error) <= COUNT + LEADS[name] * 1000.0 / 2**17 + 1e-9, (name, error)


START_GANTRY = {"X": 0.4137211, "Y": 0.2218563, "Z": -0.0871937}


def test_gantry_coordinate_after_power_on_is_the_joint_coordinate() -> None:
    scene = absolute_gantry(START_GANTRY)
    home_absolute(scene)
    assert_coordinate_is_the_joint(scene)
    for name, start in START_GANTRY.items():
        assert joint_mm(scene, name) == pytest.approx(start * 1000.0, abs=0.01), "it moved"


def test_gantry_after_a_power_cycle_the_same_point_gets_the_same_coordinate() -> None:
    """Homed, moved, switched off; a new scene (the module powered up again: the incremental
    counters start at 0) at the joint positions the axes stood at: the same coordinates."""
    scene = absolute_gantry(START_GANTRY)
    home_absolute(scene)
    X = scene.axes["X"]
    move_done(scene, X, mcl.MC_MoveAbsolute(), Position=512.25, Velocity=100.0)
    scene.run(timeout=0.2)
    assert_coordinate_is_the_joint(scene)
    before = {name: axis.actual for name, axis in scene.axes.items()}
    joints = {name: joint_mm(scene, name) / 1000.0 for name in scene.axes}
    again = absolute_gantry(joints)
    assert all(axis.io.counts == 0 for axis in again.axes.values())
    home_absolute(again)
    assert_coordinate_is_the_joint(again)
    for name, axis in again.axes.items():
        assert axis.actual == pytest.approx(before[name], abs=2 * COUNT), name


# ---------------------------------------------------------------------- the press' SSI transducer
PRESS_COUNT = 0.005
"""One count of the ram's incremental encoder and of its SSI transducer [mm]."""
PRESS_TOL = 2 * PRESS_COUNT + 1e-9
"""How far the ram's coordinate may lie from its joint coordinate once homed [mm]: one count
of the transducer (the reading is truncated) and one of the incremental encoder, whose grid
starts where the ram stood at power-up, not on the transducer's."""


def press(q: float) -> scenes.Scene:
    """The MuJoCo press, the ram at joint coordinate ``q`` [m] at power-up."""
    return scenes.load("press", start={"R": q}, trace_every=0)


def step_ram(scene: scenes.Scene, settle: float = 0.1) -> mcl.MC_StepAbsolute:
    """Power the ram, then MC_StepAbsolute once powered; until Done or Error, ``settle`` more."""
    R = scene.axes["R"]
    power, step = mcl.MC_Power(), mcl.MC_StepAbsolute()

    def program() -> None:
        power(Axis=R, Enable=True)
        step(Axis=R, Execute=power.Status)

    scene.run(program, until=lambda: step.Done or step.Error, timeout=1.0)
    scene.run(program, timeout=settle)
    return step


def ram_mm(scene: scenes.Scene) -> float:
    return joint_mm(scene, "R")


def test_press_ram_carries_a_gray_coded_ssi_transducer() -> None:
    scene = press(0.1234567)
    io = scene.io("R")
    assert io.absolute == RAM_SSI and RAM_SSI.gray and RAM_SSI.bits == 24
    assert io.counts == 0
    reading = io.absolute_position()
    assert reading is not None and abs(reading - 0.1234567) <= 5.0e-6


@pytest.mark.parametrize("q", [0.0423171, 0.1876543])
def test_press_coordinate_after_power_on_is_the_joint_coordinate(q: float) -> None:
    scene = press(q)
    step = step_ram(scene)
    R = scene.axes["R"]
    assert step.Done and R.Ref and R.state == AxisState.StandStill
    error = R.actual - ram_mm(scene)
    assert abs(error) <= PRESS_TOL, error


def test_press_after_a_power_cycle_the_same_point_gets_the_same_coordinate() -> None:
    scene = press(0.0617283)
    step_ram(scene)
    R = scene.axes["R"]
    before, q = R.actual, ram_mm(scene) / 1000.0
    again = press(q)
    step_ram(again)
    assert again.axes["R"].actual == pytest.approx(before, abs=2 * PRESS_COUNT)
    assert abs(again.axes["R"].actual - ram_mm(again)) <= PRESS_TOL


def test_press_frame_error_is_reported_not_used() -> None:
    """A corrupted SSI frame (parity/CRC bad): MC_StepAbsolute refuses with EAbsFrame 22, the
    coordinate stays the incremental one (0 at power-up) and Ref unset; once the line is clean
    again the step homes the ram."""
    scene = press(0.0917)
    R = scene.axes["R"]
    scene.faults.set("R", flt.AbsoluteFrameError())
    scene.run(timeout=0.01)
    assert scene.io("R").absolute_position() is None and not scene.io("R").absolute_ok
    step = step_ram(scene)
    assert step.Error and step.ErrorID == ErrorID.EAbsFrame == 22 and not R.Ref
    assert abs(R.actual) < 0.1, "the coordinate was not touched"
    scene.faults.clear("R", flt.AbsoluteFrameError())
    step = step_ram(scene)
    assert step.Done and R.Ref
    assert abs(R.actual - ram_mm(scene)) <= PRESS_TOL


# ---------------------------------------------------------------------- buffered after a search
def searching_axis() -> tuple[mcl.SimMachine, mcl.Axis]:
    """The simulated axis of tests/mcl/test_homing_sim.py (REF 203.5 … 253.7 mm, start 302.3 mm)
    with the SSI transducer."""
    from tests.mcl.test_homing_sim import LAYOUT

    layout: dict[str, Any] = {**LAYOUT, "sensors": replace(mcl.IDEAL_SENSORS, absolute=SSI)}
    machine = make_machine({"X": mcl.SimAxisParams(**layout)}, referenced=False)
    return machine, machine.axes["X"]


SEARCH = {
    "Direction": mcl.MC_Direction.MC_Negative,
    "Velocity": 20.0,
    "SwitchMode": mcl.MC_SwitchMode.MC_EdgeOn,
}


def test_buffered_after_a_search_reads_the_sensor_where_the_search_left_the_axis() -> None:
    machine, X = searching_axis()
    search, step = mcl.MC_StepAbsSwitch(), mcl.MC_StepAbsolute()
    buffered = mcl.MC_BufferMode.Buffered

    def program() -> None:
        search(Axis=X, Execute=True, **SEARCH)
        step(Axis=X, Execute=True, BufferMode=buffered)

    machine.run(program, until=lambda: step.Done or step.Error or search.Error, timeout=30.0)
    assert search.Done and step.Done and not step.Error
    machine.run(program, timeout=0.3)
    x = machine.sims["X"].x
    assert x < 0.2537 + 1e-3, "the search went to the REF switch"
    assert X.Ref and X.state == AxisState.StandStill
    assert pytest.approx(x * 1000.0, abs=2 * COUNT) == X.POS


def test_buffered_step_is_aborted_with_the_search_by_mc_stop() -> None:
    machine, X = searching_axis()
    search, step, stop = mcl.MC_StepAbsSwitch(), mcl.MC_StepAbsolute(), mcl.MC_Stop()
    buffered = mcl.MC_BufferMode.Buffered
    state = {"stop": False}

    def program() -> None:
        search(Axis=X, Execute=True, **SEARCH)
        step(Axis=X, Execute=True, BufferMode=buffered)
        stop(Axis=X, Execute=state["stop"])

    machine.run(program, timeout=0.5)
    assert search.Busy and step.Busy and not step.Done
    state["stop"] = True
    machine.run(program, until=lambda: step.CommandAborted or step.Done, timeout=1.0)
    assert step.CommandAborted and not (step.Done or step.Busy or step.Error)
    assert search.CommandAborted
    assert not X.Ref

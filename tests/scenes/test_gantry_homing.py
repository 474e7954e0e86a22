"""Homing on the MuJoCo gantry, judged by where the physical axis ends up.

REF switch + index pulse on every axis from random starts, homing to block against the X hard
stop, the limit-switch search, a REF search started the wrong way, and the Time/Distance/Torque
limits of a search. The physical origin of the coordinate system is ``q − POS/1000`` (joint
coordinate [m] minus the axis position [mm]): a homing procedure is only useful if that point
is the same every time.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from typing import Any

import mujoco
import numpy as np
import pytest

import mcl
from mcl import AxisState, MC_BufferMode, MC_Direction, MC_SwitchMode
from scenes.machines import gantry
from scenes.machines.gantry.scenarios import homing_repeatability
from scenes.scene import Scene
from tests.helpers import reset, scan

PARK = {"X": 0.3, "Y": 0.3, "Z": -0.1}
"""Start positions of the axes a test does not move [m] (they stay disabled; Z on its brake)."""

RESOLUTION = 1e-6
"""Encoder count [m]."""


def build(**start: float) -> Scene:
    return gantry.build(start={**PARK, **start}, trace_every=0)


def numeric(scene: Scene, name: str) -> float:
    return float(scene.model.numeric(f"gantry/{name}").data[0])


def hard_stops(scene: Scene, axis: str) -> tuple[float, float]:
    lo, hi = scene.model.jnt_range[scene.io(axis).joint]
    return float(lo), float(hi)


def origin(scene: Scene, axis: str, set_position: float = 0.0) -> float:
    """Joint coordinate [m] at which the axis coordinate equals ``set_position`` [mm]."""
    return scene.joint_position(axis) - (scene.axes[axis].POS - set_position) / 1000.0


def amp_force(scene: Scene, axis: str) -> float:
    return float(scene.data.actuator_force[scene.io(axis).actuator])


def force_limit(scene: Scene, axis: str) -> float:
    return float(scene.model.actuator_forcerange[scene.io(axis).actuator][1])


class Recorder:
    """Observer: extremes of the joint coordinate and amplifier force, states seen, NaNs."""

    def __init__(self, scene: Scene, axis: str) -> None:
        self.scene, self.axis = scene, axis
        self.q_min = self.q_max = scene.joint_position(axis)
        self.peak_force = 0.0
        self.states: set[AxisState] = set()
        self.finite = True
        scene.runtime.observers.append(self)

    def __call__(self, t: float) -> None:
        q = self.scene.joint_position(self.axis)
        self.q_min, self.q_max = min(self.q_min, q), max(self.q_max, q)
        self.peak_force = max(self.peak_force, abs(amp_force(self.scene, self.axis)))
        self.states.add(self.scene.axes[self.axis].state)
        data = self.scene.data
        self.finite = self.finite and bool(all(math.isfinite(x) for x in (*data.qpos, *data.qvel)))


def move_by(scene: Scene, axis: str, distance: float, velocity: float = 50.0) -> None:
    """MC_MoveRelative by ``distance`` [mm] reaches its target physically (0.2 s to settle)."""
    ax = scene.axes[axis]
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()
    program = scan(
        lambda: power(Axis=ax, Enable=True),
        lambda: move(Axis=ax, Execute=True, Distance=distance, Velocity=velocity),
    )
    q0 = scene.joint_position(axis)
    scene.run(program, until=lambda: move.Done or move.Error, timeout=10)
    assert move.Done, (move.ErrorID, ax.AxErrorID)
    scene.run(program, timeout=0.2)
    assert scene.joint_position(axis) - q0 == pytest.approx(distance / 1000.0, abs=20e-6)
    assert ax.state == AxisState.StandStill and ax.AxErrorID == 0


def homing_program(
    ax: mcl.Axis, power: mcl.MC_Power, *steps: tuple[Any, dict[str, Any]]
) -> Callable[[], None]:
    """PLC program: MC_Power enabled, then each homing step (block, inputs) called with
    Execute = power.Status."""

    def program() -> None:
        power(Axis=ax, Enable=True)
        for fb, inputs in steps:
            fb(Axis=ax, Execute=power.Status, **inputs)

    return program


def home_ref_index(scene: Scene, axis: str) -> tuple[mcl.MC_StepAbsSwitch, mcl.MC_StepRefPulse]:
    """REF switch (approached from below, falling edge) then the next index pulse upwards;
    returns after 0.3 s of standstill with the power still on."""
    ax = scene.axes[axis]
    power, approach, pulse = mcl.MC_Power(), mcl.MC_StepAbsSwitch(), mcl.MC_StepRefPulse()
    program = homing_program(
        ax,
        power,
        (
            approach,
            dict(
                Direction=MC_Direction.MC_SwitchNegative,
                SwitchMode=MC_SwitchMode.MC_EdgeOff,
                Velocity=50.0,
            ),
        ),
        (
            pulse,
            dict(
                Direction=MC_Direction.MC_Positive,
                Velocity=10.0,
                SetPosition=0.0,
                BufferMode=MC_BufferMode.Buffered,
            ),
        ),
    )
    scene.run(program, until=lambda: pulse.Done or pulse.Error or approach.Error, timeout=60.0)
    scene.run(program, timeout=0.3)
    return approach, pulse


def ref_starts(scene: Scene, axis: str, seed: int) -> list[float]:
    """Two starts on the REF switch (below its edge), two beyond it, one on each limit switch
    next to a hard stop [m]."""
    rng = random.Random(seed)
    lo, hi = (float(x) for x in scene.model.numeric(f"gantry/{axis}_travel").data)
    edge = numeric(scene, f"{axis}_ref_edge")
    stop_lo, stop_hi = hard_stops(scene, axis)
    below = [rng.uniform(lo + 0.002, edge - 0.005) for _ in range(2)]
    above = [rng.uniform(edge + 0.005, hi - 0.002) for _ in range(2)]
    return [*below, *above, stop_lo + 0.002, stop_hi - 0.002]


@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_ref_and_index_homing_sets_the_same_physical_origin_from_any_start(axis):
    probe = build()
    starts = ref_starts(probe, axis, seed={"X": 11, "Y": 12, "Z": 13}[axis])
    edge = numeric(probe, f"{axis}_ref_edge")
    lead = numeric(probe, f"{axis}_lead")
    assert sum(s < edge for s in starts) >= 3 and sum(s > edge for s in starts) >= 3
    origins = []
    for start in starts:
        # ideal sensors: the same count every time (tests/scenes/test_sensors.py: real ones, ±1
        # count)
        scene = gantry.build(start={**PARK, axis: start}, trace_every=0, sensors=mcl.IDEAL_SENSORS)
        ax = scene.axes[axis]
        approach, pulse = home_ref_index(scene, axis)
        assert not approach.Error and not pulse.Error, (start, approach.ErrorID, pulse.ErrorID)
        assert ax.state == AxisState.StandStill, (start, ax.state)
        assert ax.Ref and ax.AxErrorID == 0
        v = scene.data.qvel[scene.io(axis).dof]
        assert abs(v) < 1e-4, f"start {start}: still moving at {v} m/s"
        origins.append(origin(scene, axis))
    spread = max(origins) - min(origins)
    assert spread <= RESOLUTION + 1e-9, f"{axis}: origins {origins} spread {spread * 1e6:.3f} µm"
    # the first index mark above the REF edge
    expected = math.ceil(edge / lead) * lead
    for o in origins:
        assert o == pytest.approx(expected, abs=2 * RESOLUTION)


BLOCK_STARTS = (0.05, 0.2, 0.4)

BUFFERED_DIRECT = {"SetPosition": 0.0, "BufferMode": MC_BufferMode.Buffered}
"""Inputs of the MC_StepDirect that ends a homing sequence at coordinate 0."""

REF_SEARCH_UP = {
    "Direction": MC_Direction.MC_Positive,
    "SwitchMode": MC_SwitchMode.MC_EdgeOn,
    "Velocity": 50.0,
}
"""Inputs of an MC_StepAbsSwitch that looks for the rising REF edge upwards."""


def home_to_block(start: float) -> tuple[Scene, Recorder, mcl.MC_StepBlock, mcl.MC_StepDirect]:
    """MC_StepBlock toward the negative hard stop, then a buffered MC_StepDirect (SetPosition 0)."""
    scene = build(X=start)
    X = scene.axes["X"]
    rec = Recorder(scene, "X")
    power, block, direct = mcl.MC_Power(), mcl.MC_StepBlock(), mcl.MC_StepDirect()
    program = homing_program(
        X,
        power,
        (block, dict(Direction=MC_Direction.MC_Negative, Velocity=20.0, TorqueLimit=1.5)),
        (direct, BUFFERED_DIRECT),
    )
    scene.run(program, until=lambda: direct.Done or block.Error or direct.Error, timeout=40)
    return scene, rec, block, direct


def test_homing_to_block_against_the_hard_stop_is_repeatable_and_uses_full_force():
    origins = []
    for start in BLOCK_STARTS:
        scene, rec, block, direct = home_to_block(start)
        X = scene.axes["X"]
        assert direct.Done, (block.ErrorID, direct.ErrorID, X.AxErrorID)
        assert X.state == AxisState.StandStill and X.Ref
        o = origin(scene, "X")
        origins.append(o)
        stop_lo, _ = hard_stops(scene, "X")
        assert o == pytest.approx(stop_lo, abs=1e-3), "the block is the negative hard stop"
        fmax = force_limit(scene, "X")
        assert rec.peak_force >= 0.99 * fmax, f"peak {rec.peak_force:.0f} N of {fmax:.0f} N"
        assert rec.peak_force <= fmax * (1 + 1e-9)
        assert AxisState.ErrorStop not in rec.states and X.AxErrorID == 0
        assert rec.finite

        # and then it moves away normally
        q0 = scene.joint_position("X")
        move_by(scene, "X", 50.0, velocity=100.0)
        assert pytest.approx(50.0 + (q0 - o) * 1000.0, abs=0.01) == X.POS
    spread = max(origins) - min(origins)
    assert spread <= 10e-6, f"block origins {origins}, spread {spread * 1e6:.2f} µm"


def test_limit_switch_search_ends_on_the_switch_edge_and_stays_homing():
    scene = build(X=0.05)
    X = scene.axes["X"]
    trip = numeric(scene, "X_lim_neg_trip")
    power, search, direct = mcl.MC_Power(), mcl.MC_StepLimitSwitch(), mcl.MC_StepDirect()
    execute_direct = [False]

    def program() -> None:
        power(Axis=X, Enable=True)
        search(
            Axis=X,
            Execute=power.Status,
            Direction=MC_Direction.MC_Negative,
            SwitchMode=MC_SwitchMode.MC_EdgeOn,
            Velocity=20.0,
        )
        direct(Axis=X, Execute=execute_direct[0], SetPosition=-5.0)

    scene.run(program, until=lambda: search.Done or search.Error, timeout=20)
    assert search.Done, (search.ErrorID, X.AxErrorID)
    scene.run(program, timeout=0.5)
    assert scene.joint_position("X") == pytest.approx(trip, abs=0.5e-3)
    assert X.state == AxisState.Homing and not X.Ref
    assert X.AxErrorID == 0

    execute_direct[0] = True
    scene.run(program, until=lambda: direct.Done or direct.Error, timeout=1)
    assert direct.Done, direct.ErrorID
    assert X.state == AxisState.StandStill and X.Ref
    assert origin(scene, "X", set_position=-5.0) == pytest.approx(trip, abs=0.5e-3)

    # standing on LIM− is no error; moving off it is allowed
    move_by(scene, "X", 20.0)


@pytest.mark.parametrize("velocity", [50.0, 150.0])
def test_ref_search_in_the_wrong_direction_reverses_at_the_limit_switch(velocity):
    """LIM+ turns the search round before the hard stop (5 mm behind the trip point). A plain
    move overrunning LIM+ at 200 mm/s stops 1.2 mm past it (test_gantry_supervision): a search
    that ignores LIM+ as an error must still not crash where a plain move would not."""
    scene = build(X=0.9)
    X = scene.axes["X"]
    rec = Recorder(scene, "X")
    edge = numeric(scene, "X_ref_edge")
    lim_pos = numeric(scene, "X_lim_pos_trip")
    _, stop_hi = hard_stops(scene, "X")
    power, approach, direct = mcl.MC_Power(), mcl.MC_StepAbsSwitch(), mcl.MC_StepDirect()
    search = {**REF_SEARCH_UP, "Velocity": velocity}
    program = homing_program(X, power, (approach, search), (direct, BUFFERED_DIRECT))
    scene.run(program, until=lambda: direct.Done or approach.Error or direct.Error, timeout=30)
    assert approach.Done or direct.Done, (approach.ErrorID, X.AxErrorID)
    assert direct.Done
    assert rec.q_max >= lim_pos, "the search met LIM+"
    assert rec.q_max < stop_hi, "and turned before the hard stop"
    assert AxisState.ErrorStop not in rec.states and X.AxErrorID == 0
    assert X.state == AxisState.StandStill and X.Ref
    assert scene.joint_position("X") == pytest.approx(edge, abs=0.5e-3)
    assert origin(scene, "X") == pytest.approx(edge, abs=0.5e-3)


def _search_with_limit(scene: Scene, **limit: float) -> tuple[mcl.MC_StepAbsSwitch, Recorder]:
    X = scene.axes["X"]
    rec = Recorder(scene, "X")
    power, approach = mcl.MC_Power(), mcl.MC_StepAbsSwitch()
    program = homing_program(X, power, (approach, {**REF_SEARCH_UP, **limit}))
    scene.run(program, until=lambda: approach.Error or approach.Done, timeout=20)
    scene.run(lambda: power(Axis=X, Enable=True), timeout=0.5)
    return approach, rec


def _reset_and_move(scene: Scene, distance: float) -> None:
    """MC_Reset brings the axis back to StandStill, and it moves again."""
    reset(scene, scene.axes["X"])
    move_by(scene, "X", distance)


def _search_stopped_by(error: mcl.ErrorID, code: int, **limit: float) -> tuple[Scene, Recorder]:
    """A REF search from X = 0.5 m upwards with ``limit`` ends in Error ``error`` and ErrorStop
    with AxErrorID ``code``."""
    scene = build(X=0.5)
    X = scene.axes["X"]
    approach, rec = _search_with_limit(scene, **limit)
    assert approach.Error and approach.ErrorID == error
    assert X.state == AxisState.ErrorStop and X.AxErrorID == code
    return scene, rec


def test_search_time_limit_gives_etime_and_errorstop_and_reset_recovers():
    scene, rec = _search_stopped_by(mcl.ErrorID.ETime, 1, TimeLimit=0.5)
    # stopped on a ramp with the loop closed: the drive is still enabled and holds
    assert scene.io("X").enabled
    assert abs(scene.data.qvel[scene.io("X").dof]) < 1e-4
    # 0.5 s at 50 mm/s plus the stop: roughly 25 mm
    assert rec.q_max - 0.5 == pytest.approx(0.025, abs=3e-3)
    _reset_and_move(scene, -10.0)


def test_search_distance_limit_gives_edistance():
    scene, rec = _search_stopped_by(mcl.ErrorID.EDistance, 2, DistanceLimit=20.0)
    travel = rec.q_max - 0.5
    assert 0.020 <= travel < 0.022, f"travelled {travel * 1e3:.3f} mm"
    assert abs(scene.data.qvel[scene.io("X").dof]) < 1e-4
    _reset_and_move(scene, -10.0)


def _blocked_search() -> tuple[Scene, mcl.MC_StepAbsSwitch, Recorder, float]:
    """A REF search (TorqueLimit 1 mm) runs into the obstacle placed in its way."""
    scene = build(X=0.2)
    m = scene.model
    q_b = 0.25
    blockpos = m.numeric("gantry/X_obstacle_blockpos").data
    m.body_pos[m.body("gantry/X_obstacle").id] = blockpos + np.array([q_b, 0.0, 0.0])
    mujoco.mj_forward(m, scene.data)
    approach, rec = _search_with_limit(scene, TorqueLimit=1.0)
    return scene, approach, rec, q_b


def test_search_torque_limit_on_an_obstacle_gives_edev_not_errpos():
    scene, approach, rec, q_b = _blocked_search()
    X = scene.axes["X"]
    assert approach.Error and approach.ErrorID == mcl.ErrorID.EDev, approach.ErrorID
    assert X.state == AxisState.ErrorStop and X.AxErrorID == 3
    assert rec.q_max < q_b + 1e-3, "the obstacle stopped the axis"
    assert rec.q_max > q_b - 1e-3, "the axis reached the obstacle"
    assert rec.finite
    assert rec.peak_force <= force_limit(scene, "X") * (1 + 1e-9)


def test_after_the_torque_limit_error_the_drive_stops_pushing_the_obstacle():
    """TorqueLimit is there to protect machine and obstacle: once it has tripped, the stopped
    axis must not be held against the obstacle with the amplifier's peak force."""
    scene, approach, _, _ = _blocked_search()  # 0.5 s in ErrorStop already
    assert approach.ErrorID == mcl.ErrorID.EDev
    fmax = force_limit(scene, "X")
    force = abs(amp_force(scene, "X"))
    assert force < 0.1 * fmax, f"still pushing with {force:.0f} N of {fmax:.0f} N"


def test_after_the_torque_limit_error_reset_lets_the_axis_back_off_the_obstacle():
    scene, approach, _, _ = _blocked_search()
    assert approach.ErrorID == mcl.ErrorID.EDev
    _reset_and_move(scene, -10.0)


def test_the_homing_scenario_finds_the_index_above_the_ref_edge():
    """The sweep scenario ``homing_repeatability`` reads the REF edge and the lead from the
    gantry's model: the homed origin lies on the first index above the edge (120 mm)."""
    metrics = homing_repeatability(seed=1)
    assert abs(metrics["origin_error_um"]) < 2.0
    assert metrics["ref_off_mm"] == pytest.approx(110.0, abs=0.1)  # the edge, X_ref_edge

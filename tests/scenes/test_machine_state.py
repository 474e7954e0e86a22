"""Saving and restoring a machine state: a homed machine comes back homed, where it was, and a
program run after a restore repeats the motion it made after the save, bit for bit.

Judged on the physics: MuJoCo joint coordinates and velocities, the press's oil pressures, the
simulated axes' positions, and the recorded traces.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import mcl
import scenes
from mcl import AxisState, MC_BufferMode, MC_Direction, MC_SwitchMode
from mcl.trace import Trace
from plc.procedures import HomeAxis
from scenes.machines import gantry
from scenes.machines.flying_shear.devices import CutRecorder
from scenes.machines.press.hydraulics import BAR
from scenes.scene import Scene
from tests.helpers import configure

START = {"X": 0.15, "Y": 0.3, "Z": -0.1}
"""Gantry start [m]: X a short way above its REF edge, so its homing takes about 2 s."""


def homed_gantry() -> tuple[Scene, mcl.MC_Power]:
    """The gantry with X powered and homed by its homing procedure (REF switch, index)."""
    scene = gantry.build(start=START)
    X = scene.axes["X"]
    power, home = mcl.MC_Power(Axis=X), HomeAxis(X, gantry.HOMING["X"])

    def program() -> None:
        power(Enable=True)
        home(Execute=power.Status)

    scene.run(program, until=lambda: bool(home.Done), timeout=30.0)
    assert X.Ref and X.state == AxisState.StandStill
    return scene, power


class Program:
    """A new PLC program after a restore: X to 260 mm and back by 70 mm blended, Y powered
    and moved by 30 mm meanwhile (its jerk-free start from rest)."""

    def __init__(self, scene: Scene) -> None:
        X, Y = scene.axes["X"], scene.axes["Y"]
        self.power_y = mcl.MC_Power(Axis=Y)
        self.to = mcl.MC_MoveAbsolute(Axis=X, Position=260.0, Velocity=400.0)
        self.back = mcl.MC_MoveRelative(
            Axis=X, Distance=-70.0, Velocity=200.0, BufferMode=MC_BufferMode.BlendingLow
        )
        self.move_y = mcl.MC_MoveRelative(Axis=Y, Distance=30.0, Velocity=100.0)

    def __call__(self) -> None:
        self.power_y(Enable=True)
        self.to(Execute=True)
        self.back(Execute=True)
        self.move_y(Execute=self.power_y.Status)

    def run(self, scene: Scene) -> dict[str, list[tuple[float, ...]]]:
        scene.run(self, until=lambda: bool(self.back.Done and self.move_y.Done), timeout=5.0)
        scene.run(self, timeout=0.1)
        return scene.trace.rows


def test_a_homed_gantry_comes_back_where_it_was_and_still_homed():
    scene, _ = homed_gantry()
    X = scene.axes["X"]
    state = scene.save_state()
    time, position = scene.time, X.POS
    qpos, qvel = scene.data.qpos.copy(), scene.data.qvel.copy()
    move = mcl.MC_MoveAbsolute(Axis=X, Position=300.0, Velocity=400.0)
    scene.run(lambda: move(Execute=True), until=lambda: bool(move.Done), timeout=5.0)
    assert scene.joint_position("X") == pytest.approx(0.300, abs=5e-5)

    scene.restore_state(state)
    assert scene.time == time and position == X.POS
    assert np.array_equal(scene.data.qpos, qpos) and np.array_equal(scene.data.qvel, qvel)
    assert X.Ref and X.state == AxisState.StandStill and X.AxErrorID == 0
    # still homed: an absolute move lands there on the joint (coordinate = joint in mm)
    again = mcl.MC_MoveAbsolute(Axis=X, Position=200.0, Velocity=400.0)
    scene.run(lambda: again(Execute=True), until=lambda: bool(again.Done), timeout=5.0)
    scene.run(lambda: again(Execute=True), timeout=0.2)
    assert scene.joint_position("X") == pytest.approx(0.200, abs=5e-5)


def test_a_program_after_a_restore_repeats_the_motion_after_the_save_bit_for_bit():
    scene, _ = homed_gantry()
    state = scene.save_state()
    scene.trace.clear()
    after_save = Program(scene).run(scene)
    scene.restore_state(state)
    assert all(rows == [] for rows in scene.trace.rows.values())  # the window starts anew
    first = Program(scene).run(scene)
    scene.restore_state(state)
    second = Program(scene).run(scene)
    assert len(after_save["X"]) > 500, "the program ran"
    assert first == after_save and second == after_save
    # a fresh scene of the same machine, built elsewhere on its travel, takes the state too
    other = gantry.build(start={"X": 0.5, "Y": 0.1, "Z": -0.1})
    other.restore_state(state)
    assert Program(other).run(other) == after_save


def test_restoring_in_the_middle_of_a_move_lets_go_of_the_old_program():
    scene, power = homed_gantry()
    X = scene.axes["X"]
    state = scene.save_state()
    move = mcl.MC_MoveAbsolute(Axis=X, Position=600.0, Velocity=300.0)
    scene.run(lambda: move(Execute=True), timeout=0.3)
    assert move.Busy and X.state == AxisState.DiscreteMotion
    scene.restore_state(state)
    scene.run(lambda: move(Execute=True), timeout=0.05)  # the old block's ticket is gone
    assert move.CommandAborted and not move.Busy
    assert X.state == AxisState.StandStill and X.Ref
    q = scene.joint_position("X")
    scene.run(timeout=0.2)
    assert scene.joint_position("X") == pytest.approx(q, abs=5e-6)  # held where it was saved
    power(Enable=False)  # the axis stays powered until a program switches it off
    assert X.state == AxisState.Disabled


def test_saving_while_an_axis_homes_or_moves_raises_and_says_which_and_what_to_do():
    scene = gantry.build(start=START, trace_every=0)
    X = scene.axes["X"]
    power, home = mcl.MC_Power(Axis=X), HomeAxis(X, gantry.HOMING["X"])

    def program() -> None:
        power(Enable=True)
        home(Execute=power.Status)

    scene.run(program, timeout=0.2)
    assert X.state == AxisState.Homing
    with pytest.raises(mcl.StateError, match=r"axis X is in Homing.*Stop it first"):
        scene.save_state()
    scene.run(program, until=lambda: bool(home.Done), timeout=30.0)
    move = mcl.MC_MoveRelative(Axis=X, Distance=50.0, Velocity=100.0)
    scene.run(lambda: move(Execute=True), timeout=0.1)
    with pytest.raises(mcl.StateError, match=r"axis X is in DiscreteMotion.*StandStill"):
        scene.save_state()
    scene.run(lambda: move(Execute=True), until=lambda: bool(move.Done), timeout=5.0)
    scene.save_state()  # at rest again


def test_a_press_state_is_refused_by_the_gantry_and_the_gantry_is_left_alone():
    press = scenes.load("press", trace_every=0)
    state = press.save_state()
    scene = gantry.build(start=START, trace_every=0)
    qpos, t = scene.data.qpos.copy(), scene.time
    with pytest.raises(mcl.StateError, match=r"saved from machine press.*into machine gantry"):
        scene.restore_state(state)
    assert np.array_equal(scene.data.qpos, qpos) and scene.time == t


def test_the_press_gets_its_oil_pressures_and_ram_position_back():
    scene = scenes.load("press", trace_every=0)
    R = scene.axes["R"]
    power = mcl.MC_Power(Axis=R)
    scene.run(lambda: power(Enable=True), timeout=0.3)
    assert R.state == AxisState.StandStill
    state = scene.save_state()
    saved = {name: scene.signal(name) for name in ("pressure_A", "pressure_B")}
    q = scene.joint_position("R")
    down = mcl.MC_MoveRelative(Axis=R, Distance=-20.0, Velocity=100.0)
    scene.run(lambda: down(Execute=True), timeout=0.15)  # the ram accelerates on its oil
    moved = {name: scene.signal(name) for name in saved}
    assert max(abs(moved[n] - saved[n]) for n in saved) > 1.0  # bar
    scene.restore_state(state)
    assert {name: scene.signal(name) for name in saved} == saved
    assert scene.joint_position("R") == q
    assert saved["pressure_B"] * BAR > 1e5  # the ram hangs on side B


def test_a_simulated_machine_repeats_after_restore_with_its_noise_faults_and_groups():
    machine = mcl.SimMachine(
        {n: mcl.SimAxisParams(start=0.3, sensors=mcl.Sensors(seed=3)) for n in ("X", "Y")}
    )
    X, Y = machine.axes["X"], machine.axes["Y"]
    for axis in (X, Y):
        configure(axis)
    power = [mcl.MC_Power(Axis=axis) for axis in (X, Y)]
    approach = mcl.MC_StepAbsSwitch(
        Axis=X,
        Direction=MC_Direction.MC_SwitchNegative,
        SwitchMode=MC_SwitchMode.MC_EdgeOff,
        Velocity=50.0,
    )
    pulse = mcl.MC_StepRefPulse(
        Axis=X,
        Direction=MC_Direction.MC_Positive,
        Velocity=10.0,
        BufferMode=MC_BufferMode.Buffered,
    )

    def home() -> None:
        for fb in power:
            fb(Enable=True)
        approach(Execute=power[0].Status)
        pulse(Execute=power[0].Status)

    machine.run(home, until=lambda: bool(pulse.Done), timeout=30.0)
    group = mcl.AxesGroup()
    assert group.add(X) == 0
    t = machine.time
    machine.faults.schedule("Y", mcl.faults.AnalogOffset(0.2), at=t + 0.05, until=t + 0.15)
    state = machine.save_state()
    assert X.group is group  # saving leaves the program's group alone

    def run() -> list[tuple[float, ...]]:
        truth = {name: functools.partial(getattr, sim, "x") for name, sim in machine.sims.items()}
        trace = Trace(machine.axes, truth=truth)
        machine.runtime.observers[:] = [trace]
        move = mcl.MC_MoveAbsolute(Axis=X, Position=80.0, Velocity=300.0)
        move_y = mcl.MC_MoveRelative(Axis=Y, Distance=20.0, Velocity=100.0)

        def program() -> None:
            move(Execute=True)
            move_y(Execute=True)

        machine.run(program, until=lambda: bool(move.Done and move_y.Done), timeout=5.0)
        return [*trace.rows["X"], *trace.rows["Y"]]

    with pytest.raises(mcl.StateError, match="saved from SimMachine with axes X, Y"):
        mcl.SimMachine().restore_state(state)
    machine.restore_state(state)
    assert X.group is None and group.axes == []  # groups belong to the program: X moves alone
    first = run()
    assert [e.fault for e in machine.faults.events[-2:]] == [mcl.faults.AnalogOffset(0.2)] * 2
    machine.restore_state(state)
    assert not machine.faults.active("Y") and machine.faults.pending
    assert machine.plant.get_state() == state.plant
    second = run()
    assert len(first) > 200 and first == second


@pytest.mark.parametrize("name", sorted(scenes.MACHINES))
def test_every_machine_repeats_its_demo_from_a_state_saved_at_power_up(name: str):
    scene = scenes.load(name)
    state = scene.save_state()

    def demo() -> tuple[dict[str, list[tuple[float, ...]]], dict[str, float]]:
        scene.run(scenes.demo(scene), timeout=1.0)
        return scene.trace.rows, {s: scene.signal(s) for s in scene.signals}

    rows, signals = demo()
    scene.restore_state(state)
    again_rows, again_signals = demo()
    assert len(next(iter(rows.values()))) == round(1.0 / scene.runtime.servo_period)
    assert again_rows == rows
    assert again_signals.keys() == signals.keys()
    for s, value in signals.items():
        assert again_signals[s] == value or (np.isnan(value) and np.isnan(again_signals[s]))


def test_the_shear_keeps_its_measured_cuts_in_a_fresh_scene():
    from scenes.machines import flying_shear as fs

    scene = scenes.load("flying_shear")
    scene.device("wheel", fs.MeasuringWheel).ideal()  # a perfect wheel: the first piece is 1500
    demo = fs.Demo(scene, fs.CutJob(cuts=2))
    scene.run(demo, until=lambda: demo.done or bool(demo.error), timeout=30.0)
    assert demo.done and not demo.error
    line = scene.axes["L"]
    scene.run(demo, until=lambda: line.state == AxisState.StandStill, timeout=5.0)
    cuts = list(demo.recorder.cuts)
    piece = cuts[-1].length  # measured from the physics
    assert len(cuts) == 2 and piece is not None and abs(piece - 1500.0) < 1.0
    state = scene.save_state()
    fresh = scenes.load("flying_shear")
    fresh.restore_state(state)
    assert fresh.device("cuts", CutRecorder).cuts == cuts
    scene.device("cuts", CutRecorder).cuts.clear()
    scene.restore_state(state)
    assert scene.device("cuts", CutRecorder).cuts == cuts

"""MC_SetPosition on simulated axes: the coordinate moves, the carriage does not.

Judged by the simulated carriage (``carriage_mm``: metres of the plant, not the encoder) and by
the axis' coordinate: a standing axis reads the new position at once, a running move goes on
physically undisturbed (recorded cycle by cycle against the same run without the call) with its
target moved with the coordinate, mcQueued waits behind the motion given before it, refused
calls leave the axis exactly as it was.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_BufferMode, MC_ExecutionMode
from tests.helpers import (
    POS_TOL,
    carriage_mm,
    carriage_mm_s,
    configure,
    fresh_axis,
    in_velocity,
    make_machine,
    power_on,
    scan,
    tick,
)
from tests.mcl.test_fb_rules import exclusive

QUEUED = MC_ExecutionMode.mcQueued


def record(machine: mcl.SimMachine, axis: mcl.Axis) -> tuple[float, ...]:
    """What the physics and the loop do now: carriage position and velocity, analog output,
    following error, state."""
    return (
        carriage_mm(machine),
        carriage_mm_s(machine),
        axis.volts,
        axis.following_error,
        float(axis.state),
    )


def assert_same_run(run: list[tuple[float, ...]], reference: list[tuple[float, ...]]) -> None:
    """The carriage and the loop did the same, cycle by cycle, to rounding: a coordinate
    shifted by a large number changes the last bits of the following error."""
    assert len(run) == len(reference)
    for k, (row, ref) in enumerate(zip(run, reference, strict=True)):
        assert row == pytest.approx(ref, abs=1e-6), f"scan {k}: {row} != {ref}"


# ----------------------------------------------------------------------------- standing axis


def test_absolute_on_a_standing_axis_sets_the_actual_position_without_motion(machine, X):
    tick(machine, 20)
    before = carriage_mm(machine)
    error = X.following_error
    sp = mcl.MC_SetPosition()
    sp(Axis=X, Execute=True, Position=250.0)
    exclusive(sp)
    assert sp.Done and not sp.Busy and not sp.Error
    assert pytest.approx(250.0, abs=1e-9) == X.POS
    assert X.OPT1n - X.POS == pytest.approx(error, abs=1e-9), "the following error stays"
    assert X.Ref and X.state == AxisState.StandStill
    tick(machine, 100)
    assert carriage_mm(machine) == pytest.approx(before, abs=0.002)
    assert pytest.approx(250.0, abs=0.002) == X.POS
    # and the axis moves in its new coordinate
    move = mcl.MC_MoveAbsolute()
    machine.run(
        lambda: move(Axis=X, Execute=True, Position=200.0, Velocity=200.0),
        until=lambda: move.Done,
        timeout=5.0,
    )
    assert pytest.approx(200.0, abs=POS_TOL) == X.POS
    assert carriage_mm(machine) == pytest.approx(before - 50.0, abs=POS_TOL)


def test_relative_adds_the_distance_and_keeps_ref(machine, X):
    sp = mcl.MC_SetPosition()
    pos = X.POS
    sp(Axis=X, Execute=True, Position=-30.0, Relative=True)
    assert sp.Done
    assert pytest.approx(pos - 30.0, abs=1e-9) == X.POS
    assert X.Ref


def test_rising_edge_applies_once_and_done_follows_the_rules(machine, X):
    sp = mcl.MC_SetPosition(Axis=X, Position=10.0, Relative=True)
    pos = X.POS
    for _ in range(10):  # Execute held TRUE: applied once, Done held
        sp(Execute=True)
        exclusive(sp)
        assert sp.Done
        tick(machine)
    assert pytest.approx(pos + 10.0, abs=0.002) == X.POS
    sp(Execute=False)
    assert not (sp.Done or sp.Busy or sp.Error) and sp.ErrorID == 0
    sp(Execute=True)  # a new edge: once more
    assert sp.Done and pytest.approx(pos + 20.0, abs=0.002) == X.POS
    # a pulse of one scan: Done shown in the scan of the edge only
    sp(Execute=False)
    sp(Execute=True)
    assert sp.Done
    sp(Execute=False)
    assert not sp.Done


def test_disabled_axis_and_encoder_only_axis_take_a_new_coordinate():
    machine = mcl.SimMachine(
        {"X": mcl.SimAxisParams(start=0.2), "W": mcl.SimAxisParams(start=0.0, has_drive=False)}
    )
    X, W = machine.axes["X"], machine.axes["W"]
    configure(X)
    sp, sw = mcl.MC_SetPosition(), mcl.MC_SetPosition()
    sp(Axis=X, Execute=True, Position=500.0)
    sw(Axis=W, Execute=True, Position=-7.5)
    assert sp.Done and sw.Done
    assert X.state == AxisState.Disabled
    assert pytest.approx(500.0) == X.POS and pytest.approx(-7.5) == W.POS
    power_on(machine, X, referenced=False)  # closing the loop keeps the coordinate
    assert pytest.approx(500.0, abs=0.002) == X.POS and not X.Ref


def test_modulo_axis_shows_the_position_wrapped():
    machine = mcl.SimMachine(
        {"R": mcl.SimAxisParams(start=0.2)}, config=mcl.AxisConfig(modulo=360.0)
    )
    R = machine.axes["R"]
    configure(R)
    power_on(machine, R)
    sp = mcl.MC_SetPosition(Axis=R)
    sp(Execute=True, Position=370.0)
    assert sp.Done and pytest.approx(10.0) == R.POS
    sp(Execute=False)
    sp(Execute=True, Position=-20.0, Relative=True)
    assert pytest.approx(350.0) == R.POS


# ----------------------------------------------------------------------------- moving axis


def _run_move(
    call: Callable[[mcl.Axis, int], None] | None, scans: int = 900
) -> tuple[list[tuple[float, ...]], mcl.MC_MoveAbsolute, mcl.Axis]:
    machine, X = fresh_axis()
    move = mcl.MC_MoveAbsolute(Axis=X, Position=150.0, Velocity=300.0, Acceleration=3000.0)
    rows = []
    for k in range(scans):
        move(Execute=True)
        if call is not None:
            call(X, k)
        rows.append(record(machine, X))
        tick(machine)
    return rows, move, X


def test_a_running_move_goes_on_physically_undisturbed_and_its_target_moves_along():
    sp = mcl.MC_SetPosition(Position=1000.0)
    seen: dict[str, Any] = {}

    def call(axis: mcl.Axis, k: int) -> None:
        if k == 100:
            assert axis.state == AxisState.DiscreteMotion
            seen["before"] = axis.POS
            seen["error"] = axis.following_error
        sp(Axis=axis, Execute=k >= 100)
        if k == 100:
            assert sp.Done
            seen["shift"] = axis.POS - seen["before"]
            assert axis.offset == pytest.approx(seen["shift"])
            assert pytest.approx(1000.0) == axis.POS
            assert axis.OPT1n - axis.POS == pytest.approx(seen["error"], abs=1e-9)

    reference, plain, _ = _run_move(None)
    shifted, move, X = _run_move(call)
    assert_same_run(shifted, reference)
    assert plain.Done and move.Done and not move.CommandAborted
    # the target moved with the coordinate: 150 before, 150 + shift now
    assert pytest.approx(150.0 + seen["shift"], abs=POS_TOL) == X.POS


def test_on_an_accelerating_axis_the_actual_position_becomes_position_not_the_set_point():
    """Without feed-forward the loop lags some 0.13 mm while the axis speeds up: the actual
    position reads Position exactly, the set point stays that lag ahead of it."""
    machine, X = fresh_axis(Ff=0.0, Ka=0.0)
    vel, sp = mcl.MC_MoveVelocity(Axis=X), mcl.MC_SetPosition(Axis=X)
    machine.run(lambda: vel(Execute=True, Velocity=200.0, Acceleration=1000.0), timeout=0.1)
    assert X.sp_acc == pytest.approx(1000.0) and not vel.InVelocity
    lag = X.following_error
    assert lag > 0.05
    sp(Execute=True, Position=500.0)
    assert sp.Done
    assert pytest.approx(500.0, abs=1e-9) == X.POS
    assert X.sp_pos - X.POS == pytest.approx(lag, abs=1e-9)


def test_a_velocity_motion_keeps_its_speed_and_a_sw_limit_acts_in_the_new_coordinate():
    machine, X = fresh_axis(LimPos=400.0, LimNeg=-400.0)
    vel, sp = in_velocity(machine, X, 100.0), mcl.MC_SetPosition()
    start = carriage_mm(machine)
    sp(Axis=X, Execute=True, Position=300.0)  # 100 mm before LimPos now
    assert sp.Done
    tick(machine)
    assert carriage_mm_s(machine) == pytest.approx(100.0, rel=0.02)
    assert X.state == AxisState.ContinuousMotion and vel.InVelocity
    machine.run(lambda: vel(Execute=True), until=lambda: vel.Error, timeout=3.0)
    assert vel.ErrorID == ErrorID.ERRSWP
    assert carriage_mm(machine) - start == pytest.approx(100.0, abs=10.0)


# ----------------------------------------------------------------------------- mcQueued


def test_queued_waits_for_the_move_and_later_moves_are_in_the_new_coordinate(machine, X):
    first, last = mcl.MC_MoveRelative(), mcl.MC_MoveAbsolute()
    sp = mcl.MC_SetPosition(Axis=X, Position=0.0, ExecutionMode=QUEUED)
    first(Axis=X, Execute=True, Distance=60.0, Velocity=200.0)
    sp(Execute=True)
    last(Axis=X, Execute=True, Position=25.0, Velocity=200.0, BufferMode=MC_BufferMode.Buffered)
    assert sp.Busy and not sp.Done
    assert X.POS < 1.0, "not applied before the move ends"
    done_at: list[float] = []

    def program() -> None:
        first(Execute=True)
        sp(Execute=True)
        last(Execute=True)
        exclusive(sp)
        if sp.Done and not done_at:
            assert first.Done
            done_at.append(carriage_mm(machine))

    machine.run(program, until=lambda: last.Done, timeout=5.0)
    assert done_at and done_at[0] == pytest.approx(60.0, abs=POS_TOL)
    assert pytest.approx(25.0, abs=POS_TOL) == X.POS
    assert carriage_mm(machine) == pytest.approx(85.0, abs=POS_TOL)


def test_queued_behind_a_velocity_motion_applies_at_invelocity_and_the_motion_goes_on(machine, X):
    vel = mcl.MC_MoveVelocity()
    sp = mcl.MC_SetPosition(Axis=X, Position=-100.0, Relative=True, ExecutionMode=QUEUED)
    vel(Axis=X, Execute=True, Velocity=150.0)
    sp(Execute=True)
    assert sp.Busy
    positions: list[float] = []

    def program() -> None:
        vel(Execute=True)
        sp(Execute=True)
        if sp.Done and not positions:
            positions.append(X.offset)

    machine.run(program, until=lambda: sp.Done, timeout=2.0)
    assert vel.InVelocity and not vel.CommandAborted
    tick(machine, 20)
    vel(Execute=True)
    assert vel.Busy and X.state == AxisState.ContinuousMotion
    assert carriage_mm_s(machine) == pytest.approx(150.0, rel=0.02)
    assert positions[0] == pytest.approx(-100.0, abs=0.01)


def test_queued_the_actual_position_becomes_position_where_it_is_applied():
    """Applied at InVelocity, while the loop still lags the set point (no feed-forward): in
    that servo cycle the actual position reads Position exactly."""
    machine, X = fresh_axis(Ff=0.0, Ka=0.0)
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=200.0, Acceleration=1000.0)
    sp = mcl.MC_SetPosition(Axis=X, Position=500.0, ExecutionMode=QUEUED)
    cycles: list[tuple[float, float, float]] = []
    machine.runtime.observers.append(lambda t: cycles.append((X.offset, X.POS, X.sp_pos - X.POS)))
    machine.run(scan(lambda: vel(Execute=True), lambda: sp(Execute=True)), until=lambda: sp.Done)
    _, position, lag = next(c for c in cycles if c[0] != cycles[0][0])
    assert lag > 0.05
    assert position == pytest.approx(500.0, abs=1e-9)


def test_queued_on_an_idle_axis_is_done_at_once(machine, X):
    sp = mcl.MC_SetPosition(Axis=X, ExecutionMode=QUEUED)
    sp(Execute=True, Position=42.0)
    assert sp.Done and pytest.approx(42.0) == X.POS


def test_queued_aborted_by_an_aborting_move_leaves_the_coordinate(machine, X):
    first, other = mcl.MC_MoveRelative(), mcl.MC_MoveRelative()
    sp = mcl.MC_SetPosition(Axis=X, Position=500.0, ExecutionMode=QUEUED)
    first(Axis=X, Execute=True, Distance=80.0, Velocity=200.0)
    sp(Execute=True)
    tick(machine, 10)
    other(Axis=X, Execute=True, Distance=-20.0, Velocity=200.0)
    sp(Execute=True)
    exclusive(sp)
    assert sp.CommandAborted and not sp.Done and not sp.Busy
    machine.run(lambda: other(Execute=True), until=lambda: other.Done, timeout=5.0)
    assert pytest.approx(carriage_mm(machine), abs=0.01) == X.POS, "coordinate unchanged"
    sp(Execute=False)
    assert not sp.CommandAborted


def test_queued_restarted_while_waiting_withdraws_the_first_shift(machine, X):
    first = mcl.MC_MoveRelative()
    sp = mcl.MC_SetPosition(Axis=X, Relative=True, ExecutionMode=QUEUED)
    first(Axis=X, Execute=True, Distance=40.0, Velocity=200.0)
    sp(Execute=True, Position=1000.0)
    sp(Execute=False)
    sp(Execute=True, Position=5.0)  # a new edge: only this one counts
    program = scan(lambda: first(Execute=True), lambda: sp(Execute=True))
    machine.run(program, until=lambda: sp.Done, timeout=5.0)
    assert X.POS - carriage_mm(machine) == pytest.approx(5.0, abs=0.01)
    assert len(X.queue) == 0


def test_queued_behind_gear_in_is_refused_and_the_axis_keeps_its_coordinate():
    machine = make_machine("MS")
    M, S = machine.axes["M"], machine.axes["S"]
    gear, drive = mcl.MC_GearIn(), mcl.MC_MoveVelocity()
    sp = mcl.MC_SetPosition(ExecutionMode=QUEUED, Position=77.0)

    def program() -> None:
        drive(Axis=M, Execute=True, Velocity=50.0)
        gear(Master=M, Slave=S, Execute=True, RatioNumerator=1, RatioDenominator=1)

    machine.run(program, until=lambda: gear.InGear, timeout=2.0)
    pos = S.POS
    sp(Axis=S, Execute=True)
    assert sp.Error and sp.ErrorID == ErrorID.EParam
    assert pytest.approx(pos) == S.POS and gear.Busy


def test_a_master_coordinate_shift_does_not_disturb_its_geared_slave():
    machine = make_machine("MS")
    M, S = machine.axes["M"], machine.axes["S"]
    gear, drive, sp = mcl.MC_GearIn(), mcl.MC_MoveVelocity(), mcl.MC_SetPosition()

    def program() -> None:
        drive(Axis=M, Execute=True, Velocity=50.0)
        gear(Master=M, Slave=S, Execute=True, RatioNumerator=2, RatioDenominator=1)

    machine.run(program, until=lambda: gear.InGear, timeout=2.0)
    machine.run(program, timeout=0.1)
    v_before = carriage_mm_s(machine, "S")
    sp(Axis=M, Execute=True, Position=-300.0)
    assert sp.Done
    peak = 0.0
    for _ in range(50):
        program()
        peak = max(peak, abs(S.following_error))
        tick(machine)
    assert carriage_mm_s(machine, "S") == pytest.approx(v_before, rel=0.02)
    assert peak < 0.1, f"slave following error {peak} mm"


# ----------------------------------------------------------------------------- refused


def _refused(call: Callable[[mcl.Axis, int], None]) -> list[tuple[float, ...]]:
    rows, _move, _X = _run_move(call, scans=400)
    return rows


@pytest.mark.parametrize(
    ("inputs", "error"),
    [
        ({"Position": math.nan}, ErrorID.EParam),
        ({"Position": math.inf}, ErrorID.EParam),
        ({"Position": -math.inf, "Relative": True}, ErrorID.EParam),
        ({"Position": 10.0, "ExecutionMode": MC_ExecutionMode.mcDelayed}, ErrorID.EParam),
        ({"Position": 10.0, "ExecutionMode": 7}, ErrorID.EParam),
        ({"Position": 10.0, "ExecutionMode": 1.5}, ErrorID.EParam),
        ({"Position": "ten"}, ErrorID.EParam),
    ],
    ids=["nan", "inf", "relative-inf", "mcDelayed", "mode-7", "mode-1.5", "string"],
)
def test_parameter_error_leaves_the_running_move_as_it_was(inputs, error):
    bad = mcl.MC_SetPosition()
    seen: list[tuple[bool, int, float]] = []

    def call(axis: mcl.Axis, k: int) -> None:
        bad(Axis=axis, Execute=k >= 50, **inputs)
        exclusive(bad)
        if k >= 50:
            seen.append((bad.Error, bad.ErrorID, axis.offset))

    assert_same_run(_refused(call), _refused(lambda axis, k: None))
    assert all(e and code == error and offset == 0.0 for e, code, offset in seen)


def test_a_shift_beyond_a_software_limit_is_refused_with_ecil():
    machine, X = fresh_axis(LimPos=300.0, LimNeg=-300.0)
    move, sp = mcl.MC_MoveAbsolute(), mcl.MC_SetPosition()
    sp(Axis=X, Execute=True, Position=350.0)  # the axis itself beyond LimPos
    assert sp.Error and sp.ErrorID == ErrorID.Ecil and X.offset == 0.0
    sp(Execute=False)
    machine.run(
        lambda: move(Axis=X, Execute=True, Position=200.0, Velocity=200.0),
        until=lambda: X.POS > 50.0,
        timeout=2.0,
    )
    sp(Execute=True, Position=150.0, Relative=True)  # the running target would be 350
    assert sp.Error and sp.ErrorID == ErrorID.Ecil and X.offset == 0.0
    sp(Execute=False)
    sp(Execute=True, Position=50.0, Relative=True)  # target 250: inside
    assert sp.Done
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=5.0)
    assert pytest.approx(250.0, abs=POS_TOL) == X.POS
    assert carriage_mm(machine) == pytest.approx(200.0, abs=POS_TOL)


def test_error_stop_stopping_homing_and_group_member_refuse(machine, X):
    sp = mcl.MC_SetPosition(Axis=X, Position=5.0)
    stop = mcl.MC_Stop(Axis=X)
    stop(Execute=True)
    sp(Execute=True)
    assert sp.ErrorID == ErrorID.EAxStop
    sp(Execute=False)
    stop(Execute=False)
    tick(machine, 5)
    assert X.state == AxisState.StandStill
    homing = mcl.MC_StepAbsSwitch(Axis=X)
    homing(Execute=True, Velocity=20.0, Direction=mcl.MC_Direction.MC_Positive)
    tick(machine)
    assert X.state == AxisState.Homing
    sp(Execute=True)
    assert sp.ErrorID == ErrorID.Ehome
    sp(Execute=False)
    X.fault(ErrorID.ERRLIP)
    sp(Execute=True)
    assert sp.ErrorID == ErrorID.Eerrstop
    sp(Execute=False)
    assert X.offset == 0.0

    _machine2, Y = fresh_axis()
    group = mcl.AxesGroup("G")
    add = mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=Y)
    add(Execute=True)
    assert add.Done
    sp2 = mcl.MC_SetPosition(Axis=Y, Position=5.0)
    sp2(Execute=True)
    assert sp2.ErrorID == ErrorID.EGroupMember and Y.offset == 0.0


# ----------------------------------------------------------------------------- the gantry


def test_gantry_move_is_physically_undisturbed_by_a_coordinate_shift():
    """On the MuJoCo gantry, judged by the X joint: a move with MC_SetPosition (Relative
    +500 mm) in the middle follows the same joint trajectory as without it, and ends at the
    target moved with the coordinate."""
    from scenes.machines import gantry

    def run(shift: bool) -> tuple[list[float], mcl.Axis, float]:
        scene = gantry.build(start={"X": 0.3, "Y": 0.3, "Z": -0.1}, trace_every=0)
        X = scene.axes["X"]
        power, move = mcl.MC_Power(Axis=X), mcl.MC_MoveRelative(Axis=X)
        sp = mcl.MC_SetPosition(Axis=X, Position=500.0, Relative=True)
        joint: list[float] = []
        scans = [0]
        start = X.POS

        def program() -> None:
            power(Enable=True)
            move(Execute=power.Status, Distance=200.0, Velocity=400.0, Acceleration=4000.0)
            sp(Execute=shift and scans[0] >= 150)
            scans[0] += 1
            joint.append(scene.joint_position("X"))

        scene.run(program, until=lambda: move.Done, timeout=5.0)
        return joint, X, start

    reference, _, _ = run(False)
    shifted, X, start = run(True)
    assert len(shifted) == len(reference)
    worst = max(abs(a - b) for a, b in zip(shifted, reference, strict=True))
    assert worst < 1e-9, f"joint trajectories differ by {worst * 1000.0} mm"
    assert pytest.approx(X.offset) == 500.0
    assert pytest.approx(start + 200.0 + 500.0, abs=POS_TOL) == X.POS

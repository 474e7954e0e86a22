"""MC_MoveContinuousAbsolute and MC_MoveContinuousRelative on simulated axes (PLCopen Part 1 v2.0
sections 3.11, 3.12): the target is passed with EndVelocity and the axis goes on at it in
ContinuousMotion; InEndVelocity by the rules of Tab. 2.3; every buffer mode; parameter errors
leave the axis as it was."""

from __future__ import annotations

import math
from typing import Any

import pytest

import mcl
from mcl.command import ProfileCommand
from mcl.trajectory import Profile
from tests.helpers import carriage_mm_s, fresh_axis, tick
from tests.mcl.test_fb_rules import (
    exclusive,
    outputs_after_execute_fell,
    seen_while_taken_over,
)

Modes = mcl.MC_BufferMode


def command(fb: Any) -> ProfileCommand:
    """The command of ``fb``."""
    cmd = fb._cmd
    assert isinstance(cmd, ProfileCommand)
    return cmd


def planned(fb: Any) -> Profile:
    """The profile the command of ``fb`` follows."""
    cmd = fb._cmd
    assert isinstance(cmd, ProfileCommand) and cmd.profile is not None
    return cmd.profile


def passing(fb: Any) -> tuple[float, float]:
    """Where and how fast the model passes the end of the block's move [mm, mm/s]."""
    profile = planned(fb)
    p, v, a = profile.at(profile.duration)
    assert a == pytest.approx(0.0, abs=1e-6)
    return p, v


def run_to_end_velocity(machine: mcl.SimMachine, fb: Any, **inputs: Any) -> list[float]:
    """Run ``fb`` until InEndVelocity, checking the outputs every scan; returns the model
    positions of the scans before the one that shows it."""
    positions: list[float] = []
    axis = fb.Axis

    def scan() -> None:
        fb(Execute=True, **inputs)
        exclusive(fb)
        assert not fb.Done and not fb.Error, fb.ErrorID
        assert fb.Busy and fb.Active
        positions.append(axis.sp_pos)
        assert axis.state == mcl.AxisState.ContinuousMotion

    machine.run(scan, until=lambda: fb.InEndVelocity, timeout=5.0)
    return positions[:-1]


# ------------------------------------------------------------------------------ the motion
def test_absolute_passes_the_target_with_end_velocity_and_goes_on_at_it():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=100.0, Velocity=200.0, EndVelocity=50.0)
    positions = run_to_end_velocity(machine, fb)
    assert max(positions) < 100.0
    assert passing(fb) == pytest.approx((100.0, 50.0), abs=1e-9)
    assert 100.0 <= X.sp_pos <= 100.0 + 50.0 * 0.003
    machine.run(lambda: fb(Execute=True), timeout=0.5)
    assert fb.InEndVelocity and fb.Busy and fb.Active and not fb.Done
    assert X.state == mcl.AxisState.ContinuousMotion
    assert X.sp_vel == pytest.approx(50.0) and X.sp_acc == pytest.approx(0.0, abs=1e-6)
    assert carriage_mm_s(machine) == pytest.approx(50.0, abs=1.0)


def test_relative_counts_from_the_actual_position_at_the_edge():
    machine, X = fresh_axis(referenced=False)
    shift = mcl.MC_MoveRelative(Axis=X, Distance=30.0, Velocity=200.0)
    machine.run(lambda: shift(Execute=True), until=lambda: shift.Done, timeout=5.0)
    tick(machine, 50)
    start = X.POS
    fb = mcl.MC_MoveContinuousRelative(Axis=X, Distance=-40.0, Velocity=200.0, EndVelocity=-80.0)
    run_to_end_velocity(machine, fb)
    p, v = passing(fb)
    assert p == pytest.approx(start - 40.0, abs=1e-9) and v == pytest.approx(-80.0)


def test_an_end_velocity_against_the_way_to_the_target_goes_past_and_comes_back():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=50.0, Velocity=200.0, EndVelocity=-50.0)
    positions = run_to_end_velocity(machine, fb)
    assert max(positions) > 50.0 + 1.0
    assert passing(fb) == pytest.approx((50.0, -50.0), abs=1e-9)
    tick(machine, 20)
    assert X.sp_vel == pytest.approx(-50.0) and X.sp_pos < 50.0


def test_an_end_velocity_above_velocity_is_reached_just_before_the_target():
    machine, X = fresh_axis()
    samples: list[tuple[float, float]] = []
    machine.runtime.observers.append(lambda t: samples.append((X.sp_pos, X.sp_vel)))
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=150.0, Velocity=100.0, EndVelocity=300.0)
    run_to_end_velocity(machine, fb)
    assert passing(fb) == pytest.approx((150.0, 300.0), abs=1e-9)
    assert max(v for p, v in samples if p < 100.0) <= 100.0 + 1e-9  # cruising at Velocity


def test_an_end_velocity_above_vmax_is_clamped_to_vmax():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=200.0, Velocity=400.0, EndVelocity=800.0)
    run_to_end_velocity(machine, fb)
    assert passing(fb)[1] == pytest.approx(500.0)  # Vmax of the simulated axis


@pytest.mark.parametrize(
    ("fb_type", "inputs"),
    [
        (mcl.MC_MoveContinuousAbsolute, {"Position": 50.0}),
        (mcl.MC_MoveContinuousRelative, {"Distance": -50.0}),
    ],
)
def test_an_end_velocity_above_max_velocity_appl_is_clamped_to_it(fb_type, inputs):
    """MaxVelocityAppl (MC_WriteParameter 9) limits EndVelocity as it limits Velocity: the
    carriage runs on at 80 mm/s, not at the 100 asked for."""
    machine, X = fresh_axis()
    write = mcl.MC_WriteParameter(Axis=X, Execute=True, ParameterNumber=9, Value=80.0)
    write()
    assert write.Done
    sign = math.copysign(1.0, next(iter(inputs.values())))
    fb = fb_type(Axis=X, Velocity=60.0, EndVelocity=100.0 * sign, **inputs)
    run_to_end_velocity(machine, fb)
    machine.run(lambda: fb(Execute=True), timeout=0.3)
    assert fb.InEndVelocity and X.sp_vel == pytest.approx(80.0 * sign)
    assert carriage_mm_s(machine) == pytest.approx(80.0 * sign, abs=1.0)


def test_end_velocity_zero_stops_at_the_target_still_in_continuous_motion():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=40.0, Velocity=200.0, EndVelocity=0.0)
    run_to_end_velocity(machine, fb)
    machine.run(lambda: fb(Execute=True), timeout=0.3)
    assert fb.InEndVelocity and fb.Busy and X.state == mcl.AxisState.ContinuousMotion
    assert X.sp_pos == pytest.approx(40.0) and X.sp_vel == 0.0
    halt = mcl.MC_Halt(Axis=X)
    machine.run(lambda: halt(Execute=True), until=lambda: halt.Done, timeout=1.0)
    fb(Execute=True)
    assert fb.CommandAborted and X.state == mcl.AxisState.StandStill


# ------------------------------------------------------------------------------ outputs
def test_in_end_velocity_is_reset_by_the_falling_edge_the_motion_goes_on():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=30.0, Velocity=200.0, EndVelocity=40.0)
    run_to_end_velocity(machine, fb)
    fb(Execute=False)
    exclusive(fb)
    assert not fb.InEndVelocity and fb.Busy and fb.Active
    tick(machine, 20)
    fb(Execute=False)
    assert not fb.InEndVelocity and X.sp_vel == pytest.approx(40.0)


def test_in_end_velocity_pulses_one_scan_when_reached_after_execute_fell():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=30.0, Velocity=200.0, EndVelocity=40.0)
    fb(Execute=True)
    scans = outputs_after_execute_fell(machine, fb, "InEndVelocity", "Busy")
    assert sum(shown for shown, _ in scans) == 1
    assert all(busy for _, busy in scans)


def test_a_continuous_move_taken_over_reports_aborted_and_drops_in_end_velocity():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=30.0, Velocity=200.0, EndVelocity=40.0)
    run_to_end_velocity(machine, fb)
    move = mcl.MC_MoveAbsolute(Axis=X, Position=0.0, Velocity=200.0)

    def scan() -> None:
        fb(Execute=True)
        move(Execute=True)
        exclusive(fb)

    machine.run(scan, until=lambda: move.Done, timeout=5.0)
    assert fb.CommandAborted and not fb.InEndVelocity and not fb.Busy and not fb.Active


def test_aborted_before_the_target_it_never_shows_in_end_velocity():
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=300.0, Velocity=200.0, EndVelocity=40.0)
    halt = mcl.MC_Halt(Axis=X)
    machine.run(lambda: fb(Execute=True), timeout=0.2)
    seen = seen_while_taken_over(machine, fb, halt, "InEndVelocity")
    assert fb.CommandAborted and not seen


# ------------------------------------------------------------------------------ buffer modes
def test_buffered_behind_a_move_it_starts_at_rest_from_the_moves_target():
    machine, X = fresh_axis()
    move = mcl.MC_MoveAbsolute(Axis=X, Position=50.0, Velocity=200.0)
    fb = mcl.MC_MoveContinuousRelative(
        Axis=X, Distance=20.0, Velocity=100.0, EndVelocity=30.0, BufferMode=Modes.Buffered
    )

    def scan() -> None:
        move(Execute=True)
        fb(Execute=True)
        exclusive(fb)
        if not move.Done:
            assert fb.Busy and not fb.Active

    machine.run(scan, until=lambda: fb.InEndVelocity, timeout=5.0)
    assert move.Done and not move.CommandAborted
    assert planned(fb).segments[0][1:3] == pytest.approx((50.0, 0.0), abs=1e-9)
    assert passing(fb) == pytest.approx((70.0, 30.0), abs=1e-9)


@pytest.mark.parametrize(
    ("mode", "handover"),
    [
        (Modes.BlendingLow, 100.0),
        (Modes.BlendingPrevious, 200.0),
        (Modes.BlendingNext, 100.0),
        (Modes.BlendingHigh, 200.0),
    ],
)
def test_blending_behind_a_move_hands_over_at_the_blending_velocity(mode, handover):
    """MoveAbsolute to 100 mm at 200 mm/s, then the continuous move at 100 mm/s to 200 mm."""
    machine, X = fresh_axis()
    samples: list[tuple[float, float, float]] = []
    machine.runtime.observers.append(lambda t: samples.append((t, X.sp_pos, X.sp_vel)))
    move = mcl.MC_MoveAbsolute(Axis=X, Position=100.0, Velocity=200.0)
    fb = mcl.MC_MoveContinuousAbsolute(
        Axis=X, Position=200.0, Velocity=100.0, EndVelocity=50.0, BufferMode=mode
    )

    def scan() -> None:
        move(Execute=True)
        fb(Execute=True)

    machine.run(scan, until=lambda: fb.InEndVelocity, timeout=5.0)
    assert move.Done and not move.CommandAborted
    cmd = command(fb)
    assert planned(fb).segments[0][1:3] == pytest.approx((100.0, handover), abs=1e-6)
    _, _, v = min(samples, key=lambda s: abs(s[0] - cmd.t0))
    assert v == pytest.approx(handover, abs=1.0)  # the set point itself, within a cycle
    assert min(v for _, p, v in samples if 60.0 < p < 190.0) > 40.0  # no stop between
    assert passing(fb) == pytest.approx((200.0, 50.0), abs=1e-9)


@pytest.mark.parametrize("mode", [Modes.Buffered, Modes.BlendingLow])
def test_a_successor_starts_at_in_end_velocity_from_the_end_velocity(mode):
    machine, X = fresh_axis()
    fb = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=50.0, Velocity=200.0, EndVelocity=80.0)
    move = mcl.MC_MoveAbsolute(Axis=X, Position=120.0, Velocity=150.0, BufferMode=mode)
    seen_while_taken_over(machine, fb, move, "InEndVelocity")
    assert fb.CommandAborted and not fb.Busy  # taken over once it reached its end
    assert command(move).t0 == pytest.approx(command(fb).t0 + planned(fb).duration)
    assert planned(move).at(0.0)[:2] == pytest.approx((50.0, 80.0), abs=1e-9)
    assert X.state == mcl.AxisState.StandStill


# ------------------------------------------------------------------------------ refused
REFUSED: list[tuple[str, type[Any], dict[str, Any], int]] = [
    (
        "end velocity NaN",
        mcl.MC_MoveContinuousAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "EndVelocity": math.nan},
        5,
    ),
    (
        "end velocity inf",
        mcl.MC_MoveContinuousRelative,
        {"Distance": 50.0, "Velocity": 100.0, "EndVelocity": -math.inf},
        5,
    ),
    (
        "velocity 0",
        mcl.MC_MoveContinuousAbsolute,
        {"Position": 50.0, "Velocity": 0.0, "EndVelocity": 10.0},
        5,
    ),
    (
        "position NaN",
        mcl.MC_MoveContinuousAbsolute,
        {"Position": math.nan, "Velocity": 100.0, "EndVelocity": 10.0},
        5,
    ),
    (
        "distance inf",
        mcl.MC_MoveContinuousRelative,
        {"Distance": math.inf, "Velocity": 100.0, "EndVelocity": 10.0},
        5,
    ),
    (
        "acceleration negative",
        mcl.MC_MoveContinuousRelative,
        {"Distance": 5.0, "Velocity": 100.0, "Acceleration": -1.0},
        5,
    ),
    (
        "buffer mode invalid",
        mcl.MC_MoveContinuousAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "BufferMode": 6},
        5,
    ),
    (
        "target beyond LimPos",
        mcl.MC_MoveContinuousAbsolute,
        {"Position": 450.0, "Velocity": 100.0, "EndVelocity": 10.0},
        8,
    ),
    (
        "target beyond LimNeg",
        mcl.MC_MoveContinuousRelative,
        {"Distance": -450.0, "Velocity": 100.0, "EndVelocity": -10.0},
        8,
    ),
]


@pytest.mark.parametrize(
    ("fb_type", "inputs", "error_id"),
    [pytest.param(t, i, e, id=name) for name, t, i, e in REFUSED],
)
def test_a_refused_move_leaves_the_moving_axis_as_it_was(fb_type, inputs, error_id):
    machine, X = fresh_axis(LimPos=400.0, LimNeg=-300.0)
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=50.0)
    machine.run(lambda: vel(Execute=True), until=lambda: vel.InVelocity, timeout=5.0)
    fb = fb_type(Axis=X, **inputs)

    def scan() -> None:
        vel(Execute=True)
        fb(Execute=True)
        exclusive(fb)

    machine.run(scan, timeout=0.1)
    assert fb.Error and fb.ErrorID == error_id and not fb.Busy and not fb.InEndVelocity
    assert vel.InVelocity and vel.Active and not vel.CommandAborted
    assert X.state == mcl.AxisState.ContinuousMotion and X.sp_vel == 50.0


def test_absolute_needs_ref_relative_does_not():
    machine, X = fresh_axis(referenced=False)
    absolute = mcl.MC_MoveContinuousAbsolute(Axis=X, Position=10.0, Velocity=100.0)
    absolute(Execute=True)
    assert absolute.Error and absolute.ErrorID == mcl.ErrorID.Ehome
    assert X.state == mcl.AxisState.StandStill
    relative = mcl.MC_MoveContinuousRelative(Axis=X, Distance=10.0, Velocity=100.0, EndVelocity=5.0)
    run_to_end_velocity(machine, relative)


def test_a_stopping_axis_refuses_with_eaxstop():
    _, X = fresh_axis()
    mcl.MC_Stop(Axis=X)(Execute=True)
    fb = mcl.MC_MoveContinuousRelative(Axis=X, Distance=10.0, Velocity=100.0)
    fb(Execute=True)
    assert fb.Error and fb.ErrorID == mcl.ErrorID.EAxStop

"""MC_PositionProfile, MC_VelocityProfile, MC_AccelerationProfile on simulated axes (mcl.profiles;
PLCopen Part 1 v2.0 sections 3.14–3.16): the tables are followed in time, the interpolation the
reference states, scaling, the states and outputs of Tab. 2.3, refused tables leave the axis as it
was, aborting and buffering."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import Any

import pytest

import mcl
from mcl.profiles import MAX_PAIRS, TableMotion
from tests.helpers import (
    PLC,
    assert_at,
    carriage_mm,
    carriage_mm_s,
    configure,
    fresh_axis,
    power_on,
    tick,
)
from tests.mcl.test_fb_rules import exclusive, outputs_after_execute_fell, seen_while_taken_over

Sample = tuple[float, float, float, float, mcl.AxisState]
"""A servo instant: time [s], model position [mm], velocity [mm/s], acceleration, axis state."""

TP = mcl.MC_TP_REF([mcl.MC_TP(0.1, 20.0), mcl.MC_TP(0.2, 60.0), mcl.MC_TP(0.15, 40.0)])
"""Relative points: 20 mm after 0.1 s, 60 mm after 0.3 s, 40 mm (back) after 0.45 s."""

TV = mcl.MC_TV_REF([mcl.MC_TV(0.1, 100.0), mcl.MC_TV(0.2, 100.0), mcl.MC_TV(0.1, -50.0)])
"""Velocity up to 100 mm/s in 0.1 s, held 0.2 s, down to −50 mm/s in 0.1 s."""

TA = mcl.MC_TA_REF([mcl.MC_TA(0.05, 2000.0), mcl.MC_TA(0.1, 2000.0), mcl.MC_TA(0.05, 0.0)])
"""Acceleration ramping to 2000 mm/s², held, ramping back to 0: ends at 300 mm/s."""


def recorder(machine: mcl.SimMachine, X: mcl.Axis) -> list[Sample]:
    samples: list[Sample] = []
    machine.runtime.observers.append(
        lambda t: samples.append((t, X.sp_pos, X.sp_vel, X.sp_acc, X.state))
    )
    return samples


def at(samples: list[Sample], t: float) -> Sample:
    """The servo instant nearest ``t``."""
    return min(samples, key=lambda s: abs(s[0] - t))


def run_until(
    machine: mcl.SimMachine,
    scan: Callable[[], None],
    until: Callable[[], object],
    seconds: float = 5.0,
) -> None:
    machine.run(scan, until=until, timeout=seconds)


def start_time(fb: Any) -> float:
    """When the profile of ``fb`` took over the axis (its profile time 0) [s]."""
    cmd = fb._cmd
    assert isinstance(cmd, TableMotion)
    return cmd.t0


def start_position(fb: Any) -> float:
    """Where the profile of ``fb`` took over the axis (point 0 of its table) [mm]."""
    cmd = fb._cmd
    assert isinstance(cmd, TableMotion) and cmd.profile is not None
    return cmd.profile.segments[0][1]


def done_after(machine: mcl.SimMachine, fb: Any, scan: Callable[[], None]) -> float:
    """Run ``scan`` until ``fb`` is Done; the seconds from the profile's start to that scan."""
    done: list[float] = []

    def program() -> None:
        scan()
        if fb.Done and not done:
            done.append(machine.time)

    run_until(machine, program, lambda: done)
    return done[0] - start_time(fb)


# ------------------------------------------------------------------------------ following
def follow(
    machine: mcl.SimMachine, fb: Any, state: mcl.AxisState, duration: float
) -> tuple[float, float]:
    """Run ``fb`` (Execute TRUE) until Done: rule 2 holds on every scan and, until Done, the block
    is Busy and Active and the axis is in ``state``; Done comes ``duration`` [s] after the
    profile's start, within a PLC cycle. Returns that start time [s] and position [mm]."""
    X = fb.Axis

    def scan() -> None:
        fb(Execute=True)
        exclusive(fb)
        if not fb.Done:
            assert fb.Busy and fb.Active
            assert X.state == state

    assert duration <= done_after(machine, fb, scan) <= duration + PLC + 0.001
    return start_time(fb), start_position(fb)


def test_position_profile_passes_every_point_at_its_time_and_stands_at_the_last():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP)
    t0, start = follow(machine, fb, mcl.AxisState.DiscreteMotion, 0.45)
    for t, p in ((0.1, 20.0), (0.3, 60.0), (0.45, 40.0)):
        assert at(samples, t0 + t)[1] == pytest.approx(start + p, abs=1e-9)
    # the spline: velocity continuous (no step beyond what the acceleration gives in a cycle)
    moving = [s for s in samples if s[0] >= t0]
    for (_, _, v0, a0, _), (_, _, v1, a1, _) in itertools.pairwise(moving):
        assert abs(v1 - v0) <= 0.001 * max(abs(a0), abs(a1)) + 1e-6
    assert at(samples, t0 + 0.45)[2] == pytest.approx(0.0, abs=1e-9)
    assert X.state == mcl.AxisState.StandStill
    assert not fb.Busy and not fb.Active and not fb.Error
    tick(machine, 100)
    assert_at(X, start + 40.0)


def test_position_profile_scales_offsets_and_stretches_time_and_may_be_absolute():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    table = mcl.MC_TP_REF([(0.1, 10.0), (0.1, 30.0)], IsAbsolute=True)
    fb = mcl.MC_PositionProfile(
        Axis=X, TimePosition=table, PositionScale=2.0, Offset=-5.0, TimeScale=1.5
    )
    assert 0.30 <= done_after(machine, fb, lambda: fb(Execute=True)) <= 0.30 + PLC + 0.001
    t0 = start_time(fb)
    assert at(samples, t0 + 0.15)[1] == pytest.approx(15.0, abs=1e-9)
    assert at(samples, t0 + 0.30)[1] == pytest.approx(55.0, abs=1e-9)
    tick(machine, 100)
    assert_at(X, 55.0)


def test_absolute_position_profile_needs_ref_a_relative_one_does_not():
    machine, X = fresh_axis(referenced=False)
    absolute = mcl.MC_PositionProfile(
        Axis=X, TimePosition=mcl.MC_TP_REF([(0.1, 5.0)], IsAbsolute=True)
    )
    absolute(Execute=True)
    assert absolute.Error and absolute.ErrorID == mcl.ErrorID.Ehome
    relative = mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(0.1, 5.0)]))
    run_until(machine, lambda: relative(Execute=True), lambda: relative.Done)
    tick(machine, 100)
    assert_at(X, 5.0)


def test_position_profile_takes_over_a_moving_axis_without_a_velocity_step():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=150.0)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP)
    run_until(machine, lambda: vel(Execute=True), lambda: vel.InVelocity)
    tick(machine, 10)

    def scan() -> None:
        vel(Execute=True)
        fb(Execute=True)

    run_until(machine, scan, lambda: fb.Done)
    assert vel.CommandAborted and not vel.Busy
    t0, start = start_time(fb), start_position(fb)
    before, after = at(samples, t0), at(samples, t0 + 0.001)
    assert before[2] == pytest.approx(150.0)
    assert abs(after[2] - before[2]) <= 0.001 * abs(after[3]) + 1e-6
    assert at(samples, t0 + 0.45)[1] == pytest.approx(start + 40.0, abs=1e-9)


def test_velocity_profile_ramps_linearly_then_keeps_its_last_velocity_in_continuous_motion():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    fb = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=TV)
    t0, start = follow(machine, fb, mcl.AxisState.ContinuousMotion, 0.4)
    for t, v in ((0.05, 50.0), (0.1, 100.0), (0.3, 100.0), (0.35, 25.0), (0.4, -50.0)):
        assert at(samples, t0 + t)[2] == pytest.approx(v, abs=1e-9)
    assert at(samples, t0 + 0.05)[3] == pytest.approx(1000.0)
    assert at(samples, t0 + 0.35)[3] == pytest.approx(-1500.0)
    # position: the integral of the ramps (5 + 20 + 2.5 mm)
    assert at(samples, t0 + 0.4)[1] == pytest.approx(start + 27.5, abs=1e-9)
    assert not fb.Busy and not fb.Active
    tick(machine, 100)
    assert X.state == mcl.AxisState.ContinuousMotion
    assert X.sp_vel == -50.0 and X.sp_acc == 0.0
    assert carriage_mm_s(machine) == pytest.approx(-50.0, abs=1.0)


def test_velocity_profile_scales_offsets_and_stretches_time():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    fb = mcl.MC_VelocityProfile(
        Axis=X, TimeVelocity=TV, VelocityScale=0.5, Offset=10.0, TimeScale=2.0
    )
    assert 0.8 <= done_after(machine, fb, lambda: fb(Execute=True)) <= 0.8 + PLC + 0.001
    t0 = start_time(fb)
    assert at(samples, t0 + 0.2)[2] == pytest.approx(60.0)  # 0.5 · 100 + 10
    assert at(samples, t0 + 0.8)[2] == pytest.approx(-15.0)  # 0.5 · −50 + 10


def test_acceleration_profile_ramps_the_acceleration_then_goes_on_at_the_velocity_reached():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    fb = mcl.MC_AccelerationProfile(Axis=X, TimeAcceleration=TA)
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done)
    t0 = start_time(fb)
    assert at(samples, t0 + 0.025)[3] == pytest.approx(1000.0)
    assert at(samples, t0 + 0.1)[3] == pytest.approx(2000.0)
    assert at(samples, t0 + 0.05)[2] == pytest.approx(50.0)
    assert at(samples, t0 + 0.2)[2] == pytest.approx(300.0)
    tick(machine, 50)
    assert X.state == mcl.AxisState.ContinuousMotion
    assert X.sp_vel == pytest.approx(300.0) and X.sp_acc == 0.0


def test_acceleration_profile_scales_and_offsets_its_values():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    table = mcl.MC_TA_REF([(0.1, 1000.0), (0.1, 1000.0)])
    fb = mcl.MC_AccelerationProfile(
        Axis=X, TimeAcceleration=table, AccelerationScale=0.5, Offset=500.0
    )
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done)
    t0 = start_time(fb)
    assert at(samples, t0 + 0.15)[3] == pytest.approx(1000.0)
    assert at(samples, t0 + 0.2)[2] == pytest.approx(150.0)  # ½·0.1·1000 + 0.1·1000


def test_the_table_is_read_on_the_rising_edge():
    machine, X = fresh_axis()
    points = [mcl.MC_TP(0.1, 30.0)]
    table = mcl.MC_TP_REF(points)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=table)
    start = X.POS
    fb(Execute=True)
    points[0].Position = 90.0
    table.NumberOfPairs = 0
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done)
    tick(machine, 100)
    assert_at(X, start + 30.0)


# ------------------------------------------------------------------------------ outputs
def test_done_is_shown_for_one_scan_when_execute_fell_before_the_end():
    machine, X = fresh_axis()
    fb = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=TV)
    fb(Execute=True)
    scans = outputs_after_execute_fell(machine, fb, "Done")
    assert sum(done for (done,) in scans) == 1
    assert not fb.Busy and not fb.Done


def test_done_held_while_execute_is_true():
    machine, X = fresh_axis()
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP)
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done)
    machine.run(lambda: fb(Execute=True), timeout=0.1)
    assert fb.Done and not fb.Busy
    fb(Execute=False)
    assert not fb.Done


def test_a_profile_aborted_by_another_command_reports_aborted_and_never_done():
    machine, X = fresh_axis()
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP)
    halt = mcl.MC_Halt(Axis=X)
    machine.run(lambda: fb(Execute=True), timeout=0.1)
    seen_done = seen_while_taken_over(machine, fb, halt, "Done")
    assert fb.CommandAborted and not fb.Busy and not fb.Active and not seen_done
    assert X.state == mcl.AxisState.StandStill


def test_a_continuous_profile_done_and_then_taken_over_is_not_aborted():
    machine, X = fresh_axis()
    fb = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=TV)
    halt = mcl.MC_Halt(Axis=X)
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done)

    def scan() -> None:
        fb(Execute=True)
        halt(Execute=True)

    run_until(machine, scan, lambda: halt.Done)
    assert fb.Done and not fb.CommandAborted
    assert X.state == mcl.AxisState.StandStill


def test_set_override_does_not_act_on_a_profile():
    machine, X = fresh_axis()
    override = mcl.MC_SetOverride(Axis=X, Enable=True, VelFactor=0.5)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP)

    def scan() -> None:
        override()
        fb(Execute=True)

    assert 0.45 <= done_after(machine, fb, scan) <= 0.45 + PLC + 0.001


# ------------------------------------------------------------------------------ buffering
def test_buffered_profile_waits_for_done_and_counts_from_the_target():
    machine, X = fresh_axis()
    move = mcl.MC_MoveAbsolute(Axis=X, Position=50.0, Velocity=200.0)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP, BufferMode=mcl.MC_BufferMode.Buffered)
    move(Execute=True)
    fb(Execute=True)
    assert fb.Busy and not fb.Active

    def scan() -> None:
        move(Execute=True)
        fb(Execute=True)
        if not move.Done:
            assert not fb.Active

    run_until(machine, scan, lambda: fb.Done)
    assert move.Done and not move.CommandAborted
    tick(machine, 100)
    assert_at(X, 90.0)


@pytest.mark.parametrize("mode", [mcl.MC_BufferMode.BlendingLow, mcl.MC_BufferMode.BlendingHigh])
def test_blending_modes_act_as_buffered(mode):
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    move = mcl.MC_MoveAbsolute(Axis=X, Position=50.0, Velocity=200.0)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=TP, BufferMode=mode)

    def scan() -> None:
        move(Execute=True)
        fb(Execute=True)

    run_until(machine, scan, lambda: fb.Done)
    assert at(samples, start_time(fb))[2] == 0.0  # the move ended at rest
    tick(machine, 100)
    assert_at(X, 90.0)


def test_a_buffered_move_after_a_velocity_profile_starts_at_done_from_its_last_velocity():
    machine, X = fresh_axis()
    samples = recorder(machine, X)
    fb = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=TV)
    move = mcl.MC_MoveAbsolute(
        Axis=X, Position=0.0, Velocity=100.0, BufferMode=mcl.MC_BufferMode.Buffered
    )

    def scan() -> None:
        fb(Execute=True)
        move(Execute=True)

    run_until(machine, scan, lambda: move.Done)
    assert fb.Done and not fb.CommandAborted
    assert isinstance(move._cmd, mcl.command.Command)
    handover = move._cmd.t0
    assert handover == pytest.approx(start_time(fb) + 0.4)
    assert at(samples, handover)[2] == pytest.approx(-50.0)
    tick(machine, 100)
    assert_at(X, 0.0)


def test_a_queued_profile_whose_real_start_breaks_the_limits_ends_in_eparam():
    """Queued behind a velocity motion, the table is checked again where it takes over: from
    rest −200 mm/s in 20 ms is within the maxima, from 400 mm/s it is beyond them."""
    machine, X = fresh_axis()
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=400.0, Acceleration=5000.0)
    table = mcl.MC_TV_REF([(0.02, -200.0)])
    fb = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=table, BufferMode=mcl.MC_BufferMode.Buffered)

    def scan() -> None:
        vel(Execute=True)
        fb(Execute=True)

    run_until(machine, scan, lambda: fb.Error)
    assert fb.ErrorID == mcl.ErrorID.EParam
    run_until(machine, scan, lambda: X.state == mcl.AxisState.StandStill, 2.0)
    assert X.AxErrorID == 0


# ------------------------------------------------------------------------------ refused tables
def _tp(points: Any, **fields: Any) -> mcl.MC_TP_REF:
    return mcl.MC_TP_REF(points, **fields)


REFUSED: list[tuple[str, type[Any], dict[str, Any], int]] = [
    ("no table", mcl.MC_PositionProfile, {"TimePosition": None}, 5),
    ("empty", mcl.MC_PositionProfile, {"TimePosition": _tp([])}, 5),
    ("not a table", mcl.MC_PositionProfile, {"TimePosition": "0.1 10"}, 5),
    (
        "number of pairs 0",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(0.1, 1.0)], NumberOfPairs=0)},
        5,
    ),
    (
        "number of pairs beyond the array",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(0.1, 1.0)], NumberOfPairs=2)},
        5,
    ),
    ("too long", mcl.MC_PositionProfile, {"TimePosition": _tp([(0.01, 0.0)] * (MAX_PAIRS + 1))}, 5),
    (
        "time not increasing",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(0.1, 1.0), (0.0, 2.0)])},
        5,
    ),
    (
        "time going back",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(0.1, 1.0), (-0.05, 2.0)])},
        5,
    ),
    ("time NaN", mcl.MC_PositionProfile, {"TimePosition": _tp([(math.nan, 1.0)])}, 5),
    ("time infinite", mcl.MC_PositionProfile, {"TimePosition": _tp([(math.inf, 1.0)])}, 5),
    ("position NaN", mcl.MC_PositionProfile, {"TimePosition": _tp([(0.1, math.nan)])}, 5),
    ("a point of three", mcl.MC_PositionProfile, {"TimePosition": _tp([(0.1, 1.0, 2.0)])}, 5),
    ("time scale 0", mcl.MC_PositionProfile, {"TimePosition": TP, "TimeScale": 0.0}, 5),
    ("time scale NaN", mcl.MC_PositionProfile, {"TimePosition": TP, "TimeScale": math.nan}, 5),
    (
        "position scale inf",
        mcl.MC_PositionProfile,
        {"TimePosition": TP, "PositionScale": math.inf},
        5,
    ),
    ("offset NaN", mcl.MC_PositionProfile, {"TimePosition": TP, "Offset": math.nan}, 5),
    ("buffer mode invalid", mcl.MC_PositionProfile, {"TimePosition": TP, "BufferMode": 9}, 5),
    (
        "spline beyond Vmax",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(0.1, 100.0)])},
        5,
    ),  # 1.5 · 1000 mm/s at the middle
    (
        "spline beyond max acceleration",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(0.01, 1.0)])},
        5,
    ),  # 6 · 1 mm / (0.01 s)² = 60000 mm/s²
    ("beyond LimPos", mcl.MC_PositionProfile, {"TimePosition": _tp([(2.0, 500.0)])}, 8),
    (
        "spline overshoot beyond LimPos",
        mcl.MC_PositionProfile,
        {"TimePosition": _tp([(1.2, 380.0), (0.6, 395.0)])},
        8,
    ),  # to 401.4 mm between
    (
        "velocity table beyond Vmax",
        mcl.MC_VelocityProfile,
        {"TimeVelocity": mcl.MC_TV_REF([(0.1, 400.0)]), "VelocityScale": 1.5},
        5,
    ),
    (
        "velocity slope beyond max acceleration",
        mcl.MC_VelocityProfile,
        {"TimeVelocity": mcl.MC_TV_REF([(0.005, 200.0)])},
        5,
    ),
    (
        "velocity table beyond LimNeg",
        mcl.MC_VelocityProfile,
        {"TimeVelocity": mcl.MC_TV_REF([(0.1, -400.0), (1.0, -400.0)])},
        8,
    ),
    (
        "velocity value inf",
        mcl.MC_VelocityProfile,
        {"TimeVelocity": mcl.MC_TV_REF([(0.1, math.inf)])},
        5,
    ),
    ("velocity table of positions", mcl.MC_VelocityProfile, {"TimeVelocity": TP}, 5),
    (
        "acceleration beyond max",
        mcl.MC_AccelerationProfile,
        {"TimeAcceleration": mcl.MC_TA_REF([(0.001, 30000.0)])},
        5,
    ),
    (
        "acceleration table reaching beyond Vmax",
        mcl.MC_AccelerationProfile,
        {"TimeAcceleration": mcl.MC_TA_REF([(0.1, 10000.0), (0.1, 10000.0)])},
        5,
    ),
    (
        "acceleration scale NaN",
        mcl.MC_AccelerationProfile,
        {"TimeAcceleration": TA, "AccelerationScale": math.nan},
        5,
    ),
]


@pytest.mark.parametrize(
    ("fb_type", "inputs", "error_id"),
    [pytest.param(t, i, e, id=name) for name, t, i, e in REFUSED],
)
def test_a_refused_table_leaves_a_standing_axis_standing(fb_type, inputs, error_id):
    machine, X = fresh_axis(LimPos=400.0, LimNeg=-100.0)
    fb = fb_type(Axis=X, **inputs)
    before = (X.state, X.sp_pos, X.sp_vel, X.active, len(X.queue))
    for _ in range(20):
        fb(Execute=True)
        exclusive(fb)
        assert fb.Error and fb.ErrorID == error_id
        assert not fb.Busy and not fb.Active
        tick(machine)
    assert (X.state, X.sp_pos, X.sp_vel, X.active, len(X.queue)) == before
    assert X.AxErrorID == 0


@pytest.mark.parametrize(
    ("fb_type", "inputs", "error_id"),
    [pytest.param(t, i, e, id=name) for name, t, i, e in REFUSED[::3]],
)
def test_a_refused_table_leaves_a_moving_axis_moving(fb_type, inputs, error_id):
    machine, X = fresh_axis(LimPos=400.0, LimNeg=-100.0)
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=50.0)
    run_until(machine, lambda: vel(Execute=True), lambda: vel.InVelocity)
    fb = fb_type(Axis=X, **inputs)

    def scan() -> None:
        vel(Execute=True)
        fb(Execute=True)

    machine.run(scan, timeout=0.1)
    assert fb.Error and fb.ErrorID == error_id
    assert vel.InVelocity and vel.Active and not vel.CommandAborted
    assert X.state == mcl.AxisState.ContinuousMotion and X.sp_vel == 50.0


def test_slowing_down_is_checked_against_max_deceleration_speeding_up_against_max_acceleration():
    config = mcl.AxisConfig(max_acceleration=20000.0, max_deceleration=5000.0)
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)}, config=config)
    X = machine.axes["X"]
    configure(X)
    power_on(machine, X)
    up = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.01, 100.0)]))
    run_until(machine, lambda: up(Execute=True), lambda: up.Done or up.Error)
    assert up.Done  # 10000 mm/s² speeding up
    down = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.01, 0.0)]))
    down(Execute=True)
    assert down.Error and down.ErrorID == mcl.ErrorID.EParam  # 10000 mm/s² slowing down
    through = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.1, -100.0)]))
    run_until(machine, lambda: through(Execute=True), lambda: through.Done or through.Error)
    assert through.Done  # 2000 mm/s², slowing down and then speeding up the other way


@pytest.mark.parametrize(
    "fb_type",
    [mcl.MC_PositionProfile, mcl.MC_VelocityProfile, mcl.MC_AccelerationProfile],
)
def test_profiles_are_refused_by_an_axis_that_is_not_ready(fb_type):
    _, X = fresh_axis()
    stop = mcl.MC_Stop(Axis=X)
    stop(Execute=True)
    tables = {"TimePosition": TP, "TimeVelocity": TV, "TimeAcceleration": TA}
    name = next(n for n in tables if n in fb_type.INPUTS)
    fb = fb_type(Axis=X, **{name: tables[name]})
    fb(Execute=True)
    assert fb.Error and fb.ErrorID == mcl.ErrorID.EAxStop


def test_an_st_program_passes_a_struct_of_its_own_as_the_table():
    """PLCopen's example types declared in ST; a velocity profile, then a buffered continuous
    move that starts at its Done."""
    import plc.st

    machine, X = fresh_axis()
    source = """
    TYPE MC_TV : STRUCT DeltaTime : LREAL; Velocity : LREAL; END_STRUCT; END_TYPE
    TYPE MC_TV_REF : STRUCT
        NumberOfPairs : INT; MC_TV_Array : ARRAY[1..3] OF MC_TV;
    END_STRUCT; END_TYPE
    PROGRAM main
    VAR tv : MC_TV_REF; prof : MC_VelocityProfile; cont : MC_MoveContinuousRelative;
        done : BOOL; reached : BOOL; END_VAR
    tv.NumberOfPairs := 2;
    tv.MC_TV_Array[1].DeltaTime := 0.1; tv.MC_TV_Array[1].Velocity := 50.0;
    tv.MC_TV_Array[2].DeltaTime := 0.1; tv.MC_TV_Array[2].Velocity := 0.0;
    prof(Axis := X, Execute := TRUE, TimeVelocity := tv, Done => done);
    cont(Axis := X, Execute := done, Distance := 10.0, Velocity := 100.0, EndVelocity := 20.0,
         InEndVelocity => reached);
    END_PROGRAM
    """
    prog = plc.st.from_source(source, machine)
    machine.run(prog, until=lambda: prog.error or prog.reached, timeout=2.0)
    assert not prog.error
    assert X.sp_vel == pytest.approx(20.0) and X.sp_pos == pytest.approx(15.0, abs=0.1)


def test_on_a_modulo_axis_absolute_positions_count_from_the_period_the_axis_is_in():
    params = mcl.SimAxisParams(stop_neg=-1e6, stop_pos=1e6, lim_neg=-1e6, lim_pos=1e6)
    machine = mcl.SimMachine({"R": params}, config=mcl.AxisConfig(modulo=360.0))
    R = machine.axes["R"]
    configure(R)
    power_on(machine, R)
    turn = mcl.MC_MoveRelative(Axis=R, Distance=400.0, Velocity=300.0)  # into the next period
    run_until(machine, lambda: turn(Execute=True), lambda: turn.Done)
    table = mcl.MC_TP_REF([(0.5, 90.0)], IsAbsolute=True)
    fb = mcl.MC_PositionProfile(Axis=R, TimePosition=table)
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done)
    assert R.sp_pos == pytest.approx(360.0 + 90.0)  # 40° → 90° forward, not a turn back
    assert abs(R.POS - 90.0) <= 0.05


# ------------------------------------------------------------------------------ limits of run time
def _write(axis: mcl.Axis, number: int, value: float | bool) -> None:
    fb = mcl.MC_WriteBoolParameter() if isinstance(value, bool) else mcl.MC_WriteParameter()
    fb(Axis=axis, Execute=True, ParameterNumber=number, Value=value)
    assert fb.Done, fb.ErrorID


def _refused(fb: Any, error_id: int) -> None:
    """One scan of ``fb``: refused with ``error_id``, the axis stands untouched."""
    axis = fb.Axis
    fb(Execute=True)
    assert fb.Error and fb.ErrorID == error_id
    assert axis.state == mcl.AxisState.StandStill and axis.active is None


def _peak_speed(machine: mcl.SimMachine, fb: Any) -> float:
    """Run ``fb`` to Done (never an error); the carriage's highest speed [mm/s]."""
    peak = 0.0

    def scan() -> None:
        nonlocal peak
        fb(Execute=True)
        assert not fb.Error, fb.ErrorID
        peak = max(peak, abs(carriage_mm_s(machine)))

    run_until(machine, scan, lambda: fb.Done)
    return peak


def test_the_software_limits_set_at_run_time_are_the_ones_checked():
    """GT_SetConstant sets no limits (LimPos = LimNeg = 0); GT_SWLim sets them at run time."""
    machine, X = fresh_axis()
    swlim = mcl.GT_SWLim(Axis=X, Execute=True, LimPos=30.0, LimNeg=-500.0)
    swlim()
    assert swlim.Done
    _refused(mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(1.0, 100.0)])), 8)
    # 50 mm at up to 100 mm/s: beyond LimPos 30 on the way
    table = mcl.MC_TV_REF([(0.5, 100.0), (0.5, 0.0)])
    _refused(mcl.MC_VelocityProfile(Axis=X, TimeVelocity=table), 8)
    tick(machine, 50)
    assert X.AxErrorID == 0
    assert carriage_mm(machine) == pytest.approx(0.0, abs=0.05)


def test_a_software_limit_switched_off_no_longer_refuses_a_table():
    """GT_SetConstant's LimPos 30 switched off by MC_WriteBoolParameter 4: the table to +100
    runs as MC_MoveAbsolute(100) would, and the carriage gets there."""
    machine, X = fresh_axis(LimPos=30.0, LimNeg=-500.0)
    _write(X, 4, False)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(1.0, 100.0)]))
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done or fb.Error)
    assert fb.Done and X.AxErrorID == 0
    tick(machine, 100)
    assert carriage_mm(machine) == pytest.approx(100.0, abs=0.05)
    # the negative limit is still on
    _refused(mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(2.0, -650.0)])), 8)


def test_the_application_maxima_limit_the_tables():
    """MaxVelocityAppl 80 mm/s (9), MaxAccelerationAppl 200 mm/s² (13), MaxDecelerationAppl
    100 mm/s² (15): a table beyond them is refused as one beyond the system's maxima (EParam);
    one within them runs, and the carriage stays within MaxVelocityAppl."""
    machine, X = fresh_axis()
    _write(X, 9, 80.0)
    _refused(mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.5, 100.0)])), 5)
    # the spline from rest to rest peaks at 1.5 × 60 mm / 0.5 s = 180 mm/s
    _refused(mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(0.5, 60.0)])), 5)
    # the spline peaks at 1.5 × 40 mm / 1 s = 60 mm/s
    fine = mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(1.0, 40.0)]))
    assert _peak_speed(machine, fine) == pytest.approx(60.0, rel=0.03)
    _write(X, 13, 200.0)
    _write(X, 15, 100.0)
    _refused(mcl.MC_AccelerationProfile(Axis=X, TimeAcceleration=mcl.MC_TA_REF([(0.2, 500.0)])), 5)
    # speeding up at 160 mm/s² is within MaxAccelerationAppl, slowing down at 160 beyond
    # MaxDecelerationAppl
    _refused(
        mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.25, 40.0), (0.25, 0.0)])), 5
    )
    up = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.25, 40.0), (0.5, 0.0)]))
    assert _peak_speed(machine, up) == pytest.approx(40.0, rel=0.03)


def test_a_queued_table_keeps_the_maxima_of_its_execute_edge():
    """MaxVelocityAppl lowered while a table waits behind a move: the table runs as accepted
    (a command samples its limits at its Execute edge)."""
    machine, X = fresh_axis()
    move = mcl.MC_MoveRelative(Axis=X, Distance=20.0, Velocity=100.0)
    table = mcl.MC_TP_REF([(1.0, 40.0)])  # peaks at 60 mm/s
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=table, BufferMode=mcl.MC_BufferMode.Buffered)
    move(Execute=True)
    fb(Execute=True)
    assert fb.Busy and not fb.Active
    _write(X, 9, 50.0)
    peak = 0.0

    def scan() -> None:
        nonlocal peak
        move(Execute=True)
        fb(Execute=True)
        assert not fb.Error, fb.ErrorID
        if fb.Active:
            peak = max(peak, abs(carriage_mm_s(machine)))

    run_until(machine, scan, lambda: fb.Done)
    assert peak == pytest.approx(60.0, rel=0.03)
    tick(machine, 100)
    assert carriage_mm(machine) == pytest.approx(60.0, abs=0.05)


def test_after_a_software_limit_stop_a_table_back_inward_runs():
    """ERRSWN leaves the carriage just beyond SWLimitNeg; after MC_Reset a table back inward
    runs, as MC_MoveAbsolute back inward does (the positions the table moves to are checked,
    not the one the axis stands at), while one going further out is refused."""
    machine, X = fresh_axis()
    swlim = mcl.GT_SWLim(Axis=X, Execute=True, LimPos=150.0, LimNeg=-20.0)
    swlim()
    assert swlim.Done
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0, Direction=mcl.MC_Direction.MC_Negative)
    machine.run(lambda: vel(Execute=True), until=lambda: vel.Error, timeout=3.0)
    assert vel.ErrorID == mcl.ErrorID.ERRSWN
    tick(machine, 100)
    reset = mcl.MC_Reset(Axis=X)
    machine.run(lambda: reset(Execute=True), until=lambda: reset.Done, timeout=1.0)
    beyond = carriage_mm(machine)
    assert beyond < -20.0 and X.state == mcl.AxisState.StandStill
    _refused(mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(1.0, -5.0)])), 8)
    fb = mcl.MC_PositionProfile(Axis=X, TimePosition=mcl.MC_TP_REF([(1.0, 50.0)]))
    run_until(machine, lambda: fb(Execute=True), lambda: fb.Done or fb.Error)
    assert fb.Done and X.AxErrorID == 0
    tick(machine, 100)
    assert carriage_mm(machine) == pytest.approx(beyond + 50.0, abs=0.05)


def test_a_table_may_end_on_a_software_limit_not_a_count_beyond():
    """Limits ±30 mm (encoder count 0.001 mm): absolute tables to +30 and to −30 run and the
    carriage gets there; a table ending one count beyond either limit is refused (Ecil)."""
    machine, X = fresh_axis(LimPos=30.0, LimNeg=-30.0)
    for end in (30.0, -30.0):
        beyond = end + math.copysign(X.config.resolution, end)
        _refused(mcl.MC_PositionProfile(Axis=X, TimePosition=absolute(beyond)), 8)
        _peak_speed(machine, mcl.MC_PositionProfile(Axis=X, TimePosition=absolute(end)))
        assert X.AxErrorID == 0
        tick(machine, 100)
        assert carriage_mm(machine) == pytest.approx(end, abs=0.05)


def absolute(position: float) -> mcl.MC_TP_REF:
    """An absolute position table: to ``position`` [mm] in 1 s."""
    return mcl.MC_TP_REF([(1.0, position)], IsAbsolute=True)


def test_a_table_may_reach_max_velocity_appl_exactly():
    """MaxVelocityAppl 80 mm/s: a velocity table up to exactly 80 and back runs (the carriage
    peaks at 80), one up to 80.01 is refused (EParam)."""
    machine, X = fresh_axis()
    _write(X, 9, 80.0)
    over = mcl.MC_TV_REF([(0.2, 80.01), (0.2, 0.0)])
    _refused(mcl.MC_VelocityProfile(Axis=X, TimeVelocity=over), 5)
    fine = mcl.MC_VelocityProfile(Axis=X, TimeVelocity=mcl.MC_TV_REF([(0.2, 80.0), (0.2, 0.0)]))
    assert _peak_speed(machine, fine) == pytest.approx(80.0, rel=0.03)


def test_a_table_beyond_the_maximum_only_at_its_end_is_refused():
    """MaxVelocityAppl 80 mm/s: a velocity table to 60 then 90 mm/s passes 80 only in its last
    phase; an acceleration table (0 → 400 → 800 mm/s² in 0.1 + 0.2 s) reaches 140 mm/s only at
    its end, beyond MaxVelocityAppl 130. Both are refused (EParam) and the axis stands."""
    machine, X = fresh_axis()
    _write(X, 9, 80.0)
    velocities = mcl.MC_TV_REF([(0.5, 60.0), (0.5, 90.0)])
    _refused(mcl.MC_VelocityProfile(Axis=X, TimeVelocity=velocities), 5)
    _write(X, 9, 130.0)
    accelerations = mcl.MC_TA_REF([(0.1, 400.0), (0.2, 800.0)])
    _refused(mcl.MC_AccelerationProfile(Axis=X, TimeAcceleration=accelerations), 5)
    tick(machine, 50)
    assert carriage_mm(machine) == pytest.approx(0.0, abs=0.05)


def test_an_acceleration_table_within_max_velocity_appl_runs():
    """0 → 400 → −400 → 0 mm/s² in 0.1 + 0.2 + 0.1 s: from rest, 40 mm/s at its peak, back to
    rest 8 mm further on. Within MaxVelocityAppl 100 it runs and the carriage follows."""
    machine, X = fresh_axis()
    _write(X, 9, 100.0)
    table = mcl.MC_TA_REF([(0.1, 400.0), (0.2, -400.0), (0.1, 0.0)])
    fb = mcl.MC_AccelerationProfile(Axis=X, TimeAcceleration=table)
    assert _peak_speed(machine, fb) == pytest.approx(40.0, rel=0.03)
    tick(machine, 100)
    assert carriage_mm(machine) == pytest.approx(8.0, abs=0.05)

"""mcl.trajectory: time-optimal profiles within V/A/D/J and blend_to."""

from __future__ import annotations

import itertools
import math

import pytest

from mcl import trajectory
from mcl.trajectory import Limits, PlanningError, Profile

SLACK = 1e-6
"""Relative slack on every limit."""


def sample(profile: Profile, n: int = 4000) -> list[tuple[float, float, float, float]]:
    """(t, p, v, a) at n + 1 evenly spaced instants from 0 to the end of the profile."""
    out = []
    for i in range(n + 1):
        t = profile.duration * i / n
        p, v, a = profile.at(t)
        out.append((t, p, v, a))
    return out


def check_limits(profile: Profile, limits: Limits) -> None:
    """|v| <= V; |a| <= A while speeding up, <= D while slowing down; |jerk| <= J."""
    samples = sample(profile)
    for _, _, v, a in samples:
        assert abs(v) <= limits.velocity * (1 + SLACK) + 1e-9
        if v * a > 0.0:  # speeding up
            assert abs(a) <= limits.acceleration * (1 + SLACK)
        elif v * a < 0.0:  # slowing down
            assert abs(a) <= limits.deceleration * (1 + SLACK)
        assert abs(a) <= max(limits.acceleration, limits.deceleration) * (1 + SLACK)
    if math.isfinite(limits.jerk):
        for (t0, _, _, a0), (t1, _, _, a1) in itertools.pairwise(samples):
            assert abs(a1 - a0) <= limits.jerk * (t1 - t0) * (1 + SLACK) + 1e-9


def trapezoid_time(distance: float, v: float, acc: float, dec: float) -> float:
    """Duration of the time-optimal rest-to-rest move without a jerk limit (cruise reached)."""
    return distance / v + v / (2 * acc) + v / (2 * dec)


# ---------------------------------------------------------------------------------- move_to
@pytest.mark.parametrize("jerk", [math.inf, 50000.0, 5000.0])
@pytest.mark.parametrize(("p0", "target"), [(0.0, 100.0), (50.0, -30.0), (0.0, 0.5), (10.0, 9.0)])
def test_move_to_reaches_target_at_rest_within_limits(p0, target, jerk):
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=1500.0, jerk=jerk)
    profile = trajectory.move_to(p0, 0.0, 0.0, target, limits)
    p, v, a = profile.at(profile.duration)
    assert p == pytest.approx(target, abs=1e-9)
    assert v == pytest.approx(0.0, abs=1e-9)
    assert a == pytest.approx(0.0, abs=1e-6)
    assert profile.end_position == pytest.approx(target, abs=1e-9)
    assert profile.end_velocity == pytest.approx(0.0, abs=1e-9)
    # past its end the profile stays at the target
    assert profile.at(profile.duration + 1.0)[0] == pytest.approx(target, abs=1e-9)
    check_limits(profile, limits)
    positions = [s[1] for s in sample(profile)]
    assert min(positions) >= min(p0, target) - 1e-9
    assert max(positions) <= max(p0, target) + 1e-9


def test_move_to_plans_where_ruckig_misses_a_valid_input():
    """The delta picker's carry at jerk 4e6 (lowered to the joints' 2291473.292 mm/s³): 591 mm
    from rest at 3000 mm/s and 40000 mm/s² was refused (PlanningError, the group's EParam);
    so were about 2 % of the jerks between 1e6 and 5e6 mm/s³ for 1000 mm."""
    limits = Limits(3000.0, 40000.0, 40000.0, 2291473.292019821)
    profile = trajectory.move_to(0.0, 0.0, 0.0, 590.9743992137422, limits)
    assert profile.end_position == pytest.approx(590.9743992137422, abs=1e-9)
    check_limits(profile, limits)
    durations = []
    for k in range(400):
        jerk = 1.0e6 + 1.0e4 * k
        profile = trajectory.move_to(0.0, 0.0, 0.0, 1000.0, Limits(3000.0, 40000.0, 40000.0, jerk))
        assert profile.end_position == pytest.approx(1000.0, abs=1e-9), jerk
        durations.append(profile.duration)
    assert all(b <= a for a, b in itertools.pairwise(durations))  # more jerk, never slower


def test_move_to_infinite_jerk_is_the_time_optimal_trapezoid():
    limits = Limits(velocity=200.0, acceleration=1000.0, deceleration=1000.0)
    assert limits.jerk == math.inf
    profile = trajectory.move_to(0.0, 0.0, 0.0, 100.0, limits)
    assert profile.duration == pytest.approx(trapezoid_time(100.0, 200.0, 1000.0, 1000.0), rel=1e-6)
    accelerations = [s[3] for s in sample(profile)]
    assert max(accelerations) == pytest.approx(1000.0, rel=1e-6)
    assert min(accelerations) == pytest.approx(-1000.0, rel=1e-6)
    check_limits(profile, limits)


def test_move_to_jerk_limit_makes_the_move_longer_and_smooth():
    fast = trajectory.move_to(0.0, 0.0, 0.0, 100.0, Limits(200.0, 1000.0, 1000.0))
    limits = Limits(200.0, 1000.0, 1000.0, 10000.0)
    smooth = trajectory.move_to(0.0, 0.0, 0.0, 100.0, limits)
    # a / j = 0.1 s of jerk phase at each of the two acceleration ramps: + a/j in total
    assert smooth.duration == pytest.approx(fast.duration + 1000.0 / 10000.0, rel=1e-6)
    check_limits(smooth, limits)
    samples = sample(smooth)
    jerks = [
        (a1 - a0) / (t1 - t0) for (t0, _, _, a0), (t1, _, _, a1) in itertools.pairwise(samples)
    ]
    assert max(jerks) == pytest.approx(10000.0, rel=1e-3)


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_move_to_uses_acceleration_to_speed_up_and_deceleration_to_slow_down(direction):
    limits = Limits(velocity=200.0, acceleration=1000.0, deceleration=250.0)
    profile = trajectory.move_to(0.0, 0.0, 0.0, direction * 100.0, limits)
    assert profile.duration == pytest.approx(trapezoid_time(100.0, 200.0, 1000.0, 250.0), rel=1e-6)
    check_limits(profile, limits)
    speeding = [abs(a) for _, _, v, a in sample(profile) if v * a > 0.0]
    slowing = [abs(a) for _, _, v, a in sample(profile) if v * a < 0.0]
    assert max(speeding) == pytest.approx(1000.0, rel=1e-6)
    assert max(slowing) == pytest.approx(250.0, rel=1e-6)


def test_move_to_from_a_moving_state():
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=2000.0, jerk=50000.0)
    profile = trajectory.move_to(0.0, 150.0, 500.0, 80.0, limits)
    assert profile.at(0.0) == pytest.approx((0.0, 150.0, 500.0))
    assert profile.end_position == pytest.approx(80.0, abs=1e-9)
    assert profile.end_velocity == pytest.approx(0.0, abs=1e-9)
    check_limits(profile, limits)


def test_move_to_ending_with_a_velocity():
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=2000.0)
    profile = trajectory.move_to(0.0, 0.0, 0.0, 100.0, limits, v_end=120.0)
    assert profile.end_position == pytest.approx(100.0, abs=1e-9)
    assert profile.end_velocity == pytest.approx(120.0, abs=1e-9)
    # continues at its final velocity past the end
    assert profile.at(profile.duration + 0.5)[0] == pytest.approx(160.0, abs=1e-6)
    check_limits(profile, limits)


# ---------------------------------------------------------------------------------- velocity_to
@pytest.mark.parametrize("jerk", [math.inf, 20000.0])
def test_velocity_to_reaches_and_keeps_the_velocity(jerk):
    limits = Limits(velocity=150.0, acceleration=1000.0, deceleration=250.0, jerk=jerk)
    profile = trajectory.velocity_to(5.0, 0.0, 0.0, 150.0, limits)
    assert profile.end_velocity == pytest.approx(150.0, abs=1e-9)
    p_end = profile.at(profile.duration)[0]
    p, v, a = profile.at(profile.duration + 2.0)
    assert v == pytest.approx(150.0, abs=1e-9)
    assert a == pytest.approx(0.0, abs=1e-9)
    assert p == pytest.approx(p_end + 300.0, abs=1e-6)
    check_limits(profile, limits)
    if jerk == math.inf:
        assert profile.duration == pytest.approx(150.0 / 1000.0, rel=1e-6)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_velocity_to_slows_down_with_the_deceleration(sign):
    limits = Limits(velocity=150.0, acceleration=1000.0, deceleration=250.0)
    profile = trajectory.velocity_to(0.0, sign * 150.0, 0.0, sign * 50.0, limits)
    assert profile.duration == pytest.approx(100.0 / 250.0, rel=1e-6)
    assert profile.end_velocity == pytest.approx(sign * 50.0, abs=1e-9)
    check_limits(profile, limits)


def test_velocity_reversal_slows_with_deceleration_then_speeds_up_with_acceleration():
    """150 → −150 mm/s: 150/D to stand still, then 150/A to speed up the other way (time-optimal
    within A and D)."""
    limits = Limits(velocity=150.0, acceleration=1000.0, deceleration=250.0)
    profile = trajectory.velocity_to(0.0, 150.0, 0.0, -150.0, limits)
    assert profile.end_velocity == pytest.approx(-150.0, abs=1e-9)
    check_limits(profile, limits)
    assert profile.duration == pytest.approx(150.0 / 250.0 + 150.0 / 1000.0, rel=1e-3)


# ---------------------------------------------------------------------------------- stop
@pytest.mark.parametrize("v0", [100.0, -100.0])
def test_stop_ramps_to_standstill_with_the_deceleration(v0):
    profile = trajectory.stop(0.0, v0, 0.0, 500.0, math.inf)
    assert profile.duration == pytest.approx(0.2, rel=1e-6)
    assert profile.end_velocity == pytest.approx(0.0, abs=1e-9)
    p, v, _ = profile.at(profile.duration + 1.0)
    assert v == pytest.approx(0.0, abs=1e-9)
    assert p == pytest.approx(math.copysign(10.0, v0), abs=1e-9)  # v²/(2D)
    check_limits(profile, Limits(abs(v0), 500.0, 500.0))


def test_stop_jerk_limited_from_an_accelerating_state():
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=2000.0, jerk=40000.0)
    profile = trajectory.stop(0.0, 120.0, 1500.0, 2000.0, 40000.0)
    assert profile.at(0.0) == pytest.approx((0.0, 120.0, 1500.0))
    assert profile.end_velocity == pytest.approx(0.0, abs=1e-9)
    assert profile.at(profile.duration)[2] == pytest.approx(0.0, abs=1e-6)
    check_limits(profile, limits)
    assert min(v for _, _, v, _ in sample(profile)) >= -1e-9


# ---------------------------------------------------------------------------------- blend_to
BACKTRACK = 1e-6
"""Largest backward travel accepted in a forward motion [mm] (a thousandth of a count)."""


def backtrack(positions: list[float]) -> float:
    """How far a forward motion ever falls back behind the furthest point reached so far."""
    furthest, worst = -math.inf, 0.0
    for p in positions:
        furthest = max(furthest, p)
        worst = max(worst, furthest - p)
    return worst


def check_blend(
    profile: Profile, p0: float, target: float
) -> list[tuple[float, float, float, float]]:
    """Ends at target, never beyond it, never backwards (a positive move)."""
    assert profile.end_position == pytest.approx(target, abs=1e-9)
    samples = sample(profile)
    positions = [p for _, p, _, _ in samples]
    assert max(positions) <= target + 1e-9
    assert min(positions) >= p0 - 1e-9
    assert backtrack(positions) <= BACKTRACK, "the motion reverses"
    return samples


def reachable_end_velocity(
    p0: float, v0: float, a0: float, target: float, limits: Limits, wanted: float
) -> float:
    """The highest end velocity up to ``wanted`` (on a 0.5 % grid) that a time-optimal motion
    from (p0, v0, a0) reaches at ``target`` going forward only and never beyond the target."""
    oracle = Limits(
        max(limits.velocity, wanted), limits.acceleration, limits.deceleration, limits.jerk
    )
    for k in range(200, -1, -1):
        v = wanted * k / 200
        try:
            profile = trajectory.move_to(p0, v0, a0, target, oracle, v_end=v)
        except PlanningError:
            continue
        positions = [p for _, p, _, _ in sample(profile, 2000)]
        if max(positions) <= target + 1e-9 and backtrack(positions) <= BACKTRACK:
            return v
    return 0.0


@pytest.mark.parametrize("jerk", [math.inf, 50000.0])
@pytest.mark.parametrize("v_end", [50.0, 100.0, 200.0, 300.0])
def test_blend_to_reaches_the_requested_end_velocity(v_end, jerk):
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=2000.0, jerk=jerk)
    profile = trajectory.blend_to(0.0, 0.0, 0.0, 100.0, limits, v_end)
    assert profile.end_velocity == pytest.approx(v_end, rel=1e-6)
    samples = check_blend(profile, 0.0, 100.0)
    # above the motion's own velocity only at the very end (speeding up into the target)
    assert max(v for _, _, v, _ in samples) <= max(v_end, 200.0) * (1 + SLACK)
    accel = [a for *_, a in samples]
    assert max(accel) <= 2000.0 * (1 + SLACK)
    assert min(accel) >= -2000.0 * (1 + SLACK)


def test_blend_to_too_late_ends_at_target_with_the_reachable_velocity_without_jerk():
    """5 mm before the target at 100 mm/s, 200 mm/s requested: with A = 2000 the axis can reach
    sqrt(100² + 2·2000·5) = 173.2 mm/s at the target (REXYGEN variant 3)."""
    limits = Limits(velocity=100.0, acceleration=2000.0, deceleration=2000.0)
    profile = trajectory.blend_to(95.0, 100.0, 0.0, 100.0, limits, 200.0)
    check_blend(profile, 95.0, 100.0)
    assert profile.end_velocity == pytest.approx(math.sqrt(100.0**2 + 2 * 2000.0 * 5.0), rel=0.01)


def _jerk_limited_reach(v0: float, distance: float, jerk: float) -> float:
    """Largest velocity reachable from (v0, a=0) over ``distance`` ending at a=0 with a pure
    jerk ramp (Δv <= a²/j, so the acceleration limit is not touched)."""
    lo, hi = 0.0, 1000.0
    for _ in range(100):
        dv = 0.5 * (lo + hi)
        t = 2.0 * math.sqrt(dv / jerk)
        if (v0 + dv / 2.0) * t <= distance:
            lo = dv
        else:
            hi = dv
    return v0 + lo


def test_blend_to_too_late_with_jerk_limit_switches_at_reachable_velocity():
    limits = Limits(velocity=100.0, acceleration=2000.0, deceleration=2000.0, jerk=50000.0)
    profile = trajectory.blend_to(95.0, 100.0, 0.0, 100.0, limits, 200.0)
    check_blend(profile, 95.0, 100.0)
    reachable = _jerk_limited_reach(100.0, 5.0, 50000.0)
    assert reachable < 200.0
    assert profile.end_velocity == pytest.approx(reachable, rel=0.01)


@pytest.mark.parametrize("before", [95.0, 99.0, 99.9])
@pytest.mark.parametrize("jerk", [math.inf, 50000.0])
@pytest.mark.parametrize("v_end", [100.0, 200.0])
def test_blend_to_while_decelerating_never_overshoots(v_end, jerk, before):
    """The first move is already braking when the blend arrives: the target is still reached
    exactly, with the highest reachable velocity (REXYGEN variant 3)."""
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=2000.0, jerk=jerk)
    brake = trajectory.move_to(0.0, 0.0, 0.0, 100.0, limits)
    t = next(t for t, p, _, _ in sample(brake) if p >= before)
    p0, v0, a0 = brake.at(t)
    profile = trajectory.blend_to(p0, v0, a0, 100.0, limits, v_end)
    check_blend(profile, p0, 100.0)
    assert profile.end_velocity <= v_end * (1 + SLACK)
    reachable = reachable_end_velocity(p0, v0, a0, 100.0, limits, v_end)
    assert profile.end_velocity >= 0.98 * reachable, f"{reachable:.1f} mm/s were reachable"


def test_blend_to_raises_when_even_stopping_overshoots():
    limits = Limits(velocity=200.0, acceleration=2000.0, deceleration=2000.0)
    with pytest.raises(PlanningError):
        trajectory.blend_to(99.0, 200.0, 0.0, 100.0, limits, 100.0)


# ---------------------------------------------------------------------------------- errors
NAN = math.nan


@pytest.mark.parametrize(
    "limits",
    [
        Limits(NAN, 1000.0, 1000.0),
        Limits(-100.0, 1000.0, 1000.0),
        Limits(100.0, NAN, 1000.0),
        Limits(100.0, -1000.0, 1000.0),
        Limits(100.0, 1000.0, NAN),
        Limits(100.0, 1000.0, -1000.0),
        Limits(100.0, 1000.0, 1000.0, NAN),
        Limits(100.0, 1000.0, 1000.0, -5000.0),
    ],
    ids=["v-nan", "v-neg", "a-nan", "a-neg", "d-nan", "d-neg", "j-nan", "j-neg"],
)
def test_invalid_limits_raise_planning_error(limits):
    assert issubclass(PlanningError, ValueError)
    with pytest.raises(PlanningError):
        trajectory.move_to(0.0, 0.0, 0.0, 10.0, limits)


def test_nan_target_raises_planning_error():
    with pytest.raises(ValueError):
        trajectory.move_to(0.0, 0.0, 0.0, NAN, Limits(100.0, 1000.0, 1000.0))
    with pytest.raises(PlanningError):
        trajectory.move_to(0.0, 0.0, 0.0, NAN, Limits(100.0, 1000.0, 1000.0))


def test_invalid_limits_raise_planning_error_in_velocity_to_and_blend_to():
    with pytest.raises(PlanningError):
        trajectory.velocity_to(0.0, 0.0, 0.0, 50.0, Limits(100.0, NAN, 1000.0))
    with pytest.raises(PlanningError):
        trajectory.blend_to(0.0, 0.0, 0.0, 10.0, Limits(100.0, 1000.0, -1.0), 50.0)


def test_profiles_evaluate_like_ruckig_between_phase_boundaries():
    """The profile's own constant-jerk evaluation agrees with ruckig's ``at_time``: one
    trajectory (its brake pre-profile included) or two laid end to end, shifted by an offset."""
    import random

    import ruckig

    from mcl import trajectory

    rng = random.Random(7)
    worst = 0.0
    for k in range(400):
        jerk = rng.choice([math.inf, rng.uniform(1e3, 1e6)])
        vmax, up, down = rng.uniform(10, 1000), rng.uniform(100, 20000), rng.uniform(100, 20000)
        p0, v0 = rng.uniform(-100, 100), rng.uniform(-2000, 2000)
        a0 = rng.uniform(-1000, 1000) if jerk != math.inf else 0.0
        interface = ruckig.ControlInterface.Position if k % 2 else ruckig.ControlInterface.Velocity
        target, v_end = rng.uniform(-500, 500), rng.uniform(-vmax, vmax) if k % 4 < 2 else 0.0
        try:
            first = trajectory._plan(interface, p0, v0, a0, target, v_end, vmax, up, down, jerk)
            second = trajectory._plan(interface, 0.0, v_end, 0.0, target, 0.0, vmax, up, down, jerk)
        except trajectory.PlanningError:
            continue
        offset, p1 = rng.uniform(-50.0, 50.0), first.at_time(first.duration)[0][0]
        pieces = [(0.0, first, offset), (first.duration, second, p1 + offset)]
        for count in (1, 2):
            profile = trajectory.of_trajectories(pieces[:count])
            for _ in range(20):
                t = rng.uniform(0.0, profile.duration * 1.2)
                start, traj, shift = max(
                    (piece for piece in pieces[:count] if piece[0] <= t), key=lambda x: x[0]
                )
                (p,), (v,), (a,) = traj.at_time(t - start)
                mine = profile.at(t)
                for x, y in zip(mine, (p + shift, v, a), strict=True):
                    worst = max(worst, abs(x - y) / max(1.0, abs(y)))
    assert worst < 1e-9

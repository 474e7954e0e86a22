"""Time-optimal, jerk-limited 1-D motion profiles, and the blending of two motions.

The only module that imports ruckig. Profiles are planned once per command (or re-planned when a
blending command arrives) and then sampled every servo cycle. Units are the caller's user units
(mm, mm/s, mm/s², mm/s³); time in seconds.
"""

from __future__ import annotations

__all__ = [
    "Limits",
    "PlanningError",
    "Profile",
    "Segment",
    "blend_to",
    "move_to",
    "of_trajectories",
    "pass_at",
    "stop",
    "sync_to",
    "velocity_to",
]

import math
import threading
from dataclasses import dataclass
from typing import Any

import ruckig


class PlanningError(ValueError):
    """The requested motion cannot be planned (invalid limits or state); maps to ``EParam``."""


@dataclass(frozen=True, slots=True)
class Limits:
    """Kinematic limits of one motion, all positive.

    Attributes:
        velocity: maximum speed [u/s].
        acceleration: maximum acceleration, used when speeding up [u/s²].
        deceleration: maximum deceleration, used when slowing down [u/s²].
        jerk: maximum jerk [u/s³]; ``math.inf`` plans acceleration-limited profiles.
    """

    velocity: float
    acceleration: float
    deceleration: float
    jerk: float = math.inf


Segment = tuple[float, float, float, float, float]
"""A phase of constant jerk: start time [s], position [u], velocity [u/s], acceleration [u/s²]
and jerk [u/s³] at its start."""


def _segments(t0: float, traj: Any, offset: float) -> list[Segment]:
    """The phases of a ruckig trajectory (its brake pre-profile, then its seven phases) from
    ``t0`` on, positions shifted by ``offset``; the last one never ends (constant velocity)."""
    profile = traj.profiles[0][0]
    if profile.accel.duration > 0.0:
        raise PlanningError("a trajectory with an acceleration post-profile is not expected")
    out: list[Segment] = []
    t = t0
    for part, phases in ((profile.brake, 2), (profile, 7)):
        ts, ps, vs, accs, js = part.t, part.p, part.v, part.a, part.j
        for i in range(phases):
            if ts[i] > 0.0:
                out.append((t, ps[i] + offset, vs[i], accs[i], js[i]))
                t += ts[i]
    out.append((t0 + traj.duration, profile.p[7] + offset, profile.v[7], profile.a[7], 0.0))
    return out


class Profile:
    """A planned motion: position, velocity and acceleration as functions of time.

    Made of phases of constant jerk (:data:`Segment`; the same integration as ruckig's): the
    phases of one or more ruckig trajectories laid end to end (:func:`of_trajectories`), or the
    pieces of a table (:mod:`mcl.profiles`). Past its duration the profile continues at its
    final velocity (used for blending and velocity moves).

    Args:
        segments: the phases in time order, the first starting at 0; the last one never ends.
        duration: when the last phase starts [s].
    """

    __slots__ = ("_segments", "duration", "end_position", "end_velocity")

    def __init__(self, segments: list[Segment], duration: float) -> None:
        self._segments = segments
        self.duration: float = duration
        self.end_position: float = segments[-1][1]
        self.end_velocity: float = segments[-1][2]

    @property
    def segments(self) -> list[Segment]:
        """The phases of constant jerk, in time order (the last one never ends)."""
        return self._segments

    def shifted(self, delta: float) -> Profile:
        """The same motion in a coordinate system moved by ``delta`` [u]."""
        return Profile([(t, p + delta, v, a, j) for t, p, v, a, j in self._segments], self.duration)

    def then(self, other: Profile) -> Profile:
        """This profile followed by ``other`` (which starts where this one ends)."""
        offset = self.duration
        later = [(t + offset, p, v, a, j) for t, p, v, a, j in other._segments]
        return Profile(self._segments[:-1] + later, offset + other.duration)

    def at(self, t: float) -> tuple[float, float, float]:
        """Position [u], velocity [u/s] and acceleration [u/s²] at ``t`` seconds after the start."""
        segments = self._segments
        i = len(segments) - 1
        while i and t < segments[i][0]:
            i -= 1
        start, p, v, a, j = segments[i]
        dt = t - start
        return (
            p + dt * (v + dt * (a / 2.0 + dt * j / 6.0)),
            v + dt * (a + dt * j / 2.0),
            a + dt * j,
        )


def of_trajectories(pieces: list[tuple[float, Any, float]]) -> Profile:
    """The profile of ruckig trajectories laid end to end.

    Args:
        pieces: ``(start time [s], ruckig.Trajectory, position offset [u])`` in order.
    """
    segments: list[Segment] = []
    for t0, traj, offset in pieces:
        if segments:
            segments.pop()  # the previous piece's open end
        segments += _segments(t0, traj, offset)
    t0, last, _ = pieces[-1]
    return Profile(segments, t0 + last.duration)


class _Planner(threading.local):
    """A ruckig planner and its input, one pair per thread (scenes may run in several threads,
    e.g. the viewer's): a module-wide pair would let two threads overwrite each other's input
    mid-plan. Made once per thread and reused, because a ``ruckig.Ruckig`` costs about as much
    to construct as a whole plan.

    Attributes:
        tools: the planner's bound ``calculate`` and its ``InputParameter`` (one attribute: a
            thread-local look-up is dearer than a plain one).
    """

    def __init__(self) -> None:
        inp = ruckig.InputParameter(1)
        inp.target_acceleration = [0.0]  # every plan ends without acceleration
        self.tools = (ruckig.Ruckig(1).calculate, inp)


_planner = _Planner()


def _solve(calculate: Any, inp: Any) -> Any:
    """The trajectory ``calculate`` (a ruckig planner) finds for ``inp``.

    Raises:
        PlanningError: ruckig found none (the message says why).
    """
    traj = ruckig.Trajectory(1)
    try:
        result = calculate(inp, traj)
    except (ruckig.RuckigError, RuntimeError, ValueError) as exc:
        raise PlanningError(str(exc).strip()) from exc
    if result not in (ruckig.Result.Working, ruckig.Result.Finished):
        raise PlanningError(f"no trajectory: {result}")
    return traj


_JERK_RETRIES = (1e-9, 1e-8, 1e-7)
"""ruckig 0.19 finds no profile for about 2 % of valid inputs with a velocity and acceleration
limit reached (a numerical edge of its step 1: 591 mm from rest at 3000 mm/s, 40000 mm/s²,
2291473.292 mm/s³ fails, 1e-9 less jerk plans): the plan is retried with the jerk lowered by
these shares, within the limits and indistinguishable in the motion."""


def _plan(
    interface: Any,
    p0: float,
    v0: float,
    a0: float,
    target: float,
    v_end: float,
    v_max: float,
    acc_up: float,
    acc_down: float,
    jerk: float,
) -> Any:
    calculate, inp = _planner.tools
    inp.control_interface = interface
    inp.current_position = [p0]
    inp.current_velocity = [v0]
    inp.current_acceleration = [a0]
    inp.target_position = [target]
    inp.target_velocity = [v_end]
    inp.max_velocity = [v_max]
    inp.max_acceleration = [acc_up]
    inp.min_acceleration = [-acc_down]
    inp.max_jerk = [jerk]
    for share in _JERK_RETRIES:
        try:
            return _solve(calculate, inp)
        except PlanningError:
            inp.max_jerk = [jerk * (1.0 - share)]
    return _solve(calculate, inp)


def move_to(
    p0: float, v0: float, a0: float, target: float, limits: Limits, v_end: float = 0.0
) -> Profile:
    """Time-optimal motion from the state (p0, v0, a0) to ``target``, arriving with ``v_end``.

    Speeding up uses ``limits.acceleration``, slowing down ``limits.deceleration`` (in the
    direction of the target). ``|v_end|`` must not exceed ``limits.velocity``. A start faster
    than ``limits.velocity`` toward the target (a blend from a faster motion) first slows down to
    it with the deceleration, then continues.

    Raises:
        PlanningError: non-finite or inconsistent inputs.
    """
    direction = 1.0 if target > p0 or (target == p0 and v0 >= 0.0) else -1.0
    vmax = limits.velocity
    if abs(a0) < 1e-9 * max(limits.acceleration, limits.deceleration):
        a0 = 0.0  # numerical residue of a profile's end: would push v0 past its limit
    if abs(v0) > vmax and v0 * direction > 0.0:
        if abs(v0) <= vmax * (1.0 + 1e-9):  # numerically at the limit
            v0 = math.copysign(vmax, v0)
        else:
            slow = velocity_to(p0, v0, a0, math.copysign(vmax, v0), limits)
            if (target - slow.end_position) * direction > 0.0:
                rest = move_to(
                    slow.end_position, math.copysign(vmax, v0), 0.0, target, limits, v_end
                )
                return slow.then(rest)
    acc, dec = limits.acceleration, limits.deceleration
    up, down = (acc, dec) if direction > 0 else (dec, acc)
    traj = _plan(
        ruckig.ControlInterface.Position, p0, v0, a0, target, v_end, vmax, up, down, limits.jerk
    )
    return of_trajectories([(0.0, traj, 0.0)])


def velocity_to(p0: float, v0: float, a0: float, v_target: float, limits: Limits) -> Profile:
    """Time-optimal change of velocity to ``v_target`` (never ends: continues at ``v_target``).

    Slowing down uses ``limits.deceleration``, speeding up ``limits.acceleration``; a reversal
    brakes to standstill first and then speeds up the other way.
    """
    acc, dec = limits.acceleration, limits.deceleration
    vmax = max(limits.velocity, abs(v_target), abs(v0))
    if v0 * v_target < 0.0:
        brake = _plan(
            ruckig.ControlInterface.Velocity, p0, v0, a0, 0.0, 0.0, vmax, dec, dec, limits.jerk
        )
        p1 = brake.at_time(brake.duration)[0][0]
        rise = _plan(
            ruckig.ControlInterface.Velocity,
            0.0,
            0.0,
            0.0,
            0.0,
            v_target,
            vmax,
            acc,
            acc,
            limits.jerk,
        )
        return of_trajectories([(0.0, brake, 0.0), (brake.duration, rise, p1)])
    rate = acc if abs(v_target) > abs(v0) else dec
    traj = _plan(
        ruckig.ControlInterface.Velocity, p0, v0, a0, 0.0, v_target, vmax, rate, rate, limits.jerk
    )
    return of_trajectories([(0.0, traj, 0.0)])


_sync_planner = _Planner()
"""A second planner for :func:`sync_to`, whose input keeps its own velocity floor and duration."""


def sync_to(
    p0: float, v0: float, a0: float, target: float, v_end: float, limits: Limits, duration: float
) -> Profile:
    """Motion from (p0, v0, a0) to ``target`` arriving with ``v_end`` and no acceleration,
    never moving against the direction of ``v_end`` and taking at least ``duration`` [s].

    The profile takes exactly ``duration`` when that is possible within the limits, longer when
    the motion needs more time (the caller compares ``Profile.duration``). Speeding up uses
    ``limits.acceleration``, slowing down ``limits.deceleration``; ``|v_end|`` must not exceed
    ``limits.velocity``.

    Raises:
        PlanningError: no such motion (the target lies behind, or is too close to reach
            ``v_end`` without backing up), or invalid inputs.
    """
    calculate, inp = _sync_planner.tools
    inp.control_interface = ruckig.ControlInterface.Position
    inp.current_position = [p0]
    inp.current_velocity = [v0]
    inp.current_acceleration = [a0]
    inp.target_position = [target]
    inp.target_velocity = [v_end]
    acc, dec, vmax = limits.acceleration, limits.deceleration, limits.velocity
    if v_end >= 0.0:
        inp.max_velocity, inp.min_velocity = [vmax], [0.0]
        inp.max_acceleration, inp.min_acceleration = [acc], [-dec]
    else:
        inp.max_velocity, inp.min_velocity = [0.0], [-vmax]
        inp.max_acceleration, inp.min_acceleration = [dec], [-acc]
    inp.max_jerk = [limits.jerk]
    inp.minimum_duration = duration
    return of_trajectories([(0.0, _solve(calculate, inp), 0.0)])


def stop(p0: float, v0: float, a0: float, deceleration: float, jerk: float) -> Profile:
    """Ramp to standstill with the given deceleration [u/s²] and jerk [u/s³]."""
    return velocity_to(p0, v0, a0, 0.0, Limits(abs(v0) + 1.0, deceleration, deceleration, jerk))


def _monotonic(profile: Profile, start: float, target: float, samples: int = 200) -> bool:
    """The profile moves from ``start`` to ``target`` without overshooting or backing up.

    Checked on samples (ruckig's position extrema do not cover a reversal inside the range):
    positions stay between start and target, the velocity never points backward.
    """
    direction = 1.0 if target >= start else -1.0
    lo, hi = min(start, target), max(start, target)
    tol = 1e-9 * max(1.0, abs(start), abs(target))
    duration = profile.duration
    for k in range(samples + 1):
        p, v, _ = profile.at(duration * k / samples)
        if p < lo - tol or p > hi + tol or v * direction < -1e-9:
            return False
    return True


def _ramp_then_arrive(
    p0: float, v0: float, a0: float, target: float, limits: Limits, v_end: float
) -> Profile | None:
    """Cruise at ``limits.velocity``, then speed up to ``|v_end| > velocity`` ending at target."""
    direction = math.copysign(1.0, v_end)
    cruise = direction * limits.velocity
    ramp = _plan(
        ruckig.ControlInterface.Velocity,
        0.0,
        cruise,
        0.0,
        0.0,
        v_end,
        abs(v_end),
        limits.acceleration,
        limits.acceleration,
        limits.jerk,
    )
    ramp_length = ramp.at_time(ramp.duration)[0][0]
    approach_target = target - ramp_length
    try:
        approach = move_to(p0, v0, a0, approach_target, limits, v_end=cruise)
    except PlanningError:
        return None
    if not _monotonic(approach, p0, approach_target):
        return None
    return approach.then(of_trajectories([(0.0, ramp, approach_target)]))


def pass_at(
    p0: float, v0: float, a0: float, target: float, limits: Limits, v_end: float
) -> Profile:
    """Motion that passes ``target`` with exactly ``v_end`` [u/s] and then goes on at it (the
    profile never ends: it continues at ``v_end``).

    Unlike :func:`blend_to` the end velocity is a must, not a wish: where the axis is too fast
    or too close to arrive with it, it goes past the target, turns and arrives again; a
    ``v_end`` against the direction of the target likewise. ``|v_end|`` above
    ``limits.velocity`` is reached just before the target (the axis cruises at its velocity,
    then speeds up), or, where the distance is too short for that, the motion may use
    ``|v_end|`` as its velocity throughout.

    Raises:
        PlanningError: non-finite or inconsistent inputs.
    """
    if abs(v_end) <= limits.velocity:
        return move_to(p0, v0, a0, target, limits, v_end)
    profile = _ramp_then_arrive(p0, v0, a0, target, limits, v_end)
    if profile is not None:
        return profile
    faster = Limits(abs(v_end), limits.acceleration, limits.deceleration, limits.jerk)
    return move_to(p0, v0, a0, target, faster, v_end)


def blend_to(
    p0: float, v0: float, a0: float, target: float, limits: Limits, v_end: float
) -> Profile:
    """Motion to ``target`` that ends with ``v_end`` when reachable, never overshooting the target.

    Used when a blending command waits behind the current one (docs/reference.md, BufferMode).
    When ``|v_end|`` exceeds the motion's own velocity, the axis cruises at its velocity and speeds
    up just before the target. When the command came too late to reach ``v_end``, the motion still
    ends exactly at the target and switches at the nearest reachable velocity (REXYGEN variant 3).

    Raises:
        PlanningError: even ending at standstill is impossible without overshooting (the axis is
            already too fast for the remaining distance), or the inputs are invalid.
    """

    def feasible(v: float) -> Profile | None:
        if abs(v) > limits.velocity:
            return _ramp_then_arrive(p0, v0, a0, target, limits, v)
        try:
            profile = move_to(p0, v0, a0, target, limits, v_end=v)
        except PlanningError:
            return None
        return profile if _monotonic(profile, p0, target) else None

    best = feasible(v_end)
    if best is not None:
        return best
    # The reachable end velocities need not form an interval starting at 0 (with a jerk limit
    # a braking start can reach 0 and 80…99 mm/s but not 1…50): scan down from v_end on a grid,
    # then refine between the first feasible point and the infeasible one above it.
    steps = 32
    for k in range(1, steps + 1):
        lo = v_end * (1.0 - k / steps)
        candidate = feasible(lo)
        if candidate is not None:
            break
    else:
        raise PlanningError("cannot reach the target without overshooting it")
    best, hi = candidate, v_end * (1.0 - (k - 1) / steps)
    for _ in range(16):
        mid = 0.5 * (lo + hi)
        candidate = feasible(mid)
        if candidate is None:
            hi = mid
        else:
            lo, best = mid, candidate
    return best

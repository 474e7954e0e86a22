"""The path of an axes group: straight elements, corner blends and their planning.

A group move is a straight segment in the space of the members' coordinates [mm]; the motion
*along* the segment is a 1-D jerk-limited profile of the path coordinate ``s`` (0 … length)
planned with :mod:`mcl.trajectory`, and member ``i`` follows ``start_i + s·u_i`` (``u`` = unit
direction), so the tool point stays on the straight line. Ramp elements bring a running path to
a standstill along its current direction (MC_GroupStop, aborts, member faults).

Corner blending (BlendingLow/Previous/Next/High): the first segment is planned to reach the
corner ``c`` with the blending velocity ``v_b`` and zero acceleration, the second starts there
with ``v_b`` (at the corner instant ``t_c``). Let ``d`` be the path coordinate relative to the
corner: ``d < 0`` on the first segment (direction ``u1``), ``d > 0`` on the second (``u2``).
Within ``|d| < D`` (the blend's reach) the path is rounded::

    p = c + (d − g)·u1 + g·u2,   g = 2D·G(x),   x = (d + D) / (2D),
    σ = 10x³ − 15x⁴ + 6x⁵,   G(x) = ∫₀ˣ σ = 5x⁴/2 − 3x⁵ + x⁶

so ``ṗ = ḋ·((1 − σ)·u1 + σ·u2)``: the direction turns smoothly from ``u1`` to ``u2``, position,
velocity and acceleration stay continuous, the path speed does not drop to zero, and the rounded
corner lies on the inside of the turn (every point is ``c − a·u1 + b·u2`` with ``a, b ≥ 0``), so
no axis moves backwards in a blend. ``D = 0.9375·v_b²·max_i(|Δu_i| / A_i)`` (``Δu`` = change of
the unit direction) keeps the blend's own contribution to the acceleration of axis ``i``,
``ḋ²·σ'·|Δu_i| / (2D)``, within ``A_i``, the smaller path acceleration/deceleration of the two
segments (at most the axis' ``max_acceleration``); the reach is lengthened if the sum with the
segments' own acceleration would exceed an axis' ``max_acceleration``. ``v_b`` starts at the
BufferMode's velocity (capped by every member's Vmax along both segments) and is lowered until
the blended path stays within 90 % of the group's corner tolerance
(:attr:`mcl.AxesGroup.corner_tolerance`) of the polyline, checked numerically over the blend (the
rest is left to the axes, which follow the curve of the set point with a few µm of contour
error), and the reach covers at most the second half of the first segment and the first half of
the second. If no blending velocity fits,
or the corner is a reversal (above about 177°), the path stops at the corner as with Buffered.
Collinear segments hand over at ``v_b`` without a window.

This module knows nothing of axes beyond their machine data (:class:`PathPlanner`); running the
path, its queue and the member axes is :mod:`mcl.group`'s job.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Final

from mcl import trajectory
from mcl.command import Status, blend_velocity
from mcl.enums import MC_BufferMode
from mcl.trajectory import Limits, PlanningError, Profile

if TYPE_CHECKING:
    from mcl.axis import AxisConfig

Vector = list[float]
"""A point or direction in the group's coordinates, one component per member [mm]."""

EPS: Final = 1e-9
"""Lengths and speeds below this count as zero [mm], [mm/s]."""
_REVERSAL_COS: Final = -0.999
"""Corners sharper than this cosine (about 177°) are reversals: the path stops there."""
_BLEND_SAMPLES: Final = 32
"""Samples of a blend window when its deviation from the polyline is checked."""
_BLEND_SHRINK: Final = 0.7
"""Factor that lowers the blending velocity while a blend does not fit."""
_BLEND_TRIES: Final = 16
_BLEND_STRETCH: Final = (1.0, 1.3, 1.7, 2.2)
"""Longer blend windows tried while an axis would exceed its max_acceleration."""
_FITS, _TOO_HARD, _NO_FIT = 0, 1, 2
_SETPOINT_SHARE: Final = 0.9
"""Share of the corner tolerance the blended set point may use; the rest is left for the axes'
contour error in the curve, so that the tool itself stays within the tolerance."""


# ---------------------------------------------------------------------- geometry
# dot and along run every servo cycle of a group move: index loops, which compile to native
# arithmetic (zip with strict=True is a generic call with a keyword when compiled)
def dot(a: Sequence[float], b: Sequence[float]) -> float:
    """Scalar product of two vectors of one length (summed in order)."""
    total = 0.0
    for i in range(len(a)):
        total += a[i] * b[i]
    return total


def _norm(a: Sequence[float]) -> float:
    return math.sqrt(dot(a, a))


def along(start: Sequence[float], unit: Sequence[float], s: float) -> Vector:
    """The point ``s`` along ``unit`` from ``start`` (vectors of one length)."""
    return [start[i] + s * unit[i] for i in range(len(start))]


def direction(v: Sequence[float]) -> Vector:
    """Unit vector of ``v`` (zero vector for a standstill)."""
    speed = _norm(v)
    return [x / speed for x in v] if speed > EPS else [0.0] * len(v)


def distance_to_segment(p: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    """Distance of point ``p`` from the segment ``a``–``b`` [mm]."""
    ab = [y - x for x, y in zip(a, b, strict=True)]
    ap = [y - x for x, y in zip(a, p, strict=True)]
    length2 = dot(ab, ab)
    k = 0.0 if length2 <= 0.0 else min(1.0, max(0.0, dot(ap, ab) / length2))
    return _norm([d - k * e for d, e in zip(ap, ab, strict=True)])


def _smooth(x: float) -> tuple[float, float, float]:
    """Quintic step σ(x) = 10x³ − 15x⁴ + 6x⁵ and its first two derivatives (0 ≤ x ≤ 1)."""
    x2 = x * x
    return (
        x2 * x * (10.0 - 15.0 * x + 6.0 * x2),
        30.0 * x2 * (1.0 - x) ** 2,
        60.0 * x * (1.0 - x) * (1.0 - 2.0 * x),
    )


# ---------------------------------------------------------------------- path elements
class PathCommand:
    """The ticket of a group command (MC_MoveLinear*, MC_GroupStop) that its FB reads.

    Attributes:
        buffer_mode: how the command takes over the group (docs/reference.md, BufferMode).
        status: life cycle, written by the group.
        error_id: the error that ended the command (0 = none).
        hold: MC_GroupStop only: its Execute is still TRUE (the group stays in GroupStopping).
    """

    def __init__(self, buffer_mode: MC_BufferMode = MC_BufferMode.Aborting) -> None:
        self.buffer_mode = buffer_mode
        self.status = Status.Queued
        self.error_id = 0
        self.hold = False

    @property
    def busy(self) -> bool:
        """Queued or active."""
        return self.status <= Status.Active


class Blend:
    """A corner blend: the rounding within ``reach`` of the corner (module docstring); it runs
    from about ``begin`` to ``end`` (the end is estimated: the blend lasts until the second
    segment is ``reach`` past the corner)."""

    __slots__ = ("begin", "corner", "end", "reach", "speed", "successor", "t_c", "u_in", "u_out")

    def __init__(
        self,
        corner: Vector,
        u_in: Vector,
        u_out: Vector,
        speed: float,
        t_c: float,
        reach: float,
        begin: float,
        end: float,
        successor: Element,
    ) -> None:
        self.corner = corner
        self.u_in = u_in
        self.u_out = u_out
        self.speed = speed
        self.t_c = t_c
        self.reach = reach
        self.begin = begin
        self.end = end
        self.successor = successor

    @property
    def half(self) -> float:
        """Half the blend's (estimated) duration [s]; 0 for collinear segments."""
        return 0.5 * (self.end - self.begin)

    def line(self, unit: Vector, t: float) -> tuple[Vector, Vector]:
        """Position and velocity on the straight line through the corner at the blending speed."""
        ds = self.speed * (t - self.t_c)
        return along(self.corner, unit, ds), [self.speed * u for u in unit]

    def mix(
        self,
        t: float,
        q1: tuple[Vector, Vector, Vector],
        q2: tuple[Vector, Vector, Vector],
    ) -> tuple[Vector, Vector, Vector]:
        """The blended path at time ``t`` (position, velocity, acceleration vectors) from the
        incoming motion ``q1`` (before ``t_c``) or the outgoing ``q2`` (after it); outside the
        reach it is that motion itself."""
        corner, u1, u2 = self.corner, self.u_in, self.u_out
        p, v, a = q1 if t < self.t_c else q2
        u = u1 if t < self.t_c else u2
        d = dot([p[i] - corner[i] for i in range(len(p))], u)
        reach = self.reach
        if d <= -reach:
            return q1
        if d >= reach:
            return q2
        dd, ddd = dot(v, u), dot(a, u)
        width = 2.0 * reach
        x = (d + reach) / width
        sigma, dsigma, _ = _smooth(x)
        x2 = x * x
        g = width * x2 * x2 * (2.5 - 3.0 * x + x2)
        curve = dd * dd * dsigma / width
        pos, vel, acc = [], [], []
        for i in range(len(u1)):
            mixed = u1[i] + sigma * (u2[i] - u1[i])
            pos.append(corner[i] + (d - g) * u1[i] + g * u2[i])
            vel.append(dd * mixed)
            acc.append(ddd * mixed + curve * (u2[i] - u1[i]))
        return pos, vel, acc


class Element:
    """A straight piece of the path: ``start + s(t)·unit``, ``s`` a 1-D profile [mm].

    ``move`` elements come from MC_MoveLinear* and end at ``end``; ramp elements (``move`` False)
    bring the path to a standstill along ``unit`` (MC_GroupStop, aborts, faults).
    """

    __slots__ = (
        "blend_in",
        "blend_out",
        "completes",
        "end",
        "length",
        "limits",
        "move",
        "params",
        "profile",
        "start",
        "t0",
        "ticket",
        "unit",
    )

    def __init__(
        self,
        start: Vector,
        unit: Vector,
        length: float,
        limits: Limits,
        ticket: PathCommand | None,
        move: bool,
        completes: bool = True,
    ) -> None:
        self.start = start
        self.unit = unit
        self.length = length
        self.end = along(start, unit, length)
        self.limits = limits
        self.ticket = ticket
        self.move = move
        self.completes = completes
        """Reaching the end reports the ticket Done (False for the ramp that precedes a move)."""
        self.params: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
        """FB inputs of a move: Velocity, Acceleration, Deceleration, Jerk (0 = default)."""
        self.profile: Profile | None = None
        self.t0 = 0.0
        self.blend_in: Blend | None = None
        self.blend_out: Blend | None = None

    @property
    def duration(self) -> float:
        """Duration of the planned profile [s]."""
        assert self.profile is not None
        return self.profile.duration

    def at(self, t: float) -> tuple[Vector, Vector, Vector]:
        """Position, velocity, acceleration vectors of the straight motion at time ``t`` [s]."""
        assert self.profile is not None
        s, v, a = self.profile.at(t - self.t0)
        unit = self.unit
        return along(self.start, unit, s), [v * u for u in unit], [a * u for u in unit]

    def point(self, t: float) -> tuple[Vector, Vector, Vector]:
        """Path point at time ``t`` including the corner blends [mm], [mm/s], [mm/s²]."""
        assert self.profile is not None
        s, v, a = self.profile.at(t - self.t0)
        unit = self.unit
        q = (along(self.start, unit, s), [v * u for u in unit], [a * u for u in unit])
        blend = self.blend_out
        if blend is not None and blend.reach > 0.0 and t > blend.begin:
            p2, v2 = blend.line(blend.u_out, t)
            q = blend.mix(t, q, (p2, v2, [0.0] * len(p2)))
        blend = self.blend_in
        if blend is not None and blend.reach > 0.0 and (t < blend.end or s < blend.reach):
            p1, v1 = blend.line(blend.u_in, t)
            q = blend.mix(t, (p1, v1, [0.0] * len(p1)), q)
        return q


def ramp_element(
    p: Vector,
    v: Vector,
    a: Vector,
    limits: Limits,
    ticket: PathCommand | None,
    completes: bool = True,
) -> Element:
    """A ramp to standstill from the state (p, v, a) along the velocity's direction."""
    unit = direction(v)
    profile = trajectory.stop(0.0, _norm(v), dot(a, unit), limits.deceleration, limits.jerk)
    element = Element(p, unit, 0.0, limits, ticket, False, completes)
    element.profile = profile
    element.length = profile.end_position
    element.end = along(p, unit, element.length)
    return element


# ---------------------------------------------------------------------- planning
def _time_at(profile: Profile, t0: float, s: float, t_lo: float, t_hi: float) -> float:
    """The time in [t_lo, t_hi] at which a forward ``profile`` started at ``t0`` reaches ``s``
    (bisection; ``profile.at(t_lo − t0) <= s <= profile.at(t_hi − t0)``) [s]."""
    for _ in range(48):
        mid = 0.5 * (t_lo + t_hi)
        if profile.at(mid - t0)[0] < s:
            t_lo = mid
        else:
            t_hi = mid
    return t_hi


def _blend(
    element: Element,
    nxt: Element,
    profile: Profile,
    t0: float,
    speed: float,
    t_c: float,
    reach: float,
) -> Blend | None:
    """The blend of ``reach`` at the end of ``element`` into ``nxt``, its start and (estimated)
    end found on the incoming profile and on ``nxt`` planned without its own successor; None if
    the reach exceeds half of either segment or lies behind the path's current point."""
    start = element.length - reach
    if reach > 0.5 * element.length or reach > 0.5 * nxt.length or profile.at(0.0)[0] > start:
        return None
    begin = _time_at(profile, t0, start, t0, t_c)
    try:
        after = trajectory.move_to(0.0, speed, 0.0, nxt.length, nxt.limits)
    except PlanningError:
        return None
    end = _time_at(after, t_c, reach, t_c, t_c + after.duration)
    return Blend(element.end, element.unit, nxt.unit, speed, t_c, reach, begin, end, nxt)


class PathPlanner:
    """Plans path elements and corner blends for members with the given machine data.

    Args:
        configs: the members' machine data, in member order.
        vmax: the members' Vmax [mm/s] (None: no servo constants written yet).
        corner_tolerance: largest distance of a blended corner from the polyline [mm].
    """

    __slots__ = ("configs", "corner_tolerance", "vmax")

    def __init__(
        self,
        configs: Sequence[AxisConfig],
        vmax: Sequence[float | None],
        corner_tolerance: float,
    ) -> None:
        self.configs = configs
        self.vmax = vmax
        self.corner_tolerance = corner_tolerance

    def limits(
        self,
        unit: Sequence[float],
        velocity: float,
        acceleration: float,
        deceleration: float,
        jerk: float,
    ) -> Limits:
        """Limits along the path direction ``unit`` from FB inputs (validated, >= 0).

        0 means the default: the smallest default of the members (jerk: of those that have one).
        The result is clamped so that no member exceeds its Vmax, max_acceleration,
        max_deceleration or max_jerk: a limit of member ``i`` allows ``limit_i / |u_i|`` along the
        path (valid values above the maxima are clamped).
        """
        configs = self.configs
        acc = acceleration if acceleration > 0.0 else min(c.acceleration for c in configs)
        dec = deceleration if deceleration > 0.0 else min(c.deceleration for c in configs)
        jerks = [c.jerk for c in configs if c.jerk > 0.0]
        j = jerk if jerk > 0.0 else min(jerks, default=math.inf)
        v = velocity
        for c, vmax, u in zip(configs, self.vmax, unit, strict=True):
            cos = abs(u)
            if cos < EPS:
                continue
            if vmax is not None:
                v = min(v, vmax / cos)
            acc = min(acc, c.max_acceleration / cos)
            dec = min(dec, c.max_deceleration / cos)
            if c.max_jerk > 0.0:
                j = min(j, c.max_jerk / cos)
        return Limits(v, acc, dec, j)

    def move_element(
        self,
        ticket: PathCommand,
        start: Vector,
        target: Vector,
        params: tuple[float, float, float, float],
    ) -> Element:
        """The (unplanned) straight move from ``start`` to ``target`` with the FB inputs
        ``params`` (Velocity, Acceleration, Deceleration, Jerk)."""
        delta = [b - a for a, b in zip(start, target, strict=True)]
        length = _norm(delta)
        unit = [d / length for d in delta] if length > EPS else [0.0] * len(delta)
        element = Element(start, unit, length, self.limits(unit, *params), ticket, True)
        element.end = list(target)
        element.params = params
        return element

    def max_ramp(self, unit: Vector, following: Sequence[bool]) -> Limits:
        """The fastest stop along ``unit`` the members marked in ``following`` allow (their
        max_deceleration)."""
        dec = jerk = math.inf
        for c, use, u in zip(self.configs, following, unit, strict=True):
            if use and abs(u) > EPS:
                dec = min(dec, c.max_deceleration / abs(u))
                if c.max_jerk > 0.0:
                    jerk = min(jerk, c.max_jerk / abs(u))
        if math.isinf(dec):  # nobody moves along ``unit``: any finite ramp will do
            dec = min(
                (c.max_deceleration for c, use in zip(self.configs, following, strict=True) if use),
                default=1.0,
            )
        return Limits(math.inf, dec, dec, jerk)

    def plan(
        self,
        element: Element,
        nxt: Element | None,
        t0: float,
        s0: float,
        v0: float,
        a0: float,
        now: float,
    ) -> tuple[Profile, Blend | None]:
        """Profile of a move from (s0, v0, a0) at ``t0`` and its blend into the queued
        successor ``nxt`` (if any, and if it blends); ``now`` is the current servo instant [s].

        Raises:
            PlanningError: the move cannot be planned.
        """
        limits = element.limits
        if (
            nxt is None
            or not nxt.move
            or nxt.ticket is element.ticket
            or nxt.ticket is None
            or nxt.ticket.buffer_mode < MC_BufferMode.BlendingLow
            or element.length <= EPS
            or nxt.length <= EPS
            or dot(element.unit, nxt.unit) <= _REVERSAL_COS
        ):
            return trajectory.move_to(s0, v0, a0, element.length, limits), None
        u1, u2 = element.unit, nxt.unit
        v_b = blend_velocity(nxt.ticket.buffer_mode, limits.velocity, nxt.limits.velocity, 1.0, 1.0)
        v_b = min(v_b, self.limits(u1, v_b, 0, 0, 0).velocity)
        v_b = min(v_b, self.limits(u2, v_b, 0, 0, 0).velocity)
        budget = min(
            limits.acceleration,
            limits.deceleration,
            nxt.limits.acceleration,
            nxt.limits.deceleration,
        )
        k = 0.0
        for c, a, b in zip(self.configs, u1, u2, strict=True):
            k = max(k, abs(b - a) / min(budget, c.max_acceleration))
        straight = k * budget < 1e-9
        for _ in range(_BLEND_TRIES):
            try:
                profile = trajectory.blend_to(s0, v0, a0, element.length, limits, v_b)
            except PlanningError:
                break
            speed = profile.end_velocity
            if speed <= EPS:
                break
            t_c = t0 + profile.duration
            if straight:
                return profile, Blend(element.end, u1, u2, speed, t_c, 0.0, t_c, t_c, nxt)
            for stretch in _BLEND_STRETCH:
                reach = 0.9375 * speed * speed * k * stretch
                blend = _blend(element, nxt, profile, t0, speed, t_c, reach)
                if blend is None:
                    break  # a longer reach would not fit the segments either
                verdict = self._blend_fits(element, nxt, profile, t0, blend, now)
                if verdict == _FITS:
                    return profile, blend
                if verdict != _TOO_HARD:
                    break  # a longer window would only deviate more
            v_b = _BLEND_SHRINK * speed
        return trajectory.move_to(s0, v0, a0, element.length, limits), None

    def _blend_fits(
        self,
        element: Element,
        nxt: Element,
        profile: Profile,
        t0: float,
        blend: Blend,
        now: float,
    ) -> int:
        """Whether a blend is acceptable: ``_FITS``, ``_TOO_HARD`` (an axis would exceed its
        max_acceleration: try a longer reach) or ``_NO_FIT``.

        It fits when it starts in the future and after the element's own incoming blend (its
        reach covers at most the second half of ``element`` and the first half of ``nxt``,
        :func:`_blend`; the motion on ``nxt`` is estimated by planning it without its own
        successor), keeps the path within
        :data:`_SETPOINT_SHARE` of :attr:`corner_tolerance` of the polyline and every axis within
        its max_acceleration.
        """
        if blend.begin <= now or blend.begin < t0:
            return _NO_FIT
        if element.blend_in is not None and blend.begin < element.blend_in.end:
            return _NO_FIT
        try:
            after = trajectory.move_to(0.0, blend.speed, 0.0, nxt.length, nxt.limits)
        except PlanningError:
            return _NO_FIT
        u1, u2 = element.unit, nxt.unit
        width = 2.0 * blend.half
        tolerance = self.corner_tolerance * _SETPOINT_SHARE
        worst = 0.0
        too_hard = False
        times = [blend.begin + width * k / _BLEND_SAMPLES for k in range(1, _BLEND_SAMPLES)]
        for t in (*times, blend.t_c):
            if t <= blend.t_c:
                s, v, a = profile.at(t - t0)
                p2, v2 = blend.line(u2, t)
                q1 = (along(element.start, u1, s), [v * u for u in u1], [a * u for u in u1])
                q2 = (p2, v2, [0.0] * len(u2))
            else:
                p1, v1 = blend.line(u1, t)
                s, v, a = after.at(t - blend.t_c)
                q1 = (p1, v1, [0.0] * len(u1))
                q2 = (along(nxt.start, u2, s), [v * u for u in u2], [a * u for u in u2])
            p, _, acc = blend.mix(t, q1, q2)
            worst = max(
                worst,
                min(
                    distance_to_segment(p, element.start, element.end),
                    distance_to_segment(p, nxt.start, nxt.end),
                ),
            )
            if worst > tolerance:
                return _NO_FIT
            for c, ai in zip(self.configs, acc, strict=True):
                if abs(ai) > c.max_acceleration:
                    too_hard = True
        return _TOO_HARD if too_hard else _FITS


__all__ = [
    "EPS",
    "Blend",
    "Element",
    "PathCommand",
    "PathPlanner",
    "Vector",
    "along",
    "direction",
    "distance_to_segment",
    "dot",
    "ramp_element",
]

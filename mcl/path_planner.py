"""Planning a group path: the limits along each element, the look-ahead over the queued
elements, the profiles and the corner blends between them (the shapes: :mod:`mcl.path`,
:mod:`mcl.geometry`).

**Limits along a line** (direction cosines ``u_i``): a limit of member ``i`` allows
``limit_i / |u_i|`` along the path; the FB's Velocity, Acceleration, Deceleration and Jerk act
along the path (0 = the smallest default of the members) and are clamped so that no member
exceeds its Vmax, max_acceleration, max_deceleration or max_jerk.

**Limits along an arc** (radius R; a helix has the curvature ``κ = R·(Θ/L)²`` and the rate
``ρ = |dK/ds| = R·(Θ/L)³``; a plane circle κ = 1/R, ρ = 1/R²): the members' acceleration is
the vector ``a = s̈·T + ṡ²·κ·N`` and their jerk ``j = s⃛·T + 3·ṡ·s̈·κ·N + ṡ³·dK/ds``, and every
member's component is at most the vector's length. So the FB's Acceleration ``A`` and
Deceleration (each lowered to the smallest max_acceleration and max_deceleration of the members
that move) and its Jerk ``J`` (lowered to the members' max_jerk) bound these lengths:

- the velocity on the arc is at most ``√(0.7·A·R_κ)`` (the centripetal acceleration ``ṡ²·κ``
  uses at most 70 % of ``A``, :data:`CENTRIPETAL_SHARE`) and ``(0.5·J/ρ)^(1/3)`` (the
  centripetal jerk ``ṡ³·ρ`` at most half of ``J``, :data:`CURVE_JERK_SHARE`) besides the
  members' Vmax: this is where the path slows for a tight arc;
- at that velocity ``v``, the acceleration along the path is ``√(A² − (v²·κ)²)``, and with
  ``J_rest = J − v³·ρ`` at most ``J_rest / (6·v·κ)`` (the coupling ``3·ṡ·s̈·κ`` takes at most
  half of ``J_rest``); the jerk along the path is what is left, ``J_rest − 3·v·κ·s̈_max``.

A profile of ``s`` within these limits keeps every member within its own velocity, acceleration
and jerk limits; on an arc the path never runs faster than the arc's own Velocity (a blending
velocity above it is lowered). MC_MoveDirect* (``direct``) bind every member's own motion:
member ``i`` may use ``min(input, its maximum)`` of each, the member that needs longest runs at
them and the others are slowed so that all start and end together.

**Look-ahead** (:meth:`PathPlanner.entry_speeds`): every queued element gets the fastest speed
it may be entered with, from the last queued one backwards (the path stops at the end of the
last): from that speed the element can still slow down, within its deceleration and jerk, to
what the corner into the next one allows.

**Corner blends** (:mod:`mcl.path` for the shape): the blending velocity ``v_b`` starts at the
BufferMode's velocity (capped by both elements' caps and the second's look-ahead speed); the
reach is the larger of ``0.9375·v_b²·max_i(|Δu_i| / A_i)`` (the turn of direction ``Δu``: its
acceleration within ``A_i``, the smaller path acceleration/deceleration of the two elements, at
most the member's max_acceleration) and ``2.8125·v_b³·|ΔK| / J`` (the step ``ΔK`` of the
curvature vector between the elements, e.g. a line into a tangent arc: the jerk of spreading it
over the blend within the path jerk ``J``); it is lengthened
if a member would exceed its max_acceleration (or max_jerk). ``v_b`` is lowered until the
blended path stays within 90 % of the corner tolerance (the group's, or the second command's
TransitionParameter) of the elements, checked numerically over the blend (the rest is left to
the axes, which follow the curve of the set point with a few µm of contour error), and the
reach covers at most the second half of the first element and the first half of the second.
If no blending velocity fits, or the corner is a reversal (above about 177°), the path stops at
the corner as with Buffered. Elements that meet without a turn or a change of curvature hand
over at ``v_b`` without a window.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Final

from mcl import trajectory
from mcl.command import blend_velocity
from mcl.enums import MC_BufferMode
from mcl.geometry import EPS, Geometry, Line, norm, sub
from mcl.path import Blend, Element, Move, PathCommand
from mcl.trajectory import Limits, PlanningError, Profile

if TYPE_CHECKING:
    from mcl.axis import AxisConfig
    from mcl.joint_check import JointCheck

CENTRIPETAL_SHARE: Final = 0.7
"""Share of the acceleration an arc's centripetal acceleration may take at its velocity."""
CURVE_JERK_SHARE: Final = 0.5
"""Share of the jerk an arc's centripetal jerk ``ṡ³·ρ`` may take at its velocity."""
_REVERSAL_COS: Final = -0.999
"""Corners sharper than this cosine (about 177°) are reversals: the path stops there."""
_BLEND_SAMPLES: Final = 48
"""Samples of a blend window when its deviation and dynamics are checked."""
_BLEND_SHRINK: Final = 0.7
"""Factor that lowers the blending velocity while a blend does not fit."""
_BLEND_TRIES: Final = 16
_BLEND_STRETCH: tuple[float, ...] = (1.0, 1.3, 1.7, 2.2)
"""Longer blend windows tried while a member would exceed its max_acceleration or max_jerk."""
_FITS, _TOO_HARD, _NO_FIT = 0, 1, 2
_SETPOINT_SHARE: Final = 0.9
"""Share of the corner tolerance the blended set point may use; the rest is left for the axes'
contour error in the curve, so that the tool itself stays within the tolerance."""
_BEND_JERK: Final = 2.8125
"""The blend's jerk at its middle is ``2.8125·v³·|ΔK| / D`` (3·σ'(½)/2, the curvature term and
the two residual terms of :class:`mcl.path.Blend`): the reach that keeps it within ``J``."""
_TANGENT: Final = 1e-9
"""Elements whose unit tangents [1] and curvature vectors [1/mm] differ less than this meet
without a corner."""


def brake_distance(v: float, w: float, deceleration: float, jerk: float) -> float:
    """Length of a symmetric jerk-limited slow-down from ``v`` to ``w`` <= ``v`` [mm]."""
    dv = v - w
    if math.isinf(jerk):
        return (v * v - w * w) / (2.0 * deceleration)
    if dv >= deceleration * deceleration / jerk:
        return 0.5 * (v + w) * (dv / deceleration + deceleration / jerk)
    return (v + w) * math.sqrt(dv / jerk)


def brake_speed(length: float, w: float, deceleration: float, jerk: float) -> float:
    """The fastest speed from which a slow-down to ``w`` fits in ``length`` [mm/s]."""
    hi = w + math.sqrt(2.0 * deceleration * length) + 1.0
    while brake_distance(hi, w, deceleration, jerk) < length:
        hi *= 2.0
    lo = w
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        if brake_distance(mid, w, deceleration, jerk) < length:
            lo = mid
        else:
            hi = mid
    return lo


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
    the reach exceeds half of either element or lies behind the path's current point."""
    start = element.length - reach
    if reach > 0.5 * element.length or reach > 0.5 * nxt.length or profile.at(0.0)[0] > start:
        return None
    begin = _time_at(profile, t0, start, t0, t_c)
    try:
        after = trajectory.move_to(0.0, speed, 0.0, nxt.length, nxt.limits)
    except PlanningError:
        return None
    end = _time_at(after, t_c, reach, t_c, t_c + after.duration)
    return Blend(element.geometry, nxt.geometry, speed, t_c, reach, begin, end, nxt)


class PathPlanner:
    """Plans path elements and corner blends for members with the given machine data.

    Args:
        configs: the members' machine data, in member order.
        vmax: the members' Vmax [mm/s] (None: no servo constants written yet).
        corner_tolerance: largest distance of a blended corner from the path [mm].
        joints: the limits of a robot's joints behind a Cartesian path (its corner blends keep
            them too), None without a kinematic transformation.
    """

    __slots__ = ("configs", "corner_tolerance", "joints", "vmax")

    def __init__(
        self,
        configs: Sequence[AxisConfig],
        vmax: Sequence[float | None],
        corner_tolerance: float,
        joints: JointCheck | None = None,
    ) -> None:
        self.configs = configs
        self.vmax = vmax
        self.corner_tolerance = corner_tolerance
        self.joints = joints

    # ------------------------------------------------------------------ limits
    def limits(
        self,
        geometry: Geometry,
        velocity: float,
        acceleration: float,
        deceleration: float,
        jerk: float,
        direct: bool = False,
    ) -> tuple[Limits, float, float]:
        """Limits along ``geometry`` from FB inputs (validated, >= 0; 0 = the default), the
        cap: the fastest the piece may be passed [mm/s], and the bound of the path's jerk
        vector [mm/s³] (on a line the jerk along it; module docstring)."""
        if direct:
            return self._direct(geometry.share, velocity, acceleration, deceleration, jerk)
        configs = self.configs
        acc = acceleration if acceleration > 0.0 else min(c.acceleration for c in configs)
        dec = deceleration if deceleration > 0.0 else min(c.deceleration for c in configs)
        jerks = [c.jerk for c in configs if c.jerk > 0.0]
        j = jerk if jerk > 0.0 else min(jerks, default=math.inf)
        cap = math.inf
        curved = geometry.curvature > 0.0
        for c, vmax, share in zip(configs, self.vmax, geometry.share, strict=True):
            if share < EPS:
                continue
            if vmax is not None:
                cap = min(cap, vmax / share)
            scale = 1.0 if curved else share  # a curve: bound the vectors' lengths
            limit = min(c.max_acceleration, c.max_deceleration) if curved else c.max_acceleration
            acc = min(acc, limit / scale)
            dec = min(dec, (limit if curved else c.max_deceleration) / scale)
            if c.max_jerk > 0.0:
                j = min(j, c.max_jerk / scale)
        if not curved:
            return Limits(min(velocity, cap), acc, dec, j), cap, j
        limits, cap = self._curve(geometry, min(velocity, cap), acc, dec, j)
        return limits, cap, j

    @staticmethod
    def _curve(
        geometry: Geometry, velocity: float, acc: float, dec: float, jerk: float
    ) -> tuple[Limits, float]:
        """Limits along a curve whose acceleration and jerk vectors stay within ``acc``/``dec``
        and ``jerk`` (module docstring); the cap is the velocity on the curve."""
        kappa, rate = geometry.curvature, geometry.curvature_rate
        v = min(velocity, math.sqrt(CENTRIPETAL_SHARE * min(acc, dec) / kappa))
        if math.isfinite(jerk):
            v = min(v, (CURVE_JERK_SHARE * jerk / rate) ** (1.0 / 3.0))
        normal = v * v * kappa
        up = math.sqrt(acc * acc - normal * normal)
        down = math.sqrt(dec * dec - normal * normal)
        j = jerk
        if math.isfinite(jerk):
            rest = jerk - v**3 * rate
            if v > 0.0:
                up = min(up, rest / (6.0 * v * kappa))
                down = min(down, rest / (6.0 * v * kappa))
            j = rest - 3.0 * v * kappa * max(up, down)
        return Limits(v, up, down, j), v

    def _direct(
        self,
        share: Sequence[float],
        velocity: float,
        acceleration: float,
        deceleration: float,
        jerk: float,
    ) -> tuple[Limits, float, float]:
        """Limits of a synchronized point-to-point move: every member within the inputs and its
        own maxima (module docstring)."""
        v = acc = dec = j = cap = math.inf
        for c, vmax, u in zip(self.configs, self.vmax, share, strict=True):
            if u < EPS:
                continue
            top = vmax if vmax is not None else math.inf
            cap = min(cap, top / u)
            v = min(v, min(velocity, top) / u)
            acc = min(acc, min(acceleration or c.acceleration, c.max_acceleration) / u)
            dec = min(dec, min(deceleration or c.deceleration, c.max_deceleration) / u)
            axis_jerk = jerk or c.jerk or math.inf
            if c.max_jerk > 0.0:
                axis_jerk = min(axis_jerk, c.max_jerk)
            j = min(j, axis_jerk / u)
        if math.isinf(acc):  # nothing moves
            return self.limits(geometry_of(share), velocity, acceleration, deceleration, jerk)
        return Limits(v, acc, dec, j), cap, j

    def element(self, ticket: PathCommand, start: Sequence[float], move: Move) -> Element:
        """The (unplanned) element of ``move`` from ``start``.

        Raises:
            mcl.geometry.GeometryError: an arc's description fits no arc from ``start``.
        """
        geometry = move.geometry(start)
        limits, cap, jerk = self.limits(geometry, *move.params, direct=move.direct)
        element = Element(geometry, limits, cap, ticket, move)
        element.jerk = jerk
        return element

    def stop_limits(
        self, geometry: Geometry, speed: float, deceleration: float, jerk: float
    ) -> Limits:
        """Deceleration and jerk along ``geometry`` for a stop from ``speed`` with the inputs
        (0 = defaults)."""
        return self.limits(geometry, max(speed, EPS), deceleration, deceleration, jerk)[0]

    def max_ramp(self, geometry: Geometry, following: Sequence[bool], speed: float) -> Limits:
        """The fastest stop along ``geometry`` from ``speed`` the members marked in ``following``
        allow (their max_deceleration)."""
        dec = jerk = math.inf
        curved = geometry.curvature > 0.0
        for c, use, u in zip(self.configs, following, geometry.share, strict=True):
            if use and u > EPS:
                scale = 1.0 if curved else u
                dec = min(dec, c.max_deceleration / scale)
                if c.max_jerk > 0.0:
                    jerk = min(jerk, c.max_jerk / scale)
        if math.isinf(dec):  # nobody moves along it: any finite ramp will do
            dec = min(
                (c.max_deceleration for c, use in zip(self.configs, following, strict=True) if use),
                default=1.0,
            )
            return Limits(math.inf, dec, dec, jerk)
        if curved:
            return self._curve(geometry, max(speed, EPS), dec, dec, jerk)[0]
        return Limits(math.inf, dec, dec, jerk)

    # ------------------------------------------------------------------ look-ahead
    @staticmethod
    def entry_speeds(queue: Sequence[Element]) -> None:
        """Set every queued element's ``entry_max`` (module docstring), the last first."""
        exit_speed = 0.0
        for i in range(len(queue) - 1, -1, -1):
            element = queue[i]
            limits = element.limits
            entry = brake_speed(element.length, exit_speed, limits.deceleration, limits.jerk)
            element.entry_max = min(entry, element.cap)
            exit_speed = 0.0
            if i > 0 and _blends(queue[i - 1], element):
                before = queue[i - 1]
                mode_speed = blend_velocity(
                    element.mode, before.limits.velocity, limits.velocity, 1.0, 1.0
                )
                exit_speed = min(mode_speed, before.cap, element.entry_max)

    # ------------------------------------------------------------------ profiles and blends
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
        if nxt is None or not _blends(element, nxt):
            return trajectory.move_to(s0, v0, a0, element.length, limits), None
        g1, g2 = element.geometry, nxt.geometry
        u1, u2 = g1.tangent(g1.length), g2.tangent(0.0)
        if sum(a * b for a, b in zip(u1, u2, strict=True)) <= _REVERSAL_COS:
            return trajectory.move_to(s0, v0, a0, element.length, limits), None
        v_b = blend_velocity(nxt.mode, limits.velocity, nxt.limits.velocity, 1.0, 1.0)
        v_b = min(v_b, element.cap, nxt.cap, nxt.entry_max)
        tolerance = self.corner_tolerance
        move = nxt.move
        if move is not None and move.tolerance > 0.0:
            tolerance = move.tolerance
        longest = move.reach if move is not None and move.reach > 0.0 else math.inf
        for _ in range(_BLEND_TRIES):
            try:
                profile = trajectory.blend_to(s0, v0, a0, element.length, limits, v_b)
            except PlanningError:
                break
            speed = profile.end_velocity
            if speed <= EPS:
                break
            t_c = t0 + profile.duration
            if _smooth_corner(g1, g2):
                return profile, Blend(g1, g2, speed, t_c, 0.0, t_c, t_c, nxt)
            found = self._fit(element, nxt, profile, t0, speed, t_c, now, tolerance, longest)
            if found is not None:
                return profile, found
            v_b = _BLEND_SHRINK * speed
        return trajectory.move_to(s0, v0, a0, element.length, limits), None

    def _corner(self, element: Element, nxt: Element) -> tuple[float, float]:
        """The turn of direction (``max_i |Δu_i| / A_i``, [s²/mm]) and the step of the curvature
        vector over the path jerk (``|ΔK| / J``, [s³/mm²]) at the corner into ``nxt``."""
        g1, g2 = element.geometry, nxt.geometry
        _, u1, k1 = g1.frame(g1.length)
        _, u2, k2 = g2.frame(0.0)
        a, b = element.limits, nxt.limits
        budget = min(a.acceleration, a.deceleration, b.acceleration, b.deceleration)
        turn = 0.0
        for c, x, y in zip(self.configs, u1, u2, strict=True):
            turn = max(turn, abs(y - x) / min(budget, c.max_acceleration))
        jerk = min(element.jerk, nxt.jerk)
        bend = norm(sub(k2, k1)) / jerk if math.isfinite(jerk) else 0.0
        return turn, bend

    def _fit(
        self,
        element: Element,
        nxt: Element,
        profile: Profile,
        t0: float,
        speed: float,
        t_c: float,
        now: float,
        tolerance: float,
        longest: float,
    ) -> Blend | None:
        """The blend at ``speed`` with the shortest reach (from the estimate, lengthened while a
        member is pushed too hard) that fits, or None."""
        turn, bend = self._corner(element, nxt)
        estimate = max(0.9375 * speed * speed * turn, _BEND_JERK * speed**3 * bend)
        for stretch in _BLEND_STRETCH:
            reach = min(estimate * stretch, longest)
            blend = _blend(element, nxt, profile, t0, speed, t_c, reach)
            if blend is None:
                return None  # a longer reach would not fit the elements either
            verdict = self._blend_fits(element, nxt, profile, t0, blend, now, tolerance)
            if verdict == _FITS:
                return blend
            if verdict != _TOO_HARD or reach >= longest:
                return None  # a longer window would only deviate more
        return None

    def _blend_fits(
        self,
        element: Element,
        nxt: Element,
        profile: Profile,
        t0: float,
        blend: Blend,
        now: float,
        tolerance: float,
    ) -> int:
        """Whether a blend is acceptable: ``_FITS``, ``_TOO_HARD`` (a member would exceed its
        max_acceleration or max_jerk: try a longer reach) or ``_NO_FIT``.

        It fits when it starts in the future and after the element's own incoming blend (its
        reach covers at most the second half of ``element`` and the first half of ``nxt``,
        :func:`_blend`; the motion on ``nxt`` is estimated by planning it without its own
        successor), keeps the path within :data:`_SETPOINT_SHARE` of ``tolerance`` of the
        elements and every member within its max_acceleration and max_jerk (and, on a
        Cartesian path, every joint within its Vmax and max_acceleration: :attr:`joints`).
        """
        if blend.begin <= now or blend.begin < t0:
            return _NO_FIT
        if element.blend_in is not None and blend.begin < element.blend_in.end:
            return _NO_FIT
        try:
            after = trajectory.move_to(0.0, blend.speed, 0.0, nxt.length, nxt.limits)
        except PlanningError:
            return _NO_FIT
        step = (blend.end - blend.begin) / _BLEND_SAMPLES
        limit = tolerance * _SETPOINT_SHARE
        too_hard = False
        last: tuple[float, list[float]] | None = None
        times = [blend.begin + step * k for k in range(1, _BLEND_SAMPLES)]
        for t in sorted((*times, blend.t_c)):
            if t <= blend.t_c:
                s, v, a = profile.at(t - t0)
                d = s - element.length
            else:
                d, v, a = after.at(t - blend.t_c)
            p, vel, acc = blend.mix(d, v, a)
            deviation = min(element.geometry.distance(p), nxt.geometry.distance(p))
            if deviation > limit:
                return _NO_FIT
            for i, c in enumerate(self.configs):
                jerk = 0.0
                if last is not None and t > last[0]:
                    jerk = abs(acc[i] - last[1][i]) / (t - last[0])
                if abs(acc[i]) > c.max_acceleration or 0.0 < c.max_jerk < jerk:
                    too_hard = True
            if self.joints is not None and self.joints.exceeds(p, vel, acc):
                too_hard = True
            last = (t, acc)
        return _TOO_HARD if too_hard else _FITS


def _smooth_corner(g1: Geometry, g2: Geometry) -> bool:
    """The pieces meet without a turn of direction or a step of curvature (within
    :data:`_TANGENT`): no blend window is needed."""
    _, u1, k1 = g1.frame(g1.length)
    _, u2, k2 = g2.frame(0.0)
    return norm(sub(u2, u1)) < _TANGENT and norm(sub(k2, k1)) < _TANGENT


def _blends(element: Element, nxt: Element) -> bool:
    """``nxt`` blends with ``element`` at their corner (both are moves of some length in the same
    space, ``nxt`` asks for a Blending mode)."""
    return (
        element.move is not None
        and nxt.move is not None
        and nxt.ticket is not None
        and element.joint == nxt.joint
        and nxt.mode >= MC_BufferMode.BlendingLow
        and element.length > EPS
        and nxt.length > EPS
    )


def geometry_of(share: Sequence[float]) -> Geometry:
    """A zero-length line in a space of ``len(share)`` members (limits without clamping)."""
    zero = [0.0] * len(share)
    return Line(zero, list(zero))


__all__ = [
    "CENTRIPETAL_SHARE",
    "CURVE_JERK_SHARE",
    "PathPlanner",
    "brake_distance",
    "brake_speed",
]

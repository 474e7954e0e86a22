"""The path of an axes group: its elements (lines and arcs run along 1-D profiles), the corner
blends between them and the ramps that stop the group on its path.

A group move is a piece of path (:mod:`mcl.geometry`: a line, an arc or a helix) parameterised
by its arc length ``s`` (0 … length); the motion *along* it is a 1-D jerk-limited profile
``s(t)`` planned with :mod:`mcl.trajectory` (:mod:`mcl.path_planner`), and the members follow
``p(s(t))``. The shape in space never depends on the profile: a stop (MC_GroupStop, an abort,
a member's fault) replaces the profile by a ramp of ``s`` to standstill on the same path, corner
blends included (:func:`stop_element`), and the path a feed hold would resume, or an override
would run slower, is the same function of ``s``.

Corner blending (BlendingLow/Previous/Next/High): the first element is planned to reach the
corner ``c`` with the blending velocity ``v_b`` and zero path acceleration, the second starts
there with ``v_b``. Let ``d`` be the path coordinate relative to the corner (``d < 0`` on the
first element, ``d > 0`` on the second), ``P1(d)`` and ``P2(d)`` the two elements continued
through the corner, ``u1`` and ``u2`` their tangents at it. Within ``|d| < D`` (the blend's
reach) the path is::

    p = c + (d − g)·u1 + g·u2 + (1 − σ)·R1(d) + σ·R2(d),   Rk(d) = Pk(d) − c − d·uk
    g = 2D·G(x),   x = (d + D) / (2D),   σ = 10x³ − 15x⁴ + 6x⁵,   G(x) = ∫₀ˣ σ

The first three terms round the corner between the tangent lines (the direction turns smoothly
from ``u1`` to ``u2``, the speed does not drop to zero, and the rounding lies on the inside of
the turn, so no axis moves backwards); the residuals ``Rk`` (zero on a line, ``d²·κ/2`` on an
arc) bend it onto the elements, so the blend meets each element with the same position,
velocity and acceleration. Between tangent elements (a line into a tangent arc) only the
curvature changes: the blend then spreads the step of the centripetal acceleration over the
reach, which keeps the jerk finite. How the reach and the blending velocity are chosen is
:mod:`mcl.path_planner`'s job.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Final

from mcl import trajectory
from mcl.command import Status
from mcl.enums import MC_BufferMode
from mcl.geometry import (
    EPS,
    Geometry,
    Line,
    Vector,
    along,
    arc,
    direction,
    distance_to_segment,
    dot,
)
from mcl.trajectory import Limits, Profile

LINE: Final = 0
ARC: Final = 1


def _smooth(x: float) -> tuple[float, float, float]:
    """Quintic step σ(x) = 10x³ − 15x⁴ + 6x⁵ and its first two derivatives (0 ≤ x ≤ 1)."""
    x2 = x * x
    return (
        x2 * x * (10.0 - 15.0 * x + 6.0 * x2),
        30.0 * x2 * (1.0 - x) ** 2,
        60.0 * x * (1.0 - x) * (1.0 - 2.0 * x),
    )


class PathCommand:
    """The ticket of a group command (MC_MoveLinear*, MC_MoveCircular*, MC_MovePath, …) that its
    FB reads.

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


class Move:
    """One piece of a group command before it is planned: its shape (a line to ``end``, or an
    arc described as MC_MoveCircular* describes it), its dynamics and how it follows the piece
    before it.

    Args:
        end: EndPoint, absolute [mm].
        params: Velocity, Acceleration, Deceleration, Jerk (0 = default; see
            :meth:`mcl.path_planner.PathPlanner.limits`).
        mode: how the piece follows the one before it (BufferMode).
        kind: :data:`LINE` or :data:`ARC`.
        aux: the arc's AuxPoint, absolute (a point on it, its centre, or its radius first).
        circ_mode, path_choice, plane, turns: the arc's description (:func:`mcl.geometry.arc`).
        direct: the limits bind every member's own motion (MC_MoveDirect*), not the path.
        joint: with a kinematic transformation, the piece runs in the members' coordinates
            (ACS), not the MCS (:mod:`mcl.group_kinematics`).
        tolerance: the corner into this piece may deviate this far from the path [mm]
            (0 = the group's corner tolerance).
        reach: the blend into this piece leaves the path at most this far before the corner
            [mm] (0 = as the tolerance allows).
    """

    def __init__(
        self,
        end: Sequence[float],
        params: tuple[float, float, float, float],
        mode: MC_BufferMode = MC_BufferMode.Aborting,
        kind: int = LINE,
        aux: Sequence[float] = (),
        circ_mode: int = 0,
        path_choice: int = 0,
        plane: int = 0,
        turns: int = 0,
        direct: bool = False,
        tolerance: float = 0.0,
        reach: float = 0.0,
        joint: bool = False,
    ) -> None:
        self.end = [float(x) for x in end]
        self.params = params
        self.mode = mode
        self.kind = kind
        self.aux = [float(x) for x in aux]
        self.circ_mode = circ_mode
        self.path_choice = path_choice
        self.plane = plane
        self.turns = turns
        self.direct = direct
        self.tolerance = tolerance
        self.reach = reach
        self.joint = joint

    def geometry(self, start: Sequence[float]) -> Geometry:
        """The piece from ``start`` [mm].

        Raises:
            mcl.geometry.GeometryError: the arc's description fits no arc from ``start``.
        """
        if self.kind == ARC:
            return arc(
                start, self.circ_mode, self.aux, self.end, self.path_choice, self.plane, self.turns
            )
        return Line(list(start), self.end)


class Blend:
    """A corner blend: the rounding within ``reach`` of the corner (module docstring); it runs
    from about ``begin`` to ``end`` [s] (the end is estimated: the blend lasts until the second
    element is ``reach`` past the corner, passed at ``t_c`` with ``speed``)."""

    __slots__ = (
        "begin",
        "corner",
        "end",
        "geom_in",
        "geom_out",
        "reach",
        "speed",
        "successor",
        "t_c",
        "u_in",
        "u_out",
    )

    def __init__(
        self,
        geom_in: Geometry,
        geom_out: Geometry,
        speed: float,
        t_c: float,
        reach: float,
        begin: float,
        end: float,
        successor: Element,
    ) -> None:
        self.geom_in = geom_in
        self.geom_out = geom_out
        self.corner = list(geom_out.start)
        self.u_in = geom_in.tangent(geom_in.length)
        self.u_out = geom_out.tangent(0.0)
        self.speed = speed
        self.t_c = t_c
        self.reach = reach
        self.begin = begin
        self.end = end
        self.successor = successor

    def mix(self, d: float, dd: float, ddd: float) -> tuple[Vector, Vector, Vector]:
        """Position, velocity and acceleration vectors of the blended path at ``d`` [mm] from the
        corner with the path velocity ``dd`` and acceleration ``ddd``; outside the reach it is
        the element there itself."""
        reach = self.reach
        if d <= -reach:
            return _state(self.geom_in, self.geom_in.length + d, dd, ddd)
        if d >= reach:
            return _state(self.geom_out, d, dd, ddd)
        c, u1, u2 = self.corner, self.u_in, self.u_out
        p1, t1, k1 = self.geom_in.frame(self.geom_in.length + d)
        p2, t2, k2 = self.geom_out.frame(d)
        width = 2.0 * reach
        x = (d + reach) / width
        sigma, ds, dds = _smooth(x)
        ds, dds = ds / width, dds / (width * width)
        x2 = x * x
        g = width * x2 * x2 * (2.5 - 3.0 * x + x2)
        speed2 = dd * dd
        pos, vel, acc = [], [], []
        for i in range(len(c)):
            r1, r2 = p1[i] - c[i] - d * u1[i], p2[i] - c[i] - d * u2[i]
            q1, q2 = t1[i] - u1[i], t2[i] - u2[i]
            first = u1[i] + sigma * (u2[i] - u1[i]) + (1.0 - sigma) * q1 + sigma * q2
            first += ds * (r2 - r1)
            second = ds * (u2[i] - u1[i]) + (1.0 - sigma) * k1[i] + sigma * k2[i]
            second += 2.0 * ds * (q2 - q1) + dds * (r2 - r1)
            pos.append(c[i] + (d - g) * u1[i] + g * u2[i] + (1.0 - sigma) * r1 + sigma * r2)
            vel.append(first * dd)
            acc.append(first * ddd + second * speed2)
        return pos, vel, acc


def _state(geometry: Geometry, s: float, v: float, a: float) -> tuple[Vector, Vector, Vector]:
    """Position, velocity, acceleration vectors at arc length ``s`` with the path velocity ``v``
    and acceleration ``a``."""
    p, t, k = geometry.frame(s)
    v2 = v * v
    return p, [v * x for x in t], [a * x + v2 * y for x, y in zip(t, k, strict=True)]


class Element:
    """A piece of the path run along a 1-D profile of its arc length.

    Move elements come from a :class:`Move` (``move`` set) and end at ``end``; stop elements
    (``move`` None) run their ``geometry`` (corner blends included) to a standstill
    (:func:`stop_element`).

    Attributes:
        geometry: the shape (:class:`mcl.geometry.Geometry`).
        limits: along the path (:meth:`mcl.path_planner.PathPlanner.limits`).
        cap: the fastest the piece may be passed [mm/s] (members' Vmax; on an arc its
            velocity, which the curvature may have lowered).
        entry_max: the fastest the piece may be entered so that the path can still slow down
            to what the pieces behind it allow (look-ahead) [mm/s].
        jerk: the bound of the path's jerk vector on the piece [mm/s³] (on a line the jerk
            along it; on an arc more than the jerk along it, which leaves room for the
            curvature's share).
    """

    __slots__ = (
        "blend_in",
        "blend_out",
        "cap",
        "completes",
        "end",
        "entry_max",
        "geometry",
        "jerk",
        "joint",
        "length",
        "limits",
        "move",
        "profile",
        "start",
        "t0",
        "ticket",
    )

    def __init__(
        self,
        geometry: Geometry,
        limits: Limits,
        cap: float,
        ticket: PathCommand | None,
        move: Move | None,
        completes: bool = True,
    ) -> None:
        self.geometry = geometry
        self.start = list(geometry.start)
        self.end = list(geometry.end)
        self.length = geometry.length
        self.limits = limits
        self.cap = cap
        self.entry_max = math.inf
        self.jerk = limits.jerk
        self.ticket = ticket
        self.move = move
        self.completes = completes
        """Reaching the end reports the ticket Done (False for the pieces of a command before
        its last, and for the ramp that precedes a move)."""
        self.profile: Profile | None = None
        self.t0 = 0.0
        self.blend_in: Blend | None = None
        self.blend_out: Blend | None = None
        self.joint = move.joint if move is not None else False
        """With a kinematic transformation: the piece runs in the members' coordinates."""

    @property
    def mode(self) -> MC_BufferMode:
        """How the element follows the one before it (a stop element: Aborting)."""
        return self.move.mode if self.move is not None else MC_BufferMode.Aborting

    @property
    def duration(self) -> float:
        """Duration of the planned profile [s]."""
        assert self.profile is not None
        return self.profile.duration

    def state(self, s: float, v: float, a: float) -> tuple[Vector, Vector, Vector]:
        """Path point, velocity and acceleration at arc length ``s`` with path velocity ``v``
        and acceleration ``a``, the corner blends included [mm], [mm/s], [mm/s²]."""
        blend = self.blend_out
        if blend is not None and blend.reach > 0.0 and s > self.length - blend.reach:
            return blend.mix(s - self.length, v, a)
        blend = self.blend_in
        if blend is not None and blend.reach > 0.0 and s < blend.reach:
            return blend.mix(s, v, a)
        return _state(self.geometry, s, v, a)

    def point(self, t: float) -> tuple[Vector, Vector, Vector]:
        """Path point, velocity and acceleration at time ``t`` [s]."""
        assert self.profile is not None
        s, v, a = self.profile.at(t - self.t0)
        return self.state(s, v, a)


def stop_element(
    geometry: Geometry,
    s: float,
    v: float,
    a: float,
    t: float,
    limits: Limits,
    ticket: PathCommand | None = None,
    completes: bool = True,
    blends: tuple[Blend | None, Blend | None] = (None, None),
) -> Element:
    """A ramp of the path velocity from (``s``, ``v``, ``a``) on ``geometry`` (with the corner
    ``blends`` in and out of it) to a standstill, starting at ``t`` [s] with the deceleration and
    jerk of ``limits``: the group stops on its path (beyond the end it follows the element behind
    the blend, or the piece continued)."""
    element = Element(geometry, limits, math.inf, ticket, None, completes)
    element.blend_in, element.blend_out = blends
    profile = trajectory.stop(s, max(v, 0.0), a, limits.deceleration, limits.jerk)
    element.profile = profile
    element.t0 = t
    element.end = element.state(profile.end_position, 0.0, 0.0)[0]
    return element


__all__ = [
    "ARC",
    "EPS",
    "LINE",
    "Blend",
    "Element",
    "Move",
    "PathCommand",
    "Vector",
    "along",
    "direction",
    "distance_to_segment",
    "dot",
    "stop_element",
]

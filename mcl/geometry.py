"""The shapes of a group path: straight lines, circular arcs and helices, as functions of their
arc length.

A piece of the path is a curve ``p(s)`` in the space of the members' coordinates [mm] (one
coordinate per member, two or three), parameterised by its arc length ``s`` (0 … ``length``):
:meth:`Geometry.frame` gives the point, the unit tangent ``T = dp/ds`` and the curvature vector
``K = d²p/ds²``. A motion along it is a 1-D profile ``s(t)``; the members then follow
``p = p(s)``, ``v = T·ṡ``, ``a = T·s̈ + K·ṡ²``, so the path in space does not depend on how fast it
is run (a feed hold or an override only changes ``s(t)``). Every piece continues beyond its ends
(a line straight on, an arc around its circle): corner blends and stop ramps use that.

Arcs (PLCopen Part 4 MC_MoveCircular*, :func:`arc`) are built from the start point and the
block's inputs, in one of three ways (``CircMode``):

- BORDER: the arc runs from the start through ``AuxPoint`` to ``EndPoint``; the three points
  give its plane (any plane of the members' space), centre and direction; PathChoice is ignored;
  it cannot describe a full circle.
- CENTER: ``AuxPoint`` is the centre; the arc turns clockwise or counter-clockwise (PathChoice)
  from the start to ``EndPoint``; an end point equal to the start point makes a full circle, and
  ``Turns`` adds full turns. The distances of the start and of the end from the centre may differ
  by at most :data:`RADIUS_TOLERANCE` of the radius (a centre rounded by a CAM system): the centre
  is then moved onto the perpendicular bisector of the chord, so the arc runs exactly through
  both points.
- RADIUS: ``AuxPoint``'s first coordinate is the radius: of the two circles through the start and
  the end, PathChoice and the sign of the radius choose one (as in G-code: a positive radius
  the arc of at most 180°, a negative one the longer arc).

The plane (``Plane``, the G-code numbers): 17 = the plane of members 1 and 2 (XY), 18 = members
3 and 1 (ZX), 19 = members 2 and 3 (YZ); the remaining member then moves linearly from the
start to the end coordinate (a helix). 0 (automatic): the plane through the start, the centre
(or auxiliary point) and the end where they span one (no helix), else the plane of members 1 and
2 (with a helix along member 3). Clockwise and counter-clockwise are seen from the positive
normal of the plane: for 17/18/19 the third axis (Z, Y, X), for another plane the normal whose
largest component is positive.

Bad input raises :class:`GeometryError` (the blocks report it as ``EParam``): points that are
not finite, a zero radius, collinear BORDER points, a radius shorter than half the chord, an end
point off the circle (CENTER), a zero-length arc, an unknown CircMode, PathChoice or Plane.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Final

from mcl.enums import MC_CIRC_MODE, MC_CIRC_PATHCHOICE

Vector = list[float]
"""A point or direction in the group's coordinates, one component per member [mm]."""

EPS: Final = 1e-9
"""Lengths and speeds below this count as zero [mm], [mm/s]."""
RADIUS_TOLERANCE: Final = 1e-3
"""How much the end point's distance from a CENTER arc's centre may differ from the start
point's, relative to the radius."""
COLLINEAR: Final = 1e-9
"""Three points whose triangle has a sine of its largest angle below this are collinear."""
BORDER_SINE: Final = 5e-4
"""BORDER points whose triangle has a sine of its largest angle below this lie on a line: their
circle would be over 1000 times as large as its longest chord (law of sines), a line within the
positions' rounding (a start 1 µm off a 100 mm line made a circle of 2.5e9 mm)."""
PLANES: Final = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}
"""G-code plane number → (first axis, second axis, normal axis), member indices."""
TWO_PI: Final = 2.0 * math.pi


class GeometryError(ValueError):
    """The inputs describe no valid piece of path (reported as ``EParam``)."""


# ---------------------------------------------------------------------- vectors
# dot and along run every servo cycle of a group move: index loops, which compile to native
# arithmetic (zip with strict=True is a generic call with a keyword when compiled)
def dot(a: Sequence[float], b: Sequence[float]) -> float:
    """Scalar product of two vectors of one length (summed in order)."""
    total = 0.0
    for i in range(len(a)):
        total += a[i] * b[i]
    return total


def norm(a: Sequence[float]) -> float:
    """Euclidean length."""
    return math.sqrt(dot(a, a))


def along(start: Sequence[float], unit: Sequence[float], s: float) -> Vector:
    """The point ``s`` along ``unit`` from ``start`` (vectors of one length)."""
    return [start[i] + s * unit[i] for i in range(len(start))]


def direction(v: Sequence[float]) -> Vector:
    """Unit vector of ``v`` (zero vector for a standstill)."""
    speed = norm(v)
    return [x / speed for x in v] if speed > EPS else [0.0] * len(v)


def sub(a: Sequence[float], b: Sequence[float]) -> Vector:
    """``a − b``."""
    return [x - y for x, y in zip(a, b, strict=True)]


def cross(a: Sequence[float], b: Sequence[float]) -> Vector:
    """Cross product of two 3-D vectors."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def distance_to_segment(p: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    """Distance of point ``p`` from the segment ``a``–``b`` [mm]."""
    ab = sub(b, a)
    ap = sub(p, a)
    length2 = dot(ab, ab)
    k = 0.0 if length2 <= 0.0 else min(1.0, max(0.0, dot(ap, ab) / length2))
    return norm([d - k * e for d, e in zip(ap, ab, strict=True)])


def _finite(*vectors: Sequence[float]) -> None:
    for v in vectors:
        if not all(math.isfinite(x) for x in v):
            raise GeometryError("a coordinate is not a finite number")


# ---------------------------------------------------------------------- pieces
class Geometry:
    """A piece of path as a function of its arc length (module docstring).

    Attributes:
        start, end: the end points [mm].
        length: the arc length [mm].
        curvature: κ = |K| [1/mm] (constant along the piece; 0 for a line).
        curvature_rate: |dK/ds| [1/mm²] (constant; 1/R² on a plane circle).
        share: per member, the largest |T_i| along the piece: member i moves at most
            ``share[i]·ṡ``.
    """

    def __init__(self, start: Vector, end: Vector, length: float) -> None:
        self.start = start
        self.end = end
        self.length = length
        self.curvature = 0.0
        self.curvature_rate = 0.0
        self.share: Vector = [0.0] * len(start)

    def frame(self, s: float) -> tuple[Vector, Vector, Vector]:
        """Point, unit tangent and curvature vector at arc length ``s`` (any ``s``: the piece
        continues beyond its ends)."""
        raise NotImplementedError

    def point(self, s: float) -> Vector:
        """The point at arc length ``s`` [mm]."""
        return self.frame(s)[0]

    def tangent(self, s: float) -> Vector:
        """The unit tangent at arc length ``s``."""
        return self.frame(s)[1]

    def distance(self, p: Sequence[float]) -> float:
        """Distance of ``p`` from the piece (between its ends) [mm]."""
        raise NotImplementedError

    def bounds(self) -> list[tuple[float, float]]:
        """Per member, the smallest and largest coordinate the piece passes [mm]."""
        raise NotImplementedError


class Line(Geometry):
    """A straight piece from ``start`` to ``end``."""

    def __init__(self, start: Vector, end: Vector) -> None:
        delta = sub(end, start)
        length = norm(delta)
        super().__init__(list(start), list(end), length)
        self.unit = [d / length for d in delta] if length > EPS else [0.0] * len(delta)
        self.share = [abs(u) for u in self.unit]

    def frame(self, s: float) -> tuple[Vector, Vector, Vector]:
        return along(self.start, self.unit, s), list(self.unit), [0.0] * len(self.unit)

    def distance(self, p: Sequence[float]) -> float:
        return distance_to_segment(p, self.start, self.end)

    def bounds(self) -> list[tuple[float, float]]:
        return [(min(a, b), max(a, b)) for a, b in zip(self.start, self.end, strict=True)]


class Arc(Geometry):
    """A circular arc or a helix: ``p(φ) = c + R·(cos φ·e1 + sin φ·e2) + (φ/Θ)·H`` for the angle
    ``φ = Θ·s/length`` from 0 to the sweep Θ.

    Args:
        centre: the centre ``c`` [mm] (in the start point's plane).
        radius: ``R`` [mm].
        e1: unit vector from the centre to the start point.
        e2: unit vector of the direction of motion at the start (perpendicular to ``e1``).
        sweep: Θ > 0 [rad], may exceed 2π.
        lift: ``H``, the linear travel perpendicular to the plane over the whole sweep [mm]
            (zero vector: a plane arc).
    """

    def __init__(
        self, centre: Vector, radius: float, e1: Vector, e2: Vector, sweep: float, lift: Vector
    ) -> None:
        start = [c + radius * a for c, a in zip(centre, e1, strict=True)]
        length = math.hypot(radius * sweep, norm(lift))
        super().__init__(start, start, length)
        self.centre = centre
        self.radius = radius
        self.e1 = e1
        self.e2 = e2
        self.sweep = sweep
        self.lift = lift
        self.rate = sweep / length
        """dφ/ds [rad/mm]."""
        self.end = self.point(length)
        self.curvature = radius * self.rate**2
        self.curvature_rate = radius * self.rate**3
        planar = [radius * math.hypot(a, b) for a, b in zip(e1, e2, strict=True)]
        self.share = [self.rate * (r + abs(h) / sweep) for r, h in zip(planar, lift, strict=True)]

    def frame(self, s: float) -> tuple[Vector, Vector, Vector]:
        phi = self.rate * s
        c, sn = math.cos(phi), math.sin(phi)
        r, w, k = self.radius, self.rate, self.radius * self.rate * self.rate
        lift = phi / self.sweep
        point, tangent, curve = [], [], []
        for ci, a, b, h in zip(self.centre, self.e1, self.e2, self.lift, strict=True):
            point.append(ci + r * (c * a + sn * b) + lift * h)
            tangent.append(w * (r * (c * b - sn * a) + h / self.sweep))
            curve.append(-k * (c * a + sn * b))
        return point, tangent, curve

    def distance(self, p: Sequence[float]) -> float:
        q = sub(p, self.centre)
        a, b = dot(q, self.e1), dot(q, self.e2)
        angle = math.atan2(b, a) % TWO_PI
        if not any(self.lift):
            if angle <= self.sweep:
                normal = norm(
                    [x - a * u - b * w for x, u, w in zip(q, self.e1, self.e2, strict=True)]
                )
                return math.hypot(math.hypot(a, b) - self.radius, normal)
            return min(norm(sub(p, self.start)), norm(sub(p, self.end)))
        # a helix: the nearest of the turns that pass the point's angle, refined by Newton
        best = min(norm(sub(p, self.start)), norm(sub(p, self.end)))
        phi = angle
        while phi <= self.sweep:
            best = min(best, self._nearest(p, phi))
            phi += TWO_PI
        return best

    def _nearest(self, p: Sequence[float], phi: float) -> float:
        """Distance of ``p`` from the helix near the angle ``phi`` (Newton on |p(φ) − p|²)."""
        w = self.rate
        s = phi / w
        for _ in range(6):
            q, t, k = self.frame(s)
            d = sub(q, p)
            slope, curve = dot(d, t), dot(t, t) + dot(d, k)
            if curve <= 0.0:
                break
            s = min(max(s - slope / curve, 0.0), self.length)
        return norm(sub(self.point(s), p))

    def bounds(self) -> list[tuple[float, float]]:
        result = []
        for i, (a, b, h) in enumerate(zip(self.e1, self.e2, self.lift, strict=True)):
            values = [self.start[i], self.end[i]]
            if h == 0.0 and math.hypot(a, b) > 0.0:
                phase = math.atan2(b, a)  # x_i = c_i + R·|(a, b)|·cos(φ − phase)
                first = math.ceil((0.0 - phase) / math.pi)
                last = math.floor((self.sweep - phase) / math.pi)
                for k in range(first, min(last, first + 3) + 1):
                    values.append(self.point((phase + k * math.pi) / self.rate)[i])
            result.append((min(values), max(values)))
        return result


# ---------------------------------------------------------------------- building arcs
def _embed(v: Sequence[float]) -> Vector:
    """A 2-D or 3-D vector as 3-D."""
    return [*v, 0.0] if len(v) == 2 else list(v)


def _positive_normal(n: Vector) -> Vector:
    """``n`` or ``−n``: the one whose largest component (by magnitude) is positive."""
    big = max(range(3), key=lambda i: abs(n[i]))
    return n if n[big] > 0.0 else [-x for x in n]


def _plane(size: int, plane: int) -> tuple[int, int, int] | None:
    """The (axis, axis, normal) member indices of a G-code plane; None for automatic (0)."""
    if plane == 0:
        return None
    if plane not in PLANES:
        raise GeometryError(f"Plane {plane}: 0 (automatic), 17, 18 or 19")
    axes = PLANES[plane]
    if size < 3 and plane != 17:
        raise GeometryError(f"Plane {plane} needs a group of three members")
    return axes


def _unit_axis(index: int) -> Vector:
    return [1.0 if i == index else 0.0 for i in range(3)]


def _arc_about(
    start: Vector, centre: Vector, end: Vector, normal: Vector, ccw: bool, turns: int, full: bool
) -> Arc:
    """The 3-D arc about ``centre`` in the plane of unit ``normal`` from ``start`` to ``end``
    (both in that plane through the centre; ``full``: the end is the start)."""
    radius = norm(sub(start, centre))
    e1 = [x / radius for x in sub(start, centre)]
    e2 = cross(normal, e1) if ccw else cross(e1, normal)
    q = sub(end, centre)
    angle = math.atan2(dot(q, e2), dot(q, e1)) % TWO_PI
    sweep = TWO_PI if full else angle
    if sweep <= EPS:
        sweep = TWO_PI  # the end sits on the start within rounding: a full circle
    return Arc(centre, radius, e1, e2, sweep + TWO_PI * turns, [0.0, 0.0, 0.0])


def _shrink(arc: Arc, size: int, lift: Vector) -> Arc:
    """The 3-D ``arc`` with a ``lift`` in the group's ``size`` coordinates."""
    if size == 3:
        return Arc(arc.centre, arc.radius, arc.e1, arc.e2, arc.sweep, lift)
    return Arc(arc.centre[:2], arc.radius, arc.e1[:2], arc.e2[:2], arc.sweep, [0.0, 0.0])


def _border(start: Vector, aux: Vector, end: Vector) -> Arc:
    a, b, c = sub(aux, start), sub(end, start), sub(end, aux)
    if min(norm(a), norm(b), norm(c)) <= EPS:
        raise GeometryError("BORDER needs three different points (start, AuxPoint, EndPoint)")
    n = cross(a, b)
    area = norm(n)  # = the product of two sides times the sine of the angle between them
    if area <= BORDER_SINE * min(norm(a) * norm(b), norm(a) * norm(c), norm(b) * norm(c)):
        raise GeometryError(
            "the start, AuxPoint and EndPoint lie on a line (their circle over 1000 times its"
            " chord): no circle"
        )
    n = [x / area for x in n]
    # circumcentre: start + (|a|²·b − |b|²·a) × (a × b) / (2·|a × b|²)
    w = [dot(a, a) * y - dot(b, b) * x for x, y in zip(a, b, strict=True)]
    offset = cross(w, n)
    centre = [s + x / (2.0 * area) for s, x in zip(start, offset, strict=True)]
    # start → aux → end turns counter-clockwise about a × b
    return _arc_about(start, centre, end, n, True, 0, False)


def _centre_arc(
    start: Vector, centre: Vector, end: Vector, ccw: bool, plane: int, turns: int, size: int
) -> tuple[Arc, Vector]:
    """The 3-D arc of a CENTER arc and its lift (module docstring)."""
    axes = _plane(size, plane)
    if axes is None:
        n = cross(sub(start, centre), sub(end, centre))
        if norm(n) > COLLINEAR * norm(sub(start, centre)) * norm(sub(end, centre)):
            normal = _positive_normal(direction(n))
            return _fitted(start, centre, end, normal, ccw, turns), [0.0, 0.0, 0.0]
        axes = PLANES[17]
    k = axes[2]
    normal = _unit_axis(k)
    lift = [end[k] - start[k] if i == k else 0.0 for i in range(3)]
    flat_centre = [start[k] if i == k else centre[i] for i in range(3)]
    flat_end = [start[k] if i == k else end[i] for i in range(3)]
    return _fitted(start, flat_centre, flat_end, normal, ccw, turns), lift


def _fitted(
    start: Vector, centre: Vector, end: Vector, normal: Vector, ccw: bool, turns: int
) -> Arc:
    """The arc about ``centre`` (moved onto the chord's bisector when the end's distance differs
    within the tolerance) from ``start`` to ``end``, all in one plane."""
    r0, r1 = norm(sub(start, centre)), norm(sub(end, centre))
    if r0 <= EPS:
        raise GeometryError("the centre lies on the start point: zero radius")
    if abs(r1 - r0) > RADIUS_TOLERANCE * r0:
        raise GeometryError(
            f"the end point is {r1:g} from the centre, the start point {r0:g}: not on one circle"
        )
    chord = sub(end, start)
    full = norm(chord) <= EPS * max(1.0, r0)
    if not full:
        mid = [(a + b) / 2.0 for a, b in zip(start, end, strict=True)]
        u = direction(chord)
        offset = sub(centre, mid)
        centre = [m + o - dot(offset, u) * x for m, o, x in zip(mid, offset, u, strict=True)]
    return _arc_about(start, centre, end, normal, ccw, turns, full)


def _radius_arc(
    start: Vector, end: Vector, radius: float, ccw: bool, plane: int, size: int
) -> tuple[Arc, Vector]:
    axes = _plane(size, plane) or PLANES[17]
    k = axes[2]
    normal = _unit_axis(k)
    lift = [end[k] - start[k] if i == k else 0.0 for i in range(3)]
    flat_end = [start[k] if i == k else end[i] for i in range(3)]
    chord = sub(flat_end, start)
    half = norm(chord) / 2.0
    if half <= EPS:
        raise GeometryError("RADIUS: the end point equals the start point (no chord)")
    r = abs(radius)
    if r < half:
        if r < half * (1.0 - RADIUS_TOLERANCE):
            raise GeometryError(f"RADIUS {r:g} is shorter than half the chord ({half:g})")
        r = half
    u = direction(chord)
    left = cross(normal, u)  # the centre of a counter-clockwise short arc lies on the left
    side = 1.0 if ccw == (radius > 0.0) else -1.0
    h = side * math.sqrt(max(r * r - half * half, 0.0))
    centre = [s + half * x + h * y for s, x, y in zip(start, u, left, strict=True)]
    return _arc_about(start, centre, flat_end, normal, ccw, 0, False), lift


def arc(
    start: Sequence[float],
    mode: int,
    aux: Sequence[float],
    end: Sequence[float],
    path_choice: int = MC_CIRC_PATHCHOICE.CLOCKWISE,
    plane: int = 0,
    turns: int = 0,
) -> Arc:
    """The arc of an MC_MoveCircular* block from ``start`` (absolute coordinates, 2 or 3 members;
    module docstring).

    Args:
        start: where the arc starts [mm].
        mode: CircMode (:class:`mcl.MC_CIRC_MODE`).
        aux: AuxPoint, absolute [mm]: a point on the arc (BORDER), the centre (CENTER), or the
            radius as its first value (RADIUS).
        end: EndPoint, absolute [mm].
        path_choice: :class:`mcl.MC_CIRC_PATHCHOICE` (CENTER and RADIUS).
        plane: 0 automatic, 17, 18 or 19.
        turns: additional full turns (CENTER only), >= 0.

    Raises:
        GeometryError: the inputs describe no arc (the message says why).
    """
    size = len(start)
    if size not in (2, 3) or len(end) != size or len(aux) != size:
        raise GeometryError("an arc needs a group of two or three members and points of as many")
    _finite(start, aux, end)
    if mode not in (MC_CIRC_MODE.BORDER, MC_CIRC_MODE.CENTER, MC_CIRC_MODE.RADIUS):
        raise GeometryError(f"CircMode {mode}: 0 BORDER, 1 CENTER or 2 RADIUS")
    if path_choice not in (MC_CIRC_PATHCHOICE.CLOCKWISE, MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE):
        raise GeometryError(f"PathChoice {path_choice}: 0 CLOCKWISE or 1 COUNTERCLOCKWISE")
    if turns < 0 or (turns and mode != MC_CIRC_MODE.CENTER):
        raise GeometryError("Turns must be >= 0, and 0 unless CircMode is CENTER")
    ccw = path_choice == MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
    s3, a3, e3 = _embed(start), _embed(aux), _embed(end)
    if mode == MC_CIRC_MODE.BORDER:
        _plane(size, plane)
        if plane:
            raise GeometryError("BORDER takes its plane from its three points: Plane 0")
        flat, lift = _border(s3, a3, e3), [0.0, 0.0, 0.0]
    elif mode == MC_CIRC_MODE.CENTER:
        flat, lift = _centre_arc(s3, a3, e3, ccw, plane, turns, size)
    else:
        flat, lift = _radius_arc(s3, e3, aux[0], ccw, plane, size)
    if size == 2 and any(lift):
        raise GeometryError("a two-member group has no axis for a helix")
    result = _shrink(flat, size, lift)
    result.end = list(end)  # exactly the commanded end point (not its rounded image)
    return result


__all__ = [
    "BORDER_SINE",
    "COLLINEAR",
    "EPS",
    "PLANES",
    "RADIUS_TOLERANCE",
    "Arc",
    "Geometry",
    "GeometryError",
    "Line",
    "Vector",
    "along",
    "arc",
    "cross",
    "direction",
    "distance_to_segment",
    "dot",
    "norm",
    "sub",
]

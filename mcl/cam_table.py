"""Cam tables: the slave position as a function of the master position, segment by segment.

A table is a list of points ``mcl.MC_CamPoint(Master, Slave, Velocity, Acceleration, Law)``
(or ``(Master, Slave[, Velocity[, Acceleration[, Law]]])`` tuples) in an
``mcl.MC_CAM_REF(Points=[...], NumberOfPoints=None)``; an ST program passes a STRUCT of its own
with the same fields. ``Master`` [master u] must increase strictly; ``Slave`` [slave u];
``Velocity`` is the slope ds/dm [slave u / master u] and ``Acceleration`` the curvature d²s/dm²
[slave u / master u²] at the point, NaN where not given (0 for the motion laws, free for the
spline). ``Law`` (``mcl.CamLaw``) is the interpolation of the segment from this point to the next
(the last point's law is not used):

- ``Linear``: a straight line (constant slope; the slope jumps at its ends).
- ``CubicSpline``: consecutive spline segments form one cubic spline, continuous in slope and
  curvature at its inner points; at its ends it takes the point's Velocity where given, else it
  is natural (curvature 0); a periodic table whose segments are all spline segments is one
  periodic spline (the slave rise over the period taken out first).
- ``Polynomial5``: the quintic with the Velocity and Acceleration of both end points (VDI 2143
  Blatt 1, "Polynom 5. Grades"; rest to rest it is ``10z³ − 15z⁴ + 6z⁵``).
- ``ModifiedSine``, ``ModifiedTrapezoid``: the rest-to-rest laws of VDI 2143 Blatt 1
  ("modifizierte Sinuslinie", "modifizierte Beschleunigungs-Trapezlinie"; closed forms as in
  H. A. Rothbart, Cam Design Handbook, ch. 3, and R. L. Norton, Cam Design and Manufacturing
  Handbook, ch. 3), applied to the deviation from the straight line of the segment's end slope,
  which must be the same at both ends (0 rest to rest): ``s = s0 + v·Δm·z + (Δs − v·Δm)·f(z)``,
  ``z = (m − m0)/Δm``. Their characteristic values are Cv = 1.76, Ca = 5.53 (modified sine) and
  Cv = 2.00, Ca = 4.89 (modified trapezoid).

MC_CamTableSelect checks the table (:func:`compile_cam`) and refuses a bad one with ``EParam``
and its reason (``ErrorText``): fewer than two or more than :data:`MAX_POINTS` points, a value
that is not finite, the master not strictly increasing, an unknown law, a modified law whose end
slopes differ, and a jump of the slope or the curvature where the laws on both sides promise
continuity: the slope at a point between two segments that are not both Linear, the curvature
between two segments of the motion laws (Polynomial5, ModifiedSine, ModifiedTrapezoid); a
periodic table is checked across its period boundary too. The position is continuous by
construction (each segment ends at the next point).

:func:`rotary_knife` builds the cam of a rotary cross cutter.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import Any, Final

from mcl.fb import number

MAX_POINTS: Final = 10000
"""The most points a cam table may have (as Intel's RTmotion)."""
TOLERANCE: Final = 1e-6
"""Relative tolerance of the continuity checks (of the larger slope or curvature there)."""

_POLY: Final = 0
_SINE: Final = 1
_TRAP: Final = 2

_PI: Final = math.pi
_MS_K: Final = 1.0 / (4.0 + math.pi)
_TRAP_A: Final = 8.0 * math.pi / (2.0 + math.pi)
"""Peak acceleration of the modified trapezoid, Ca = 8π/(2 + π) ≈ 4.888."""


class CamLaw(IntEnum):
    """The interpolation of a cam segment (VDI 2143 motion laws and the classic interpolations)."""

    Linear = 0
    CubicSpline = 1
    Polynomial5 = 2
    ModifiedSine = 3
    ModifiedTrapezoid = 4


@dataclass
class MC_CamPoint:
    """One point of a cam table: ``Master`` [master u], ``Slave`` [slave u], slope ``Velocity``
    ds/dm and curvature ``Acceleration`` d²s/dm² (NaN: not given), ``Law`` of the segment that
    starts here (:class:`CamLaw`)."""

    Master: float = 0.0
    Slave: float = 0.0
    Velocity: float = math.nan
    Acceleration: float = math.nan
    Law: int = CamLaw.Linear


@dataclass
class MC_CAM_REF:
    """A cam table (PLCopen's vendor-specific MC_CAM_REF).

    Attributes:
        Points: the points (:class:`MC_CamPoint`, or tuples ``(Master, Slave[, Velocity[,
            Acceleration[, Law]]])``).
        NumberOfPoints: how many of them the table uses; None: all.
        Problem: why the table cannot be run ("" when it can).
        Name: what the table is called where it is shown ("": nothing).
    """

    Points: Sequence[Any] = ()
    NumberOfPoints: int | None = None
    Problem: str = ""
    """Why a table built by a helper (:func:`rotary_knife`) cannot be run; MC_CamTableSelect
    refuses a table with a Problem (``EParam``)."""
    Name: str = ""
    """What the table is called where it is shown (the viewer's cam view, the cam plot)."""


# ------------------------------------------------------------------------------ motion laws
def modified_sine(z: float) -> tuple[float, float, float]:
    """VDI 2143 modified sine, rest to rest over z ∈ [0, 1]: f, f′, f″.

    Acceleration: a quarter sine of period 1/2 on [0, 1/8] and [7/8, 1], a sine of period 3/2
    between (Rothbart, Cam Design Handbook, eq. 3.22)."""
    k = _MS_K
    if z <= 0.125 or z >= 0.875:
        w = 4.0 * _PI * z
        base = 0.0 if z <= 0.125 else 4.0 * k
        return (
            base + _PI * k * z - 0.25 * k * math.sin(w),
            _PI * k * (1.0 - math.cos(w)),
            4.0 * _PI * _PI * k * math.sin(w),
        )
    w = _PI / 3.0 * (1.0 + 4.0 * z)
    return (
        2.0 * k + _PI * k * z - 2.25 * k * math.sin(w),
        _PI * k * (1.0 - 3.0 * math.cos(w)),
        4.0 * _PI * _PI * k * math.sin(w),
    )


def modified_trapezoid(z: float) -> tuple[float, float, float]:
    """VDI 2143 modified trapezoid, rest to rest over z ∈ [0, 1]: f, f′, f″.

    Acceleration: sine ramps on [0, 1/8], [3/8, 5/8], [7/8, 1], constant ±Ca between, Ca =
    8π/(2 + π) (Norton, Cam Design and Manufacturing Handbook, sec. 3.9); the second half is the
    point reflection of the first, f(z) = 1 − f(1 − z)."""
    if z > 0.5:
        p, v, a = modified_trapezoid(1.0 - z)
        return 1.0 - p, v, -a
    A = _TRAP_A
    c = 4.0 * _PI
    if z <= 0.125:
        return (
            A / c * (z - math.sin(c * z) / c),
            A / c * (1.0 - math.cos(c * z)),
            A * math.sin(c * z),
        )
    f1 = A / c * (0.125 - 1.0 / c)
    v1 = A / c
    if z <= 0.375:
        u = z - 0.125
        return f1 + v1 * u + 0.5 * A * u * u, v1 + A * u, A
    f2 = f1 + 0.25 * v1 + A / 32.0
    v2 = v1 + 0.25 * A
    u = z - 0.375
    return (
        f2 + v2 * u + A / (c * c) * (1.0 - math.cos(c * u)),
        v2 + A / c * math.sin(c * u),
        A * math.cos(c * u),
    )


def quintic(
    h: float, ds: float, v0: float, a0: float, v1: float, a1: float
) -> tuple[float, float, float, float, float, float]:
    """Coefficients c0…c5 of the quintic ``s(u) = Σ cᵢ uⁱ`` on [0, h] from (0, v0, a0) to
    (ds, v1, a1) (Hermite quintic; VDI 2143 Polynom 5. Grades)."""
    h2, h3 = h * h, h * h * h
    c3 = (20.0 * ds - (8.0 * v1 + 12.0 * v0) * h - (3.0 * a0 - a1) * h2) / (2.0 * h3)
    c4 = (-30.0 * ds + (14.0 * v1 + 16.0 * v0) * h + (3.0 * a0 - 2.0 * a1) * h2) / (2.0 * h3 * h)
    c5 = (12.0 * ds - 6.0 * (v1 + v0) * h + (a1 - a0) * h2) / (2.0 * h3 * h2)
    return 0.0, v0, 0.5 * a0, c3, c4, c5


def polynomial(c: Sequence[float], u: float) -> tuple[float, float, float]:
    """Value, first and second derivative of ``Σ c[i] uⁱ`` (six coefficients) at ``u``."""
    c0, c1, c2, c3, c4, c5 = c[0], c[1], c[2], c[3], c[4], c[5]
    p = c0 + u * (c1 + u * (c2 + u * (c3 + u * (c4 + u * c5))))
    v = c1 + u * (2.0 * c2 + u * (3.0 * c3 + u * (4.0 * c4 + u * 5.0 * c5)))
    a = 2.0 * c2 + u * (6.0 * c3 + u * (12.0 * c4 + u * 20.0 * c5))
    return p, v, a


def _quadratic_roots(c0: float, c1: float, c2: float) -> list[float]:
    """The real roots of ``c0 + c1·z + c2·z²`` (c2 ≠ 0), without cancellation."""
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return []
    q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
    return [q / c2] + ([c0 / q] if q != 0.0 else [])


def _largest_cubic_root(c0: float, c1: float, c2: float, c3: float) -> float:
    """The real root of largest magnitude of ``c0 + c1·z + c2·z² + c3·z³`` (c3 ≠ 0): Cardano's
    formula, its trigonometric form when all three roots are real."""
    a, b, d = c2 / c3, c1 / c3, c0 / c3
    p = b - a * a / 3.0
    q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + d
    disc = 0.25 * q * q + p * p * p / 27.0
    if disc >= 0.0:
        u = math.cbrt(-0.5 * q - math.copysign(math.sqrt(disc), q))
        return (u - p / (3.0 * u) if u != 0.0 else 0.0) - a / 3.0
    r = 2.0 * math.sqrt(-p / 3.0)
    phi = math.acos(max(-1.0, min(1.0, 3.0 * q / (p * r))))
    roots = [r * math.cos((phi - 2.0 * _PI * k) / 3.0) - a / 3.0 for k in range(3)]
    return max(roots, key=abs)


def real_roots(c: Sequence[float]) -> list[float]:
    """The real roots in [0, 1] of ``Σ c[i] zⁱ`` (at most a cubic; leading coefficients that
    vanish against the others are dropped), in closed form: a cubic's largest root by Cardano,
    the other two from the quadratic left when it is divided out; each root polished by a
    Newton step."""
    coefficients = list(c)
    size = max((abs(x) for x in coefficients), default=0.0)
    while coefficients and abs(coefficients[-1]) <= 1e-14 * size:
        coefficients.pop()
    roots: list[float] = []
    if len(coefficients) == 2:
        roots = [-coefficients[0] / coefficients[1]]
    elif len(coefficients) == 3:
        roots = _quadratic_roots(coefficients[0], coefficients[1], coefficients[2])
    elif len(coefficients) == 4:
        c0, c1, c2, c3 = coefficients
        z1 = _largest_cubic_root(c0, c1, c2, c3)
        roots = [z1]
        if z1 != 0.0:  # divide (z − z1) out from the low end: stable for the smaller roots
            e0 = -c0 / z1
            e1 = (e0 - c1) / z1
            e2 = (e1 - c2) / z1
            roots += _quadratic_roots(e0, e1, e2) if e2 != 0.0 else []
        else:
            roots += _quadratic_roots(c1, c2, c3)
    polished = []
    for z in roots:
        value = slope = 0.0
        for x in reversed(coefficients):
            slope = slope * z + value
            value = value * z + x
        if slope != 0.0:
            z -= value / slope
        if 0.0 <= z <= 1.0:
            polished.append(z)
    return polished


def polynomial_peaks(c: Sequence[float], h: float) -> tuple[float, float]:
    """The largest |first| and |second derivative| of ``Σ c[i] uⁱ`` (six coefficients) on
    [0, ``h``]: at the ends or where the next derivative is 0 (a cubic and a quadratic in
    ``z = u/h``)."""
    b = [c[k] * h**k for k in range(6)]  # the polynomial in z
    turning_slope = real_roots([2.0 * b[2], 6.0 * b[3], 12.0 * b[4], 20.0 * b[5]])
    turning_curvature = real_roots([6.0 * b[3], 24.0 * b[4], 60.0 * b[5]])
    slope = max(abs(polynomial(c, h * z)[1]) for z in (0.0, 1.0, *turning_slope))
    curvature = max(abs(polynomial(c, h * z)[2]) for z in (0.0, 1.0, *turning_curvature))
    return slope, curvature


# ------------------------------------------------------------------------------ the checked cam
class Cam:
    """A checked cam table, ready to be evaluated every servo cycle (:func:`compile_cam`).

    Segment ``i`` spans ``masters[i]`` … ``masters[i + 1]``; its ``kinds[i]`` is a polynomial
    (coefficients in the local coordinate ``u = m − masters[i]``) or a modified law (``s0``,
    slope ``v``, length ``h``, deviation ``D`` in ``coefficients[i]``).
    """

    def __init__(
        self,
        masters: list[float],
        kinds: list[int],
        coefficients: list[list[float]],
        periodic: bool,
        laws: list[int],
    ) -> None:
        self.masters = masters
        self.laws = laws
        """The :class:`CamLaw` of each segment, as the table gives it."""
        self.kinds = kinds
        self.coefficients = coefficients
        self.periodic = periodic
        self.start = masters[0]
        """The first master position [master u]."""
        self.period = masters[-1] - masters[0]
        """The master length of the table [master u]."""
        first = self.segment(0, 0.0)
        last = self.segment(len(kinds) - 1, masters[-1] - masters[-2])
        self.slave_start = first[0]
        self.rise = last[0] - first[0]
        """What the slave advances per period [slave u] (0 for a cam that returns)."""
        self.end_slopes = first[1], last[1]
        self._last = 0
        slope = curvature = 0.0
        for i in range(len(kinds)):
            v, a = self._peaks(i)
            slope, curvature = max(slope, v), max(curvature, a)
        self.peak_slope = slope
        """The largest |ds/dm| of the table."""
        self.peak_curvature = curvature
        """The largest |d²s/dm²| of the table."""

    def _peaks(self, i: int) -> tuple[float, float]:
        """The largest |slope| and |curvature| of segment ``i``, exact: for a line and the
        modified laws from their closed forms (f′ runs from 0 to Cv, |f″| up to Ca), for a
        polynomial at its ends and where its next derivative is 0 (:func:`polynomial_peaks`)."""
        c = self.coefficients[i]
        kind = self.kinds[i]
        if kind != _POLY:
            v, h, d = c[1], c[2], c[3]
            cv, ca = (
                (4.0 * _PI * _MS_K, 4.0 * _PI * _PI * _MS_K) if kind == _SINE else (2.0, _TRAP_A)
            )
            return max(abs(v), abs(v + d / h * cv)), abs(d) / (h * h) * ca
        return polynomial_peaks(c, self.masters[i + 1] - self.masters[i])

    def segment(self, i: int, u: float) -> tuple[float, float, float]:
        """Slave position, slope and curvature in segment ``i`` at ``u`` from its start."""
        c = self.coefficients[i]
        kind = self.kinds[i]
        if kind == _POLY:
            return polynomial(c, u)
        s0, v, h, d = c[0], c[1], c[2], c[3]
        z = u / h
        f, f1, f2 = modified_sine(z) if kind == _SINE else modified_trapezoid(z)
        return s0 + v * u + d * f, v + d / h * f1, d / (h * h) * f2

    def cycle(self, m: float) -> int:
        """The period number of master position ``m`` (0 in the table's own range)."""
        if not self.periodic or self.period <= 0.0:
            return 0
        return math.floor((m - self.start) / self.period)

    def at(self, m: float) -> tuple[float, float, float]:
        """Slave position [slave u], slope ds/dm and curvature d²s/dm² at master ``m``.

        Periodic: the table repeats every :attr:`period`, the slave advancing :attr:`rise` per
        period. Not periodic: beyond its ends the slave goes on along the end slope (its
        position and velocity stay continuous)."""
        masters = self.masters
        base = 0.0
        if self.periodic:
            k = self.cycle(m)
            if k:
                m -= k * self.period
                base = k * self.rise
        elif m < masters[0]:
            v = self.end_slopes[0]
            return self.slave_start + v * (m - masters[0]), v, 0.0
        elif m > masters[-1]:
            v = self.end_slopes[1]
            return self.slave_start + self.rise + v * (m - masters[-1]), v, 0.0
        i = self._last
        n = len(self.kinds)
        if not masters[i] <= m < masters[i + 1]:
            i = min(max(bisect.bisect_right(masters, m) - 1, 0), n - 1)
            self._last = i
        p, v, a = self.segment(i, m - masters[i])
        return base + p, v, a


def _points(table: Any) -> list[tuple[float, float, float, float, int]] | str:
    """The points of a table as (master, slave, slope, curvature, law), or why it has none."""
    points = getattr(table, "Points", None)
    if isinstance(points, str | bytes) or not isinstance(points, Sequence):
        return "the table has no Points (a sequence of MC_CamPoint)"
    count = getattr(table, "NumberOfPoints", None)
    used = len(points) if count is None else count
    if isinstance(used, bool) or not isinstance(used, int) or not 0 <= used <= len(points):
        return f"NumberOfPoints {count!r} is not 0 … {len(points)} (the points given)"
    if used < 2:
        return f"a cam table needs at least 2 points, it has {used}"
    if used > MAX_POINTS:
        return f"a cam table has at most {MAX_POINTS} points, it has {used}"
    result: list[tuple[float, float, float, float, int]] = []
    for i, point in enumerate(points[:used]):
        if hasattr(point, "Master"):
            fields = [
                point.Master,
                getattr(point, "Slave", math.nan),
                getattr(point, "Velocity", math.nan),
                getattr(point, "Acceleration", math.nan),
                getattr(point, "Law", 0),
            ]
        elif isinstance(point, Sequence) and not isinstance(point, str | bytes):
            defaults: list[Any] = [math.nan, math.nan, math.nan, math.nan, CamLaw.Linear]
            fields = [*point, *defaults[len(point) :]] if 2 <= len(point) <= 5 else []
        else:
            fields = []
        if not fields:
            return f"point {i} is neither an MC_CamPoint nor (Master, Slave[, …]): {point!r}"
        m, s, v, a = (number(x) for x in fields[:4])
        if not (math.isfinite(m) and math.isfinite(s)):
            return f"point {i}: Master {m} and Slave {s} must be finite"
        if math.isinf(v) or math.isinf(a):
            return (
                f"point {i}: Velocity {v} and Acceleration {a} must be finite (or NaN: not given)"
            )
        law = fields[4]
        if isinstance(law, bool) or not isinstance(law, int) or law not in tuple(CamLaw):
            return f"point {i}: Law {law!r} is not a CamLaw (0 … {len(CamLaw) - 1})"
        if result and not m > result[-1][0]:
            return f"point {i}: Master {m} does not increase (point {i - 1}: {result[-1][0]})"
        result.append((m, s, v, a, int(law)))
    return result


def _given(x: float) -> float:
    return 0.0 if math.isnan(x) else x


def _tridiagonal(a: list[float], b: list[float], c: list[float], r: list[float]) -> list[float]:
    """Solve ``a[i]·x[i−1] + b[i]·x[i] + c[i]·x[i+1] = r[i]`` (Thomas algorithm; ``a[0]`` and
    ``c[-1]`` unused); the spline systems are diagonally dominant."""
    n = len(b)
    cp, rp = [0.0] * n, [0.0] * n
    cp[0], rp[0] = c[0] / b[0], r[0] / b[0]
    for i in range(1, n):
        w = b[i] - a[i] * cp[i - 1]
        cp[i] = c[i] / w
        rp[i] = (r[i] - a[i] * rp[i - 1]) / w
    x = [0.0] * n
    x[-1] = rp[-1]
    for i in range(n - 2, -1, -1):
        x[i] = rp[i] - cp[i] * x[i + 1]
    return x


def spline_slopes(
    x: list[float], y: list[float], v0: float, v1: float, periodic: bool
) -> list[float]:
    """The slopes at the knots of the cubic spline through (``x``, ``y``): continuous slope and
    curvature at the inner knots, ``h[i]·m[i−1] + 2(h[i−1] + h[i])·m[i] + h[i−1]·m[i+1] =
    3(h[i]·d[i−1] + h[i−1]·d[i])`` (de Boor, A Practical Guide to Splines, ch. IV); at the ends
    the slope ``v0`` / ``v1`` where given (not NaN), else natural (curvature 0); ``periodic``:
    slope and curvature the same at both ends (the slave's rise over the period is kept)."""
    n = len(x) - 1
    h = [x[i + 1] - x[i] for i in range(n)]
    d = [(y[i + 1] - y[i]) / h[i] for i in range(n)]
    if periodic:
        if n == 1:
            return [d[0], d[0]]
        # unknowns m[0] … m[n−1] (m[n] = m[0]): a cyclic system, solved with Sherman–Morrison
        a = [h[i] for i in range(n)]
        b = [2.0 * (h[i - 1] + h[i]) for i in range(n)]
        c = [h[i - 1] for i in range(n)]
        r = [3.0 * (h[i] * d[i - 1] + h[i - 1] * d[i]) for i in range(n)]
        if n == 2:
            a00, a01 = b[0], a[0] + c[0]
            a10, a11 = a[1] + c[1], b[1]
            det = a00 * a11 - a01 * a10
            m0 = (r[0] * a11 - a01 * r[1]) / det
            m1 = (a00 * r[1] - a10 * r[0]) / det
            return [m0, m1, m0]
        corner_low, corner_high = a[0], c[n - 1]  # m[n−1] in row 0, m[0] in row n−1
        gamma = -b[0]
        bb = list(b)
        bb[0] -= gamma
        bb[n - 1] -= corner_low * corner_high / gamma
        first = _tridiagonal(a, bb, c, r)
        u = [0.0] * n
        u[0], u[n - 1] = gamma, corner_high
        z = _tridiagonal(a, bb, c, u)
        factor = (first[0] + corner_low * first[n - 1] / gamma) / (
            1.0 + z[0] + corner_low * z[n - 1] / gamma
        )
        m = [first[i] - factor * z[i] for i in range(n)]
        return [*m, m[0]]
    a = [0.0] * (n + 1)
    b = [0.0] * (n + 1)
    c = [0.0] * (n + 1)
    r = [0.0] * (n + 1)
    if math.isnan(v0):
        b[0], c[0], r[0] = 2.0, 1.0, 3.0 * d[0]
    else:
        b[0], r[0] = 1.0, v0
    for i in range(1, n):
        a[i], b[i], c[i] = h[i], 2.0 * (h[i - 1] + h[i]), h[i - 1]
        r[i] = 3.0 * (h[i] * d[i - 1] + h[i - 1] * d[i])
    if math.isnan(v1):
        a[n], b[n], r[n] = 1.0, 2.0, 3.0 * d[n - 1]
    else:
        b[n], r[n] = 1.0, v1
    return _tridiagonal(a, b, c, r)


def _spline_runs(
    pts: list[tuple[float, float, float, float, int]], periodic: bool
) -> dict[int, list[float]]:
    """Cubic coefficients (of ``u`` from the segment's start) of each run of CubicSpline
    segments."""
    n = len(pts) - 1
    laws = [p[4] for p in pts[:n]]
    result: dict[int, list[float]] = {}
    whole = periodic and all(law == CamLaw.CubicSpline for law in laws)
    runs: list[tuple[int, int]] = [(0, n)] if whole else []
    i = 0
    while i < n and not whole:
        if laws[i] != CamLaw.CubicSpline:
            i += 1
            continue
        j = i
        while j < n and laws[j] == CamLaw.CubicSpline:
            j += 1
        runs.append((i, j))
        i = j
    for i, j in runs:
        x = [pts[k][0] for k in range(i, j + 1)]
        y = [pts[k][1] for k in range(i, j + 1)]
        m = spline_slopes(x, y, pts[i][2], pts[j][2], whole)
        for k in range(i, j):
            q = k - i
            h = x[q + 1] - x[q]
            d = (y[q + 1] - y[q]) / h
            c2 = (3.0 * d - 2.0 * m[q] - m[q + 1]) / h
            c3 = (m[q] + m[q + 1] - 2.0 * d) / (h * h)
            result[k] = [y[q], m[q], c2, c3, 0.0, 0.0]
    return result


def _level(a: int, b: int) -> int:
    """What a junction between segments of laws ``a`` and ``b`` must keep continuous: 0 the
    position only (two Linear), 2 slope and curvature (two motion laws), else 1 the slope."""
    if a == CamLaw.Linear and b == CamLaw.Linear:
        return 0
    laws = (CamLaw.Polynomial5, CamLaw.ModifiedSine, CamLaw.ModifiedTrapezoid)
    return 2 if a in laws and b in laws else 1


def _jump(x: float, y: float, scale: float) -> bool:
    return abs(x - y) > TOLERANCE * max(abs(x), abs(y), scale)


def compile_cam(table: Any, periodic: bool) -> Cam | str:
    """The checked cam of ``table`` (an :class:`MC_CAM_REF` or an object with its fields), or
    the reason it is refused (see the module text)."""
    problem = getattr(table, "Problem", "")
    if problem:
        return str(problem)
    pts = _points(table)
    if isinstance(pts, str):
        return pts
    n = len(pts) - 1
    splines = (
        _spline_runs(pts, periodic) if any(p[4] == CamLaw.CubicSpline for p in pts[:n]) else {}
    )
    kinds: list[int] = []
    coefficients: list[list[float]] = []
    for i in range(n):
        m0, s0, v0, a0, law = pts[i]
        m1, s1, v1, a1, _ = pts[i + 1]
        h, ds = m1 - m0, s1 - s0
        if law == CamLaw.Linear:
            kinds.append(_POLY)
            coefficients.append([s0, ds / h, 0.0, 0.0, 0.0, 0.0])
        elif law == CamLaw.CubicSpline:
            kinds.append(_POLY)
            coefficients.append(splines[i])
        elif law == CamLaw.Polynomial5:
            c = quintic(h, ds, _given(v0), _given(a0), _given(v1), _given(a1))
            kinds.append(_POLY)
            coefficients.append([s0, c[1], c[2], c[3], c[4], c[5]])
        else:
            name = CamLaw(law).name
            v = _given(v0)
            if _jump(v, _given(v1), abs(ds / h)):
                return (
                    f"segment {i} ({name}): the slope must be the same at both ends, "
                    f"Velocity {v} at point {i}, {_given(v1)} at point {i + 1}"
                )
            for j, acc in ((i, a0), (i + 1, a1)):
                if not math.isnan(acc) and acc != 0.0:
                    return f"segment {i} ({name}): Acceleration at point {j} must be 0 or NaN"
            kinds.append(_SINE if law == CamLaw.ModifiedSine else _TRAP)
            coefficients.append([s0, v, h, ds - v * h])
    cam = Cam([p[0] for p in pts], kinds, coefficients, periodic, [p[4] for p in pts[:n]])
    return _check_junctions(cam, [p[4] for p in pts[:n]]) or cam


def _check_junctions(cam: Cam, laws: list[int]) -> str:
    """Why the slope or curvature jumps at a point where the laws promise continuity ("": no)."""
    n = len(laws)
    masters = cam.masters
    scale = 0.0  # the steepest chord: what a jump of the slope is measured against
    shortest = math.inf
    for i in range(n):
        h = masters[i + 1] - masters[i]
        chord = cam.segment(i, h)[0] - cam.segment(i, 0.0)[0]
        scale, shortest = max(scale, abs(chord / h)), min(shortest, h)
    junctions = [(i, i - 1, i) for i in range(1, n)]
    if cam.periodic:
        junctions.append((n, n - 1, 0))
    for point, left, right in junctions:
        level = _level(laws[left], laws[right])
        if level == 0:
            continue
        _, v_l, a_l = cam.segment(left, masters[left + 1] - masters[left])
        _, v_r, a_r = cam.segment(right, 0.0)
        where = "at the period boundary" if point == n else f"at point {point}"
        if _jump(v_l, v_r, scale):
            return f"the slope jumps {where}: {v_l:.6g} before, {v_r:.6g} after"
        if level == 2 and _jump(a_l, a_r, scale / shortest):
            return f"the curvature jumps {where}: {a_l:.6g} before, {a_r:.6g} after"
    return ""


# ------------------------------------------------------------------------------ rotary knife
def rotary_knife(
    cut_length: float,
    circumference: float,
    blades: int,
    sync_angle: float,
    law: int = CamLaw.ModifiedSine,
) -> MC_CAM_REF:
    """The cam of a rotary cross cutter: master = web position over one cut length [mm],
    slave = drum angle over 360°/``blades`` [°].

    The cut is at the period boundary (master 0, slave 0: a blade at the anvil). Over
    ``sync_angle`` [°] of drum rotation centred on the cut, the blade tip's surface speed equals
    the web's (slope 360°/``circumference``); between, the drum speeds up (a cut shorter than
    circumference/blades) or slows down (a longer one) along ``law`` (ModifiedSine,
    ModifiedTrapezoid or Polynomial5), a velocity-to-velocity transition of the same slope at
    both ends. Points: 0 (sync), sync end, transition end, one cut length.

    What the drum cannot do (:func:`knife_problem`) is in the table's ``Problem``:
    MC_CamTableSelect refuses it with ``EParam`` and that reason.

    Args:
        cut_length: the length of one piece [mm].
        circumference: the circle of the blade tips [mm].
        blades: blades on the drum (1 …).
        sync_angle: drum rotation in sync with the web around each cut [°].
        law: the motion law between the sync zones.
    """
    problem = knife_problem(cut_length, circumference, blades, sync_angle, law)
    if problem:
        return MC_CAM_REF(Points=(), NumberOfPoints=None, Problem=problem)
    name = (
        f"rotary knife {cut_length:g} mm, {circumference:g} mm drum, {blades} blade"
        f"{'s' if blades > 1 else ''}, sync {sync_angle:g}°"
    )
    pitch = 360.0 / blades
    k = 360.0 / circumference
    half = 0.5 * sync_angle
    w = half / k
    if w == 0.0:
        return MC_CAM_REF(
            Points=[
                MC_CamPoint(0.0, 0.0, k, 0.0, law),
                MC_CamPoint(cut_length, pitch, k, 0.0, CamLaw.Linear),
            ],
            NumberOfPoints=None,
            Name=name,
        )
    return MC_CAM_REF(
        Points=[
            MC_CamPoint(0.0, 0.0, k, math.nan, CamLaw.Linear),
            MC_CamPoint(w, half, k, 0.0, law),
            MC_CamPoint(cut_length - w, pitch - half, k, 0.0, CamLaw.Linear),
            MC_CamPoint(cut_length, pitch, k, math.nan, CamLaw.Linear),
        ],
        NumberOfPoints=None,
        Name=name,
    )


def knife_problem(
    cut_length: float, circumference: float, blades: int, sync_angle: float, law: int
) -> str:
    """Why the drum cannot cut ``cut_length`` ("" when it can): invalid values, a sync zone
    longer than the piece, or a transition that would turn the drum backwards (the slowest
    slope of the law's velocity-to-velocity transition below 0)."""
    values = (cut_length, circumference, sync_angle)
    if not all(math.isfinite(x) for x in values) or cut_length <= 0.0 or circumference <= 0.0:
        return f"cut length {cut_length} and circumference {circumference} must be finite > 0"
    if isinstance(blades, bool) or not isinstance(blades, int) or blades < 1:
        return f"blades {blades!r} must be an integer >= 1"
    pitch = 360.0 / blades
    if not 0.0 <= sync_angle < pitch:
        return f"sync angle {sync_angle}° must be >= 0 and below 360°/blades = {pitch:g}°"
    if law not in (CamLaw.ModifiedSine, CamLaw.ModifiedTrapezoid, CamLaw.Polynomial5):
        return f"law {law!r} must be ModifiedSine, ModifiedTrapezoid or Polynomial5"
    k = 360.0 / circumference
    sync = sync_angle / k
    if cut_length <= sync:
        return (
            f"cut length {cut_length:g} mm is not longer than the sync zone "
            f"({sync:g} mm of web for {sync_angle:g}° at {circumference:g} mm circumference)"
        )
    h = cut_length - sync
    deviation = (pitch - sync_angle) - k * h
    peak = {CamLaw.ModifiedSine: 4.0 * math.pi * _MS_K, CamLaw.ModifiedTrapezoid: 2.0}.get(
        CamLaw(law), 1.875
    )
    slowest = k + min(0.0, deviation / h * peak)
    if slowest < 0.0:
        longest = (pitch - sync_angle) / k * peak / (peak - 1.0) + sync
        return (
            f"cut length {cut_length:g} mm: the drum would turn backwards between the cuts "
            f"(the longest cut with this sync angle and law is {longest:.6g} mm)"
        )
    return ""


__all__ = [
    "MAX_POINTS",
    "MC_CAM_REF",
    "Cam",
    "CamLaw",
    "MC_CamPoint",
    "compile_cam",
    "knife_problem",
    "rotary_knife",
]

"""Cam tables (mcl.cam_table): the motion laws against their textbook closed forms, the cubic
spline's continuity, periodic tables across the period boundary, the rotary-knife helper, and
every malformed table refused by MC_CamTableSelect with EParam and its reason.

The closed forms below are written independently of the library, with the numerical constants
of R. L. Norton, Cam Design and Manufacturing Handbook (2nd ed.), ch. 3 (modified sine, modified
trapezoid) and VDI 2143 Blatt 1 (the 3-4-5 polynomial), for a rise of 1 over a master length of 1.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mcl
from mcl.cam_table import MAX_POINTS, CamLaw, MC_CamPoint, compile_cam, knife_problem
from tests.helpers import make_machine

Z = np.linspace(0.0, 1.0, 10000)
"""The 10 000 master positions of a unit segment at which each law is compared."""
PI = math.pi


def modified_sine(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Norton, eq. 3.19 (β = 1, h = 1)."""
    w = 4.0 * PI * z
    u = 4.0 * PI / 3.0 * z - PI / 6.0
    middle = (z > 0.125) & (z < 0.875)
    end = z >= 0.875
    s = np.where(middle, 0.28004957 + 0.43990085 * z - 0.31505577 * np.cos(u), 0.0)
    s = np.where(
        ~middle, 0.43990085 * z - 0.03500624 * np.sin(w) + np.where(end, 0.56009915, 0.0), s
    )
    v = np.where(middle, 0.43990085 + 1.31970255 * np.sin(u), 0.43990085 * (1.0 - np.cos(w)))
    a = np.where(middle, 5.52795707 * np.cos(u), 5.52795707 * np.sin(w))
    return s, v, a


def modified_trapezoid(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Norton, eq. 3.16 (β = 1, h = 1), piece by piece."""
    A, w = 4.88812376, 4.0 * PI * z
    pieces = [
        (
            z <= 0.125,
            0.38898448 * z - 0.03095448 * np.sin(w),
            0.38898448 * (1.0 - np.cos(w)),
            A * np.sin(w),
        ),
        (
            (z > 0.125) & (z <= 0.375),
            2.44406188 * z * z - 0.22203097 * z + 0.00723407,
            A * z - 0.22203097,
            A + 0.0 * z,
        ),
        (
            (z > 0.375) & (z <= 0.625),
            1.61101545 * z - 0.03095448 * np.sin(w - PI) - 0.30550773,
            1.61101545 - 0.38898448 * np.cos(w - PI),
            A * np.sin(w - PI),
        ),
        (
            (z > 0.625) & (z <= 0.875),
            4.6660917 * z - 2.44406188 * z * z - 1.2292648,
            4.6660917 - A * z,
            -A + 0.0 * z,
        ),
        (
            z > 0.875,
            0.61101552 + 0.38898448 * z + 0.03095448 * np.sin(w - 3.0 * PI),
            0.38898448 * (1.0 + np.cos(w - 3.0 * PI)),
            -A * np.sin(w - 3.0 * PI),
        ),
    ]
    s, v, a = np.zeros_like(z), np.zeros_like(z), np.zeros_like(z)
    for mask, ps, pv, pa in pieces:
        s, v, a = np.where(mask, ps, s), np.where(mask, pv, v), np.where(mask, pa, a)
    return s, v, a


def polynomial_345(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """VDI 2143: 10z³ − 15z⁴ + 6z⁵."""
    return (
        10 * z**3 - 15 * z**4 + 6 * z**5,
        30 * z**2 - 60 * z**3 + 30 * z**4,
        60 * z - 180 * z**2 + 120 * z**3,
    )


LAWS = {
    CamLaw.ModifiedSine: (modified_sine, 1.7596, 5.5280),
    CamLaw.ModifiedTrapezoid: (modified_trapezoid, 2.0000, 4.8881),
    CamLaw.Polynomial5: (polynomial_345, 1.8750, 5.7735),
}
"""Law → (closed form, Cv, Ca): the peak slope and curvature of a unit rise (Norton, table 3-2)."""


def evaluate(cam: mcl.cam_table.Cam, masters: np.ndarray) -> np.ndarray:
    return np.array([cam.at(float(m)) for m in masters])


def table(*points: object) -> mcl.MC_CAM_REF:
    return mcl.MC_CAM_REF(Points=list(points))


@pytest.mark.parametrize("law", list(LAWS), ids=lambda law: CamLaw(law).name)
def test_each_law_matches_its_closed_form_at_10000_points(law: CamLaw):
    closed, cv, ca = LAWS[law]
    # a rise of 40 over 250 master units: s = 40 f(z), ds/dm = 40/250 f', d²s/dm² = 40/250² f''
    cam = compile_cam(table(MC_CamPoint(100.0, 10.0, 0.0, 0.0, law), (350.0, 50.0)), False)
    assert not isinstance(cam, str), cam
    got = evaluate(cam, 100.0 + 250.0 * Z)
    s, v, a = closed(Z)
    # the textbook constants have eight digits
    assert np.max(np.abs(got[:, 0] - (10.0 + 40.0 * s))) < 40.0 * 2e-6
    assert np.max(np.abs(got[:, 1] - 40.0 / 250.0 * v)) < 40.0 / 250.0 * 2e-6
    assert np.max(np.abs(got[:, 2] - 40.0 / 250.0**2 * a)) < 40.0 / 250.0**2 * 2e-6
    assert np.max(got[:, 1]) * 250.0 / 40.0 == pytest.approx(cv, abs=1e-4)
    assert np.max(np.abs(got[:, 2])) * 250.0**2 / 40.0 == pytest.approx(ca, abs=1e-3)


@pytest.mark.parametrize("law", [CamLaw.ModifiedSine, CamLaw.ModifiedTrapezoid])
def test_a_modified_law_between_equal_slopes_is_the_law_on_the_deviation(law: CamLaw):
    # slope 0.3 at both ends: s = s0 + 0.3·Δm·z + (Δs − 0.3·Δm)·f(z)
    cam = compile_cam(table(MC_CamPoint(0.0, 0.0, 0.3, 0.0, law), (200.0, 100.0, 0.3)), False)
    assert not isinstance(cam, str), cam
    got = evaluate(cam, 200.0 * Z)
    s, v, a = LAWS[law][0](Z)
    deviation = 100.0 - 0.3 * 200.0
    assert np.max(np.abs(got[:, 0] - (60.0 * Z + deviation * s))) < deviation * 2e-6
    assert np.max(np.abs(got[:, 1] - (0.3 + deviation / 200.0 * v))) < deviation / 200.0 * 2e-6
    assert np.max(np.abs(got[:, 2] - deviation / 200.0**2 * a)) < deviation / 200.0**2 * 2e-6


def test_a_quintic_meets_the_given_slopes_and_curvatures():
    cam = compile_cam(
        table(MC_CamPoint(0.0, 1.0, 0.5, -0.01, CamLaw.Polynomial5), (10.0, 4.0, -0.2, 0.03)),
        False,
    )
    assert not isinstance(cam, str), cam
    assert cam.at(0.0) == pytest.approx((1.0, 0.5, -0.01), abs=1e-12)
    assert cam.at(10.0 - 1e-12) == pytest.approx((4.0, -0.2, 0.03), abs=1e-9)


def test_a_cubic_spline_passes_its_points_with_continuous_slope_and_curvature():
    xs = [0.0, 1.0, 2.5, 3.0, 5.0]
    ys = [0.0, 2.0, 1.0, 3.0, 3.5]
    points = [
        MC_CamPoint(x, y, math.nan, math.nan, CamLaw.CubicSpline)
        for x, y in zip(xs, ys, strict=True)
    ]
    points[0].Velocity = 1.5  # clamped at the start, natural at the end
    cam = compile_cam(table(*points), False)
    assert not isinstance(cam, str), cam
    for x, y in zip(xs, ys, strict=True):
        assert cam.at(x)[0] == pytest.approx(y, abs=1e-12)
    for x in xs[1:-1]:
        before, after = cam.at(x - 1e-9), cam.at(x + 1e-9)
        assert before[1] == pytest.approx(after[1], abs=1e-6)
        assert before[2] == pytest.approx(after[2], abs=1e-5)
    assert cam.at(0.0)[1] == pytest.approx(1.5)
    assert cam.at(5.0 - 1e-12)[2] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("ends", ["natural", "clamped", "periodic"])
def test_the_cubic_spline_is_scipys_at_10000_points(ends: str):
    from scipy.interpolate import CubicSpline

    rng = np.random.default_rng(7)
    xs = np.cumsum(rng.uniform(0.5, 2.0, 12))
    ys = rng.uniform(-3.0, 3.0, 12)
    v0, v1 = (0.7, -1.2) if ends == "clamped" else (math.nan, math.nan)
    points = [
        MC_CamPoint(x, y, math.nan, math.nan, CamLaw.CubicSpline)
        for x, y in zip(xs, ys, strict=True)
    ]
    points[0].Velocity, points[-1].Velocity = v0, v1
    cam = compile_cam(table(*points), ends == "periodic")
    assert not isinstance(cam, str), cam
    if ends == "periodic":  # scipy's periodic spline needs y[0] = y[-1]: the rise taken out
        rise = (ys[-1] - ys[0]) / (xs[-1] - xs[0])
        flat = ys - rise * (xs - xs[0])
        flat[-1] = flat[0]
        ref = CubicSpline(xs, flat, bc_type="periodic")
    else:
        rise = 0.0
        ref = CubicSpline(xs, ys, bc_type="natural" if ends == "natural" else ((1, v0), (1, v1)))
    masters = xs[0] + (xs[-1] - xs[0]) * Z
    got = evaluate(cam, masters)
    assert np.max(np.abs(got[:, 0] - ref(masters) - rise * (masters - xs[0]))) < 1e-9
    assert np.max(np.abs(got[:, 1] - ref(masters, 1) - rise)) < 1e-9
    assert np.max(np.abs(got[:, 2] - ref(masters, 2))) < 1e-8


def test_a_periodic_spline_is_smooth_across_the_period_boundary_and_rises_per_period():
    points = [
        MC_CamPoint(x, y, math.nan, math.nan, CamLaw.CubicSpline)
        for x, y in ((0.0, 0.0), (1.0, 2.0), (2.0, 1.5), (4.0, 6.0))
    ]
    cam = compile_cam(table(*points), True)
    assert not isinstance(cam, str), cam
    assert cam.rise == 6.0 and cam.period == 4.0
    for k in range(-2, 4):
        before, after = cam.at(4.0 * k - 1e-9), cam.at(4.0 * k + 1e-9)
        assert before[0] == pytest.approx(6.0 * k, abs=1e-7)
        assert before == pytest.approx(after, abs=1e-5)


@pytest.mark.parametrize("cut", [600.0, 1800.0])
@pytest.mark.parametrize("law", list(LAWS), ids=lambda law: CamLaw(law).name)
def test_the_knife_cam_matches_the_web_in_the_sync_zone_and_is_smooth_at_the_cut(cut, law):
    circumference, sync = 1000.0, 60.0
    cam = compile_cam(mcl.rotary_knife(cut, circumference, 1, sync, law), True)
    assert not isinstance(cam, str), cam
    k = 360.0 / circumference
    w = 0.5 * sync / k  # web length of half the sync zone [mm]
    assert cam.period == cut and cam.rise == 360.0
    for m in np.linspace(-w, w, 101):
        for period in range(-1, 3):
            s, slope, curvature = cam.at(float(m) + period * cut)
            assert s == pytest.approx(k * float(m) + 360.0 * period, abs=1e-9)
            assert slope == pytest.approx(k, rel=1e-12)
            assert curvature == pytest.approx(0.0, abs=1e-12)
    samples = evaluate(cam, np.linspace(0.0, cut, 2001))
    assert np.all(np.diff(samples[:, 0]) > 0.0), "the drum never stands or turns back"
    assert np.all(np.abs(np.diff(samples[:, 1])) < 0.01 * cam.peak_slope), "no slope jump"


def test_two_blades_share_the_drum_turn():
    cam = compile_cam(mcl.rotary_knife(300.0, 1000.0, 2, 40.0), True)
    assert not isinstance(cam, str), cam
    assert cam.rise == 180.0


def test_the_knife_helper_refuses_what_the_drum_cannot_do_and_says_why():
    law = CamLaw.ModifiedSine
    reason = knife_problem(3000.0, 1000.0, 1, 60.0, law)
    assert "backwards" in reason
    longest = float(reason.split("is ")[-1].split(" mm")[0])
    assert knife_problem(longest * 0.999, 1000.0, 1, 60.0, law) == ""
    assert knife_problem(longest * 1.001, 1000.0, 1, 60.0, law) != ""
    assert "sync zone" in knife_problem(100.0, 1000.0, 1, 60.0, law)
    assert "360°/blades" in knife_problem(600.0, 1000.0, 2, 180.0, law)
    assert "blades" in knife_problem(600.0, 1000.0, 0, 60.0, law)
    assert "finite" in knife_problem(math.nan, 1000.0, 1, 60.0, law)
    assert "law" in knife_problem(600.0, 1000.0, 1, 60.0, CamLaw.Linear)
    assert mcl.rotary_knife(3000.0, 1000.0, 1, 60.0).Problem == reason


def _points(n: int) -> list[tuple[float, float]]:
    return [(float(i), 0.0) for i in range(n)]


P5 = CamLaw.Polynomial5
MALFORMED = {
    "no table": (None, "no Points"),
    "one point": (table((0.0, 0.0)), "at least 2 points"),
    "too many points": (table(*_points(MAX_POINTS + 1)), f"at most {MAX_POINTS}"),
    "NumberOfPoints": (mcl.MC_CAM_REF(Points=_points(3), NumberOfPoints=4), "NumberOfPoints"),
    "not a point": (table((0.0, 0.0), "abc"), "point 1 is neither"),
    "master NaN": (table((0.0, 0.0), (math.nan, 1.0)), "must be finite"),
    "slave infinite": (table((0.0, 0.0), (1.0, math.inf)), "must be finite"),
    "velocity infinite": (table((0.0, 0.0, math.inf), (1.0, 1.0)), "must be finite"),
    "master not increasing": (table((0.0, 0.0), (2.0, 1.0), (1.0, 2.0)), "does not increase"),
    "master repeated": (table((0.0, 0.0), (0.0, 1.0)), "does not increase"),
    "unknown law": (table((0.0, 0.0, 0.0, 0.0, 9), (1.0, 1.0)), "is not a CamLaw"),
    "modified law, different slopes": (
        table(MC_CamPoint(0.0, 0.0, 0.0, 0.0, CamLaw.ModifiedSine), (1.0, 1.0, 0.5)),
        "the same at both ends",
    ),
    "slope jump": (
        table((0.0, 0.0, 0.0, 0.0, P5), (1.0, 1.0, 0.0, 0.0, CamLaw.Linear), (2.0, 3.0)),
        "the slope jumps at point 1",
    ),
    "curvature jump": (
        table(
            (0.0, 0.0, 0.0, 0.0, P5),
            MC_CamPoint(1.0, 1.0, 0.0, 0.5, CamLaw.ModifiedSine),
            (2.0, 2.0),
        ),
        "Acceleration at point 1 must be 0",
    ),
    "periodic slope jump": (
        table((0.0, 0.0, 0.0, 0.0, P5), (1.0, 1.0, 1.0, 0.0, P5), (2.0, 2.0, 0.5, 0.0)),
        "at the period boundary",
    ),
    "periodic curvature jump": (
        table((0.0, 0.0, 1.0, 0.0, P5), (1.0, 1.0, 1.0, 0.0, P5), (2.0, 2.0, 1.0, 0.3)),
        "the curvature jumps at the period boundary",
    ),
    "knife too long": (mcl.rotary_knife(3000.0, 1000.0, 1, 60.0), "backwards"),
}
"""Malformed table → (the table, what its reason says). All periodic."""


@pytest.fixture(scope="module")
def two_axes() -> mcl.SimMachine:
    return make_machine("MS")


@pytest.mark.parametrize("case", list(MALFORMED))
def test_a_malformed_table_gives_eparam_with_its_reason(two_axes, case):
    bad, reason = MALFORMED[case]
    M, S = two_axes.axes["M"], two_axes.axes["S"]
    select = mcl.MC_CamTableSelect(Master=M, Slave=S, CamTable=bad, Periodic=True)
    select(Execute=True)
    assert select.Error and select.ErrorID == mcl.ErrorID.EParam and not select.Done
    assert reason in select.ErrorText, select.ErrorText
    assert select.CamTableID == 0
    select(Execute=False)
    assert not select.Error and select.ErrorID == 0


def test_a_good_table_is_selected_and_a_linear_junction_may_bend(two_axes):
    M, S = two_axes.axes["M"], two_axes.axes["S"]
    select = mcl.MC_CamTableSelect(Master=M, Slave=S, Periodic=False)
    select(Execute=True, CamTable=table((0.0, 0.0), (1.0, 1.0), (2.0, 3.0)))
    assert select.Done and select.CamTableID > 0 and select.ErrorText == ""
    first = select.CamTableID
    select(Execute=False)
    select(Execute=True, CamTable=table((0.0, 0.0), (1.0, 2.0)))
    assert select.Done and select.CamTableID == first, "one ID per instance"
    other = mcl.MC_CamTableSelect(Master=M, Slave=S, CamTable=table((0.0, 0.0), (1.0, 2.0)))
    other(Execute=True)
    assert other.Done and other.CamTableID != first
    same = mcl.MC_CamTableSelect(Master=M, Slave=M, CamTable=table((0.0, 0.0), (1.0, 2.0)))
    same(Execute=True)
    assert same.ErrorID == mcl.ErrorID.EParam and "same axis" in same.ErrorText
    bent, _ = MALFORMED["periodic curvature jump"]  # the curvature jumps only across the period
    once = mcl.MC_CamTableSelect(Master=M, Slave=S, CamTable=bent, Periodic=False)
    once(Execute=True)
    assert once.Done and once.ErrorText == ""


QUINTICS = {
    "rest to rest 0 → 100 over 360": ((0.0, 0.0, 0.0, 0.0, P5), (360.0, 100.0, 0.0, 0.0)),
    "velocity to velocity": ((0.0, 0.0, 0.2, 0.0, P5), (100.0, 40.0, 0.2, 0.0)),
    "every end given": ((0.0, 0.0, -0.3, 0.004, P5), (50.0, 10.0, 0.6, -0.01)),
    "cubic spline": (
        (0.0, 0.0, 0.5, math.nan, CamLaw.CubicSpline),
        (30.0, 20.0, math.nan, math.nan, CamLaw.CubicSpline),
        (100.0, 30.0, -0.2, math.nan),
    ),
}
"""Polynomial segments whose steepest slope and curvature lie inside them."""


@pytest.mark.parametrize("case", list(QUINTICS))
def test_the_peaks_of_a_polynomial_segment_are_its_exact_extremes(case: str) -> None:
    """The peak slope and curvature MC_CamIn checks against the slave's limits are the
    polynomial's extremes, not a sample of them: equal (within 10⁻⁹) to their maxima over
    200 000 intervals, the 3-4-5 rise to its closed form (Cv 1.875, Ca 10/√3)."""
    cam = compile_cam(table(*QUINTICS[case]), False)
    assert not isinstance(cam, str), cam
    masters = np.linspace(cam.start, cam.start + cam.period, 200_001)
    shape = evaluate(cam, masters)
    slope, curvature = np.abs(shape[:, 1]).max(), np.abs(shape[:, 2]).max()
    assert cam.peak_slope == pytest.approx(slope, rel=1e-9)
    assert cam.peak_curvature == pytest.approx(curvature, rel=1e-9)
    if case.startswith("rest to rest"):
        assert cam.peak_slope == pytest.approx(1.875 * 100.0 / 360.0, rel=1e-12)
        assert cam.peak_curvature == pytest.approx(10.0 / math.sqrt(3.0) * 100.0 / 360.0**2)


def _unit_roots(rng: np.random.Generator, case: str) -> tuple[list[float], list[float]]:
    """Coefficients (lowest first) of a polynomial built from its roots, and its real roots in
    [0, 1]: three real roots, one real root and a complex pair, a quadratic, a line."""
    poly = np.polynomial.polynomial
    if case == "three real":
        roots = sorted(rng.uniform(-0.5, 1.5, 3))
        c = list(poly.polyfromroots(roots) * rng.uniform(0.1, 50.0))
    elif case == "one real":
        real, re, im = rng.uniform(-0.5, 1.5), rng.uniform(-1.0, 2.0), rng.uniform(0.05, 1.0)
        roots = [real]
        pair = poly.polyfromroots([complex(re, im), complex(re, -im)])
        c = list(poly.polymul([-real, 1.0], pair.real) * rng.uniform(-50.0, -0.1))
    elif case == "quadratic":
        roots = sorted(rng.uniform(-0.5, 1.5, 2))
        c = list(poly.polyfromroots(roots) * rng.uniform(-9.0, 9.0))
    else:
        roots = [rng.uniform(-0.5, 1.5)]
        c = list(poly.polyfromroots(roots) * rng.uniform(0.5, 9.0))
    return [float(x) for x in c], [r for r in roots if 0.0 <= r <= 1.0]


@pytest.mark.parametrize("case", ["three real", "one real", "quadratic", "line"])
def test_the_real_roots_of_a_segment_s_derivative_are_found_in_the_unit_interval(case: str):
    """Where a polynomial segment's slope or curvature peaks (a root of its next derivative):
    every real root in [0, 1] of a cubic, quadratic or line, exact to 10⁻⁹, none outside;
    a leading coefficient 10⁻¹⁶ of the others' size is dropped (the root of the rest stays)."""
    rng = np.random.default_rng(sum(map(ord, case)))
    for _ in range(300):
        c, expected = _unit_roots(rng, case)
        found = sorted(mcl.cam_table.real_roots(c))
        assert found == pytest.approx(sorted(expected), abs=1e-9), c
        assert sorted(mcl.cam_table.real_roots([*c, 1e-16 * max(map(abs, c))])) == pytest.approx(
            sorted(expected), abs=1e-9
        )


def test_the_peaks_of_random_quintic_segments_are_never_below_their_dense_maxima():
    """MC_CamIn checks a cam's peak slope and curvature against the slave's limits: for 300
    random quintic segments (master lengths 0.1 … 500) they equal the maxima over 100 000
    intervals within 10⁻⁷ and are never below any sample (a peak read low let a cam past the
    slave's acceleration limit)."""
    rng = np.random.default_rng(32)
    z = np.linspace(0.0, 1.0, 100_001)
    for _ in range(300):
        h = float(10.0 ** rng.uniform(-1.0, 2.7))
        b = rng.normal(0.0, 1.0, 6) * 10.0 ** rng.uniform(-2.0, 2.0, 6)
        c = [float(b[k] / h**k) for k in range(6)]  # the polynomial in u = z·h
        d1 = np.polynomial.polynomial.polyder(b)
        slope = float(np.abs(np.polynomial.polynomial.polyval(z, d1)).max()) / h
        curvature = (
            float(
                np.abs(
                    np.polynomial.polynomial.polyval(z, np.polynomial.polynomial.polyder(d1))
                ).max()
            )
            / h**2
        )
        peak_slope, peak_curvature = mcl.cam_table.polynomial_peaks(c, h)
        assert peak_slope == pytest.approx(slope, rel=1e-7)
        assert peak_curvature == pytest.approx(curvature, rel=1e-7)
        assert peak_slope >= slope * (1.0 - 1e-12) and peak_curvature >= curvature * (1.0 - 1e-12)


@pytest.mark.parametrize("power", [3, 4, 5])
def test_a_segment_that_is_a_pure_power_of_the_master_peaks_at_its_end(power: int):
    """A Polynomial5 segment from rest to (1, 1) with the end slope n and curvature n(n−1) is
    s = zⁿ (its next derivative has a double root at 0): it compiles, and its peak slope and
    curvature are the end's, n and n(n−1)."""
    points = [(0.0, 0.0, 0.0, 0.0, P5), (1.0, 1.0, float(power), float(power * (power - 1)))]
    cam = compile_cam(table(*points), False)
    assert not isinstance(cam, str), cam
    assert (cam.peak_slope, cam.peak_curvature) == (power, power * (power - 1))

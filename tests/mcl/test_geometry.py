"""The shapes of a group path (mcl.geometry): arcs from each CircMode, their direction, plane,
helix, turns, extent and distance, and the inputs that describe no arc."""

from __future__ import annotations

import math

import pytest

from mcl import MC_CIRC_MODE, MC_CIRC_PATHCHOICE
from mcl.geometry import Arc, GeometryError, Line, arc

BORDER, CENTER, RADIUS = MC_CIRC_MODE.BORDER, MC_CIRC_MODE.CENTER, MC_CIRC_MODE.RADIUS
CW, CCW = MC_CIRC_PATHCHOICE.CLOCKWISE, MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE


def _on_circle(a: Arc, centre: list[float], radius: float, samples: int = 64) -> float:
    """Largest relative radius error of points along the arc."""
    worst = 0.0
    for k in range(samples + 1):
        p = a.point(a.length * k / samples)
        worst = max(worst, abs(math.dist(p, centre) - radius) / radius)
    return worst


def test_line_frame_distance_and_bounds() -> None:
    line = Line([0.0, 0.0, 0.0], [3.0, 4.0, 0.0])
    assert line.length == 5.0
    p, t, k = line.frame(2.5)
    assert p == pytest.approx([1.5, 2.0, 0.0]) and t == pytest.approx([0.6, 0.8, 0.0])
    assert k == [0.0, 0.0, 0.0]
    assert line.point(10.0) == pytest.approx([6.0, 8.0, 0.0])  # continues beyond its end
    assert line.distance([0.0, 5.0, 0.0]) == pytest.approx(3.0)
    assert line.bounds() == [(0.0, 3.0), (0.0, 4.0), (0.0, 0.0)]
    assert line.share == pytest.approx([0.6, 0.8, 0.0]) and line.curvature == 0.0


@pytest.mark.parametrize(
    ("choice", "middle"),
    [(CCW, [0.0, 10.0]), (CW, [0.0, -10.0])],
)
def test_centre_half_circle_turns_as_chosen(choice: int, middle: list[float]) -> None:
    """CENTER from (10, 0) about the origin to (−10, 0): counter-clockwise passes (0, 10),
    clockwise (0, −10), seen from +Z."""
    a = arc([10.0, 0.0], CENTER, [0.0, 0.0], [-10.0, 0.0], choice)
    assert a.length == pytest.approx(10.0 * math.pi)
    assert a.point(a.length / 2) == pytest.approx(middle, abs=1e-12)
    assert a.end == [-10.0, 0.0]
    assert a.curvature == pytest.approx(0.1) and a.curvature_rate == pytest.approx(0.01)
    assert _on_circle(a, [0.0, 0.0], 10.0) < 1e-15


def test_centre_full_circle_and_turns() -> None:
    """The end on the start: a full circle; Turns adds full turns."""
    one = arc([5.0, 0.0], CENTER, [0.0, 0.0], [5.0, 0.0], CCW)
    three = arc([5.0, 0.0], CENTER, [0.0, 0.0], [5.0, 0.0], CCW, turns=2)
    assert one.sweep == pytest.approx(2 * math.pi)
    assert three.length == pytest.approx(3 * one.length)
    assert one.point(one.length / 4) == pytest.approx([0.0, 5.0], abs=1e-12)
    assert three.point(three.length) == pytest.approx([5.0, 0.0], abs=1e-12)
    quarter = arc([5.0, 0.0], CENTER, [0.0, 0.0], [0.0, 5.0], CCW, turns=1)
    assert quarter.sweep == pytest.approx(2.5 * math.pi)


def test_centre_moved_onto_the_bisector_within_the_tolerance() -> None:
    """An end point 0.05 % off the circle (a rounded centre): the arc runs exactly through both
    points about a centre on the chord's bisector."""
    a = arc([10.0, 0.0], CENTER, [0.0, 0.0], [0.0, 10.005], CCW)
    assert math.dist(a.centre, [10.0, 0.0]) == pytest.approx(math.dist(a.centre, [0.0, 10.005]))
    assert a.point(a.length) == pytest.approx([0.0, 10.005], abs=1e-12)
    with pytest.raises(GeometryError, match="not on one circle"):
        arc([10.0, 0.0], CENTER, [0.0, 0.0], [0.0, 10.2], CCW)


def test_border_passes_its_three_points_in_any_plane() -> None:
    """BORDER in a tilted plane of three members: the arc runs from the start through the
    auxiliary point to the end, PathChoice ignored."""
    start, aux, end = [1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [-1.0, 0.0, 0.0]
    for choice in (CW, CCW):
        a = arc(start, BORDER, aux, end, choice)
        assert a.radius == pytest.approx(3.0 * 2.0 / (4.0 * math.sqrt(2.0)))  # abc / 4·area
        assert a.distance(aux) < 1e-12  # on the arc, between start and end
        assert a.point(a.length) == pytest.approx(end, abs=1e-12)
        for p in (start, aux, end):
            assert math.dist(p, a.centre) == pytest.approx(a.radius, rel=1e-12)
    reverse = arc(end, BORDER, aux, start)
    assert reverse.length == pytest.approx(arc(start, BORDER, aux, end).length)


@pytest.mark.parametrize(
    ("radius", "choice", "sweep", "centre"),
    [
        (10.0, CW, 60.0, [5.0, -8.660254]),
        (10.0, CCW, 60.0, [5.0, 8.660254]),
        (-10.0, CW, 300.0, [5.0, 8.660254]),
        (-10.0, CCW, 300.0, [5.0, -8.660254]),
    ],
)
def test_radius_chooses_the_centre_by_direction_and_sign(
    radius: float, choice: int, sweep: float, centre: list[float]
) -> None:
    """RADIUS from (0, 0) to (10, 0), R = 10: a positive radius the short arc (60°), a negative
    one the long arc (300°), on the side the direction gives."""
    a = arc([0.0, 0.0], RADIUS, [radius, 0.0], [10.0, 0.0], choice)
    assert math.degrees(a.sweep) == pytest.approx(sweep)
    assert a.centre == pytest.approx(centre, abs=1e-6)
    assert a.point(a.length) == pytest.approx([10.0, 0.0], abs=1e-12)


def test_radius_of_half_the_chord_is_a_half_circle() -> None:
    a = arc([0.0, 0.0], RADIUS, [5.0, 0.0], [10.0, 0.0], CCW)
    assert math.degrees(a.sweep) == pytest.approx(180.0)


@pytest.mark.parametrize(
    ("plane", "start", "end", "middle"),
    [
        (17, [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [7.0710678, 7.0710678, 0.0]),
        (18, [0.0, 0.0, 10.0], [10.0, 0.0, 0.0], [7.0710678, 0.0, 7.0710678]),
        (19, [0.0, 10.0, 0.0], [0.0, 0.0, 10.0], [0.0, 7.0710678, 7.0710678]),
    ],
)
def test_planes_turn_counter_clockwise_about_their_normal(
    plane: int, start: list[float], end: list[float], middle: list[float]
) -> None:
    """G17 turns X→Y about +Z, G18 Z→X about +Y, G19 Y→Z about +X (counter-clockwise)."""
    a = arc(start, CENTER, [0.0, 0.0, 0.0], end, CCW, plane=plane)
    assert math.degrees(a.sweep) == pytest.approx(90.0)
    assert a.point(a.length / 2) == pytest.approx(middle, abs=1e-6)


def test_helix_lifts_the_normal_axis_linearly() -> None:
    """Two turns in XY while Z rises 8 mm: Z is linear in the angle, XY on the circle."""
    a = arc([10.0, 0.0, 0.0], CENTER, [0.0, 0.0, 0.0], [10.0, 0.0, 8.0], CCW, plane=17, turns=1)
    assert a.length == pytest.approx(math.hypot(2 * math.pi * 10.0 * 2, 8.0))
    for k in range(9):
        p = a.point(a.length * k / 8)
        assert p[2] == pytest.approx(8.0 * k / 8)
        assert math.hypot(p[0], p[1]) == pytest.approx(10.0, rel=1e-14)
    assert a.curvature == pytest.approx(10.0 / (10.0**2 + (8.0 / (4 * math.pi)) ** 2))
    assert a.distance([10.0, 0.0, 4.0]) == pytest.approx(0.0, abs=1e-9)
    assert a.distance([10.0, 0.0, 2.0]) > 1.0  # between the turns
    assert a.bounds() == [
        pytest.approx((-10.0, 10.0)),
        pytest.approx((-10.0, 10.0)),
        pytest.approx((0.0, 8.0)),
    ]


def test_bounds_and_distance_of_a_quarter() -> None:
    """A quarter from (10, 0) to (0, 10) spans x and y 0…10; a point off the arc's angles is as
    far as the nearer end."""
    a = arc([10.0, 0.0], CENTER, [0.0, 0.0], [0.0, 10.0], CCW)
    assert a.bounds() == [pytest.approx((0.0, 10.0)), pytest.approx((0.0, 10.0))]
    assert a.distance([12.0, 0.0]) == pytest.approx(2.0)
    assert a.distance([0.0, -10.0]) == pytest.approx(math.dist([0.0, -10.0], [10.0, 0.0]))
    wide = arc([10.0, 0.0], CENTER, [0.0, 0.0], [0.0, -10.0], CCW)  # 270° over the top
    assert wide.bounds() == [pytest.approx((-10.0, 10.0)), pytest.approx((-10.0, 10.0))]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([0.0, 0.0], BORDER, [1.0, 1.0], [2.0, 2.0]), "on a line"),
        # a start one encoder count (1 µm) off a 100 mm line: a circle of 2.5e9 mm before
        (([300.001, 200.001], BORDER, [350.0, 200.0], [400.0, 200.0]), "on a line"),
        (([0.0, 0.0], BORDER, [50.0, 0.012], [100.0, 0.0]), "on a line"),  # R 104 167 mm
        (([0.0, 0.0], BORDER, [0.0, 0.0], [2.0, 2.0]), "three different points"),
        (([0.0, 0.0], BORDER, [1.0, 1.0], [0.0, 0.0]), "three different points"),
        (([0.0, 0.0], RADIUS, [1.0, 0.0], [10.0, 0.0]), "shorter than half the chord"),
        (([0.0, 0.0], RADIUS, [5.0, 0.0], [0.0, 0.0]), "no chord"),
        (([0.0, 0.0], CENTER, [0.0, 0.0], [1.0, 0.0]), "zero radius"),
        (([0.0, 0.0], CENTER, [5.0, 0.0], [10.0, 1.0]), "not on one circle"),
        (([0.0, math.nan], CENTER, [5.0, 0.0], [10.0, 0.0]), "finite"),
        (([0.0, 0.0], CENTER, [math.inf, 0.0], [10.0, 0.0]), "finite"),
        (([0.0, 0.0], 7, [5.0, 0.0], [10.0, 0.0]), "CircMode"),
        (([0.0, 0.0], CENTER, [5.0, 0.0], [10.0, 0.0], 2), "PathChoice"),
        (([0.0, 0.0], CENTER, [5.0, 0.0], [10.0, 0.0], CW, 16), "Plane"),
        (([0.0, 0.0], CENTER, [5.0, 0.0], [10.0, 0.0], CW, 18), "three members"),
        (([0.0, 0.0], CENTER, [5.0, 0.0], [10.0, 0.0], CW, 0, -1), "Turns"),
        (([0.0, 0.0], RADIUS, [5.0, 0.0], [10.0, 0.0], CW, 0, 1), "Turns"),
        (([0.0, 0.0, 0.0], BORDER, [1.0, 1.0, 0.0], [2.0, 0.0, 0.0], CW, 17), "Plane 0"),
        (([0.0, 0.0], CENTER, [5.0, 0.0, 0.0], [10.0, 0.0]), "two or three members"),
        (([0.0], CENTER, [5.0], [10.0]), "two or three members"),
    ],
)
def test_inputs_that_describe_no_arc(args: tuple, message: str) -> None:
    with pytest.raises(GeometryError, match=message):
        arc(*args)


def test_a_flat_border_arc_is_still_an_arc() -> None:
    """A sagitta of 0.013 mm on a 100 mm chord (R 96 154 mm, under 1000 chords): an arc through
    the three points."""
    a = arc([0.0, 0.0], BORDER, [50.0, 0.013], [100.0, 0.0])
    assert a.radius == pytest.approx((50.0**2 + 0.013**2) / (2 * 0.013))
    assert a.distance([50.0, 0.013]) == pytest.approx(0.0, abs=1e-6)

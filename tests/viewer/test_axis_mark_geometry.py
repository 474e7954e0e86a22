"""The geometry of the axis marks (viewer.view3d.axis_marks) without a server: arrow lengths
for small and large machines, the rotation that points an arrow along its joint, the part's
extent beyond the anchor, a hinge's curved arrow, where a camera draws a point and when two
labels overlap."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from viewer.view3d.axis_marks import (
    ARC_SEGMENTS,
    LABEL_LINE,
    MAX_ARROW,
    MIN_ARROW,
    AxisJoint,
    _hinge_arc,
    axis_joints,
    labels_overlap,
    mark_length,
    quat_z_to,
    rotate,
    screen_points,
)

MARGIN = 0.3 * LABEL_LINE
"""The margin between two labels side by side [px]."""


def test_arrows_grow_with_the_machine_within_their_limits() -> None:
    assert mark_length(0.1) == MIN_ARROW
    assert mark_length(2.0) == pytest.approx(0.24)
    assert mark_length(100.0) == MAX_ARROW


@pytest.mark.parametrize(
    "direction",
    [(1, 0, 0), (0, -1, 0), (-1, 0, 0), (0, 0, 1), (0, 0, -1), (0.8, 0, -0.6), (0, 0.6, -0.8)],
)
def test_an_arrow_turned_from_z_points_along_its_joint(direction: tuple[float, ...]) -> None:
    d = np.asarray(direction, dtype=np.float64)
    quat = quat_z_to(d)
    assert np.linalg.norm(quat) == pytest.approx(1.0)
    np.testing.assert_allclose(rotate(quat, np.array([0.0, 0.0, 1.0])), d, atol=1e-12)


def test_integer_directions_and_vectors_are_taken_as_numbers() -> None:
    np.testing.assert_allclose(quat_z_to(np.array([0, 0, 1])), (1.0, 0.0, 0.0, 0.0))
    half_turn_about_x = np.array([0, 1, 0, 0])
    np.testing.assert_allclose(rotate(half_turn_about_x, np.array([0, 1, 2])), (0, -1, -2))


def two_slides() -> mujoco.MjModel:
    """Two parts on slides from the world origin: ``back`` along −x, ``ahead`` along +x, each
    a box of half sizes 0.1 × 0.2 × 0.3 m 0.5 m out, a little off the axis (−y, −z)."""
    return mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody>
        <body name="machine/back"><joint name="b" type="slide" axis="-1 0 0"/>
          <geom type="box" size="0.1 0.2 0.3" pos="-0.5 -0.05 -0.02"/></body>
        <body name="ahead"><joint name="a" type="slide" axis="1 0 0"/>
          <geom type="box" size="0.1 0.2 0.3" pos="0.5 -0.05 -0.02"/></body>
        <body name="arm" pos="0 0 1"><joint name="h" type="hinge" axis="0 0 1"/>
          <geom type="box" size="0.1 0.2 0.3" pos="0.5 -0.05 -0.02"/></body>
        </worldbody></mujoco>"""
    )


def test_a_part_s_extent_beyond_its_anchor_places_its_mark() -> None:
    """A slide's mark starts beyond its part's far end along the axis; a hinge's arc turns
    outside the part's farthest corner from the axis, above its end face."""
    marks = axis_joints(two_slides(), [("B", "b"), ("A", "a"), ("H", "h"), ("N", "")])
    back, ahead, arm = marks
    assert [m.axis for m in marks] == ["B", "A", "H"]  # N has no joint: no mark
    assert (back.part, ahead.part, arm.part) == ("back", "ahead", "arm")
    assert not back.hinge and arm.hinge
    assert back.reach == pytest.approx(0.6) and back.face == pytest.approx(0.6)
    assert ahead.reach == pytest.approx(0.6)
    assert arm.reach == pytest.approx(math.hypot(0.6, 0.25))  # across the z axis
    assert arm.face == pytest.approx(0.28)  # the top face, along +z


def test_a_hinge_arc_spans_three_quarters_of_a_turn_outside_the_part() -> None:
    mark = AxisJoint("H", 0, 1, "arm", True, reach=0.2, face=0.1)
    segments, height = _hinge_arc(mark, 0.1)
    assert segments.shape == (ARC_SEGMENTS, 2, 3) and height == pytest.approx(0.11)
    np.testing.assert_allclose(segments[0, 0], (0.23, 0.0, 0.11), atol=1e-12)
    np.testing.assert_allclose(segments[-1, 1], (0.0, -0.23, 0.11), atol=1e-12)
    turns = np.unwrap(np.arctan2(segments[:, 0, 1], segments[:, 0, 0]))
    np.testing.assert_allclose(turns, np.linspace(0.0, 1.5 * math.pi, ARC_SEGMENTS + 1)[:-1])
    radii = np.linalg.norm(segments[:, :, :2], axis=2)
    np.testing.assert_allclose(radii, 0.23)
    small = AxisJoint("H", 0, 1, "arm", True, reach=0.01, face=0.0)
    np.testing.assert_allclose(np.linalg.norm(_hinge_arc(small, 0.1)[0][:, :, :2], axis=2), 0.03)


def test_a_camera_draws_points_right_and_up_from_the_centre() -> None:
    eye, target = np.array([0.0, -10.0, 10.0]), np.array([0.0, 0.0, 0.0])
    drawn = screen_points([np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])], eye, target, 190)
    np.testing.assert_allclose(drawn, [(0.0, 10.0), (190 * math.sqrt(2) / 20, 0.0)], atol=1e-9)
    farther = np.array([0.0, 2.0, 0.0])  # the same line of sight, another distance
    assert screen_points([target], eye, farther, 100)[0][0] == pytest.approx(0.0)
    down, below = np.array([0.0, 0.0, 10.0]), np.array([0.0, 0.0, 0.0])
    points = [np.array([1.0, 2.0, 0.0]), np.array([1.0, 0.0, 9.5])]
    np.testing.assert_allclose(screen_points(points, down, below, 100), [(10, 20), (200, 0)])


def test_labels_overlap_within_their_width_and_line_height_and_a_margin() -> None:
    widths = (100.0, 40.0)  # a's text is the longer
    a = (50.0, 30.0)
    assert labels_overlap(a, (50.0 + 100 + MARGIN - 0.1, 30.0), widths)  # b right of a
    assert not labels_overlap(a, (50.0 + 100 + MARGIN + 0.1, 30.0), widths)
    assert labels_overlap(a, (50.0 - 40 - MARGIN + 0.1, 30.0), widths)  # b left of a
    assert not labels_overlap(a, (50.0 - 40 - MARGIN - 0.1, 30.0), widths)
    assert not labels_overlap(a, (50.0 - 60.0, 30.0), widths)  # b's own width counts
    assert labels_overlap(a, (50.0, 30.0 + 1.3 * LABEL_LINE - 0.1), widths)
    assert not labels_overlap(a, (50.0, 30.0 + 1.3 * LABEL_LINE + 0.1), widths)
    assert not labels_overlap(a, (50.0, 30.0 - 1.3 * LABEL_LINE - 0.1), widths)
    assert not labels_overlap(a, (50.0 + 100 + MARGIN, 30.0), widths)  # just clear
    assert not labels_overlap(a, (50.0, 30.0 + 1.3 * LABEL_LINE), widths)

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
    LABEL_LIFT,
    LABEL_LINE,
    MAX_ARROW,
    MIN_ARROW,
    AxisJoint,
    _hinge_arc,
    axis_joints,
    label_slots,
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


def offset_joints() -> mujoco.MjModel:
    """A part on a slide along −z whose joint sits off its body's origin (body turned 30° about
    z), and a wheel on a hinge about +x above its part: the extents depend on the anchor, on
    the geoms' lower corners and on the part's full body name."""
    return mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody>
        <body name="rig/table/slider" pos="0.2 0.1 0.3" euler="0 0 30">
          <joint name="s" type="slide" pos="0.05 0.02 0.01" axis="0 0 -1"/>
          <geom type="box" size="0.1 0.2 0.3" pos="0 0.05 -0.1"/></body>
        <body name="wheel" pos="0 0 1"><joint name="h" type="hinge" axis="1 0 0" pos="0 0 0.1"/>
          <geom type="box" size="0.1 0.05 0.2" pos="0.1 0 -0.3"/></body>
        </worldbody></mujoco>"""
    )


def test_extents_are_measured_from_the_joint_s_anchor_to_every_corner() -> None:
    """The slide's part reaches 0.41 m along −z below an anchor 0.01 m above the body's origin
    (its box's lower face); the wheel's part lies below its hinge, 0.6 m from the axis at its
    lower corners. An axis without a joint listed first does not hide the axes after it, and
    a part is named by the last piece of its body's name."""
    slide, hinge = axis_joints(offset_joints(), [("N", ""), ("S", "s"), ("H", "h")])
    assert (slide.axis, slide.part, hinge.axis, hinge.part) == ("S", "slider", "H", "wheel")
    assert slide.reach == pytest.approx(0.41) and slide.face == pytest.approx(0.41)
    assert hinge.face == pytest.approx(0.2)
    assert hinge.reach == pytest.approx(math.hypot(0.05, 0.6))


def test_a_label_is_lifted_by_the_fewest_steps_that_clear_the_labels_before_it() -> None:
    """Three labels at one tip, seen from the front 100 m away (focal 1000 px): one step of
    4 m up lifts a label clear of the one below, so the first stays, the second rises one step,
    the third two. Seen along the lifting direction no step ever clears them: a label rises
    at most four steps per label, then stays there."""
    tip = np.zeros(3)
    front = (np.array([0.0, -100.0, 0.0]), np.zeros(3))
    assert label_slots([tip] * 3, ["X + (a)"] * 3, 4.0, [front], 1000.0) == [0, 1, 2]
    assert label_slots([tip] * 3, ["X + (a)"] * 3, 0.0, [front], 1000.0) == [0, 0, 0]
    along_lift = (-10.0 * LABEL_LIFT, np.zeros(3))
    assert label_slots([tip] * 2, ["X + (a)"] * 2, 4.0, [along_lift], 100.0) == [0, 8]


def test_a_camera_looking_nearly_down_has_the_y_axis_up_on_screen() -> None:
    """A camera off the origin (the norm of its view ray is not that of eye + target), and one
    looking nearly straight down, tilted a little toward +y: a point on the screen's up line
    (+y made square to the view) is drawn straight above the centre at its pinhole height."""
    eye, target = np.array([1.0, -9.0, 11.0]), np.array([1.0, 1.0, 1.0])
    drawn = screen_points([np.array([1.0, 1.0, 2.0])], eye, target, 100.0)
    np.testing.assert_allclose(drawn, [(0.0, 100.0 / 19.0)], atol=1e-9)  # 1/√2 up, 19/√2 deep
    eye, target = np.array([0.0, -0.5, 10.0]), np.zeros(3)
    forward = (target - eye) / np.linalg.norm(target - eye)
    up = np.array([0.0, 1.0, 0.0]) - forward[1] * forward
    up /= np.linalg.norm(up)
    point = target + 2.0 * up
    depth = float((point - eye) @ forward)
    drawn = screen_points([point], eye, target, 100.0)
    np.testing.assert_allclose(drawn, [(0.0, 100.0 * 2.0 / depth)], atol=1e-9)

"""The 3-D view explains the machine: axis marks at the joints along their positive directions,
the parts of an axis in error tinted red until it is reset, a legend naming every body, and a
click on a part naming it on that page.

Positions and directions are compared with MuJoCo's forward kinematics (``data.xanchor``,
``data.xaxis``, a point carried by a joint's body); the session is driven synchronously with a
fake wall clock (:func:`tests.viewer.test_session.run`).
"""

from __future__ import annotations

import itertools
import time
from typing import TYPE_CHECKING, TypeVar

import imageio.v3 as iio
import mujoco
import numpy as np
import pytest
import viser

import mcl
import mcl.faults
import scenes
from plc.operator.hmi import Move
from tests.viewer.test_axis_mark_geometry import offset_joints, two_slides
from tests.viewer.test_browser import browser, wait_for
from tests.viewer.test_session import FakeClock, run, view
from viewer.pages.app import ViewerApp
from viewer.serving.server import Viewer
from viewer.sim.session import Session
from viewer.view3d import views
from viewer.view3d.axis_marks import (
    LABEL_CHAR,
    LABEL_LINE,
    MARK_COLOR,
    MARK_ERROR_COLOR,
    AxisMarks,
    axis_joints,
    mark_length,
)
from viewer.view3d.legend import legend_html, legend_rows
from viewer.view3d.views import VIEWS

if TYPE_CHECKING:
    from playwright.sync_api import Browser

__all__ = ["browser"]  # the Chromium fixture of the browser tests, used here too

Handle = TypeVar("Handle", bound=viser.SceneNodeHandle)

MACHINES_WITH_MODELS = ("gantry", "flying_shear", "press", "rotary_cutter", "cell")

LAMPS = ("_lim_neg_geom", "_lim_pos_geom", "_ref_geom")
"""Endings of the switch geoms, lit by their inputs whatever else their body shows."""


def is_lamp(model: mujoco.MjModel, g: int) -> bool:
    """Whether geom ``g`` is a switch lamp."""
    return model.geom(g).name.endswith(LAMPS)


def marks_of(
    server: viser.ViserServer, name: str, start: dict[str, float]
) -> tuple[mujoco.MjModel, mujoco.MjData, AxisMarks]:
    """A machine at ``start`` (joint coordinates [m, rad]), kinematics current, and the marks
    of all its axes drawn for that pose."""
    scene = scenes.load(name, trace_every=0)
    model, data = scene.model, scene.data
    for joint, q in start.items():
        data.qpos[model.joint(joint).qposadr[0]] = q
    mujoco.mj_kinematics(model, data)
    joints = [(axis, model.joint(scene.io(axis).joint).name) for axis in scene.axes]
    marks = AxisMarks(server, model, axis_joints(model, joints), length=0.2)
    marks.update(data.xpos, data.xquat, {})
    return model, data, marks


def test_gantry_marks_sit_at_the_joints_and_point_along_them(server: viser.ViserServer) -> None:
    """X, Y, Z away from home: each mark's frame is at the joint's anchor carried along by the
    part (MuJoCo's ``xanchor`` of a slide is the anchor at ``qpos0``, on the parent: moved by
    q along ``xaxis``), its arrow lies on the line through it along +axis in world frame, and
    its label names the axis and part."""
    start = {"gantry/X": 0.4, "gantry/Y": 0.25, "gantry/Z": -0.1}
    model, data, marks = marks_of(server, "gantry", start)
    parts = {"X": "bridge", "Y": "carriage", "Z": "ram"}
    for axis, part in parts.items():
        j = model.joint(f"gantry/{axis}").id
        adr = model.jnt_qposadr[j]
        e = data.xaxis[j]
        anchor = data.xanchor[j] + (data.qpos[adr] - model.qpos0[adr]) * e
        np.testing.assert_allclose(marks.anchor(axis), anchor, atol=1e-9)
        np.testing.assert_allclose(marks.direction(axis), e, atol=1e-9)
        start_point, end_point = marks.arrow(axis)
        arrow = end_point - start_point
        assert float(arrow @ e) == pytest.approx(0.2, rel=1e-6)  # along +axis, its length
        offset = start_point - anchor
        assert np.linalg.norm(offset - (offset @ e) * e) < 1e-9  # on the joint's line
        assert marks.label(axis) == f"{axis} + ({part})"
    # the bridge's mark travels with it: X 0.4 m from home puts it 0.4 m along +x
    np.testing.assert_allclose(marks.anchor("X") - model.body("gantry/bridge").pos, [0.4, 0, 0])


def shear_like_marks(
    server: viser.ViserServer, name: str, lift: bool
) -> tuple[AxisMarks, list[tuple[np.ndarray, np.ndarray]]]:
    """The marks of machine ``name`` at its start, given the camera presets as a page's
    Views does (``lift``: labels may be lifted), and the presets' cameras (eye, target)."""
    scene = scenes.load(name, trace_every=0)
    model, data = scene.model, scene.data
    mujoco.mj_kinematics(model, data)
    bounds = views._machine_bounds(model, data)
    assert bounds is not None
    center, radius = bounds
    cameras = [(views._camera_position(center, radius, d), center) for d in VIEWS.values()]
    joints = [(axis, model.joint(scene.io(axis).joint).name) for axis in scene.axes]
    marks = AxisMarks(
        server,
        model,
        axis_joints(model, joints),
        mark_length(radius),
        step=views.label_step(radius) if lift else 0.0,
        cameras=cameras,
        focal=views.FOCAL_PX,
    )
    marks.update(data.xpos, data.xquat, {})
    return marks, cameras


def overlaps(marks: AxisMarks, eye: np.ndarray, target: np.ndarray) -> list[tuple[str, str]]:
    """The pairs of labels whose boxes (:data:`LABEL_LINE` high, :data:`LABEL_CHAR` a character
    wide, the lower left corner at the label's point) overlap as a pinhole camera at ``eye``
    looking at ``target`` (z up, focal length ``views.FOCAL_PX``) draws them."""
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 0.2:  # looking down: +y is up on the screen
        right = np.cross([0.0, 1.0, 0.0], forward)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    boxes = {}
    for mark in marks.axes:
        d = marks.label_position(mark.axis) - eye
        x = views.FOCAL_PX * float(d @ right) / float(d @ forward)
        y = views.FOCAL_PX * float(d @ up) / float(d @ forward)
        boxes[mark.axis] = (x, y, x + LABEL_CHAR * len(marks.label(mark.axis)), y + LABEL_LINE)
    return [
        (a, b)
        for (a, p), (b, q) in itertools.combinations(boxes.items(), 2)
        if p[0] < q[2] and q[0] < p[2] and p[1] < q[3] and q[1] < p[3]
    ]


def test_labels_that_would_overlap_are_lifted_apart_with_a_line_to_their_arrow(
    server: viser.ViserServer,
) -> None:
    """The flying shear's L, W and S point along its line: seen from the side (the camera
    preset) their labels at the arrows' tips overlap. Lifted as a page's Views lifts them, no
    two labels overlap in any preset, on the shear and on the gantry; a lifted label has a
    line leading from its arrow's tip, one at its tip none."""
    unlifted, cameras = shear_like_marks(server, "flying_shear", lift=False)
    side = list(VIEWS).index("Side")
    assert overlaps(unlifted, *cameras[side])  # the problem
    assert all(unlifted.leader(a.axis) is None for a in unlifted.axes)
    unlifted.remove()
    for name in ("flying_shear", "gantry"):
        marks, cameras = shear_like_marks(server, name, lift=True)
        for eye, target in cameras:
            assert not overlaps(marks, eye, target), (name, eye)
        for mark in marks.axes:
            line = marks.leader(mark.axis)
            tip = marks.arrow(mark.axis)[1]  # the arrow's head; the label just beyond it
            if line is None:
                assert np.linalg.norm(marks.label_position(mark.axis) - tip) < 0.1 * marks.length
            else:
                assert np.linalg.norm(line[0] - tip) < 0.1 * marks.length
                np.testing.assert_allclose(line[1], marks.label_position(mark.axis))
                assert np.linalg.norm(line[1] - line[0]) > 0.1 * marks.length
        assert name != "flying_shear" or any(marks.leader(a.axis) is not None for a in marks.axes)
        marks.remove()


@pytest.mark.parametrize("axis", ["L", "W"])
def test_a_hinge_mark_turns_the_way_its_joint_turns(server: viser.ViserServer, axis: str) -> None:
    """The flying shear's pinch roll (axis +y) and measuring wheel (axis −y): the mark sits at
    the joint's anchor along its axis, and its curved arrow's head points where a point of the
    part at the head moves when the joint turns by a small positive angle."""
    joint = f"flying_shear/{axis}"
    model, data, marks = marks_of(server, "flying_shear", {joint: 0.7})
    j = model.joint(joint).id
    np.testing.assert_allclose(marks.anchor(axis), data.xanchor[j], atol=1e-9)
    np.testing.assert_allclose(marks.direction(axis), data.xaxis[j], atol=1e-9)
    tail, head = marks.arrow(axis)
    body = int(model.jnt_bodyid[j])
    rotation = data.xmat[body].reshape(3, 3)
    carried = rotation.T @ (tail - data.xpos[body])  # the head's tail as a point of the part
    data.qpos[model.jnt_qposadr[j]] += 1e-4
    mujoco.mj_kinematics(model, data)
    moved = data.xpos[body] + data.xmat[body].reshape(3, 3) @ carried - tail
    direction = (head - tail) / np.linalg.norm(head - tail)
    assert float(direction @ moved) / np.linalg.norm(moved) > 0.999


def test_the_parts_of_an_axis_in_error_turn_red_until_it_is_reset(
    server: viser.ViserServer,
) -> None:
    """A LIM+ forced on while X moves: X errors; the geoms of the bridge, the carriage and the
    ram (what X moves) turn red, the frame's stay as they were, X's arrow is red and its label
    shows the error number. Faults cleared and X reset: every colour is back."""
    clock = FakeClock()
    session = Session("gantry", clock=clock)
    app = ViewerApp(session, server, clock=clock)
    app.frame()
    scene, marks = app.model_scene, app.views.marks
    assert scene is not None and marks is not None
    model = session.scene.model
    moved = {model.body(f"gantry/{b}").id for b in ("bridge", "carriage", "ram")}
    frame_body = model.body("gantry/").id
    before = {g: scene.geom_color(g) for b in moved | {frame_body} for g in scene.body_geoms(b)}

    requests = session.requests("X")
    requests.set_power(True)
    run(session, clock, 0.2)
    requests.move(Move("relative", 5.0, 100.0, 1000.0))
    session.inject("X", mcl.faults.SwitchStuck("lim_pos", True))
    run(session, clock, 0.2)
    failed = view(session)
    assert failed.error_id != 0
    app.frame()
    for b in moved:
        for g in scene.body_geoms(b):
            r, gr, bl = scene.geom_color(g)
            assert is_lamp(model, g) or (r > gr + 60 and r > bl + 60), model.geom(g).name
    unlit = [g for g in scene.body_geoms(frame_body) if not is_lamp(model, g)]
    assert len(unlit) > 10 and all(scene.geom_color(g) == before[g] for g in unlit)
    assert scene.tinted_bodies == moved
    assert marks.arrow_color("X") == MARK_ERROR_COLOR and marks.arrow_color("Y") == MARK_COLOR
    assert marks.label("X") == f"⚠ X error {failed.error_id} (bridge)"

    session.clear_faults("X")
    run(session, clock, 0.1)
    requests.reset()
    run(session, clock, 0.2)
    assert view(session).error_id == 0
    app.frame()
    assert not scene.tinted_bodies
    for b in moved:
        for g in scene.body_geoms(b):
            assert is_lamp(model, g) or scene.geom_color(g) == scene.model_color(g)
    assert marks.arrow_color("X") == MARK_COLOR and marks.label("X") == "X + (bridge)"

    app.views.show_axis_labels = False  # the View folder's "Axis labels: off"
    app._draw()
    app.frame()
    assert not marks.visible


@pytest.mark.parametrize("name", MACHINES_WITH_MODELS)
def test_the_legend_explains_every_body(name: str) -> None:
    """Every body of the machine is a row of the legend with its description from the model,
    the gantry's magenta block is named as the test obstacle it is, and the legend names the
    switch lamps and the overlays in their colours."""
    scene = scenes.load(name, trace_every=0)
    model = scene.model
    axes = {model.joint(scene.io(a).joint).name: a for a in scene.axes}
    rows = legend_rows(model, axes)
    by_body = {row.body: row for row in rows if row.body is not None}
    drawn = {int(b) for b in model.geom_bodyid}
    assert drawn <= set(by_body)
    for b in drawn:
        row = by_body[b]
        assert row.part.startswith(model.body(b).name) and len(row.role) > 40, row
    parts = {row.part: row for row in rows}
    if any(model.geom(g).name.endswith("_lim_neg_geom") for g in range(model.ngeom)):
        assert parts["LIM switch lit"].color == (242, 38, 26)  # the cutter's drum has REF only
    assert parts["REF switch lit"].color == (255, 184, 0)
    assert parts["set-point ghost"].color == (38, 191, 242)
    assert {"dog", "axis mark", "axis in error", "contact force"} <= set(parts)
    if "gantry/X_obstacle" in parts:
        obstacle = parts["gantry/X_obstacle"]
        assert obstacle.color == (191, 26, 166) and "obstacle" in obstacle.role
        assert "X_bumper" in obstacle.role
    page = legend_html(rows)
    assert all(f"<b>{model.body(b).name}" in page for b in drawn)


@pytest.mark.browser
def test_a_click_on_the_magenta_block_names_it_on_that_page(browser: Browser) -> None:
    """In headless Chromium: the gantry's magenta block is found in the canvas by its colour
    and clicked; the page shows a notification naming it as the test obstacle."""
    v = Viewer("gantry", port=0, demo=False)
    context = browser.new_context(viewport={"width": 1280, "height": 1000})
    try:
        page = context.new_page()
        page.goto(v.url)
        page.get_by_role("button", name="Take control", exact=True).wait_for(timeout=30_000)
        wait_for(lambda: v.app.frames > 0, 5.0, "the first frame")
        time.sleep(0.5)
        canvas = page.locator("canvas").first
        box = canvas.bounding_box()
        assert box is not None
        image = iio.imread(canvas.screenshot(), extension=".png")[..., :3].astype(np.int16)
        r, g, b = image[..., 0], image[..., 1], image[..., 2]
        ys, xs = np.nonzero((r - g > 80) & (b - g > 60))
        assert xs.size > 20, "the magenta block is not in the picture"
        x = box["x"] + float(np.median(xs)) * box["width"] / image.shape[1]
        y = box["y"] + float(np.median(ys)) * box["height"] / image.shape[0]
        page.mouse.click(x, y)
        note = page.locator(".mantine-Notification-root", has_text="gantry/X_obstacle")
        note.wait_for(timeout=15_000)
        assert "Test obstacle" in note.inner_text()
    finally:
        context.close()
        v.close()


def node(server: viser.ViserServer, name: str, kind: type[Handle]) -> Handle:
    """The scene node ``name`` of the server, of handle type ``kind``."""
    handle = server.scene.get_handle_by_name(name)
    assert isinstance(handle, kind), (name, handle)
    return handle


def test_a_mark_s_nodes_show_its_arrow_label_and_lines_as_drawn(server: viser.ViserServer) -> None:
    """A slide along −z with its joint off its turned body's origin and a hinge about +x,
    moved away from their start: each frame sits at its joint's anchor carried by the part
    (no axes triad drawn), the slide's arrow starts a tenth of its length beyond the part and
    is one length long along +axis, the hinge's arrow head is 0.35 lengths long and its axis
    line runs from the anchor half a length beyond the arc; the label sits a twentieth of a
    length beyond the head, drawn over the parts; the arrow is 0.05 lengths thick with a head
    0.13 lengths wide and 0.2 long, the lines 3 (arc), 1.5 (axis) and 1 px (leader) wide. In
    error the hinge's arc and arrow turn red, and green again when the error is gone."""
    model = offset_joints()
    data = mujoco.MjData(model)
    marks = AxisMarks(server, model, axis_joints(model, [("S", "s"), ("H", "h")]), length=0.1)
    for axis in ("S", "H"):  # before the first pose: the label beyond the head as drawn
        tail, head = marks.arrow(axis)
        expected = head + 0.005 * marks.direction(axis)
        np.testing.assert_allclose(marks.label_position(axis), expected, atol=1e-7)
    data.qpos[:] = (0.3, 0.7)
    mujoco.mj_kinematics(model, data)
    marks.update(data.xpos, data.xquat, {})
    slide, hinge = marks.axes
    s, h = model.joint("s").id, model.joint("h").id
    np.testing.assert_allclose(marks.anchor("S"), data.xanchor[s] + 0.3 * data.xaxis[s])
    np.testing.assert_allclose(marks.anchor("H"), data.xanchor[h], atol=1e-9)
    e = data.xaxis[s]
    np.testing.assert_allclose(marks.direction("S"), e, atol=1e-9)
    tail, head = marks.arrow("S")
    np.testing.assert_allclose(tail, marks.anchor("S") + (slide.reach + 0.01) * e, atol=1e-7)
    np.testing.assert_allclose(head - tail, 0.1 * e, atol=1e-7)
    np.testing.assert_allclose(marks.label_position("S"), head + 0.005 * e, atol=1e-7)
    tail, head = marks.arrow("H")
    assert np.linalg.norm(head - tail) == pytest.approx(0.035, rel=1e-6)
    axis_line = node(server, "/axis_marks/1/axis", viser.LineSegmentsHandle)
    height = hinge.face + 0.01
    along = np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, height + 0.05]]])
    np.testing.assert_allclose(np.asarray(axis_line.points, np.float64), along, atol=1e-7)
    assert node(server, "/axis_marks", viser.FrameHandle).show_axes is False
    arc = node(server, "/axis_marks/1/arc", viser.LineSegmentsHandle)
    lines = {"arc": arc, "axis": axis_line}
    for k in (0, 1):
        assert node(server, f"/axis_marks/{k}", viser.FrameHandle).show_axes is False
        arrow = node(server, f"/axis_marks/{k}/arrow", viser.ArrowsHandle)
        assert (arrow.shaft_radius, arrow.head_radius, arrow.head_length) == pytest.approx(
            (0.005, 0.013, 0.02)
        )
        label = node(server, f"/axis_marks/labels/{k}/label", viser.LabelHandle)
        assert label.depth_test is False and label.anchor == "bottom-left"
        leader = node(server, f"/axis_marks/labels/{k}/leader", viser.LineSegmentsHandle)
        assert leader.visible is False
        lines[f"leader {k}"] = leader
    widths = {name: (line.thickness, line.thickness_units) for name, line in lines.items()}
    assert widths == {
        "arc": (3.0, "screen"),
        "axis": (1.5, "screen"),
        "leader 0": (1.0, "screen"),
        "leader 1": (1.0, "screen"),
    }
    assert tuple(np.asarray(arc.colors).reshape(-1, 3)[0]) == MARK_COLOR
    marks.update(data.xpos, data.xquat, {"H": 17})
    assert tuple(np.asarray(arc.colors).reshape(-1, 3)[0]) == MARK_ERROR_COLOR
    assert marks.arrow_color("H") == MARK_ERROR_COLOR and marks.arrow_color("S") == MARK_COLOR
    marks.update(data.xpos, data.xquat, {})
    assert tuple(np.asarray(arc.colors).reshape(-1, 3)[0]) == MARK_COLOR
    with pytest.raises(KeyError, match=r"no mark of axis 'Q'; marked: \['S', 'H'\]"):
        marks.anchor("Q")


def test_labels_stay_at_their_tips_unless_a_lift_step_is_given(server: viser.ViserServer) -> None:
    """Two marks of one joint put their labels on one spot in every camera; given the cameras
    but no lift step, neither label is lifted and no leader line is drawn."""
    model = offset_joints()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    axes = axis_joints(model, [("S", "s"), ("T", "s")])
    camera = (np.array([3.0, -4.0, 2.0]), np.zeros(3))
    marks = AxisMarks(server, model, axes, length=0.1, cameras=[camera], focal=500.0)
    marks.update(data.xpos, data.xquat, {})
    np.testing.assert_allclose(marks.label_position("T"), marks.label_position("S"))
    assert marks.leader("S") is None and marks.leader("T") is None


def test_labels_are_lifted_for_the_width_of_the_text_they_show(server: viser.ViserServer) -> None:
    """Two labels side by side seen from the front, 110 px apart: "B + (back)" is 75 px wide,
    so "A + (ahead)" to its right stays at its tip, with no leader line."""
    model = two_slides()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    axes = axis_joints(model, [("B", "b"), ("A", "a")])
    front = (np.array([0.0, -10.0, 0.0]), np.zeros(3))
    marks = AxisMarks(server, model, axes, length=0.1, step=0.05, cameras=[front], focal=770.0)
    marks.update(data.xpos, data.xquat, {})
    np.testing.assert_allclose(marks.label_position("A"), [0.715, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(marks.label_position("B"), [-0.715, 0.0, 0.0], atol=1e-9)
    assert marks.leader("A") is None and marks.leader("B") is None

"""Axis marks of the 3-D view: every axis' name and positive direction drawn on the machine.

Each axis with a joint in the model (driven or encoder-only) gets a mark that rides on the body
its joint moves: a frame at the joint's anchor on that body whose local z is the joint's axis
(``data.xaxis``), computed each frame from the body poses of the snapshot (MuJoCo's
``data.xanchor`` of a slide is the anchor where ``q = qpos0``, on the parent; the mark's anchor
is that point carried along by the slide). A slide gets a
straight arrow along +axis that starts where the moving part ends (so it is not hidden inside
it) on the line through the anchor; a hinge gets a curved arrow turning the positive way about
the axis (right-hand rule) around the part's end face, and a thin line along the axis. A label
at the arrow's head names the axis and its part (``"X + (bridge)"``). The marks move with the
part because that is where an engineer looks for "which part is X": a mark fixed on the parent
would stay behind while the part travels away from it.

Labels whose places would overlap as a camera preset sees them (the flying shear's L, W and S
all point along its line: seen from the side their tips fall together) are lifted apart, each
by its own number of steps up (world +y +z, seen apart from the front, the side and the top), a
thin line leading from the arrow's tip to the lifted label.

While an axis has an error (``AxisView.error_id`` ≠ 0) its arrow turns red and its label reads
the error number; viser 1.1.1 draws labels in one colour, so the text carries the warning.
"""

from __future__ import annotations

__all__ = [
    "ARC_SEGMENTS",
    "ARC_TURN",
    "ARROW_SHARE",
    "HINGE",
    "LABEL_CHAR",
    "LABEL_LIFT",
    "LABEL_LINE",
    "MARK_COLOR",
    "MARK_ERROR_COLOR",
    "MAX_ARROW",
    "MIN_ARROW",
    "SLIDE",
    "AxisJoint",
    "AxisMarks",
    "axis_joints",
    "label_slots",
    "label_text",
    "labels_overlap",
    "mark_length",
    "quat_z_to",
    "rotate",
    "screen_points",
]

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt
import viser

MARK_COLOR = (20, 150, 70)
"""Colour of the axis arrows (green, RGB in [0, 255])."""

MARK_ERROR_COLOR = (230, 25, 25)
"""Colour of the arrow of an axis in error (red, RGB in [0, 255])."""

ARROW_SHARE = 0.12
"""Arrow length as a share of the machine's radius (:func:`mark_length`)."""

MIN_ARROW, MAX_ARROW = 0.05, 0.6
"""Shortest and longest arrow [m]."""

ARC_TURN = 1.5 * np.pi
"""Angle [rad] the curved arrow of a hinge spans."""

ARC_SEGMENTS = 24
"""Line segments of a hinge's curved arrow."""

LABEL_LIFT = np.array([0.0, 1.0, 1.0])
"""Direction a label is lifted in when it would overlap another, per step (world)."""

LABEL_LINE, LABEL_CHAR = 18.0, 7.5
"""Height of a label's line and width of its character [CSS px] (its box, to find overlaps)."""

HINGE = int(mujoco.mjtJoint.mjJNT_HINGE)
SLIDE = int(mujoco.mjtJoint.mjJNT_SLIDE)


def mark_length(radius: float) -> float:
    """Arrow length [m] for a machine of ``radius`` [m] (:data:`ARROW_SHARE`, clipped)."""
    return float(np.clip(ARROW_SHARE * radius, MIN_ARROW, MAX_ARROW))


def quat_z_to(direction: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Quaternion (w, x, y, z) of the shortest rotation taking +z onto ``direction`` (unit)."""
    quat = np.zeros(4)
    z = np.array([0.0, 0.0, 1.0])
    if float(direction @ z) < -1.0 + 1e-12:
        return np.array([0.0, 1.0, 0.0, 0.0])  # half a turn about x
    mujoco.mju_quatZ2Vec(quat, np.asarray(direction, dtype=np.float64))
    return quat


def rotate(
    quat: npt.NDArray[np.floating], vector: npt.NDArray[np.floating]
) -> npt.NDArray[np.float64]:
    """``vector`` rotated by the unit quaternion ``quat`` (w, x, y, z)."""
    out = np.zeros(3)
    mujoco.mju_rotVecQuat(out, np.asarray(vector, dtype=np.float64), np.asarray(quat, np.float64))
    return out


@dataclass(frozen=True, slots=True)
class AxisJoint:
    """An axis as its mark sees it.

    Attributes:
        axis: Axis name in the scene (``"X"``).
        joint: Joint id in the model.
        body: Id of the body the joint moves.
        part: Short name of that body (``"bridge"``).
        hinge: The joint is a hinge (else a slide).
        reach: Extent [m] of the part's geoms beyond the anchor along +axis (slide) or across
            the axis (hinge).
        face: Extent [m] of the part's geoms along +axis from the anchor (hinge: its end face).
    """

    axis: str
    joint: int
    body: int
    part: str
    hinge: bool
    reach: float
    face: float


def _extents(model: mujoco.MjModel, joint: int) -> tuple[float, float]:
    """Extents [m] of the joint's body's geoms in the joint frame: the farthest point along
    +axis, and the farthest distance from the axis (corners of each geom's bounding box)."""
    body = int(model.jnt_bodyid[joint])
    anchor = np.asarray(model.jnt_pos[joint], dtype=np.float64)
    e = np.asarray(model.jnt_axis[joint], dtype=np.float64)
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    along, across = 0.0, 0.0
    for g in np.flatnonzero(np.asarray(model.geom_bodyid) == body):
        center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        for corner in center + signs * half:
            point = model.geom_pos[g] + rotate(model.geom_quat[g], corner) - anchor
            a = float(point @ e)
            along = max(along, a)
            across = max(across, float(np.linalg.norm(point - a * e)))
    return along, across


def axis_joints(model: mujoco.MjModel, axes: Sequence[tuple[str, str]]) -> tuple[AxisJoint, ...]:
    """The axes with a slide or hinge joint in the model, in order.

    Args:
        model: The compiled model.
        axes: ``(axis name, joint name)`` of every axis; one without a joint in the model
            (or with a ball or free joint) gets no mark.
    """
    marks = []
    for name, joint_name in axes:
        j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint_name) if joint_name else -1
        if j < 0 or int(model.jnt_type[j]) not in (HINGE, SLIDE):
            continue
        body = int(model.jnt_bodyid[j])
        part = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"body{body}"
        along, across = _extents(model, j)
        hinge = int(model.jnt_type[j]) == HINGE
        marks.append(
            AxisJoint(
                name, j, body, part.rsplit("/", 1)[-1], hinge, across if hinge else along, along
            )
        )
    return tuple(marks)


def label_text(mark: AxisJoint, error_id: int) -> str:
    """What a mark's label says: ``"X + (bridge)"``, in error ``"⚠ X error 17 (bridge)"``."""
    if error_id:
        return f"⚠ {mark.axis} error {error_id} ({mark.part})"
    return f"{mark.axis} + ({mark.part})"


def screen_points(
    points: Sequence[npt.NDArray[np.float64]],
    eye: npt.NDArray[np.float64],
    target: npt.NDArray[np.float64],
    focal: float,
) -> list[tuple[float, float]]:
    """Where a camera at ``eye`` looking at ``target`` (z up) draws ``points`` [m]: right and
    up [CSS px] from the canvas' centre, for a ``focal`` length [px]."""
    forward = (target - eye) / np.linalg.norm(target - eye)
    up = np.array([0.0, 0.0, 1.0]) - forward[2] * forward
    if np.linalg.norm(up) < 0.2:  # looking straight down: the screen's up is +y
        up = np.array([0.0, 1.0, 0.0]) - forward[1] * forward
    up /= np.linalg.norm(up)
    right = np.cross(forward, up)
    result = []
    for p in points:
        d = p - eye
        depth = max(float(d @ forward), 1e-9)
        result.append((focal * float(d @ right) / depth, focal * float(d @ up) / depth))
    return result


def labels_overlap(
    a: tuple[float, float], b: tuple[float, float], widths: tuple[float, float]
) -> bool:
    """Whether labels whose lower left corners are drawn at ``a`` and ``b`` [px], ``widths``
    [px] wide and :data:`LABEL_LINE` high, overlap (with a margin)."""
    across, height = b[0] - a[0], b[1] - a[1]
    width = widths[0] if across >= 0.0 else widths[1]
    return abs(height) < 1.3 * LABEL_LINE and abs(across) < width + 0.3 * LABEL_LINE


def label_slots(
    tips: Sequence[npt.NDArray[np.float64]],
    texts: Sequence[str],
    step: float,
    cameras: Sequence[tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]],
    focal: float,
) -> list[int]:
    """Steps of ``step`` [m] (along :data:`LABEL_LIFT`) each label is lifted by so that no two
    overlap as any of the ``cameras`` ((eye, target) [m], ``focal`` length [px]) draws them;
    the first label stays at its tip, a later one gets the fewest steps that clear the labels
    before it (at most four steps per label: one that no lift clears stays there)."""
    if step <= 0.0 or not cameras:
        return [0] * len(tips)
    widths = [LABEL_CHAR * len(t) for t in texts]
    slots: list[int] = []
    for k, tip in enumerate(tips):
        slot = 0
        while slot < 4 * len(tips):
            places = [tips[j] + slots[j] * step * LABEL_LIFT for j in range(k)]
            places.append(tip + slot * step * LABEL_LIFT)
            clash = False
            for eye, target in cameras:
                drawn = screen_points(places, eye, target, focal)
                clash = clash or any(
                    labels_overlap(drawn[j], drawn[k], (widths[j], widths[k])) for j in range(k)
                )
            if not clash:
                break
            slot += 1
        slots.append(slot)
    return slots


def _slide_arrow(mark: AxisJoint, length: float) -> npt.NDArray[np.float64]:
    """Start and end [m] of a slide's arrow in the mark frame (local z = joint axis)."""
    start = mark.reach + 0.1 * length
    return np.array([[[0.0, 0.0, start], [0.0, 0.0, start + length]]])


def _hinge_arc(mark: AxisJoint, length: float) -> tuple[npt.NDArray[np.float64], float]:
    """Line segments of a hinge's curved arrow in the mark frame and its height [m] along the
    axis (beyond the part's end face)."""
    radius = max(mark.reach * 1.15, 0.3 * length)
    height = mark.face + 0.1 * length
    angles = np.linspace(0.0, ARC_TURN, ARC_SEGMENTS + 1)
    points = np.stack(
        [radius * np.cos(angles), radius * np.sin(angles), np.full_like(angles, height)], axis=1
    )
    return np.stack([points[:-1], points[1:]], axis=1), height


class AxisMarks:
    """The marks of a machine's axes, one frame each, moved and re-coloured only on change.

    Args:
        server: The viser server.
        model: The compiled model.
        axes: The axes to mark (:func:`axis_joints`).
        length: Arrow length [m] (:func:`mark_length`).
        prefix: Node path of the marks' root frame.
        step: How far [m] a label is lifted per step (0: never; about a line of it as the
            camera presets show the machine).
        cameras: The camera presets, (eye, target) [m], in which labels must not overlap.
        focal: Their focal length [CSS px] (half the canvas' height over the tangent of half
            its field of view).
    """

    def __init__(
        self,
        server: viser.ViserServer,
        model: mujoco.MjModel,
        axes: Sequence[AxisJoint],
        length: float,
        prefix: str = "/axis_marks",
        step: float = 0.0,
        cameras: Sequence[tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]] = (),
        focal: float = 1.0,
    ) -> None:
        self._model = model
        self._step, self._cameras, self._focal = step, tuple(cameras), focal
        self._slots: list[int] | None = None
        self._tips: list[npt.NDArray[np.float64]] = []
        self._leaders: list[viser.LineSegmentsHandle] = []
        self._server = server
        self._axes = tuple(axes)
        self.length = length
        """Arrow length [m]."""
        self._errors = dict.fromkeys((a.axis for a in self._axes), 0)
        self._frames: list[viser.FrameHandle] = []
        self._arrows: list[viser.ArrowsHandle] = []
        self._labels: list[viser.LabelHandle] = []
        self._arcs: list[viser.LineSegmentsHandle | None] = []
        with server.atomic():
            self._root = server.scene.add_frame(prefix, show_axes=False)
            for k, mark in enumerate(self._axes):
                self._add(f"{prefix}/{k}", f"{prefix}/labels/{k}", mark)

    def _add(self, node: str, label_node: str, mark: AxisJoint) -> None:
        """The frame, arrow and label of one axis (at the model's reference pose until the
        first :meth:`update`; the label, in world coordinates, at its arrow's tip then)."""
        scene, length = self._server.scene, self.length
        frame = scene.add_frame(node, show_axes=False)
        arc: viser.LineSegmentsHandle | None = None
        if mark.hinge:
            segments, height = _hinge_arc(mark, length)
            arc = scene.add_line_segments(
                f"{node}/arc", segments, colors=MARK_COLOR, thickness=3.0, thickness_units="screen"
            )
            scene.add_line_segments(
                f"{node}/axis",
                np.array([[[0.0, 0.0, 0.0], [0.0, 0.0, height + 0.5 * length]]]),
                colors=MARK_COLOR,
                thickness=1.5,
                thickness_units="screen",
            )
            end = segments[-1, 1]
            tangent = np.array([-np.sin(ARC_TURN), np.cos(ARC_TURN), 0.0])
            head = np.array([[end, end + 0.35 * length * tangent]])
            tip = head[0, 1]
        else:
            head = _slide_arrow(mark, length)
            tip = head[0, 1]
        arrow = scene.add_arrows(
            f"{node}/arrow",
            points=head.astype(np.float32),
            colors=MARK_COLOR,
            shaft_radius=0.05 * length,
            head_radius=0.13 * length,
            head_length=0.2 * length,
        )
        tip = tip + np.array([0.0, 0.0, 0.05 * length])  # just beyond the head
        label = scene.add_label(
            f"{label_node}/label",
            label_text(mark, 0),
            position=tip,
            depth_test=False,
            anchor="bottom-left",
        )
        leader = scene.add_line_segments(
            f"{label_node}/leader",
            np.zeros((1, 2, 3)),
            colors=MARK_COLOR,
            thickness=1.0,
            thickness_units="screen",
            visible=False,
        )
        self._tips.append(tip)
        self._leaders.append(leader)
        self._frames.append(frame)
        self._arrows.append(arrow)
        self._labels.append(label)
        self._arcs.append(arc)

    @property
    def axes(self) -> tuple[AxisJoint, ...]:
        """The marked axes."""
        return self._axes

    def _index(self, axis: str) -> int:
        for k, mark in enumerate(self._axes):
            if mark.axis == axis:
                return k
        raise KeyError(f"no mark of axis {axis!r}; marked: {[a.axis for a in self._axes]}")

    def anchor(self, axis: str) -> npt.NDArray[np.float64]:
        """World position [m] of the mark's frame: the joint's anchor as last drawn."""
        return np.array(self._frames[self._index(axis)].position, dtype=np.float64)

    def direction(self, axis: str) -> npt.NDArray[np.float64]:
        """World direction of the mark's axis (unit) as last drawn."""
        return rotate(self._frames[self._index(axis)].wxyz, np.array([0.0, 0.0, 1.0]))

    def arrow(self, axis: str) -> npt.NDArray[np.float64]:
        """World start and end [m] of the (head) arrow of the mark, shape (2, 3)."""
        k = self._index(axis)
        frame = self._frames[k]
        local = np.asarray(self._arrows[k].points, dtype=np.float64)[0]
        return np.array([frame.position + rotate(frame.wxyz, p) for p in local])

    def label(self, axis: str) -> str:
        """The text of the axis' label."""
        return self._labels[self._index(axis)].text

    def leader(self, axis: str) -> npt.NDArray[np.float64] | None:
        """World start and end [m] of the line leading from the arrow's tip to the lifted
        label, shape (2, 3); None while the label sits at the tip."""
        line = self._leaders[self._index(axis)]
        return np.array(line.points, dtype=np.float64)[0] if line.visible else None

    def label_position(self, axis: str) -> npt.NDArray[np.float64]:
        """World position [m] of the axis' label (its lower left corner) as last drawn."""
        return np.array(self._labels[self._index(axis)].position, dtype=np.float64)

    def arrow_color(self, axis: str) -> tuple[int, int, int]:
        """The colour of the axis' arrow (RGB in [0, 255])."""
        colors = np.asarray(self._arrows[self._index(axis)].colors).reshape(-1, 3)
        r, g, b = (int(c) for c in colors[0])
        return (r, g, b)

    @property
    def visible(self) -> bool:
        """Whether the marks are shown."""
        return bool(self._root.visible)

    @visible.setter
    def visible(self, visible: bool) -> None:
        if bool(self._root.visible) != visible:
            self._root.visible = visible

    def update(
        self,
        xpos: npt.NDArray[np.floating],
        xquat: npt.NDArray[np.floating],
        errors: Mapping[str, int],
    ) -> None:
        """Place each mark at its joint's anchor along its joint's axis (from the body poses),
        and show each axis' error; only what changed is sent.

        Args:
            xpos: World position of every body [m], shape (nbody, 3).
            xquat: World orientation of every body (w, x, y, z), shape (nbody, 4).
            errors: ``AxisView.error_id`` by axis name (a missing axis: no error).
        """
        model = self._model
        tips = []
        with self._server.atomic():
            for k, mark in enumerate(self._axes):
                quat = xquat[mark.body]
                anchor = xpos[mark.body] + rotate(quat, model.jnt_pos[mark.joint])
                wxyz = quat_z_to(rotate(quat, model.jnt_axis[mark.joint]))
                frame = self._frames[k]
                if not np.array_equal(frame.position, anchor):
                    frame.position = anchor
                if not np.array_equal(frame.wxyz, wxyz):
                    frame.wxyz = wxyz
                tips.append(anchor + rotate(wxyz, self._tips[k]))
                error = int(errors.get(mark.axis, 0))
                if error != self._errors[mark.axis]:
                    self._errors[mark.axis] = error
                    self._labels[k].text = label_text(mark, error)
                    color = np.array(MARK_ERROR_COLOR if error else MARK_COLOR, dtype=np.uint8)
                    self._arrows[k].colors = color
                    arc = self._arcs[k]
                    if arc is not None:
                        arc.colors = color
                    self._leaders[k].colors = color
            self._place_labels(tips)

    def _place_labels(self, tips: list[npt.NDArray[np.float64]]) -> None:
        """Each label at its arrow's tip, lifted by its slot (found at the first pose drawn);
        a lifted one with its leader line from the tip."""
        if self._slots is None:
            texts = [label_text(mark, 0) for mark in self._axes]
            self._slots = label_slots(tips, texts, self._step, self._cameras, self._focal)
        for k, tip in enumerate(tips):
            lift = self._slots[k] * self._step * LABEL_LIFT
            position = tip + lift
            label = self._labels[k]
            if not np.array_equal(label.position, position):
                label.position = position
                if self._slots[k]:
                    self._leaders[k].points = np.array([[tip, position]])
                    self._leaders[k].visible = True

    def remove(self) -> None:
        """Remove the marks' nodes from the scene."""
        self._root.remove()
        self._frames.clear()
        self._arrows.clear()
        self._labels.clear()
        self._arcs.clear()
        self._leaders.clear()

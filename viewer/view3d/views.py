"""Views and cameras: the camera presets framed on the machine, cameras that follow a body, and
the 3-D overlays the View folder shows (set-point ghost, forces, axis marks, the parts of an axis
in error tinted red, the group's path, the legend; a click on a part names it on that page); for
every page."""

from __future__ import annotations

__all__ = [
    "CAMERA_FOV",
    "FOCAL_PX",
    "FOLLOW_OFF",
    "FOLLOW_STEP",
    "FRAME_ASPECT",
    "FRAME_OUTLIER",
    "OFF",
    "ON",
    "SWITCH_CHOICES",
    "VIEWS",
    "Views",
    "label_step",
]

import math
from collections.abc import Callable, Sequence
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt
import viser

from viewer.pages.widgets import SceneGui
from viewer.sim.snapshot import Snapshot
from viewer.view3d.axis_marks import LABEL_LINE, AxisMarks, axis_joints, mark_length
from viewer.view3d.frame_marks import FrameMarks
from viewer.view3d.legend import ERROR_TINT, LegendRow, body_row, legend_html, legend_rows
from viewer.view3d.model_scene import ModelScene
from viewer.view3d.overlays import (
    DEFAULT_FORCE_SCALE,
    FORCE_SCALES,
    ContactOverlay,
    SetPointGhost,
    ghost_axes,
    moved_bodies,
)
from viewer.view3d.path_trail import PathView

OFF, ON = "off", "on"
SWITCH_CHOICES = (OFF, ON)
"""Choices of an overlay that is shown or not (a dropdown: the page offers no checkboxes)."""

FOLLOW_OFF = OFF
"""Follow-camera choice: the camera stays where the page puts it."""

FOLLOW_STEP = 1e-4
"""Body travel [m] after which a following camera is moved along (smaller moves accumulate)."""

FRAME_OUTLIER = 50.0
"""Geoms bigger than this many times the median geom are left out of the camera framing."""

CAMERA_FOV = math.radians(75.0)
"""Vertical field of view of a page's camera [rad] (viser's initial camera)."""

FOCAL_PX = 400.0 / math.tan(0.5 * CAMERA_FOV)
"""Focal length [CSS px] of a page's camera in the 800 px high canvas of a 1280×800 page."""

FRAME_ASPECT = 0.8
"""Narrowest canvas (width / height) the framing fits the machine into: half of a 1280×800 page."""

VIEWS = {
    "Fit": (0.9, -1.6, 0.9),
    "Front": (0.0, -1.0, 0.15),
    "Side": (1.0, 0.0, 0.15),
    "Top": (0.0, -0.05, 1.0),
}
"""Camera presets: direction from the machine's centre to the camera."""


class Views:
    """The cameras and 3-D overlays of the current model. The View folder's callbacks set the
    wishes (:attr:`follow`, :attr:`show_ghost`, :attr:`show_contacts`, :attr:`force_scale`) and
    call ``redraw``; :meth:`update` (the update thread) draws them.

    Args:
        server: The viser server.
        redraw: Asks for the next frame to be drawn even without a new snapshot.
    """

    def __init__(self, server: viser.ViserServer, redraw: Callable[[], None]) -> None:
        self.server = server
        self._redraw = redraw
        self.ghost: SetPointGhost | None = None
        """The set-point ghost (made when first shown, dropped with its scene)."""
        self.contacts: ContactOverlay | None = None
        """The contact overlay of the current model (None without a model)."""
        self.show_ghost = False
        """The set-point ghost is drawn (the View folder's toggle)."""
        self.show_contacts = False
        """Contact, hard-stop and tendon forces are drawn (the View folder's choice)."""
        self.force_scale = DEFAULT_FORCE_SCALE
        """Length of the force arrows, a key of :data:`FORCE_SCALES`."""
        self.follow = FOLLOW_OFF
        """Body the pages' cameras follow (:data:`FOLLOW_OFF`: none)."""
        self._follow_anchor: dict[int, tuple[int, npt.NDArray[np.float64]]] = {}
        """Per page: the followed body and its position [m] when the camera last moved along."""
        self.marks: AxisMarks | None = None
        """The axis marks of the current model (None without a model)."""
        self.show_axis_labels = True
        """The axis marks are drawn (the View folder's toggle)."""
        self.legend: list[LegendRow] = []
        """The legend of the current model."""
        self._follow_ids: dict[str, int] = {}
        self._bounds: tuple[npt.NDArray[np.float64], float] | None = None
        self._scene: ModelScene | None = None
        self._moved: dict[str, list[int]] = {}
        """Per axis with a joint: the bodies it moves (tinted while it is in error)."""
        self._failing: frozenset[str] = frozenset()
        self.path = PathView(server)
        """The group's commanded and actual path (the View folder's Path choice)."""
        self.frames = FrameMarks(server)
        """The robot groups' product coordinate systems (tracked: moving with the belt)."""

    def clear(self) -> None:
        """Drop the overlays, the followed body and the framing of the scene that goes."""
        overlays: list[SetPointGhost | ContactOverlay | AxisMarks | None] = [
            self.ghost,
            self.contacts,
            self.marks,
        ]
        for overlay in overlays:
            if overlay is not None:
                overlay.remove()
        self.ghost = self.contacts = self.marks = None
        self.path.clear()
        self.frames.remove()
        self._scene = None
        self._moved = {}
        self._failing = frozenset()
        self.legend = []
        self.follow = FOLLOW_OFF
        self._follow_anchor = {}
        self._bounds = None

    def frame(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Frame a new model (kinematics of ``data`` current): new pages look at it."""
        self._bounds = _machine_bounds(model, data)
        if self._bounds is None:
            return
        center, radius = self._bounds
        self.server.initial_camera.fov = CAMERA_FOV
        self.server.initial_camera.look_at = center
        self.server.initial_camera.position = _camera_position(center, radius, VIEWS["Fit"])

    def add_forces(self) -> None:
        """The force overlay of a new model (drawn when :attr:`show_contacts`)."""
        self.contacts = ContactOverlay(
            self.server, prefix="/contacts", scale=FORCE_SCALES[self.force_scale]
        )

    def add_marks(self, snapshot: Snapshot, scene: ModelScene) -> None:
        """The axis marks, error tints, legend and click explanations of a new model."""
        model = snapshot.model
        if model is None:
            return
        joints = [(name, view.joint) for name, view in snapshot.axes.items() if view.joint]
        radius = 1.0 if self._bounds is None else self._bounds[1]
        axes = axis_joints(model, joints)
        self.marks = AxisMarks(
            self.server,
            model,
            axes,
            mark_length(radius),
            step=label_step(radius),
            cameras=[(_camera_position(*self._bounds, d), self._bounds[0]) for d in VIEWS.values()]
            if self._bounds is not None
            else (),
            focal=FOCAL_PX,
        )
        self._scene = scene
        self._moved = {a.axis: moved_bodies(model, [int(model.jnt_qposadr[a.joint])]) for a in axes}
        self.legend = legend_rows(model, {joint: name for name, joint in joints})
        scene.on_click(self._explain)
        self.path.prepare(snapshot)

    def _explain(self, client: viser.ClientHandle, body: int) -> None:
        """A click on a part: that page is told what it is."""
        row = body_row(self.legend, body)
        if row is not None:
            client.add_notification(row.part, row.role, auto_close_seconds=8.0)

    def build(self, gui: SceneGui, model: mujoco.MjModel, scene: ModelScene | None) -> None:
        """The View folder: camera presets, follow camera and the 3-D overlays (each page moves
        its own camera; for everyone)."""
        self._follow_ids = {}
        if scene is not None:
            drawn = scene.body_handles
            for b in scene.moving_body_ids:
                name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(b)) or f"body{b}"
                if name in drawn:
                    self._follow_ids[name] = int(b)
        folder = gui.folder("View", order=8, expand_by_default=False)
        with folder:
            for label, direction in VIEWS.items():
                button = gui.button(label, control=False, hint=f"Camera: {label.lower()}")
                button.on_click(self._look(direction))
        with folder:
            self._build_choices(gui)
            self.path.build(gui, self._redraw)
            if self.legend:
                with gui.api.add_folder("Legend", expand_by_default=False):
                    gui.api.add_html(legend_html(self.legend))

    def _look(self, direction: Sequence[float]) -> Callable[[Any], None]:
        """A camera preset button's callback: the page looks at the machine from ``direction``."""

        def look(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if event.client is not None and self._bounds is not None:
                center, radius = self._bounds
                position = _camera_position(center, radius, direction)
                # position first: setting it carries the look-at point along (the camera
                # keeps its orientation), so the look-at point goes second
                event.client.camera.position = position
                event.client.camera.look_at = center

        return look

    def _build_choices(self, gui: SceneGui) -> None:
        """The Follow, Axis labels, Set-point ghost and Forces dropdowns."""
        bodies = [FOLLOW_OFF, *self._follow_ids]
        follow = gui.dropdown(
            "Follow", bodies, FOLLOW_OFF, control=False, hint="Cameras keep their offset to it"
        )
        labels = gui.dropdown(
            "Axis labels",
            SWITCH_CHOICES,
            SWITCH_CHOICES[self.show_axis_labels],
            control=False,
            hint="Each axis' name and positive direction on the part it moves",
        )
        ghost = gui.dropdown(
            "Set-point ghost",
            SWITCH_CHOICES,
            SWITCH_CHOICES[self.show_ghost],
            control=False,
            hint="Moving parts drawn where the axes' set points put them",
        )
        contacts = gui.dropdown(
            "Forces (contacts, stops, tendons)",
            [OFF, *FORCE_SCALES],
            self.force_scale if self.show_contacts else OFF,
            control=False,
            hint="Contact, hard-stop and tendon force arrows, arrow length per newton",
        )

        @follow.on_update
        def _(event: Any) -> None:
            self.follow = follow.value
            self._redraw()

        @labels.on_update
        def _(event: Any) -> None:
            self.show_axis_labels = labels.value == ON
            self._redraw()

        @ghost.on_update
        def _(event: Any) -> None:
            self.show_ghost = ghost.value == ON
            self._redraw()

        @contacts.on_update
        def _(event: Any) -> None:
            self.show_contacts = contacts.value in FORCE_SCALES
            if self.show_contacts:
                self.force_scale = contacts.value
            self._redraw()

    def update(self, snapshot: Snapshot) -> None:
        """Set-point ghost, forces, axis marks, error tints, the groups' product coordinate
        systems and the follow cameras, as the View folder says."""
        model = snapshot.model
        if model is None:
            return
        self._show_errors(snapshot)
        ghost = self.ghost
        if self.show_ghost:
            if ghost is None:
                joints = [(n, v.joint) for n, v in snapshot.axes.items() if v.has_drive and v.joint]
                axes = ghost_axes(model, snapshot.scene, joints)
                ghost = self.ghost = SetPointGhost(model, self.server, axes, prefix="/ghost")
            ghost.visible = True
            ghost.update(snapshot.qpos, [snapshot.axes[a.name].following_error for a in ghost.axes])
        elif ghost is not None:
            ghost.visible = False
        contacts = self.contacts
        if contacts is not None:
            contacts.scale = FORCE_SCALES[self.force_scale]
            contacts.enabled = self.show_contacts
            if snapshot.contacts is not None:
                contacts.update(snapshot.contacts, snapshot.constraints)
        self.path.update(snapshot)
        self.frames.update(snapshot)
        self._follow_cameras(snapshot)

    def _show_errors(self, snapshot: Snapshot) -> None:
        """The axis marks where their joints are, and the parts of the axes in error tinted
        (sent only when the set of axes in error changes)."""
        marks = self.marks
        if marks is not None:
            marks.visible = self.show_axis_labels
            if self.show_axis_labels:
                errors = {name: view.error_id for name, view in snapshot.axes.items()}
                marks.update(snapshot.xpos, snapshot.xquat, errors)
        failing = frozenset(n for n, v in snapshot.axes.items() if v.error_id and n in self._moved)
        if failing != self._failing and self._scene is not None:
            self._failing = failing
            bodies = {b for name in failing for b in self._moved[name]}
            self._scene.tint_bodies(bodies, ERROR_TINT)

    def _follow_cameras(self, snapshot: Snapshot) -> None:
        """Move each page's camera by the travel of the followed body since the last move, so
        that it keeps its offset to the body (and the page can still orbit and zoom)."""
        body = self._follow_ids.get(self.follow)
        anchors = self._follow_anchor
        if body is None or body >= snapshot.xpos.shape[0]:
            anchors.clear()
            return
        target = snapshot.xpos[body]
        clients = self.server.get_clients()
        for client_id in [c for c in anchors if c not in clients]:
            del anchors[client_id]
        for client_id, client in clients.items():
            anchor = anchors.get(client_id)
            if anchor is None or anchor[0] != body:
                anchors[client_id] = (body, target.copy())
                continue
            shift = target - anchor[1]
            if float(np.max(np.abs(shift))) < FOLLOW_STEP:
                continue
            client.camera.position = client.camera.position + shift
            anchors[client_id] = (body, target.copy())


def _machine_bounds(
    model: mujoco.MjModel, data: mujoco.MjData
) -> tuple[npt.NDArray[np.float64], float] | None:
    """Centre [m] and radius [m] of the machine: every geom but planes and those more than
    :data:`FRAME_OUTLIER` times the median size (an endless strip); None: nothing solid."""
    rbound_all = np.asarray(model.geom_rbound)
    solid = np.asarray(model.geom_type) != mujoco.mjtGeom.mjGEOM_PLANE
    if not solid.any():
        return None
    solid &= rbound_all <= FRAME_OUTLIER * float(np.median(rbound_all[solid]))
    rbound = rbound_all[solid][:, None]
    xpos = np.asarray(data.geom_xpos)[solid]
    low, high = (xpos - rbound).min(axis=0), (xpos + rbound).max(axis=0)
    return 0.5 * (low + high), 0.5 * float(np.linalg.norm(high - low))


def label_step(radius: float) -> float:
    """Height [m] of a label's line (:data:`~viewer.view3d.axis_marks.LABEL_LINE`) at the
    machine's centre as a camera preset framing a machine of ``radius`` [m] shows it."""
    distance = radius / math.sin(math.atan(math.tan(0.5 * CAMERA_FOV) * FRAME_ASPECT))
    return LABEL_LINE * distance / FOCAL_PX


def _camera_position(
    center: npt.NDArray[np.float64], radius: float, direction: Sequence[float]
) -> npt.NDArray[np.float64]:
    """Camera position [m] looking at ``center`` from ``direction`` at a distance that shows
    a sphere of ``radius`` whole in a canvas of :data:`FRAME_ASPECT` (and any wider one)."""
    d = np.asarray(direction, dtype=np.float64)
    half = math.atan(math.tan(0.5 * CAMERA_FOV) * FRAME_ASPECT)  # horizontal half angle
    return center + radius / math.sin(half) * d / np.linalg.norm(d)

"""The commanded and the actual path of an axes group in the 3-D view: the trail of its tool
point (the model's ``tool`` site, else the body of its last member), commanded where the
members' set points put it and actual where the physics' joints do, the actual one's deviation
from the commanded one magnified on request.

Each drawn point is one snapshot's: the commanded point is the forward kinematics of the joints
moved to their axes' set points (joint + following error / scale, as the set-point ghost does:
:mod:`viewer.view3d.overlays`), the actual point that of the joints as measured. Drawn with
magnification k, the actual point is ``commanded + k · (actual − commanded)``: a following error
of 10 µm shows as 1 mm at ×100, and the factor is written beside the trail. A point is added
when the tool point moved :data:`MIN_STEP`; the trail keeps the last :data:`TRAIL_POINTS` in
line nodes of :data:`CHUNK` points, of which only the newest is sent again as it grows. The View
folder's ``Clear path`` empties it, and so does a new machine (:meth:`PathView.clear`).
"""

from __future__ import annotations

__all__ = [
    "ACTUAL_COLOR",
    "CHUNK",
    "COMMANDED_COLOR",
    "MAGNIFICATIONS",
    "MIN_STEP",
    "TRAIL_POINTS",
    "PathTrail",
    "PathView",
    "tool_point",
]

from collections.abc import Callable, Sequence
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt
import viser

import scenes
from viewer.pages.widgets import SceneGui
from viewer.sim.snapshot import Snapshot
from viewer.view3d.overlays import GhostAxis, ghost_axes, moved_bodies

TRAIL_POINTS = 4000
"""Points of the trail kept at most (the oldest chunk goes first)."""

CHUNK = 200
"""Points of one line node of the trail."""

MIN_STEP = 2e-5
"""Travel [m] of the commanded or the actual tool point after which a point is added."""

MAGNIFICATIONS = {"×1": 1.0, "×10": 10.0, "×100": 100.0, "×1000": 1000.0}
"""The Path choices: label → magnification of the actual path's deviation."""

COMMANDED_COLOR = (40, 190, 80)
"""Colour of the commanded path (green, RGB in [0, 255])."""

ACTUAL_COLOR = (255, 120, 0)
"""Colour of the actual path (orange, RGB in [0, 255])."""

OFF = "off"
"""The Path choice that draws no path."""

Points = npt.NDArray[np.float64]


def tool_point(model: mujoco.MjModel, axes: Sequence[GhostAxis]) -> tuple[str, int]:
    """The point whose path is drawn: ``("site", id)`` of a site named ``tool`` (or ``…/tool``)
    that every member moves, else ``("body", id)`` of the body of the last member's joint."""
    moved = set(moved_bodies(model, [a.qpos_adr for a in axes]))
    for a in axes:
        moved &= set(moved_bodies(model, [a.qpos_adr]))
    for s in range(model.nsite):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, s) or ""
        if name.split("/")[-1] == "tool" and int(model.site_bodyid[s]) in moved:
            return "site", s
    adr = axes[-1].qpos_adr
    joint = next(j for j in range(model.njnt) if int(model.jnt_qposadr[j]) == adr)
    return "body", int(model.jnt_bodyid[joint])


class PathTrail:
    """The trail of a group's tool point, commanded and actual, in ``server``'s scene.

    Args:
        server: The viser server.
        model: The compiled model.
        axes: The group's members with a joint (:func:`~viewer.view3d.overlays.ghost_axes`).
        prefix: Node path of the trail.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        model: mujoco.MjModel,
        axes: Sequence[GhostAxis],
        prefix: str = "/path",
    ) -> None:
        self._server = server
        self._model = model
        self._data = mujoco.MjData(model)
        self._adrs = np.array([a.qpos_adr for a in axes], dtype=np.intp)
        self._scales = np.array([a.scale for a in axes], dtype=np.float64)
        self._point = tool_point(model, axes)
        self._prefix = prefix
        self._magnification = 1.0
        self._chunks: list[tuple[list[Points], list[Points]]] = []
        self._nodes: list[tuple[viser.LineSegmentsHandle, viser.LineSegmentsHandle] | None] = []
        self._label: viser.LabelHandle | None = None
        self._serial = 0

    def measure(
        self, qpos: npt.NDArray[np.float64], following_errors: Sequence[float]
    ) -> tuple[Points, Points]:
        """The commanded and the actual tool point [m, world] of joints ``qpos`` with the
        members' ``following_errors`` (set point minus actual position [user units])."""
        data = self._data
        data.qpos[:] = qpos
        mujoco.mj_kinematics(self._model, data)
        actual = self._position()
        data.qpos[self._adrs] += np.asarray(following_errors, dtype=np.float64) / self._scales
        mujoco.mj_kinematics(self._model, data)
        return self._position(), actual

    def _position(self) -> Points:
        kind, index = self._point
        return np.array(self._data.site_xpos[index] if kind == "site" else self._data.xpos[index])

    @property
    def magnification(self) -> float:
        """Factor of the actual path's deviation from the commanded path as drawn."""
        return self._magnification

    @magnification.setter
    def magnification(self, factor: float) -> None:
        if factor != self._magnification:
            self._magnification = factor
            for k in range(len(self._chunks)):
                self._draw(k)
            self._draw_label()

    @property
    def commanded(self) -> Points:
        """The commanded points of the trail [m], shape (n, 3), oldest first."""
        return self._points(0)

    @property
    def actual(self) -> Points:
        """The actual points of the trail [m] as measured (not magnified)."""
        return self._points(1)

    @property
    def drawn(self) -> tuple[Points, Points]:
        """The segments as drawn, commanded and actual (magnified), each shape (n, 2, 3) [m]."""
        nodes = [n for n in self._nodes if n is not None]
        empty = np.zeros((0, 2, 3))
        return (
            np.concatenate([empty, *(n[0].points for n in nodes)]),
            np.concatenate([empty, *(n[1].points for n in nodes)]),
        )

    @property
    def label(self) -> str:
        """The text written beside the trail (empty: no trail)."""
        return "" if self._label is None else self._label.text

    def update(self, qpos: npt.NDArray[np.float64], following_errors: Sequence[float]) -> None:
        """Add the tool point of this snapshot when it moved :data:`MIN_STEP` since the last
        one, and draw the newest chunk."""
        commanded, actual = self.measure(qpos, following_errors)
        chunks = self._chunks
        if chunks:
            last_c, last_a = chunks[-1][0][-1], chunks[-1][1][-1]
            step = max(np.linalg.norm(commanded - last_c), np.linalg.norm(actual - last_a))
            if step < MIN_STEP:
                return
        if not chunks or len(chunks[-1][0]) >= CHUNK:
            joint = ([chunks[-1][0][-1]], [chunks[-1][1][-1]]) if chunks else ([], [])
            chunks.append(joint)  # a new chunk goes on from the last point of the previous
            self._nodes.append(None)
            if sum(len(c[0]) - 1 for c in chunks) > TRAIL_POINTS:
                self._drop_oldest()
        chunks[-1][0].append(commanded)
        chunks[-1][1].append(actual)
        self._draw(len(chunks) - 1)
        self._draw_label()

    def clear(self) -> None:
        """Empty the trail."""
        for nodes in self._nodes:
            for node in nodes or ():
                node.remove()
        if self._label is not None:
            self._label.remove()
        self._chunks, self._nodes, self._label = [], [], None

    remove = clear

    def _points(self, which: int) -> Points:
        chunks = self._chunks
        parts = [np.array(c[which][1 if k else 0 :]) for k, c in enumerate(chunks) if c[which]]
        return np.concatenate([np.zeros((0, 3)), *[p.reshape(-1, 3) for p in parts]])

    def _drop_oldest(self) -> None:
        self._chunks.pop(0)
        nodes = self._nodes.pop(0)
        for node in nodes or ():
            node.remove()

    def _draw(self, k: int) -> None:
        """Send chunk ``k`` (its nodes replaced)."""
        commanded, actual = (np.array(p) for p in self._chunks[k])
        if len(commanded) < 2:
            return
        shown = commanded + self._magnification * (actual - commanded)
        old = self._nodes[k]
        self._serial += 1
        scene = self._server.scene
        nodes = tuple(
            scene.add_line_segments(
                f"{self._prefix}/{name}{self._serial}",
                np.stack([p[:-1], p[1:]], axis=1),
                colors=color,
                thickness=2.0,
                thickness_units="screen",
            )
            for name, p, color in (
                ("commanded", commanded, COMMANDED_COLOR),
                ("actual", shown, ACTUAL_COLOR),
            )
        )
        self._nodes[k] = (nodes[0], nodes[1])
        for node in old or ():
            node.remove()

    def _draw_label(self) -> None:
        """The label at the newest commanded point: the colours and the magnification."""
        if not self._chunks:
            return
        text = f"path: commanded (green), actual (orange) deviation ×{self._magnification:g}"
        position = self._chunks[-1][0][-1]
        label = self._label
        if label is None:
            self._label = self._server.scene.add_label(
                f"{self._prefix}/label", text, position=position, anchor="bottom-left"
            )
        else:
            if label.text != text:
                label.text = text
            label.position = position


class PathView:
    """The View folder's Path choice and the trail it draws for the current machine's group
    (its definition's ``group``; none: no choice).

    Args:
        server: The viser server.
    """

    def __init__(self, server: viser.ViserServer) -> None:
        self.server = server
        self.trail: PathTrail | None = None
        """The trail of the current model (made when first shown)."""
        self.choice = OFF
        """The Path choice: :data:`OFF` or a key of :data:`MAGNIFICATIONS`."""
        self.available = False
        """The current machine has a group to draw the path of (else no Path choice)."""
        self._clear = False

    def prepare(self, snapshot: Snapshot) -> None:
        """A new machine: whether it has a group (:attr:`available`)."""
        self.available = snapshot.model is not None and bool(_members(snapshot))

    def clear(self) -> None:
        """Drop the trail (the machine changes)."""
        if self.trail is not None:
            self.trail.remove()
        self.trail = None

    def request_clear(self) -> None:
        """Empty the trail at the next update (the Clear path button)."""
        self._clear = True

    def build(self, gui: SceneGui, redraw: Callable[[], None]) -> None:
        """The Path dropdown and the Clear path button (in the View folder) of a machine with
        a group."""
        if not self.available:
            return
        choice = gui.dropdown(
            "Path (actual deviation)",
            [OFF, *MAGNIFICATIONS],
            self.choice,
            control=False,
            hint="The group's tool point: commanded path, actual path with its deviation ×k",
        )
        clear = gui.button("Clear path", control=False, hint="Empty the drawn path")

        @choice.on_update
        def _(event: Any) -> None:
            self.choice = choice.value
            redraw()

        @clear.on_click
        def _(event: Any) -> None:
            self.request_clear()
            redraw()

    def update(self, snapshot: Snapshot) -> None:
        """Add the snapshot's tool point to the trail while the Path choice is on; empty it
        when it is off."""
        trail = self.trail
        if self._clear and trail is not None:
            trail.clear()
        self._clear = False
        model = snapshot.model
        if self.choice not in MAGNIFICATIONS or model is None:
            if trail is not None:
                trail.clear()
            return
        if trail is None:
            members = _members(snapshot)
            if not members:
                return
            axes = ghost_axes(model, snapshot.scene, [(n, snapshot.axes[n].joint) for n in members])
            trail = self.trail = PathTrail(self.server, model, axes)
        trail.magnification = MAGNIFICATIONS[self.choice]
        errors = [snapshot.axes[n].following_error for n in _members(snapshot)]
        trail.update(snapshot.qpos, errors)


def _members(snapshot: Snapshot) -> list[str]:
    """The group's members of the snapshot's machine that have a drive and a joint."""
    group = scenes.definition(snapshot.scene).group
    axes = snapshot.axes
    return [n for n in group if n in axes and axes[n].has_drive and axes[n].joint]

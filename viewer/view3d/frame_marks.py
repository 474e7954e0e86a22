"""The product coordinate system (PCS) of each robot group in the 3-D view: a small triad at the
frame's origin (x red, y green, z blue) with a label naming it and what carries it
(``"PCS delta · on C"``), moving with the belt while the group tracks a part, hidden while the
group has no PCS (:class:`~viewer.sim.product_frames.FrameView`)."""

from __future__ import annotations

__all__ = ["TRIAD_LENGTH", "FrameMarks", "frame_label"]

import numpy as np
import viser

from viewer.sim.product_frames import FrameView
from viewer.sim.snapshot import Snapshot

TRIAD_LENGTH = 0.15
"""Length of the triad's arms [m]."""


def frame_label(view: FrameView) -> str:
    """What the frame's label says: ``"PCS delta · on C"`` (``"PCS delta"`` standing still)."""
    return f"PCS {view.group}" + (f" · on {view.master}" if view.master else "")


def _wxyz(x_axis: tuple[float, float, float]) -> np.ndarray:
    """The rotation about the world z that turns the world x onto ``x_axis`` (w, x, y, z)."""
    half = 0.5 * float(np.arctan2(x_axis[1], x_axis[0]))
    return np.array([np.cos(half), 0.0, 0.0, np.sin(half)])


class FrameMarks:
    """The triads of the groups' PCS, made when a group first has one, hidden when it has none.

    Args:
        server: The viser server.
        prefix: Node path of the triads.
    """

    def __init__(self, server: viser.ViserServer, prefix: str = "/product_frames") -> None:
        self._server, self._prefix = server, prefix
        self._frames: dict[str, viser.FrameHandle] = {}
        self._labels: dict[str, viser.LabelHandle] = {}

    def update(self, snapshot: Snapshot) -> None:
        """Each group's triad where its PCS is now; those without one hidden (only changes are
        sent)."""
        shown = {view.group: view for view in snapshot.frames}
        with self._server.atomic():
            for group, view in shown.items():
                frame = self._frames.get(group)
                if frame is None:
                    frame = self._add(group)
                position, wxyz = np.asarray(view.origin), _wxyz(view.x_axis)
                if not np.array_equal(frame.position, position):
                    frame.position = position
                if not np.allclose(frame.wxyz, wxyz, atol=1e-9):
                    frame.wxyz = wxyz
                label = self._labels[group]
                if label.text != frame_label(view):
                    label.text = frame_label(view)
                if not frame.visible:
                    frame.visible = True
            for group, frame in self._frames.items():
                if group not in shown and frame.visible:
                    frame.visible = False

    def _add(self, group: str) -> viser.FrameHandle:
        scene, node = self._server.scene, f"{self._prefix}/{group}"
        frame = scene.add_frame(node, axes_length=TRIAD_LENGTH, axes_radius=0.04 * TRIAD_LENGTH)
        self._labels[group] = scene.add_label(
            f"{node}/label",
            f"PCS {group}",
            position=(0.0, 0.0, 1.2 * TRIAD_LENGTH),
            depth_test=False,
            anchor="bottom-center",
        )
        self._frames[group] = frame
        return frame

    def origin(self, group: str) -> np.ndarray | None:
        """World position [m] of ``group``'s triad as last drawn; None while it is hidden."""
        frame = self._frames.get(group)
        if frame is None or not frame.visible:
            return None
        return np.array(frame.position, dtype=np.float64)

    def label(self, group: str) -> str:
        """The text of ``group``'s label (empty: never drawn)."""
        label = self._labels.get(group)
        return "" if label is None else label.text

    def remove(self) -> None:
        """Remove the triads from the scene."""
        for frame in self._frames.values():
            frame.remove()
        self._frames.clear()
        self._labels.clear()

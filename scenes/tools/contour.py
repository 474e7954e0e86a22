"""Contour error: how far the tool point strays from the ideal straight segments of a path.

:func:`run_path` runs a group path on a scene and records the tool site; :class:`Contour`
measures it against the polyline, on the straight parts (stops at Buffered corners included)
and near the blended corners.
"""

from __future__ import annotations

__all__ = ["Contour", "distance_to_polyline", "run_path"]

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

import mcl
from scenes.tools.grouping import PoweredGroup


def distance_to_polyline(
    points: np.ndarray, vertices: Sequence[Sequence[float]] | np.ndarray
) -> np.ndarray:
    """Distance of each point to the nearest segment of a polyline.

    Args:
        points: (N, 3) positions.
        vertices: the polyline's corner points, in order (at least two).

    Returns:
        (N,) distances, in the units of the inputs.
    """
    v = np.asarray(vertices, dtype=float)
    if v.ndim != 2 or len(v) < 2:
        raise ValueError("a polyline needs at least two vertices")
    p = np.asarray(points, dtype=float)
    best = np.full(len(p), np.inf)
    for a, b in itertools.pairwise(v):
        ab = b - a
        length2 = float(ab @ ab)
        s = np.zeros(len(p)) if length2 == 0.0 else np.clip((p - a) @ ab / length2, 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(p - (a + s[:, None] * ab), axis=1))
    return best


@dataclass(frozen=True)
class Contour:
    """The tool point along a group path, measured on the physics (world frame, m).

    Attributes:
        points: (N, 3) positions of the tool site, one per servo cycle while the path ran.
        vertices: the ideal polyline: the start point and each commanded corner/end point.
        blended: per inner corner (``vertices[1:-1]``), whether the path blends through it.
    """

    points: np.ndarray
    vertices: np.ndarray
    blended: tuple[bool, ...]

    @property
    def errors(self) -> np.ndarray:
        """(N,) distance of each point from the polyline [m]."""
        return distance_to_polyline(self.points, self.vertices)

    def near_blends(self, radius: float) -> np.ndarray:
        """(N,) whether a point lies within ``radius`` [m] of a blended corner."""
        near = np.zeros(len(self.points), dtype=bool)
        for corner, blended in zip(self.vertices[1:-1], self.blended, strict=True):
            if blended:
                near |= np.linalg.norm(self.points - corner, axis=1) <= radius
        return near

    def straight_error(self, radius: float) -> float:
        """Largest error away from the blended corners, stops at Buffered corners included [m]."""
        errors = self.errors[~self.near_blends(radius)]
        return float(errors.max()) if errors.size else 0.0

    def corner_error(self, radius: float) -> float:
        """Largest error within ``radius`` of a blended corner [m] (0 without blends)."""
        errors = self.errors[self.near_blends(radius)]
        return float(errors.max()) if errors.size else 0.0


def _segments(
    group: mcl.AxesGroup,
    distances: Sequence[Sequence[float]],
    modes: Sequence[mcl.MC_BufferMode],
    velocity: float,
    acceleration: float,
    jerk: float,
) -> list[mcl.MC_MoveLinearRelative]:
    """One MC_MoveLinearRelative per segment, its inputs bound."""
    return [
        mcl.MC_MoveLinearRelative(
            AxesGroup=group,
            Distance=list(d),
            Velocity=velocity,
            Acceleration=acceleration,
            Deceleration=acceleration,
            Jerk=jerk,
            BufferMode=mode,
        )
        for d, mode in zip(distances, modes, strict=True)
    ]


def run_path(
    scene: Any,
    axes: Sequence[str],
    tool: str,
    distances: Sequence[Sequence[float]],
    modes: Sequence[mcl.MC_BufferMode],
    velocity: float,
    corner_tolerance: float,
    acceleration: float = 2000.0,
    jerk: float = 20000.0,
) -> Contour:
    """Power the axes, group them and run a path of MC_MoveLinearRelative segments.

    The axes must move the tool along world x, y, z (a Cartesian machine such as the gantry),
    one per coordinate, their user unit a fixed multiple of the metre (``scene.scales``).

    Args:
        scene: a :class:`scenes.scene.Scene` with the axes still Disabled.
        axes: the group members, in the order of the distance components.
        tool: the site whose world position is measured (e.g. ``"gantry/tool"``).
        distances: each segment's distance [u] per member.
        modes: each segment's BufferMode (Buffered: stop at the corner; Blending*: round it).
        velocity, acceleration, jerk: of the path [u/s, u/s², u/s³].
        corner_tolerance: the group's corner tolerance [u].

    Raises:
        RuntimeError: a block ended in error (the message names it).
    """
    members = [scene.axes[a] for a in axes]
    scales = np.array([scene.scales[a] for a in axes])
    grouped = PoweredGroup(members, "contour", corner_tolerance)
    group, enable = grouped.group, grouped.enable
    moves = _segments(group, distances, modes, velocity, acceleration, jerk)
    go = [False]

    def program() -> None:
        grouped()
        for m in moves:
            m(Execute=go[0])
        for fb in (*grouped.blocks, *moves):
            if fb.Error:
                raise RuntimeError(f"{type(fb).__name__}: error {fb.ErrorID}")

    scene.run(program, until=lambda: enable.Done, timeout=2.0)
    scene.run(program, timeout=0.2)  # settle
    site = scene.model.site(tool).id
    data = scene.data
    start = data.site_xpos[site].copy()
    origin = np.array([m.actual for m in members])
    points: list[np.ndarray] = []

    def observe(t: float) -> None:
        points.append(data.site_xpos[site].copy())

    go[0] = True
    scene.runtime.observers.append(observe)
    try:
        scene.run(program, until=lambda: moves[-1].Done, timeout=60.0)
        scene.run(program, timeout=0.1)
    finally:
        scene.runtime.observers.remove(observe)
    targets = origin + np.cumsum(np.array(distances, dtype=float), axis=0)
    vertices = np.vstack([start, start + (targets - origin) / scales])
    blended = tuple(m >= mcl.MC_BufferMode.BlendingLow for m in modes[1:])
    return Contour(np.array(points), vertices, blended)

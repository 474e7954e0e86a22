"""Contour error: how far the tool point strays from the ideal straight segments of a path."""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np


def distance_to_polyline(points: np.ndarray, vertices: Sequence[Sequence[float]]) -> np.ndarray:
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

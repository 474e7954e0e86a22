"""The velocity an encoder-only axis shows: the mean over the last :data:`WINDOW` of its
position, sampled by the simulation thread every PLC scan.

Such an axis (a measuring wheel) has no servo constants, so no velocity filter: its ``VEL`` is
one servo cycle's count difference, which flickers by a whole count per cycle — 0.025 mm per
1 ms, ±25 mm/s, for a wheel standing still on a line that holds with one count of dither. Over
:data:`WINDOW` one count is 0.25 mm/s."""

from __future__ import annotations

__all__ = ["WINDOW", "MeanVelocity"]

from collections import deque
from collections.abc import Mapping

import mcl

WINDOW = 0.1
"""Time [s] over which an encoder-only axis' velocity is averaged."""


class MeanVelocity:
    """The mean velocity over :data:`WINDOW` of each encoder-only axis [u/s].

    Used from the simulation thread only: :meth:`sample` once per PLC scan.

    Args:
        axes: The scene's axes by name (those with a drive are left out).
        period: The PLC period [s].
    """

    def __init__(self, axes: Mapping[str, mcl.Axis], period: float) -> None:
        self._axes = tuple((n, a) for n, a in axes.items() if not a.has_drive)
        length = max(2, round(WINDOW / period) + 1)
        self._samples: dict[str, deque[tuple[float, float]]] = {
            name: deque(maxlen=length) for name, _ in self._axes
        }

    def sample(self, time: float) -> None:
        """Take the (unwrapped) position of every encoder-only axis at ``time`` [s]."""
        for name, axis in self._axes:
            self._samples[name].append((time, axis.actual))

    def velocity(self, name: str, axis: mcl.Axis) -> float:
        """What the axis ``name`` shows [u/s]: its mean over the window if it is encoder-only
        (and sampled twice), else its ``VEL``."""
        samples = self._samples.get(name)
        if not samples or len(samples) < 2:
            return float(axis.VEL)
        (t0, p0), (t1, p1) = samples[0], samples[-1]
        return (p1 - p0) / (t1 - t0) if t1 > t0 else float(axis.VEL)

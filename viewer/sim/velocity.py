"""The velocity an encoder-only axis shows, as a drive shows it: the position difference over
the last :data:`WINDOW`, smoothed by a first-order filter of time constant
:data:`TIME_CONSTANT`, updated by the simulation thread every PLC scan.

Such an axis (a measuring wheel) has no servo constants, so no velocity filter: its ``VEL`` is
one servo cycle's count difference, which flickers by a whole count per cycle — 0.025 mm per
1 ms, ±25 mm/s, for a wheel standing still on a line that holds with one count of dither. Over
:data:`WINDOW` one count is 0.125 mm/s; the filter smooths that to a few hundredths of a mm/s,
so a scope's trace of a wheel standing still is a line at 0, not a block. The shown velocity
lags a ramp of the line by about ``WINDOW / 2 + TIME_CONSTANT`` (0.2 s)."""

from __future__ import annotations

__all__ = ["TIME_CONSTANT", "WINDOW", "ShownVelocity"]

from collections import deque
from collections.abc import Mapping

import mcl

WINDOW = 0.2
"""Time [s] over which an encoder-only axis' position difference is taken."""

TIME_CONSTANT = 0.1
"""Time constant [s] of the first-order filter after the position difference."""


class ShownVelocity:
    """The velocity of each encoder-only axis as shown [u/s]: position difference over
    :data:`WINDOW`, then a first-order filter of :data:`TIME_CONSTANT`.

    Used from the simulation thread only: :meth:`sample` once per PLC scan.

    Args:
        axes: The scene's axes by name (those with a drive are left out).
        period: The PLC period [s].
    """

    def __init__(self, axes: Mapping[str, mcl.Axis], period: float) -> None:
        self._axes = tuple((n, a) for n, a in axes.items() if not a.has_drive)
        self._length = length = max(2, round(WINDOW / period) + 1)
        self._samples: dict[str, deque[tuple[float, float]]] = {
            name: deque(maxlen=length) for name, _ in self._axes
        }
        self._filtered: dict[str, float] = {}

    def sample(self, time: float) -> None:
        """Take the (unwrapped) position of every encoder-only axis at ``time`` [s] and update
        its filtered velocity."""
        for name, axis in self._axes:
            samples = self._samples[name]
            previous = samples[-1][0] if samples else time
            samples.append((time, axis.actual))
            (t0, p0), (t1, p1) = samples[0], samples[-1]
            if t1 <= t0:
                continue
            difference = (p1 - p0) / (t1 - t0)
            filtered = self._filtered.get(name)
            if filtered is None or len(samples) < self._length:  # the filter starts at the
                self._filtered[name] = difference  # difference over the first whole window
            else:
                share = min(1.0, (time - previous) / TIME_CONSTANT)
                self._filtered[name] = filtered + share * (difference - filtered)

    def velocity(self, name: str, axis: mcl.Axis) -> float:
        """What the axis ``name`` shows [u/s]: its filtered velocity if it is encoder-only (and
        sampled twice), else its ``VEL``."""
        filtered = self._filtered.get(name)
        return float(axis.VEL) if filtered is None else filtered

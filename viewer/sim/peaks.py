"""Peak hold of the following error: the largest |following error| of every axis since the last
reset, sampled by the simulation thread every PLC scan (not from the snapshots a page sees)."""

from __future__ import annotations

__all__ = ["PeakHold"]

from collections.abc import Mapping

import mcl


class PeakHold:
    """The |max| following error of each axis since the last :meth:`reset` [u of the axis].

    Used from the simulation thread only: :meth:`sample` once per PLC scan, :meth:`reset` as a
    queued command between two scans.

    Args:
        axes: The scene's axes by name.
    """

    def __init__(self, axes: Mapping[str, mcl.Axis]) -> None:
        self._axes = tuple(axes.items())
        self._peaks = dict.fromkeys(axes, 0.0)

    def sample(self) -> None:
        """Take the following error of every axis now (one PLC scan)."""
        peaks = self._peaks
        for name, axis in self._axes:
            error = abs(axis.following_error)
            if error > peaks[name]:
                peaks[name] = error

    def reset(self) -> None:
        """Forget the peaks: every axis starts again from its following error now."""
        for name in self._peaks:
            self._peaks[name] = 0.0
        self.sample()

    def peak(self, name: str) -> float:
        """The peak |following error| of the axis ``name`` since the last reset [u]."""
        return self._peaks[name]

"""The scope recorder: every scope channel of a scene (axes, their switches and outputs, the
published signals) sampled on one time base into a ring buffer."""

from __future__ import annotations

__all__ = ["Recorder", "Ring"]

import functools
import math
import threading
from collections.abc import Callable, Mapping, Sequence
from typing import Literal

import numpy as np
import numpy.typing as npt

import mcl
from scenes.scene import Scene
from viewer.sim.snapshot import AxisInfo, Channel


class Recorder:
    """Every scope channel of a scene on one time base, in a ring buffer (thread-safe).

    Per axis: position, set point, velocity, following error and command [V] (the last three
    only with a drive), its switch inputs, index, digital outputs and an error flag (AxErrorID
    ≠ 0); then the machine's published signals.

    Args:
        scene: The scene.
        info: What the machine definition says about each axis (its switches).
        length: Samples kept per channel.
    """

    def __init__(self, scene: Scene, info: Mapping[str, AxisInfo], length: int) -> None:
        channels: list[Channel] = []
        readers: list[Callable[[], float]] = []

        def add(name: str, unit: str, digital: bool, read: Callable[[], float]) -> None:
            channels.append(Channel(name, unit, digital))
            readers.append(read)

        for name, axis in scene.axes.items():
            unit = axis.config.unit
            io = axis.io
            add(f"{name} position", unit, False, functools.partial(_attribute, axis, "POS"))
            if axis.has_drive:
                add(f"{name} set point", unit, False, functools.partial(_set_point, axis))
            add(f"{name} velocity", f"{unit}/s", False, functools.partial(_attribute, axis, "VEL"))
            if axis.has_drive:
                fe = functools.partial(_attribute, axis, "following_error")
                add(f"{name} following error", unit, False, fe)
                add(f"{name} command", "V", False, functools.partial(_attribute, axis, "volts"))
            for switch in info[name].switches:
                label = {"lim_neg": "LIM-", "lim_pos": "LIM+", "ref": "REF"}.get(switch, switch)
                add(f"{name} {label}", "", True, functools.partial(_attribute, io, switch))
            add(f"{name} index", "", True, functools.partial(_attribute, io, "index"))
            for k in range(len(io.outputs)):
                add(f"{name} DO{k}", "", True, functools.partial(_output, io, k))
            add(f"{name} error", "", True, functools.partial(_axis_error, axis))
        for signal_name, signal in scene.signals.items():
            owner = scene.signal_owner(signal_name)
            add(signal_name, signal.unit, False, _signal_reader(owner, signal.read))
        self.channels = tuple(channels)
        """The channels, in the order of :meth:`series`' rows."""
        self._readers = readers
        self.ring = Ring(len(channels), length)
        """The samples."""

    def record(self, t: float) -> None:
        """Store one sample of every channel taken at simulated time ``t`` [s] (the simulation
        thread calls it)."""
        self.ring.append(t, [read() for read in self._readers])

    def series(self, since: float = -math.inf) -> tuple[npt.NDArray[np.float64], ...]:
        """Copies of the samples at or after ``since`` [s], oldest first: ``(t, values)`` with
        values of shape (channels, samples)."""
        return self.ring.window(since)


class Ring:
    """Samples of some channels on one time base, the newest ``length`` kept (thread-safe).

    Args:
        channels: Values per sample.
        length: Samples kept.
    """

    def __init__(self, channels: int, length: int) -> None:
        self.length = max(int(length), 2)
        """Samples kept."""
        self._t = np.zeros(self.length)
        self._values = np.zeros((channels, self.length))
        self._next = 0
        self._count = 0
        self._lock = threading.Lock()

    def append(self, t: float, row: Sequence[float]) -> None:
        """Store the sample ``row`` (one value per channel) taken at time ``t`` [s]."""
        with self._lock:
            k = self._next
            self._t[k] = t
            self._values[:, k] = row
            self._next = (k + 1) % self.length
            self._count = min(self._count + 1, self.length)

    @property
    def latest(self) -> float:
        """Time [s] of the newest sample (-inf: none yet)."""
        with self._lock:
            return float(self._t[self._next - 1]) if self._count else -math.inf

    @property
    def oldest(self) -> float:
        """Time [s] of the oldest sample kept (inf: none yet)."""
        with self._lock:
            if not self._count:
                return math.inf
            return float(self._t[(self._next - self._count) % self.length])

    def window(
        self, since: float = -math.inf, until: float = math.inf, rows: Sequence[int] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Copies of the samples with ``since`` ≤ t ≤ ``until`` [s], oldest first: ``(t,
        values)``, values of shape (rows, samples) (``rows``: channel indices, None: all)."""
        with self._lock:
            first = (self._next - self._count) % self.length
            order = (first + self._span(first, since, until)) % self.length
            t = self._t[order]
            values = (
                self._values[:, order]
                if rows is None
                else self._values[np.ix_(np.asarray(rows, dtype=np.intp), order)]
            )
        return t, values

    def _span(self, first: int, since: float, until: float) -> npt.NDArray[np.intp]:
        """Positions (from the oldest sample) of the samples in [since, until]."""
        n = self._count
        head = self._t[first : min(first + n, self.length)]
        tail = self._t[: max(first + n - self.length, 0)]

        def position(time: float, side: Literal["left", "right"]) -> int:
            k = int(np.searchsorted(head, time, side))
            return k if k < head.size else head.size + int(np.searchsorted(tail, time, side))

        return np.arange(position(since, "left"), position(until, "right"), dtype=np.intp)


def _attribute(owner: object, name: str) -> float:
    """A number or flag attribute as a float (a flag: 0 or 1)."""
    return float(getattr(owner, name))


def _set_point(axis: mcl.Axis) -> float:
    """An axis' set point [u]: actual position plus following error."""
    return axis.POS + axis.following_error


def _output(io: mcl.channel.AxisChannel, k: int) -> float:
    """Digital output ``k`` of a channel: 0 or 1."""
    return float(bool(io.outputs[k]))


def _axis_error(axis: mcl.Axis) -> float:
    """1 while the axis has an error (AxErrorID ≠ 0), else 0."""
    return float(axis.AxErrorID != 0)


def _signal_reader(scene: Scene, read: Callable[[Scene], float]) -> Callable[[], float]:
    """A published signal as a scope reader (NaN when reading it fails)."""

    def reader() -> float:
        try:
            return float(read(scene))
        except Exception:
            return math.nan

    return reader

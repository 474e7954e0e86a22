"""The scope recorder: every scope channel of a scene (axes, their switches and outputs, the
published signals) sampled on one time base into a ring buffer."""

from __future__ import annotations

import functools
import math
import threading
from collections.abc import Callable, Mapping

import numpy as np
import numpy.typing as npt

import mcl
from scenes.scene import Scene
from viewer.snapshot import AxisInfo, Channel


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
            add(signal_name, signal.unit, False, _signal_reader(scene, signal.read))
        self.channels = tuple(channels)
        """The channels, in the order of :meth:`series`' rows."""
        self._readers = readers
        self._length = max(int(length), 2)
        self._t = np.zeros(self._length)
        self._values = np.zeros((len(channels), self._length))
        self._next = 0
        self._count = 0
        self._lock = threading.Lock()

    def record(self, t: float) -> None:
        """Store one sample of every channel taken at simulated time ``t`` [s]."""
        row = [read() for read in self._readers]
        with self._lock:
            k = self._next
            self._t[k] = t
            self._values[:, k] = row
            self._next = (k + 1) % self._length
            self._count = min(self._count + 1, self._length)

    def series(self, since: float = -math.inf) -> tuple[npt.NDArray[np.float64], ...]:
        """Copies of the samples at or after ``since`` [s], oldest first: ``(t, values)`` with
        values of shape (channels, samples)."""
        with self._lock:
            n, k = self._count, self._next
            order = np.arange(k - n, k) % self._length
            t = self._t[order]
            keep = t >= since
            return t[keep], self._values[:, order[keep]]


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

"""The scope recorder: every scope channel of a scene (axes, their switches and outputs, the
published signals) sampled on one time base into a ring buffer, and a second, coarser one that
keeps each channel's minimum and maximum of every bucket of samples for much longer (no peak
is lost, the memory stays bounded)."""

from __future__ import annotations

__all__ = ["Extremes", "Recorder", "Ring", "extreme_order"]

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
    only with a drive; an encoder-only axis' velocity as shown, and its raw velocity), its
    switch inputs, index, digital outputs and an error flag (AxErrorID ≠ 0); then the machine's
    published signals.

    Args:
        scene: The scene.
        info: What the machine definition says about each axis (its switches).
        length: Samples kept per channel.
        every: Samples per bucket of the coarse buffer (:class:`Extremes`).
        buckets: Buckets the coarse buffer keeps.
        velocity: The velocity an axis shows, by name and axis [u/s] (None: its ``VEL``). An
            encoder-only axis' ``velocity`` channel records it, and its ``raw velocity``
            channel its ``VEL`` (one servo cycle's count difference).
    """

    def __init__(
        self,
        scene: Scene,
        info: Mapping[str, AxisInfo],
        length: int,
        every: int = 50,
        buckets: int = 6000,
        velocity: Callable[[str, mcl.Axis], float] | None = None,
    ) -> None:
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
            raw = functools.partial(_attribute, axis, "VEL")
            if axis.has_drive or velocity is None:
                add(f"{name} velocity", f"{unit}/s", False, raw)
            else:
                add(f"{name} velocity", f"{unit}/s", False, functools.partial(velocity, name, axis))
                add(f"{name} raw velocity", f"{unit}/s", False, raw)
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
        """The samples (the last ones, every one as recorded)."""
        self.extremes = Extremes(self.ring, every, buckets)
        """The minimum and maximum of every bucket of samples (a longer stretch)."""

    def record(self, t: float) -> None:
        """Store one sample of every channel taken at simulated time ``t`` [s] (the simulation
        thread calls it)."""
        self.ring.append(t, [read() for read in self._readers])
        self.extremes.sampled()

    @property
    def oldest(self) -> float:
        """Time [s] of the oldest sample either buffer keeps (inf: none yet)."""
        return self.extremes.oldest

    def samples(
        self, since: float = -math.inf, until: float = math.inf, rows: Sequence[int] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], float]:
        """:meth:`Extremes.samples`."""
        return self.extremes.samples(since, until, rows)

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
        self.channels = channels
        """Values per sample."""
        self._t = np.zeros(self.length)
        self._values = np.zeros((channels, self.length))
        self._next = 0
        self._count = 0
        self._lock = threading.Lock()

    def append(self, t: float, row: Sequence[float] | npt.NDArray[np.float64]) -> None:
        """Store the sample ``row`` (one value per channel) taken at time ``t`` [s]."""
        with self._lock:
            k = self._next
            self._t[k] = t
            self._values[:, k] = row
            self._next = (k + 1) % self.length
            self._count = min(self._count + 1, self.length)

    @property
    def full(self) -> bool:
        """It holds :attr:`length` samples (each new one drops the oldest)."""
        with self._lock:
            return self._count == self.length

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

    def samples(
        self, since: float = -math.inf, until: float = math.inf, rows: Sequence[int] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], float]:
        """:meth:`window` and the bucket of its samples: 0 (every one as recorded)."""
        return (*self.window(since, until, rows), 0.0)

    def newest(self, n: int) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Copies of the newest ``n`` samples (fewer if it holds fewer), oldest first."""
        with self._lock:
            n = min(n, self._count)
            order = np.arange(self._next - n, self._next) % self.length
            return self._t[order], self._values[:, order]

    def _span(self, first: int, since: float, until: float) -> npt.NDArray[np.intp]:
        """Positions (from the oldest sample) of the samples in [since, until]."""
        n = self._count
        head = self._t[first : min(first + n, self.length)]
        tail = self._t[: max(first + n - self.length, 0)]

        def position(time: float, side: Literal["left", "right"]) -> int:
            k = int(np.searchsorted(head, time, side))
            return k if k < head.size else head.size + int(np.searchsorted(tail, time, side))

        return np.arange(position(since, "left"), position(until, "right"), dtype=np.intp)


class Extremes:
    """Each channel's minimum and maximum over every ``every`` samples of a fine :class:`Ring`,
    the newest ``buckets`` buckets kept in a coarse ring of its own: two samples per bucket,
    the earlier extreme at the bucket's first sample time and the later at its last (a
    one-sample spike stays in it; thread-safe like its rings).

    Args:
        fine: The ring whose samples it condenses.
        every: Samples per bucket.
        buckets: Buckets kept.
    """

    def __init__(self, fine: Ring, every: int, buckets: int) -> None:
        self.fine, self.every = fine, max(int(every), 1)
        self.ring = Ring(fine.channels, 2 * max(int(buckets), 1))
        """The extremes: two samples per bucket."""
        self.bucket = math.nan
        """Length of a bucket [s] (NaN until the first is complete)."""
        self._pending = 0

    def sampled(self) -> None:
        """The fine ring has one more sample: a bucket complete, its extremes are kept."""
        self._pending += 1
        if self._pending < self.every:
            return
        self._pending = 0
        t, values = self.fine.newest(self.every)
        if t.size < 2:
            return
        pick = np.stack(extreme_order(values), axis=1)  # (channels, 2)
        pair = np.take_along_axis(values, pick, axis=1)
        self.ring.append(float(t[0]), pair[:, 0])
        self.ring.append(float(t[-1]), pair[:, 1])
        self.bucket = float(t[-1] - t[0]) * t.size / (t.size - 1)

    @property
    def oldest(self) -> float:
        """Time [s] of the oldest sample it or the fine ring keeps (inf: none yet)."""
        return min(self.fine.oldest, self.ring.oldest)

    def samples(
        self, since: float = -math.inf, until: float = math.inf, rows: Sequence[int] | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], float]:
        """The samples with ``since`` ≤ t ≤ ``until`` [s] like :meth:`Ring.samples`: every one
        as recorded while the fine ring holds the whole stretch (bucket 0); for a longer one
        the extremes of each bucket, then the fine samples after the last complete bucket
        (bucket: its length [s])."""
        fine = self.fine
        if not fine.full or until - since <= fine.latest - fine.oldest + 1e-9:
            return fine.samples(since, until, rows)
        t, values = self.ring.window(since, until, rows)
        after = float(np.nextafter(t[-1], math.inf)) if t.size else since
        newest_t, newest = fine.window(after, until, rows)
        return (
            np.concatenate([t, newest_t]),
            np.concatenate([values, newest], axis=1),
            self.bucket,
        )


def extreme_order(
    values: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp]]:
    """Positions (along the last axis) of each row's minimum and maximum, the earlier first
    (NaN ignored; a row of NaN gives position 0 twice)."""
    low = np.argmin(np.where(np.isnan(values), np.inf, values), axis=-1)
    high = np.argmax(np.where(np.isnan(values), -np.inf, values), axis=-1)
    return np.minimum(low, high), np.maximum(low, high)


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

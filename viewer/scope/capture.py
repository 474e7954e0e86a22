"""What a scope records: its triggers (free run, threshold crossing, any axis error, a given
time), the acquisition (run, single, freeze, pre-trigger) over the recorder's samples, and the
recordings it keeps (the last few, to overlay one on the live one)."""

from __future__ import annotations

__all__ = [
    "AT_TIME",
    "FREE_RUN",
    "HISTORY_LENGTH",
    "ON_ERROR",
    "THRESHOLD",
    "Acquisition",
    "History",
    "Recording",
    "Samples",
    "Trigger",
    "Window",
    "error_trigger",
    "first_crossing",
    "recording_of",
    "threshold_trigger",
]

import math
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from viewer.scope.units import Display
from viewer.sim.recorder import Ring
from viewer.sim.snapshot import Channel

FREE_RUN = "free run"
"""Trigger kind: none (a rolling window; Single records the next recording length)."""

THRESHOLD = "threshold"
"""Trigger kind: a channel crossing a level."""

ON_ERROR = "on any axis error"
"""Trigger kind: the rising edge of any axis' error flag."""

AT_TIME = "at a time"
"""Trigger kind: a given simulated time (a step test's recording)."""

HISTORY_LENGTH = 5
"""Recordings a scope keeps."""


@dataclass(frozen=True)
class Trigger:
    """What starts a recording.

    Attributes:
        kind: :data:`FREE_RUN`, :data:`THRESHOLD`, :data:`ON_ERROR` or :data:`AT_TIME`.
        rows: The recorder channels watched (their indices).
        level: The level a watched channel crosses [its recorded unit].
        rising: Crossing upwards (False: downwards).
        time: The trigger time of :data:`AT_TIME` [s].
        label: What it waits for, for the status line.
    """

    kind: str = FREE_RUN
    rows: tuple[int, ...] = ()
    level: float = 0.5
    rising: bool = True
    time: float = 0.0
    label: str = FREE_RUN


def error_trigger(channels: Sequence[Channel]) -> Trigger:
    """The rising edge of any axis' error flag (the ``"<axis> error"`` channels)."""
    rows = tuple(k for k, c in enumerate(channels) if c.digital and c.name.endswith(" error"))
    return Trigger(ON_ERROR, rows, 0.5, True, label=ON_ERROR)


def threshold_trigger(
    channels: Sequence[Channel], name: str, level: float, rising: bool, shown: str = ""
) -> Trigger:
    """Channel ``name`` crossing ``level`` [recorded unit] (``shown``: the level as the user
    gave it, for the status line)."""
    rows = tuple(k for k, c in enumerate(channels) if c.name == name)
    edge = "rising" if rising else "falling"
    return Trigger(THRESHOLD, rows, level, rising, label=f"{name} {edge} through {shown or level}")


def first_crossing(
    t: npt.NDArray[np.float64],
    values: npt.NDArray[np.float64],
    level: float,
    rising: bool,
    after: float,
) -> float | None:
    """Time [s] of the first sample past ``level`` whose predecessor was not, later than
    ``after`` (None: no such sample)."""
    if t.size < 2:
        return None
    if rising:
        crossed = (values[1:] >= level) & (values[:-1] < level)
    else:
        crossed = (values[1:] <= level) & (values[:-1] > level)
    found = np.flatnonzero(crossed & (t[1:] > after))
    return float(t[found[0] + 1]) if found.size else None


@dataclass(frozen=True)
class Window:
    """The stretch of simulated time a scope shows.

    Attributes:
        start: First sample time [s].
        end: Last sample time [s] (now, while recording).
        origin: Time [s] shown as 0 (the trigger, or the start of a free-running recording).
        trigger_at: Trigger time [s] (None: free running).
        complete: The recording is complete (frozen).
        status: The scope's state line.
    """

    start: float
    end: float
    origin: float
    trigger_at: float | None
    complete: bool
    status: str


class Acquisition:
    """When a scope records: run, single, freeze; the trigger search over a :class:`Ring`.

    Not thread-safe (the page's scope serialises its calls).

    Args:
        length: Recording length [s].
        pre: Pre-trigger, a fraction of the recording before the trigger.
    """

    def __init__(self, length: float = 2.0, pre: float = 0.1) -> None:
        self.length = length
        """Recording length [s]."""
        self.pre = pre
        """Fraction of the recording before the trigger."""
        self.trigger = Trigger()
        self.running = True
        """It records (False: frozen)."""
        self.single = False
        """It freezes after the next complete recording."""
        self.armed_since = -math.inf
        """Simulated time [s] after which the trigger counts."""
        self.trigger_at: float | None = None
        """Time [s] of the trigger of the recording under way (None: armed or free running)."""
        self.shown: Window | None = None
        """What the scope showed last."""
        self._searched = -math.inf
        self._complete: Window | None = None

    def run(self, now: float, single: bool = False) -> None:
        """Record from ``now`` [s] on: continuously, or (``single``) one recording."""
        self.running, self.single = True, single
        self._arm(now)

    def freeze(self) -> Window | None:
        """Stop recording; what is shown stays (None: nothing yet)."""
        self.running = False
        return self.shown

    def set_trigger(self, trigger: Trigger, now: float) -> None:
        """A new trigger, armed from ``now`` [s] if the scope runs."""
        self.trigger = trigger
        if self.running:
            self._arm(now)

    def _arm(self, since: float) -> None:
        self.armed_since = self._searched = since
        self.trigger_at = None
        if self.trigger.kind == AT_TIME:
            self.trigger_at = self.trigger.time
        elif self.trigger.kind == FREE_RUN and self.single:
            self.trigger_at = since

    @property
    def start(self) -> float:
        """First sample time [s] of the recording under way (trigger minus pre-trigger)."""
        at = self.trigger_at if self.trigger_at is not None else math.nan
        pre = 0.0 if self.trigger.kind == FREE_RUN else self.pre
        return at - pre * self.length

    def poll(self, ring: Ring, now: float) -> tuple[Window, bool]:
        """What to show at ``now`` (the newest sample time [s]) and whether a recording has
        just completed."""
        if not self.running:
            return self.shown or self._rolling(now, "frozen"), False
        if self.trigger.kind == FREE_RUN and not self.single:
            self.shown = self._rolling(now, "running")
            return self.shown, False
        if self.trigger_at is None:
            self.trigger_at = self._search(ring, now)
            if self.trigger_at is None:
                last = self._complete or self._rolling(now, "")
                waiting = f"armed: waiting for {self.trigger.label}"
                self.shown = _with_status(last, waiting)
                return self.shown, False
        start, at = self.start, self.trigger_at
        end = start + self.length
        if now < end:
            done = max(0.0, min(1.0, (now - start) / self.length))
            status = f"{_trigger_text(self.trigger, at)}, recording {100.0 * done:.0f} %"
            self.shown = Window(start, now, at, self._at(), False, status)
            return self.shown, False
        self.shown = self._complete = Window(
            start, end, at, self._at(), True, _trigger_text(self.trigger, at)
        )
        if self.single:
            self.running = False
        else:
            self._arm(end)
        return self.shown, True

    def _at(self) -> float | None:
        return None if self.trigger.kind == FREE_RUN else self.trigger_at

    def _rolling(self, now: float, status: str) -> Window:
        return Window(now - self.length, now, now - self.length, None, False, status)

    def _search(self, ring: Ring, now: float) -> float | None:
        """The first trigger in the samples since the last search (None: none yet)."""
        trigger = self.trigger
        if trigger.kind not in (THRESHOLD, ON_ERROR) or not trigger.rows:
            return None
        t, values = ring.window(self._searched, now, trigger.rows)
        self._searched = max(self._searched, now)
        found = [
            at
            for row in values
            if (at := first_crossing(t, row, trigger.level, trigger.rising, self.armed_since))
            is not None
        ]
        return min(found) if found else None


def _with_status(window: Window, status: str) -> Window:
    return Window(
        window.start, window.end, window.origin, window.trigger_at, window.complete, status
    )


def _trigger_text(trigger: Trigger, at: float) -> str:
    if trigger.kind == FREE_RUN:
        return f"recording from t = {at:.4f} s"
    return f"triggered at t = {at:.4f} s ({trigger.label})"


@dataclass(frozen=True)
class Recording:
    """Samples of some channels over a :class:`Window`, in their display units.

    Attributes:
        number: Its number in the scope's history (0: the live recording).
        names: Channel names.
        displays: How each channel is shown (unit, scale).
        t: Sample times [s] of simulated time.
        values: Samples (channels × samples) [display units].
        window: The stretch of time it covers (its origin: trigger or start).
        bucket: 0: every sample as recorded; > 0: a long recording, each pair of samples the
            minimum and maximum over a bucket this long [s] (the newest samples as recorded).
    """

    number: int
    names: tuple[str, ...]
    displays: tuple[Display, ...]
    t: npt.NDArray[np.float64]
    values: npt.NDArray[np.float64]
    window: Window
    bucket: float = 0.0

    @property
    def resolution(self) -> str:
        """What its samples are: ``every 2 ms`` or ``min and max of every 0.1 s`` ('' when it
        has fewer than two samples)."""
        if self.bucket > 0.0:
            return f"min and max of every {self.bucket:.3g} s"
        if self.t.size < 2:
            return ""
        return f"every {1e3 * float(np.median(np.diff(self.t))):.3g} ms"

    @property
    def x(self) -> npt.NDArray[np.float64]:
        """Sample times relative to the origin [s]."""
        return self.t - self.window.origin

    @property
    def label(self) -> str:
        """How the history lists it: number, trigger, time."""
        w = self.window
        what = "triggered" if w.trigger_at is not None else "recorded"
        return f"#{self.number} {what} at {w.origin:.3f} s ({w.end - w.start:.2f} s)"

    def headers(self, titles: Mapping[str, str] | None = None) -> tuple[str, ...]:
        """Channel names (or their ``titles``, by name) with their display units."""
        named = titles or {}
        return tuple(
            f"{named.get(n, n)} [{d.unit}]" for n, d in zip(self.names, self.displays, strict=True)
        )

    def at(self, x: float) -> npt.NDArray[np.float64]:
        """Each channel's value at the sample nearest to ``x`` [s from the origin] (NaN when
        there are no samples)."""
        if not self.t.size:
            return np.full(len(self.names), math.nan)
        k = int(np.argmin(np.abs(self.x - x)))
        return self.values[:, k].copy()

    def peak(self, name: str) -> float | None:
        """Time [s from the origin] of the largest |value| of channel ``name`` (None: not in
        the recording or no samples)."""
        if name not in self.names or not self.t.size:
            return None
        row = np.abs(self.values[self.names.index(name)])
        if not np.isfinite(row).any():
            return None
        return float(self.x[int(np.nanargmax(row))])


class Samples(Protocol):
    """Where a recording's samples come from (a :class:`Ring`, or the recorder's two
    buffers)."""

    def samples(
        self, since: float, until: float, rows: Sequence[int] | None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], float]: ...


def recording_of(
    source: Samples,
    window: Window,
    rows: Sequence[int],
    names: Sequence[str],
    displays: Sequence[Display],
    number: int = 0,
) -> Recording:
    """The samples of channels ``rows`` of ``source`` over ``window``, in display units."""
    t, values, bucket = source.samples(window.start, window.end, rows)
    factors = np.array([d.factor for d in displays]).reshape(-1, 1)
    return Recording(number, tuple(names), tuple(displays), t, values * factors, window, bucket)


class History:
    """The last :data:`HISTORY_LENGTH` complete or frozen recordings, numbered from 1."""

    def __init__(self, length: int = HISTORY_LENGTH) -> None:
        self._kept: deque[Recording] = deque(maxlen=length)
        self._count = 0

    def add(self, recording: Recording) -> Recording:
        """Keep ``recording`` (dropping the oldest); it, numbered."""
        self._count += 1
        numbered = Recording(
            self._count,
            recording.names,
            recording.displays,
            recording.t,
            recording.values,
            recording.window,
            recording.bucket,
        )
        self._kept.append(numbered)
        return numbered

    @property
    def recordings(self) -> tuple[Recording, ...]:
        """The recordings kept, oldest first."""
        return tuple(self._kept)

    def find(self, label: str) -> Recording | None:
        """The recording of ``label`` (None: not kept)."""
        return next((r for r in self._kept if r.label == label), None)

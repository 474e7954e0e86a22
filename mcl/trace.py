"""Trace recorder: what a commissioning engineer plots, per axis and servo cycle; CSV export."""

from __future__ import annotations

import csv
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

from mcl.axis import Axis
from mcl.faults import FaultEvent

Reader = Callable[[], float]
"""Reads one value now (a ground truth, a published signal)."""

FIELDS = (
    "t",
    "model",
    "actual",
    "velocity",
    "following_error",
    "volts",
    "state",
    "lim_pos",
    "lim_neg",
    "ref",
    "index",
    "truth",
)
"""Recorded columns: time [s], model and actual position [u], actual velocity [u/s], following
error [u], analog command [V], state (AxisState value), inputs (0/1), and a ground-truth value
supplied by the plant (e.g. the MuJoCo joint coordinate [m]; NaN when none)."""


class Trace:
    """Records every ``every``-th servo cycle of each axis; attach with ``runtime.observers``.

    Args:
        axes: the axes by name.
        every: decimation in servo cycles (1 = every cycle).
        truth: per axis name, a function returning a ground-truth value (optional).
        signals: further values recorded with each sample, by name (pressures, forces).
        events: the fault changes so far (``machine.faults.events``), shown with the trace.
    """

    def __init__(
        self,
        axes: Mapping[str, Axis],
        every: int = 1,
        truth: Mapping[str, Reader] | None = None,
        signals: Mapping[str, Reader] | None = None,
        events: Callable[[], Sequence[FaultEvent]] | None = None,
    ) -> None:
        if every < 1:
            raise ValueError(f"every must be >= 1 servo cycle, got {every}")
        self.axes = dict(axes)
        self.every = every
        self.truth = dict(truth or {})
        self.signals = dict(signals or {})
        self._events = events
        self.rows: dict[str, list[tuple[float, ...]]] = {name: [] for name in self.axes}
        self.signal_rows: list[tuple[float, ...]] = []
        """Per sample: time [s], then each signal in the order of ``signals``."""
        self._count = 0

    def __call__(self, t: float) -> None:
        """Record the current servo cycle (an observer of :class:`mcl.Runtime`)."""
        self._count += 1
        if self._count % self.every:
            return
        nan = float("nan")
        for name, ax in self.axes.items():
            io = ax.io
            truth = self.truth.get(name)
            self.rows[name].append(
                (
                    t,
                    ax.sp_pos,
                    ax.actual,
                    ax.VEL,
                    ax.following_error,
                    ax.volts,
                    int(ax.state),
                    io.lim_pos,
                    io.lim_neg,
                    io.ref,
                    io.index,
                    truth() if truth is not None else nan,
                )
            )
        if self.signals:
            self.signal_rows.append((t, *(read() for read in self.signals.values())))

    @property
    def events(self) -> list[FaultEvent]:
        """The injected faults set and cleared so far (time, axis, fault, set or cleared)."""
        return list(self._events()) if self._events is not None else []

    def signal(self, name: str) -> list[float]:
        """The recorded values of a published signal."""
        if name not in self.signals:
            raise KeyError(f"no signal {name!r} in the trace; signals: {list(self.signals)}")
        i = list(self.signals).index(name) + 1
        return [float(row[i]) for row in self.signal_rows]

    def column(self, axis: str, field: str) -> list[float]:
        """One recorded column of one axis, e.g. ``trace.column("X", "following_error")``."""
        if axis not in self.rows:
            raise KeyError(f"no axis {axis!r} in the trace; axes: {list(self.rows)}")
        if field not in FIELDS:
            raise KeyError(f"no field {field!r}; fields: {FIELDS}")
        i = FIELDS.index(field)
        return [float(row[i]) for row in self.rows[axis]]

    def clear(self) -> None:
        """Forget what was recorded."""
        for rows in self.rows.values():
            rows.clear()
        self.signal_rows.clear()

    def to_csv(self, path: str | Path) -> Path:
        """Write all axes to one CSV file (columns ``<axis>.<field>``, then the signals, one row
        per sample)."""
        path = Path(path)
        names = list(self.rows)
        signals = self.signal_rows if self.signals else [()] * len(self.rows[names[0]])
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(
                [f"{n}.{field}" for n in names for field in FIELDS] + list(self.signals)
            )
            for *rows, extra in zip(*(self.rows[n] for n in names), signals, strict=True):
                writer.writerow([value for row in rows for value in row] + list(extra[1:]))
        return path

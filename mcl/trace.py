"""Trace recorder: what a commissioning engineer plots, per axis and servo cycle, in a bounded
window; CSV export and streaming to a CSV or NumPy file."""

from __future__ import annotations

__all__ = ["FIELDS", "CsvSink", "NpySink", "Reader", "Trace"]

import csv
import math
from array import array
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, TextIO

import numpy as np
import numpy.typing as npt

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


class CsvSink:
    """Samples appended to a CSV file as text (open it in a spreadsheet; ~1 µs per value)."""

    def __init__(self, path: Path, columns: Sequence[str]) -> None:
        self._file: TextIO = path.open("w", newline="")
        self._writer: Any = csv.writer(self._file)
        self._writer.writerow(columns)

    def write(self, rows: npt.NDArray[np.float64]) -> None:
        """Append rows (one sample each)."""
        self._writer.writerows(rows.tolist())

    def flush(self) -> None:
        """Hand what was written to the operating system."""
        self._file.flush()

    def close(self) -> None:
        """Close the file."""
        self._file.close()


class NpySink:
    """Samples appended to a NumPy ``.npy`` file as binary records, one named float64 field per
    column (``numpy.load(path)["X.actual"]``); the header holds the row count, rewritten on
    every flush, so the file is complete after each :meth:`flush`."""

    _MAGIC = b"\x93NUMPY\x01\x00"

    def __init__(self, path: Path, columns: Sequence[str]) -> None:
        self._descr = [(name, "<f8") for name in columns]
        self._rows = 0
        self._size = len(self._header(10**15, 0))  # room for any row count
        self._file = path.open("wb")
        self._file.write(self._header(0, self._size))

    def _header(self, rows: int, size: int) -> bytes:
        """The format 1.0 header for ``rows`` rows, padded to ``size`` bytes (0: to 64)."""
        text = repr({"descr": self._descr, "fortran_order": False, "shape": (rows,)})
        size = size or -(-(len(self._MAGIC) + 2 + len(text) + 1) // 64) * 64
        text = text.ljust(size - len(self._MAGIC) - 3) + "\n"
        return self._MAGIC + (len(text)).to_bytes(2, "little") + text.encode("latin1")

    def write(self, rows: npt.NDArray[np.float64]) -> None:
        """Append rows (one sample each)."""
        self._file.write(np.ascontiguousarray(rows, dtype="<f8").tobytes())
        self._rows += len(rows)

    def flush(self) -> None:
        """Record the row count in the header and hand the file to the operating system."""
        end = self._file.tell()
        self._file.seek(0)
        self._file.write(self._header(self._rows, self._size))
        self._file.seek(end)
        self._file.flush()

    def close(self) -> None:
        """Flush and close the file."""
        self.flush()
        self._file.close()


class Trace:
    """Records every ``every``-th servo cycle of each axis; attach with ``runtime.observers``.

    Memory is bounded: the trace keeps the last ``keep`` samples (a moving window, 8 bytes per
    value), and with ``stream`` it writes every sample to a file as well, so a long scenario
    keeps everything on disk and only the window in memory.

    Args:
        axes: the axes by name.
        every: decimation in servo cycles (1 = every cycle).
        truth: per axis name, a function returning a ground-truth value (optional).
        signals: further values recorded with each sample, by name (pressures, forces).
        events: the fault changes so far (``machine.faults.events``), shown with the trace.
        keep: samples kept in memory (the window), at least 1.
        stream: a file that receives every sample (the columns of :meth:`to_csv`): ``.csv``
            text, or ``.npy`` binary records (fast: about 20× cheaper per sample than text);
            written in blocks as samples leave the window, completed by :meth:`flush`.
    """

    def __init__(
        self,
        axes: Mapping[str, Axis],
        every: int = 1,
        truth: Mapping[str, Reader] | None = None,
        signals: Mapping[str, Reader] | None = None,
        events: Callable[[], Sequence[FaultEvent]] | None = None,
        keep: int = 60_000,
        stream: str | Path | None = None,
    ) -> None:
        if every < 1:
            raise ValueError(f"every must be >= 1 servo cycle, got {every}")
        if keep < 1:
            raise ValueError(f"keep must be >= 1 sample, got {keep}")
        self.axes = dict(axes)
        self.every = every
        self.keep = keep
        self.truth = dict(truth or {})
        self.signals = dict(signals or {})
        self._events = events
        self._axis_data = {name: array("d") for name in self.axes}
        self._signal_data = array("d")
        self._count = 0
        self._held = 0
        self.samples = 0
        """Samples recorded since the start (or :meth:`clear`), kept or not."""
        self._written = 0
        self.stream = None if stream is None else Path(stream)
        """The file that receives every sample (None: none)."""
        self._sink: CsvSink | NpySink | None = None
        if self.stream is not None:
            if self.stream.suffix not in (".csv", ".npy"):
                raise ValueError(
                    f"stream must be a .csv (text) or .npy (binary) file, got {self.stream.name!r}"
                )
            sink = CsvSink if self.stream.suffix == ".csv" else NpySink
            self._sink = sink(self.stream, self._header())

    def __call__(self, t: float) -> None:
        """Record the current servo cycle (an observer of :class:`mcl.Runtime`)."""
        self._count += 1
        if self._count % self.every:
            return
        nan = math.nan
        truths = self.truth
        for name, ax in self.axes.items():
            io = ax.io
            truth = truths.get(name)
            self._axis_data[name].extend(
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
            self._signal_data.extend((t, *(read() for read in self.signals.values())))
        self.samples += 1
        self._held += 1
        if self._held >= 2 * self.keep:  # amortised: the window moves in blocks of `keep`
            self._trim()

    def _trim(self) -> None:
        """Drop the samples before the window (streaming those not yet written)."""
        drop = self._held - self.keep
        if self._sink is not None:
            first = self.samples - self._held  # number of the oldest sample held
            self._write(self._written - first, drop)
        self._drop(drop)

    def _drop(self, n: int) -> None:
        self._held -= n
        width = len(FIELDS)
        for data in self._axis_data.values():
            del data[: n * width]
        if self.signals:
            del self._signal_data[: n * (len(self.signals) + 1)]

    def _write(self, start: int, stop: int) -> None:
        """Stream the held samples ``start`` to ``stop`` (positions in the window)."""
        if stop <= start:
            return
        axes, signals = self._table(start, stop)
        rows = np.hstack([*axes, signals[:, 1:]]) if self.signals else np.hstack(axes)
        assert self._sink is not None
        self._sink.write(rows)
        self._written += stop - start

    def _table(self, start: int, stop: int) -> tuple[list[npt.NDArray[np.float64]], Any]:
        width = len(FIELDS)
        axes = [
            np.frombuffer(data, dtype=np.float64).reshape(-1, width)[start:stop]
            for data in self._axis_data.values()
        ]
        signals = (
            np.frombuffer(self._signal_data, dtype=np.float64).reshape(-1, len(self.signals) + 1)[
                start:stop
            ]
            if self.signals
            else None
        )
        return axes, signals

    def flush(self) -> None:
        """Write the samples not yet streamed and flush the file (no-op without ``stream``)."""
        if self._sink is None:
            return
        self._write(self._written - (self.samples - self._held), self._held)
        self._sink.flush()

    def close(self) -> None:
        """:meth:`flush` and close the stream (the window stays readable)."""
        self.flush()
        if self._sink is not None:
            self._sink.close()
            self._sink = None

    @property
    def nbytes(self) -> int:
        """Memory held by the recorded values [bytes]."""
        arrays = [*self._axis_data.values(), self._signal_data]
        return sum(a.buffer_info()[1] * a.itemsize for a in arrays)

    @property
    def rows(self) -> dict[str, list[tuple[float, ...]]]:
        """The samples in the window, per axis: one tuple of :data:`FIELDS` per sample."""
        width = len(FIELDS)
        return {
            name: [tuple(data[i : i + width]) for i in range(0, len(data), width)]
            for name, data in self._axis_data.items()
        }

    @property
    def events(self) -> list[FaultEvent]:
        """The injected faults set and cleared so far (time, axis, fault, set or cleared)."""
        return list(self._events()) if self._events is not None else []

    def signal(self, name: str) -> list[float]:
        """The recorded values of a published signal (in the window)."""
        if name not in self.signals:
            raise KeyError(f"no signal {name!r} in the trace; signals: {list(self.signals)}")
        width = len(self.signals) + 1
        i = list(self.signals).index(name) + 1
        return list(self._signal_data[i::width])

    def column(self, axis: str, field: str) -> list[float]:
        """One recorded column of one axis (in the window), e.g.
        ``trace.column("X", "following_error")``."""
        if axis not in self._axis_data:
            raise KeyError(f"no axis {axis!r} in the trace; axes: {list(self._axis_data)}")
        if field not in FIELDS:
            raise KeyError(f"no field {field!r}; fields: {FIELDS}")
        return list(self._axis_data[axis][FIELDS.index(field) :: len(FIELDS)])

    def clear(self) -> None:
        """Forget what was recorded (what was streamed stays in the file); the next sample is
        taken ``every`` servo cycles from now."""
        self.flush()
        self._drop(self._held)
        self.samples = self._written = self._count = 0

    def _header(self) -> list[str]:
        return [f"{n}.{field}" for n in self.axes for field in FIELDS] + list(self.signals)

    def to_csv(self, path: str | Path) -> Path:
        """Write the window of all axes to one CSV file (columns ``<axis>.<field>``, then the
        signals; one row per sample)."""
        path = Path(path)
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(self._header())
            if self.axes:
                axes, signals = self._table(0, self._held)
                rows = np.hstack([*axes, signals[:, 1:]]) if self.signals else np.hstack(axes)
                writer.writerows(rows.tolist())
        return path

"""What a scope makes of a recording: the cursor read-out (values at A and B, B−A, Δt, 1/Δt),
an overlay aligned on it, the plot's points (decimated, peaks kept) and the CSV export."""

from __future__ import annotations

__all__ = [
    "MAX_POINTS",
    "Readout",
    "aligned",
    "decimate",
    "readout",
    "readout_html",
    "recording_csv",
]

import csv
import html
import io
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from viewer.scope.capture import Recording
from viewer.scope.units import Display, format_value
from viewer.sim.recorder import extreme_order

MAX_POINTS = 2000
"""Points per channel a page is sent at most."""


@dataclass(frozen=True)
class Readout:
    """The cursors' read-out of a recording.

    Attributes:
        a: Cursor A [s from the origin].
        b: Cursor B [s from the origin].
        headers: Channel names with units.
        displays: How each channel is shown (its unit and resolution).
        last: Each channel's newest value [display unit].
        at_a: Each channel's value at A.
        at_b: Each channel's value at B.
    """

    a: float
    b: float
    headers: tuple[str, ...]
    displays: tuple[Display, ...]
    last: npt.NDArray[np.float64]
    at_a: npt.NDArray[np.float64]
    at_b: npt.NDArray[np.float64]

    @property
    def dt(self) -> float:
        """B − A [s]."""
        return self.b - self.a

    @property
    def rate(self) -> float:
        """1 / (B − A) [Hz] (inf when A = B)."""
        return 1.0 / self.dt if self.dt else math.inf


def readout(
    recording: Recording, a: float, b: float, titles: Mapping[str, str] | None = None
) -> Readout:
    """The values of every channel of ``recording`` at cursors ``a`` and ``b`` [s] (channels
    named by their ``titles``, by name, where given)."""
    values = recording.values
    last = values[:, -1].copy() if values.shape[1] else np.full(values.shape[0], math.nan)
    return Readout(
        a, b, recording.headers(titles), recording.displays, last, recording.at(a), recording.at(b)
    )


def readout_html(r: Readout) -> str:
    """The read-out table, whole in a 300 px column: per channel a row with its name and unit,
    then a row of its last value and its values at A, at B and B − A (numbers in that unit,
    rounded to its resolution); then the cursors' times, Δt and 1/Δt."""
    number = '<td style="text-align:right;font-family:monospace;white-space:nowrap">'
    name = (
        '<tr style="border-top:1px solid rgba(128,128,128,0.3)">'
        '<td colspan="4" style="overflow-wrap:anywhere;padding-top:2px">'
    )
    rows = "".join(
        f"{name}{html.escape(h)}</td></tr><tr>"
        + "".join(f"{number}{html.escape(format_value(v, d.resolution))}</td>" for v in values)
        + "</tr>"
        for h, d, *values in zip(
            r.headers, r.displays, r.last, r.at_a, r.at_b, r.at_b - r.at_a, strict=True
        )
    )
    part = '<span style="white-space:nowrap">'
    head = "".join(f'<th style="text-align:right">{c}</th>' for c in ("last", "A", "B", "B−A"))
    return (
        '<table style="font-size:0.75em;width:100%;border-collapse:collapse">'
        f"<tr>{head}</tr>{rows}</table>"
        f'<div style="font-size:0.85em">{part}A = {r.a:.4f} s</span>, '
        f"{part}B = {r.b:.4f} s</span>, {part}Δt = {r.dt * 1e3:.3f} ms</span>, "
        f"{part}1/Δt = {_number(r.rate)} Hz</span></div>"
    )


def _number(value: float) -> str:
    """A read-out number without a unit (1/Δt), four significant digits."""
    return format_value(value, 0.0)


def aligned(recording: Recording, overlay: Recording) -> npt.NDArray[np.float64]:
    """The channels of ``overlay`` that ``recording`` has, at the recording's sample times
    (both aligned at their origins; NaN where the overlay has no samples or no such channel):
    one row per channel of ``recording``."""
    x, ox = recording.x, overlay.x
    rows = np.full((len(recording.names), x.size), math.nan)
    if ox.size < 2:
        return rows
    outside = (x < ox[0]) | (x > ox[-1])
    for k, name in enumerate(recording.names):
        if name in overlay.names:
            row = np.interp(x, ox, overlay.values[overlay.names.index(name)])
            row[outside] = math.nan
            rows[k] = row
    return rows


def decimate(
    x: npt.NDArray[np.float64], rows: npt.NDArray[np.float64], max_points: int = MAX_POINTS
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """At most ``max_points`` points per row, keeping each bucket's minimum and maximum (in
    their order in time, NaN ignored) so that no peak is lost; ``(x, rows)`` unchanged when
    short enough."""
    n = x.size
    if n <= max_points:
        return x, rows
    buckets = max_points // 2
    size = -(-n // buckets)
    pad = buckets * size - n
    xs = np.pad(x, (0, pad), mode="edge").reshape(buckets, size)
    vs = np.pad(rows, ((0, 0), (0, pad)), mode="edge").reshape(rows.shape[0], buckets, size)
    first, second = extreme_order(vs)
    pick = np.stack([first, second], axis=2)  # (rows, buckets, 2)
    values = np.take_along_axis(vs, pick, axis=2).reshape(rows.shape[0], 2 * buckets)
    times = np.stack([xs[:, 0], xs[:, -1]], axis=1).reshape(2 * buckets)
    return times, values


def recording_csv(recording: Recording, overlay: Recording | None = None) -> str:
    """The recording as CSV: ``t [s]`` (from its origin, the trigger or start; its header says
    the resolution, ``t [s] (every 2 ms)``), one column per channel (header with units), then
    the overlay's channels at the same times."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    headers = list(recording.headers())
    columns = [recording.values]
    if overlay is not None:
        headers += [f"{h} (#{overlay.number})" for h in recording.headers()]
        columns.append(aligned(recording, overlay))
    table = np.vstack(columns) if columns else np.zeros((0, recording.t.size))
    resolution = recording.resolution
    writer.writerow([f"t [s] ({resolution})" if resolution else "t [s]", *headers])
    for k, x in enumerate(recording.x):
        writer.writerow([f"{x:.6f}", *(_cell(v) for v in table[:, k])])
    return out.getvalue()


def _cell(value: float) -> str:
    return f"{value:.9g}" if math.isfinite(value) else ""

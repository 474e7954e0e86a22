"""Plots of a trace on one time base: position and set point, following error, volts, the
switches and the published signals (cut lengths, pressures, forces), as PNG and as HTML.

``plot(scene.trace, "run")`` writes ``run.png`` and ``run.html``; ``python -m scenes plot
trace.csv`` does the same for a trace written with ``trace.to_csv`` or streamed to a file.
"""

from __future__ import annotations

__all__ = ["SWITCHES", "axes_of", "figure", "frame", "plot", "plot_table", "sweep_figure"]

from mcl.extras import require

require("scenes.tools.plot", "plot")

import html
import io
import re
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from mcl.trace import FIELDS, Trace
from scenes.errors import UserError

SWITCHES = ("lim_neg", "lim_pos", "ref", "index")


def frame(trace: Trace | str | Path) -> pd.DataFrame:
    """A trace as a table: columns ``<axis>.<field>`` and the signals, one row per sample.

    Args:
        trace: a recorded trace, or a ``.csv`` / ``.npy`` file written by one.

    Raises:
        UserError: a missing file, or one that is not a trace (one line: the file, the line
            where known, what is wrong and what a trace file holds).
    """
    if isinstance(trace, Trace):
        columns = [f"{n}.{f}" for n in trace.axes for f in FIELDS]
        data = {c: trace.column(*c.split(".", 1)) for c in columns}
        table = pd.DataFrame(data)
        for name in trace.signals:
            table[name] = trace.signal(name)
        return table
    path = Path(trace)
    expected = "a trace written by scene.trace.to_csv (.csv) or streamed (.csv, .npy)"
    if path.suffix not in (".csv", ".npy"):
        raise UserError.at(str(path), "", f"a {path.suffix or 'suffix-less'} file", expected)
    if not path.is_file():
        raise UserError.at(str(path), "", "no such file", f"{expected}, relative to {Path.cwd()}")
    try:
        table = pd.DataFrame(np.load(path)) if path.suffix == ".npy" else pd.read_csv(path)
    except pd.errors.EmptyDataError:
        raise UserError.at(str(path), "", "empty", expected) from None
    except pd.errors.ParserError as error:
        found = re.search(r"line (\d+)", str(error))
        where = f"{path}:{found.group(1)}" if found else str(path)
        what = re.sub(r"^C error:\s*", "", str(error).split(". ")[-1].strip().rstrip("."))
        raise UserError.at(where, "", what, expected) from None
    except (ValueError, OSError, UnicodeDecodeError) as error:
        what = "not a NumPy .npy file" if path.suffix == ".npy" else f"not readable ({error})"
        raise UserError.at(str(path), "", what, expected) from None
    axes = axes_of(table)
    if not axes:
        raise UserError.at(
            f"{path}:1", "", f"no '<axis>.t' column (columns: {list(table.columns)[:6]})", expected
        )
    for name in axes:
        missing = [f"{name}.{f}" for f in FIELDS if f"{name}.{f}" not in table.columns]
        if missing:
            raise UserError.at(f"{path}:1", "", f"columns {missing} missing", expected)
    for column in table.columns:
        if not pd.api.types.is_numeric_dtype(table[column]):
            values = pd.to_numeric(table[column], errors="coerce")
            row = int(values.isna().to_numpy().argmax())
            at = f"{path}:{row + 2}" if path.suffix == ".csv" else str(path)
            raise UserError.at(
                at, column, f"{table[column].iloc[row]!r} is not a number", "numbers only"
            )
    return table


def axes_of(table: pd.DataFrame) -> list[str]:
    """The axis names of a trace table."""
    return [c[: -len(".t")] for c in table.columns if c.endswith(".t")]


def figure(table: pd.DataFrame, title: str = "") -> plt.Figure:
    """The trace on one time base: one row of plots per quantity, all axes in each."""
    axes = axes_of(table)
    signals = [c for c in table.columns if "." not in c]
    rows = ["position", "following error", "volts", "switches"] + (["signals"] if signals else [])
    heights = [2.0, 1.5, 1.5, 0.25 * len(axes) * len(SWITCHES)] + ([1.5] if signals else [])
    fig, panels = plt.subplots(
        len(rows), 1, sharex=True, figsize=(11, sum(heights) + 1.0), height_ratios=heights
    )
    t = table[f"{axes[0]}.t"]
    ticks: list[tuple[float, str]] = []
    for name in axes:
        p = panels[0].plot(t, table[f"{name}.actual"], label=f"{name} actual")[0]
        panels[0].plot(t, table[f"{name}.model"], "--", color=p.get_color(), label=f"{name} set")
        panels[1].plot(t, table[f"{name}.following_error"], label=name)
        panels[2].plot(t, table[f"{name}.volts"], label=name)
        for k, switch in enumerate(SWITCHES):
            row = k + axes.index(name) * len(SWITCHES)
            panels[3].step(t, table[f"{name}.{switch}"] * 0.8 + row, where="post")
            ticks.append((row + 0.4, f"{name} {switch}"))
    for name in signals:
        panels[4].plot(table[f"{axes[0]}.t"], table[name], label=name)
    for panel, label in zip(panels, rows, strict=True):
        panel.set_ylabel(label)
        panel.grid(True, alpha=0.3)
        if panel is not panels[3]:
            panel.legend(loc="upper right", fontsize="x-small", ncol=4)
    panels[3].set_yticks([y for y, _ in ticks], [name for _, name in ticks], fontsize="x-small")
    panels[-1].set_xlabel("t [s]")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def plot(trace: Trace | str | Path, out: str | Path, title: str = "") -> tuple[Path, Path]:
    """Write the trace as ``<out>.png`` and ``<out>.html`` (the plot as zoomable SVG, with the
    table of its last samples); returns both paths."""
    table = frame(trace)
    fig = figure(table, title)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    png, page = out.with_suffix(".png"), out.with_suffix(".html")
    fig.savefig(png, dpi=110)
    svg = io.StringIO()
    fig.savefig(svg, format="svg")
    plt.close(fig)
    name = html.escape(title or out.stem)
    page.write_text(
        f"<!doctype html><meta charset='utf-8'><title>{name}</title><h1>{name}</h1>"
        f"{svg.getvalue()[svg.getvalue().index('<svg') :]}"
        f"<h2>Last samples</h2>{table.tail(20).to_html(float_format='%.6g')}",
        encoding="utf-8",
    )
    return png, page


def plot_table(
    table: pd.DataFrame,
    x: str,
    ys: list[str],
    out: str | Path,
    title: str = "",
    colour: Sequence[str] = (),
) -> Path:
    """A sweep's metrics against one parameter as ``<out>.png`` (see :func:`sweep_figure`)."""
    fig = sweep_figure(table, x, ys, title, colour)
    path = Path(out).with_suffix(".png")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def sweep_figure(
    table: pd.DataFrame, x: str, ys: list[str], title: str = "", colour: Sequence[str] = ()
) -> plt.Figure:
    """A sweep's metrics against one parameter, one panel per metric, numbers in full on the
    axes (no offset such as +1.1e2).

    Args:
        table: the sweep's table.
        x: the parameter on the horizontal axis.
        ys: the metrics, one panel each.
        title: the figure's title (the scenario, its seed and size).
        colour: the other swept parameters; the points are coloured by the first (a legend for
            up to 10 values, else a colour bar), the title names the rest.
    """
    shade = colour[0] if colour else None
    if len(colour) > 1:
        title += f"\nalso varied: {', '.join(colour[1:])}"
    with plt.rc_context({"axes.formatter.useoffset": False}):
        fig, panels = plt.subplots(
            len(ys), 1, sharex=True, figsize=(8, 2.4 * len(ys) + 1.2), layout="constrained"
        )
        panel_list = list(np.atleast_1d(panels))
        numeric = shade is not None and pd.api.types.is_numeric_dtype(table[shade])
        values = (
            sorted(table[shade].dropna().unique(), key=None if numeric else str) if shade else []
        )
        if len(values) > 10 and not numeric:
            shade, values = None, []  # too many names to tell apart by colour
        for panel, y in zip(panel_list, ys, strict=True):
            if shade is None:
                panel.plot(table[x], table[y], "o", markersize=3)
            elif len(values) <= 10:
                for k, value in enumerate(values):
                    rows = table[table[shade] == value]
                    panel.plot(
                        rows[x],
                        rows[y],
                        "o",
                        markersize=3,
                        color=f"C{k}",
                        label=f"{value:g}" if isinstance(value, float) else str(value),
                    )
            else:
                points = panel.scatter(table[x], table[y], c=table[shade], s=9, cmap="viridis")
            panel.set_ylabel(y)
            panel.grid(True, alpha=0.3)
        if shade is not None and len(values) <= 10:
            panel_list[0].legend(title=shade, fontsize="x-small", loc="best", ncol=5)
        elif shade is not None:
            fig.colorbar(points, ax=panel_list, label=shade)
        panel_list[-1].set_xlabel(x)
        if title:
            fig.suptitle(title, fontsize="medium")
        fig.canvas.draw()  # the tick labels, while the rc settings hold
    return fig

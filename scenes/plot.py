"""Plots of a trace on one time base: position and set point, following error, volts, the
switches and the published signals (cut lengths, pressures, forces), as PNG and as HTML.

``plot(scene.trace, "run")`` writes ``run.png`` and ``run.html``; ``python -m scenes plot
trace.csv`` does the same for a trace written with ``trace.to_csv`` or streamed to a file.
"""

from __future__ import annotations

import html
import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from mcl.trace import FIELDS, Trace

SWITCHES = ("lim_neg", "lim_pos", "ref", "index")


def frame(trace: Trace | str | Path) -> pd.DataFrame:
    """A trace as a table: columns ``<axis>.<field>`` and the signals, one row per sample.

    Args:
        trace: a recorded trace, or a ``.csv`` / ``.npy`` file written by one.

    Raises:
        ValueError: a file that is not a trace (the message names the missing columns).
    """
    if isinstance(trace, Trace):
        columns = [f"{n}.{f}" for n in trace.axes for f in FIELDS]
        data = {c: trace.column(*c.split(".", 1)) for c in columns}
        table = pd.DataFrame(data)
        for name in trace.signals:
            table[name] = trace.signal(name)
        return table
    path = Path(trace)
    table = pd.DataFrame(np.load(path)) if path.suffix == ".npy" else pd.read_csv(path)
    if not any(c.endswith(".t") for c in table.columns):
        raise ValueError(
            f"{path}: not a trace (no '<axis>.t' column; columns: {list(table.columns)[:8]})"
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


def plot_table(table: pd.DataFrame, x: str, ys: list[str], out: str | Path) -> Path:
    """A sweep's metrics against one parameter (one scatter per metric) as ``<out>.png``."""
    fig, panels = plt.subplots(len(ys), 1, sharex=True, figsize=(8, 2.4 * len(ys) + 0.6))
    for panel, y in zip(np.atleast_1d(panels), ys, strict=True):
        panel.plot(table[x], table[y], "o", markersize=3)
        panel.set_ylabel(y)
        panel.grid(True, alpha=0.3)
    np.atleast_1d(panels)[-1].set_xlabel(x)
    fig.tight_layout()
    path = Path(out).with_suffix(".png")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

"""The cam view of a page: the profile of the first cammed axis' table over one period (slave
position, velocity ds/dm and acceleration d²s/dm², each in its own track of the plot's height,
as the scope's stacked tracks draw them) with the operating point, the slave's set point and
actual position moving along it, and a line of the table's ID, name, laws, InSync, period,
offsets and scalings. Hidden while no axis is cammed
(:attr:`viewer.sim.snapshot.Snapshot.cams`)."""

from __future__ import annotations

__all__ = [
    "COLORS",
    "POINT_COLORS",
    "CamPanel",
    "info_html",
    "plot_data",
    "plot_style",
    "value_range",
]

import html
import itertools
import math
from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext

import numpy as np
import numpy.typing as npt
import viser
import viser.uplot

import mcl
from viewer.scope.tracks import stacked_layout
from viewer.scope.units import Display
from viewer.serving.retire import retire
from viewer.sim.cam_view import CamView
from viewer.sim.snapshot import Snapshot

COLORS = ("#1f77b4", "#2ca02c", "#9467bd")
"""Position, velocity, acceleration (their traces)."""

POINT_COLORS = {"operating point": "#d62728", "set point": "#000000", "actual": "#ff7f0e"}
"""The markers on the position trace."""


def info_html(view: CamView, others: tuple[str, ...]) -> str:
    """The line under the plot: table, laws (runs of the same law counted, the first 12 runs),
    InSync, period, offsets, scalings."""
    p = view.profile
    name = f" “{html.escape(view.name)}”" if view.name else ""
    runs = [(law, len(list(group))) for law, group in itertools.groupby(p.laws)]
    laws = ", ".join(html.escape(law) + (f" ×{n}" if n > 1 else "") for law, n in runs[:12])
    laws += ", …" if len(runs) > 12 else ""
    sync = "InSync" if view.in_sync else ("blending in" if view.coupled else "waiting")
    also = f"<br>also cammed: {html.escape(', '.join(others))}" if others else ""
    return (
        f'<div data-cam="info" style="font-size:0.75em">'
        f"<b>{html.escape(view.slave)}</b> cammed to <b>{html.escape(view.master or '?')}</b>, "
        f"table {view.table_id}{name}: {sync}; "
        f"{'periodic' if p.periodic else 'not periodic'}, period {p.period:g} "
        f"{html.escape(view.master_unit)}, rise {p.rise:g} {html.escape(view.slave_unit)}<br>"
        f"laws: {laws}<br>"
        f"master {view.table_master:.4g} (period {view.cycle}), table {view.table_slave:.4g}, "
        f"set point {view.set_slave:.4g}, actual {view.actual_slave:.4g}<br>"
        f"MasterOffset {view.master_offset:g}, MasterScaling {view.master_scaling:g}, "
        f"SlaveOffset {view.slave_offset:g}, SlaveScaling {view.slave_scaling:g}, "
        f"phase shift {view.phase_shift:g}{also}</div>"
    )


def plot_data(view: CamView) -> tuple[npt.NDArray[np.float64], ...]:
    """x (table master), position, velocity, acceleration, then one marker row per point of
    :data:`POINT_COLORS` (NaN but at the operating point's master position)."""
    p = view.profile
    markers = []
    at = -1
    if math.isfinite(view.table_master):
        at = int(np.argmin(np.abs(p.master - view.table_master)))
    for value in (view.table_slave, view.set_slave, view.actual_slave):
        row = np.full(p.master.size, math.nan)
        if at >= 0:
            row[at] = value
        markers.append(row)
    return (p.master, p.slave, p.velocity, p.acceleration, *markers)


def value_range(values: npt.NDArray[np.float64], margin: float = 0.05) -> tuple[float, float]:
    """A y range holding ``values`` with ``margin`` of its span on either side; a flat trace
    gets a span of a tenth of its size (or 1 at 0)."""
    low, high = float(np.min(values)), float(np.max(values))
    span = high - low
    if span <= 1e-12 * max(abs(low), abs(high), 1.0):
        span = 0.1 * max(abs(low), abs(high)) or 1.0
        middle = 0.5 * (low + high)
        low, high = middle - 0.5 * span, middle + 0.5 * span
    return low - margin * span, high + margin * span


def plot_style(
    view: CamView,
) -> tuple[
    tuple[viser.uplot.Series, ...], tuple[viser.uplot.Axis, ...], dict[str, viser.uplot.Scale]
]:
    """Series, axes and scales of the plot: the three traces stacked in tracks of the plot's
    height (position on top), one y axis labelling each track's top value (its unit in the
    legend), so that the plot keeps the chart's width
    (:func:`~viewer.scope.tracks.stacked_layout`); fixed ranges from the profile (the master
    over one period, each trace with a margin), so that the markers' rows, NaN but at the
    operating point, leave the scales alone."""
    su, mu = view.slave_unit, view.master_unit
    p = view.profile
    units = (su, f"{su}/{mu}", f"{su}/{mu}²")
    labels = (f"slave [{su}]", f"ds/dm [{units[1]}]", f"d²s/dm² [{units[2]}]")
    traces = (p.slave, p.velocity, p.acceleration)
    displays = [Display("-", 1.0, 0.0)] * len(traces)  # the units are in the legend
    placed = stacked_layout(displays, [value_range(t) for t in traces], COLORS)
    series = [viser.uplot.Series(label=f"master [{mu}] (table)")]
    axis = placed.axes[0]
    axis["scale"] = "y0"
    axes = [viser.uplot.Axis(label=series[0]["label"]), axis]
    x_range = (float(p.master[0]), float(p.master[-1]))
    scales: dict[str, viser.uplot.Scale] = {
        "x": viser.uplot.Scale(time=False, auto=False, range=x_range)
    }
    for k, (label, color, key) in enumerate(zip(labels, COLORS, placed.scales, strict=True)):
        series.append(viser.uplot.Series(label=label, stroke=color, width=1.5, scale=f"y{k}"))
        scales[f"y{k}"] = viser.uplot.Scale(auto=False, range=placed.ranges[key])
    for label, color in POINT_COLORS.items():
        series.append(
            viser.uplot.Series(
                label=label,
                stroke=color,
                width=1.0,
                scale="y0",
                points={"show": True, "size": 9.0, "fill": color, "stroke": color},
            )
        )
    return tuple(series), tuple(axes), scales


class CamPanel:
    """The cam view in a page's GUI (``gui``: the page's ``client.gui``, inside its folder;
    ``atomic``: groups the plot's updates into one message, ``client.atomic``: a page that
    got a new profile's series before its data would draw series without data and fail)."""

    def __init__(
        self,
        gui: viser.GuiApi,
        folder: viser.GuiFolderHandle,
        atomic: Callable[[], AbstractContextManager[None]] = nullcontext,
    ) -> None:
        self._folder, self._atomic = folder, atomic
        with folder:
            self._info = gui.add_html("")
            self.plot = gui.add_uplot(
                data=(np.zeros(2), np.zeros(2)),
                series=(viser.uplot.Series(label="master"), viser.uplot.Series(label="")),
                scales={"x": viser.uplot.Scale(time=False, auto=True)},
                legend={"live": False},
                aspect=1.9,
            )
        self._shown = ""
        self._profile: mcl.CamProfile | None = None
        self._point: tuple[float, ...] = ()
        folder.visible = False

    def update(self, snapshot: Snapshot) -> None:
        """Show ``snapshot``'s first cammed axis (sends only what changed); hidden without."""
        views = snapshot.cams
        if not views:
            if self._folder.visible:
                self._folder.visible = False
                self._profile = None
            return
        view = views[0]
        if not self._folder.visible:
            self._folder.visible = True
        content = info_html(view, tuple(v.slave for v in views[1:]))
        if content != self._shown:
            self._shown = self._info.content = content
        point = (view.table_master, view.table_slave, view.set_slave, view.actual_slave)
        profile = view.profile is not self._profile
        if not profile and point == self._point:
            return
        with self._atomic():  # a new profile's series and its data in one message
            if profile:
                self._profile = view.profile
                series, axes, scales = plot_style(view)
                self.plot.series, self.plot.axes, self.plot.scales = series, axes, scales
            self._point = point
            self.plot.data = plot_data(view)

    def remove(self) -> None:
        """Remove the view from the page."""
        retire([self._info, self.plot])

"""The cam view in headless Chromium (1400×1000) on the running rotary cutter: for the 300 mm
table and, after the length change on the fly, the 900 mm one, the page's uPlot chart draws the
slave's position, velocity and acceleration over one period on finite scales, with the
operating point, the set point and the actual position as markers on the position trace; the
line under it shows the actual position beside the set point, both in the table's period. At
1280×800 the chart's plotting area takes most of its width."""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import numpy as np
import pytest

from tests.viewer.test_browser import browser, wait_for
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the Chromium fixture, shared with the viewer's browser tests

SHOWN = """() => ({
    info: document.querySelector('[data-cam="info"]')?.innerText ?? "",
    charts: Object.values(window.__viserTestpoints?.uplots ?? {}).map((u) => ({
        labels: u.chart.series.map((s) => s.label),
        drawn: u.chart.series.map((s) => Boolean(s._paths && s._paths.stroke)),
        scales: Object.fromEntries(
            Object.entries(u.chart.scales).map(([k, s]) => [k, [s.min ?? null, s.max ?? null]])),
        data: u.chart.data.map((d) => Array.from(d)),
    })),
})"""
"""At one instant: the cam view's line, and every uPlot chart of the page as drawn: its
series' labels, whether uPlot drew a path for each, its scales' ranges and its data (via
viser's test points)."""
MARKERS = ("operating point", "set point", "actual")


@pytest.fixture(scope="module")
def page(browser: Browser) -> Iterator[Page]:
    """A page of the rotary cutter's viewer, which runs its demo."""
    with Viewer("rotary_cutter", port=0, demo=True) as viewer:
        context = browser.new_context(viewport={"width": 1400, "height": 1000})
        p = context.new_page()
        try:
            p.goto(viewer.url)
            yield p
        finally:
            context.close()


def cam_view(page: Page, length: float) -> tuple[dict[str, Any], str] | None:
    """The cam view's chart and line once they show the ``length`` mm table, else None."""
    shown = page.evaluate(SHOWN)
    if f"rotary knife {length:g} mm" not in shown["info"]:
        return None
    for chart in shown["charts"]:
        x = chart["data"][0] if "slave [deg]" in chart["labels"] else []
        if x and x[-1] == pytest.approx(length) and all(chart["drawn"][1:]):
            return chart, shown["info"]
    return None


@pytest.mark.parametrize("length", [300.0, 900.0])
def test_the_cam_view_draws_the_running_table_with_its_markers(page: Page, length: float) -> None:
    p = page
    seen: list[tuple[dict[str, Any], str]] = []

    def shown() -> bool:
        view = cam_view(p, length)
        seen.extend([view] if view is not None else [])
        return bool(seen)

    wait_for(shown, 120.0, f"the {length:g} mm table drawn")
    chart, info = seen[0]
    labels = chart["labels"]
    _, *rows = (np.array(d, dtype=float) for d in chart["data"])
    slave = rows[0]
    assert chart["scales"]["x"] == pytest.approx([0.0, length])
    for k, trace in enumerate(rows[:3]):  # position, ds/dm, d²s/dm²: drawn within their scale
        low, high = chart["scales"][f"y{k}"]
        assert math.isfinite(low) and math.isfinite(high), (k, low, high)
        assert np.isfinite(trace).all() and low <= trace.min() <= trace.max() <= high
    assert slave[0] == pytest.approx(0.0) and slave[-1] == pytest.approx(360.0)
    at = set()
    for name in MARKERS:  # one point each, on the position trace at the operating point
        row = rows[labels.index(name) - 1]
        finite = np.flatnonzero(np.isfinite(row))
        assert finite.size == 1, (name, finite)
        at.add(int(finite[0]))
        assert row[finite[0]] == pytest.approx(slave[finite[0]], abs=1.0), name
    assert len(at) == 1 and all(chart["drawn"][labels.index(n)] for n in MARKERS)
    found = re.search(r"set point (-?[\d.e+-]+), actual (-?[\d.e+-]+)", info)
    assert found, info
    set_point, actual = float(found[1]), float(found[2])
    assert 0.0 <= set_point <= 360.0 and abs(actual - set_point) < 1.0, info


PLOT = """() => Object.values(window.__viserTestpoints?.uplots ?? {}).map((u) => ({
    labels: u.chart.series.map((s) => s.label),
    width: u.chart.width,
    plot: u.chart.bbox.width / devicePixelRatio,
}))"""
"""Every uPlot chart of the page: its series' labels, its width and its plotting area's width
[CSS px]."""


def test_the_cam_chart_gives_its_plot_most_of_its_width_at_1280x800(browser: Browser) -> None:
    with Viewer("rotary_cutter", port=0, demo=True) as viewer:
        context = browser.new_context(viewport={"width": 1280, "height": 800})
        page = context.new_page()
        try:
            page.goto(viewer.url)
            found: list[dict[str, Any]] = []

            def cam_chart() -> bool:
                charts = page.evaluate(PLOT)
                found[:] = [c for c in charts if "slave [deg]" in c["labels"] and c["width"] > 0]
                return bool(found)

            wait_for(cam_chart, 120.0, "the cam view's chart")
            chart = found[0]
            assert chart["plot"] >= 0.6 * chart["width"], chart
        finally:
            context.close()

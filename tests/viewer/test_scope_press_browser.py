"""The press' scope at 1280×800 in headless Chromium while its demo runs: the legend names the
published signals by their labels with their units (``pressure A [bar]``, not ``pressure_A``),
and over a recording of a press cycle every channel's drawn trace spans a readable part of the
plot's height, each unit on a y axis of its own or in a track of its own labelled by one y
axis, each track at least :data:`~viewer.scope.tracks.MIN_TRACK` high (read from the page's
uPlot chart)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

import scenes
from tests.viewer.test_browser import browser, wait_for
from tests.viewer.test_scope_browser import new_page
from viewer.scope.tracks import MIN_TRACK
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]

SPANS = """() => Object.values(window.__viserTestpoints?.uplots ?? {}).map((u) => {
    const c = u.chart, height = c.bbox.height / devicePixelRatio;
    return {
        height: height,
        axes: c.axes.slice(1).filter((a) => a.show !== false).map((a) => a.scale),
        series: c.series.slice(1).map((s, i) => {
            const ys = c.data[i + 1];
            let low = Infinity, high = -Infinity;
            for (const y of ys) {
                if (y === null || !Number.isFinite(y)) continue;
                const at = c.valToPos(y, s.scale);
                low = Math.min(low, at);
                high = Math.max(high, at);
            }
            return {label: s.label, scale: s.scale, span: high > low ? high - low : 0};
        }),
    };
})"""
"""Per series of the page's chart: its label, its scale and the height [CSS px] its drawn
values span; the plotting area's height and the scales that have a y axis shown."""

LABELS = {
    "force": "load cell force [kN]",
    "pressure_A": "pressure A [bar]",
    "pressure_B": "pressure B [bar]",
    "R position": "R position [mm]",
    "R set point": "R set point [mm]",
}
"""What the legend calls each of the press' scope channels."""


@pytest.fixture(scope="module")
def press(browser: Browser) -> Iterator[tuple[Page, Viewer]]:
    """A 1280×800 page of the press' viewer, which runs its demo."""
    with Viewer("press", port=0, demo=True) as viewer:
        page, _ = new_page(browser, viewer, 1280, 800)
        try:
            yield page, viewer
        finally:
            page.context.close()


def chart(page: Page) -> dict[str, Any]:
    charts: list[dict[str, Any]] = page.evaluate(SPANS)
    return charts[0] if charts else {"series": [], "axes": [], "height": 0.0}


def test_the_legend_names_the_press_signals_by_their_labels(press: tuple[Page, Viewer]) -> None:
    page, _ = press
    assert tuple(LABELS) == scenes.definition("press").scope.channels
    wanted = list(LABELS.values())

    def shown() -> bool:
        return [s["label"] for s in chart(page)["series"]][: len(wanted)] == wanted

    wait_for(shown, 60.0, "the labels in the scope's legend")


def test_every_press_channel_spans_a_readable_part_of_the_plot(
    press: tuple[Page, Viewer],
) -> None:
    page, viewer = press
    session = viewer.session
    wait_for(lambda: session.snapshot.demo.runs >= 1, 60.0, "the press demo running")
    since = session.snapshot.time
    wait_for(lambda: session.snapshot.time > since + 12.0, 180.0, "a full 10 s recording")
    drawn = chart(page)
    if os.environ.get("SCOPE_SCREENSHOTS"):
        folder = Path(os.environ["SCOPE_SCREENSHOTS"])
        page.screenshot(path=str(folder / "scope-press.png"), timeout=120_000)
    traces = drawn["series"][: len(LABELS)]
    assert len(traces) == len(LABELS) and drawn["height"] > 0.0, drawn
    one_axis = len(drawn["axes"]) == 1  # an axis labelling every unit's track
    for trace in traces:
        assert trace["span"] >= 0.2 * drawn["height"], (trace, drawn["height"])
        assert one_axis or trace["scale"] in drawn["axes"], (trace, drawn["axes"])
    tracks = {trace["scale"] for trace in traces}  # kN, bar, mm: a track each at 1280×800
    assert drawn["height"] >= len(tracks) * MIN_TRACK - 0.5, (len(tracks), drawn["height"])
    for scale in tracks:  # each track's traces fill most of its height, not a 17 px strip
        tallest = max(t["span"] for t in traces if t["scale"] == scale)
        assert tallest >= 0.75 * MIN_TRACK, (scale, traces)

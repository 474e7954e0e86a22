"""The scope of eight channels at 1280×800 in headless Chromium: on y axes shared by unit and
in stacked tracks, every channel drawn over at least 60 % of the plot's width and inside its
y range (the series and scales read from the page's uPlot chart); a machine chosen on the page
opens the scope on its own channels and runs its demo, Repeat demo on."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

import scenes
from tests.viewer.test_browser import browser, choose_scene, take_control, wait_for
from tests.viewer.test_scope_browser import choose, new_page
from viewer.scope.panel import PageScope
from viewer.scope.tracks import MIN_TRACK, SHARED, STACKED
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]

EIGHT = (
    "X position",
    "X set point",
    "X velocity",
    "X following error",
    "X command",
    "Y following error",
    "Z following error",
    "X error",
)
"""Eight channels in five units (mm, mm/s, µm, V, 0/1)."""

DRAWN = """() => Object.values(window.__viserTestpoints?.uplots ?? {}).map((u) => {
    const c = u.chart, xs = c.data[0], plot = c.bbox.width / devicePixelRatio;
    return {
        width: c.width,
        plot: plot,
        height: c.bbox.height / devicePixelRatio,
        series: c.series.slice(1).map((s, i) => {
            const ys = c.data[i + 1], sc = c.scales[s.scale];
            let first = null, last = null, inside = 0, finite = 0;
            for (let k = 0; k < xs.length; k++) {
                if (ys[k] === null || !Number.isFinite(ys[k])) continue;
                finite++;
                if (ys[k] >= sc.min && ys[k] <= sc.max) inside++;
                if (first === null) first = k;
                last = k;
            }
            const span = first === null ? 0
                : c.valToPos(xs[last], "x") - c.valToPos(xs[first], "x");
            return {label: s.label, span: span, finite: finite, inside: inside};
        }),
    };
})"""
"""Per series of the page's chart: the width [CSS px] its points span and how many of its
points lie inside its scale's range; the chart's width and its plotting area's width and
height."""


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """The gantry viewer on a free loopback port, without demo."""
    with Viewer("gantry", port=0, demo=False) as v:
        yield v


def drawn(page: Page) -> dict[str, Any]:
    charts: list[dict[str, Any]] = page.evaluate(DRAWN)
    return charts[0] if charts else {"series": []}


def scope_page(browser: Browser, viewer: Viewer) -> tuple[Page, PageScope]:
    """A 1280×800 page and its scope."""
    page, mine = new_page(browser, viewer, 1280, 800)
    assert mine.scope is not None
    return page, mine.scope


@pytest.mark.parametrize("layout", [SHARED, STACKED])
def test_eight_channels_are_each_drawn_over_most_of_the_plot_at_1280x800(
    browser: Browser, viewer: Viewer, layout: str
) -> None:
    page, scope = scope_page(browser, viewer)
    try:
        scope.show_channels(EIGHT)
        scope.set_layout(layout)
        assert scope.channels == list(EIGHT)
        page.get_by_role("tab", name="Trigger").click()
        choose(page, "Recording", "2 s")  # not the gantry's 20 s
        wait_for(lambda: scope.acquisition.length == 2.0, 10.0, "the 2 s recording")
        since = viewer.session.snapshot.time  # the new length starts a new recording
        wait_for(lambda: viewer.session.snapshot.time > since + 2.5, 30.0, "a full recording")

        def complete() -> bool:
            labels = [s["label"] for s in drawn(page)["series"]]
            return all(any(label.startswith(n + " [") for label in labels) for n in EIGHT)

        wait_for(complete, 20.0, "eight channels on the page")
        chart = drawn(page)
        if os.environ.get("SCOPE_SCREENSHOTS"):
            folder = Path(os.environ["SCOPE_SCREENSHOTS"])
            page.screenshot(
                path=str(folder / f"scope-eight-{layout.split()[0]}.png"), timeout=120_000
            )
        traces = [s for s in chart["series"] if s["label"].split(" [")[0] in EIGHT]
        assert len(traces) == len(EIGHT)
        tracks = len(EIGHT) if layout == STACKED else 5  # four units' tracks, the digital's
        assert chart["height"] >= tracks * MIN_TRACK - 0.5, chart["height"]  # the plot grew
        for trace in traces:
            assert trace["span"] >= 0.6 * chart["width"], (trace, chart["width"])
            assert trace["inside"] >= 0.95 * trace["finite"] > 0, trace
    finally:
        page.context.close()


SERIES = """() => Object.values(window.__viserTestpoints?.uplots ?? {}).map(
    (u) => u.chart.series.map((s) => s.label))"""
"""The series labels of the page's charts."""


def test_a_machine_chosen_on_the_page_runs_its_demo_with_its_own_scope(browser: Browser) -> None:
    with Viewer("gantry", port=0, demo=True) as viewer:
        page, scope = scope_page(browser, viewer)
        try:
            assert viewer.session.repeat_demo
            gantry = scenes.definition("gantry").scope
            assert scope.channels == list(gantry.channels)
            take_control(page, viewer)
            choose_scene(page, viewer, "press")
            press = scenes.definition("press").scope
            signals = scenes.definition("press").signals  # named by their labels
            wanted = [f"{getattr(signals.get(n), 'label', '') or n} [" for n in press.channels]

            def shown() -> bool:
                charts: list[list[str]] = page.evaluate(SERIES)
                labels = charts[0][1 : 1 + len(wanted)] if charts else []
                return len(labels) == len(wanted) and all(
                    label.startswith(w) for label, w in zip(labels, wanted, strict=True)
                )

            wait_for(shown, 60.0, "the press's scope channels on the page")
            session = viewer.session
            wait_for(lambda: session.snapshot.demo.running, 30.0, "the press demo running")
            assert session.repeat_demo and session.scene_name == "press"
            mine = [p for p in viewer.app.pages.all() if p.scope is not None]
            assert mine and mine[0].scope is not None
            assert mine[0].scope.acquisition.length >= press.seconds
        finally:
            page.context.close()

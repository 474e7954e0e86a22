"""The page scope in headless Chromium (1400×1000): each page's scope in its own wide panel
below the overview; a 400 mm/s move of the gantry's X with its following error on a µm axis and
the "A to peak" cursor; two recordings overlaid and exported; a watching page's scope settings
leave the operator's scope and plot alone."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pytest

from plc.operator.hmi import Move
from tests.viewer.test_browser import browser, wait_for
from viewer.pages.layout import COLUMN_WIDTH
from viewer.pages.layout import Page as ViewerPage
from viewer.scope.panel import PageScope
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the fixture, shared with the viewer's browser tests

CHART = """() => Object.values(window.__viserTestpoints?.uplots ?? {}).map((u) => ({
    series: u.chart.series.map((s) => s.label),
    dashed: u.chart.series.map((s) => Boolean(s.dash && s.dash.length)),
    axes: u.chart.axes.map((a) => a.label ?? null),
    points: u.chart.data[0].length,
    last: u.chart.data.length > 1 ? Array.from(u.chart.data[1].slice(-50)) : [],
    width: u.chart.width,
}))"""
"""What the page's uPlot chart shows (via viser's test points)."""


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """The gantry viewer on a free loopback port, without demo, X powered."""
    with Viewer("gantry", port=0, demo=False) as v:
        v.session.requests("X").set_power(True)
        wait_for(lambda: v.session.snapshot.axes["X"].powered, 10.0, "X powered")
        yield v


@pytest.fixture(scope="module")
def operator(browser: Browser, viewer: Viewer) -> Iterator[tuple[Page, ViewerPage]]:
    """The operator's page, shared by the tests of this module (in file order)."""
    page, mine = open_page(browser, viewer)
    try:
        yield page, mine
    finally:
        page.context.close()


def new_page(
    browser: Browser, viewer: Viewer, width: int = 1400, height: int = 1000
) -> tuple[Page, ViewerPage]:
    """A new page (its own browser context) of ``width`` × ``height`` and the viewer's page
    object of it, once its scope exists."""
    before = {p.client.client_id for p in viewer.app.pages.all()}
    page = browser.new_context(viewport={"width": width, "height": height}).new_page()
    page.goto(viewer.url)
    page.get_by_text("Acquisition").first.wait_for(timeout=60_000)

    def new() -> ViewerPage | None:
        fresh = [p for p in viewer.app.pages.all() if p.client.client_id not in before]
        return fresh[0] if fresh and fresh[0].scope is not None else None

    wait_for(lambda: new() is not None, 10.0, "the page's scope")
    mine = new()
    assert mine is not None and mine.scope is not None
    return page, mine


def open_page(browser: Browser, viewer: Viewer) -> tuple[Page, ViewerPage]:
    """A new page and the viewer's page object of it, with its scope drawn."""
    page, mine = new_page(browser, viewer)
    wait_for(lambda: bool(chart(page)) and chart(page)[0]["points"] > 2, 30.0, "a plot")
    return page, mine


def chart(page: Page) -> list[dict[str, Any]]:
    result: list[dict[str, Any]] = page.evaluate(CHART)
    return result


def scope_of(page: ViewerPage) -> PageScope:
    assert page.scope is not None
    return page.scope


def choose(page: Page, label: str, option: str) -> None:
    """Pick ``option`` in the dropdown ``label`` of the page."""
    page.get_by_role("combobox", name=label, exact=True).click()
    page.get_by_role("option", name=option, exact=True).click()


def test_the_peak_following_error_of_a_400_mm_s_move_with_the_a_to_peak_cursor(
    operator: tuple[Page, ViewerPage], viewer: Viewer
) -> None:
    page, mine = operator
    scope = scope_of(mine)
    width = chart(page)[0]["width"]
    assert 0.85 * COLUMN_WIDTH <= width <= COLUMN_WIDTH  # a wide plot in the left column
    page.get_by_role("tab", name="Trigger").click()
    choose(page, "Recording", "2 s")  # not the gantry's 20 s
    wait_for(lambda: scope.acquisition.length == 2.0, 10.0, "the 2 s recording")
    page.get_by_role("button", name="Single", exact=True).click()
    wait_for(lambda: scope.acquisition.single, 10.0, "Single to arrive")
    viewer.session.requests("X").move(Move("relative", 150.0, 400.0, 4000.0))
    wait_for(lambda: not scope.acquisition.running, 30.0, "the recording to complete")
    recording = scope.recording
    wait_for(lambda: "[µm]" in chart(page)[0]["axes"], 15.0, "the µm axis")
    assert chart(page)[0]["series"][1] == "X following error [µm]"
    assert "--" not in page.locator(".u-legend").first.inner_text()  # no empty values
    page.get_by_role("tab", name="Cursors").click()
    page.get_by_role("button", name="A to peak", exact=True).click()
    peak = recording.values[0][np.argmax(np.abs(recording.values[0]))]
    wait_for(lambda: scope.cursors["A"] != 0.0, 10.0, "the cursor to move")
    header = f"A = {scope.cursors['A']:.4f} s"  # the read-out of the new cursor, not the old
    wait_for(lambda: page.get_by_text(header).count() > 0, 15.0, "the read-out at A")
    cell = page.locator("td", has_text="X following error [µm]").first  # name and unit
    value = cell.locator("xpath=../following-sibling::tr[1]/td[2]")  # the value at A
    assert abs(float(value.inner_text().replace("−", "-")) - peak) < 1.0
    t, values = viewer.session.recorder.series()
    names = [c.name for c in viewer.session.recorder.channels]
    fe = values[names.index("X following error")]
    inside = (t >= recording.t[0]) & (t <= recording.t[-1])
    assert abs(abs(peak) - 1e3 * np.max(np.abs(fe[inside]))) < 1.0  # the session's own


def test_two_recordings_overlay_and_the_csv_carries_both(
    operator: tuple[Page, ViewerPage], viewer: Viewer
) -> None:
    page, mine = operator
    scope = scope_of(mine)
    session = viewer.session
    for distance in (-60.0, 60.0):
        scope.capture(["X following error", "X position"], session.snapshot.time, 0.6)
        session.requests("X").move(Move("relative", distance, 400.0, 4000.0))
        wait_for(lambda: not scope.acquisition.running, 20.0, "a recording")
    first = scope.history.recordings[0]
    page.get_by_role("tab", name="History").click()
    choose(page, "Overlay", first.label)
    wait_for(lambda: scope.overlay is first, 10.0, "the overlay choice")
    wait_for(lambda: any(chart(page)[0]["dashed"]), 15.0, "the dashed overlay")
    shown = chart(page)[0]
    assert f"X following error [µm] #{first.number}" in shown["series"]
    with page.expect_download(timeout=15_000) as info:
        page.get_by_role("button", name="Export CSV", exact=True).click()
    header, *lines = Path(info.value.path()).read_text().splitlines()
    assert header.split(",")[1:] == [
        "X following error [µm]",
        "X position [mm]",
        f"X following error [µm] (#{first.number})",
        f"X position [mm] (#{first.number})",
    ]
    assert len(lines) == scope.recording.t.size
    choose(page, "Overlay", "none")
    # the overlay's rows leave the plot and the read-out first, so the buttons below them
    # stand still when Run is clicked
    wait_for(lambda: not any(chart(page)[0]["dashed"]), 15.0, "the overlay gone")
    page.get_by_role("button", name="Run", exact=True).click()
    acquisition = scope.acquisition
    wait_for(lambda: acquisition.running and scope.overlay is None, 10.0, "Run")
    assert not acquisition.single, "Single was pressed, not Run"


def test_a_watching_page_changes_only_its_own_scope(
    browser: Browser, viewer: Viewer, operator: tuple[Page, ViewerPage]
) -> None:
    page, operators = operator
    watcher, watchers = open_page(browser, viewer)
    try:
        mine, theirs = scope_of(operators), scope_of(watchers)
        settings = (tuple(mine.channels), mine.acquisition.length, mine.acquisition.trigger)
        assert mine.acquisition.running
        choose(watcher, "Ch 1", "Y position")
        watcher.get_by_role("tab", name="Trigger").click()
        choose(watcher, "Recording", "10 s")
        watcher.get_by_role("button", name="Freeze", exact=True).click()
        wait_for(lambda: not theirs.acquisition.running, 10.0, "the watcher's freeze")
        assert theirs.channels[0] == "Y position" and theirs.acquisition.length == 10.0
        assert (tuple(mine.channels), mine.acquisition.length, mine.acquisition.trigger) == settings
        assert mine.acquisition.running
        wait_for(lambda: chart(watcher)[0]["series"][1] == "Y position [mm]", 15.0, "Y")
        before = chart(page)[0]
        assert before["series"][1] == "X following error [µm]"
        viewer.session.requests("X").move(Move("relative", 20.0, 400.0, 4000.0))
        time.sleep(1.0)
        after = chart(page)[0]
        assert after["series"][1] == "X following error [µm]"
        assert after["last"] != before["last"]  # the operator's plot runs on
    finally:
        watcher.context.close()

"""The overview and the axis panel in headless Chromium (1400×1000): after an encoder wire
break on X every value of X stays visible, in the same place and of the same width, and keeps
updating; the error history and the results table stay inside the panel.

A viser server of the test's own shows the overview in a left panel and X's panel in the main
panel, fed from a gantry session stepped by the test (no simulation thread)."""

from __future__ import annotations

import dataclasses
import socket
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest
import viser

import mcl.faults
from plc.operator.hmi import Move
from tests.viewer.test_browser import browser
from viewer.pages.overview import Overview
from viewer.pages.panels import axis_panel_html, events_html, results_html
from viewer.sim.session import Session
from viewer.sim.snapshot import Event

if TYPE_CHECKING:
    from playwright.sync_api import Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the Chromium fixture, shared with the viewer's browser tests

OVERVIEW_WIDTH = 640
"""Width of the test's overview panel [px]."""

ROW = 'tr[data-axis="X"]:not([data-line="error"]) [data-field]'
PANEL = "td[data-value]"
BOXES = """els => els.map(e => {
    const r = e.getBoundingClientRect();
    const table = e.closest('table');
    const frame = (table.dataset.overview ? e.closest('div') : table.parentElement)
        .getBoundingClientRect();
    return {field: e.dataset.field || e.dataset.value, x: r.x, y: r.y, width: r.width,
            height: r.height, inside: r.left >= frame.left - 0.5 && r.right <= frame.right + 0.5,
            whole: e.scrollWidth <= e.clientWidth, text: e.textContent.trim()};
})"""
"""The box of each cell [px], whether it lies inside its panel and shows its whole text."""


@dataclasses.dataclass
class Screen:
    """The test's page: the overview and X's panel, updated from the session by hand."""

    page: Page
    session: Session
    overview: Overview
    panel: viser.GuiHtmlHandle

    def show(self, **replace: Any) -> None:
        """Send the session's snapshot (X's view with ``replace``'d fields) to the page."""
        snapshot = self.session.snapshot
        x = dataclasses.replace(snapshot.axes["X"], **replace)
        self.overview.update(dataclasses.replace(snapshot, axes={**snapshot.axes, "X": x}))
        self.panel.content = axis_panel_html(x)

    def cells(self, selector: str) -> list[dict[str, Any]]:
        result: list[dict[str, Any]] = self.page.eval_on_selector_all(selector, BOXES)
        return result

    def wait_text(self, selector: str, text: str) -> None:
        self.page.locator(selector, has_text=text).first.wait_for(timeout=5_000)


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
    return port


@pytest.fixture
def screen(browser: Any) -> Iterator[Screen]:
    server = viser.ViserServer(host="127.0.0.1", port=_free_port(), verbose=False)
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    try:
        session = Session("gantry")
        left = server.gui.add_panel()
        with left.add_tab("Overview"):
            overview = Overview(server.gui)
        left.dock_left()
        left.set_width(OVERVIEW_WIDTH)
        with server.gui.add_folder("Axes"):
            panel = server.gui.add_html("")
        page = context.new_page()
        page.goto(f"http://127.0.0.1:{server.get_port()}")
        screen = Screen(page, session, overview, panel)
        screen.show()
        page.locator(ROW).first.wait_for(timeout=30_000)
        yield screen
    finally:
        context.close()
        server.stop()


def _same_places(before: list[dict[str, Any]], after: list[dict[str, Any]]) -> None:
    """The cells of ``after`` sit where those of ``before`` did, as wide, all inside and whole."""
    assert [c["field"] for c in after] == [c["field"] for c in before]
    for old, new in zip(before, after, strict=True):
        for key in ("x", "y", "width", "height"):
            assert new[key] == pytest.approx(old[key], abs=0.5), (new["field"], key)
        assert new["inside"] and new["whole"], new


def test_a_wire_break_keeps_every_value_of_x_in_place(screen: Screen, tmp_path: Path) -> None:
    session = screen.session
    session.requests("X").set_power(True)
    session.advance(100)
    session.requests("X").move(Move("relative", 200.0, 400.0, 4000.0))
    session.advance(150)
    screen.show()
    screen.wait_text(ROW, "400.00")
    row, panel = screen.cells(ROW), screen.cells(PANEL)
    assert {"position", "velocity", "following_error", "output"} <= {c["field"] for c in row}
    assert {"Position", "Velocity", "Following error", "State"} <= {c["field"] for c in panel}

    session.inject("X", mcl.faults.EncoderWireBreak())
    session.requests("X").move(Move("relative", 5.0, 100.0, 1000.0))  # refused: ErrorStop
    session.advance(10)
    screen.show()
    screen.wait_text('[data-field="error_text"]', "2001")
    view = session.snapshot.axes["X"]
    screen.wait_text(ROW, f"{view.position:.3f}")  # the row still follows the axis
    faulted, faulted_panel = screen.cells(ROW), screen.cells(PANEL)
    fields = {c["field"]: c["text"] for c in faulted}
    assert fields["set_velocity"] == "0.00" and abs(float(fields["velocity"])) < 1.0  # was 400
    assert "ErrorStop" in {c["text"] for c in faulted_panel}
    screen.page.screenshot(path=tmp_path / "wire_break.png")
    _same_places(row, faulted)
    _same_places(panel, faulted_panel)

    screen.show(
        error="encoder line fault " * 30,
        last_error="Move_by:" + "x" * 400,
        last_error_kind="Refused",
    )
    screen.wait_text('[data-text="Refused"]', "xxxx")
    _same_places(row, screen.cells(ROW))
    _same_places(panel, screen.cells(PANEL))
    clamp = screen.page.eval_on_selector(
        'tr[data-axis="X"] [data-field="error_text"]',
        "e => [e.getBoundingClientRect().height, e.scrollHeight > e.clientHeight]",
    )
    assert clamp[1] and clamp[0] < 40  # cut off after two lines, not growing the row


def test_the_error_history_and_the_results_stay_inside_the_panel(screen: Screen) -> None:
    snapshot = screen.session.snapshot
    events = tuple(Event(0.0, 1.0, "X", f"Move by: error {k} " + "y" * 120) for k in range(3))
    columns = tuple(f"column {k}" for k in range(14))
    rows = tuple(tuple(f"{1000.0 * k:.3f}" for k in range(14)) for _ in range(3))
    results = dataclasses.replace(snapshot, events=events, results=(columns, rows))
    screen.panel.content = events_html(results) + results_html(results)
    screen.wait_text("[data-results]", "column 13")
    frame = screen.page.eval_on_selector(
        "[data-results]",
        """e => {
            const panel = e.parentElement.parentElement.getBoundingClientRect();
            const events = [...document.querySelectorAll('[data-event]')].map(
                d => d.getBoundingClientRect().right <= panel.right + 0.5);
            const r = e.getBoundingClientRect();
            return {inside: r.right <= panel.right + 0.5, scrolls: e.scrollWidth > e.clientWidth,
                    events: events};
        }""",
    )
    assert frame["inside"] and frame["scrolls"]  # wider than the panel: it scrolls inside
    assert frame["events"] == [True, True, True]

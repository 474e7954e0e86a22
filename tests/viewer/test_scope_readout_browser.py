"""The scope's cursor read-out in headless Chromium at 1280×800 and 1920×1080: with eight of
the cell's channels of the longest names and units (the gantry's following errors and
velocities, the press' force and pressures) while its demo runs, every cell of the read-out
(last, A, B and B−A of each channel) is whole in the page's left column: no cell's text
overflows it, none reaches past an ancestor that clips it, none needs sideways scrolling."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from tests.viewer.test_browser import browser, wait_for
from tests.viewer.test_scope_browser import new_page
from viewer.scope.panel import MAX_CHANNELS
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser

pytestmark = pytest.mark.browser

__all__ = ["browser"]

CHANNELS = (
    "gantry/X following error",
    "gantry/Y following error",
    "gantry/X velocity",
    "press/force",
    "press/force_hydraulic",
    "press/pressure_A",
    "press/pressure_B",
    "gantry_in_zone",
)
"""Eight of the cell's channels with the longest names and units (``gantry in the press zone
[0/1]``, ``load cell force [kN]``)."""

CLIPPED = """() => {
    const table = [...document.querySelectorAll("table")]
        .find((t) => t.innerText.includes("B−A"));
    if (!table) return null;
    const clips = [];
    for (let e = table.parentElement; e; e = e.parentElement) {
        const style = getComputedStyle(e);
        if (style.overflowX !== "visible" || style.overflowY !== "visible") clips.push(e);
    }
    const view = {left: 0, right: innerWidth};
    const cells = [...table.querySelectorAll("td, th")];
    const clipped = cells.filter((c) => {
        const box = c.getBoundingClientRect();
        const outside = clips.some((e) => {
            const r = e.getBoundingClientRect();
            return box.left < r.left + e.clientLeft - 0.5
                || box.right > r.left + e.clientLeft + e.clientWidth + 0.5;
        });
        return c.scrollWidth > c.clientWidth || outside
            || box.left < view.left || box.right > view.right;
    }).map((c) => c.innerText);
    return {cells: cells.map((c) => c.innerText), clipped: clipped};
}"""
"""The read-out's cells (their text) and those clipped: wider than their text, or reaching
past an ancestor that clips its content (a column, a scrolling box) or past the window."""


SHOW = """() => [...document.querySelectorAll("table")]
    .find((t) => t.innerText.includes("B−A"))?.scrollIntoView({block: "center"})"""
"""Scroll the read-out into view (for the screenshot)."""


@pytest.fixture(scope="module")
def cell() -> Iterator[Viewer]:
    """The cell's viewer, which runs its demo."""
    with Viewer("cell", port=0, demo=True) as viewer:
        yield viewer


def read_out(page: Any) -> dict[str, Any]:
    found: dict[str, Any] | None = page.evaluate(CLIPPED)
    return found or {"cells": [], "clipped": []}


@pytest.mark.parametrize("size", [(1280, 800), (1920, 1080)], ids=["1280x800", "1920x1080"])
def test_every_cell_of_the_read_out_of_eight_long_channels_is_whole(
    browser: Browser, cell: Viewer, size: tuple[int, int], tmp_path: Path
) -> None:
    names = [c.name for c in cell.session.snapshot.channels]
    assert len(CHANNELS) == MAX_CHANNELS and set(CHANNELS) <= set(names)
    page, mine = new_page(browser, cell, *size)
    try:
        scope = mine.scope
        assert scope is not None
        scope.show_channels(CHANNELS)
        wait_for(lambda: scope.recording.names == CHANNELS, 10.0, "the eight channels")
        wait_for(
            lambda: sum("[" in c for c in read_out(page)["cells"]) == len(CHANNELS),
            30.0,
            "the eight channels in the read-out",
        )
        wait_for(lambda: "—" not in "".join(read_out(page)["cells"]), 30.0, "values at A and B")
        page.evaluate(SHOW)
        page.screenshot(path=str(tmp_path / f"readout-{size[0]}x{size[1]}.png"))
        found = read_out(page)
        assert len(found["cells"]) >= 4 * MAX_CHANNELS  # last, A, B, B−A of each
        assert found["clipped"] == []
    finally:
        page.context.close()

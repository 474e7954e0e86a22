"""Scene switches and resets leave the page's console clean (headless Chromium, 1280×800).

With the demos running the panels are updated at every refresh; the page takes several of the
server's sends at once while it draws a 3-D frame in software, and an element updated and removed
within one batch used to log "Tried to update non-existent component" (viser applies a batch's
updates after its removals). The viewer now hides an element at once and removes it later
(:mod:`viewer.serving.retire`)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import pytest

from tests.viewer.test_browser import browser, choose_scene, take_control, wait_for
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser, ConsoleMessage

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the fixture, shared with the viewer's browser tests


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """The gantry viewer with its demo (each machine chosen starts its own)."""
    with Viewer("gantry", port=0, demo=True) as v:
        yield v


def test_switching_machines_and_resetting_logs_no_console_error(
    browser: Browser, viewer: Viewer
) -> None:
    errors: list[str] = []

    def hear(message: ConsoleMessage) -> None:
        if message.type == "error":
            errors.append(message.text)

    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        page = context.new_page()
        page.on("console", hear)
        page.on("pageerror", lambda error: errors.append(str(error)))
        page.goto(viewer.url)
        page.get_by_role("button", name="Power", exact=True).wait_for(timeout=60_000)
        take_control(page, viewer)
        session = viewer.session
        wait_for(lambda: session.snapshot.demo.running, 30.0, "the gantry's demo")
        for name in ("rotary_cutter", "press", "gantry"):
            choose_scene(page, viewer, name)
            wait_for(lambda: session.snapshot.demo.running, 30.0, f"the {name} demo")
            page.get_by_text("Step: ").first.wait_for(timeout=30_000)  # its panels refresh
            before = session.snapshot.generation
            page.get_by_role("button", name="Reset scene", exact=True).click()
            wait_for(lambda: session.snapshot.generation > before, 30.0, "the reset")  # noqa: B023
            wait_for(
                lambda: viewer.app._generation == session.snapshot.generation,
                30.0,
                "the rebuilt panels",
            )
            # the demo panel shown anew (the demo may have started again already; a panel
            # taken away stays hidden for a while before it is removed)
            page.locator("text=/Not started\\.|Step: / >> visible=true").first.wait_for(
                timeout=30_000
            )
    finally:
        context.close()
    assert not errors, f"{len(errors)} console errors, the first: {errors[:3]}"

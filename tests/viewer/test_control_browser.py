"""Control between two pages in headless Chromium: a page asks the operator for control, the
operator refuses it on their own page; when the operator's page closes, control passes to the
page that asked."""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import TYPE_CHECKING

import pytest

from tests.viewer.test_browser import _free_port, browser, wait_for
from viewer.serving.server import Viewer

if TYPE_CHECKING:
    from playwright.sync_api import Browser, BrowserContext, Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the fixture, shared with the other browser tests


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """A viewer of a machine without 3-D model (light for a browser without GPU)."""
    with Viewer("single_axis", port=_free_port(), demo=False) as v:
        yield v


def _open(browser: Browser, viewer: Viewer) -> tuple[BrowserContext, Page, int]:
    """A new page of the viewer (its own browser context) and its client id."""
    before = set(viewer.app.control_pages.pages)
    context = browser.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    page.goto(viewer.url)
    page.get_by_text("Watching").first.wait_for(timeout=30_000)
    wait_for(lambda: len(set(viewer.app.control_pages.pages) - before) == 1, 10.0, "the page")
    (client_id,) = set(viewer.app.control_pages.pages) - before
    return context, page, client_id


@pytest.fixture(scope="module")
def operator(browser: Browser, viewer: Viewer) -> Iterator[tuple[BrowserContext, Page, int]]:
    """The page in control (opened with the printed address, Take control pressed)."""
    context, page, client_id = _open(browser, viewer)
    page.get_by_role("button", name="Take control", exact=True).click()
    wait_for(lambda: viewer.app.control.owner == client_id, 5.0, "control to be taken")
    try:
        yield context, page, client_id
    finally:
        context.close()


def test_the_token_leaves_the_address_bar_and_the_page_works(
    operator: tuple[BrowserContext, Page, int], viewer: Viewer
) -> None:
    _, page, client_id = operator
    assert viewer.token is not None and viewer.token not in page.url
    assert page.url.rstrip("/").endswith(str(viewer.port))
    page.get_by_text("You are in control").wait_for(timeout=5_000)
    page.get_by_text("lifesign").wait_for(timeout=5_000)
    assert viewer.app.control.owner == client_id


def test_the_operator_refuses_a_request_on_their_page(
    browser: Browser, operator: tuple[BrowserContext, Page, int], viewer: Viewer
) -> None:
    _, page_a, a = operator
    context, page_b, b = _open(browser, viewer)
    try:
        page_b.get_by_text(f"Watching — operator #{a} in control").wait_for(timeout=5_000)
        assert page_b.get_by_role("button", name="Take control", exact=True).count() == 0
        page_b.get_by_role("button", name="Request control", exact=True).click()
        page_a.get_by_text(f"Operator #{b} requests control", exact=True).wait_for(timeout=5_000)
        assert viewer.app.control.owner == a  # asking takes nothing
        page_a.get_by_role("button", name="Refuse", exact=True).click()
        page_b.get_by_text(f"refused by operator #{a}").first.wait_for(timeout=5_000)
        assert viewer.app.control.owner == a and viewer.app.control.request is None
        page_a.get_by_text("You are in control").wait_for(timeout=5_000)
        page_b.get_by_text(f"Watching — operator #{a} in control").wait_for(timeout=5_000)
        assert page_b.get_by_text("You are in control").count() == 0
    finally:
        context.close()


def test_control_passes_to_the_requester_when_the_operator_page_closes(
    browser: Browser, operator: tuple[BrowserContext, Page, int], viewer: Viewer
) -> None:
    context_a, page_a, a = operator
    context, page_b, b = _open(browser, viewer)
    try:
        page_b.get_by_role("button", name="Request control", exact=True).click()
        page_a.get_by_text(f"Operator #{b} requests control", exact=True).wait_for(timeout=5_000)
        closed = time.monotonic()
        context_a.close()
        wait_for(lambda: viewer.app.control.owner == b, 5.0, "control to pass on")
        handover = time.monotonic() - closed
        page_b.get_by_text("You are in control").wait_for(timeout=5_000)
        print(f"handover after the operator's page closed: {handover * 1e3:.0f} ms")
        assert handover < 2.0  # closing is noticed at once, not after the lifesign timeout
        events = [e.text for e in viewer.session._events]
        assert f"operator #{a} left: operator #{b} in control" in events
    finally:
        context.close()

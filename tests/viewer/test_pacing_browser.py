"""A page that draws its 3-D view in software paces its drawing (headless Chromium, software
WebGL): no 3-D frame for a moment after a press on the panels, so that the command and the
state that answers it go through first; while the machine moves, frames no closer than the
software frame period; the moved machine drawn once the pause is over."""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from typing import TYPE_CHECKING

import pytest

from plc.operator.hmi import Move
from tests.viewer.test_browser import browser, wait_for
from viewer.serving.server import Viewer
from viewer.view3d.renderer import INPUT_PAUSE_MS, SOFTWARE_FPS

if TYPE_CHECKING:
    from playwright.sync_api import Browser

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the fixture, shared with the viewer's browser tests

PRESS_AND_DRAWS = """(ms) => new Promise((done) => {
    // a press on the panels, then the times [ms after it] at which the page began to draw a
    // 3-D frame on its canvas (a call of the renderer that drew: three.js counts the frames)
    const gl = window.__viserMutable.scene.__r3f.root.getState().gl;
    const render = gl.render; const draws = [];
    gl.render = function (scene, camera) {
        const start = performance.now() - t0; const frame = gl.info.render.frame;
        const canvas = gl.getRenderTarget() === null;  // not a pass into a texture
        const result = render.call(this, scene, camera);
        if (canvas && gl.info.render.frame !== frame) draws.push(start);
        return result;
    };
    const t0 = performance.now();
    document.body.dispatchEvent(new PointerEvent('pointerdown', {bubbles: true}));
    setTimeout(() => { gl.render = render; done(draws); }, ms);
})"""


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    with Viewer("gantry", port=0, demo=False) as v:
        yield v


def test_a_software_page_pauses_its_3d_frames_after_a_press_and_paces_them(
    browser: Browser, viewer: Viewer
) -> None:
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        page = context.new_page()
        page.goto(viewer.url)
        page.get_by_role("button", name="Power", exact=True).wait_for(timeout=60_000)
        page.get_by_text("No GPU (software WebGL)").first.wait_for(timeout=30_000)
        wait_for(
            lambda: page.evaluate(
                "() => !!window.__viserMutable.scene.__r3f.root.getState().gl.__paced"
            ),
            30.0,
            "the page to pace its 3-D view",
        )
        session = viewer.session
        session.requests("X").set_power(True)
        wait_for(lambda: session.snapshot.axes["X"].powered, 10.0, "X powered")

        session.requests("X").move(Move("relative", 60.0, 30.0, 300.0))  # 2 s of motion
        wait_for(lambda: abs(session.snapshot.axes["X"].velocity) > 1.0, 10.0, "X moving")
        draws = page.evaluate(PRESS_AND_DRAWS, INPUT_PAUSE_MS + 1000.0)
        assert draws, "the moving machine was never drawn"
        assert draws[0] >= INPUT_PAUSE_MS, f"a 3-D frame {draws[0]:.0f} ms after a press"
        gaps = [b - a for a, b in itertools.pairwise(draws)]
        assert gaps, "the moving machine was drawn only once"
        assert min(gaps) >= 1000.0 / SOFTWARE_FPS - 1.0, f"frames {min(gaps):.0f} ms apart"
    finally:
        context.close()

"""The group's path in headless Chromium (1280×800): the page's View folder set to Path ×100,
the gantry's group runs a line and a circle of R = 50 mm at 200 mm/s: the trail the page was
sent spans them, its actual points deviate from the commanded ones, the factor is written beside
it (``PATH_SCREENSHOTS``: a folder for a screenshot of the 3-D view)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pytest

from tests.viewer.test_browser import browser, wait_for
from tests.viewer.test_path_trail import OUT_OF_THE_CORNER, CircleDemo
from tests.viewer.test_scope_browser import choose
from viewer.serving.server import Viewer
from viewer.sim.session import Session

if TYPE_CHECKING:
    from playwright.sync_api import Browser

pytestmark = pytest.mark.browser

__all__ = ["browser"]

RADIUS = 50.0
"""Radius of the circle [mm]."""


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """The gantry viewer on a free loopback port with the circle as its demo (not started)."""
    session = Session("gantry", demo=partial(CircleDemo, radius=RADIUS, velocity=200.0))
    with Viewer("gantry", port=0, demo=False, session=session) as v:
        yield v


def test_the_page_draws_the_circle_with_its_magnified_deviation(
    browser: Browser, viewer: Viewer
) -> None:
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        page = context.new_page()
        page.goto(viewer.url)
        page.get_by_text("View", exact=True).first.click(timeout=60_000)  # open the folder
        choose(page, "Path (actual deviation)", "×100")
        wait_for(lambda: viewer.app.views.path.choice == "×100", 10.0, "the Path choice")
        # the trail begins with the first frame drawn after the choice (one point per frame):
        # the circle starts once it has
        wait_for(lambda: viewer.app.views.path.trail is not None, 30.0, "the trail's start")
        trail = viewer.app.views.path.trail
        assert trail is not None
        start = trail.commanded[-1].copy()
        viewer.session.start_demo()
        wait_for(lambda: viewer.session.snapshot.demo.done, 60.0, "the circle")
        end = start + np.array(OUT_OF_THE_CORNER) / 1e3  # where the circle closes

        def closed() -> bool:  # a frame drawn after the circle's end
            return bool(np.linalg.norm(trail.commanded[-1] - end) < 1e-3)

        wait_for(closed, 30.0, "the trail's last point at the circle's end")
        commanded = trail.commanded
        xy = commanded[:, :2]
        span = xy.max(axis=0) - xy.min(axis=0)
        # one point per snapshot: a loaded machine publishes fewer, and the trail cuts the
        # circle's extremes by the sagitta of its widest chord
        chord = np.linalg.norm(np.diff(xy, axis=0), axis=1).max()
        sagitta = chord**2 / (8 * RADIUS / 1e3)
        expected = np.array([2 * RADIUS / 1e3 + 0.06, RADIUS / 1e3 + 0.06])
        assert np.all(span <= expected + 1e-3)
        assert np.all(span >= expected - 1e-3 - 2 * sagitta)
        assert chord < 0.04  # a circle, drawn with more than eight chords
        assert np.linalg.norm(trail.actual - commanded, axis=1).max() > 1e-6
        assert trail.label.endswith("deviation ×100")
        folder = os.environ.get("PATH_SCREENSHOTS")
        if folder:  # the 3-D view alone, looking at the circle from the front and above
            page.mouse.click(651, 7)  # collapse the left panel
            page.mouse.click(1267, 7)  # and the right one
            centre = commanded[-1] + [RADIUS / 1e3, 0.0, 0.0]
            for client in viewer.server.get_clients().values():
                client.camera.up_direction = (0.0, 0.0, 1.0)
                client.camera.look_at = centre
                client.camera.position = centre + np.array([0.03, -0.22, 0.14])
            page.wait_for_timeout(2000)
            page.screenshot(path=str(Path(folder) / "path-circle.png"), timeout=120_000)
    finally:
        context.close()

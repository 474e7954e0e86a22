"""The flying shear's axis labels in headless Chromium at 1280×800: after each camera preset
(Side, where the line's L, W and S all point at the camera, Front, Top, Fit) the labels, as the
page's own camera projects them into its 3-D canvas, lie apart."""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pytest
import viser.transforms as tf

from tests.viewer.test_browser import browser, wait_for
from tests.viewer.test_scope_browser import new_page
from viewer.serving.server import Viewer
from viewer.view3d.axis_marks import LABEL_CHAR, LABEL_LINE
from viewer.view3d.views import VIEWS

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

    from viewer.pages.layout import Page as ViewerPage

pytestmark = pytest.mark.browser

__all__ = ["browser"]

CANVAS = """() => {
    const c = [...document.querySelectorAll('canvas')].filter((c) => !c.closest('.uplot'))
        .map((c) => c.getBoundingClientRect()).sort((a, b) => b.width - a.width)[0];
    return [c.width, c.height];
}"""
"""The 3-D canvas' width and height [CSS px]."""


@pytest.fixture(scope="module")
def shear(browser: Browser) -> Iterator[tuple[Page, ViewerPage, Viewer]]:
    """A 1280×800 page of the flying shear's viewer (no demo), its View folder open."""
    with Viewer("flying_shear", port=0, demo=False) as viewer:
        page, mine = new_page(browser, viewer, 1280, 800)
        try:
            folder = page.get_by_text("View", exact=True).locator("visible=true").first
            folder.scroll_into_view_if_needed()
            folder.click()
            yield page, mine, viewer
        finally:
            page.context.close()


def label_boxes(page: Page, mine: ViewerPage, viewer: Viewer) -> dict[str, tuple[float, ...]]:
    """Each axis label's box (left, top, right, bottom) [CSS px] in the 3-D canvas as the
    page's camera draws it (the label's lower left corner at its point)."""
    marks = viewer.app.views.marks
    assert marks is not None
    camera = mine.client.camera
    rotation = tf.SO3(np.asarray(camera.wxyz)).as_matrix()  # OpenCV camera: x right, y down
    width, height = page.evaluate(CANVAS)
    focal = 0.5 * height / np.tan(0.5 * camera.fov)
    boxes: dict[str, tuple[float, ...]] = {}
    for mark in marks.axes:
        local = (marks.label_position(mark.axis) - np.asarray(camera.position)) @ rotation
        assert local[2] > 0.0, mark.axis  # in front of the camera
        x = 0.5 * width + focal * local[0] / local[2]
        y = 0.5 * height + focal * local[1] / local[2]
        wide = LABEL_CHAR * len(marks.label(mark.axis))
        boxes[mark.axis] = (x, y - LABEL_LINE, x + wide, y)
    return boxes


@pytest.mark.parametrize("preset", list(VIEWS))
def test_the_axis_labels_lie_apart_in_each_camera_preset(
    shear: tuple[Page, ViewerPage, Viewer], preset: str, tmp_path: Path
) -> None:
    page, mine, viewer = shear
    direction = np.asarray(VIEWS[preset]) / np.linalg.norm(VIEWS[preset])

    def arrived() -> bool:
        camera = mine.client.camera
        seen = np.asarray(camera.position) - np.asarray(camera.look_at)
        return float(seen @ direction) > 0.999 * float(np.linalg.norm(seen))

    page.get_by_role("button", name=preset, exact=True).locator("visible=true").first.click()
    wait_for(arrived, 10.0, f"the {preset} camera")
    page.wait_for_timeout(500)
    page.screenshot(path=tmp_path / f"shear-{preset}.png")
    boxes: dict[str, Any] = label_boxes(page, mine, viewer)
    assert set(boxes) == {"L", "W", "S"}
    for (a, box_a), (b, box_b) in itertools.combinations(boxes.items(), 2):
        apart = (box_a[2] <= box_b[0] or box_b[2] <= box_a[0] or box_a[3] <= box_b[1]) or box_b[
            3
        ] <= box_a[1]
        assert apart, (preset, a, box_a, b, box_b)

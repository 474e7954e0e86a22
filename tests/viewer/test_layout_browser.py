"""The page's layout in headless Chromium at 1280×800 and 1920×1080, read from the element
boxes: the 3-D canvas at least half the page wide; the first axis' Power, Reset, Stop, Jog±,
Move to and Home inside the page without scrolling, no floating window over them; on the cell
every axis label whole (``gantry/X``, its unit, its tab) and both machines, the gantry and the
press, inside the canvas as the page's camera sees them."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
import numpy.typing as npt
import pytest
import viser
import viser.transforms as tf

from tests.viewer.test_browser import _free_port, browser, wait_for
from viewer.pages.layout import COLUMN_WIDTH
from viewer.pages.overview import Overview
from viewer.serving.server import Viewer
from viewer.sim.session import Session
from viewer.view3d.views import VIEWS, _camera_position

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

pytestmark = pytest.mark.browser

__all__ = ["browser"]  # the Chromium fixture, shared with the viewer's browser tests

SIZES = ((1280, 800), (1920, 1080))
"""Page sizes [CSS px] the layout must fit."""

BUTTONS = ("Power", "Reset", "Stop", "Jog+", "Jog−", "Move to", "Home")
"""The first axis' buttons that must be in view at once."""

BOXES = """(names) => {
    const canvas = [...document.querySelectorAll('canvas')].filter((c) => !c.closest('.uplot'))
        .map((c) => c.getBoundingClientRect()).sort((a, b) => b.width - a.width)[0];
    const buttons = names.map((name) => {
        const b = [...document.querySelectorAll('button')].find(
            (e) => e.textContent.trim() === name && e.getBoundingClientRect().width > 0);
        if (!b) return {name: name, found: false};
        const r = b.getBoundingClientRect();
        const top = document.elementFromPoint(r.x + r.width / 2, r.y + r.height / 2);
        return {name: name, found: true, left: r.left, right: r.right, top: r.top,
                bottom: r.bottom, uncovered: top !== null && b.contains(top)};
    });
    return {canvas: {left: canvas.left, width: canvas.width}, buttons: buttons,
            width: innerWidth, height: innerHeight,
            scrolled: [...document.querySelectorAll('*')].some((e) => e.scrollTop > 0)};
}"""
"""The canvas' box, each button's box and whether it is the element seen at its centre."""

LABELS = """() => {
    const whole = (e) => e.scrollWidth <= e.clientWidth + 1;
    const names = [...document.querySelectorAll('td[data-field="name"]')].map((e) => ({
        text: e.textContent.trim(), whole: whole(e)}));
    const cells = (field) => [...document.querySelectorAll(`td[data-field="${field}"]`)].map(
        (e) => ({text: e.textContent.trim(), whole: whole(e)}));
    const fe = cells("following_error"), peak = cells("peak_following_error");
    const tabs = [...document.querySelectorAll('[role="tab"]')].map((e) => ({
        text: e.textContent.trim(), whole: [e, ...e.querySelectorAll('*')].every(whole)}));
    return {names: names, fe: fe, peak: peak, tabs: tabs};
}"""
"""The overview's axis names, following errors and their peaks, and every tab label: text,
shown whole."""


def open_page(browser: Browser, viewer: Viewer, width: int, height: int) -> Page:
    """A page of ``width`` × ``height`` with the first axis' panel laid out."""
    page = browser.new_context(viewport={"width": width, "height": height}).new_page()
    page.goto(viewer.url)
    page.get_by_role("button", name="Power", exact=True).first.wait_for(timeout=60_000)
    page.locator('td[data-field="name"]').first.wait_for(timeout=30_000)
    page.wait_for_timeout(6000)  # the docked panels settle (the axes' tabs widen the panel)
    return page


@pytest.fixture(scope="module")
def cell() -> Iterator[Viewer]:
    """The cell (the gantry and the press) on a free loopback port, without demo."""
    with Viewer("cell", port=0, demo=False) as v:
        yield v


@pytest.mark.parametrize(("width", "height"), SIZES)
def test_the_canvas_is_half_the_page_and_the_axis_buttons_are_in_view(
    browser: Browser, cell: Viewer, width: int, height: int
) -> None:
    page = open_page(browser, cell, width, height)
    try:
        boxes: dict[str, Any] = page.evaluate(BOXES, list(BUTTONS))
    finally:
        page.context.close()
    assert boxes["width"] == width and boxes["height"] == height
    assert boxes["canvas"]["width"] >= 0.5 * width, boxes["canvas"]
    assert not boxes["scrolled"]
    for button in boxes["buttons"]:
        assert button["found"], button
        assert button["left"] >= 0 and button["right"] <= width, button
        assert button["top"] >= 0 and button["bottom"] <= height, button  # no scrolling
        assert button["uncovered"], button  # no floating window over it


def test_the_cell_s_labels_are_whole(browser: Browser, cell: Viewer) -> None:
    page = open_page(browser, cell, 1280, 800)
    try:
        labels: dict[str, Any] = page.evaluate(LABELS)
    finally:
        page.context.close()
    axes = list(cell.session.snapshot.axes)
    assert axes == ["gantry/X", "gantry/Y", "gantry/Z", "press/R"]
    assert [n["text"] for n in labels["names"]] == [f"{a} mm" for a in axes]
    assert all(n["whole"] for n in labels["names"]), labels["names"]
    assert all(f["whole"] for f in labels["fe"]), labels["fe"]
    tabs = {t["text"]: t["whole"] for t in labels["tabs"]}
    assert all(tabs.get(a) for a in axes), tabs


OVERVIEW = """() => {
    const table = document.querySelector('table[data-overview]');
    const frame = table.parentElement, box = frame.getBoundingClientRect();
    const fields = [...table.querySelectorAll('[data-field]')].map((e) => {
        const r = e.getBoundingClientRect();
        return {field: e.dataset.field, text: e.textContent.trim(),
                whole: e.scrollWidth <= e.clientWidth + 1,
                inside: r.left >= box.left - 0.5 && r.right <= box.right + 0.5};
    });
    return {scrolls: frame.scrollWidth > frame.clientWidth + 1, width: box.width,
            fields: fields};
}"""
"""The overview's frame: whether it scrolls sideways, and each value, name and lamp of the table:
its text, shown whole and inside the frame."""


def fits(overview: dict[str, Any], axes: int) -> None:
    """Every value of the ``axes`` axes' overview readable without scrolling sideways."""
    assert not overview["scrolls"], overview["width"]
    fields = overview["fields"]
    values = [f for f in fields if f["field"] in ("position", "set_velocity", "output")]
    assert len(values) == 3 * axes
    bad = [f for f in fields if not (f["whole"] and f["inside"])]
    assert not bad, bad


@pytest.mark.parametrize(("width", "height"), SIZES)
def test_the_overview_fits_its_column(
    browser: Browser, cell: Viewer, width: int, height: int, tmp_path: Path
) -> None:
    """The cell's four axes (the longest names, ``gantry/X``) in the page's left column: no
    sideways scrolling, every value, name, unit and lamp whole."""
    page = open_page(browser, cell, width, height)
    try:
        overview: dict[str, Any] = page.evaluate(OVERVIEW)
        page.screenshot(path=tmp_path / "overview.png")
    finally:
        page.context.close()
    fits(overview, 4)


def test_a_following_error_in_mdeg_is_whole(browser: Browser) -> None:
    """The rotary cutter's overview in a page of the test's own, its drum D (deg) showing a
    following error and a peak at its limit (MaxPositionLag 5 deg): each cell shows its text
    whole."""
    session = Session("rotary_cutter")
    server = viser.ViserServer(host="127.0.0.1", port=_free_port(), verbose=False)
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        left = server.gui.add_panel()
        with left.add_tab("Overview"), server.gui.add_folder("All axes"):  # as on the page
            overview = Overview(server.gui)
        left.dock_left()
        left.set_width(COLUMN_WIDTH)
        snapshot = session.snapshot
        drum = dataclasses.replace(
            snapshot.axes["D"], following_error=-4.9999, peak_following_error=5.0
        )
        overview.update(dataclasses.replace(snapshot, axes={**snapshot.axes, "D": drum}))
        page = context.new_page()
        page.goto(f"http://127.0.0.1:{server.get_port()}")
        page.locator('td[data-field="name"]').first.wait_for(timeout=30_000)
        labels: dict[str, Any] = page.evaluate(LABELS)
        fits(page.evaluate(OVERVIEW), len(snapshot.axes))  # the FE's unit with each value
    finally:
        context.close()
        server.stop()
        session.close()
    degrees = [f["text"] for f in labels["fe"] if f["text"].endswith("mdeg")]
    assert degrees == ["-4999.9 mdeg"], labels["fe"]
    assert all(f["whole"] for f in labels["fe"]), labels["fe"]
    peaks = [f for f in labels["peak"] if f["text"].endswith("mdeg")]
    assert [f["text"] for f in peaks] == ["5000.0 mdeg"] and peaks[0]["whole"], peaks


def projected(camera: Any, points: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``points`` [m] in the page camera's normalised image coordinates (−1…1 inside), and
    their depth in front of it (third column)."""
    rotation = tf.SO3(np.asarray(camera.wxyz)).as_matrix()  # OpenCV camera: x right, y down
    local = (points - np.asarray(camera.position)) @ rotation
    tan_v = np.tan(0.5 * camera.fov)
    tan_h = tan_v * camera.aspect
    return np.column_stack(
        (local[:, 0] / local[:, 2] / tan_h, local[:, 1] / local[:, 2] / tan_v, local[:, 2])
    )


def machine_points(viewer: Viewer, prefix: str) -> npt.NDArray[np.float64]:
    """The centres [m] of the solid geoms of the bodies named ``prefix``…"""
    snapshot = viewer.session.snapshot
    model = snapshot.model
    assert model is not None
    data = mujoco.MjData(model)
    data.qpos[:] = snapshot.qpos
    mujoco.mj_kinematics(model, data)
    names = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(b)) or "" for b in range(model.nbody)
    ]
    geoms = [
        g
        for g in range(model.ngeom)
        if names[model.geom_bodyid[g]].startswith(prefix)
        and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE
    ]
    assert geoms, prefix
    return np.asarray(data.geom_xpos)[geoms]


def test_the_cell_s_camera_shows_the_gantry_and_the_press(browser: Browser, cell: Viewer) -> None:
    before = set(cell.server.get_clients())
    page = open_page(browser, cell, 1280, 800)
    try:
        (client_id,) = set(cell.server.get_clients()) - before
        camera = cell.server.get_clients()[client_id].camera
        target = np.asarray(cell.server.initial_camera.position)
        wait_for(
            lambda: bool(np.allclose(camera.position, target, atol=1e-3)),
            10.0,
            "the page's camera at the initial view",
        )
        for machine in ("gantry/", "press/"):
            image = projected(camera, machine_points(cell, machine))
            assert (image[:, 2] > 0.0).all(), machine  # in front of the camera
            assert (np.abs(image[:, :2]) <= 0.95).all(), (machine, image)
    finally:
        page.context.close()


def test_each_camera_preset_turns_the_camera_onto_the_cell(browser: Browser, cell: Viewer) -> None:
    """Fit, Front, Side and Top, one after the other: the page's camera (as the page reports
    it) stands where the preset puts it, looks at the machine's centre and sees both
    machines (a preset that kept the previous view's direction drew an empty, white view)."""
    before = set(cell.server.get_clients())
    page = open_page(browser, cell, 1280, 800)
    try:
        (client_id,) = set(cell.server.get_clients()) - before
        camera = cell.server.get_clients()[client_id].camera
        bounds = cell.app.views._bounds
        assert bounds is not None
        center, radius = bounds
        page.get_by_text("View", exact=True).locator("visible=true").first.click()
        for name in ("Side", "Top", "Front", "Fit"):
            page.get_by_role("button", name=name, exact=True).locator("visible=true").first.click()
            target = _camera_position(center, radius, VIEWS[name])

            def there(at: npt.NDArray[np.float64] = target) -> bool:
                # the page reports its camera as it takes each of the preset's settings in turn
                return bool(
                    np.allclose(camera.position, at, atol=1e-3)
                    and np.allclose(camera.look_at, center, atol=1e-3)
                )

            wait_for(there, 20.0, f"the page's camera at the {name} view, onto the centre")
            for machine in ("gantry/", "press/"):
                image = projected(camera, machine_points(cell, machine))
                assert (image[:, 2] > 0.0).all(), (name, machine)  # in front of the camera
                assert (np.abs(image[:, :2]) <= 1.0).all(), (name, machine, image)
    finally:
        page.context.close()

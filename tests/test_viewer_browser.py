"""The viewer in headless Chromium: the page shows the machine, and its buttons move the axis.

The viewer runs in this process (server, simulation and update threads); Playwright drives a
headless Chromium against it like an operator would: press Power, hold Jog+, let go.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

import imageio.v3 as iio
import numpy as np
import pytest

from viewer.app import Viewer, port_available

if TYPE_CHECKING:
    from playwright.sync_api import Browser, Page

pytestmark = pytest.mark.browser

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
INSTALL_TIMEOUT = 600.0
"""Seconds allowed for ``apt-get update`` plus ``apt-get install chromium``."""


def _install_chromium() -> str | None:
    """Install Debian's chromium with apt-get (root only); the reason if it cannot be done."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        return f"{CHROMIUM} is missing and installing it needs root (apt-get install chromium)"
    if shutil.which("apt-get") is None:
        return f"{CHROMIUM} is missing and there is no apt-get to install it"
    deadline = time.monotonic() + INSTALL_TIMEOUT
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    try:
        for command in (["apt-get", "update"], ["apt-get", "install", "-y", "chromium"]):
            subprocess.run(
                command,
                check=True,
                env=env,
                timeout=max(deadline - time.monotonic(), 1.0),
                capture_output=True,
            )
    except (subprocess.SubprocessError, OSError) as exc:
        return f"{CHROMIUM} is missing and apt-get install chromium failed: {exc}"
    return None if os.path.exists(CHROMIUM) else f"apt-get did not install {CHROMIUM}"


@pytest.fixture(scope="session")
def browser() -> Iterator[Browser]:
    """Headless Chromium driven by Playwright (installed with apt-get when missing and root)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("playwright's Python package is not installed (pip install playwright)")
    if not os.path.exists(CHROMIUM):
        reason = _install_chromium()
        if reason is not None:
            pytest.skip(reason)
    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            yield chromium
        finally:
            chromium.close()


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
    return port


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """The gantry viewer on a free loopback port, without demo; stopped and its port freed."""
    port = _free_port()
    v = Viewer("gantry", port=port, demo=False)
    try:
        yield v
    finally:
        v.close()
        assert port_available("127.0.0.1", port), "the viewer's port is still taken"


@pytest.fixture(scope="module")
def page(browser: Browser, viewer: Viewer) -> Iterator[Page]:
    """The viewer's page, loaded (its axis panel is shown); shared by the tests of this module,
    which run in file order: first look, then operate."""
    context = browser.new_context(viewport={"width": 1280, "height": 1000})
    p = context.new_page()
    try:
        p.goto(viewer.url)
        p.get_by_role("button", name="Power", exact=True).wait_for(timeout=30_000)
        yield p
    finally:
        context.close()


def wait_for(condition: Callable[[], bool], timeout: float, what: str) -> None:
    """Poll ``condition`` until it holds (wall clock: the browser and the server run live)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.02)


def test_canvas_shows_the_machine(
    page: Page, viewer: Viewer, tmp_path_factory: pytest.TempPathFactory
) -> None:
    wait_for(lambda: viewer.app.frames > 0, 5.0, "the first frame")
    time.sleep(0.5)  # let three.js draw a few frames after the scene arrived
    shot = page.locator("canvas").first.screenshot()
    (tmp_path_factory.mktemp("viewer") / "canvas.png").write_bytes(shot)
    image = iio.imread(shot, extension=".png")[..., :3].astype(np.int16)
    height, width = image.shape[:2]
    assert height > 200 and width > 200
    # The machine stands in the middle of the initial view; the control panel (right) and
    # notifications (top left) float over the canvas, so look at the centre-left region only.
    view = image[int(0.3 * height) : int(0.75 * height), int(0.25 * width) : int(0.65 * width)]
    pixels = view.reshape(-1, 3)
    background = np.median(image[:5, : width // 2].reshape(-1, 3), axis=0)  # the backdrop
    differs = np.abs(pixels - background).sum(axis=1) > 30
    colours = np.unique(pixels, axis=0)
    r, g, b = pixels[:, 0], pixels[:, 1], pixels[:, 2]
    bridge_blue = (b > r + 60) & (b > g + 30)
    assert differs.mean() > 0.2, "the canvas is (almost) blank"
    assert len(colours) > 200, f"only {len(colours)} distinct colours: nothing shaded"
    assert bridge_blue.sum() > 200, "the (blue) bridge of the gantry is not in the picture"


def test_power_and_jog_move_the_axis(page: Page, viewer: Viewer) -> None:
    session = viewer.session
    start = session.scene.joint_position("X")  # ground truth [m]

    page.get_by_role("button", name="Power", exact=True).click()
    wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")

    jog = page.get_by_role("button", name="Jog+", exact=True)
    jog.scroll_into_view_if_needed()
    box = jog.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    wait_for(lambda: session.snapshot.axes["X"].jogging == 1, 5.0, "the jog request")
    time.sleep(0.6)
    page.mouse.up()
    moved = session.scene.joint_position("X") - start
    assert moved > 0.001, f"X moved {moved * 1e3:.3f} mm while Jog+ was held"

    # Released: the jog request ends (click or dead-man deadline) and the axis stops.
    wait_for(lambda: session.snapshot.axes["X"].jogging == 0, 2.0, "the jog to end")
    wait_for(lambda: abs(session.snapshot.axes["X"].velocity) < 0.5, 3.0, "X to stand still")
    stopped = session.scene.joint_position("X")
    time.sleep(0.3)
    assert abs(session.scene.joint_position("X") - stopped) < 1e-4
    assert session.snapshot.axes["X"].state == "StandStill"

"""The viewer in headless Chromium: the page shows the machine, and its buttons move the axis.

The viewer runs in this process (server, simulation and update threads); Playwright drives a
headless Chromium against it like an operator would: press Power, hold Jog+, let go, pick another
machine in the chooser. What a panel shows comes from the machine definition in the registry.
"""

from __future__ import annotations

import itertools
import os
import re
import shutil
import socket
import subprocess
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import imageio.v3 as iio
import numpy as np
import pytest
import viser

import scenes
from plc.operator.hmi import Move
from tests.viewer.test_session import SHEAR
from viewer.serving.server import Viewer, port_available

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


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    """Headless Chromium driven by Playwright (installed with apt-get when missing and root).

    Module scope: Playwright's sync API runs an event loop in this thread while it is started,
    so it is stopped before tests of other modules run here (they may call ``asyncio.run``)."""
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
        take_control(p, viewer)
        yield p
    finally:
        context.close()


def take_control(page: Page, viewer: Viewer) -> int:
    """Press Take control and wait until the app names this page's client as the operator."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    button = page.get_by_role("button", name="Take control", exact=True)
    try:
        button.click(timeout=15_000)
    except PlaywrightTimeout:  # the page's first websocket dropped while loading: reload it
        page.reload()
        page.get_by_role("button", name="Power", exact=True).wait_for(timeout=30_000)
        button.click(timeout=15_000)
    before = set(viewer.server.get_clients())
    wait_for(lambda: viewer.app.control.owner is not None, 5.0, "control to be taken")
    owner = viewer.app.control.owner
    assert owner is not None and owner in before
    page.get_by_text(f"operator #{owner}").first.wait_for(timeout=5_000)
    return owner


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


def test_a_held_alt_arrow_key_jogs_until_let_go(page: Page, viewer: Viewer) -> None:
    """Alt+→ held: the keyboard repeats it, each repeat renews the jog; let go, the axis
    stops."""
    session = viewer.session
    if not session.snapshot.axes["X"].powered:
        page.get_by_role("button", name="Power", exact=True).click()
        wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")
    page.evaluate("document.activeElement && document.activeElement.blur()")
    page.keyboard.down("Alt")
    page.keyboard.down("ArrowRight")
    wait_for(lambda: session.snapshot.axes["X"].jogging == 1, 5.0, "the key's jog")
    start, sim0 = session.scene.joint_position("X"), session.scene.time
    # 1.5 s of the keyboard's auto-repeat (a keydown with repeat set every 30 ms), three times
    # the first press' 0.55 s; sent inside the page, as the keyboard would
    page.evaluate(
        """() => new Promise((done) => {
            const t0 = performance.now();
            const timer = setInterval(() => {
                document.activeElement.dispatchEvent(new KeyboardEvent("keydown", {
                    key: "ArrowRight", code: "ArrowRight", altKey: true, repeat: true,
                    bubbles: true,
                }));
                if (performance.now() - t0 > 1500) { clearInterval(timer); done(null); }
            }, 30);
        })"""
    )
    moved, simulated = session.scene.joint_position("X") - start, session.scene.time - sim0
    page.keyboard.up("ArrowRight")
    page.keyboard.up("Alt")
    # Judged on the simulated time that passed (on a loaded machine the simulation runs slower
    # than the wall clock): the first press alone jogs for 0.55 of the 1.5 s, so less than
    # 37 % of that time at the default jog velocity; the repeats keep it going most of it
    # (a server thread starved of the CPU may miss a few repeats: the jog then pauses).
    jog_velocity = 0.1 * session.snapshot.axes["X"].vmax * 1e-3  # the default [m/s]
    assert simulated > 0.0
    assert moved > 0.5 * jog_velocity * simulated, (
        f"X moved {moved * 1e3:.1f} mm in {simulated:.2f} s of simulated time while Alt+→ "
        f"was held: the repeats did not keep the jog alive"
    )

    wait_for(lambda: session.snapshot.axes["X"].jogging == 0, 2.0, "the jog to end")
    wait_for(lambda: abs(session.snapshot.axes["X"].velocity) < 0.5, 3.0, "X to stand still")
    stopped = session.scene.joint_position("X")
    time.sleep(0.3)
    assert abs(session.scene.joint_position("X") - stopped) < 1e-4


def scene_options(page: Page) -> list[str]:
    """Open the scene chooser and read its options (closes it again)."""
    chooser = page.get_by_role("combobox", name="Scene", exact=True)
    chooser.click()
    options = page.get_by_role("option")
    options.first.wait_for(timeout=5_000)
    names = [text.strip() for text in options.all_inner_texts()]
    page.keyboard.press("Escape")
    return names


def choose_scene(page: Page, viewer: Viewer, name: str) -> None:
    """Pick a machine in the chooser and wait until the session and the page show it."""
    page.get_by_role("combobox", name="Scene", exact=True).click()
    page.get_by_role("option", name=name, exact=True).click()
    wait_for(lambda: viewer.session.scene_name == name, 10.0, f"the session to load {name}")
    wait_for(
        lambda: (
            viewer.app.frames > 0 and viewer.app._generation == viewer.session.snapshot.generation
        ),
        5.0,
        "the rebuilt panels",
    )
    # a page without a GPU on a busy machine takes seconds to lay out a new machine's panels
    page.get_by_text(scenes.definition(name).description, exact=False).wait_for(timeout=30_000)


def test_the_chooser_lists_the_registry_and_switches_machines_both_ways(
    page: Page, viewer: Viewer
) -> None:
    assert scene_options(page) == sorted(scenes.MACHINES)
    assert {"gantry", "single_axis"} <= set(scenes.MACHINES)

    choose_scene(page, viewer, "single_axis")
    session = viewer.session
    assert viewer.app.model_scene is None
    page.get_by_text("no 3-D model").first.wait_for(timeout=5_000)
    unit = session.scene.axes["X"].config.unit
    page.get_by_text(f"Jog velocity [{unit}/s]").wait_for(timeout=5_000)
    page.get_by_text("Homing", exact=True).first.wait_for(timeout=5_000)
    (homing,) = [h for h in viewer.app._scene_inputs if getattr(h, "label", "") == "Homing"]
    assert "recipe" not in homing.options  # no recipe: index pulse or set position only

    page.get_by_role("button", name="Power", exact=True).click()
    wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")
    page.get_by_role("button", name="Run demo", exact=True).click()
    wait_for(lambda: session.snapshot.demo.running, 5.0, "the demo to start")
    wait_for(lambda: session.snapshot.demo.done, 20.0, "the single_axis demo to finish")
    page.get_by_text("Done", exact=True).wait_for(timeout=5_000)  # said once
    assert page.get_by_text("Done: done").count() == 0
    assert not session.snapshot.demo.error and not session.snapshot.fault

    choose_scene(page, viewer, "gantry")
    assert viewer.app.model_scene is not None
    for name in ("Power", "Home", "Jog+"):
        assert page.get_by_role("button", name=name, exact=True).count() == 1
    assert page.get_by_text("no 3-D model").count() == 0


def test_the_machine_definition_decides_what_the_panels_show(
    browser: Browser, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(scenes.MACHINES, SHEAR.name, SHEAR)
    port = _free_port()
    with Viewer(SHEAR.name, port=port, demo=False) as shear:
        context = browser.new_context(viewport={"width": 1280, "height": 1000})
        try:
            p = context.new_page()
            p.goto(shear.url)
            p.get_by_role("button", name="Reset", exact=True).wait_for(timeout=30_000)
            assert SHEAR.name in scene_options(p)
            # master: encoder only, unit m; no drive buttons
            p.get_by_text("encoder only").wait_for(timeout=5_000)
            p.get_by_text(re.compile(r"^\s*-?\d+\.\d+ m/s$")).wait_for(timeout=5_000)
            for name in ("Power", "Home", "Jog+", "Jog−", "Stop"):
                assert p.get_by_role("button", name=name, exact=True).count() == 0, name
            # signals panel: label with unit (no label given: the name, readable), value
            p.get_by_role("cell", name="cut force [N]").wait_for(timeout=5_000)
            # knife: unit deg, a drive, two digital outputs, only a REF switch, no recipe
            p.get_by_role("tab", name="knife", exact=True).click()
            p.get_by_text("Jog velocity [deg/s]").wait_for(timeout=5_000)
            for name in ("Power", "Jog+", "Jog−", "Stop"):
                assert p.get_by_role("button", name=name, exact=True).count() == 1, name
            (homing,) = [h for h in shear.app._scene_inputs if getattr(h, "label", "") == "Homing"]
            assert "recipe" not in homing.options
            knife = shear.app._axes["knife"].html
            assert "LIM+" not in knife  # the knife's panel (the overview has a LIM+ column)
            assert knife.count(">DO1<") + knife.count(" DO1<") == 1  # one output lamp
            p.get_by_text("DO1", exact=True).first.wait_for(timeout=5_000)
        finally:
            context.close()
    assert port_available("127.0.0.1", port)


# ------------------------------------------------------------------ commissioning (issue 12)


def test_a_page_of_another_origin_cannot_operate_anything(browser: Browser, viewer: Viewer) -> None:
    """A hostile page that even knows the token cannot open the websocket."""
    clients = len(viewer.server.get_clients())
    context = browser.new_context()
    try:
        p = context.new_page()
        hostile = (
            "<html><body><script>"
            f"const ws = new WebSocket('ws://127.0.0.1:{viewer.port}/?token={viewer.token}',"
            f" ['viser-v{viser.__version__}']);"
            "ws.onopen = () => { document.title = 'open'; };"
            "ws.onerror = () => { document.title = 'refused'; };"
            "</script></body></html>"
        )
        p.route(
            "http://attacker.example/",
            lambda route: route.fulfill(status=200, content_type="text/html", body=hostile),
        )
        p.goto("http://attacker.example/")
        p.wait_for_function("document.title !== ''", timeout=10_000)
        assert p.title() == "refused"
    finally:
        context.close()
    assert len(viewer.server.get_clients()) == clients


def test_one_operator_in_control_the_others_watch(
    browser: Browser, page: Page, viewer: Viewer
) -> None:
    session = viewer.session
    context = browser.new_context(viewport={"width": 1280, "height": 1000})
    try:
        other = context.new_page()
        other.goto(viewer.url)
        other.get_by_role("button", name="Power", exact=True).wait_for(timeout=120_000)
        owner = viewer.app.control.owner
        powered = session.snapshot.axes["X"].powered
        other.get_by_role("button", name="Power", exact=True).click()  # a watcher
        other.get_by_text("take control first").first.wait_for(timeout=10_000)
        assert session.snapshot.axes["X"].powered == powered
        assert viewer.app.control.owner == owner
        other.get_by_role("button", name="Request control", exact=True).click()
        page.get_by_role("button", name="Grant", exact=True).click()  # the operator hands over
        wait_for(lambda: viewer.app.control.owner not in (None, owner), 10.0, "the handover")
        newcomer = viewer.app.control.owner
        other.get_by_text("You are in control").wait_for(timeout=10_000)
        page.get_by_text(f"Watching — operator #{newcomer} in control").wait_for(timeout=10_000)
    finally:
        context.close()
    wait_for(lambda: viewer.app.control.owner is None, 10.0, "control to be freed on leaving")
    take_control(page, viewer)


def test_move_to_a_typed_position(page: Page, viewer: Viewer) -> None:
    session = viewer.session
    if not session.snapshot.axes["X"].powered:
        page.get_by_role("button", name="Power", exact=True).click()
        wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")
    start = session.scene.joint_position("X")
    box = page.get_by_label("Distance [mm]", exact=True)
    box.scroll_into_view_if_needed()
    box.fill("30")
    box.press("Enter")
    wait_for(
        lambda: any(
            getattr(h, "label", "") == "Distance [mm]" and h.value == 30.0
            for h in viewer.app._scene_inputs
        ),
        5.0,
        "the distance to arrive",
    )
    page.get_by_role("button", name="Move by", exact=True).click()
    wait_for(lambda: session.snapshot.axes["X"].message == "Move by: done", 10.0, "the move")
    moved = (session.scene.joint_position("X") - start) * 1e3
    assert moved == pytest.approx(30.0, abs=0.1)


def test_save_state_and_restore_state_bring_the_machine_back(page: Page, viewer: Viewer) -> None:
    session = viewer.session
    if not session.snapshot.axes["X"].powered:
        page.get_by_role("button", name="Power", exact=True).click()
        wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")
    wait_for(lambda: session.snapshot.axes["X"].state == "StandStill", 10.0, "X at rest")
    saved = session.scene.joint_position("X")  # ground truth [m]
    page.get_by_role("button", name="Save state", exact=True).click()
    wait_for(lambda: any("saved at" in e.text for e in session.snapshot.events), 5.0, "the save")
    session.requests("X").move(Move("relative", 40.0, 200.0, 2000.0))
    wait_for(
        lambda: (
            session.scene.joint_position("X") - saved > 0.0399
            and session.snapshot.axes["X"].state == "StandStill"
        ),
        10.0,
        "the move by 40 mm",
    )
    restore = page.get_by_role("button", name="Restore state", exact=True)
    restore.click()
    wait_for(lambda: any("restored" in e.text for e in session.snapshot.events), 5.0, "restore")
    assert abs(session.scene.joint_position("X") - saved) < 1e-4  # back, and held there
    wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X still powered")
    page.get_by_role("button", name="Power", exact=True).wait_for(timeout=30_000)


def test_stop_all_from_any_page_stops_the_axes(
    browser: Browser, page: Page, viewer: Viewer
) -> None:
    session = viewer.session
    session.requests("X").set_power(True)
    wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")
    context = browser.new_context(viewport={"width": 1280, "height": 1000})
    try:
        watcher = context.new_page()
        watcher.goto(viewer.url)
        stop = watcher.get_by_role("button", name="STOP all axes", exact=True)
        stop.wait_for(timeout=120_000)
        session.requests("X").move(Move("relative", 500.0, 100.0, 1000.0))
        wait_for(lambda: abs(session.snapshot.axes["X"].velocity) > 50.0, 5.0, "X to move")
        stop.click(timeout=120_000)  # the watcher has no control: STOP all works anyway
        wait_for(lambda: abs(session.snapshot.axes["X"].velocity) < 0.5, 5.0, "X to stop")
        x = session.scene.joint_position("X")
        time.sleep(0.3)
        assert abs(session.scene.joint_position("X") - x) < 1e-4
    finally:
        context.close()


def test_the_scope_exports_what_it_shows_as_csv(page: Page, viewer: Viewer) -> None:
    owner = viewer.app.control.owner
    mine = viewer.app.pages.get(owner) if owner is not None else None
    assert mine is not None and mine.scope is not None
    page.get_by_role("tab", name="History").click()
    button = page.get_by_role("button", name="Export CSV", exact=True)
    button.scroll_into_view_if_needed()
    with page.expect_download(timeout=15_000) as info:
        button.click()
    text = Path(info.value.path()).read_text()
    header, *lines = text.splitlines()
    time = "t [s] (every 2 ms)"  # the resolution of what is exported: every sample
    assert header.split(",") == [time, *mine.scope.recording.headers()] and len(lines) > 10
    t = [float(line.split(",")[0]) for line in lines]
    assert all(b > a for a, b in itertools.pairwise(t))


def test_ending_the_demo_leaves_a_usable_machine(page: Page, viewer: Viewer) -> None:
    session = viewer.session
    page.get_by_role("button", name="Run demo", exact=True).click()
    wait_for(lambda: bool(session.snapshot.groups), 120.0, "the demo to group the axes")
    assert session.snapshot.demo.running
    page.get_by_role("button", name="End demo", exact=True).click()
    wait_for(lambda: not session.snapshot.demo.running, 30.0, "the demo to end")
    wait_for(lambda: not session.snapshot.groups, 10.0, "the group to be released")
    x = session.snapshot.axes["X"]
    assert x.referenced and x.powered and x.group == ""
    start = session.scene.joint_position("X")
    page.get_by_role("button", name="Step+", exact=True).first.click()
    wait_for(lambda: "Move by" in session.snapshot.axes["X"].message, 10.0, "the step")
    wait_for(lambda: session.snapshot.axes["X"].message == "Move by: done", 10.0, "the step")
    assert (session.scene.joint_position("X") - start) * 1e3 == pytest.approx(1.0, abs=0.05)

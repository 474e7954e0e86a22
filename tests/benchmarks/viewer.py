"""Benchmark: the gantry with the browser viewer attached (30 Hz), ~2 × 10 s of wall time.

Prints JSON:

- ``realtime_factor``: simulated seconds per wall second while the demo runs (1.0: the viewer
  keeps up and does not slow the simulation);
- ``fps_achieved``: frames per second the server sent (poses, lamps), ``panel_hz_achieved``:
  refreshes per second of the axis panels, ``browser_fps``: frames per second the page drew
  (``requestAnimationFrame`` in headless Chromium, software WebGL), ``browser_panel_hz``: how
  often the page's status line changed in its DOM;
- ``frame_update_us``: wall time of one server frame;
- ``pacing``: simulated seconds per wall second of a bare session (no viewer) asked for 0.5×,
  3× and as fast as possible (``inf``), each over one wall second (the tests check the pacing
  on an injected clock; this is the real ratio);
- ``overlays``: the same figures (``realtime_factor``, ``fps_achieved``, ``panel_hz_achieved``,
  ``frame_update_us``, ``browser_fps``, ``browser_panel_hz``) for a second window with every
  view open: the set-point ghost and the contact forces shown, the cameras following the Z ram
  and the page's scope recording eight channels;
- ``visible``: from the click on *Step+* to the page's Position read-out moving by 0.01 u (the
  page's own clock), with the 3-D view (the gantry) and without one (``single_axis``), and the 3-D
  frame rate the viewer chose for the page (:mod:`viewer.view3d.renderer`);
- ``click_to_motion_ms``: from the click on *Step+* (Playwright's mouse click in the page) to the
  first motion of the X joint in the physics (1 µm), ``hold_to_motion_ms`` for holding *Jog−*,
  and ``request_to_motion_ms`` from the server-side request alone (PLC and servo pipeline);
  median, 90th percentile and max of several tries.

A headless Chromium (Playwright, ``/usr/bin/chromium``) is connected when available; without it
only the server-side figures are given.

Run: ``python -m tests.benchmarks.viewer [seconds]``; ``visible [CLICKS]`` gives the
click-to-visible figures alone, ``path [CLICKS]`` where a click's time goes
(:func:`path_breakdown`: each stage's delay after the one before, page and server on this
machine's wall clock).
"""

from __future__ import annotations

import json
import math
import os
import statistics
import sys
import time
from contextlib import ExitStack
from typing import TYPE_CHECKING, Any, cast

from plc.operator.hmi import Move
from viewer.serving.server import Viewer
from viewer.sim.session import Session

if TYPE_CHECKING:
    from playwright.sync_api import Page

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
TRIES = 5
"""Clicks (and holds) timed for the latency figures."""


def _connect_browser(stack: ExitStack, viewer: Viewer) -> Page | None:
    """Open the viewer in headless Chromium and take control; None if Playwright or Chromium
    is missing."""
    if not os.path.exists(CHROMIUM):
        return None
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        return None
    playwright = stack.enter_context(sync_playwright())
    browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    stack.callback(browser.close)
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.goto(viewer.url)
    page.get_by_role("button", name="Power", exact=True).wait_for(timeout=60_000)
    page.get_by_role("button", name="Take control", exact=True).click(timeout=120_000)
    deadline = time.monotonic() + 10.0
    while viewer.app.control.owner is None and time.monotonic() < deadline:
        time.sleep(0.01)
    return page


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def _browser_fps(page: Page, seconds: float = 2.0) -> float:
    """Frames per second the page draws (requestAnimationFrame callbacks)."""
    frames = page.evaluate(
        """(ms) => new Promise((done) => {
            let n = 0; const t0 = performance.now();
            const tick = () => {
                n += 1;
                if (performance.now() - t0 < ms) requestAnimationFrame(tick); else done(n);
            };
            requestAnimationFrame(tick);
        })""",
        seconds * 1000.0,
    )
    return float(frames) / seconds


def _browser_panel_hz(page: Page, seconds: float = 3.0) -> float:
    """Times per second the page's status line (simulated time) changes in the DOM."""
    changes = page.evaluate(
        """(ms) => new Promise((done) => {
            const all = Array.from(document.querySelectorAll('div'));
            const inner = all.reverse().find((e) => e.textContent.includes(' · t = '));
            if (!inner) { done(-1); return; }
            // the HTML element's content is replaced on each update: watch its container
            const line = inner.parentElement.parentElement;
            let n = 0; let last = line.textContent;
            const observer = new MutationObserver(() => {
                if (line.textContent !== last) { n += 1; last = line.textContent; }
            });
            observer.observe(line, {subtree: true, childList: true, characterData: true});
            setTimeout(() => { observer.disconnect(); done(n); }, ms);
        })""",
        seconds * 1000.0,
    )
    return float(changes) / seconds


def _wait_motion(viewer: Viewer, start: float, timeout: float = 5.0) -> float:
    """Wall time [s] when the X joint first moved 1 µm from ``start`` (NaN: it did not)."""
    deadline = time.perf_counter() + timeout
    while time.perf_counter() < deadline:
        if abs(viewer.session.scene.joint_position("X") - start) > 1e-6:
            return time.perf_counter()
        time.sleep(0.0005)
    return float("nan")


VISIBLE = """(timeout) => { window.__visible = new Promise((done) => {
    const value = () => {  // the panel's HTML is replaced at each refresh: look it up anew
        const cell = Array.from(document.querySelectorAll('td')).find(
            (td) => td.textContent.trim() === 'Position' && td.offsetParent !== null);
        return cell ? cell.nextElementSibling.textContent : '';
    };
    const number = () => parseFloat(value().replace('\u2212', '-'));
    let t0 = null; const before = number();
    const observer = new MutationObserver(() => {  // moved, not the last digit's flicker
        if (t0 !== null && Math.abs(number() - before) >= 0.01) {
            observer.disconnect(); done(performance.now() - t0);
        }
    });
    observer.observe(document.body, {subtree: true, childList: true, characterData: true});
    window.addEventListener('pointerdown', () => { t0 = performance.now(); },
                            {once: true, capture: true});
    setTimeout(() => { observer.disconnect(); done(null); }, timeout);
}); }"""
"""From the page's pointerdown to the shown axis' Position read-out moving by 0.01 u [ms] (in
the page's own clock; the last digit's flicker at standstill is no motion; null: no change
within ``timeout``)."""


def _visible_latency(
    page: Page, viewer: Viewer, axis: str = "X", tries: int = TRIES
) -> dict[str, Any]:
    """Click (Step+) to visible motion on the page: its Position read-out changes [ms]."""
    session = viewer.session
    session.requests(axis).set_power(True)
    while not session.snapshot.axes[axis].powered:
        time.sleep(0.01)
    step = page.get_by_role("button", name="Step+", exact=True).first
    step.scroll_into_view_if_needed()
    delays: list[float] = []
    for _ in range(tries):
        time.sleep(0.5)  # standing still
        box = step.bounding_box()
        assert box is not None
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        page.evaluate(VISIBLE, 5000)
        page.mouse.down()
        page.mouse.up()
        delay = page.evaluate("() => window.__visible")
        delays.append(float("nan") if delay is None else float(delay))
    return _summary(delays)


PAGE_MARKS = """(timeout) => { window.__marks = new Promise((done) => {
    const value = () => {
        const cell = Array.from(document.querySelectorAll('td')).find(
            (td) => td.textContent.trim() === 'Position' && td.offsetParent !== null);
        return cell ? cell.nextElementSibling.textContent : '';
    };
    const number = () => parseFloat(value().replace('\u2212', '-'));
    const epoch = () => performance.timeOrigin + performance.now();
    let down = null; const before = number();
    const queued = []; const drained = [];  // the viewer's message queue: batches in, out
    const queue = window.__viserMutable ? window.__viserMutable.messageQueue : null;
    if (queue) {
        queue.push = function (...items) {
            if (down !== null) queued.push(epoch());
            return Array.prototype.push.apply(this, items);
        };
        queue.splice = function (...args) {
            if (down !== null) drained.push(epoch());
            return Array.prototype.splice.apply(this, args);
        };
    }
    const observer = new MutationObserver(() => {
        if (down !== null && Math.abs(number() - before) >= 0.01) {
            observer.disconnect();
            if (queue) { delete queue.push; delete queue.splice; }
            done([down, epoch(), queued, drained]);
        }
    });
    observer.observe(document.body, {subtree: true, childList: true, characterData: true});
    window.addEventListener('pointerdown', () => { down = epoch(); },
                            {once: true, capture: true});
    setTimeout(() => { observer.disconnect(); done(null); }, timeout);
}); }"""
"""The page's pointerdown and its Position read-out's first change by 0.01 u, in epoch ms."""

PATH_STAGES = (
    "callback",
    "taken",
    "motion",
    "published",
    "panel_sent",
    "arrived",
    "applied",
    "shown",
)
"""The marks along a click's path after the page's pointerdown: the server's button callback,
the PLC scan that took the move, the X joint's first motion (1 µm), the first published
snapshot whose position moved by 0.01 u, the axis panel's HTML sent with it, the first batch of
messages in the page's queue after it, the queue drained, the page's read-out changed."""


def _path_marks(page: Page, viewer: Viewer, tries: int, axis: str = "X") -> dict[str, Any]:
    """Where a click's time goes: each stage's delay after the one before [ms] (median, p90,
    max over ``tries`` Step+ clicks; wall clock of this machine, shared by page and server)."""
    import threading

    session, app = viewer.session, viewer.app
    session.requests(axis).set_power(True)
    while not session.snapshot.axes[axis].powered:
        time.sleep(0.01)
    requests = session.requests(axis)
    panel = app._axes[axis]  # the benchmark watches the panel it clicks
    marks: dict[str, float] = {}
    original_move, original_take, original_show = requests.move, requests.take, panel.show

    def move(value: Any) -> None:
        marks.setdefault("callback", time.time() * 1e3)
        original_move(value)

    def take() -> Any:
        taken = original_take()
        if taken.move is not None:
            marks.setdefault("taken", time.time() * 1e3)
        return taken

    def show(view: Any) -> None:
        original_show(view)
        start = marks.get("start_position")
        if start is not None and abs(view.position - start) >= 0.01:
            marks.setdefault("panel_sent", time.time() * 1e3)

    watched = cast(Any, requests), cast(Any, panel)
    watched[0].move, watched[0].take, watched[1].show = move, take, show
    step = page.get_by_role("button", name="Step+", exact=True).first
    step.scroll_into_view_if_needed()
    rows: list[dict[str, float]] = []
    for _ in range(tries):
        time.sleep(0.5)
        marks.clear()
        joint0 = session.scene.joint_position(axis)
        marks["start_position"] = session.snapshot.axes[axis].position
        stop = threading.Event()

        def watch(joint0: float = joint0, stop: threading.Event = stop) -> None:
            while not stop.is_set():
                moved = abs(session.scene.joint_position(axis) - joint0) > 1e-6
                if "motion" not in marks and moved:
                    marks["motion"] = time.time() * 1e3
                position = session.snapshot.axes[axis].position
                if "published" not in marks and abs(position - marks["start_position"]) >= 0.01:
                    marks["published"] = time.time() * 1e3
                time.sleep(0.0005)

        watcher = threading.Thread(target=watch, daemon=True)
        watcher.start()
        box = step.bounding_box()
        assert box is not None
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        page.evaluate(PAGE_MARKS, 5000)
        page.mouse.down()
        page.mouse.up()
        shown = page.evaluate("() => window.__marks")
        stop.set()
        watcher.join()
        if shown is None:
            continue
        marks["down"], marks["shown"] = float(shown[0]), float(shown[1])
        sent = marks.get("panel_sent")
        if sent is not None:  # the first message in the page's queue after the panel was sent
            arrived = [t for t in shown[2] if t >= sent - 1.0]
            if arrived:
                marks["arrived"] = arrived[0]
                applied = [t for t in shown[3] if t >= arrived[0]]
                if applied:
                    marks["applied"] = applied[0]
        rows.append(dict(marks))
    watched[0].move, watched[0].take, watched[1].show = original_move, original_take, original_show
    result: dict[str, Any] = {}
    previous = "down"
    for stage in PATH_STAGES:
        delays = [r[stage] - r[previous] for r in rows if stage in r and previous in r]
        result[f"{previous}->{stage}"] = _summary(delays)
        previous = stage
    result["total"] = _summary([r["shown"] - r["down"] for r in rows])
    return result


def path_breakdown(fps: float = 30.0, tries: int = TRIES) -> dict[str, Any]:
    """:func:`_path_marks` with the 3-D view (the gantry) and without one (``single_axis``)."""
    result: dict[str, Any] = {"fps_asked": fps, "load": os.getloadavg()[0]}
    for scene, key in (("gantry", "with_3d"), ("single_axis", "without_3d")):
        with ExitStack() as stack:
            viewer = Viewer(scene, port=0, demo=False, fps=fps)
            stack.callback(viewer.close)
            page = _connect_browser(stack, viewer)
            if page is None:
                return {}
            time.sleep(2.0)  # the page has reported its renderer
            result[key] = _path_marks(page, viewer, tries)
    return result


def visible_latencies(fps: float = 30.0, tries: int = TRIES) -> dict[str, Any]:
    """Click-to-visible-motion [ms] in headless Chromium with the 3-D view (the gantry) and
    without one (``single_axis``), the viewer asked for ``fps``, over ``tries`` clicks; and the
    3-D frame rate it chose for the page (lower where the page draws in software)."""
    result: dict[str, Any] = {"fps_asked": fps, "load": os.getloadavg()[0]}
    for scene, key in (("gantry", "with_3d"), ("single_axis", "without_3d")):
        with ExitStack() as stack:
            viewer = Viewer(scene, port=0, demo=False, fps=fps)
            stack.callback(viewer.close)
            page = _connect_browser(stack, viewer)
            if page is None:
                return {}
            time.sleep(2.0)  # the page has reported its renderer
            result[key] = {
                "click_to_visible_ms": _visible_latency(page, viewer, tries=tries),
                "fps_chosen": viewer.app.renderers.fps,
                "renderer": viewer.app.renderers.renderer(viewer.app.control.owner or 0),
            }
    return result


def _latencies(page: Page, viewer: Viewer) -> dict[str, Any]:
    """Click-to-motion (Step+) and hold-to-motion (Jog−) latencies [ms]."""
    session = viewer.session
    session.requests("X").set_power(True)
    while not session.snapshot.axes["X"].powered:
        time.sleep(0.01)
    clicks: list[float] = []
    holds: list[float] = []
    step = page.get_by_role("button", name="Step+", exact=True).first
    step.scroll_into_view_if_needed()
    jog = page.get_by_role("button", name="Jog−", exact=True).first  # back towards the start
    for _ in range(TRIES):
        time.sleep(0.5)  # standing still
        start = session.scene.joint_position("X")
        box = step.bounding_box()
        assert box is not None
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        t0 = time.perf_counter()
        page.mouse.down()
        page.mouse.up()
        clicks.append((_wait_motion(viewer, start) - t0) * 1e3)
    for _ in range(TRIES):
        time.sleep(0.5)
        start = session.scene.joint_position("X")
        jog.scroll_into_view_if_needed()
        box = jog.bounding_box()
        assert box is not None
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        t0 = time.perf_counter()
        page.mouse.down()
        holds.append((_wait_motion(viewer, start) - t0) * 1e3)
        time.sleep(0.2)
        page.mouse.up()
    return {"click_to_motion_ms": _summary(clicks), "hold_to_motion_ms": _summary(holds)}


def _request_to_motion(viewer: Viewer) -> dict[str, Any]:
    """From a Step request set by the server (what a click's callback does) to the first motion
    of the X joint [ms]: the PLC and servo pipeline alone, without the browser."""
    session = viewer.session
    session.requests("X").set_power(True)
    while not session.snapshot.axes["X"].powered:
        time.sleep(0.01)
    delays: list[float] = []
    for k in range(TRIES):
        time.sleep(0.5)
        start = session.scene.joint_position("X")
        t0 = time.perf_counter()
        session.requests("X").move(Move("relative", (-1.0) ** k, 100.0, 1000.0))
        delays.append((_wait_motion(viewer, start) - t0) * 1e3)
    return _summary(delays)


def _summary(delays: list[float]) -> dict[str, Any]:
    """Median, 90th percentile and max [ms] of the tries that moved, and how many did not."""
    moved = [d for d in delays if math.isfinite(d)]
    return {
        "median": round(statistics.median(moved), 1) if moved else None,
        "p90": round(_percentile(moved, 0.9), 1) if moved else None,
        "max": round(max(moved), 1) if moved else None,
        "tries": len(delays),
        "no_motion": len(delays) - len(moved),
    }


def _frame_costs(viewer: Viewer) -> dict[str, Any]:
    """Median and 95th percentile [µs] of the server's recent frames."""
    costs_us = [c * 1e6 for c in viewer.app.frame_costs]
    return {
        "median": round(statistics.median(costs_us), 1) if costs_us else None,
        "p95": round(_percentile(costs_us, 0.95), 1) if costs_us else None,
        "frames": len(costs_us),
    }


def _overlays(viewer: Viewer, page: Page | None, seconds: float) -> dict[str, Any]:
    """Frame rate, panel rate and cost with every view open (the demo still running), over
    ``seconds``: the ghost and contacts shown, the cameras following the ram, and each page's
    scope recording its first eight channels over twice ``seconds``."""
    session, app = viewer.session, viewer.app
    app.show_ghost = app.show_contacts = True
    app.follow = "gantry/ram"
    channels = [c.name for c in session.recorder.channels if not c.digital][:8]
    for open_page in app.pages.all():
        if open_page.scope is not None:
            open_page.scope.capture(channels, session.snapshot.time, 2.0 * seconds, pre=0.0)
    time.sleep(0.5)  # the ghost is built on the first frame
    app.frame_costs.clear()
    frames0, panels0 = app.frames, app.panel_updates
    sim0, wall0 = session.snapshot.time, time.monotonic()
    browser_fps = _browser_fps(page, min(seconds, 3.0)) if page is not None else None
    browser_panel_hz = _browser_panel_hz(page, min(seconds, 3.0)) if page is not None else None
    time.sleep(max(seconds - (time.monotonic() - wall0), 0.0))
    frames, panels, sim, wall = (
        app.frames,
        app.panel_updates,
        session.snapshot.time,
        time.monotonic(),
    )
    costs = _frame_costs(viewer)
    app.show_ghost = app.show_contacts = False
    app.follow = "off"
    elapsed = wall - wall0
    return {
        "realtime_factor": round((sim - sim0) / elapsed, 4),
        "fps_achieved": round((frames - frames0) / elapsed, 2),
        "panel_hz_achieved": round((panels - panels0) / elapsed, 2),
        "browser_fps": None if browser_fps is None else round(browser_fps, 1),
        "browser_panel_hz": None if browser_panel_hz is None else round(browser_panel_hz, 1),
        "frame_update_us": costs,
        "scope_channels": len(channels),
    }


def _pacing(seconds: float = 1.0) -> dict[str, float]:
    """Simulated seconds per wall second of the gantry session (no viewer) at 0.5×, 3× and as
    fast as possible, each over ``seconds`` of wall time."""
    ratios = {}
    for speed in (0.5, 3.0, math.inf):
        with Session("gantry", speed=speed) as session:
            time.sleep(0.2)  # the thread has started and caught up
            sim0, wall0 = session.scene.time, time.monotonic()
            time.sleep(seconds)
            sim, wall = session.scene.time, time.monotonic()
        ratios[str(speed)] = round((sim - sim0) / (wall - wall0), 3)
    return ratios


def run(seconds: float = 10.0) -> dict[str, Any]:
    """Run the gantry demo at 1× with the viewer (and a browser) attached for ``seconds``, then
    time clicks and holds."""
    with ExitStack() as stack:
        viewer = Viewer("gantry", port=0, speed=1.0, demo=False, fps=30.0)
        stack.callback(viewer.close)
        page = _connect_browser(stack, viewer)
        session, app = viewer.session, viewer.app
        session.reset()  # start the demo on a fresh scene, after the page has loaded
        while session.snapshot.time > 0.1:
            time.sleep(0.01)
        session.start_demo()
        app.frame_costs.clear()
        frames0, panels0 = app.frames, app.panel_updates
        sim0, wall0 = session.snapshot.time, time.monotonic()
        browser_fps = _browser_fps(page, min(seconds, 3.0)) if page is not None else None
        browser_panel_hz = _browser_panel_hz(page, min(seconds, 3.0)) if page is not None else None
        time.sleep(max(seconds - (time.monotonic() - wall0), 0.0))
        snapshot = session.snapshot
        frames, panels, sim, wall = app.frames, app.panel_updates, snapshot.time, time.monotonic()
        costs = _frame_costs(viewer)
        overlays = _overlays(viewer, page, seconds)
        session.end_demo()
        latency = {"request_to_motion_ms": _request_to_motion(viewer)}
        if page is not None:
            latency.update(_latencies(page, viewer))
    elapsed = wall - wall0
    return {
        "scene": "gantry",
        "speed": 1.0,
        "browser_connected": page is not None,
        "wall_s": round(elapsed, 3),
        "simulated_s": round(sim - sim0, 3),
        "realtime_factor": round((sim - sim0) / elapsed, 4),
        "fps_target": 30.0,
        "fps_achieved": round((frames - frames0) / elapsed, 2),
        "panel_hz_achieved": round((panels - panels0) / elapsed, 2),
        "browser_fps": None if browser_fps is None else round(browser_fps, 1),
        "browser_panel_hz": None if browser_panel_hz is None else round(browser_panel_hz, 1),
        "frame_update_us": costs,
        "overlays": overlays,
        **latency,
        "demo_step_at_end": snapshot.demo.step,
        "visible": visible_latencies(),
        "pacing": _pacing(),
    }


if __name__ == "__main__":
    if sys.argv[1:2] == ["visible"]:  # the click-to-visible figures alone: visible [TRIES]
        tries = int(sys.argv[2]) if len(sys.argv) > 2 else TRIES
        print(json.dumps(visible_latencies(tries=tries), indent=2))
    elif sys.argv[1:2] == ["path"]:  # where a click's time goes: path [TRIES]
        tries = int(sys.argv[2]) if len(sys.argv) > 2 else TRIES
        print(json.dumps(path_breakdown(tries=tries), indent=2))
    else:
        print(json.dumps(run(float(sys.argv[1]) if len(sys.argv) > 1 else 10.0), indent=2))

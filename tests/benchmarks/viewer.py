"""Benchmark: the gantry demo at 1× with the browser viewer attached (30 Hz), ~10 s of wall time.

Prints JSON: the achieved real-time factor (simulated seconds per wall second; 1.0 means the
viewer keeps up and does not slow the simulation), the wall time of one viewer frame (poses,
switch colours, and every third frame the panels and the plot) in µs, and the frame rate achieved.
A headless Chromium (Playwright, ``/usr/bin/chromium``) is connected when available, so that the
server really sends every message to a client.

Run: ``python -m tests.benchmarks.viewer [seconds]``.
"""

from __future__ import annotations

import json
import os
import socket
import statistics
import sys
import time
from contextlib import ExitStack
from typing import Any

from viewer.app import Viewer

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
    return port


def _connect_browser(stack: ExitStack, url: str) -> bool:
    """Open the viewer in headless Chromium; False if Playwright or Chromium is missing."""
    if not os.path.exists(CHROMIUM):
        return False
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        return False
    playwright = stack.enter_context(sync_playwright())
    browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    stack.callback(browser.close)
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.goto(url)
    page.get_by_role("button", name="Power", exact=True).wait_for(timeout=30_000)
    return True


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def run(seconds: float = 10.0) -> dict[str, Any]:
    """Run the gantry demo at 1× with the viewer (and a browser) attached for ``seconds``."""
    with ExitStack() as stack:
        viewer = Viewer("gantry", port=_free_port(), speed=1.0, demo=False, fps=30.0)
        stack.callback(viewer.close)
        browser = _connect_browser(stack, viewer.url)
        session, app = viewer.session, viewer.app
        session.reset()  # start the demo on a fresh scene, after the page has loaded
        while session.snapshot.time > 0.1:
            time.sleep(0.01)
        session.start_demo()
        app.frame_costs.clear()
        frames0, sim0, wall0 = app.frames, session.snapshot.time, time.monotonic()
        time.sleep(seconds)
        snapshot = session.snapshot
        frames, sim, wall = app.frames, snapshot.time, time.monotonic()
        costs_us = [c * 1e6 for c in app.frame_costs]
    elapsed = wall - wall0
    return {
        "scene": "gantry",
        "speed": 1.0,
        "browser_connected": browser,
        "wall_s": round(elapsed, 3),
        "simulated_s": round(sim - sim0, 3),
        "realtime_factor": round((sim - sim0) / elapsed, 4),
        "fps_target": 30.0,
        "fps_achieved": round((frames - frames0) / elapsed, 2),
        "frame_update_us": {
            "median": round(statistics.median(costs_us), 1) if costs_us else None,
            "p95": round(_percentile(costs_us, 0.95), 1) if costs_us else None,
            "frames": len(costs_us),
        },
        "demo_step_at_end": snapshot.demo.step,
    }


if __name__ == "__main__":
    print(json.dumps(run(float(sys.argv[1]) if len(sys.argv) > 1 else 10.0), indent=2))

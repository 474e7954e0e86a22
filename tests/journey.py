"""A user's journey through the viewer, every registered machine: ``make journey``.

Starts the viewer in a process of its own on a free loopback port and drives headless Chromium
(1280×800) through each machine of ``scenes.MACHINES`` as a new user would: choose it in the
chooser, take control, run the demo twice (the second run must start and end), home one axis and
move it, provoke an error (a move beyond the software limit, or a move of an axis without power)
and reset it, and open each view (the all-axes overview, the scope, the cam view where the
machine cams an axis, the Watch tab, the camera presets). Every step writes a screenshot to the
output folder (``.build/journey/`` unless ``--out`` says otherwise) for a person to look at; the
folder is printed at the end.

It waits for what the page shows (a demo's step, an axis' message), never for a fixed time, and
fails with one clear message when the page logs an error to its console, a demo does not run
twice, a view draws no series, or a camera preset draws an empty 3-D view.

Run: ``python -m tests.journey [--out DIR] [--machines a,b] [--speed S]`` (about 2 minutes per
machine on two cores).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from playwright.sync_api import Error as PlaywrightError
from playwright.sync_api import TimeoutError as PlaywrightTimeout

import scenes
from viewer.view3d.renderer import is_software

if TYPE_CHECKING:
    from playwright.sync_api import ConsoleMessage, Locator, Page, ViewportSize

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / ".build" / "journey"
"""Where the screenshots go unless told otherwise."""
VIEWPORT: ViewportSize = {"width": 1280, "height": 800}
"""The page's size [CSS px]: a laptop's screen."""
DOCS_IMAGES = ROOT / "docs" / "images"
"""Where ``--docs`` writes the documentation's pictures."""
DOCS_LIMIT = 150_000
"""Bytes a documentation picture may take."""
README_MACHINE = "gantry"
"""The machine of the README's picture."""
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
INTO_THE_DEMO = 4
"""Steps of its demo a machine goes through before its picture is taken."""
START_TIMEOUT = 120.0
"""Seconds the viewer process may take to print its address."""
LOAD_TIMEOUT = 120_000
"""Milliseconds a page (or a new machine's panels) may take to appear on a busy machine."""
STEP_TIMEOUT = 180_000
"""Milliseconds an axis command may take to end (a drum homing at half real time: a minute)."""
SHOT_TIMEOUT = 180_000
"""Milliseconds a screenshot may take (a page busy drawing in software waits for a frame)."""
DEMO_TIMEOUT = 300_000
"""Milliseconds one demo run may take."""

RENDERER = """() => {
    const gl = document.createElement('canvas').getContext('webgl');
    const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
    return gl ? String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER)) : '';
}"""
"""The page's WebGL renderer."""

CHARTS = """() => Object.values(window.__viserTestpoints?.uplots ?? {}).map((u) => {
    const data = u.chart.data ?? [];
    const finite = data.slice(1).map((s) => Array.from(s ?? []).filter(
        (v) => v !== null && Number.isFinite(v)).length);
    const root = u.chart.root;
    const box = root ? root.getBoundingClientRect() : null;
    return {
        series: u.chart.series.slice(1).map((s) => s.label ?? ""),
        points: data.length ? data[0].length : 0,
        finite: finite,
        visible: Boolean(box && box.width > 0 && box.height > 0 && root.offsetParent !== null),
    };
})"""
"""The uPlot charts of the page (viser's test points): their series and points."""


class JourneyError(AssertionError):
    """What the journey found wrong, in one sentence a person can act on."""


@dataclass
class Chart:
    """A uPlot chart read from the page."""

    series: list[str]
    points: int
    finite: list[int]
    """Finite values of each series."""
    visible: bool

    @property
    def drawn(self) -> list[str]:
        """The series with at least two finite points (a line)."""
        return [s for s, n in zip(self.series, self.finite, strict=False) if n >= 2]


def charts_drawing_nothing(charts: Sequence[Chart]) -> list[Chart]:
    """The visible charts that draw no series (no series has two finite points)."""
    return [c for c in charts if c.visible and not c.drawn]


BLANK = 0.98
"""Share of a 3-D view's pixels in one colour above which it draws nothing (the background)."""

OPEN_PART = (0.1, 0.125, 0.9, 0.75)
"""The part of the 3-D view no floating window or button covers (left, top, right, bottom as
fractions of its box): the Operator window floats over its lower left."""


def blank(picture: bytes) -> bool:
    """Whether a screenshot (PNG) of the 3-D view is one colour in its :data:`OPEN_PART` but
    for less than 1 - :data:`BLANK` of the pixels: the camera sees nothing of the machine."""
    import io

    from PIL import Image

    with Image.open(io.BytesIO(picture)) as image:
        w, h = image.size
        left, top, right, bottom = OPEN_PART
        part = image.convert("RGB").crop(
            (int(left * w), int(top * h), int(right * w), int(bottom * h))
        )
    colours = part.getcolors(part.width * part.height) or []
    most = max((count for count, _ in colours), default=0)
    return most > BLANK * part.width * part.height


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free on ``host`` now."""
    with socket.socket() as sock:
        sock.bind((host, 0))
        port: int = sock.getsockname()[1]
    return port


URL = re.compile(r"\bat (http://\S+)")
"""The address the viewer prints when it serves."""


def viewer_url(line: str) -> str | None:
    """The address in the viewer's start line (None: not that line)."""
    match = URL.search(line)
    return match.group(1) if match else None


@contextmanager
def viewer_process(
    scene: str, speed: str = "1", fps: str | None = None, demo: bool = False
) -> Iterator[str]:
    """The viewer (``python -m viewer``) on a free loopback port in a process of its own,
    without demo unless ``demo``; yields its address and stops it (SIGTERM) at the end.

    Raises:
        JourneyError: If it exits or prints no address within :data:`START_TIMEOUT`.
    """
    port = free_port()
    command = [sys.executable, "-m", "viewer", "--scene", scene, "--port", str(port)]
    command += (
        ["--speed", speed] + (["--fps", fps] if fps else []) + ([] if demo else ["--no-demo"])
    )
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    process = subprocess.Popen(
        command, cwd=ROOT, env=env, stdout=subprocess.PIPE, text=True, bufsize=1
    )
    try:
        yield _read_url(process)
    finally:
        process.terminate()
        try:
            process.wait(20.0)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def _read_url(process: subprocess.Popen[str]) -> str:
    """The address the viewer process prints first."""
    assert process.stdout is not None
    deadline = time.monotonic() + START_TIMEOUT
    lines: list[str] = []
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if not line:
            break
        lines.append(line)
        url = viewer_url(line)
        if url is not None:
            return url
    raise JourneyError(
        f"the viewer printed no address within {START_TIMEOUT:g} s (exit status "
        f"{process.poll()}): {''.join(lines)[-500:]!r}"
    )


@dataclass
class Console:
    """The errors the page logs to its console (and its uncaught exceptions)."""

    errors: list[str] = field(default_factory=list)

    def hear(self, message: ConsoleMessage) -> None:
        if message.type == "error":
            self.errors.append(message.text)

    def uncaught(self, error: Exception) -> None:
        self.errors.append(f"uncaught: {error}")

    def check(self, where: str) -> None:
        """Raises JourneyError naming the console errors logged so far (at ``where``)."""
        if self.errors:
            shown = "; ".join(e[:200] for e in self.errors[:5])
            raise JourneyError(
                f"{len(self.errors)} console error(s) by {where}: {shown}"
                + (" …" if len(self.errors) > 5 else "")
            )


@dataclass(frozen=True)
class Plan:
    """What the journey does on one machine."""

    machine: str
    axis: str
    """The axis to home, move and drive into an error (a driven one)."""
    target: float | None
    """A Move to target beyond the axis' software limit [user unit] (None: no limits; the
    error is a move of the axis without power)."""


def plan(name: str) -> Plan:
    """The journey on machine ``name``: its first driven axis with a homing recipe (else its
    first driven one) and a target 10 % of the travel beyond its positive software limit."""
    definition = scenes.definition(name)
    parts = [(part.machine.name + "/", part.machine) for part in definition.parts]
    axes = [
        (prefix + axis, spec)
        for prefix, machine in (parts or [("", definition)])
        for axis, spec in machine.axes.items()
        if spec.drive != "encoder"
    ]
    if not axes:
        raise JourneyError(f"{name} has no driven axis to operate")
    homeable = [(axis, spec) for axis, spec in axes if spec.homing is not None]
    axis, spec = (homeable or axes)[0]
    constants = spec.constants
    high, low = (constants.LimPos, constants.LimNeg) if constants is not None else (0.0, 0.0)
    target = None
    if math.isfinite(high) and math.isfinite(low) and high > low:
        target = round(high + 0.1 * (high - low), 3)
    return Plan(name, axis, target)


class Journey:
    """One page of the viewer driven through the machines, a screenshot per step.

    Args:
        page: The page (its console watched from here on).
        out: The screenshots' folder.
    """

    def __init__(self, page: Page, out: Path, shots: list[Path] | None = None) -> None:
        self.page, self.out = page, out
        page.set_default_timeout(STEP_TIMEOUT)  # a click on a loaded machine: not 30 s
        self.console = Console()
        page.on("console", self.console.hear)
        page.on("pageerror", self.console.uncaught)
        self.shots: list[Path] = [] if shots is None else shots
        """The screenshots so far (shared by the pages of one journey)."""
        self.machine = ""

    def shot(self, step: str) -> Path:
        """A screenshot of the whole page: ``NN-machine-step.png``."""
        path = self.out / f"{len(self.shots) + 1:02d}-{self.machine}-{step}.png"
        self.page.screenshot(path=path, timeout=SHOT_TIMEOUT)
        self.shots.append(path)
        return path

    def button(self, name: str) -> Locator:
        return self.page.get_by_role("button", name=name, exact=True).locator("visible=true")

    def text(self, pattern: str | re.Pattern[str]) -> Locator:
        return self.page.get_by_text(pattern).locator("visible=true").first

    def open(self, url: str) -> None:
        """Load the page until its panels are there; where it draws in software, wait for its
        line saying so (shown where the machine has a 3-D model) and close viser's own notice
        about it, as a user would."""
        self.page.goto(url)
        chooser = self.page.get_by_role("combobox", name="Scene", exact=True)
        chooser.wait_for(timeout=LOAD_TIMEOUT)
        if is_software(self.page.evaluate(RENDERER)):
            if scenes.definition(chooser.input_value()).model:
                line = self.page.get_by_text("No GPU (software WebGL)").first
                line.wait_for(timeout=LOAD_TIMEOUT)
            notice = self.page.locator(".mantine-Notification-root", has_text="Software WebGL")
            notice.first.wait_for(timeout=LOAD_TIMEOUT)
            notice.first.locator("button").first.click()

    # ------------------------------------------------------------------------- steps

    def choose(self, name: str) -> None:
        """Pick the machine in the chooser; wait for its status line and its axis tabs."""
        self.machine = name
        chooser = self.page.get_by_role("combobox", name="Scene", exact=True)
        for attempt in range(3):  # a busy page may close the list before the click lands
            chooser.scroll_into_view_if_needed()
            chooser.click()
            try:
                self.page.get_by_role("option", name=name, exact=True).click(timeout=15_000)
                break
            except PlaywrightTimeout:
                self.page.keyboard.press("Escape")
                if attempt == 2:
                    raise JourneyError(f"the chooser did not offer {name}") from None
        status = re.compile(rf"^{re.escape(name)} · t = ")
        self.page.get_by_text(status).first.wait_for(timeout=LOAD_TIMEOUT)
        self.page.get_by_text(scenes.definition(name).description).first.wait_for(
            timeout=LOAD_TIMEOUT
        )
        self.shot("chosen")

    def take_control(self) -> None:
        """Take control unless this page has it (choosing a machine needs it, too)."""
        if self.page.get_by_text("You are in control").count() == 0:
            self.button("Take control").click()
            self.page.get_by_text("You are in control").first.wait_for(timeout=STEP_TIMEOUT)

    def demo_twice(self) -> None:
        """Run the demo, and when it is done run it again until it is done again.

        Raises:
            JourneyError: If a run stops with an error or does not end in time.
        """
        for run in (1, 2):
            self.button("Run demo").click()
            self._wait_demo("Step: ", run, "start")
            if run == 1:
                self._into_the_demo()
                self.shot("demo-running")
                self.check_charts("the scope while the demo runs")
            self._wait_demo("Done", run, "end", cam=run == 1)
            self.shot(f"demo-{run}-done")

    def _wait_demo(self, prefix: str, run: int, what: str, cam: bool = False) -> None:
        """Wait until the demo box reads ``prefix`` (a demo error fails); with ``cam``, look at
        the cam view the first time the demo cams an axis."""
        looked = False
        demo = self.page.get_by_text(re.compile(r"^(Step: |Done\b|Ended at: )|^Not started\.$"))
        timeout = STEP_TIMEOUT if what == "start" else DEMO_TIMEOUT
        deadline = time.monotonic() + timeout / 1000.0
        while time.monotonic() < deadline:
            texts = [t.strip() for t in demo.all_inner_texts()]
            if any(t.startswith(prefix) for t in texts):
                return
            if cam and not looked:
                looked = self._look_at_cam()
            errors = self._demo_errors()
            if errors:
                self.shot(f"demo-{run}-failed")
                raise JourneyError(f"{self.machine}: the demo's run {run} failed: {errors[0]}")
            self.page.wait_for_timeout(200)
        self.shot(f"demo-{run}-stuck")
        raise JourneyError(
            f"{self.machine}: the demo's run {run} did not {what} within {timeout / 1000:g} s "
            f"(the demo box reads {demo.all_inner_texts()!r})"
        )

    def _demo_errors(self) -> list[str]:
        """The demo box's red text (what stopped the demo), if any."""
        boxes = self.page.locator("span[style*='#c62828']").locator("visible=true")
        texts = [t.strip() for t in boxes.all_inner_texts()]
        return [t for t in texts if t and not t.startswith("stopped")]

    def _into_the_demo(self, steps: int = INTO_THE_DEMO) -> None:
        """Wait until the demo has gone through ``steps`` steps (or ended): the machine moves."""
        demo = self.page.get_by_text(re.compile(r"^(Step: |Done\b|Ended at: )"))
        seen: list[str] = []
        deadline = time.monotonic() + DEMO_TIMEOUT / 1000.0
        while len(seen) < steps and time.monotonic() < deadline:
            texts = [t.strip() for t in demo.all_inner_texts()]
            step = texts[0] if texts else ""
            if not step.startswith("Step: "):
                return
            if step not in seen:
                seen.append(step)
            self.page.wait_for_timeout(100)

    def _look_at_cam(self) -> bool:
        """The cam view, if it is shown (an axis is cammed): its charts draw, a screenshot."""
        cam = self.page.get_by_text("Cam", exact=True).locator("visible=true")
        if not cam.count():
            return False
        cam.first.scroll_into_view_if_needed()
        self.check_charts("the cam view while the demo runs")
        self.shot("view-cam")
        self.page.get_by_text("All axes", exact=True).first.scroll_into_view_if_needed()
        return True

    def check_charts(self, what: str) -> list[Chart]:
        """Wait until every visible chart draws a series.

        Raises:
            JourneyError: If a visible chart draws none within 30 s.
        """
        deadline = time.monotonic() + 30.0
        while True:
            charts = self.charts()
            empty = charts_drawing_nothing(charts)
            if charts and not empty:
                return charts
            if time.monotonic() > deadline:
                self.shot("no-series")
                shown = [c.series for c in empty] or "no chart at all"
                raise JourneyError(f"{self.machine}: {what} draws no series: {shown}")
            self.page.wait_for_timeout(250)

    def charts(self) -> list[Chart]:
        raw: list[dict[str, Any]] = self.page.evaluate(CHARTS)
        return [Chart(c["series"], c["points"], c["finite"], c["visible"]) for c in raw]

    def axis_tab(self, axis: str) -> None:
        """Show the axis' tab in the Axes folder."""
        tab = self.page.get_by_role("tab", name=axis, exact=True)
        if tab.count():
            tab.first.click()

    def axis_field(self, axis: str, label: str) -> Locator:
        return self.page.get_by_label(label, exact=True).locator("visible=true").first

    def home_and_move(self, axis: str) -> None:
        """Power the axis, home it, move it by its Distance; each waits for its ``done``."""
        self.axis_tab(axis)
        self._power(True)
        self.button("Home").first.click()
        self._wait_message("Home: done")
        self.shot(f"{_slug(axis)}-homed")
        move = self.button("Move by").first
        move.scroll_into_view_if_needed()
        move.click()
        self._wait_message("Move by: done")
        self.shot(f"{_slug(axis)}-moved")

    def _power(self, on: bool) -> None:
        state = self.page.locator("td", has_text=re.compile(r"^State$")).locator("visible=true")
        state.first.wait_for(timeout=STEP_TIMEOUT)
        disabled = "Disabled" in self._axis_text()
        if disabled == on:
            self.button("Power").first.click()
            deadline = time.monotonic() + STEP_TIMEOUT / 1000.0
            while ("Disabled" in self._axis_text()) == on:
                if time.monotonic() > deadline:
                    raise JourneyError(f"{self.machine}: Power did not switch the axis {on}")
                self.page.wait_for_timeout(100)

    def _axis_text(self) -> str:
        """The read-outs of the axis panel shown."""
        panel = self.page.locator("div", has=self.page.locator("[data-text='Error']")).locator(
            "visible=true"
        )
        return panel.last.inner_text() if panel.count() else ""

    def _wait_message(self, text: str) -> None:
        """Wait until the shown axis panel's message reads ``text`` (an error fails)."""
        deadline = time.monotonic() + STEP_TIMEOUT / 1000.0
        while text not in self._axis_text():
            if time.monotonic() > deadline:
                self.shot("stuck")
                raise JourneyError(
                    f"{self.machine}: no {text!r} within {STEP_TIMEOUT / 1000:g} s; the axis "
                    f"panel reads {self._axis_text()[-300:]!r}"
                )
            self.page.wait_for_timeout(100)

    def provoke_error(self, journey: Plan) -> None:
        """A move beyond the software limit (or of an axis without power), then Reset: the
        error shows, and Reset clears it."""
        self.axis_tab(journey.axis)
        if journey.target is not None:
            target = self.axis_field(journey.axis, _label(self._axis_text(), "Target"))
            target.fill(f"{journey.target:g}")
            target.press("Enter")
            self.page.wait_for_timeout(300)  # the value travels to the server
            self.button("Move to").first.click()
        else:
            self._power(False)
            self.button("Move by").first.click()
        deadline = time.monotonic() + STEP_TIMEOUT / 1000.0
        while not re.search(r"Error: (?!—)|Refused:", self._axis_text()):
            if time.monotonic() > deadline:
                self.shot("no-error")
                raise JourneyError(f"{self.machine}: the provoked error does not show")
            self.page.wait_for_timeout(100)
        self.shot(f"{_slug(journey.axis)}-error")
        self.button("Reset").first.click()
        deadline = time.monotonic() + STEP_TIMEOUT / 1000.0
        while "Error: —" not in self._axis_text():
            if time.monotonic() > deadline:
                self.shot("reset-stuck")
                raise JourneyError(f"{self.machine}: Reset did not clear the error")
            self.page.wait_for_timeout(100)
        self.shot(f"{_slug(journey.axis)}-reset")

    def views(self) -> None:
        """Each view: the overview and the scope (their charts draw), the Watch tab, the camera
        presets of the View folder (where the machine has a 3-D model)."""
        self.page.get_by_role("tab", name="Axes and scope").first.click()
        self.check_charts("the scope")
        self.shot("view-overview-scope")
        self.page.get_by_role("tab", name="Watch").first.click()
        self.shot("view-watch")
        self.page.get_by_role("tab", name="Axes and scope").first.click()
        folder = self.page.get_by_text("View", exact=True).locator("visible=true")
        if not folder.count():
            return  # no 3-D model, no View folder
        folder.first.scroll_into_view_if_needed()
        folder.first.click()
        for name in ("Front", "Side", "Top", "Fit"):
            self.button(name).first.click()
            picture = self.settle()
            self.shot(f"view-{name.lower()}")
            if blank(picture):
                raise JourneyError(f"{self.machine}: the {name} camera preset draws an empty view")

    def settle(self, timeout: float = 10.0) -> bytes:
        """Wait until the 3-D canvas draws the same picture twice (a camera move is animated);
        the picture (PNG)."""
        canvas = self.page.locator("canvas").first
        deadline = time.monotonic() + timeout
        last = canvas.screenshot()
        while time.monotonic() < deadline:
            self.page.wait_for_timeout(200)
            picture = canvas.screenshot()
            if picture == last:
                return picture
            last = picture
        return last

    def picture(self, name: str) -> None:
        """Machine ``name`` chosen, its demo a few steps in: the documentation's picture."""
        self.take_control()
        self.choose(name)
        self.button("Run demo").click()
        self._wait_demo("Step: ", 1, "start")
        self._into_the_demo()
        self.shot("demo-running")
        self.console.check(f"{name}'s demo")

    def machine_journey(self, name: str) -> None:
        """Everything on machine ``name``."""
        journey = plan(name)
        self.take_control()
        self.choose(name)
        self.console.check(f"choosing {name}")
        self.demo_twice()
        self.console.check(f"{name}'s demo")
        self.home_and_move(journey.axis)
        self.provoke_error(journey)
        self.console.check(f"{name}'s axis {journey.axis}")
        self.views()
        self.console.check(f"{name}'s views")


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_")


def _label(panel: str, field: str) -> str:
    """The label of a number field: ``Target [mm]`` (the unit from the panel's Position)."""
    match = re.search(r"Position\s+\S+\s+(\S+)", panel)
    unit = match.group(1) if match else ""
    return f"{field} [{unit}]" if unit else field


def optimise(shot: Path, target: Path, limit: int = DOCS_LIMIT) -> int:
    """Write ``shot`` as a small PNG at ``target`` (the same size, fewer colours until it is at
    most ``limit`` bytes); returns its size [bytes]."""
    from PIL import Image

    target.parent.mkdir(parents=True, exist_ok=True)
    with Image.open(shot) as image:
        rgb = image.convert("RGB")
    for colours in (256, 128, 64, 32, 16):
        rgb.quantize(colors=colours, dither=Image.Dither.NONE).save(target, optimize=True)
        if target.stat().st_size <= limit:
            break
    return target.stat().st_size


def publish(shots: Sequence[Path], docs: Path = DOCS_IMAGES) -> list[Path]:
    """The documentation's pictures from a journey's screenshots: each machine's running demo
    (``machines/NAME.png``) and the gantry's as the README's (``viewer.png``)."""
    written = []
    for shot in shots:
        match = re.fullmatch(r"\d+-(\w+)-demo-running\.png", shot.name)
        if match is None:
            continue
        name = match.group(1)
        targets = [docs / "machines" / f"{name}.png"]
        if name == README_MACHINE:
            targets.append(docs / "viewer.png")
        for target in targets:
            optimise(shot, target)
            written.append(target)
    return written


def run(out: Path, machines: Sequence[str], speed: str = "1", pictures: bool = False) -> list[Path]:
    """The journey through ``machines``, each in a page of its own opened anew (as a new user
    would; the camera a page was turned to stays with it); with ``pictures`` only each
    machine's picture (:meth:`Journey.picture`). Returns the screenshots.

    Raises:
        JourneyError: What went wrong (the screenshots so far are kept).
    """
    from playwright.sync_api import sync_playwright

    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("*.png"):
        old.unlink()
    first = [m for m in sorted(scenes.MACHINES) if m not in machines][:1] or [machines[-1]]
    with viewer_process(first[0], speed) as url, sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        shots: list[Path] = []
        try:
            for name in machines:
                context = browser.new_context(viewport=VIEWPORT)
                journey = Journey(context.new_page(), out, shots)
                journey.open(url)
                if pictures:
                    journey.picture(name)
                else:
                    journey.machine_journey(name)
                context.close()
        finally:
            browser.close()
    return shots


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests.journey", description=__doc__)
    parser.add_argument("--out", type=Path, default=OUT, help=f"screenshots' folder ({OUT})")
    parser.add_argument("--machines", default="", help="comma-separated (default: all)")
    parser.add_argument("--speed", default="1", help="the simulation's speed (default 1)")
    parser.add_argument(
        "--pictures",
        action="store_true",
        help="only each machine's picture, its demo a few steps in (with --docs: quicker)",
    )
    parser.add_argument(
        "--docs",
        action="store_true",
        help=f"also write the documentation's pictures to {DOCS_IMAGES.relative_to(ROOT)}",
    )
    args = parser.parse_args(argv)
    machines = [m for m in args.machines.split(",") if m] or sorted(scenes.MACHINES)
    unknown = [m for m in machines if m not in scenes.MACHINES]
    if unknown:
        parser.error(f"unknown machine(s) {unknown}; known: {sorted(scenes.MACHINES)}")
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))  # clean up
    started = time.monotonic()
    try:
        shots = run(args.out, machines, args.speed, args.pictures)
    except (JourneyError, PlaywrightError) as exc:
        print(f"journey FAILED: {exc}\nscreenshots so far: {args.out}", file=sys.stderr)
        return 1
    if args.docs:
        for picture in publish(shots):
            print(f"{picture.relative_to(ROOT)}: {picture.stat().st_size // 1000} kB")
    print(
        f"journey passed: {len(machines)} machine(s), {len(shots)} screenshots in "
        f"{time.monotonic() - started:.0f} s: {args.out}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

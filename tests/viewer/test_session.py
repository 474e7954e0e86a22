"""The viewer without a browser: the simulation session, the operator program, the app, the CLI.

Most tests drive the session synchronously (``Session.advance``) with a fake wall clock, so the
jog dead-man deadline and everything else is deterministic. The pacing and pause/step tests run
the simulation thread for real and assert loosely.
"""

from __future__ import annotations

import dataclasses
import errno
import http.client
import itertools
import logging
import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from functools import partial
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
import viser
import viser.infra

import mcl
import mcl.faults
import scenes
import viewer.__main__ as cli
import viewer.pages.app as app_module
from plc.operator.hmi import DEADMAN, Move
from scenes.scene import Scene
from tests.helpers import ROOT, run_coroutine
from viewer.pages.app import LAMP_LIMIT, LAMP_REF, ViewerApp
from viewer.pages.panels import axis_panel_html, results_html, signals_html
from viewer.scope.panel import SINGLE, PageScope
from viewer.serving.security import LOG_BURST, REFUSED_MESSAGES, AccessPolicy, BoundedLog
from viewer.serving.server import DEFAULT_HOST, PortInUseError, Viewer, port_available
from viewer.sim.session import SCOPE_SECONDS, Session, choices
from viewer.sim.snapshot import RESULTS_SHOWN, AxisView

ROOT = ROOT


CAMERA = {
    "wxyz": [1.0, 0.0, 0.0, 0.0],
    "position": [2.0, -2.0, 2.0],
    "fov": 1.0,
    "near": 0.01,
    "far": 100.0,
    "image_height": 600,
    "image_width": 800,
    "look_at": [0.0, 0.0, 0.0],
    "up_direction": [0.0, 0.0, 1.0],
}
"""The camera a page reports when it opens (a ViewerCameraMessage's fields)."""


class FakeClock:
    """A wall clock the test moves by hand [s]; with ``tick`` > 0 it also moves on by that much
    each time it is read."""

    def __init__(self) -> None:
        self.now = 100.0
        self.tick = 0.0

    def __call__(self) -> float:
        now = self.now
        self.now += self.tick
        return now


class StandInDemo:
    """A demo program: power X, move it 20 mm (relative: no reference needed), done."""

    def __init__(self, scene: Scene) -> None:
        self.X = scene.axes["X"]
        self.power = mcl.MC_Power()
        self.move = mcl.MC_MoveRelative()
        self.step = "power on"
        self.done = False
        self.error = ""

    def __call__(self) -> None:
        self.power(Axis=self.X, Enable=True)
        self.move(
            Axis=self.X,
            Execute=self.power.Status,
            Distance=20.0,
            Velocity=200.0,
            Acceleration=2000.0,
            Deceleration=2000.0,
            Jerk=50000.0,
        )
        if self.power.Status and not self.done:
            self.step = "move X to 20 mm"
        if self.move.Done:
            self.step, self.done = "done", True


class FailingDemo:
    """A demo program with a bug."""

    def __init__(self, scene: Scene) -> None:
        self.step = "about to fail"
        self.done = False
        self.error = ""

    def __call__(self) -> None:
        raise ZeroDivisionError("division by zero in the demo")


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def session(clock: FakeClock) -> Session:
    """The gantry, not running (driven by :func:`run`)."""
    return Session("gantry", clock=clock, demo=StandInDemo)


def run(
    session: Session, clock: FakeClock, seconds: float, jog: tuple[str, int] | None = None
) -> None:
    """Advance simulated time and the fake wall clock together (1×), in 50 ms chunks;
    ``jog = (axis, direction)`` holds a jog button meanwhile (refreshed every chunk)."""
    plc = session.scene.runtime.plc_period
    chunk = 25
    for _ in range(round(seconds / (chunk * plc))):
        if jog is not None:
            session.requests(jog[0]).jog(jog[1])
        session.advance(chunk)
        clock.now += chunk * plc


def view(session: Session, axis: str = "X") -> AxisView:
    return session.snapshot.axes[axis]


def wait_for(condition: Callable[[], bool], timeout: float = 5.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.005)


# ------------------------------------------------------------------------------------ pacing


@pytest.mark.parametrize("speed", [0.5, 3.0])
def test_simulated_time_follows_speed_times_wall_time(speed: float) -> None:
    """The simulation thread paced by the session's (here: fake) wall clock: moved on in 10 ms
    steps for a second, simulated time catches up to within one PLC cycle of speed × elapsed
    wall time, never ahead of it, and the snapshot's realtime_factor reads the speed. (The
    real ratio on a real clock is measured by ``python -m tests.benchmarks.viewer``.)"""
    clock = FakeClock()
    wall0 = clock.now
    with Session("gantry", speed=speed, clock=clock) as session:
        plc = session.scene.runtime.plc_period
        for _ in range(100):  # one second of wall time
            clock.now += 0.01
            due = speed * (clock.now - wall0)
            wait_for(partial(lambda t: session.scene.time >= t, due - plc), timeout=30.0)
            assert session.scene.time <= due + 1e-9, "ahead of the wall clock"
        factor = session.snapshot.realtime_factor
    assert factor == pytest.approx(speed, rel=0.05)


def test_as_fast_as_possible_outruns_the_wall_clock() -> None:
    """At speed inf the simulation does not wait for the wall clock at all: with the (fake)
    clock standing still it runs half a simulated second."""
    clock = FakeClock()
    with Session("gantry", speed=1.0, clock=clock) as session:
        session.speed = math.inf
        wait_for(lambda: math.isinf(session.snapshot.speed), timeout=30.0)
        sim0, wall0 = session.scene.time, clock.now
        wait_for(lambda: session.scene.time > sim0 + 0.5, timeout=60.0)
        assert clock.now == wall0
        clock.tick = 0.001  # let the clock run again, so that the thread can stop


def test_speed_must_be_positive(session: Session) -> None:
    with pytest.raises(ValueError, match="speed must be > 0"):
        session.speed = 0.0
    with pytest.raises(ValueError, match="speed must be > 0"):
        Session("gantry", speed=-1.0)


def test_pause_single_step_and_resume() -> None:
    with Session("gantry", paused=True) as session:
        plc = session.scene.runtime.plc_period
        time.sleep(0.1)
        assert session.snapshot.paused and session.snapshot.time == 0.0

        session.step()
        wait_for(lambda: session.snapshot.time > 0.0)
        assert session.snapshot.time == pytest.approx(plc)
        time.sleep(0.1)
        assert session.snapshot.time == pytest.approx(plc)  # still paused

        session.step(3)
        wait_for(lambda: session.snapshot.time > 1.5 * plc)
        assert session.snapshot.time == pytest.approx(4 * plc)

        session.resume()
        wait_for(lambda: session.snapshot.time > 0.05)
        assert not session.snapshot.paused
        session.pause()
        wait_for(lambda: session.snapshot.paused)
        paused_at = session.snapshot.time
        time.sleep(0.1)
        assert session.snapshot.time == paused_at
    assert not session.running


def test_reset_rebuilds_the_scene(session: Session, clock: FakeClock) -> None:
    session.requests("X").set_power(True)
    run(session, clock, 0.1)
    run(session, clock, 0.5, jog=("X", 1))
    assert view(session).joint_position > 0.01
    generation, old_scene = session.snapshot.generation, session.scene

    session.reset()
    snapshot = session.snapshot
    assert snapshot.generation == generation + 1
    assert session.scene is not old_scene
    assert snapshot.time == 0.0
    assert view(session).joint_position == 0.0
    assert not view(session).powered and view(session).power_request is None


def test_unknown_scene_names_the_valid_ones(session: Session) -> None:
    with pytest.raises(KeyError, match="gantry"):
        session.load("no_such_scene")
    with pytest.raises(KeyError, match="axes"):
        session.requests("Q")


# ------------------------------------------------------------------ operator requests → FBs


def test_power_button_switches_the_drive_through_mc_power(
    session: Session, clock: FakeClock
) -> None:
    operator = session.operator.axes["X"]
    session.toggle_power("X")
    run(session, clock, 0.05)
    assert operator.power.Status and view(session).state == "StandStill"
    session.toggle_power("X")
    run(session, clock, 0.05)
    assert not operator.power.Status and view(session).state == "Disabled"


def test_jog_runs_while_held_and_stops_when_the_deadman_runs_out(
    session: Session, clock: FakeClock
) -> None:
    requests = session.requests("X")
    requests.set_power(True)
    requests.jog_velocity = 50.0
    run(session, clock, 0.05)

    run(session, clock, 1.0, jog=("X", 1))
    moving = view(session)
    assert moving.jogging == 1 and moving.state == "ContinuousMotion"
    assert moving.velocity == pytest.approx(50.0, rel=0.05)
    assert moving.joint_position > 0.03

    # No more hold messages (button released, tab closed): the request dies after DEADMAN.
    run(session, clock, DEADMAN + 0.3)
    stopped = view(session)
    assert stopped.jogging == 0 and stopped.state == "StandStill"
    run(session, clock, 0.2)
    assert view(session).joint_position == pytest.approx(stopped.joint_position, abs=1e-6)

    run(session, clock, 0.5, jog=("X", -1))
    assert view(session).velocity < -40.0
    requests.release_jog()  # a click (the release) ends the jog at once
    run(session, clock, 0.05)
    assert view(session).jogging == 0


def test_jog_without_power_is_refused_by_gt_jog_and_nothing_moves(
    session: Session, clock: FakeClock
) -> None:
    run(session, clock, 0.5, jog=("X", 1))
    operator = session.operator.axes["X"]
    assert operator.jog.Error and operator.jog.ErrorID == mcl.ErrorID.Epower == 10
    assert "error 10" in view(session).message
    assert view(session).joint_position == 0.0
    assert not session.scene.data.ctrl.any()  # the amplifiers never got a volt


def test_stop_holds_the_axis_until_done_then_releases(session: Session, clock: FakeClock) -> None:
    requests = session.requests("X")
    requests.set_power(True)
    run(session, clock, 0.05)
    run(session, clock, 0.5, jog=("X", 1))
    requests.release_jog()
    requests.stop()
    session.advance(1)
    assert view(session).stopping and view(session).state == "Stopping"
    run(session, clock, 0.5)
    operator = session.operator.axes["X"]
    assert not operator.stopping and not operator.stop.Execute
    assert view(session).state == "StandStill"
    assert view(session).message == "Stop: done"


def test_reset_clears_a_limit_switch_error() -> None:
    clock = FakeClock()
    session = Session("gantry", clock=clock, overrides={"start": {"X": 0.99}})
    requests = session.requests("X")
    requests.set_power(True)
    run(session, clock, 0.05)
    run(session, clock, 0.5, jog=("X", 1))
    failed = view(session)
    assert failed.lim_pos and failed.state == "ErrorStop"
    assert failed.error_id == mcl.ErrorID.ERRLIP
    assert failed.error == mcl.error_text(mcl.ErrorID.ERRLIP)

    run(session, clock, DEADMAN + 0.1)
    requests.reset()
    run(session, clock, 0.1)
    cleared = view(session)
    assert cleared.state == "StandStill" and cleared.error_id == 0 and cleared.error == ""
    assert cleared.message == "Reset: done"


def test_home_reaches_the_reference_on_the_gantry(session: Session, clock: FakeClock) -> None:
    requests = session.requests("X")
    requests.set_power(True)
    run(session, clock, 0.05)
    requests.home()
    run(session, clock, 0.05)
    assert view(session).homing and view(session).state == "Homing"
    for _ in range(200):
        run(session, clock, 0.05)
        if not view(session).homing:
            break
    homed = view(session)
    assert homed.message == "Home: done" and homed.referenced
    # The recipe makes the coordinate equal the joint coordinate (index pulse at 120 mm).
    assert homed.position == pytest.approx(homed.joint_position * 1000.0, abs=0.01)


def test_home_drives_the_press_ram_to_its_top_stop_and_sets_the_reference(
    clock: FakeClock,
) -> None:
    from scenes.machines.press import BLOCK_HOMING

    session = Session("press", clock=clock)
    requests = session.requests("R")
    requests.set_power(True)
    run(session, clock, 0.05)
    requests.home()  # the press's recipe: to the block
    for _ in range(200):
        run(session, clock, 0.05)
        if not view(session, "R").homing:
            break
    assert view(session, "R").message == "Home: done"
    run(session, clock, 0.5)  # the ram sags onto the stop, the integral action lifts it clear
    homed = view(session, "R")
    assert homed.referenced and homed.state == "StandStill"
    assert homed.position == pytest.approx(BLOCK_HOMING.set_position, abs=0.015)
    # held clear of the top stop (joint coordinate 0) by about the in-position window
    assert 0.02 < homed.joint_position * 1000.0 < 0.1


# ------------------------------------------------------------------------------- the demo


def test_demo_runs_and_a_power_press_takes_the_machine_back(
    session: Session, clock: FakeClock
) -> None:
    assert session.demo_available()
    session.requests("X").set_power(False)  # the operator's MC_Power would fight the demo...
    session.start_demo()  # ...so starting the demo hands power back to it
    assert view(session).power_request is None
    scene = session.scene
    start = scene.joint_position("X") * scene.scales["X"]  # the physics [mm]
    run(session, clock, 0.05)
    assert session.snapshot.demo.running and session.snapshot.demo.step == "move X to 20 mm"
    run(session, clock, 1.0)
    demo = session.snapshot.demo
    assert demo.done and demo.step == "done" and not demo.running
    moved = scene.joint_position("X") * scene.scales["X"] - start
    assert moved == pytest.approx(20.0, abs=0.01), "the carriage moved by the demo's 20 mm"
    assert view(session).position == pytest.approx(20.0, abs=0.01)

    session.start_demo()
    run(session, clock, 0.05)
    session.toggle_power("X")  # the operator intervenes: the demo ends, the drive goes off
    run(session, clock, 0.05)
    assert not session.snapshot.demo.running
    assert view(session).state == "Disabled"


def test_a_failing_demo_is_reported_and_the_simulation_goes_on(clock: FakeClock) -> None:
    session = Session("gantry", clock=clock, demo=FailingDemo)
    session.start_demo()
    run(session, clock, 0.1)
    demo = session.snapshot.demo
    assert not demo.running and "ZeroDivisionError" in demo.error
    assert session.snapshot.time == pytest.approx(0.1)


class ErrorReportingDemo:
    """A demo program that reports a function block error through ``error``, as
    ``python -m scenes run`` expects (it then stops)."""

    def __init__(self, scene: Scene) -> None:
        self.step, self.done, self.error = "move", False, ""
        self.calls = 0

    def __call__(self) -> None:
        self.calls += 1
        if self.calls == 3:
            self.error = "move: MC_MoveAbsolute error 10"


def test_a_demo_that_reports_an_error_ends_and_shows_it(clock: FakeClock) -> None:
    programs: list[ErrorReportingDemo] = []

    def factory(scene: Scene) -> ErrorReportingDemo:
        programs.append(ErrorReportingDemo(scene))
        return programs[-1]

    session = Session("single_axis", clock=clock, demo=factory)
    session.start_demo()
    run(session, clock, 0.1)
    demo = session.snapshot.demo
    assert not demo.running and not demo.done and demo.step == "move"
    assert demo.error == "move: MC_MoveAbsolute error 10"
    assert programs[0].calls == 3  # not called after it reported the error


@pytest.mark.skipif(
    scenes.definition("gantry").demo is None, reason="the gantry has no demo program yet"
)
def test_the_gantry_demo_starts(clock: FakeClock) -> None:
    session = Session("gantry", clock=clock)
    session.start_demo()
    run(session, clock, 0.5)
    demo = session.snapshot.demo
    assert demo.running and demo.step and not demo.error
    assert all(v.powered for v in session.snapshot.axes.values())


def test_the_scope_recorder_holds_the_last_seconds_of_every_channel(
    session: Session, clock: FakeClock
) -> None:
    session.requests("X").set_power(True)
    run(session, clock, 9.0)
    run(session, clock, 2.0, jog=("X", 1))
    t, values = session.recorder.series()
    names = [c.name for c in session.recorder.channels]
    assert values.shape == (len(names), t.size) and t.size > 100
    assert np.all(np.diff(t) > 0.0)
    assert 10.5 < t[-1] - t[0] <= 11.0 + 1e-9  # all of it: the ring holds SCOPE_SECONDS
    assert session.recorder.ring.length * np.median(np.diff(t)) >= SCOPE_SECONDS
    assert t[-1] <= session.snapshot.time
    volts = values[names.index("X command")]
    assert volts[-1] > 1.0  # jogging at 100 mm/s needs ~1 V
    position = values[names.index("X position")]
    assert position[-1] - position[0] > 100.0  # the jog, in mm


# ------------------------------------------------------------------------------- the app


def rgb(color: tuple[float, float, float]) -> tuple[int, int, int]:
    r, g, b = (round(c * 255.0) for c in color)
    return (r, g, b)


def test_panels_answer_a_state_change_within_a_frame_then_keep_their_rate(
    server: viser.ViserServer, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A click's move shows on the axis panel a frame (33 ms) after its state changed, not a
    panel period later; a machine whose states stay as they are refreshes at the panel rate."""
    wall = FakeClock()
    monkeypatch.setattr(app_module, "time", SimpleNamespace(monotonic=wall, perf_counter=wall))
    app = ViewerApp(session, server, fps=30.0, panel_hz=12.0)

    def frames(seconds: float) -> list[float]:
        """Frames at 30 Hz, each with a new snapshot; the wall times of panel refreshes."""
        refreshed = []
        for _ in range(round(seconds * 30)):
            before = app.panel_updates
            session.advance(5)
            app.frame()
            if app.panel_updates > before:
                refreshed.append(wall.now)
            wall.now += 1 / 30
        return refreshed

    frames(1.0)  # settled: standstill, no state changes
    steady = frames(1.0)
    assert 9 <= len(steady) <= 13  # the panel rate (12 Hz, on frames of 30 Hz: every third)
    session.requests("X").set_power(True)
    answered = frames(0.3)
    assert view(session).powered
    assert len(answered) >= 7  # every frame of the 0.25 s after the change
    assert max(b - a for a, b in itertools.pairwise(answered[:7])) < 0.04
    later = frames(1.0)
    assert len(later) <= 13


def test_the_prompt_refresh_ends_0_25_s_after_the_last_state_change(
    server: viser.ViserServer, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    """At 8 frames/s with panels at 4 Hz: every frame refreshes the panels in the 0.25 s after
    an axis' state, ErrorID or power last changed; the frame 0.25 s after it is back at the
    panel rate (0.125 s since the last refresh: not yet due). Times in eighths of a second,
    exact in binary."""
    wall = FakeClock()
    monkeypatch.setattr(app_module, "time", SimpleNamespace(monotonic=wall, perf_counter=wall))
    app = ViewerApp(session, server, fps=8.0, panel_hz=4.0)
    states: list[tuple[Any, ...]] = []
    refreshed: list[bool] = []
    times: list[float] = []
    for k in range(16):
        if k == 2:
            session.requests("X").set_power(True)
        before = app.panel_updates
        session.advance(5)
        app.frame()
        axes = session.snapshot.axes.values()
        states.append(tuple((a.state, a.error_id, a.powered) for a in axes))
        refreshed.append(app.panel_updates > before)
        times.append(wall.now)
        wall.now += 0.125
    assert view(session).powered
    changed = max(k for k in range(1, 16) if states[k] != states[k - 1])
    assert changed <= 12
    assert all(refreshed[changed : changed + 2])  # 0 and 0.125 s after the change
    assert times[changed + 2] - times[changed] == app_module.PROMPT_S
    assert not refreshed[changed + 2]  # 0.25 s after: the prompt is over, 4 Hz not yet due
    assert refreshed[changed + 3]  # 0.25 s after the last refresh


def test_switch_geoms_light_up_from_the_plant_inputs(server: viser.ViserServer) -> None:
    session = Session("gantry", overrides={"start": {"X": 1.007}})  # beyond the LIM+ trip
    app = ViewerApp(session, server)
    app.frame()
    scene = app.model_scene
    assert scene is not None
    model_color = scene.geom_handle("gantry/X_lim_neg_geom").color
    assert view(session).lim_pos and not view(session).ref
    assert scene.geom_handle("gantry/X_lim_pos_geom").color == rgb(LAMP_LIMIT)
    assert scene.geom_handle("gantry/X_ref_geom").color != rgb(LAMP_REF)
    assert view(session, "Y").ref
    assert scene.geom_handle("gantry/Y_ref_geom").color == rgb(LAMP_REF)
    assert model_color not in (rgb(LAMP_LIMIT), rgb(LAMP_REF))


def test_the_app_follows_relocated_bodies_and_rebuilds_on_reset(
    server: viser.ViserServer, session: Session
) -> None:
    app = ViewerApp(session, server)
    app.frame()
    model = session.scene.model
    body = model.body("gantry/X_obstacle").id
    assert app.model_scene is not None
    frame = app.model_scene.body_handles["gantry/X_obstacle"]
    parked = frame.position.copy()
    blocking = model.numeric("gantry/X_obstacle_blockpos").data + np.array([0.3, 0.0, 0.0])
    model.body_pos[body] = blocking
    session.advance(1)
    app.frame()
    np.testing.assert_allclose(frame.position, session.scene.data.xpos[body])
    assert np.linalg.norm(frame.position - parked) > 0.1

    old = app.model_scene
    session.reset()
    app.frame()
    assert app.model_scene is not old
    assert app.frames == 3


def test_the_page_offers_no_code_execution_and_no_file_access(
    monkeypatch: pytest.MonkeyPatch, server: viser.ViserServer, session: Session
) -> None:
    sent: list[str] = []
    original = viser.infra.WebsockServer.queue_message

    def spy(self: viser.infra.WebsockServer, message: viser.infra.Message) -> None:
        sent.append(type(message).__name__)
        original(self, message)

    monkeypatch.setattr(viser.infra.WebsockServer, "queue_message", spy)
    app = ViewerApp(session, server)
    app.frame()
    gui = {name for name in sent if name.startswith("Gui")}
    allowed = {
        "GuiFolderMessage",
        "GuiHtmlMessage",
        "GuiDropdownMessage",
        "GuiButtonMessage",
        "GuiNumberMessage",
        "GuiPanelMessage",
        "GuiSetPanelPositionMessage",
        "GuiSetPanelWidthMessage",
        "GuiTabGroupMessage",
        "GuiSliderMessage",
        "GuiUplotMessage",
        "GuiUpdateMessage",
        "GuiRemoveMessage",
    }
    assert gui <= allowed, f"unexpected GUI elements: {gui - allowed}"

    # No public share tunnel, no uploads, whatever a client sends.
    handlers = server._websock_server._incoming_handlers
    assert not {type_.__name__ for type_ in handlers} & set(REFUSED_MESSAGES)
    assert {"ShareUrlRequest", "FileTransferStartUpload"} <= set(REFUSED_MESSAGES)

    # Texts from the simulation are escaped, never interpreted as markup.
    hostile = dataclasses.replace(
        view(session), error="<script>alert(1)</script>", message="<img src=x onerror=alert(1)>"
    )
    page = axis_panel_html(hostile)
    assert "<script>" not in page and "<img" not in page

    # The HTTP server only hands out the viewer's client files.
    connection = http.client.HTTPConnection("127.0.0.1", server.get_port(), timeout=5)
    for path in ("/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/pyproject.toml"):
        connection.request("GET", path)
        response = connection.getresponse()
        response.read()
        assert response.status == 404, path
    connection.close()


# ------------------------------------------------------------------ machines from the registry

SHEAR = scenes.MachineDef(
    name="viewer_test_shear",
    description="test machine: encoder-only master, rotary knife with a digital output",
    axes={
        "master": scenes.AxisDef(
            config=mcl.AxisConfig(resolution=1e-6, dev_max=0.002, in_position=1e-5, unit="m"),
            drive="encoder",
            unit="m",
            switches=(),
            sim=mcl.SimAxisParams(has_drive=False, start=0.0),
        ),
        "knife": scenes.AxisDef(
            config=mcl.AxisConfig(resolution=1e-6 * 180.0 / math.pi, unit="deg"),
            constants=mcl.ServoConstants(Kp=3.0, Ki=150.0, Ff=1.0, Kc=50.0, Vmax=28.6, Filter=2.0),
            unit="deg",
            scale=180.0 / math.pi,
            switches=("ref",),
            digital_outputs=2,
            sim=mcl.SimAxisParams(start=0.2, digital_outputs=2),
        ),
    },
    signals={
        "cut_force": scenes.Signal("N", lambda scene: 1000.0 * scene.joint_position("knife")),
        "broken": scenes.Signal("bar", lambda scene: 1.0 / 0.0),
    },
)
"""A machine only these tests register: what its definition says decides what the viewer shows."""


@pytest.fixture
def shear(monkeypatch: pytest.MonkeyPatch, clock: FakeClock) -> Session:
    """A session of :data:`SHEAR`, registered for this test only."""
    monkeypatch.setitem(scenes.MACHINES, SHEAR.name, SHEAR)
    return Session(SHEAR.name, clock=clock)


def scenes_list() -> list[str]:
    """The machine names ``python -m scenes list`` prints."""
    output = subprocess.run(
        [sys.executable, "-m", "scenes", "list"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    ).stdout
    return [line.split()[0] for line in output.splitlines() if line.strip()]


def test_the_chooser_lists_the_machines_of_python_m_scenes_list(
    server: viser.ViserServer, session: Session
) -> None:
    listed = scenes_list()
    assert listed == sorted(scenes.MACHINES) == choices()
    assert {"gantry", "single_axis"} <= set(listed)
    app = ViewerApp(session, server)
    assert list(app.scene_choices) == listed
    assert cli.parser().get_default("scene") in listed


def test_a_registered_machine_is_offered_without_viewer_code(
    monkeypatch: pytest.MonkeyPatch, server: viser.ViserServer, session: Session
) -> None:
    monkeypatch.setitem(scenes.MACHINES, SHEAR.name, SHEAR)
    assert SHEAR.name in choices()
    assert SHEAR.name in ViewerApp(session, server).scene_choices
    assert cli.parser().parse_args(["--scene", SHEAR.name]).scene == SHEAR.name


def test_single_axis_runs_its_demo_to_done_without_a_model(clock: FakeClock) -> None:
    session = Session("single_axis", clock=clock)
    snapshot = session.snapshot
    assert snapshot.model is None and snapshot.xpos.shape == (0, 3)
    assert snapshot.description == scenes.definition("single_axis").description
    assert session.demo_available() == (scenes.definition("single_axis").demo is not None)
    session.start_demo()
    for _ in range(100):
        run(session, clock, 0.5)
        if session.snapshot.demo.done or session.snapshot.demo.error:
            break
    demo = session.snapshot.demo
    assert demo.done and demo.step == "done" and not demo.error and not demo.running
    x = view(session)
    assert x.state == "StandStill" and x.joint == ""
    assert x.joint_position == pytest.approx(session.scene.joint_position("X"))
    t, values = session.recorder.series()
    volts = values[[c.name for c in session.recorder.channels].index("X command")]
    assert len(t) > 100 and np.abs(volts).max() > 0.1


def test_a_machine_without_demo_says_so(
    monkeypatch: pytest.MonkeyPatch, clock: FakeClock, server: viser.ViserServer
) -> None:
    monkeypatch.setitem(scenes.MACHINES, SHEAR.name, SHEAR)
    assert SHEAR.demo is None
    session = Session(SHEAR.name, clock=clock)
    assert not session.demo_available() and not session.snapshot.demo.available
    with pytest.raises(RuntimeError, match="no demo"):
        session.start_demo()
    app = ViewerApp(session, server)
    app.frame()
    assert app._demo_button.disabled


def test_units_shown_come_from_the_axis_config(server: viser.ViserServer, shear: Session) -> None:
    gantry = Session("gantry")
    for session in (gantry, shear):
        app = ViewerApp(session, server)
        app.frame()
        for name, axis in session.scene.axes.items():
            unit = axis.config.unit
            shown = session.snapshot.axes[name]
            assert shown.unit == unit
            page = axis_panel_html(shown)
            assert f" {unit}/s<" in page and f" {unit}<" in page
            if unit != "mm":
                assert " mm" not in page
    assert {a.config.unit for a in shear.scene.axes.values()} == {"m", "deg"}


def test_the_scope_labels_carry_each_channel_unit(
    server: viser.ViserServer, shear: Session
) -> None:
    app = ViewerApp(shear, server)
    scope = PageScope(server.gui, app.gate, shear, shear.snapshot, server.atomic)
    shear.advance(10)
    scope.update()
    assert scope.recording.headers() == ("master position [m]",)  # the master has no drive
    scope._slots[0].value = "knife following error"  # type: ignore[misc]
    scope._slots[1].value = "knife DO1"  # type: ignore[misc]
    shear.advance(10)
    scope.update()
    assert scope.recording.headers() == ("knife following error [mdeg]", "knife DO1 [0/1]")


def test_an_encoder_only_axis_has_no_drive_buttons(
    server: viser.ViserServer, shear: Session, clock: FakeClock
) -> None:
    app = ViewerApp(shear, server)
    app.frame()
    assert app.axis_widgets["master"] == ["Reset"]
    knife = app.axis_widgets["knife"]
    # the buttons that must fit the page's height first (tests/viewer/test_layout_browser.py)
    assert knife[:7] == ["Power", "Reset", "Stop", "Jog+", "Jog−", "Move to", "Home"]
    (homing,) = [h for h in app._scene_inputs if getattr(h, "label", "") == "Homing"]
    assert "recipe" not in homing.options  # no recipe: index pulse or set position only
    master = view(shear, "master")
    assert not master.has_drive and view(shear, "knife").has_drive
    page = axis_panel_html(master)
    assert "encoder only" in page and "Command" not in page
    # The library refuses power on it (ErrorID 14), whatever sends the request.
    shear.toggle_power("master")
    run(shear, clock, 0.05)
    assert view(shear, "master").message == f"Power: error 14 ({mcl.error_text(14)})"
    assert not view(shear, "master").powered


def test_switch_and_output_lamps_follow_the_definition(
    server: viser.ViserServer, shear: Session
) -> None:
    knife = view(shear, "knife")
    assert knife.switches == ("ref",) and view(shear, "master").switches == ()
    assert knife.outputs == (False, False)
    page = axis_panel_html(knife)
    assert "REF" in page and "LIM" not in page and "DO0" in page and "DO1" in page
    assert "DO0" not in axis_panel_html(view(shear, "master"))

    shear.scene.axes["knife"].io.outputs[1] = True  # the program sets the knife valve
    shear.advance(1)
    assert view(shear, "knife").outputs == (False, True)
    lit = axis_panel_html(view(shear, "knife"))
    assert lit.count("#1e88e5") == 1  # one output lamp lit

    gantry = axis_panel_html(view(Session("gantry")))
    assert all(lamp in gantry for lamp in ("LIM−", "REF", "LIM+")) and "DO0" not in gantry


def test_published_signals_are_shown_with_their_units(
    server: viser.ViserServer, shear: Session
) -> None:
    signals = {s.name: s for s in shear.snapshot.signals}
    assert list(signals) == list(SHEAR.signals)
    assert signals["cut_force"].unit == "N"
    assert signals["cut_force"].value == pytest.approx(1000.0 * shear.scene.joint_position("knife"))
    assert math.isnan(signals["broken"].value)  # a failing reader does not stop the simulation
    app = ViewerApp(shear, server)
    app.frame()
    assert app._signals is not None
    page = signals_html(shear.snapshot)
    assert "cut force [N]" in page and "broken [bar]" in page  # no label: the name, readable
    assert app._signals.content == page

    plain = ViewerApp(Session("single_axis"), server)
    assert plain._signals is None  # no signals: no panel


def test_the_app_switches_between_a_model_and_simulated_axes(
    server: viser.ViserServer, session: Session
) -> None:
    app = ViewerApp(session, server)
    app.frame()
    assert app.model_scene is not None and app._note is None
    session.load("single_axis")
    app.frame()
    assert app.model_scene is None and app._note is not None
    assert list(app.axis_widgets) == list(session.scene.axes) == ["X"]
    assert "no 3-D model" in app._status.content
    session.start_demo()
    session.advance(50)
    app.frame()
    assert session.snapshot.demo.running and not session.snapshot.fault
    session.load("gantry")
    app.frame()
    assert app.model_scene is not None and app._note is None
    assert list(app.axis_widgets) == ["X", "Y", "Z"]
    # the gantry has recipes: Home (after the buttons that fit the page's height first)
    assert app.axis_widgets["X"][:7] == [
        "Power",
        "Reset",
        "Stop",
        "Jog+",
        "Jog−",
        "Move to",
        "Home",
    ]


# ------------------------------------------------------------------------------- the CLI


def test_the_viewer_binds_the_loopback_interface_by_default() -> None:
    args = cli.parser().parse_args([])
    assert args.host == DEFAULT_HOST == "127.0.0.1"
    assert args.port == 8080 and args.scene == "gantry" and args.speed == 1.0
    assert not args.no_demo
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    with Viewer(port=port, demo=False) as v:
        assert v.host == "127.0.0.1" and v.port == port
        assert v.url == f"http://127.0.0.1:{port}/?token={v.token}"
        assert v.token is not None and len(v.token) >= 32 and not v.exposed
    assert port_available("127.0.0.1", port)


def test_cli_options_are_checked() -> None:
    assert cli.parse_speed("max") == math.inf
    assert cli.parse_speed("0.25") == 0.25
    with pytest.raises(SystemExit) as exit_info:
        cli.parser().parse_args(["--speed", "-1"])
    assert exit_info.value.code == 2
    with pytest.raises(SystemExit):
        cli.parser().parse_args(["--scene", "nope"])
    for name in scenes.MACHINES:
        assert cli.parser().parse_args(["--scene", name]).scene == name


def test_a_taken_port_exits_with_status_2(capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert not port_available("127.0.0.1", port)
        with pytest.raises(PortInUseError) as error:
            Viewer(port=port)
        assert error.value.errno == errno.EADDRINUSE
        assert cli.main(["--port", str(port), "--no-demo"]) == 2
    assert f"port {port} on 127.0.0.1 is already in use" in capsys.readouterr().err


def test_ctrl_c_stops_the_viewer_cleanly() -> None:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    process = subprocess.Popen(
        [sys.executable, "-m", "viewer", "--port", str(port), "--no-demo"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        # as in a terminal: a test worker may ignore SIGINT, and the child would inherit that
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    lines: list[str] = []
    assert process.stdout is not None
    reader = threading.Thread(target=lambda: lines.extend(process.stdout or ()), daemon=True)
    reader.start()
    try:
        wait_for(lambda: any("viewer: gantry at" in line for line in lines), timeout=60.0)
        process.send_signal(signal.SIGINT)
        assert process.wait(timeout=15) == 0
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        reader.join(5)
    output = "".join(lines)
    assert f"viewer: gantry at http://127.0.0.1:{port}" in output
    assert "viewer: stopping" in output and "Traceback" not in output
    assert port_available("127.0.0.1", port)


# ------------------------------------------------------------------ security (issue 12)


def _http(
    port: int, path: str, host: str | None = None, **headers: str
) -> tuple[int, dict[str, str]]:
    """GET ``path`` with an explicit Host header; (status, headers)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    connection.putrequest("GET", path, skip_host=True)
    connection.putheader("Host", host or f"127.0.0.1:{port}")
    for name, value in headers.items():
        connection.putheader(name.replace("_", "-"), value)
    connection.endheaders()
    response = connection.getresponse()
    response.read()
    connection.close()
    return response.status, dict(response.getheaders())


def _websocket(port: int, origin: str | None, token: str) -> str:
    """Open the viser websocket like a page of ``origin``; "open" or why it was refused."""
    import asyncio

    import websockets.asyncio.client

    async def attempt() -> str:
        try:
            async with websockets.asyncio.client.connect(
                f"ws://127.0.0.1:{port}/?token={token}",
                origin=origin,  # type: ignore[arg-type]
                subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
                open_timeout=10,
            ) as connection:
                await asyncio.wait_for(connection.recv(), 10)
                return "open"
        except websockets.exceptions.InvalidStatus as exc:
            return f"refused {exc.response.status_code}"

    return run_coroutine(attempt())


@pytest.fixture(scope="module")
def guarded() -> Iterator[Viewer]:
    """The gantry viewer with its access policy, on a free loopback port."""
    with Viewer("gantry", port=0, demo=False) as v:
        yield v


def test_only_the_token_opens_the_page_and_it_comes_back_as_a_cookie(guarded: Viewer) -> None:
    port, token = guarded.port, guarded.token
    assert token is not None and guarded.url.endswith(f"/?token={token}")
    status, headers = _http(port, f"/?token={token}")
    assert status == 303 and headers["Location"] == "/"  # the token leaves the address bar
    cookie = headers["Set-Cookie"]
    assert f"mcl_viewer_token_{port}={token}" in cookie and "HttpOnly" in cookie
    assert "SameSite=Strict" in cookie
    assert _http(port, "/")[0] == 403
    assert _http(port, "/?token=guess")[0] == 403
    assert _http(port, "/", Cookie=f"mcl_viewer_token_{port}={token}")[0] == 200
    assert _http(port, "/", Cookie=f"mcl_viewer_token_{port}=guess")[0] == 403


def test_a_foreign_host_header_is_refused(guarded: Viewer) -> None:
    port, token = guarded.port, guarded.token
    for host in (f"attacker.example:{port}", "attacker.example", f"127.0.0.1:{port + 1}"):
        assert _http(port, f"/?token={token}", host=host)[0] == 403, host
    for host in (f"localhost:{port}", f"127.0.0.1:{port}"):
        assert _http(port, f"/?token={token}", host=host)[0] == 303, host


def test_every_response_forbids_framing_and_carries_a_content_policy(guarded: Viewer) -> None:
    port, token = guarded.port, guarded.token
    for path in (f"/?token={token}", "/", "/nothing-here"):
        _, headers = _http(port, path)
        csp = headers["Content-Security-Policy"]
        assert "frame-ancestors 'none'" in csp and "object-src 'none'" in csp, path
        assert headers["X-Frame-Options"] == "DENY"
        assert headers["X-Content-Type-Options"] == "nosniff"
        assert headers["Referrer-Policy"] == "no-referrer"  # the token never leaks


def test_a_long_path_gives_414_and_one_log_line(
    guarded: Viewer, caplog: pytest.LogCaptureFixture
) -> None:
    with caplog.at_level(logging.WARNING):
        status, _ = _http(guarded.port, "/" + "a" * 4000 + f"?token={guarded.token}")
    assert status == 414
    lines = [r for r in caplog.records if "too long" in r.getMessage()]
    assert len(lines) == 1 and lines[0].exc_info is None
    assert guarded.token is not None
    assert guarded.token not in caplog.text  # the query (with the token) is never logged


def test_only_a_same_origin_websocket_with_the_token_connects(guarded: Viewer) -> None:
    port, token = guarded.port, guarded.token
    assert token is not None
    clients = len(guarded.server.get_clients())
    assert _websocket(port, "http://attacker.example", token) == "refused 403"
    assert _websocket(port, None, token) == "refused 403"
    assert _websocket(port, f"http://127.0.0.1:{port + 1}", token) == "refused 403"
    assert _websocket(port, f"http://127.0.0.1:{port}", "guess") == "refused 403"
    assert len(guarded.server.get_clients()) == clients
    assert _websocket(port, f"http://127.0.0.1:{port}", token) == "open"


def test_malformed_messages_drop_the_client_with_bounded_one_line_logs(
    guarded: Viewer, caplog: pytest.LogCaptureFixture
) -> None:
    import asyncio

    import websockets.asyncio.client

    port, token = guarded.port, guarded.token

    async def send_garbage() -> int:
        closed = 0
        for _ in range(LOG_BURST + 10):
            async with websockets.asyncio.client.connect(
                f"ws://127.0.0.1:{port}/?token={token}",
                origin=f"http://127.0.0.1:{port}",  # type: ignore[arg-type]
                subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
            ) as connection:
                await connection.send(b"\xc1 not msgpack")
                try:
                    while True:
                        await asyncio.wait_for(connection.recv(), 10)
                except websockets.exceptions.ConnectionClosed:
                    closed += 1
        return closed

    guarded.policy.log = BoundedLog(logging.getLogger("viewer.serving.security"))
    with caplog.at_level(logging.WARNING):
        assert run_coroutine(send_garbage()) == LOG_BURST + 10  # each one was dropped
    records = [r for r in caplog.records if r.name.startswith(("viewer", "websockets", "asyncio"))]
    assert all(r.exc_info is None and "\n" not in r.getMessage() for r in records)
    assert "Traceback" not in caplog.text
    assert len(records) <= LOG_BURST + 1


def test_binding_beyond_loopback_needs_a_token_and_warns_with_the_real_address() -> None:
    with pytest.raises(ValueError, match="token is mandatory"):
        AccessPolicy("0.0.0.0", 8080, None)
    AccessPolicy("127.0.0.1", 8080, None)  # loopback may go without
    with Viewer("single_axis", host="0.0.0.0", port=0, demo=False) as v:
        assert v.exposed and v.token is not None
        assert "0.0.0.0" not in v.url and "localhost" not in v.url and v.token in v.url
        warning = v.warning()
        assert "WARNING" in warning and v.url in warning
        with pytest.raises(ValueError):
            Viewer("single_axis", host="0.0.0.0", port=0, demo=False, token=False)


# ------------------------------------------------------------------ GUI values and control


def _gui_update(app: ViewerApp, client_id: int, handle: Any, value: Any) -> None:
    """Deliver a GUI value from page ``client_id`` as the websocket would."""
    import viser._messages

    message = viser._messages.GuiUpdateMessage(handle._impl.uuid, {"value": value})
    run_coroutine(app.gate._on_update(client_id, message))  # type: ignore[arg-type]


def test_a_nan_or_out_of_range_value_is_refused_and_not_passed_on(
    monkeypatch: pytest.MonkeyPatch, server: viser.ViserServer, session: Session
) -> None:
    sent: list[Any] = []
    original = viser.infra.WebsockServer.queue_message

    def spy(self: viser.infra.WebsockServer, message: viser.infra.Message) -> None:
        sent.append(message)
        original(self, message)

    app = ViewerApp(session, server)
    slider = next(h for h in app._scene_inputs if getattr(h, "label", "").startswith("Jog velo"))
    app.control.take(7)
    before = slider.value
    monkeypatch.setattr(viser.infra.WebsockServer, "queue_message", spy)
    for bad in (math.nan, math.inf, -1.0, 1e12, "10", True, None):
        _gui_update(app, 7, slider, bad)
    assert slider.value == before
    # nothing of the bad values re-broadcast (the panel's own refreshes of other elements may run
    # meanwhile; a reset of this slider to its old value is allowed)
    assert not any(
        type(m).__name__ == "GuiUpdateMessage"
        and m.uuid == slider._impl.uuid
        and m.updates.get("value", before) != before
        for m in sent
    )
    assert session.requests("X").jog_velocity == 0.0
    refused = [e.text for e in session.snapshot.events] + [e.text for e in session._events]
    assert any("refused" in text for text in refused)


def test_a_page_without_control_cannot_operate(
    server: viser.ViserServer, session: Session, clock: FakeClock
) -> None:
    app = ViewerApp(session, server)
    power = app._axes["X"].power
    assert power is not None
    _gui_update(app, 3, power, True)  # nobody in control
    run(session, clock, 0.1)
    assert not view(session).powered
    assert any("take control first" in e.text for e in session.snapshot.events)
    app.control.take(3)
    _gui_update(app, 4, power, True)  # another page
    run(session, clock, 0.1)
    assert not view(session).powered
    # STOP all is for everyone
    assert app.gate.rules[app._stop_all._impl.uuid].control is False


def test_the_server_renews_the_deadman_of_a_held_jog_until_release(
    server: viser.ViserServer, session: Session, clock: FakeClock
) -> None:
    """A slow page sends hold messages late: the server keeps the jog alive meanwhile."""
    app = ViewerApp(session, server)
    session.requests("X").set_power(True)
    run(session, clock, 0.2)
    app.control.take(5)
    monkey_clients = {5: object()}
    app.server.get_clients = lambda: monkey_clients  # type: ignore[method-assign,assignment,return-value]
    with app._holds_lock:
        app._holds[5] = app_module._Hold(session.snapshot.generation, "X", 1, time.monotonic())
    start = session.scene.joint_position("X")
    for _ in range(10):  # 0.5 s of simulated jogging with no hold message, renewed per frame
        app.renew_holds()
        run(session, clock, 0.05)
    assert view(session).jogging == 1
    assert session.scene.joint_position("X") - start > 0.005
    app._drop_holds(5)  # release
    run(session, clock, 0.3)
    assert view(session).jogging == 0


# ------------------------------------------------------------------ commissioning


def test_ending_the_demo_releases_the_group_and_leaves_a_homed_usable_machine(
    clock: FakeClock,
) -> None:
    session = Session("gantry", clock=clock)
    session.start_demo()
    for _ in range(200):
        run(session, clock, 0.1)
        if session.snapshot.groups:
            break
    assert session.snapshot.groups, "the gantry demo groups its axes"
    session.end_demo()
    run(session, clock, 1.0)
    assert session.snapshot.groups == ()
    assert all(v.referenced and v.powered and not v.group for v in session.snapshot.axes.values())
    start = session.scene.joint_position("X")
    run(session, clock, 0.5, jog=("X", 1))
    assert session.scene.joint_position("X") - start > 0.002
    assert not any("1000" in v.last_error for v in session.snapshot.axes.values())


def test_a_refused_command_lands_in_the_error_history_with_timestamps(
    session: Session, clock: FakeClock
) -> None:
    run(session, clock, 0.2)
    before = time.time()
    session.requests("X").move(Move("relative", 10.0, 100.0, 1000.0))  # not powered
    run(session, clock, 0.1)
    x = view(session)
    assert x.last_error.startswith("Move by: error")
    event = session.snapshot.events[-1]
    assert event.source == "X" and event.text == x.last_error
    assert before <= event.wall <= time.time()
    assert event.time == pytest.approx(0.2, abs=0.01)  # simulated time of the refusal
    assert "Move by: error" in axis_panel_html(x)


def test_move_to_a_position_and_by_a_distance(session: Session, clock: FakeClock) -> None:
    session.requests("X").set_power(True)
    run(session, clock, 0.2)
    start = session.scene.joint_position("X")
    session.requests("X").move(Move("relative", 25.0, 200.0, 2000.0))
    run(session, clock, 1.0)
    assert (session.scene.joint_position("X") - start) * 1e3 == pytest.approx(25.0, abs=0.05)
    session.requests("X").move(Move("absolute", 0.0, 200.0, 2000.0))
    run(session, clock, 0.1)
    assert view(session).last_error.startswith("Move to: error")  # no reference yet
    session.requests("X").home()
    for _ in range(40):
        run(session, clock, 0.5)
        if view(session).message == "Home: done":
            break
    target = view(session).position - 40.0
    before = session.scene.joint_position("X")
    session.requests("X").move(Move("absolute", target, 200.0, 2000.0))
    run(session, clock, 1.0)
    assert view(session).position == pytest.approx(target, abs=0.05)
    assert (session.scene.joint_position("X") - before) * 1e3 == pytest.approx(-40.0, abs=0.05)
    assert view(session).message == "Move to: done"
    with pytest.raises(ValueError, match="velocity"):
        Move("absolute", 1.0, math.nan, 1.0)


def test_stop_all_stops_every_axis_and_the_demo(clock: FakeClock) -> None:
    session = Session("gantry", clock=clock)
    session.requests("X").set_power(True)
    session.requests("Y").set_power(True)
    run(session, clock, 0.2)
    session.requests("X").move(Move("relative", 300.0, 200.0, 2000.0))
    session.requests("Y").move(Move("relative", 300.0, 200.0, 2000.0))
    run(session, clock, 0.3)
    assert abs(view(session, "X").velocity) > 100.0
    session.stop_all()
    run(session, clock, 0.5)
    for axis in ("X", "Y"):
        assert abs(view(session, axis).velocity) < 0.5
    x = session.scene.joint_position("X")
    run(session, clock, 0.3)
    assert session.scene.joint_position("X") == pytest.approx(x, abs=1e-5)
    assert any(e.text == "STOP all axes" for e in session.snapshot.events)


class ResultsDemo(StandInDemo):
    """The stand-in demo with a results table (one row per scan, like one row per cut)."""

    def __init__(self, scene: Scene) -> None:
        super().__init__(scene)
        self.results: list[dict[str, object]] = []

    def __call__(self) -> None:
        super().__call__()
        n = len(self.results) + 1
        self.results.append({"cut": n, "length [mm]": 1500.0 + n / 1000.0, "note": "<b>x</b>"})


def test_a_demo_results_table_is_shown_escaped(server: viser.ViserServer, clock: FakeClock) -> None:
    session = Session("gantry", clock=clock, demo=ResultsDemo)
    session.start_demo()
    run(session, clock, 0.1)
    columns, rows = session.snapshot.results
    assert columns == ("cut", "length [mm]", "note")
    assert len(rows) == RESULTS_SHOWN and rows[-1][0] == str(len(rows[-1]) and int(rows[-1][0]))
    assert rows[-1][1] == f"{1500.0 + int(rows[-1][0]) / 1000.0:.3f}"
    page = results_html(session.snapshot)
    assert "<b>x</b>" not in page and "&lt;b&gt;" in page
    app = ViewerApp(session, server)
    app.frame()
    assert app._results is not None and app._results.content == page
    session.end_demo()
    run(session, clock, 0.1)
    assert session.snapshot.results[0] == columns  # kept after the demo ended


def test_the_scope_offers_every_channel_and_triggers_on_an_axis_error(
    server: viser.ViserServer, session: Session, clock: FakeClock
) -> None:
    app = ViewerApp(session, server)
    scope = PageScope(server.gui, app.gate, session, session.snapshot, server.atomic)
    names = [c.name for c in session.snapshot.channels]
    assert {"X position", "X set point", "X following error", "X command", "X LIM+"} <= set(names)
    session.requests("X").set_power(True)
    run(session, clock, 0.5)
    scope.update()
    assert scope.recording.headers() == (  # the gantry's defaults
        "X following error [µm]",
        "Y following error [µm]",
        "Z following error [µm]",
    )
    # Trigger on the error of any axis: a limit switch forced on gives one.
    scope._trigger.value = "on any axis error"  # type: ignore[misc]
    scope._length.value = "2 s"  # type: ignore[misc]  # not the gantry's 20 s
    scope._set_length()
    scope._act(SINGLE)
    session.requests("X").move(Move("relative", 5.0, 100.0, 1000.0))
    session.inject("X", mcl.faults.SwitchStuck("lim_pos", True))
    for _ in range(60):
        run(session, clock, 0.05)
        scope.update()
        if not scope.acquisition.running:
            break
    assert "triggered at" in scope.status
    window = scope.recording.window
    t, values = session.recorder.series()
    error = values[names.index("X error")]
    assert window.trigger_at == t[np.flatnonzero(error > 0.5)[0]]
    frozen = scope.recording
    run(session, clock, 0.5)
    scope.update()
    assert scope.recording is frozen  # a single recording stays


def test_set_position_without_moving_and_homing_on_an_index_pulse(
    session: Session, clock: FakeClock
) -> None:
    session.requests("X").set_power(True)
    run(session, clock, 0.2)
    joint = session.scene.joint_position("X")
    session.requests("X").home("set position (no motion)", 123.0)
    run(session, clock, 0.2)
    x = view(session)
    assert x.message == "Home: done" and x.referenced
    assert x.position == pytest.approx(123.0, abs=0.01)
    assert session.scene.joint_position("X") == pytest.approx(joint, abs=2e-6)  # no motion
    session.requests("X").home("index pulse +", 0.0)
    for _ in range(40):
        run(session, clock, 0.25)
        if not session.operator.axes["X"].homing:
            break
    x = view(session)
    assert x.message == "Home: done" and x.referenced
    assert abs(x.position) < 1.0  # 0 at the index pulse, then the stop ramp
    assert session.scene.joint_position("X") > joint  # it searched in the positive direction
    with pytest.raises(ValueError, match="homing procedure"):
        session.requests("X").home("teleport", 0.0)


def test_over_the_websocket_control_hotkey_steps_and_value_checks(guarded: Viewer) -> None:
    """A real client: it must take control before its hotkey moves the axis, and a NaN it sends
    is neither applied nor passed on to the other pages."""
    import asyncio

    import msgspec
    import websockets.asyncio.client

    app, session = guarded.app, guarded.session
    session.requests("X").set_power(True)
    wait_for(lambda: session.snapshot.axes["X"].powered, 10.0)
    step_plus = next(c for c in app._commands if c._impl.props.label == "X step +")
    slider = next(h for h in app._scene_inputs if getattr(h, "label", "").startswith("Jog velo"))

    def send(kind: str, **fields: Any) -> bytes:
        return msgspec.msgpack.encode({"type": kind, **fields})

    async def operate() -> None:
        async with websockets.asyncio.client.connect(
            f"ws://127.0.0.1:{guarded.port}/?token={guarded.token}",
            origin=f"http://127.0.0.1:{guarded.port}",  # type: ignore[arg-type]
            subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
        ) as connection:
            await asyncio.wait_for(connection.recv(), 10)
            await connection.send(send("ViewerCameraMessage", **CAMERA))  # viser: connected
            for _ in range(100):
                if app.control_pages.pages:
                    break
                await asyncio.sleep(0.05)
            (page,) = app.control_pages.pages.values()
            take = page.take
            start = session.scene.joint_position("X")
            await connection.send(send("CommandTriggerMessage", uuid=step_plus._impl.uuid))
            await asyncio.sleep(1.0)
            assert session.scene.joint_position("X") == pytest.approx(start, abs=1e-6)
            await connection.send(
                send("GuiUpdateMessage", uuid=take._impl.uuid, updates={"value": True})
            )
            for _ in range(100):
                if app.control.owner is not None:
                    break
                await asyncio.sleep(0.05)
            assert app.control.owner is not None
            await connection.send(send("CommandTriggerMessage", uuid=step_plus._impl.uuid))
            for _ in range(100):
                if session.snapshot.axes["X"].message == "Move by: done":
                    break
                await asyncio.sleep(0.05)
            moved = (session.scene.joint_position("X") - start) * 1e3
            assert moved == pytest.approx(1.0, abs=0.02)  # one Step (1 mm)
            before = slider.value
            await connection.send(
                send("GuiUpdateMessage", uuid=slider._impl.uuid, updates={"value": math.nan})
            )
            await asyncio.sleep(0.5)
            assert slider.value == before
            assert session.requests("X").jog_velocity == 0.0

    run_coroutine(operate())
    assert any("invalid value nan" in e.text for e in session.snapshot.events)
    assert any("take control first" in e.text for e in session.snapshot.events)


def test_the_cli_refuses_to_serve_the_network_without_a_token(
    capsys: pytest.CaptureFixture[str],
) -> None:
    port = _free_port_for_cli()
    assert cli.main(["--host", "0.0.0.0", "--no-token", "--port", str(port)]) == 2
    assert "token is mandatory" in capsys.readouterr().err
    assert port_available("0.0.0.0", port)


def _free_port_for_cli() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


def test_faults_offered_follow_the_definition_and_force_the_input(
    server: viser.ViserServer, shear: Session, clock: FakeClock
) -> None:
    app = ViewerApp(shear, server)
    (kind,) = [h for h in app._scene_inputs if getattr(h, "label", "") == "Fault"]
    options = list(kind.options)
    assert "knife: force REF on" in options and not any("LIM" in o for o in options)
    assert "knife: amplifier fault" in options and "master: amplifier fault" not in options
    assert "master: encoder freeze" in options
    run(shear, clock, 0.05)
    level = view(shear, "knife").ref
    shear.inject("knife", mcl.faults.SwitchStuck("ref", not level))
    run(shear, clock, 0.05)
    assert view(shear, "knife").ref == (not level)
    shear.clear_faults("knife")
    run(shear, clock, 0.05)
    assert view(shear, "knife").ref == level
    texts = [e.text for e in shear.snapshot.events]
    assert any(t.startswith("fault injected: SwitchStuck") for t in texts)
    assert "faults cleared" in texts


def test_tuning_writes_the_servo_constants_through_gt_setconstant(
    session: Session, clock: FakeClock
) -> None:
    run(session, clock, 0.05)
    constants = view(session).constants
    assert constants is not None
    session.requests("X").write_constants(dataclasses.replace(constants, Kp=2.0 * constants.Kp))
    run(session, clock, 0.05)
    written = session.scene.axes["X"].constants
    assert written is not None and written.Kp == pytest.approx(2.0 * constants.Kp)
    assert view(session).message == "Write constants: done"
    session.requests("X").write_constants(dataclasses.replace(constants, Ki=-1.0))
    run(session, clock, 0.05)
    assert view(session).last_error.startswith("Write constants: error 5")  # EParam
    assert session.scene.axes["X"].constants == written  # left alone
    assert session.snapshot.events[-1].text == view(session).last_error


def test_a_saved_state_comes_back_homed_with_a_fresh_operator(
    session: Session, clock: FakeClock
) -> None:
    session.restore_state()
    assert session.snapshot.events[-1].text == "no saved state of gantry to restore: save one first"
    session.requests("X").set_power(True)
    run(session, clock, 0.2)
    session.requests("X").home("set position (no motion)", 123.0)
    run(session, clock, 0.2)
    assert view(session).referenced
    session.save_state()
    saved_at, joint = session.scene.time, session.scene.joint_position("X")
    assert session.snapshot.events[-1].text == f"state of gantry saved at {saved_at:.3f} s"
    session.requests("X").move(Move("relative", 60.0, 200.0, 2000.0))
    run(session, clock, 0.1)
    session.save_state()  # X moves: refused, the saved state stays
    refused = session.snapshot.events[-1].text
    assert refused.startswith("state not saved:") and "axis X is in DiscreteMotion" in refused
    run(session, clock, 1.0)
    assert (session.scene.joint_position("X") - joint) * 1e3 == pytest.approx(60.0, abs=0.05)
    generation = session.snapshot.generation
    session.restore_state()
    x = view(session)
    assert session.snapshot.generation == generation + 1  # the operator program is new
    assert session.scene.time == saved_at and session.scene.joint_position("X") == joint
    assert x.referenced and x.powered and x.message == "" and x.position == pytest.approx(123.0)
    restored = session.snapshot.events[-1].text
    assert restored == f"state of gantry restored: saved at {saved_at:.3f} s"
    session.requests("X").move(Move("absolute", 143.0, 200.0, 2000.0))  # needs the reference
    run(session, clock, 1.0)
    assert view(session).message == "Move to: done"
    assert (session.scene.joint_position("X") - joint) * 1e3 == pytest.approx(20.0, abs=0.05)
    session.load("single_axis")  # one state per machine: none saved for this one
    session.restore_state()
    assert session.snapshot.events[-1].text.startswith("no saved state of single_axis")
    session.load("gantry")  # a rebuilt gantry takes the gantry's state
    session.restore_state()
    assert session.scene.joint_position("X") == joint and view(session).referenced

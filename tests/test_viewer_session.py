"""The viewer without a browser: the simulation session, the operator program, the app, the CLI.

Most tests drive the session synchronously (``Session.advance``) with a fake wall clock, so the
jog dead-man deadline and everything else is deterministic. The pacing and pause/step tests run
the simulation thread for real and assert loosely.
"""

from __future__ import annotations

import dataclasses
import errno
import http.client
import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
import viser
import viser.infra

import mcl
import scenes
import viewer.__main__ as cli
from scenes.scene import Scene
from viewer.app import (
    DEFAULT_HOST,
    LAMP_LIMIT,
    LAMP_REF,
    REFUSED_MESSAGES,
    PortInUseError,
    Viewer,
    ViewerApp,
    axis_panel_html,
    port_available,
    signals_html,
)
from viewer.operator import DEADMAN
from viewer.session import AxisView, Session, choices

ROOT = Path(__file__).resolve().parent.parent


class FakeClock:
    """A wall clock the test moves by hand [s]."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


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
    with Session("gantry", speed=speed) as session:
        time.sleep(0.1)
        sim0, wall0 = session.snapshot.time, time.monotonic()
        time.sleep(0.8)
        sim1, wall1 = session.snapshot.time, time.monotonic()
        factor = session.snapshot.realtime_factor
    ratio = (sim1 - sim0) / (wall1 - wall0)
    assert 0.5 * speed < ratio < 1.5 * speed
    assert 0.5 * speed < factor < 1.5 * speed


def test_as_fast_as_possible_outruns_the_wall_clock() -> None:
    with Session("gantry", speed=1.0) as session:
        session.speed = math.inf
        wait_for(lambda: math.isinf(session.snapshot.speed))
        sim0, wall0 = session.snapshot.time, time.monotonic()
        time.sleep(0.5)
        sim1, wall1 = session.snapshot.time, time.monotonic()
    assert (sim1 - sim0) / (wall1 - wall0) > 2.0


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


# ------------------------------------------------------------------------------- the demo


def test_demo_runs_and_a_power_press_takes_the_machine_back(
    session: Session, clock: FakeClock
) -> None:
    assert session.demo_available()
    session.requests("X").set_power(False)  # the operator's MC_Power would fight the demo...
    session.start_demo()  # ...so starting the demo hands power back to it
    assert view(session).power_request is None
    run(session, clock, 0.05)
    assert session.snapshot.demo.running and session.snapshot.demo.step == "move X to 20 mm"
    run(session, clock, 1.0)
    demo = session.snapshot.demo
    assert demo.done and demo.step == "done" and not demo.running
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


def test_history_holds_the_last_seconds_of_following_error_and_volts(
    session: Session, clock: FakeClock
) -> None:
    session.requests("X").set_power(True)
    run(session, clock, 5.0, jog=("X", 1))
    t, fe, volts = session.snapshot.history["X"]
    assert len(t) == len(fe) == len(volts) > 100
    assert np.all(np.diff(t) > 0.0)
    assert 3.5 < t[-1] - t[0] <= 4.0 and t[-1] <= session.snapshot.time
    assert volts[-1] > 1.0  # jogging at 100 mm/s needs ~1 V


# ------------------------------------------------------------------------------- the app


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield srv
    finally:
        srv.stop()


def rgb(color: tuple[float, float, float]) -> tuple[int, int, int]:
    r, g, b = (round(c * 255.0) for c in color)
    return (r, g, b)


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
    t, _, volts = session.snapshot.history["X"]
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


def test_the_plot_labels_follow_the_selected_axis_unit(
    server: viser.ViserServer, shear: Session
) -> None:
    app = ViewerApp(shear, server)
    shear.advance(10)
    app.frame()
    assert app.plot_labels[1] == "following error [m]"  # the first axis, master
    assert app._plot_axis is not None
    app._plot_axis.value = "knife"  # type: ignore[misc]  # viser's setter exists
    shear.advance(10)
    app._last_plot = -math.inf
    app.frame()
    assert app.plot_labels[1] == "following error [deg]"


def test_an_encoder_only_axis_has_no_drive_buttons(
    server: viser.ViserServer, shear: Session, clock: FakeClock
) -> None:
    app = ViewerApp(shear, server)
    app.frame()
    assert app.axis_widgets["master"] == ["Reset"]
    assert app.axis_widgets["knife"] == ["Power", "Reset", "Jog+", "Jog−", "Stop"]  # no recipe
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
    assert "cut_force" in page and " N" in page and "bar" in page
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
    assert app.axis_widgets["X"][:3] == ["Power", "Reset", "Home"]  # the gantry has recipes


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
        assert v.url == f"http://127.0.0.1:{port}"
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

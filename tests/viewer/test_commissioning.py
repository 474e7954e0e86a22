"""Commissioning from the page, measured on the physics: the reversing sequence A ↔ B, the slow
jog, the step test of the position loop, repeating demos, and the controls that ask for them.

The sessions run synchronously (``Session.advance``) with a fake wall clock, as in
tests/viewer/test_session.py.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import pytest
import viser

import mcl
import mcl.faults
from plc.commissioning.reversing import Reversing
from plc.commissioning.step_test import STEP_WINDOW, step_response
from plc.operator.hmi import Move
from tests.helpers import run_coroutine
from tests.viewer.test_browser import browser, page, viewer, wait_for
from viewer.pages.app import ViewerApp
from viewer.pages.commissioning import JOG_SPEEDS
from viewer.serving.server import Viewer
from viewer.sim.demo_run import REPEAT_PAUSE
from viewer.sim.session import Session

if TYPE_CHECKING:
    from playwright.sync_api import Page

__all__ = ["browser", "page", "viewer"]  # the browser test's fixtures


class FakeClock:
    """A wall clock the test moves by hand [s]."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def gantry(clock: FakeClock) -> Session:
    """The gantry with X powered and referenced where it stands (set position 0)."""
    session = Session("gantry", clock=clock)
    requests = session.requests("X")
    requests.set_power(True)
    session.advance(50)
    requests.home("set position (no motion)", 0.0)
    session.advance(50)
    assert session.snapshot.axes["X"].referenced
    return session


def joint_mm(session: Session, axis: str = "X") -> float:
    """The physics' joint position of ``axis`` in its user unit."""
    scene = session.scene
    return scene.joint_position(axis) * scene.scales[axis]


def record(session: Session, cycles: int, clock: FakeClock | None = None) -> np.ndarray:
    """Run ``cycles`` PLC cycles one by one; rows of (simulated time [s], joint [u])."""
    plc = session.scene.runtime.plc_period
    rows = []
    for _ in range(cycles):
        session.advance(1)
        if clock is not None:
            clock.now += plc
        rows.append((session.scene.time, joint_mm(session)))
    return np.array(rows)


def stays(samples: np.ndarray, target: float, tolerance: float) -> list[tuple[float, float]]:
    """The spans (first, last time [s]) in which the joint stays within ``tolerance`` of
    ``target``."""
    inside = np.abs(samples[:, 1] - target) <= tolerance
    edges = np.flatnonzero(np.diff(np.concatenate(([0], inside.astype(int), [0]))))
    t = samples[:, 0]
    return [(float(t[i]), float(t[j - 1])) for i, j in zip(edges[::2], edges[1::2], strict=True)]


# ------------------------------------------------------------------------- reversing sequence


def test_the_reversing_sequence_runs_its_cycles_between_a_and_b_and_stops(
    gantry: Session,
) -> None:
    tolerance = gantry.scene.axes["X"].config.in_position
    dwell = 0.3
    gantry.requests("X").reverse(Reversing(10.0, 60.0, 200.0, 2000.0, dwell, cycles=2))
    samples = record(gantry, 1800)  # 3.6 s
    at_a = [s for s in stays(samples, 10.0, tolerance) if s[1] - s[0] > 0.1]
    at_b = [s for s in stays(samples, 60.0, tolerance) if s[1] - s[0] > 0.1]
    assert len(at_a) == 2 and len(at_b) == 2  # two cycles: A, B, A, B
    for first, last in (*at_a, at_b[0]):
        assert dwell <= last - first <= dwell + 0.05  # the dwell, measured on the joint
    assert at_b[1][1] == pytest.approx(samples[-1, 0])  # it stays at B: the sequence ended
    assert at_a[0][0] < at_b[0][0] < at_a[1][0] < at_b[1][0]
    progress = gantry.snapshot.axes["X"].commissioning
    assert progress is not None
    assert progress.reversing.text == "cycle 2 of 2: done"
    assert gantry.snapshot.axes["X"].message == "Reversing: done (2 cycles)"


def test_stop_sequence_halts_the_axis_between_its_targets(gantry: Session) -> None:
    requests = gantry.requests("X")
    requests.reverse(Reversing(0.0, 100.0, 200.0, 2000.0, 0.0, cycles=0))
    record(gantry, 150)  # on the way to B
    moving = joint_mm(gantry)
    assert 5.0 < moving < 95.0
    requests.end_reversing()
    after = record(gantry, 250)
    assert after[-1, 1] == pytest.approx(after[-50, 1], abs=1e-3)  # stands still
    assert moving < after[-1, 1] < 95.0  # ramped down (MC_Halt), B not reached
    view = gantry.snapshot.axes["X"]
    assert view.commissioning is not None and view.commissioning.reversing.phase == "stopped"
    assert gantry.scene.axes["X"].state == mcl.AxisState.StandStill


def test_a_fault_ends_the_reversing_sequence(gantry: Session) -> None:
    gantry.requests("X").reverse(Reversing(0.0, 100.0, 200.0, 2000.0, 0.0, cycles=0))
    record(gantry, 100)
    gantry.inject("X", mcl.faults.EncoderWireBreak())
    record(gantry, 100)
    view = gantry.snapshot.axes["X"]
    assert view.commissioning is not None and not view.commissioning.reversing.running
    assert view.commissioning.reversing.phase == "fault"
    assert view.message.startswith("Reversing: error 2001")


def test_an_operator_move_takes_the_axis_over_from_the_sequence(gantry: Session) -> None:
    requests = gantry.requests("X")
    requests.reverse(Reversing(0.0, 100.0, 200.0, 2000.0, 0.0, cycles=0))
    record(gantry, 100)
    requests.move(Move("absolute", 30.0, 100.0, 1000.0))
    samples = record(gantry, 800)
    assert samples[-1, 1] == pytest.approx(30.0, abs=0.01)  # where the operator sent it
    view = gantry.snapshot.axes["X"]
    assert view.commissioning is not None and view.commissioning.reversing.phase == "aborted"


# ------------------------------------------------------------------------------------ override


def test_override_50_percent_halves_a_running_move_without_a_velocity_jump(
    gantry: Session,
) -> None:
    requests = gantry.requests("X")
    requests.move(Move("absolute", 600.0, 200.0, 2000.0))
    before = record(gantry, 400)  # 0.8 s: at 200 mm/s since 0.1 s
    requests.override = 50.0
    after = record(gantry, 600)
    samples = np.concatenate((before, after))
    t, x = samples[:, 0], samples[:, 1]
    velocity = np.diff(x) / np.diff(t)
    acceleration = np.diff(velocity) / np.diff(t[1:])
    assert velocity[300:399].mean() == pytest.approx(200.0, rel=0.02)
    assert velocity[-100:].mean() == pytest.approx(100.0, rel=0.02)
    config = gantry.scene.axes["X"].config
    assert np.abs(acceleration[390:]).max() <= config.deceleration  # ramped, no jump
    view = gantry.snapshot.axes["X"]
    assert view.commissioning is not None and view.commissioning.override == 50.0
    with pytest.raises(ValueError):
        requests.override = 151.0


# ------------------------------------------------------------------------------------ jog speed


@pytest.mark.parametrize(("slow", "expected"), [(False, 200.0), (True, 20.0)])
def test_slow_jog_moves_at_a_tenth_of_the_jog_velocity(
    gantry: Session, clock: FakeClock, slow: bool, expected: float
) -> None:
    requests = gantry.requests("X")
    requests.jog_velocity = 200.0
    requests.jog_slow = slow
    plc = gantry.scene.runtime.plc_period
    rows = []
    for _ in range(500):  # 1 s, Jog+ held
        requests.jog(1)
        gantry.advance(1)
        clock.now += plc
        rows.append((gantry.scene.time, joint_mm(gantry)))
    samples = np.array(rows)
    steady = samples[-200:]  # the last 0.4 s, long after the ramp
    velocity = (steady[-1, 1] - steady[0, 1]) / (steady[-1, 0] - steady[0, 0])
    assert velocity == pytest.approx(expected, rel=0.02)


# ------------------------------------------------------------------------------------ step test


def test_the_step_response_figures_of_known_responses() -> None:
    tau = 0.01
    t = np.linspace(0.0, 0.2, 20001)
    first_order = 2.0 * (1.0 - np.exp(-t / tau))
    r = step_response(t, first_order, 0.0, 2.0)
    assert r.rise_time == pytest.approx(tau * math.log(9.0), rel=1e-3)
    assert r.settling_time == pytest.approx(tau * math.log(50.0), rel=1e-3)
    assert r.overshoot == 0.0
    assert r.steady_state_error == pytest.approx(0.0, abs=1e-6)
    zeta, wn = 0.3, 200.0
    wd = wn * math.sqrt(1.0 - zeta**2)
    phi = math.acos(zeta)
    second = 1.0 - np.exp(-zeta * wn * t) * np.sin(wd * t + phi) / math.sqrt(1.0 - zeta**2)
    r = step_response(t, second, 0.0, 1.0)
    assert r.overshoot == pytest.approx(100.0 * math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)))
    with pytest.raises(ValueError):
        step_response([0.0], [0.0], 0.0, 1.0)


def test_the_step_test_reports_the_figures_of_the_joint_response(gantry: Session) -> None:
    started: list[tuple[int, str, float, float]] = []
    gantry.on_step = lambda *args: started.append(args)
    gantry.advance(50)
    before = joint_mm(gantry)
    gantry.requests("X").step_test(1.0, client_id=7)
    samples = record(gantry, round(1.2 * STEP_WINDOW / gantry.scene.runtime.plc_period))
    assert len(started) == 1
    client, axis, start, length = started[0]
    assert (client, axis, length) == (7, "X", STEP_WINDOW)
    view = gantry.snapshot.axes["X"]
    assert view.commissioning is not None and view.commissioning.step is not None
    reported = view.commissioning.step
    # the figures of the physics' own response, found here independently
    y = (samples[:, 1] - before) / 1.0
    t = samples[:, 0]
    t10 = np.interp(0.1, y[: np.argmax(y >= 0.9) + 1], t[: np.argmax(y >= 0.9) + 1])
    t90 = np.interp(0.9, y[: np.argmax(y >= 0.9) + 1], t[: np.argmax(y >= 0.9) + 1])
    overshoot = 100.0 * (y.max() - 1.0)
    assert reported.rise_time == pytest.approx(t90 - t10, abs=0.002)  # one PLC cycle
    assert reported.overshoot == pytest.approx(overshoot, abs=1.0)
    assert reported.settling_time < STEP_WINDOW
    assert abs(reported.steady_state_error) < gantry.scene.axes["X"].config.in_position
    assert t[0] - start <= 0.0021  # the step started in the scan that reported it
    assert samples[-1, 1] - before == pytest.approx(1.0, abs=0.005)


def test_a_step_test_needs_standstill_and_a_bounded_amplitude(
    gantry: Session, clock: FakeClock
) -> None:
    requests = gantry.requests("X")
    requests.step_test(50.0, client_id=1)  # beyond 5 mm
    record(gantry, 10)
    assert "refused: amplitude" in gantry.snapshot.axes["X"].message
    requests.jog(1)
    record(gantry, 20)
    requests.jog(1)
    requests.step_test(1.0, client_id=1)
    record(gantry, 10)
    view = gantry.snapshot.axes["X"]
    assert "refused: the axis must stand still" in view.message
    assert view.commissioning is not None and view.commissioning.step is None
    assert any("Step test: refused" in e.text for e in gantry.snapshot.events)


# ------------------------------------------------------------------------------------ repeat


def test_with_repeat_on_the_press_demo_starts_again(clock: FakeClock) -> None:
    session = Session("press", clock=clock)
    session.repeat_demo = True
    session.start_demo()
    plc = session.scene.runtime.plc_period
    runs: list[int] = []
    done_at: list[float] = []
    for _ in range(round(10.0 / (50 * plc))):
        session.advance(50)
        demo = session.snapshot.demo
        runs.append(demo.runs)
        if demo.done and (not done_at or done_at[-1] < session.scene.time - 2.0):
            done_at.append(session.scene.time)
    assert max(runs) >= 2
    assert len(done_at) >= 2  # it ended, then ran through again
    assert done_at[1] - done_at[0] > REPEAT_PAUSE


def test_a_failed_demo_does_not_repeat(clock: FakeClock) -> None:
    class Failing:
        def __init__(self, scene: Any) -> None:
            self.step, self.done, self.error = "failing", False, ""

        def __call__(self) -> None:
            raise RuntimeError("bug")

    session = Session("gantry", clock=clock, demo=Failing)
    session.repeat_demo = True
    session.start_demo()
    session.advance(1500)
    demo = session.snapshot.demo
    assert demo.runs == 1 and demo.error and not demo.running


# ------------------------------------------------------------------------------------ controls


def _callbacks_without_a_browser(app: ViewerApp) -> None:
    """Let the values the gate passes on reach the elements' callbacks at once (viser runs
    them only for a connected page, in its thread pool)."""
    gui = app.server.gui
    passed_on = gui._handle_gui_updates

    async def update(client_id: Any, message: Any) -> None:
        await passed_on(client_id, message)
        handle = app.server.gui._gui_input_handle_from_uuid[message.uuid]
        for callback in handle._impl.update_cb:
            callback(viser.GuiEvent(cast(Any, None), client_id, handle))

    gui._handle_gui_updates = update  # type: ignore[method-assign]


def _gui_update(app: ViewerApp, client_id: int, handle: Any, value: Any) -> None:
    """Deliver a GUI value from page ``client_id`` as the websocket would."""
    import viser._messages

    message = viser._messages.GuiUpdateMessage(handle._impl.uuid, {"value": value})
    run_coroutine(app.gate._on_update(client_id, message))  # type: ignore[arg-type]


def _input(app: ViewerApp, label: str, axis_index: int = 0) -> Any:
    handles = [h for h in app._scene_inputs if getattr(h, "label", "") == label]
    return handles[axis_index]


def test_the_controls_start_a_sequence_and_choose_the_jog_speed(
    server: viser.ViserServer, gantry: Session
) -> None:
    app = ViewerApp(gantry, server)
    _callbacks_without_a_browser(app)
    assert set(app._commissioning) == {"X", "Y", "Z"}
    app.control.take(5)
    speed = _input(app, "Jog speed")
    _gui_update(app, 5, speed, JOG_SPEEDS[1])
    assert gantry.requests("X").jog_slow
    _gui_update(app, 5, _input(app, "Override [%]"), 80.0)
    _gui_update(app, 5, _input(app, "Override [%]"), 200.0)  # beyond 150 %: refused
    assert gantry.requests("X").override == 80.0
    _gui_update(app, 5, _input(app, "B [mm]"), 20.0)
    _gui_update(app, 5, _input(app, "Cycles (0: until stopped)"), 1.0)
    _gui_update(app, 5, _input(app, "Dwell [s]"), 0.1)
    _gui_update(app, 5, _input(app, "Start sequence"), True)
    samples = record(gantry, 600)
    assert samples[:, 1].max() == pytest.approx(20.0, abs=0.01)
    assert samples[-1, 1] == pytest.approx(20.0, abs=0.01)  # A = 0, B = 20, one cycle
    app.frame()
    assert "cycle 1 of 1: done" in app._commissioning["X"].progress.content
    # a value out of range is refused, not passed on
    _gui_update(app, 5, _input(app, "Step amplitude [mm]"), 1e6)
    assert _input(app, "Step amplitude [mm]").value != 1e6
    # Repeat demo is a gated switch
    _gui_update(app, 6, app._repeat, "on")  # not in control
    assert not gantry.repeat_demo
    _gui_update(app, 5, app._repeat, "on")
    assert gantry.repeat_demo
    # the switch shows the session's setting, also one made elsewhere (Viewer(demo=True))
    gantry.repeat_demo = False
    app.frame()
    assert app._repeat.value == "off"
    gantry.repeat_demo = True
    app.frame()
    assert app._repeat.value == "on"


# ------------------------------------------------------------------------------------ browser


@pytest.mark.browser
def test_the_page_runs_a_step_test_and_shows_its_figures(page: Page, viewer: Viewer) -> None:
    session = viewer.session
    if not session.snapshot.axes["X"].powered:
        page.get_by_role("button", name="Power", exact=True).click()
        wait_for(lambda: session.snapshot.axes["X"].powered, 5.0, "X powered")
    wait_for(
        lambda: (
            session.snapshot.axes["X"].state == "StandStill"
            and abs(session.snapshot.axes["X"].following_error) < 0.005
        ),
        5.0,
        "X in position",
    )
    folder = page.get_by_text("Commissioning", exact=True).first
    folder.scroll_into_view_if_needed()
    folder.click()
    button = page.get_by_role("button", name="Step test", exact=True).first
    button.scroll_into_view_if_needed()
    start = session.scene.joint_position("X")
    button.click()
    page.get_by_text("rise time", exact=False).first.wait_for(timeout=30_000)
    step = session.snapshot.axes["X"].commissioning
    assert step is not None and step.step is not None
    moved = (session.scene.joint_position("X") - start) * 1e3
    assert moved == pytest.approx(step.step.amplitude, abs=0.01)  # the step, on the joint

"""What the panels say happened: a move stopped by a limit switch is "Aborted", a target beyond
a software limit is "Refused" with the limit named; Reset clears the red line; the Home position
field shows what homing gives the axis; the error history is the machine's own; the measuring
wheel standing still reads (close to) 0 mm/s; a finished demo says "Done" once. Sessions
driven synchronously (``advance``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

import numpy as np
import pytest

from plc.operator.hmi import HOMING_PROCEDURES, Move
from viewer.pages import axis_panel
from viewer.pages.overview import overview_html
from viewer.pages.panels import axis_panel_html, demo_html, events_html
from viewer.sim.session import Session
from viewer.sim.snapshot import AxisView, DemoView


@pytest.fixture
def gantry() -> Iterator[Session]:
    """The gantry, X powered (not homed: its software limits are off)."""
    session = Session("gantry")
    session.requests("X").set_power(True)
    session.advance(500)
    yield session
    session.close()


def x(session: Session) -> AxisView:
    return session.snapshot.axes["X"]


def test_a_move_a_limit_switch_stops_is_aborted_not_refused(gantry: Session) -> None:
    gantry.requests("X").move(Move("relative", 2000.0, 200.0, 2000.0))
    gantry.advance(8000)
    view = x(gantry)
    assert view.error_id == 2004  # LIM+ stopped it on its way
    assert view.last_error.startswith("Move by: error 2004")
    assert view.last_error_kind == "Aborted"
    assert 'data-text="Aborted"' in axis_panel_html(view)
    assert 'data-text="Refused"' not in axis_panel_html(view)
    assert "aborted: Move by: error 2004" in overview_html(gantry.snapshot)


def test_a_target_beyond_a_software_limit_is_refused_with_the_limit(gantry: Session) -> None:
    gantry.requests("X").home("recipe", 0.0)
    gantry.advance(20_000)
    assert x(gantry).referenced
    gantry.requests("X").move(Move("absolute", 5000.0, 100.0, 1000.0))
    gantry.advance(50)
    view = x(gantry)
    assert view.last_error_kind == "Refused"
    assert "error 8" in view.last_error
    assert "target 5000.000 mm beyond the positive SW limit 1002.000 mm" in view.last_error
    assert 'data-text="Refused"' in axis_panel_html(view)
    gantry.requests("X").move(Move("relative", -2000.0, 100.0, 1000.0))
    gantry.advance(50)
    assert "beyond the negative SW limit -2.000 mm" in x(gantry).last_error


def test_reset_clears_the_red_line_of_the_last_error(gantry: Session) -> None:
    gantry.requests("X").move(Move("relative", 2000.0, 200.0, 2000.0))
    gantry.advance(8000)
    assert x(gantry).last_error
    gantry.requests("X").reset()
    gantry.advance(100)
    view = x(gantry)
    assert view.message == "Reset: done"
    assert view.last_error == "" and view.error_id == 0
    html = axis_panel_html(view)
    assert 'data-text="Aborted"' not in html and 'data-text="Refused"' not in html
    assert "#c62828" not in html  # nothing red left


def test_the_home_position_field_shows_what_homing_gives_the_axis(gantry: Session) -> None:
    recipe = x(gantry).home_position
    assert recipe == 120.0  # the gantry's X: the index pulse is 120 mm of the joint
    field = axis_panel.home_position_field("recipe", recipe, 7.0, "mm")
    assert field.value == 120.0 and field.disabled and "120 mm" in field.hint
    for procedure in HOMING_PROCEDURES[1:]:
        field = axis_panel.home_position_field(procedure, recipe, 7.0, "mm")
        assert field.value == 7.0 and not field.disabled
    gantry.requests("X").home("recipe", 0.0)
    gantry.advance(20_000)
    assert x(gantry).position == pytest.approx(120.0, abs=0.01)  # what the field shows
    set_here = HOMING_PROCEDURES[3]
    gantry.requests("X").home(set_here, 0.0)
    gantry.advance(100)
    assert x(gantry).position == pytest.approx(0.0, abs=0.01)  # what the field said


def test_the_error_history_is_the_machine_s_own(gantry: Session) -> None:
    gantry.requests("X").move(Move("relative", 2000.0, 200.0, 2000.0))
    gantry.advance(8000)
    assert "error 2004" in events_html(gantry.snapshot)
    gantry.load("cell")
    gantry.advance(10)
    history = events_html(gantry.snapshot)
    assert "error 2004" not in history
    assert "No errors on cell." in history
    assert "2 more on other machines" in history


def test_the_measuring_wheel_standing_still_reads_its_mean_velocity() -> None:
    from viewer.sim import velocity  # the module of the shown velocity

    session = Session("flying_shear")
    session.advance(round(velocity.WINDOW / session.scene.runtime.plc_period) + 10)
    shown, raw = [], []
    for _ in range(200):
        session.advance(7)
        shown.append(session.snapshot.axes["W"].velocity)
        raw.append(session.scene.axes["W"].VEL)
    session.close()
    assert np.ptp(raw) >= 25.0  # one count (0.025 mm) per 1 ms servo cycle
    assert (
        np.max(np.abs(shown)) <= 0.025 / velocity.WINDOW + 1e-9
    )  # one count per window: 0.25 mm/s


def test_a_refusal_is_said_once_in_the_axis_panel() -> None:
    session = Session("gantry")
    session.requests("X").move(Move("relative", 10.0, 100.0, 1000.0))  # not powered
    session.advance(50)
    view = x(session)
    assert view.last_error_kind == "Refused" and view.message == view.last_error
    panel = axis_panel_html(view)
    assert panel.count(view.last_error.split(" (")[0]) == 1, panel
    session.requests("X").set_power(True)
    session.advance(50)
    session.requests("X").move(Move("relative", 1.0, 100.0, 1000.0))
    session.advance(500)
    assert x(session).message == "Move by: done"  # another outcome is said under the lamps
    assert "Move by: done" in axis_panel_html(x(session))


@pytest.mark.parametrize(
    ("step", "done", "running", "text"),
    [
        ("done", True, False, "Done"),
        ("parked", True, False, "Done: parked"),
        ("move X", False, True, "Step: move X"),
        ("move X", False, False, "Ended at: move X"),
    ],
)
def test_the_demo_box_says_done_once(step: str, done: bool, running: bool, text: str) -> None:
    session = Session("single_axis")
    snapshot = dataclasses.replace(
        session.snapshot, demo=DemoView(True, running, done, step, ""), groups=()
    )
    session.close()
    assert demo_html(snapshot).split(">", 1)[1].startswith(f"{text}<")

"""A click's effect shows at the next frame: when an axis' state, motion or message changes,
the panels go out at once (and every frame for a moment), not at the next panel refresh."""

from __future__ import annotations

import time

import viser

from tests.viewer.test_session import FakeClock, run
from viewer.pages.app import PROMPT_SECONDS, ViewerApp
from viewer.sim.session import Session


def test_an_axis_that_starts_a_command_is_shown_at_the_next_frame(
    server: viser.ViserServer,
) -> None:
    """Panels refreshed every 2 s: a frame with nothing new for the axes sends no panel; the
    frame after Power sends the axis panel reading StandStill."""
    clock = FakeClock()
    session = Session("single_axis", clock=clock)
    app = ViewerApp(session, server, clock=clock, panel_hz=0.5)
    run(session, clock, 0.05)  # the first scans: the axis reads Disabled
    app.frame()
    time.sleep(PROMPT_SECONDS + 0.05)  # the first frame's prompt is over
    run(session, clock, 0.05)
    app.frame()
    assert app.panel_updates == 1  # nothing changed for the axes: the next refresh in 2 s
    session.requests("X").set_power(True)
    run(session, clock, 0.1)
    assert session.snapshot.axes["X"].state == "StandStill"
    app.frame()
    assert app.panel_updates == 2
    assert "StandStill" in app._axes["X"].html
    time.sleep(PROMPT_SECONDS + 0.05)
    run(session, clock, 0.05)
    app.frame()
    assert app.panel_updates == 2  # the moment is over: back to the panel rate

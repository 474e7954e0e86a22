"""The group's commanded and actual path in the 3-D view, as the viewer sends it while the
gantry's group runs a circle: the commanded points on the commanded circle, the actual ones drawn
at 100 × their deviation measured from the physics' joints (the factor written beside them), the
trail emptied by Clear path and when the machine changes, and never longer than its bound."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
import viser

import mcl
from scenes.scene import Scene
from scenes.tools.grouping import PoweredGroup
from tests.viewer.test_session import FakeClock
from viewer.pages.app import ViewerApp
from viewer.sim.session import Session
from viewer.view3d.overlays import ghost_axes
from viewer.view3d.path_trail import CHUNK, TRAIL_POINTS, PathTrail

RADIUS = 20.0
"""Radius of the circle [mm]."""

OUT_OF_THE_CORNER = [60.0, 60.0, 0.0]
"""The line before the circle, away from the limit switches [mm]."""


class CircleDemo:
    """The gantry's axes grouped, a line out of the corner, then a full counter-clockwise circle
    in XY by its centre, ``radius`` [mm] to +X of the start, at ``velocity`` [mm/s]; then the
    group disabled and taken apart."""

    def __init__(self, scene: Scene, radius: float = RADIUS, velocity: float = 100.0) -> None:
        self.radius, self.velocity = radius, velocity
        self.grouped = PoweredGroup([scene.axes[a] for a in "XYZ"], "XYZ", 0.1)
        group = self.grouped.group
        self.line = mcl.MC_MoveLinearRelative(AxesGroup=group)
        self.circle = mcl.MC_MoveCircularRelative(AxesGroup=group)
        self.disable = mcl.MC_GroupDisable(AxesGroup=group)
        self.ungroup = mcl.MC_UngroupAllAxes(AxesGroup=group)
        self.finishing = self.ungrouping = False
        self.step, self.done, self.error = "grouping", False, ""

    def __call__(self) -> None:
        self.grouped()
        ramp = {"Velocity": self.velocity, "Acceleration": 2e3, "Deceleration": 2e3, "Jerk": 2e4}
        self.line(Execute=self.grouped.enable.Done, Distance=OUT_OF_THE_CORNER, **ramp)
        self.circle(
            Execute=self.line.Done,
            CircMode=mcl.MC_CIRC_MODE.CENTER,
            AuxPoint=[self.radius, 0.0, 0.0],
            EndPoint=[0.0, 0.0, 0.0],
            PathChoice=mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE,
            **ramp,
        )
        self.finishing = self.finishing or bool(self.circle.Done)
        self.disable(Execute=self.finishing)
        self.ungrouping = self.ungrouping or bool(self.disable.Done)
        self.ungroup(Execute=self.ungrouping)
        self.done = bool(self.ungroup.Done)  # the axes left at rest, outside any group
        self.step = (
            "circle" if self.line.Done else "line" if self.grouped.enable.Done else "grouping"
        )


def frames_until(app: ViewerApp, clock: FakeClock, done: Callable[[], bool], what: str) -> None:
    """Run the session 10 ms at a time, a frame after each, until ``done()``."""
    session = app.session
    for _ in range(1000):
        session.advance(5)
        clock.now += 5 * session.scene.runtime.plc_period
        app.frame()
        if done():
            return
    raise AssertionError(f"{what}: not within 10 s")


def test_the_circle_is_drawn_commanded_and_actual_magnified(server: viser.ViserServer) -> None:
    clock = FakeClock()
    session = Session("gantry", clock=clock, demo=CircleDemo)
    app = ViewerApp(session, server, clock=clock)
    app.views.path.choice = "×100"  # as the View folder's Path choice sets it
    session.start_demo()
    demo = session._demo.program
    assert isinstance(demo, CircleDemo)
    frames_until(app, clock, lambda: bool(demo.line.Done), "the line")
    trail = app.views.path.trail
    assert trail is not None and len(trail.commanded) > 10  # the line was drawn
    app.views.path.request_clear()  # as the Clear path button does
    app._redraw = True
    app.frame()
    assert len(trail.commanded) <= 1  # Clear path: at most this frame's point
    frames_until(app, clock, lambda: demo.done, "the circle")

    commanded, actual = trail.commanded, trail.actual
    assert len(commanded) > 100
    centre = commanded[0] + [RADIUS / 1e3, 0.0, 0.0]
    radius = np.linalg.norm((commanded - centre)[:, :2], axis=1)
    assert np.abs(radius - RADIUS / 1e3).max() < 5e-6  # on the commanded circle
    assert np.ptp(commanded[:, 2]) < 5e-6
    angles = np.unwrap(np.arctan2(*(commanded - centre)[:, 1::-1].T))
    assert angles[-1] - angles[0] == pytest.approx(2 * np.pi, abs=0.05)

    drawn_commanded, drawn_actual = trail.drawn
    np.testing.assert_allclose(drawn_commanded[:, 0], commanded[:-1], atol=1e-12)
    deviation = actual - commanded
    np.testing.assert_allclose(drawn_actual[:, 1], (commanded + 100.0 * deviation)[1:], atol=1e-9)
    assert np.linalg.norm(deviation, axis=1).max() > 1e-6  # a deviation the ×100 shows
    # a point of the trail: the physics' tool point, and where the set points put it (the
    # gantry's axes run along x, y and z)
    tool = session.scene.data.site("gantry/tool").xpos
    errors = [session.snapshot.axes[a].following_error for a in "XYZ"]
    at_set_points, measured = trail.measure(session.snapshot.qpos, errors)
    np.testing.assert_allclose(measured, tool, atol=1e-12)
    np.testing.assert_allclose(at_set_points, tool + np.array(errors) / 1e3, atol=1e-12)
    assert "×100" in trail.label

    trail.magnification = 10.0
    np.testing.assert_allclose(trail.drawn[1][:, 1], (commanded + 10.0 * deviation)[1:], atol=1e-9)
    assert "×10 " in trail.label + " "

    session.load("press")
    app.frame()
    assert app.views.path.trail is None  # dropped with the machine


def test_the_trail_keeps_its_bound(server: viser.ViserServer) -> None:
    """A long trail keeps no more than TRAIL_POINTS (plus one chunk) points, the newest ones."""
    snapshot = Session("gantry").snapshot
    assert snapshot.model is not None
    axes = ghost_axes(snapshot.model, "gantry", [(a, f"gantry/{a}") for a in "XYZ"])
    trail = PathTrail(server, snapshot.model, axes)
    qpos = snapshot.qpos.copy()
    x = axes[0].qpos_adr
    for k in range(TRAIL_POINTS + 3 * CHUNK):
        qpos[x] = 1e-4 * k
        trail.update(qpos, [0.0, 0.0, 0.0])
    points = trail.actual
    assert TRAIL_POINTS - CHUNK <= len(points) <= TRAIL_POINTS + CHUNK
    assert points[-1][0] - points[0][0] == pytest.approx(1e-4 * (len(points) - 1), rel=1e-6)
    trail.clear()
    assert len(trail.commanded) == 0 and trail.label == ""


def test_a_machine_without_a_group_has_no_path_choice(server: viser.ViserServer) -> None:
    clock = FakeClock()
    app = ViewerApp(Session("press", clock=clock), server, clock=clock)
    app.frame()
    assert not app.views.path.available
    app.session.load("gantry")
    app.frame()
    assert app.views.path.available

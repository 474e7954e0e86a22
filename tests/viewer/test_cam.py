"""The viewer's cam view data: a slave cammed on the gantry (Y to X) publishes its table's
profile and an operating point that agrees with its set point; nothing when no axis is cammed."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
import pytest
import viser

import mcl
from scenes.scene import Scene
from tests.viewer.test_session import FakeClock, run
from viewer.pages.cam_panel import CamPanel, info_html, plot_data, plot_style
from viewer.sim.cam_view import CamView
from viewer.sim.session import Session

LIFT = mcl.MC_CAM_REF(
    Points=[
        mcl.MC_CamPoint(0.0, 0.0, 0.0, 0.0, mcl.CamLaw.Polynomial5),
        mcl.MC_CamPoint(10.0, 5.0, 0.0, 0.0, mcl.CamLaw.ModifiedSine),
        mcl.MC_CamPoint(20.0, 0.0, 0.0, 0.0, mcl.CamLaw.Linear),
    ],
    Name="lift 5 mm",
)
"""Y lifts 5 mm and returns while X travels 20 mm (per period)."""


class CamDemo:
    """Power X and Y, cam Y to X through :data:`LIFT` (relative), move X 30 mm."""

    def __init__(self, scene: Scene) -> None:
        self.X, self.Y = scene.axes["X"], scene.axes["Y"]
        self.power_x, self.power_y = mcl.MC_Power(), mcl.MC_Power()
        self.select = mcl.MC_CamTableSelect()
        self.cam_in = mcl.MC_CamIn()
        self.move = mcl.MC_MoveRelative()
        self.step, self.done, self.error = "power on", False, ""
        self.coupled_at: tuple[float, float] | None = None
        """X's and Y's set points [mm] where Y was coupled (X stands until then)."""

    def __call__(self) -> None:
        X, Y = self.X, self.Y
        self.power_x(Axis=X, Enable=True)
        self.power_y(Axis=Y, Enable=True)
        on = self.power_x.Status and self.power_y.Status
        self.select(
            Master=X,
            Slave=Y,
            Execute=on,
            CamTable=LIFT,
            Periodic=True,
            MasterAbsolute=False,
            SlaveAbsolute=False,
        )
        self.cam_in(
            Master=X,
            Slave=Y,
            Execute=self.select.Done or self.cam_in.Busy,
            CamTableID=self.select.CamTableID,
            MasterScaling=1.0,
            SlaveScaling=1.0,
        )
        if self.cam_in.InSync and self.coupled_at is None:
            self.coupled_at = X.sp_pos, Y.sp_pos
        self.move(
            Axis=X,
            Execute=self.cam_in.InSync,
            Distance=30.0,
            Velocity=60.0,
            Acceleration=600.0,
            Deceleration=600.0,
            Jerk=20000.0,
        )
        if self.cam_in.Error or self.move.Error:
            self.error = f"cam {self.cam_in.ErrorID}, move {self.move.ErrorID}"


@pytest.fixture
def session() -> tuple[Session, FakeClock]:
    clock = FakeClock()
    return Session("gantry", clock=clock, demo=CamDemo), clock


def test_a_cammed_slave_publishes_its_profile_and_an_operating_point_on_its_set_point(
    session: tuple[Session, FakeClock],
) -> None:
    sess, clock = session
    assert not sess.snapshot.cams, "nothing is cammed yet"
    sess.start_demo()
    run(sess, clock, 0.3)
    views = sess.snapshot.cams
    assert [v.slave for v in views] == ["Y"]
    view = views[0]
    assert (view.master, view.name) == ("X", "lift 5 mm")
    assert view.profile.laws == ("Polynomial5", "ModifiedSine")
    assert view.profile.period == 20.0 and view.profile.periodic
    # the profile: rest at both ends, the 5 mm lift at the middle point
    profile = view.profile
    assert profile.master[0] == 0.0 and profile.master[-1] == 20.0
    assert profile.slave.max() == pytest.approx(5.0, abs=1e-12)
    middle = int(np.argmin(np.abs(profile.master - 10.0)))
    assert profile.master[middle] == 10.0 and profile.slave[middle] == pytest.approx(5.0)
    assert abs(profile.velocity[0]) < 1e-12 and abs(profile.velocity[-1]) < 1e-12
    demo = sess._demo.program
    assert isinstance(demo, CamDemo) and demo.coupled_at is not None
    assert view.table_id == demo.select.CamTableID > 0
    x0, y0 = demo.coupled_at
    points: list[CamView] = []
    for _ in range(12):  # X moves 30 mm: one period boundary passed
        run(sess, clock, 0.05)
        snapshot = sess.snapshot
        p = snapshot.cams[0]
        points.append(p)
        # from the axes' own set points: the table starts where X and Y were at the coupling
        x, y = snapshot.axes["X"].set_position, snapshot.axes["Y"].set_position
        assert p.table_master == pytest.approx((x - x0) % 20.0, abs=1e-9)
        assert p.set_slave == pytest.approx(y - y0, abs=1e-9)
    assert {p.cycle for p in points} == {0, 1}
    for p in points:
        assert p.coupled and p.in_sync
        assert 0.0 <= p.table_master < 20.0
        # the operating point is on the profile, and the slave's set point is there
        on_profile = float(np.interp(p.table_master, profile.master, profile.slave))
        assert p.table_slave == pytest.approx(on_profile, abs=2e-3)
        assert p.set_slave == pytest.approx(p.table_slave, abs=1e-9)
        assert abs(p.actual_slave - p.set_slave) < 0.5  # the servo's following error
    moved = [p.table_master for p in points]
    assert max(moved) - min(moved) > 10.0, "the operating point moves along the profile"
    last = points[-1]
    # what the page's cam view draws of it: the markers on the profile at the operating point
    grid, position, velocity, acceleration, *markers = plot_data(last)
    assert grid.size == position.size == velocity.size == acceleration.size
    at = int(np.nanargmax(markers[1]))
    assert abs(grid[at] - last.table_master) <= 20.0 / 1000
    assert markers[0][at] == last.table_slave and markers[1][at] == last.set_slave
    assert np.isnan(markers[1]).sum() == grid.size - 1
    text = info_html(last, ())
    assert f"table {last.table_id}" in text and "lift 5 mm" in text and "InSync" in text
    assert "Polynomial5, ModifiedSine" in text and "period 20 mm" in text


def test_the_cam_view_is_gone_once_the_slave_is_uncoupled(
    session: tuple[Session, FakeClock],
) -> None:
    sess, clock = session
    sess.start_demo()
    run(sess, clock, 0.3)
    assert sess.snapshot.cams
    sess.stop_all()
    run(sess, clock, 0.3)
    assert not sess.snapshot.cams


def test_a_modulo_slave_shows_its_actual_position_in_the_tables_period() -> None:
    """The rotary cutter's drum (modulo 360°) on its cam: the actual position the view gives is
    the set point's, within the servo's following error, in the same period (not the wrapped
    axis position against a continuous set point), and the plot's scales are the profile's
    (finite: the markers' rows, NaN but at the operating point, do not set them)."""
    clock = FakeClock()
    sess = Session("rotary_cutter", clock=clock)
    sess.start_demo()
    for _ in range(60):
        run(sess, clock, 0.25)
        if sess.snapshot.cams and sess.snapshot.demo.step.startswith("cut"):
            break
    views = sess.snapshot.cams
    assert views and views[0].slave == "D" and views[0].in_sync, sess.snapshot.demo.step
    view = views[0]
    assert 0.0 <= view.set_slave <= 360.0
    assert abs(view.actual_slave - view.set_slave) < 1.0, (view.actual_slave, view.set_slave)
    _, _, scales = plot_style(view)
    ranges = {name: scale["range"] for name, scale in scales.items()}
    for name, (low, high) in ranges.items():
        assert low is not None and high is not None and np.isfinite([low, high]).all(), name
    low, high = ranges["y0"]
    assert low is not None and high is not None and low <= 0.0 and high >= 360.0


def test_a_new_profile_reaches_the_page_with_its_data_in_one_message(
    server: viser.ViserServer, session: tuple[Session, FakeClock]
) -> None:
    """The cam view sends a profile's series, axes and scales with its data in one atomic
    message (a page given the series first drew series without data and failed in uPlot)."""
    sess, clock = session
    sess.start_demo()
    run(sess, clock, 0.3)
    sent: list[tuple[int, int]] = []

    @contextmanager
    def atomic() -> Iterator[None]:
        yield
        sent.append((len(panel.plot.series), len(panel.plot.data)))

    panel = CamPanel(server.gui, server.gui.add_folder("Cam"), atomic)
    initial = (len(panel.plot.series), len(panel.plot.data))
    panel.update(sess.snapshot)
    assert len(sent) == 1 and sent[0][0] == sent[0][1] > initial[0]  # series with their rows
    panel.update(sess.snapshot)
    assert len(sent) == 1  # nothing new: nothing sent
    run(sess, clock, 0.1)
    panel.update(sess.snapshot)  # the operating point moved: its data alone
    assert len(sent) == 2 and sent[1] == sent[0]

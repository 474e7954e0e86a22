"""The rotary cross cutter: web line, measuring wheel as master, knife drum geared to it.

Every figure is measured from the physics: the web joint M is the truth of every length, a cut
is where the blade's tip was on the web when it went through it (its depth from the drum angle).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import viser

import mcl
import scenes
from plc.procedures import HomeAxis
from scenes.machines import rotary_cutter as rc
from scenes.scene import Scene
from tests.viewer.test_session import FakeClock, run
from viewer.pages.app import ViewerApp
from viewer.sim.session import Session

P = f"{rc.MACHINE.name}/"
"""The prefix of the machine's names in the model of its scene."""


def load(ideal: bool = True, **options: object) -> Scene:
    """The rotary cutter; ``ideal``: a perfect measuring wheel and a drum without runout."""
    scene = scenes.load("rotary_cutter", trace_every=0, **options)
    if ideal:
        scene.device("wheel", rc.MeasuringWheel).ideal()
        drum(scene).ideal()
    return scene


def drum(scene: Scene) -> rc.KnifeDrum:
    return scene.device("drum", rc.KnifeDrum)


def cut(scene: Scene, job: rc.CutterJob, ratio: tuple[int, int] | None = None) -> rc.Demo:
    """Run the geared demo with ``job`` to its end or its error (``ratio``: another gear ratio,
    drum degrees per mm of web)."""
    demo = rc.Demo(scene, job)
    if ratio is not None:
        demo.gear.RatioNumerator, demo.gear.RatioDenominator = ratio
    scene.run(demo, until=lambda: demo.done or bool(demo.error), timeout=30.0)
    assert demo.done, demo.step
    return demo


def lengths(demo: rc.Demo) -> np.ndarray:
    """The lengths of the job's pieces [mm], from the physics."""
    return np.array([math.nan if c.length is None else c.length for c in demo.pieces()])


# ---------------------------------------------------------------------------------- homing
@pytest.mark.parametrize("start", [100.0, -45.0], ids=["off the cam", "on the cam"])
def test_the_drum_homes_on_its_ref_cam_and_the_motor_index(start: float) -> None:
    """From either side of the REF cam the drum finds the same origin: the motor index after
    the cam's edge at −36°, the drum's 0° (blades horizontal); the axis then reads the joint
    angle in degrees, modulo 360°, within a count or two (index jitter, encoder noise) once it
    stands."""
    scene = load(start={"D": math.radians(start)})
    D = scene.axes["D"]
    power, home = mcl.MC_Power(Axis=D), HomeAxis(D, rc.HOMING["D"])

    def program() -> None:
        power(Enable=True)
        home(Execute=power.Status)

    scene.run(program, until=lambda: home.Done or home.Error, timeout=20.0)
    assert home.Done and D.Ref, home.ErrorID
    done = scene.time  # the drum settles from its stop on the index, then stands
    scene.run(program, until=lambda: scene.time > done + 0.2, timeout=1.0)
    angle = math.degrees(scene.joint_position("D"))
    assert abs(angle) < 10.0  # stopped just past the index it set to 0°
    error = (D.POS - angle + 180.0) % 360.0 - 180.0
    assert abs(error) < 0.0075, error  # two counts of 0.0036°


# ---------------------------------------------------------------------------------- cutting
@pytest.mark.parametrize("blades", [2, 1])
def test_geared_pieces_are_one_blade_pitch_long_from_the_physics(blades: int) -> None:
    """Geared 18/25 °/mm to an ideal wheel, the tips run at web speed: every piece is the tip
    circle over the blades (250 or 500 mm) within 0.5 mm, the blades cut in turn, none misses,
    and while a blade is in the web its tip runs within 1.5 % of the web's speed (the tip's
    horizontal speed falls with the cosine of its angle, 0.44 % where it enters the web). The
    drive as it stands without its cutting-force feed-forward (the drum synchronous until the
    blade bites; the feed-forward's own test is below)."""
    scene = load()
    demo = cut(scene, rc.CutterJob(cuts=5, blades=blades, cut_force=0.0))
    pieces = demo.pieces()
    assert len(pieces) == 5 and not drum(scene).misses
    pitch = 500.0 / blades
    measured = lengths(demo)
    assert np.abs(measured - pitch).max() < 0.5, measured
    assert abs(measured.mean() - pitch) < 0.1, measured
    turns = [c.blade for c in pieces]
    assert set(turns) == set(range(1, blades + 1))
    assert all(a != b for a, b in itertools.pairwise(turns)) or blades == 1
    assert all(c.through and 0.3 <= c.depth <= 0.36 for c in pieces)
    mismatch = max(c.mismatch for c in pieces)
    assert 0.0044 < mismatch < 0.015, mismatch
    for c in pieces:  # the drive's load against the motor's catalogue limits
        assert 0.0 < c.torque < 71.3 and c.current < drum(scene).peak_current


def test_the_wheels_slip_lengthens_the_pieces_by_its_share() -> None:
    """The wheel is the master: at −0.3 % slip it reads short, the drum turns 0.3 % slower
    than the web and every piece comes out 250 mm / 0.997 (+0.75 mm)."""
    scene = load()
    scene.device("wheel", rc.MeasuringWheel).slip = -0.003
    np.testing.assert_allclose(lengths(cut(scene, rc.CutterJob(cuts=4))), 250.0 / 0.997, atol=0.05)


def test_a_drum_out_of_sync_with_the_web_shows_its_mismatch_and_drag() -> None:
    """Geared 17/25 instead of 18/25, the tips run 5.6 % slower than the web: the pieces are
    264.7 mm, the mismatch in the web above 5 %, the blade drags on the web with ~190 N (in
    sync: ~25 N) and the drum's peak torque per cut triples."""
    synced = load()
    good = cut(synced, rc.CutterJob(cuts=4)).pieces()
    slow = cut(load(), rc.CutterJob(cuts=4), ratio=(17, 25))
    bad = slow.pieces()
    np.testing.assert_allclose(lengths(slow), 250.0 * 18 / 17, atol=0.1)
    assert min(c.mismatch for c in bad) > 0.05 > 0.015 > max(c.mismatch for c in good)
    assert min(c.drag for c in bad) > 150.0 > 50.0 > max(c.drag for c in good)
    assert min(c.torque for c in bad[1:]) > 2.0 * max(c.torque for c in good[1:])


@pytest.mark.parametrize("speed", [500.0, 1000.0, 1500.0], ids=["30 m/min", "60", "90"])
def test_the_cutting_force_feed_forward_keeps_the_tips_with_the_web_at_every_speed(
    speed: float,
) -> None:
    """The drive's cutting-force feed-forward (2 kN, the board's) holds the drum's speed as the
    blade bites: at 30, 60 and 90 m/min the tips run within 0.8 % of the web while in it (up
    to 0.44 % is the geometry) and the pieces stay one pitch long; without it the drum dips by
    about the same speed at every line speed, 1.2 % of the web's or more at 30 m/min."""
    job = rc.CutterJob(speed=speed, cuts=5)
    fed = cut(load(), job)
    mismatch = [c.mismatch for c in fed.pieces()]
    assert len(mismatch) >= 4 and max(mismatch) < 0.008, mismatch
    assert np.abs(lengths(fed) - 250.0).max() < 0.5
    if speed == 500.0:
        bare = cut(load(), rc.CutterJob(speed=speed, cuts=5, cut_force=0.0))
        assert min(c.mismatch for c in bare.pieces()) > 0.012


def test_a_blade_that_does_not_go_through_the_web_cuts_nothing() -> None:
    """With 0.06 mm of drum runout blade 1's tip stops 0.29 mm deep in the 0.3 mm web: its
    passes are misses, only blade 2 separates the web, so the pieces are 500 mm long."""
    scene = load()
    drum(scene).runout = 6e-5
    demo = cut(scene, rc.CutterJob(cuts=4))
    assert len(demo.pieces()) >= 3 and {c.blade for c in demo.pieces()} == {2}
    np.testing.assert_allclose(lengths(demo), 500.0, atol=0.5)
    misses = drum(scene).misses
    assert misses and {m.blade for m in misses} == {1}
    assert all(0.28 < m.depth < 0.3 for m in misses)


# ---------------------------------------------------------------------------------- configuration
def test_a_bad_configuration_is_refused_with_a_clear_message() -> None:
    scene = load()
    with pytest.raises(ValueError, match=r"3 blades fitted; the drum takes 1 or 2"):
        drum(scene).blades = 3
    with pytest.raises(ValueError, match=r"blades must be 1 or 2"):
        rc.CutterJob(blades=0)
    with pytest.raises(ValueError, match=r"needs the drum at 720 rpm .* at most 4500 mm/s"):
        rc.CutterJob(speed=6000.0)
    with pytest.raises(ValueError, match=r"cuts must be >= 1"):
        rc.CutterJob(cuts=0)
    assert drum(scene).blades == 2  # the refused setting changed nothing


# ---------------------------------------------------------------------------------- viewer
def test_the_viewer_draws_the_fitted_blades_and_runs_the_demo(server: viser.ViserServer) -> None:
    """The machine loads in the viewer: every blade fitted has a node (with one blade the
    second is not drawn), the demo runs in the session and the drum turns."""
    clock = FakeClock()
    session = Session("rotary_cutter", clock=clock)
    drum(session.scene).blades = 1
    app = ViewerApp(session, server, clock=clock)
    app.frame()
    handles = app._model_scene.geom_handles  # type: ignore[union-attr]
    assert f"{P}blade_1" in handles and f"{P}blade_2" not in handles
    assert f"{P}drum_geom" in handles and f"{P}web_geom" in handles
    session.start_demo()
    run(session, clock, 2.0)
    app.frame()
    demo = session.snapshot.demo
    assert demo.running and not demo.error and demo.step != "power on", demo
    assert abs(session.scene.joint_position("D")) > 0.5  # the drum homed and turned

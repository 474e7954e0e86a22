"""The knife drum supervised in every state where its loop stays closed, judged by the physics.

The drum runs on the cam demo (scenes.machines.rotary_cutter.cam_demo): 300 mm pieces at
60 m/min. What a user sees is measured per servo instant from the MuJoCo drum joint (angle,
rate), the blades in the web (the drum device), the volts and the enable the amplifier gets and
AxErrorID.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import pytest

import mcl
import scenes
from mcl import AxisState, ErrorID
from mcl import faults as flt
from plc.procedures import HomeAxis
from scenes.machines import rotary_cutter as rc
from scenes.machines.rotary_cutter.cam_demo import Batch, CamDemo, CamJob
from scenes.parts import MeasuringWheel
from scenes.scene import Scene
from tests.helpers import scan

PIECE = 300.0
"""Piece length [mm]."""
DEV_MAX = 5.0
"""The drum's DevMax [°]."""
SERVO = 0.001
"""Servo period [s]."""


def wrap(angle: float) -> float:
    """An angle difference in [−180°, 180°)."""
    return (angle + 180.0) % 360.0 - 180.0


@dataclass
class Sample:
    """One servo instant of the drum."""

    t: float
    angle: float
    """Drum joint angle [°] (continuous)."""
    rate: float
    """Drum joint rate [°/s]."""
    volts: float
    enabled: bool
    error: int
    hold: float
    """The model position (GT_SInfo 20, OPT1n) [°], within 0..360."""
    moving: bool
    """The model velocity (GT_SInfo 21, OPT2n) is not 0."""
    in_web: bool
    """A blade's tip is in the web."""


class DrumLog:
    """Every servo instant of the drum (an observer of the scene's runtime)."""

    def __init__(self, scene: Scene) -> None:
        self.scene, self.axis = scene, scene.axes["D"]
        self.joint = scene.joint("D")
        self.io = scene.io("D")
        self.drum = scene.device("drum", rc.KnifeDrum)
        self.samples: list[Sample] = []
        scene.runtime.observers.append(self)

    def __call__(self, t: float) -> None:
        axis, io = self.axis, self.io
        self.samples.append(
            Sample(
                t,
                math.degrees(self.joint.position),
                math.degrees(self.joint.velocity),
                io.volts,
                io.enabled,
                axis.AxErrorID,
                axis.OPT1n,
                axis.OPT2n != 0.0,
                self.drum.engaged,
            )
        )

    def since(self, t: float) -> list[Sample]:
        return [s for s in self.samples if s.t >= t]

    @staticmethod
    def passes(samples: list[Sample]) -> int:
        """Blade passes into the web that begin within ``samples``."""
        return sum(not a.in_web and b.in_web for a, b in itertools.pairwise(samples))


class Line:
    """The cam demo cutting 300 mm pieces at 60 m/min inside a PLC program that may speed the
    line up (MC_MoveVelocity on L, its own block) and stops the web (MC_Stop on L) as soon as
    the drum has an error."""

    def __init__(self) -> None:
        scene = self.scene = scenes.load("rotary_cutter", trace_every=0)
        scene.device("wheel", MeasuringWheel).ideal()
        scene.device("drum", rc.KnifeDrum).ideal()
        self.demo = CamDemo(scene, CamJob(batches=(Batch(PIECE, 1000),), learn_scale=False))
        L, self.D, self.W = (scene.axes[n] for n in ("L", "D", "W"))
        self.faster = mcl.MC_MoveVelocity(
            Axis=L, Velocity=1500.0, Acceleration=1000.0, Deceleration=1000.0
        )
        self.stop = mcl.MC_Stop(Axis=L, Deceleration=1000.0)
        self.speed_up = False
        self.boundaries: list[float] = []
        """The wheel's position at each period boundary the program saw [mm]."""
        self.log = DrumLog(scene)

    def __call__(self) -> None:
        """One PLC scan."""
        demo = self.demo
        seen = len(demo.boundaries)
        demo()
        if len(demo.boundaries) > seen:
            self.boundaries.append(self.W.POS)
        self.faster(Execute=self.speed_up)
        self.stop(Execute=self.D.AxErrorID != 0)

    def cutting(self, pieces: int) -> None:
        """Run until ``pieces`` pieces of the batch have been cut."""
        self.scene.run(self, until=lambda: len(self.boundaries) > pieces + 1, timeout=20.0)

    def phase(self) -> float:
        """Where in its piece the web is [0..1)."""
        return ((self.W.POS - self.boundaries[-1]) % PIECE) / PIECE

    def web_speed(self) -> float:
        """The web's speed from the physics [m/min]."""
        return 60.0 * self.scene.joint("M").velocity

    def until_error(self) -> float:
        """Run until the drum has an error; the time of it [s]."""
        self.scene.run(self, until=lambda: self.D.AxErrorID, timeout=10.0)
        return self.scene.time


def speed_up_at(phase: int) -> tuple[Line, float, float]:
    """The line speeds up to 90 m/min at 1 m/s² from ``phase``/12 of a piece on: the cam stops
    the drum with ECamLimit. Runs on for 1.5 s (the program stops the web meanwhile); returns
    the line, the web speed at the error [m/min] and the time the stop ramp ended [s]."""
    line = Line()
    line.cutting(2)
    line.scene.run(line, until=lambda: line.phase() >= phase / 12.0, timeout=1.0)
    line.speed_up = True
    t_error = line.until_error()
    web = line.web_speed()
    line.scene.run(line, timeout=1.5)
    ramp_end = next(s.t for s in line.log.since(t_error) if not s.moving)
    return line, web, ramp_end


def test_a_cam_stop_that_leaves_the_blade_in_the_web_leaves_no_loop_fighting_it() -> None:
    """300 mm pieces at 60 m/min, then the line speeds up to 90 m/min at 1 m/s²: at about
    78 m/min the cam's check stops the drum with ECamLimit 23. For each of 12 phases of the piece
    at which the speed-up starts, measured from the end of the stop ramp on:

    - the drum holds where the ramp ended (its model position is the drum's angle: no wrap);
    - while its loop is closed the drum stays within DevMax of that hold, and a following error
      beyond it opens the loop with 2001 (enable off after the quick stop);
    - no blade goes into the web again, the drum turns less than 15°, the amplifier never gets
      more than 5 V, and the drum ends at rest.

    Some phases end the stop with the blade in the web (the web, still running, drags it):
    the ones the check is about."""
    in_web = 0
    for phase in range(12):
        line, web, ramp_end = speed_up_at(phase)
        cam = line.demo.cams[1]
        assert cam.Error and cam.ErrorID == ErrorID.ECamLimit, phase
        assert 74.0 < web < 82.0, (phase, web)
        after = line.log.since(ramp_end)
        first = after[0]
        in_web += first.in_web
        assert abs(wrap(first.angle - first.hold)) < DEV_MAX, (phase, first)
        opened = next((s.t for s in after if s.error != ErrorID.ECamLimit), math.inf)
        for s in after:
            if s.t < opened:  # the loop closed: within DevMax of the hold
                assert s.enabled and abs(wrap(s.angle - s.hold)) <= DEV_MAX, (phase, s)
            else:  # opened by 2001 (the amplifier gets 0 V a servo cycle later), kept
                assert s.error == ErrorID.ERRPOS, (phase, s)
                assert s.volts == 0.0 or s.t <= opened + SERVO, (phase, s)
                assert not s.enabled or s.t <= opened + 0.1 + 2 * SERVO, (phase, s)
        assert line.log.passes(after) == 0, (phase, "a blade went into the web again")
        angles = [s.angle for s in after]
        assert max(angles) - min(angles) < 15.0, (phase, min(angles), max(angles))
        assert max(abs(s.volts) for s in after) < 5.0, phase
        assert abs(after[-1].rate) < 1.0, (phase, after[-1])
    assert in_web >= 2, "phases that stop the blade in the web"


def _assert_wire_break_opens_the_loop(line: Line, program: Callable[[], None]) -> None:
    """A broken encoder cable on the drum now: 2001 at once, 0 V, the amplifier's quick stop
    brings the drum to rest, the enable drops after quick_stop_time, no blade goes into the web
    and the drum never turns faster than it did."""
    scene, D = line.scene, line.D
    t0 = scene.time
    scene.faults.set("D", flt.EncoderWireBreak())
    scene.run(program, timeout=0.5)
    after = line.log.since(t0)
    t_error = next((s.t for s in after if s.error == ErrorID.ERRPOS), None)
    assert t_error is not None, f"no 2001: {after[-1]}"
    assert t_error - t0 <= SERVO
    later = [s for s in after if s.t > t_error + SERVO]
    assert all(s.error == ErrorID.ERRPOS and s.volts == 0.0 for s in later)
    enabled = [s.t for s in later if s.enabled]
    quick_stop = D.config.quick_stop_time
    assert enabled and max(enabled) == pytest.approx(t_error + quick_stop, abs=2 * SERVO)
    rate = abs(after[0].rate)
    assert max(abs(s.rate) for s in after) <= rate + 1.0, "no runaway"
    stopped = [s.angle for s in later if s.t >= t_error + quick_stop]
    assert max(stopped) - min(stopped) < 0.01 and abs(after[-1].rate) < 0.1, "at rest"
    assert line.log.passes(after) == 0 and not after[-1].in_web
    assert D.state == AxisState.ErrorStop


@pytest.mark.parametrize("when", ["during the stop ramp", "at rest"])
def test_a_broken_encoder_cable_in_errorstop_opens_the_loop(when: str) -> None:
    """The cam stops the drum (ECamLimit 23) with its blades clear of the web; its encoder
    cable breaks during the stop ramp or once the drum and the web stand: 2001, the loop opens
    and the amplifier stops the drum, instead of the drum running away at full voltage."""
    if when == "at rest":
        line, _, ramp_end = speed_up_at(0)
        assert not line.log.since(ramp_end)[0].in_web
    else:
        line = Line()
        line.cutting(2)
        line.speed_up = True
        line.until_error()
        assert line.D.moving and line.log.samples[-1].rate > 500.0
    assert line.D.AxErrorID == ErrorID.ECamLimit and line.D.loop_closed
    _assert_wire_break_opens_the_loop(line, line)


def _master_lost(line: Line) -> Callable[[], None]:
    line.cutting(1)
    line.scene.faults.set("W", flt.EncoderWireBreak())
    line.until_error()
    line.scene.run(line, timeout=1.5)
    assert line.D.AxErrorID == ErrorID.EMasterError and line.D.loop_closed
    return line


def _stopping(line: Line) -> Callable[[], None]:
    D = line.D
    power = mcl.MC_Power(Axis=D)
    move = mcl.MC_MoveRelative(Axis=D, Distance=90.0, Velocity=360.0)
    stop = mcl.MC_Stop(Axis=D)
    line.scene.run(lambda: power(Enable=True), until=lambda: power.Status, timeout=1.0)
    line.scene.run(scan(lambda: power(Enable=True), lambda: move(Execute=True)), timeout=0.1)

    def program() -> None:
        power(Enable=True)
        stop(Execute=True)

    line.scene.run(program, until=lambda: stop.Done, timeout=1.0)
    assert D.state == AxisState.Stopping
    return program


def _homing(line: Line) -> Callable[[], None]:
    D = line.D
    power, home = mcl.MC_Power(Axis=D), HomeAxis(D, rc.HOMING["D"])

    def program() -> None:
        power(Enable=True)
        home(Execute=power.Status)

    line.scene.run(program, until=lambda: D.state == AxisState.Homing, timeout=1.0)
    line.scene.run(program, timeout=0.1)
    assert D.state == AxisState.Homing
    return program


@pytest.mark.parametrize(
    "bring",
    [_master_lost, _stopping, _homing],
    ids=["ErrorStop 17 (the cam's master lost)", "Stopping", "Homing"],
)
def test_a_broken_encoder_cable_opens_the_loop_in_every_closed_loop_state(
    bring: Callable[[Line], Callable[[], None]],
) -> None:
    """The drum's cam master (the measuring wheel) loses its encoder, so the cam stops the drum
    with EMasterError 17; or MC_Stop holds the drum in Stopping; or it is homing: a broken
    encoder cable on the drum then opens its loop with 2001."""
    line = Line()
    program = bring(line)
    _assert_wire_break_opens_the_loop(line, program)

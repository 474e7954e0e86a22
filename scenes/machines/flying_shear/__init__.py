"""The flying shear (models/flying_shear.xml): a strip line cut to length or to print marks.

Three mcl axes: ``L`` the line drive (pinch rolls, MC_MoveVelocity), ``W`` the measuring wheel
(encoder only: the gearing master, its touch probe wired to the mark sensor) and ``S`` the shear
carriage (the slave, homed on REF + index). The knife is not an axis: digital output 0 of ``S``
switches its valve. Python devices run before every physics step: the eccentric pinch roll (the
line-speed ripple), the measuring wheel's errors (measurement only; ``ideal()`` turns them off),
the knife's valve, cylinder and grip on the strip, and :class:`CutRecorder`, which takes every
cut from the physics (the material coordinate under the knife when the blade comes down on the
strip). :class:`Demo` is the PLC program: cut to length (MC_GearInPos, Zeroing 1, with the
cut-length correction from the measured pieces) or to the print marks (Zeroing 2, with the
register that learns the wheel's scale from the print pitch).

Commissioning data: carriage Kv = Kp·Vmax/10 = 150 1/s, acceleration feed-forward
Ka = m_eff/Kamp + current lag + half a servo period = 132.3/26500 + 1.5 ms + 0.5 ms = 7 ms; line
Kv = 30 1/s, Ka = J_eff/Kamp + 2 ms = 1.11/115 + 2 ms = 12 ms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import mcl
from mcl.errors import check_finite
from scenes.definition import AxisDef, MachineDef, Signal
from scenes.machines.flying_shear.devices import (
    MARK_PITCH,
    MARKS,
    Cut,
    CutRecorder,
    EccentricRoll,
    KnifeCylinder,
    MeasuringWheel,
    mark_at,
)
from scenes.plant.mujoco import Probe
from scenes.procedures import HomeAxis, HomingRecipe
from scenes.scene import Scene

COMPILED_MODULES = ("devices",)
"""The modules of this package that the compiled build covers (its devices, run every physics
step)."""

PREFIX = "flying_shear/"
"""The prefix of the machine's names in a scene's model."""
ROLL_RADIUS = 0.48 / (2.0 * math.pi)
"""Pinch-roll radius [m]: 480 mm circumference (2.08 turns per second at 60 m/min, so a 1.5 m
piece sees the ripple at a new phase each cut)."""
WHEEL_RADIUS = 0.25 / (2.0 * math.pi)
"""Measuring-wheel radius [m]: 250 mm circumference."""
SENSOR_DELAY = 0.001
"""Mark sensor delay [s] (contrast scanner and input filter)."""


DEVICES = {
    "ripple": EccentricRoll,
    "wheel": MeasuringWheel,
    "knife": KnifeCylinder,
    "cuts": CutRecorder,  # after the knife: it reads the knife's force of the same step
}
"""The machine's Python devices by name (each ``(model, data, prefix) -> device``)."""


class ZeroingRecorder:
    """How well MC_GearInPos' Zeroing 2 zeroed the master at each print mark, from the physics;
    a runtime observer (called every servo cycle).

    When the master coordinate falls back by more than half a print pitch within a servo cycle,
    it has just been set to 0 at a mark; the recorder then compares it with the true strip
    travel since that mark passed the sensor.

    Args:
        scene: the flying-shear scene.
        marks: the print marks (on the strip coordinate M).
    """

    def __init__(self, scene: Scene, marks: mcl.Marks = MARKS) -> None:
        self.master = scene.axes["W"]
        self.marks = marks
        self._strip: Any = memoryview(scene.data.qpos)
        self._m = int(scene.model.joint(f"{PREFIX}M").qposadr[0])
        self._last = self.master.POS
        self.errors: list[float] = []
        """Per zeroing: master coordinate minus the true travel since the mark [mm]."""

    def __call__(self, t: float) -> None:
        """Observe one servo instant."""
        position, marks = self.master.POS, self.marks
        if position < self._last - 500.0 * marks.pitch:
            m = float(self._strip[self._m])
            travel = m - mark_at(marks, round((m - marks.first) / marks.pitch))
            self.errors.append(position - 1000.0 * travel)
        self._last = position


# ---------------------------------------------------------------------------------- axes
HOMING = HomingRecipe(set_position=80.0, search_velocity=200.0, index_velocity=50.0)
"""Carriage homing: REF is on below 60 mm; search away from it, then the next index pulse in
the positive direction (80 mm) is the origin, so the coordinate is the joint coordinate in mm."""

AXES = {
    "L": AxisDef(
        config=mcl.AxisConfig(
            resolution=0.0096,
            dev_max=20.0,
            in_position=0.1,
            acceleration=500.0,
            deceleration=500.0,
            max_acceleration=2000.0,
            max_deceleration=2000.0,
        ),
        constants=mcl.ServoConstants(
            Kp=0.125, Ki=1.25, Ff=1.0, Kc=50.0, Vmax=2400.0, Filter=2.0, Ka=0.012
        ),
        joint="L",
        unit="mm",
        scale=1000.0 * ROLL_RADIUS,
        switches=(),
    ),
    "W": AxisDef(
        config=mcl.AxisConfig(resolution=0.025, dev_max=20.0, in_position=0.1),
        drive="encoder",
        joint="W",
        unit="mm",
        scale=1000.0 * WHEEL_RADIUS,
        switches=(),
        probe=Probe(marks=MARKS, joint="M", delay=SENSOR_DELAY),
    ),
    "S": AxisDef(
        config=mcl.AxisConfig(
            resolution=0.001,
            dev_max=5.0,
            in_position=0.05,
            acceleration=10000.0,
            deceleration=10000.0,
            jerk=500000.0,
            max_acceleration=20000.0,
            max_deceleration=20000.0,
        ),
        constants=mcl.ServoConstants(
            Kp=0.375, Ki=18.75, Ff=1.0, Kc=50.0, Vmax=4000.0, Filter=2.0, Ka=0.007
        ),
        homing=HOMING,
        digital_outputs=1,
    ),
}
"""Line drive L (mm of strip at the nominal roll radius), measuring wheel W (the master, mm of
strip), carriage S (the slave, mm; digital output 0 = knife down)."""


# ---------------------------------------------------------------------------------- program
@dataclass(frozen=True)
class CutJob:
    """What the demo cuts and how.

    Attributes:
        speed: line speed [mm/s] (1000 = 60 m/min).
        length: piece length [mm] (length mode).
        cuts: number of cuts (the first is the head cut).
        mode: ``"length"`` (MC_GearInPos Zeroing 1) or ``"mark"`` (Zeroing 2 on the marks).
        delay: Delay input of MC_GearInPos in mark mode [ms] (the sensor delay compensates).
        park: carriage waiting position [mm].
        knife_on: how long digital output 0 stays on per cut [s].
        knife_up: from the output off until the blade is clear of the strip [s].
        sync_acceleration: the acceleration the approach is laid out for [mm/s²] (below the
            block's limit :data:`SYNC_LIMIT`, so a jerk-limited plan fits).
        kv: bandwidth of MC_GearInPos' filter on the measuring wheel [1/s].
        register: in mark mode, learn the wheel's scale first: MC_TouchProbe on two print
            pitches, measured against the nominal pitch, scales the mark-to-knife distance and
            sets the gear ratio to its inverse (so a slipping wheel still cuts at the mark, at
            strip speed).
        pitch: the nominal print pitch [mm] (the register's reference).
        correction: in length mode, the cut-length correction: a length gauge on the run-out
            table measures every piece (to ``gauge``); the wheel's scale, master travel per
            piece over measured length averaged over the last :data:`CORRECTION_PIECES`
            pieces, scales the next cut's MasterSyncPosition and sets the gear ratio to its
            inverse (so the pieces come out at ``length`` and the carriage runs at strip speed).
        gauge: resolution of the run-out table's length gauge [mm].
        scale: the wheel's scale at the start (1 + its error, as learned on an earlier run);
            the register (mark mode) or the correction (length mode) goes on from it.
    """

    speed: float = 1000.0
    length: float = 1500.0
    cuts: int = 21
    mode: Literal["length", "mark"] = "length"
    delay: float = SENSOR_DELAY * 1000.0
    park: float = 100.0
    knife_on: float = 0.08
    knife_up: float = 0.06
    sync_acceleration: float = 8000.0
    kv: float = 100.0
    register: bool = True
    pitch: float = MARK_PITCH * 1000.0
    correction: bool = True
    gauge: float = 0.1
    scale: float = 1.0

    def __post_init__(self) -> None:
        if self.mode not in ("length", "mark"):
            raise ValueError(f"CutJob.mode must be 'length' or 'mark', got {self.mode!r}")
        names = (
            "speed",
            "length",
            "knife_on",
            "knife_up",
            "sync_acceleration",
            "kv",
            "pitch",
            "gauge",
            "scale",
        )
        check_finite(self, names, True)
        if not 0.5 <= self.scale <= 2.0:
            raise ValueError(
                f"CutJob.scale must be within 0.5 … 2 (1 = a perfect wheel), got {self.scale}"
            )
        if self.cuts < 1:
            raise ValueError(f"CutJob.cuts must be >= 1, got {self.cuts}")

    @property
    def approach(self) -> float:
        """Carriage travel while it accelerates to the line speed [mm] (at least 150 mm)."""
        return max(150.0, self.speed**2 / (2.0 * self.sync_acceleration))

    @property
    def sync_position(self) -> float:
        """Carriage position where it runs with the strip [mm] (SlaveSyncPosition)."""
        return self.park + self.approach

    @property
    def start_distance(self) -> float:
        """Master travel while the carriage accelerates [mm]: twice the carriage's travel at a
        constant acceleration (MasterStartDistance)."""
        return 2.0 * self.approach


RATIO_BASE = 10000
"""Numerator of the gear ratio 1/scale the register sets (INT: at most 32767)."""
CORRECTION_PIECES = 4
"""Pieces the cut-length correction averages the wheel's scale over."""
SYNC_LIMIT = 10000.0
"""Acceleration and deceleration limit of the carriage while synchronising [mm/s²]."""

START = "start the line, park the carriage"
"""The demo's step that brings the line to speed."""
PHASES = ("wait for sync", "knife down", "knife up", "return")
"""The phases of one cut."""


class Demo:
    """The flying-shear program: power the line and the carriage, home the carriage, bring the
    line to speed, then cut ``job.cuts`` times with MC_GearInPos (length: Zeroing 1, the next
    cut ``length`` after the last; mark: Zeroing 2, the cut at each print mark), the knife down
    only when InSync, the carriage back with an Aborting MC_MoveAbsolute; finally stop the line.

    ``recorder`` holds every cut measured from the physics; ``step`` names the cut, its phase
    and the last piece's length and error.

    Args:
        scene: the flying-shear scene.
        job: what to cut (default: 21 cuts of 1500 mm at 60 m/min, so 20 pieces).
    """

    def __init__(self, scene: Scene, job: CutJob | None = None) -> None:
        self.scene = scene
        self.job = job = job or CutJob()
        L, W, S = (scene.axes[n] for n in ("L", "W", "S"))
        self.L, self.W, self.S = L, W, S
        self.recorder = scene.device("cuts", CutRecorder)
        self.power = [mcl.MC_Power(Axis=L), mcl.MC_Power(Axis=S)]
        self.home = HomeAxis(S, HOMING)
        self.park = mcl.MC_MoveAbsolute(
            Axis=S, Position=job.park, Velocity=1000.0, Acceleration=5000.0, Deceleration=5000.0
        )
        self.line = mcl.MC_MoveVelocity(
            Axis=L, Velocity=job.speed, Acceleration=1000.0, Deceleration=1000.0, Jerk=5000.0
        )
        self.line_stop = mcl.MC_Stop(Axis=L, Deceleration=1000.0, Jerk=4000.0)
        self.gear = mcl.MC_GearInPos(
            Master=W,
            Slave=S,
            RatioNumerator=RATIO_BASE,
            RatioDenominator=round(RATIO_BASE * job.scale),
            SlaveSyncPosition=job.sync_position,
            MasterStartDistance=job.start_distance,
            Velocity=3000.0,
            Acceleration=SYNC_LIMIT,
            Deceleration=SYNC_LIMIT,
            Jerk=0.0,
            Kv=job.kv,
            Zeroing=1 if job.mode == "length" else 2,
            Delay=job.delay if job.mode == "mark" else 0.0,
        )
        self.knife_down = mcl.MC_WriteDigitalOutput(Axis=S, OutputNumber=0, Value=True)
        self.knife_up = mcl.MC_WriteDigitalOutput(Axis=S, OutputNumber=0, Value=False)
        self.back = mcl.MC_MoveAbsolute(
            Axis=S,
            Position=job.park,
            Velocity=3000.0,
            Acceleration=10000.0,
            Deceleration=10000.0,
            Jerk=500000.0,
            BufferMode=mcl.MC_BufferMode.Aborting,
        )
        self.mark_distance = 1000.0 * self._sensor_to_knife() + job.sync_position
        """Strip distance from the mark sensor to the knife at the sync position [mm]."""
        self.probe = mcl.MC_TouchProbe(Axis=W)
        self.latches: list[float] = []
        """Master positions of the print marks the register measured [mm]."""
        self.scale = job.scale
        """The wheel's scale (its reading over the strip's travel) as the register (measured
        over nominal print pitch) or the correction (master travel over measured piece
        length) learned it."""
        self.travels: list[float] = []
        """Per cut the master travel it was set for (MasterSyncPosition, Zeroing 1) [mm]."""
        self.scales: list[float] = []
        """Per measured piece the wheel's scale it showed (length mode with correction)."""
        self._rearm = False
        self.stage = "power on"
        self.cut = 0
        """The cut in progress (1 … job.cuts)."""
        self.phase = 0
        self._timer = 0.0
        self.error = ""
        self.blocks: dict[str, Any] = {"home": self.home, "gear": self.gear}
        """The blocks a report watches, by name."""

    def _sensor_to_knife(self) -> float:
        """Strip distance from the mark sensor to the knife at carriage coordinate 0 [m]."""
        return self.recorder.sensor_offset - self.recorder.knife_offset

    @property
    def step(self) -> str:
        """What the program is doing; in the cut loop, the last piece's length and error."""
        if self.error:
            return self.error
        if self.stage == "done":
            return f"done: {self.summary()}"
        if self.stage != "cut":
            return self.stage
        text = f"cut {self.cut} of {self.job.cuts}: {PHASES[self.phase]}"
        last = self.recorder.cuts[-1] if self.recorder.cuts else None
        if self.phase == 0 and last is not None and last.length is not None:
            text += f"  (piece {len(self.recorder.cuts) - 1}: {self._piece(last)})"
        return text

    def errors(self) -> list[float]:
        """Per piece the error [mm]: its length minus ``job.length`` (length mode) or the
        cut's distance from its mark (mark mode), from the physics."""
        cuts = [c for c in self.recorder.cuts if c.length is not None]
        if self.job.mode == "mark":
            return [c.mark for c in cuts]
        return [c.length - self.job.length for c in cuts if c.length is not None]

    @property
    def results(self) -> list[dict[str, float | int | None]]:
        """One row per cut, from the physics: its length and error, its distance from the print
        mark, the carriage/strip speed mismatch and the blade's drag (shown by the viewer)."""
        rows: list[dict[str, float | int | None]] = []
        for k, cut in enumerate(self.recorder.cuts):
            error = None
            if cut.length is not None:
                error = cut.mark if self.job.mode == "mark" else cut.length - self.job.length
            rows.append(
                {
                    "cut": k,
                    "length [mm]": cut.length,
                    "error [mm]": error,
                    "from mark [mm]": cut.mark,
                    "mismatch [%]": 100.0 * cut.speed_mismatch,
                    "drag [N]": cut.drag,
                }
            )
        return rows

    def summary(self) -> str:
        """The pieces' errors: count, mean and worst [mm]."""
        errors = self.errors()
        if not errors:
            return "no pieces"
        what = "from the mark" if self.job.mode == "mark" else "length error"
        worst = max(errors, key=abs)
        return (
            f"{len(errors)} pieces, {what} mean {sum(errors) / len(errors):+.3f} mm, "
            f"worst {worst:+.3f} mm"
        )

    def _piece(self, cut: Cut) -> str:
        assert cut.length is not None
        if self.job.mode == "mark":
            return f"{cut.length:.3f} mm, {cut.mark:+.3f} mm from its mark"
        return f"{cut.length:.3f} mm, error {cut.length - self.job.length:+.3f} mm"

    @property
    def done(self) -> bool:
        """All cuts made and the line stopped."""
        return self.stage == "done"

    def _go(self, stage: str) -> None:
        self.stage, self._timer = stage, self.scene.time

    def _phase(self, phase: int) -> None:
        self.phase, self._timer = phase, self.scene.time

    REGISTER_MARKS = 3
    """Marks the register measures (two pitches: the print errors of the inner mark cancel)."""

    def _register(self, measuring: bool) -> None:
        """MC_TouchProbe on the master, re-armed after each mark, while ``measuring``."""
        probe = self.probe
        probe(Execute=measuring and not self._rearm)
        self._rearm = False
        if measuring and probe.Done:
            self.latches.append(probe.RecordedPosition)
            self._rearm = True  # Execute falls for one scan: the next edge arms it again
        if probe.Error:
            self.error = f"measure the print pitch: MC_TouchProbe error {probe.ErrorID}"

    def _set_scale(self, scale: float) -> None:
        """The wheel's scale learned: the carriage runs at strip speed, ratio = 1/scale."""
        self.scale = scale
        self.gear.RatioNumerator = RATIO_BASE
        self.gear.RatioDenominator = round(RATIO_BASE * scale)

    def _correct(self) -> None:
        """Cut-length correction: the pieces the gauge measured since the last cut give the
        wheel's scale (master travel per piece over its measured length)."""
        job = self.job
        cuts = self.recorder.cuts
        for k in range(len(self.scales) + 1, min(len(cuts), len(self.travels))):
            length = cuts[k].length
            assert length is not None
            measured = round(length / job.gauge) * job.gauge
            self.scales.append(self.travels[k] / measured)
        if self.scales:
            recent = self.scales[-CORRECTION_PIECES:]
            self._set_scale(sum(recent) / len(recent))

    def _next_cut(self) -> None:
        """Start the next cut: where it synchronises (MasterSyncPosition)."""
        job = self.job
        self.cut += 1
        if job.mode == "mark":  # from the mark (Zeroing 2) to the knife at the sync position
            self.gear.MasterSyncPosition = self.mark_distance * self.scale
        elif self.cut == 1:  # the head cut: soon; Zeroing 1 makes its sync point 0
            self.gear.MasterSyncPosition = self.W.POS + job.start_distance + 200.0
        else:  # the previous sync point reads 0 (Zeroing 1)
            if job.correction:
                self._correct()
            self.gear.MasterSyncPosition = job.length * self.scale
        self.travels.append(self.gear.MasterSyncPosition)
        self._phase(0)

    def __call__(self) -> None:
        """One PLC scan."""
        stage, job = self.stage, self.job
        for power in self.power:
            power(Enable=True)
        self.home(Execute=stage == "home the carriage")
        self.park(Execute=stage == START)
        self.line(Execute=stage == START)
        self.line_stop(Execute=stage == "stop the line")
        self._register(stage == "measure the print pitch")
        cutting = stage == "cut"
        phase = self.phase if cutting else -1
        self.gear(Execute=phase == 0)
        self.knife_down(Execute=phase == 1)
        self.knife_up(Execute=phase == 2)
        self.back(Execute=phase == 3)
        for name, fb in (("home", self.home), ("gear", self.gear), ("return", self.back)):
            if fb.Error:
                self.error = f"{stage} {self.cut}: {name} error {fb.ErrorID}"
                return
        for power in self.power:
            if power.Error:
                self.error = f"{stage}: MC_Power error {power.ErrorID}"
                return
        elapsed = self.scene.time - self._timer
        if stage == "power on" and all(p.Status for p in self.power):
            self._go("home the carriage")
        elif stage == "home the carriage" and self.home.Done:
            self._go(START)
        elif stage == START and self.park.Done and self.line.InVelocity:
            if job.mode == "mark" and job.register:
                self._go("measure the print pitch")
            else:
                self._next_cut()
                self._go("cut")
        elif stage == "measure the print pitch" and len(self.latches) == self.REGISTER_MARKS:
            pitches = len(self.latches) - 1
            self._set_scale((self.latches[-1] - self.latches[0]) / (pitches * job.pitch))
            self._next_cut()
            self._go("cut")
        elif phase == 0 and self.gear.InSync:
            self._phase(1)
        elif phase == 1 and elapsed >= job.knife_on:
            self._phase(2)
        elif phase == 2 and elapsed >= job.knife_up:
            self._phase(3)
        elif phase == 3 and self.back.Done:
            if self.cut < job.cuts:
                self._next_cut()
            else:
                self._go("stop the line")
        elif stage == "stop the line" and self.line_stop.Done:
            self._go("done")


def _signal_knife(scene: Scene) -> float:
    return 1000.0 * scene.joint(f"{PREFIX}K").position


def _signal_valve(scene: Scene) -> float:
    return scene.device("knife", KnifeCylinder).spool


def _signal_drag(scene: Scene) -> float:
    return scene.device("knife", KnifeCylinder).drag


def _signal_piece(scene: Scene) -> float:
    return scene.device("cuts", CutRecorder).last_piece


def _signal_mark(scene: Scene) -> float:
    return scene.device("cuts", CutRecorder).last_mark


def _signal_speed(scene: Scene) -> float:
    return 60.0 * scene.joint(f"{PREFIX}M").velocity


def _signal_relative(scene: Scene) -> float:
    return 1000.0 * (scene.joint(f"{PREFIX}S").velocity - scene.joint(f"{PREFIX}M").velocity)


MACHINE = MachineDef(
    name="flying_shear",
    description="flying shear: strip line, measuring wheel, carriage gearing in, knife cylinder",
    model="flying_shear.xml",
    axes=AXES,
    devices=DEVICES,
    demo=Demo,
    signals={
        "knife": Signal("mm", _signal_knife),
        "valve": Signal("-", _signal_valve),
        "drag": Signal("N", _signal_drag),
        "strip_speed": Signal("m/min", _signal_speed),
        "carriage_minus_strip": Signal("mm/s", _signal_relative),
        "last_piece": Signal("mm", _signal_piece),
        "last_cut_to_mark": Signal("mm", _signal_mark),
    },
    demo_start={"S": 0.3},
)
"""The flying shear in the registry."""

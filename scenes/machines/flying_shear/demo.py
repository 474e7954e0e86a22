"""The flying-shear program (:class:`Demo`): cut to length (MC_GearInPos, Zeroing 1, with the
cut-length correction from the measured pieces) or to the print marks (Zeroing 2, with the
register that learns the wheel's scale from the print pitch); :class:`CutJob` says what it cuts.
"""

from __future__ import annotations

__all__ = [
    "CORRECTION_PIECES",
    "PHASES",
    "PHASE_OF",
    "RATIO_BASE",
    "START",
    "SYNC_LIMIT",
    "CutJob",
    "Demo",
]

from dataclasses import dataclass
from typing import Any, Literal

import mcl
from mcl.errors import check_finite
from plc.procedures import HomeAxis
from plc.sequence import REST, Block, StepSequence, at_rest, never
from scenes.machines.flying_shear.axes import HOMING, SENSOR_DELAY
from scenes.machines.flying_shear.devices import MARK_PITCH, Cut, CutRecorder
from scenes.scene import Scene


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
PHASE_OF = {name: k for k, name in enumerate(PHASES)}
"""The number of each phase of a cut."""


class Demo(StepSequence):
    """The flying-shear program: power the line and the carriage, home the carriage, bring the
    line to speed, then cut ``job.cuts`` times with MC_GearInPos (length: Zeroing 1, the next
    cut ``length`` after the last; mark: Zeroing 2, the cut at each print mark), the knife down
    only when InSync, the carriage back with an Aborting MC_MoveAbsolute; finally stop the line
    (its MC_Stop released: every axis at rest, the demo may run again).

    ``recorder`` holds every cut measured from the physics; ``step`` names the cut, its phase
    and the last piece's length and error.

    Args:
        scene: the flying-shear scene.
        job: what to cut (default: 21 cuts of 1500 mm at 60 m/min, so 20 pieces).
    """

    STEPS = (
        "power on",
        "home the carriage",
        START,
        "measure the print pitch",
        *PHASES,
        "stop the line",
        REST,
        "done",
    )

    def __init__(self, scene: Scene, job: CutJob | None = None) -> None:
        self.scene = scene
        self.job = job = job or CutJob()
        L, W, S = (scene.axes[n] for n in ("L", "W", "S"))
        self.L, self.W, self.S = L, W, S
        self.recorder = scene.device("cuts", CutRecorder)
        self.first = len(self.recorder.cuts)
        """Cuts the recorder held before this run (an earlier run's)."""
        self.power = [mcl.MC_Power(Axis=L), mcl.MC_Power(Axis=S)]
        self.home = HomeAxis(S, HOMING["S"])
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
        self.index = 0
        self.cut = 0
        """The cut in progress (1 … job.cuts)."""
        self.error = ""
        self.blocks: dict[str, Any] = {"home": self.home, "gear": self.gear}
        """The blocks a report watches, by name."""
        self._declare_steps()

    def _declare_steps(self) -> None:
        """The step table: each step's end, what follows it; every step watches the homing,
        the gearing, the return and MC_Power."""
        job = self.job
        watched: dict[str, Block] = {
            "home": self.home,
            "gear": self.gear,
            "return": self.back,
            "power L": self.power[0],
            "power S": self.power[1],
        }

        step = self.watching(watched)
        self.declare(
            step("power on", lambda: all(p.Status for p in self.power)),
            step("home the carriage", lambda: self.home.Done),
            step(START, lambda: self.park.Done and self.line.InVelocity, self._after_start),
            step(
                "measure the print pitch",
                lambda: len(self.latches) == self.REGISTER_MARKS,
                self._after_register,
            ),
            step(PHASES[0], lambda: self.gear.InSync),
            step(PHASES[1], lambda: self._elapsed() >= job.knife_on),
            step(PHASES[2], lambda: self._elapsed() >= job.knife_up),
            step(PHASES[3], lambda: self.back.Done, self._after_cut),
            step("stop the line", lambda: self.line_stop.Done),
            step(REST, lambda: at_rest(self.scene.axes.values())),
            step("done", never),
        )

    @property
    def stage(self) -> str:
        """The step of the program; ``"cut"`` in any phase of a cut."""
        name = self.STEPS[self.index]
        return "cut" if name in PHASE_OF else name

    @property
    def phase(self) -> int:
        """The phase of the cut in progress (its number in :data:`PHASES`; 0 outside a cut)."""
        return PHASE_OF.get(self.STEPS[self.index], 0)

    def _elapsed(self) -> float:
        """Time in the current step [s]."""
        return self.scene.time - self.entered

    def _after_start(self) -> str:
        """The line runs: measure the print pitch first (mark mode with the register), else cut."""
        if self.job.mode == "mark" and self.job.register:
            return "measure the print pitch"
        self._next_cut()
        return PHASES[0]

    def _after_register(self) -> str:
        """The pitch measured: the wheel's scale learned, the first cut."""
        pitches = len(self.latches) - 1
        self._set_scale((self.latches[-1] - self.latches[0]) / (pitches * self.job.pitch))
        self._next_cut()
        return PHASES[0]

    def _after_cut(self) -> str:
        """The carriage is back: the next cut, or stop the line after the last."""
        if self.cut < self.job.cuts:
            self._next_cut()
            return PHASES[0]
        return "stop the line"

    def failure(self, step: str, block: str, error_id: int) -> str:
        """The ``error`` text: the stage (with the cut for the axis blocks) and the block."""
        stage = "cut" if step in PHASE_OF else step
        if block.startswith("power"):
            return f"{stage}: MC_Power error {error_id}"
        return f"{stage} {self.cut}: {block} error {error_id}"

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
        cuts = self.cuts
        last = cuts[-1] if len(cuts) > 1 else None
        if self.phase == 0 and last is not None and last.length is not None:
            text += f"  (piece {len(cuts) - 1}: {self._piece(last)})"
        return text

    @property
    def cuts(self) -> list[Cut]:
        """This run's cuts, from the physics; the first is its head cut (the length the
        recorder gives it runs from an earlier run's last cut, not a piece)."""
        return self.recorder.cuts[self.first :]

    def pieces(self) -> list[Cut]:
        """This run's cuts that end a piece (all but its head cut)."""
        return [c for c in self.cuts[1:] if c.length is not None]

    def errors(self) -> list[float]:
        """Per piece the error [mm]: its length minus ``job.length`` (length mode) or the
        cut's distance from its mark (mark mode), from the physics."""
        cuts = self.pieces()
        if self.job.mode == "mark":
            return [c.mark for c in cuts]
        return [c.length - self.job.length for c in cuts if c.length is not None]

    @property
    def results(self) -> list[dict[str, float | int | None]]:
        """One row per cut, from the physics: its length and error, its distance from the print
        mark, the carriage/strip speed mismatch and the blade's drag (shown by the viewer)."""
        rows: list[dict[str, float | int | None]] = []
        for k, cut in enumerate(self.cuts):
            length = cut.length if k > 0 else None
            error = None
            if length is not None:
                error = cut.mark if self.job.mode == "mark" else length - self.job.length
            rows.append(
                {
                    "cut": k,
                    "length [mm]": length,
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
        cuts = self.cuts
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

    def __call__(self) -> None:
        """One PLC scan."""
        stage = self.stage
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
        self.advance(self.scene.time)

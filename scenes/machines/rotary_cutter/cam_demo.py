"""The rotary cutter cutting to length with a cam (:class:`CamDemo`): the drum on
``mcl.rotary_knife`` tables (MC_CamTableSelect, MC_CamIn), the tips at web speed around each cut
and the drum faster or slower between, so a piece may be shorter or longer than the tip circle.
The wheel's scale is learned from the print pitch (MC_TouchProbe) and corrects the cam's
MasterScaling; a new length takes over at a period boundary (a new MC_CamIn on the cammed
drum); with ``register`` MC_Phasing keeps every cut at its print mark. :class:`CamJob` says
what it cuts.
"""

from __future__ import annotations

__all__ = [
    "COUPLED",
    "CUT_ANGLE",
    "REGISTER_MARKS",
    "Batch",
    "CamDemo",
    "CamJob",
    "stopping_distance",
]

import math
from dataclasses import dataclass, field
from typing import Any

import mcl
from mcl.errors import check_finite
from plc.procedures import HomeAxis
from plc.sequence import REST, Block, StepSequence, at_rest, never
from scenes.machines.rotary_cutter.axes import CUT_FORCE, HOMING, SENSOR_DELAY, TIP_CIRCUMFERENCE
from scenes.machines.rotary_cutter.devices import Cut, KnifeDrum
from scenes.machines.rotary_cutter.marks import MARK_FIRST, MARK_PITCH, PRINT_MARKS, PrintMarks
from scenes.scene import Scene

CUT_ANGLE = 90.0
"""Drum angle at which blade 1 points down at the anvil [°] (the cam's slave 0)."""
COUPLED = ("couple the cam", "start the web", "measure the print pitch", "cut", "stop the web")
"""The steps in which the drum is on its cam."""
REGISTER_MARKS = 5
"""Marks the scale is learned over (four print pitches: the print errors of the inner marks
cancel)."""


@dataclass(frozen=True)
class Batch:
    """``cuts`` pieces of ``length`` [mm]."""

    length: float
    cuts: int

    def __post_init__(self) -> None:
        check_finite(self, ("length",), True)
        if self.cuts < 1:
            raise ValueError(f"Batch.cuts must be >= 1, got {self.cuts}")


def stopping_distance(speed: float, acceleration: float) -> float:
    """The web's travel from MC_Stop at ``speed`` [mm/s] to a standstill, decelerating at
    ``acceleration`` [mm/s²] with a jerk of 10 × it [mm]."""
    jerk = 10.0 * acceleration
    return speed * speed / (2.0 * acceleration) + speed * acceleration / (2.0 * jerk)


def _short_and_long() -> tuple[Batch, ...]:
    return (Batch(0.6 * TIP_CIRCUMFERENCE, 6), Batch(1.8 * TIP_CIRCUMFERENCE, 4))


@dataclass(frozen=True)
class CamJob:
    """What the cam demo cuts and how.

    Attributes:
        batches: the lengths in order, each for its number of pieces; the next takes over at
            the period boundary after the last piece of the one before, on the fly.
        speed: web speed [mm/s] (1000 = 60 m/min).
        blades: blades fitted (1 or 2; None: the model's).
        sync_angle: drum rotation in sync with the web around each cut [°] (the blade is in
            the web for 10.8° of it).
        acceleration: the web's ramp [mm/s²].
        scale: the wheel's scale (its reading over the web's travel) to start from.
        learn_scale: learn the scale from :data:`REGISTER_MARKS` print marks first (the
            pieces cut meanwhile are run-in pieces).
        register: cut at the print marks: every mark the probe latches gives the distance of
            its cut from the next period boundary, and MC_Phasing shifts the cam by it (every
            batch's length must then be the print pitch).
        cut_force: the force the web resists the blade with, as the drive's cutting-force
            feed-forward is set for [N] (:attr:`KnifeDrum.feed_forward`; 0: off); default the
            board's 5 N/mm over its 400 mm width.
    """

    batches: tuple[Batch, ...] = field(default_factory=_short_and_long)
    speed: float = 1000.0
    blades: int | None = 1
    sync_angle: float = 30.0
    acceleration: float = 2000.0
    scale: float = 1.0
    learn_scale: bool = True
    register: bool = False
    cut_force: float = CUT_FORCE

    def __post_init__(self) -> None:
        check_finite(self, ("speed", "sync_angle", "acceleration", "scale"), True)
        check_finite(self, ("cut_force",), False)
        if not self.batches:
            raise ValueError("CamJob.batches must name at least one Batch(length, cuts)")
        if self.blades not in (None, 1, 2):
            raise ValueError(f"CamJob.blades must be 1 or 2 (on the drum), got {self.blades}")
        if not 0.5 <= self.scale <= 2.0:
            raise ValueError(
                f"CamJob.scale must be within 0.5 … 2 (1: a perfect wheel), got {self.scale}"
            )
        last = self.batches[-1]
        stopping = stopping_distance(self.speed, self.acceleration)
        if (last.cuts + 0.5) * last.length < stopping:
            raise ValueError(
                f"CamJob: the web needs {stopping:g} mm to stop from {self.speed:g} mm/s; the "
                f"last batch ({last.cuts} × {last.length:g} mm) must be at least that long less "
                f"half a piece: more pieces or a steeper acceleration"
            )
        pitch = 1000.0 * MARK_PITCH
        if self.register and any(b.length != pitch for b in self.batches):
            raise ValueError(
                f"CamJob.register cuts at the print marks: every batch's length must be the "
                f"print pitch {pitch:g} mm"
            )


class CamDemo(StepSequence):
    """Cut to length with the drum on a cam: power, home the drum (unless a run before homed
    it), turn it to the middle between two cuts without a blade passing the web, couple it to
    the measuring wheel (MC_CamIn, mcAbsolute, the table started half a piece before its first
    cut), run the web up, learn the wheel's scale over the print marks,
    then cut each batch at ``MasterScaling = 1/scale``; the next batch's table is selected and
    its MC_CamIn issued half a piece before the running batch's last cut, the blade clear of
    the web, so it takes over at that cut (a table or cam refused leaves the running one
    cutting: no wrong cut). Finally the web stops with the blades clear of it (the stop
    planned to end half a piece after the last batch's last cut) and MC_Halt ends the drum's
    cam: every axis at rest, the demo may run again.

    Args:
        scene: the rotary-cutter scene.
        job: what to cut (default: 6 pieces of 300 mm, then 4 of 900 mm, one blade).
        marks: the print marks on the web (judging a registered cut).
    """

    STEPS = (
        "power on",
        "home the drum",
        "turn the drum to its start",
        "couple the cam",
        "start the web",
        "measure the print pitch",
        "cut",
        "stop the web",
        REST,
        "done",
    )

    def __init__(
        self, scene: Scene, job: CamJob | None = None, marks: PrintMarks = PRINT_MARKS
    ) -> None:
        self.scene = scene
        self.job = job = job or CamJob()
        self.marks = marks
        L, W, D = (scene.axes[n] for n in ("L", "W", "D"))
        self.L, self.W, self.D = L, W, D
        self.drum = scene.device("drum", KnifeDrum)
        if job.blades is not None:
            self.drum.blades = job.blades
        self.drum.feed_forward = job.cut_force
        blades = self.drum.blades
        self.pitch = 360.0 / blades
        """Drum angle per cut [°]."""
        # cam 0: the run-in (the first batch's table, absolute on the drum); cam k: batch k − 1
        lengths = [job.batches[0].length, *(b.length for b in job.batches)]
        self.lengths = lengths
        """The piece length of each cam [mm]."""
        self.selects, self.cams = self._cam_blocks(blades)
        self.power = [mcl.MC_Power(Axis=L), mcl.MC_Power(Axis=D)]
        self.home = HomeAxis(D, HOMING["D"])
        self.referenced = D.Ref
        """The drum had its reference when the program began (a run before this one homed
        it): it is not homed again."""
        self.start = mcl.MC_MoveAbsolute(
            Axis=D,
            Velocity=180.0,
            Acceleration=2000.0,
            Deceleration=2000.0,
            Direction=mcl.MC_Direction.MC_Shortest,
        )
        """Turns the drum to the middle between the cuts it stands between (no blade passes
        the standing web); set once the drum is homed (:meth:`_after_homing`)."""
        self.line = mcl.MC_MoveVelocity(
            Axis=L,
            Velocity=job.speed,
            Acceleration=job.acceleration,
            Deceleration=job.acceleration,
            Jerk=10.0 * job.acceleration,
        )
        self.line_stop = mcl.MC_Stop(
            Axis=L, Deceleration=job.acceleration, Jerk=10.0 * job.acceleration
        )
        self.drum_halt = mcl.MC_Halt(Axis=D, Deceleration=10000.0)
        """Ends the cam once the web stands (the drum stands with it)."""
        self.probe = mcl.MC_TouchProbe(Axis=W)
        self.phasing = mcl.MC_Phasing(
            Master=W, Slave=D, Velocity=500.0, Acceleration=5000.0, Deceleration=5000.0
        )
        self.latches: list[float] = []
        """Master positions of the print marks the probe latched [mm]."""
        self.shifts: list[float] = []
        """Per registered mark the phase shift it asked for [master mm]."""
        self.scale = job.scale
        """The wheel's scale, as learned from the print pitch."""
        self.issued = 0
        """The last cam issued."""
        self.running = 0
        """The cam that runs."""
        self.periods = 0
        """Period boundaries passed under the running cam."""
        self.boundaries: list[tuple[float, int]] = []
        """Per period boundary: when [s] and the cam that ended its piece."""
        self._boundary_master = 0.0
        self._issue_at = math.inf
        """Master position at which the next cam is issued: half a piece after a boundary,
        the blade clear of the web (a refused cam leaves the running one cutting) [master mm]."""
        self._in_sync = [False] * len(self.cams)
        self._rearm = False
        self._shift_pending = False
        self._shift_from = 0.0
        self.blocks: dict[str, Any] = {"home": self.home, "cam": self.cams[0]}
        self._declare_steps()

    def _declare_steps(self) -> None:
        """The step table: each step's end, what follows it; every step watches every block."""
        watched: dict[str, Block] = {
            "home": self.home,
            "start": self.start,
            "web": self.line,
            "probe": self.probe,
            "phasing": self.phasing,
            "halt": self.drum_halt,
            "power L": self.power[0],
            "power D": self.power[1],
            **{f"table {k}": s for k, s in enumerate(self.selects)},
            **{f"cam {k}": c for k, c in enumerate(self.cams)},
        }
        step = self.watching(watched)
        self.declare(
            step("power on", lambda: all(p.Status for p in self.power)),
            step("home the drum", lambda: self.referenced or self.home.Done, self._after_homing),
            step("turn the drum to its start", lambda: self.start.Done),
            step("couple the cam", lambda: self.cams[0].InSync),
            step("start the web", lambda: self.line.InVelocity, self._after_start),
            step(
                "measure the print pitch",
                lambda: len(self.latches) >= REGISTER_MARKS,
                self._after_pitch,
            ),
            step("cut", self._cut_done),
            step("stop the web", lambda: self.line_stop.Done),
            step(REST, lambda: self.drum_halt.Done and at_rest(self.scene.axes.values())),
            step("done", never),
        )

    def _cam_blocks(self, blades: int) -> tuple[list[mcl.MC_CamTableSelect], list[mcl.MC_CamIn]]:
        """Per cam its table's MC_CamTableSelect and its MC_CamIn: cam 0 absolute on the drum
        (the run-in, started half a piece before its first cut), the others relative."""
        job, W, D = self.job, self.W, self.D
        tables = [
            mcl.rotary_knife(x, TIP_CIRCUMFERENCE, blades, job.sync_angle) for x in self.lengths
        ]
        selects = [
            mcl.MC_CamTableSelect(
                Master=W,
                Slave=D,
                CamTable=t,
                Periodic=True,
                MasterAbsolute=False,
                SlaveAbsolute=k == 0,
            )
            for k, t in enumerate(tables)
        ]
        cams = [
            mcl.MC_CamIn(
                Master=W,
                Slave=D,
                StartMode=mcl.MC_StartMode.mcAbsolute,
                MasterOffset=0.5 * self.lengths[0] if k == 0 else 0.0,
                SlaveOffset=CUT_ANGLE if k == 0 else 0.0,
                MasterScaling=1.0 / job.scale,
            )
            for k in range(len(tables))
        ]
        return selects, cams

    # ------------------------------------------------------------------ sequence
    def _after_homing(self) -> str:
        """The drum knows its angle: its start is the middle between the two blade positions
        at the web it stands between (half a pitch from each), reached without a blade
        passing the standing web; the run-in cam is laid so that its cuts fall on them."""
        between = math.floor((self.D.POS - CUT_ANGLE) / self.pitch)
        self.start.Position = (CUT_ANGLE + (between + 0.5) * self.pitch) % 360.0
        self.cams[0].SlaveOffset = (CUT_ANGLE + between * self.pitch) % 360.0
        return "turn the drum to its start"

    def _after_start(self) -> str:
        if self.job.learn_scale:
            return "measure the print pitch"
        return self._after_pitch()

    def _after_pitch(self) -> str:
        """The scale learned (or given): the first batch's cam, with MasterScaling 1/scale."""
        if self.job.learn_scale:
            marks = self.latches[:REGISTER_MARKS]
            self.scale = (marks[-1] - marks[0]) / ((len(marks) - 1) * 1000.0 * MARK_PITCH)
        self._issue()
        return "cut"

    def _issue(self) -> None:
        """Issue the next cam (it takes over at the next period boundary)."""
        self.issued += 1
        self.cams[self.issued].MasterScaling = 1.0 / self.scale

    def _cut_done(self) -> bool:
        """The last batch is cutting: stop the web so that it stands half a piece after the
        batch's last cut (the blades clear of it)."""
        if self.running != len(self.cams) - 1:
            return False
        period = self._period(self.running)
        last_cut = self._boundary_master + (self.job.batches[-1].cuts - self.periods) * period
        stop_at = (
            last_cut
            + 0.5 * period
            - self.scale * stopping_distance(self.job.speed, self.job.acceleration)
        )
        return stop_at <= self.W.POS

    def failure(self, step: str, block: str, error_id: int) -> str:
        """The ``error`` text: the step, the block and its ErrorID (a table's reason too)."""
        text = f"{step}: {block} error {error_id}"
        if block.startswith("table"):
            text += f" ({self.selects[int(block.split()[1])].ErrorText})"
        return text

    def _boundary(self) -> None:
        """A period boundary passed: book the piece that ended; a cam issued before took over
        here; half a piece before the boundary that ends a batch's last piece, issue the next
        batch's cam (it takes over at that boundary)."""
        self.boundaries.append((self.scene.time, self.running))
        self._boundary_master += self._period(self.running)
        if self.issued > self.running:  # the issued cam took over at this boundary
            self.running, self.periods = self.issued, 0
        elif self.running > 0:
            self.periods += 1
        if self.running == 0 or self.running + 1 >= len(self.cams):
            return
        if self.periods == self.job.batches[self.running - 1].cuts - 1:
            self._issue_at = self._boundary_master + 0.5 * self._period(self.running)

    def _period(self, cam: int) -> float:
        """The master travel of one period of cam ``cam`` [master mm]."""
        return self.lengths[cam] / self.cams[cam].MasterScaling

    def _coupled(self) -> None:
        """Cam 0 is on (the web stands): its first boundary comes half a piece on."""
        self._boundary_master = self.W.POS - 0.5 * self._period(0)

    def _mark(self, latched: float) -> None:
        """Registration: the cut for the mark latched at ``latched`` [master mm] comes when
        the mark reaches the cut line; shift the cam by its distance from the boundary."""
        if not self.job.register or self.running != self.issued or self._shift_pending:
            return  # (a shift from the run-in on, not across a takeover, one at a time)
        travel = 1000.0 * self.sensor_to_cut() * self.scale
        arrival = latched - SENSOR_DELAY * self.W.VEL + travel
        period = self._period(self.running)
        early = (arrival - self._boundary_master) % period  # the boundary comes before it
        if early > 0.5 * period:
            early -= period
        self.shifts.append(-early)
        self.phasing.PhaseShift = -early
        self._shift_from = self.phasing.AbsolutePhaseShift
        self._boundary_master += early  # the boundaries come that much later
        self._shift_pending = True

    def sensor_to_cut(self) -> float:
        """Web distance from the mark sensor to the cut line (under the drum axis) [m]."""
        scene = self.scene
        sensor = scene.model.site(scene.model_name("mark_sensor")).id
        data = scene.data
        axis = data.xanchor[scene.model.joint(scene.model_name("D")).id]
        return float(axis[0] - data.site_xpos[sensor][0])

    # ------------------------------------------------------------------ results
    def pieces(self) -> list[tuple[Cut, float]]:
        """Each piece cut after the run-in with the length it was to have [mm]: the cam that
        ran up to the period boundary the cut belongs to."""
        rows = []
        for cut in self.drum.cuts:
            if cut.length is None or not self.boundaries:
                continue
            t, cam = min(self.boundaries, key=lambda b: abs(b[0] - cut.time))
            if abs(t - cut.time) < 0.05 and cam > 0:
                rows.append((cut, self.lengths[cam]))
        return rows

    def errors(self) -> list[float]:
        """Per piece its length minus the length it was to have [mm], from the physics."""
        return [c.length - target for c, target in self.pieces() if c.length is not None]

    def from_mark(self, cut: Cut) -> float:
        """A cut's distance from the nearest print mark as printed [mm] (+: upstream of it)."""
        drum = self.drum
        web_at_sensor = 1000.0 * (drum.web_offset + self.sensor_to_cut())
        k0 = round(((cut.position - web_at_sensor) / 1000.0 - MARK_FIRST) / MARK_PITCH)
        nearest = min(
            (web_at_sensor + 1000.0 * self.marks.passing(k) for k in range(max(0, k0 - 2), k0 + 3)),
            key=lambda m: abs(m - cut.position),
        )
        return cut.position - nearest

    @property
    def results(self) -> list[dict[str, float | int | None]]:
        """One row per piece, from the physics (shown by the viewer)."""
        drum = self.drum
        return [
            {
                "target [mm]": target,
                "length [mm]": cut.length,
                "error [mm]": None if cut.length is None else cut.length - target,
                "from mark [mm]": self.from_mark(cut),
                "mismatch [%]": 100.0 * cut.mismatch,
                "drum torque [N·m]": cut.torque,
                "motor current [A]": cut.current,
                "of peak [%]": 100.0 * cut.current / drum.peak_current,
            }
            for cut, target in self.pieces()
        ]

    def summary(self) -> str:
        """Per length: pieces, mean and worst error [mm]."""
        parts = []
        for length in dict.fromkeys(b.length for b in self.job.batches):
            errors = [
                c.length - t for c, t in self.pieces() if t == length and c.length is not None
            ]
            if errors:
                worst = max(errors, key=abs)
                parts.append(
                    f"{len(errors)} × {length:g} mm: mean {sum(errors) / len(errors):+.3f}, "
                    f"worst {worst:+.3f} mm"
                )
        return "; ".join(parts) or "no pieces"

    @property
    def step(self) -> str:
        """What the program is doing."""
        if self.error:
            return self.error
        name = self.STEPS[self.index]
        if name == "done":
            return f"done: {self.summary()}"
        if name != "cut" or self.running == 0:
            return name
        batch = self.job.batches[self.running - 1]
        return f"cut {batch.length:g} mm: piece {self.periods} of {batch.cuts}"

    # ------------------------------------------------------------------ scan
    def __call__(self) -> None:
        """One PLC scan."""
        stage = self.STEPS[self.index]
        # inputs set as attributes, blocks called without keywords: the cheap way per scan
        for power in self.power:
            power.Enable = True
            power()
        self.home(Execute=stage == "home the drum" and not self.referenced)
        start = self.start
        start.Execute = stage == "turn the drum to its start"
        start()
        coupled = stage in COUPLED
        boundary = False
        for k, (select, cam) in enumerate(zip(self.selects, self.cams, strict=True)):
            issued = coupled and k <= self.issued
            select.Execute = issued
            select()
            if select.Done:
                cam.CamTableID = select.CamTableID
            cam.Execute = issued and (select.Done or cam.Execute)
            cam()
            # a period boundary: EndOfProfile, or a new cam's InSync (it took over there)
            took_over = k > 0 and cam.InSync and not self._in_sync[k]
            if k == 0 and cam.InSync and not self._in_sync[0]:
                self._coupled()
            self._in_sync[k] = cam.InSync
            boundary = boundary or cam.EndOfProfile or took_over
        if boundary:
            self._boundary()
        if self._issue_at <= self.W.POS:
            self._issue_at = math.inf
            self._issue()
        probing = stage in ("measure the print pitch", "cut", "stop the web")
        probe = self.probe
        probe.Execute = probing and not self._rearm
        probe()
        self._rearm = False
        if probing and probe.Done:
            self.latches.append(probe.RecordedPosition)
            self._rearm = True  # Execute falls for one scan: the next edge arms it again
            self._mark(probe.RecordedPosition)
        phasing = self.phasing
        phasing.Execute = self._shift_pending
        phasing()
        if phasing.CommandAborted and self._shift_pending:  # a new cam ended it: what is left
            done = phasing.AbsolutePhaseShift - self._shift_from  # of it stays undone
            self._boundary_master += phasing.PhaseShift - done
        if phasing.Done or phasing.Error or phasing.CommandAborted:
            self._shift_pending = False
        line, line_stop, drum_halt = self.line, self.line_stop, self.drum_halt
        line.Execute = stage in ("start the web", "measure the print pitch", "cut")
        line()
        line_stop.Execute = stage == "stop the web"
        line_stop()
        drum_halt.Execute = stage == REST
        drum_halt()
        self.advance(self.scene.time)

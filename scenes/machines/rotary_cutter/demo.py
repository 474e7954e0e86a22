"""The rotary cutter's program (:class:`Demo`): home the drum, gear it to the measuring wheel
with MC_GearIn (tip speed = web speed), run the web and cut; in this mode every piece is one
blade pitch long (tip circumference / blades). :class:`CutterJob` says what it cuts.
"""

from __future__ import annotations

__all__ = ["DRUM_SPEED_LIMIT", "CutterJob", "Demo"]

import math
from dataclasses import dataclass
from typing import Any

import mcl
from mcl.errors import check_finite
from plc.procedures import HomeAxis
from plc.sequence import REST, Block, StepSequence, at_rest, never
from scenes.machines.rotary_cutter.axes import CUT_FORCE, GEAR_RATIO, HOMING, TIP_CIRCUMFERENCE
from scenes.machines.rotary_cutter.devices import Cut, KnifeDrum
from scenes.scene import Scene

DRUM_SPEED_LIMIT = 3000.0 / 5.0
"""The drum's speed at 10 V [rpm]: the motor's rated 3000 rpm through the 5:1 gearbox (the
axis' Vmax); the demo leaves 10 % of it to the position loop."""


@dataclass(frozen=True)
class CutterJob:
    """What the demo cuts and how.

    Attributes:
        speed: web speed [mm/s] (1000 = 60 m/min, the design point).
        cuts: cuts to make (the first is the head cut: ``cuts − 1`` pieces).
        blades: blades fitted (1 or 2; None: the model's ``D_blades``).
        acceleration: the web's ramp [mm/s²].
        cut_force: the force the web resists the blade with, as the drive's cutting-force
            feed-forward is set for [N] (:attr:`KnifeDrum.feed_forward`; 0: off).
    """

    speed: float = 1000.0
    cuts: int = 9
    blades: int | None = None
    acceleration: float = 2000.0
    cut_force: float = CUT_FORCE

    def __post_init__(self) -> None:
        check_finite(self, ("speed", "acceleration"), True)
        check_finite(self, ("cut_force",), False)
        if self.cuts < 1:
            raise ValueError(f"CutterJob.cuts must be >= 1, got {self.cuts}")
        if self.blades not in (None, 1, 2):
            raise ValueError(
                f"CutterJob.blades must be 1 or 2 (blades on the drum), got {self.blades}"
            )
        drum = 60.0 * self.speed / TIP_CIRCUMFERENCE
        limit = 0.9 * DRUM_SPEED_LIMIT
        fastest = limit * TIP_CIRCUMFERENCE / 60.0  # web speed [mm/s]
        if drum > limit:
            raise ValueError(
                f"CutterJob.speed {self.speed:g} mm/s ({0.06 * self.speed:g} m/min) needs the "
                f"drum at {drum:.0f} rpm (its motor at {5 * drum:.0f} rpm); the drive reaches "
                f"{DRUM_SPEED_LIMIT:.0f} rpm at 10 V and keeps 10 % for the position loop: at most "
                f"{fastest:.0f} mm/s ({0.06 * fastest:.0f} m/min)"
            )


class Demo(StepSequence):
    """The rotary cutter's program in geared mode: power the web feed and the drum, home the
    drum (REF cam + motor index; not again when a run before homed it), gear it to the
    measuring wheel with MC_GearIn at 18/25 °/mm (the tips' surface speed is the web's), run
    the web up to ``job.speed`` and let the blades cut ``job.cuts`` times; then stop the web
    (the drum follows it down) and end the gearing (MC_Halt): every axis at rest, the demo may
    run again.

    ``drum`` holds every cut measured from the physics; ``step`` names the cut and the last
    piece.

    Args:
        scene: the rotary-cutter scene.
        job: what to cut (default: 9 cuts at 60 m/min).
    """

    STEPS = (
        "power on",
        "home the drum",
        "gear in",
        "start the web",
        "cut",
        "stop the web",
        REST,
        "done",
    )

    def __init__(self, scene: Scene, job: CutterJob | None = None) -> None:
        self.scene = scene
        self.job = job = job or CutterJob()
        L, W, D = (scene.axes[n] for n in ("L", "W", "D"))
        self.L, self.W, self.D = L, W, D
        self.drum = scene.device("drum", KnifeDrum)
        if job.blades is not None:
            self.drum.blades = job.blades
        self.drum.feed_forward = job.cut_force
        self.power = [mcl.MC_Power(Axis=L), mcl.MC_Power(Axis=D)]
        self.home = HomeAxis(D, HOMING["D"])
        self.referenced = D.Ref
        """The drum had its reference when the program began (a run before this one homed
        it): it is not homed again."""
        self.gear = mcl.MC_GearIn(
            Master=W,
            Slave=D,
            RatioNumerator=GEAR_RATIO[0],
            RatioDenominator=GEAR_RATIO[1],
            Acceleration=5000.0,
            Deceleration=5000.0,
        )
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
        """Ends the gearing once the web stands (the drum stands with it)."""
        self.start = len(self.drum.cuts)
        """Cuts recorded before this run (an earlier run's)."""
        self.first = 0
        """Cuts recorded before the cutting began."""
        self.blocks: dict[str, Any] = {"home": self.home, "gear": self.gear}
        """The blocks a report watches, by name."""
        watched: dict[str, Block] = {
            "home": self.home,
            "gear": self.gear,
            "web": self.line,
            "halt": self.drum_halt,
            "power L": self.power[0],
            "power D": self.power[1],
        }

        step = self.watching(watched)
        self.declare(
            step("power on", lambda: all(p.Status for p in self.power)),
            step("home the drum", lambda: self.referenced or self.home.Done),
            step("gear in", lambda: self.gear.InGear),
            step("start the web", lambda: self.line.InVelocity, self._begin),
            step("cut", lambda: self.made() >= job.cuts),
            step("stop the web", lambda: self.line_stop.Done),
            step(REST, lambda: self.drum_halt.Done and at_rest(scene.axes.values())),
            step("done", never),
        )

    def _begin(self) -> str:
        self.first = len(self.drum.cuts)
        return "cut"

    def made(self) -> int:
        """Cuts made since the web reached its speed."""
        return len(self.drum.cuts) - self.first

    def pieces(self) -> list[Cut]:
        """The job's cuts at web speed that end a piece (each has a length)."""
        cuts = self.drum.cuts[self.first : self.first + self.job.cuts]
        return [c for c in cuts if c.length is not None]

    def errors(self) -> list[float]:
        """Per piece its length minus the blade pitch [mm], from the physics."""
        pitch = 1000.0 * self.drum.pitch
        return [c.length - pitch for c in self.pieces() if c.length is not None]

    @property
    def results(self) -> list[dict[str, float | int | None]]:
        """One row per cut, from the physics (shown by the viewer)."""
        drum = self.drum
        rows: list[dict[str, float | int | None]] = []
        for k, cut in enumerate(drum.cuts[self.start :]):
            rows.append(
                {
                    "cut": k,
                    "blade": cut.blade,
                    "length [mm]": cut.length,
                    "mismatch [%]": 100.0 * cut.mismatch,
                    "drag [N]": cut.drag,
                    "drum torque [N·m]": cut.torque,
                    "motor current [A]": cut.current,
                    "of peak [%]": 100.0 * cut.current / drum.peak_current,
                }
            )
        return rows

    def summary(self) -> str:
        """The pieces' errors against the blade pitch: count, mean and worst [mm]."""
        errors = self.errors()
        if not errors:
            return "no pieces"
        worst = max(errors, key=abs)
        return (
            f"{len(errors)} pieces of {1000.0 * self.drum.pitch:.1f} mm, error mean "
            f"{sum(errors) / len(errors):+.3f} mm, worst {worst:+.3f} mm"
        )

    @property
    def step(self) -> str:
        """What the program is doing; while cutting, the last piece."""
        if self.error:
            return self.error
        name = self.STEPS[self.index]
        if name == "done":
            return f"done: {self.summary()}"
        if name != "cut":
            return name
        last = self.drum.last_piece
        text = f"cut {self.made()} of {self.job.cuts}"
        return text if math.isnan(last) else f"{text}  (last piece {last:.3f} mm)"

    def __call__(self) -> None:
        """One PLC scan."""
        stage = self.STEPS[self.index]
        for power in self.power:
            power(Enable=True)
        self.home(Execute=stage == "home the drum" and not self.referenced)
        self.gear(Execute=stage in ("gear in", "start the web", "cut", "stop the web"))
        self.line(Execute=stage in ("start the web", "cut"))
        self.line_stop(Execute=stage == "stop the web")
        self.drum_halt(Execute=stage == REST)
        self.advance(self.scene.time)

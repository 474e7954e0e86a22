"""The press cycle (:class:`Demo`): home to block against the top stop (MC_StepBlock, then
MC_StepDirect), rapid approach at 250 mm/s, slow down 5 mm before the part and press at 20 mm/s
(GT_MoveAbsBlock, blended) until side A reaches 150 bar (ExtStop from the pressure comparison),
hold 75 kN for 0.5 s (MC_ForceControl on the pressure-derived force, buffered behind the stroke
so that it takes over in the servo cycle the stroke stops), decompress over 100 ms
(MC_ForceControl ramping down) and return to the top.

The force loop: on the part the force rises about 330 kN/s per volt of valve command, so the
admittance Gain = 5 mm/s per kN (through the feed-forward: 0.17 V per kN) puts its crossover
near 55 rad/s (see mcl.force).
"""

from __future__ import annotations

__all__ = [
    "BAR_PER_VOLT",
    "DECOMPRESSION",
    "DWELL",
    "FORCE_GAIN",
    "HOLD_FORCE",
    "PART",
    "PRESSURE_STOP",
    "STEPS",
    "TOP",
    "WATCHED",
    "Demo",
    "force_inputs",
    "model_force_inputs",
]

from functools import cache
from typing import Any

import mujoco

import mcl
from plc.procedures import HomeAxis
from plc.sequence import Step, StepSequence, never
from scenes.machines.press.axes import BLOCK_HOMING, MODEL, WEIGHT
from scenes.machines.press.devices import CylinderDevice, cylinder_data
from scenes.machines.press.hydraulics import BAR, Cylinder
from scenes.scene import Scene, model_path

PART = 250.0
"""Stroke position where the punch touches the part [mm] (the recipe's part height)."""
PRESSURE_STOP = 150.0
"""Side-A pressure that ends the pressing stroke [bar]."""
HOLD_FORCE = 75.0
"""Force held during the dwell [kN]."""
DWELL = 0.5
"""Dwell at the force [s]."""
DECOMPRESSION = 0.1
"""Time of the decompression ramp [s]."""
TOP = 10.0
"""Top position of the cycle [mm]."""
BAR_PER_VOLT = 25.0
"""Pressure transducers: 250 bar at 10 V."""
FORCE_GAIN = 5.0
"""Admittance of the force loop [mm/s per kN]."""


def force_inputs(cylinder: Cylinder) -> dict[str, float]:
    """MC_ForceControl inputs that make its force the pressing force in kN from the two pressure
    transducers: ``p_A·A_A − p_B·A_B`` plus the ram's weight (the areas of ``cylinder``)."""
    return {
        "InputNumber": 0,
        "Scale": BAR_PER_VOLT * BAR * float(cylinder.area_a) / 1000.0,
        "InputNumber2": 1,
        "Scale2": -BAR_PER_VOLT * BAR * float(cylinder.area_b) / 1000.0,
        "Offset": WEIGHT,
    }


@cache
def model_force_inputs() -> dict[str, float]:
    """:func:`force_inputs` of the cylinder in the press's model file (``FORCE_INPUTS``)."""
    _, cylinder, _ = cylinder_data(mujoco.MjModel.from_xml_path(str(model_path(MODEL))))
    return force_inputs(cylinder)


STEPS = (
    "power on",
    "home to block",
    "set the reference",
    "rapid approach",
    "press to 150 bar",
    "hold the force",
    "decompress",
    "return",
    "done",
)

WATCHED = {
    "power on": (),
    "home to block": ("block", "direct"),
    "set the reference": ("block", "direct"),
    "rapid approach": ("approach", "press", "hold"),
    "press to 150 bar": ("approach", "press", "hold"),
    "hold the force": ("hold",),
    "decompress": ("decompress",),
    "return": ("retract",),
    "done": (),
}
"""The blocks that act in each step (besides MC_Power, which acts in every step)."""


class Demo(StepSequence):
    """The press cycle; call once per PLC cycle. ``step`` says what it does, ``done`` when the
    cycle is complete."""

    STEPS = STEPS

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        R = self.R = scene.axes["R"]
        self.index = 0
        self.error = ""
        inputs = force_inputs(scene.device("cylinder", CylinderDevice).hydraulics.cylinder)
        self.power = mcl.MC_Power(Axis=R, Enable=True)
        self.homing = HomeAxis(R, BLOCK_HOMING)
        self.block, self.direct = self.homing.approach, self.homing.pulse
        self.pressure = mcl.MC_ReadAnalogInput(Axis=R, InputNumber=0, Enable=True)
        self.approach = mcl.MC_MoveAbsolute(
            Axis=R, Position=PART - 5.0, Velocity=250.0, Acceleration=3000.0, Deceleration=3000.0
        )
        self.press = mcl.GT_MoveAbsBlock(
            Axis=R,
            Position=PART + 10.0,
            Velocity=20.0,
            Acceleration=3000.0,
            Deceleration=3000.0,
            BufferMode=mcl.MC_BufferMode.BlendingLow,
        )
        self.hold = mcl.MC_ForceControl(
            Axis=R,
            Force=HOLD_FORCE,
            ForceRamp=200.0,
            Velocity=20.0,
            Gain=FORCE_GAIN,
            Tolerance=0.5,
            BufferMode=mcl.MC_BufferMode.Buffered,
            **inputs,
        )
        self.decompress = mcl.MC_ForceControl(
            Axis=R,
            Force=2.0,
            ForceRamp=(HOLD_FORCE - 2.0) / DECOMPRESSION,
            Velocity=20.0,
            Gain=FORCE_GAIN,
            Tolerance=1.0,
            **inputs,
        )
        self.retract = mcl.MC_MoveAbsolute(
            Axis=R, Position=TOP, Velocity=200.0, Acceleration=2000.0, Deceleration=2000.0
        )
        self.blocks: dict[str, Any] = {
            name: getattr(self, name)
            for name in ("power", "block", "direct", "approach", "press", "hold", "decompress")
        }
        self.blocks["retract"] = self.retract
        """The blocks a report watches, by name."""
        self.peak = 0.0
        """Highest side-A pressure read while pressing [bar]."""
        self.results: list[dict[str, float | str]] = []
        """One row per finished step: when, where the ram stood, pressure and force (from the
        physics; shown by the viewer)."""
        done = {
            "power on": lambda: self.power.Status,
            "home to block": lambda: self.block.Done,
            "set the reference": lambda: self.direct.Done,
            "rapid approach": lambda: self.approach.Done,
            "press to 150 bar": lambda: self.press.Done,
            "hold the force": lambda: self._elapsed() >= DWELL,
            "decompress": lambda: self._elapsed() >= DECOMPRESSION and self.decompress.InForce,
            "return": lambda: self.retract.Done,
        }
        self.declare(
            *(
                Step(
                    s,
                    done.get(s, never),
                    {n: self.blocks[n] for n in ("power", *WATCHED[s])},
                )
                for s in STEPS
            )
        )

    def _elapsed(self) -> float:
        """Time in the current step [s]."""
        return self.scene.time - self.entered

    def enter(self, index: int, now: float) -> None:
        """Record the step that ended (a row of ``results``), then go to step ``index``."""
        scene = self.scene
        self.results.append(
            {
                "step": STEPS[self.index],
                "ended [s]": now,
                "took [s]": now - self.entered,
                "ram [mm]": scene.joint_position("R") * 1000.0,
                "p_A [bar]": float(scene.signal("pressure_A")),
                "force [kN]": float(scene.signal("force")),
            }
        )
        super().enter(index, now)

    def __call__(self) -> None:
        """One PLC scan."""
        step = STEPS[self.index]
        # inputs set as attributes, blocks called without keywords: the cheap way per scan
        power, pressure = self.power, self.pressure
        approach, press, hold = self.approach, self.press, self.hold
        power()
        pressure()
        p_a = pressure.Value * BAR_PER_VOLT
        self.homing(Execute=step in ("home to block", "set the reference"))
        approach.Execute = press.Execute = step in ("rapid approach", "press to 150 bar")
        press.ExtStop = p_a >= PRESSURE_STOP
        approach()
        press()
        # queued behind the pressing stroke: it takes over in the servo cycle the stroke stops
        hold.Execute = step in ("rapid approach", "press to 150 bar", "hold the force")
        hold()
        self.decompress.Execute = step == "decompress"
        self.decompress()
        self.retract.Execute = step == "return"
        self.retract()
        if step == "press to 150 bar":
            self.peak = max(self.peak, p_a)
        self.advance(self.scene.time)

"""The hydraulic press (models/hydraulic_press.xml): a valve-controlled cylinder pressing a part.

One mcl axis ``R``, the ram's stroke in mm (0 = top, positive = down), driven by the Python
device ``cylinder`` (:class:`.hydraulics.CylinderDevice`: servo valve, differential cylinder,
oil columns) with ±10 V. Its analog inputs: 0 = pressure A, 1 = pressure B
(0–250 bar → 0–10 V, 12 bit, seeded noise), 2 = the load cell under the part (0–150 kN → 0–10 V).

:class:`Demo` is the press cycle: home to block against the top stop (MC_StepBlock, then
MC_StepDirect), rapid approach at 250 mm/s, slow down 5 mm before the part and press at 20 mm/s
(GT_MoveAbsBlock, blended) until side A reaches 150 bar (ExtStop from the pressure comparison),
hold 75 kN for 0.5 s (MC_ForceControl on the pressure-derived force, buffered behind the stroke
so that it takes over in the servo cycle the stroke stops), decompress over 100 ms
(MC_ForceControl ramping down) and return to the top.

Commissioning data (measured on the model, see models/README.md): Vmax = 300 mm/s, the free
extension speed at +10 V with the ram's weight; retracting runs 207 mm/s at −10 V, so
FfNeg = 300/207 = 1.45. Position gain Kv = Kp·Vmax/10 = 30 1/s, well below 2·ζ_h·ω_h (the
lowest hydraulic natural frequency is 80 Hz = 505 1/s, its damping 0.1–0.2), which leaves room
for the valve's lag and the module's delays; Ka = the valve's lag 2ζ/ω = 3.7 ms plus the module's
delays (1.5 ms). The force loop: on the part the force rises about 330 kN/s per volt of valve
command, so the admittance Gain = 5 mm/s per kN (through the feed-forward: 0.17 V per kN) puts its
crossover near 55 rad/s (see mcl.force).
"""

from __future__ import annotations

import math
from typing import Any

import mujoco

import mcl
from scenes.definition import AxisDef, MachineDef, Signal
from scenes.machines.press.hydraulics import (
    BAR,
    ContactForce,
    Cylinder,
    CylinderDevice,
    Supply,
    Valve,
)
from scenes.plant.mujoco import numeric
from scenes.procedures import BlockHoming
from scenes.program import StepSequence
from scenes.scene import Scene

COMPILED_MODULES = ("hydraulics",)
"""The modules of this package that the compiled build covers (the valve and the cylinder, run
every physics step)."""

PREFIX = "press/"
"""The prefix of the machine's names in a scene's model."""
MASS = 200.0
"""Moving mass of the ram with piston and rod [kg]."""
WEIGHT = MASS * 9.81 / 1000.0
"""The ram's weight [kN] (it adds to the pressing force)."""
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


def cylinder_data(model: mujoco.MjModel, prefix: str = "") -> tuple[Valve, Cylinder, Supply]:
    """The valve, cylinder and supply of the model's numerics (models/README.md).

    Raises:
        WiringError: a numeric is missing, of the wrong size or out of range.
    """
    bore, rod, stroke = numeric(model, f"{prefix}R_cylinder", 3, 0.0)
    dead_a, dead_b = numeric(model, f"{prefix}R_dead_volume", 2, 0.0)
    coulomb, pressure_friction = numeric(model, f"{prefix}R_seal_friction", 2, -1e-300)
    (leakage,) = numeric(model, f"{prefix}R_internal_leakage", 1, -1e-300)
    flow, dp, frequency, damping = numeric(model, f"{prefix}R_valve", 4, 0.0)
    overlap, hysteresis, clearance, laminar = numeric(model, f"{prefix}R_valve_spool", 4, -1e-300)
    supply, tank, beta = numeric(model, f"{prefix}R_supply", 3, -1e-300)
    relief, override, relief_flow = numeric(model, f"{prefix}R_line_relief", 3, 0.0)
    return (
        Valve(flow, dp, frequency, damping, overlap, hysteresis, clearance, laminar),
        Cylinder(bore, rod, stroke, dead_a, dead_b, coulomb, pressure_friction, leakage),
        Supply(supply, tank, relief, override, relief_flow, beta),
    )


def make_cylinder(model: mujoco.MjModel, data: mujoco.MjData, prefix: str) -> CylinderDevice:
    """The press cylinder device of a compiled model (a :data:`DeviceFactory`)."""
    valve, cylinder, supply = cylinder_data(model, prefix)
    full, bits, noise = numeric(model, f"{prefix}R_transducer", 3, 0.0)
    cell, cell_bits, cell_noise = numeric(model, f"{prefix}R_load_cell", 3, 0.0)
    return CylinderDevice(
        model,
        data,
        f"{prefix}R",
        valve,
        cylinder,
        supply,
        (float(full), round(bits), float(noise)),
        (float(cell), round(cell_bits), float(cell_noise)),
        load=ContactForce(model, data, prefix),
    )


AREA_A = math.pi / 4.0 * 0.080**2
"""Piston area of the 80 mm bore [m²]."""
AREA_B = AREA_A - math.pi / 4.0 * 0.056**2
"""Annulus area with the 56 mm rod [m²]."""
FORCE_INPUTS = {
    "InputNumber": 0,
    "Scale": BAR_PER_VOLT * BAR * AREA_A / 1000.0,
    "InputNumber2": 1,
    "Scale2": -BAR_PER_VOLT * BAR * AREA_B / 1000.0,
    "Offset": WEIGHT,
}
"""MC_ForceControl inputs that make its force the pressing force in kN from the two pressure
transducers: ``p_A·A_A − p_B·A_B`` plus the ram's weight."""
FORCE_GAIN = 5.0
"""Admittance of the force loop [mm/s per kN]."""

REFERENCE = 0.05
"""Coordinate set where the homed ram is held, clear of the top stop [mm]."""
BLOCK_HOMING = BlockHoming(
    direction=mcl.MC_Direction.MC_Negative,
    velocity=10.0,
    threshold=1.0,
    time_limit=40.0,
    set_position=REFERENCE,
)
"""Homing to the top stop at 10 mm/s; found at standstill with a following error of 1 mm (1 V on
the valve: side B near supply pressure)."""
HOMING = {
    "Direction": BLOCK_HOMING.direction,
    "Velocity": BLOCK_HOMING.velocity,
    "TorqueLimit": BLOCK_HOMING.threshold,
    "TimeLimit": BLOCK_HOMING.time_limit,
}
"""MC_StepBlock inputs of :data:`BLOCK_HOMING`."""

AXES = {
    "R": AxisDef(
        config=mcl.AxisConfig(
            resolution=0.005,
            dev_max=5.0,
            in_position=0.05,
            acceleration=2000.0,
            deceleration=2000.0,
            jerk=0.0,
            max_acceleration=5000.0,
            max_deceleration=20000.0,
        ),
        constants=mcl.ServoConstants(
            Kp=1.0,
            Ki=5.0,
            Ff=1.0,
            FfNeg=1.45,
            Kc=50.0,
            Vmax=300.0,
            LimPos=295.0,
            LimNeg=-1.0,
            Filter=2.0,
            Ka=0.0052,
        ),
        drive="device",
        device="cylinder",
        analog=("p_A", "p_B", "load"),
        homing=BLOCK_HOMING,
    )
}
"""The ram axis (user unit mm)."""


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
        self._since = 0.0
        self.power = mcl.MC_Power(Axis=R, Enable=True)
        self.block = mcl.MC_StepBlock(Axis=R, **HOMING)
        self.direct = mcl.MC_StepDirect(
            Axis=R, SetPosition=REFERENCE, BufferMode=mcl.MC_BufferMode.Buffered
        )
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
            **FORCE_INPUTS,
        )
        self.decompress = mcl.MC_ForceControl(
            Axis=R,
            Force=2.0,
            ForceRamp=(HOLD_FORCE - 2.0) / DECOMPRESSION,
            Velocity=20.0,
            Gain=FORCE_GAIN,
            Tolerance=1.0,
            **FORCE_INPUTS,
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
        self._watched = [(self.power, *(self.blocks[n] for n in WATCHED[s])) for s in STEPS]
        """Per step, the blocks whose error stops the cycle."""
        self.peak = 0.0
        """Highest side-A pressure read while pressing [bar]."""
        self.results: list[dict[str, float | str]] = []
        """One row per finished step: when, where the ram stood, pressure and force (from the
        physics; shown by the viewer)."""

    def _next(self) -> None:
        scene = self.scene
        self.results.append(
            {
                "step": STEPS[self.index],
                "ended [s]": scene.time,
                "took [s]": scene.time - self._since,
                "ram [mm]": scene.joint_position("R") * 1000.0,
                "p_A [bar]": float(scene.signal("pressure_A")),
                "force [kN]": float(scene.signal("force")),
            }
        )
        self.index += 1
        self._since = scene.time

    def __call__(self) -> None:
        """One PLC scan."""
        step = STEPS[self.index]
        # inputs set as attributes, blocks called without keywords: the cheap way per scan
        power, pressure, block, direct = self.power, self.pressure, self.block, self.direct
        approach, press, hold = self.approach, self.press, self.hold
        power()
        pressure()
        p_a = pressure.Value * BAR_PER_VOLT
        block.Execute = direct.Execute = step in ("home to block", "set the reference")
        block()
        direct()
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
        for fb in self._watched[self.index]:
            if fb.Error:
                name = next(n for n, b in self.blocks.items() if b is fb)
                self.error = f"{step}: {name} error {fb.ErrorID}"
                return
        if (
            (step == "power on" and self.power.Status)
            or (step == "home to block" and self.block.Done)
            or (step == "set the reference" and self.direct.Done)
            or (step == "rapid approach" and self.approach.Done)
            or (step == "press to 150 bar" and self.press.Done)
            or (step == "hold the force" and self.scene.time - self._since >= DWELL)
            or (
                step == "decompress"
                and self.scene.time - self._since >= DECOMPRESSION
                and self.decompress.InForce
            )
            or (step == "return" and self.retract.Done)
        ):
            self._next()


def _signal_pressure_a(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.p_a / BAR


def _signal_pressure_b(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.p_b / BAR


def _signal_force(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).load_force / 1000.0


def _signal_hydraulic(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.force() / 1000.0


def _signal_valve(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.spool


MACHINE = MachineDef(
    name="press",
    description="hydraulic press: servo valve, 80/56 cylinder, 200 kg ram, part on a spring",
    model="hydraulic_press.xml",
    axes=AXES,
    devices={"cylinder": make_cylinder},
    demo=Demo,
    signals={
        "pressure_A": Signal("bar", _signal_pressure_a),
        "pressure_B": Signal("bar", _signal_pressure_b),
        "force": Signal("kN", _signal_force),
        "force_hydraulic": Signal("kN", _signal_hydraulic),
        "valve": Signal("-", _signal_valve),
    },
    servo_period=0.001,
    plc_period=0.001,
    demo_start={"R": 0.03},
)
"""The hydraulic press in the registry."""

"""The press's ram axis ``R`` (stroke in mm, 0 = top, positive = down) and its homing recipe.

Commissioning data (measured on the model, see models/README.md): Vmax = 300 mm/s, the free
extension speed at +10 V with the ram's weight; retracting runs 207 mm/s at −10 V, so
FfNeg = 300/207 = 1.45. Position gain Kv = Kp·Vmax/10 = 30 1/s, well below 2·ζ_h·ω_h (the
lowest hydraulic natural frequency is 80 Hz = 505 1/s, its damping 0.1–0.2), which leaves room
for the valve's lag and the module's delays; Ka = the valve's lag 2ζ/ω = 3.7 ms plus the module's
delays (1.5 ms).
"""

from __future__ import annotations

__all__ = [
    "AXES",
    "BLOCK_HOMING",
    "HOMING",
    "MASS",
    "MODEL",
    "RAM_SSI",
    "REFERENCE",
    "STEP_BLOCK_INPUTS",
    "WEIGHT",
]

import mcl
from plc.procedures import BlockHoming
from scenes.definition import AxisDef
from scenes.machines.press.devices import ANALOG_INPUTS

MODEL = "hydraulic_press.xml"
"""The press's MJCF model (in models/)."""
MASS = 200.0
"""Moving mass of the ram with piston and rod [kg]."""
WEIGHT = MASS * 9.81 / 1000.0
"""The ram's weight [kN] (it adds to the pressing force)."""

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
HOMING = {"R": BLOCK_HOMING}
"""The homing recipe of each axis."""
STEP_BLOCK_INPUTS = {
    "Direction": BLOCK_HOMING.direction,
    "Velocity": BLOCK_HOMING.velocity,
    "TorqueLimit": BLOCK_HOMING.threshold,
    "TimeLimit": BLOCK_HOMING.time_limit,
}
"""The inputs of the MC_StepBlock that :data:`BLOCK_HOMING` runs."""

RAM_SSI = mcl.AbsoluteEncoder.ssi(resolution=5.0e-6, bits=24, offset=-0.010, gray=True)
"""The ram's SSI linear transducer (magnetostrictive, models/README.md): 5 µm, 24 bit Gray,
its zero 10 mm above the ram's top (the null zone), so the stroke reads 2000 … 62000 counts."""

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
        analog=ANALOG_INPUTS,
        homing=BLOCK_HOMING,
        sensors=mcl.Sensors(absolute=RAM_SSI),
    )
}
"""The ram axis (user unit mm)."""

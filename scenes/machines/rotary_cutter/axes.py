"""The rotary cross cutter's axes: ``L`` the web feed (pinch rolls), ``W`` the measuring wheel
(encoder only, the drum's master, its touch probe wired to the mark sensor) and ``D`` the knife
drum (a modulo-360° hinge axis, homed on its REF cam and the motor's index).

Commissioning data: drum Kv = Kp·Vmax/10 = 0.4·3600/10 = 144 1/s, acceleration feed-forward
Ka = J_eff/Kamp + current lag + half a servo period = 0.1598/100 + 1 ms + 0.5 ms = 3.1 ms; web
feed Kv = 30 1/s, Ka = J_eff/Kamp + 1.5 ms = 0.118/12 + 1.5 ms = 11.3 ms.
"""

from __future__ import annotations

__all__ = [
    "AXES",
    "CUT_FORCE",
    "GEAR_RATIO",
    "HOMING",
    "ROLL_RADIUS",
    "SENSOR_DELAY",
    "TIP_CIRCUMFERENCE",
]

import math

import mcl
from plc.procedures import HomingRecipe
from scenes.definition import AxisDef
from scenes.machines.rotary_cutter.marks import MARKS
from scenes.parts import line_axis, wheel_axis

ROLL_RADIUS = 0.4 / (2.0 * math.pi)
"""Pinch-roll radius [m]: 400 mm circumference."""
TIP_CIRCUMFERENCE = 500.0
"""The blades' tip circle [mm] (r = 79.577 mm)."""
SENSOR_DELAY = 0.0005
"""Mark sensor delay [s] (contrast scanner and input filter)."""
CUT_FORCE = 2000.0
"""The force the web resists a blade with [N]: the board's 5 N/mm (its data) over the 400 mm
width; what the demos set the drive's cutting-force feed-forward for."""
GEAR_RATIO = (18, 25)
"""Drum degrees per mm of web at tip speed = web speed: 360/500 = 18/25 (MC_GearIn's INTs)."""

HOMING = {
    # REF is on from −56° to −36°: search it negative, leave it positive (its edge at −36°),
    # the next index positive (every 72° of the drum, one per motor turn) is the drum's 0°
    "D": HomingRecipe(search_velocity=90.0, index_velocity=40.0, set_position=0.0),
}
"""The homing recipe of each homed axis (the drum)."""

AXES = {
    "L": line_axis(
        ROLL_RADIUS,
        resolution=0.008,
        acceleration=1000.0,
        max_acceleration=4000.0,
        constants=mcl.ServoConstants(
            Kp=0.075, Ki=0.75, Ff=1.0, Kc=50.0, Vmax=4000.0, Filter=2.0, Ka=0.0113
        ),
    ),
    "W": wheel_axis(MARKS, SENSOR_DELAY),
    "D": AxisDef(
        config=mcl.AxisConfig(
            resolution=0.0036,
            dev_max=5.0,
            in_position=0.05,
            acceleration=10000.0,
            deceleration=10000.0,
            max_acceleration=20000.0,
            max_deceleration=20000.0,
            modulo=360.0,
        ),
        constants=mcl.ServoConstants(
            Kp=0.4, Ki=20.0, Ff=1.0, Kc=50.0, Vmax=3600.0, Filter=2.0, Ka=0.0031
        ),
        switches=("ref",),
        homing=HOMING["D"],
    ),
}
"""Web feed L (mm of web at the nominal roll radius), measuring wheel W (the master, mm of web),
knife drum D (the slave, degrees, modulo 360°)."""

"""The flying shear's axes: ``L`` the line drive (pinch rolls), ``W`` the measuring wheel (encoder
only, its touch probe wired to the mark sensor) and ``S`` the shear carriage (homed on REF +
index; digital output 0 switches the knife's valve).

Commissioning data: carriage Kv = Kp·Vmax/10 = 150 1/s, acceleration feed-forward
Ka = m_eff/Kamp + current lag + half a servo period = 132.3/26500 + 1.5 ms + 0.5 ms = 7 ms; line
Kv = 30 1/s, Ka = J_eff/Kamp + 2 ms = 1.11/115 + 2 ms = 12 ms.
"""

from __future__ import annotations

__all__ = [
    "AXES",
    "HOMING",
    "ROLL_RADIUS",
    "SENSOR_DELAY",
]

import math

import mcl
from plc.procedures import HomingRecipe
from scenes.definition import AxisDef
from scenes.machines.flying_shear.devices import MARKS
from scenes.parts import line_axis, wheel_axis

ROLL_RADIUS = 0.48 / (2.0 * math.pi)
"""Pinch-roll radius [m]: 480 mm circumference (2.08 turns per second at 60 m/min, so a 1.5 m
piece sees the ripple at a new phase each cut)."""
SENSOR_DELAY = 0.001
"""Mark sensor delay [s] (contrast scanner and input filter)."""


HOMING = {
    # REF is on below 60 mm: search away from it, then the next index pulse in the positive
    # direction (80 mm) is the origin, so the coordinate is the joint coordinate in mm
    "S": HomingRecipe(set_position=80.0, search_velocity=200.0, index_velocity=50.0),
}
"""The homing recipe of each homed axis (the carriage)."""

AXES = {
    "L": line_axis(
        ROLL_RADIUS,
        resolution=0.0096,
        acceleration=500.0,
        max_acceleration=2000.0,
        constants=mcl.ServoConstants(
            Kp=0.125, Ki=1.25, Ff=1.0, Kc=50.0, Vmax=2400.0, Filter=2.0, Ka=0.012
        ),
    ),
    "W": wheel_axis(MARKS, SENSOR_DELAY),
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
        homing=HOMING["S"],
        digital_outputs=1,
    ),
}
"""Line drive L (mm of strip at the nominal roll radius), measuring wheel W (the master, mm of
strip), carriage S (the slave, mm; digital output 0 = knife down)."""

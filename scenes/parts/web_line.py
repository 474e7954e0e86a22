"""The axes of a web line (a strip or a web pulled through pinch rolls past a measuring wheel), as
the flying shear and the rotary cutter have them: the line drive ``L`` and the measuring wheel
``W``, the master of the machine's cutting axis, its touch probe wired to the mark sensor.

The joints and numerics they need are the model's web line (models/README.md): the roll ``L``,
the web ``M`` it drives through the equality ``pinch``, the wheel ``W`` rolling on it through
``wheel_roll`` (the device :class:`~scenes.parts.measuring_wheel.MeasuringWheel`).
"""

from __future__ import annotations

__all__ = ["WHEEL_RADIUS", "line_axis", "wheel_axis"]

import math

import mcl
from scenes.definition import AxisDef
from scenes.plant.mujoco import Probe

WHEEL_RADIUS = 0.25 / (2.0 * math.pi)
"""Measuring-wheel radius [m]: 250 mm circumference."""


def line_axis(
    roll_radius: float,
    resolution: float,
    acceleration: float,
    max_acceleration: float,
    constants: mcl.ServoConstants,
) -> AxisDef:
    """The line drive ``L``: the pinch rolls' motor, its coordinate mm of web at the rolls'
    nominal radius ``roll_radius`` [m], without switches.

    Args:
        roll_radius: the pinch roll's nominal radius [m].
        resolution: mm of web per encoder count.
        acceleration: the ramps' acceleration and deceleration [mm/s²].
        max_acceleration: the largest a command may ask for, either way [mm/s²].
        constants: the servo constants.
    """
    return AxisDef(
        config=mcl.AxisConfig(
            resolution=resolution,
            dev_max=20.0,
            in_position=0.1,
            acceleration=acceleration,
            deceleration=acceleration,
            max_acceleration=max_acceleration,
            max_deceleration=max_acceleration,
        ),
        constants=constants,
        joint="L",
        unit="mm",
        scale=1000.0 * roll_radius,
        switches=(),
    )


def wheel_axis(marks: mcl.Marks, sensor_delay: float) -> AxisDef:
    """The measuring wheel ``W``: an encoder only (0.025 mm of web per count at the radius
    :data:`WHEEL_RADIUS`), its touch probe on the mark sensor, which sees ``marks`` on the web's
    coordinate ``M`` after ``sensor_delay`` [s]."""
    return AxisDef(
        config=mcl.AxisConfig(resolution=0.025, dev_max=20.0, in_position=0.1),
        drive="encoder",
        joint="W",
        unit="mm",
        scale=1000.0 * WHEEL_RADIUS,
        switches=(),
        probe=Probe(marks=marks, joint="M", delay=sensor_delay),
    )

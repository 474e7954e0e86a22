"""The three-axis gantry (models/gantry.xml) wired to three mcl axes X, Y, Z.

Commissioning data: encoder 1 µm per count, Vmax from the amplifiers' velocity at 10 V, position
loop gain Kv = Kp·Vmax/10 ≈ 150 1/s, acceleration feed-forward Ka = m_eff/Kamp + current lag +
half a servo period ≈ 7 ms, integral action for friction (and gravity on Z).
"""

from __future__ import annotations

from typing import Any

import mcl
from scenes.procedures import HomingRecipe
from scenes.scene import AxisSpec, Machine, Scene


def _spec(vmax: float, kp: float, ki: float, max_acc: float) -> AxisSpec:
    return AxisSpec(
        config=mcl.AxisConfig(
            resolution=0.001,
            dev_max=2.0,
            in_position=0.005,
            acceleration=2000.0,
            deceleration=2000.0,
            jerk=50000.0,
            max_acceleration=max_acc,
            max_deceleration=max_acc,
        ),
        constants=mcl.ServoConstants(
            Kp=kp, Ki=ki, Ff=1.0, Kc=50.0, Vmax=vmax, Filter=2.0, Ka=0.007, Ki1=0.0
        ),
    )


AXES = {
    "X": _spec(vmax=1000.0, kp=1.5, ki=75.0, max_acc=20000.0),
    "Y": _spec(vmax=1000.0, kp=1.5, ki=75.0, max_acc=20000.0),
    "Z": _spec(vmax=500.0, kp=3.0, ki=150.0, max_acc=20000.0),
}
"""Commissioning data of the gantry axes (user units mm)."""

HOMING = {
    # REF is on below its edge: search away from it (SwitchNegative), stop where it goes off,
    # then the next index pulse in the positive direction is the origin. SetPosition makes the
    # coordinate equal the joint coordinate in mm (index pulses at 120, 90 and -20 mm).
    "X": HomingRecipe(set_position=120.0),
    "Y": HomingRecipe(set_position=90.0),
    "Z": HomingRecipe(set_position=-20.0, search_velocity=25.0),
}
"""REF switch + index homing of each axis."""


def build(start: dict[str, float] | None = None, **scene_options: Any) -> Scene:
    """The gantry scene.

    Args:
        start: joint coordinates at power-up [m] per axis, e.g. ``{"X": 0.3}``.
        **scene_options: ``servo_period``, ``plc_period``, ``trace_every`` (see :class:`Scene`).
    """
    return Scene([Machine("gantry", "gantry.xml", AXES, start=start or {})], **scene_options)

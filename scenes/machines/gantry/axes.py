"""The gantry's axes X, Y, Z: machine data, servo constants and homing recipes.

Commissioning data: encoder 1 µm per count, Vmax = the axis velocity at 10 V (3000 rpm of each
motor), servo constants found by ``python -m scenes.tools.commissioning gantry X`` (Y, Z): velocity
steps on each amplifier give its gain, lag and friction; Ff corrects the gain, Ka = the lag plus
the module's delays, Kv = 1/(2·lag) ≈ 195 1/s, Kf the friction's voltage, Ki a corner at Kv/8
(what is left, and the weight on Z); Vf (FRICTION_BAND) the friction feed-forward's band.
Software limits 2 mm outside the working travel, inside the LIM switches (5 mm outside it); from
Vmax the error-stop ramp (max_deceleration) ends before the hard stops.
"""

from __future__ import annotations

__all__ = ["AXES", "HOMING", "SW_MARGIN"]

import mcl
from plc.procedures import HomingRecipe
from scenes.definition import AxisDef


def _spec(
    vmax: float,
    gains: tuple[float, float, float, float, float],
    travel: tuple[float, float],
    homing: HomingRecipe,
) -> AxisDef:
    """One gantry axis: ``gains`` = (Kp, Ki, Ff, Ka, Kf) from the commissioning procedure,
    ``travel`` = working travel [mm] (the software limits lie SW_MARGIN outside it)."""
    kp, ki, ff, ka, kf = gains
    return AxisDef(
        config=mcl.AxisConfig(
            resolution=0.001,
            dev_max=2.0,
            in_position=0.005,
            acceleration=2000.0,
            deceleration=2000.0,
            jerk=50000.0,
            max_acceleration=20000.0,
            max_deceleration=20000.0,
        ),
        constants=mcl.ServoConstants(
            Kp=kp,
            Ki=ki,
            Ff=ff,
            Kc=50.0,
            Vmax=vmax,
            LimPos=travel[1] + SW_MARGIN,
            LimNeg=travel[0] - SW_MARGIN,
            Filter=2.0,
            Ka=ka,
            Kf=kf,
            Vf=FRICTION_BAND,
            Ki1=0.0,
        ),
        homing=homing,
    )


FRICTION_BAND = 0.02
"""The band Vf of each axis' friction feed-forward [mm/s]. At a reversal the model velocity
crosses zero with the acceleration a; inside the band the feed-forward makes up for only part
of the Coulomb friction, and the amplifier's velocity loop lets the carriage stand while the
model velocity is below about Vf (Vf is small against the ~1.3 mm/s the friction takes away),
so the axis falls behind by about Vf²/(2·a). Vf = 0.02 mm/s keeps that below 0.1 µm (a tenth
of an encoder count) down to a = 2 mm/s², the reversal of F1000 on a circle of R 140 mm; without
a band (Vf = 0: Kf's own band of 1.3 mm/s) it is the whole following error that builds up the
friction force, ~7 µm on Y."""

SW_MARGIN = 2.0
"""Software limits outside the working travel [mm]; the LIM switches trip 5 mm outside it."""

HOMING = {
    # REF is on below its edge: search away from it (SwitchNegative), stop where it goes off,
    # then the next index pulse in the positive direction is the origin. SetPosition makes the
    # coordinate equal the joint coordinate in mm (index pulses at 120, 100 and -20 mm).
    "X": HomingRecipe(set_position=120.0),
    "Y": HomingRecipe(set_position=100.0),
    "Z": HomingRecipe(set_position=-20.0, search_velocity=25.0),
}
"""REF switch + index homing of each axis."""

AXES = {
    "X": _spec(1000.0, (1.9565, 47.78, 1.0015, 0.00256, 0.006), (0.0, 1000.0), HOMING["X"]),
    "Y": _spec(1000.0, (1.9638, 48.05, 1.0033, 0.00256, 0.0133), (0.0, 600.0), HOMING["Y"]),
    "Z": _spec(500.0, (3.9466, 97.17, 1.0018, 0.00254, 0.0143), (-250.0, 0.0), HOMING["Z"]),
}
"""Commissioning data of the gantry axes (user units mm)."""

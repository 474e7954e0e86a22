"""The delta picker's axes: the three upper arms ``A1``, ``A2``, ``A3`` (hinges, deg; 0 = arm
horizontal, positive = down) and the infeed conveyor ``C`` (mm of belt), its touch probe wired to
the photo eye; the robot's geometry and the parts on the belt.

Commissioning data: the arms' constants are those ``python -m scenes.tools.commissioning
delta_picker A1`` derives from velocity steps on the amplifier (gain 88.3 °/s per V, lag 5.0 ms,
loop lag 6.5 ms: Kv 77 1/s) at the start pose (every arm horizontal); the conveyor's: Kv =
0.6·1500/10 = 90 1/s. SW limits 1° inside the LIM switches. The arms' acceleration feed-forward
``Ka`` is that of the working poses over the belt and the tray (the arms 5–63° down, the
effector's and the other arms' inertia reflected onto each arm; the drive's lag there 7.4 ms
instead of 6.5 ms): in the standard cycle at 100 m/s² the tool point then lags at most 1.25 mm
(rms 0.57 mm) behind its set point, against 1.9 mm (rms 1.0 mm) with the start pose's 0.00659 s
(1.4 mm with 0.008 s, 2.4 mm with 0.009 s).
"""

from __future__ import annotations

__all__ = [
    "ARMS",
    "AXES",
    "BELT_TOP",
    "BELT_Y",
    "DELTA",
    "EYE_DELAY",
    "EYE_X",
    "HOMING",
    "PART_HEIGHT",
    "PART_X",
    "TOOL",
]

import mcl
from plc.procedures import HomingRecipe
from scenes.definition import AxisDef
from scenes.machines.delta_picker.devices import BEAM
from scenes.plant.mujoco import Probe

ARMS = ("A1", "A2", "A3")
"""The arms, in group member order (arm i at azimuth (i − 1)·120° about the base's z)."""
DELTA = mcl.DeltaKinematics(
    base_radius=200.0,
    effector_radius=50.0,
    upper_arm=350.0,
    forearm=800.0,
    theta_min=-30.0,
    theta_max=85.0,
    tcp=mcl.TcpLimits(velocity=4000.0, acceleration=20000.0, max_acceleration=100000.0, jerk=3.0e7),
)
"""The robot's kinematics: MCS origin at the centre of the base plane (1.6 m above the floor),
z up; the tool point is the effector's centre; the arms' range is their working travel. The
tool point's limits: 4 m/s, 100 m/s² (the class's 10 g; in the standard cycle the motors take
up to 78 % of their peak torque), jerk 3·10⁷ mm/s³ at most (the moves ask less: what they leave
of it turns a blended corner)."""
TOOL = 50.0
"""The vacuum cup's face below the effector's centre [mm]."""
BELT_TOP = -880.0
"""The belt's top face in the MCS [mm] (the tray's top lies as high)."""
BELT_Y = -150.0
"""The belt's centre line in the MCS [mm]; side guides centre the parts on it."""
EYE_X = -400.0
"""The photo eye across the belt [mm of MCS x], where the parts come within the robot's reach."""
EYE_DELAY = 0.0005
"""The photo eye's response time [s] (the belt runs on meanwhile: the demo takes it off)."""
PART_HEIGHT = 30.0
"""The parts: 60 × 60 × 30 mm, 0.1 kg [mm]."""
PART_X = (-1000.0, -1328.7, -1580.6, -1900.9, -2250.3, -2598.8, -2905.8, -3227.8)
"""Each part's centre on the belt at belt coordinate 0 [mm of MCS x] (random spacing 240–370
mm, seed 37; the model's parts ``part0`` … stand there)."""
SEARCH = 20.0
"""REF search velocity of the arms [deg/s]."""

HOMING = {
    # REF is on below -9° (the arm raised): from the horizontal arm search it negative, leave it
    # positive at its edge, the next motor index positive (every 18° of the arm) is 0°
    arm: HomingRecipe(search_velocity=SEARCH, index_velocity=10.0, set_position=0.0)
    for arm in ARMS
}
"""REF switch + motor index homing of each arm."""


def _arm(outputs: int = 0) -> AxisDef:
    """One arm; ``outputs`` digital outputs on its channel."""
    return AxisDef(
        config=mcl.AxisConfig(
            resolution=0.0001,
            dev_max=1.0,
            in_position=0.01,
            acceleration=5000.0,
            deceleration=5000.0,
            jerk=200000.0,
            max_acceleration=20000.0,
            max_deceleration=20000.0,
            unit="deg",
        ),
        constants=mcl.ServoConstants(
            Kp=0.8752,
            Ki=8.46,
            Ff=1.0189,
            Kc=50.0,
            Vmax=900.0,
            LimPos=87.0 - 1.0,
            LimNeg=-32.0 + 1.0,
            Filter=2.0,
            Ka=0.0075,
            Kf=0.0157,
            Ki1=0.0,
        ),
        homing=HOMING["A1"],
        digital_outputs=outputs,
    )


AXES = {
    "A1": _arm(outputs=1),
    "A2": _arm(),
    "A3": _arm(),
    "C": AxisDef(
        config=mcl.AxisConfig(
            resolution=0.001,
            dev_max=5.0,
            in_position=0.05,
            acceleration=2000.0,
            deceleration=2000.0,
            max_acceleration=5000.0,
            max_deceleration=5000.0,
        ),
        constants=mcl.ServoConstants(
            Kp=0.6, Ki=10.0, Ff=1.0, Kc=50.0, Vmax=1500.0, Filter=2.0, Ka=0.004
        ),
        switches=(),
        probe=Probe(marks=BEAM, device="eye", delay=EYE_DELAY),
    ),
}
"""Arms A1–A3 (deg) and conveyor C (mm of belt). Digital output 0 of A1 is the vacuum valve."""

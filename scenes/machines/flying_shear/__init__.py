"""The flying shear (models/flying_shear.xml): a strip line cut to length or to print marks.

Three mcl axes (:mod:`.axes`): ``L`` the line drive (pinch rolls, MC_MoveVelocity), ``W`` the
measuring wheel (encoder only: the gearing master, its touch probe wired to the mark sensor) and
``S`` the shear carriage (the slave, homed on REF + index). The knife is not an axis: digital
output 0 of ``S`` switches its valve. Python devices (:mod:`.devices`) run before every physics
step: the eccentric pinch roll (the line-speed ripple), the measuring wheel's errors
(measurement only; ``ideal()`` turns them off), the knife's valve, cylinder and grip on the
strip, and :class:`CutRecorder`, which takes every cut from the physics (the material coordinate
under the knife when the blade comes down on the strip). :class:`Demo` (:mod:`.demo`) is the PLC
program: cut to length (MC_GearInPos, Zeroing 1, with the cut-length correction from the
measured pieces) or to the print marks (Zeroing 2, with the register that learns the wheel's
scale from the print pitch). :mod:`.zeroing` measures Zeroing 2 from the physics;
:mod:`.definition` is the machine in the registry.
"""

from scenes.machines.flying_shear.axes import (
    AXES,
    HOMING,
    ROLL_RADIUS,
    SENSOR_DELAY,
)
from scenes.machines.flying_shear.definition import DEVICES, MACHINE
from scenes.machines.flying_shear.demo import (
    CORRECTION_PIECES,
    PHASES,
    RATIO_BASE,
    START,
    SYNC_LIMIT,
    CutJob,
    Demo,
)
from scenes.machines.flying_shear.devices import (
    MARK_PITCH,
    MARKS,
    Cut,
    CutRecorder,
    EccentricRoll,
    KnifeCylinder,
    mark_at,
)
from scenes.machines.flying_shear.zeroing import ZeroingRecorder
from scenes.parts import WHEEL_RADIUS, MeasuringWheel

COMPILED_MODULES = ("devices",)
"""The modules of this package that the compiled build covers (its devices, run every physics
step)."""

__all__ = [
    "AXES",
    "CORRECTION_PIECES",
    "DEVICES",
    "HOMING",
    "MACHINE",
    "MARKS",
    "MARK_PITCH",
    "PHASES",
    "RATIO_BASE",
    "ROLL_RADIUS",
    "SENSOR_DELAY",
    "START",
    "SYNC_LIMIT",
    "WHEEL_RADIUS",
    "Cut",
    "CutJob",
    "CutRecorder",
    "Demo",
    "EccentricRoll",
    "KnifeCylinder",
    "MeasuringWheel",
    "ZeroingRecorder",
    "mark_at",
]

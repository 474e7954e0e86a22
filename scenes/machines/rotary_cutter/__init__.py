"""The rotary cross cutter (models/rotary_cutter.xml): a web line cut across by a knife drum.

Three mcl axes (:mod:`.axes`): ``L`` the web feed (pinch rolls, MC_MoveVelocity), ``W`` the
measuring wheel (encoder only: the drum's master, its touch probe wired to the mark sensor) and
``D`` the knife drum (modulo 360°, homed on its REF cam and the motor's index). Python devices run
before every physics step: the measuring wheel's errors (the web line's wheel of
:mod:`scenes.parts`, measurement only) and :class:`KnifeDrum` (:mod:`.devices`): the blades in the
web (cutting force, grip along the web) and every cut taken from the physics (a piece is cut when a
blade's tip has gone through the web). Two PLC programs: :class:`CamDemo` (:mod:`.cam_demo`, the
machine's demo) cuts to length on ``mcl.rotary_knife`` cams, pieces shorter and longer than the tip
circle, a length change on the fly, registration to the print marks; :class:`Demo` (:mod:`.demo`)
gears the drum to the wheel with MC_GearIn, tip speed = web speed, so each piece is one blade pitch
long. :mod:`.definition` is the machine in the registry.
"""

from scenes.machines.rotary_cutter.axes import (
    AXES,
    CUT_FORCE,
    GEAR_RATIO,
    HOMING,
    ROLL_RADIUS,
    SENSOR_DELAY,
    TIP_CIRCUMFERENCE,
)
from scenes.machines.rotary_cutter.cam_demo import Batch, CamDemo, CamJob
from scenes.machines.rotary_cutter.definition import DEVICES, MACHINE
from scenes.machines.rotary_cutter.demo import DRUM_SPEED_LIMIT, CutterJob, Demo
from scenes.machines.rotary_cutter.devices import Cut, KnifeDrum
from scenes.machines.rotary_cutter.marks import MARK_PITCH, MARKS, PRINT_MARKS, PrintMarks
from scenes.parts import WHEEL_RADIUS, MeasuringWheel

COMPILED_MODULES = ("devices",)
"""The modules of this package that the compiled build covers (its devices, run every physics
step)."""

__all__ = [
    "AXES",
    "CUT_FORCE",
    "DEVICES",
    "DRUM_SPEED_LIMIT",
    "GEAR_RATIO",
    "HOMING",
    "MACHINE",
    "MARKS",
    "MARK_PITCH",
    "PRINT_MARKS",
    "ROLL_RADIUS",
    "SENSOR_DELAY",
    "TIP_CIRCUMFERENCE",
    "WHEEL_RADIUS",
    "Batch",
    "CamDemo",
    "CamJob",
    "Cut",
    "CutterJob",
    "Demo",
    "KnifeDrum",
    "MeasuringWheel",
    "PrintMarks",
]

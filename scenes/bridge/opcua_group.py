"""The OPC UA methods of an axes group (the ``Group`` object of :mod:`scenes.bridge.opcua_nodes`):
Part 4's group blocks with their inputs by their PLCopen names, each one a command of the group
block's control word (:data:`plc.operator.group_bus.GROUP_CONTROL_BITS`), as an axis' methods
are its block's commands (:mod:`scenes.bridge.opcua_methods`).

A point (``Position``, ``Distance``, ``AuxPoint``, ``EndPoint``) is an array of Doubles, one per
member in member order; an array of another length, or with a value that is no finite REAL, is
refused with BadInvalidArgument (the argument's own status: BadTypeMismatch, BadOutOfRange).
"""

from __future__ import annotations

__all__ = ["GROUP_METHODS", "GroupMethod", "group_command", "point"]

import math
from dataclasses import dataclass
from typing import Any

from asyncua import ua

from scenes.bridge.opcua_methods import (
    ACCELERATION,
    BUFFER_MODE,
    DECELERATION,
    F32_MAX,
    JERK,
    NUMBERS,
    RAMP,
    Argument,
    Method,
    Refused,
)
from scenes.bridge.table import SignalTable


@dataclass(frozen=True)
class GroupMethod(Method):
    """A method of the group: ``fixed`` are parameters the method itself sets (``relative``:
    the absolute or the relative block)."""

    fixed: tuple[tuple[str, float], ...] = ()


END = Argument("EndPoint", "point", "end", "end point, one value per member [u]")
ARC = (
    Argument("CircMode", "u16", "circ_mode", "mcl.MC_CIRC_MODE: 0 BORDER, 1 CENTER, 2 RADIUS"),
    Argument("AuxPoint", "point", "aux", "border point, centre or (RADIUS) the radius first [u]"),
    END,
    Argument("PathChoice", "u16", "path_choice", "0 clockwise, 1 counter-clockwise"),
    Argument("Plane", "u16", "plane", "0 automatic, 17 XY, 18 ZX, 19 YZ"),
    Argument("Turns", "u16", "turns", "more full turns of a CENTER arc"),
)
MOTION = (*RAMP, BUFFER_MODE)
COORD_SYSTEM = Argument(
    "CoordSystem",
    "u16",
    "coord_system",
    "mcl.MC_COORD_SYSTEM: 0 ACS (joints), 1 MCS (Cartesian), 2 PCS (the product's)",
)
MOVE = (*RAMP, COORD_SYSTEM, BUFFER_MODE)
"""A move's dynamics, coordinate system and BufferMode (PLCopen's order of the inputs)."""
RELATIVE = Argument("Relative", "bool", "relative", "end and aux relative to the start")
FRAME_RAMP = (ACCELERATION, JERK)
"""The ramp of the tool point into a new PCS (0: its defaults)."""
ROTATION = Argument("RotZ", "f32", "frame_rz", "the frame's rotation about z [deg]")
TRACK = (
    Argument("ConveyorBelt", "axis", "belt", "the belt axis' name"),
    Argument("ConveyorBeltOrigin", "point", "frame", "the belt frame's origin x, y, z [mm, MCS]"),
    ROTATION,
    Argument("InitialObjectPosition", "point", "object", "the part in the belt frame [mm]"),
    Argument("LatchedPosition", "f32", "latched_position", "the belt's position at the latch"),
    Argument("Horizon", "f32", "horizon", "the part within reach that long [s]"),
    *FRAME_RAMP,
)
"""MC_TrackConveyorBelt's inputs (the origin's rotation, a part of PLCopen's frame, apart)."""
CARTESIAN = (
    Argument("TransX", "f32", "frame_1", "the PCS origin's x [mm, MCS]"),
    Argument("TransY", "f32", "frame_2", "its y [mm]"),
    Argument("TransZ", "f32", "frame_3", "its z [mm]"),
    Argument("RotAngle1", "f32", "frame_rz", "its rotation about z [deg]"),
    *FRAME_RAMP,
)
"""MC_SetCartesianTransform's inputs (a delta's tool point turns about z alone)."""
ABSOLUTE: tuple[tuple[str, float], ...] = (("relative", 0.0),)
BY_DISTANCE: tuple[tuple[str, float], ...] = (("relative", 1.0),)

GROUP_METHODS = (
    GroupMethod("MC_GroupEnable", "enable", (), "MC_AddAxisToGroup of each member, MC_GroupEnable"),
    GroupMethod("MC_GroupDisable", "enable", (), "MC_GroupDisable, MC_UngroupAllAxes"),
    GroupMethod("MC_GroupReset", "reset", (), "MC_GroupReset: leave GroupErrorStop"),
    GroupMethod(
        "MC_MoveLinearAbsolute",
        "move_linear",
        (Argument("Position", "point", "end", "target, one value per member [u]"), *MOVE),
        "MC_MoveLinearAbsolute",
        ABSOLUTE,
    ),
    GroupMethod(
        "MC_MoveLinearRelative",
        "move_linear",
        (Argument("Distance", "point", "end", "distance, one value per member [u]"), *MOVE),
        "MC_MoveLinearRelative",
        BY_DISTANCE,
    ),
    GroupMethod(
        "MC_MoveCircularAbsolute",
        "move_circular",
        (*ARC, *MOVE),
        "MC_MoveCircularAbsolute",
        ABSOLUTE,
    ),
    GroupMethod(
        "MC_MoveCircularRelative",
        "move_circular",
        (*ARC, *MOVE),
        "MC_MoveCircularRelative",
        BY_DISTANCE,
    ),
    GroupMethod(
        "AppendLine",
        "append_line",
        (END, *MOTION, RELATIVE),
        "append a line to the group's path table (an MC_PATH_DATA_REF)",
    ),
    GroupMethod(
        "AppendArc",
        "append_arc",
        (*ARC, *MOTION, RELATIVE),
        "append an arc to the group's path table",
    ),
    GroupMethod("ClearPath", "clear_path", (), "empty the group's path table"),
    GroupMethod(
        "MC_MovePath", "move_path", (COORD_SYSTEM, BUFFER_MODE), "MC_MovePath of the path table"
    ),
    GroupMethod("MC_GroupStop", "stop", (DECELERATION, JERK), "MC_GroupStop"),
    GroupMethod("MC_GroupHalt", "halt", (DECELERATION, JERK), "MC_GroupHalt along the path"),
    GroupMethod(
        "MC_GroupInterrupt", "interrupt", (DECELERATION, JERK), "MC_GroupInterrupt: feed hold"
    ),
    GroupMethod("MC_GroupContinue", "continue", (), "MC_GroupContinue: the path resumes"),
    GroupMethod(
        "MC_GroupSetOverride",
        "set_override",
        (
            Argument("VelFactor", "f32", "vel_factor", "path velocity factor (1.0: 100 %)"),
            Argument("AccFactor", "f32", "acc_factor", "acceleration factor (0 < … ≤ 4.0)"),
            Argument("JerkFactor", "f32", "jerk_factor", "jerk factor (0 < … ≤ 8.0)"),
        ),
        "MC_GroupSetOverride, enabled until the group's next command; the group keeps it",
    ),
    GroupMethod(
        "MC_TrackConveyorBelt",
        "track_belt",
        TRACK,
        "MC_TrackConveyorBelt: the PCS moves with a part",
    ),
    GroupMethod(
        "MC_SetCoordinateTransform",
        "set_frame",
        (
            Argument("CoordTransform", "point", "frame", "the PCS origin x, y, z [mm, MCS]"),
            ROTATION,
            *FRAME_RAMP,
        ),
        "MC_SetCoordinateTransform: a fixed PCS (zeros: the MCS); ends a conveyor tracking",
    ),
    GroupMethod(
        "MC_SetCartesianTransform",
        "set_frame",
        CARTESIAN,
        "MC_SetCartesianTransform: a fixed PCS, as MC_SetCoordinateTransform",
    ),
)
"""The methods of the group."""


def point(variant: ua.Variant, members: int) -> list[float]:
    """The values of a point argument: an array of ``members`` finite REALs.

    Raises:
        Refused: BadTypeMismatch (no array of numbers), BadOutOfRange (another length, a
            value that is no finite REAL).
    """
    values = variant.Value
    if variant.VariantType not in NUMBERS or not isinstance(values, list):
        raise Refused(ua.StatusCodes.BadTypeMismatch, "an array of numbers is due")
    if len(values) != members:
        raise Refused(ua.StatusCodes.BadOutOfRange, f"{members} values are due, not {len(values)}")
    if not all(math.isfinite(v) and abs(v) <= F32_MAX for v in values):
        raise Refused(ua.StatusCodes.BadOutOfRange, "a value is no finite REAL")
    return [float(v) for v in values]


def group_command(
    table: SignalTable, group: str, method: GroupMethod, values: dict[str, Any]
) -> None:
    """Group method ``method`` with its checked ``values`` into the table: the enable level
    set or cleared, or the command requested with its parameters.

    Raises:
        NotInControl: the PLC is not in control.
    """
    if method.bit == "enable":
        table.set_bit(group, "enable", method.name == "MC_GroupEnable")
        return
    params: dict[str, float] = {}
    for argument in method.arguments:
        value = values[argument.name]
        if argument.kind == "point":
            params.update((f"{argument.field}_{k + 1}", v) for k, v in enumerate(value))
        else:
            params[argument.field] = float(value)
    params.update(method.fixed)
    table.request(group, method.bit, params)

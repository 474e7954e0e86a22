"""The OPC UA methods of an axis (:mod:`scenes.bridge.opcua_nodes`): the PLCopen blocks with
their inputs by their PLCopen names and types, and how a client's values are checked (a Bad
status code for each one refused)."""

from __future__ import annotations

__all__ = [
    "ACCELERATION",
    "ARGUMENT_TYPE",
    "BUFFER_MODE",
    "DECELERATION",
    "DISTANCE",
    "F32_MAX",
    "FORCE",
    "JERK",
    "MASTER",
    "METHODS",
    "NUMBERS",
    "POSITION",
    "RAMP",
    "RANGE",
    "RATIO",
    "SYNC",
    "VELOCITY",
    "ZEROING",
    "ArgKind",
    "Argument",
    "Method",
    "Refused",
    "boolean",
    "methods_of",
    "number",
]

import math
from dataclasses import dataclass
from typing import Literal

from asyncua import ua

from plc.operator.bus import CommandWords

F32_MAX = 3.4028234663852886e38
"""The largest REAL of the register map: a REAL field takes no larger magnitude."""


RANGE = {
    "u16": (0, 0xFFFF),
    "i16": (-0x8000, 0x7FFF),
    "u32": (0, 0xFFFFFFFF),
    "i32": (-(2**31), 2**31 - 1),
}
"""The values an integer type holds."""

NUMBERS = frozenset(
    {
        ua.VariantType.SByte,
        ua.VariantType.Byte,
        ua.VariantType.Int16,
        ua.VariantType.UInt16,
        ua.VariantType.Int32,
        ua.VariantType.UInt32,
        ua.VariantType.Int64,
        ua.VariantType.UInt64,
        ua.VariantType.Float,
        ua.VariantType.Double,
    }
)
"""The variant types a number may come as (a client's 300 is an Int64, 300.0 a Double)."""


class Refused(Exception):
    """A write or argument refused, with the status code that says why."""

    def __init__(self, code: int, why: str) -> None:
        super().__init__(why)
        self.code = code


def number(variant: ua.Variant | None, kind: str) -> float:
    """The value of a numeric ``variant`` for a field or argument of ``kind`` (``f32``: a
    finite REAL; ``u16``, ``i16``, ``u32``, ``i32``: a whole number within the type).

    Raises:
        Refused: BadTypeMismatch (no scalar number), BadOutOfRange (not finite, too large,
            not whole, beyond the type).
    """
    if variant is None or variant.VariantType not in NUMBERS or variant.is_array:
        raise Refused(ua.StatusCodes.BadTypeMismatch, "a number is due")
    value = variant.Value
    if not isinstance(value, int | float) or isinstance(value, bool):
        raise Refused(ua.StatusCodes.BadTypeMismatch, "a number is due")
    if kind == "f32":
        if not (math.isfinite(value) and abs(value) <= F32_MAX):
            raise Refused(ua.StatusCodes.BadOutOfRange, f"{value} is no finite REAL")
        return float(value)
    lo, hi = RANGE[kind]
    if isinstance(value, float) and not value.is_integer():
        raise Refused(ua.StatusCodes.BadOutOfRange, f"{value} is not a whole number")
    if not lo <= value <= hi:
        raise Refused(ua.StatusCodes.BadOutOfRange, f"{value} lies outside {lo}…{hi}")
    return float(value)


def boolean(variant: ua.Variant | None) -> bool:
    """The value of a Boolean ``variant``.

    Raises:
        Refused: BadTypeMismatch (not a scalar Boolean).
    """
    if variant is None or variant.VariantType != ua.VariantType.Boolean or variant.is_array:
        raise Refused(ua.StatusCodes.BadTypeMismatch, "a Boolean is due")
    return bool(variant.Value)


ArgKind = Literal["f32", "u16", "i16", "bool", "axis", "direction", "point"]
"""An argument's type: a REAL (Double), UINT, INT, BOOL, an axis of the table by name (String),
an MC_Direction (Int32: 1 positive, 3 negative), a point of a group (an array of Doubles, one
per member)."""

ARGUMENT_TYPE = {
    "f32": ua.VariantType.Double,
    "u16": ua.VariantType.UInt16,
    "i16": ua.VariantType.Int16,
    "bool": ua.VariantType.Boolean,
    "axis": ua.VariantType.String,
    "direction": ua.VariantType.Int32,
    "point": ua.VariantType.Double,
}


@dataclass(frozen=True)
class Argument:
    """An input of a method: a PLCopen block's input."""

    name: str
    kind: ArgKind
    field: str
    """The table parameter it sets (empty: the method uses it itself)."""
    description: str


def _arg(name: str, kind: ArgKind, field: str, description: str) -> Argument:
    return Argument(name, kind, field, description)


POSITION = _arg("Position", "f32", "position", "target position [u]")
DISTANCE = _arg("Distance", "f32", "distance", "distance [u]")
VELOCITY = _arg("Velocity", "f32", "velocity", "velocity [u/s]")
ACCELERATION = _arg("Acceleration", "f32", "acceleration", "acceleration [u/s²]")
DECELERATION = _arg("Deceleration", "f32", "deceleration", "deceleration [u/s²] (0: default)")
JERK = _arg("Jerk", "f32", "jerk", "jerk [u/s³] (0: trapezoidal)")
BUFFER_MODE = _arg("BufferMode", "u16", "buffer_mode", "mcl.MC_BufferMode (0: Aborting)")
RAMP = (VELOCITY, ACCELERATION, DECELERATION, JERK)
MASTER = _arg("Master", "axis", "master", "the master axis' name")
RATIO = (
    _arg("RatioNumerator", "i16", "ratio_numerator", "gear ratio numerator (INT)"),
    _arg("RatioDenominator", "u16", "ratio_denominator", "gear ratio denominator (UINT)"),
)
SYNC = (
    _arg("MasterSyncPosition", "f32", "master_sync_position", "master position of sync [u]"),
    _arg("SlaveSyncPosition", "f32", "slave_sync_position", "slave position of sync [u]"),
    _arg("MasterStartDistance", "f32", "master_start_distance", "master distance to sync [u]"),
)
ZEROING = _arg("Zeroing", "u16", "zeroing", "0 none, 1 length, 2 mark")
FORCE = (
    _arg("Force", "f32", "force", "force set point [F]"),
    _arg("ForceRamp", "f32", "force_ramp", "force ramp [F/s] (0: at once)"),
    VELOCITY,
    ACCELERATION,
    _arg("Gain", "f32", "gain", "admittance [u/s/F]"),
    _arg("InputNumber", "i16", "input_number", "analog input of the force"),
    _arg("Scale", "f32", "scale", "force per volt of InputNumber [F/V]"),
    _arg("InputNumber2", "i16", "input_number2", "second analog input (−1: none)"),
    _arg("Scale2", "f32", "scale2", "force per volt of InputNumber2 [F/V]"),
    _arg("Offset", "f32", "offset", "force offset [F]"),
    _arg("Tolerance", "f32", "tolerance", "InForce window [F]"),
    BUFFER_MODE,
)


@dataclass(frozen=True)
class Method:
    """A method of an axis: a PLCopen block, called by control bit ``bit`` (an Execute
    command of :meth:`SignalTable.request`, or ``enable``, ``jog``, ``outputs``)."""

    name: str
    bit: str
    arguments: tuple[Argument, ...]
    description: str


METHODS = (
    Method("MC_Power", "enable", (_arg("Enable", "bool", "", "power on"),), "MC_Power Enable"),
    Method("MC_Reset", "reset", (), "MC_Reset: leave ErrorStop"),
    Method("MC_MoveAbsolute", "move_absolute", (POSITION, *RAMP, BUFFER_MODE), "MC_MoveAbsolute"),
    Method("MC_MoveRelative", "move_relative", (DISTANCE, *RAMP, BUFFER_MODE), "MC_MoveRelative"),
    Method("MC_MoveAdditive", "move_additive", (DISTANCE, *RAMP, BUFFER_MODE), "MC_MoveAdditive"),
    Method(
        "MC_MoveVelocity",
        "move_velocity",
        (*RAMP, _arg("Direction", "direction", "", "1 positive, 3 negative"), BUFFER_MODE),
        "MC_MoveVelocity",
    ),
    Method("MC_Home", "home", (), "the machine's homing recipe"),
    Method(
        "MC_StepDirect",
        "home_direct",
        (_arg("SetPosition", "f32", "position", "the position the axis gets where it stands [u]"),),
        "MC_StepDirect: homed where it stands, without motion",
    ),
    Method("MC_Stop", "stop", (DECELERATION, JERK), "MC_Stop"),
    Method("MC_Halt", "halt", (DECELERATION, JERK), "MC_Halt"),
    Method(
        "GT_Jog",
        "jog",
        (
            _arg("JogPos", "bool", "", "jog positive (a level)"),
            _arg("JogNeg", "bool", "", "jog negative (a level)"),
            _arg("JogVelo", "f32", "velocity", "jog velocity [u/s] (its magnitude)"),
        ),
        "GT_Jog while JogPos or JogNeg is set",
    ),
    Method(
        "MC_GearIn",
        "gear_in",
        (MASTER, *RATIO, ACCELERATION, DECELERATION, JERK),
        "MC_GearIn",
    ),
    Method(
        "MC_GearInPos",
        "gear_in_pos",
        (MASTER, *RATIO, *SYNC, VELOCITY, ACCELERATION, DECELERATION, JERK, ZEROING),
        "MC_GearInPos",
    ),
    Method("MC_GearOut", "gear_out", (), "MC_GearOut"),
    Method("MC_ForceControl", "force_control", FORCE, "MC_ForceControl"),
    Method(
        "MC_WriteDigitalOutput",
        "outputs",
        (
            _arg("OutputNumber", "u16", "", "the output"),
            _arg("Value", "bool", "", "its value"),
        ),
        "MC_WriteDigitalOutput",
    ),
)
"""Every method an axis may have; :func:`methods_of` says which one has."""


def methods_of(axis: CommandWords) -> list[Method]:
    """The methods of an axis: MC_Power and GT_Jog where it has a drive, the commands it takes
    (:attr:`CommandWords.commands`), MC_WriteDigitalOutput where it has outputs."""
    takes = set(axis.commands)
    if axis.operator.axis.has_drive:
        takes |= {"enable", "jog"}
    if axis.operator.outputs:
        takes.add("outputs")
    return [m for m in METHODS if m.bit in takes]

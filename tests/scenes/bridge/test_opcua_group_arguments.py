"""The arguments of the group's OPC UA methods, in-process: a point is an array of one finite
REAL per member, refused by its length, a NaN, ±inf, a value beyond a REAL or its type; each
method sets its fields of the group block and requests its command."""

from __future__ import annotations

import math

import pytest
from asyncua import ua

import scenes
from plc.operator.group_bus import GROUP_CONTROL_BITS
from scenes.bridge.opcua_group import GROUP_METHODS, GroupMethod, group_command
from scenes.bridge.opcua_group import point as point_value
from scenes.bridge.opcua_methods import F32_MAX, Refused
from scenes.bridge.table import SignalTable

D = ua.VariantType.Double
codes = ua.StatusCodes


def point(*values: float) -> ua.Variant:
    return ua.Variant(list(values), D, is_array=True)


def test_a_point_is_an_array_of_one_finite_real_per_member() -> None:
    assert point_value(point(1.0, -2.5, 3.0), 3) == [1.0, -2.5, 3.0]
    ints = point_value(ua.Variant([1, 2], ua.VariantType.Int32, is_array=True), 2)
    assert ints == [1.0, 2.0] and all(isinstance(v, float) for v in ints)
    numbers, finite = "an array of numbers is due", "a value is no finite REAL"
    refused = {
        "two of three": (point(1.0, 2.0), codes.BadOutOfRange, "3 values are due, not 2"),
        "four": (point(1.0, 2.0, 3.0, 4.0), codes.BadOutOfRange, "3 values are due, not 4"),
        "NaN": (point(1.0, math.nan, 3.0), codes.BadOutOfRange, finite),
        "inf": (point(1.0, 2.0, -math.inf), codes.BadOutOfRange, finite),
        "beyond a REAL": (point(1.0, 2.0, 1e39), codes.BadOutOfRange, finite),
        "a scalar": (ua.Variant(1.0, D), codes.BadTypeMismatch, numbers),
        "texts": (ua.Variant(["a", "b", "c"]), codes.BadTypeMismatch, numbers),
        "Booleans": (ua.Variant([True] * 3), codes.BadTypeMismatch, numbers),
    }
    for what, (variant, code, why) in refused.items():
        with pytest.raises(Refused) as caught:
            point_value(variant, 3)
        assert (caught.value.code, str(caught.value)) == (code, why), what
    at_the_limit = point_value(point(F32_MAX, -F32_MAX, 0.0), 3)
    assert at_the_limit == [F32_MAX, -F32_MAX, 0.0]


def method(name: str) -> GroupMethod:
    return next(m for m in GROUP_METHODS if m.name == name)


def test_a_method_sets_the_group_fields_and_requests_its_command() -> None:
    table = SignalTable(scenes.definition("gantry"))
    group_command(table, "group", method("MC_GroupEnable"), {})
    assert int(table.get("group.control")) == 1
    values = {
        "CircMode": 1.0,
        "AuxPoint": [30.0, 1.0, 2.0],
        "EndPoint": [3.0, 4.0, 5.0],
        "PathChoice": 1.0,
        "Plane": 17.0,
        "Turns": 2.0,
        "Velocity": 50.0,
        "Acceleration": 600.0,
        "Deceleration": 700.0,
        "Jerk": 8000.0,
        "CoordSystem": 1.0,
        "BufferMode": 4.0,
    }
    group_command(table, "group", method("MC_MoveCircularRelative"), values)
    expected = {
        "circ_mode": 1.0, "aux_1": 30.0, "aux_2": 1.0, "aux_3": 2.0, "end_1": 3.0,
        "end_2": 4.0, "end_3": 5.0, "path_choice": 1.0, "plane": 17.0, "turns": 2.0,
        "velocity": 50.0, "acceleration": 600.0, "deceleration": 700.0, "jerk": 8000.0,
        "buffer_mode": 4.0, "relative": 1.0, "coord_system": 1.0,
    }  # fmt: skip
    assert {name: table.get(f"group.{name}") for name in expected} == expected
    assert table.requested("group")[0] == GROUP_CONTROL_BITS.index("move_circular")
    group_command(table, "group", method("MC_MoveCircularAbsolute"), values)
    assert table.get("group.relative") == 0.0
    line = {"Position": [7.0, 8.0, 9.0], "Velocity": 1.0, "Acceleration": 2.0}
    line |= {"Deceleration": 3.0, "Jerk": 4.0, "CoordSystem": 0.0, "BufferMode": 0.0}
    group_command(table, "group", method("MC_MoveLinearAbsolute"), line)
    assert [table.get(f"group.end_{k}") for k in (1, 2, 3)] == [7.0, 8.0, 9.0]
    assert table.get("group.coord_system") == 0.0
    assert table.requested("group")[0] == GROUP_CONTROL_BITS.index("move_linear")
    append = {"EndPoint": [1.0, 0.0, 0.0], **{k: v for k, v in line.items() if k != "Position"}}
    group_command(table, "group", method("AppendLine"), {**append, "Relative": True})
    assert table.get("group.relative") == 1.0
    group_command(table, "group", method("AppendLine"), {**append, "Relative": False})
    assert table.get("group.relative") == 0.0
    factors = {"VelFactor": 0.5, "AccFactor": 0.25, "JerkFactor": 0.125}
    group_command(table, "group", method("MC_GroupSetOverride"), factors)
    assert [table.get(f"group.{n}_factor") for n in ("vel", "acc", "jerk")] == [0.5, 0.25, 0.125]
    assert table.requested("group")[0] == GROUP_CONTROL_BITS.index("set_override")
    group_command(table, "group", method("MC_GroupDisable"), {})
    assert int(table.get("group.control")) == 0
    bits = {m.name: m.bit for m in GROUP_METHODS}
    assert {b for b in bits.values()} == set(GROUP_CONTROL_BITS)  # every command has a method


def test_the_frame_methods_set_the_pcs_fields_and_request_their_command() -> None:
    """MC_TrackConveyorBelt (the belt by its axis number), MC_SetCoordinateTransform and
    MC_SetCartesianTransform (a fixed PCS: both set_frame)."""
    table = SignalTable(scenes.definition("delta_picker"))
    values = {
        "ConveyorBelt": float(table.axes.index("C")),
        "ConveyorBeltOrigin": [-400.0, -150.0, -775.0],
        "RotZ": 5.0,
        "InitialObjectPosition": [-30.0, 2.0, 0.5],
        "LatchedPosition": 1234.5,
        "Horizon": 0.5,
        "Acceleration": 3000.0,
        "Jerk": 1.0e5,
    }
    group_command(table, "group", method("MC_TrackConveyorBelt"), values)
    expected = {
        "belt": 3.0, "frame_1": -400.0, "frame_2": -150.0, "frame_3": -775.0, "frame_rz": 5.0,
        "object_1": -30.0, "object_2": 2.0, "object_3": 0.5, "latched_position": 1234.5,
        "horizon": 0.5, "acceleration": 3000.0, "jerk": 1.0e5,
    }  # fmt: skip
    assert {name: table.get(f"group.{name}") for name in expected} == expected
    assert table.requested("group")[0] == GROUP_CONTROL_BITS.index("track_belt")
    fixed = {"CoordTransform": [1.0, 2.0, -700.0], "RotZ": 30.0, "Acceleration": 0.0, "Jerk": 0.0}
    group_command(table, "group", method("MC_SetCoordinateTransform"), fixed)
    frame = [table.get(f"group.frame_{k}") for k in ("1", "2", "3", "rz")]
    assert frame == [1.0, 2.0, -700.0, 30.0]
    assert table.requested("group")[0] == GROUP_CONTROL_BITS.index("set_frame")
    cartesian = {"TransX": 4.0, "TransY": 5.0, "TransZ": -650.0, "RotAngle1": -15.0}
    cartesian |= {"Acceleration": 100.0, "Jerk": 2000.0}
    group_command(table, "group", method("MC_SetCartesianTransform"), cartesian)
    frame = [table.get(f"group.frame_{k}") for k in ("1", "2", "3", "rz")]
    assert frame == [4.0, 5.0, -650.0, -15.0]
    assert (table.get("group.acceleration"), table.get("group.jerk")) == (100.0, 2000.0)
    assert table.requested("group")[0] == GROUP_CONTROL_BITS.index("set_frame")

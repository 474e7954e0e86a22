"""A PLC over the bridge commands the delta picker in Cartesian coordinates: the group block's
``coord_system`` (MCS) makes move_linear a line of the tool point, the machine's kinematics set
by the bridge when it enables the group; the Modbus server in its own process, in lockstep."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import mcl
from mcl.geometry import distance_to_segment
from scenes.bridge.table import GROUP_CONTROL_BITS, GROUP_STATUS_BITS
from scenes.machines.delta_picker.axes import ARMS, DELTA
from tests.bridge_clients import ModbusLockstep, bits, modbus_server

TARGET = [200.0, -100.0, -750.0]
"""The tool point's target [mm, MCS]."""


def group_bits(*names: str) -> int:
    return sum(1 << GROUP_CONTROL_BITS.index(n) for n in names)


def group_status(plc: ModbusLockstep, name: str) -> bool:
    return bool(int(plc.read("group.status")) >> GROUP_STATUS_BITS.index(name) & 1)


def tool_point(plc: ModbusLockstep) -> list[float]:
    """The tool point of the arms' actual positions (their encoders) [mm, MCS]."""
    return DELTA.forward([plc.read(f"group.actual_{k}") for k in (1, 2, 3)])


def test_a_plc_over_modbus_moves_the_delta_pickers_tool_point_on_a_line(tmp_path: Path) -> None:
    with modbus_server("delta_picker", tmp_path / "stderr.txt", "--lockstep") as client:
        plc = ModbusLockstep("delta_picker", client)
        for arm in ARMS:
            plc.write(f"{arm}.control", bits("enable"))
        plc.until(lambda: all(plc.status(a, "power") for a in ARMS), 2.0, "power")
        for arm in ARMS:  # the arms home together: the closed chains move one arm with another
            plc.write(f"{arm}.control", bits("enable", "home"))
        plc.until(lambda: all(plc.status(a, "done") for a in ARMS), 30.0, "homing", 0.05)
        for arm in ARMS:
            plc.write(f"{arm}.control", bits("enable"))
        plc.write("group.control", group_bits("enable"))
        plc.until(lambda: group_status(plc, "enabled"), 1.0, "enable")
        start = tool_point(plc)
        plc.write_all(
            {
                "group.velocity": 1000.0,
                "group.acceleration": 10000.0,
                "group.deceleration": 10000.0,
                "group.jerk": 500000.0,
                "group.coord_system": int(mcl.MC_COORD_SYSTEM.MCS),
                **{f"group.end_{k + 1}": x for k, x in enumerate(TARGET)},
            }
        )
        plc.write("group.control", group_bits("enable", "move_linear"))
        samples = []

        def done() -> bool:
            samples.append(tool_point(plc))
            return group_status(plc, "done") or group_status(plc, "error")

        plc.until(done, 2.0, "the line")
        assert group_status(plc, "done"), plc.read("group.error_id")
        plc.run(0.1)
        end = tool_point(plc)
    deviation = max(distance_to_segment(p, start, TARGET) for p in samples)
    print(f"start {np.round(start, 2)}, off the line {deviation:.3f} mm, end {np.round(end, 3)}")
    assert np.linalg.norm(np.subtract(end, TARGET)) < 0.1
    assert deviation < 0.3  # the arms' joint-space interpolation would bow off it by millimetres

"""The bridge's PLC program driven through its signal table in-process: the gantry's X axis
powered, homed with its recipe and moved to 300 mm (checked on the joint), a target beyond the
software limit refused with its ErrorID, a write to a read-only register refused."""

from __future__ import annotations

import pytest

import mcl
import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable, WriteRefused, decode, encode
from scenes.scene import Scene

PARK = {"X": 0.2, "Y": 0.3, "Z": -0.1}
"""Start joint coordinates [m]."""


def bit(name: str) -> int:
    return 1 << CONTROL_BITS.index(name)


def status(table: SignalTable, axis: str, name: str) -> bool:
    return bool(int(table.get(f"{axis}.status")) >> STATUS_BITS.index(name) & 1)


@pytest.fixture
def rig() -> tuple[Scene, SignalTable, BridgeProgram]:
    scene = scenes.load("gantry", start=PARK, trace_every=0)
    table = SignalTable(scenes.definition("gantry"))
    return scene, table, BridgeProgram(scene, [table], scenes.homing(scene))


def command(table: SignalTable, axis: str, word: int) -> None:
    """Write a control word the way a client does: raw registers."""
    field = table.by_name[f"{axis}.control"]
    table.write(field.address, encode("u16", word))


def power_and_home(scene: Scene, table: SignalTable, program: BridgeProgram) -> None:
    command(table, "X", bit("enable"))
    scene.run(program, until=lambda: status(table, "X", "power"), timeout=1.0)
    command(table, "X", bit("enable") | bit("home"))
    scene.run(program, until=lambda: status(table, "X", "done"), timeout=60.0)
    assert status(table, "X", "homed")
    command(table, "X", bit("enable"))
    scene.run(program, timeout=0.01)


def test_power_home_and_move_to_300_mm(rig: tuple[Scene, SignalTable, BridgeProgram]) -> None:
    scene, table, program = rig
    power_and_home(scene, table, program)
    origin = scene.joint_position("X") - scene.axes["X"].POS / 1000.0
    for name, value in (("position", 300.0), ("velocity", 200.0), ("acceleration", 1000.0)):
        table.set(f"X.{name}", value)
    table.set("X.deceleration", 1000.0)
    command(table, "X", bit("enable") | bit("move_absolute"))
    scene.run(program, until=lambda: status(table, "X", "done"), timeout=10.0)
    assert scene.joint_position("X") - origin == pytest.approx(0.300, abs=20e-6)
    assert table.get("X.actual_position") == pytest.approx(300.0, abs=0.02)
    assert table.get("X.state") == mcl.AxisState.StandStill
    assert table.get("sim.cycle") > 0 and table.get("sim.time") == pytest.approx(scene.time, 0.01)


def test_target_beyond_software_limit_gives_its_error_id(
    rig: tuple[Scene, SignalTable, BridgeProgram],
) -> None:
    scene, table, program = rig
    power_and_home(scene, table, program)
    limit = scene.axes["X"].constants.LimPos  # type: ignore[union-attr]
    before = scene.joint_position("X")
    table.update([("X.position", limit + 10.0), ("X.velocity", 200.0)])
    table.update([("X.acceleration", 1000.0), ("X.deceleration", 1000.0)])
    command(table, "X", bit("enable") | bit("move_absolute"))
    scene.run(program, timeout=0.2)
    assert status(table, "X", "error")
    assert table.get("X.error_id") == 8  # Ecil: target beyond an active software limit
    assert scene.joint_position("X") == pytest.approx(before, abs=5e-6)


def test_client_writes_are_checked(rig: tuple[Scene, SignalTable, BridgeProgram]) -> None:
    _, table, _ = rig
    status_field = table.by_name["X.status"]
    with pytest.raises(WriteRefused):
        table.write(status_field.address, [1])
    with pytest.raises(WriteRefused):
        table.write(table.size + 10, [1])
    with pytest.raises(WriteRefused):
        table.read(table.size - 1, 2)
    assert decode("f32", encode("f32", 300.0)) == 300.0
    assert encode("f32", 1.0) == [0x3F80, 0x0000]  # high word first


def test_jog_velocity_and_stop(rig: tuple[Scene, SignalTable, BridgeProgram]) -> None:
    scene, table, program = rig
    table.update([("X.velocity", 50.0), ("X.acceleration", 1000.0), ("X.deceleration", 1000.0)])
    command(table, "X", bit("enable"))
    scene.run(program, until=lambda: status(table, "X", "power"), timeout=1.0)
    start = scene.joint_position("X")
    command(table, "X", bit("enable") | bit("jog_pos"))
    scene.run(program, timeout=0.5)
    command(table, "X", bit("enable"))
    scene.run(program, timeout=0.3)
    jogged = scene.joint_position("X")
    assert 0.015 < jogged - start < 0.03  # about 50 mm/s for 0.5 s
    table.set("X.velocity", -50.0)  # MC_MoveVelocity: the sign is the direction
    command(table, "X", bit("enable") | bit("move_velocity"))
    scene.run(program, timeout=0.5)
    assert scene.joint_position("X") < jogged - 0.015
    command(table, "X", bit("enable") | bit("stop"))
    scene.run(program, until=lambda: status(table, "X", "done"), timeout=1.0)
    assert table.get("X.command") == CONTROL_BITS.index("stop") + 1
    assert table.get("X.state") == mcl.AxisState.Stopping  # until Stop's Execute drops
    command(table, "X", bit("enable"))
    scene.run(program, timeout=0.05)
    assert table.get("X.state") == mcl.AxisState.StandStill
    assert abs(table.get("X.actual_velocity")) < 1.0

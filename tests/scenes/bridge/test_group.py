"""The bridge's group block driven through the gantry's signal table in-process, as a PLC writes
it: the axes powered by their own blocks, the group enabled, then a full circle
(move_circular) and a path of a line, an arc and a line (append_line, append_arc, move_path),
checked on the joints; a refused arc shows its ErrorID; a line at 50 % override, held,
continued and halted."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mcl
import scenes
from mcl.geometry import Line, arc
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import (
    CONTROL_BITS,
    GROUP_BASE,
    GROUP_CONTROL_BITS,
    GROUP_STATUS_BITS,
    SignalTable,
    encode,
)
from scenes.scene import Scene

START = {"X": 0.5, "Y": 0.3, "Z": -0.1}
"""Start joint coordinates [m]."""


def group_bit(*names: str) -> int:
    return sum(1 << GROUP_CONTROL_BITS.index(n) for n in names)


def group_status(table: SignalTable, name: str) -> bool:
    return bool(int(table.get("group.status")) >> GROUP_STATUS_BITS.index(name) & 1)


def write(table: SignalTable, name: str, value: float) -> None:
    """Write a field the way a client does: raw registers."""
    field = table.by_name[name]
    table.write(field.address, encode(field.kind, value))


@pytest.fixture
def rig() -> tuple[Scene, SignalTable, BridgeProgram]:
    """The gantry with its axes powered and its group enabled through the table."""
    scene = scenes.load("gantry", start=START, trace_every=0)
    table = SignalTable(scenes.definition("gantry"))
    program = BridgeProgram(scene, [table], scenes.homing(scene))
    assert table.by_name["group.control"].address == GROUP_BASE
    for axis in "XYZ":
        write(table, f"{axis}.control", 1 << CONTROL_BITS.index("enable"))
    write(table, "group.control", group_bit("enable"))
    scene.run(program, until=lambda: group_status(table, "enabled"), timeout=2.0)
    assert table.get("group.state") == mcl.GroupState.GroupStandby
    for name, value in (("velocity", 50.0), ("acceleration", 2000.0), ("deceleration", 2000.0)):
        write(table, f"group.{name}", value)
    write(table, "group.jerk", 20000.0)
    scene.run(program, timeout=0.2)  # settle
    return scene, table, program


def joints(scene: Scene) -> np.ndarray:
    """The joints X, Y, Z [mm]."""
    return np.array([scene.joint_position(a) for a in "XYZ"]) * 1000.0


def test_the_bridge_commands_an_arc(rig: tuple[Scene, SignalTable, BridgeProgram]) -> None:
    """A full circle of R = 30 mm (CENTER, relative, counter-clockwise): done, the joints on the
    circle within 10 µm, Z still; then collinear BORDER points give Error with EParam."""
    scene, table, program = rig
    start = joints(scene)
    samples: list[np.ndarray] = []
    scene.runtime.observers.append(lambda t: samples.append(joints(scene)))
    for name, value in (
        ("circ_mode", mcl.MC_CIRC_MODE.CENTER),
        ("path_choice", mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE),
        ("relative", 1),
        ("aux_1", 30.0),
    ):
        write(table, f"group.{name}", value)
    count = table.get("group.command_count")
    write(table, "group.control", group_bit("enable", "move_circular"))
    scene.run(program, until=lambda: group_status(table, "done"), timeout=10.0)
    assert table.get("group.command_count") == count + 1
    assert table.get("group.command") == GROUP_CONTROL_BITS.index("move_circular") + 1
    points = np.array(samples) - start
    radius = np.linalg.norm(points[:, :2] - np.array([30.0, 0.0]), axis=1)
    assert np.abs(radius - 30.0).max() < 0.010
    assert np.abs(points[:, 2]).max() < 0.010
    assert np.linalg.norm(points[-1]) < 0.005
    angles = np.unwrap(np.arctan2(points[:, 1], points[:, 0] - 30.0))
    assert angles[-1] - angles[0] == pytest.approx(2 * math.pi, abs=1e-2)

    write(table, "group.control", group_bit("enable"))  # acknowledge
    scene.run(program, timeout=0.01)
    assert not group_status(table, "done")
    write(table, "group.circ_mode", mcl.MC_CIRC_MODE.BORDER)
    write(table, "group.aux_1", 10.0)
    write(table, "group.end_1", 20.0)
    write(table, "group.control", group_bit("enable", "move_circular"))
    scene.run(program, timeout=0.01)
    assert group_status(table, "error") and table.get("group.error_id") == mcl.ErrorID.EParam


def test_the_bridge_commands_a_path(rig: tuple[Scene, SignalTable, BridgeProgram]) -> None:
    """Three segments appended (a line, a tangent half circle by its radius, a line back),
    then move_path: the joints follow the path within 20 µm and end at its end."""
    scene, table, program = rig
    start = joints(scene)
    write(table, "group.relative", 1)
    write(table, "group.buffer_mode", mcl.MC_BufferMode.BlendingLow)
    segments = (
        ("append_line", dict(end_1=40.0, end_2=0.0)),
        ("append_arc", dict(end_1=0.0, end_2=20.0, aux_1=10.0, circ_mode=2, path_choice=1)),
        ("append_line", dict(end_1=-40.0, end_2=0.0)),
    )
    for bit, fields in segments:
        for name, value in fields.items():
            write(table, f"group.{name}", value)
        write(table, "group.control", group_bit("enable", bit))
        scene.run(program, until=lambda: group_status(table, "done"), timeout=0.1)
        write(table, "group.control", group_bit("enable"))
        scene.run(program, until=lambda: not group_status(table, "done"), timeout=0.1)
    assert table.get("group.segments") == 3
    samples: list[np.ndarray] = []
    scene.runtime.observers.append(lambda t: samples.append(joints(scene)))
    write(table, "group.control", group_bit("enable", "move_path"))
    scene.run(program, until=lambda: group_status(table, "done"), timeout=10.0)
    points = np.array(samples) - start
    pieces = [
        Line([0.0, 0.0], [40.0, 0.0]),
        arc([40.0, 0.0], mcl.MC_CIRC_MODE.RADIUS, [10.0, 0.0], [40.0, 20.0], 1),
        Line([40.0, 20.0], [0.0, 20.0]),
    ]
    contour = max(min(g.distance(p[:2]) for g in pieces) for p in points)
    assert contour < 0.020
    assert points[-1][:2] == pytest.approx([0.0, 20.0], abs=0.005)


def command(
    scene: Scene, table: SignalTable, program: BridgeProgram, bit: str, seconds: float
) -> None:
    """Raise command ``bit`` (the group still enabled), run ``seconds``, lower it again."""
    write(table, "group.control", group_bit("enable", bit))
    scene.run(program, timeout=seconds)
    write(table, "group.control", group_bit("enable"))


def speed(scene: Scene, program: BridgeProgram) -> float:
    """The joints' speed over the next 0.1 s [mm/s]."""
    before = joints(scene)
    scene.run(program, timeout=0.1)
    return float(np.linalg.norm(joints(scene) - before)) / 0.1


def test_the_bridge_holds_overrides_and_halts_the_group(
    rig: tuple[Scene, SignalTable, BridgeProgram],
) -> None:
    """set_override 50 %: a line at 50 mm/s runs at 25 mm/s (done while the bit is set);
    interrupt holds it on the way (the line's block still busy) and continue ends it at its
    end; back at 100 %, halt stops the next line on the way, in GroupStandby; an override of
    3.0 is refused with EParam."""
    scene, table, program = rig
    start = joints(scene)
    for name, value in (("vel_factor", 0.5), ("acc_factor", 1.0), ("jerk_factor", 1.0)):
        write(table, f"group.{name}", value)
    write(table, "group.control", group_bit("enable", "set_override"))
    scene.run(program, timeout=0.01)
    assert group_status(table, "done")
    write(table, "group.control", group_bit("enable"))
    write(table, "group.relative", 1)
    write(table, "group.end_1", -40.0)
    command(scene, table, program, "move_linear", 0.6)
    assert speed(scene, program) == pytest.approx(25.0, abs=0.5)
    command(scene, table, program, "interrupt", 0.3)
    assert speed(scene, program) < 0.01
    held = joints(scene) - start
    assert -39.0 < held[0] < -1.0
    assert table.get("group.state") == mcl.GroupState.GroupStandby
    command(scene, table, program, "continue", 0.3)
    assert speed(scene, program) == pytest.approx(25.0, abs=0.5)
    scene.run(program, timeout=2.0)
    assert joints(scene) - start == pytest.approx([-40.0, 0.0, 0.0], abs=0.005)

    write(table, "group.vel_factor", 1.0)
    command(scene, table, program, "set_override", 0.01)
    write(table, "group.end_1", 40.0)
    command(scene, table, program, "move_linear", 0.6)
    assert speed(scene, program) == pytest.approx(50.0, abs=0.5)
    write(table, "group.control", group_bit("enable", "halt"))
    scene.run(program, timeout=0.3)
    assert group_status(table, "done")
    assert table.get("group.state") == mcl.GroupState.GroupStandby
    assert -39.0 < (joints(scene) - start)[0] < -1.0

    write(table, "group.control", group_bit("enable"))
    write(table, "group.vel_factor", 3.0)
    write(table, "group.control", group_bit("enable", "set_override"))
    scene.run(program, timeout=0.01)
    assert group_status(table, "error") and table.get("group.error_id") == mcl.ErrorID.EParam


def test_the_bridge_sets_the_acceleration_factor(
    rig: tuple[Scene, SignalTable, BridgeProgram],
) -> None:
    """acc_factor 0.25 (register 46) with vel_factor 1.0: the path's acceleration stays within
    a quarter, so a 50 mm/s line runs at √0.25 of it, 25 mm/s, and ends at its end; acc_factor
    0 and jerk_factor 0 are refused with EParam."""
    scene, table, program = rig
    start = joints(scene)
    for name, value in (("vel_factor", 1.0), ("acc_factor", 0.25), ("jerk_factor", 1.0)):
        write(table, f"group.{name}", value)
    command(scene, table, program, "set_override", 0.01)
    write(table, "group.relative", 1)
    write(table, "group.end_1", -40.0)
    command(scene, table, program, "move_linear", 0.6)
    assert speed(scene, program) == pytest.approx(25.0, abs=0.5)
    scene.run(program, timeout=1.6)
    assert joints(scene) - start == pytest.approx([-40.0, 0.0, 0.0], abs=0.005)
    for name in ("acc_factor", "jerk_factor"):
        write(table, f"group.{name}", 0.0)
        write(table, "group.control", group_bit("enable", "set_override"))
        scene.run(program, timeout=0.01)
        assert group_status(table, "error") and table.get("group.error_id") == mcl.ErrorID.EParam
        write(table, "group.control", group_bit("enable"))
        write(table, f"group.{name}", 1.0)

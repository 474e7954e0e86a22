"""Conveyor tracking over the bridge, in-process through the delta picker's signal table as a
PLC writes it: the arms and the belt powered by their blocks, the group enabled (the bridge sets
its kinematics), the arms homed, the belt running; track_belt makes the product coordinate
system move with a part, a move in PCS (coord_system 2) lands on it and the cup follows it (on
the physics); set_frame ends the tracking and the cup stands. A belt number that names no belt
is refused with EParam."""

from __future__ import annotations

import numpy as np
import pytest

import mcl
import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import (
    CONTROL_BITS,
    GROUP_CONTROL_BITS,
    GROUP_STATUS_BITS,
    STATUS_BITS,
    SignalTable,
)
from scenes.machines.delta_picker.axes import ARMS
from scenes.scene import Scene
from tests.scenes.bridge.test_group import write

BELT_SPEED = 200.0
"""[mm/s]"""
ORIGIN = (-250.0, -150.0, -760.0)
"""The belt frame's origin [mm, MCS]: on the belt's centre line, over it."""


def group_bit(*names: str) -> int:
    return sum(1 << GROUP_CONTROL_BITS.index(n) for n in names)


def group_status(table: SignalTable, name: str) -> bool:
    return bool(int(table.get("group.status")) >> GROUP_STATUS_BITS.index(name) & 1)


@pytest.fixture
def rig() -> tuple[Scene, SignalTable, BridgeProgram]:
    """The delta picker, its arms and belt powered, the group enabled, the belt running."""
    scene = scenes.load("delta_picker", trace_every=0)
    table = SignalTable(scenes.definition("delta_picker"))
    program = BridgeProgram(scene, [table], scenes.homing(scene))
    enable, home = 1 << CONTROL_BITS.index("enable"), 1 << CONTROL_BITS.index("home")
    for axis in (*ARMS, "C"):
        write(table, f"{axis}.control", enable)
    scene.run(program, timeout=0.05)
    for arm in ARMS:  # the arms home together: the closed chains move one arm with another
        write(table, f"{arm}.control", enable | home)
    done = 1 << STATUS_BITS.index("done")
    homed = lambda: all(int(table.get(f"{a}.status")) & done for a in ARMS)  # noqa: E731
    scene.run(program, until=homed, timeout=30.0)
    for arm in ARMS:
        write(table, f"{arm}.control", enable)
    write(table, "group.control", group_bit("enable"))
    scene.run(program, until=lambda: group_status(table, "enabled"), timeout=2.0)
    scene.run(program, timeout=0.1)  # the kinematics set after the enable
    write(table, "C.velocity", BELT_SPEED)
    write(table, "C.acceleration", 2000.0)
    running = (1 << CONTROL_BITS.index("enable")) | (1 << CONTROL_BITS.index("move_velocity"))
    write(table, "C.control", running)
    scene.run(program, timeout=0.3)
    return scene, table, program


def cup(scene: Scene) -> np.ndarray:
    """The cup's face on the physics [mm, world]."""
    return 1000.0 * scene.data.site_xpos[scene.model.site("delta_picker/tool").id].copy()


def command(scene: Scene, table: SignalTable, program: BridgeProgram, name: str) -> None:
    """Raise the group command's bit until it is done or refused (at most 2 s)."""
    write(table, "group.control", group_bit("enable", name))
    scene.run(
        program,
        until=lambda: group_status(table, "done") or group_status(table, "error"),
        timeout=2.0,
    )


def test_the_bridge_tracks_a_part_on_the_belt(
    rig: tuple[Scene, SignalTable, BridgeProgram],
) -> None:
    scene, table, program = rig
    for k, x in enumerate(ORIGIN):
        write(table, f"group.frame_{k + 1}", x)
    write(table, "group.belt", table.axes.index("C"))
    write(table, "group.latched_position", table.get("C.actual_position"))
    write(table, "group.horizon", 0.3)
    command(scene, table, program, "track_belt")
    assert group_status(table, "done"), table.get("group.error_id")
    # a move in PCS onto the part, 20 mm above the belt frame's origin as it moves
    write(table, "group.control", group_bit("enable"))
    for name, value in (("velocity", 1000.0), ("acceleration", 10000.0), ("jerk", 5.0e5)):
        write(table, f"group.{name}", value)
    write(table, "group.deceleration", 10000.0)
    for k, x in enumerate((0.0, 0.0, 20.0)):
        write(table, f"group.end_{k + 1}", x)
    write(table, "group.coord_system", int(mcl.MC_COORD_SYSTEM.PCS))
    scene.run(program, timeout=0.01)
    command(scene, table, program, "move_linear")
    assert group_status(table, "done"), table.get("group.error_id")
    scene.run(program, timeout=0.1)
    before = cup(scene)
    scene.run(program, timeout=0.2)
    travel = cup(scene) - before
    assert travel[0] == pytest.approx(BELT_SPEED * 0.2, abs=0.5)  # it follows the part
    assert abs(travel[1]) < 0.2 and abs(travel[2]) < 0.2
    # set_frame of zeros: the MCS again, the cup slows down to a standstill
    write(table, "group.control", group_bit("enable"))
    for name in ("frame_1", "frame_2", "frame_3", "frame_rz"):
        write(table, f"group.{name}", 0.0)
    scene.run(program, timeout=0.01)
    command(scene, table, program, "set_frame")
    assert group_status(table, "done"), table.get("group.error_id")
    scene.run(program, timeout=0.2)
    stood = cup(scene)
    scene.run(program, timeout=0.2)
    assert np.linalg.norm(cup(scene) - stood) < 0.05


def test_a_belt_number_of_no_belt_is_refused(rig: tuple[Scene, SignalTable, BridgeProgram]) -> None:
    scene, table, program = rig
    for k, x in enumerate(ORIGIN):
        write(table, f"group.frame_{k + 1}", x)
    for belt in (table.axes.index(ARMS[0]), 99):  # an arm of the group, no axis
        write(table, "group.belt", belt)
        command(scene, table, program, "track_belt")
        assert group_status(table, "error")
        assert table.get("group.error_id") == mcl.ErrorID.EParam
        write(table, "group.control", group_bit("enable"))
        scene.run(program, timeout=0.01)

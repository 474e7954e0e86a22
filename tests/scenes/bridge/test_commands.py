"""The bridge's commands beyond single moves, through the signal table in-process: a command
requested as a method call does (Done stays visible, a repeat starts again; a requested stop
ends when the next command comes, which is taken), a pulse shorter
than a scan, MoveAdditive buffered behind a move, commands the axis cannot take, the PLC out of
control, a cell's one table per machine; measured on the joints."""

from __future__ import annotations

import pytest

import mcl
import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import CONTROL_BITS, NotInControl, WriteRefused, encode, tables_of
from tests.bridge_clients import InProcess, bits

MOVE = {"X.velocity": 200.0, "X.acceleration": 2000.0, "X.deceleration": 2000.0}


@pytest.fixture
def gantry() -> InProcess:
    plc = InProcess("gantry")
    plc.power_and_home(("X",), "X")
    plc.write_all(MOVE)
    return plc


def test_a_requested_command_keeps_its_done_and_a_repeat_starts_again(gantry: InProcess) -> None:
    table, plc = gantry.table, gantry
    start = plc.scene.joint_position("X")
    table.request("X", "move_relative", {"distance": 50.0})
    plc.until(lambda: plc.status("X", "done"), 5.0, "first move")
    plc.run(0.5)
    assert plc.status("X", "done")  # held: a subscriber sees it whenever it looks
    assert plc.scene.joint_position("X") - start == pytest.approx(0.050, abs=20e-6)
    table.request("X", "move_relative", {"distance": 50.0})  # the same again: a new edge
    plc.run(0.02)
    assert plc.status("X", "busy")
    plc.until(lambda: plc.status("X", "done"), 5.0, "second move")
    assert plc.scene.joint_position("X") - start == pytest.approx(0.100, abs=20e-6)
    with pytest.raises(WriteRefused):
        table.request("X", "enable")  # a level, not a command
    with pytest.raises(WriteRefused):
        table.request("X", "move_relative", {"status": 1.0})  # not a parameter


def test_a_requested_stop_ends_when_the_next_command_comes(gantry: InProcess) -> None:
    table, plc = gantry.table, gantry

    def stop_a_velocity_move() -> float:
        """A requested MC_MoveVelocity stopped by a requested MC_Stop: Done, and the axis held in
        Stopping (its Execute stays set); where X stands [m]."""
        table.request("X", "move_velocity", {"velocity": 50.0})
        plc.run(0.3)
        assert plc.status("X", "in_velocity")
        table.request("X", "stop")
        plc.until(lambda: plc.status("X", "done"), 2.0, "the stop")
        plc.run(0.1)
        assert plc.read("X.state") == mcl.AxisState.Stopping  # until Done AND NOT Execute
        return plc.scene.joint_position("X")

    start = stop_a_velocity_move()
    table.request("X", "move_relative", {"distance": 20.0, "velocity": 200.0})
    plc.until(lambda: plc.status("X", "done"), 5.0, "the requested move")
    assert plc.read("X.error_id") == 0  # taken: no EAxStop
    assert plc.scene.joint_position("X") - start == pytest.approx(0.020, abs=20e-6)
    start = stop_a_velocity_move()
    plc.write_all({"X.distance": 30.0, "X.velocity": 200.0})
    plc.write("X.control", bits("enable", "move_relative"))
    plc.until(lambda: plc.status("X", "done"), 5.0, "the move of the control word")
    assert plc.read("X.error_id") == 0
    assert plc.scene.joint_position("X") - start == pytest.approx(0.030, abs=20e-6)
    assert table.get("X.command") == 1 + CONTROL_BITS.index("move_relative")


def test_a_pulse_shorter_than_a_scan_starts_the_command(gantry: InProcess) -> None:
    plc, table = gantry, gantry.table
    start = plc.scene.joint_position("X")
    plc.write("X.distance", 20.0)
    plc.write("X.control", bits("enable", "move_relative"))  # set and cleared before a scan
    plc.write("X.control", bits("enable"))
    plc.run(0.02)
    assert plc.read("X.state") == mcl.AxisState.DiscreteMotion
    plc.until(lambda: plc.read("X.state") == mcl.AxisState.StandStill, 5.0, "the move ends")
    assert plc.scene.joint_position("X") - start == pytest.approx(0.020, abs=20e-6)
    assert table.get("X.command") == 1 + CONTROL_BITS.index("move_relative")


def test_move_additive_buffered_behind_a_move(gantry: InProcess) -> None:
    plc = gantry
    start = plc.read("X.actual_position")
    plc.write_all({"X.position": start + 100.0, "X.distance": 30.0})
    plc.write("X.control", bits("enable", "move_absolute"))
    plc.run(0.05)
    plc.write("X.buffer_mode", int(mcl.MC_BufferMode.Buffered))
    plc.write("X.control", bits("enable", "move_absolute", "move_additive"))
    plc.until(lambda: plc.status("X", "done"), 5.0, "the additive move")
    assert plc.read("X.actual_position") == pytest.approx(start + 130.0, abs=0.02)


def test_commands_the_axis_cannot_take_are_refused_with_eparam() -> None:
    plc = InProcess("gantry")
    plc.write("X.control", bits("enable"))
    plc.until(lambda: plc.status("X", "power"), 2.0, "power")
    plc.write("X.master", 0)  # the slave itself as master
    plc.write_all({"X.ratio_numerator": 1, "X.ratio_denominator": 1})
    plc.write("X.control", bits("enable", "gear_in"))
    plc.run(0.02)
    assert plc.status("X", "error") and plc.read("X.error_id") == mcl.ErrorID.EParam
    press = InProcess("press")  # one axis: no gearing
    assert "R.master" not in press.table.by_name
    press.write("R.control", bits("enable", "gear_in"))
    press.run(0.02)
    assert press.status("R", "error") and press.read("R.error_id") == mcl.ErrorID.EParam


def test_the_plc_out_of_control_is_refused_and_leaves_the_axes_alone(gantry: InProcess) -> None:
    plc, table = gantry, gantry.table
    plc.write("X.distance", 100.0)
    plc.write("X.control", bits("enable", "move_relative"))
    plc.run(0.1)
    table.in_control = False  # an operator of the viewer takes control
    with pytest.raises(NotInControl):
        plc.write("X.control", bits("enable", "stop"))
    with pytest.raises(NotInControl):
        table.request("X", "stop")
    assert table.get("sim.control") == 0
    plc.until(lambda: plc.read("X.state") == mcl.AxisState.StandStill, 5.0, "the move ends")
    assert plc.status("X", "power")  # its blocks are not called: nothing powered off
    table.in_control = True
    plc.write("X.control", bits("enable"))
    plc.run(0.05)
    assert plc.status("X", "power")


def test_a_cell_has_one_table_per_machine() -> None:
    definition = scenes.definition("cell")
    tables = tables_of(definition)
    assert [t.unit_id for t in tables] == list(range(1, len(definition.parts) + 1))
    scene = scenes.load("cell", trace_every=0)
    assert sorted(a for t in tables for a in t.axes) == sorted(scene.axes)
    program = BridgeProgram(scene, tables, scenes.homing(scene))
    for t in tables:  # every part's axes at 100 + 100·i of its own table
        assert t.by_name[f"{t.axes[0]}.control"].address == 100
    tables[-1].write(tables[-1].by_name["sim.target"].address, encode("u32", 7))
    assert program.target == 7  # the largest target any table was given
    scene.run(program, timeout=0.05)
    assert all(t.get("sim.cycle") == program.cycles for t in tables)

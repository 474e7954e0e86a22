"""What an integrator following docs/bridge.md meets, in-process on the machines' tables: a move
the blocks refuse says why in the log and the map gives the velocities an axis takes; a refused
power-on shows MC_Power's Error; the cell's interlock signals are in every part's table (and its
OPC UA tree); an axis without a homing recipe is homed with MC_StepDirect (the home_direct bit)
and then moves to an absolute position, measured on the joint."""

from __future__ import annotations

import logging

import pytest

import mcl
import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import tables_of
from scenes.tools import cli
from tests.bridge_clients import InProcess, bits


def test_a_velocity_below_1_percent_of_vmax_is_refused_with_its_reason(
    caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    plc = InProcess("flying_shear")
    plc.write("S.control", bits("enable"))
    plc.until(lambda: plc.status("S", "power"), 2.0, "power")
    start = plc.scene.joint_position("S")
    plc.write_all({"S.velocity": 20.0, "S.acceleration": 1000.0, "S.deceleration": 1000.0})
    with caplog.at_level(logging.WARNING, "scenes.bridge.program"):
        plc.write("S.control", bits("enable", "move_velocity"))
        plc.run(0.1)
        assert plc.status("S", "error") and plc.read("S.error_id") == mcl.ErrorID.EParam
        plc.write("S.control", bits("enable", "jog_pos"))
        plc.run(0.1)
        assert plc.read("S.error_id") == mcl.ErrorID.EParam
    reasons = [r.getMessage() for r in caplog.records]
    assert reasons == [
        "S: Move velocity: error 5 (invalid command parameter: Velocity 20 mm/s below 1 % of "
        "Vmax (40 mm/s))",
        "S: Jog+: error 5 (invalid command parameter: Velocity 20 mm/s below 1 % of Vmax "
        "(40 mm/s))",
    ]
    assert plc.scene.joint_position("S") == pytest.approx(start, abs=1e-5)  # left alone
    plc.write("S.velocity", 50.0)  # 1 % of Vmax is 40 mm/s
    plc.write("S.control", bits("enable", "move_velocity"))
    plc.until(lambda: plc.status("S", "in_velocity"), 2.0, "the velocity")
    assert cli.main(["bridge", "map", "flying_shear"]) == 0
    assert "| 40 … 4000 mm/s (below 1 % of Vmax: ErrorID 5;" in capsys.readouterr().out


def test_a_refused_power_on_shows_mc_powers_error(caplog: pytest.LogCaptureFixture) -> None:
    plc = InProcess("flying_shear")
    with caplog.at_level(logging.WARNING, "scenes.bridge.program"):
        plc.write("W.control", bits("enable"))  # W: an encoder, no drive
        plc.run(0.1)
    text = f"W: Power: error 14 ({mcl.error_text(14)})"
    assert [r.getMessage() for r in caplog.records] == [text]  # once, though Enable stays set
    assert plc.read("W.state") == mcl.AxisState.Disabled
    assert plc.status("W", "error") and not plc.status("W", "power")
    assert plc.read("W.error_id") == mcl.ErrorID.ENoDrive
    plc.write("W.control", 0)  # Enable falls: MC_Power's Error with it
    plc.run(0.1)
    assert not plc.status("W", "error") and plc.read("W.error_id") == 0


def test_the_cells_interlock_signals_are_in_every_parts_table() -> None:
    cell = scenes.definition("cell")
    tables = tables_of(cell)
    scene = scenes.load("cell", trace_every=0)
    BridgeProgram(scene, tables, scenes.homing(scene))  # publishes once
    for table in tables:
        for name in ("gantry_in_zone", "ram_up"):
            field = table.by_name[f"signal.{name}"]
            assert field.access == "r" and field.address >= 1000
            assert table.get(field.name) == scene.signal(name)
    assert tables[1].get("signal.ram_up") == 1.0  # the press stands with its ram up


def test_an_axis_without_a_recipe_is_homed_directly_and_moves_absolutely() -> None:
    plc = InProcess("single_axis")
    plc.write("X.control", bits("enable"))
    plc.until(lambda: plc.status("X", "power"), 2.0, "power")
    plc.write("X.control", bits("enable", "home"))
    plc.run(0.05)
    assert plc.read("X.error_id") == mcl.ErrorID.EParam  # no recipe
    start = plc.scene.joint_position("X")
    plc.write("X.position", 12.5)
    plc.write("X.control", bits("enable", "home_direct"))
    plc.until(lambda: plc.status("X", "done"), 1.0, "home direct")
    assert plc.status("X", "homed") and plc.read("X.actual_position") == pytest.approx(12.5)
    plc.write("X.control", bits("enable"))
    plc.write_all({"X.position": 50.0, "X.velocity": 50.0})
    plc.write("X.control", bits("enable", "move_absolute"))
    plc.until(lambda: plc.status("X", "done"), 5.0, "the absolute move")
    assert plc.read("X.error_id") == 0
    assert plc.scene.joint_position("X") - start == pytest.approx(0.0375, abs=20e-6)

"""The signal table as a user of the register map sees it: fixed addresses, the map printed by
the command line, published signals read from the running machine, refused values, a Modbus
server that will not bind beyond loopback."""

from __future__ import annotations

import math

import pytest

import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable, encode
from scenes.tools import cli


def test_map_of_the_gantry(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["bridge", "map", "gantry", "--csv"]) == 0
    rows = capsys.readouterr().out.strip().splitlines()
    table = SignalTable(scenes.definition("gantry"))
    assert len(rows) == 1 + len(table.fields)
    assert any(r.startswith("100,X.control,u16,rw") for r in rows)
    assert any(r.startswith("324,Z.actual_position,f32,r") for r in rows)
    assert cli.main(["bridge", "map", "gantry"]) == 0
    assert "| 124 | X.actual_position | f32 | r |" in capsys.readouterr().out


@pytest.mark.parametrize("machine", ["press", "cell"])
def test_published_signals_are_in_the_table(machine: str) -> None:
    scene = scenes.load(machine, trace_every=0)
    table = SignalTable(scenes.definition(machine))
    assert sorted(table.signals) == sorted(scene.signals)  # a cell's parts' too: press/force
    program = BridgeProgram(scene, [table], scenes.homing(scene))
    scene.run(program, timeout=0.1)
    program()  # one more scan at this instant: the table holds the values of now
    for name in table.signals:
        assert table.get(f"signal.{name}") == pytest.approx(scene.signal(name), rel=1e-6, abs=1e-6)


def test_a_nan_velocity_is_refused_by_the_block() -> None:
    scene = scenes.load("gantry", start={"X": 0.2}, trace_every=0)
    table = SignalTable(scenes.definition("gantry"))
    program = BridgeProgram(scene, [table], scenes.homing(scene))
    table.write(table.by_name["X.control"].address, [1])
    scene.run(program, timeout=0.2)
    before = scene.joint_position("X")
    table.write(table.by_name["X.velocity"].address, encode("f32", math.nan))
    table.set("X.distance", 50.0)
    word = 1 | 1 << CONTROL_BITS.index("move_relative")
    table.write(table.by_name["X.control"].address, [word])
    scene.run(program, timeout=0.5)
    assert int(table.get("X.status")) >> STATUS_BITS.index("error") & 1
    assert table.get("X.error_id") != 0
    assert scene.joint_position("X") == pytest.approx(before, abs=5e-6)


def test_modbus_refuses_to_bind_beyond_loopback(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["bridge", "modbus", "gantry", "--host", "0.0.0.0"]) == 2
    assert "loopback" in capsys.readouterr().err  # one line on standard error


def test_modbus_beyond_loopback_needs_ip_addresses_to_allow(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert cli.main(["bridge", "modbus", "gantry", "--host", "0.0.0.0", "--allow", "plc"]) == 2
    assert "--allow takes IP addresses" in capsys.readouterr().err

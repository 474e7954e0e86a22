"""docs/bridge.md as an integrator follows it: the OpenPLC and CODESYS settings it gives work on
every axis of every machine (the server in its own process, in lockstep: the blocks written and
read, the PLC commands the drive), its table of an axis' block is the one the server serves, and
the map names travel limits, homing, ErrorIDs and the unit ids refused."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import mcl
import scenes
from scenes.bridge.table import (
    AXIS_FIELDS,
    AXIS_STRIDE,
    FORCE_FIELDS,
    GEAR_FIELDS,
    OUTPUTS,
    STATUS_BITS,
    WriteRefused,
    tables_of,
)
from scenes.tools import cli
from tests.bridge_clients import bits, modbus_server
from tests.helpers import ROOT

DOCS = (ROOT / "docs" / "bridge.md").read_text()


def openplc() -> dict[str, int]:
    """The OpenPLC slave device the docs give (its mbconfig.cfg lines)."""
    lines = re.findall(r'device0\.(Holding_Registers\w*) = "(\d+)"', DOCS)
    return {name: int(value) for name, value in lines}


def codesys() -> dict[str, tuple[int, ...]]:
    """The CODESYS Modbus slave channels the docs give: the numbers of each (offset and length;
    read offset and length, write offset and length)."""
    channels = {}
    for row in re.findall(r"^\| (?:status|command|lockstep) \|.*$", DOCS, re.M):
        cells = [c.strip() for c in row.strip("|").split("|")]
        channels[cells[0]] = tuple(int(n) for n in re.findall(r"\d+", f"{cells[2]} {cells[3]}"))
    return channels


def test_the_docs_give_the_same_blocks_to_both_plcs() -> None:
    config = openplc()
    read = (config["Holding_Registers_Read_Start"], config["Holding_Registers_Read_Size"])
    write = (config["Holding_Registers_Start"], config["Holding_Registers_Size"])
    channels = codesys()
    assert channels["status"] == read
    assert channels["command"] == write
    assert channels["lockstep"] == (*read, 6, 2)  # read the status, write sim.target


@pytest.mark.once  # see the marker in pyproject.toml
@pytest.mark.parametrize("machine", sorted(scenes.MACHINES))
def test_the_docs_settings_command_every_axis(machine: str, tmp_path: Path) -> None:
    """The docs' blocks, moved to each axis' base (100 · i further), written and read as the
    PLCs poll them: every write accepted, the status block read, the drive powered by the
    control word of the write block."""
    config = openplc()
    read_start, read_size = (
        config["Holding_Registers_Read_Start"],
        config["Holding_Registers_Read_Size"],
    )
    write_start, write_size = config["Holding_Registers_Start"], config["Holding_Registers_Size"]
    status = STATUS_BITS.index("power")
    with modbus_server(machine, tmp_path / "stderr.txt", "--lockstep") as client:
        target = 0
        for table in tables_of(scenes.definition(machine)):
            unit = table.unit_id
            axes = scenes.definition(machine).scene_axes
            drives = {a: axes[a].drive != "encoder" for a in table.axes}
            for i, axis in enumerate(table.axes):
                shift = AXIS_STRIDE * i
                block = [bits("enable")] + [0] * (write_size - 1)
                reply = client.write_registers(write_start + shift, block, device_id=unit)
                assert not reply.isError(), f"{axis}: {reply}"
                target += 50
                reply = client.readwrite_registers(
                    read_address=read_start + shift,
                    read_count=read_size,
                    write_address=6,
                    values=[target >> 16, target & 0xFFFF],
                    device_id=unit,
                )  # the lockstep channel: 50 PLC cycles, then the status block
                assert not reply.isError(), f"{axis}: {reply}"
                word = reply.registers[table.by_name[f"{axis}.status"].address - read_start - shift]
                assert bool(word >> status & 1) == drives[axis], f"{axis}: power"
                reply = client.read_holding_registers(
                    read_start + shift, count=read_size, device_id=unit
                )
                assert not reply.isError(), f"{axis}: {reply}"
                block[0] = 0
                assert not client.write_registers(
                    write_start + shift, block, device_id=unit
                ).isError()


def rows_of_the_axis_table() -> dict[str, int]:
    """The docs' table of an axis' block: field name → offset."""
    section = DOCS[DOCS.index("| offset | field | type | access |") :]
    section = section[: section.index("\n\n")]
    offsets: dict[str, int] = {}
    for row in section.splitlines()[2:]:
        cells = [c.strip() for c in row.strip("|").split("|")]
        names = re.findall(r"`(\w+)`", cells[1])
        if cells[0].startswith("40 + 2"):
            continue  # analog_k: one per input
        if "…" in cells[0]:
            first, last = (int(n) for n in cells[0].split("…"))
            numbers = list(range(first, last + 1, (last - first) // (len(names) - 1)))
        else:
            numbers = [int(n) for n in re.findall(r"\d+", cells[0])]
        assert len(numbers) == len(names), row
        offsets.update(zip(names, numbers, strict=True))
    return offsets


def test_the_docs_table_of_an_axis_block_is_the_served_one() -> None:
    served = {f.name: f.offset for f in (*AXIS_FIELDS, *GEAR_FIELDS, *FORCE_FIELDS, OUTPUTS)}
    assert rows_of_the_axis_table() == served


def test_the_map_tells_an_integrator_limits_homing_error_ids_and_unit_ids(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert cli.main(["bridge", "map", "gantry"]) == 0
    text = capsys.readouterr().out
    assert "| X | 100 … 167 | mm | −2 … 1002 mm (software limits) | LIM−, LIM+, REF |" in text
    assert "X = 120 mm at the index pulse" in text  # where homing sets the reference
    assert "also 0 and 255" in text and "GATEWAY_PATH_UNAVAILABLE" in text
    for error in mcl.ErrorID:
        assert f"| {int(error)} | {error.name} | {mcl.error_text(error)} |" in text
    assert cli.main(["bridge", "map", "press"]) == 0
    text = capsys.readouterr().out
    assert "to the mechanical block (negative), backs off: R = 0.05 mm there" in text
    assert cli.main(["bridge", "map", "rotary_cutter"]) == 0
    assert "| D | 300 … 367 | deg |" in capsys.readouterr().out  # a hinge: degrees


def test_the_docs_group_blocks_fit_the_served_group_block() -> None:
    table = tables_of(scenes.definition("gantry"))[0]
    rows = re.findall(r"^\| group \((?:commands|overrides, frames)\) \|(.*)$", DOCS, re.M)
    assert len(rows) == 2  # one OpenPLC device entry each
    blocks = [[int(n) for n in re.findall(r"(\d+), size (\d+)", row)[-1]] for row in rows]
    read_start, read_size = (int(n) for n in re.findall(r"(\d+), size (\d+)", rows[0])[0])
    table.read(read_start, read_size)  # every register of the read block is served
    writable = set()
    for start, size in blocks:
        table.write(start, [0] * size)  # taken whole
        writable |= set(range(start, start + size))
        with pytest.raises(WriteRefused):  # a register more runs into the read-only status
            table.write(start - 1 if start > 900 else start, [0] * (size + 1))
    group = {
        a
        for f in table.fields
        if f.name.startswith("group.")
        for a in range(f.address, f.address + f.width)
    }
    rw = {
        a
        for f in table.fields
        if f.name.startswith("group.") and f.access == "rw"
        for a in range(f.address, f.address + f.width)
    }
    assert rw <= writable and not writable & (group - rw)
    assert "one device entry per axis" in " ".join(DOCS.split())


def test_the_maps_name_the_units_served_and_the_state_numbers(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert cli.main(["bridge", "map", "cell"]) == 0
    text = capsys.readouterr().out
    assert "Unit id 2 serves the cell's other part; any other is refused" in text
    assert "Unit id 1 serves the cell's other part; any other is refused" in text
    assert "PLCopen state (mcl.AxisState): 0 Disabled, 1 StandStill, 2 Homing," in text
    assert "group state (mcl.GroupState): 0 GroupDisabled, 1 GroupStandby," in text
    tree = DOCS[DOCS.index("```\nObjects") :]
    assert "├─ Group                       s=group" in tree[: tree.index("```", 4)]

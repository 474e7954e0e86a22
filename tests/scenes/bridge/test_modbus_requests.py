"""The Modbus TCP server in its own process as a PLC's Modbus master meets it: a request is
checked whole before anything is written (FC 23 too), several requests in one TCP segment are
all answered in order, function codes and unit ids it does not serve are refused, ``--allow``
serves exactly the addresses named; a slow master sees every Done (results held until it
acknowledges, ``command_count`` names each command); a stop with deceleration 0 ramps with the
axis' default; a negative INT register; a write refused while the viewer's operator commands."""

from __future__ import annotations

import random
import socket
import struct
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from pymodbus.client import ModbusTcpClient
from pymodbus.constants import ExcCodes
from pymodbus.pdu.file_message import FileRecord

import mcl
import scenes
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable, decode, encode
from tests.bridge_clients import ModbusLockstep, bits, free_port, modbus_server

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

TABLE = SignalTable(scenes.definition("gantry"))


def at(name: str) -> int:
    return TABLE.by_name[name].address


@pytest.fixture
def lockstep(tmp_path: Path) -> Iterator[ModbusLockstep]:
    """A lockstep server of the gantry and a master of it (the machine stands between steps)."""
    with modbus_server("gantry", tmp_path / "stderr.txt", "--lockstep") as client:
        yield ModbusLockstep("gantry", client)


@pytest.fixture
def free(tmp_path: Path) -> Iterator[ModbusTcpClient]:
    """A free-running server of the gantry (1× real time) and a client."""
    with modbus_server("gantry", tmp_path / "stderr.txt") as client:
        yield client


def image(client: ModbusTcpClient) -> list[int]:
    """Every register of the gantry's table."""
    registers: list[int] = []
    for start in range(0, TABLE.size, 125):
        reply = client.read_holding_registers(start, count=min(125, TABLE.size - start))
        assert not reply.isError(), reply
        registers += reply.registers
    return registers


def test_a_refused_read_write_request_writes_nothing(lockstep: ModbusLockstep) -> None:
    client = lockstep.client
    before = image(client)
    reply = client.readwrite_registers(
        read_address=TABLE.size, read_count=2, write_address=at("X.control"), values=[1]
    )
    assert reply.isError() and reply.exception_code == ExcCodes.ILLEGAL_ADDRESS
    assert image(client) == before  # X.control still 0
    lockstep.run(0.2)
    assert not lockstep.status("X", "power")  # the drive did not power up
    rng = random.Random(7)
    refused = 0
    for _ in range(300):  # random requests, some refused: a refused one changes nothing
        before = image(client)
        reply = client.readwrite_registers(
            read_address=rng.randrange(0, TABLE.size + 40),
            read_count=rng.randrange(1, 126),
            write_address=rng.randrange(100, TABLE.size),
            values=[rng.choice([0, 0, 1, 0x8000]) for _ in range(rng.randrange(1, 5))],
        )
        if reply.isError():
            refused += 1
            assert image(client) == before
    assert 50 < refused < 300


def frame(tid: int, pdu: bytes, unit: int = 1) -> bytes:
    """A Modbus TCP frame."""
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


def test_several_requests_in_one_segment_are_all_answered_in_order(
    lockstep: ModbusLockstep,
) -> None:
    port = lockstep.client.comm_params.port
    requests = [
        frame(1, struct.pack(">BHH", 3, at("sim.time"), 2)),
        frame(2, struct.pack(">BHHBHH", 16, at("X.velocity"), 2, 4, *encode("f32", 150.0))),
        frame(3, struct.pack(">BHH", 3, at("X.velocity"), 2)),
        frame(4, struct.pack(">BHH", 3, 9999, 1)),  # outside the table: an exception
    ]
    with socket.create_connection(("127.0.0.1", int(port)), timeout=5) as raw:
        raw.sendall(b"".join(requests))  # one segment
        answers = [receive(raw) for _ in requests]
    assert [tid for tid, _ in answers] == [1, 2, 3, 4]
    assert [pdu[0] for _, pdu in answers] == [3, 16, 3, 0x83]
    assert decode("f32", struct.unpack(">HH", answers[2][1][2:6])) == 150.0
    assert answers[3][1][1] == ExcCodes.ILLEGAL_ADDRESS


def receive(raw: socket.socket) -> tuple[int, bytes]:
    """One Modbus TCP frame: its transaction id and PDU."""
    head = b""
    while len(head) < 7:
        chunk = raw.recv(7 - len(head))
        assert chunk, "the server closed the connection"
        head += chunk
    tid, _, length = struct.unpack(">HHH", head[:6])
    pdu = b""
    while len(pdu) < length - 1:
        chunk = raw.recv(length - 1 - len(pdu))
        assert chunk, "the server closed the connection"
        pdu += chunk
    return tid, pdu


def test_function_codes_and_unit_ids_not_served_are_refused(lockstep: ModbusLockstep) -> None:
    client = lockstep.client
    others = [
        client.read_exception_status(),  # 7
        client.diag_read_diagnostic_register(),  # 8
        client.diag_get_comm_event_counter(),  # 11
        client.diag_get_comm_event_log(),  # 12
        client.report_device_id(),  # 17
        client.read_file_record([FileRecord(file_number=1, record_number=0, record_length=2)]),
        client.read_fifo_queue(address=at("X.status")),  # 24
        client.read_device_information(),  # 43
        client.read_coils(0, count=1),  # 1
    ]
    assert [r.isError() and r.exception_code for r in others] == [ExcCodes.ILLEGAL_FUNCTION] * 9
    for unit in (0, 2, 255):  # the gantry is unit 1
        reply = client.read_holding_registers(at("sim.time"), count=2, device_id=unit)
        assert reply.isError() and reply.exception_code == ExcCodes.GATEWAY_PATH_UNAVIABLE
        reply = client.write_register(at("X.control"), 1, device_id=unit)
        assert reply.isError()
    assert not client.read_holding_registers(at("sim.time"), count=2, device_id=1).isError()
    lockstep.run(0.1)
    assert not lockstep.status("X", "power")  # no write of another unit id reached X


def test_with_allow_only_the_addresses_named_are_served(tmp_path: Path) -> None:
    import os
    import subprocess
    import sys

    port = free_port()
    log = tmp_path / "stderr.txt"
    command = [sys.executable, "-m", "scenes", "bridge", "modbus", "gantry", "--port", str(port)]
    options = ["--host", "0.0.0.0", "--allow", "198.51.100.7", "--lockstep"]
    with log.open("w") as stderr:
        process = subprocess.Popen(
            [*command, *options],
            env={**os.environ, "MCL_PURE_PYTHON": "1"},
            stdout=subprocess.PIPE,
            stderr=stderr,
            text=True,
        )
    try:
        assert process.stdout is not None
        assert "Modbus TCP on 0.0.0.0" in process.stdout.readline()
        local = ModbusTcpClient("127.0.0.1", port=port, timeout=1, retries=0)
        local.connect()
        try:
            answered = not local.read_holding_registers(0, count=2).isError()
        except Exception:  # closed at once: no answer
            answered = False
        local.close()
        assert not answered  # 127.0.0.1 is not in --allow
        assert process.poll() is None
    finally:
        process.terminate()
        process.wait(10)
    assert "refused a Modbus connection from 127.0.0.1" in log.read_text()


def read_block(client: ModbusTcpClient) -> dict[str, int]:
    """X's status block (120 … 149) as a 100 ms master reads it each poll: the status word,
    command and command_count at offsets 20, 32 and 49 of the block (docs/bridge.md)."""
    reply = client.read_holding_registers(120, count=30)
    assert not reply.isError(), reply
    r = reply.registers
    return {"status": r[0], "command": r[32 - 20], "command_count": r[49 - 20]}


def flag(block: dict[str, int], name: str) -> bool:
    return bool(block["status"] >> STATUS_BITS.index(name) & 1)


def write(client: ModbusTcpClient, name: str, value: float) -> None:
    f = TABLE.by_name[name]
    assert not client.write_registers(f.address, encode(f.kind, value)).isError()


def position(client: ModbusTcpClient) -> float:
    return decode("f32", client.read_holding_registers(at("X.actual_position"), count=2).registers)


def test_a_slow_master_sees_every_done_and_acknowledges_it(free: ModbusTcpClient) -> None:
    """A master polling every 100 ms that clears the command bit at once (the status is
    published every 10 ms, Done lasts one scan in the block) sees each move's Done: it is held
    until the master starts the next command. One that holds the bit until Done acknowledges
    it by clearing the bit: Done drops."""
    client = free
    for name, value in (("velocity", 200.0), ("acceleration", 2000.0), ("deceleration", 2000.0)):
        write(client, f"X.{name}", value)
    write(client, "X.distance", 20.0)
    write(client, "X.control", bits("enable"))
    deadline = time.monotonic() + 5.0
    while not flag(read_block(client), "power"):
        assert time.monotonic() < deadline
        time.sleep(0.1)
    start = position(client)
    seen = 0
    for _ in range(5):
        count = read_block(client)["command_count"]
        write(client, "X.control", bits("enable", "move_relative"))
        write(client, "X.control", bits("enable"))  # cleared before the command is done
        deadline = time.monotonic() + 3.0
        while time.monotonic() < deadline:
            time.sleep(0.1)
            block = read_block(client)
            if block["command_count"] != count and flag(block, "done"):
                assert block["command"] == CONTROL_BITS.index("move_relative") + 1
                seen += 1
                break
    assert seen == 5
    assert position(client) == pytest.approx(start + 100.0, abs=0.02)
    count = read_block(client)["command_count"]
    write(client, "X.control", bits("enable", "move_relative"))  # held until Done
    deadline = time.monotonic() + 3.0
    while not ((b := read_block(client))["command_count"] != count and flag(b, "done")):
        assert time.monotonic() < deadline
        time.sleep(0.1)
    time.sleep(0.3)
    assert flag(read_block(client), "done")  # held while the bit is set
    write(client, "X.control", bits("enable"))  # the acknowledgement: Done drops
    deadline = time.monotonic() + 2.0
    while flag(read_block(client), "done"):
        assert time.monotonic() < deadline, "Done not dropped after the acknowledgement"
        time.sleep(0.02)
    assert position(client) == pytest.approx(start + 120.0, abs=0.02)


def stop_distance(plc: ModbusLockstep, deceleration: float) -> float:
    """X at 200 mm/s, then stopped with ``deceleration`` (0: the axis' default): the distance
    it takes to stand [mm]."""
    plc.write_all({"X.velocity": 200.0, "X.acceleration": 2000.0, "X.deceleration": 2000.0})
    plc.write("X.control", bits("enable", "move_velocity"))
    plc.until(lambda: plc.status("X", "in_velocity"), 2.0, "at speed")
    plc.write("X.deceleration", deceleration)
    start = plc.read("X.actual_position")
    plc.write("X.control", bits("enable", "stop"))
    plc.until(lambda: plc.status("X", "done"), 3.0, "stopped")
    plc.write("X.control", bits("enable"))
    plc.run(0.05)
    assert abs(plc.read("X.actual_velocity")) < 1.0
    return plc.read("X.actual_position") - start


def test_a_stop_with_deceleration_0_ramps_with_the_default(lockstep: ModbusLockstep) -> None:
    plc = lockstep
    plc.write("X.control", bits("enable"))
    plc.until(lambda: plc.status("X", "power"), 2.0, "power")
    config = scenes.definition("gantry").axes["X"].config
    jerk = config.jerk  # the axis' default jerk shapes both ramps

    def ramp(a: float) -> float:  # 200 mm/s to standstill at a [mm/s²] with that jerk [mm]
        return 200.0**2 / (2.0 * a) + 200.0 * a / (2.0 * jerk)

    assert stop_distance(plc, 200.0) == pytest.approx(ramp(200.0), rel=0.02)  # 100.4 mm
    default = stop_distance(plc, 0.0)  # the axis' default deceleration, not the last one
    assert default == pytest.approx(ramp(config.deceleration), rel=0.02)  # 14 mm


def test_a_negative_int_register_is_minus_one(tmp_path: Path) -> None:
    """0xFFFF in the press' InputNumber2 (an INT) is −1, "no second input": MC_ForceControl
    takes it (65535 would be an input the axis lacks: EParam)."""
    with modbus_server("press", tmp_path / "stderr.txt", "--lockstep") as client:
        plc = ModbusLockstep("press", client)
        plc.write("R.control", bits("enable"))
        plc.until(lambda: plc.status("R", "power"), 2.0, "power")
        plc.write_all({"R.force": 5.0, "R.velocity": 20.0, "R.gain": 1.0, "R.scale": 1.0})
        address = plc.table.by_name["R.input_number2"].address
        assert not client.write_register(address, 0xFFFF).isError()
        assert client.read_holding_registers(address, count=1).registers == [0xFFFF]
        plc.write("R.control", bits("enable", "force_control"))
        plc.run(0.1)
        assert plc.status("R", "active") and not plc.status("R", "error")
        assert plc.read("R.error_id") == 0
        assert plc.read("R.state") == mcl.AxisState.ContinuousMotion


def test_a_write_while_the_viewers_operator_commands_is_device_busy() -> None:
    from viewer.sim.external_plc import ExternalPlc

    plc = ExternalPlc("gantry", port=free_port())  # not in control until its program runs
    client = ModbusTcpClient("127.0.0.1", port=int(plc.label.rsplit(":", 1)[1].rstrip(")")))
    try:
        assert client.connect()
        reply = client.write_register(at("X.control"), bits("enable"))
        assert reply.isError() and reply.exception_code == ExcCodes.DEVICE_BUSY
        reply = client.write_registers(at("X.position"), encode("f32", 100.0))
        assert reply.isError() and reply.exception_code == ExcCodes.DEVICE_BUSY
        assert client.read_holding_registers(at("sim.control"), count=1).registers == [0]
        assert plc.tables[0].get("X.control") == 0 and plc.tables[0].get("X.position") == 0
    finally:
        client.close()
        plc.close()


def test_a_write_of_more_than_123_registers_is_illegal_value_and_the_connection_stays(
    lockstep: ModbusLockstep,
) -> None:
    port = lockstep.client.comm_params.port
    too_many = struct.pack(">BHHB", 16, at("X.control"), 124, 248) + bytes(248)
    with socket.create_connection(("127.0.0.1", int(port)), timeout=5) as raw:
        raw.sendall(frame(1, too_many))
        tid, pdu = receive(raw)
        assert (tid, pdu[0], pdu[1]) == (1, 0x90, ExcCodes.ILLEGAL_VALUE)
        raw.sendall(frame(2, struct.pack(">BHH", 3, at("X.control"), 1)))  # the same connection
        assert receive(raw) == (2, bytes([3, 2, 0, 0]))  # nothing was written

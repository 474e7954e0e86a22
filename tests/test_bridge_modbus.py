"""The Modbus TCP server in its own process, driven by a pymodbus client: the gantry's X axis
powered, homed and moved to 300 mm (read back from the actual-position registers); refused
requests answered with Modbus exceptions while the server stays up."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator

import pytest
from pymodbus.client import ModbusTcpClient

import scenes
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable

TABLE = SignalTable(scenes.definition("gantry"))
FLOAT = ModbusTcpClient.DATATYPE.FLOAT32


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def client() -> Iterator[ModbusTcpClient]:
    port = free_port()
    env = {**os.environ, "MCL_PURE_PYTHON": "1"}
    command = [sys.executable, "-m", "scenes", "bridge", "modbus", "gantry", "--port", str(port)]
    server = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True)
    try:
        assert server.stdout is not None
        assert "Modbus TCP on 127.0.0.1" in server.stdout.readline()
        modbus = ModbusTcpClient("127.0.0.1", port=port)
        assert modbus.connect()
        yield modbus
        modbus.close()
        assert server.poll() is None  # still up after every request of the test
    finally:
        server.terminate()
        server.wait(10)


def address(name: str) -> int:
    return TABLE.by_name[name].address


def read_float(modbus: ModbusTcpClient, name: str) -> float:
    reply = modbus.read_holding_registers(address(name), count=2)
    assert not reply.isError()
    return float(modbus.convert_from_registers(reply.registers, FLOAT, word_order="big"))  # type: ignore[arg-type]


def write_float(modbus: ModbusTcpClient, name: str, value: float) -> None:
    registers = modbus.convert_to_registers(value, FLOAT, word_order="big")
    assert not modbus.write_registers(address(name), registers).isError()


def control(modbus: ModbusTcpClient, *bits: str) -> None:
    word = sum(1 << CONTROL_BITS.index(b) for b in bits)
    assert not modbus.write_register(address("X.control"), word).isError()


def status(modbus: ModbusTcpClient, bit: str) -> bool:
    reply = modbus.read_holding_registers(address("X.status"), count=1)
    return bool(reply.registers[0] >> STATUS_BITS.index(bit) & 1)


def finished(modbus: ModbusTcpClient, command: str) -> bool:
    """The PLC has taken ``command`` as the current one and it is Done."""
    current = modbus.read_holding_registers(address("X.command"), count=1).registers[0]
    return current == CONTROL_BITS.index(command) + 1 and status(modbus, "done")


def wait(condition: Callable[[], bool], seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.02)


def test_power_home_and_move_to_300_mm(client: ModbusTcpClient) -> None:
    control(client, "enable")
    wait(lambda: status(client, "power"), 5.0)
    control(client, "enable", "home")
    wait(lambda: finished(client, "home"), 30.0)
    assert status(client, "homed")
    control(client, "enable")
    for name, value in (("position", 300.0), ("velocity", 200.0)):
        write_float(client, f"X.{name}", value)
    write_float(client, "X.acceleration", 1000.0)
    write_float(client, "X.deceleration", 1000.0)
    control(client, "enable", "move_absolute")
    wait(lambda: finished(client, "move_absolute"), 15.0)
    assert read_float(client, "X.actual_position") == pytest.approx(300.0, abs=0.02)
    assert read_float(client, "sim.time") > 3.0


def test_refused_requests_leave_the_server_up(client: ModbusTcpClient) -> None:
    assert client.write_register(address("X.status"), 1).isError()  # read-only
    assert client.write_register(TABLE.size + 5, 1).isError()  # outside the table
    assert client.read_holding_registers(TABLE.size - 1, count=4).isError()
    assert client.read_coils(0, count=1).isError()
    assert not client.read_holding_registers(address("X.status"), count=1).isError()

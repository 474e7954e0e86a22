"""The Modbus TCP server in its own process, driven by a pymodbus client: the gantry's X axis
powered, homed and moved to 300 mm (read back from the actual-position registers); refused
requests, 10 000 random ones and malformed frames answered with Modbus exceptions while the
server and the machine stay up."""

from __future__ import annotations

import ast
import importlib.util
import os
import random
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from pymodbus.client import ModbusTcpClient

import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable, decode, encode
from tests.bridge_clients import SCENARIO, WATCHED
from tests.helpers import ROOT

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

TABLE = SignalTable(scenes.definition("gantry"))
FLOAT = ModbusTcpClient.DATATYPE.FLOAT32


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def port() -> int:
    return free_port()


@contextmanager
def server(port: int, log: Path, *options: str) -> Iterator[ModbusTcpClient]:
    """The gantry's Modbus server in its own process, and a client connected to it."""
    env = {**os.environ, "MCL_PURE_PYTHON": "1"}
    command = [sys.executable, "-m", "scenes", "bridge", "modbus", "gantry", "--port", str(port)]
    with log.open("w") as stderr:
        process = subprocess.Popen(
            [*command, *options], env=env, stdout=subprocess.PIPE, stderr=stderr, text=True
        )
    try:
        assert process.stdout is not None
        assert "Modbus TCP on 127.0.0.1" in process.stdout.readline()
        modbus = ModbusTcpClient("127.0.0.1", port=port)
        assert modbus.connect()
        yield modbus
        modbus.close()
        assert process.poll() is None  # still up after every request of the test
    finally:
        process.terminate()
        process.wait(10)
    assert "Traceback" not in log.read_text()


@pytest.fixture
def client(port: int, tmp_path: Path) -> Iterator[ModbusTcpClient]:
    with server(port, tmp_path / "stderr.txt") as modbus:
        yield modbus


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
    write_float(client, "X.position", 5000.0)  # beyond the software limit
    control(client, "enable")
    wait(lambda: not status(client, "done"), 2.0)
    control(client, "enable", "move_absolute")
    wait(lambda: status(client, "error"), 2.0)
    assert client.read_holding_registers(address("X.error_id"), count=1).registers == [8]
    assert read_float(client, "X.actual_position") == pytest.approx(300.0, abs=0.02)
    control(client, "enable", "reset")
    wait(lambda: finished(client, "reset"), 2.0)
    assert not status(client, "error")


def test_the_example_client_homes_and_moves_the_gantry(client: ModbusTcpClient, port: int) -> None:
    example = ROOT / "examples" / "bridge_modbus_client.py"
    command = [sys.executable, str(example), "--port", str(port)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert abs(float(result.stdout.split()[2]) - 300.0) < 0.02  # "X at 300.001 mm"


def test_the_example_client_needs_pymodbus_only_and_the_maps_addresses() -> None:
    example = ROOT / "examples" / "bridge_modbus_client.py"
    tree = ast.parse(example.read_text())
    imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert {m.split(".")[0] for m in imported} <= {"__future__", "argparse", "struct", "time"} | {
        "collections",
        "pymodbus",
    }
    spec = importlib.util.spec_from_file_location("bridge_modbus_client", example)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for name, field in (
        ("CONTROL", "X.control"),
        ("STATUS", "X.status"),
        ("ACTUAL_POSITION", "X.actual_position"),
        ("COMMAND", "X.command"),
        ("COMMAND_COUNT", "X.command_count"),
    ):
        assert getattr(module, name) == address(field), name
    assert address("X.position") == module.CONTROL + 2  # the block's ramp follows the outputs
    calls = [
        getattr(n.func, "attr", getattr(n.func, "id", ""))
        for n in ast.walk(tree)
        if isinstance(n, ast.Call)
    ]
    calls = [c for c in calls if c.startswith("write_")]
    assert set(calls) == {"write_registers", "write_block"}  # FC 16 of the block only


def test_refused_requests_leave_the_server_up(client: ModbusTcpClient) -> None:
    assert client.write_register(address("X.status"), 1).isError()  # read-only
    assert client.write_register(TABLE.size + 5, 1).isError()  # outside the table
    assert client.read_holding_registers(TABLE.size - 1, count=4).isError()
    assert client.read_coils(0, count=1).isError()
    assert not client.read_holding_registers(address("X.status"), count=1).isError()


def fuzz_request(modbus: ModbusTcpClient, rng: random.Random) -> None:
    """One random request: any register function, address, count and value."""
    address, count = rng.randrange(0, TABLE.size + 50), rng.randrange(1, 126)
    value = rng.randrange(0, 0x10000)
    kind = rng.randrange(6)
    if kind == 0:
        modbus.read_holding_registers(address, count=count)
    elif kind == 1:
        modbus.read_input_registers(address, count=count)
    elif kind == 2:
        modbus.write_register(address, value)
    elif kind == 3:
        modbus.write_registers(address, [rng.randrange(0, 0x10000) for _ in range(count % 8 + 1)])
    elif kind == 4:
        modbus.read_coils(address, count=count)
    else:
        modbus.mask_write_register(
            address=address, and_mask=value, or_mask=rng.randrange(0, 0x10000)
        )


def test_ten_thousand_random_requests_and_malformed_frames(
    client: ModbusTcpClient, port: int
) -> None:
    rng = random.Random(23)
    for _ in range(10_000):
        fuzz_request(client, rng)
    for frame in (b"\x00", b"\xff" * 300, b"\x00\x01\x00\x00\x00\x06\x01\x03\x00", b""):
        with socket.create_connection(("127.0.0.1", port), timeout=2) as raw:
            raw.sendall(frame)  # a malformed frame, then a half-open connection closed
    before = read_float(client, "sim.time")
    time.sleep(0.2)
    assert read_float(client, "sim.time") > before  # the machine still runs


def in_process_trace() -> list[list[int]]:
    """The registers of :data:`WATCHED` after every step of the scenario, run in-process and
    published after each step as a lockstep server publishes them."""
    scene = scenes.load("gantry", trace_every=0)
    table = SignalTable(scenes.definition("gantry"))
    program = BridgeProgram(scene, [table], scenes.homing(scene), publish_every_scan=False)
    trace = []
    for cycles, writes in SCENARIO:
        for name, value in writes.items():
            f = table.by_name[name]
            table.write(f.address, encode(f.kind, value))
        scene.run(program, timeout=cycles * scene.runtime.plc_period)
        program.publish()
        trace.append([r for name in WATCHED for r in registers(table, name)])
    return trace


def registers(table: SignalTable, name: str) -> list[int]:
    f = table.by_name[name]
    return table.read(f.address, f.width)


def test_lockstep_equals_in_process_bit_for_bit(port: int, tmp_path: Path) -> None:
    reference = in_process_trace()
    rng = random.Random(5)
    trace: list[list[int]] = []
    target = 0
    with server(port, tmp_path / "stderr.txt", "--lockstep") as modbus:
        for cycles, writes in SCENARIO:
            for name, value in writes.items():
                f = TABLE.by_name[name]
                assert not modbus.write_registers(f.address, encode(f.kind, value)).isError()
                time.sleep(rng.uniform(0.0, 0.003))  # whatever the network timing
            target += cycles
            assert not modbus.write_registers(
                address("sim.target"), encode("u32", target)
            ).isError()
            wait(acknowledged(modbus, target), 10.0)
            trace.append([r for n in WATCHED for r in read(modbus, n)])
    assert trace == reference
    assert decode("f32", reference[-1][:2]) == pytest.approx(300.0, abs=0.02)


def read(modbus: ModbusTcpClient, name: str) -> list[int]:
    f = TABLE.by_name[name]
    return list(modbus.read_holding_registers(f.address, count=f.width).registers)


def acknowledged(modbus: ModbusTcpClient, target: int) -> Callable[[], bool]:
    """The lockstep server has run up to PLC cycle ``target``."""
    return lambda: read_u32(modbus, "sim.cycle") == target


def read_u32(modbus: ModbusTcpClient, name: str) -> int:
    return int(decode("u32", read(modbus, name)))


def own_address() -> str | None:
    """This machine's address beyond loopback (None: it has none)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.connect(("198.51.100.1", 9))  # no packet is sent: the route gives the address
            host = str(s.getsockname()[0])
        except OSError:
            return None
    return None if host.startswith("127.") else host


def test_beyond_loopback_only_the_allowed_addresses_are_served(tmp_path: Path) -> None:
    host = own_address()
    if host is None:
        pytest.skip("this machine has no address beyond loopback")
    port = free_port()
    log = tmp_path / "stderr.txt"
    command = [sys.executable, "-m", "scenes", "bridge", "modbus", "gantry", "--port", str(port)]
    options = ["--host", host, "--allow", "198.51.100.7"]
    env = {**os.environ, "MCL_PURE_PYTHON": "1"}
    with log.open("w") as stderr:
        process = subprocess.Popen(
            [*command, *options], env=env, stdout=subprocess.PIPE, stderr=stderr, text=True
        )
    try:
        assert process.stdout is not None
        assert f"Modbus TCP on {host}" in process.stdout.readline()
        assert "warning: Modbus has no security" in process.stdout.readline()
        stranger = ModbusTcpClient(host, port=port, timeout=1, retries=0)
        stranger.connect()
        reply_ok = False
        try:
            reply_ok = not stranger.read_holding_registers(0, count=2).isError()
        except Exception:  # the connection is closed at once: no answer
            reply_ok = False
        stranger.close()
        assert not reply_ok
        assert process.poll() is None
    finally:
        process.terminate()
        process.wait(10)
    assert "refused a Modbus connection from" in log.read_text()

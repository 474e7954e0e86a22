"""A Modbus TCP client that homes the gantry's X axis and moves it to 300 mm, as an external PLC
would (docs/bridge.md). Start the server first:

    python -m scenes bridge modbus gantry --port 5020
    python examples/bridge_modbus_client.py --port 5020
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

from pymodbus.client import ModbusTcpClient

import scenes
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable

TABLE = SignalTable(scenes.definition("gantry"))
"""The register map (``python -m scenes bridge map gantry`` prints it)."""
FLOAT = ModbusTcpClient.DATATYPE.FLOAT32


def at(name: str) -> int:
    """The register address of a field."""
    return TABLE.by_name[name].address


def command(client: ModbusTcpClient, *bits: str) -> None:
    """Write X's control word with ``bits`` set."""
    client.write_register(at("X.control"), sum(1 << CONTROL_BITS.index(b) for b in bits))


def write_float(client: ModbusTcpClient, name: str, value: float) -> None:
    """Write an f32 field (high word first)."""
    client.write_registers(at(name), client.convert_to_registers(value, FLOAT, word_order="big"))


def read_float(client: ModbusTcpClient, name: str) -> float:
    """Read an f32 field."""
    registers = client.read_holding_registers(at(name), count=2).registers
    return float(client.convert_from_registers(registers, FLOAT, word_order="big"))  # type: ignore[arg-type]


def started(client: ModbusTcpClient) -> int:
    """X's ``command_count``: the commands started so far."""
    return int(client.read_holding_registers(at("X.command_count"), count=1).registers[0])


def done(client: ModbusTcpClient, bit: str, before: int) -> bool:
    """The command of control bit ``bit``, started after number ``before``, is Done (its
    Error raises): the handshake of docs/bridge.md."""
    if started(client) == before:
        return False  # not started yet: the status is still the last command's
    block = client.read_holding_registers(at("X.status"), count=3).registers  # … error_id
    current = client.read_holding_registers(at("X.command"), count=1).registers[0]
    if current != CONTROL_BITS.index(bit) + 1:
        raise RuntimeError(f"{bit}: another command started")
    if block[0] >> STATUS_BITS.index("error") & 1:
        raise RuntimeError(f"{bit}: error {block[2]}")
    return bool(block[0] >> STATUS_BITS.index("done") & 1)


def powered(client: ModbusTcpClient) -> bool:
    """MC_Power's Status of X."""
    status = client.read_holding_registers(at("X.status"), count=1).registers[0]
    return bool(status >> STATUS_BITS.index("power") & 1)


def wait(condition: Callable[[], bool], seconds: float) -> None:
    """Poll ``condition`` every 20 ms for at most ``seconds``."""
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            raise TimeoutError("no answer in time")
        time.sleep(0.02)


def home_and_move(port: int, target: float = 300.0) -> float:
    """Power X, home it with its recipe, move it to ``target`` [mm]; its actual position [mm]."""
    client = ModbusTcpClient("127.0.0.1", port=port)
    if not client.connect():
        raise ConnectionError(f"no server on 127.0.0.1:{port}")
    try:
        command(client, "enable")
        wait(lambda: powered(client), 5.0)
        before = started(client)
        command(client, "enable", "home")
        wait(lambda: done(client, "home", before), 30.0)
        command(client, "enable")  # the bit cleared: the result acknowledged
        for name, value in (("position", target), ("velocity", 200.0)):
            write_float(client, f"X.{name}", value)
        write_float(client, "X.acceleration", 1000.0)
        write_float(client, "X.deceleration", 1000.0)
        before = started(client)
        command(client, "enable", "move_absolute")
        wait(lambda: done(client, "move_absolute", before), 15.0)
        command(client, "enable")
        return read_float(client, "X.actual_position")
    finally:
        client.close()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, default=5020)
    print(f"X at {home_and_move(parser.parse_args().port):.3f} mm")

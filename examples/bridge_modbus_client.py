"""A Modbus TCP client that homes the gantry's X axis and moves it to 300 mm, as an external PLC
would (docs/bridge.md). It needs pymodbus only, so it runs on the PLC's side; the register
numbers are those of the map (``python -m scenes bridge map gantry``, docs/bridge.md). Start
the server first:

    python -m scenes bridge modbus gantry --port 5020
    python examples/bridge_modbus_client.py --port 5020
"""

from __future__ import annotations

import argparse
import struct
import time
from collections.abc import Callable

from pymodbus.client import ModbusTcpClient

UNIT = 1
"""The gantry's unit id."""
X = 100
"""X's block: the first axis' base address (docs/bridge.md, The register map)."""
CONTROL = X + 0
"""X.control, the first register of its write block (docs/bridge.md, OpenPLC: 100 … 114)."""
STATUS = X + 20
"""X.status; X.state and X.error_id follow it."""
ACTUAL_POSITION = X + 24
"""X.actual_position (f32)."""
COMMAND = X + 32
"""X.command: the current command's control bit + 1."""
COMMAND_COUNT = X + 49
"""X.command_count: the commands started."""

ENABLE, HOME, MOVE_ABSOLUTE = 1 << 0, 1 << 5, 1 << 2
"""Bits of the control word."""
DONE, ERROR, POWER = 1 << 0, 1 << 3, 1 << 9
"""Bits of the status word."""
BIT_NUMBER = {HOME: 5, MOVE_ABSOLUTE: 2}
"""A command's control bit number (``command`` reads it + 1)."""


def words(value: float) -> list[int]:
    """An f32 as two registers, high word first."""
    return list(struct.unpack(">HH", struct.pack(">f", value)))


def real(registers: list[int]) -> float:
    """The f32 of two registers, high word first."""
    return float(struct.unpack(">f", struct.pack(">HH", *registers))[0])


def read(client: ModbusTcpClient, address: int, count: int) -> list[int]:
    """Holding registers from ``address`` (an error raises)."""
    reply = client.read_holding_registers(address, count=count, device_id=UNIT)
    if reply.isError():
        raise RuntimeError(f"read {address}: {reply}")
    return list(reply.registers)


def write_block(client: ModbusTcpClient, control: int, ramp: tuple[float, ...] = ()) -> None:
    """One function-16 write of X's block from its control word: the control word, the
    outputs (0) and ``ramp`` — position, distance, velocity, acceleration, deceleration, jerk —
    so that the scan that sees the bit sees the parameters too."""
    values = [control, 0]
    for value in ramp:
        values += words(value)
    reply = client.write_registers(CONTROL, values, device_id=UNIT)
    if reply.isError():
        raise RuntimeError(f"write {CONTROL}: {reply}")


def started(client: ModbusTcpClient) -> int:
    """X's ``command_count``: the commands started so far."""
    return read(client, COMMAND_COUNT, 1)[0]


def done(client: ModbusTcpClient, bit: int, before: int) -> bool:
    """The command of control bit ``bit``, started after number ``before``, is Done (its
    Error raises): the handshake of docs/bridge.md."""
    if started(client) == before:
        return False  # not started yet: the status is still the last command's
    status, _, error_id = read(client, STATUS, 3)
    if read(client, COMMAND, 1)[0] != BIT_NUMBER[bit] + 1:
        raise RuntimeError(f"control bit {BIT_NUMBER[bit]}: another command started")
    if status & ERROR:
        raise RuntimeError(f"control bit {BIT_NUMBER[bit]}: error {error_id}")
    return bool(status & DONE)


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
        write_block(client, ENABLE)
        wait(lambda: bool(read(client, STATUS, 1)[0] & POWER), 5.0)
        before = started(client)
        write_block(client, ENABLE | HOME)
        wait(lambda: done(client, HOME, before), 30.0)
        write_block(client, ENABLE)  # the bit cleared: the result acknowledged
        before = started(client)
        # position, distance, velocity, acceleration, deceleration, jerk and the bit: one write
        write_block(client, ENABLE | MOVE_ABSOLUTE, (target, 0.0, 200.0, 1000.0, 1000.0, 0.0))
        wait(lambda: done(client, MOVE_ABSOLUTE, before), 15.0)
        write_block(client, ENABLE)
        return real(read(client, ACTUAL_POSITION, 2))
    finally:
        client.close()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, default=5020)
    print(f"X at {home_and_move(parser.parse_args().port):.3f} mm")

"""The Modbus TCP server of the bridge (pymodbus 3.15): a machine's signal table as holding
registers of unit id :data:`UNIT_ID`, its simulation running in its own thread: free at a
speed (1×: real time) or in lockstep with the client (:mod:`scenes.bridge.pacing`).

Function codes 3 and 4 read the table, 6, 16, 22 and 23 write its command fields; a read
outside the table or a write to a read-only or unmapped register gets the exception
ILLEGAL_ADDRESS, coil and discrete-input codes ILLEGAL_FUNCTION. The server binds loopback only.
"""

from __future__ import annotations

import asyncio
import ipaddress
import logging
import math
import signal

from pymodbus.constants import ExcCodes
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import DataType, SimData, SimDevice

import scenes
from scenes.bridge.pacing import LockstepRun, PacedRun
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import SignalTable, WriteRefused

log = logging.getLogger(__name__)

UNIT_ID = 1
"""The Modbus unit id of the machine."""

REGISTER_CODES = (3, 4, 6, 16, 22, 23)
"""Function codes on registers: read, write single and multiple, mask write, read/write (a
write is read back after it is done)."""


def device(table: SignalTable, unit_id: int = UNIT_ID) -> SimDevice:
    """A pymodbus device whose registers are the table's (synchronised on every request)."""

    async def action(
        function_code: int,
        start_address: int,
        address: int,
        count: int,
        registers: list[int],
        values: list[int] | list[bool] | None,
    ) -> ExcCodes | None:
        try:
            if function_code not in REGISTER_CODES:
                return ExcCodes.ILLEGAL_FUNCTION
            if values is not None:
                table.write(address, [int(v) for v in values])
            else:
                offset = address - start_address
                registers[offset : offset + count] = table.read(address, count)
        except WriteRefused as refused:
            log.warning("refused: function %d at %d: %s", function_code, address, refused)
            return ExcCodes.ILLEGAL_ADDRESS
        return None

    data = SimData(address=0, count=table.size, values=0, datatype=DataType.REGISTERS)
    return SimDevice(id=unit_id, simdata=[data], action=action)


def check_host(host: str) -> None:
    """Refuse an address beyond loopback (Modbus has no security of its own).

    Raises:
        ValueError: not a loopback address.
    """
    try:
        loopback = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = host == "localhost"
    if not loopback:
        raise ValueError(f"the Modbus server binds loopback only, got {host!r}")


async def serve(
    machine: str, host: str = "127.0.0.1", port: int = 5020, speed: float | None = 1.0
) -> None:
    """Build the scene of ``machine``, run it (free at ``speed`` × real time; None: lockstep)
    and serve its table until SIGTERM/SIGINT."""
    check_host(host)
    definition = scenes.definition(machine)
    scene = scenes.load(machine, trace_every=0)
    table = SignalTable(definition)
    program = BridgeProgram(scene, table, scenes.homing(scene))
    run = LockstepRun(program) if speed is None else PacedRun(program, speed)
    server = ModbusTcpServer([device(table)], address=(host, port))
    loop = asyncio.get_running_loop()
    for number in (signal.SIGTERM, signal.SIGINT):
        loop.add_signal_handler(number, lambda: asyncio.ensure_future(server.shutdown()))
    run.start()
    try:
        await server.serve_forever(background=True)  # listening once this returns
        mode = "lockstep" if speed is None else f"free-running at {speed:g}x"
        print(f"{machine}: Modbus TCP on {host}:{port}, unit id {UNIT_ID}, {mode}", flush=True)
        await server.serving
    finally:
        run.stop()


def main(machine: str, host: str, port: int, speed: float | None = 1.0) -> int:
    """The ``bridge modbus`` command: serve until stopped; 2 for a refused host or speed."""
    try:
        check_host(host)
        if speed is not None and not (math.isfinite(speed) and speed > 0.0):
            raise ValueError(f"speed must be a finite number > 0, got {speed}")
    except ValueError as error:
        print(error)
        return 2
    asyncio.run(serve(machine, host, port, speed))
    return 0

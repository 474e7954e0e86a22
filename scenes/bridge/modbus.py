"""The Modbus TCP server of the bridge (pymodbus 3.15): each machine's signal table as holding
registers of its unit id (a cell: one per part, 1, 2, …), the simulation running in its own
thread: free at a speed (1×: real time) or in lockstep with the client
(:mod:`scenes.bridge.pacing`).

Function codes 3 and 4 read the table, 6, 16, 22 and 23 write its command fields; a read
outside the table or a write to a read-only or unmapped register gets the exception
ILLEGAL_ADDRESS, coil and discrete-input codes ILLEGAL_FUNCTION, a write while an operator of the
viewer is in control (``sim.control`` 0) DEVICE_BUSY. In lockstep, the answer to a write of
``sim.target`` comes when the scene has run to it (at most
:data:`scenes.bridge.serving.ACK_TIMEOUT`): one request per PLC cycle (FC 23 also reads the
status back in it).

The server binds loopback. Modbus has no security of its own: another address needs
``allow`` (the client addresses accepted; every other connection is closed at once) and prints
a warning.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Sequence

from pymodbus.constants import ExcCodes
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler
from pymodbus.simulator import DataType, SimData, SimDevice

from scenes.bridge.machine import Bridge, check_speed
from scenes.bridge.pacing import LockstepRun
from scenes.bridge.serving import (
    acknowledge,
    admitted,
    allowed,
    check_host,
    is_loopback,
    run_command,
    stop_on_signals,
)
from scenes.bridge.table import NotInControl, SignalTable, WriteRefused

log = logging.getLogger(__name__)

REGISTER_CODES = (3, 4, 6, 16, 22, 23)
"""Function codes on registers: read, write single and multiple, mask write, read/write (a
write is read back after it is done)."""


def device(table: SignalTable, lockstep: LockstepRun | None = None) -> SimDevice:
    """A pymodbus device whose registers are the table's (synchronised on every request);
    with ``lockstep``, a write of the target is answered when the scene is there."""
    target = table.by_name["sim.target"]

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
                if lockstep is not None and address <= target.address < address + len(values):
                    await acknowledge(lockstep, int(table.get("sim.target")))
            else:
                offset = address - start_address
                registers[offset : offset + count] = table.read(address, count)
        except NotInControl as refused:
            log.warning("refused: function %d at %d: %s", function_code, address, refused)
            return ExcCodes.DEVICE_BUSY
        except WriteRefused as refused:
            log.warning("refused: function %d at %d: %s", function_code, address, refused)
            return ExcCodes.ILLEGAL_ADDRESS
        return None

    data = SimData(address=0, count=table.size, values=0, datatype=DataType.REGISTERS)
    return SimDevice(id=table.unit_id, simdata=[data], action=action)


class Server(ModbusTcpServer):
    """A Modbus TCP server that closes every connection from an address not allowed.

    Args:
        devices: the devices (one per unit id).
        address: (host, port) to bind.
        allow: client addresses accepted besides loopback ones.
    """

    def __init__(
        self, devices: list[SimDevice], address: tuple[str, int], allow: Sequence[str] = ()
    ) -> None:
        super().__init__(devices, address=address)
        self.allowed = allowed(allow)

    def callback_new_connection(self) -> ServerRequestHandler:
        """A handler that checks its peer first."""
        return _Guarded(self, self.trace_packet, self.trace_pdu, self.trace_connect)


class _Guarded(ServerRequestHandler):
    """The request handler of a connection: closed at once when its peer is not allowed."""

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        served, host = admitted(transport.get_extra_info("peername"), self.server.allowed)
        if not served:
            log.warning("refused a Modbus connection from %s (not in --allow)", host)
            transport.close()
            return
        super().connection_made(transport)


def server_of(
    bridge: Bridge, host: str = "127.0.0.1", port: int = 5020, allow: Sequence[str] = ()
) -> Server:
    """The Modbus server of ``bridge``'s tables.

    Raises:
        ValueError: a host beyond loopback without ``allow``.
    """
    check_host(host, allow)
    lockstep = bridge.run if isinstance(bridge.run, LockstepRun) else None
    return Server([device(t, lockstep) for t in bridge.tables], (host, port), allow)


async def serve(
    machine: str,
    host: str = "127.0.0.1",
    port: int = 5020,
    speed: float | None = 1.0,
    allow: Sequence[str] = (),
) -> None:
    """Build the scene of ``machine``, run it (free at ``speed`` × real time; None: lockstep)
    and serve its tables until SIGTERM/SIGINT."""
    bridge = Bridge(machine, speed)
    server = server_of(bridge, host, port, allow)
    stop_on_signals(server.shutdown)
    bridge.start()
    try:
        await server.serve_forever(background=True)  # listening once this returns
        units = ", ".join(f"{t.unit_id} {t.machine}" for t in bridge.tables)
        print(f"{machine}: Modbus TCP on {host}:{port}, unit id {units}, {bridge.mode}", flush=True)
        if not is_loopback(host):
            print(
                f"warning: Modbus has no security: serving {host} to {', '.join(allow)}",
                flush=True,
            )
        await server.serving
    finally:
        bridge.stop()


def main(
    machine: str, host: str, port: int, speed: float | None = 1.0, allow: Sequence[str] = ()
) -> int:
    """The ``bridge modbus`` command: serve until stopped; 2 for a refused host or speed."""

    def checks() -> None:
        check_host(host, allow)
        check_speed(speed)

    return run_command(checks, lambda: serve(machine, host, port, speed, allow))

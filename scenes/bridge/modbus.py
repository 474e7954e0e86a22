"""The Modbus TCP server of the bridge (pymodbus 3.15): each machine's signal table as holding
registers of its unit id (a cell: one per part, 1, 2, …), the simulation running in its own
thread: free at a speed (1×: real time) or in lockstep with the client
(:mod:`scenes.bridge.runs`).

Function codes 3 and 4 read the table, 6, 16, 22 and 23 write its command fields; every other
function code gets the exception ILLEGAL_FUNCTION, a unit id the server has no table for
(0 and 255 too) GATEWAY_PATH_UNAVAILABLE. A request is checked whole before anything is
written: a read outside the table or a write to a read-only or unmapped register gets
ILLEGAL_ADDRESS, a value other than 0 into a reserved register ILLEGAL_VALUE, a write while an
operator of the viewer is in control (``sim.control`` 0) DEVICE_BUSY. The requests of a
connection are answered one after the other, in their order, however many one TCP segment
carries. In lockstep, the answer to a write of ``sim.target`` comes when the scene has run to
it (at most :data:`scenes.bridge.serving.ACK_TIMEOUT`): one request per PLC cycle (FC 23 also
reads the status back in it).

The server binds loopback. Modbus has no security of its own: another address needs
``allow``, the client addresses served (every other connection is closed at once), and prints
a warning.
"""

from __future__ import annotations

__all__ = [
    "MAX_LENGTH",
    "MAX_PENDING",
    "MBAP",
    "REGISTER_CODES",
    "Server",
    "device",
    "main",
    "serve",
    "server_of",
]

import asyncio
import logging
from collections.abc import Sequence
from typing import Any

from pymodbus.constants import ExcCodes
from pymodbus.pdu import ExceptionResponse, ModbusPDU
from pymodbus.pdu.register_message import ReadWriteMultipleRegistersRequest
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler
from pymodbus.simulator import DataType, SimData, SimDevice

from scenes.bridge.machine import Bridge, check_speed
from scenes.bridge.runs import LockstepRun
from scenes.bridge.serving import (
    acknowledge,
    admitted,
    allowed,
    check_host,
    is_loopback,
    run_command,
    stop_on_signals,
)
from scenes.bridge.table import NotInControl, SignalTable, ValueRefused, WriteRefused

log = logging.getLogger(__name__)

REGISTER_CODES = (3, 4, 6, 16, 22, 23)
"""The function codes served: read holding and input registers, write single and multiple,
mask write, read/write (a write is read back after it is done)."""

MBAP = 7
"""Bytes of a Modbus TCP frame's header: transaction id, protocol id 0, length, unit id."""
MAX_PDU = 253
"""Largest PDU of the Modbus specification (123 registers of a function 16)."""
MAX_LENGTH = 266
"""Largest length field of a frame taken: the unit id and a PDU whose byte count (one byte)
says up to 255 data bytes (a function 23 of 127 registers); a PDU beyond :data:`MAX_PDU` is
answered with ILLEGAL_VALUE, a longer frame closes the connection."""
MAX_PENDING = 64
"""Requests of one connection waiting for their answer; a client that sends more is closed."""


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
        except ValueRefused as refused:
            log.warning("refused: function %d at %d: %s", function_code, address, refused)
            return ExcCodes.ILLEGAL_VALUE
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
        allow: the client addresses served (empty: loopback ones).
    """

    def __init__(
        self, devices: list[SimDevice], address: tuple[str, int], allow: Sequence[str] = ()
    ) -> None:
        super().__init__(devices, address=address)
        self.allowed = allowed(allow)
        self.units = frozenset(d.id for d in devices)

    def callback_new_connection(self) -> ServerRequestHandler:
        """A connection that checks its peer first."""
        return _Connection(self, self.trace_packet, self.trace_pdu, self.trace_connect)


class _Connection(ServerRequestHandler):
    """A client's connection: closed at once when its peer is not allowed; its requests taken
    from the byte stream as they come and answered one after the other, in their order."""

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        served, host = admitted(transport.get_extra_info("peername"), self.server.allowed)
        if not served:
            log.warning("refused a Modbus connection from %s (not in --allow)", host)
            transport.close()
            self.server.active_connections.pop(self.unique_id, None)
            return
        super().connection_made(transport)
        self._received = b""
        self._requests: asyncio.Queue[ModbusPDU] = asyncio.Queue()
        self._answering = asyncio.create_task(self._answer_all())

    def callback_disconnected(self, exc: Exception | None) -> None:
        """The client closed the connection: its requests still waiting are dropped."""
        self._stop_answering()
        super().callback_disconnected(exc)

    def close(self, reconnect: bool = False) -> None:
        """Close the connection: its requests still waiting are dropped."""
        self._stop_answering()
        super().close(reconnect)

    def _stop_answering(self) -> None:
        answering = getattr(self, "_answering", None)
        if answering is not None:
            answering.cancel()

    def data_received(self, data: bytes) -> None:
        """Take every whole frame received so far (several in one segment, too)."""
        self._received += data
        while len(self._received) >= MBAP:
            head = self._received
            length = int.from_bytes(head[4:6], "big")
            if head[2:4] != b"\x00\x00" or not 2 <= length <= MAX_LENGTH:
                log.warning("closed a Modbus connection: not a Modbus TCP frame")
                self.close()
                return
            end = MBAP - 1 + length
            if len(head) < end:
                return
            self._received = head[end:]
            if self._requests.qsize() >= MAX_PENDING:
                log.warning("closed a Modbus connection: more than %d requests", MAX_PENDING)
                self.close()
                return
            tid, unit = int.from_bytes(head[0:2], "big"), head[6]
            self._requests.put_nowait(self._decode(head[MBAP:end], tid, unit))

    def _decode(self, pdu: bytes, tid: int, unit: int) -> ModbusPDU:
        """The request of a frame, or the exception that answers one that is none."""
        request = self.server.decoder.decode(pdu) if len(pdu) <= MAX_PDU else None
        if request is None:
            code = pdu[0] & 0x7F  # a served function malformed, or another function
            known = code in REGISTER_CODES
            request = ExceptionResponse(
                code, ExcCodes.ILLEGAL_VALUE if known else ExcCodes.ILLEGAL_FUNCTION
            )
        request.transaction_id, request.dev_id = tid, unit
        return request

    async def _answer_all(self) -> None:
        while True:
            request = await self._requests.get()
            response = await self._answer(request)
            response.transaction_id, response.dev_id = request.transaction_id, request.dev_id
            if self.transport is not None:
                self.pdu_send(response)

    async def _answer(self, request: ModbusPDU) -> ModbusPDU:
        """The response to one request (an exception if it is refused)."""
        code = request.function_code
        if isinstance(request, ExceptionResponse):
            return request
        if code not in REGISTER_CODES:
            return ExceptionResponse(code, ExcCodes.ILLEGAL_FUNCTION)
        if request.dev_id not in self.server.units:
            log.warning("refused: function %d for unit id %d (none such)", code, request.dev_id)
            return ExceptionResponse(code, ExcCodes.GATEWAY_PATH_UNAVIABLE)
        context: Any = self.server.context
        try:
            if isinstance(request, ReadWriteMultipleRegistersRequest):
                refused = await _read_refused(context, request)  # checked before the write
                if refused is not None:
                    return ExceptionResponse(code, refused)
            response: ModbusPDU = await request.datastore_update(context, request.dev_id)
        except Exception as error:  # the server stays up; the client gets an exception
            log.error("function %d failed: %s: %s", code, type(error).__name__, error)
            return ExceptionResponse(code, ExcCodes.DEVICE_FAILURE)
        return response


async def _read_refused(
    context: Any, request: ReadWriteMultipleRegistersRequest
) -> ExcCodes | None:
    """The exception the read of an FC 23 request gets, if any (None: it may be done; a count
    beyond 1 … 125 is left to the request's own check)."""
    if not 1 <= request.read_count <= 125:
        return None
    read = await context.async_getValues(
        request.dev_id, 23, request.read_address, request.read_count
    )
    return read if isinstance(read, ExcCodes) else None


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

"""An external PLC in the viewer: the Modbus TCP server of the bridge (``--modbus PORT``) or its
OPC UA server (``--opcua PORT``) on the machine the viewer shows, offered as one more entry of the
Program choice.

The PLC commands the machine exactly while that entry is the running program: Run demo hands it
the machine (the operator hands power over, as to a demo), and whatever ends a demo — STOP all,
a Power button, End demo, another program, a reset — takes it back at the next PLC cycle. While
it is not in control the status stays live and its writes are refused (``sim.control`` 0,
Modbus exception DEVICE_BUSY, OPC UA BadInvalidState), so one owner commands at a time and STOP
all always works.
"""

from __future__ import annotations

__all__ = ["START_TIMEOUT", "ExternalPlc", "PlcInControl", "Transport"]

import asyncio
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import scenes
from scenes.bridge.modbus import Server, device
from scenes.bridge.program import BridgeProgram
from scenes.bridge.runs import CHUNK, Run
from scenes.bridge.serving import check_host
from scenes.bridge.table import SignalTable, tables_of
from scenes.definition import MachineDef
from scenes.scene import Scene

if TYPE_CHECKING:
    from scenes.bridge import opcua

Transport = Literal["modbus", "opcua"]
"""How the PLC reaches the machine: Modbus TCP or OPC UA."""

START_TIMEOUT = 15.0
"""Longest wall time [s] the server may take to listen."""


@dataclass(frozen=True)
class _Served:
    """What the OPC UA node tree serves in the viewer: the tables, and a bridge program on a
    scene of the machine for the axes' methods (the viewer scans its own); no run of its own."""

    definition: MachineDef
    tables: list[SignalTable]
    program: BridgeProgram
    lockstep: bool = False
    run: Run | None = None


class ExternalPlc:
    """The Modbus TCP or OPC UA server of ``machine``'s signal tables, serving from its own
    thread, and the bridge program that turns them into function-block calls on the viewer's
    scene.

    Args:
        machine: registry name of the machine it serves (the viewer's ``--scene``).
        host: interface to bind (Modbus: loopback unless ``allow`` names clients; OPC UA:
            beyond loopback encrypted sessions of user plc only, the password from
            MCL_OPCUA_PASSWORD).
        port: TCP port.
        allow: client addresses accepted beyond loopback.
        protocol: ``modbus`` or ``opcua``.

    Raises:
        ValueError: a host beyond loopback without ``allow`` (Modbus) or a password (OPC UA),
            or a bad address in ``allow``.
        OSError: the port cannot be served (taken, privileged).
    """

    def __init__(
        self,
        machine: str,
        host: str = "127.0.0.1",
        port: int = 5020,
        allow: Sequence[str] = (),
        protocol: Transport = "modbus",
    ) -> None:
        self.protocol = protocol
        self._security: opcua.Security | None = None
        if protocol == "opcua":
            from scenes.bridge import opcua

            self._security = opcua.security_of(host, allow)
        else:
            check_host(host, allow, "--modbus-allow")
        self.machine = machine
        self.tables: list[SignalTable] = tables_of(scenes.definition(machine))
        for table in self.tables:
            table.in_control = False
        what = (
            f"OPC UA opc.tcp://{host}:{port}"
            if protocol == "opcua"
            else f"Modbus TCP {host}:{port}"
        )
        self.label = f"external PLC ({what})"
        """The Program choice's entry."""
        self._address = (host, port)
        self._allow = tuple(allow)
        self._program: BridgeProgram | None = None
        self._commanding = False
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: Server | None = None
        self._ua: opcua.Server | None = None
        self._ua_stop: asyncio.Event | None = None
        self._started = threading.Event()
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._serve, name="external-plc", daemon=True)
        self._thread.start()
        self._started.wait(START_TIMEOUT)
        if self._error is not None:
            raise self._error
        if self._server is None and self._ua is None:
            raise OSError(f"the {what} server did not start")

    # ------------------------------------------------------------------------- server thread

    def _serve(self) -> None:
        try:
            asyncio.run(self._listen() if self.protocol == "modbus" else self._listen_opcua())
        except BaseException as error:  # reported to the constructor (it raises it)
            self._error = error
            self._started.set()

    async def _listen_opcua(self) -> None:
        from scenes.bridge import opcua

        self._loop = asyncio.get_running_loop()
        host, port = self._address
        opcua.quiet_asyncua()
        scene = scenes.load(self.machine, trace_every=0)  # for the axes' methods only
        served = _Served(
            scenes.definition(self.machine),
            self.tables,
            BridgeProgram(scene, self.tables, scenes.homing(scene)),
        )
        server = await opcua.server_of(
            served, host, port, self._allow, self._security, opcua.cache_dir()
        )
        opcua.quiet_asyncua()
        try:
            await server.start()
        except OSError as error:
            raise OSError(f"cannot serve OPC UA on {host}:{port} (is the port taken?)") from error
        self._ua_stop = asyncio.Event()
        self._ua = server
        self._started.set()
        try:
            await self._ua_stop.wait()
        finally:
            await server.stop()

    async def _listen(self) -> None:
        self._loop = asyncio.get_running_loop()
        server = Server([device(t) for t in self.tables], self._address, self._allow)
        try:
            await server.serve_forever(background=True)
        except RuntimeError as error:  # pymodbus: "Could not start listen"
            host, port = self._address
            text = f"cannot serve Modbus TCP on {host}:{port} (is the port taken?)"
            raise OSError(text) from error
        self._server = server
        self._started.set()
        await server.serving

    def close(self) -> None:
        """Stop the server (its connections close)."""
        loop, server, stop = self._loop, self._server, self._ua_stop
        if loop is None or not loop.is_running():
            return
        if server is not None:
            asyncio.run_coroutine_threadsafe(server.shutdown(), loop)
        elif stop is not None:
            loop.call_soon_threadsafe(stop.set)
        self._thread.join(2.0)

    @property
    def banner(self) -> str:
        """What the viewer prints at start: the entry and how the tables are addressed."""
        if self.protocol == "opcua":
            from scenes.bridge.opcua_nodes import NAMESPACE

            return f"{self.label}, namespace {NAMESPACE}"
        units = ", ".join(f"{t.unit_id} {t.machine}" for t in self.tables)
        return f"{self.label}, unit id {units}"

    @property
    def connections(self) -> int:
        """Clients connected now."""
        if self._server is not None:
            return len(self._server.active_connections)
        bserver = self._ua.bserver if self._ua is not None else None
        return len(bserver.clients) if bserver is not None else 0

    # ------------------------------------------------------------------------- simulation thread

    def serves(self, scene: Scene) -> bool:
        """Whether the server's tables are those of ``scene``'s machine."""
        return scene.name == self.machine

    def install(self, scene: Scene) -> None:
        """A scene was installed: a fresh bridge program on it if it is the served machine
        (else the status stands still and the PLC is refused until it is back)."""
        self._commanding = False
        for table in self.tables:
            table.in_control = False
        self._program = (
            BridgeProgram(scene, self.tables, scenes.homing(scene)) if self.serves(scene) else None
        )

    def program(self, scene: Scene) -> PlcInControl:
        """What Run demo runs when the external PLC is chosen."""
        if not self.serves(scene):
            raise ValueError(f"the external PLC serves {self.machine}, not {scene.name}")
        return PlcInControl(self)

    def scan(self, running: object) -> None:
        """One PLC cycle (after the demo's): the PLC commands while ``running``, the session's
        running program, is its :class:`PlcInControl`; the status is published either way."""
        program = self._program
        if program is None:
            return
        commanding = isinstance(running, PlcInControl) and running.plc is self
        if commanding != self._commanding:
            self._commanding = commanding
            for table in self.tables:
                table.in_control = commanding
        program()
        nodes = self._ua.bridge_nodes if self._ua is not None else None
        if nodes is not None and program.cycles % self._publish_every(program) == 0:
            nodes.published(program.cycles)  # the OPC UA variables follow

    @staticmethod
    def _publish_every(program: BridgeProgram) -> int:
        """PLC cycles between two refreshes of the OPC UA variables (10 ms of the machine)."""
        return max(1, round(CHUNK / program.scene.runtime.plc_period))

    @property
    def commanding(self) -> bool:
        """Whether the PLC commands the machine (as of the last PLC cycle)."""
        return self._commanding


class PlcInControl:
    """The running program while the external PLC is in control (a demo program to the
    session: it never ends by itself; the bridge program itself runs in :meth:`ExternalPlc.scan`).
    """

    def __init__(self, plc: ExternalPlc) -> None:
        self.plc = plc

    @property
    def done(self) -> bool:
        """Never: the PLC is in control until something takes it back."""
        return False

    @property
    def error(self) -> str:
        """No error of its own (the PLC's refused commands are in their status words)."""
        return ""

    @property
    def step(self) -> str:
        """Who commands, and how many clients are connected."""
        n = self.plc.connections
        clients = "no client connected" if n == 0 else f"{n} client{'s' * (n != 1)} connected"
        return f"the {self.plc.label} is in control; {clients}"

    def __call__(self) -> None:
        """Nothing of its own (see :meth:`ExternalPlc.scan`)."""

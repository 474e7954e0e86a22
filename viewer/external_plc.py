"""An external PLC in the viewer: the Modbus TCP server of the bridge (``--modbus PORT``) on the
machine the viewer shows, offered as one more entry of the Program choice.

The PLC commands the machine exactly while that entry is the running program: Run demo hands it
the machine (the operator hands power over, as to a demo), and whatever ends a demo — STOP all,
a Power button, End demo, another program, a reset — takes it back at the next PLC cycle. While
it is not in control the status stays live and its writes are refused (``sim.control`` 0,
Modbus exception DEVICE_BUSY), so one owner commands at a time and STOP all always works.
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Sequence

import scenes
from scenes.bridge.modbus import Server, device
from scenes.bridge.program import BridgeProgram
from scenes.bridge.serving import check_host
from scenes.bridge.table import SignalTable, tables_of
from scenes.scene import Scene

START_TIMEOUT = 5.0
"""Longest wall time [s] the server may take to listen."""


class ExternalPlc:
    """The Modbus TCP server of ``machine``'s signal tables, serving from its own thread, and
    the bridge program that turns them into function-block calls on the viewer's scene.

    Args:
        machine: registry name of the machine it serves (the viewer's ``--scene``).
        host: interface to bind (loopback unless ``allow`` names clients).
        port: TCP port.
        allow: client addresses accepted beyond loopback.

    Raises:
        ValueError: a host beyond loopback without ``allow``, or a bad address in it.
        OSError: the port cannot be served (taken, privileged).
    """

    def __init__(
        self, machine: str, host: str = "127.0.0.1", port: int = 5020, allow: Sequence[str] = ()
    ) -> None:
        check_host(host, allow, "--modbus-allow")
        self.machine = machine
        self.tables: list[SignalTable] = tables_of(scenes.definition(machine))
        for table in self.tables:
            table.in_control = False
        self.label = f"external PLC (Modbus TCP {host}:{port})"
        """The Program choice's entry."""
        self._address = (host, port)
        self._allow = tuple(allow)
        self._program: BridgeProgram | None = None
        self._commanding = False
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: Server | None = None
        self._started = threading.Event()
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._serve, name="external-plc", daemon=True)
        self._thread.start()
        self._started.wait(START_TIMEOUT)
        if self._error is not None:
            raise self._error
        if self._server is None:
            raise OSError(f"the Modbus server on {host}:{port} did not start")

    # ------------------------------------------------------------------------- server thread

    def _serve(self) -> None:
        try:
            asyncio.run(self._listen())
        except BaseException as error:  # reported to the constructor (it raises it)
            self._error = error
            self._started.set()

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
        loop, server = self._loop, self._server
        if loop is not None and server is not None and loop.is_running():
            asyncio.run_coroutine_threadsafe(server.shutdown(), loop)
            self._thread.join(2.0)

    @property
    def connections(self) -> int:
        """Clients connected now."""
        server = self._server
        return len(server.active_connections) if server is not None else 0

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

"""The OPC UA server in its own process as asyncua clients written from docs/bridge.md meet it:
a control-word command after a method call is taken; each command has its number
(``command_count``), so a repeated call is never judged by the previous Done; a called stop
ends when the next command comes, and that command is taken; a client's
keep-alive is answered during a long Advance in lockstep; a channel with a security mode the
server has no endpoint for is refused at once; idle TCP connections do not lock clients out."""

from __future__ import annotations

import asyncio
import socket
import time
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from asyncua import Client, ua
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from asyncua.crypto.security_policies import SecurityPolicyBasic256Sha256
from cryptography.x509.oid import ExtendedKeyUsageOID

import mcl
from scenes.bridge.opcua_nodes import MAX_ADVANCE
from scenes.bridge.table import CONTROL_BITS
from tests.bridge_clients import NAMESPACE, opcua_server

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

D = ua.VariantType.Double
MOVE_RELATIVE = CONTROL_BITS.index("move_relative") + 1


class Axis:
    """A client's handles on an axis, as the docs' example has them."""

    def __init__(self, client: Client, ns: int, name: str) -> None:
        self.client, self.ns, self.name = client, ns, name

    def node(self, field: str) -> Any:
        return self.client.get_node(f"ns={self.ns};s={self.name}.{field}")

    async def value(self, field: str) -> Any:
        return await self.node(field).read_value()

    async def call(self, method: str, *args: ua.Variant) -> None:
        node = self.client.get_node(f"ns={self.ns};s={self.name}")
        await node.call_method(f"{self.ns}:{method}", *args)

    async def done_after(self, count: int, seconds: float = 5.0) -> None:
        """Wait until a command after number ``count`` is Done (docs: judge a command once
        ``command_count`` has passed the count read before it)."""
        await until(lambda: self._done_after(count), seconds, f"{self.name}: command after {count}")

    async def at(self, position: float) -> bool:
        """The axis stands at ``position`` [mm]."""
        actual = await self.value("actual_position")
        return abs(actual - position) < 0.02 and abs(await self.value("actual_velocity")) < 0.5

    async def _done_after(self, count: int) -> bool:
        return await self.value("command_count") != count and bool(await self.value("status.done"))


async def until(condition: Callable[[], Awaitable[bool]], seconds: float, what: str) -> None:
    deadline = time.monotonic() + seconds
    while not await condition():
        assert time.monotonic() < deadline, f"{what}: not within {seconds} s"
        await asyncio.sleep(0.02)


def relative(distance: float) -> list[ua.Variant]:
    """MC_MoveRelative's arguments: Distance, 200 mm/s, 2000 mm/s², 2000 mm/s², Jerk 0,
    Aborting."""
    ramp = [ua.Variant(v, D) for v in (distance, 200.0, 2000.0, 2000.0, 0.0)]
    return [*ramp, ua.Variant(0, ua.VariantType.UInt16)]


def test_a_control_word_command_after_a_method_call_is_taken(tmp_path: Path) -> None:
    """MC_MoveRelative(20 mm), then the control word with move_relative and 30 mm: X moves on
    by 30 mm (measured at the actual position)."""

    async def body(port: int) -> None:
        async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
            x = Axis(client, await client.get_namespace_index(NAMESPACE), "X")
            await x.call("MC_Power", ua.Variant(True, ua.VariantType.Boolean))
            await until(lambda: x.value("status.power"), 5.0, "power")
            start = await x.value("actual_position")
            await x.call("MC_MoveRelative", *relative(20.0))
            await until(lambda: x.at(start + 20.0), 5.0, "the first move")
            await client.write_values(
                [x.node("distance"), x.node("control")],
                [ua.Variant(30.0, D), ua.Variant(9, ua.VariantType.UInt16)],  # enable, move
            )
            await until(lambda: x.at(start + 50.0), 5.0, "the move of the control word")
            assert await x.value("command") == MOVE_RELATIVE

    with opcua_server("gantry", tmp_path / "stderr.txt") as port:
        asyncio.run(body(port))


def test_each_command_has_its_number(tmp_path: Path) -> None:
    """Commands by method and by control word, each judged once ``command_count`` has passed
    the number read before it: the Done judged is always the new command's (the same call
    again included), measured at the actual position."""

    async def body(port: int) -> None:
        async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
            x = Axis(client, await client.get_namespace_index(NAMESPACE), "X")
            await x.call("MC_Power", ua.Variant(True, ua.VariantType.Boolean))
            await until(lambda: x.value("status.power"), 5.0, "power")
            start = await x.value("actual_position")
            count = await x.value("command_count")
            await x.call("MC_MoveRelative", *relative(20.0))
            await x.done_after(count)
            assert await x.value("actual_position") == pytest.approx(start + 20.0, abs=0.02)
            count = await x.value("command_count")  # a command word after the call
            await client.write_values(
                [x.node("distance"), x.node("control")],
                [ua.Variant(30.0, D), ua.Variant(9, ua.VariantType.UInt16)],
            )
            await x.done_after(count)
            assert await x.value("actual_position") == pytest.approx(start + 50.0, abs=0.02)
            for k in range(3):  # the same call again (the control word's bit still set)
                count = await x.value("command_count")
                await x.call("MC_MoveRelative", *relative(20.0))
                await x.done_after(count)
                expected = start + 70.0 + 20.0 * k
                assert await x.value("actual_position") == pytest.approx(expected, abs=0.02)
            assert await x.value("command_count") == count + 1

    with opcua_server("gantry", tmp_path / "stderr.txt") as port:
        asyncio.run(body(port))


def test_a_called_stop_ends_when_the_next_command_comes(tmp_path: Path) -> None:
    """MC_Stop called on a velocity move: Done, and the axis held in Stopping (its Execute
    stays set) until the next command; then a call of MC_MoveRelative and, after another
    MC_Stop, a move of the control word are taken (no EAxStop): X moves by 20 and by 30 mm,
    measured at the actual position."""

    async def stopped(x: Axis) -> None:
        count = await x.value("command_count")
        velocity = [ua.Variant(v, D) for v in (50.0, 1000.0, 1000.0, 0.0)]
        positive = ua.Variant(int(mcl.MC_Direction.MC_Positive), ua.VariantType.Int32)
        await x.call("MC_MoveVelocity", *velocity, positive, ua.Variant(0, ua.VariantType.UInt16))
        await until(lambda: x.value("status.in_velocity"), 5.0, "at velocity")
        await x.call("MC_Stop", ua.Variant(0.0, D), ua.Variant(0.0, D))
        await x.done_after(count + 1)
        await asyncio.sleep(0.1)
        assert await x.value("state") == mcl.AxisState.Stopping  # until Done AND NOT Execute

    async def body(port: int) -> None:
        async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
            x = Axis(client, await client.get_namespace_index(NAMESPACE), "X")
            await x.call("MC_Power", ua.Variant(True, ua.VariantType.Boolean))
            await until(lambda: x.value("status.power"), 5.0, "power")
            await stopped(x)
            start = await x.value("actual_position")
            count = await x.value("command_count")
            await x.call("MC_MoveRelative", *relative(20.0))
            await x.done_after(count)
            assert await x.value("error_id") == 0
            assert await x.value("actual_position") == pytest.approx(start + 20.0, abs=0.02)
            await stopped(x)
            start = await x.value("actual_position")
            count = await x.value("command_count")
            await client.write_values(
                [x.node("distance"), x.node("control")],
                [ua.Variant(30.0, D), ua.Variant(9, ua.VariantType.UInt16)],  # enable, move
            )
            await x.done_after(count)
            assert await x.value("error_id") == 0
            assert await x.value("actual_position") == pytest.approx(start + 30.0, abs=0.02)

    with opcua_server("gantry", tmp_path / "stderr.txt") as port:
        asyncio.run(body(port))


def test_the_keep_alive_is_answered_during_a_long_advance(tmp_path: Path) -> None:
    """asyncua's client probes the server every second and drops the session when a probe
    is not answered within a second; an Advance answered after 2 s must not cost it."""

    async def body(port: int) -> None:
        lost: list[Exception] = []

        async def on_lost(error: Exception) -> None:
            lost.append(error)

        client = Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10)
        client.connection_lost_callback = on_lost
        async with client:
            ns = await client.get_namespace_index(NAMESPACE)
            sim = client.get_node(f"ns={ns};s=sim")
            started = time.monotonic()
            cycle = await sim.call_method(
                f"{ns}:Advance", ua.Variant(MAX_ADVANCE, ua.VariantType.UInt32)
            )
            assert time.monotonic() - started > 1.5  # longer than a probe waits
            assert 0 <= cycle < MAX_ADVANCE  # answered after 2 s, the step not yet done
            await asyncio.sleep(1.5)  # the next probes
            assert not lost
            assert await client.get_node(f"ns={ns};s=sim.cycle").read_value() >= cycle

    with opcua_server("gantry", tmp_path / "stderr.txt", "--lockstep") as port:
        asyncio.run(body(port))


def test_a_channel_without_a_matching_endpoint_is_refused_at_once(tmp_path: Path) -> None:
    """A secure server offers SignAndEncrypt only: a client asking for Sign (its own pick, the
    server's certificate at hand) is answered BadSecurityModeRejected, not left waiting."""
    password = tmp_path / "password"
    password.write_text("s3cret-for-the-test\n")
    password.chmod(0o600)
    certs = tmp_path / "certs"
    key, cert = tmp_path / "client-key.pem", tmp_path / "client-cert.der"
    uri = "urn:mcl-testbench:test-client"
    asyncio.run(
        setup_self_signed_certificate(
            key, cert, uri, "localhost", [ExtendedKeyUsageOID.CLIENT_AUTH], {"commonName": "t"}
        )
    )

    async def attempt(port: int, mode: ua.MessageSecurityMode) -> str:
        client = Client(f"opc.tcp://127.0.0.1:{port}/", timeout=5)
        client.application_uri = uri
        client.set_user("plc")
        client.set_password("s3cret-for-the-test")
        server_cert = str(certs / "server-cert.der")
        await client.set_security(
            SecurityPolicyBasic256Sha256, str(cert), str(key), server_certificate=server_cert,
            mode=mode,
        )  # fmt: skip
        try:
            await client.connect()
        except Exception as error:
            return type(error).__name__
        await client.disconnect()
        return "ok"

    options = ["--secure", "--password-file", str(password), "--certs", str(certs)]
    with opcua_server("gantry", tmp_path / "stderr.txt", *options) as port:
        started = time.monotonic()
        assert asyncio.run(attempt(port, ua.MessageSecurityMode.Sign)) == "BadSecurityModeRejected"
        assert time.monotonic() - started < 3.0  # at once, not after the client's timeout
        assert asyncio.run(attempt(port, ua.MessageSecurityMode.SignAndEncrypt)) == "ok"


def test_idle_connections_do_not_lock_clients_out(tmp_path: Path) -> None:
    """Eight TCP connections that say nothing fill the server's eight places; a client still
    gets in at once (the oldest idle one gives way)."""

    async def read_time(port: int) -> float:
        async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=3) as client:
            ns = await client.get_namespace_index(NAMESPACE)
            return float(await client.get_node(f"ns={ns};s=sim.time").read_value())

    with opcua_server("gantry", tmp_path / "stderr.txt", "--lockstep") as port:
        idle = [socket.create_connection(("127.0.0.1", port), timeout=5) for _ in range(8)]
        try:
            time.sleep(0.3)
            started = time.monotonic()
            assert asyncio.run(read_time(port)) == 0.0
            assert time.monotonic() - started < 3.0
        finally:
            for connection in idle:
                connection.close()

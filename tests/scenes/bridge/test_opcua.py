"""The OPC UA server in its own process, driven by asyncua clients: the gantry's X axis powered,
homed and moved to 300 mm through the PLCopen methods (read back from the actual position the
physics gives), a move beyond the software limit refused with its ErrorID, reset; a subscription
sees X move; the press and the flying shear over OPC UA in lockstep as in-process, to the bit;
refused writes and calls answered with Bad status codes, 10 000 random requests, a client that
vanishes, while the server and the machine stay up; beyond loopback only encrypted sessions of
the user with the password."""

from __future__ import annotations

import asyncio
import math
import random
import socket
import subprocess
import sys
import time
from collections.abc import Awaitable, Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from asyncua import Client, Node, ua
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from asyncua.crypto.security_policies import SecurityPolicyBasic256Sha256
from cryptography.x509.oid import ExtendedKeyUsageOID

import mcl
import scenes
from scenes.bridge.table import CONTROL_BITS, SignalTable
from scenes.tools import cli
from tests.bridge_clients import (
    NAMESPACE,
    PRESS_FORCE,
    InProcess,
    OpcuaLockstep,
    free_port,
    gantry_lockstep,
    opcua_client,
    opcua_server,
    press_holds,
    shear_cuts,
)
from tests.helpers import ROOT

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

TABLE = SignalTable(scenes.definition("gantry"))
D = ua.VariantType.Double


def run(coroutine: Awaitable[Any]) -> Any:
    return asyncio.run(coroutine)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def free_log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where the free-running server logs."""
    return tmp_path_factory.mktemp("opcua") / "stderr.txt"


@pytest.fixture(scope="module")
def free_server(free_log: Path) -> Iterator[int]:
    """A free-running gantry server (at 2× real time) shared by the tests of this module that
    use it, in their order (the fuzz test last); its port."""
    with opcua_server("gantry", free_log, "--speed", "2") as port:
        yield port


class Gantry:
    """An asyncua client's handles on the gantry's nodes."""

    def __init__(self, client: Client, ns: int) -> None:
        self.client, self.ns = client, ns

    def node(self, name: str) -> Node:
        return self.client.get_node(f"ns={self.ns};s={name}")

    async def value(self, name: str) -> Any:
        return await self.node(name).read_value()

    async def call(self, axis: str, method: str, *args: ua.Variant) -> Any:
        return await self.node(axis).call_method(f"{self.ns}:{method}", *args)

    async def until(self, condition: Callable[[], Awaitable[bool]], seconds: float) -> None:
        deadline = time.monotonic() + seconds
        while not await condition():
            assert time.monotonic() < deadline, "condition not met in time"
            await asyncio.sleep(0.02)

    async def finished(self, axis: str, command: str) -> bool:
        """``command`` is the axis' current one and Done."""
        current = await self.value(f"{axis}.command")
        return current == CONTROL_BITS.index(command) + 1 and bool(
            await self.value(f"{axis}.status.done")
        )

    async def move(self, axis: str, position: float) -> None:
        """MC_MoveAbsolute(Position, 200 mm/s, 1000 mm/s², 1000 mm/s², Jerk 0, Aborting)."""
        ramp = [ua.Variant(v, D) for v in (position, 200.0, 1000.0, 1000.0, 0.0)]
        await self.call(axis, "MC_MoveAbsolute", *ramp, ua.Variant(0, ua.VariantType.UInt16))


async def connected(port: int, body: Callable[[Gantry], Awaitable[Any]]) -> Any:
    async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
        return await body(Gantry(client, await client.get_namespace_index(NAMESPACE)))


class Changes:
    """A subscription's handler: the values of its data change notifications."""

    def __init__(self) -> None:
        self.values: list[float] = []

    def datachange_notification(self, node: Node, value: float, data: Any) -> None:
        self.values.append(value)


def test_power_home_move_to_300_mm_limit_and_reset(free_server: int) -> None:
    async def body(g: Gantry) -> None:
        await g.call("X", "MC_Power", ua.Variant(True, ua.VariantType.Boolean))
        await g.until(lambda: g.value("X.status.power"), 5.0)
        await g.call("X", "MC_Home")
        await g.until(lambda: g.finished("X", "home"), 30.0)
        assert await g.value("X.status.homed")
        changes = Changes()
        subscription = await g.client.create_subscription(20, changes)
        await subscription.subscribe_data_change(g.node("X.actual_position"))
        await asyncio.sleep(0.5)  # standing at the index (120 mm): the encoder may flip a count
        start = await g.value("X.actual_position")
        await g.move("X", 300.0)
        await g.until(lambda: g.finished("X", "move_absolute"), 15.0)
        assert await g.value("X.actual_position") == pytest.approx(300.0, abs=0.02)
        assert await g.value("sim.time") > 3.0
        await asyncio.sleep(0.1)
        await subscription.delete()
        moving = [v for v in changes.values if start + 1.0 < v < 299.0]  # not standing
        assert len(moving) > 15  # notified all along the move (0.75 s wall at 20 ms)
        assert moving == sorted(moving)
        assert changes.values[-1] == pytest.approx(300.0, abs=0.02)
        await g.move("X", 5000.0)  # beyond the software limit
        await g.until(lambda: g.value("X.status.error"), 2.0)
        assert await g.value("X.error_id") == 8
        assert await g.value("X.actual_position") == pytest.approx(300.0, abs=0.02)
        await g.call("X", "MC_Reset")
        await g.until(lambda: g.finished("X", "reset"), 2.0)
        assert not await g.value("X.status.error")

    run(connected(free_server, body))


def test_the_example_client_homes_and_moves_the_gantry(free_server: int) -> None:
    example = ROOT / "examples" / "bridge_opcua_client.py"
    command = [sys.executable, str(example), "--port", str(free_server), "--position", "250"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert abs(float(result.stdout.split()[2]) - 250.0) < 0.02  # "X at 250.001 mm"


def bad(status: ua.StatusCode | None, code: int) -> bool:
    return status is not None and status.value == code


def test_refused_writes_and_calls_leave_the_server_and_the_axis_alone(free_server: int) -> None:
    codes = ua.StatusCodes

    async def body(g: Gantry) -> None:
        await g.call("X", "MC_Power", ua.Variant(True, ua.VariantType.Boolean))
        await g.until(lambda: g.value("X.status.power"), 5.0)
        before = await g.value("X.position")

        async def write(name: str, variant: ua.Variant) -> ua.StatusCode:
            nodeid = g.node(name).nodeid
            return (await g.client.uaclient.write_attributes([nodeid], [ua.DataValue(variant)]))[0]

        assert bad(await write("X.nothing", ua.Variant(1.0, D)), codes.BadNodeIdUnknown)
        assert bad(
            await write("X.position", ua.Variant("300", ua.VariantType.String)),
            codes.BadTypeMismatch,
        )
        assert bad(await write("X.position", ua.Variant(True)), codes.BadTypeMismatch)
        assert bad(await write("X.position", ua.Variant([1.0, 2.0], D)), codes.BadTypeMismatch)
        assert bad(await write("X.position", ua.Variant(math.nan, D)), codes.BadOutOfRange)
        assert bad(await write("X.position", ua.Variant(math.inf, D)), codes.BadOutOfRange)
        assert bad(await write("X.position", ua.Variant(1e39, D)), codes.BadOutOfRange)
        assert bad(
            await write("X.buffer_mode", ua.Variant(70000, ua.VariantType.Int32)),
            codes.BadOutOfRange,
        )
        assert bad(await write("X.buffer_mode", ua.Variant(1.5, D)), codes.BadOutOfRange)
        assert bad(await write("X.actual_position", ua.Variant(0.0, D)), codes.BadNotWritable)
        assert bad(await write("X.status.done", ua.Variant(True)), codes.BadNotWritable)
        read = await g.client.uaclient.read_attributes(
            [g.node("X.nothing").nodeid], ua.AttributeIds.Value
        )
        assert bad(read[0].StatusCode, codes.BadNodeIdUnknown)
        assert await g.value("X.position") == before

        async def call(method: str, *args: ua.Variant) -> ua.CallMethodResult:
            request = ua.CallMethodRequest(
                ObjectId=g.node("X").nodeid,
                MethodId=g.node(f"X.{method}").nodeid,
                InputArguments=list(args),
            )
            return (await g.client.uaclient.call([request]))[0]

        result = await call("MC_MoveAbsolute", ua.Variant(math.nan, D))
        assert bad(result.StatusCode, codes.BadArgumentsMissing)
        nan_move = [ua.Variant(v, D) for v in (math.nan, 200.0, 1000.0, 1000.0, 0.0)]
        result = await call("MC_MoveAbsolute", *nan_move, ua.Variant(0, ua.VariantType.UInt16))
        assert bad(result.StatusCode, codes.BadInvalidArgument)
        assert bad(result.InputArgumentResults[0], codes.BadOutOfRange)
        assert result.InputArgumentResults[1].is_good()
        result = await call("MC_Power", ua.Variant(1, ua.VariantType.Int32))
        assert bad(result.InputArgumentResults[0], codes.BadTypeMismatch)
        result = await call("MC_Reset", ua.Variant(1.0, D))
        assert bad(result.StatusCode, codes.BadTooManyArguments)
        gear = [ua.Variant("Q", ua.VariantType.String), *[ua.Variant(1, ua.VariantType.Int16)] * 2]
        result = await call("MC_GearIn", *gear, *[ua.Variant(1.0, D)] * 3)
        assert bad(result.InputArgumentResults[0], codes.BadOutOfRange)  # no axis Q
        result = await call("MC_Nothing")
        assert result.StatusCode.is_bad()
        result = await call("MC_Reset")
        assert result.StatusCode.is_good()
        # a velocity the block refuses is taken by the table and refused by MC_MoveAbsolute
        position = await g.value("X.actual_position")
        ramp = [ua.Variant(v, D) for v in (position + 50.0, -5.0, 1000.0, 1000.0, 0.0)]
        await g.call("X", "MC_MoveAbsolute", *ramp, ua.Variant(0, ua.VariantType.UInt16))
        await g.until(lambda: g.value("X.status.error"), 2.0)
        assert await g.value("X.error_id") == mcl.ErrorID.EParam
        assert await g.value("X.actual_position") == pytest.approx(position, abs=0.02)
        # writes faster than the scan: 200 targets in 200 requests; the last one counts
        for k in range(200):
            assert (await write("X.position", ua.Variant(100.0 + k, D))).is_good()
        assert await g.value("X.position") == 299.0
        await g.call("X", "MC_Reset")
        await g.until(lambda: g.finished("X", "reset"), 2.0)

    run(connected(free_server, body))


def random_variant(rng: random.Random) -> ua.Variant:
    kind = rng.randrange(8)
    if kind == 0:
        return ua.Variant(rng.choice([math.nan, math.inf, -math.inf, 1e300, -0.0]), D)
    if kind == 1:
        return ua.Variant(rng.uniform(-1e4, 1e4), D)
    if kind == 2:
        return ua.Variant(rng.randrange(-(2**31), 2**31), ua.VariantType.Int32)
    if kind == 3:
        return ua.Variant(rng.randrange(0, 2**16), ua.VariantType.UInt16)
    if kind == 4:
        return ua.Variant(rng.random() < 0.5, ua.VariantType.Boolean)
    if kind == 5:
        return ua.Variant(rng.choice(["X", "Y", "", "Ω" * 50]), ua.VariantType.String)
    if kind == 6:
        return ua.Variant([rng.random() for _ in range(3)], D)
    return ua.Variant(None)


def random_request(g: Gantry, rng: random.Random, names: list[str]) -> tuple[str, Any]:
    """A random read, write or method call of a random node (now and then an unknown one)."""
    axis = rng.choice([*TABLE.axes, "Q"])
    what = rng.randrange(3)
    if what == 2:
        method = rng.choice(
            ["MC_Power", "MC_Reset", "MC_MoveAbsolute", "MC_MoveRelative", "MC_MoveVelocity",
             "MC_Home", "MC_Stop", "MC_Halt", "GT_Jog", "MC_GearIn", "MC_GearInPos",
             "MC_GearOut", "MC_Nothing"]
        )  # fmt: skip
        args = [random_variant(rng) for _ in range(rng.randrange(8))]
        return "call", ua.CallMethodRequest(
            ObjectId=g.node(axis).nodeid,
            MethodId=g.node(f"{axis}.{method}").nodeid,
            InputArguments=args,
        )
    name = rng.choice(names) if rng.random() < 0.9 else f"{axis}.nothing{rng.randrange(9)}"
    return ("read" if what == 0 else "write"), g.node(name).nodeid


def test_ten_thousand_random_requests_and_a_vanishing_client(
    free_server: int, free_log: Path
) -> None:
    names = [f.name for f in TABLE.fields] + [f"X.status.{b}" for b in ("done", "error")]

    async def fuzz(g: Gantry) -> int:
        rng = random.Random(23)
        statuses: list[ua.StatusCode] = []
        uaclient = g.client.uaclient
        for _ in range(100):  # 100 batches of 100 requests, each batch one request per service
            batch = [random_request(g, rng, names) for _ in range(100)]
            reads = [n for what, n in batch if what == "read"]
            writes = [n for what, n in batch if what == "write"]
            calls = [c for what, c in batch if what == "call"]
            if reads:
                values = await uaclient.read_attributes(reads, ua.AttributeIds.Value)
                statuses += [v.StatusCode or ua.StatusCode() for v in values]
            if writes:
                data = [ua.DataValue(random_variant(rng)) for _ in writes]
                statuses += await uaclient.write_attributes(writes, data, ua.AttributeIds.Value)
            if calls:
                statuses += [r.StatusCode for r in await uaclient.call(calls)]
        internal = ua.StatusCodes.BadInternalError
        assert not [s for s in statuses if s.value == internal]  # every one judged, none failed
        assert 1000 < sum(s.is_bad() for s in statuses) < 9000  # many refused, many taken
        return len(statuses)

    async def vanish(port: int) -> None:
        """A client that opens a session and disappears without closing it, and raw
        connections that send a fragment of a frame and close."""
        client = Client(f"opc.tcp://127.0.0.1:{port}/", timeout=5)
        await client.connect()
        client.uaclient.protocol.transport.abort()  # type: ignore[union-attr]
        for frame in (b"HEL", b"HELF\xff\xff\xff\xff" + b"\x00" * 32, b"\x00" * 100):
            with socket.create_connection(("127.0.0.1", port), timeout=2) as raw:
                raw.sendall(frame)

    async def still_runs(g: Gantry) -> None:
        before = await g.value("sim.time")
        await asyncio.sleep(0.2)
        assert await g.value("sim.time") > before  # the machine still runs
        for axis in TABLE.axes:  # and stands within its travel, its values finite
            position = await g.value(f"{axis}.actual_position")
            assert math.isfinite(position) and -50.0 < position < 1100.0

    assert run(connected(free_server, fuzz)) == 10_000
    run(vanish(free_server))
    run(connected(free_server, still_runs))
    assert "Error while processing" not in free_log.read_text()


def test_lockstep_equals_in_process_bit_for_bit(tmp_path: Path) -> None:
    reference = gantry_lockstep(InProcess("gantry", by_name=True))
    log = tmp_path / "stderr.txt"
    with opcua_server("gantry", log, "--lockstep") as port, opcua_client(port) as client:
        trace = gantry_lockstep(OpcuaLockstep("gantry", client), random.Random(5))
    assert [[v.hex() for v in step] for step in trace] == [
        [v.hex() for v in step] for step in reference
    ]
    assert reference[-1][0] == pytest.approx(300.0, abs=0.02)  # X.actual_position


@pytest.mark.parametrize("machine", ["flying_shear", "press"])
def test_the_machines_over_opcua_in_lockstep_as_in_process(machine: str, tmp_path: Path) -> None:
    """The shear cuts through its knife output and the press holds its force over OPC UA in
    lockstep: the same pieces and forces as in-process, to the bit."""

    def scenario(plc: InProcess | OpcuaLockstep) -> list[float]:
        return shear_cuts(plc, 1) if machine == "flying_shear" else press_holds(plc, 0.1)

    reference = scenario(InProcess(machine, by_name=True))
    log = tmp_path / "stderr.txt"
    with opcua_server(machine, log, "--lockstep") as port, opcua_client(port) as client:
        assert scenario(OpcuaLockstep(machine, client)) == reference
    if machine == "press":
        assert all(abs(f - PRESS_FORCE) < 1.0 for f in reference)  # the load cell
    else:
        assert reference[0] == pytest.approx(1500.0, abs=5.0)  # the piece cut


def own_address() -> str | None:
    """This machine's address beyond loopback (None: it has none)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.connect(("198.51.100.1", 9))  # no packet is sent: the route gives the address
            host = str(s.getsockname()[0])
        except OSError:
            return None
    return None if host.startswith("127.") else host


def test_beyond_loopback_only_encrypted_sessions_of_the_user(tmp_path: Path) -> None:
    host = own_address() or "0.0.0.0"
    reach = host if host != "0.0.0.0" else "127.0.0.1"
    password = tmp_path / "password"
    password.write_text("s3cret-for-the-test\n")
    password.chmod(0o600)
    certs = tmp_path / "certs"
    options = ["--host", host, "--password-file", str(password), "--certs", str(certs)]
    key, cert = tmp_path / "client-key.pem", tmp_path / "client-cert.der"
    uri = "urn:mcl-testbench:test-client"
    run(
        setup_self_signed_certificate(
            key, cert, uri, "localhost", [ExtendedKeyUsageOID.CLIENT_AUTH], {"commonName": "test"}
        )
    )

    async def attempt(port: int, user: str | None, secret: str, secure: bool) -> str:
        """``ok`` when a session reads a value, else the Bad status the server answered."""
        client = Client(f"opc.tcp://{reach}:{port}/", timeout=5)
        client.application_uri = uri
        if user is not None:
            client.set_user(user)
            client.set_password(secret)
        if secure:
            mode = ua.MessageSecurityMode.SignAndEncrypt
            await client.set_security(SecurityPolicyBasic256Sha256, str(cert), str(key), mode=mode)
        try:
            await client.connect()
        except ua.UaStatusCodeError as error:
            return type(error).__name__
        try:
            ns = await client.get_namespace_index(NAMESPACE)
            value = await client.get_node(f"ns={ns};s=sim.time").read_value()
            return "ok" if value >= 0.0 else "no time"
        finally:
            await client.disconnect()

    with opcua_server("gantry", tmp_path / "stderr.txt", *options) as port:
        assert certs.stat().st_mode & 0o777 == 0o700
        assert (certs / "server-key.pem").stat().st_mode & 0o777 == 0o600
        refused = "BadSecurityModeRejected"
        assert run(attempt(port, None, "", False)) == refused  # anonymous, no security
        assert run(attempt(port, "plc", "s3cret-for-the-test", False)) == refused  # in the clear
        assert run(attempt(port, None, "", True)) == "BadIdentityTokenRejected"  # anonymous
        assert run(attempt(port, "plc", "wrong", True)) == "BadUserAccessDenied"
        assert run(attempt(port, "plc", "s3cret-for-the-test", True)) == "ok"


@pytest.mark.parametrize(
    "options, message",
    [
        (["--host", "0.0.0.0"], "needs the password of user 'plc'"),
        (["--host", "0.0.0.0", "--password-file", "{loose}"], "expected mode 600"),
        (["--allow", "somewhere"], "--allow takes IP addresses"),
        (["--secure", "--password-file", "{tight}", "--certs", "{open}"], "expected mode 700"),
    ],
)
def test_a_refused_security_setting_is_one_line(
    options: list[str],
    message: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    for name, mode in (("loose", 0o644), ("tight", 0o600)):
        (tmp_path / name).write_text("pw\n")
        (tmp_path / name).chmod(mode)
    (tmp_path / "open").mkdir(mode=0o755)
    (tmp_path / "open").chmod(0o755)
    names = ("loose", "tight", "open")
    args = [o.format(**{n: str(tmp_path / n) for n in names}) for o in options]
    monkeypatch.delenv("MCL_OPCUA_PASSWORD", raising=False)
    assert cli.main(["bridge", "opcua", "gantry", *args]) == 2
    stderr = capsys.readouterr().err
    assert message in stderr and len(stderr.strip().splitlines()) == 1


def test_a_group_readable_password_file_is_refused(tmp_path: Path) -> None:
    """Mode 640 lets the file's group read the password: the server does not start (one line
    on standard error, exit status 2)."""
    password = tmp_path / "password"
    password.write_text("s3cret-for-the-test\n")
    password.chmod(0o640)
    command = [sys.executable, "-m", "scenes", "bridge", "opcua", "gantry", "--host", "0.0.0.0"]
    options = ["--port", str(free_port()), "--password-file", str(password)]
    options += ["--certs", str(tmp_path / "certs")]
    try:
        done = subprocess.run([*command, *options], capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("the server started with a group-readable password file")
    assert done.returncode == 2
    assert "others may read or write it (mode 640)" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1

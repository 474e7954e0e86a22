"""The OPC UA server of the bridge (asyncua 2.1): a machine's signal tables as a node tree
(:mod:`scenes.bridge.opcua_nodes`: variables of the fields, PLCopen methods of the axes, the
Simulation object), the simulation running in its own thread, free at a speed or in lockstep
with the client (:mod:`scenes.bridge.runs`). The same tables, blocks, rules and ErrorIDs as
the Modbus server's (:mod:`scenes.bridge.modbus`).

Security: the server binds loopback and serves it without security (anonymous, no encryption),
as the Modbus server does. On another address — or on loopback with ``secure`` — only encrypted
sessions of the user :data:`USER` are served: endpoints Basic256Sha256 and Aes256Sha256RsaPss,
SignAndEncrypt only; no anonymous session, none without encryption; the password from a file
only its owner may read (``--password-file``) or from the environment variable
:data:`PASSWORD_ENV`; a self-signed server certificate made on the first start in ``certs``, a
directory only its owner may enter. A client's certificate is accepted as it comes (the password
says who may command). ``allow`` (optional) restricts the client addresses further: every other
connection is closed at once.

Bounded: at most :data:`MAX_CONNECTIONS` connections (when all are taken, the oldest one without
an activated session gives way to a new one) and :data:`MAX_SUBSCRIPTIONS` subscriptions,
messages of :data:`MAX_MESSAGE` bytes; a session must be activated within :data:`ACTIVATION` s.
A secure channel the server has no endpoint for is refused at once (BadSecurityModeRejected,
BadSecurityPolicyRejected); while a write or call waits for the scene (lockstep), the
connection's reads are answered (:class:`_Processor`).
"""

from __future__ import annotations

__all__ = [
    "ACTIVATION",
    "APPLICATION_URI",
    "CERTS",
    "IN_TURN",
    "MAX_CONNECTIONS",
    "MAX_MESSAGE",
    "MAX_SUBSCRIPTIONS",
    "PASSWORD_ENV",
    "READ",
    "SECURE_POLICIES",
    "SESSION_REQUESTS",
    "USER",
    "PasswordUser",
    "Security",
    "Server",
    "cache_dir",
    "certificate",
    "check_certs",
    "init",
    "main",
    "quiet_asyncua",
    "read_password",
    "security_of",
    "serve",
    "server_of",
]

import asyncio
import contextlib
import fcntl
import hmac
import logging
import os
import socket
import stat
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

from asyncua import Server as UaServer
from asyncua import ua
from asyncua.common.connection import TransportLimits
from asyncua.common.utils import ServiceError
from asyncua.crypto import uacrypto
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.binary_server_asyncio import BinaryServer, OPCUAProtocol
from asyncua.server.internal_server import InternalServer
from asyncua.server.uaprocessor import UaProcessor
from asyncua.server.user_managers import UserManager
from asyncua.ua.ua_binary import nodeid_from_binary, uatcp_to_binary
from cryptography.x509.oid import ExtendedKeyUsageOID

from scenes.bridge.machine import Bridge, check_speed
from scenes.bridge.opcua_nodes import BridgeNodes, Served
from scenes.bridge.serving import (
    admitted,
    allowed,
    check_allow,
    is_loopback,
    run_command,
    stop_on_signals,
)

log = logging.getLogger(__name__)

USER = "plc"
"""The user of a secure session."""
PASSWORD_ENV = "MCL_OPCUA_PASSWORD"
"""The environment variable with the user's password."""
APPLICATION_URI = "urn:mcl-testbench:bridge"
"""The server's application URI (in its certificate)."""
CERTS = Path.home() / ".mcl-testbench" / "opcua"
"""Where the server's key and certificate are made and kept by default."""

SECURE_POLICIES = (
    ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt,
    ua.SecurityPolicyType.Aes256Sha256RsaPss_SignAndEncrypt,
)
"""The endpoints of a secure server."""

MAX_CONNECTIONS = 8
"""Connections served at once (more are closed at once)."""
MAX_SUBSCRIPTIONS = 32
"""Subscriptions of all sessions together."""
MAX_MESSAGE = 4 * 1024 * 1024
"""Largest message [bytes] the server takes."""
ACTIVATION = 10.0
"""A connection without an activated session after this long [s] is closed."""


@dataclass(frozen=True)
class Security:
    """How the server is reached: ``password`` (None: loopback without security) and the
    directory of its certificate."""

    password: str | None = None
    certs: Path = CERTS

    @property
    def secure(self) -> bool:
        """Encrypted sessions of :data:`USER` only."""
        return self.password is not None

    @property
    def policies(self) -> list[ua.SecurityPolicyType]:
        """The endpoints' security policies."""
        return list(SECURE_POLICIES) if self.secure else [ua.SecurityPolicyType.NoSecurity]

    @property
    def tokens(self) -> list[type]:
        """The user identity tokens taken."""
        return [ua.UserNameIdentityToken] if self.secure else [ua.AnonymousIdentityToken]


def security_of(
    host: str,
    allow: Sequence[str] = (),
    secure: bool = False,
    certs: Path = CERTS,
    password_file: Path | None = None,
    environ: Mapping[str, str] = os.environ,
) -> Security:
    """The security of a server on ``host``: secure beyond loopback, or when asked for; the
    password read from ``password_file`` (of mode 0600 or stricter) or else from
    :data:`PASSWORD_ENV`; the certificate's directory checked (:func:`check_certs`).

    Raises:
        ValueError: a bad address in ``allow``, a secure server without a password, a password
            file others may read, a certificate directory others may enter.
    """
    check_allow(allow)
    if not (secure or not is_loopback(host)):
        return Security(None, certs)
    password = read_password(password_file) if password_file else environ.get(PASSWORD_ENV, "")
    if not password:
        raise ValueError(
            f"a secure OPC UA server (beyond loopback, or --secure) needs the password of user "
            f"{USER!r}: set {PASSWORD_ENV} or give --password-file FILE (mode 0600)"
        )
    check_certs(certs)
    return Security(password, certs)


def read_password(path: Path) -> str:
    """The password in the first line of ``path``, a file only its owner may read or write.

    Raises:
        ValueError: no such file, others may read or write it, or its first line is empty.
    """
    try:
        mode = path.stat().st_mode
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeError) as error:
        raise ValueError(f"--password-file {path}: {error}") from None
    if mode & 0o077:
        raise ValueError(
            f"--password-file {path}: others may read or write it (mode {mode & 0o777:o}); "
            f"expected mode 600: chmod 600 {path}"
        )
    password = text.splitlines()[0] if text else ""
    if not password:
        raise ValueError(f"--password-file {path}:1: the password is empty")
    return password


def check_certs(certs: Path) -> None:
    """Make the certificate directory ``certs`` (mode 0700) or check that only its owner may
    enter an existing one.

    Raises:
        ValueError: it cannot be made, is no directory, or others may enter it.
    """
    try:
        certs.mkdir(parents=True, exist_ok=True, mode=0o700)
        mode = certs.stat().st_mode
    except OSError as error:
        raise ValueError(f"--certs {certs}: {error}") from None
    if not stat.S_ISDIR(mode):
        raise ValueError(f"--certs {certs}: not a directory")
    if mode & 0o077:
        raise ValueError(
            f"--certs {certs}: others may enter it (mode {mode & 0o777:o}), and it keeps the "
            f"server's private key; expected mode 700: chmod 700 {certs}"
        )


class PasswordUser(UserManager):
    """The user :data:`USER` with ``password``; nobody else."""

    def __init__(self, password: str) -> None:
        self._password = password.encode()

    def get_user(
        self,
        iserver: InternalServer,
        username: str | None = None,
        password: str | None = None,
        certificate: Any = None,
    ) -> User | None:
        """The user if name and password match (compared in constant time), else None."""
        given = str(password or "").encode()
        if username == USER and hmac.compare_digest(given, self._password):
            return User(role=UserRole.User, name=USER)
        log.warning("refused an OPC UA session: user %r, wrong name or password", username)
        return None


class Server(UaServer):
    """An asyncua server that closes every connection from an address not allowed.

    Args:
        allow: client addresses accepted besides loopback ones (empty: every address).
        users: who may open a session (None: anyone, anonymous).
    """

    def __init__(self, allow: Sequence[str] = (), users: UserManager | None = None) -> None:
        super().__init__(user_manager=users)
        self.allowed = allowed(allow) if allow else None
        self.secure = users is not None
        self.bridge_nodes: BridgeNodes | None = None
        """The node tree of the tables (:func:`server_of` makes it)."""

    async def start(self) -> None:
        """Listen (asyncua's start, with the guarded binary server)."""
        if self.iserver.certificate is not None:
            uacrypto.check_certificate(
                self.iserver.certificate, self._application_uri, socket.gethostname()
            )
        await self._setup_server_nodes()
        await self.iserver.start()
        host, port = self._get_bind_socket_info()
        self.bserver = _Guarded(
            self.iserver, host or "", port or 0, self.limits, self.allowed, self.secure
        )
        self.bserver.set_policies(self._policies)
        try:
            await self.bserver.start()
        except Exception:
            await self.iserver.stop()
            raise


class _Guarded(BinaryServer):
    """The binary server whose connections from addresses not allowed are closed at once and,
    ``secure``, whose sessions need an encrypted channel."""

    def __init__(
        self,
        iserver: InternalServer,
        host: str,
        port: int,
        limits: TransportLimits,
        allow: frozenset[str] | None,
        secure: bool,
    ) -> None:
        super().__init__(iserver, host, port, limits)
        self.allowed = allow
        self.secure = secure

    def _make_protocol(self) -> OPCUAProtocol:
        return _Protocol(
            iserver=self.iserver,
            policies=self._policies,
            clients=self.clients,
            closing_tasks=self.closing_tasks,
            limits=self.limits,
            allow=self.allowed,
            secure=self.secure,
        )


class _Protocol(OPCUAProtocol):
    """A connection: closed at once when its peer is not allowed (``allow`` None: every peer
    is); when the server is full, the oldest connection without an activated session gives way
    to it; its messages go to a :class:`_Processor`."""

    def __init__(
        self, *args: Any, allow: frozenset[str] | None, secure: bool, **kwargs: Any
    ) -> None:
        super().__init__(*args, **kwargs)
        self.allowed = allow
        self.secure = secure

    def connection_made(self, transport: Any) -> None:
        peer = transport.get_extra_info("peername")
        served, host = (True, "") if self.allowed is None else admitted(peer, self.allowed)
        if not served:
            log.warning("refused an OPC UA connection from %s (not in --allow)", host)
            transport.close()
            return
        if len(self.clients) >= self.iserver.max_connections:
            self._make_room()
        super().connection_made(transport)
        if self.processor is not None:
            self.processor = _Processor(self.iserver, self.transport, self.limits, self.secure)
            self.processor.set_policies(self.policies)

    def _make_room(self) -> None:
        """Close the oldest connection that has no activated session (one that connected and
        said nothing, or never finished its handshake), so that a client gets in."""
        for client in self.clients:
            processor = client.processor
            session = processor.session if processor is not None else None
            if session is None or not session.is_activated():
                log.warning("closed an idle OPC UA connection from %s: full", client.peer_name)
                self.clients.remove(client)
                if client.transport is not None:
                    client.transport.abort()
                return


SESSION_REQUESTS = frozenset(
    ua.NodeId(ua.Int32(code))
    for code in (
        ua.ObjectIds.CreateSessionRequest_Encoding_DefaultBinary,
        ua.ObjectIds.ActivateSessionRequest_Encoding_DefaultBinary,
    )
)
"""The requests that open a session."""

IN_TURN = frozenset(
    ua.NodeId(ua.Int32(code))
    for code in (
        ua.ObjectIds.WriteRequest_Encoding_DefaultBinary,
        ua.ObjectIds.CallRequest_Encoding_DefaultBinary,
    )
)
"""The requests that may wait for the scene (a lockstep target written, Advance called): taken
in turn, while reads are answered at once."""

READ = ua.NodeId(ua.Int32(ua.ObjectIds.ReadRequest_Encoding_DefaultBinary))


class _ChannelRefused(Exception):
    """A secure channel the server has no endpoint for (the status code says why)."""

    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


class _Processor(UaProcessor):
    """The processor of a connection's messages.

    - A secure channel with a security policy or mode the server has no endpoint for is
      answered with an error message, BadSecurityPolicyRejected or BadSecurityModeRejected,
      and closed (asyncua would leave the client waiting).
    - ``secure``: a session on a channel without encryption is refused (BadSecurityModeRejected)
      — asyncua would open it with a valid password sent in the clear; the endpoints
      (GetEndpoints, FindServers) stay readable to find the secure ones.
    - Writes and calls are taken in turn, one after the other; while one waits for the scene
      (lockstep), the connection's reads — a client's keep-alive — are answered at once, and its
      other requests wait their turn.
    """

    def __init__(
        self, iserver: InternalServer, transport: Any, limits: TransportLimits, secure: bool
    ) -> None:
        super().__init__(iserver, transport, limits)
        self.secure = secure
        self._turn: asyncio.Task[None] | None = None

    async def process(self, header: Any, body: Any) -> bool:
        try:
            return bool(await super().process(header, body))
        except (ua.UaError, _ChannelRefused) as error:
            if header.MessageType != ua.MessageType.SecureOpen:
                raise
            status = ua.StatusCode(
                ua.UInt32(getattr(error, "code", ua.StatusCodes.BadSecurityPolicyRejected))
            )
            log.warning("refused an OPC UA secure channel: %s", status.name)
            message = ua.ErrorMessage(status, ua.String("no endpoint with this security"))
            error_type = cast(ua.MessageType, ua.MessageType.Error)
            self._transport.write(uatcp_to_binary(error_type, message))
            return False

    def open_secure_channel(self, algohdr: Any, seqhdr: Any, body: Any) -> None:
        try:
            super().open_secure_channel(algohdr, seqhdr, body)
        except ua.UaError:  # the policy is served, not with this mode
            raise _ChannelRefused(ua.StatusCodes.BadSecurityModeRejected) from None

    async def process_message(self, seqhdr: Any, body: Any) -> Any:
        typeid = nodeid_from_binary(body.copy())
        idle = self._turn is None or self._turn.done()
        if typeid == READ or (idle and typeid not in IN_TURN):
            return await super().process_message(seqhdr, body)
        self._turn = asyncio.create_task(self._in_turn(self._turn, seqhdr, body))
        return True

    async def _in_turn(self, before: asyncio.Task[None] | None, seqhdr: Any, body: Any) -> None:
        """Process a message once the one before it is done; close the connection when the
        message says so."""
        if before is not None:
            await asyncio.wait({before})
        if not await super().process_message(seqhdr, body):
            self._transport.close()

    async def _process_message(self, typeid: Any, requesthdr: Any, seqhdr: Any, body: Any) -> Any:
        encrypted = self._connection.security_policy.Mode == ua.MessageSecurityMode.SignAndEncrypt
        if self.secure and typeid in SESSION_REQUESTS and not encrypted:
            log.warning("refused an OPC UA session on a channel without encryption")
            raise ServiceError(ua.StatusCodes.BadSecurityModeRejected)
        return await super()._process_message(typeid, requesthdr, seqhdr, body)

    async def close(self) -> None:
        """The connection is lost: a message waiting its turn is dropped."""
        if self._turn is not None:
            self._turn.cancel()
        await super().close()


def cache_dir() -> Path:
    """Where the server keeps the standard address space between starts."""
    root = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(root) / "mcl-testbench"


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


async def init(server: UaServer, cache: Path | None) -> None:
    """Initialise ``server`` with the standard address space, made once into ``cache`` (a
    shelf, loaded in a fraction of the time it takes to make) and read from there after;
    None: made every time."""
    if cache is None:
        await server.init()
        return
    shelf = cache / f"asyncua-{_asyncua_version()}-address-space"
    ready = shelf.with_suffix(".db")  # what asyncua looks for; a marker where dbm writes others
    if not (shelf.is_file() or ready.is_file()):
        with _locked(cache / "address-space.lock"):
            if not (shelf.is_file() or ready.is_file()):
                with tempfile.TemporaryDirectory(dir=cache) as scratch:
                    made = Path(scratch) / shelf.name
                    await server.init(made)
                    for file in Path(scratch).iterdir():
                        os.replace(file, cache / file.name)
                if not (shelf.is_file() or ready.is_file()):
                    ready.touch()
                return
    await server.init(shelf)


def _asyncua_version() -> str:
    from importlib.metadata import version

    return version("asyncua")


async def certificate(server: UaServer, certs: Path) -> None:
    """Load the server's key and self-signed certificate from ``certs`` (checked by
    :func:`check_certs`), made there on the first start (the key readable by its owner only)."""
    check_certs(certs)
    key, cert = certs / "server-key.pem", certs / "server-cert.der"
    host = socket.gethostname()
    await setup_self_signed_certificate(
        key,
        cert,
        APPLICATION_URI,
        host,
        [ExtendedKeyUsageOID.SERVER_AUTH],
        {"organizationName": "mcl-testbench", "commonName": f"bridge on {host}"},
    )
    key.chmod(0o600)
    await server.load_certificate(str(cert))
    await server.load_private_key(str(key))


async def server_of(
    bridge: Served,
    host: str = "127.0.0.1",
    port: int = 4840,
    allow: Sequence[str] = (),
    security: Security | None = None,
    cache: Path | None = None,
) -> Server:
    """The OPC UA server of ``bridge``'s tables, ready to start.

    Raises:
        ValueError: a host beyond loopback without a password, a bad address in ``allow``.
    """
    security = security or security_of(host, allow)
    if not is_loopback(host) and not security.secure:
        raise ValueError("beyond loopback the OPC UA server is secure only")
    server = Server(allow, PasswordUser(security.password) if security.password else None)
    await init(server, cache)
    server.set_endpoint(f"opc.tcp://{host}:{port}/")
    server.set_server_name(f"mcl-testbench bridge: {bridge.definition.name}")
    await server.set_application_uri(APPLICATION_URI)
    server.allow_remote_admin(False)
    server.set_security_policy(security.policies)
    server.set_identity_tokens(security.tokens)
    if security.secure:
        await certificate(server, security.certs)
    iserver = server.iserver
    iserver.max_connections = MAX_CONNECTIONS
    iserver.max_subscriptions = MAX_SUBSCRIPTIONS
    iserver.max_pending_activation_seconds = ACTIVATION
    iserver.max_monitored_item_queue_size = 1000
    server.limits = TransportLimits(
        max_recv_buffer=65535,
        max_send_buffer=65535,
        max_chunk_count=MAX_MESSAGE // 65535 + 1,
        max_message_size=MAX_MESSAGE,
    )
    server.bridge_nodes = BridgeNodes(server, bridge)
    await server.bridge_nodes.build()
    return server


class _OneLine(logging.Filter):
    """asyncua's records without their tracebacks: one line each (what a client sent wrong
    is no error of the server)."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info:
            error = record.exc_info[1]
            record.msg = f"{record.getMessage()}: {type(error).__name__}: {error}"
            record.args = None
            record.exc_info = None
            record.exc_text = None
        return True


def quiet_asyncua() -> None:
    """asyncua logs warnings and errors only, one line each."""
    logger = logging.getLogger("asyncua")
    logger.setLevel(logging.WARNING)
    for name in (
        "asyncua",
        *[n for n in logging.root.manager.loggerDict if n.startswith("asyncua.")],
    ):
        logging.getLogger(name).addFilter(_OneLine())


async def serve(
    machine: str,
    host: str = "127.0.0.1",
    port: int = 4840,
    speed: float | None = 1.0,
    allow: Sequence[str] = (),
    security: Security | None = None,
) -> None:
    """Build the scene of ``machine``, run it (free at ``speed`` × real time; None: lockstep)
    and serve its tables until SIGTERM/SIGINT."""
    quiet_asyncua()
    bridge = Bridge(machine, speed)
    server = await server_of(bridge, host, port, allow, security, cache_dir())
    quiet_asyncua()  # the loggers asyncua made meanwhile
    stopped = asyncio.Event()

    async def stop() -> None:
        stopped.set()

    stop_on_signals(stop)
    bridge.start()
    try:
        async with server:
            how = f"secure (user {USER})" if security and security.secure else "no security"
            print(
                f"{machine}: OPC UA on opc.tcp://{host}:{port}/, {how}, {bridge.mode}", flush=True
            )
            await stopped.wait()
    finally:
        bridge.stop()


def main(
    machine: str,
    host: str,
    port: int,
    speed: float | None = 1.0,
    allow: Sequence[str] = (),
    secure: bool = False,
    certs: Path = CERTS,
    password_file: Path | None = None,
) -> int:
    """The ``bridge opcua`` command: serve until stopped; 2 for a refused speed, port, allow
    entry, password or certificate directory."""
    security = Security()

    def checks() -> None:
        nonlocal security
        security = security_of(host, allow, secure, certs, password_file)
        check_speed(speed)
        if not 0 < port < 65536:
            raise ValueError(f"--port takes 1…65535, got {port}")

    return run_command(checks, lambda: serve(machine, host, port, speed, allow, security))

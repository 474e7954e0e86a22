"""Who may open the viewer and what a page may send: origin, host, token, headers, GUI values.

The viewer is a control panel of a machine, so a browser tab of any other site must not be able
to operate it, and nobody on the network without the address printed at start:

=====================  ==========================================================================
Same origin only       A websocket handshake needs an ``Origin`` header equal to
                       ``http://<Host>``; a page of another origin (or none) gets 403.
Expected Host only     The ``Host`` header must name this server (``127.0.0.1:PORT``,
                       ``localhost:PORT``, ``[::1]:PORT``, or the real addresses of the
                       machine when it binds beyond loopback, plus ``allowed_hosts``); anything
                       else (DNS rebinding) gets 403.
Secret token           :func:`make_token` at each start; the printed address carries it as
                       ``?token=…``. A request that presents it there is answered with a 303
                       redirect to the same address without the token (so neither the address
                       bar nor the history keeps it) that sets an HttpOnly, SameSite=Strict
                       cookie (named per port) every further request (files, websocket) must
                       carry. Mandatory when binding beyond loopback.
One Host header        A request with more than one ``Host`` header gets 400.
Headers                Every response carries a Content-Security-Policy with
                       ``frame-ancestors 'none'``, ``X-Frame-Options: DENY``, ``nosniff``,
                       ``Referrer-Policy: no-referrer`` (the token never leaks) and
                       ``Cache-Control: no-store``.
Bounded logging        Refused requests, malformed messages and failing handlers give one line
                       each, at most :data:`LOG_BURST` per :data:`LOG_WINDOW` seconds; the rest
                       is counted and summarised. A client that sends a malformed message is
                       disconnected.
GUI values             :class:`GuiGate` checks every value, hold message and hotkey command a page
                       sends against the element's rule (type, choices, finite range) and
                       whether the sender holds control, before viser applies it or passes it
                       on to the other pages.
Small messages         A websocket message from a page may be :data:`MAX_MESSAGE` long at most; a
                       longer one closes that page's connection (code 1009).
Lifesign               Every page is pinged (:mod:`viewer.serving.lifesign`); one that stops
                       answering is dropped.
No share, no upload    :func:`harden` makes the server drop viser's requests to open a public
                       share tunnel and to upload files (:data:`REFUSED_MESSAGES`).
=====================  ==========================================================================

viser 1.1.1 passes its own request handler to ``websockets.asyncio.server.serve`` inside
``WebsockServer._background_worker`` and offers no hook for the handshake; :func:`secure_server`
therefore wraps that one call while the server starts (under a lock, restored at once) to add the
checks above around viser's handler. The wrapping is pinned to :data:`VISER_VERSION`; another
version raises instead of serving unprotected.
"""

from __future__ import annotations

__all__ = [
    "LOG_BURST",
    "LOG_WINDOW",
    "LOOPBACK_NAMES",
    "MAX_MESSAGE",
    "MAX_PATH",
    "REFUSED_MESSAGES",
    "VISER_VERSION",
    "AccessPolicy",
    "BoundedLog",
    "GuiGate",
    "Refusal",
    "Rule",
    "boolean",
    "button_value",
    "choice_of",
    "harden",
    "is_loopback",
    "is_wildcard",
    "make_token",
    "network_addresses",
    "number_in",
    "public_hosts",
    "secure_server",
]

import asyncio
import contextlib
import hmac
import http
import io
import ipaddress
import logging
import math
import secrets
import socket
import threading
import time
import weakref
from collections.abc import Awaitable, Callable, Iterable, Sequence
from dataclasses import dataclass
from http.cookies import SimpleCookie
from typing import Any
from urllib.parse import parse_qs, parse_qsl, urlencode, urlsplit

import viser
import viser._messages as messages
import websockets.asyncio.server
from viser.infra import ClientId
from websockets.asyncio.server import ServerConnection
from websockets.http11 import Request, Response

from viewer.serving.lifesign import (
    CLOSE_TIMEOUT,
    LIFESIGN_INTERVAL,
    LIFESIGN_TIMEOUT,
    LifesignConnection,
)

log = logging.getLogger(__name__)

VISER_VERSION = "1.1.1"
"""The viser version whose websocket start-up :func:`secure_server` wraps."""

MAX_PATH = 1024
"""Longest request target (path and query) served [characters]; longer ones get 414."""

MAX_MESSAGE = 1024 * 1024
"""Longest websocket message a page may send [bytes] (1 MiB; a page sends GUI values, camera
poses and hold messages of a few hundred bytes)."""

LOG_BURST = 20
"""Lines of refused requests and bad messages logged per :data:`LOG_WINDOW` at most."""

LOG_WINDOW = 60.0
"""Window [s] of the log budget."""

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "[::1]")
"""Host names of this machine's loopback interface, as they appear in a Host header."""


def make_token() -> str:
    """A fresh secret for one start of the viewer (32 URL-safe characters, 192 bits)."""
    return secrets.token_urlsafe(24)


def is_loopback(host: str) -> bool:
    """Whether binding ``host`` serves this machine only (127.0.0.0/8, ::1, ``localhost``)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def is_wildcard(host: str) -> bool:
    """Whether binding ``host`` serves every interface (``0.0.0.0``, ``::`` or empty)."""
    return host in ("", "0.0.0.0", "::", "[::]")


def network_addresses() -> list[str]:
    """This machine's addresses on the network (no loopback), best first; may be empty.

    The first is the address of the interface with the default route (found by connecting a UDP
    socket, which sends nothing).
    """
    found: list[str] = []
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.connect(("192.0.2.1", 9))  # TEST-NET-1: never routed anywhere for real
            found.append(str(probe.getsockname()[0]))
    except OSError:
        pass
    try:
        infos = socket.getaddrinfo(socket.gethostname(), None)
    except OSError:
        infos = []
    for info in infos:
        address = str(info[4][0])
        if address not in found and not is_loopback(address):
            found.append(address)
    return [a for a in found if not is_loopback(a) and not is_wildcard(a)]


def _host_literal(host: str) -> str:
    """A host as it appears in a URL or Host header (IPv6 in brackets)."""
    return f"[{host}]" if ":" in host and not host.startswith("[") else host


def public_hosts(bind: str) -> list[str]:
    """Names under which a server bound to ``bind`` is reached, best first (no ports)."""
    if is_loopback(bind):
        names = [_host_literal(bind)] if bind != "localhost" else []
        return names + [n for n in LOOPBACK_NAMES if n not in names]
    names = [_host_literal(a) for a in network_addresses()] if is_wildcard(bind) else []
    if not is_wildcard(bind):
        names.append(_host_literal(bind))
    for name in (socket.gethostname(), socket.getfqdn()):
        if name and name not in names:
            names.append(name.lower())
    if is_wildcard(bind):
        names += [n for n in LOOPBACK_NAMES if n not in names]
    return names


class BoundedLog:
    """One-line warnings with a budget: :data:`LOG_BURST` lines per :data:`LOG_WINDOW` seconds.

    Args:
        logger: Where the lines go.
        burst: Lines per window.
        window: Window length [s].
        clock: Monotonic clock [s].
    """

    def __init__(
        self,
        logger: logging.Logger = log,
        burst: int = LOG_BURST,
        window: float = LOG_WINDOW,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self._logger = logger
        self._burst = burst
        self._window = window
        self._clock = clock
        self._lock = threading.Lock()
        self._start = -math.inf
        self._count = 0
        self._suppressed = 0
        self.lines = 0
        """Lines written so far."""

    def warning(self, text: str) -> None:
        """Log ``text`` on one line (newlines removed, at most 300 characters) if the budget
        allows; else count it."""
        line = " ".join(text.split())[:300]
        with self._lock:
            now = self._clock()
            if now - self._start >= self._window:
                if self._suppressed:
                    self._logger.warning(
                        "viewer: %d more such messages suppressed", self._suppressed
                    )
                    self.lines += 1
                self._start, self._count, self._suppressed = now, 0, 0
            if self._count >= self._burst:
                self._suppressed += 1
                return
            self._count += 1
            self.lines += 1
        self._logger.warning("viewer: %s", line)


def _host_of(request: Request) -> str | None:
    """The request's Host header (stripped, lower case; "" without one), None if it has
    several."""
    values = request.headers.get_all("Host")
    if len(values) > 1:
        return None
    return values[0].strip().lower() if values else ""


def _is_websocket(request: Request) -> bool:
    """Whether ``request`` asks to open a websocket."""
    return any(v.strip().lower() == "websocket" for v in request.headers.get_all("Upgrade"))


def _without_token(target: str) -> str:
    """A request target (path and query) without its ``token`` parameter."""
    parts = urlsplit(target)
    query = urlencode([(k, v) for k, v in parse_qsl(parts.query, True) if k != "token"])
    return (parts.path or "/") + (f"?{query}" if query else "")


def _describe(exc: BaseException) -> str:
    """An exception in one short line."""
    return f"{type(exc).__name__}: {exc}"[:200]


class _OneLine(logging.Filter):
    """Turns websockets' handshake and handler errors into bounded one-line warnings."""

    def __init__(self, bounded: BoundedLog) -> None:
        super().__init__()
        self._bounded = bounded

    def filter(self, record: logging.LogRecord) -> bool:
        if record.levelno < logging.WARNING and record.exc_info is None:
            return True
        detail = ""
        if record.exc_info and record.exc_info[1] is not None:
            detail = f" ({_describe(record.exc_info[1])})"
        self._bounded.warning(f"websocket: {record.getMessage()}{detail}")
        return False


@dataclass(frozen=True)
class Refusal:
    """Why a request is refused: HTTP status and a short text for the client."""

    status: http.HTTPStatus
    reason: str


class AccessPolicy:
    """The checks every HTTP request and websocket handshake passes (see the module docstring).

    Args:
        bind: The interface the server binds (``127.0.0.1``, ``0.0.0.0``, an address).
        port: Its TCP port (may be set later with :attr:`port` when the OS picks it).
        token: The secret every connection must present; ``None`` only on loopback.
        allowed_hosts: Further names the server may be reached under (a DNS name, a proxy),
            without port.
        log: Where refusals are reported.

    Raises:
        ValueError: If ``token`` is None or empty while ``bind`` is not a loopback address.
    """

    def __init__(
        self,
        bind: str,
        port: int,
        token: str | None,
        allowed_hosts: Iterable[str] = (),
        log: BoundedLog | None = None,
    ) -> None:
        if not token and not is_loopback(bind):
            raise ValueError(
                f"binding {bind!r} reaches beyond this machine: a token is mandatory there"
            )
        self.bind = bind
        self.port = port
        self.token = token or None
        self.names = [*public_hosts(bind), *(h.lower() for h in allowed_hosts)]
        """Host names (no port) a Host header may carry, best first."""
        self.log = log or BoundedLog()
        self.refused = 0
        """Requests refused so far."""
        self.beacons: dict[str, Callable[[dict[str, str]], None]] = {}
        """Paths a page reports to (answered 204 after the checks), with what hears the query."""

    @property
    def cookie_name(self) -> str:
        """Name of the token cookie; per port, as cookies do not tell ports apart."""
        return f"mcl_viewer_token_{self.port}"

    def hosts(self) -> set[str]:
        """The Host header values accepted (``name:port``, lower case)."""
        return {f"{name}:{self.port}".lower() for name in self.names}

    def url(self, name: str | None = None) -> str:
        """The address to open (with the token), under ``name`` or the best host name."""
        host = name or self.names[0]
        query = f"/?token={self.token}" if self.token else "/"
        return f"http://{_host_literal(host)}:{self.port}{query}"

    def _token_of(self, request: Request) -> tuple[str | None, bool]:
        """The token a request presents and whether it came in the query string."""
        query = parse_qs(urlsplit(request.path).query)
        if "token" in query:
            return query["token"][-1], True
        cookies = SimpleCookie()
        for header in request.headers.get_all("Cookie"):
            try:
                cookies.load(header)
            except Exception:  # a malformed cookie header counts as none
                continue
        morsel = cookies.get(self.cookie_name)
        return (morsel.value if morsel is not None else None), False

    def refusal(self, request: Request) -> Refusal | None:
        """Why ``request`` must be refused, or None if it may pass."""
        if len(request.path) > MAX_PATH:
            return Refusal(http.HTTPStatus.REQUEST_URI_TOO_LONG, "request target too long")
        host = _host_of(request)
        if host is None:
            return Refusal(http.HTTPStatus.BAD_REQUEST, "more than one Host header")
        if host not in self.hosts():
            return Refusal(http.HTTPStatus.FORBIDDEN, f"unexpected Host header {host[:80]!r}")
        if _is_websocket(request):
            origin = request.headers.get("Origin", "").strip().lower()
            if origin != f"http://{host}":
                return Refusal(http.HTTPStatus.FORBIDDEN, f"cross-origin websocket {origin[:80]!r}")
        if self.token is not None:
            token, _ = self._token_of(request)
            if token is None or not hmac.compare_digest(token.encode(), self.token.encode()):
                return Refusal(
                    http.HTTPStatus.FORBIDDEN,
                    "missing or wrong token: open the address the viewer printed at start",
                )
        return None

    def headers(self, request: Request) -> dict[str, str]:
        """The security headers of every response to ``request``."""
        host = _host_of(request)
        connect = f" ws://{host}" if host is not None and host in self.hosts() else ""
        csp = (
            "default-src 'self'; "
            "script-src 'self' 'unsafe-inline' 'unsafe-eval' 'wasm-unsafe-eval' blob:; "
            "worker-src 'self' blob:; style-src 'self' 'unsafe-inline'; "
            "img-src 'self' data: blob:; font-src 'self' data:; media-src 'self' data: blob:; "
            f"connect-src 'self'{connect} data: blob:; frame-ancestors 'none'; "
            "base-uri 'none'; form-action 'none'; object-src 'none'"
        )
        return {
            "Content-Security-Policy": csp,
            "X-Frame-Options": "DENY",
            "X-Content-Type-Options": "nosniff",
            "Referrer-Policy": "no-referrer",
            "Cache-Control": "no-store",
            "Cross-Origin-Opener-Policy": "same-origin",
            "Cross-Origin-Resource-Policy": "same-origin",
        }

    def process_request(
        self, inner: Callable[[ServerConnection, Request], Response | None] | None
    ) -> Callable[[ServerConnection, Request], Response | None]:
        """viser's request handler ``inner`` behind the checks; errors give 404, one line."""

        def process(connection: ServerConnection, request: Request) -> Response | None:
            try:
                refusal = self.refusal(request)
            except Exception as exc:
                refusal = Refusal(http.HTTPStatus.BAD_REQUEST, _describe(exc))
            if refusal is not None:
                self.refused += 1
                self.log.warning(
                    f"refused {_path(request)!r} from {_peer(connection)}: {refusal.reason}"
                )
                return connection.respond(refusal.status, refusal.reason + "\n")
            token_in_query = self.token is not None and self._token_of(request)[1]
            if token_in_query and not _is_websocket(request):
                return self._redirect(connection, request)
            beacon = self.beacons.get(urlsplit(request.path).path)
            if beacon is not None:
                beacon(dict(parse_qsl(urlsplit(request.path).query)))
                return connection.respond(http.HTTPStatus.NO_CONTENT, "")
            if inner is None:
                return None
            try:
                return inner(connection, request)
            except Exception as exc:  # e.g. a file name the OS rejects
                self.log.warning(f"request {_path(request)!r} failed: {_describe(exc)}")
                return connection.respond(http.HTTPStatus.NOT_FOUND, "not found\n")

        return process

    def _redirect(self, connection: ServerConnection, request: Request) -> Response:
        """The answer to a request that passed with the token in its query: 303 to the same
        address without it, setting the token cookie."""
        response = connection.respond(http.HTTPStatus.SEE_OTHER, "see other\n")
        response.headers["Location"] = _without_token(request.path)
        response.headers["Set-Cookie"] = (
            f"{self.cookie_name}={self.token}; Path=/; HttpOnly; SameSite=Strict"
        )
        return response

    def process_response(
        self, connection: ServerConnection, request: Request, response: Response
    ) -> Response | None:
        """Add the security headers."""
        for name, value in self.headers(request).items():
            response.headers[name] = value
        return None


def _path(request: Request) -> str:
    """The request's path for a log line: without the query (it may carry the token), short."""
    return urlsplit(request.path).path[:80]


def _peer(connection: ServerConnection) -> str:
    try:
        address = connection.remote_address
    except Exception:
        return "?"
    return str(address[0]) if isinstance(address, tuple) and address else "?"


def _guard_handler(
    handler: Callable[[ServerConnection], Awaitable[None]], bounded: BoundedLog
) -> Callable[[ServerConnection], Awaitable[None]]:
    """viser's connection handler; a client whose message breaks it is dropped with one line."""

    async def guarded(connection: ServerConnection) -> None:
        try:
            await handler(connection)
        except asyncio.CancelledError:
            raise
        except Exception as exc:
            bounded.warning(f"dropped client {_peer(connection)} after {_describe(exc)}")

    return guarded


_serve_lock = threading.Lock()


def secure_server(policy: AccessPolicy, **kwargs: Any) -> viser.ViserServer:
    """A viser server whose every request and handshake passes ``policy``.

    Args:
        policy: The checks (its port is set to the bound one).
        **kwargs: For :class:`viser.ViserServer` (host, port, label, verbose).

    Raises:
        RuntimeError: If the installed viser is not :data:`VISER_VERSION`.
    """
    if viser.__version__ != VISER_VERSION:
        raise RuntimeError(
            f"viewer.serving.security wraps the websocket start-up of viser {VISER_VERSION}; "
            f"viser {viser.__version__} is installed (pin viser=={VISER_VERSION})"
        )
    module = websockets.asyncio.server
    original = module.serve
    bounded = policy.log

    def serve(handler: Any, *args: Any, **options: Any) -> Any:
        options["process_request"] = policy.process_request(options.get("process_request"))
        options["process_response"] = policy.process_response
        options["max_size"] = MAX_MESSAGE
        options["create_connection"] = LifesignConnection
        options["ping_interval"] = LIFESIGN_INTERVAL
        options["ping_timeout"] = LIFESIGN_TIMEOUT
        options["close_timeout"] = CLOSE_TIMEOUT
        return original(_guard_handler(handler, bounded), *args, **options)

    with _serve_lock:
        setattr(module, "serve", serve)  # noqa: B010 - restored below; see the module docstring
        try:
            # viser prints its own banner with an address without the token (and "localhost"
            # for 0.0.0.0); the viewer prints the right one instead.
            with contextlib.redirect_stdout(io.StringIO()):
                server = viser.ViserServer(**kwargs)
        finally:
            setattr(module, "serve", original)  # noqa: B010
    policy.port = server.get_port()
    one_line = _OneLine(bounded)
    for name in ("websockets.server", "websockets"):
        logger = logging.getLogger(name)
        if not any(isinstance(f, _OneLine) for f in logger.filters):
            logger.addFilter(one_line)
    loop = server._websock_server._background_event_loop
    if loop is not None:

        def on_error(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
            exc = context.get("exception")
            text = _describe(exc) if isinstance(exc, BaseException) else str(context["message"])
            bounded.warning(f"message handler failed: {text}")

        loop.call_soon_threadsafe(loop.set_exception_handler, on_error)
    return server


REFUSED_MESSAGES = ("ShareUrlRequest", "FileTransferStartUpload", "FileTransferPart")
"""Requests a browser could send to any viser server that this viewer ignores: opening a public
share tunnel (which would put the operator controls on the internet) and file uploads."""


def harden(server: viser.ViserServer) -> None:
    """Make a viser server refuse :data:`REFUSED_MESSAGES` and hide its share button.

    viser 1.1.1 has no public switch for this, so the handlers are unregistered from its websocket
    server; a message without a handler is dropped.

    Args:
        server: The server, before clients connect.
    """
    server.gui.configure_theme(show_share_button=False)
    websock = server._websock_server
    handlers = websock._incoming_handlers
    for name in REFUSED_MESSAGES:
        message_class = getattr(messages, name, None)
        if message_class is not None and message_class in handlers:
            websock.unregister_handler(message_class)


# ------------------------------------------------------------------------------ GUI values


@dataclass(frozen=True)
class Rule:
    """What a GUI element accepts from a page.

    Attributes:
        accept: Whether a value is valid (type, choices, range).
        control: Only the operator in control may change it (False: anyone, e.g. STOP all).
        label: The element's label, for the refusal message.
    """

    accept: Callable[[Any], bool]
    control: bool
    label: str


def button_value(value: Any) -> bool:
    """A button press: ``True``."""
    return value is True


def choice_of(options: Sequence[str]) -> Callable[[Any], bool]:
    """Accepts one of ``options`` (a dropdown)."""
    allowed = tuple(options)
    return lambda value: isinstance(value, str) and value in allowed


def number_in(low: float, high: float) -> Callable[[Any], bool]:
    """Accepts a finite number in [low, high] (a slider or number box; no bool, no NaN)."""

    def accept(value: Any) -> bool:
        return (
            isinstance(value, int | float)
            and not isinstance(value, bool)
            and math.isfinite(value)
            and low <= value <= high
        )

    return accept


def boolean(value: Any) -> bool:
    """A checkbox: a bool."""
    return isinstance(value, bool)


_GATED = (
    (messages.GuiUpdateMessage, "_handle_gui_updates"),
    (messages.GuiButtonHoldMessage, "_handle_gui_button_hold"),
    (messages.CommandTriggerMessage, "_handle_command_trigger"),
)
"""The messages a page sends to GUI elements, and the handlers of viser's GUI for them."""


def _release(interface: Any, gui: viser.GuiApi) -> None:
    """Take the GUI message handlers of ``gui`` off ``interface`` (the server's or a page's
    connection): the gate calls them after its checks instead."""
    handlers = interface._incoming_handlers
    for message_class, name in _GATED:
        handler = getattr(gui, name)
        if handler in handlers.get(message_class, ()):
            interface.unregister_handler(message_class, handler)


async def _adopt(client: viser.ClientHandle) -> None:
    """A page connected: what it sends to its own elements (``client.gui``) passes the gate
    too (run in the event loop before any other connect callback makes such an element)."""
    _release(client._websock_connection, client.gui)


_gates: weakref.WeakKeyDictionary[viser.ViserServer, GuiGate] = weakref.WeakKeyDictionary()
"""The gate installed on each server."""


class GuiGate:
    """Checks every GUI value and hold message a page sends before viser acts on it.

    An element without a rule accepts nothing. A refused value is not applied, not passed on to
    the other pages, and the sender's element is set back to the server's value; ``on_refused``
    hears of it (client id, element label, reason). The elements of one page alone
    (``client.gui``) pass the same checks: their messages reach viser only through the gate.

    Args:
        server: The viser server (its GUI handlers are wrapped).
        in_control: Whether a client holds control.
        on_refused: Called for each refused message.
        log: Where refusals are logged (bounded).
    """

    def __init__(
        self,
        server: viser.ViserServer,
        in_control: Callable[[int], bool],
        on_refused: Callable[[int, str, str], None],
        log: BoundedLog | None = None,
    ) -> None:
        self.server = server
        self.rules: dict[str, Rule] = {}
        self._in_control = in_control
        self._on_refused = on_refused
        self._log = log or BoundedLog()
        gui = server.gui
        websock = server._websock_server
        previous = _gates.get(server)
        if previous is not None:  # a new app on the same server: its gate replaces the old one
            websock.unregister_handler(messages.GuiUpdateMessage, previous._on_update)
            websock.unregister_handler(messages.GuiButtonHoldMessage, previous._on_hold)
            websock.unregister_handler(messages.CommandTriggerMessage, previous._on_command)
        else:
            _release(websock, gui)
            server.on_client_connect(_adopt)
        _gates[server] = self
        websock.register_handler(messages.GuiUpdateMessage, self._on_update)
        websock.register_handler(messages.GuiButtonHoldMessage, self._on_hold)
        websock.register_handler(messages.CommandTriggerMessage, self._on_command)

    def _scope(self, client_id: int, uuid: str) -> viser.GuiApi | None:
        """The GUI the element ``uuid`` belongs to: the server's (every page's) or that of the
        page ``client_id`` (None: the page is gone)."""
        gui = self.server.gui
        if uuid in gui._gui_input_handle_from_uuid or uuid in gui._command_handle_from_uuid:
            return gui
        client = self.server.get_clients().get(client_id)
        return client.gui if client is not None else None

    def allow(self, handle: Any, accept: Callable[[Any], bool], control: bool = True) -> None:
        """Let pages change ``handle`` with values ``accept`` takes (by the operator in control
        unless ``control`` is False)."""
        self.rules[handle._impl.uuid] = Rule(accept, control, str(getattr(handle, "label", "")))

    def allow_command(self, handle: Any, label: str, control: bool = True) -> None:
        """Let pages trigger the command (hotkey) ``handle`` (those in control unless
        ``control`` is False)."""
        self.rules[handle._impl.uuid] = Rule(button_value, control, label)

    def forget(self, handles: Iterable[Any]) -> None:
        """Drop the rules of removed elements."""
        for handle in handles:
            self.rules.pop(handle._impl.uuid, None)

    def _refuse(self, client_id: int, uuid: str, label: str, reason: str) -> None:
        self._log.warning(f"client {client_id}: refused {label or uuid!r}: {reason}")
        self._on_refused(client_id, label, reason)
        scope = self._scope(client_id, uuid)
        handle = scope._gui_input_handle_from_uuid.get(uuid) if scope is not None else None
        client = self.server.get_clients().get(client_id)
        if handle is not None and client is not None and not isinstance(handle.value, bool):
            client._websock_connection.queue_message(
                messages.GuiUpdateMessage(uuid, {"value": handle.value})
            )

    async def _on_update(self, client_id: ClientId, message: messages.GuiUpdateMessage) -> None:
        try:
            rule = self.rules.get(message.uuid)
            updates = message.updates
            if rule is None:
                self._refuse(client_id, str(message.uuid)[:40], "", "no such input")
                return
            if not isinstance(updates, dict) or set(updates) != {"value"}:
                self._refuse(client_id, message.uuid, rule.label, "only a value may be sent")
                return
            if not rule.accept(updates["value"]):
                self._refuse(
                    client_id, message.uuid, rule.label, f"invalid value {updates['value']!r:.40}"
                )
                return
            if rule.control and not self._in_control(client_id):
                self._refuse(client_id, message.uuid, rule.label, "take control first")
                return
            scope = self._scope(client_id, message.uuid)
            if scope is not None:
                await scope._handle_gui_updates(client_id, message)
        except Exception as exc:
            self._log.warning(f"client {client_id}: bad GUI update: {_describe(exc)}")

    async def _on_command(
        self, client_id: ClientId, message: messages.CommandTriggerMessage
    ) -> None:
        try:
            rule = self.rules.get(message.uuid)
            if rule is None:
                return
            if rule.control and not self._in_control(client_id):
                self._refuse(client_id, message.uuid, rule.label, "take control first")
                return
            scope = self._scope(client_id, message.uuid)
            if scope is not None:
                await scope._handle_command_trigger(client_id, message)
        except Exception as exc:
            self._log.warning(f"client {client_id}: bad command message: {_describe(exc)}")

    async def _on_hold(self, client_id: ClientId, message: messages.GuiButtonHoldMessage) -> None:
        try:
            rule = self.rules.get(message.uuid)
            if rule is None or not (
                isinstance(message.frequency, int | float) and math.isfinite(message.frequency)
            ):
                return
            if rule.control and not self._in_control(client_id):
                self._refuse(client_id, message.uuid, rule.label, "take control first")
                return
            scope = self._scope(client_id, message.uuid)
            if scope is not None:
                await scope._handle_gui_button_hold(client_id, message)
        except Exception as exc:
            self._log.warning(f"client {client_id}: bad hold message: {_describe(exc)}")

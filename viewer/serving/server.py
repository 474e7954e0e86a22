"""Serving the viewer: :class:`Viewer` bundles session, viser server and app behind the access
policy of :mod:`viewer.serving.security`, on a port checked to be free first.

``Viewer(scene="gantry", port=8080)`` serves the viewer on ``http://127.0.0.1:8080/?token=…``
until :meth:`Viewer.close`.
"""

from __future__ import annotations

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "PortInUseError", "Viewer", "port_available"]

import errno
import socket
from collections.abc import Iterable

from viewer.pages.app import ViewerApp
from viewer.serving import loop_safe
from viewer.serving.security import AccessPolicy, BoundedLog, is_loopback, make_token, secure_server
from viewer.sim.session import Session
from viewer.view3d import renderer

loop_safe.install()  # before any viser server: its buffers' events woken safely from threads

DEFAULT_HOST = "127.0.0.1"
"""Interface the viewer binds unless told otherwise: this machine only."""

DEFAULT_PORT = 8080
"""TCP port of the viewer's HTTP and websocket server."""


class PortInUseError(OSError):
    """The requested TCP port is taken (the message names host and port)."""


def port_available(host: str, port: int) -> bool:
    """Whether a server could listen on ``host:port`` now (tries to bind a socket).

    Uses ``SO_REUSEADDR`` like the viewer's server, so a port whose last connection lingers in
    TIME_WAIT counts as available while one with a listening socket does not.

    Args:
        host: Interface address, e.g. ``"127.0.0.1"``.
        port: TCP port (0 is always available).

    Raises:
        OSError: If the address cannot be bound for another reason than being in use (unknown
            host, an address of another machine, a privileged port).
    """
    infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    for family, kind, proto, _, address in infos:
        with socket.socket(family, kind, proto) as sock:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            try:
                sock.bind(address)
            except OSError as exc:
                if exc.errno == errno.EADDRINUSE:
                    return False
                raise
    return True


def _port_in_use(host: str, port: int) -> PortInUseError:
    return PortInUseError(
        errno.EADDRINUSE, f"port {port} on {host} is already in use; choose another --port"
    )


class Viewer:
    """A session, a viser server and the app in one: the viewer as the CLI starts it.

    Args:
        scene: Registry name of the scene to show first.
        host: Interface to bind (default: this machine only).
        port: TCP port; 0 picks a free one.
        speed: Simulated seconds per wall second (``math.inf``: as fast as possible).
        demo: Start the scene's demo program (if it has one), and the demo of every machine
            chosen on a page; Repeat demo on.
        fps: Frame rate of the 3-D updates [Hz].
        environment_map: Light the scene with an HDRI environment map (slow without a GPU).
        session: Use this session instead of making one (it is started and closed here).
        token: The secret every connection must present: ``True`` makes a fresh one
            (:func:`~viewer.serving.security.make_token`), a string uses it, ``False`` serves
            without
            one (loopback only).
        allowed_hosts: Further host names the viewer may be reached under (a DNS name).

    Every request and websocket passes :class:`~viewer.serving.security.AccessPolicy` (same origin,
    expected Host, token, security headers); :attr:`url` carries the token.

    Raises:
        PortInUseError: If the port is taken.
        OSError: If the address cannot be served for another reason (see :func:`port_available`).
        ValueError: If ``token`` is False and ``host`` is not a loopback address.
    """

    def __init__(
        self,
        scene: str = "gantry",
        *,
        host: str = DEFAULT_HOST,
        port: int = DEFAULT_PORT,
        speed: float = 1.0,
        demo: bool = True,
        fps: float = 30.0,
        environment_map: bool = False,
        session: Session | None = None,
        token: bool | str = True,
        allowed_hosts: Iterable[str] = (),
    ) -> None:
        secret = make_token() if token is True else (token or None)
        self.policy = AccessPolicy(host, port, secret, allowed_hosts, BoundedLog())
        """The checks every request passes."""
        if not port_available(host, port):
            raise _port_in_use(host, port)
        self.session = session if session is not None else Session(scene, speed=speed)
        self.server = secure_server(
            self.policy, host=host, port=port, label="mcl testbench", verbose=False
        )
        try:
            if port and self.server.get_port() != port:  # viser moved on to another port
                raise _port_in_use(host, port)
            self.app = ViewerApp(
                self.session,
                self.server,
                fps=fps,
                environment_map=environment_map,
                log=self.policy.log,
                demo=demo,
            )
            self.policy.beacons[renderer.PATH] = self.app.renderers.report
            self.session.repeat_demo = demo
            if demo and self.session.demo_available():
                self.session.start_demo()
            self.session.start()
            self.app.start()
        except BaseException:
            self.session.close()
            self.server.stop()
            raise

    @property
    def host(self) -> str:
        """Interface the server is bound to."""
        return self.server.get_host()

    @property
    def port(self) -> int:
        """TCP port the server listens on."""
        return self.server.get_port()

    @property
    def url(self) -> str:
        """Address to open in a browser, with the token (the machine's real address when it
        binds every interface)."""
        return self.policy.url()

    @property
    def token(self) -> str | None:
        """The secret of this start (None: served without one, loopback only)."""
        return self.policy.token

    @property
    def exposed(self) -> bool:
        """The viewer is reachable from other machines (it binds beyond loopback)."""
        return not is_loopback(self.host)

    def warning(self) -> str:
        """What to tell when the viewer binds beyond loopback (empty on loopback)."""
        if not self.exposed:
            return ""
        return (
            f"WARNING: the viewer is reachable from the network, not just this machine. Open "
            f"{self.url} ; anyone with this address (and its token) can operate the machine. "
            f"Bind 127.0.0.1 to serve this machine only."
        )

    def close(self) -> None:
        """Stop the update loop, the simulation thread and the server (frees the port)."""
        self.app.stop()
        self.session.close()
        self.server.stop()

    def __enter__(self) -> Viewer:
        """The running viewer."""
        return self

    def __exit__(self, *exc: object) -> None:
        """Close the viewer."""
        self.close()

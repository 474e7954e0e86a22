"""The lifesign of a page: the websocket's keepalive pings, which the browser answers on its own
(no script of the page involved), timed per connection.

The server pings every page every :data:`LIFESIGN_INTERVAL`; each answer (pong) is the page's
lifesign. A page without an answer for :data:`LIFESIGN_TIMEOUT` counts as gone
(:class:`~viewer.serving.control.Operators` hands its control on), and the websocket library drops
its
connection soon after (ping timeout, then at most :data:`CLOSE_TIMEOUT` for the closing
handshake).
"""

from __future__ import annotations

__all__ = [
    "CLOSE_TIMEOUT",
    "LIFESIGN_INTERVAL",
    "LIFESIGN_TIMEOUT",
    "Lifesign",
    "LifesignConnection",
    "lifesign",
]

import time
from dataclasses import dataclass
from typing import Any

import viser
from websockets.asyncio.server import ServerConnection

LIFESIGN_INTERVAL = 1.0
"""Wall time [s] between two pings to a page."""

LIFESIGN_TIMEOUT = 3.0
"""Wall time [s] without an answer after which a page counts as gone (cut off or hung)."""

CLOSE_TIMEOUT = 2.0
"""Wall time [s] the server waits for a closing page's close frame before it drops the TCP
connection (a hung page never sends one)."""


class LifesignConnection(ServerConnection):
    """A websocket connection that remembers when its page last answered a ping."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.answered = time.monotonic()
        """Monotonic wall clock [s] of the last answer (of the opening before the first)."""

    def acknowledge_pings(self, data: bytes) -> None:
        """A pong arrived: an answer to one of our pings is a lifesign."""
        if data in self.pending_pings:
            self.answered = time.monotonic()
        super().acknowledge_pings(data)


@dataclass(frozen=True)
class Lifesign:
    """How a page answers the pings."""

    latency: float
    """Round trip [s] of the last answered ping (0.0 before the first)."""
    age: float
    """Wall time [s] since the last answer."""

    @property
    def alive(self) -> bool:
        """The page answered within :data:`LIFESIGN_TIMEOUT`."""
        return self.age <= LIFESIGN_TIMEOUT


def lifesign(server: viser.ViserServer, client_id: int) -> Lifesign | None:
    """The lifesign of the page ``client_id`` (None: no such live connection, e.g. closed).

    Args:
        server: The viser server (started by :func:`~viewer.serving.security.secure_server`).
        client_id: The page's client id.
    """
    connection = server._websock_server._live_connections.get(client_id)  # viser 1.1.1
    if not isinstance(connection, LifesignConnection):
        return None
    return Lifesign(connection.latency, max(time.monotonic() - connection.answered, 0.0))

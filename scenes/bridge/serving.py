"""What the bridge's servers (:mod:`scenes.bridge.modbus`, :mod:`scenes.bridge.opcua`) share:
the loopback rule and the allow-list of client addresses, the lockstep acknowledgement, stopping
on SIGTERM/SIGINT and the command's exit on a user's mistake."""

from __future__ import annotations

__all__ = [
    "ACK_TIMEOUT",
    "acknowledge",
    "admitted",
    "allowed",
    "check_allow",
    "check_host",
    "is_loopback",
    "run_command",
    "stop_on_signals",
]

import asyncio
import contextlib
import ipaddress
import signal
import sys
from collections.abc import Callable, Coroutine, Sequence
from typing import Any

from scenes.bridge.runs import Run

ACK_TIMEOUT = 2.0
"""Longest wall time [s] the answer to a lockstep target waits for the scene to get there (a
client then reads ``sim.cycle`` until it does)."""


def is_loopback(host: str) -> bool:
    """Whether ``host`` is a loopback address (or ``localhost``)."""
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return host == "localhost"


def check_host(
    host: str,
    allow: Sequence[str] = (),
    flag: str = "--allow",
    server: str = "Modbus",
    why: str = "Modbus has no security of its own",
) -> None:
    """Refuse an address beyond loopback without an allow-list of client addresses (given
    with the command-line option ``flag``), and an allow-list entry that is no IP address.

    Args:
        host: the address to bind.
        allow: the client addresses accepted besides loopback ones.
        flag: the option that gives them (for the message).
        server: the server's name (for the message).
        why: why a host beyond loopback needs the list (for the message).

    Raises:
        ValueError: says what is wrong and what would be right.
    """
    if not is_loopback(host) and not allow:
        raise ValueError(
            f"the {server} server binds loopback only, got {host!r}: {why}; to serve another "
            f"address, name the PLC's address with {flag} ADDRESS"
        )
    check_allow(allow, flag)


def check_allow(allow: Sequence[str], flag: str = "--allow") -> None:
    """Refuse an allow-list entry that is no IP address (``flag``: the option, for the
    message).

    Raises:
        ValueError: says which entry.
    """
    for address in allow:
        try:
            ipaddress.ip_address(address)
        except ValueError:
            raise ValueError(f"{flag} takes IP addresses, got {address!r}") from None


def allowed(allow: Sequence[str]) -> frozenset[str]:
    """The allow-list as the addresses a peer name shows (checked by :func:`check_host`)."""
    return frozenset(_address(a) for a in allow)


def _address(host: str) -> str:
    """``host`` written as a peer name shows it (an IPv4 address mapped into IPv6 as IPv4);
    itself when it is no IP address."""
    try:
        address = ipaddress.ip_address(host)
    except ValueError:
        return host
    mapped = getattr(address, "ipv4_mapped", None)
    return str(mapped or address)


def admitted(peer: Any, allow: frozenset[str]) -> tuple[bool, str]:
    """Whether a connection from ``peer`` (a socket's peer name) is served — with an
    allow-list, exactly the addresses in it (loopback too only when named); without one,
    loopback ones — and the peer's address (``?``: unknown)."""
    host = _address(str(peer[0])) if peer else ""
    return (host in allow if allow else is_loopback(host)), host or "?"


async def acknowledge(run: Run, cycle: int) -> bool:
    """Wait until ``run`` has published PLC cycle ``cycle`` (at most :data:`ACK_TIMEOUT`),
    without blocking the event loop; whether it has."""
    loop = asyncio.get_running_loop()
    reached = asyncio.Event()

    def tell() -> None:  # in the simulation thread, or here at once
        with contextlib.suppress(RuntimeError):  # the loop closed: the server stops
            loop.call_soon_threadsafe(reached.set)

    run.when_published(cycle, tell)
    try:
        await asyncio.wait_for(reached.wait(), ACK_TIMEOUT)
    except TimeoutError:
        run.forget(tell)
    return run.published >= cycle


def stop_on_signals(stop: Callable[[], Coroutine[Any, Any, Any]]) -> None:
    """Run the coroutine ``stop()`` on SIGTERM or SIGINT (in the running loop)."""
    loop = asyncio.get_running_loop()
    for number in (signal.SIGTERM, signal.SIGINT):
        loop.add_signal_handler(number, lambda: asyncio.ensure_future(stop()))


def run_command(checks: Callable[[], None], serve: Callable[[], Coroutine[Any, Any, None]]) -> int:
    """A server command: ``checks()`` first (a ValueError is the user's mistake: its message
    on one line of standard error, exit status 2), then ``serve()`` until it returns (0)."""
    try:
        checks()
    except ValueError as error:
        print(error, file=sys.stderr)
        return 2
    asyncio.run(serve())
    return 0

"""Who operates: one page in control at a time, the others watch; the dead-man of the jogs the
page in control holds (buttons and keys), and the notes the pages get about it."""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import viser

from viewer.session import Session

HOLD_TIMEOUT = 1.0
"""Wall time [s] a held jog button stays held without a hold message from its page. The server
renews the jog's dead-man every frame meanwhile, so a slow page (hold messages late) still jogs
smoothly; release, disconnect or loss of control end the jog at once."""

JOG_HOLD_HZ = 20.0
"""Rate [Hz] at which a held jog button refreshes its dead-man deadline (0.2 s: 4 refreshes)."""

KEY_JOG_FIRST = 0.55
"""Wall time [s] a jog key's first trigger keeps the jog alive: longer than a browser's delay
before a held key repeats (typically 0.5 s)."""

KEY_JOG_REPEAT = 0.15
"""Wall time [s] each auto-repeat of a held jog key keeps the jog alive (keys repeat every
~0.03-0.1 s); the jog stops this long after the key is let go."""


class Control:
    """Who operates: one client at a time holds control, the others watch (thread-safe)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.owner: int | None = None
        """Client id of the operator in control (None: nobody)."""
        self.since = 0.0
        """Wall clock [s since the epoch] when the owner took control."""

    def take(self, client_id: int) -> int | None:
        """``client_id`` takes control; the client that had it (None: nobody)."""
        with self._lock:
            previous = self.owner
            self.owner, self.since = client_id, time.time()
        return previous

    def release(self, client_id: int) -> bool:
        """``client_id`` gives control up (if it has it); whether it had it."""
        with self._lock:
            if self.owner != client_id:
                return False
            self.owner = None
            return True

    def holds(self, client_id: int) -> bool:
        """Whether ``client_id`` is in control."""
        return self.owner == client_id


@dataclass
class Hold:
    """A jog button a page holds."""

    generation: int
    axis: str
    direction: int
    last: float
    timeout: float = HOLD_TIMEOUT
    """Wall time [s] after ``last`` that the hold lives without a new message."""
    key: bool = False
    """Held through a jog key (renewed by the key's auto-repeat) rather than a button."""


class Operators:
    """The pages as operators: who is in control (:class:`Control`), the jog each page holds
    (its dead-man) and the notes the pages get (thread-safe).

    Args:
        session: The simulation the operators operate.
        server: The viser server of the pages.
        clock: Monotonic wall clock [s] of the holds' dead-man.
    """

    def __init__(
        self, session: Session, server: viser.ViserServer, clock: Callable[[], float]
    ) -> None:
        self.session = session
        self.server = server
        self._clock = clock
        self.control = Control()
        """Who operates (the others watch)."""
        self.holds: dict[int, Hold] = {}
        """The jog each page holds, by client id (under :attr:`lock`)."""
        self.lock = threading.Lock()
        self._refusals: dict[tuple[int, str], float] = {}

    # ------------------------------------------------------------------------- pages

    def connect(self, client: viser.ClientHandle) -> None:
        """A page opened: tell it who it is and that it watches."""
        client.add_notification(
            f"You are operator #{client.client_id}",
            "You watch. Press Take control to operate; STOP all works for everyone.",
            auto_close_seconds=8.0,
        )

    def disconnect(self, client: viser.ClientHandle) -> None:
        """A page closed: its jog ends and it loses control."""
        self.drop(client.client_id)
        if self.control.release(client.client_id):
            self.session.record_event("viewer", f"operator #{client.client_id} left: no control")

    def refused(self, client_id: int, label: str, reason: str) -> None:
        """A page sent something the gate refused: history entry and a note (once a second)."""
        now = time.monotonic()
        key = (client_id, label)
        if now - self._refusals.get(key, -math.inf) < 1.0:
            return
        self._refusals[key] = now
        what = label or "an unknown input"
        self.session.record_event("viewer", f"operator #{client_id}: {what} refused: {reason}")
        client = self.server.get_clients().get(client_id)
        if client is not None:
            client.add_notification(f"{what}: refused", reason, color="red", auto_close_seconds=4.0)

    def take(self, client_id: int) -> None:
        """The Take control button: the page operates; the one that did watches (told so)."""
        previous = self.control.take(client_id)
        if previous == client_id:
            return
        if previous is not None:
            self.drop(previous)
            other = self.server.get_clients().get(previous)
            if other is not None:
                other.add_notification(
                    "Control taken",
                    f"Operator #{client_id} operates now; you watch.",
                    color="yellow",
                    auto_close_seconds=8.0,
                )
        self.session.record_event("viewer", f"operator #{client_id} took control")

    def give(self, client_id: int) -> None:
        """The Release control button: the page watches (if it was in control)."""
        if self.control.release(client_id):
            self.drop(client_id)
            self.session.record_event("viewer", f"operator #{client_id} released control")

    # ------------------------------------------------------------------------- jog dead-man

    def hold(self, client_id: int, generation: int, axis: str, direction: int) -> None:
        """A page holds a jog button (a hold message): ``axis`` jogs in ``direction``."""
        with self.lock:
            self.holds[client_id] = Hold(generation, axis, direction, self._clock())
        self.session.requests(axis).jog(direction)

    def let_go(self, client_id: int) -> None:
        """A page let a jog button go (its hold ends; the button ends the jog)."""
        with self.lock:
            self.holds.pop(client_id, None)

    def drop(self, client_id: int, expired: Hold | None = None) -> None:
        """End the jog a page holds (only the hold ``expired`` if given: a newer one of a
        key's repeat or a button, made meanwhile, stays)."""
        with self.lock:
            if expired is not None and self.holds.get(client_id) is not expired:
                return
            hold = self.holds.pop(client_id, None)
        if hold is not None and hold.generation == self.session.snapshot.generation:
            self.session.requests(hold.axis).release_jog()

    def drop_all(self) -> None:
        """End every held jog."""
        with self.lock:
            clients = list(self.holds)
        for client_id in clients:
            self.drop(client_id)

    def forget(self) -> None:
        """Forget every hold (its scene was replaced)."""
        with self.lock:
            self.holds.clear()

    def renew(self) -> None:
        """Renew the dead-man of every held jog button (or key) whose page is connected, in
        control and sent a hold message (or key trigger) within the hold's timeout
        (:data:`HOLD_TIMEOUT`, :data:`KEY_JOG_FIRST`, :data:`KEY_JOG_REPEAT`); drop the others
        (jog ends)."""
        now = self._clock()
        clients = self.server.get_clients()
        generation = self.session.snapshot.generation
        with self.lock:
            holds = list(self.holds.items())
        for client_id, hold in holds:
            alive = (
                client_id in clients
                and self.control.holds(client_id)
                and now - hold.last <= hold.timeout
                and hold.generation == generation
            )
            if alive:
                self.session.requests(hold.axis).jog(hold.direction)
            else:
                self.drop(client_id, hold)

    def key_jog(self, client_id: int, generation: int, axis: str, direction: int) -> None:
        """What a jog hotkey does: jog ``axis`` while the page keeps triggering the key.

        The first trigger holds the jog for :data:`KEY_JOG_FIRST`, each further trigger of the
        same key (the browser's auto-repeat) for :data:`KEY_JOG_REPEAT` from then on; when the
        triggers stop, :meth:`renew` lets the jog end. Another key or a jog button of the same
        page replaces the hold (the jog it held stops).

        Args:
            client_id: The page (the gate let only the page in control through).
            generation: Scene generation the key belongs to (a key of a replaced scene does
                nothing).
            axis: The axis.
            direction: +1 (Jog+) or −1 (Jog−).
        """
        if self.session.snapshot.generation != generation:
            return
        now = self._clock()
        with self.lock:
            previous = self.holds.get(client_id)
            same = previous is not None and (
                previous.key,
                previous.generation,
                previous.axis,
                previous.direction,
            ) == (True, generation, axis, direction)
            repeat = same and previous is not None and now - previous.last <= previous.timeout
            timeout = KEY_JOG_REPEAT if repeat else KEY_JOG_FIRST
            self.holds[client_id] = Hold(generation, axis, direction, now, timeout, key=True)
        if previous is not None and not same and previous.generation == generation:
            self.session.requests(previous.axis).release_jog()
        self.session.requests(axis).jog(direction)

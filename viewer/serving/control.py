"""Who operates: one page in control at a time, the others watch and may ask for control (the
operator grants or refuses; a page that closes or stops answering hands it on); the dead-man of
the jogs the page in control holds (buttons and keys), and the notes the pages get about it."""

from __future__ import annotations

__all__ = [
    "HOLD_TIMEOUT",
    "JOG_HOLD_HZ",
    "KEY_JOG_FIRST",
    "KEY_JOG_REPEAT",
    "REQUEST_TIMEOUT",
    "Asked",
    "Control",
    "Hold",
    "Operators",
    "Request",
]

import enum
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import viser

from viewer.serving.lifesign import lifesign
from viewer.sim.session import Session

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


REQUEST_TIMEOUT = 30.0
"""Wall time [s] a request for control waits for the operator's answer before it counts as
refused."""


class Asked(enum.Enum):
    """What a page's Take control (or Request control) press did."""

    TAKEN = "taken"
    """Nobody was in control: the page is now."""
    HOLDS = "holds"
    """The page was in control already."""
    ASKED = "asked"
    """The page's request waits for the operator's answer."""
    PENDING = "pending"
    """The page's request was waiting already."""
    BUSY = "busy"
    """Another page's request waits: one at a time."""


@dataclass(frozen=True)
class Request:
    """A page asks the operator in control for control."""

    requester: int
    """Client id of the page asking."""
    owner: int
    """Client id of the operator asked."""
    since: float
    """Monotonic wall clock [s] of the request."""


class Control:
    """Who operates: one client at a time holds control, the others watch; a watcher asks the
    operator for control, who grants or refuses (thread-safe)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.owner: int | None = None
        """Client id of the operator in control (None: nobody)."""
        self.since = 0.0
        """Wall clock [s since the epoch] when the owner took control."""
        self.request: Request | None = None
        """The request waiting for the owner's answer (None: none)."""

    def _pass(self, client_id: int | None) -> None:
        """Control passes to ``client_id`` (None: nobody); a waiting request ends (under the
        lock)."""
        self.owner, self.since, self.request = client_id, time.time(), None

    def take(self, client_id: int) -> int | None:
        """``client_id`` takes control whoever has it; the client that had it (None: nobody)."""
        with self._lock:
            previous = self.owner
            self._pass(client_id)
        return previous

    def ask(self, client_id: int, now: float) -> Asked:
        """``client_id`` presses Take control at ``now`` [s, monotonic]: takes it if nobody has
        it, else asks the operator (one request at a time)."""
        with self._lock:
            if self.owner is None:
                self._pass(client_id)
                return Asked.TAKEN
            if self.owner == client_id:
                return Asked.HOLDS
            if self.request is not None:
                return Asked.PENDING if self.request.requester == client_id else Asked.BUSY
            self.request = Request(client_id, self.owner, now)
            return Asked.ASKED

    def answer(self, client_id: int, grant: bool) -> Request | None:
        """The operator ``client_id`` grants (control passes) or refuses the waiting request;
        the request answered (None: ``client_id`` is not in control or nobody asks)."""
        with self._lock:
            request = self.request
            if request is None or self.owner != client_id:
                return None
            if grant:
                self._pass(request.requester)
            else:
                self.request = None
            return request

    def cancel(self, client_id: int) -> Request | None:
        """``client_id`` withdraws its request; the request withdrawn (None: it had none)."""
        with self._lock:
            request = self.request
            if request is None or request.requester != client_id:
                return None
            self.request = None
            return request

    def expire(self, now: float, timeout: float) -> Request | None:
        """End the request if it has waited longer than ``timeout`` [s] at ``now`` [s,
        monotonic]; the request ended (None: none expired)."""
        with self._lock:
            request = self.request
            if request is None or now - request.since <= timeout:
                return None
            self.request = None
            return request

    def leave(self, client_id: int) -> tuple[bool, int | None]:
        """``client_id`` gives control up or is gone: control passes to the waiting requester
        (else nobody); a request of ``client_id`` ends. Whether it was in control, and who is
        now."""
        with self._lock:
            if self.request is not None and self.request.requester == client_id:
                self.request = None
            if self.owner != client_id:
                return False, self.owner
            self._pass(self.request.requester if self.request is not None else None)
            return True, self.owner

    def release(self, client_id: int) -> bool:
        """``client_id`` gives control up (if it has it): whether it had it (control passes to
        a waiting requester, else nobody)."""
        return self.leave(client_id)[0]

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
        """A page closed: its jog ends, its request ends, and its control passes to the page
        that asked for it (else to nobody), at once."""
        self._gone(client.client_id, "left")

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

    def note(self, client_id: int, title: str, body: str, color: Any = None) -> None:
        """A notification on the page ``client_id`` (if it is open)."""
        client = self.server.get_clients().get(client_id)
        if client is not None:
            client.add_notification(title, body, color=color, auto_close_seconds=8.0)

    def _event(self, text: str) -> None:
        self.session.record_event("viewer", text)

    def take(self, client_id: int) -> None:
        """The Take control (Request control) button: takes control if nobody has it, else
        asks the operator in control, who grants or refuses it."""
        asked = self.control.ask(client_id, self._clock())
        request = self.control.request
        if asked is Asked.TAKEN:
            self._event(f"operator #{client_id} took control")
        elif asked is Asked.ASKED and request is not None:
            self._event(f"operator #{client_id} requests control from operator #{request.owner}")
            self.note(
                request.owner,
                "Control requested",
                f"Operator #{client_id} requests control: Grant or Refuse in the Operator "
                f"window (refused by itself after {REQUEST_TIMEOUT:g} s).",
                "yellow",
            )
        elif asked is Asked.BUSY:
            self.note(client_id, "Request not sent", "Another operator's request waits.", "red")

    def answer(self, client_id: int, grant: bool) -> None:
        """The Grant or Refuse button of the operator in control."""
        request = self.control.answer(client_id, grant)
        if request is None:
            return
        if grant:
            self.drop(client_id)
            self._event(f"operator #{client_id} granted control to operator #{request.requester}")
            self.note(request.requester, "Control granted", f"by operator #{client_id}", "green")
        else:
            self._event(f"operator #{client_id} refused control to operator #{request.requester}")
            refused = f"refused by operator #{client_id}"
            self.note(request.requester, "Request refused", refused, "red")

    def cancel(self, client_id: int) -> None:
        """The Cancel request button of a page whose request waits."""
        if self.control.cancel(client_id) is not None:
            self._event(f"operator #{client_id} withdrew the request for control")

    def give(self, client_id: int) -> None:
        """The Release control button: the page watches (if it was in control); control
        passes to a page that asked for it."""
        was_owner, owner = self.control.leave(client_id)
        if was_owner:
            self.drop(client_id)
            self._event(f"operator #{client_id} released control")
            if owner is not None:
                self.note(owner, "Control passed to you", f"operator #{client_id} released it")

    def supervise(self) -> None:
        """Refuse a request unanswered for :data:`REQUEST_TIMEOUT`; a page in control without
        a lifesign for :data:`~viewer.serving.lifesign.LIFESIGN_TIMEOUT` is gone (see
        :meth:`_gone`)."""
        request = self.control.expire(self._clock(), REQUEST_TIMEOUT)
        if request is not None:
            text = f"no answer from operator #{request.owner} within {REQUEST_TIMEOUT:g} s"
            self._event(f"request of operator #{request.requester} for control refused: {text}")
            self.note(request.requester, "Request refused", text, "red")
        owner = self.control.owner
        sign = lifesign(self.server, owner) if owner is not None else None
        if owner is not None and sign is not None and not sign.alive:
            self._gone(owner, f"stopped answering (no lifesign for {sign.age:.1f} s)")

    def _gone(self, client_id: int, why: str) -> None:
        """The page ``client_id`` closed or stopped answering: its jog ends, its control passes
        to the page that asked for it (else to nobody)."""
        self.drop(client_id)
        was_owner, owner = self.control.leave(client_id)
        if not was_owner:
            return
        if owner is None:
            self._event(f"operator #{client_id} {why}: nobody in control")
        else:
            self._event(f"operator #{client_id} {why}: operator #{owner} in control")
            self.note(owner, "Control passed to you", f"operator #{client_id} {why}", "green")

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
                self.session.requests(hold.axis, answer=False).jog(hold.direction)
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

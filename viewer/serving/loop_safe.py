"""viser's message buffers woken safely from the viewer's threads.

viser 1.1.1's ``AsyncMessageBuffer.push`` (every GUI or scene handle the viewer updates) calls
``message_event.set()`` in the pushing thread: the simulation thread, the update thread or a
GUI callback's. ``asyncio.Event`` is not thread-safe: its ``set()`` iterates the event's waiters
(a deque) while the event loop's thread adds and removes its waiter in ``wait()``, which now and
then ended in ``RuntimeError: deque mutated during iteration`` in the pushing thread. ``push``
also wakes the loop properly (``call_soon_threadsafe(message_event.set)``, or at the end of an
atomic block), so off the loop's thread raising the flag is all ``set()`` needs to do.

:func:`install` gives every message buffer made from then on such an event
(:class:`LoopSafeEvent`); the viewer installs it before it makes its server.
"""

from __future__ import annotations

__all__ = ["LoopSafeEvent", "install"]

import asyncio
from typing import Any

from viser.infra._async_message_buffer import AsyncMessageBuffer


class LoopSafeEvent(asyncio.Event):
    """An ``asyncio.Event`` whose :meth:`set` may be called from any thread: on the event loop's
    thread it wakes the waiters (even when the flag is up already: another thread raised it),
    elsewhere it only raises the flag (the caller wakes the loop with
    ``call_soon_threadsafe(event.set)``)."""

    def set(self) -> None:
        try:
            running: asyncio.AbstractEventLoop | None = asyncio.get_running_loop()
        except RuntimeError:
            running = None
        bound = getattr(self, "_loop", None)
        flag: Any = self
        flag._value = True
        if running is None or (bound is not None and running is not bound):
            return  # not the loop's thread: never touch the waiters here
        for waiter in tuple(flag._waiters):
            if not waiter.done():
                waiter.set_result(True)


def install() -> None:
    """Give every message buffer viser makes from now on a :class:`LoopSafeEvent` (once)."""
    made = AsyncMessageBuffer.__init__
    if getattr(made, "loop_safe", False):
        return

    def made_loop_safe(self: AsyncMessageBuffer, *args: Any, **kwargs: Any) -> None:
        made(self, *args, **kwargs)
        self.message_event = LoopSafeEvent()

    made_loop_safe.loop_safe = True  # type: ignore[attr-defined]
    AsyncMessageBuffer.__init__ = made_loop_safe  # type: ignore[method-assign]

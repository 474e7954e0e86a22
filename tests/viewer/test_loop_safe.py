"""viser's message buffers woken from the viewer's threads: the event a handle's update sets in
the simulation or update thread never iterates the event loop's waiters there (which raised
"deque mutated during iteration" when the loop added or removed its waiter meanwhile), and a
waiter on the loop is still woken."""

from __future__ import annotations

import asyncio
import threading
from collections import deque
from collections.abc import Iterator
from typing import Any

import pytest
import viser

from viewer.serving.loop_safe import LoopSafeEvent


class WaiterAddedMeanwhile(deque[Any]):
    """The waiters of an event while the loop's thread adds one as the first is looked at."""

    def __iter__(self) -> Iterator[Any]:
        items = super().__iter__()
        yield next(items)
        self.append(None)  # the loop's thread: wait() appends its waiter
        yield from items


def set_in_a_thread(event: asyncio.Event) -> BaseException | None:
    """Call ``event.set()`` in a thread of its own (no event loop); what it raised."""
    raised: list[BaseException] = []

    def run() -> None:
        try:
            event.set()
        except BaseException as exc:  # reported to the test
            raised.append(exc)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    return raised[0] if raised else None


@pytest.fixture
def loop() -> Iterator[asyncio.AbstractEventLoop]:
    """An event loop running in a thread of its own, as viser's."""
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    try:
        yield loop
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(5.0)
        loop.close()


def test_asyncio_s_event_set_off_the_loop_breaks_when_the_loop_adds_a_waiter(
    loop: asyncio.AbstractEventLoop,
) -> None:
    """The failure: a plain asyncio.Event, set off the loop's thread (what viser's push did)."""
    plain = asyncio.Event()
    waiters = WaiterAddedMeanwhile([loop.create_future()])
    plain._waiters = waiters
    raised = set_in_a_thread(plain)
    assert isinstance(raised, RuntimeError) and "mutated during iteration" in str(raised)


def test_the_viewer_s_event_set_off_the_loop_only_raises_the_flag_and_the_loop_wakes(
    loop: asyncio.AbstractEventLoop,
) -> None:
    event = LoopSafeEvent()

    async def wait() -> bool:
        return await event.wait()

    waiting = asyncio.run_coroutine_threadsafe(wait(), loop)
    while not getattr(event, "_waiters", None):  # the loop's task waits
        threading.Event().wait(0.001)
    waiters = event._waiters
    event._waiters = WaiterAddedMeanwhile(waiters)
    assert set_in_a_thread(event) is None  # off the loop: the waiters are not touched
    assert event.is_set() and not waiting.done()
    event._waiters = waiters
    loop.call_soon_threadsafe(event.set)  # what viser's push does next
    assert waiting.result(timeout=5.0) is True


def test_every_buffer_of_a_viewer_s_server_gets_the_safe_event() -> None:
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        buffer = server._websock_server._broadcast_buffer
        assert isinstance(buffer.message_event, LoopSafeEvent)
    finally:
        server.stop()

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
from viser.infra._async_message_buffer import AsyncMessageBuffer

from viewer.serving.loop_safe import LoopSafeEvent, install


class WaiterAddedMeanwhile(deque[Any]):
    """The waiters of an event while the loop's thread adds one as the first is looked at."""

    def __iter__(self) -> Iterator[Any]:
        items = super().__iter__()
        yield next(items)
        self.append(None)  # the loop's thread: wait() appends its waiter
        yield from items


def set_in_a_thread(event: asyncio.Event, on_a_loop: bool = False) -> BaseException | None:
    """Call ``event.set()`` in a thread of its own (with an event loop of its own running:
    ``on_a_loop``, as a GUI callback run by ``asyncio.run``); what it raised."""
    raised: list[BaseException] = []

    async def on_its_loop() -> None:
        event.set()

    def run() -> None:
        try:
            if on_a_loop:
                asyncio.run(on_its_loop())
            else:
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


@pytest.mark.parametrize("on_a_loop", [False, True], ids=["no loop", "another loop"])
def test_the_viewer_s_event_set_off_the_loop_only_raises_the_flag_and_the_loop_wakes(
    loop: asyncio.AbstractEventLoop, on_a_loop: bool
) -> None:
    event = LoopSafeEvent()

    async def wait() -> bool:
        return await event.wait()

    waiting = asyncio.run_coroutine_threadsafe(wait(), loop)
    while not getattr(event, "_waiters", None):  # the loop's task waits
        threading.Event().wait(0.001)
    waiters = event._waiters
    event._waiters = WaiterAddedMeanwhile(waiters)
    assert set_in_a_thread(event, on_a_loop) is None  # off the loop: waiters not touched
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


def test_install_gives_each_buffer_made_after_it_the_safe_event_once(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Installed on a buffer class as viser makes it: each new buffer is made as before (its
    arguments passed on) and gets the safe event; installing again changes nothing."""
    made: list[tuple[Any, ...]] = []

    def plain(self: AsyncMessageBuffer, *args: Any, **kwargs: Any) -> None:
        made.append((self, args, kwargs))
        self.message_event = asyncio.Event()

    monkeypatch.setattr(AsyncMessageBuffer, "__init__", plain)
    install()
    once = AsyncMessageBuffer.__init__
    install()
    assert AsyncMessageBuffer.__init__ is once and once is not plain
    buffer = AsyncMessageBuffer("loop", persistent_messages=True)  # type: ignore[arg-type]
    assert made == [(buffer, ("loop",), {"persistent_messages": True})]
    assert isinstance(buffer.message_event, LoopSafeEvent)

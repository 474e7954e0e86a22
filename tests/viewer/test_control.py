"""Control as a master control: one page operates, another asks and the operator grants or
refuses; a page that closes or stops answering the pings hands control to the page that asked.
And the server details: one Host header, small websocket messages, the token out of the address
bar."""

from __future__ import annotations

import asyncio
import http.client
import socket
import time
from collections.abc import Iterator
from typing import Any

import msgspec
import pytest
import viser
import websockets.asyncio.client
from websockets.asyncio.client import ClientConnection

from tests.helpers import run_coroutine
from tests.viewer.test_session import CAMERA, FakeClock
from viewer.pages.control_page import control_html, lifesign_html
from viewer.serving.control import REQUEST_TIMEOUT, Asked, Control, Operators
from viewer.serving.lifesign import LIFESIGN_INTERVAL, LIFESIGN_TIMEOUT, Lifesign
from viewer.serving.security import MAX_MESSAGE
from viewer.serving.server import Viewer
from viewer.sim.session import Session

pytestmark = pytest.mark.once  # see the marker in pyproject.toml


@pytest.fixture(scope="module")
def viewer() -> Iterator[Viewer]:
    """A viewer of a machine without 3-D model, on a free loopback port."""
    with Viewer("single_axis", port=0, demo=False) as v:
        yield v


def _encode(kind: str, **fields: Any) -> bytes:
    return msgspec.msgpack.encode({"type": kind, **fields})


async def _until(condition: Any, timeout: float, what: str) -> float:
    """Wait until ``condition()`` holds; the wall time it took [s]."""
    start = time.monotonic()
    while not condition():
        if time.monotonic() - start > timeout:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        await asyncio.sleep(0.01)
    return time.monotonic() - start


async def _page(viewer: Viewer, *, keepalive: bool = True) -> tuple[ClientConnection, int]:
    """A page as a raw websocket client that carries the token cookie; it and its client id
    (once its control elements exist). Without ``keepalive`` it sends no pings of its own."""
    before = set(viewer.app.control_pages.pages)
    connection = await websockets.asyncio.client.connect(
        f"ws://127.0.0.1:{viewer.port}/",
        origin=f"http://127.0.0.1:{viewer.port}",  # type: ignore[arg-type]
        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
        additional_headers={"Cookie": f"{viewer.policy.cookie_name}={viewer.token}"},
        ping_interval=20.0 if keepalive else None,
        max_size=None,
    )
    await connection.send(_encode("ViewerCameraMessage", **CAMERA))
    pages = viewer.app.control_pages.pages
    await _until(lambda: len(set(pages) - before) == 1, 10.0, "the page's control elements")
    (client_id,) = set(pages) - before
    return connection, client_id


async def _press(viewer: Viewer, connection: ClientConnection, client_id: int, part: str) -> None:
    """Press the control button ``part`` (take, cancel, release, grant, refuse) of a page."""
    button = getattr(viewer.app.control_pages.pages[client_id], part)
    await connection.send(
        _encode("GuiUpdateMessage", uuid=button._impl.uuid, updates={"value": True})
    )


async def _drain(connection: ClientConnection) -> None:
    """Read (and forget) what the server sends, so the client answers pings."""
    try:
        async for _ in connection:
            pass
    except websockets.exceptions.ConnectionClosed:
        pass


# ------------------------------------------------------------------------- who is in control


def test_nobody_in_control_take_is_at_once_else_the_operator_is_asked() -> None:
    control = Control()
    assert control.ask(1, now=0.0) is Asked.TAKEN and control.owner == 1
    assert control.ask(1, now=0.0) is Asked.HOLDS
    assert control.ask(2, now=1.0) is Asked.ASKED and control.owner == 1
    assert control.ask(2, now=2.0) is Asked.PENDING
    assert control.ask(3, now=2.0) is Asked.BUSY  # one request at a time
    assert control.answer(2, grant=True) is None  # only the operator answers
    request = control.answer(1, grant=False)
    assert request is not None and request.requester == 2 and control.owner == 1
    assert control.request is None
    assert control.ask(3, now=3.0) is Asked.ASKED
    assert control.cancel(2) is None and control.cancel(3) is not None
    assert control.ask(3, now=4.0) is Asked.ASKED
    control.answer(1, grant=True)
    assert control.owner == 3 and control.request is None


def test_a_page_that_goes_hands_control_to_the_page_that_asked() -> None:
    control = Control()
    control.ask(1, now=0.0)
    control.ask(2, now=0.0)
    assert control.leave(2) == (False, 1) and control.request is None  # requester gone
    control.ask(2, now=0.0)
    assert control.leave(1) == (True, 2) and control.request is None
    assert control.release(2) and control.owner is None  # nobody asked: nobody in control


def test_an_unanswered_request_is_refused_after_the_request_timeout(
    server: viser.ViserServer,
) -> None:
    clock = FakeClock()
    operators = Operators(Session("single_axis"), server, clock)
    operators.take(1)
    operators.take(2)
    clock.now += REQUEST_TIMEOUT - 0.1
    operators.supervise()
    assert operators.control.request is not None
    clock.now += 0.2
    operators.supervise()
    assert operators.control.request is None and operators.control.owner == 1
    events = [e.text for e in operators.session._events]
    assert any("no answer from operator #1 within 30 s" in text for text in events)


def test_each_page_reads_its_own_control_line() -> None:
    control = Control()
    assert "nobody in control" in control_html(4, control, None)
    control.ask(4, now=0.0)
    control.ask(5, now=0.0)
    sign = Lifesign(latency=0.012, age=0.4)
    mine = control_html(4, control, sign, now=0.0)
    assert "You are in control" in mine and "12 ms, 0.4 s ago" in mine
    theirs = control_html(5, control, None, now=10.0)
    assert "Watching — operator #4 in control" in theirs and "You are" not in theirs
    assert "Your request waits for operator #4 (20 s left)" in theirs
    assert "#43a047" in lifesign_html(Lifesign(0.01, 0.5))  # green: answered lately
    assert "#e53935" in lifesign_html(Lifesign(0.01, LIFESIGN_TIMEOUT + 0.5))


def test_grant_and_refuse_work_only_from_the_page_in_control(viewer: Viewer) -> None:
    control = viewer.app.control

    async def scenario() -> None:
        (a, ia), (b, ib) = await _page(viewer), await _page(viewer)
        readers = [asyncio.create_task(_drain(c)) for c in (a, b)]
        await _press(viewer, a, ia, "take")
        await _until(lambda: control.owner == ia, 5.0, "A in control")
        await _press(viewer, b, ib, "take")  # Request control
        await _until(lambda: control.request is not None, 5.0, "B's request")
        await _press(viewer, b, ib, "grant")  # B's own (hidden) Grant: not in control
        button = viewer.app.control_pages.pages[ia].grant
        await b.send(_encode("GuiUpdateMessage", uuid=button._impl.uuid, updates={"value": 1}))
        await b.send(_encode("GuiUpdateMessage", uuid=button._impl.uuid, updates={"value": True}))
        await asyncio.sleep(0.5)
        assert control.owner == ia and control.request is not None
        await _press(viewer, a, ia, "grant")
        await _until(lambda: control.owner == ib, 5.0, "control granted to B")
        for connection in (a, b):
            await connection.close()
        await asyncio.gather(*readers)

    run_coroutine(scenario())
    assert any("take control first" in e.text for e in viewer.session._events)


def test_a_hung_page_in_control_hands_it_on_within_the_lifesign_timeout(viewer: Viewer) -> None:
    """The operator's page stops answering (its connection stays open but unread): control
    passes to the page that asked within LIFESIGN_TIMEOUT + 1 s, not before the page was late."""
    control = viewer.app.control
    measured: list[float] = []

    async def scenario() -> None:
        hung, ih = await _page(viewer, keepalive=False)
        asker, ia = await _page(viewer)
        reading = asyncio.create_task(_drain(asker))
        hung_reading = asyncio.create_task(_drain(hung))
        await _press(viewer, hung, ih, "take")
        await _until(lambda: control.owner == ih, 5.0, "the first page in control")
        await asyncio.sleep(2 * LIFESIGN_INTERVAL)  # it answers: it keeps control
        assert control.owner == ih
        await _press(viewer, asker, ia, "take")
        await _until(lambda: control.request is not None, 5.0, "the request")
        hung_reading.cancel()
        hung.transport.pause_reading()  # from now on: no pong, nothing read
        silent = time.monotonic()
        await _until(lambda: control.owner == ia, LIFESIGN_TIMEOUT + 3.0, "the handover")
        measured.append(time.monotonic() - silent)
        clients = viewer.server.get_clients
        await _until(lambda: ih not in clients(), 10.0, "the hung page to be dropped")
        await asker.close()
        await reading
        hung.transport.abort()

    run_coroutine(scenario())
    (handover,) = measured
    print(f"handover after the operator's page went silent: {handover:.2f} s")
    assert LIFESIGN_TIMEOUT - LIFESIGN_INTERVAL - 0.2 < handover < LIFESIGN_TIMEOUT + 1.0
    assert any("stopped answering" in e.text for e in viewer.session._events)


# ------------------------------------------------------------------------- server details


def _raw(port: int, request: str) -> bytes:
    """Send ``request`` as is; the status line and headers of the answer."""
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        sock.sendall(request.encode())
        answer = b""
        while b"\r\n\r\n" not in answer:
            chunk = sock.recv(4096)
            if not chunk:
                break
            answer += chunk
    return answer


def test_two_host_headers_get_400_with_the_security_headers(viewer: Viewer) -> None:
    port, token = viewer.port, viewer.token
    here = f"127.0.0.1:{port}"
    page = f"GET /?token={token} HTTP/1.1\r\nHost: {here}\r\nHost: evil.example\r\n\r\n"
    socket_upgrade = (
        f"GET /?token={token} HTTP/1.1\r\nHost: {here}\r\nHost: {here}\r\n"
        f"Upgrade: websocket\r\nConnection: Upgrade\r\nOrigin: http://{here}\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
    )
    for request in (page, socket_upgrade):
        answer = _raw(port, request)
        assert answer.startswith(b"HTTP/1.1 400"), answer[:40]
        assert b"X-Frame-Options: DENY" in answer


def test_a_2_mib_message_closes_that_connection_and_the_others_go_on(viewer: Viewer) -> None:
    closed: list[int | None] = []

    async def scenario() -> None:
        big, _ = await _page(viewer)
        other, other_id = await _page(viewer)
        reading = asyncio.create_task(_drain(other))
        await big.send(b"\x00" * (2 * MAX_MESSAGE))
        try:
            async for _ in big:
                pass
        except websockets.exceptions.ConnectionClosed as exc:
            closed.append(exc.rcvd.code if exc.rcvd else None)
        assert other_id in viewer.server.get_clients()
        await _press(viewer, other, other_id, "take")  # the other page still operates
        await _until(lambda: viewer.app.control.owner == other_id, 5.0, "control")
        late, _ = await _page(viewer)  # and a new page opens
        for connection in (other, late):
            await connection.close()
        await reading

    run_coroutine(scenario())
    assert closed == [1009]  # message too big


def test_the_token_in_the_address_is_traded_for_a_cookie_by_a_redirect(viewer: Viewer) -> None:
    port, token = viewer.port, viewer.token

    def get(path: str, **headers: str) -> http.client.HTTPResponse:
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
        connection.request("GET", path, headers=headers)
        response = connection.getresponse()
        response.read()
        connection.close()
        return response

    response = get(f"/?token={token}&view=top")
    assert response.status == 303 and response.getheader("Location") == "/?view=top"
    cookie = response.getheader("Set-Cookie", "")
    assert cookie.startswith(f"{viewer.policy.cookie_name}={token};") and "HttpOnly" in cookie
    assert get(f"/?token={token}x").status == 403  # a wrong token is still refused
    assert get("/?view=top", Cookie=cookie.split(";")[0]).status == 200


def test_a_silent_operator_with_nobody_asking_loses_control_and_its_jog(
    server: viser.ViserServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    import viewer.serving.control

    session = Session("single_axis")
    operators = Operators(session, server, FakeClock())
    operators.take(1)
    operators.hold(1, session.snapshot.generation, "X", +1)
    age = {1: LIFESIGN_TIMEOUT - 0.1}
    monkeypatch.setattr(viewer.serving.control, "lifesign", lambda _, c: Lifesign(0.01, age[c]))
    operators.supervise()
    assert operators.control.owner == 1 and 1 in operators.holds
    assert session.requests("X").take().jog_pos  # the jog runs while the page answers
    age[1] = LIFESIGN_TIMEOUT + 0.1
    operators.supervise()
    assert operators.control.owner is None and 1 not in operators.holds
    assert not session.requests("X").take().jog_pos  # the jog ended with the lifesign

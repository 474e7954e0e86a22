"""The control part of the Operator window, per page (like the master control of an axis
control panel): each page reads its own line ("You are in control" with the link's lifesign, or
"Watching — operator #N in control since …"), and its own buttons: Take control (Request
control while another page has it), Cancel request, Release control, and on the page in control
the request of another page with Grant and Refuse.

The elements belong to their page alone (``client.gui``), placed in the Operator window of the
server; every press passes the :class:`~viewer.serving.security.GuiGate` (Grant and Refuse only
from the
page in control).
"""

from __future__ import annotations

__all__ = [
    "LAMP_ALIVE",
    "LAMP_LATE",
    "LAMP_LOST",
    "ControlPages",
    "PageControl",
    "control_html",
    "lifesign_html",
    "request_html",
]

import html
import threading
import time
from dataclasses import dataclass, field
from typing import Any

import viser

from viewer.pages.panels import utc
from viewer.serving.control import REQUEST_TIMEOUT, Control, Operators
from viewer.serving.lifesign import LIFESIGN_INTERVAL, LIFESIGN_TIMEOUT, Lifesign, lifesign
from viewer.serving.security import GuiGate, button_value

_BOX = '<div style="font-size:0.85em;line-height:1.4;padding:0 0.6em">{}</div>'

LAMP_ALIVE, LAMP_LATE, LAMP_LOST = "#43a047", "#ffb300", "#e53935"
"""Colours of the lifesign dot: answered within 1.5 pings, within the timeout, not since."""


def lifesign_html(sign: Lifesign | None) -> str:
    """The lifesign of the link: a dot, the last round trip [ms] and the time since [s]."""
    if sign is None:
        return "lifesign: no link"
    if sign.age <= 1.5 * LIFESIGN_INTERVAL:
        colour = LAMP_ALIVE
    else:
        colour = LAMP_LATE if sign.age <= LIFESIGN_TIMEOUT else LAMP_LOST
    return (
        f'lifesign <span style="color:{colour}">●</span> '
        f"{sign.latency * 1e3:.0f} ms, {sign.age:.1f} s ago"
    )


def control_html(
    client_id: int,
    control: Control,
    sign: Lifesign | None,
    now: float | None = None,
    plc: str = "",
) -> str:
    """The control line of the page ``client_id``: in control (with the lifesign ``sign`` of
    its link) or watching whom; its waiting request with the time left (``now``: monotonic
    wall clock [s], default the current); first, the external PLC ``plc`` that commands the
    machine (empty: none does)."""
    now = time.monotonic() if now is None else now
    owner, request = control.owner, control.request
    since = f"since {utc(control.since)[:8]} UTC"
    if owner == client_id:
        text = f"<b>You are in control</b> (operator #{client_id}) {since}"
        text += "<br>" + lifesign_html(sign)
    elif owner is None:
        text = "Watching — nobody in control: press <b>Take control</b> to operate."
    else:
        text = f"Watching — operator #{owner} in control {since}"
    if request is not None and request.requester == client_id:
        left = max(REQUEST_TIMEOUT - (now - request.since), 0.0)
        text += f"<br>Your request waits for operator #{request.owner} ({left:.0f} s left)."
    if plc:
        text = (
            f'<span style="color:#1565c0"><b>The {html.escape(plc)} commands the machine</b>'
            "</span> — STOP all, a Power button or End demo takes it back.<br>" + text
        )
    return _BOX.format(text)


def request_html(control: Control, now: float | None = None) -> str:
    """The request the operator in control is asked to answer (empty: none)."""
    request = control.request
    if request is None:
        return ""
    now = time.monotonic() if now is None else now
    left = max(REQUEST_TIMEOUT - (now - request.since), 0.0)
    return _BOX.format(
        f'<span style="color:#e65100"><b>Operator #{request.requester} requests control</b>'
        f"</span> ({left:.0f} s left)"
    )


@dataclass
class PageControl:
    """The control elements of one page (and what was last sent to them)."""

    line: viser.GuiHtmlHandle
    take: viser.GuiButtonHandle
    cancel: viser.GuiButtonHandle
    release: viser.GuiButtonHandle
    prompt: viser.GuiHtmlHandle
    grant: viser.GuiButtonHandle
    refuse: viser.GuiButtonHandle
    shown: dict[tuple[str, str], Any] = field(default_factory=dict)

    @property
    def buttons(self) -> list[viser.GuiButtonHandle]:
        """The page's control buttons."""
        return [self.take, self.cancel, self.release, self.grant, self.refuse]

    def set(self, part: str, prop: str, value: Any) -> None:
        """Set ``prop`` of the element ``part`` to ``value`` if it changed (not on an element
        viser removed: the page is closing)."""
        handle = getattr(self, part)
        if self.shown.get((part, prop)) != value and not handle._impl.removed:
            self.shown[(part, prop)] = value
            setattr(handle, prop, value)


class ControlPages:
    """The control elements of every page, in the Operator window (thread-safe).

    Args:
        gate: Checks every press.
        operators: Who operates (the buttons act on it).
        tab: The Operator window's tab the elements go into.
        order: Order of the first element in the tab (the others follow).
    """

    def __init__(
        self, gate: GuiGate, operators: Operators, tab: viser.GuiTabHandle, order: float
    ) -> None:
        self.gate, self.operators, self._tab, self._order = gate, operators, tab, order
        self._lock = threading.Lock()
        self._build_lock = threading.Lock()
        self.pages: dict[int, PageControl] = {}
        """The control elements of each open page, by client id."""

    def connect(self, client: viser.ClientHandle) -> None:
        """A page opened: its own control line and buttons."""
        gui, client_id, order = client.gui, client.client_id, self._order
        with self._build_lock, self._tab:  # a tab is a context of one thread at a time
            line = gui.add_html(control_html(client_id, self.operators.control, None), order=order)
            buttons = (
                ("Take control", viser.Icon.USER_CHECK, "Operate (or ask the operator)", True),
                ("Cancel request", viser.Icon.X, "Withdraw your request", False),
                ("Release control", viser.Icon.USER_X, "Watch only", False),
            )
            take, cancel, release = (
                gui.add_button(label, icon=icon, hint=hint, visible=shown, order=order + i)
                for i, (label, icon, hint, shown) in enumerate(buttons, start=1)
            )
            prompt = gui.add_html("", visible=False, order=order + 4)
            grant = gui.add_button("Grant", color="green", visible=False, order=order + 5)
            refuse = gui.add_button("Refuse", color="red", visible=False, order=order + 6)
        page = PageControl(line, take, cancel, release, prompt, grant, refuse)
        for button in (take, cancel, release):
            self.gate.allow(button, button_value, control=False)
        for button in (grant, refuse):
            self.gate.allow(button, button_value, control=True)
        operators = self.operators
        take.on_click(lambda _: operators.take(client_id))
        cancel.on_click(lambda _: operators.cancel(client_id))
        release.on_click(lambda _: operators.give(client_id))
        grant.on_click(lambda _: operators.answer(client_id, grant=True))
        refuse.on_click(lambda _: operators.answer(client_id, grant=False))
        with self._lock:
            self.pages[client_id] = page
        self._show(client_id, page)

    def disconnect(self, client: viser.ClientHandle) -> None:
        """A page closed: forget its elements (viser removed them) and their rules."""
        with self._lock:
            page = self.pages.pop(client.client_id, None)
        if page is not None:
            self.gate.forget(page.buttons)

    def refresh(self) -> None:
        """Send every page what changed in its control line and buttons."""
        with self._lock:
            pages = list(self.pages.items())
        for client_id, page in pages:
            self._show(client_id, page)

    def _show(self, client_id: int, page: PageControl) -> None:
        control = self.operators.control
        owner, request = control.owner, control.request
        in_control = owner == client_id
        asking = request is not None and request.requester == client_id
        asked = in_control and request is not None
        sign = lifesign(self.operators.server, client_id) if in_control else None
        plc = self.operators.session.plc_in_control
        page.set("line", "content", control_html(client_id, control, sign, plc=plc))
        page.set("take", "label", "Take control" if owner is None else "Request control")
        page.set("take", "visible", not in_control and not asking)
        page.set("cancel", "visible", asking)
        page.set("release", "visible", in_control)
        page.set("prompt", "content", request_html(control) if asked else "")
        for part in ("prompt", "grant", "refuse"):
            page.set(part, "visible", asked)

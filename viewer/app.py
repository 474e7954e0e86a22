"""The browser viewer: viser GUI for a :class:`~viewer.session.Session` and its update loop.

:class:`ViewerApp` builds the control panel and the 3-D scene (:class:`ModelScene`) and runs a
loop in its own thread that, up to ``fps`` times per second, takes the session's latest
:class:`~viewer.session.Snapshot` and sends what changed: body poses, switch colours, the
overlays of :mod:`viewer.overlays` (set-point ghost, forces) and the follow cameras, the
axis panels, the error history and the scope. GUI callbacks only call :class:`Session` methods
(request flags and queued commands) and the scope's own state; viser objects are modified by the
update thread (and the notifications of the callbacks).

:class:`Viewer` bundles server, session and app: ``Viewer(scene="gantry", port=8080)`` serves
the viewer on ``http://127.0.0.1:8080/?token=…`` until :meth:`Viewer.close`, behind the access
policy of :mod:`viewer.security` (same origin, expected Host, token, security headers).

Everything machine-specific comes from the registry (``scenes.MACHINES``) and the scene: the
chooser lists ``sorted(scenes.MACHINES)``; each axis panel shows the axis' own unit, only the
switches the machine definition gives it, its digital inputs and outputs, and drive buttons only
if it has a drive (Home only with a homing recipe); a machine that publishes signals gets a
signals panel (and scope channels); a demo with a ``results`` table gets a results panel; a
machine of simulated axes (no MuJoCo model) shows a note instead of a 3-D model.

The page offers no way to run code or touch files: no text inputs, no uploads, only buttons,
dropdowns, sliders and number boxes whose values the :class:`~viewer.security.GuiGate` checks
against fixed choices and finite ranges (and control) before viser applies them; viser's share
tunnel and upload requests are refused (:func:`harden`).
"""

from __future__ import annotations

import csv
import dataclasses
import errno
import html
import io
import logging
import math
import socket
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt
import viser
import viser.uplot
from viser._messages import HotkeyKey

import mcl.faults
import scenes
from viewer.model_scene import ModelScene
from viewer.operator import HOMING_PROCEDURES, AxisRequests, Move
from viewer.overlays import (
    DEFAULT_FORCE_SCALE,
    FORCE_SCALES,
    ContactOverlay,
    SetPointGhost,
    ghost_axes,
)
from viewer.security import (
    AccessPolicy,
    BoundedLog,
    GuiGate,
    button_value,
    choice_of,
    is_loopback,
    make_token,
    number_in,
    secure_server,
)
from viewer.session import AxisView, Channel, Recorder, Session, Snapshot, choices

log = logging.getLogger(__name__)

DEFAULT_HOST = "127.0.0.1"
"""Interface the viewer binds unless told otherwise: this machine only."""

DEFAULT_PORT = 8080
"""TCP port of the viewer's HTTP and websocket server."""

SPEEDS: dict[str, float] = {
    "0.1×": 0.1,
    "0.25×": 0.25,
    "0.5×": 0.5,
    "1×": 1.0,
    "2×": 2.0,
    "5×": 5.0,
    "10×": 10.0,
    "max": math.inf,
}
"""Speed choices: label → simulated seconds per wall second (``inf``: as fast as possible)."""

JOG_HOLD_HZ = 20.0
"""Rate [Hz] at which a held jog button refreshes its dead-man deadline (0.2 s: 4 refreshes)."""

LAMP_LIMIT = (0.95, 0.15, 0.10)
"""Colour of an actuated limit switch (red), RGB in [0, 1]."""

LAMP_REF = (1.0, 0.72, 0.0)
"""Colour of an actuated reference switch (amber), RGB in [0, 1]."""

_LAMP_HTML = {
    "on_limit": "#e53935",
    "on_ref": "#ffb300",
    "on_info": "#43a047",
    "on_output": "#1e88e5",
    "off": "#cfd8dc",
}

SWITCHES = (("lim_neg", LAMP_LIMIT), ("lim_pos", LAMP_LIMIT), ("ref", LAMP_REF))
"""Switch kinds of models/README.md and their lamp colours."""

SWITCH_LAMPS = (
    ("lim_neg", "LIM−", "on_limit"),
    ("ref", "REF", "on_ref"),
    ("lim_pos", "LIM+", "on_limit"),
)
"""Panel lamps of the switch inputs: (AxisView field, label, lamp kind), left to right."""

NO_MODEL_NOTE = "simulated axes: no 3-D model"
"""Shown in the 3-D view for a machine without a MuJoCo model."""


REFUSED_MESSAGES = ("ShareUrlRequest", "FileTransferStartUpload", "FileTransferPart")
"""Requests a browser could send to any viser server that this viewer ignores: opening a public
share tunnel (which would put the operator controls on the internet) and file uploads."""


def harden(server: viser.ViserServer) -> None:
    """Make a viser server refuse :data:`REFUSED_MESSAGES` and hide its share button.

    viser 1.1.1 has no public switch for this, so the handlers are unregistered from its websocket
    server; a message without a handler is dropped.

    Args:
        server: The server, before clients connect.
    """
    server.gui.configure_theme(show_share_button=False)
    websock = server._websock_server
    handlers = websock._incoming_handlers
    for name in REFUSED_MESSAGES:
        message_class = getattr(viser._messages, name, None)
        if message_class is not None and message_class in handlers:
            websock.unregister_handler(message_class)


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


def speed_label(speed: float) -> str:
    """Dropdown label of a speed factor (``"1×"``, ``"max"``, or e.g. ``"3×"``)."""
    for label, value in SPEEDS.items():
        if value == speed:
            return label
    return f"{speed:g}×"


def _lamp(on: bool, label: str, kind: str) -> str:
    color = _LAMP_HTML[kind] if on else _LAMP_HTML["off"]
    return (
        f'<span style="white-space:nowrap;margin-right:0.7em">'
        f'<span style="display:inline-block;width:0.75em;height:0.75em;border-radius:50%;'
        f'background:{color};border:1px solid #90a4ae;vertical-align:-0.1em"></span> '
        f"{label}</span>"
    )


def _table(rows: Sequence[tuple[str, str]]) -> str:
    """A two-column read-out table (names left, values right in monospace)."""
    body = "".join(
        f'<tr><td style="padding:0 0.5em 0 0">{name}</td>'
        f'<td style="text-align:right;font-family:monospace;white-space:pre">{value}</td></tr>'
        for name, value in rows
    )
    return f'<table style="width:100%;border-collapse:collapse">{body}</table>'


def axis_panel_html(view: AxisView) -> str:
    """The read-outs of one axis as HTML: values in the axis' unit, state, error text, lamps.

    Only what the axis has is shown: the switches of its machine definition, its digital inputs
    (``DI``) and outputs (``DO``, read-only), the command only if it has a drive.

    Args:
        view: The axis view of a snapshot.

    Returns:
        An HTML fragment (texts escaped).
    """
    unit = html.escape(view.unit)
    error = html.escape(view.error) if view.error else "—"
    rows = [
        ("Position", f"{view.position:10.3f} {unit}"),
        ("Velocity", f"{view.velocity:10.2f} {unit}/s"),
    ]
    if view.has_drive:
        rows += [
            ("Following error", f"{view.following_error:10.4f} {unit}"),
            ("Command", f"{view.volts:10.3f} V"),
        ]
    else:
        rows.append(("Drive", "none (encoder only)"))
    rows += [
        ("State", f"<b>{html.escape(view.state or '—')}</b>"),
        ("Error", f'<span style="color:#c62828">{error}</span>' if view.error else error),
    ]
    if view.last_error:
        rows.append(
            ("Refused", f'<span style="color:#c62828">{html.escape(view.last_error)}</span>')
        )
    if view.group:
        rows.append(("Group", html.escape(view.group)))
    lamps = "".join(
        _lamp(bool(getattr(view, field)), label, kind)
        for field, label, kind in SWITCH_LAMPS
        if field in view.switches
    )
    lamps += _lamp(view.index, "Index", "on_info") + _lamp(view.referenced, "Homed", "on_info")
    lamps += "".join(_lamp(on, f"DI{i}", "on_info") for i, on in enumerate(view.inputs))
    outputs = "".join(_lamp(on, f"DO{i}", "on_output") for i, on in enumerate(view.outputs))
    if outputs:
        outputs = f'<div style="line-height:1.6">Outputs: {outputs}</div>'
    message = html.escape(view.message) if view.message else "&nbsp;"
    return (
        f'<div style="font-size:0.85em;padding:0 0.75em">{_table(rows)}'
        f'<div style="margin-top:0.4em;line-height:1.6">{lamps}</div>{outputs}'
        f'<div style="color:#546e7a;margin-top:0.2em">{message}</div></div>'
    )


def signals_html(snapshot: Snapshot) -> str:
    """The machine's published signals as HTML: name, value, unit (texts escaped)."""
    rows = [
        (html.escape(s.name), f"{s.value:12.3f} {html.escape(s.unit)}") for s in snapshot.signals
    ]
    return f'<div style="font-size:0.85em;padding:0 0.75em">{_table(rows)}</div>'


def status_html(snapshot: Snapshot) -> str:
    """The simulation status line: simulated time, speed, achieved real-time factor."""
    if snapshot.fault:
        state = f'<span style="color:#c62828">stopped: {html.escape(snapshot.fault)}</span>'
    elif snapshot.paused:
        state = "paused"
    else:
        state = (
            f"running at {speed_label(snapshot.speed)} (achieved {snapshot.realtime_factor:.2f}×)"
        )
    note = "" if snapshot.model is not None else f" · {NO_MODEL_NOTE}"
    return (
        f'<div style="font-size:0.85em;padding:0 0.75em">'
        f"<b>{html.escape(snapshot.scene)}</b> · t = {snapshot.time:9.3f} s · {state}"
        f'<div style="color:#546e7a">{html.escape(snapshot.description)}{note}</div></div>'
    )


SCOPE_TRACES = 4
"""Signals the scope shows at once."""

SCOPE_WINDOWS = ("1 s", "2 s", "4 s", "10 s")
"""Time bases the scope offers."""

FREE_RUN = "free run"
"""Scope trigger choice: no trigger."""

ON_ERROR = "on any axis error"
"""Scope trigger choice: the rising edge of any axis' error flag."""

NO_TRACE = "—"
"""Scope channel choice: nothing."""

HOLD_TIMEOUT = 1.0
"""Wall time [s] a held jog button stays held without a hold message from its page. The server
renews the jog's dead-man every frame meanwhile, so a slow page (hold messages late) still jogs
smoothly; release, disconnect or loss of control end the jog at once."""

EVENTS_SHOWN = 15
"""Entries of the error history the panel shows (newest first)."""

STEPS = ("0.01", "0.1", "1", "10", "100")
"""Incremental jog steps [u]."""

STEP_KEYS: tuple[tuple[HotkeyKey, HotkeyKey], ...] = (
    ("arrowright", "arrowleft"),
    ("arrowup", "arrowdown"),
    ("pageup", "pagedown"),
)
"""Hotkeys (with Shift) of Step+ and Step− of the first three driven axes; each press (and each
key repeat while held) moves the axis by its Step."""

JOG_KEYS = STEP_KEYS
"""Hotkeys (with Alt) of Jog+ and Jog− of the first three driven axes: the axis jogs while the
key is held. The page sends a trigger on the press and on every auto-repeat of the key, no
release: each trigger renews a dead-man (:data:`KEY_JOG_FIRST`, then :data:`KEY_JOG_REPEAT`)."""

KEY_JOG_FIRST = 0.55
"""Wall time [s] a jog key's first trigger keeps the jog alive: longer than a browser's delay
before a held key repeats (typically 0.5 s)."""

KEY_JOG_REPEAT = 0.15
"""Wall time [s] each auto-repeat of a held jog key keeps the jog alive (keys repeat every
~0.03-0.1 s); the jog stops this long after the key is let go."""

OFF, ON = "off", "on"
SWITCH_CHOICES = (OFF, ON)
"""Choices of an overlay that is shown or not (a dropdown: the page offers no checkboxes)."""

FOLLOW_OFF = OFF
"""Follow-camera choice: the camera stays where the page puts it."""

FOLLOW_STEP = 1e-4
"""Body travel [m] after which a following camera is moved along (smaller moves accumulate)."""

FAULTS: dict[str, mcl.faults.Fault] = {
    "force LIM+ on": mcl.faults.SwitchStuck("lim_pos", True),
    "force LIM− on": mcl.faults.SwitchStuck("lim_neg", True),
    "force REF on": mcl.faults.SwitchStuck("ref", True),
    "force REF off": mcl.faults.SwitchStuck("ref", False),
    "encoder freeze": mcl.faults.EncoderFreeze(),
    "encoder wire break": mcl.faults.EncoderWireBreak(),
    "drive not ready": mcl.faults.DriveNotReady(),
    "amplifier fault": mcl.faults.AmplifierFault(),
    "brake does not hold": mcl.faults.BrakeFailure(),
    "analog offset 0.1 V": mcl.faults.AnalogOffset(0.1),
}
"""Inputs the panel can force and faults it can inject (``scene.faults``), by label; the panel
offers each for the axes it applies to."""

TUNING = (
    ("Kp", "Kp [V/u]", 0.0, 1e6),
    ("Ki", "Ki [V/(u·s)]", 0.0, 1e6),
    ("Ff", "Ff [-]", 0.0, 10.0),
    ("Ka", "Ka [s]", 0.0, 10.0),
    ("LimPos", "LimPos [u]", -1e9, 1e9),
    ("LimNeg", "LimNeg [u]", -1e9, 1e9),
)
"""Servo constants of the tuning panel: (GT_SetConstant input, label, min, max)."""

FRAME_OUTLIER = 50.0
"""Geoms bigger than this many times the median geom are left out of the camera framing."""

VIEWS = {
    "Fit": (0.9, -1.6, 0.9),
    "Front": (0.0, -1.0, 0.15),
    "Side": (1.0, 0.0, 0.15),
    "Top": (0.0, -0.05, 1.0),
}
"""Camera presets: direction from the machine's centre to the camera."""


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
class _Hold:
    """A jog button a page holds."""

    generation: int
    axis: str
    direction: int
    last: float
    timeout: float = HOLD_TIMEOUT
    """Wall time [s] after ``last`` that the hold lives without a new message."""
    key: bool = False
    """Held through a jog key (renewed by the key's auto-repeat) rather than a button."""


@dataclass
class _AxisWidgets:
    """The GUI elements of one axis panel."""

    panel: viser.GuiHtmlHandle
    power: viser.GuiButtonHandle | None
    unit: str
    buttons: tuple[str, ...]
    html: str = ""
    powered: bool | None = None


def _utc(wall: float) -> str:
    """Wall-clock time as ``HH:MM:SS.mmm`` UTC."""
    return time.strftime("%H:%M:%S", time.gmtime(wall)) + f".{int(wall % 1.0 * 1000):03d}"


def events_html(snapshot: Snapshot, shown: int = EVENTS_SHOWN) -> str:
    """The error history, newest first: UTC time, simulated time, source, text (escaped)."""
    events = snapshot.events[-shown:][::-1]
    if not events:
        return '<div style="font-size:0.85em;padding:0 0.75em">No errors.</div>'
    rows = "".join(
        f'<tr><td style="white-space:nowrap;font-family:monospace">{_utc(e.wall)}</td>'
        f'<td style="white-space:nowrap;font-family:monospace">t={e.time:.3f}</td>'
        f"<td>{html.escape(e.source)}</td><td>{html.escape(e.text)}</td></tr>"
        for e in events
    )
    return (
        f'<div style="font-size:0.8em;padding:0 0.75em"><table style="border-collapse:collapse">'
        f"{rows}</table></div>"
    )


def results_html(snapshot: Snapshot) -> str:
    """The demo's results table (last rows; texts escaped)."""
    columns, rows = snapshot.results
    if not columns:
        return '<div style="font-size:0.85em;padding:0 0.75em">No results yet.</div>'
    head = "".join(f'<th style="padding:0 0.4em">{html.escape(c)}</th>' for c in columns)
    body = "".join(
        "<tr>"
        + "".join(
            f'<td style="text-align:right;font-family:monospace;padding:0 0.4em">'
            f"{html.escape(v)}</td>"
            for v in row
        )
        + "</tr>"
        for row in rows
    )
    return (
        f'<div style="font-size:0.8em;padding:0 0.75em;overflow-x:auto">'
        f'<table style="border-collapse:collapse"><tr>{head}</tr>{body}</table></div>'
    )


def scope_csv(
    names: Sequence[str], t: npt.NDArray[np.float64], values: npt.NDArray[np.float64]
) -> str:
    """The scope's traces as CSV: ``t [s]`` then one column per trace (header with units)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["t [s]", *names])
    for k in range(t.size):
        writer.writerow([f"{t[k]:.6f}", *(f"{v:.9g}" for v in values[:, k])])
    return out.getvalue()


class ViewerApp:
    """Control panel and 3-D scene of a session in a viser server, updated by its own thread.

    Every value a page sends passes a :class:`~viewer.security.GuiGate`: it must fit the
    element (choices, finite ranges), and everything that operates the machine needs control
    (:class:`Control`, the Take control button); STOP all, the camera views and the scope are
    for everyone.

    Args:
        session: The simulation to show and operate.
        server: The viser server to build the GUI in.
        fps: Frames per second of the update loop [Hz] (poses and switch colours).
        panel_hz: Refresh rate of the axis panels and the status line [Hz].
        plot_hz: Refresh rate of the scope [Hz].
        environment_map: Light the scene with viser's HDRI environment map. It looks best but
            makes a browser without GPU (software WebGL) draw ~10× slower; the default lights
            the scene with a hemisphere light and the default lights without shadows instead
            (shadows halve the frame rate of a browser without GPU).
        log: Where refused GUI messages are logged (bounded).
        clock: Monotonic wall clock [s] of the jog holds' dead-man (injectable for tests).
    """

    def __init__(
        self,
        session: Session,
        server: viser.ViserServer,
        *,
        fps: float = 30.0,
        panel_hz: float = 12.0,
        plot_hz: float = 10.0,
        environment_map: bool = False,
        log: BoundedLog | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.session = session
        self.server = server
        self._clock = clock
        self._frame_period = 1.0 / fps
        self._panel_period = 1.0 / panel_hz
        self._plot_period = 1.0 / plot_hz
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None
        self.frame_costs: deque[float] = deque(maxlen=10_000)
        """Wall time [s] of recent frames that had a new snapshot to send."""
        self.frames = 0
        """Frames that sent a new snapshot."""
        self.panel_updates = 0
        """Times the panels were refreshed."""

        self._model_scene: ModelScene | None = None
        self._generation = 0
        self._last: Snapshot | None = None
        self._last_panel = self._last_plot = -math.inf
        self._axes: dict[str, _AxisWidgets] = {}
        self._lamps: list[tuple[str, str, str, tuple[float, float, float]]] = []
        """Switch geoms coloured from the inputs: (axis, AxisView field, geom, lamp colour)."""
        self._note: viser.LabelHandle | None = None
        self._scene_gui: list[viser.GuiFolderHandle] = []
        self._scene_inputs: list[Any] = []
        self._commands: list[Any] = []
        self._steps: dict[str, viser.GuiDropdownHandle[str]] = {}
        self._signals: viser.GuiHtmlHandle | None = None
        self._signals_html = ""
        self._results: viser.GuiHtmlHandle | None = None
        self._results_html = ""
        self._events_html = ""
        self._control_html = ""
        self._pause_label = ""
        self._status_html = self._demo_html = ""
        self._bounds: tuple[npt.NDArray[np.float64], float] | None = None
        self.control = Control()
        """Who operates (the others watch)."""
        self._holds: dict[int, _Hold] = {}
        self._holds_lock = threading.Lock()
        # 3-D overlays: the GUI callbacks set the wishes, the update thread draws
        self._ghost: SetPointGhost | None = None
        self._contacts: ContactOverlay | None = None
        self.show_ghost = False
        """The set-point ghost is drawn (the View folder's toggle)."""
        self.show_contacts = False
        """Contact, hard-stop and tendon forces are drawn (the View folder's choice)."""
        self.force_scale = DEFAULT_FORCE_SCALE
        """Length of the force arrows, a key of :data:`FORCE_SCALES`."""
        self.follow = FOLLOW_OFF
        """Body the pages' cameras follow (:data:`FOLLOW_OFF`: none)."""
        self._follow_anchor: dict[int, tuple[int, npt.NDArray[np.float64]]] = {}
        """Per page: the followed body and its position [m] when the camera last moved along."""
        self._follow_ids: dict[str, int] = {}
        self._redraw = False
        self._refusals: dict[tuple[int, str], float] = {}
        # scope state
        self._scope_plot: viser.GuiUplotHandle | None = None
        self._scope_traces: list[viser.GuiDropdownHandle[str]] = []
        self._scope_window: viser.GuiDropdownHandle[str] | None = None
        self._scope_trigger: viser.GuiDropdownHandle[str] | None = None
        self._scope_run: viser.GuiButtonHandle | None = None
        self._scope_status: viser.GuiHtmlHandle | None = None
        self._scope_paused = False
        self._scope_armed_since = -math.inf
        self._scope_trigger_at: float | None = None
        self._scope_style: tuple[str, ...] = ()
        self.scope_shown: tuple[tuple[str, ...], npt.NDArray[np.float64], npt.NDArray[np.float64]]
        """What the scope shows: (trace names with units, t [s], values (traces × samples))."""
        self.scope_shown = ((), np.zeros(0), np.zeros((0, 0)))

        harden(server)
        self.gate = GuiGate(server, self.control.holds, self._refused, log=log)
        """Checks every GUI value a page sends."""
        server.on_client_connect(self._on_connect)
        server.on_client_disconnect(self._on_disconnect)
        server.scene.set_up_direction("+z")
        if not environment_map:
            server.scene.configure_environment_map(None)
            server.scene.configure_default_lights(cast_shadow=False)
            server.scene.add_light_hemisphere(
                "/lights/hemisphere",
                sky_color=(255, 255, 255),
                ground_color=(120, 120, 120),
                intensity=1.0,
            )
        self._build_static_gui()
        self._rebuild(session.snapshot)

    @property
    def model_scene(self) -> ModelScene | None:
        """The 3-D scene of the current model (replaced when the session loads a scene); None
        for a machine of simulated axes, which has no model."""
        return self._model_scene

    @property
    def scene_choices(self) -> tuple[str, ...]:
        """The machines the scene chooser offers (``sorted(scenes.MACHINES)``)."""
        return tuple(self._scene_choice.options)

    @property
    def axis_widgets(self) -> dict[str, list[str]]:
        """The labels of the buttons of each axis panel (what the operator can press)."""
        return {name: list(w.buttons) for name, w in self._axes.items()}

    # ------------------------------------------------------------------------- clients

    def _on_connect(self, client: viser.ClientHandle) -> None:
        client.add_notification(
            f"You are operator #{client.client_id}",
            "You watch. Press Take control to operate; STOP all works for everyone.",
            auto_close_seconds=8.0,
        )

    def _on_disconnect(self, client: viser.ClientHandle) -> None:
        self._drop_holds(client.client_id)
        if self.control.release(client.client_id):
            self.session.record_event("viewer", f"operator #{client.client_id} left: no control")

    def _refused(self, client_id: int, label: str, reason: str) -> None:
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

    def _drop_holds(self, client_id: int, expired: _Hold | None = None) -> None:
        """End the jog a page holds (only the hold ``expired`` if given: a newer one of a
        key's repeat or a button, made meanwhile, stays)."""
        with self._holds_lock:
            if expired is not None and self._holds.get(client_id) is not expired:
                return
            hold = self._holds.pop(client_id, None)
        if hold is not None and hold.generation == self.session.snapshot.generation:
            self.session.requests(hold.axis).release_jog()

    def renew_holds(self) -> None:
        """Renew the dead-man of every held jog button (or key) whose page is connected, in
        control and sent a hold message (or key trigger) within the hold's timeout
        (:data:`HOLD_TIMEOUT`, :data:`KEY_JOG_FIRST`, :data:`KEY_JOG_REPEAT`); drop the others
        (jog ends)."""
        now = self._clock()
        clients = self.server.get_clients()
        generation = self.session.snapshot.generation
        with self._holds_lock:
            holds = list(self._holds.items())
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
                self._drop_holds(client_id, hold)

    def key_jog(self, client_id: int, generation: int, axis: str, direction: int) -> None:
        """What a jog hotkey does: jog ``axis`` while the page keeps triggering the key.

        The first trigger holds the jog for :data:`KEY_JOG_FIRST`, each further trigger of the
        same key (the browser's auto-repeat) for :data:`KEY_JOG_REPEAT` from then on; when the
        triggers stop, :meth:`renew_holds` lets the jog end. Another key or a jog button of the
        same page replaces the hold (the jog it held stops).

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
        with self._holds_lock:
            previous = self._holds.get(client_id)
            same = previous is not None and (
                previous.key,
                previous.generation,
                previous.axis,
                previous.direction,
            ) == (True, generation, axis, direction)
            repeat = same and previous is not None and now - previous.last <= previous.timeout
            timeout = KEY_JOG_REPEAT if repeat else KEY_JOG_FIRST
            self._holds[client_id] = _Hold(generation, axis, direction, now, timeout, key=True)
        if previous is not None and not same and previous.generation == generation:
            self.session.requests(previous.axis).release_jog()
        self.session.requests(axis).jog(direction)

    # ------------------------------------------------------------------------- GUI: static

    def _button(
        self,
        label: str,
        *,
        control: bool = True,
        **kwargs: Any,
    ) -> viser.GuiButtonHandle:
        """A button the gate lets pages press (those in control unless ``control`` is False)."""
        button = self.server.gui.add_button(label, **kwargs)
        self.gate.allow(button, button_value, control)
        return button

    def _build_static_gui(self) -> None:
        """Control, simulation and demo controls (independent of the scene)."""
        gui = self.server.gui
        session = self.session
        operator = gui.add_panel(order=-1)  # a window of its own: never scrolled out of sight
        operator.float(x=15, y=-15, width=300)
        with operator.add_tab("Operator", icon=viser.Icon.USER):
            self._stop_all = self._button(
                "STOP all axes",
                control=False,
                color="red",
                icon=viser.Icon.HAND_STOP,
                hint="Ends the demo, ramps every axis and group down (anyone may press it)",
            )
            self._control_status = gui.add_html("")
            self._take = self._button(
                "Take control", control=False, icon=viser.Icon.USER_CHECK, hint="Operate"
            )
            self._give = self._button(
                "Release control", control=False, icon=viser.Icon.USER_X, hint="Watch only"
            )
        with gui.add_folder("Simulation", order=0):
            self._status = gui.add_html("", order=0)
            self._scene_choice = gui.add_dropdown(
                "Scene", choices(), initial_value=session.scene_name, order=1
            )
            self.gate.allow(self._scene_choice, choice_of(choices()))
            labels = list(SPEEDS)
            current = speed_label(session.speed)
            if current not in labels:
                labels.insert(0, current)
            self._speeds = {label: SPEEDS.get(label, session.speed) for label in labels}
            self._speed_choice = gui.add_dropdown("Speed", labels, initial_value=current, order=2)
            self.gate.allow(self._speed_choice, choice_of(labels))
            self._pause = self._button("Pause", icon=viser.Icon.PLAYER_PAUSE, order=3)
            self._step = self._button(
                "Step",
                hint="Pause and run one PLC cycle",
                icon=viser.Icon.PLAYER_TRACK_NEXT,
                order=4,
            )
            self._reset = self._button(
                "Reset scene",
                hint="Rebuild the scene from scratch",
                icon=viser.Icon.REFRESH,
                order=5,
            )
            self._save_state = self._button(
                "Save state",
                hint="Keep the machine as it is now (at rest: homed, powered, pressures)",
                icon=viser.Icon.DEVICE_FLOPPY,
                order=6,
            )
            self._restore_state = self._button(
                "Restore state",
                hint="Return to the saved state (time, physics, axes; the panel's blocks anew)",
                icon=viser.Icon.RESTORE,
                order=7,
            )
        with gui.add_folder("Demo", order=1):
            # two buttons, not a toggle: a click a slow page sends late must not restart a demo
            self._demo_button = self._button("Run demo", icon=viser.Icon.PLAYER_PLAY, order=0)
            self._end_demo = self._button(
                "End demo",
                icon=viser.Icon.PLAYER_STOP,
                hint="Stop the demo and hand the machine over (its groups are released)",
                order=0.5,
            )
            self._release = self._button(
                "Release group",
                icon=viser.Icon.UNLINK,
                hint="Take the axes groups apart (MC_GroupDisable, MC_UngroupAllAxes)",
                order=1,
            )
            self._demo_step = gui.add_html("", order=2)

        @self._stop_all.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            with self._holds_lock:
                clients = list(self._holds)
            for client_id in clients:
                self._drop_holds(client_id)
            session.stop_all()

        @self._take.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if event.client_id is None:
                return
            previous = self.control.take(event.client_id)
            if previous != event.client_id:
                if previous is not None:
                    self._drop_holds(previous)
                    other = self.server.get_clients().get(previous)
                    if other is not None:
                        other.add_notification(
                            "Control taken",
                            f"Operator #{event.client_id} operates now; you watch.",
                            color="yellow",
                            auto_close_seconds=8.0,
                        )
                session.record_event("viewer", f"operator #{event.client_id} took control")

        @self._give.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if event.client_id is not None and self.control.release(event.client_id):
                self._drop_holds(event.client_id)
                session.record_event("viewer", f"operator #{event.client_id} released control")

        @self._scene_choice.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            name = self._scene_choice.value
            if name in scenes.MACHINES and name != session.scene_name:
                session.load(name)

        @self._speed_choice.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            speed = self._speeds.get(self._speed_choice.value)
            if speed is not None:
                session.speed = speed

        @self._pause.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if session.snapshot.paused:
                session.resume()
            else:
                session.pause()

        @self._step.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            session.step()

        @self._reset.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            session.reset()

        @self._save_state.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            session.save_state()

        @self._restore_state.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            with self._holds_lock:
                clients = list(self._holds)
            for client_id in clients:
                self._drop_holds(client_id)
            session.restore_state()

        @self._demo_button.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            demo = session.snapshot.demo
            if demo.available and not demo.running:
                session.start_demo()

        @self._end_demo.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            session.end_demo()

        @self._release.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            session.release_groups()

    # ------------------------------------------------------------------------- GUI: scene

    def _rebuild(self, snapshot: Snapshot) -> None:
        """(Re)build the 3-D scene and every panel of the scene for a new scene."""
        if self._model_scene is not None:
            self._model_scene.remove()
            self._model_scene = None
        if self._note is not None:
            self._note.remove()
            self._note = None
        if self._ghost is not None:
            self._ghost.remove()
            self._ghost = None
        if self._contacts is not None:
            self._contacts.remove()
            self._contacts = None
        self.follow = FOLLOW_OFF
        self._follow_anchor = {}
        for folder in self._scene_gui:
            folder.remove()
        self.gate.forget(self._scene_inputs + self._commands)
        for command in self._commands:
            command.remove()
        self._scene_inputs = []
        self._commands = []
        self._steps = {}
        self._scene_gui = []
        self._axes = {}
        self._lamps = []
        self._signals = None
        self._signals_html = ""
        self._results = None
        self._results_html = ""
        self._events_html = ""
        self._last = None
        self._generation = snapshot.generation
        self._last_panel = self._last_plot = -math.inf  # show the new scene's panels at once
        self._bounds = None
        with self._holds_lock:
            self._holds.clear()

        model = snapshot.model
        if model is not None:
            data = mujoco.MjData(model)
            data.qpos[:] = snapshot.qpos
            mujoco.mj_kinematics(model, data)
            self._bounds = _machine_bounds(model, data)
            self._place_camera()
            data.xpos[:] = snapshot.xpos
            data.xquat[:] = snapshot.xquat
            self._model_scene = ModelScene(model, self.server, prefix="/scene", data=data)
            self._contacts = ContactOverlay(
                self.server, prefix="/contacts", scale=FORCE_SCALES[self.force_scale]
            )
            handles = self._model_scene.geom_handles
            self._lamps = [
                (name, kind, geom, color)
                for name, view in snapshot.axes.items()
                for kind, color in SWITCHES
                if view.joint and (geom := f"{view.joint}_{kind}_geom") in handles
            ]
        else:
            self._note = self.server.scene.add_label(
                "/scene_note", f"{snapshot.scene}: {NO_MODEL_NOTE}", anchor="center-center"
            )

        gui = self.server.gui
        generation = snapshot.generation
        axes_folder = gui.add_folder("Axes", order=2)
        self._scene_gui.append(axes_folder)
        with axes_folder:
            tabs = gui.add_tab_group()
            for name, view in snapshot.axes.items():
                with tabs.add_tab(name):
                    self._axes[name] = self._build_axis_panel(name, view, generation)
        if snapshot.signals:
            signals_folder = gui.add_folder("Signals", order=3)
            self._scene_gui.append(signals_folder)
            with signals_folder:
                self._signals_html = signals_html(snapshot)
                self._signals = gui.add_html(self._signals_html)
        if snapshot.demo.available:
            results_folder = gui.add_folder("Results", order=4)
            self._scene_gui.append(results_folder)
            with results_folder:
                self._results_html = results_html(snapshot)
                self._results = gui.add_html(self._results_html)
        self._build_step_keys(generation)
        self._build_jog_keys(generation)
        self._build_scope(snapshot)
        events_folder = gui.add_folder("Error history", order=6)
        self._scene_gui.append(events_folder)
        with events_folder:
            self._events = gui.add_html(events_html(snapshot))
        self._build_faults(snapshot, generation)
        if model is not None:
            self._build_views(model)

    def _build_step_keys(self, generation: int) -> None:
        """Shift+arrow keys (and PageUp/PageDown) step the first three driven axes."""
        session = self.session
        for name, (plus, minus) in zip(self._steps, STEP_KEYS, strict=False):
            for key, sign in ((plus, 1.0), (minus, -1.0)):
                label = f"{name} step {'+' if sign > 0 else '−'}"
                command = self.server.gui.add_command(
                    label, description=f"Move {name} by its Step", hotkey=key, modifier="shift"
                )
                self.gate.allow_command(command, label)
                self._commands.append(command)

                def step(event: Any, axis: str = name, s: float = sign) -> None:
                    if session.snapshot.generation != generation:
                        return
                    view = session.snapshot.axes[axis]
                    distance = s * float(self._steps[axis].value)
                    velocity = 0.1 * (view.vmax if math.isfinite(view.vmax) else 100.0)
                    session.requests(axis).move(
                        Move("relative", distance, velocity, 10.0 * velocity)
                    )

                command.on_trigger(step)

    def _build_jog_keys(self, generation: int) -> None:
        """Alt+arrow keys (and Alt+PageUp/PageDown) jog the first three driven axes while held
        (:meth:`key_jog`)."""
        for name, (plus, minus) in zip(self._steps, JOG_KEYS, strict=False):
            for key, sign in ((plus, 1), (minus, -1)):
                label = f"{name} jog {'+' if sign > 0 else '−'}"
                command = self.server.gui.add_command(
                    label,
                    description=f"Jog {name} while the key is held",
                    hotkey=key,
                    modifier="alt",
                )
                self.gate.allow_command(command, label)
                self._commands.append(command)

                def jog(event: Any, axis: str = name, d: int = sign) -> None:
                    if event.client_id is not None:
                        self.key_jog(event.client_id, generation, axis, d)

                command.on_trigger(jog)

    def _build_views(self, model: mujoco.MjModel) -> None:
        """Camera presets, follow camera and the 3-D overlays (each page moves its own camera;
        for everyone)."""
        gui = self.server.gui
        self._follow_ids = {}
        if self._model_scene is not None:
            drawn = self._model_scene.body_handles
            for b in self._model_scene.moving_body_ids:
                name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(b)) or f"body{b}"
                if name in drawn:
                    self._follow_ids[name] = int(b)
        bodies = [FOLLOW_OFF, *self._follow_ids]
        folder = gui.add_folder("View", order=8, expand_by_default=False)
        self._scene_gui.append(folder)
        with folder:
            for label, direction in VIEWS.items():
                button = self._button(label, control=False, hint=f"Camera: {label.lower()}")
                self._scene_inputs.append(button)

                def look(event: viser.GuiEvent[viser.GuiButtonHandle], d: Any = direction) -> None:
                    if event.client is not None and self._bounds is not None:
                        center, radius = self._bounds
                        position = _camera_position(center, radius, d)
                        event.client.camera.look_at = center
                        event.client.camera.position = position

                button.on_click(look)

        with folder:
            follow = gui.add_dropdown(
                "Follow", bodies, initial_value=FOLLOW_OFF, hint="Cameras keep their offset to it"
            )
            self.gate.allow(follow, choice_of(bodies), control=False)
            ghost = gui.add_dropdown(
                "Set-point ghost",
                SWITCH_CHOICES,
                initial_value=SWITCH_CHOICES[self.show_ghost],
                hint="Moving parts drawn where the axes' set points put them",
            )
            self.gate.allow(ghost, choice_of(SWITCH_CHOICES), control=False)
            choices_ = [OFF, *FORCE_SCALES]
            contacts = gui.add_dropdown(
                "Forces (contacts, stops, tendons)",
                choices_,
                initial_value=self.force_scale if self.show_contacts else OFF,
                hint="Contact, hard-stop and tendon force arrows, arrow length per newton",
            )
            self.gate.allow(contacts, choice_of(choices_), control=False)
            self._scene_inputs += [follow, ghost, contacts]

        @follow.on_update
        def _(event: Any) -> None:
            self.follow = follow.value
            self._redraw = True

        @ghost.on_update
        def _(event: Any) -> None:
            self.show_ghost = ghost.value == ON
            self._redraw = True

        @contacts.on_update
        def _(event: Any) -> None:
            self.show_contacts = contacts.value in FORCE_SCALES
            if self.show_contacts:
                self.force_scale = contacts.value
            self._redraw = True

    def _build_faults(self, snapshot: Snapshot, generation: int) -> None:
        """Forcing inputs and injecting faults through ``scene.faults``: one choice per axis and
        fault it can have (switch faults only for its switches, drive faults only with a
        drive)."""
        gui = self.server.gui
        session = self.session
        choices_ = {
            f"{name}: {label}": (name, fault)
            for name, view in snapshot.axes.items()
            for label, fault in FAULTS.items()
            if _applies(fault, view)
        }
        labels = list(choices_)
        names = list(snapshot.axes)
        folder = gui.add_folder("Faults", order=7, expand_by_default=False)
        self._scene_gui.append(folder)
        with folder:
            kind = gui.add_dropdown("Fault", labels, initial_value=labels[0])
            self.gate.allow(kind, choice_of(labels))
            inject = self._button("Inject", color="orange", icon=viser.Icon.BOLT)
            axis = gui.add_dropdown("Clear axis", names, initial_value=names[0])
            self.gate.allow(axis, choice_of(names))
            clear = self._button("Clear faults", icon=viser.Icon.ERASER)
            self._scene_inputs += [axis, kind, inject, clear]

        @inject.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if session.snapshot.generation == generation:
                session.inject(*choices_[kind.value])

        @clear.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if session.snapshot.generation == generation:
                session.clear_faults(axis.value)

    def _build_scope(self, snapshot: Snapshot) -> None:
        """The scope: several channels on one time base, run/pause, trigger, CSV export."""
        gui = self.server.gui
        names = [c.name for c in snapshot.channels]
        digital = [c.name for c in snapshot.channels if c.digital]
        first = next(iter(snapshot.axes))
        defaults = [
            f"{first} following error",
            f"{first} command",
            f"{first} position",
            NO_TRACE,
        ]
        defaults = [d if d in names else NO_TRACE for d in defaults]
        options = [NO_TRACE, *names]
        triggers = [FREE_RUN, ON_ERROR, *(f"rising: {n}" for n in digital)]
        folder = gui.add_folder("Scope", order=5)
        self._scene_gui.append(folder)
        self._scope_paused = False
        self._scope_trigger_at = None
        self._scope_style = ()
        with folder:
            self._scope_status = gui.add_html("")
            self._scope_plot = gui.add_uplot(
                data=(np.zeros(1), np.zeros(1)),
                series=(viser.uplot.Series(label="t [s]"), viser.uplot.Series(label="")),
                scales={"x": viser.uplot.Scale(time=False, auto=True)},
                title="",
                aspect=1.2,
            )
            self._scope_traces = []
            for k in range(SCOPE_TRACES):
                trace = gui.add_dropdown(f"Trace {k + 1}", options, initial_value=defaults[k])
                self.gate.allow(trace, choice_of(options), control=False)
                self._scope_traces.append(trace)
            self._scope_window = gui.add_dropdown("Time base", SCOPE_WINDOWS, initial_value="4 s")
            self.gate.allow(self._scope_window, choice_of(SCOPE_WINDOWS), control=False)
            self._scope_trigger = gui.add_dropdown("Trigger", triggers, initial_value=FREE_RUN)
            self.gate.allow(self._scope_trigger, choice_of(triggers), control=False)
            run = self._button("Run / Pause", control=False, icon=viser.Icon.PLAYER_PAUSE)
            export = self._button("Export CSV", control=False, icon=viser.Icon.DOWNLOAD)
            self._scope_run = run
            self._scene_inputs += [*self._scope_traces, self._scope_window, self._scope_trigger]
            self._scene_inputs += [run, export]

        @run.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if self._scope_paused:
                self._scope_paused = False
                self._scope_trigger_at = None
                self._scope_armed_since = self.session.snapshot.time
            else:
                self._scope_paused = True
            self._last_plot = -math.inf

        @export.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            names, t, values = self.scope_shown
            if event.client is not None:
                content = scope_csv(names, t, values).encode()
                event.client.send_file_download("scope.csv", content, save_immediately=True)

        def rearm(event: Any) -> None:
            self._scope_trigger_at = None
            self._scope_armed_since = self.session.snapshot.time
            self._scope_paused = False
            self._last_plot = -math.inf

        self._scope_trigger.on_update(rearm)
        for trace in self._scope_traces:
            trace.on_update(lambda event: setattr(self, "_last_plot", -math.inf))
        self._scope_window.on_update(lambda event: setattr(self, "_last_plot", -math.inf))

    def _build_axis_panel(self, name: str, view: AxisView, generation: int) -> _AxisWidgets:
        """Read-outs and buttons of one axis (inside its tab), as its definition says: an
        encoder-only axis gets no drive buttons, an axis without a homing recipe no Home."""
        gui = self.server.gui
        session = self.session

        def current() -> bool:
            return session.snapshot.generation == generation

        def on_click(
            action: Callable[[AxisRequests], None],
        ) -> Callable[[viser.GuiEvent[viser.GuiButtonHandle]], None]:
            def callback(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
                if current():  # a click on a panel of a replaced scene is ignored
                    action(session.requests(name))

            return callback

        def button(label: str, **kwargs: Any) -> viser.GuiButtonHandle:
            handle = self._button(label, **kwargs)
            self._scene_inputs.append(handle)
            buttons.append(label)
            return handle

        def number(label: str, value: float, low: float, high: float, step: float) -> Any:
            handle = gui.add_number(label, initial_value=value, min=low, max=high, step=step)
            self.gate.allow(handle, number_in(low, high))
            self._scene_inputs.append(handle)
            return handle

        panel = gui.add_html(axis_panel_html(view))
        buttons: list[str] = []
        power = None
        if view.has_drive:
            power = button("Power", color="gray", icon=viser.Icon.POWER, hint="MC_Power on/off")
            power.on_click(on_click(lambda _: session.toggle_power(name)))
        reset = button("Reset", icon=viser.Icon.REFRESH_ALERT, hint="MC_Reset: clear the error")
        reset.on_click(on_click(AxisRequests.reset))
        if not view.has_drive:
            return _AxisWidgets(panel=panel, power=None, unit=view.unit, buttons=tuple(buttons))
        procedures = [p for p in HOMING_PROCEDURES if p != "recipe" or view.homeable]
        procedure = gui.add_dropdown("Homing", procedures, initial_value=procedures[0])
        self.gate.allow(procedure, choice_of(procedures))
        self._scene_inputs.append(procedure)
        home_position = number(f"Home position [{view.unit}]", 0.0, -1e9, 1e9, 0.001)
        home = button("Home", icon=viser.Icon.HOME, hint="Run the chosen homing procedure")

        @home.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if current():
                session.requests(name).home(procedure.value, float(home_position.value))

        jog_pos = button("Jog+", icon=viser.Icon.ARROW_RIGHT, hint="Hold to jog (GT_Jog)")
        jog_neg = button("Jog−", icon=viser.Icon.ARROW_LEFT, hint="Hold to jog (GT_Jog)")
        for handle, direction in ((jog_pos, 1), (jog_neg, -1)):

            def hold(event: viser.GuiEvent[viser.GuiButtonHandle], d: int = direction) -> None:
                if current() and event.client_id is not None:
                    with self._holds_lock:
                        self._holds[event.client_id] = _Hold(generation, name, d, self._clock())
                    session.requests(name).jog(d)

            def release(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
                if event.client_id is not None:
                    with self._holds_lock:
                        self._holds.pop(event.client_id, None)
                if current():
                    session.requests(name).release_jog()

            handle.on_hold(hold, callback_hz=JOG_HOLD_HZ)
            handle.on_click(release)  # a click ends on release
        stop = button("Stop", color="red", icon=viser.Icon.HAND_STOP, hint="MC_Stop")
        stop.on_click(on_click(AxisRequests.stop))
        vmax = view.vmax if math.isfinite(view.vmax) and view.vmax > 0.0 else 100.0
        unit = view.unit
        velocity = gui.add_slider(
            f"Jog velocity [{unit}/s]",
            min=round(0.01 * vmax, 3),
            max=round(vmax, 3),
            step=round(0.01 * vmax, 3),
            initial_value=round(0.1 * vmax, 3),
        )
        self.gate.allow(velocity, number_in(round(0.01 * vmax, 3), round(vmax, 3)))
        self._scene_inputs.append(velocity)

        @velocity.on_update
        def _(event: viser.GuiEvent[viser.GuiSliderHandle[float]]) -> None:
            value = float(velocity.value)
            if current() and math.isfinite(value) and 0.0 < value <= vmax:
                session.requests(name).jog_velocity = value

        step = gui.add_dropdown(f"Step [{unit}]", STEPS, initial_value="1")
        self.gate.allow(step, choice_of(STEPS))
        self._scene_inputs.append(step)
        self._steps[name] = step
        step_pos = button("Step+", icon=viser.Icon.CHEVRON_RIGHT, hint="Move by one step")
        step_neg = button("Step−", icon=viser.Icon.CHEVRON_LEFT, hint="Move back one step")
        target = number(f"Target [{unit}]", 0.0, -1e9, 1e9, 0.001)
        distance = number(f"Distance [{unit}]", 10.0, -1e9, 1e9, 0.001)
        move_velocity = number(f"Velocity [{unit}/s]", round(0.1 * vmax, 3), 1e-6, vmax, 0.001)
        acceleration = number(f"Acceleration [{unit}/s²]", round(vmax, 3), 1e-6, 1e9, 0.001)
        move_to = button("Move to", icon=viser.Icon.TARGET, hint="MC_MoveAbsolute to Target")
        move_by = button("Move by", icon=viser.Icon.ARROWS_HORIZONTAL, hint="MC_MoveRelative")

        def move(kind: str, value: Callable[[], float]) -> Callable[[Any], None]:
            def callback(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
                if current():
                    session.requests(name).move(
                        Move(
                            kind,
                            float(value()),
                            float(move_velocity.value),
                            float(acceleration.value),
                        )
                    )

            return callback

        move_to.on_click(move("absolute", lambda: target.value))
        move_by.on_click(move("relative", lambda: distance.value))
        step_pos.on_click(move("relative", lambda: float(step.value)))
        step_neg.on_click(move("relative", lambda: -float(step.value)))

        constants = view.constants
        with gui.add_folder("Tuning", expand_by_default=False):
            fields = {
                field: number(
                    label.replace("u", unit, 1) if "[" in label else label,
                    float(getattr(constants, field)) if constants is not None else 0.0,
                    low,
                    high,
                    0.001,
                )
                for field, label, low, high in TUNING
            }
            write = button("Write constants", icon=viser.Icon.DEVICE_FLOPPY, hint="GT_SetConstant")

        @write.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            base = session.snapshot.axes[name].constants
            if not current() or base is None:
                return
            values = {field: float(handle.value) for field, handle in fields.items()}
            session.requests(name).write_constants(dataclasses.replace(base, **values))

        return _AxisWidgets(panel=panel, power=power, unit=unit, buttons=tuple(buttons))

    def _place_camera(self) -> None:
        """Aim the initial camera of new clients at the machine (everything but planes)."""
        if self._bounds is None:
            return
        center, radius = self._bounds
        self.server.initial_camera.look_at = center
        self.server.initial_camera.position = _camera_position(center, radius, VIEWS["Fit"])

    # ------------------------------------------------------------------------- update loop

    def start(self) -> None:
        """Start the update thread (no-op if it runs)."""
        if self._thread is not None and self._thread.is_alive():
            return
        self._stopping.clear()
        self._thread = threading.Thread(target=self._loop, name="viewer-update", daemon=True)
        self._thread.start()

    def stop(self, timeout: float = 5.0) -> None:
        """Stop the update thread and wait for it [s at most]."""
        self._stopping.set()
        if self._thread is not None:
            self._thread.join(timeout)
            self._thread = None

    def _loop(self) -> None:
        next_frame = time.monotonic()
        failing = False
        while not self._stopping.is_set():
            try:
                self.renew_holds()
                self.frame()
                failing = False
            except Exception:  # keep the viewer alive; the next frame starts afresh
                if not failing:
                    log.exception("viewer frame failed")
                failing = True
                self._last = None
            next_frame += self._frame_period
            delay = next_frame - time.monotonic()
            if delay < 0.0:  # late: do not try to catch up with a burst of frames
                next_frame = time.monotonic()
                delay = 0.0
            self._stopping.wait(delay)

    def frame(self) -> None:
        """Send what changed since the last frame (called by the update thread)."""
        snapshot = self.session.snapshot
        if snapshot is self._last and not self._redraw:
            return
        self._redraw = False
        start = time.perf_counter()
        if snapshot.generation != self._generation:
            self._rebuild(snapshot)
        model_scene = self._model_scene
        if model_scene is not None:
            model_scene.update_poses(snapshot.xpos, snapshot.xquat)
            axes = snapshot.axes
            for name, kind, geom, color in self._lamps:
                if getattr(axes[name], kind):
                    model_scene.set_geom_color(geom, color)
                else:
                    model_scene.reset_geom_color(geom)
            self._update_overlays(snapshot)
        now = time.monotonic()
        slack = 0.5 * self._frame_period  # e.g. every third frame at 30 fps for 10 Hz
        if now - self._last_panel >= self._panel_period - slack:
            self._last_panel = now
            self._update_panels(snapshot)
        if now - self._last_plot >= self._plot_period - slack:
            self._last_plot = now
            self._update_scope(snapshot)
        self._last = snapshot
        self.frames += 1
        self.frame_costs.append(time.perf_counter() - start)

    @property
    def ghost(self) -> SetPointGhost | None:
        """The set-point ghost (made when first shown, dropped with its scene)."""
        return self._ghost

    @property
    def contacts(self) -> ContactOverlay | None:
        """The contact overlay of the current model (None without a model)."""
        return self._contacts

    def _update_overlays(self, snapshot: Snapshot) -> None:
        """Set-point ghost, forces and the follow cameras, as the View folder says."""
        model = snapshot.model
        if model is None:
            return
        ghost = self._ghost
        if self.show_ghost:
            if ghost is None:
                joints = [(n, v.joint) for n, v in snapshot.axes.items() if v.has_drive and v.joint]
                axes = ghost_axes(model, snapshot.scene, joints)
                ghost = self._ghost = SetPointGhost(model, self.server, axes, prefix="/ghost")
            ghost.visible = True
            ghost.update(snapshot.qpos, [snapshot.axes[a.name].following_error for a in ghost.axes])
        elif ghost is not None:
            ghost.visible = False
        contacts = self._contacts
        if contacts is not None:
            contacts.scale = FORCE_SCALES[self.force_scale]
            contacts.enabled = self.show_contacts
            if snapshot.contacts is not None:
                contacts.update(snapshot.contacts, snapshot.constraints)
        self._follow_cameras(snapshot)

    def _follow_cameras(self, snapshot: Snapshot) -> None:
        """Move each page's camera by the travel of the followed body since the last move, so
        that it keeps its offset to the body (and the page can still orbit and zoom)."""
        body = self._follow_ids.get(self.follow)
        anchors = self._follow_anchor
        if body is None or body >= snapshot.xpos.shape[0]:
            anchors.clear()
            return
        target = snapshot.xpos[body]
        clients = self.server.get_clients()
        for client_id in [c for c in anchors if c not in clients]:
            del anchors[client_id]
        for client_id, client in clients.items():
            anchor = anchors.get(client_id)
            if anchor is None or anchor[0] != body:
                anchors[client_id] = (body, target.copy())
                continue
            shift = target - anchor[1]
            if float(np.max(np.abs(shift))) < FOLLOW_STEP:
                continue
            client.camera.position = client.camera.position + shift
            anchors[client_id] = (body, target.copy())

    def _control_text(self) -> str:
        owner = self.control.owner
        if owner is None:
            text = "Nobody is in control: press <b>Take control</b> to operate."
        else:
            text = f"In control: <b>operator #{owner}</b> since {_utc(self.control.since)[:8]} UTC"
        return f'<div style="font-size:0.85em;padding:0 0.75em">{text}</div>'

    def _update_panels(self, snapshot: Snapshot) -> None:
        """Status line, control, demo, buttons, axis read-outs, history (only changes sent)."""
        self.panel_updates += 1
        status = status_html(snapshot)
        if status != self._status_html:
            self._status_html = self._status.content = status
        control = self._control_text()
        if control != self._control_html:
            self._control_html = self._control_status.content = control
        pause_label = "Resume" if snapshot.paused else "Pause"
        if pause_label != self._pause_label:
            self._pause_label = self._pause.label = pause_label
            self._pause.icon = (
                viser.Icon.PLAYER_PLAY if snapshot.paused else viser.Icon.PLAYER_PAUSE
            )
        demo = snapshot.demo
        startable = demo.available and not demo.running
        if self._demo_button.disabled == startable:
            self._demo_button.disabled = not startable
        if self._end_demo.disabled == demo.running:
            self._end_demo.disabled = not demo.running
        if not demo.available:
            text = "This scene has no demo program."
        elif demo.error:
            text = f'<span style="color:#c62828">{html.escape(demo.error)}</span>'
        elif demo.step:
            prefix = "Done: " if demo.done else ("Step: " if demo.running else "Ended at: ")
            text = prefix + html.escape(demo.step)
        else:
            text = "Not started."
        if snapshot.groups:
            text += "<br>Axes group: " + html.escape(", ".join(snapshot.groups))
        demo_html = f'<div style="font-size:0.85em;padding:0 0.75em">{text}</div>'
        if demo_html != self._demo_html:
            self._demo_html = self._demo_step.content = demo_html
        for name, widgets in self._axes.items():
            view = snapshot.axes[name]
            panel = axis_panel_html(view)
            if panel != widgets.html:
                widgets.html = widgets.panel.content = panel
            if widgets.power is not None and view.powered != widgets.powered:
                widgets.powered = view.powered
                widgets.power.color = "green" if view.powered else "gray"
        if self._signals is not None:
            signals = signals_html(snapshot)
            if signals != self._signals_html:
                self._signals_html = self._signals.content = signals
        if self._results is not None:
            results = results_html(snapshot)
            if results != self._results_html:
                self._results_html = self._results.content = results
        events = events_html(snapshot)
        if events != self._events_html:
            self._events_html = self._events.content = events

    def _update_scope(self, snapshot: Snapshot) -> None:
        """The scope's traces over the time base; frozen while paused or after a trigger."""
        plot, window_choice, trigger = self._scope_plot, self._scope_window, self._scope_trigger
        if plot is None or window_choice is None or trigger is None:
            return
        window = float(window_choice.value.split()[0])
        channels = snapshot.channels
        index = {c.name: k for k, c in enumerate(channels)}
        chosen = [t.value for t in self._scope_traces if t.value in index]
        recorder = self.session.recorder
        if recorder.channels != channels:
            return  # the session moved on to another scene: the next snapshot rebuilds
        status = "running"
        if self._scope_paused:
            status = "paused"
            if self._scope_trigger_at is not None:
                status = f"triggered at t = {self._scope_trigger_at:.3f} s"
            names = tuple(self.scope_shown[0])
            if names == tuple(_trace_name(channels[index[n]]) for n in chosen):
                self._scope_status_text(status)
                return
            t, values = self._scope_frozen_window(recorder, window)
        else:
            t, values = recorder.series(since=snapshot.time - window)
            if trigger.value != FREE_RUN and t.size:
                at = self._find_trigger(trigger.value, index, t, values)
                if at is not None:
                    self._scope_trigger_at = at
                    if t[-1] >= at + 0.5 * window:
                        self._scope_paused = True
                        t, values = self._scope_frozen_window(recorder, window)
                        status = f"triggered at t = {at:.3f} s"
                    else:
                        status = f"triggered at t = {at:.3f} s, recording"
                else:
                    status = "armed: waiting for " + trigger.value
        rows = [index[n] for n in chosen]
        shown = values[rows] if rows else np.zeros((0, t.size))
        names = tuple(_trace_name(channels[k]) for k in rows)
        self.scope_shown = (names, t, shown)
        self._scope_status_text(status)
        if t.size < 2 or not rows:
            return
        units = tuple("0/1" if channels[k].digital else channels[k].unit for k in rows)
        with self.server.atomic():
            if (names, units) != (self._scope_style[: len(names)], self._scope_style[len(names) :]):
                self._scope_style = (*names, *units)
                plot.series, plot.axes, plot.scales = _scope_style(names, units)
                plot.title = " · ".join(names)
            plot.data = (t, *shown)

    def _scope_frozen_window(
        self, recorder: Recorder, window: float
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The samples of a triggered capture (trigger in the middle) or the last window."""
        at = self._scope_trigger_at
        t_shown = self.scope_shown[1]
        if at is None:
            end = float(t_shown[-1]) if t_shown.size else self.session.snapshot.time
            t, values = recorder.series(since=end - window)
            keep = t <= end
            return t[keep], values[:, keep]
        t, values = recorder.series(since=at - 0.5 * window)
        keep = t <= at + 0.5 * window
        return t[keep], values[:, keep]

    def _find_trigger(
        self,
        mode: str,
        index: dict[str, int],
        t: npt.NDArray[np.float64],
        values: npt.NDArray[np.float64],
    ) -> float | None:
        """Time [s] of the first trigger edge after arming (None: none yet)."""
        if self._scope_trigger_at is not None:
            return self._scope_trigger_at
        if mode == ON_ERROR:
            rows = [k for n, k in index.items() if n.endswith(" error") and "following" not in n]
        else:
            name = mode.removeprefix("rising: ")
            rows = [index[name]] if name in index else []
        fresh = t > self._scope_armed_since
        for k in rows:
            level = values[k] > 0.5
            edges = np.flatnonzero(level[1:] & ~level[:-1] & fresh[1:]) + 1
            if edges.size:
                return float(t[edges[0]])
        return None

    def _scope_status_text(self, status: str) -> None:
        if self._scope_status is None:
            return
        content = (
            f'<div style="font-size:0.85em;padding:0 0.75em">Scope: {html.escape(status)}</div>'
        )
        if self._scope_status.content != content:
            self._scope_status.content = content

    @property
    def scope_status(self) -> str:
        """The scope's state line (running, paused, armed, triggered at …)."""
        return self._scope_status.content if self._scope_status is not None else ""


def _applies(fault: mcl.faults.Fault, view: AxisView) -> bool:
    """Whether an axis can have ``fault``: a switch it has, a drive and brake if it has one."""
    if isinstance(fault, mcl.faults.SwitchStuck):
        return fault.switch in view.switches
    if fault.key() in ("drive", "brake", "analog_out"):
        return view.has_drive
    return True


def _trace_name(channel: Channel) -> str:
    """A scope trace's label: name and unit."""
    return f"{channel.name} [{channel.unit}]" if channel.unit else f"{channel.name} [0/1]"


def _scope_style(
    names: Sequence[str], units: Sequence[str]
) -> tuple[
    tuple[viser.uplot.Series, ...], tuple[viser.uplot.Axis, ...], dict[str, viser.uplot.Scale]
]:
    """Series, axes and scales of the scope: one y scale per unit, the first two with axes."""
    colors = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd")
    distinct = list(dict.fromkeys(units))
    series = [viser.uplot.Series(label="t [s]")]
    for k, (name, unit) in enumerate(zip(names, units, strict=True)):
        series.append(
            viser.uplot.Series(label=name, stroke=colors[k % len(colors)], width=1.5, scale=unit)
        )
    axes = [viser.uplot.Axis(label="t [s]")]
    for k, unit in enumerate(distinct[:2]):
        axes.append(
            viser.uplot.Axis(
                scale=unit, label=f"[{unit}]", side=3 if k == 0 else 1, grid={"show": k == 0}
            )
        )
    scales = {"x": viser.uplot.Scale(time=False, auto=True)}
    for unit in distinct:
        scales[unit] = (
            viser.uplot.Scale(auto=False, range=(-0.1, 1.1))
            if unit == "0/1"
            else viser.uplot.Scale(auto=True)
        )
    return tuple(series), tuple(axes), scales


def _machine_bounds(
    model: mujoco.MjModel, data: mujoco.MjData
) -> tuple[npt.NDArray[np.float64], float] | None:
    """Centre [m] and radius [m] of the machine: every geom but planes and those more than
    :data:`FRAME_OUTLIER` times the median size (an endless strip); None: nothing solid."""
    rbound_all = np.asarray(model.geom_rbound)
    solid = np.asarray(model.geom_type) != mujoco.mjtGeom.mjGEOM_PLANE
    if not solid.any():
        return None
    solid &= rbound_all <= FRAME_OUTLIER * float(np.median(rbound_all[solid]))
    rbound = rbound_all[solid][:, None]
    xpos = np.asarray(data.geom_xpos)[solid]
    low, high = (xpos - rbound).min(axis=0), (xpos + rbound).max(axis=0)
    return 0.5 * (low + high), 0.5 * float(np.linalg.norm(high - low))


def _camera_position(
    center: npt.NDArray[np.float64], radius: float, direction: Sequence[float]
) -> npt.NDArray[np.float64]:
    """Camera position [m] looking at ``center`` from ``direction`` at a distance that shows
    a sphere of ``radius``."""
    d = np.asarray(direction, dtype=np.float64)
    return center + 1.7 * radius * d / np.linalg.norm(d)


class Viewer:
    """A session, a viser server and the app in one: the viewer as the CLI starts it.

    Args:
        scene: Registry name of the scene to show first.
        host: Interface to bind (default: this machine only).
        port: TCP port; 0 picks a free one.
        speed: Simulated seconds per wall second (``math.inf``: as fast as possible).
        demo: Start the scene's demo program (if it has one).
        fps: Frame rate of the 3-D updates [Hz].
        environment_map: Light the scene with an HDRI environment map (slow without a GPU).
        session: Use this session instead of making one (it is started and closed here).
        token: The secret every connection must present: ``True`` makes a fresh one
            (:func:`~viewer.security.make_token`), a string uses it, ``False`` serves without
            one (loopback only).
        allowed_hosts: Further host names the viewer may be reached under (a DNS name).

    Every request and websocket passes :class:`~viewer.security.AccessPolicy` (same origin,
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
            raise PortInUseError(
                errno.EADDRINUSE, f"port {port} on {host} is already in use; choose another --port"
            )
        self.session = session if session is not None else Session(scene, speed=speed)
        self.server = secure_server(
            self.policy, host=host, port=port, label="mcl testbench", verbose=False
        )
        try:
            if port and self.server.get_port() != port:  # viser moved on to another port
                raise PortInUseError(
                    errno.EADDRINUSE,
                    f"port {port} on {host} is already in use; choose another --port",
                )
            self.app = ViewerApp(
                self.session,
                self.server,
                fps=fps,
                environment_map=environment_map,
                log=self.policy.log,
            )
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

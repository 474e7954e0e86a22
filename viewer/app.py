"""The browser viewer: viser GUI for a :class:`~viewer.session.Session` and its update loop.

:class:`ViewerApp` builds the control panel and the 3-D scene (:class:`ModelScene`) and runs a
loop in its own thread that, up to ``fps`` times per second, takes the session's latest
:class:`~viewer.session.Snapshot` and sends what changed: body poses, switch colours, the axis
panels and the live plot. GUI callbacks only call :class:`Session` methods (request flags and
queued commands); every viser object is modified by the update thread alone.

:class:`Viewer` bundles server, session and app: ``Viewer(scene="gantry", port=8080)`` serves
the viewer on ``http://127.0.0.1:8080`` until :meth:`Viewer.close`.

Everything machine-specific comes from the registry (``scenes.MACHINES``) and the scene: the
chooser lists ``sorted(scenes.MACHINES)``; each axis panel shows the axis' own unit, only the
switches the machine definition gives it, its digital inputs and outputs, and drive buttons only
if it has a drive (Home only with a homing recipe); a machine that publishes signals gets a
signals panel; a machine of simulated axes (no MuJoCo model) shows a note instead of a 3-D model.

The page offers no way to run code or touch files: no text inputs, no uploads, only buttons,
dropdowns and sliders whose values are checked against fixed choices and ranges; viser's share
tunnel and upload requests are refused (:func:`harden`).
"""

from __future__ import annotations

import errno
import functools
import html
import logging
import math
import socket
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import viser
import viser.uplot

import scenes
from viewer.model_scene import ModelScene
from viewer.operator import AxisRequests
from viewer.session import AxisView, Session, Snapshot, choices

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


@dataclass
class _AxisWidgets:
    """The GUI elements of one axis panel."""

    panel: viser.GuiHtmlHandle
    power: viser.GuiButtonHandle | None
    unit: str
    buttons: tuple[str, ...]
    html: str = ""
    powered: bool | None = None


class ViewerApp:
    """Control panel and 3-D scene of a session in a viser server, updated by its own thread.

    Args:
        session: The simulation to show and operate.
        server: The viser server to build the GUI in.
        fps: Frames per second of the update loop [Hz] (poses and switch colours).
        panel_hz: Refresh rate of the axis panels and the status line [Hz].
        plot_hz: Refresh rate of the live plot [Hz].
        environment_map: Light the scene with viser's HDRI environment map. It looks best but
            makes a browser without GPU (software WebGL) draw ~10× slower; the default lights
            the scene with a hemisphere light instead.
    """

    def __init__(
        self,
        session: Session,
        server: viser.ViserServer,
        *,
        fps: float = 30.0,
        panel_hz: float = 10.0,
        plot_hz: float = 10.0,
        environment_map: bool = False,
    ) -> None:
        self.session = session
        self.server = server
        self._frame_period = 1.0 / fps
        self._panel_period = 1.0 / panel_hz
        self._plot_period = 1.0 / plot_hz
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None
        self.frame_costs: deque[float] = deque(maxlen=10_000)
        """Wall time [s] of recent frames that had a new snapshot to send."""
        self.frames = 0
        """Frames that sent a new snapshot."""

        self._model_scene: ModelScene | None = None
        self._generation = 0
        self._last: Snapshot | None = None
        self._last_panel = self._last_plot = -math.inf
        self._plot_time = math.nan
        self._axes: dict[str, _AxisWidgets] = {}
        self._lamps: list[tuple[str, str, str, tuple[float, float, float]]] = []
        """Switch geoms coloured from the inputs: (axis, AxisView field, geom, lamp colour)."""
        self._note: viser.LabelHandle | None = None
        self._scene_gui: list[viser.GuiFolderHandle] = []
        self._signals: viser.GuiHtmlHandle | None = None
        self._signals_html = ""
        self._plot_unit = ""
        self._plot: viser.GuiUplotHandle | None = None
        self._plot_axis: viser.GuiDropdownHandle[str] | None = None
        self._pause_label = ""
        self._demo_label = ""
        self._status_html = self._demo_html = ""

        harden(server)
        server.scene.set_up_direction("+z")
        if not environment_map:
            server.scene.configure_environment_map(None)
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

    # ------------------------------------------------------------------------- GUI: static

    def _build_static_gui(self) -> None:
        """Simulation controls and demo controls (independent of the scene)."""
        gui = self.server.gui
        session = self.session
        with gui.add_folder("Simulation", order=0):
            self._status = gui.add_html("", order=0)
            self._scene_choice = gui.add_dropdown(
                "Scene", choices(), initial_value=session.scene_name, order=1
            )
            labels = list(SPEEDS)
            current = speed_label(session.speed)
            if current not in labels:
                labels.insert(0, current)
            self._speeds = {label: SPEEDS.get(label, session.speed) for label in labels}
            self._speed_choice = gui.add_dropdown("Speed", labels, initial_value=current, order=2)
            self._pause = gui.add_button("Pause", icon=viser.Icon.PLAYER_PAUSE, order=3)
            self._step = gui.add_button(
                "Step",
                hint="Pause and run one PLC cycle",
                icon=viser.Icon.PLAYER_TRACK_NEXT,
                order=4,
            )
            self._reset = gui.add_button(
                "Reset scene",
                hint="Rebuild the scene from scratch",
                icon=viser.Icon.REFRESH,
                order=5,
            )
        with gui.add_folder("Demo", order=1):
            self._demo_button = gui.add_button("Run demo", icon=viser.Icon.PLAYER_PLAY, order=0)
            self._demo_step = gui.add_html("", order=1)

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

        @self._demo_button.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            demo = session.snapshot.demo
            if demo.running:
                session.end_demo()
            elif demo.available:
                session.start_demo()

    # ------------------------------------------------------------------------- GUI: scene

    def _rebuild(self, snapshot: Snapshot) -> None:
        """(Re)build the 3-D scene, the axis panels, the signals and the plot for a new scene."""
        if self._model_scene is not None:
            self._model_scene.remove()
            self._model_scene = None
        if self._note is not None:
            self._note.remove()
            self._note = None
        for folder in self._scene_gui:
            folder.remove()
        self._scene_gui = []
        self._axes = {}
        self._lamps = []
        self._signals = None
        self._signals_html = ""
        self._last = None
        self._generation = snapshot.generation
        self._plot_time = math.nan
        self._plot_unit = ""
        self._last_panel = self._last_plot = -math.inf  # show the new scene's panels at once

        model = snapshot.model
        if model is not None:
            data = mujoco.MjData(model)
            data.qpos[:] = snapshot.qpos
            mujoco.mj_kinematics(model, data)
            self._place_camera(model, data)
            data.xpos[:] = snapshot.xpos
            data.xquat[:] = snapshot.xquat
            self._model_scene = ModelScene(model, self.server, prefix="/scene", data=data)
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
        plot_folder = gui.add_folder("Plot", order=4)
        self._scene_gui.append(plot_folder)
        with plot_folder:
            names = list(snapshot.axes)
            self._plot_axis = gui.add_dropdown("Axis", names, initial_value=names[0])
            self._plot_unit = snapshot.axes[names[0]].unit
            series, axes = _plot_style(self._plot_unit)
            self._plot = gui.add_uplot(
                data=(np.zeros(1), np.zeros(1), np.zeros(1)),
                series=series,
                scales={
                    "x": viser.uplot.Scale(time=False, auto=True),
                    "fe": viser.uplot.Scale(auto=True),
                    "V": viser.uplot.Scale(auto=True),
                },
                axes=axes,
                title=f"{names[0]}: following error and command",
                aspect=1.4,
            )

        @self._plot_axis.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            self._plot_time = math.nan  # redraw with the new axis at the next plot refresh

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

        panel = gui.add_html(axis_panel_html(view))
        buttons: list[str] = []
        power = None
        if view.has_drive:
            power = gui.add_button(
                "Power", color="gray", icon=viser.Icon.POWER, hint="MC_Power on/off"
            )
            power.on_click(on_click(lambda _: session.toggle_power(name)))
            buttons.append("Power")
        reset = gui.add_button(
            "Reset", icon=viser.Icon.REFRESH_ALERT, hint="MC_Reset: clear the axis error"
        )
        reset.on_click(on_click(AxisRequests.reset))
        buttons.append("Reset")
        if not view.has_drive:
            return _AxisWidgets(panel=panel, power=None, unit=view.unit, buttons=tuple(buttons))
        if view.homeable:
            home = gui.add_button("Home", icon=viser.Icon.HOME, hint="The axis' homing recipe")
            home.on_click(on_click(AxisRequests.home))
            buttons.append("Home")
        jog_pos = gui.add_button("Jog+", icon=viser.Icon.ARROW_RIGHT, hint="Hold to jog (GT_Jog)")
        jog_neg = gui.add_button("Jog−", icon=viser.Icon.ARROW_LEFT, hint="Hold to jog (GT_Jog)")
        for button, direction in ((jog_pos, 1), (jog_neg, -1)):
            button.on_hold(
                on_click(functools.partial(AxisRequests.jog, direction=direction)),
                callback_hz=JOG_HOLD_HZ,
            )
            button.on_click(on_click(AxisRequests.release_jog))  # a click ends on release
        stop = gui.add_button("Stop", color="red", icon=viser.Icon.HAND_STOP, hint="MC_Stop")
        stop.on_click(on_click(AxisRequests.stop))
        buttons += ["Jog+", "Jog−", "Stop"]
        vmax = view.vmax if math.isfinite(view.vmax) and view.vmax > 0.0 else 100.0
        velocity = gui.add_slider(
            f"Jog velocity [{view.unit}/s]",
            min=round(0.01 * vmax, 3),
            max=round(vmax, 3),
            step=round(0.01 * vmax, 3),
            initial_value=round(0.1 * vmax, 3),
        )

        @velocity.on_update
        def _(event: viser.GuiEvent[viser.GuiSliderHandle[float]]) -> None:
            value = float(velocity.value)
            if current() and math.isfinite(value) and 0.0 < value <= vmax:
                session.requests(name).jog_velocity = value

        return _AxisWidgets(panel=panel, power=power, unit=view.unit, buttons=tuple(buttons))

    def _place_camera(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Aim the initial camera of new clients at the machine (everything but planes)."""
        solid = np.asarray(model.geom_type) != mujoco.mjtGeom.mjGEOM_PLANE
        if not solid.any():
            return
        rbound = np.asarray(model.geom_rbound)[solid][:, None]
        xpos = np.asarray(data.geom_xpos)[solid]
        low, high = (xpos - rbound).min(axis=0), (xpos + rbound).max(axis=0)
        center = 0.5 * (low + high)
        radius = 0.5 * float(np.linalg.norm(high - low))
        direction = np.array([0.9, -1.6, 0.9])
        direction /= np.linalg.norm(direction)
        self.server.initial_camera.look_at = center
        self.server.initial_camera.position = center + 1.7 * radius * direction

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
        if snapshot is self._last:
            return
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
        now = time.monotonic()
        if now - self._last_panel >= self._panel_period:
            self._last_panel = now
            self._update_panels(snapshot)
        if now - self._last_plot >= self._plot_period:
            self._last_plot = now
            self._update_plot(snapshot)
        self._last = snapshot
        self.frames += 1
        self.frame_costs.append(time.perf_counter() - start)

    def _update_panels(self, snapshot: Snapshot) -> None:
        """Status line, demo, buttons and axis read-outs (only what changed is sent)."""
        status = status_html(snapshot)
        if status != self._status_html:
            self._status_html = self._status.content = status
        pause_label = "Resume" if snapshot.paused else "Pause"
        if pause_label != self._pause_label:
            self._pause_label = self._pause.label = pause_label
            self._pause.icon = (
                viser.Icon.PLAYER_PLAY if snapshot.paused else viser.Icon.PLAYER_PAUSE
            )
        demo = snapshot.demo
        demo_label = "End demo" if demo.running else "Run demo"
        if demo_label != self._demo_label:
            self._demo_label = self._demo_button.label = demo_label
            self._demo_button.icon = (
                viser.Icon.PLAYER_STOP if demo.running else viser.Icon.PLAYER_PLAY
            )
        if self._demo_button.disabled == demo.available:
            self._demo_button.disabled = not demo.available
        if not demo.available:
            text = "This scene has no demo program."
        elif demo.error:
            text = f'<span style="color:#c62828">{html.escape(demo.error)}</span>'
        elif demo.step:
            prefix = "Done: " if demo.done else ("Step: " if demo.running else "Ended at: ")
            text = prefix + html.escape(demo.step)
        else:
            text = "Not started."
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

    def _update_plot(self, snapshot: Snapshot) -> None:
        """Following error and command of the selected axis over the last seconds."""
        plot, choice = self._plot, self._plot_axis
        if plot is None or choice is None:
            return
        name = choice.value
        series = snapshot.history.get(name)
        if series is None or snapshot.time == self._plot_time:
            return
        t, fe, volts = series
        if t.size < 2:
            return
        self._plot_time = snapshot.time
        title = f"{name}: following error and command"
        unit = snapshot.axes[name].unit
        with self.server.atomic():
            if plot.title != title:
                plot.title = title
            if unit != self._plot_unit:
                self._plot_unit = unit
                plot.series, plot.axes = _plot_style(unit)
            plot.data = (t, fe, volts)

    @property
    def plot_labels(self) -> tuple[str, ...]:
        """The series labels of the live plot (its units follow the selected axis)."""
        return (
            tuple(str(s.get("label", "")) for s in self._plot.series)
            if self._plot is not None
            else ()
        )


def _plot_style(unit: str) -> tuple[tuple[viser.uplot.Series, ...], tuple[viser.uplot.Axis, ...]]:
    """Series and axes of the live plot for an axis whose user unit is ``unit``."""
    series = (
        viser.uplot.Series(label="t [s]"),
        viser.uplot.Series(
            label=f"following error [{unit}]", stroke="#d62728", width=1.5, scale="fe"
        ),
        viser.uplot.Series(label="command [V]", stroke="#1f77b4", width=1.0, scale="V"),
    )
    axes = (
        viser.uplot.Axis(label="t [s]"),
        viser.uplot.Axis(scale="fe", label=f"FE [{unit}]"),
        viser.uplot.Axis(scale="V", side=1, label="U [V]", grid={"show": False}),
    )
    return series, axes


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

    Raises:
        PortInUseError: If the port is taken.
        OSError: If the address cannot be served for another reason (see :func:`port_available`).
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
    ) -> None:
        if not port_available(host, port):
            raise PortInUseError(
                errno.EADDRINUSE, f"port {port} on {host} is already in use; choose another --port"
            )
        self.session = session if session is not None else Session(scene, speed=speed)
        self.server = viser.ViserServer(host=host, port=port, label="mcl testbench", verbose=False)
        try:
            if port and self.server.get_port() != port:  # viser moved on to another port
                raise PortInUseError(
                    errno.EADDRINUSE,
                    f"port {port} on {host} is already in use; choose another --port",
                )
            self.app = ViewerApp(
                self.session, self.server, fps=fps, environment_map=environment_map
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
        """Address to open in a browser."""
        host = self.host
        return f"http://[{host}]:{self.port}" if ":" in host else f"http://{host}:{self.port}"

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

"""The browser viewer's GUI skeleton and its update loop, for a
:class:`~viewer.sim.session.Session`.

:class:`ViewerApp` builds the control panel (operator, simulation and demo controls; per scene
the axis panels of :mod:`viewer.pages.axis_panel`, signals, results, error history,
:mod:`viewer.pages.faults_panel`, :mod:`viewer.view3d.views`), each page's own panels
(:mod:`viewer.pages.layout`:
the overview and the scope) and the 3-D scene (:class:`ModelScene`), and runs a loop in its own
thread that, up to ``fps`` times per second, takes the session's latest
:class:`~viewer.sim.snapshot.Snapshot` and sends what changed: body poses, switch colours, the
overlays and follow cameras, the panels (:mod:`viewer.pages.panels`), the error history and each
page's overview and scope. GUI callbacks only call :class:`Session` methods (request flags and
queued commands) and set the scopes' and the views' choices; viser objects are modified by the
update thread (and the notifications of the callbacks).

Everything machine-specific comes from the registry (``scenes.MACHINES``) and the scene: the
chooser lists ``sorted(scenes.MACHINES)``; each axis panel shows the axis' own unit, only the
switches the machine definition gives it, its digital inputs and outputs, and drive buttons only
if it has a drive (Home only with a homing recipe); a machine that publishes signals gets a
signals panel (and scope channels); a demo with a ``results`` table gets a results panel; a
machine of simulated axes (no MuJoCo model) shows a note instead of a 3-D model.

The page offers no way to run code or touch files: no text inputs, no uploads, only buttons,
dropdowns, sliders and number boxes whose values the :class:`~viewer.serving.security.GuiGate`
checks
against fixed choices and finite ranges (and control) before viser applies them; viser's share
tunnel and upload requests are refused (:func:`~viewer.serving.security.harden`). :class:`Viewer` of
:mod:`viewer.serving.server` serves it.
"""

from __future__ import annotations

__all__ = ["ViewerApp", "demo_runs_html", "program_html"]

import html
import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any, Generic, TypeVar, cast, overload

import mujoco
import viser

import scenes
from viewer.pages.axis_panel import AxisPanel, add_hotkeys
from viewer.pages.commissioning import CommissioningPanel
from viewer.pages.control_page import ControlPages
from viewer.pages.faults_panel import build_faults
from viewer.pages.layout import CONTROL_WIDTH, Pages
from viewer.pages.panels import (
    NO_MODEL_NOTE,
    SPEEDS,
    demo_html,
    events_html,
    results_html,
    signals_html,
    speed_label,
    status_html,
)
from viewer.pages.widgets import SceneGui, gated_button
from viewer.serving.control import Control, Hold, Operators
from viewer.serving.security import BoundedLog, GuiGate, choice_of, harden
from viewer.sim.demo_run import REPEAT_PAUSE
from viewer.sim.programs import ProgramChoice
from viewer.sim.session import Session, choices
from viewer.sim.snapshot import Snapshot
from viewer.view3d.legend import (
    LAMP_LIMIT as LAMP_LIMIT,  # the lamps' colours, under their old home
)
from viewer.view3d.legend import LAMP_REF as LAMP_REF
from viewer.view3d.legend import SWITCHES
from viewer.view3d.model_scene import ModelScene
from viewer.view3d.overlays import ContactOverlay, SetPointGhost
from viewer.view3d.renderer import Renderers
from viewer.view3d.views import OFF, ON, SWITCH_CHOICES, Views

log = logging.getLogger(__name__)

PROMPT_S = 0.25
"""How long [s] the panels refresh every frame after an axis changed state, ErrorID or power."""

_Hold = Hold
"""A jog a page holds (:class:`~viewer.serving.control.Hold`)."""

T = TypeVar("T")


class _Part(Generic[T]):
    """An attribute of one of the app's parts (its views), read and written under a
    name of the app."""

    def __init__(self, part: str, name: str) -> None:
        self.part, self.name = part, name

    @overload
    def __get__(self, app: None, owner: type) -> _Part[T]: ...
    @overload
    def __get__(self, app: object, owner: type | None = None) -> T: ...
    def __get__(self, app: object, owner: type | None = None) -> T | _Part[T]:
        if app is None:
            return self
        return cast(T, getattr(getattr(app, self.part), self.name))

    def __set__(self, app: object, value: T) -> None:
        setattr(getattr(app, self.part), self.name, value)


class ViewerApp:
    """Control panel and 3-D scene of a session in a viser server, updated by its own thread.

    Every value a page sends passes a :class:`~viewer.serving.security.GuiGate`: it must fit the
    element (choices, finite ranges), and everything that operates the machine needs control
    (:class:`~viewer.serving.control.Control`, the Take control button); STOP all, the camera views
    and
    the scope are for everyone.

    Args:
        session: The simulation to show and operate.
        server: The viser server to build the GUI in.
        fps: Frames per second of the update loop [Hz] (poses and switch colours; the 3-D
            view at most :data:`~viewer.view3d.renderer.SOFTWARE_FPS` while a page draws in
            software, :mod:`viewer.view3d.renderer`).
        panel_hz: Refresh rate of the axis panels and the status line [Hz].
        plot_hz: Refresh rate of the scope [Hz].
        environment_map: Light the scene with viser's HDRI environment map. It looks best but
            makes a browser without GPU (software WebGL) draw ~10× slower; the default lights
            the scene with a hemisphere light and the default lights without shadows instead
            (shadows halve the frame rate of a browser without GPU).
        log: Where refused GUI messages are logged (bounded).
        clock: Monotonic wall clock [s] of the jog holds' dead-man (injectable for tests).
        demo: A machine chosen on a page starts its demo program.
    """

    show_ghost = _Part[bool]("views", "show_ghost")
    """The set-point ghost is drawn (the View folder's toggle)."""
    show_contacts = _Part[bool]("views", "show_contacts")
    """Contact, hard-stop and tendon forces are drawn (the View folder's choice)."""
    force_scale = _Part[str]("views", "force_scale")
    """Length of the force arrows, a key of :data:`~viewer.view3d.overlays.FORCE_SCALES`."""
    follow = _Part[str]("views", "follow")
    """Body the pages' cameras follow (:data:`~viewer.view3d.views.FOLLOW_OFF`: none)."""

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
        demo: bool = False,
    ) -> None:
        self.session = session
        self.demo_on_choice = demo
        """A machine chosen on a page starts its demo."""
        self.server = server
        self._frame_period = 1.0 / fps
        self.renderers = Renderers(fps)
        """What draws each page's 3-D view; the 3-D frame rate follows from it."""
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
        self._last_panel = self._last_plot = self._last_control = self._last_pose = -math.inf
        self._axis_states: tuple[tuple[str, int, bool], ...] = ()
        """Each axis' state, ErrorID and power as the panels last saw them."""
        self._prompt_until = -math.inf
        """Until then [s, monotonic] the panels refresh every frame (after a state change)."""
        self._axes: dict[str, AxisPanel] = {}
        self._commissioning: dict[str, CommissioningPanel] = {}
        """The Commissioning folders of the driven axes."""
        self._lamps: list[tuple[str, str, str, tuple[float, float, float]]] = []
        """Switch geoms coloured from the inputs: (axis, AxisView field, geom, lamp colour)."""
        self._note: viser.LabelHandle | None = None
        self._signals: viser.GuiHtmlHandle | None = None
        self._results: viser.GuiHtmlHandle | None = None
        self._shown: dict[str, str] = {}
        """The HTML last sent to each panel, by panel name (only changes are sent)."""
        self._pause_label = ""
        self._redraw = False
        self.operators = Operators(session, server, clock)
        """Who operates and the jogs their pages hold."""
        self.control: Control = self.operators.control
        """Who operates (the others watch)."""
        self._holds, self._holds_lock = self.operators.holds, self.operators.lock
        self.views = Views(server, self._draw)
        """Camera presets, follow cameras and 3-D overlays."""

        harden(server)
        self.gate = GuiGate(server, self.control.holds, self.operators.refused, log=log)
        """Checks every GUI value a page sends."""
        self._gui = SceneGui(self.gate)
        self.pages = Pages(session, self.gate, self._plot)
        """Each page's own panels (overview, scope)."""
        session.on_step = self.pages.show_step
        server.on_client_connect(self.operators.connect)
        server.on_client_disconnect(self.operators.disconnect)
        server.on_client_connect(self.pages.connect)
        server.on_client_disconnect(self.pages.disconnect)
        server.on_client_connect(self.renderers.connect)
        server.on_client_disconnect(self.renderers.disconnect)
        _light(server, environment_map)
        # docked, the control panel leaves the canvas to the machine (floating, it covers its
        # right part: the camera frames the machine in the middle of the canvas)
        server.gui.main_panel.dock_right()
        server.gui.main_panel.set_width(CONTROL_WIDTH)
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

    @property
    def ghost(self) -> SetPointGhost | None:
        """The set-point ghost (made when first shown, dropped with its scene)."""
        return self.views.ghost

    @property
    def contacts(self) -> ContactOverlay | None:
        """The contact overlay of the current model (None without a model)."""
        return self.views.contacts

    @property
    def _scene_inputs(self) -> list[Any]:
        return self._gui.inputs

    @property
    def _commands(self) -> list[Any]:
        return self._gui.commands

    def _draw(self) -> None:
        """Draw the next frame even without a new snapshot."""
        self._redraw = True

    def _plot(self) -> None:
        """Update the pages' scopes at the next frame."""
        self._last_plot = -math.inf
        self._redraw = True

    # ------------------------------------------------------------------------- operators

    def _drop_holds(self, client_id: int, expired: Hold | None = None) -> None:
        """End the jog a page holds (:meth:`Operators.drop
        <viewer.serving.control.Operators.drop>`)."""
        self.operators.drop(client_id, expired)

    def renew_holds(self) -> None:
        """Renew the dead-man of the held jogs, drop the expired
        (:meth:`Operators.renew <viewer.serving.control.Operators.renew>`)."""
        self.operators.renew()

    def key_jog(self, client_id: int, generation: int, axis: str, direction: int) -> None:
        """What a jog hotkey does (:meth:`Operators.key_jog
        <viewer.serving.control.Operators.key_jog>`)."""
        self.operators.key_jog(client_id, generation, axis, direction)

    # ------------------------------------------------------------------------- GUI: static

    def _button(self, label: str, *, control: bool = True, **kwargs: Any) -> viser.GuiButtonHandle:
        """A button the gate lets pages press (those in control unless ``control`` is False)."""
        return gated_button(self.gate, label, control=control, **kwargs)

    def _build_static_gui(self) -> None:
        """Control, simulation and demo controls (independent of the scene)."""
        self._build_operator()
        self._build_simulation()
        self._build_demo()

    def _build_operator(self) -> None:
        """The Operator tab, in a window of its own (never scrolled out of sight): STOP all, and
        per page its control line and buttons (:class:`~viewer.pages.control_page.ControlPages`)."""
        gui, operators = self.server.gui, self.operators
        operator = gui.add_panel(order=-1)
        operator.float(x=15, y=-15, width=300)
        with operator.add_tab("Operator", icon=viser.Icon.USER) as tab:
            self._stop_all = self._button(
                "STOP all axes",
                control=False,
                color="red",
                icon=viser.Icon.HAND_STOP,
                hint="Ends the demo, ramps every axis and group down (anyone may press it)",
                order=0,
            )
        self.control_pages = ControlPages(self.gate, operators, tab, order=1)
        """The control line and buttons of each page."""
        self.server.on_client_connect(self.control_pages.connect)
        self.server.on_client_disconnect(self.control_pages.disconnect)

        @self._stop_all.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            operators.drop_all()
            self.session.stop_all()

    def _update_control(self) -> None:
        """Supervise control (lifesign, requests) and, at the panel rate, refresh each page's
        control line (also while the simulation is paused)."""
        self.operators.supervise()
        now = time.monotonic()
        if now - self._last_control >= self._panel_period:
            self._last_control = now
            self.control_pages.refresh()
            self.renderers.refresh(self.session.snapshot.model is not None)

    def _build_simulation(self) -> None:
        """The status line and the scene chooser on top; the Simulation folder (below the axes):
        speed, pause, step, reset, save and restore."""
        gui, session = self.server.gui, self.session
        # which machine, and the chooser, on top; the axes' controls next (order 2)
        self._status = gui.add_html("", order=-2)
        self._scene_choice = gui.add_dropdown(
            "Scene", choices(), initial_value=session.scene_name, order=-1
        )
        self.gate.allow(self._scene_choice, choice_of(choices()))
        with gui.add_folder("Simulation", order=3):
            labels = list(SPEEDS)
            current = speed_label(session.speed)
            if current not in labels:
                labels.insert(0, current)
            self._speeds = {label: SPEEDS.get(label, session.speed) for label in labels}
            self._speed_choice = gui.add_dropdown("Speed", labels, initial_value=current, order=2)
            self.gate.allow(self._speed_choice, choice_of(labels))
            self._pause = self._button("Pause", icon=viser.Icon.PLAYER_PAUSE, order=3)
            actions = (
                ("Step", "Pause and run one PLC cycle", viser.Icon.PLAYER_TRACK_NEXT, session.step),
                (
                    "Reset scene",
                    "Rebuild the scene from scratch",
                    viser.Icon.REFRESH,
                    session.reset,
                ),
                (
                    "Save state",
                    "Keep the machine as it is now (at rest: homed, powered, pressures)",
                    viser.Icon.DEVICE_FLOPPY,
                    session.save_state,
                ),
                (
                    "Restore state",
                    "Return to the saved state (time, physics, axes; the panel's blocks anew)",
                    viser.Icon.RESTORE,
                    self._restore_state,
                ),
            )
            for order, (label, hint, icon, action) in enumerate(actions, start=4):
                self._button(label, hint=hint, icon=icon, order=order).on_click(_call(action))

        @self._scene_choice.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            name = self._scene_choice.value
            if name in scenes.MACHINES and name != session.scene_name:
                session.load(name, demo=self.demo_on_choice)

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

    def _restore_state(self) -> None:
        """Restore state: the held jogs end, the session returns to the saved state."""
        self.operators.drop_all()
        self.session.restore_state()

    def _build_demo(self) -> None:
        """The Demo folder: run and end the demo, repeat it, release its group, its step."""
        gui, session = self.server.gui, self.session
        with gui.add_folder("Demo", order=3.5):
            labels = session.programs.labels or ("none",)
            self._program = gui.add_dropdown(
                "Program",
                labels,
                initial_value=labels[0],
                hint="What Run demo runs: the machine's Python demo or an ST program for it",
                order=-1,
            )
            self.gate.allow(self._program, choice_of(labels))
            self._program_error = gui.add_html("", order=-0.5)
            # two buttons, not a toggle: a click a slow page sends late must not restart a demo
            self._demo_button = self._button("Run demo", icon=viser.Icon.PLAYER_PLAY, order=0)
            self._end_demo = self._button(
                "End demo",
                icon=viser.Icon.PLAYER_STOP,
                hint="Stop the demo and hand the machine over (its groups are released)",
                order=0.5,
            )
            release = self._button(
                "Release group",
                icon=viser.Icon.UNLINK,
                hint="Take the axes groups apart (MC_GroupDisable, MC_UngroupAllAxes)",
                order=1,
            )
            self._repeat = gui.add_dropdown(
                "Repeat demo",
                SWITCH_CHOICES,
                initial_value=ON if session.repeat_demo else OFF,
                hint=f"A demo that ends well starts again after {REPEAT_PAUSE:g} s",
                order=1.5,
            )
            self.gate.allow(self._repeat, choice_of(SWITCH_CHOICES))
            self._demo_step = gui.add_html("", order=2)
            self._demo_runs = gui.add_html("", order=3)

        @self._program.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            chosen = session.programs.chosen
            if self._program.value in session.programs.labels and (
                chosen is None or chosen.label != self._program.value
            ):
                session.programs.choose(self._program.value)

        @self._repeat.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            if self._repeat.value in SWITCH_CHOICES:
                session.repeat_demo = self._repeat.value == ON

        @self._demo_button.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            demo = session.snapshot.demo
            if demo.available and not demo.running:
                session.start_demo()

        self._end_demo.on_click(_call(session.end_demo))
        release.on_click(_call(session.release_groups))

    def _show_programs(self) -> None:
        """The Program choice of a new scene: its programs, the chosen one."""
        programs = self.session.programs
        labels = programs.labels or ("none",)
        self.gate.allow(self._program, choice_of(labels))
        if tuple(self._program.options) != labels:
            self._program.options = labels
        if programs.chosen is not None:
            cast(Any, self._program).value = programs.chosen.label  # viser types it read-only

    # ------------------------------------------------------------------------- GUI: scene

    def _rebuild(self, snapshot: Snapshot) -> None:
        """(Re)build the 3-D scene and every panel of the scene for a new scene."""
        self._clear_scene()
        self._generation = snapshot.generation
        self._show_programs()
        self._build_model(snapshot)
        gui = self._gui = SceneGui(self.gate)
        generation = snapshot.generation
        with gui.folder("Axes", order=0):
            tabs = self.server.gui.add_tab_group()
            for name, view in snapshot.axes.items():
                with tabs.add_tab(name):
                    self._axes[name] = AxisPanel(
                        gui, self.session, self.operators, view, generation
                    )
                    if view.has_drive:
                        self._commissioning[name] = CommissioningPanel(
                            gui, self.session, view, generation
                        )
        if snapshot.signals:
            with gui.folder("Signals", order=4):
                self._signals = self._add_panel("signals", signals_html(snapshot))
        if snapshot.demo.available:
            with gui.folder("Results", order=5):
                self._results = self._add_panel("results", results_html(snapshot))
        steps = {n: p.step for n, p in self._axes.items() if p.step is not None}
        add_hotkeys(gui, self.session, self.operators, steps, generation)
        with gui.folder("Error history", order=6):
            self._events = self.server.gui.add_html(events_html(snapshot))
        build_faults(gui, self.session, snapshot)
        if snapshot.model is not None:
            self.views.build(gui, snapshot.model, self._model_scene)
        self.pages.rebuild(snapshot)

    def _add_panel(self, name: str, content: str) -> viser.GuiHtmlHandle:
        """An HTML panel of the scene showing ``content``."""
        self._shown[name] = content
        return self.server.gui.add_html(content)

    def _clear_scene(self) -> None:
        """Remove the 3-D scene and every panel of the scene that goes."""
        nodes: list[ModelScene | viser.LabelHandle | None] = [self._model_scene, self._note]
        for node in nodes:
            if node is not None:
                node.remove()
        self._model_scene = self._note = None
        self.views.clear()
        self._gui.remove()
        self._axes = {}
        self._commissioning = {}
        self._lamps = []
        self._signals = None
        self._results = None
        for name in ("signals", "results", "events"):
            self._shown[name] = ""
        self._last = None
        self._last_panel = self._last_plot = self._last_pose = -math.inf  # the new scene at once
        self.operators.forget()

    def _build_model(self, snapshot: Snapshot) -> None:
        """The 3-D scene of the snapshot's model and its switch lamps (a note without one)."""
        model = snapshot.model
        if model is None:
            self._note = self.server.scene.add_label(
                "/scene_note", f"{snapshot.scene}: {NO_MODEL_NOTE}", anchor="center-center"
            )
            return
        data = mujoco.MjData(model)
        data.qpos[:] = snapshot.qpos
        mujoco.mj_kinematics(model, data)
        self.views.frame(model, data)
        data.xpos[:] = snapshot.xpos
        data.xquat[:] = snapshot.xquat
        self._model_scene = ModelScene(model, self.server, prefix="/scene", data=data)
        self.views.add_forces()
        self.views.add_marks(snapshot, self._model_scene)
        handles = self._model_scene.geom_handles
        self._lamps = [
            (name, kind, geom, color)
            for name, view in snapshot.axes.items()
            for kind, color in SWITCHES
            if view.joint and (geom := f"{view.joint}_{kind}_geom") in handles
        ]

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
                self._update_control()
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
        repeat = ON if self.session.repeat_demo else OFF  # set after the page was made, too
        if self._repeat.value != repeat:
            cast(Any, self._repeat).value = repeat  # viser types it read-only
        snapshot = self.session.snapshot
        if snapshot is self._last and not self._redraw:
            return
        self._redraw = False
        start = time.perf_counter()
        if snapshot.generation != self._generation:
            self._rebuild(snapshot)
        now = time.monotonic()
        slack = 0.5 * self._frame_period  # e.g. every third frame at 30 fps for 10 Hz
        model_scene = self._model_scene
        if model_scene is not None:
            fps = self.renderers.fps  # lowered while a page draws in software
            if fps >= self.renderers.requested or now - self._last_pose >= 1.0 / fps - slack:
                self._last_pose = now
                self._update_3d(model_scene, snapshot)
            else:  # a page draws in software: the latest pose follows at its lower rate
                self._redraw = True
        if self._panel_due(snapshot, now, slack):
            self._last_panel = now
            self._update_panels(snapshot)
            self.pages.update_panels(snapshot)
        if now - self._last_plot >= self._plot_period - slack:
            self._last_plot = now
            self.pages.update_plots()
        self._last = snapshot
        self.frames += 1
        self.frame_costs.append(time.perf_counter() - start)

    def _panel_due(self, snapshot: Snapshot, now: float, slack: float) -> bool:
        """The panels refresh at the panel rate, and every frame for :data:`PROMPT_S` after an
        axis changed state, ErrorID or power (a click's move shows its first motion a frame
        after it, not a panel period)."""
        states = tuple((a.state, a.error_id, a.powered) for a in snapshot.axes.values())
        if states != self._axis_states:
            self._axis_states = states
            self._prompt_until = now + PROMPT_S
        return now < self._prompt_until or now - self._last_panel >= self._panel_period - slack

    def _update_3d(self, model_scene: ModelScene, snapshot: Snapshot) -> None:
        """Body poses, switch lamps, overlays and follow cameras of ``snapshot``."""
        model_scene.update_poses(snapshot.xpos, snapshot.xquat)
        axes = snapshot.axes
        for name, kind, geom, color in self._lamps:
            if getattr(axes[name], kind):
                model_scene.set_geom_color(geom, color)
            else:
                model_scene.reset_geom_color(geom)
        self.views.update(snapshot)

    def _show(self, name: str, handle: viser.GuiHtmlHandle, content: str) -> None:
        """Send ``content`` to the HTML panel ``name`` if it changed."""
        if content != self._shown.get(name, ""):
            self._shown[name] = handle.content = content

    def _update_panels(self, snapshot: Snapshot) -> None:
        """Status line, demo, buttons, axis read-outs, history (only changes sent)."""
        self.panel_updates += 1
        self._show("status", self._status, status_html(snapshot))
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
        self._show("demo", self._demo_step, demo_html(snapshot))
        programs = self.session.programs
        self._show(
            "program", self._program_error, program_html(programs.chosen, programs.translating)
        )
        self._show("demo runs", self._demo_runs, demo_runs_html(demo.runs, demo.repeat))
        for name, panel in self._axes.items():
            panel.show(snapshot.axes[name])
        for name, commissioning in self._commissioning.items():
            commissioning.show(snapshot.axes[name])
        if self._signals is not None:
            self._show("signals", self._signals, signals_html(snapshot))
        if self._results is not None:
            self._show("results", self._results, results_html(snapshot))
        self._show("events", self._events, events_html(snapshot))


def program_html(chosen: ProgramChoice | None, translating: str = "") -> str:
    """The file being translated, or why the chosen program cannot run (its translation
    error); empty when it can."""
    if translating:
        return (
            '<div style="font-size:0.85em;padding:0 0.75em">'
            f"Translating {html.escape(translating)} …</div>"
        )
    if chosen is None or not chosen.error:
        return ""
    return (
        '<div style="font-size:0.85em;padding:0 0.75em;color:#c62828;overflow-wrap:anywhere">'
        f"{html.escape(chosen.error)}</div>"
    )


def demo_runs_html(runs: int, repeat: bool) -> str:
    """Which run of a repeating demo this is (empty without Repeat demo)."""
    if not (repeat and runs):
        return ""
    return f'<div style="font-size:0.85em;padding:0 0.75em">Run {runs} (repeating)</div>'


def _call(action: Callable[[], None]) -> Callable[[Any], None]:
    """A button callback that calls ``action``."""
    return lambda event: action()


def _light(server: viser.ViserServer, environment_map: bool) -> None:
    """Up is +z; without the environment map: default lights without shadows and a hemisphere
    light (see :class:`ViewerApp`)."""
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

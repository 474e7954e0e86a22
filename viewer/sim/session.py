"""A live simulation for the viewer: a scene run in its own thread, paced to the wall clock.

The scene itself runs in lockstep on simulated time (``Scene.run``); the simulation thread keeps
it at ``speed`` × elapsed wall time with the testbench's pacing loop (:mod:`scenes.pacing`): it
runs PLC cycles whenever simulated time lags, and sleeps otherwise; at ``speed = math.inf`` it
runs as fast as the CPU allows. Each PLC cycle calls the scene's demo program (while it runs) and
then the operator program (:mod:`plc.operator`), whose panels (:class:`~plc.operator.hmi.Panel`)
turn the operator's request flags into function block calls. Nothing else touches the
simulation: the GUI only sets request flags and reads :class:`Snapshot` objects, immutable copies
of what it shows, which the simulation thread publishes up to ``snapshot_hz`` times per wall
second. A viewer therefore never blocks the simulation and cannot perturb it.

Commands (pause, step, speed, reset, scene, demo, save and restore state) are queued and applied
by the simulation thread between two PLC cycles, so they never race with a running cycle.
"""

from __future__ import annotations

__all__ = [
    "EVENTS_KEPT",
    "HISTORY_SAMPLE",
    "LONG_BUCKET",
    "LONG_SECONDS",
    "SCOPE_SECONDS",
    "DemoFactory",
    "Session",
    "choices",
]

import logging
import math
import queue
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import Any

import mcl
import mcl.faults
import scenes
from plc.commissioning.step_test import StepListener
from plc.operator.axis import Clock
from plc.operator.hmi import AxisRequests, Panel, panel_program
from plc.operator.program import OperatorProgram
from plc.st.runtime.watch import WatchedProgram, WatchRow
from scenes import DemoProgram, MachineDef
from scenes.pacing import Pacing, check_speed
from scenes.scene import Scene
from viewer.sim.cam_view import ProfileCache, cam_views
from viewer.sim.demo_run import DemoRun
from viewer.sim.peaks import PeakHold
from viewer.sim.product_frames import ProductFrames
from viewer.sim.programs import ProgramCatalog, ProgramSelection
from viewer.sim.recorder import Recorder
from viewer.sim.snapshot import (
    Event,
    SignalView,
    Snapshot,
    axis_info,
    axis_view,
    copy_array,
    mujoco_of,
)
from viewer.sim.velocity import ShownVelocity
from viewer.view3d.overlays import constraint_forces, contact_forces

log = logging.getLogger(__name__)

DemoFactory = Callable[[Scene], DemoProgram]
"""Makes the demo program of a loaded scene (``scenes.demo`` by default)."""

HISTORY_SAMPLE = 0.002
"""Sampling period [s] of simulated time of the scope channels (rounded to whole PLC cycles)."""

SCOPE_SECONDS = 60.0
"""Simulated seconds every scope channel keeps every sample of."""

LONG_SECONDS = 600.0
"""Simulated seconds every scope channel keeps its minimum and maximum of every
:data:`LONG_BUCKET` of (the longest recording the scope offers)."""

LONG_BUCKET = 0.1
"""Simulated seconds a bucket of the long buffer spans (rounded to whole samples)."""

EVENTS_KEPT = 200
"""Entries of the error history kept (oldest dropped)."""


def choices() -> list[str]:
    """The machines the viewer offers: ``sorted(scenes.MACHINES)``, as ``python -m scenes list``."""
    return sorted(scenes.MACHINES)


class Session:
    """A scene simulated live for the viewer; see the module docstring.

    Example::

        with Session("gantry", speed=1.0) as session:   # starts the simulation thread
            session.requests("X").set_power(True)
            snapshot = session.snapshot

    Args:
        scene: Registry name of the machine (one of ``scenes.MACHINES``).
        speed: Simulated seconds per wall second; ``math.inf`` runs as fast as possible.
        paused: Start paused.
        clock: Monotonic wall clock [s] for pacing and the jog dead-man deadlines.
        demo: Makes a scene's demo program; default ``scenes.demo`` for machines whose definition
            has a demo (``MachineDef.demo``).
        overrides: Keyword overrides for ``scenes.load``; the trace is off unless given
            (``trace_every=0``), so a long session does not accumulate memory.
        snapshot_hz: Snapshots published per wall second at most.
        programs: The ST programs the Program choice offers besides the Python demo
            (default: the repository's ``examples/st/<machine>_demo.st``).

    Raises:
        KeyError: If the scene is unknown.
        ValueError: If ``speed`` is not > 0.
    """

    def __init__(
        self,
        scene: str = "gantry",
        *,
        speed: float = 1.0,
        paused: bool = False,
        clock: Clock = time.monotonic,
        demo: DemoFactory | None = None,
        overrides: Mapping[str, Any] | None = None,
        snapshot_hz: float = 60.0,
        programs: ProgramCatalog | None = None,
    ) -> None:
        self._clock = clock
        self._demo_factory = demo
        self._overrides = {"trace_every": 0, **(overrides or {})}
        self._snapshot_period = 1.0 / snapshot_hz
        self._pacing = Pacing(speed, clock)
        self._paused = paused
        self._steps = 0
        self._commands: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()
        self._wake = threading.Event()
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None
        self._generation = 0
        self._fault = ""
        self._rate: deque[tuple[float, float]] = deque()
        self._last_publish = -math.inf
        self._answer = False
        """An operator's request was asked for: publish after the next run of PLC cycles."""

        self._scene_name = scene
        self._definition = scenes.definition(scene)
        self._scene, self._operator = self._build(scene)
        self._events: deque[Event] = deque(maxlen=EVENTS_KEPT)
        self._demo = DemoRun(self.record_event)
        self._saved: dict[str, mcl.MachineState] = {}
        """The state saved with :meth:`save_state`, by machine name."""
        self.on_step: StepListener | None = None
        """Hears that a step test starts: (client id, axis, start, length [s] of simulated
        time); called in the simulation thread (None: nobody listens)."""
        self.programs = ProgramSelection(programs or ProgramCatalog(), self.record_event)
        """The Program choice: what Run demo runs (``programs.choose(label)``)."""
        self._plc = self.programs.catalog.external
        """The external PLC the viewer serves (None: none), scanned every PLC cycle."""
        self._watch: tuple[WatchRow, ...] = ()
        self._install(scene, self._scene, self._operator)

    # ------------------------------------------------------------------------------ building

    def _build(self, name: str) -> tuple[Scene, OperatorProgram[Panel]]:
        """Load a scene and make its operator program (in the calling thread)."""
        scene = scenes.load(name, **self._overrides)
        return scene, self._operator_for(name, scene)

    def _operator_for(self, name: str, scene: Scene) -> OperatorProgram[Panel]:
        """A fresh operator program on the axes of ``scene`` (of the machine ``name``)."""
        return panel_program(
            scene.axes,
            scenes.definition(name).homing,
            self._clock,
            on_error=self.record_event,
            sim_time=lambda: scene.time,
            on_step=self._step_started,
        )

    def _step_started(self, client_id: int, axis: str, start: float, length: float) -> None:
        """A step test starts: tell :attr:`on_step` (simulation thread)."""
        listener = self.on_step
        if listener is not None:
            listener(client_id, axis, start, length)

    def _install(self, name: str, scene: Scene, operator: OperatorProgram[Panel]) -> None:
        """Make a freshly built scene the running one (simulation thread or not yet running)."""
        definition = scenes.definition(name)
        self._scene_name = name
        self._definition = definition
        self._scene = scene
        self._operator = operator
        if self._plc is not None:
            self._plc.install(scene)
        self._axis_info = axis_info(definition, scene)
        self._model, self._data = mujoco_of(scene)
        self.programs.install(scene, self._demo_factory is not None or definition.demo is not None)
        self._has_demo = bool(self.programs.choices)
        self._demo.clear()
        plc = scene.runtime.plc_period
        self._record_every = max(1, round(HISTORY_SAMPLE / plc))
        self._scan_count = 0
        sample = plc * self._record_every
        self._velocities = ShownVelocity(scene.axes, plc)
        self._recorder = Recorder(
            scene,
            self._axis_info,
            round(SCOPE_SECONDS / sample) + 1,
            every=max(1, round(LONG_BUCKET / sample)),
            buckets=round(LONG_SECONDS / LONG_BUCKET),
            velocity=self._velocities.velocity,
        )
        self._axis_errors = {name: axis.AxErrorID for name, axis in scene.axes.items()}
        self._peaks = PeakHold(scene.axes)
        self._profiles = ProfileCache()
        self._frames = ProductFrames()
        self._generation += 1
        self._fault = ""
        self._restart_pacing()
        self._publish(force=True)

    # ------------------------------------------------------------------------------ queries

    @property
    def scene(self) -> Scene:
        """The scene being simulated (read it only while the thread is stopped or paused)."""
        return self._scene

    @property
    def scene_name(self) -> str:
        """Registry name of the scene being simulated."""
        return self._scene_name

    @property
    def definition(self) -> MachineDef:
        """The registry definition of the machine being simulated."""
        return self._definition

    @property
    def operator(self) -> OperatorProgram[Panel]:
        """The operator program of the current scene."""
        return self._operator

    @property
    def snapshot(self) -> Snapshot:
        """The latest published snapshot (safe from any thread)."""
        return self._snapshot

    @property
    def speed(self) -> float:
        """Simulated seconds per wall second (``math.inf``: as fast as possible)."""
        return self._pacing.speed

    @speed.setter
    def speed(self, speed: float) -> None:
        checked = check_speed(speed)

        def apply() -> None:
            self._pacing.restart(checked)
            self._rate.clear()

        self._post(apply)

    @property
    def paused(self) -> bool:
        """Whether the simulation is paused."""
        return self._paused

    @property
    def running(self) -> bool:
        """Whether the simulation thread is alive."""
        return self._thread is not None and self._thread.is_alive()

    @property
    def recorder(self) -> Recorder:
        """The scope channels of the current scene (read from any thread)."""
        return self._recorder

    def record_event(self, source: str, text: str) -> None:
        """Add an entry to the error history (from any thread)."""
        self._events.append(Event(time.time(), self._scene.time, source, text, self._scene_name))

    @property
    def watch(self) -> tuple[WatchRow, ...]:
        """The watch table of the running ST program, as last published (empty: none runs)."""
        return self._watch

    def force(self, name: str, value: bool | float | None) -> bool:
        """Force variable ``name`` of the running ST program to ``value`` (None: unforce it);
        a refusal (no ST program runs, no such variable, a wrong value) is logged in the error
        history. Whether it was done."""
        demo = self._demo.program
        try:
            if not isinstance(demo, WatchedProgram):
                raise ValueError("no ST program runs")
            if value is None:
                demo.unforce(name)
            else:
                demo.force(name, value)
        except ValueError as exc:
            self.record_event("watch", f"force of {name!r} refused: {exc}")
            return False
        self.record_event("watch", f"{name} unforced" if value is None else f"{name} forced")
        return True

    @property
    def plc_in_control(self) -> str:
        """The external PLC while it commands the machine (its label; empty: none does)."""
        plc = self._plc
        return plc.label if plc is not None and plc.commanding else ""

    def demo_available(self) -> bool:
        """Whether the current scene has a demo program."""
        return self._has_demo

    def requests(self, axis: str, *, answer: bool = True) -> AxisRequests:
        """The operator request flags of an axis of the current scene; with ``answer`` the
        snapshot after the next run of PLC cycles (whose first scan takes a request set now) is
        published at once, not at the next publishing time (False: a jog's renewal).

        Raises:
            KeyError: If the scene has no such axis; the message names its axes.
        """
        try:
            requests = self._operator.front_ends[axis].requests
        except KeyError:
            raise KeyError(
                f"scene {self._scene_name!r} has no axis {axis!r}; axes: {list(self._scene.axes)}"
            ) from None
        self._answer = self._answer or answer
        return requests

    # ------------------------------------------------------------------------------ commands

    def _post(self, command: Callable[[], None]) -> None:
        """Apply a command between two PLC cycles: queued while the thread runs, else now."""
        if self.running:
            self._commands.put(command)
            self._wake.set()
        else:
            command()
            self._publish(force=True)

    def _drain(self) -> bool:
        """Apply the queued commands (simulation thread); whether there were any."""
        applied = False
        while True:
            try:
                command = self._commands.get_nowait()
            except queue.Empty:
                return applied
            try:
                command()
            except Exception as exc:  # e.g. a demo program that fails to construct
                log.exception("viewer command failed")
                self._fault = f"{type(exc).__name__}: {exc}"
            applied = True

    def pause(self) -> None:
        """Stop advancing simulated time (the PLC and servo cycles stop with it)."""

        def apply() -> None:
            self._paused = True

        self._post(apply)

    def resume(self) -> None:
        """Continue after :meth:`pause` or :meth:`step`."""

        def apply() -> None:
            self._paused = False
            self._steps = 0
            self._restart_pacing()

        self._post(apply)

    def step(self, cycles: int = 1) -> None:
        """Pause and run ``cycles`` PLC cycles (one by default).

        Raises:
            ValueError: If ``cycles`` < 1.
        """
        if cycles < 1:
            raise ValueError(f"cycles must be >= 1, got {cycles}")

        def apply() -> None:
            self._paused = True
            self._steps += cycles

        self._post(apply)
        if not self.running:
            self._run_steps()

    def reset(self) -> None:
        """Rebuild the current scene from scratch (the demo stops; pause and speed stay)."""
        self.load(self._scene_name)

    def save_state(self) -> None:
        """The Save state button: keep the machine as it is now (e.g. homed) for
        :meth:`restore_state`, one state per machine (a new one replaces it).

        Refused while an axis moves; either way the error history says what happened.
        """

        def apply() -> None:
            name = self._scene_name
            try:
                state = self._scene.save_state()
            except mcl.StateError as exc:
                self.record_event("viewer", f"state not saved: {exc}")
                return
            self._saved[name] = state
            self.record_event("viewer", f"state of {name} saved at {state.time:.3f} s")

        self._post(apply)

    def restore_state(self) -> None:
        """The Restore state button: return the machine to the state saved with
        :meth:`save_state` (positions, power, homing, errors, simulated time).

        The demo stops and the operator program starts afresh on the restored scene, as after
        :meth:`reset`, but the axes keep their power and reference. Without a saved state of
        this machine nothing happens but an entry in the error history.
        """

        def apply() -> None:
            name = self._scene_name
            state = self._saved.get(name)
            if state is None:
                self.record_event("viewer", f"no saved state of {name} to restore: save one first")
                return
            scene = self._scene
            try:
                scene.restore_state(state)
            except mcl.StateError as exc:
                self.record_event("viewer", f"state not restored: {exc}")
                return
            self._install(name, scene, self._operator_for(name, scene))
            self.record_event("viewer", f"state of {name} restored: saved at {state.time:.3f} s")

        self._post(apply)

    def load(self, name: str, demo: bool = False) -> None:
        """Replace the simulation by a freshly built scene ``name``; with ``demo``, its demo
        program (if it has one) starts with it.

        The scene is built in the calling thread, then swapped in between two PLC cycles.

        Raises:
            KeyError: If the scene is unknown.
        """
        scene, operator = self._build(name)
        self.programs.prepare(scene)

        def apply() -> None:
            self._install(name, scene, operator)
            if demo and self._has_demo:
                self._begin_demo()

        self._post(apply)

    def start_demo(self) -> None:
        """Start the scene's demo program afresh; the operator hands power back to it.

        Raises:
            RuntimeError: If the scene has no demo program.
        """
        if not self.demo_available():
            raise RuntimeError(f"scene {self._scene_name!r} has no demo program")
        generation = self._generation

        def apply() -> None:
            if generation != self._generation:
                return  # the scene was replaced meanwhile
            self._demo.runs = 0
            self._begin_demo()

        self._post(apply)

    @property
    def repeat_demo(self) -> bool:
        """Repeat demo: a demo that ends successfully starts again after :data:`REPEAT_PAUSE`
        (a fresh program from the demo factory); a failed demo does not repeat."""
        return self._demo.repeat

    @repeat_demo.setter
    def repeat_demo(self, repeat: bool) -> None:
        self._demo.repeat = bool(repeat)

    def _begin_demo(self) -> None:
        """Make a fresh demo program and run it (simulation thread)."""
        factory = self.programs.factory(self._demo_factory)
        if self._demo.begin(factory, self._scene, self._scene_name):
            for panel in self._operator.front_ends.values():
                panel.release_power()

    def end_demo(self) -> None:
        """Stop calling the demo program and take its axes groups apart, so that every axis
        can be homed, jogged and moved again (the axes keep power and reference)."""

        def apply() -> None:
            self._demo.program = None
            self._operator.release_groups()

        self._post(apply)

    def release_groups(self) -> None:
        """The Release group button: take every axes group apart (its motion ramps down)."""
        self._post(self._operator.release_groups)

    def stop_all(self) -> None:
        """STOP for all axes: ends the demo, releases jogs and groups (their motion ramps
        down), MC_Stop on every other driven axis."""

        def apply() -> None:
            self._demo.program = None
            for panel in self._operator.front_ends.values():
                panel.stop_all()
            self._operator.release_groups()

        self.record_event("viewer", "STOP all axes")
        self._post(apply)

    def inject(self, axis: str, fault: mcl.faults.Fault) -> None:
        """Inject ``fault`` on ``axis`` through ``scene.faults`` (between two PLC cycles).

        Raises:
            KeyError: If the scene has no such axis.
        """
        self.requests(axis)

        def apply() -> None:
            self._scene.faults.set(axis, fault)

        self.record_event(axis, f"fault injected: {fault!r}")
        self._post(apply)

    def clear_faults(self, axis: str) -> None:
        """Clear every injected fault of ``axis``.

        Raises:
            KeyError: If the scene has no such axis.
        """
        self.requests(axis)

        def apply() -> None:
            faults = self._scene.faults
            for fault in faults.active(axis):
                faults.clear(axis, fault)

        self.record_event(axis, "faults cleared")
        self._post(apply)

    def active_faults(self, axis: str) -> list[mcl.faults.Fault]:
        """The faults set on ``axis`` now."""
        return list(self._scene.faults.active(axis))

    def reset_peaks(self) -> None:
        """The Reset peaks button: the peak following errors start again from now."""
        self._post(lambda: self._peaks.reset())

    def toggle_power(self, axis: str) -> None:
        """The Power button of an axis: ends a running demo, then toggles the drive.

        The demo program calls its own MC_Power every scan; while it runs, an operator power
        request would fight it, so pressing Power takes the machine back into manual operation.

        Raises:
            KeyError: If the scene has no such axis.
        """
        requests = self.requests(axis)

        def apply() -> None:
            self._demo.program = None
            requests.toggle_power()

        self._post(apply)

    # ------------------------------------------------------------------------------ running

    def _scan(self) -> None:
        """One PLC scan: demo program (while it runs), operator program, scope channels."""
        outcome = self._demo.scan(self._scene.time, self._scene_name)
        if outcome == "ended":
            self._operator.release_groups()
        elif outcome == "repeat":
            self._begin_demo()
        if self._plc is not None:
            self._plc.scan(self._demo.program)
        self._operator()
        self._peaks.sample()
        self._velocities.sample(self._scene.time)
        errors = self._axis_errors
        for name, axis in self._scene.axes.items():
            code = axis.AxErrorID
            if code != errors[name]:
                errors[name] = code
                if code:
                    self.record_event(name, f"axis error {code} ({mcl.error_text(code)})")
        self._scan_count += 1
        if self._scan_count >= self._record_every:
            self._scan_count = 0
            t = self._scene.runtime.time
            self._recorder.record(t)

    def _run_cycles(self, cycles: int) -> None:
        """Run ``cycles`` PLC cycles; an exception pauses the simulation and is reported."""
        scene = self._scene
        try:
            scene.run(self._scan, timeout=cycles * scene.runtime.plc_period)
        except Exception as exc:
            log.exception("simulation of scene %r failed", self._scene_name)
            self._paused = True
            self._fault = f"{type(exc).__name__}: {exc}"

    def _run_steps(self) -> None:
        """Run the requested single steps (simulation thread, or the caller when stopped)."""
        while self._steps > 0:
            self._steps -= 1
            self._run_cycles(1)
            if self._fault:
                self._steps = 0
        self._publish(force=True)

    def advance(self, cycles: int) -> None:
        """Run ``cycles`` PLC cycles in the calling thread, regardless of pause and speed.

        For scripts and tests that drive the session without its thread.

        Raises:
            RuntimeError: If the simulation thread is running.
        """
        if self.running:
            raise RuntimeError("advance() drives a stopped session; the thread is running")
        self._drain()
        self._run_cycles(cycles)
        self._publish(force=True)

    def start(self) -> None:
        """Start the simulation thread (no-op if it runs)."""
        if self.running:
            return
        self._stopping.clear()
        self._restart_pacing()
        self._thread = threading.Thread(target=self._loop, name="viewer-simulation", daemon=True)
        self._thread.start()

    def close(self, timeout: float = 5.0) -> None:
        """Stop the simulation thread and wait for it [s at most]."""
        thread = self._thread
        if thread is None:
            return
        self._stopping.set()
        self._wake.set()
        thread.join(timeout)
        self._thread = None
        self._drain()

    def __enter__(self) -> Session:
        """Start the simulation thread."""
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        """Stop the simulation thread."""
        self.close()

    def _loop(self) -> None:
        """The simulation thread: the pacing loop (:mod:`scenes.pacing`) until :meth:`close`."""
        self._pacing.run(_Paced(self), self._stopping)

    def _held(self) -> bool:
        """Before each look at the clock: apply the queued commands; while paused, run the
        single steps asked for or wait. Whether nothing is to run now."""
        if self._drain():
            self._publish(force=True)
        if not self._paused:
            return False
        if self._steps:
            self._run_steps()
        else:
            self._idle(0.05)
        return True

    def _restart_pacing(self) -> None:
        """Pace from now on (a new scene, resumed, started): no backlog, a fresh rate."""
        self._pacing.restart()
        self._rate.clear()

    def _idle(self, seconds: float) -> None:
        """Sleep up to ``seconds`` [s] of wall time, or until a command arrives (0: just let
        the GUI threads have the interpreter)."""
        if seconds <= 0.0:
            time.sleep(0)
        elif self._wake.wait(seconds):
            self._wake.clear()

    # ------------------------------------------------------------------------------ snapshots

    def _publish(self, force: bool = False) -> None:
        """Copy what the viewer shows into a new :class:`Snapshot` (at most snapshot_hz)."""
        now = self._clock()
        if not force and now - self._last_publish < self._snapshot_period:
            return
        self._last_publish = now
        scene = self._scene
        sim = scene.time
        rate = self._rate
        rate.append((now, sim))
        while len(rate) > 2 and now - rate[0][0] > 1.0:
            rate.popleft()
        span = rate[-1][0] - rate[0][0]
        factor = (rate[-1][1] - rate[0][1]) / span if span > 0.0 else 0.0
        demo = self._demo
        demo.sample()
        program = demo.program
        self._watch = program.rows() if isinstance(program, WatchedProgram) else ()
        panels, info = self._operator.front_ends, self._axis_info
        peak, velocity = self._peaks.peak, self._velocities.velocity
        views = {
            name: axis_view(scene, name, panels[name], info[name], peak(name), velocity(name, axis))
            for name, axis in scene.axes.items()
        }
        model, data = self._model, self._data
        self._snapshot = Snapshot(
            generation=self._generation,
            scene=self._scene_name,
            description=self._definition.description,
            time=sim,
            wall=now,
            model=model,
            qpos=copy_array(None if data is None else data.qpos, (0,)),
            xpos=copy_array(None if data is None else data.xpos, (0, 3)),
            xquat=copy_array(None if data is None else data.xquat, (0, 4)),
            axes=MappingProxyType(views),
            signals=tuple(self._signal_view(name) for name in scene.signals),
            paused=self._paused,
            speed=self._pacing.speed,
            realtime_factor=0.0 if self._paused else factor,
            demo=demo.view(self.demo_available()),
            fault=self._fault,
            events=tuple(self._events),
            results=demo.results,
            channels=self._recorder.channels,
            groups=tuple(g.name for g in self._operator.groups()),
            contacts=None if model is None or data is None else contact_forces(model, data),
            constraints=None if model is None or data is None else constraint_forces(model, data),
            cams=cam_views(scene.axes, self._profiles),
            frames=self._frames(self._operator.groups(), model, data),
        )

    def _signal_view(self, name: str) -> SignalView:
        signal = self._scene.signals[name]
        try:
            value = float(signal.read(self._scene.signal_owner(name)))
        except Exception:  # a faulty reader must not stop the simulation thread
            log.debug("signal %r of scene %r failed", name, self._scene_name, exc_info=True)
            value = math.nan
        label = signal.label or name.replace("_", " ")
        return SignalView(name=name, value=value, unit=signal.unit, label=label)


class _Paced:
    """The session as its pacing loop sees it (:class:`scenes.pacing.Paced`; the simulation
    thread)."""

    def __init__(self, session: Session) -> None:
        self.session = session

    def simulated(self) -> tuple[float, float]:
        scene = self.session.scene
        return scene.time, scene.runtime.plc_period

    def held(self) -> bool:
        return self.session._held()

    def run_cycles(self, cycles: int) -> None:
        self.session._run_cycles(cycles)

    def ran(self) -> None:
        session = self.session
        answer, session._answer = session._answer, False
        session._publish(force=answer)

    def idle(self, seconds: float) -> None:
        self.session._idle(seconds)

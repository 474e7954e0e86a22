"""The viewer's front end of the operator program: the operator panel's buttons as PLC code.

The browser never touches the simulation. A button only sets a request in :class:`AxisRequests`
(thread-safe, like an HMI variable); once per PLC cycle, in the simulation thread, the axis'
:class:`Panel` takes the requests and turns them into the :class:`~plc.operator.axis.Orders` of
its :class:`~plc.operator.axis.AxisOperator`, which calls the library's function blocks:

=============  ===================================================================================
Power          ``power``; a toggle: the request becomes "on" if the axis is Disabled, else "off".
               Until the operator first presses it MC_Power is not called, so a running demo
               program keeps power in its own hands.
Reset          ``reset``.
Home           ``home`` with the chosen procedure (:data:`HOMING_PROCEDURES`): the scene's
               recipe (REF and index, or to a block), the next index pulse in either direction,
               or set position without moving.
Jog+ / Jog−    the jog levels: a request is a dead-man deadline (:data:`DEADMAN` [s] of wall
               time) that every hold message of the browser refreshes; when it runs out — button
               released, tab closed, network gone — the jog stops.
Stop           ``stop`` (on a member of an axes group: the program takes the group apart).
Move           ``move_absolute`` (to a position) or ``move_relative`` (by a distance) with the
               operator's velocity and acceleration; a new move aborts the last one.
Write          ``constants``: GT_SetConstant with the operator's servo constants (tuning).
Reversing      :class:`~plc.commissioning.reversing.ReversingSequence`: ``MC_MoveAbsolute``
               to A, dwell, to B, dwell, … for a number of cycles; Stop sequence ends it with
               ``MC_Halt``.
Step test      :class:`~plc.commissioning.step_test.StepTest`: a set-point step
               (``MC_MoveRelative`` at the axis' limits) from standstill, its response recorded
               and measured.
Jog speed      fast (the jog velocity) or slow (:data:`SLOW_JOG_FRACTION` of it).
Override       ``MC_SetOverride``, every scan once the operator set a velocity override.
=============  ===================================================================================

A press executes its command until the block is no longer busy (Done, Error or aborted; its
outcome is the axis' message), then its Execute is released; pressing Reset, Home or Stop again
meanwhile changes nothing, a new move starts afresh. A jog, a move, a homing or Stop of the
operator ends a running reversing sequence or step test (the operator takes the axis over).
Every scan ends with ``GT_AxStatusString`` and ``GT_AxErrStringEN`` for the panel's texts.
:func:`panel_program` makes the operator program of a scene driven by its panels.
"""

from __future__ import annotations

__all__ = [
    "DEADMAN",
    "DEFAULT_JOG_FRACTION",
    "HOMING_PROCEDURES",
    "MIN_VELOCITY_FRACTION",
    "SLOW_JOG_FRACTION",
    "AxisOperator",
    "AxisRequests",
    "Clock",
    "ErrorSink",
    "Move",
    "OperatorProgram",
    "Requests",
]

import math
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass

import mcl
from plc.commissioning.axis import (
    MAX_OVERRIDE,
    NO_COMMISSIONING,
    CommissioningRequests,
    CommissioningView,
)
from plc.commissioning.reversing import Reversing
from plc.commissioning.step_test import StepListener
from plc.operator.axis import (
    HOMING_PROCEDURES,
    MOVES,
    AxisOperator,
    Clock,
    ErrorSink,
    Orders,
    Parameters,
    no_parameters,
)
from plc.operator.program import OperatorProgram
from plc.procedures import Recipe

DEADMAN = 0.2
"""Wall time [s] a jog request stays alive after the last hold message of the browser."""

DEFAULT_JOG_FRACTION = 0.1
"""Default jog velocity as a fraction of the axis' Vmax (velocity at 10 V)."""

SLOW_JOG_FRACTION = 0.1
"""Slow jog: this fraction of the jog velocity (fast jog: all of it)."""

MIN_VELOCITY_FRACTION = 0.01
"""The library's slowest motion: 1 % of Vmax (a slow jog is never slower)."""


@dataclass(frozen=True, slots=True)
class Requests:
    """What the operator wants from one axis in one PLC scan (taken from :class:`AxisRequests`).

    Attributes:
        power: ``True``/``False`` to switch the drive on/off, ``None``: no change of hands.
        toggle_power: a Power press to be resolved against the axis state.
        reset: a Reset press.
        home: a Home press: (procedure of :data:`HOMING_PROCEDURES`, home position [u], used by
            the index-pulse procedures and set position); None: none.
        stop: a Stop press.
        jog_pos: Jog+ is held (its dead-man deadline has not run out).
        jog_neg: Jog− is held.
        jog_velocity: jog velocity [u/s]; 0 = the default (a tenth of Vmax).
        move: a move press: (``"absolute"`` or ``"relative"``, position or distance [u],
            velocity [u/s], acceleration [u/s²]); None: none.
        constants: servo constants to write with GT_SetConstant; None: none.
        commissioning: the presses of the commissioning controls.
        jog_slow: jog at :data:`SLOW_JOG_FRACTION` of the jog velocity.
    """

    power: bool | None
    toggle_power: bool
    reset: bool
    home: tuple[str, float] | None
    stop: bool
    jog_pos: bool
    jog_neg: bool
    jog_velocity: float
    move: Move | None = None
    constants: mcl.ServoConstants | None = None
    commissioning: CommissioningRequests = NO_COMMISSIONING
    jog_slow: bool = False


@dataclass(frozen=True, slots=True)
class Move:
    """A move the operator asked for.

    Attributes:
        kind: ``"absolute"`` (to ``target``) or ``"relative"`` (by ``target``).
        target: position or distance [u].
        velocity: [u/s], > 0.
        acceleration: acceleration and deceleration [u/s²], > 0.
    """

    kind: str
    target: float
    velocity: float
    acceleration: float

    def __post_init__(self) -> None:
        if self.kind not in ("absolute", "relative"):
            raise ValueError(f"move kind must be 'absolute' or 'relative', got {self.kind!r}")
        if not math.isfinite(self.target):
            raise ValueError(f"move target must be a finite number, got {self.target}")
        for name in ("velocity", "acceleration"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"move {name} must be a finite number > 0, got {value}")

    @property
    def command(self) -> str:
        """Its Execute command: ``move_absolute`` or ``move_relative``."""
        return f"move_{self.kind}"

    def parameter(self, name: str) -> float:
        """Its parameters (:data:`~plc.operator.axis.Parameters`): the target as ``position`` or
        ``distance``, the velocity, the acceleration as acceleration and deceleration."""
        if name == ("position" if self.kind == "absolute" else "distance"):
            return self.target
        if name == "velocity":
            return self.velocity
        return self.acceleration if name in ("acceleration", "deceleration") else 0.0


class AxisRequests:
    """Operator request flags of one axis, written by GUI threads, read by the PLC thread.

    Presses are latched until the operator program takes them; a jog request is a deadline on
    the wall clock ``clock`` that :meth:`jog` pushes :data:`DEADMAN` seconds ahead.

    Args:
        clock: Monotonic wall clock [s] (injectable for tests).
        deadman: Life time [s] of a jog request after the last :meth:`jog` call.
    """

    def __init__(self, clock: Clock = time.monotonic, deadman: float = DEADMAN) -> None:
        self._clock = clock
        self._deadman = deadman
        self._lock = threading.Lock()
        self._power: bool | None = None
        self._toggle = False
        self._reset = False
        self._home: tuple[str, float] | None = None
        self._stop = False
        self._jog_until = {1: -math.inf, -1: -math.inf}
        self._jog_velocity = 0.0
        self._move: Move | None = None
        self._constants: mcl.ServoConstants | None = None
        self._reversing: Reversing | None = None
        self._end_reversing = False
        self._step: tuple[float, int] | None = None
        self._override: float | None = None
        self.jog_slow = False
        """Jog at :data:`SLOW_JOG_FRACTION` of the jog velocity (the Jog speed switch)."""

    def set_power(self, on: bool) -> None:
        """Request the drive on (``True``) or off (``False``)."""
        with self._lock:
            self._power = bool(on)
            self._toggle = False

    def toggle_power(self) -> None:
        """The Power button: on if the axis is Disabled when the PLC sees it, else off."""
        with self._lock:
            self._toggle = True

    def release_power(self) -> None:
        """Stop calling the operator's MC_Power (e.g. while a demo program owns the drives)."""
        with self._lock:
            self._power = None
            self._toggle = False

    def reset(self) -> None:
        """The Reset button (MC_Reset)."""
        with self._lock:
            self._reset = True

    def home(self, procedure: str = "recipe", position: float = 0.0) -> None:
        """The Home button: run ``procedure`` (one of :data:`HOMING_PROCEDURES`); ``position``
        [u] is the coordinate an index-pulse procedure or set position gives the axis.

        Raises:
            ValueError: An unknown procedure or a position that is not finite.
        """
        if procedure not in HOMING_PROCEDURES:
            raise ValueError(
                f"homing procedure must be one of {HOMING_PROCEDURES}, got {procedure!r}"
            )
        if not math.isfinite(position):
            raise ValueError(f"home position must be a finite number, got {position}")
        with self._lock:
            self._home = (procedure, float(position))

    def stop(self) -> None:
        """The Stop button (MC_Stop)."""
        with self._lock:
            self._stop = True

    def move(self, move: Move) -> None:
        """The Move button: move to a position or by a distance (replaces a pending press)."""
        with self._lock:
            self._move = move

    def write_constants(self, constants: mcl.ServoConstants) -> None:
        """The Write button of the tuning panel (GT_SetConstant checks the values)."""
        with self._lock:
            self._constants = constants

    def reverse(self, sequence: Reversing) -> None:
        """The Start sequence button: run a reversing sequence (replaces a running one)."""
        with self._lock:
            self._reversing = sequence

    def end_reversing(self) -> None:
        """The Stop sequence button: MC_Halt ends the reversing sequence."""
        with self._lock:
            self._end_reversing = True
            self._reversing = None

    def step_test(self, amplitude: float, client_id: int) -> None:
        """The Step test button of the page ``client_id``: a step of ``amplitude`` [u].

        Raises:
            ValueError: An amplitude that is not finite.
        """
        if not math.isfinite(amplitude):
            raise ValueError(f"step amplitude must be a finite number, got {amplitude}")
        with self._lock:
            self._step = (float(amplitude), int(client_id))

    @property
    def override(self) -> float | None:
        """Velocity override [%] (MC_SetOverride); None: the operator has not set one."""
        return self._override

    @override.setter
    def override(self, percent: float) -> None:
        if not (math.isfinite(percent) and 0.0 <= percent <= MAX_OVERRIDE):
            raise ValueError(f"override must be in [0, {MAX_OVERRIDE:g}] %, got {percent}")
        self._override = float(percent)

    def jog(self, direction: int) -> None:
        """Hold Jog+ (``direction`` > 0) or Jog− (< 0) for another :data:`DEADMAN` seconds.

        Raises:
            ValueError: If ``direction`` is 0.
        """
        if direction == 0:
            raise ValueError("jog direction must be +1 (Jog+) or -1 (Jog−), got 0")
        key = 1 if direction > 0 else -1
        until = self._clock() + self._deadman
        with self._lock:
            self._jog_until[key] = until

    def release_jog(self) -> None:
        """Let go of both jog buttons at once (without waiting for the dead-man deadline)."""
        with self._lock:
            self._jog_until[1] = self._jog_until[-1] = -math.inf

    @property
    def jog_velocity(self) -> float:
        """Jog velocity [u/s]; 0 = a tenth of the axis' Vmax."""
        return self._jog_velocity

    @jog_velocity.setter
    def jog_velocity(self, velocity: float) -> None:
        if not (math.isfinite(velocity) and velocity >= 0.0):
            raise ValueError(f"jog velocity must be a finite number >= 0, got {velocity}")
        self._jog_velocity = float(velocity)

    def take(self) -> Requests:
        """The requests for this PLC scan; presses are consumed."""
        now = self._clock()
        with self._lock:
            requests = Requests(
                power=self._power,
                toggle_power=self._toggle,
                reset=self._reset,
                home=self._home,
                stop=self._stop,
                jog_pos=now < self._jog_until[1],
                jog_neg=now < self._jog_until[-1],
                jog_velocity=self._jog_velocity,
                move=self._move,
                constants=self._constants,
                commissioning=CommissioningRequests(
                    self._reversing, self._end_reversing, self._step, self._override
                ),
                jog_slow=self.jog_slow,
            )
            self._toggle = self._reset = self._stop = self._end_reversing = False
            self._home = None
            self._move = None
            self._constants = None
            self._reversing = None
            self._step = None
        return requests


class Panel:
    """The panel of one axis: its requests as its operator's orders (one PLC scan per call).

    Args:
        operator: The axis' function blocks.
        requests: Its request flags.
    """

    def __init__(self, operator: AxisOperator, requests: AxisRequests) -> None:
        self.operator = operator
        self.requests = requests
        self.power_request: bool | None = None
        """Level passed to MC_Power's Enable; ``None`` while the operator has not pressed Power."""
        self.jog_slow = False
        """The slow jog speed was chosen in the last scan of a jog."""
        self._pressed: set[str] = set()
        """The commands a press executes until they end."""
        self.status = mcl.GT_AxStatusString()
        self.error_text = mcl.GT_AxErrStringEN()
        """The axis' state and error as the panel shows them (called after every scan)."""

    @property
    def commissioning_view(self) -> CommissioningView:
        """What the commissioning controls show now."""
        return self.operator.commissioning.view(self.jog_slow)

    def release_power(self) -> None:
        """Hand the drive back: MC_Power is no longer called (called from the PLC thread)."""
        self.requests.release_power()
        self.power_request = None

    def stop_all(self) -> None:
        """The axis' part of STOP all (called from the PLC thread between two scans): the jog
        released, and MC_Stop if the axis is powered."""
        self.requests.release_jog()
        if self.operator.axis.state != mcl.AxisState.Disabled:
            self.requests.stop()

    def __call__(self) -> None:
        """One PLC scan: take the requests, give the orders."""
        operator, axis = self.operator, self.operator.axis
        r = self.requests.take()
        if r.power is not None:
            self.power_request = r.power
        if r.toggle_power:
            self.power_request = axis.state == mcl.AxisState.Disabled
        start: dict[str, Parameters] = {}
        if r.reset:
            self._press(start, "reset")
        if r.home is not None and not operator.homing and operator.select_homing(*r.home):
            self._press(start, "home")
        if r.move is not None:
            self._pressed -= MOVES  # the last move's Execute falls: the new one aborts it
            start[r.move.command] = r.move.parameter
        if r.stop and axis.has_drive:
            if axis.group is not None:
                operator.note("Stop", "the axis' group ramps down and is released")
                operator.group_stop = True
            else:
                self._press(start, "stop")
        self._pressed.update(start)
        jogging = r.jog_pos or r.jog_neg or operator.jog.Enable
        taken_over = r.move is not None or r.home is not None or r.jog_pos or r.jog_neg or r.stop
        if jogging:
            self.jog_slow = r.jog_slow
        operator(
            Orders(
                power=self.power_request,
                execute=frozenset(self._pressed),
                start=start,
                jog_pos=r.jog_pos,
                jog_neg=r.jog_neg,
                jog_velocity=self._jog_velocity(r) if jogging else 0.0,
                constants=r.constants,
                commissioning=r.commissioning,
                taken_over=taken_over,
            )
        )
        self._pressed -= operator.finished
        self.status(Axis=axis, Enable=True)
        self.error_text(Axis=axis, Enable=True)

    def _press(self, start: dict[str, Parameters], command: str) -> None:
        """Start ``command`` unless a press already executes it."""
        if command not in self._pressed:
            start[command] = no_parameters

    def _jog_velocity(self, r: Requests) -> float:
        """JogVelo [u/s]: the operator's (0: :data:`DEFAULT_JOG_FRACTION` of Vmax), slow:
        :data:`SLOW_JOG_FRACTION` of it, never below the library's slowest motion."""
        constants = self.operator.axis.constants
        vmax = constants.Vmax if constants is not None else 0.0
        velocity = r.jog_velocity or DEFAULT_JOG_FRACTION * vmax
        if r.jog_slow:
            slowest = MIN_VELOCITY_FRACTION * vmax * (1.0 + 1e-9)  # a margin for rounding
            velocity = max(SLOW_JOG_FRACTION * velocity, slowest)
        return velocity


def panel_program(
    axes: Mapping[str, mcl.Axis],
    recipes: Mapping[str, Recipe],
    clock: Clock = time.monotonic,
    on_error: ErrorSink | None = None,
    *,
    sim_time: Clock,
    on_step: StepListener | None = None,
) -> OperatorProgram[Panel]:
    """The operator program of a scene driven by its operator panels, one per axis
    (``program.front_ends[name].requests`` are what the GUI writes).

    Args:
        axes: The scene's axes by name.
        recipes: Homing recipes by axis name (axes without one have no recipe procedure).
        clock: Monotonic wall clock [s] for the jog dead-man deadlines.
        on_error: Hears of every refused command: (axis or group, text).
        sim_time: Simulated time [s] of the scene.
        on_step: Hears that a step test starts (in the simulation thread).
    """
    panels = [
        Panel(
            AxisOperator(axis, recipes.get(name), (), on_error, sim_time=sim_time, on_step=on_step),
            AxisRequests(clock),
        )
        for name, axis in axes.items()
    ]
    return OperatorProgram(panels, on_error)

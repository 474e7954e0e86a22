"""The operator panel as PLC code: HMI request flags and the operator program that obeys them.

The browser never touches the simulation. A button only sets a request in :class:`AxisRequests`
(thread-safe, like an HMI variable); :class:`OperatorProgram` runs in the simulation thread once
per PLC cycle, reads the requests and passes them to the library's function blocks:

=============  ===================================================================================
Power          ``MC_Power``; a toggle: the request becomes "on" if the axis is Disabled, else "off".
               Until the operator first presses it the block is not called, so a running demo
               program keeps power in its own hands.
Reset          ``MC_Reset``: Execute from the request until Done or Error, then released.
Home           the chosen homing procedure (:data:`HOMING_PROCEDURES`): the scene's
               recipe (REF and index, or to a block) through ``plc.procedures.HomeAxis``, or
               ``MC_StepRefPulse`` on the next index pulse in either direction, or
               ``MC_StepDirect`` (set the position without moving); Execute until it is no
               longer Busy (Done, Error or aborted), then released.
Jog+ / Jog−    ``GT_Jog`` (levels JogPos / JogNeg): a request is a dead-man deadline
               (:data:`DEADMAN` [s] of wall time) that every hold message of the browser refreshes;
               when it runs out — button released, tab closed, network gone — the jog stops.
Stop           ``MC_Stop``: Execute from the request until Done (or Error), then released so that
               the axis leaves Stopping.
Move           ``MC_MoveAbsolute`` (to a position) or ``MC_MoveRelative`` (by a distance) with the
               operator's velocity and acceleration; a new move aborts the last one.
Write          ``GT_SetConstant`` with the operator's servo constants (tuning).
Reversing      :class:`~plc.commissioning.reversing.ReversingSequence`: ``MC_MoveAbsolute``
               to A, dwell, to B, dwell, … for a number of cycles; Stop sequence ends it with
               ``MC_Halt``.
Step test      :class:`~plc.commissioning.step_test.StepTest`: a set-point step
               (``MC_MoveRelative`` at the axis' limits) from standstill, its response recorded
               and measured.
Jog speed      fast (the jog velocity) or slow (:data:`SLOW_JOG_FRACTION` of it).
Override       ``MC_SetOverride``, every scan once the operator set a velocity override.
Release group  every axes group the scene's axes belong to: ``MC_GroupReset`` (from
               GroupErrorStop), ``MC_GroupDisable`` (the group ramps to standstill), then
               ``MC_UngroupAllAxes``: the axes can be jogged, moved and homed one by one again.
=============  ===================================================================================

A jog, a move, a homing or Stop of the operator ends a running reversing sequence or step test
(the operator takes the axis over).

A command a block refuses (an Error with its ErrorID) is reported through ``on_error`` (axis and
text), so the panel can keep a history of refused commands and axis errors.

Every scan also calls ``GT_AxStatusString`` and ``GT_AxErrStringEN`` for the panel's texts.
"""

from __future__ import annotations

__all__ = [
    "DEADMAN",
    "DEFAULT_JOG_FRACTION",
    "HOMING_PROCEDURES",
    "INDEX_FRACTION",
    "MIN_VELOCITY_FRACTION",
    "SLOW_JOG_FRACTION",
    "AxisOperator",
    "AxisRequests",
    "Clock",
    "ErrorSink",
    "GroupRelease",
    "Move",
    "OperatorProgram",
    "Requests",
]

import math
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import mcl
from plc.commissioning.axis import (
    MAX_OVERRIDE,
    NO_COMMISSIONING,
    AxisCommissioning,
    CommissioningRequests,
    CommissioningView,
)
from plc.commissioning.reversing import Reversing
from plc.commissioning.step_test import StepListener
from plc.procedures import HomeAxis, HomingRecipe, Recipe

DEADMAN = 0.2
"""Wall time [s] a jog request stays alive after the last hold message of the browser."""

DEFAULT_JOG_FRACTION = 0.1
"""Default jog velocity as a fraction of the axis' Vmax (velocity at 10 V)."""

HOMING_PROCEDURES = ("recipe", "index pulse +", "index pulse −", "set position (no motion)")
"""Homing procedures of the Home button: the machine's recipe (REF and index, or to a block;
only where the definition gives one), MC_StepRefPulse in the positive or negative direction,
MC_StepDirect."""

SLOW_JOG_FRACTION = 0.1
"""Slow jog: this fraction of the jog velocity (fast jog: all of it)."""

MIN_VELOCITY_FRACTION = 0.01
"""The library's slowest motion: 1 % of Vmax (a slow jog is never slower)."""

INDEX_FRACTION = 0.02
"""Index-search velocity of the index-pulse procedures without a recipe, as a fraction of Vmax."""

Clock = Callable[[], float]
"""Monotonic wall clock [s]."""

ErrorSink = Callable[[str, str], None]
"""Hears of a refused command: (axis name, text)."""


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


class AxisOperator:
    """The operator's function blocks of one axis and their sequencing (one PLC scan per call).

    Args:
        axis: The axis.
        requests: Its request flags.
        recipe: Its homing recipe; ``None``: the Home button reports that there is none.
        on_error: Hears of every refused command and failed procedure: (axis name, text).
        sim_time: Simulated time [s] (dwell of the reversing sequence, step test recording).
        on_step: Hears that a step test starts (called in the simulation thread).
    """

    def __init__(
        self,
        axis: mcl.Axis,
        requests: AxisRequests,
        recipe: Recipe | None,
        on_error: ErrorSink | None = None,
        *,
        sim_time: Clock,
        on_step: StepListener | None = None,
    ) -> None:
        self.axis = axis
        self.requests = requests
        self.power = mcl.MC_Power()
        self.reset = mcl.MC_Reset()
        self.recipe = HomeAxis(axis, recipe) if recipe is not None else None
        self.index_pulse = mcl.MC_StepRefPulse(Axis=axis)
        self.set_position = mcl.MC_StepDirect(Axis=axis)
        self.home: HomeAxis | mcl.MC_StepRefPulse | mcl.MC_StepDirect | None = None
        """The homing procedure running or last run (None: none yet)."""
        self.jog = mcl.GT_Jog()
        self.stop = mcl.MC_Stop()
        self.move_absolute = mcl.MC_MoveAbsolute()
        self.move_relative = mcl.MC_MoveRelative()
        self.set_constant = mcl.GT_SetConstant()
        self._on_error = on_error
        self.moving: mcl.MC_MoveAbsolute | mcl.MC_MoveRelative | None = None
        """The move block the operator last started (None: no move of the operator)."""
        self.group_stop = False
        """Stop was pressed on a group member: the program releases its group."""
        self.last_error = ""
        """The last refused command, e.g. ``"Jog+: error 1000 (...)"`` (empty: none)."""
        self.status = mcl.GT_AxStatusString()
        self.error_text = mcl.GT_AxErrStringEN()
        self.power_request: bool | None = None
        """Level passed to MC_Power's Enable; ``None`` while the operator has not pressed Power."""
        self.resetting = False
        self.homing = False
        self.stopping = False
        self.message = ""
        """Outcome of the last operator command, e.g. ``"Home: done"``."""
        self.commissioning = AxisCommissioning(axis, sim_time, self._note, on_step)
        """Reversing sequence and step test."""
        self.jog_slow = False
        """The slow jog speed was chosen in the last scan."""

    @property
    def commissioning_view(self) -> CommissioningView:
        """What the commissioning controls show now."""
        return self.commissioning.view(self.jog_slow)

    @property
    def jogging(self) -> int:
        """Direction of the jog request seen in the last scan: +1, −1 or 0."""
        return int(self.jog.JogPos) - int(self.jog.JogNeg) if self.jog.Enable else 0

    def release_power(self) -> None:
        """Hand the drive back: MC_Power is no longer called (called from the PLC thread)."""
        self.power_request = None

    def __call__(self) -> None:
        """One PLC scan: take the requests and call the function blocks."""
        axis = self.axis
        r = self.requests.take()
        if r.power is not None:
            self.power_request = r.power
        if r.toggle_power:
            self.power_request = axis.state == mcl.AxisState.Disabled
        if self.power_request is not None:
            self.power(Axis=axis, Enable=self.power_request)
            if self.power.Error:
                self._report("Power", self.power.ErrorID)
        if r.reset:
            self.resetting = True
        self.resetting = self._execute(self.reset, self.resetting, "Reset")
        if r.home is not None and not self.homing:
            self._start_homing(*r.home)
        self._scan_homing()
        taken_over = r.move is not None or r.jog_pos or r.jog_neg or r.home is not None or r.stop
        self.commissioning(r.commissioning, taken_over)
        self._scan_jog(r)
        self._scan_move(r.move)
        if r.constants is not None:
            values = {f: getattr(r.constants, f) for f in mcl.GT_SetConstant.INPUTS}
            self.set_constant(Axis=axis, Execute=True, **values)
            self._report("Write constants", self.set_constant.ErrorID)
            self.set_constant(Axis=axis, Execute=False)
        if r.stop and axis.has_drive:
            if axis.group is not None:
                self.message = "Stop: the axis' group ramps down and is released"
                self.group_stop = True
            else:
                self.stopping = True
        self.stopping = self._execute(self.stop, self.stopping, "Stop")
        self.status(Axis=axis, Enable=True)
        self.error_text(Axis=axis, Enable=True)

    def _execute(self, block: mcl.MC_Reset | mcl.MC_Stop, running: bool, command: str) -> bool:
        """Call a command block with ``Execute = running`` (once more after it ran, to drop
        Execute); whether it still runs (its end is reported)."""
        if running or block.Execute:
            block(Axis=self.axis, Execute=running)
            if running and (block.Done or block.Error):
                self._report(command, block.ErrorID)
                return False
        return running

    def _scan_homing(self) -> None:
        """Call the running homing procedure; report how it ended."""
        home = self.home
        if home is None or not self.homing:
            return
        home(Execute=True)
        if not home.Busy:
            self.homing = False
            if home.Done:
                self.message = "Home: done"
            elif home.Error:
                self._report("Home", home.ErrorID)
            else:
                self.message = "Home: aborted"
            home(Execute=False)

    def _scan_jog(self, r: Requests) -> None:
        """GT_Jog while a jog is requested (and once more when it ends)."""
        jog_pos, jog_neg = r.jog_pos, r.jog_neg
        if jog_pos or jog_neg or self.jog.Enable:
            velocity = r.jog_velocity or self._default_jog_velocity()
            self.jog_slow = r.jog_slow
            if r.jog_slow:
                velocity = max(SLOW_JOG_FRACTION * velocity, self._slowest_velocity())
            self.jog(
                Axis=self.axis,
                Enable=jog_pos or jog_neg,
                JogPos=jog_pos,
                JogNeg=jog_neg,
                JogVelo=velocity,
            )
            if self.jog.Error:
                self._report("Jog+" if jog_pos else "Jog−", self.jog.ErrorID)

    def _scan_move(self, move: Move | None) -> None:
        """Start a requested move (a fresh rising edge), or call the running one."""
        axis = self.axis
        if move is not None:
            block = self.move_absolute if move.kind == "absolute" else self.move_relative
            if self.moving is not None:
                self.moving(Axis=axis, Execute=False)  # a fresh rising edge for the new move
            target = {"Position" if move.kind == "absolute" else "Distance": move.target}
            block(
                Axis=axis,
                Execute=True,
                Velocity=move.velocity,
                Acceleration=move.acceleration,
                Deceleration=move.acceleration,
                **target,
            )
            self.moving = block
            self._check_move(block)
        elif self.moving is not None:
            self.moving(Axis=axis, Execute=True)
            self._check_move(self.moving)

    def _note(self, command: str, text: str, error_id: int) -> None:
        """What became of a commissioning command (:data:`~plc.commissioning.axis.Note`)."""
        if error_id:
            self._report(command, error_id)
        elif text.startswith("refused"):
            self._refuse(command, text.removeprefix("refused: "))
        else:
            self.message = f"{command}: {text}"

    def _refuse(self, command: str, why: str) -> None:
        """A command the operator program itself refuses (reported like a block's refusal)."""
        self.message = self.last_error = f"{command}: refused: {why}"
        if self._on_error is not None:
            self._on_error(self.axis.name, self.message)

    def _default_jog_velocity(self) -> float:
        return DEFAULT_JOG_FRACTION * self._vmax()

    def _slowest_velocity(self) -> float:
        """The library's slowest motion [u/s] (with a margin for rounding)."""
        return MIN_VELOCITY_FRACTION * self._vmax() * (1.0 + 1e-9)

    def _vmax(self) -> float:
        constants = self.axis.constants
        return constants.Vmax if constants is not None else 0.0

    def _start_homing(self, procedure: str, position: float) -> None:
        """Set up the chosen homing procedure (called by the scan that takes the press)."""
        if procedure == "recipe":
            if self.recipe is None:
                self.message = "Home: no homing recipe for this axis"
                return
            self.home = self.recipe
        elif procedure == "set position (no motion)":
            self.set_position.SetPosition = position
            self.home = self.set_position
        else:
            pulse = self.index_pulse
            pulse.Direction = (
                mcl.MC_Direction.MC_Positive
                if procedure.endswith("+")
                else mcl.MC_Direction.MC_Negative
            )
            recipe = self.recipe.recipe if self.recipe is not None else None
            pulse.Velocity = (
                recipe.index_velocity
                if isinstance(recipe, HomingRecipe)
                else INDEX_FRACTION * self._vmax()
            )
            pulse.SetPosition = position
            self.home = pulse
        self.homing = True

    def _check_move(self, block: mcl.MC_MoveAbsolute | mcl.MC_MoveRelative) -> None:
        """Report a move that ended (Done, Error or aborted) and release its Execute."""
        if block.Busy:
            return
        name = "Move to" if block is self.move_absolute else "Move by"
        if block.Error:
            self._report(name, block.ErrorID)
        elif block.Done:
            self.message = f"{name}: done"
        else:
            self.message = f"{name}: aborted"
        block(Axis=self.axis, Execute=False)
        self.moving = None

    def _report(self, command: str, error_id: int) -> None:
        if error_id:
            self.message = f"{command}: error {error_id} ({mcl.error_text(error_id)})"
            self.last_error = self.message
            if self._on_error is not None:
                self._on_error(self.axis.name, self.message)
        else:
            self.message = f"{command}: done"


class GroupRelease:
    """Takes one axes group apart (one PLC scan per call): MC_GroupReset if it is in
    GroupErrorStop, MC_GroupDisable (its motion ramps to standstill), MC_UngroupAllAxes.

    Args:
        group: The group.
        on_error: Hears of a refusal: ("group <name>", text).
    """

    def __init__(self, group: mcl.AxesGroup, on_error: ErrorSink | None = None) -> None:
        self.group = group
        self.reset = mcl.MC_GroupReset(AxesGroup=group)
        self.disable = mcl.MC_GroupDisable(AxesGroup=group)
        self.ungroup = mcl.MC_UngroupAllAxes(AxesGroup=group)
        self._on_error = on_error
        self._steps: list[mcl.MC_GroupReset | mcl.MC_GroupDisable | mcl.MC_UngroupAllAxes] = []
        if group.state == mcl.GroupState.GroupErrorStop:
            self._steps.append(self.reset)
        self._steps += [self.disable, self.ungroup]
        self.done = False
        """The group is empty (or the release ended with an error)."""

    def __call__(self) -> None:
        """One scan: the current step until Done or Error, then the next."""
        if self.done:
            return
        block = self._steps[0]
        block(Execute=True)
        if block.Error:
            if self._on_error is not None:
                name = type(block).__name__
                self._on_error(
                    f"group {self.group.name}",
                    f"{name}: error {block.ErrorID} ({mcl.error_text(block.ErrorID)})",
                )
            block(Execute=False)
            self.done = True
        elif block.Done:
            block(Execute=False)
            self._steps.pop(0)
            self.done = not self._steps


class OperatorProgram:
    """The operator PLC program of a scene: one :class:`AxisOperator` per axis, and the release
    of axes groups.

    Args:
        axes: The scene's axes by name.
        recipes: Homing recipes by axis name (axes without one cannot be homed).
        clock: Monotonic wall clock [s] for the jog dead-man deadlines.
        on_error: Hears of every refused command: (axis or group, text).
        sim_time: Simulated time [s] of the scene.
        on_step: Hears that a step test starts (in the simulation thread).
    """

    def __init__(
        self,
        axes: Mapping[str, mcl.Axis],
        recipes: Mapping[str, Recipe],
        clock: Clock = time.monotonic,
        on_error: ErrorSink | None = None,
        *,
        sim_time: Clock,
        on_step: StepListener | None = None,
    ) -> None:
        self.requests = {name: AxisRequests(clock) for name in axes}
        """Request flags by axis name (the only thing the GUI writes)."""
        self.axes = {
            name: AxisOperator(
                axis,
                self.requests[name],
                recipes.get(name),
                on_error,
                sim_time=sim_time,
                on_step=on_step,
            )
            for name, axis in axes.items()
        }
        """Function blocks by axis name."""
        self._operators = list(self.axes.values())
        self._on_error = on_error
        self._release = threading.Event()
        self.releasing: list[GroupRelease] = []
        """Groups being taken apart."""

    def groups(self) -> list[mcl.AxesGroup]:
        """The axes groups the scene's axes belong to now."""
        found: list[mcl.AxesGroup] = []
        for operator in self._operators:
            group = operator.axis.group
            if isinstance(group, mcl.AxesGroup) and group not in found:
                found.append(group)
        return found

    def release_groups(self) -> None:
        """Take every axes group apart at the next scan (thread-safe)."""
        self._release.set()

    def stop_all(self) -> None:
        """STOP for every axis (called from the PLC thread between two scans): jogs released,
        groups taken apart (their motion ramps down), MC_Stop on every powered driven axis
        outside a group."""
        for name, requests in self.requests.items():
            requests.release_jog()
            if self.axes[name].axis.state != mcl.AxisState.Disabled:
                requests.stop()
        self._release.set()

    def __call__(self) -> None:
        """One PLC scan: group releases first, then every axis' operator blocks."""
        if self._release.is_set():
            self._release.clear()
            busy = {r.group for r in self.releasing}
            self.releasing += [
                GroupRelease(g, self._on_error) for g in self.groups() if g not in busy
            ]
        if self.releasing:
            for release in self.releasing:
                release()
            self.releasing = [r for r in self.releasing if not r.done]
        for operator in self._operators:
            operator()
            if operator.group_stop:
                operator.group_stop = False
                self._release.set()

    def release_power(self) -> None:
        """Hand every drive back to the other program (called from the PLC thread)."""
        for name, operator in self.axes.items():
            self.requests[name].release_power()
            operator.release_power()

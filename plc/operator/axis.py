"""The operator program of one axis: its function blocks and their sequencing, driven through one
vocabulary of commands by a front end — the viewer's buttons (:mod:`plc.operator.hmi`) or a
fieldbus master's command words (:mod:`plc.operator.bus`).

Each PLC scan the front end says in :class:`Orders` what it wants: MC_Power's Enable, the Execute
commands whose Execute is set (and those of them that start now, each with its parameters), the
jog levels, the digital outputs, servo constants to write and the commissioning presses.
:class:`AxisOperator` passes them to the library's blocks:

==============  ==================================================================================
power           ``MC_Power`` Enable (a level; None: the block is not called, so that another
                program keeps the drive in its hands)
reset           ``MC_Reset``
home_direct     ``MC_StepDirect`` (position: the axis is homed where it stands, without motion, as
                ``MC_SetPosition`` with Ref; a bus master's direct homing)
home            the homing procedure chosen (:meth:`AxisOperator.select_homing`): the machine's
                recipe (``plc.procedures.HomeAxis``; the default), ``MC_StepRefPulse`` on the
                next index pulse, ``MC_StepDirect`` (set the position without moving)
move_absolute   ``MC_MoveAbsolute`` (position, velocity, acceleration, deceleration, jerk,
                buffer_mode)
move_relative   ``MC_MoveRelative`` (distance, …)
move_additive   ``MC_MoveAdditive`` (distance, …)
move_velocity   ``MC_MoveVelocity`` (velocity: its sign is the direction, …)
gear_in         ``MC_GearIn`` (master: its number among the masters, ratio_numerator,
                ratio_denominator, acceleration, deceleration, jerk)
gear_in_pos     ``MC_GearInPos`` (… master/slave_sync_position, master_start_distance, velocity,
                zeroing)
gear_out        ``MC_GearOut``
force_control   ``MC_ForceControl`` (force, force_ramp, gain, …, velocity, acceleration)
halt, stop      ``MC_Halt``, ``MC_Stop`` (deceleration, jerk; 0: the block's default ramp)
jog             ``GT_Jog`` (JogPos / JogNeg levels, JogVelo)
outputs         ``MC_WriteDigitalOutput`` for every output that differs from its bit of the word
constants       ``GT_SetConstant`` (tuning)
commissioning   the reversing sequence, step test and override (:mod:`plc.commissioning.axis`)
==============  ==================================================================================

An Execute command's block is called while its Execute is set, in the scan it falls, and while it
is busy or shows an output; an idle one is not. Its parameters are passed when it starts (a block
samples its inputs on the rising edge); a command started again while its Execute is still set
first gets one call with Execute FALSE (a fresh rising edge). One scan calls MC_Power, reset and
homing, the commissioning functions, the jog, the moves, gearing and force control, the
constants, halt and stop (a stop in the same scan has the last word), and the outputs.

How every command whose Execute is set ended — Done, Error with its ErrorID, or aborted — is
reported once, from here for both front ends: in :attr:`AxisOperator.message`
(``"Move to: done"``), an error also in :attr:`AxisOperator.last_error` and to ``on_error``, and
whether the command was refused (its block failed in the scan it started) or aborted (an error
stopped it on its way) in :attr:`AxisOperator.last_error_kind`; a target beyond a software limit
is reported with the limit it lies beyond. A Reset that is done clears the last error.
"""

from __future__ import annotations

__all__ = [
    "ABORTED",
    "COMMANDS",
    "HOMING_PROCEDURES",
    "INDEX_FRACTION",
    "LABELS",
    "MOVES",
    "REFUSED",
    "AxisOperator",
    "Orders",
    "no_parameters",
    "showing",
    "whole",
]

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import mcl
from mcl.motion import motion_refusal
from plc.commissioning.axis import AxisCommissioning, CommissioningRequests
from plc.commissioning.step_test import StepListener
from plc.procedures import HomeAxis, HomingRecipe, Recipe

Clock = Callable[[], float]
"""A clock [s] (simulated time, or a monotonic wall clock)."""

ErrorSink = Callable[[str, str], None]
"""Hears of a refused command: (axis name, text)."""

Parameters = Callable[[str], float]
"""A command's parameter by name (``position``, ``velocity``, ``buffer_mode``, …); 0.0 for one
not given."""

Block = Any
"""An Execute command's block (MC_MoveAbsolute, HomeAxis, …): Done, Busy, Error, ErrorID; maybe
Active, CommandAborted."""

LABELS = {
    "reset": "Reset",
    "home": "Home",
    "home_direct": "Home direct",
    "move_absolute": "Move to",
    "move_relative": "Move by",
    "move_additive": "Move additive",
    "move_velocity": "Move velocity",
    "gear_in": "Gear in",
    "gear_in_pos": "Gear in at position",
    "gear_out": "Gear out",
    "force_control": "Force control",
    "halt": "Halt",
    "stop": "Stop",
}
"""The Execute commands (each the name of its block's attribute) and what a message calls them."""

COMMANDS = tuple(LABELS)
"""The Execute commands."""

MOVES = frozenset({"move_absolute", "move_relative", "move_additive", "move_velocity"})
"""The moves (a new one aborts the last)."""

REFUSED = "Refused"
"""A command whose block failed in the scan it started (its inputs, the axis' state)."""

ABORTED = "Aborted"
"""A command an error stopped on its way (a limit switch, the following error)."""

HOMING_PROCEDURES = ("recipe", "index pulse +", "index pulse −", "set position (no motion)")
"""The homing procedures of ``home``: the machine's recipe (REF and index, or to a block; only
where the definition gives one), MC_StepRefPulse in the positive or negative direction,
MC_StepDirect."""

INDEX_FRACTION = 0.02
"""Index-search velocity of the index-pulse procedures without a recipe, as a fraction of Vmax."""

_FIRST = ("reset", "home", "home_direct")
_MOTION = (
    "move_absolute",
    "move_relative",
    "move_additive",
    "move_velocity",
    "gear_in",
    "gear_in_pos",
    "gear_out",
    "force_control",
)
_RAMP_DOWN = ("halt", "stop")
_GEARING = frozenset({"gear_in", "gear_in_pos", "gear_out"})


def no_parameters(name: str) -> float:
    """The parameters of a command given none: every one 0.0."""
    return 0.0


@dataclass(frozen=True, slots=True)
class Orders:
    """What a front end tells an axis in one PLC scan.

    Attributes:
        power: MC_Power's Enable; None: MC_Power is not called.
        execute: the Execute commands (:data:`COMMANDS`) whose Execute is set.
        start: of those, the ones that start now, each with its parameters.
        jog_pos: GT_Jog's JogPos (a level).
        jog_neg: GT_Jog's JogNeg.
        jog_velocity: GT_Jog's JogVelo [u/s].
        outputs: the digital outputs wanted, bit k = output k; None: left alone.
        constants: servo constants to write with GT_SetConstant; None: none.
        commissioning: the presses of the commissioning controls; None: the front end has
            none (the commissioning functions are not called).
        taken_over: the operator takes the axis over in this scan (ends a running reversing
            sequence or step test).
    """

    power: bool | None = None
    execute: frozenset[str] = frozenset()
    start: Mapping[str, Parameters] = field(default_factory=dict)
    jog_pos: bool = False
    jog_neg: bool = False
    jog_velocity: float = 0.0
    outputs: int | None = None
    constants: mcl.ServoConstants | None = None
    commissioning: CommissioningRequests | None = None
    taken_over: bool = False


def whole(value: float) -> int:
    """An INT input from a parameter (0 for a value that is not finite or beyond 32 bits)."""
    return round(value) if math.isfinite(value) and abs(value) < 2**31 else 0


class AxisOperator:
    """The function blocks of one axis and their sequencing (one PLC scan per call with the
    front end's :class:`Orders`).

    Args:
        axis: The axis.
        recipe: Its homing recipe; ``None``: the recipe procedure reports that there is none.
        masters: The axes whose number the ``master`` parameter of gearing gives (a number
            outside them gives the blocks the axis itself as master: EParam).
        on_error: Hears of every refused command and failed procedure: (axis name, text).
        sim_time: Simulated time [s] (dwell of the reversing sequence, step test recording).
        on_step: Hears that a step test starts (called in the simulation thread).
    """

    def __init__(
        self,
        axis: mcl.Axis,
        recipe: Recipe | None,
        masters: Sequence[mcl.Axis] = (),
        on_error: ErrorSink | None = None,
        *,
        sim_time: Clock,
        on_step: StepListener | None = None,
    ) -> None:
        self.axis = axis
        self.masters = list(masters)
        self.power = mcl.MC_Power()
        self.reset = mcl.MC_Reset()
        self.recipe = HomeAxis(axis, recipe) if recipe is not None else None
        self.index_pulse = mcl.MC_StepRefPulse(Axis=axis)
        self.set_position = mcl.MC_StepDirect(Axis=axis)
        self.home: HomeAxis | mcl.MC_StepRefPulse | mcl.MC_StepDirect | None = self.recipe
        """The homing procedure ``home`` runs (None: none)."""
        self.home_direct = mcl.MC_StepDirect()
        self.move_absolute = mcl.MC_MoveAbsolute()
        self.move_relative = mcl.MC_MoveRelative()
        self.move_additive = mcl.MC_MoveAdditive()
        self.move_velocity = mcl.MC_MoveVelocity()
        self.gear_in = mcl.MC_GearIn()
        self.gear_in_pos = mcl.MC_GearInPos()
        self.gear_out = mcl.MC_GearOut()
        self.force_control = mcl.MC_ForceControl()
        self.halt = mcl.MC_Halt()
        self.stop = mcl.MC_Stop()
        self.jog = mcl.GT_Jog()
        self.outputs = [mcl.MC_WriteDigitalOutput() for _ in axis.io.outputs]
        self.set_constant = mcl.GT_SetConstant()
        self.commissioning = AxisCommissioning(axis, sim_time, self.note, on_step)
        """Reversing sequence, step test and override."""
        self.message = ""
        """Outcome of the last command, e.g. ``"Home: done"``."""
        self.last_error = ""
        """The last command that failed, e.g. ``"Jog+: error 1000 (...)"`` (empty: none; a
        Reset that is done clears it)."""
        self.last_error_kind = REFUSED
        """:data:`REFUSED` or :data:`ABORTED`: what became of the command of :attr:`last_error`."""
        self.group_stop = False
        """The front end asks the program to take the axis' group apart (a Stop on a member)."""
        self.finished: set[str] = set()
        """The Execute commands whose end was reported since they last started."""
        self._levels: frozenset[str] = frozenset()
        self._on_error = on_error

    def block(self, command: str) -> Block | None:
        """The block of Execute command ``command`` (``home``: the chosen procedure, None for
        none)."""
        return getattr(self, command)

    def executing(self, command: str) -> bool:
        """Whether ``command``'s Execute was set in the last scan and it has not ended."""
        return command in self._levels and command not in self.finished

    @property
    def homing(self) -> bool:
        """A homing procedure runs."""
        return self.executing("home")

    @property
    def stopping(self) -> bool:
        """MC_Stop's Execute is set and it has not ended."""
        return self.executing("stop")

    @property
    def jogging(self) -> int:
        """Direction of the jog in the last scan: +1, −1 or 0."""
        return int(self.jog.JogPos) - int(self.jog.JogNeg) if self.jog.Enable else 0

    def select_homing(self, procedure: str, position: float = 0.0) -> bool:
        """Choose the procedure the next start of ``home`` runs (one of
        :data:`HOMING_PROCEDURES`); ``position`` [u] is the coordinate an index-pulse procedure
        or set position gives the axis. Whether there is one (the recipe procedure of an axis
        without a recipe: no, and :attr:`message` says so). A procedure whose Execute is still
        set is released first."""
        chosen: HomeAxis | mcl.MC_StepRefPulse | mcl.MC_StepDirect
        if procedure == "recipe":
            if self.recipe is None:
                self.message = "Home: no homing recipe for this axis"
                return False
            chosen = self.recipe
        elif procedure == HOMING_PROCEDURES[3]:
            self.set_position.SetPosition = position
            chosen = self.set_position
        else:
            pulse = chosen = self.index_pulse
            positive = procedure.endswith("+")
            pulse.Direction = (
                mcl.MC_Direction.MC_Positive if positive else mcl.MC_Direction.MC_Negative
            )
            recipe = self.recipe.recipe if self.recipe is not None else None
            pulse.Velocity = (
                recipe.index_velocity
                if isinstance(recipe, HomingRecipe)
                else INDEX_FRACTION * self._vmax()
            )
            pulse.SetPosition = position
        if self.home is not None and chosen is not self.home and "home" in self._levels:
            self.home(Execute=False)
            self._levels -= {"home"}
        self.home = chosen
        return True

    def __call__(self, orders: Orders) -> None:
        """One PLC scan: the orders to the blocks, in the order of the module docstring."""
        axis = self.axis
        if orders.power is not None:
            refused = self.power.Error
            self.power(Axis=axis, Enable=orders.power)
            if self.power.Error and not refused:
                self._report("Power", self.power.ErrorID)
        self._execute(_FIRST, orders)
        if orders.commissioning is not None:
            self.commissioning(orders.commissioning, orders.taken_over)
        self._jog(orders)
        self._execute(_MOTION, orders)
        if orders.constants is not None:
            self._write_constants(orders.constants)
        self._execute(_RAMP_DOWN, orders)
        if orders.outputs is not None:
            self._write_outputs(orders.outputs)
        self._levels = orders.execute

    def _execute(self, commands: tuple[str, ...], orders: Orders) -> None:
        """Call the blocks of ``commands`` as the module docstring says; report the ends."""
        levels = self._levels
        for name in commands:
            block = getattr(self, name)
            if block is None:
                continue
            execute = name in orders.execute
            params = orders.start.get(name)
            if params is not None:
                self.finished.discard(name)
                if name in levels:
                    self._call(name, False, None)  # a fresh rising edge
            if execute or name in levels or showing(block):
                self._call(name, execute, params)
                if execute and not block.Busy and name not in self.finished:
                    self._ended(name, block, started=params is not None)

    def _call(self, name: str, execute: bool, params: Parameters | None) -> None:
        """Call command ``name``'s block with ``execute``; its inputs from ``params`` (at the
        start; None: the block keeps those it sampled)."""
        block = getattr(self, name)
        if name == "home":
            block(Execute=execute)
            return
        inputs = self._inputs(name, params) if params is not None else {}
        if name in _GEARING:
            block(Slave=self.axis, Execute=execute, **inputs)
        else:
            block(Axis=self.axis, Execute=execute, **inputs)

    def _inputs(self, name: str, p: Parameters) -> dict[str, Any]:
        """The inputs of command ``name``'s block from its parameters ``p`` (0 for an INT
        that is not finite; the master by its number; a velocity move's direction from the
        velocity's sign)."""
        inputs: dict[str, Any] = {
            key: whole(p(parameter)) if integer else p(parameter)
            for key, parameter, integer in _INPUTS[name]
        }
        if "Master" in inputs:
            inputs["Master"] = self.master(inputs["Master"])
        if name == "move_velocity":
            velocity = inputs["Velocity"]
            inputs["Velocity"] = abs(velocity)
            negative = velocity < 0
            positive = mcl.MC_Direction.MC_Positive
            inputs["Direction"] = mcl.MC_Direction.MC_Negative if negative else positive
        return inputs

    def _jog(self, orders: Orders) -> None:
        """GT_Jog while a jog level is set (and once more when it drops)."""
        jog_pos, jog_neg = orders.jog_pos, orders.jog_neg
        if jog_pos or jog_neg or self.jog.Enable:
            refused = self.jog.Error
            jogging = bool(self.jog.Enable and not refused)
            self.jog(
                Axis=self.axis,
                Enable=jog_pos or jog_neg,
                JogPos=jog_pos,
                JogNeg=jog_neg,
                JogVelo=orders.jog_velocity,
            )
            if self.jog.Error and not refused:
                jog = self.jog
                ramp = (jog.JogVelo, jog.JogAcc, jog.JogDec, jog.JogJerk)
                eparam = jog.ErrorID == mcl.ErrorID.EParam
                detail = motion_refusal(self.axis, *ramp) if eparam else ""
                label = "Jog+" if jog_pos else "Jog−"
                self._report(label, jog.ErrorID, aborted=jogging, detail=detail)

    def _write_constants(self, constants: mcl.ServoConstants) -> None:
        """GT_SetConstant with ``constants`` (it checks them), Execute dropped at once."""
        values = {f: getattr(constants, f) for f in mcl.GT_SetConstant.INPUTS}
        self.set_constant(Axis=self.axis, Execute=True, **values)
        self._report("Write constants", self.set_constant.ErrorID)
        self.set_constant(Axis=self.axis, Execute=False)

    def _write_outputs(self, wanted: int) -> None:
        """MC_WriteDigitalOutput for every output whose bit differs from the output."""
        for k, block in enumerate(self.outputs):
            value = bool(wanted >> k & 1)
            block(
                Axis=self.axis,
                Execute=value != self.axis.io.outputs[k],
                OutputNumber=k,
                Value=value,
            )

    def master(self, number: float) -> mcl.Axis:
        """The master of gearing number ``number`` (outside the masters: the axis itself)."""
        k = whole(number)
        return self.masters[k] if 0 <= k < len(self.masters) else self.axis

    def _vmax(self) -> float:
        constants = self.axis.constants
        return constants.Vmax if constants is not None else 0.0

    def _ended(self, name: str, block: Block, started: bool = False) -> None:
        """Report how command ``name`` ended (once per start; ``started``: in the scan it
        started, so an error refused it)."""
        self.finished.add(name)
        label = LABELS[name]
        if block.Error:
            detail = self._why(name, block)
            self._report(label, block.ErrorID, aborted=not started, detail=detail)
        elif block.Done:
            self.message = f"{label}: done"
            if name == "reset":
                self.last_error = ""
        else:
            self.message = f"{label}: aborted"

    def _why(self, name: str, block: Block) -> str:
        """Why command ``name``'s block failed, where the ErrorID alone does not say: the
        software limit a target lies beyond (Ecil), the ramp input a move refuses (EParam)."""
        if block.ErrorID == mcl.ErrorID.Ecil:
            return self._beyond_limit(name, block)
        if block.ErrorID == mcl.ErrorID.EParam and name in MOVES:
            ramp = (block.Velocity, block.Acceleration, block.Deceleration, block.Jerk)
            return motion_refusal(self.axis, *ramp)
        return ""

    def _beyond_limit(self, name: str, block: Block) -> str:
        """Which software limit a move's target lies beyond, and where (empty: not known)."""
        axis = self.axis
        if name == "move_absolute":
            target = float(block.Position)
        elif name == "move_relative":
            target = axis.sp_pos + float(block.Distance)
        else:
            return ""
        low, high = axis.sw_limit_range()
        unit = axis.config.unit
        if target > high:
            return f"target {target:.3f} {unit} beyond the positive SW limit {high:.3f} {unit}"
        if target < low:
            return f"target {target:.3f} {unit} beyond the negative SW limit {low:.3f} {unit}"
        return ""

    def note(self, command: str, text: str, error_id: int = 0) -> None:
        """What became of a command that is no block's (:data:`~plc.commissioning.axis.Note`):
        an ErrorID is reported as a block's, a text ``"refused: …"`` as a refusal, any other
        text is the message ``"<command>: <text>"``."""
        if error_id:
            self._report(command, error_id)
        elif text.startswith("refused"):
            self._refuse(command, text.removeprefix("refused: "))
        else:
            self.message = f"{command}: {text}"

    def _refuse(self, command: str, why: str) -> None:
        """A command the program itself refuses (reported like a block's refusal)."""
        self.message = self.last_error = f"{command}: refused: {why}"
        self.last_error_kind = REFUSED
        if self._on_error is not None:
            self._on_error(self.axis.name, self.message)

    def _report(self, command: str, error_id: int, aborted: bool = False, detail: str = "") -> None:
        """Report ``command``'s ``error_id`` (0: done): refused, or ``aborted`` on its way;
        ``detail`` says more (e.g. the software limit)."""
        if error_id:
            text = mcl.error_text(error_id) + (f": {detail}" if detail else "")
            self.message = f"{command}: error {error_id} ({text})"
            self.last_error = self.message
            self.last_error_kind = ABORTED if aborted else REFUSED
            if self._on_error is not None:
                self._on_error(self.axis.name, self.message)
        else:
            self.message = f"{command}: done"


def showing(block: Block) -> bool:
    """Whether a block is busy or shows an output (so it must see the next scan)."""
    return bool(block.Busy or block.Done or block.Error or getattr(block, "CommandAborted", False))


def _snake(name: str) -> str:
    """The parameter of a block input: ``BufferMode`` → ``buffer_mode``."""
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


_RAMP = ("Velocity", "Acceleration", "Deceleration", "Jerk", "BufferMode")
_GEAR = ("Master", "RatioNumerator", "RatioDenominator", "Acceleration", "Deceleration", "Jerk")
_INTEGERS = frozenset(
    {"BufferMode", "RatioNumerator", "RatioDenominator", "Zeroing", "InputNumber", "InputNumber2"}
)
_SYNC = ("MasterSyncPosition", "SlaveSyncPosition", "MasterStartDistance", "Velocity", "Zeroing")
_FORCE = ("Force", "ForceRamp", "Velocity", "Acceleration", "Gain", "InputNumber", "Scale")
_FORCE2 = ("InputNumber2", "Scale2", "Offset", "Tolerance", "BufferMode")
_INPUTS = {
    command: tuple((name, _snake(name), name in _INTEGERS) for name in inputs)
    for command, inputs in {
        "reset": (),
        "move_absolute": ("Position", *_RAMP),
        "move_relative": ("Distance", *_RAMP),
        "move_additive": ("Distance", *_RAMP),
        "move_velocity": _RAMP,
        "gear_in": _GEAR,
        "gear_in_pos": (*_GEAR, *_SYNC),
        "gear_out": (),
        "force_control": (*_FORCE, *_FORCE2),
        "halt": ("Deceleration", "Jerk"),
        "stop": ("Deceleration", "Jerk"),
    }.items()
}
_INPUTS["home_direct"] = (("SetPosition", "position", False),)
"""Each Execute command's block inputs from its parameters: (input, parameter, an INT) — the
parameter is the input's name in snake case (``buffer_mode``; home_direct's SetPosition:
``position``); home has Execute only."""

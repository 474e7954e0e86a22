"""Function-block base semantics shared by every block (docs/reference.md, Calling a function
block; MotionControlLib Tab. 2.3).

A function block is called once per PLC scan with keyword inputs: ``fb(Axis=X, Execute=True,
Position=10.0)``. Inputs that are not passed keep the value of the previous call; an unknown input
name is a programming mistake and raises ``TypeError`` naming the valid ones. Problems of a
running block are reported through ``Error``/``ErrorID`` only, never by raising.

Inputs are declared, typed attributes: each class lists the inputs it adds in ``INPUTS`` and
declares them with their initial values, so the classes compile to native classes. Constant
inputs can be bound once, at construction (``MC_MoveAbsolute(Axis=X, Velocity=200.0)``) or by
attribute assignment, so that a scan passes only what changes (``move(Execute=start)``).

Keyword inputs are converted to the declared type: a REAL input takes any real number (anything
else, a huge integer included, becomes NaN), an INT input takes an integer or an integral real
(anything else becomes :data:`INVALID_INT`), a BOOL input takes anything with a truth value. An
invalid value then gives ``EParam`` on the rising edge, and the axis is left alone.
"""

from __future__ import annotations

__all__ = [
    "INVALID_INT",
    "EnableFB",
    "ExecuteFB",
    "FunctionBlock",
    "InputSpec",
    "MotionFB",
    "Ticket",
    "TicketOwner",
    "boolean",
    "input_names",
    "input_spec",
    "integer",
    "non_negative",
    "number",
    "positive",
]

import math
from typing import Any, ClassVar, Final, Protocol

from mypy_extensions import mypyc_attr

from mcl.axis import Axis as AxisRef
from mcl.command import Command, Status
from mcl.enums import MC_BufferMode
from mcl.errors import ErrorID
from mcl.group import AxesGroup as GroupRef

INVALID_INT: Final = -(2**63)
"""What an INT input holds after a value that is not an integer (→ EParam)."""


def number(value: object) -> float:
    """A REAL input as float; anything that is not a real number becomes NaN (→ EParam)."""
    if type(value) is float:
        return value
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return math.nan


def integer(value: object) -> int:
    """An INT input as int; anything but an integer or an integral real becomes
    :data:`INVALID_INT` (→ EParam)."""
    if isinstance(value, int):
        return int(value)
    real = number(value)
    if math.isfinite(real) and real == math.floor(real):
        return int(real)
    return INVALID_INT


def boolean(value: object) -> bool:
    """A BOOL input; a value without a truth value counts as FALSE."""
    if type(value) is bool:
        return value
    try:
        return bool(value)
    except Exception:  # e.g. an array: ambiguous
        return False


def positive(value: float) -> bool:
    """Finite and > 0."""
    return math.isfinite(value) and value > 0.0


def non_negative(value: float) -> bool:
    """Finite and >= 0."""
    return math.isfinite(value) and value >= 0.0


_REAL: Final = 0
_INT: Final = 1
_BOOL: Final = 2
_ANY: Final = 3
_AXIS: Final = 4
_GROUP: Final = 5
_TEXT: Final = 6
_MASTER_INPUT: Final = 7


class InputSpec:
    """The inputs of one FB class: name → kind, found once per class."""

    def __init__(self, kinds: dict[str, int], refs: tuple[str, ...]) -> None:
        self.kinds = kinds
        self.refs = refs
        self.names = ", ".join(kinds)


_SPECS: dict[type, InputSpec] = {}


def _kind(name: str, default: object) -> int:
    if name in ("Axis", "Master", "Slave"):
        return _AXIS
    if name == "AxesGroup":
        return _GROUP
    if name in ("ConveyorBelt", "RotaryTable"):
        return _MASTER_INPUT
    if isinstance(default, bool):
        return _BOOL
    if isinstance(default, int):
        return _INT
    if isinstance(default, float):
        return _REAL
    if isinstance(default, str):
        return _TEXT
    return _ANY


def input_spec(fb: FunctionBlock) -> InputSpec:
    """The inputs of ``fb``'s class: its in-outs (``REFS``), then every ``INPUTS`` along the
    class hierarchy; their kinds come from the initial values of a fresh instance."""
    cls = type(fb)
    spec = _SPECS.get(cls)
    if spec is None:
        names: list[str] = list(cls.REFS)
        for klass in reversed(cls.__mro__):
            for name in klass.__dict__.get("INPUTS", ()):
                if name not in names:
                    names.append(name)
        spec = _SPECS[cls] = InputSpec(
            {name: _kind(name, getattr(fb, name)) for name in names}, cls.REFS
        )
    return spec


def input_names(cls: type[FunctionBlock]) -> tuple[str, ...]:
    """The in-outs and inputs of an FB class, in order."""
    return tuple(input_spec(cls()).kinds)


@mypyc_attr(allow_interpreted_subclasses=True)
class FunctionBlock:
    """Base: declared inputs with initial values, kept between calls; the in-out references.

    Args:
        **inputs: inputs bound at construction (as if passed in a first call).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ()
    """The inputs this class adds (declared as annotated attributes with initial values)."""
    REFS: ClassVar[tuple[str, ...]] = ("Axis",)
    """The in-out references (``Axis``; ``AxesGroup``; ``Master``/``Slave`` for gearing)."""
    OWNER: ClassVar[str] = "Axis"
    """The in-out whose axis runs the block's command (``Slave`` for gearing)."""

    Axis: AxisRef | None = None
    AxesGroup: GroupRef | None = None

    def __init__(self, **inputs: Any) -> None:
        self._spec = input_spec(self)
        self._owner_is_axis = self.OWNER == "Axis"
        """The command runs on ``Axis`` (a native read, not one by name, in every scan)."""
        self._connected = False
        if inputs:
            self._take_inputs(inputs)

    def _take_inputs(self, inputs: dict[str, Any]) -> None:
        """Store keyword inputs, converted to their declared types."""
        kinds = self._spec.kinds
        for name, value in inputs.items():
            kind = kinds.get(name, -1)
            if kind == _BOOL:
                value = boolean(value)
            elif kind == _REAL:
                value = number(value)
            elif kind == _INT:
                value = integer(value)
            elif kind == _TEXT:
                value = value if isinstance(value, str) else ""  # not a text: none
            elif kind == _MASTER_INPUT:  # an axis given as an input: not an axis, none
                value = value if isinstance(value, AxisRef) else None
            elif kind in (_AXIS, _GROUP):
                if value is None:
                    continue  # an open in-out keeps its previous reference
                expected: type = AxisRef if kind == _AXIS else GroupRef
                if not isinstance(value, expected):
                    raise TypeError(
                        f"{type(self).__name__}.{name} must be an mcl.{expected.__name__}, "
                        f"got {type(value).__name__}"
                    )
            elif kind != _ANY:
                raise TypeError(
                    f"{type(self).__name__} has no input {name!r}; inputs: {self._spec.names}"
                )
            setattr(self, name, value)
        if not self._connected:
            self._connected = all(getattr(self, ref) is not None for ref in self._spec.refs)

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan of the block (declared here: the compiled classes need it at the root)."""
        raise NotImplementedError

    def _scan(self, inputs: dict[str, Any]) -> None:
        """Start of a scan: take the keyword inputs, check the in-outs are connected."""
        if inputs:
            self._take_inputs(inputs)
        if not self._connected:
            self._inputs_taken()

    def _inputs_taken(self) -> None:
        """A scan may run: every in-out is connected (else a programming error)."""
        if not self._connected:
            self._connected = all(getattr(self, ref) is not None for ref in self._spec.refs)
            if not self._connected:
                missing = [ref for ref in self._spec.refs if getattr(self, ref) is None]
                raise TypeError(
                    f"{type(self).__name__} needs {missing[0]}=<the in-out reference>; "
                    f"it was never connected"
                )

    @property
    def axis(self) -> AxisRef:
        """The axis that runs the block's command (its ``OWNER`` in-out)."""
        axis = self.Axis if self._owner_is_axis else getattr(self, self.OWNER)
        if axis is None:
            raise TypeError(f"{type(self).__name__} needs {self.OWNER}=<mcl.Axis>")
        assert isinstance(axis, AxisRef)
        return axis

    @property
    def group(self) -> GroupRef:
        """The connected axes group."""
        group = self.AxesGroup
        if group is None:
            raise TypeError(f"{type(self).__name__} needs AxesGroup=<mcl.AxesGroup>")
        return group


@mypyc_attr(allow_interpreted_subclasses=True)
class ExecuteFB(FunctionBlock):
    """Edge-triggered block: Execute, Done, Busy, Error, ErrorID (docs/reference.md, Outputs).

    Subclasses implement :meth:`_begin` (on the rising edge: validate the sampled inputs, start
    the work, return an error code or 0) and :meth:`_poll` (every call while busy: return the final
    status once reached, else None).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Execute",)
    Execute: bool = False

    def __init__(self, **inputs: Any) -> None:
        self.Done = False
        self.Busy = False
        self.Error = False
        self.ErrorID = 0
        self._prev_execute = False
        self._final: Status | None = None
        self._final_error = 0
        self._final_shown = False
        self._running = False
        self._quiet = True
        """Idle with every output FALSE: a scan with Execute FALSE changes nothing."""
        super().__init__(**inputs)

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan of the block (the inputs not passed keep their values; a keyword-only
        ``Execute`` with a default is not kept by a compiled class that interpreted classes may
        subclass, so Execute is one of the keyword inputs)."""
        if inputs:
            self._take_inputs(inputs)
        if not self._connected:
            self._inputs_taken()
        execute = self.Execute
        if execute or not self._quiet:  # quiet and Execute FALSE: the scan changes nothing
            if execute and not self._prev_execute:
                self._restart()
            self._prev_execute = execute
            if self._running:
                final = self._poll()
                if final is not None:
                    self._finish(final, self._error_of_poll())
            self._show(execute)
            self._quiet = not execute and not self._running and self._final is None
        self._scanned()

    def _scanned(self) -> None:
        """The end of every scan (a subclass passes a level input to its running command)."""

    def _restart(self) -> None:
        if self._running:
            self._withdraw()
        self._final, self._final_error, self._final_shown = None, 0, False
        self._running = True
        self._command_started()
        error = self._begin()
        if error:
            self._finish(Status.Error, error)

    def _finish(self, final: Status, error: int = 0) -> None:
        self._running = False
        self._final, self._final_error, self._final_shown = final, error, False

    def _show(self, execute: bool) -> None:
        """Drive the outputs; a final state stays while Execute is TRUE, else for one call."""
        final = self._final
        visible = final is not None and (execute or not self._final_shown)
        if final is not None:
            self._final_shown = True
            if not visible:
                self._final = None  # shown and reset by the falling edge: consumed
        self.Busy = self._running
        self.Done = visible and final == Status.Done
        self.Error = visible and final == Status.Error
        self.ErrorID = self._final_error if self.Error else 0
        self._show_more(visible, final)

    def _show_more(self, visible: bool, final: Status | None) -> None:
        """Extra outputs of a subclass (Active, CommandAborted, ...)."""

    def _command_started(self) -> None:
        """A rising edge of Execute starts a new job (reset per-job output memory here)."""

    def _begin(self) -> int:
        raise NotImplementedError

    def _poll(self) -> Status | None:
        return Status.Done

    def _error_of_poll(self) -> int:
        return 0

    def _withdraw(self) -> None:
        """A new edge arrived while busy: forget the previous job, which reports neither Done nor
        CommandAborted."""


class Ticket(Protocol):
    """What a motion block reads back from the job it handed over (a :class:`Command` for an
    axis, a path command for a group)."""

    status: Status
    error_id: int

    @property
    def busy(self) -> bool:
        """Queued or active."""
        ...


class TicketOwner(Protocol):
    """Who runs the tickets of a motion block: an :class:`Axis` or an axes group."""

    def cancel(self, ticket: Any) -> None:
        """Withdraw a ticket of a restarted block (no Done/Aborted will be reported)."""
        ...


@mypyc_attr(allow_interpreted_subclasses=True)
class MotionFB(ExecuteFB):
    """A motion block: hands a ticket to the axis (or group); Active, CommandAborted/Aborted.

    Subclasses implement :meth:`_command` (validate the sampled inputs and return the ticket or
    an error code); the owner reports back through the ticket's status. Group blocks override
    :meth:`_submit` and :meth:`_owner`.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("BufferMode",)
    BufferMode: int = MC_BufferMode.Aborting

    def __init__(self, **inputs: Any) -> None:
        self.Active = False
        self.CommandAborted = False
        self._cmd: Ticket | None = None
        self._reached_shown = False
        super().__init__(**inputs)

    @property
    def Aborted(self) -> bool:
        """Teco's name of ``CommandAborted``."""
        return self.CommandAborted

    def _begin(self) -> int:
        self._reached_shown = False
        try:
            mode = MC_BufferMode(self.BufferMode)
        except ValueError:
            return ErrorID.EParam
        result = self._command(mode)
        if isinstance(result, int):
            return result
        error = self._submit(result)
        if error:
            return error
        if result.status == Status.Error:
            return result.error_id
        self._cmd = result
        return 0

    def _command(self, mode: MC_BufferMode) -> Any:
        """The ticket for the sampled inputs, or an error code (int)."""
        raise NotImplementedError

    def _submit(self, ticket: Any) -> int:
        """Hand the ticket over; an error code when refused before it reaches the owner."""
        self.axis.submit(ticket)
        return 0

    def _owner(self) -> TicketOwner:
        return self.axis

    def _poll(self) -> Status | None:
        cmd = self._cmd
        if cmd is None or cmd.busy:
            return None
        return cmd.status

    def _error_of_poll(self) -> int:
        return self._cmd.error_id if self._cmd is not None else 0

    def _withdraw(self) -> None:
        if self._cmd is not None and self._cmd.status == Status.Queued:
            self._owner().cancel(self._cmd)
        self._cmd = None

    def _show_more(self, visible: bool, final: Status | None) -> None:
        cmd = self._cmd
        self.Active = self._running and cmd is not None and cmd.status == Status.Active
        self.CommandAborted = visible and final == Status.Aborted

    def _reached(self) -> bool:
        """The activating output of a never-ending command (InVelocity, InEndVelocity) as this
        scan shows it: TRUE while this instance's command is active and has reached its signal;
        reset by the falling edge of Execute, but shown for one scan when reached after it."""
        cmd = self._cmd
        reached = (
            self._running
            and isinstance(cmd, Command)
            and cmd.status == Status.Active
            and cmd.signal
        )
        show = reached and (bool(self.Execute) or not self._reached_shown)
        self._reached_shown = self._reached_shown or show
        return show


@mypyc_attr(allow_interpreted_subclasses=True)
class EnableFB(FunctionBlock):
    """Level-sensitive block: Enable, Valid, Error, ErrorID (docs/reference.md, Calling a
    function block).

    Subclasses implement :meth:`_evaluate`, called every scan while Enable is TRUE, which
    refreshes the outputs and returns an error code (0 = valid).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Enable",)
    Enable: bool = False

    def __init__(self, **inputs: Any) -> None:
        self.Valid = False
        self.Error = False
        self.ErrorID = 0
        super().__init__(**inputs)

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan of the block (the inputs not passed keep their values)."""
        if inputs:
            self._take_inputs(inputs)
        if not self._connected:
            self._inputs_taken()
        if self.Enable:
            error = self._evaluate()
            self.Valid = not error
            self.Error = bool(error)
            self.ErrorID = error
        else:
            self._disable()
            self.Valid = self.Error = False
            self.ErrorID = 0

    def _evaluate(self) -> int:
        raise NotImplementedError

    def _disable(self) -> None:
        """Enable is FALSE: reset the block's own outputs."""

"""Function-block base semantics shared by every block (MotionControlLib Tab. 2.3).

A function block is called once per PLC scan with keyword inputs: ``fb(Axis=X, Execute=True,
Position=10.0)``. Inputs that are not passed keep the value of the previous call; an
unknown input name is a programming mistake and raises ``TypeError`` naming the valid ones.
Problems of a running block are reported through ``Error``/``ErrorID`` only.
"""

from __future__ import annotations

import inspect
import math
from typing import Any, ClassVar, Protocol

from mcl.axis import Axis
from mcl.command import Status
from mcl.enums import MC_BufferMode
from mcl.errors import ErrorID


def number(value: Any) -> float:
    """An input as float; anything that is not a real number becomes NaN (→ EParam)."""
    if isinstance(value, bool):
        return float(value)
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def positive(value: float) -> bool:
    """Finite and > 0."""
    return math.isfinite(value) and value > 0.0


def non_negative(value: float) -> bool:
    """Finite and >= 0."""
    return math.isfinite(value) and value >= 0.0


class FunctionBlock:
    """Base: declared inputs with defaults, kept between calls; the in-out ``Axis``."""

    AXIS_INPUTS: ClassVar[tuple[str, ...]] = ("Axis",)
    """The in-out axis references (``Axis``; ``Master``/``Slave`` for gearing)."""
    OWNER: ClassVar[str] = "Axis"
    """The in-out whose axis runs the block's command (``Slave`` for gearing)."""

    _all_inputs: ClassVar[dict[str, Any]] = {}
    _names: ClassVar[frozenset[str]] = frozenset()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """Collect the inputs: public annotated class attributes with an initial value (not
        ClassVar), merged along the class hierarchy."""
        super().__init_subclass__(**kwargs)
        merged: dict[str, Any] = {}
        for klass in reversed(cls.__mro__):
            for name, hint in inspect.get_annotations(klass).items():
                if (
                    name in klass.__dict__
                    and not name.startswith("_")
                    and not str(hint).startswith("ClassVar")
                    and name not in cls.AXIS_INPUTS
                ):
                    merged[name] = klass.__dict__[name]
        cls._all_inputs = merged
        cls._names = frozenset(merged) | frozenset(cls.AXIS_INPUTS)

    def __init__(self) -> None:
        for name, value in self._all_inputs.items():
            setattr(self, name, value)
        for name in self.AXIS_INPUTS:
            setattr(self, name, None)

    def _take_inputs(self, inputs: dict[str, Any]) -> None:
        if not inputs.keys() <= self._names:
            unknown = sorted(inputs.keys() - self._names)
            valid = ", ".join([*self.AXIS_INPUTS, *self._all_inputs])
            raise TypeError(f"{type(self).__name__} has no input {unknown[0]!r}; inputs: {valid}")
        state = self.__dict__
        for name in self.AXIS_INPUTS:
            if name in inputs and inputs[name] is not state[name]:
                value = inputs[name]
                if value is None:  # an open in-out keeps its previous reference
                    inputs = {k: v for k, v in inputs.items() if k != name}
                else:
                    self._check_axis_type(name, value)
        state.update(inputs)
        for name in self.AXIS_INPUTS:
            if state[name] is None:
                raise TypeError(
                    f"{type(self).__name__} needs {name}=<the in-out reference>; "
                    f"it was never connected"
                )

    def _check_axis_type(self, name: str, value: Any) -> None:
        if not isinstance(value, Axis):
            raise TypeError(
                f"{type(self).__name__}.{name} must be an mcl.Axis, got {type(value).__name__}"
            )

    @property
    def axis(self) -> Axis:
        """The axis that runs the block's command (its ``OWNER`` in-out); a block called without
        ever getting one is a programming error."""
        axis = getattr(self, self.OWNER)
        if axis is None:
            raise TypeError(f"{type(self).__name__} needs {self.OWNER}=<mcl.Axis>")
        assert isinstance(axis, Axis)
        return axis


class ExecuteFB(FunctionBlock):
    """Edge-triggered block: Execute, Done, Busy, Error, ErrorID (docs/reference.md, Outputs).

    Subclasses implement :meth:`_begin` (on the rising edge: validate the sampled inputs, start
    the work, return an error code or 0) and :meth:`_poll` (every call while busy: return the final
    status once reached, else None).
    """

    Execute: bool = False
    DONE_NAME: ClassVar[str] = "Done"

    def __init__(self) -> None:
        super().__init__()
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

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan of the block."""
        self._take_inputs(inputs)
        execute = bool(self.Execute)
        if self._quiet and not execute:
            return
        if execute and not self._prev_execute:
            self._restart()
        self._prev_execute = execute
        if self._running:
            final = self._poll()
            if final is not None:
                self._finish(final, self._error_of_poll())
        self._show(execute)
        self._quiet = not execute and not self._running and self._final is None

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


class MotionFB(ExecuteFB):
    """A motion block: hands a ticket to the axis (or group); Active, CommandAborted/Aborted.

    Subclasses implement :meth:`_command` (validate the sampled inputs and return the ticket or
    an error code); the owner reports back through the ticket's status. Group blocks override
    :meth:`_submit` and :meth:`_owner`.
    """

    BufferMode: int = MC_BufferMode.Aborting

    def __init__(self) -> None:
        super().__init__()
        self.Active = False
        self.CommandAborted = False
        self._cmd: Ticket | None = None

    @property
    def Aborted(self) -> bool:
        """Teco's name of ``CommandAborted``."""
        return self.CommandAborted

    def _begin(self) -> int:
        try:
            mode = MC_BufferMode(int(self.BufferMode))
        except (TypeError, ValueError, OverflowError):
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


class EnableFB(FunctionBlock):
    """Level-sensitive block: Enable, Valid, Error, ErrorID (docs/reference.md, Calling a
    function block).

    Subclasses implement :meth:`_evaluate`, called every scan while Enable is TRUE, which
    refreshes the outputs and returns an error code (0 = valid).
    """

    Enable: bool = False

    def __init__(self) -> None:
        super().__init__()
        self.Valid = False
        self.Error = False
        self.ErrorID = 0

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan of the block."""
        self._take_inputs(inputs)
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

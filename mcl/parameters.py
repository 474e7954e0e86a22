"""Axis parameters: MC_ReadParameter, MC_ReadBoolParameter, MC_WriteParameter,
MC_WriteBoolParameter (PLCopen Part 1 v2.0; announced in the MotionControlLib, Tab. 2.2).

A parameter is chosen by its number: the PLCopen numbers 1–16 and, in the vendor range, the
axis error as 1000 (the MotionControlLib notes at MC_ReadAxisError that MC_ReadParameter
reads the same AxisErrorID) and the servo constants of GT_SetConstant as 1000 + their place in
its inputs (1001 Kp … 1017 Vf); the table below lists them.

A write takes effect as PLCopen describes: the software limits and the following-error
supervision from the next servo cycle; MaxVelocityAppl, MaxAccelerationAppl,
MaxDecelerationAppl and MaxJerk limit the motion commands given afterwards (a command samples its
limits at its Execute edge, so the running and the already queued ones keep theirs), also the
stop ramps of MC_Stop and MC_Halt; the axis' error and power-off stops keep the machine data's
ramp. An application maximum above the system's is clamped to it (read it back to see the
value in force); MaxJerk 0 means the machine data's `max_jerk` (no limit where that is 0 too).
Writing a software limit behaves as GT_SWLim (switching a limit on or moving it where the axis
or a commanded target lies beyond it is refused with `Ecil` 8, switching one off never is; both
on with SWLimitPos <= SWLimitNeg is `EParam`). Writing a constant 1001–1017 is GT_SetConstant
with that one value changed (1007 and 1008 set both software limits and switch them on when
LimPos > LimNeg, as GT_SetConstant does); GT_SetConstant itself sets the software limits anew
from its LimPos/LimNeg.

Errors: an unknown number, or a BOOL parameter given to a REAL block and the other way round:
`ENoParameter` 19; a write to a read-only parameter: `EReadOnly` 20; a value out of range, NaN
or infinite: `EParam` 5; 8, 9 and 1001–1017 before GT_SetConstant: `Econst` 12.
"""

from __future__ import annotations

__all__ = [
    "BOOL_PARAMETERS",
    "CONSTANTS",
    "PARAMETERS",
    "READ_ONLY",
    "REAL_PARAMETERS",
    "REFERENCE_TABLE",
    "VENDOR",
    "MC_ReadBoolParameter",
    "MC_ReadParameter",
    "MC_WriteBoolParameter",
    "MC_WriteParameter",
    "ParameterWrite",
    "read_bool",
    "read_real",
    "write_bool",
    "write_real",
]

import dataclasses
import math
from typing import TYPE_CHECKING, Any, ClassVar, Final

from mcl.command import Deferred, Status
from mcl.enums import MC_ExecutionMode
from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB, non_negative, number, positive
from mcl.servo import ServoConstants

if TYPE_CHECKING:
    from mcl.axis import Axis

VENDOR: Final = 1000
"""The servo constant at place i (1-based) of GT_SetConstant's inputs is parameter VENDOR + i."""
CONSTANTS: Final = tuple(f.name for f in dataclasses.fields(ServoConstants))
"""The servo constants in the order of GT_SetConstant's inputs (1001 = Kp)."""

PARAMETERS: Final[tuple[tuple[int, str, bool, bool, str], ...]] = (
    (1, "CommandedPosition", False, False, "the model (set-point) position [u], wrapped (modulo)"),
    (2, "SWLimitPos", False, True, "positive software limit [u]"),
    (3, "SWLimitNeg", False, True, "negative software limit [u]"),
    (4, "EnableLimitPos", True, True, "the positive software limit is supervised"),
    (5, "EnableLimitNeg", True, True, "the negative software limit is supervised"),
    (6, "EnablePosLagMonitoring", True, True, "the following error is supervised (ERRPOS)"),
    (7, "MaxPositionLag", False, True, "following-error limit DevMax [u], > 0"),
    (8, "MaxVelocitySystem", False, False, "Vmax of GT_SetConstant [u/s]"),
    (9, "MaxVelocityAppl", False, True, "velocity limit of commanded motion [u/s], > 0"),
    (10, "ActualVelocity", False, False, "VEL, the filtered measured velocity [u/s]"),
    (11, "CommandedVelocity", False, False, "the model velocity [u/s]"),
    (12, "MaxAccelerationSystem", False, False, "machine data max_acceleration [u/s²]"),
    (13, "MaxAccelerationAppl", False, True, "acceleration limit of commanded motion [u/s²]"),
    (14, "MaxDecelerationSystem", False, False, "machine data max_deceleration [u/s²]"),
    (15, "MaxDecelerationAppl", False, True, "deceleration limit of commanded motion [u/s²]"),
    (16, "MaxJerk", False, True, "jerk limit of commanded motion [u/s³], >= 0, at most max_jerk"),
    (VENDOR, "AxisErrorID", False, False, "the axis error AxErrorID, as MC_ReadAxisError"),
    *(
        (VENDOR + i, name, False, True, "servo constant, checked as by GT_SetConstant")
        for i, name in enumerate(CONSTANTS, start=1)
    ),
)
"""(number, name, BOOL, writable, meaning) of every parameter."""
REAL_PARAMETERS: Final = {n: name for n, name, is_bool, _, _ in PARAMETERS if not is_bool}
"""The REAL parameters by number (MC_ReadParameter, MC_WriteParameter)."""
BOOL_PARAMETERS: Final = {n: name for n, name, is_bool, _, _ in PARAMETERS if is_bool}
"""The BOOL parameters by number (MC_ReadBoolParameter, MC_WriteBoolParameter)."""
REFERENCE_TABLE: Final = (
    ("number", "name", "type", "access", "in this library"),
    tuple(
        (str(n), name, "BOOL" if is_bool else "REAL", "read/write" if w else "read", text)
        for n, name, is_bool, w, text in PARAMETERS
    ),
)
"""The table of the parameters in the reference (header, rows)."""
READ_ONLY: Final = frozenset(n for n, _, _, writable, _ in PARAMETERS if not writable)
"""The parameters that can only be read."""


def _constant(number: int) -> str:
    """The servo constant of a vendor parameter number, or "" for another number."""
    index = number - VENDOR - 1
    return CONSTANTS[index] if 0 <= index < len(CONSTANTS) else ""


def read_real(axis: Axis, number: int) -> tuple[int, float]:
    """(error, value) of REAL parameter ``number`` of ``axis`` (error 0: valid)."""
    p, c, config = axis.parameters, axis.constants, axis.config
    if number == 1:
        return 0, axis.optional(20)
    if number == 2:
        return 0, p.sw_limit_pos
    if number == 3:
        return 0, p.sw_limit_neg
    if number == 7:
        return 0, p.max_position_lag
    if number == 10:
        return 0, axis.VEL
    if number == 11:
        return 0, axis.sp_vel
    if number == 12:
        return 0, config.max_acceleration
    if number == 13:
        return 0, min(p.max_acceleration_appl, config.max_acceleration)
    if number == 14:
        return 0, config.max_deceleration
    if number == 15:
        return 0, min(p.max_deceleration_appl, config.max_deceleration)
    if number == 16:
        return 0, p.max_jerk
    if number == VENDOR:
        return 0, float(axis.AxErrorID)
    name = _constant(number)
    if number not in (8, 9) and not name:
        return ErrorID.ENoParameter, 0.0
    if c is None:
        return ErrorID.Econst, 0.0
    if number == 8:
        return 0, c.Vmax
    if number == 9:
        return 0, axis.max_velocity()
    return 0, float(getattr(c, name))


def read_bool(axis: Axis, number: int) -> tuple[int, bool]:
    """(error, value) of BOOL parameter ``number`` of ``axis`` (error 0: valid)."""
    p = axis.parameters
    if number == 4:
        return 0, p.sw_enable_pos
    if number == 5:
        return 0, p.sw_enable_neg
    if number == 6:
        return 0, p.lag_monitoring
    return ErrorID.ENoParameter, False


def write_real(axis: Axis, number: int, value: float) -> int:
    """Write REAL parameter ``number`` of ``axis``; the error code (0 = written)."""
    if number in READ_ONLY:
        return ErrorID.EReadOnly
    if number not in REAL_PARAMETERS:
        return ErrorID.ENoParameter
    if not math.isfinite(value):
        return ErrorID.EParam
    p, c, config = axis.parameters, axis.constants, axis.config
    if number == 2:
        return axis.set_sw_limits(value, p.sw_limit_neg, p.sw_enable_pos, p.sw_enable_neg)
    if number == 3:
        return axis.set_sw_limits(p.sw_limit_pos, value, p.sw_enable_pos, p.sw_enable_neg)
    if number == 16:
        if not non_negative(value):
            return ErrorID.EParam
        system = config.max_jerk
        p.max_jerk = min(value, system) if system > 0.0 and value > 0.0 else value or system
        return 0
    if not positive(value) and number in (7, 9, 13, 15):
        return ErrorID.EParam
    if number == 7:
        p.max_position_lag = value
        return 0
    if number == 13:
        p.max_acceleration_appl = min(value, config.max_acceleration)
        return 0
    if number == 15:
        p.max_deceleration_appl = min(value, config.max_deceleration)
        return 0
    if c is None:
        return ErrorID.Econst
    if number == 9:
        p.max_velocity_appl = min(value, c.Vmax)
        return 0
    name = _constant(number)
    if name == "Vmax":
        valid = positive(value)
    elif name in ("LimPos", "LimNeg"):
        valid = True
    else:  # gains, Filter
        valid = non_negative(value)
    if not valid:
        return ErrorID.EParam
    changes: dict[str, Any] = {name: value}
    axis.set_constants(dataclasses.replace(c, **changes), sw_limits=name in ("LimPos", "LimNeg"))
    return 0


def write_bool(axis: Axis, number: int, value: bool) -> int:
    """Write BOOL parameter ``number`` of ``axis``; the error code (0 = written)."""
    p = axis.parameters
    if number == 4:
        return axis.set_sw_limits(p.sw_limit_pos, p.sw_limit_neg, value, p.sw_enable_neg)
    if number == 5:
        return axis.set_sw_limits(p.sw_limit_pos, p.sw_limit_neg, p.sw_enable_pos, value)
    if number == 6:
        p.lag_monitoring = value
        return 0
    return ErrorID.ENoParameter


class ParameterWrite(Deferred):
    """MC_WriteParameter / MC_WriteBoolParameter in mcQueued: the write, applied in the queue."""

    def __init__(self, number: int, value: float, is_bool: bool) -> None:
        super().__init__()
        self.number = number
        self.value = value
        self.is_bool = is_bool

    def apply(self, axis: Axis) -> float:
        if self.is_bool:
            error = write_bool(axis, self.number, self.value != 0.0)
        else:
            error = write_real(axis, self.number, self.value)
        self.status, self.error_id = (Status.Error, error) if error else (Status.Done, 0)
        return 0.0


class MC_ReadParameter(EnableFB):
    """Publishes the REAL parameter ``ParameterNumber`` of the axis in ``Value`` (PLCopen
    Part 1 v2.0 MC_ReadParameter; the numbers are listed above).

    Level-sensitive: while ``Enable`` is TRUE the parameter is read in every call (a changed
    ParameterNumber counts at once); ``Valid`` and ``Busy`` while the value is valid (Busy is
    FALSE with Error here, so that Busy and Error stay exclusive as in every block of this
    library; PLCopen keeps Busy TRUE while enabled). ``Value`` is 0.0 while not valid.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("ParameterNumber",)
    ParameterNumber: int = 0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Busy = False
        self.Value = 0.0

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan."""
        super().__call__(**inputs)
        self.Busy = self.Valid

    def _evaluate(self) -> int:
        error, value = read_real(self.axis, self.ParameterNumber)
        self.Value = value
        return error

    def _disable(self) -> None:
        self.Value = 0.0


class MC_ReadBoolParameter(EnableFB):
    """Publishes the BOOL parameter ``ParameterNumber`` of the axis in ``Value`` (PLCopen
    Part 1 v2.0 MC_ReadBoolParameter): 4 EnableLimitPos, 5 EnableLimitNeg, 6
    EnablePosLagMonitoring; as MC_ReadParameter otherwise (``Value`` FALSE while not valid).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("ParameterNumber",)
    ParameterNumber: int = 0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Busy = False
        self.Value = False

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan."""
        super().__call__(**inputs)
        self.Busy = self.Valid

    def _evaluate(self) -> int:
        error, value = read_bool(self.axis, self.ParameterNumber)
        self.Value = value
        return error

    def _disable(self) -> None:
        self.Value = False


class _WriteFB(ExecuteFB):
    """Common part of MC_WriteParameter and MC_WriteBoolParameter."""

    INPUTS: ClassVar[tuple[str, ...]] = ("ParameterNumber",)
    ParameterNumber: int = 0
    IS_BOOL: ClassVar[bool] = False

    def __init__(self, **inputs: Any) -> None:
        self.CommandAborted = False
        self._write: ParameterWrite | None = None
        super().__init__(**inputs)

    def _value(self) -> float:
        raise NotImplementedError

    def _mode(self) -> int:
        raise NotImplementedError

    def _begin(self) -> int:
        axis = self.axis
        self._write = None
        mode = self._mode()
        if mode not in (MC_ExecutionMode.mcImmediately, MC_ExecutionMode.mcQueued):
            return ErrorID.EParam
        parameter = self.ParameterNumber
        known = BOOL_PARAMETERS if self.IS_BOOL else REAL_PARAMETERS
        if parameter not in known:
            return ErrorID.ENoParameter
        if parameter in READ_ONLY:
            return ErrorID.EReadOnly
        value = self._value()
        if not math.isfinite(value):
            return ErrorID.EParam
        write = ParameterWrite(parameter, value, self.IS_BOOL)
        if mode == MC_ExecutionMode.mcImmediately:
            write.apply(axis)
        else:
            axis.submit_deferred(write)
        if write.status == Status.Error:
            return write.error_id
        self._write = write
        return 0

    def _poll(self) -> Status | None:
        write = self._write
        if write is None or write.busy:
            return None
        return write.status

    def _error_of_poll(self) -> int:
        return self._write.error_id if self._write is not None else 0

    def _withdraw(self) -> None:
        write = self._write
        if write is not None and write.status == Status.Queued:
            self.axis.cancel(write)
        self._write = None

    def _show_more(self, visible: bool, final: Status | None) -> None:
        self.CommandAborted = visible and final == Status.Aborted


class MC_WriteParameter(_WriteFB):
    """Writes ``Value`` to the REAL parameter ``ParameterNumber`` of the axis (PLCopen Part 1
    v2.0 MC_WriteParameter; the numbers and when a write takes effect are listed above).

    Inputs sampled on the rising edge of Execute. ``ExecutionMode`` (``MC_ExecutionMode``):
    ``mcImmediately`` writes in the scan of the edge (``Done`` there); ``mcQueued`` waits
    behind the motion commands given before it like a Buffered command and writes when the one
    before it signals its output (``Busy`` until then; ``CommandAborted``, beyond PLCopen,
    when an Aborting command, a stop or power-off ends the queue first: not written);
    ``mcDelayed`` is not defined for this block (``EParam``). A refused write changes nothing.
    Writing is allowed in every axis state: parameters are no motion commands (the
    MotionControlLib names the parameter blocks among those that never change the axis state).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Value", "ExecutionMode")
    Value: float = 0.0
    ExecutionMode: int = MC_ExecutionMode.mcImmediately

    def _value(self) -> float:
        return number(self.Value)

    def _mode(self) -> int:
        return self.ExecutionMode


class MC_WriteBoolParameter(_WriteFB):
    """Writes ``Value`` to the BOOL parameter ``ParameterNumber`` of the axis (PLCopen Part 1
    v2.0 MC_WriteBoolParameter): 4 EnableLimitPos, 5 EnableLimitNeg (switching a limit on is
    refused with ``Ecil`` 8 while the axis or a commanded target lies beyond it; switching one
    off is always allowed, also while the axis stands beyond the other), 6
    EnablePosLagMonitoring (FALSE: the following error no longer stops the axis with ERRPOS
    2001; the software limits still allow the actual position MaxPositionLag beyond them).
    Otherwise as MC_WriteParameter."""

    INPUTS: ClassVar[tuple[str, ...]] = ("Value", "ExecutionMode")
    Value: bool = False
    ExecutionMode: int = MC_ExecutionMode.mcImmediately
    IS_BOOL: ClassVar[bool] = True

    def _value(self) -> float:
        return 1.0 if self.Value else 0.0

    def _mode(self) -> int:
        return self.ExecutionMode

"""Single-axis administrative function blocks (MotionControlLib chapter 3)."""

from __future__ import annotations

__all__ = [
    "GT_Analog",
    "GT_AxErrStringCZ",
    "GT_AxErrStringEN",
    "GT_AxStatusString",
    "GT_SInfo",
    "GT_SWLim",
    "GT_SetConstant",
    "MC_Power",
    "MC_ReadActualPosition",
    "MC_ReadAxisError",
    "MC_ReadStatus",
    "MC_Reset",
    "MC_SetPosition",
]

import dataclasses
import math
from typing import Any, ClassVar

from mcl.command import CoordinateShift, Status
from mcl.enums import AxisState, MC_BufferMode, MC_ExecutionMode
from mcl.errors import ErrorID, error_text
from mcl.fb import EnableFB, ExecuteFB, non_negative, number, positive
from mcl.servo import ServoConstants, dac_code_volts


class GT_SetConstant(ExecuteFB):
    """Writes the servo constants of the axis (MotionControlLib §3.1); ``Ka``, ``Kf``, ``FfNeg``,
    ``Deadband``, ``Kfp``, ``Tfp`` and ``Vf`` are this library's extensions.

    Inputs: Kp [V/u], Ki [V/(u·s)], Kd [V·s/u], Ff [-], Kc [1/s], Vmax [u/s at 10 V],
    LimPos, LimNeg [u] (LimPos <= LimNeg: no software limits), Ki1 [V/(u·s)], Filter [ms],
    Ka [s], Kf [V], FfNeg [-] (0 = as Ff), Deadband [V], Kfp [V] and Tfp [s] (the friction
    pulse at a reversal) and Vf [u/s] (the friction feed-forward's band; see
    :class:`ServoConstants`). Vmax must be > 0, gains, Filter, Deadband, Kfp, Tfp and Vf >= 0,
    all finite; else EParam.

    Software limits (active once the axis has Ref, not on a modulo axis): a command whose
    target lies beyond one is refused (Ecil 8) and leaves the axis alone; a target exactly on a
    limit is valid. While the axis runs, the model (set) position crossing a limit in the
    outward direction (a velocity move, jogging, gearing) stops the axis with ERRSWP 2006 /
    ERRSWN 2007 on the maximum ramp. The actual position may pass a limit by the following
    error the loop allows (DevMax; a settling overshoot of a move to the limit is no error);
    moving outward more than DevMax beyond it (possible only where the following error is not
    supervised, e.g. SpeedMode 1) is ERRSWP / ERRSWN as well. Moving back inward is always
    allowed.
    """

    # the fields of ServoConstants, in order and with its defaults (a test keeps them equal)
    INPUTS: ClassVar[tuple[str, ...]] = (
        "Kp", "Ki", "Kd", "Ff", "Kc", "Vmax", "LimPos", "LimNeg", "Ki1", "Filter", "Ka", "Kf",
        "FfNeg", "Deadband", "Kfp", "Tfp", "Vf",
    )  # fmt: skip
    Kp: float = 0.0
    Ki: float = 0.0
    Kd: float = 0.0
    Ff: float = 1.0
    Kc: float = 0.0
    Vmax: float = 0.0
    LimPos: float = 0.0
    LimNeg: float = 0.0
    Ki1: float = 0.0
    Filter: float = 0.0
    Ka: float = 0.0
    Kf: float = 0.0
    FfNeg: float = 0.0
    Deadband: float = 0.0
    Kfp: float = 0.0
    Tfp: float = 0.0
    Vf: float = 0.0

    def _begin(self) -> int:
        values = {f.name: number(getattr(self, f.name)) for f in dataclasses.fields(ServoConstants)}
        for name, value in values.items():
            if name == "Vmax":
                valid = positive(value)
            elif name in ("LimPos", "LimNeg"):
                valid = math.isfinite(value)
            else:  # gains, Filter
                valid = non_negative(value)
            if not valid:
                return ErrorID.EParam
        self.axis.set_constants(ServoConstants(**values))
        return 0


class MC_Power(EnableFB):
    """Switches the drive on and closes the position loop (MotionControlLib §3.2).

    Inputs: Enable (level), SpeedMode (0 closed position loop, 1 open loop: output voltage =
    model velocity × 10 V / Vmax), BufferMode (accepted for compatibility).
    Outputs: Status (the effective state of the power stage: TRUE while the module enables the
    drive and the axis is not Disabled), Error, ErrorID. On a following error (ERRPOS 2001) the
    loop opens but the drive stays enabled at 0 V for ``AxisConfig.quick_stop_time`` while its
    own velocity loop brakes the axis: Status stays TRUE until the enable drops, then FALSE (the
    axis stays in ErrorStop). Enable=TRUE from Disabled clears the axis' Ref flag. After a
    GT_EStop the axis stays Disabled (Status FALSE, no error) until Enable has been FALSE once and
    the E-stop's Enable is FALSE (see GT_EStop).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("SpeedMode", "BufferMode")
    SpeedMode: int = 0
    BufferMode: int = MC_BufferMode.Aborting

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Status = False

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan: the axis follows Enable."""
        self._scan(inputs)
        axis = self.axis
        enable = self.Enable
        error = 0
        speed_mode = self.SpeedMode
        if enable and not axis.has_drive:
            error = ErrorID.ENoDrive
        elif enable and axis.constants is None:
            error = ErrorID.Econst
        elif enable and speed_mode != 0 and speed_mode != 1:
            error = ErrorID.EParam
        else:
            axis.power(enable, int(speed_mode) if enable else 0)
        self.Status = axis.drive_enabled and axis.state != AxisState.Disabled
        self.Error = bool(error)
        self.ErrorID = error
        self.Valid = self.Status and not error


class MC_ReadStatus(EnableFB):
    """Publishes the axis state as flags (MotionControlLib §3.3)."""

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self._flags(None)
        self.Ref = False

    def _flags(self, state: AxisState | None) -> None:
        self.Disabled = state == AxisState.Disabled
        self.StandStill = state == AxisState.StandStill
        self.Homing = state == AxisState.Homing
        self.DiscreteMotion = state == AxisState.DiscreteMotion
        self.ContinuousMotion = state == AxisState.ContinuousMotion
        self.SynchronizedMotion = state == AxisState.SynchronizedMotion
        self.Stopping = state == AxisState.Stopping
        self.ErrorStop = state == AxisState.ErrorStop

    def _evaluate(self) -> int:
        self._flags(self.axis.state)
        self.Ref = self.axis.Ref
        return 0

    def _disable(self) -> None:
        self._flags(None)
        self.Ref = False


class MC_ReadAxisError(EnableFB):
    """Publishes the axis error (MotionControlLib §3.4): ``AxisErrorID``; ``Error`` = the axis has
    an error."""

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.AxisErrorID = 0

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan."""
        super().__call__(**inputs)
        if self.Enable:
            self.AxisErrorID = self.axis.AxErrorID
            self.Error = self.AxisErrorID != 0
            self.ErrorID = 0
        else:
            self.AxisErrorID = 0

    def _evaluate(self) -> int:
        return 0


class MC_Reset(ExecuteFB):
    """Clears the axis errors; ErrorStop → StandStill (Disabled if the error opened the loop).

    Done once the state is reached: after the error stop ramp has finished, and where the error
    opened the loop, once the amplifier's quick stop has ended and the drive is off (a Disabled
    axis never has its power stage on).
    """

    def _begin(self) -> int:
        return 0

    def _poll(self) -> Status | None:
        return Status.Done if self.axis.reset() else None


class MC_ReadActualPosition(EnableFB):
    """Publishes the actual position ``Position`` [u] (MotionControlLib §3.6)."""

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Position = 0.0

    def _evaluate(self) -> int:
        self.Position = self.axis.POS
        return 0

    def _disable(self) -> None:
        self.Position = 0.0


class MC_SetPosition(ExecuteFB):
    """Shifts the coordinate system of the axis without moving it (PLCopen Part 1 v2.0,
    MC_SetPosition; announced in the MotionControlLib, Tab. 2.2): actual position and set point
    move by the same distance, the following error stays.

    Inputs (sampled on the rising edge of Execute): ``Position`` [u], the new actual position,
    or with ``Relative`` TRUE the distance added to the coordinate; ``ExecutionMode``
    (``MC_ExecutionMode``): ``mcImmediately`` applies it in the scan of the edge, ``mcQueued``
    queues it behind the motion commands given before it as if it were Buffered: it is applied
    when the command before it signals its output (``Done``; ``InVelocity`` of MC_MoveVelocity,
    which then goes on), so commands given after it are in the new coordinate. ``mcDelayed``
    is not defined for this block (``EParam``). ``Done`` once the coordinate has its new value
    (in the scan of the edge for mcImmediately or an idle axis), ``Busy`` while queued.

    On a moving axis the command that runs goes on physically undisturbed: its path and target
    move with the coordinate (PLCopen: the commanded position is kept and is now expressed in
    the shifted coordinate system), and so do the targets of the commands queued behind it. The
    software limits keep their values in the new coordinate system; a shift that would put the
    axis or such a target beyond an active limit (with Ref) is refused with ``Ecil`` 8. The
    block does not set Ref (use MC_FinishHoming for that). A modulo axis shows the new
    position wrapped into its period.

    Allowed in Disabled (an encoder-only axis too), StandStill and the motion states. PLCopen
    lets every block be called in ErrorStop and Stopping but executes none there but MC_Reset
    (Note 1 of the state diagram, the same in the MotionControlLib): ``Eerrstop`` 11 /
    ``EAxStop`` 6. Refused in Homing (``Ehome`` 9: the homing procedure sets the coordinate) and
    on a group member (1000: the group's path is laid out in its members' coordinates).
    ``Position`` not finite or an unknown ExecutionMode: ``EParam``; a refused call leaves the
    axis as it was. ``CommandAborted`` (beyond PLCopen, mcQueued only): an Aborting command, a
    stop or power-off ended the queue before the shift was applied (an axis error: ``Error``
    with the axis' code); the coordinate is then unchanged.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Position", "Relative", "ExecutionMode")
    Position: float = 0.0
    Relative: bool = False
    ExecutionMode: int = MC_ExecutionMode.mcImmediately

    def __init__(self, **inputs: Any) -> None:
        self.CommandAborted = False
        self._shift: CoordinateShift | None = None
        super().__init__(**inputs)

    def _begin(self) -> int:
        axis = self.axis
        self._shift = None
        error = axis.check_coordinate()
        if error:
            return error
        position = number(self.Position)
        mode = self.ExecutionMode
        if not math.isfinite(position) or mode not in (
            MC_ExecutionMode.mcImmediately,
            MC_ExecutionMode.mcQueued,
        ):
            return ErrorID.EParam
        relative = bool(self.Relative)
        if mode == MC_ExecutionMode.mcImmediately:
            return axis.shift_coordinate(position if relative else position - axis.actual)
        shift = CoordinateShift(position, relative)
        axis.submit_deferred(shift)
        if shift.status == Status.Error:
            return shift.error_id
        self._shift = shift
        return 0

    def _poll(self) -> Status | None:
        shift = self._shift
        if shift is None:
            return Status.Done
        return None if shift.busy else shift.status

    def _error_of_poll(self) -> int:
        return self._shift.error_id if self._shift is not None else 0

    def _withdraw(self) -> None:
        shift = self._shift
        if shift is not None and shift.status == Status.Queued:
            self.axis.cancel(shift)
        self._shift = None

    def _show_more(self, visible: bool, final: Status | None) -> None:
        self.CommandAborted = visible and final == Status.Aborted


class GT_SWLim(ExecuteFB):
    """Sets the software limits at run time and switches each on or off (MotionControlLib
    Tab. 2.2 announces the block without a description; PLCopen Part 1 v2.0 has none, its
    parameters 2–5 of MC_WriteParameter and MC_WriteBoolParameter do the same).

    The inputs are this library's, as the manual names the block only. Inputs (sampled on
    the rising edge of Execute): ``LimPos``, ``LimNeg`` [u], the limits; ``EnableLimitPos``,
    ``EnableLimitNeg``: the limit is supervised. ``Done`` in the scan of
    the edge; the limits act from the next servo cycle, as those of GT_SetConstant (with Ref, on
    a linear axis: targets beyond are refused with ``Ecil`` 8, the model crossing a limit
    outward stops the axis with ERRSWP 2006 / ERRSWN 2007). A later GT_SetConstant sets the
    limits anew from its own LimPos/LimNeg. Allowed in every axis state (it is no motion
    command); needs the constants of GT_SetConstant (``Econst`` 12).

    A new limit (switched on, or moved while on) that the axis already stands beyond, or that
    the running or a queued move's target lies beyond, is refused: ``Ecil`` 8 and nothing
    changes, the move goes on to its target (rather than the module's software-limit stop
    halting it halfway with an axis error; a refused call leaves the axis as it was, as every
    parameter error does). A limit left on where it was is not checked again: after a
    software-limit stop, which leaves the axis just beyond the limit, the other limit may be
    switched off or moved, and a move back inward is allowed. Motion
    without a target (MC_MoveVelocity, GT_Jog, a geared slave) heading for the new limit is
    stopped there by the supervision, ERRSWP / ERRSWN on the maximum ramp, as by a limit set
    before it started. Not finite values, or both limits on with LimPos <= LimNeg:
    ``EParam``. On a modulo axis the limits are stored but never act.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("LimPos", "LimNeg", "EnableLimitPos", "EnableLimitNeg")
    LimPos: float = 0.0
    LimNeg: float = 0.0
    EnableLimitPos: bool = True
    EnableLimitNeg: bool = True

    def _begin(self) -> int:
        axis = self.axis
        if axis.constants is None:
            return ErrorID.Econst
        pos, neg = number(self.LimPos), number(self.LimNeg)
        if not (math.isfinite(pos) and math.isfinite(neg)):
            return ErrorID.EParam
        return axis.set_sw_limits(pos, neg, bool(self.EnableLimitPos), bool(self.EnableLimitNeg))


class GT_Analog(ExecuteFB):
    """Writes the DAC directly while the axis is Disabled, for drive set-up
    (MotionControlLib §3.15).

    Inputs: Analog (INT −4095..4095: −4095 → +10.5 V, +4095 → −10.5 V, as the MotionControlLib
    manual documents), Par (0 = write, 1 = end). Not Disabled → EpowerOff 13. MC_Power also ends it.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Analog", "Par")
    Analog: int = 0
    Par: int = 0

    def _begin(self) -> int:
        axis = self.axis
        analog, par = number(self.Analog), number(self.Par)
        if par not in (0.0, 1.0) or not math.isfinite(analog) or abs(analog) > 4095:
            return ErrorID.EParam
        if axis.state != AxisState.Disabled:
            return ErrorID.EpowerOff
        axis.set_analog(None if par == 1.0 else dac_code_volts(int(analog)))
        return 0


class GT_SInfo(ExecuteFB):
    """Selects what OPT1n / OPT2n of the AXIS_REF show (MotionControlLib §3.19).

    20 model position, 21 model velocity, 22 encoder status, 23 following error,
    24 position captured at InSync. Other selectors → EParam.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("What1", "What2")
    What1: int = 20
    What2: int = 21

    def _begin(self) -> int:
        what = (number(self.What1), number(self.What2))
        if any(w not in (20.0, 21.0, 22.0, 23.0, 24.0) for w in what):
            return ErrorID.EParam
        self.axis.opt_select = (int(what[0]), int(what[1]))
        return 0


class GT_AxStatusString(EnableFB):
    """The axis state as text in ``StatStr`` (MotionControlLib §3.16)."""

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.StatStr = ""

    def _evaluate(self) -> int:
        self.StatStr = self.axis.state.name
        return 0

    def _disable(self) -> None:
        self.StatStr = ""


class GT_AxErrStringEN(EnableFB):
    """The active axis error as English text in ``ErrStr``; ``Error`` = an axis error is active."""

    LANGUAGE: ClassVar[str] = "en"

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.ErrStr = ""

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan."""
        super().__call__(**inputs)
        if self.Enable:
            code = self.axis.AxErrorID
            self.ErrStr = error_text(code, self.LANGUAGE) if code else ""
            self.Error = code != 0
        else:
            self.ErrStr = ""

    def _evaluate(self) -> int:
        return 0


class GT_AxErrStringCZ(GT_AxErrStringEN):
    """The active axis error as Czech text in ``ErrStr``; ``Error`` = an axis error is active."""

    LANGUAGE: ClassVar[str] = "cz"

"""Homing step blocks (MotionControlLib chapter 6).

A coarse approach step (MC_StepAbsSwitch, MC_StepLimitSwitch, MC_StepBlock) leaves the axis in
Homing; a finishing step (MC_StepRefPulse, MC_StepDirect, MC_FinishHoming) sets the coordinate,
sets ``Ref`` and returns the axis to StandStill (the flying references, which command no motion:
:mod:`mcl.flying_reference`). Searches use the axis' default
acceleration, deceleration and jerk; while searching the limit switches do not trip an axis
error: hitting one reverses the search (the second one ends it with the limit-switch error).
"""

from __future__ import annotations

__all__ = [
    "AbsoluteCoordinate",
    "BlockSearch",
    "HomingStep",
    "MC_FinishHoming",
    "MC_StepAbsSwitch",
    "MC_StepAbsolute",
    "MC_StepBlock",
    "MC_StepDirect",
    "MC_StepLimitSwitch",
    "MC_StepRefPulse",
    "RefPulseSearch",
    "SetCoordinate",
    "Supervision",
    "SwitchSearch",
]

import math
from typing import TYPE_CHECKING, ClassVar

from mcl import trajectory
from mcl.command import BlockRelease, Command
from mcl.enums import AxisState, MC_BufferMode, MC_Direction, MC_SwitchMode
from mcl.errors import ErrorID
from mcl.fb import MotionFB, non_negative, number, positive
from mcl.trajectory import Limits, Profile

if TYPE_CHECKING:
    from mcl.axis import Axis


class Supervision:
    """TorqueLimit (following error [u]), TimeLimit [s], DistanceLimit [u]; 0 = off."""

    __slots__ = ("distance", "time", "torque")

    def __init__(self, torque: float, time: float, distance: float) -> None:
        self.torque, self.time, self.distance = torque, time, distance

    def violated(self, axis: Axis, t: float, origin: float) -> int:
        """The homing error due now (EDev 3, ETime 1, EDistance 2) or 0."""
        if self.torque and abs(axis.following_error) > self.torque:
            return ErrorID.EDev
        if self.time and t > self.time:
            return ErrorID.ETime
        if self.distance and abs(axis.actual - origin) > self.distance:
            return ErrorID.EDistance
        return 0


class HomingStep(Command):
    """Base of the moving homing steps: a velocity search with supervision, then an ending."""

    state = AxisState.Homing
    end_state = AxisState.Homing
    ignores_limit_switches = True

    def __init__(
        self, buffer_mode: MC_BufferMode, limits: Limits, direction: float, supervision: Supervision
    ) -> None:
        super().__init__(buffer_mode)
        self.limits = limits
        self.velocity = limits.velocity
        self.direction = direction
        self.supervision = supervision
        self.origin = 0.0
        self.searching = True
        self.profile: Profile | None = None
        self.tp = 0.0
        """Start of the current phase, seconds after ``t0``."""

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        axis.Ref = False
        self.origin = axis.actual
        self.tp = 0.0
        self.profile = trajectory.velocity_to(p, v, a, self.direction * self.velocity, self.limits)

    def phase(self, profile: Profile, t: float) -> tuple[float, float, float]:
        """Switch to a new profile that starts now (``t`` seconds after ``t0``)."""
        self.profile, self.tp = profile, t
        return profile.at(0.0)

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        profile = self.profile
        assert profile is not None
        p, v, a = profile.at(t - self.tp)
        if not self.searching:
            if t - self.tp >= profile.duration:
                self.signal = True
                return self.finish(axis, p)
            return p, v, a
        error = self.supervision.violated(axis, t, self.origin)
        if error:
            axis.fault(error, stop_pushing=error == ErrorID.EDev)
            return axis.sp_pos, axis.sp_vel, axis.sp_acc
        return self.search(axis, t, p, v, a)

    def search(
        self, axis: Axis, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float]:
        """One servo cycle of the search; returns the set point."""
        raise NotImplementedError

    def finish(self, axis: Axis, p: float) -> tuple[float, float, float]:
        """Set point once the ending phase is over."""
        return p, 0.0, 0.0

    def handover_state(
        self, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float, float]:
        profile = self.profile
        if self.searching or profile is None:
            return t, p, v, a
        return (self.tp + profile.duration, *profile.at(profile.duration))

    def reverse(
        self, t: float, p: float, v: float, a: float, brake: Limits | None = None
    ) -> tuple[float, float, float]:
        """Turn the search around; ``brake``: the ramp to slow down with (default: the search's)."""
        self.direction = -self.direction
        limits = self.limits
        if brake is not None:
            limits = Limits(limits.velocity, limits.acceleration, brake.deceleration, brake.jerk)
        return self.phase(
            trajectory.velocity_to(p, v, a, self.direction * self.velocity, limits), t
        )


class SwitchSearch(HomingStep):
    """Search a switch (REF or a limit switch) by SwitchMode; stop, return to the captured point.

    Args:
        switch: ``"ref"``, ``"lim_pos"`` or ``"lim_neg"``; ``"lim"`` = the limit switch in the
            current search direction.
        mode: the MC_SwitchMode condition.
    """

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        limits: Limits,
        direction: float,
        supervision: Supervision,
        switch: str,
        mode: MC_SwitchMode,
    ) -> None:
        super().__init__(buffer_mode, limits, direction, supervision)
        self.switch = switch
        self.mode = mode
        self.captured = 0.0
        self._level: bool | None = None
        self._reversed_at_limit = False
        self._returning = False

    def _input(self, axis: Axis) -> bool:
        io = axis.io
        if self.switch == "ref":
            return io.ref
        if self.switch == "lim":
            return io.lim_pos if self.direction > 0 else io.lim_neg
        return io.lim_pos if self.switch == "lim_pos" else io.lim_neg

    def search(
        self, axis: Axis, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float]:
        level = self._input(axis)
        previous = level if self._level is None else self._level
        self._level = level
        rising, falling = level and not previous, previous and not level
        mode = self.mode
        if mode == MC_SwitchMode.MC_EdgeSwitchPositive:
            mode = MC_SwitchMode.MC_EdgeOn if self.direction > 0 else MC_SwitchMode.MC_EdgeOff
        elif mode == MC_SwitchMode.MC_EdgeSwitchNegative:
            mode = MC_SwitchMode.MC_EdgeOff if self.direction > 0 else MC_SwitchMode.MC_EdgeOn
        found = (
            (mode == MC_SwitchMode.MC_On and level)
            or (mode == MC_SwitchMode.MC_Off and not level)
            or (mode == MC_SwitchMode.MC_EdgeOn and rising)
            or (mode == MC_SwitchMode.MC_EdgeOff and falling)
        )
        if found:
            self.captured = axis.actual
            self.searching = False
            return self.phase(
                trajectory.stop(p, v, a, self.limits.deceleration, self.limits.jerk), t
            )
        opposite = (self.mode == MC_SwitchMode.MC_EdgeOn and falling) or (
            self.mode == MC_SwitchMode.MC_EdgeOff and rising
        )
        if opposite:
            return self.reverse(t, p, v, a)
        if self.switch == "ref":
            io = axis.io
            limit = io.lim_pos if self.direction > 0 else io.lim_neg
            if limit and v * self.direction > 0.0:
                if self._reversed_at_limit:
                    axis.fault(ErrorID.ERRLIP if self.direction > 0 else ErrorID.ERRLIN)
                    return p, v, a
                self._reversed_at_limit = True
                self._level = None
                return self.reverse(t, p, v, a, brake=axis.max_ramp())  # spare the hard stop
        return p, v, a

    def finish(self, axis: Axis, p: float) -> tuple[float, float, float]:
        if not self._returning:  # stopped: come back to the captured position
            self._returning = True
            self.signal = False
            profile = trajectory.move_to(p, 0.0, 0.0, self.captured, self.limits)
            self.profile, self.tp = (
                profile,
                self.tp + (self.profile.duration if self.profile else 0.0),
            )
            return profile.at(0.0)
        return self.captured, 0.0, 0.0


class BlockSearch(HomingStep):
    """Drive against a mechanical stop until the velocity falls below 5 % of Velocity and the
    following error exceeds DevRef; then stop pushing and back off clear of the stop
    (:class:`~mcl.command.BlockRelease`); ``signal`` once the axis holds there in position."""

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        limits: Limits,
        direction: float,
        supervision: Supervision,
        dev_ref: float,
    ) -> None:
        super().__init__(buffer_mode, limits, direction, supervision)
        self.dev_ref = dev_ref
        self.release: BlockRelease | None = None

    def search(
        self, axis: Axis, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float]:
        if abs(axis.VEL) < 0.05 * self.velocity and abs(axis.following_error) > self.dev_ref:
            self.searching = False
            release = self.release = BlockRelease(axis, t, self.direction, self.limits)
            return release.setpoint(axis, t)
        return p, v, a

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        release = self.release
        if release is None:
            return super().setpoint(axis, t)
        p, v, a = release.setpoint(axis, t)
        self.signal = release.done
        return p, v, a

    def handover_state(
        self, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float, float]:
        return t, p, v, a

    def rebase(self, delta: float) -> None:
        if self.release is not None:
            self.release.rebase(delta)


class RefPulseSearch(HomingStep):
    """Search the next rising edge of the index pulse; set SetPosition there; stop, no return."""

    end_state = AxisState.StandStill

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        limits: Limits,
        direction: float,
        supervision: Supervision,
        set_position: float,
        stop_ramp: Limits,
    ) -> None:
        super().__init__(buffer_mode, limits, direction, supervision)
        self.set_position = set_position
        self.stop_ramp = stop_ramp
        self._seq = 0

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        super().start(axis, p, v, a, v_end)
        self._seq = axis.io.index_seq

    def search(
        self, axis: Axis, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float]:
        io = axis.io
        if io.index_seq == self._seq:
            return p, v, a
        edge = io.index_count * axis.config.resolution + axis.offset
        delta = self.set_position - edge
        axis.rebase(delta)
        axis.Ref = True
        self.searching = False
        p += delta
        return self.phase(
            trajectory.stop(p, v, a, self.stop_ramp.deceleration, self.stop_ramp.jerk), t
        )


class SetCoordinate(Command):
    """MC_StepDirect / MC_FinishHoming: no motion; set the coordinate (or keep it) and Ref.

    The coordinate is set at the model position the axis stands at (where the preceding step
    holds it; the actual position at StandStill): SetPosition is then the position the axis is
    commanded to, the loop's residual error stays as it was.
    """

    state = AxisState.Homing

    def __init__(self, buffer_mode: MC_BufferMode, set_position: float | None) -> None:
        super().__init__(buffer_mode)
        self.set_position = set_position
        self.position = 0.0
        """The model position it keeps [u]: where the preceding step left it, rebased."""

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        delta = 0.0
        if self.set_position is not None:
            delta = self.set_position - p
            axis.rebase(delta)
        self.position = p + delta
        axis.Ref = True

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        self.signal = True
        return self.position, 0.0, 0.0

    def rebase(self, delta: float) -> None:
        self.position += delta


class AbsoluteCoordinate(Command):
    """MC_StepAbsolute: no motion; the actual position becomes the absolute sensor's reading
    (in axis units) plus an offset, and Ref is set.

    The reading is taken when the command starts (after a preceding buffered step: where that
    step left the axis); the whole coordinate system moves with it, as for MC_StepDirect.
    """

    state = AxisState.Homing

    def __init__(self, buffer_mode: MC_BufferMode, offset: float) -> None:
        super().__init__(buffer_mode)
        self.offset = offset
        self.position = 0.0
        """The model position it keeps [u], rebased."""
        self.failed = False
        """No valid reading at the start (a frame error): the axis error EAbsFrame follows."""

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        io = axis.io
        reading = io.absolute_position()
        delta = 0.0
        self.failed = reading is None
        if reading is not None:
            target = reading * (axis.config.resolution / io.resolution) + self.offset
            delta = target - axis.actual
            axis.rebase(delta)
            axis.Ref = True
        self.position = p + delta

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        if self.failed:  # the frame failed between the call and the start (a buffered step)
            axis.fault(ErrorID.EAbsFrame)
            return axis.sp_pos, axis.sp_vel, axis.sp_acc
        self.signal = True
        return self.position, 0.0, 0.0

    def rebase(self, delta: float) -> None:
        self.position += delta


# --------------------------------------------------------------------------- function blocks


class _HomingFB(MotionFB):
    """Common inputs of the searching steps (docs/reference.md, Homing step blocks)."""

    INPUTS: ClassVar[tuple[str, ...]] = (
        "Direction",
        "Velocity",
        "TorqueLimit",
        "TimeLimit",
        "DistanceLimit",
    )
    Direction: int = MC_Direction.MC_Positive
    Velocity: float = 0.0
    TorqueLimit: float = 0.0
    TimeLimit: float = 0.0
    DistanceLimit: float = 0.0

    SWITCH_DIRECTIONS = False
    """Whether MC_SwitchPositive / MC_SwitchNegative are allowed (they need a switch)."""

    def _checks(self) -> tuple[Limits, float, Supervision] | int:
        axis = self.axis
        error = axis.check_ready(homing_ok=True)
        if error:
            return error
        v = number(self.Velocity)
        torque, time, distance = (
            number(x) for x in (self.TorqueLimit, self.TimeLimit, self.DistanceLimit)
        )
        if not positive(v) or axis.velocity_too_low(v):
            return ErrorID.EParam
        if not (non_negative(torque) and non_negative(time) and non_negative(distance)):
            return ErrorID.EParam
        direction = number(self.Direction)
        if direction == MC_Direction.MC_Positive:
            sign = 1.0
        elif direction == MC_Direction.MC_Negative:
            sign = -1.0
        elif self.SWITCH_DIRECTIONS and direction in (
            MC_Direction.MC_SwitchPositive,
            MC_Direction.MC_SwitchNegative,
        ):
            on = axis.io.ref
            sign = -1.0 if on else 1.0
            if direction == MC_Direction.MC_SwitchNegative:
                sign = -sign
        else:
            return ErrorID.EParam
        limits = axis.limits(v, 0.0, 0.0, 0.0)
        return limits, sign, Supervision(torque, time, distance)

    def _switch_mode(self) -> MC_SwitchMode | None:
        try:
            return MC_SwitchMode(int(number(self.SwitchMode)))  # type: ignore[attr-defined]
        except (ValueError, OverflowError):
            return None


class MC_StepAbsSwitch(_HomingFB):
    """Approach the reference switch REF (MotionControlLib §6.1): search by SwitchMode, stop, come
    back to the captured switch position; the axis stays in Homing."""

    INPUTS: ClassVar[tuple[str, ...]] = ("SwitchMode",)
    SwitchMode: int = MC_SwitchMode.MC_EdgeOn
    SWITCH_DIRECTIONS = True

    def _command(self, mode: MC_BufferMode) -> Command | int:
        checked = self._checks()
        if isinstance(checked, int):
            return checked
        switch_mode = self._switch_mode()
        if switch_mode is None:
            return ErrorID.EParam
        limits, sign, supervision = checked
        return SwitchSearch(mode, limits, sign, supervision, "ref", switch_mode)


class MC_StepLimitSwitch(_HomingFB):
    """Approach the limit switch in the search direction (MotionControlLib §6.2); stays in
    Homing."""

    INPUTS: ClassVar[tuple[str, ...]] = ("SwitchMode",)
    SwitchMode: int = MC_SwitchMode.MC_EdgeOn

    def _command(self, mode: MC_BufferMode) -> Command | int:
        checked = self._checks()
        if isinstance(checked, int):
            return checked
        switch_mode = self._switch_mode()
        if switch_mode is None or switch_mode > MC_SwitchMode.MC_EdgeOff:
            return ErrorID.EParam
        limits, sign, supervision = checked
        switch = "lim_pos" if sign > 0 else "lim_neg"
        return SwitchSearch(mode, limits, sign, supervision, switch, switch_mode)


class MC_StepBlock(_HomingFB):
    """Drive against a mechanical stop (MotionControlLib §6.3): found when the actual velocity is
    below 5 % of Velocity and the following error exceeds TorqueLimit (= DevRef [u], 0 < DevRef <
    DevMax). The axis stays in Homing.

    Once the stop is found the drive stops pushing at once: the model stands at the actual
    position and the integral action (Ki, Ki1) is cleared and held off for
    ``AxisConfig.release_time``, so the compressed stop springs the axis back; then the axis
    backs off by the in-position window and is held there, clear of the stop, with the full
    regulator. Done once it is in position there: that is the reference point a following
    MC_StepDirect sets.
    """

    def _command(self, mode: MC_BufferMode) -> Command | int:
        checked = self._checks()
        if isinstance(checked, int):
            return checked
        limits, sign, supervision = checked
        dev_ref = supervision.torque
        if not 0.0 < dev_ref < self.axis.parameters.max_position_lag:
            return ErrorID.EParam
        supervision.torque = 0.0  # TorqueLimit is the detection threshold here, not an error
        return BlockSearch(mode, limits, sign, supervision, dev_ref)


class MC_StepRefPulse(_HomingFB):
    """Search the next index pulse NI in Direction (MotionControlLib §6.4): SetPosition is set at
    its rising edge, the axis stops on the maximum ramp without returning; Ref set, StandStill."""

    INPUTS: ClassVar[tuple[str, ...]] = ("SetPosition",)
    SetPosition: float = 0.0

    def _command(self, mode: MC_BufferMode) -> Command | int:
        checked = self._checks()
        if isinstance(checked, int):
            return checked
        position = number(self.SetPosition)
        if not math.isfinite(position):
            return ErrorID.EParam
        limits, sign, supervision = checked
        return RefPulseSearch(mode, limits, sign, supervision, position, self.axis.max_ramp())


class MC_StepDirect(MotionFB):
    """Set SetPosition [u] at the current standstill position (MotionControlLib §6.5); Ref,
    StandStill.

    The standstill position is the one the axis is held at: after an approach step the model
    position that step ended with (after MC_StepBlock: clear of the stop, see there), at
    StandStill the actual position. No motion; the drive keeps holding the axis where it is.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("SetPosition",)
    SetPosition: float = 0.0

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        error = axis.check_ready(homing_ok=True)
        if error:
            return error
        position = number(self.SetPosition)
        if not math.isfinite(position):
            return ErrorID.EParam
        if mode == MC_BufferMode.Aborting and axis.moving:
            return ErrorID.EParam  # the axis must stand still
        return SetCoordinate(mode, position)


class MC_StepAbsolute(MotionFB):
    """Home an axis with an absolute measuring system without motion (PLCopen Part 5
    MC_StepAbsolute): the actual position becomes the absolute sensor's reading, scaled to axis
    units, plus Offset [u]; Ref, StandStill.

    The axis' absolute sensor (:attr:`mcl.Sensors.absolute`: a multi-turn absolute encoder or an
    SSI transducer) gives the position at once, from power-on; nothing is searched, so the step
    ends in the cycle it starts. The reading is the sensor's travel from its own zero (its
    ``offset``) converted with the axis' scale (``AxisConfig.resolution`` per incremental count
    over the channel's travel per count); Offset shifts the coordinate further (0: the axis
    coordinate is the sensor's). Unlike MC_StepDirect no position is imposed: the coordinate
    follows the sensor, and is the same after a power cycle. Refused like MC_StepDirect
    (Disabled ``Epower``, ErrorStop ``Eerrstop``, Stopping ``EAxStop``, a moving axis with
    Aborting ``EParam``); Offset NaN/infinite gives ``EParam``; then an axis without an absolute
    sensor gives ``ENoAbsolute`` 21, a frame that failed its parity / CRC check
    (:class:`mcl.faults.AbsoluteFrameError`) ``EAbsFrame`` 22. A refused block leaves the axis
    untouched (coordinate, Ref, state). Should the frame fail between a buffered call and the
    step's start, the step ends with the axis error ``EAbsFrame`` (ErrorStop), Ref stays unset.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Offset",)
    Offset: float = 0.0

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        error = axis.check_ready(homing_ok=True)
        if error:
            return error
        offset = number(self.Offset)
        if not math.isfinite(offset):
            return ErrorID.EParam
        if axis.io.absolute is None:
            return ErrorID.ENoAbsolute
        if axis.io.absolute_position() is None:
            return ErrorID.EAbsFrame  # a frame failed its check: its word is not used
        if mode == MC_BufferMode.Aborting and axis.moving:
            return ErrorID.EParam  # the axis must stand still
        return AbsoluteCoordinate(mode, offset)


class MC_FinishHoming(MotionFB):
    """End homing without motion (MotionControlLib §6.6): the coordinate stays, Ref is set,
    StandStill."""

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        error = axis.check_ready(homing_ok=True)
        if error:
            return error
        if mode == MC_BufferMode.Aborting and axis.moving:
            return ErrorID.EParam
        return SetCoordinate(mode, None)

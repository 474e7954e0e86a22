"""Single-axis motion function blocks (MotionControlLib §3.7–3.14)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar

from mcl import trajectory
from mcl.command import (
    BlockRelease,
    Command,
    Halt,
    MoveContinuous,
    MoveTo,
    MoveVelocity,
    Status,
    Stop,
)
from mcl.enums import AxisState, MC_BufferMode, MC_Direction
from mcl.errors import ErrorID
from mcl.fb import FunctionBlock, MotionFB, non_negative, number, positive
from mcl.trajectory import Limits

if TYPE_CHECKING:
    from mcl.axis import Axis


def motion_limits(
    axis: Axis, velocity: Any, acceleration: Any, deceleration: Any, jerk: Any
) -> Limits | int:
    """Validated limits of a motion FB (the parameter checks), or ``EParam``.

    Velocity must be > 0 and at least 1 % of Vmax; Acceleration, Deceleration, Jerk >= 0
    (0 = axis default); values above the axis maxima are clamped; an acceleration or
    deceleration too small to reach or leave the velocity within 100 s is refused
    (:func:`motion_refusal` says which).
    """
    checked = _checked_limits(axis, velocity, acceleration, deceleration, jerk)
    return ErrorID.EParam if isinstance(checked, str) else checked


def motion_refusal(
    axis: Axis, velocity: Any, acceleration: Any, deceleration: Any, jerk: Any
) -> str:
    """Why :func:`motion_limits` refuses these inputs with ``EParam`` (empty: it does not),
    e.g. ``"Velocity 20 mm/s below 1 % of Vmax (40 mm/s)"``."""
    checked = _checked_limits(axis, velocity, acceleration, deceleration, jerk)
    return checked if isinstance(checked, str) else ""


def _checked_limits(
    axis: Axis, velocity: Any, acceleration: Any, deceleration: Any, jerk: Any
) -> Limits | str:
    """The limits of :func:`motion_limits`, or why they are refused."""
    v, a, d, j = number(velocity), number(acceleration), number(deceleration), number(jerk)
    unit = axis.config.unit
    if not positive(v):
        return f"Velocity {v:g} {unit}/s is not > 0"
    if axis.velocity_too_low(v):
        least = 0.01 * axis.constants.Vmax if axis.constants is not None else 0.0
        return f"Velocity {v:g} {unit}/s below 1 % of Vmax ({least:g} {unit}/s)"
    for name, value in (("Acceleration", a), ("Deceleration", d), ("Jerk", j)):
        if not non_negative(value):
            return f"{name} {value:g} is not >= 0"
    limits = axis.limits(v, a, d, j)
    for name, ramp in (
        ("Acceleration", limits.acceleration),
        ("Deceleration", limits.deceleration),
    ):
        if ramp * 100.0 < limits.velocity:
            return f"{name} {ramp:g} {unit}/s² takes over 100 s to {limits.velocity:g} {unit}/s"
    return limits


def ready_limits(
    axis: Axis, velocity: Any, acceleration: Any, deceleration: Any, jerk: Any
) -> Limits | int:
    """The axis accepts a motion command now and its limits are valid: the limits, or the error
    (:meth:`Axis.check_ready` first, then :func:`motion_limits`)."""
    return axis.check_ready() or motion_limits(axis, velocity, acceleration, deceleration, jerk)


def stop_limits(axis: Axis, deceleration: Any, jerk: Any) -> Limits | int:
    """Validated limits of a stop ramp (Deceleration, Jerk >= 0; 0 = default), or ``EParam``."""
    d, j = number(deceleration), number(jerk)
    if not (non_negative(d) and non_negative(j)):
        return ErrorID.EParam
    assert axis.constants is not None
    return axis.limits(axis.constants.Vmax, d, d, j)


def absolute_target(axis: Axis, position: Any, direction: Any, mode: MC_BufferMode) -> float | None:
    """The model target of an absolute move to ``position`` [u] (None: not a valid input); on
    a modulo axis the way ``direction`` (an ``MC_Direction``) says from where the move starts."""
    target = number(position)
    if not math.isfinite(target):
        return None
    if not axis.config.modulo:
        return target
    way = number(direction)
    if way not in (1.0, 2.0, 3.0, 4.0):
        return None
    return axis.modulo_target(target, int(way), axis.start_position(mode))


def relative_target(axis: Axis, distance: Any, mode: MC_BufferMode) -> float | None:
    """The model target of a move by ``distance`` [u] (None: not a valid input): from the
    actual position when it aborts or the axis has no command, else from the end of the
    preceding motion."""
    length = number(distance)
    if not math.isfinite(length):
        return None
    if mode == MC_BufferMode.Aborting or axis.active is None:
        return axis.actual + length
    return axis.start_position(mode) + length


class _MoveFB(MotionFB):
    """Common inputs of the moves: Velocity, Acceleration, Deceleration, Jerk."""

    INPUTS: ClassVar[tuple[str, ...]] = ("Velocity", "Acceleration", "Deceleration", "Jerk")
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0
    NEEDS_REF: ClassVar[bool] = False

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        limits = ready_limits(axis, self.Velocity, self.Acceleration, self.Deceleration, self.Jerk)
        if isinstance(limits, int):
            return limits
        target = self._target(mode)
        if target is None:
            return ErrorID.EParam
        if self.NEEDS_REF and not axis.Ref:
            return ErrorID.Ehome
        error = axis.check_target(target)
        if error:
            return error
        return self._make(mode, limits, target)

    def _target(self, mode: MC_BufferMode) -> float | None:
        raise NotImplementedError

    def _make(self, mode: MC_BufferMode, limits: Limits, target: float) -> Command | int:
        return MoveTo(mode, limits, target)


class MC_MoveAbsolute(_MoveFB):
    """Move to an absolute ``Position`` [u] (MotionControlLib §3.8); needs Ref.

    ``Direction`` matters only on a modulo axis: MC_Positive, MC_Negative, MC_Shortest or
    MC_Current (the current direction of motion, else shortest).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Position", "Direction")
    Position: float = 0.0
    Direction: int = MC_Direction.MC_Shortest
    NEEDS_REF: ClassVar[bool] = True

    def _target(self, mode: MC_BufferMode) -> float | None:
        return absolute_target(self.axis, self.Position, self.Direction, mode)


class MoveToBlock(MoveTo):
    """MoveTo that stops early on ExtStop (maximum ramp) or when the following error exceeds
    TorqueLimit (the drive lets go of the block and holds the axis clear of it,
    :class:`~mcl.command.BlockRelease`); not overridden: its block detection and release run in
    real time."""

    blendable = False
    overridable = False

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        limits: Limits,
        target: float,
        torque_limit: float,
        ramp: Limits,
    ) -> None:
        super().__init__(buffer_mode, limits, target)
        self.torque_limit = torque_limit
        self.ramp = ramp
        self.ext_stop = False
        self.stopping = False
        self.release: BlockRelease | None = None

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        release = self.release
        if release is not None:
            p, v, a = release.setpoint(axis, t)
            self.signal = release.done
            return p, v, a
        p, v, a = super().setpoint(axis, t)
        if self.stopping or self.signal:
            return p, v, a
        e = axis.following_error
        if 0.0 < self.torque_limit < abs(e):
            v = axis.VEL  # still moving (not yet at rest: 5 % of Velocity): stop from there
            v = v if abs(v) >= 0.05 * self.velocity else 0.0
            self.release = release = BlockRelease(axis, t, e, self.limits, v)
            self.signal = False
            return release.setpoint(axis, t)
        if self.ext_stop:
            self.stopping = True
            self.profile = trajectory.stop(p, v, a, self.ramp.deceleration, self.ramp.jerk)
            self.t0 += t
        return p, v, a

    def handover_state(
        self, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float, float]:
        if self.release is not None:
            return t, p, v, a
        return super().handover_state(t, p, v, a)

    def rebase(self, delta: float) -> None:
        super().rebase(delta)
        if self.release is not None:
            self.release.rebase(delta)


class GT_MoveAbsBlock(MC_MoveAbsolute):
    """MoveAbsolute that stops at a mechanical block or on ``ExtStop`` (MotionControlLib §3.9).

    ``ExtStop`` (level, read every scan) stops at once on the axis' maximum ramp, e.g. from a
    pressure comparison; Done at standstill. A following error above ``TorqueLimit`` (> 0;
    0 = off) [u] means the axis has run into a block: the loop stays closed but the drive stops
    pushing at once (the model restarts at the actual position, integral action cleared; an
    axis still moving faster than 5 % of Velocity stops from there on the maximum ramp) and
    lets the block spring the axis back for ``AxisConfig.release_time``; then the axis backs
    off by the in-position window and is held there, clear of the block; Done once it is in
    position.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("ExtStop", "TorqueLimit")
    ExtStop: bool = False
    TorqueLimit: float = 0.0

    def _scanned(self) -> None:
        """ExtStop is passed to the running command every scan."""
        if isinstance(self._cmd, MoveToBlock) and self._cmd.busy:
            self._cmd.ext_stop = bool(self.ExtStop)

    def _make(self, mode: MC_BufferMode, limits: Limits, target: float) -> Command | int:
        torque = number(self.TorqueLimit)
        if not non_negative(torque):
            return ErrorID.EParam
        cmd = MoveToBlock(mode, limits, target, torque, self.axis.max_ramp())
        cmd.ext_stop = bool(self.ExtStop)
        return cmd


class MC_MoveRelative(_MoveFB):
    """Move by ``Distance`` [u] from the actual position at the edge (MotionControlLib §3.10).

    The residual loop error is zeroed first; no Ref needed (SW limits only checked with Ref).
    Buffered, the distance counts from the end of the preceding motion.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Distance",)
    Distance: float = 0.0

    def _target(self, mode: MC_BufferMode) -> float | None:
        return relative_target(self.axis, self.Distance, mode)


class MC_MoveAdditive(_MoveFB):
    """Move by ``Distance`` [u] added to the last commanded target (MotionControlLib §3.12,
    REXYGEN MC_MoveAdditive).

    In DiscreteMotion (and when buffered) the target is the last commanded target + Distance,
    otherwise the actual position + Distance. No Ref needed.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Distance",)
    Distance: float = 0.0

    def _target(self, mode: MC_BufferMode) -> float | None:
        distance = number(self.Distance)
        if not math.isfinite(distance):
            return None
        axis = self.axis
        if axis.state == AxisState.DiscreteMotion or (
            mode != MC_BufferMode.Aborting and axis.active is not None
        ):
            return axis.last_target() + distance
        return axis.actual + distance


class MC_MoveVelocity(MotionFB):
    """Never-ending motion at ``Velocity`` [u/s] in ``Direction`` (MotionControlLib §3.11).

    ``InVelocity`` once the velocity is reached; ends only when another command takes over.
    Direction: MC_Positive, MC_Negative or MC_Current (the current direction, positive at rest).
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "Velocity",
        "Acceleration",
        "Deceleration",
        "Jerk",
        "Direction",
    )
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0
    Direction: int = MC_Direction.MC_Positive

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.InVelocity = False

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        limits = ready_limits(axis, self.Velocity, self.Acceleration, self.Deceleration, self.Jerk)
        if isinstance(limits, int):
            return limits
        direction = number(self.Direction)
        if direction == MC_Direction.MC_Current:
            direction = MC_Direction.MC_Negative if axis.sp_vel < 0.0 else MC_Direction.MC_Positive
        if direction not in (MC_Direction.MC_Positive, MC_Direction.MC_Negative):
            return ErrorID.EParam
        sign = 1.0 if direction == MC_Direction.MC_Positive else -1.0
        return MoveVelocity(mode, limits, sign * limits.velocity)

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        self.InVelocity = self._reached()


class _MoveContinuousFB(_MoveFB):
    """A move that passes its target with ``EndVelocity`` and goes on at it (PLCopen Part 1
    v2.0 sections 3.11, 3.12): ``InEndVelocity`` instead of Done."""

    INPUTS: ClassVar[tuple[str, ...]] = ("EndVelocity",)
    EndVelocity: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.InEndVelocity = False

    def _make(self, mode: MC_BufferMode, limits: Limits, target: float) -> Command | int:
        end = number(self.EndVelocity)
        if not math.isfinite(end):
            return ErrorID.EParam
        vmax = self.axis.max_velocity()  # Vmax, or MaxVelocityAppl below it
        return MoveContinuous(mode, limits, target, math.copysign(min(abs(end), vmax), end))

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        self.InEndVelocity = self._reached()


class MC_MoveContinuousAbsolute(_MoveContinuousFB):
    """Move to ``Position`` [u], pass it with ``EndVelocity`` [u/s] and go on at that velocity
    (PLCopen Part 1 v2.0 section 3.11, beyond the Teco library: one of its announced
    blocks); needs Ref.

    ``EndVelocity`` is signed: its sign is the direction the axis passes the target in (against
    the way to the target, the axis goes past, turns and comes back through it). The axis is in
    ContinuousMotion from the start, as PLCopen says (it will not stop by itself): at the
    target ``InEndVelocity`` rises and the axis runs on at ``EndVelocity`` until another command
    takes over (the block then reports CommandAborted); ``Done`` never rises. ``EndVelocity``
    0 stops at the target and holds it, still in ContinuousMotion. ``|EndVelocity|`` may exceed
    ``Velocity`` (the axis speeds up just before the target) and is clamped, as ``Velocity``,
    to Vmax and to MaxVelocityAppl (MC_WriteParameter 9) below it. Only the target is checked
    against the SW limits; beyond it the supervision stops the axis at a limit, as for
    MC_MoveVelocity. All buffer modes: it takes over like MC_MoveAbsolute, and a Buffered or
    blending successor starts at ``InEndVelocity``, from the end velocity (its own end velocity
    is not changed by a blending successor). ``Direction`` as for MC_MoveAbsolute (modulo axes
    only). PLCopen's ``ContinuousUpdate`` is not implemented.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Position", "Direction")
    Position: float = 0.0
    Direction: int = MC_Direction.MC_Shortest
    NEEDS_REF: ClassVar[bool] = True

    def _target(self, mode: MC_BufferMode) -> float | None:
        return absolute_target(self.axis, self.Position, self.Direction, mode)


class MC_MoveContinuousRelative(_MoveContinuousFB):
    """Move by ``Distance`` [u], pass the end with ``EndVelocity`` [u/s] and go on at that
    velocity (PLCopen Part 1 v2.0 section 3.12, beyond the Teco library: one of its announced
    blocks).

    The distance counts as for MC_MoveRelative (from the actual position at the edge, from the
    end of the preceding motion when buffered); no Ref needed. Otherwise as
    MC_MoveContinuousAbsolute: ``InEndVelocity`` at the end point, ContinuousMotion, all buffer
    modes.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Distance",)
    Distance: float = 0.0

    def _target(self, mode: MC_BufferMode) -> float | None:
        return relative_target(self.axis, self.Distance, mode)


class MC_Halt(MotionFB):
    """Ramp to standstill with ``Deceleration`` [u/s²] and ``Jerk``; DiscreteMotion, abortable.

    Beyond the Teco library (PLCopen Part 1); Done at standstill, the axis then goes to StandStill.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Deceleration", "Jerk")
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        error = axis.check_ready(homing_ok=True)
        if error:
            return error
        limits = stop_limits(axis, self.Deceleration, self.Jerk)
        if isinstance(limits, int):
            return limits
        return Halt(mode, limits)


class MC_Stop(MotionFB):
    """Stop the axis (MotionControlLib §3.13): Stopping until Done AND NOT Execute.

    While Execute is TRUE no other motion command is accepted (EAxStop 6). Several instances
    may stop one axis: a later one takes over the ramp (the earlier reports CommandAborted), but
    every instance keeps holding the axis in Stopping while its own Execute is TRUE; the axis
    goes to StandStill once the ramp is done and the Execute of every instance that stopped it
    is FALSE.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Deceleration", "Jerk")
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self._holding: Stop | None = None
        """The Stop this instance's Execute holds the axis with."""

    def _scanned(self) -> None:
        """The axis leaves Stopping once Done and Execute is FALSE."""
        holding = self._holding
        if holding is not None:
            holding.hold = bool(self.Execute)

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        error = axis.check_ready(stopping_ok=True, homing_ok=True)
        if error:
            return error
        limits = stop_limits(axis, self.Deceleration, self.Jerk)
        if isinstance(limits, int):
            return limits
        return Stop(limits)

    def _submit(self, cmd: Command) -> int:
        assert isinstance(cmd, Stop)
        if self._holding is not None:
            self._holding.hold = False  # restarted: the new Stop holds in its place
        self._holding = cmd
        self.axis.begin_stop(cmd)
        return 0


class GT_Jog(FunctionBlock):
    """Hold-to-run jogging (MotionControlLib §3.7): while Enable, JogPos / JogNeg move the axis.

    Inputs (read every scan): Enable, JogPos, JogNeg, JogVelo [u/s], JogAcc, JogDec [u/s²],
    JogJerk [u/s³]. Built on a velocity move; releasing the button ramps down with JogDec on an
    abortable halt, so a new press takes over at once. No Ref needed. Outputs: Busy (a jog motion
    is running), Error, ErrorID.
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "Enable",
        "JogPos",
        "JogNeg",
        "JogVelo",
        "JogAcc",
        "JogDec",
        "JogJerk",
    )
    Enable: bool = False
    JogPos: bool = False
    JogNeg: bool = False
    JogVelo: float = 0.0
    JogAcc: float = 0.0
    JogDec: float = 0.0
    JogJerk: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Busy = False
        self.Error = False
        self.ErrorID = 0
        self._direction = 0
        self._cmd: Command | None = None

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan."""
        self._scan(inputs)
        axis = self.axis
        want = 0
        if self.Enable and bool(self.JogPos) != bool(self.JogNeg):
            want = 1 if self.JogPos else -1
        if want != self._direction:
            self._direction = want
            self.Error, self.ErrorID = False, 0
            if not (want and self._move(axis, want)):
                self._release(axis)
        if not self.Enable:
            self.Error, self.ErrorID = False, 0
        self.Busy = not self.Error and self._cmd is not None and self._cmd.busy

    def _release(self, axis: Axis) -> None:
        """The button is let go (or the new press was refused): ramp a running jog down."""
        if isinstance(self._cmd, MoveVelocity) and self._cmd.busy:
            limits = stop_limits(axis, self.JogDec, self.JogJerk)
            if isinstance(limits, int):
                limits = axis.max_ramp()
            self._cmd = Halt(MC_BufferMode.Aborting, limits)
            axis.submit(self._cmd)

    def _move(self, axis: Axis, direction: int) -> bool:
        """Start jogging in ``direction``; False (and Error) when refused."""
        limits = ready_limits(axis, self.JogVelo, self.JogAcc, self.JogDec, self.JogJerk)
        if isinstance(limits, int):
            self.Error, self.ErrorID = True, limits
            return False
        cmd = MoveVelocity(MC_BufferMode.Aborting, limits, direction * limits.velocity)
        axis.submit(cmd)
        if cmd.status == Status.Error:
            self.Error, self.ErrorID = True, cmd.error_id
            return False
        self._cmd = cmd
        return True


class GT_EStop(FunctionBlock):
    """Emergency stop of every axis of the module (MotionControlLib §3.14).

    On the rising edge of Enable: all axes stop at once, loops open, brakes engage, errors are
    cleared, every axis goes Disabled. ``Done`` while Enable is TRUE and all axes are Disabled.

    The stop latches, as an emergency stop must not end in an automatic restart: while Enable
    is TRUE no axis of the module can be powered, and after Enable has fallen an axis powers up
    again only once its MC_Power has been called with Enable = FALSE (acknowledging the stop)
    and then with Enable = TRUE. An MC_Power whose Enable stays TRUE through the emergency stop
    keeps its axis Disabled (Status FALSE, no error).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Enable",)
    Enable: bool = False

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Done = False
        self._prev = False

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan."""
        self._scan(inputs)
        axis = self.axis
        axes = axis.module.axes if axis.module is not None else [axis]
        enable = bool(self.Enable)
        if enable and not self._prev:
            for member in axes:
                member.emergency_stop()
        if enable or self._prev:
            for member in axes:
                member.hold_estop(self, enable)
        self._prev = enable
        self.Done = enable and all(m.state == AxisState.Disabled for m in axes)


__all__ = [
    "GT_EStop",
    "GT_Jog",
    "GT_MoveAbsBlock",
    "MC_Halt",
    "MC_MoveAbsolute",
    "MC_MoveAdditive",
    "MC_MoveContinuousAbsolute",
    "MC_MoveContinuousRelative",
    "MC_MoveRelative",
    "MC_MoveVelocity",
    "MC_Stop",
    "motion_refusal",
]

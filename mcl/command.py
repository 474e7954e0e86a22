"""Motion commands: the job tickets that function blocks hand to an axis.

A command is created on the rising ``Execute`` edge of a motion FB, queued on the axis according to
its BufferMode, and then owned by the axis: every servo cycle the active command produces the
model position, velocity and acceleration. The FB only reads the ticket's ``status``,
``signal`` and ``error_id`` to drive its outputs, so an FB never touches the servo loop.
"""

from __future__ import annotations

__all__ = [
    "BlockRelease",
    "Command",
    "CoordinateShift",
    "Deferred",
    "Halt",
    "Hold",
    "MoveContinuous",
    "MoveTo",
    "MoveVelocity",
    "ProfileCommand",
    "Status",
    "Stop",
    "blend_velocity",
]

from enum import IntEnum
from typing import TYPE_CHECKING

from mypy_extensions import mypyc_attr

from mcl import trajectory
from mcl.enums import AxisState, MC_BufferMode
from mcl.trajectory import Limits, Profile

if TYPE_CHECKING:
    from mcl.axis import Axis


class Status(IntEnum):
    """Life cycle of a command."""

    Queued = 0
    Active = 1
    Done = 2
    Aborted = 3
    Error = 4


@mypyc_attr(allow_interpreted_subclasses=True)
class Command:
    """Base of every motion command.

    Attributes:
        state: the axis state while this command is active.
        buffer_mode: how it takes over the axis.
        status: life cycle, written by the axis.
        signal: the activating output reached (Done, InVelocity, ...): a buffered successor may
            start now (MotionControlLib Tab. 2.4).
        error_id: the error that ended the command (0 = none).
        velocity: commanded speed, for blending [u/s]; 0 for commands that cannot be blended.
        target: end position [u]; None for commands that do not end at a position.
        t0: simulated time at which the command's profile starts [s].
    """

    state = AxisState.DiscreteMotion
    end_state = AxisState.StandStill
    """State of the axis when the command ends with nothing queued behind it."""
    blendable = False
    ignores_limit_switches = False
    accepts_buffered = True
    """A buffered or blending command may queue behind this one (not behind MC_GearIn)."""
    overridable = False
    """The command follows MC_SetOverride (its profile time is scaled, :mod:`mcl.time_scale`)."""

    def __init__(self, buffer_mode: MC_BufferMode = MC_BufferMode.Aborting) -> None:
        self.buffer_mode = buffer_mode
        self.status = Status.Queued
        self.signal = False
        self.error_id = 0
        self.velocity = 0.0
        self.target: float | None = None
        self.t0 = 0.0

    @property
    def busy(self) -> bool:
        """Queued or active."""
        return self.status <= Status.Active

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        """Take over the axis from the model state (p, v, a); ``v_end``: blending velocity [u/s].

        Raises:
            trajectory.PlanningError: the motion cannot be planned.
        """
        raise NotImplementedError

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        """Model position, velocity, acceleration ``t`` seconds after ``t0``; may set ``signal``."""
        raise NotImplementedError

    def finished(self) -> bool:
        """The command ends (reports Done) once its signal is reached."""
        return self.signal

    def handover_state(
        self, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float, float]:
        """When (seconds after ``t0``) and in which model state the signal was reached.

        ``t`` and (p, v, a) are the current servo instant and set point; a successor starts
        from the returned state at the returned time, so blending is exact to the sub-cycle.
        """
        return t, p, v, a

    def rebase(self, delta: float) -> None:
        """The axis coordinate moved by ``delta`` [u] while this command runs (a gearing block
        zeroes its master): the motion goes on physically unchanged. Commands that read the
        axis state every cycle need nothing."""


class ProfileCommand(Command):
    """A command that follows one planned profile."""

    def __init__(self, buffer_mode: MC_BufferMode, limits: Limits) -> None:
        super().__init__(buffer_mode)
        self.limits = limits
        self.velocity = limits.velocity
        self.profile: Profile | None = None

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        profile = self.profile
        assert profile is not None
        if t >= profile.duration:
            self.signal = True
        return profile.at(t)

    def handover_state(
        self, t: float, p: float, v: float, a: float
    ) -> tuple[float, float, float, float]:
        profile = self.profile
        assert profile is not None
        return (profile.duration, *profile.at(profile.duration))

    def rebase(self, delta: float) -> None:
        if self.profile is not None:
            self.profile = self.profile.shifted(delta)
        if self.target is not None:
            self.target += delta


class MoveTo(ProfileCommand):
    """Discrete move to an absolute model target (MoveAbsolute/Relative/Additive, AbsBlock)."""

    blendable = True
    overridable = True

    def __init__(self, buffer_mode: MC_BufferMode, limits: Limits, target: float) -> None:
        super().__init__(buffer_mode, limits)
        self.target = target

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self.plan(p, v, a, v_end)

    def plan(self, p: float, v: float, a: float, v_end: float) -> None:
        """(Re)plan from the model state to the target, ending with ``v_end`` [u/s]."""
        assert self.target is not None
        if v_end == 0.0:
            self.profile = trajectory.move_to(p, v, a, self.target, self.limits)
        else:
            self.profile = trajectory.blend_to(p, v, a, self.target, self.limits, v_end)


class MoveContinuous(MoveTo):
    """Move to an absolute model target that passes it with ``end_velocity`` and goes on at it
    (MC_MoveContinuousAbsolute/Relative); never ends by itself, ``signal`` = InEndVelocity.

    ContinuousMotion from the start (PLCopen: it will not stop by itself). Its end velocity is
    its own: a blending successor does not change it (not blendable as the first of two)."""

    state = AxisState.ContinuousMotion
    blendable = False

    def __init__(
        self, buffer_mode: MC_BufferMode, limits: Limits, target: float, end_velocity: float
    ) -> None:
        super().__init__(buffer_mode, limits, target)
        self.end_velocity = end_velocity

    def plan(self, p: float, v: float, a: float, v_end: float) -> None:
        assert self.target is not None
        self.profile = trajectory.pass_at(p, v, a, self.target, self.limits, self.end_velocity)

    def finished(self) -> bool:
        return False


class MoveVelocity(ProfileCommand):
    """Never-ending motion at a velocity; ``signal`` = InVelocity."""

    state = AxisState.ContinuousMotion
    overridable = True

    def __init__(self, buffer_mode: MC_BufferMode, limits: Limits, velocity: float) -> None:
        super().__init__(buffer_mode, limits)
        self.commanded = velocity
        self.velocity = abs(velocity)

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self.profile = trajectory.velocity_to(p, v, a, self.commanded, self.limits)

    def finished(self) -> bool:
        return False


class Halt(ProfileCommand):
    """Ramp to standstill in DiscreteMotion; may be aborted (MC_Halt)."""

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self.profile = trajectory.stop(p, v, a, self.limits.deceleration, self.limits.jerk)


class Stop(Halt):
    """Ramp to standstill in Stopping; holds the axis there while the FB's Execute is TRUE."""

    state = AxisState.Stopping
    end_state = AxisState.Stopping

    def __init__(self, limits: Limits) -> None:
        super().__init__(MC_BufferMode.Aborting, limits)
        self.hold = True
        """Mirrors the FB's Execute: the axis leaves Stopping when done and not held."""


class Hold(Command):
    """Keeps the model at a position with zero velocity (e.g. after a stop ramp)."""

    def __init__(self, position: float, state: AxisState) -> None:
        super().__init__()
        self.position = position
        self.state = state

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self.position = p

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        return self.position, 0.0, 0.0

    def finished(self) -> bool:
        return False

    def rebase(self, delta: float) -> None:
        self.position += delta


class Deferred(Command):
    """An administrative command in ExecutionMode mcQueued (MC_SetPosition, MC_WriteParameter):
    it waits in the axis queue like a Buffered command and is applied when the command before it
    signals its output (``Done``, ``InVelocity``, ...); it moves nothing, and the command
    before it goes on when nothing else is queued (see :meth:`mcl.axis.Axis.submit_deferred`).
    """

    def __init__(self) -> None:
        super().__init__(MC_BufferMode.Buffered)

    def apply(self, axis: Axis) -> float:
        """Take effect now: set ``status`` (Done, or Error with ``error_id``, nothing changed);
        return how far the axis coordinate moved [u]."""
        raise NotImplementedError

    def moved(self, end: float) -> float:
        """Where a motion that ends at ``end`` [u] before this command ends after it."""
        return end

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        raise AssertionError("a deferred command is applied by the axis, never started")


class CoordinateShift(Deferred):
    """MC_SetPosition in mcQueued: a shift of the axis coordinate, applied in the queue.

    Args:
        position: the new actual position [u], or the distance to add (``relative``).
        relative: ``position`` is a distance added to the coordinate.
    """

    def __init__(self, position: float, relative: bool) -> None:
        super().__init__()
        self.position = position
        self.relative = relative

    def delta(self, actual: float) -> float:
        """How far the coordinate moves when applied at the actual position ``actual`` [u]."""
        return self.position if self.relative else self.position - actual

    def apply(self, axis: Axis) -> float:
        delta = self.delta(axis.actual)
        error = axis.shift_coordinate(delta, queued=False)
        if error:
            self.status, self.error_id = Status.Error, error
            return 0.0
        self.status = Status.Done
        return delta

    def moved(self, end: float) -> float:
        """The actual position is then about the model's (the loop's residual error aside)."""
        return end + self.position if self.relative else self.position


class BlockRelease:
    """How the drive lets go of a mechanical block it has run into (MC_StepBlock, the
    TorqueLimit of GT_MoveAbsBlock): it stops pushing at once and then holds the axis just clear
    of the block, so that no integral action can wind up against it.

    1. Release, for ``AxisConfig.release_time``: the model restarts from the actual position
       of the detection, at rest (or, where the axis is still moving, with ``velocity``, and
       stops on the maximum ramp), and the integral action (Ki and Ki1) is cleared and held at
       zero, so only ``Kp·e`` acts: the compressed block springs the axis back (a load such as
       gravity sags until ``Kp·e`` carries it) and the drive presses with at most Kp times that
       spring-back.
    2. Back off: from where the release left the model, it moves to the in-position window (at
       least two encoder counts) away from the actual position at that instant, away from the
       block, jerk-limited with ``limits``; the full regulator then holds the axis there, clear
       of the block.
    3. ``done`` once the back-off has ended and the axis is within the in-position window.

    Args:
        axis: the blocked axis.
        t: the instant of the detection, on the owning command's time base [s].
        toward: +1 / −1, the side of the block.
        limits: the ramp of the back-off.
        velocity: the actual velocity to stop from [u/s]; 0 for an axis at rest.
    """

    def __init__(
        self, axis: Axis, t: float, toward: float, limits: Limits, velocity: float = 0.0
    ) -> None:
        self.toward = 1.0 if toward > 0.0 else -1.0
        self.limits = limits
        ramp = axis.max_ramp()
        self.ramp = trajectory.stop(axis.actual, velocity, 0.0, ramp.deceleration, ramp.jerk)
        """The model during the release."""
        self.t_start = t
        self.t_end = t + max(axis.config.release_time, self.ramp.duration)
        """When the release ends and the back-off starts [s]."""
        self.profile: Profile | None = None
        self.done = False
        if axis.regulator is not None:
            axis.regulator.clear_integral()

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        """Model position, velocity, acceleration at ``t`` (the owning command's time base)."""
        profile = self.profile
        if profile is None:
            p, v, a = self.ramp.at(t - self.t_start)
            if t < self.t_end:
                if axis.regulator is not None:
                    axis.regulator.clear_integral()
                return p, v, a
            config = axis.config
            backoff = max(config.in_position, 2.0 * config.resolution)
            target = axis.actual - self.toward * backoff
            self.t_end = t
            profile = trajectory.move_to(p, 0.0, 0.0, target, self.limits)
            self.profile = profile
        p, v, a = profile.at(t - self.t_end)
        if (
            not self.done
            and t - self.t_end >= profile.duration
            and abs(p - axis.actual) <= axis.config.in_position
        ):
            self.done = True
        return p, v, a

    def rebase(self, delta: float) -> None:
        """The axis coordinate moved by ``delta`` [u]: the motion goes on physically unchanged."""
        self.ramp = self.ramp.shifted(delta)
        if self.profile is not None:
            self.profile = self.profile.shifted(delta)


def blend_velocity(
    mode: MC_BufferMode, v1: float, v2: float, direction1: float, direction2: float
) -> float:
    """Signed velocity at which a first motion hands over to a blending second one [u/s].

    Args:
        mode: the second command's BufferMode.
        v1, v2: commanded speeds of the first and the second motion [u/s].
        direction1, direction2: +1/−1/0, directions of the two motions; a reversal (or a motion
            of zero length) hands over at standstill.
    """
    if mode < MC_BufferMode.BlendingLow or direction1 == 0.0 or direction1 != direction2:
        return 0.0
    if mode == MC_BufferMode.BlendingLow:
        speed = min(v1, v2)
    elif mode == MC_BufferMode.BlendingPrevious:
        speed = v1
    elif mode == MC_BufferMode.BlendingNext:
        speed = v2
    else:
        speed = max(v1, v2)
    return direction1 * speed

"""The time scaling behind MC_SetOverride: how an override factor acts on an axis' motion.

An overridden command is planned as usual, in its own *profile time*; while it runs, its profile
time advances by ``f·dt`` per servo cycle instead of ``dt``, with ``f`` the applied factor. The
axis thus follows the planned path exactly (the move still ends at its target), at ``f`` times the
planned velocity, ``f²`` times the acceleration and ``f³`` times the jerk. ``f`` = 0 freezes the
profile: the axis stands on its path and goes on when the factor rises again.

A change of the factor is ramped: ``f`` moves toward the commanded factor by at most
:func:`ramp_rate` per second, so the set-point velocity never jumps (its change from the ramp is
at most the axis' default deceleration).
"""

from __future__ import annotations

__all__ = ["MAX_FACTOR", "TimeScale", "ramp_rate"]

from typing import TYPE_CHECKING

from mcl import handover

if TYPE_CHECKING:
    from mcl.axis import Axis
    from mcl.command import Command

MAX_FACTOR = 2.0
"""The largest velocity factor MC_SetOverride accepts (200 %)."""


def ramp_rate(axis: Axis) -> float:
    """How fast the applied factor follows the commanded one [1/s]: the axis' default
    deceleration over its reference velocity ``Vmax``, so a motion at up to ``Vmax`` changes its
    velocity through the ramp by at most that deceleration."""
    constants = axis.constants
    vmax = constants.Vmax if constants is not None else 1.0
    return axis.config.deceleration / vmax


class TimeScale:
    """The override state of one axis while its factor is not 1.0 or still ramping.

    Attributes:
        target: the commanded factor (MC_SetOverride's VelFactor).
        factor: the applied factor, ramping toward ``target``; it matters only while an
            overridable command runs (it is 1.0 when one takes over a motion that was not
            overridden, and ``target`` when one starts from rest).
        profile_v, profile_a: the running command's velocity [u/s] and acceleration [u/s²] in
            its profile time at ``profile_at``, where a successor or a re-plan continues.
        profile_at: the servo instant of ``profile_v`` and ``profile_a`` [s].
    """

    def __init__(self, target: float) -> None:
        self.target = target
        self.factor = 1.0
        self.profile_v = 0.0
        self.profile_a = 0.0
        self.profile_at = -1.0e300

    @property
    def idle(self) -> bool:
        """Factor 1.0 commanded and applied: the axis needs no scaling."""
        return self.target == 1.0 and self.factor == 1.0

    def setpoint(self, axis: Axis, cmd: Command, t: float) -> tuple[float, float, float]:
        """The set point of ``axis`` at ``t`` [s] while it runs the overridable ``cmd``: the
        command's profile time scaled by the ramped factor; a successor that takes over in the
        cycle is scaled as well where it is overridable."""
        f, f_dot = self.advance(cmd, t - axis.t_sp, ramp_rate(axis))
        p, v, a = cmd.setpoint(axis, t - cmd.t0)
        if cmd.signal and (axis.queue or cmd.finished()):
            p, v, a = handover.hand_over(axis, cmd, t, p, v, a, f)
            successor = axis.active
            if successor is None or not successor.overridable:
                return p, v, a
            f, f_dot = self.factor, 0.0
        p, v, a = self.to_wall(t, p, v, a, f, f_dot)
        if self.idle:
            axis._time_scale = None
        return p, v, a

    def advance(self, cmd: Command, dt: float, rate: float) -> tuple[float, float]:
        """One servo cycle of ``dt`` [s]: ramp the factor at ``rate`` [1/s] and delay ``cmd``'s
        start so that its profile time advances by the factor's mean over the cycle.

        Returns:
            The applied factor at the end of the cycle and its rate of change [1/s].
        """
        f0 = self.factor
        step = rate * dt
        f1 = min(self.target, f0 + step) if self.target > f0 else max(self.target, f0 - step)
        self.factor = f1
        cmd.t0 += dt * (1.0 - 0.5 * (f0 + f1))
        return f1, (f1 - f0) / dt if dt > 0.0 else 0.0

    def to_wall(
        self, t: float, p: float, v: float, a: float, f: float, f_dot: float
    ) -> tuple[float, float, float]:
        """The set point at servo instant ``t`` from the command's profile-time state (p, v, a),
        with the applied factor ``f`` changing at ``f_dot`` [1/s]; remembers the profile state."""
        self.profile_v, self.profile_a, self.profile_at = v, a, t
        return p, f * v, f * f * a + f_dot * v

    def profile_state(self, t: float) -> tuple[float, float] | None:
        """The running command's profile-time velocity and acceleration at ``t`` (None: it was
        not scaled then)."""
        if self.profile_at == t:
            return self.profile_v, self.profile_a
        return None

    def entry(
        self, overridable: bool, v: float, a: float, profile: tuple[float, float] | None
    ) -> tuple[float, float, float]:
        """The applied factor and the velocity and acceleration a starting command plans from.

        Args:
            overridable: the command follows the override.
            v, a: the set-point velocity [u/s] and acceleration [u/s²] it takes over.
            profile: the same in the profile time of the overridden motion it takes over
                (None: the motion it takes over was not overridden).
        """
        if not overridable:
            return 1.0, v, a
        if v == 0.0 and a == 0.0:
            return self.target, 0.0, 0.0
        if profile is not None:
            return self.factor, profile[0], profile[1]
        return 1.0, v, a

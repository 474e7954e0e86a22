"""The path clock of an axes group: the time scaling behind MC_GroupSetOverride and the feed hold
of MC_GroupInterrupt / MC_GroupContinue.

A group's path is planned in *path time* τ (:mod:`mcl.group`: every element's profile s(τ)); per
servo cycle τ advances by ``f·dt`` with ``f`` the applied factor. The members therefore follow
the planned path point p(s(τ)) exactly, whatever ``f`` does: the contour never changes, a move
still ends at its end point, and ``f`` = 0 holds the group on its path. The wall-clock
kinematics are v = f·v_τ and a = f²·a_τ + ḟ·v_τ.

MC_GroupSetOverride's AccFactor and JerkFactor limit the path's acceleration and jerk to those
factors of the planned ones: as ``f`` scales them by f² and f³, the override's factor is
``min(VelFactor, √AccFactor, ∛JerkFactor)`` (:attr:`PathClock.scale`): a lower AccFactor or
JerkFactor also lowers the path velocity (time scaling keeps the planned profile's shape), and
a VelFactor above 1 takes full effect only with AccFactor ≥ VelFactor² and JerkFactor ≥
VelFactor³.

``f`` follows its target (the override's factor, or 0 while held) along a jerk-limited ramp: its
rate ḟ
is at most D / v_τ and changes by at most J / v_τ per second, with v_τ the path velocity in path
time and D, J the deceleration and jerk of the ramp (the feed hold's inputs, or the members'
defaults for an override change); so the ramp adds at most D to the path acceleration and J to
its jerk (up to 1.5·J in the last servo cycle, where the discrete ramp lands on its target). It
comes to rest on its target without overshoot.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from mcl.geometry import Vector

MAX_FACTOR = 2.0
"""The largest VelFactor MC_GroupSetOverride accepts (200 %); AccFactor up to its square and
JerkFactor up to its cube (the acceleration and the jerk of a path at that factor)."""

_SLOW = 1.0e-9
"""The path velocity below which the factor may change at once [mm/s]."""


class PathClock:
    """Path time and the ramped factor of one group.

    Attributes:
        tau: the path time at the group's last servo instant [s].
        factor: the applied factor f; ``rate`` its derivative ḟ [1/s].
        override: MC_GroupSetOverride's VelFactor.
        acc_factor, jerk_factor: its AccFactor and JerkFactor (> 0).
        held: a feed hold (MC_GroupInterrupt) is in force: the target is 0.
        unscaled: a stop that ignores the override runs (MC_GroupStop, a disable, a member
            fault): the target is 1 until the group stands.
        deceleration, jerk: the ramp's bounds along the path [mm/s²], [mm/s³].
    """

    def __init__(self) -> None:
        self.tau = 0.0
        self.factor = 1.0
        self.rate = 0.0
        self.override = 1.0
        self.acc_factor = 1.0
        self.jerk_factor = 1.0
        self.held = False
        self.unscaled = False
        self.deceleration = 1.0
        self.jerk = 1.0

    @property
    def scale(self) -> float:
        """The override's factor: VelFactor, at most √AccFactor and ∛JerkFactor (the path's
        acceleration and jerk follow f² and f³)."""
        return min(self.override, math.sqrt(self.acc_factor), math.pow(self.jerk_factor, 1 / 3))

    @property
    def target(self) -> float:
        """The factor the ramp heads for."""
        if self.unscaled:
            return 1.0
        return 0.0 if self.held else self.scale

    @property
    def at_rest(self) -> bool:
        """The factor stands on its target."""
        return self.factor == self.target and self.rate == 0.0

    def restart(self, t: float) -> None:
        """The group stands: path time restarts at the servo instant ``t`` [s] and a motion that
        starts from rest takes the override at once."""
        self.tau = t
        self.held = self.unscaled = False
        self.factor, self.rate = self.scale, 0.0

    def unscale(self) -> None:
        """Run what follows at factor 1 (a stop that ignores the override; the caller re-plans
        it from the wall-clock state :meth:`wall`); a feed hold ends."""
        self.factor, self.rate = 1.0, 0.0
        self.held = False
        self.unscaled = True

    def advance(self, dt: float, speed: float) -> None:
        """Advance by ``dt`` [s] of wall time with the path velocity ``speed`` [mm/s] in path
        time: ramp the factor toward its target and advance the path time."""
        f0 = self.factor
        err = self.target - f0
        if err == 0.0 and self.rate == 0.0:
            self.tau += f0 * dt
            return
        speed = max(abs(speed), _SLOW)
        most = self.deceleration / speed
        change = self.jerk / speed * dt
        # the fastest rate from which the ramp can still stop on the target when it brakes from
        # the next step on (r²/2q + r·dt = |err|)
        brake = math.sqrt(change * change + 2.0 * self.jerk / speed * abs(err)) - change
        if math.isinf(change):  # no jerk limit: an acceleration-limited ramp
            brake = most
        wanted = math.copysign(min(most, brake), err)
        rate = self.rate + min(max(wanted - self.rate, -change), change)
        f1 = f0 + 0.5 * (self.rate + rate) * dt
        if (self.target - f1) * err <= 0.0 or abs(self.target - f1) < 1.0e-12:
            f1, rate = self.target, 0.0
        self.tau += 0.5 * (f0 + f1) * dt
        self.factor, self.rate = f1, rate

    def wall(self, v: Sequence[float], a: Sequence[float]) -> tuple[Vector, Vector]:
        """Wall-clock velocity and acceleration from those in path time (v_τ, a_τ)."""
        f, rate = self.factor, self.rate
        return (
            [f * x for x in v],
            [f * f * y + rate * x for x, y in zip(v, a, strict=True)],
        )


__all__ = ["MAX_FACTOR", "PathClock"]

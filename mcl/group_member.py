"""The command a group motion runs on each member axis (:mod:`mcl.group`)."""

from __future__ import annotations

__all__ = ["GroupMember"]

from typing import TYPE_CHECKING

from mcl import trajectory
from mcl.axis import Axis
from mcl.command import Command
from mcl.enums import AxisState, MC_BufferMode
from mcl.trajectory import Limits, Profile

if TYPE_CHECKING:
    from mcl.group import AxesGroup


class GroupMember(Command):
    """The command a group move runs on each member axis (axis state SynchronizedMotion).

    Its set point is the member's component of the group's path point; it never ends by itself:
    the group ends it (Done) when the path is complete and nothing is queued, or makes it ramp
    to standstill on its own (:meth:`stop`) when the path can no longer be followed.
    """

    state = AxisState.SynchronizedMotion

    def __init__(self, group: AxesGroup, index: int) -> None:
        super().__init__(MC_BufferMode.Aborting)
        self.group = group
        self.index = index
        self._last = 0.0
        self._v = 0.0
        self._a = 0.0
        self._t = 0.0
        """The last set point [u], its velocity [u/s], acceleration [u/s²] and time [s]."""
        self._stop: Profile | None = None
        self._stop_t0 = 0.0

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self._last, self._v, self._a = p, v, a

    def release(self, position: float | None = None) -> None:
        """End the command at its next set point, which holds ``position`` [mm] (None: the last
        set point)."""
        if position is not None:
            self._last = position
        self.signal = True

    def stop(self, ramp: Limits) -> None:
        """Leave the path: ramp from the last set point to standstill with ``ramp``'s
        deceleration [u/s²] and jerk [u/s³], then end (the velocity never steps)."""
        self._stop = trajectory.stop(self._last, self._v, self._a, ramp.deceleration, ramp.jerk)
        self._stop_t0 = self._t

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        if self.signal:
            return self._last, 0.0, 0.0
        if self._stop is None:
            # the servo instant itself (not t0 + t), so every member reads the same path point
            p, v, a = self.group._setpoint(self.index, axis.t_cycle)
            if self.signal:  # released by this very evaluation: the path stands at its end
                return self._last, 0.0, 0.0
        stop = self._stop
        if stop is not None:  # stopped, perhaps by this very evaluation (a point refused)
            p, v, a = stop.at(t - self._stop_t0)
            self.signal = t - self._stop_t0 >= stop.duration
        self._last, self._v, self._a, self._t = p, v, a, t
        return p, v, a

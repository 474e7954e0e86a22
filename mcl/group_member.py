"""The command a group motion runs on each member axis (:mod:`mcl.group`)."""

from __future__ import annotations

__all__ = ["GroupMember"]

from typing import TYPE_CHECKING

from mcl.axis import Axis
from mcl.command import Command
from mcl.enums import AxisState, MC_BufferMode

if TYPE_CHECKING:
    from mcl.group import AxesGroup


class GroupMember(Command):
    """The command a group move runs on each member axis (axis state SynchronizedMotion).

    Its set point is the member's component of the group's path point; it never ends by itself:
    the group ends it (Done) when the path is complete and nothing is queued.
    """

    state = AxisState.SynchronizedMotion

    def __init__(self, group: AxesGroup, index: int) -> None:
        super().__init__(MC_BufferMode.Aborting)
        self.group = group
        self.index = index
        self._last = 0.0

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self._last = p

    def release(self, position: float | None = None) -> None:
        """End the command at its next set point, which holds ``position`` [mm] (None: the last
        set point)."""
        if position is not None:
            self._last = position
        self.signal = True

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        if not self.signal:
            # the servo instant itself (not t0 + t), so every member reads the same path point
            p, v, a = self.group._setpoint(self.index, axis.t_cycle)
            if not self.signal:  # else released by this very evaluation: the path has ended
                self._last = p
                return p, v, a
        return self._last, 0.0, 0.0  # released: it holds there, at rest

"""Function blocks of axes groups (MotionControlLib chapter 5).

Every block has the in-out ``AxesGroup`` (an :class:`mcl.group.AxesGroup`);
MC_AddAxisToGroup also has ``Axis``. Positions and distances are lists with one value per member
in the order the members were added [mm]; Velocity [mm/s], Acceleration, Deceleration [mm/s²] and
Jerk [mm/s³] act along the path (0 = default, values above what a member allows are clamped).

Beyond the Teco library: MC_GroupEnable, MC_GroupDisable, MC_GroupReset, MC_GroupStop,
MC_MoveLinearRelative (PLCopen Part 4). A group that is not enabled refuses motion commands with
``Epower`` 10; a member change while the group moves is refused with ``EParam`` 5.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

from mcl.command import Status
from mcl.enums import GroupState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB, MotionFB, non_negative, number, positive
from mcl.group import AxesGroup
from mcl.path import PathCommand


def _vector(value: Any, size: int) -> list[float] | None:
    """A list input as floats; None unless a sequence of ``size`` finite numbers."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        return None
    if len(value) != size:
        return None
    numbers = [number(x) for x in value]
    return numbers if all(math.isfinite(x) for x in numbers) else None


class MC_AddAxisToGroup(ExecuteFB):
    """Adds ``Axis`` to ``AxesGroup`` (MotionControlLib §5.1); members keep the order they were
    added in.

    Errors: 1004 the axis already belongs to a group, 1001 the group is full (3 axes),
    Eerrstop 11 in GroupErrorStop, EAxStop 6 in GroupStopping, EParam 5 while the group moves.
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup", "Axis")

    def _begin(self) -> int:
        return self.group.add(self.axis)


class MC_UngroupAllAxes(ExecuteFB):
    """Removes every axis from the group (MotionControlLib §5.2); Done once the group's motion has
    stopped, the group is then GroupDisabled. Errors: 1005 the group has no axes; Eerrstop 11 in
    GroupErrorStop (MotionControlLib Fig. 2.2, note 4)."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self._error = 0

    def _begin(self) -> int:
        return self.group.check_ungroup()

    def _poll(self) -> Status | None:
        group = self.group
        self._error = group.check_ungroup()
        if self._error:
            return Status.Error
        if group.moving:
            return None
        group.ungroup()
        return Status.Done

    def _error_of_poll(self) -> int:
        return self._error


class MC_GroupEnable(ExecuteFB):
    """GroupDisabled → GroupStandby (PLCopen Part 4); 1005 when the group has no axes."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def _begin(self) -> int:
        return self.group.enable()


class MC_GroupDisable(ExecuteFB):
    """→ GroupDisabled in every state but GroupErrorStop (Eerrstop 11) (PLCopen Part 4).

    A running motion is aborted (its blocks report CommandAborted) and ramps to standstill along
    the path with the default deceleration; Done once the group stands.
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def _begin(self) -> int:
        return self.group.disable()

    def _poll(self) -> Status | None:
        return None if self.group.moving else Status.Done


class MC_GroupReset(ExecuteFB):
    """Leaves GroupErrorStop (PLCopen Part 4): resets the members in ErrorStop (as MC_Reset),
    clears GroupErrorID; Done once the group is out of GroupErrorStop (members whose error
    opened the loop are then Disabled). 1005 when the group has no axes."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def _begin(self) -> int:
        return 0 if self.group.axes else ErrorID.EGroupEmpty

    def _poll(self) -> Status | None:
        return Status.Done if self.group.reset() else None


class MC_GroupReadError(EnableFB):
    """Publishes the group error (MotionControlLib §5.3): Valid, Error, ErrorID, GroupErrorID."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.GroupErrorID = 0

    def _evaluate(self) -> int:
        group = self.group
        group.update()
        self.GroupErrorID = group.GroupErrorID
        return 0

    def _disable(self) -> None:
        self.GroupErrorID = 0


class MC_GroupReadStatus(EnableFB):
    """Publishes the group state as flags (MotionControlLib §5.4) and ``InPosition``: the group
    stands and every member is within its in-position window of the end point of the last
    motion."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.GroupDisabled = False
        self.GroupStandby = False
        self.GroupMoving = False
        self.GroupHoming = False
        self.GroupStopping = False
        self.GroupErrorStop = False
        self.InPosition = False

    def _evaluate(self) -> int:
        group = self.group
        group.update()
        self._flags(group.state)
        self.InPosition = group.in_position()
        return 0

    def _flags(self, state: GroupState | None) -> None:
        self.GroupDisabled = state == GroupState.GroupDisabled
        self.GroupStandby = state == GroupState.GroupStandby
        self.GroupMoving = state == GroupState.GroupMoving
        self.GroupHoming = state == GroupState.GroupHoming
        self.GroupStopping = state == GroupState.GroupStopping
        self.GroupErrorStop = state == GroupState.GroupErrorStop

    def _disable(self) -> None:
        self._flags(None)
        self.InPosition = False


class MC_GroupReadActualPosition(EnableFB):
    """Publishes the members' actual positions ``Position`` [mm] (MotionControlLib §5.5), in
    member order; 1005 when the group has no axes."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Position: list[float] = []

    def _evaluate(self) -> int:
        group = self.group
        if not group.axes:
            self.Position = []
            return ErrorID.EGroupEmpty
        self.Position = [axis.POS for axis in group.axes]
        return 0

    def _disable(self) -> None:
        self.Position = []


class _GroupMotionFB(MotionFB):
    """A group motion block: hands a :class:`PathCommand` to the group (the ticket handling of
    :class:`MotionFB`: Active, CommandAborted, restart).

    Subclasses implement :meth:`_submit` (validate the sampled inputs, hand the command over,
    or return an error code).
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def _command(self, mode: MC_BufferMode) -> PathCommand:
        return PathCommand(mode)

    def _submit(self, ticket: PathCommand) -> int:
        raise NotImplementedError

    def _owner(self) -> AxesGroup:
        return self.group

    def _poll(self) -> Status | None:
        self.group.update()
        return super()._poll()


class _MoveLinearFB(_GroupMotionFB):
    """Common inputs of the linear moves: Velocity, Acceleration, Deceleration, Jerk (along the
    path; 0 = default)."""

    INPUTS: ClassVar[tuple[str, ...]] = ("Velocity", "Acceleration", "Deceleration", "Jerk")
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0
    NEEDS_REF: ClassVar[bool] = False

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready()
        if error:
            return error
        v, a = number(self.Velocity), number(self.Acceleration)
        d, j = number(self.Deceleration), number(self.Jerk)
        if not positive(v) or not (non_negative(a) and non_negative(d) and non_negative(j)):
            return ErrorID.EParam
        axes = group.axes
        if any(axis.velocity_too_low(v) for axis in axes):
            return ErrorID.EParam
        limits = group.path_limits([0.0] * len(axes), v, a, d, j)
        if min(limits.acceleration, limits.deceleration) * 100.0 < v:
            return ErrorID.EParam
        target = self._target(group, ticket.buffer_mode)
        if target is None:
            return ErrorID.EParam
        if self.NEEDS_REF and not all(axis.Ref for axis in axes):
            return ErrorID.Ehome
        for axis, x in zip(axes, target, strict=True):
            error = axis.check_target(x)
            if error:
                return error
        group.submit_move(ticket, target, v, a, d, j)
        return 0

    def _target(self, group: AxesGroup, mode: MC_BufferMode) -> list[float] | None:
        raise NotImplementedError


class MC_MoveLinearAbsolute(_MoveLinearFB):
    """Linear interpolation of the group to the absolute point ``Position`` [mm]
    (MotionControlLib §5.6).

    The tool point stays on the straight line from the start point; all buffer modes
    (Blending*: the corner is rounded within the group's corner tolerance). Needs Ref on every
    member (Ehome 9); a target beyond a member's SW limit → Ecil 8; a Position that is not a list
    of finite numbers, one per member → EParam 5.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Position",)
    Position: Sequence[float] = ()
    NEEDS_REF: ClassVar[bool] = True

    def _target(self, group: AxesGroup, mode: MC_BufferMode) -> list[float] | None:
        return _vector(self.Position, len(group.axes))


class MC_MoveLinearRelative(_MoveLinearFB):
    """Linear interpolation of the group by ``Distance`` [mm] (PLCopen Part 4).

    The distance counts from the current path point when the move aborts (the actual positions
    when the group stands), from the end of the last queued move otherwise. No Ref needed.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Distance",)
    Distance: Sequence[float] = ()

    def _target(self, group: AxesGroup, mode: MC_BufferMode) -> list[float] | None:
        distance = _vector(self.Distance, len(group.axes))
        if distance is None:
            return None
        start = group.start_point(mode)
        return [s + d for s, d in zip(start, distance, strict=True)]


class MC_GroupStop(_GroupMotionFB):
    """Stops the group (PLCopen Part 4): the path velocity ramps to zero along the path with
    ``Deceleration`` [mm/s²] and ``Jerk`` [mm/s³] (0 = default); GroupStopping until Done AND NOT
    Execute, and no other group motion is accepted meanwhile (EAxStop 6)."""

    INPUTS: ClassVar[tuple[str, ...]] = ("Deceleration", "Jerk")
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def _scanned(self) -> None:
        """The group leaves GroupStopping once Done and Execute is FALSE."""
        if isinstance(self._cmd, PathCommand):
            self._cmd.hold = bool(self.Execute)

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready(stopping_ok=True)
        if error:
            return error
        d, j = number(self.Deceleration), number(self.Jerk)
        if not (non_negative(d) and non_negative(j)):
            return ErrorID.EParam
        ticket.hold = bool(self.Execute)
        group.submit_stop(ticket, d, j)
        return 0


__all__ = [
    "MC_AddAxisToGroup",
    "MC_GroupDisable",
    "MC_GroupEnable",
    "MC_GroupReadActualPosition",
    "MC_GroupReadError",
    "MC_GroupReadStatus",
    "MC_GroupReset",
    "MC_GroupStop",
    "MC_MoveLinearAbsolute",
    "MC_MoveLinearRelative",
    "MC_UngroupAllAxes",
]

"""Control blocks of axes groups (PLCopen Part 4 v2.0): halt, feed hold, override, coordinate
shift and read-outs.

The override and the feed hold act on the group's path clock (:mod:`mcl.path_clock`): the path
is planned in path time, which advances by the applied factor f per unit of time, so the members
follow the commanded contour exactly at any factor, a move still ends at its end point, and
f = 0 holds the group on its path. Changes of f are ramped (jerk-limited).

MC_GroupInterrupt holds the path (f → 0, on the path, with its Deceleration and Jerk) without
ending the interrupted command: its block stays Busy and Active, CommandAborted stays FALSE.
Once the group stands the interrupt is Done and the group reads GroupStandby (PLCopen Part 4 has
no Interrupted state; the members stay in SynchronizedMotion, holding the path point in closed
loop). While held, motion blocks, MC_GroupHalt, MC_GroupInterrupt, MC_AddAxisToGroup and
MC_GroupSetPosition are refused (EAxStop 6, EParam 5 for the administrative ones); only
MC_GroupStop (and MC_GroupDisable, or a member's fault) ends an interrupt, and ends the held
commands (CommandAborted). MC_GroupContinue resumes the path from the held point (f ramps back to
the override with the interrupt's Deceleration and Jerk) to the same end.

MC_GroupStop, MC_GroupDisable and a member's fault stop the path unaffected by the override
(their ramp starts from the actual path velocity at factor 1); MC_GroupHalt's ramp and the moves
run on the path clock.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

from mcl.axis import Axis
from mcl.command import Status
from mcl.enums import MC_COORD_SYSTEM, AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB, FunctionBlock, MotionFB, integer, non_negative, number
from mcl.group import AxesGroup
from mcl.group_fb import COORD_SYSTEMS, GroupMotionFB, _vector
from mcl.kinematics import KinematicsError
from mcl.path import PathCommand
from mcl.path_clock import MAX_FACTOR
from mcl.software_limits import shift_refused


def _ramp_inputs(deceleration: float, jerk: float) -> tuple[float, float] | None:
    """Deceleration and Jerk inputs when valid (finite, >= 0; 0 = default), else None."""
    d, j = number(deceleration), number(jerk)
    return (d, j) if non_negative(d) and non_negative(j) else None


class MC_GroupHalt(GroupMotionFB):
    """Stops the group's path like MC_GroupStop, but as an ordinary motion (PLCopen Part 4): the
    path velocity ramps to zero along the path with ``Deceleration`` [mm/s²] and ``Jerk``
    [mm/s³] (0 = default), on the path clock (the override acts on it); the group stays
    GroupMoving meanwhile, another move may abort the halt, and the group is GroupStandby once it
    stands (Done). Aborts every running and queued group command. Errors: those of the moves
    (group disabled Epower 10, GroupErrorStop Eerrstop 11, GroupStopping or a feed hold EAxStop
    6); Deceleration or Jerk negative or not finite, a BufferMode other than Aborting → EParam 5.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Deceleration", "Jerk")
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready()
        if error:
            return error
        ramp = _ramp_inputs(self.Deceleration, self.Jerk)
        if ramp is None or ticket.buffer_mode != MC_BufferMode.Aborting:
            return ErrorID.EParam
        group.submit_stop(ticket, ramp[0], ramp[1], halt=True)
        return 0


class _HoldFB(ExecuteFB):
    """An edge-triggered block of the feed hold with CommandAborted (MC_GroupStop, a disable or
    a member's fault ended the hold before the block was Done)."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def __init__(self, **inputs: Any) -> None:
        self.CommandAborted = False
        super().__init__(**inputs)

    def _show_more(self, visible: bool, final: Status | None) -> None:
        self.CommandAborted = visible and final == Status.Aborted


class MC_GroupInterrupt(_HoldFB):
    """Feed hold (PLCopen Part 4): the group slows down on its path to a standstill (the path
    clock's factor ramps to 0 with ``Deceleration`` [mm/s²] and ``Jerk`` [mm/s³] along the
    path, 0 = default) without ending the interrupted command, which stays Busy and Active;
    Done once the group stands (GroupStandby; with nothing to hold: at once). MC_GroupContinue
    resumes the path. CommandAborted: MC_GroupStop, MC_GroupDisable or a member's fault ended
    the hold first. Errors: as the moves (Epower 10, Eerrstop 11, EAxStop 6 in GroupStopping or
    already held); Deceleration or Jerk negative or not finite → EParam 5.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Deceleration", "Jerk")
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def _begin(self) -> int:
        ramp = _ramp_inputs(self.Deceleration, self.Jerk)
        if ramp is None:
            return ErrorID.EParam
        return interrupt(self.group, ramp[0], ramp[1])

    def _poll(self) -> Status | None:
        group = self.group
        group.update()
        if group.interrupted:
            return Status.Done if group.clock.at_rest else None
        if group.moving or group.stopping:  # the hold was ended by a stop
            return Status.Aborted
        return Status.Done  # nothing held, or the path ended during the ramp


def interrupt(group: AxesGroup, deceleration: float, jerk: float) -> int:
    """Hold the path of ``group`` (the clock's factor ramps to 0 with ``deceleration``
    [mm/s²] and ``jerk`` [mm/s³] along it, 0 = defaults) without ending its commands; the error
    code of :meth:`AxesGroup.check_ready` (EAxStop 6 while held already). A standing group has
    nothing to hold."""
    error = group.check_ready()
    if error or not group.has_path:
        return error
    limits = group.nominal_limits(1.0, 0.0, deceleration, jerk)
    group.clock.deceleration, group.clock.jerk = limits.deceleration, limits.jerk
    group.clock.held = True
    return 0


class MC_GroupContinue(_HoldFB):
    """Resumes a path held by MC_GroupInterrupt (PLCopen Part 4): from the held point the path
    clock's factor ramps back to the override (with the interrupt's Deceleration and Jerk), and
    the interrupted commands go on to their ends. Done once the path runs at the override again
    (or has ended); CommandAborted when it is interrupted again, or MC_GroupStop,
    MC_GroupDisable or a member's fault stops it first. Errors: the group holds no path →
    EParam 5.
    """

    def _begin(self) -> int:
        group = self.group
        group.update()
        if not group.interrupted:
            return ErrorID.EParam
        group.clock.held = False
        return 0

    def _poll(self) -> Status | None:
        group = self.group
        group.update()
        if group.interrupted or group.stopping or group.clock.unscaled:
            return Status.Aborted  # held again, or a stop, a disable or a fault took over
        if not group.moving or group.clock.at_rest:
            return Status.Done
        return None


class MC_GroupSetOverride(FunctionBlock):
    """Sets the group's override (PLCopen Part 4): its path runs at ``VelFactor`` (1.0 = 100 %,
    0 … 2.0) times the planned velocity, on the same contour (:mod:`mcl.path_clock`); a change is
    ramped with the members' default deceleration and jerk along the path, a motion that starts
    from rest takes the factor at once. VelFactor 0 holds the path without ending its commands
    (the group reads GroupMoving).

    Level-sensitive: while ``Enable`` is TRUE the factor is written in every call; with
    ``Enable`` FALSE the group keeps the last one. ``Enabled`` and ``Busy`` while the group
    follows this block's factors. ``AccFactor`` and ``JerkFactor`` limit the path's acceleration
    and jerk to those factors of the planned ones: the path runs at min(VelFactor, √AccFactor,
    ∛JerkFactor) (with time scaling the acceleration follows the factor squared, the jerk
    cubed; a lower AccFactor or JerkFactor therefore lowers the velocity too), and a change is
    ramped with the members' default deceleration × AccFactor and jerk × JerkFactor. VelFactor
    negative, not finite or above 2.0, AccFactor not in ]0, 4.0], JerkFactor not in ]0, 8.0]
    → EParam 5 (the group keeps its factors); no members → 1005.
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("Enable", "VelFactor", "AccFactor", "JerkFactor")
    Enable: bool = False
    VelFactor: float = 1.0
    AccFactor: float = 1.0
    JerkFactor: float = 1.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Enabled = False
        self.Busy = False
        self.Error = False
        self.ErrorID = 0

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan: while Enable, write the factor to the group."""
        self._scan(inputs)
        error = self._write() if self.Enable else 0
        self.Enabled = self.Busy = bool(self.Enable) and not error
        self.Error = bool(error)
        self.ErrorID = error

    def _write(self) -> int:
        group = self.group
        if not group.axes:
            return ErrorID.EGroupEmpty
        vel, acc, jerk = number(self.VelFactor), number(self.AccFactor), number(self.JerkFactor)
        if not (non_negative(vel) and vel <= MAX_FACTOR):
            return ErrorID.EParam
        if not (0.0 < acc <= MAX_FACTOR**2 and 0.0 < jerk <= MAX_FACTOR**3):
            return ErrorID.EParam
        clock = group.clock
        if (vel, acc, jerk) != (clock.override, clock.acc_factor, clock.jerk_factor):
            set_override(group, vel, acc, jerk)
        return 0


def set_override(group: AxesGroup, factor: float, acc: float, jerk: float) -> None:
    """The path of ``group`` runs at ``factor`` times its planned velocity, its acceleration
    within ``acc`` and its jerk within ``jerk`` times the planned ones (:attr:`PathClock.scale`);
    ramped with the members' default deceleration × ``acc`` and jerk × ``jerk`` (a feed hold
    keeps its own ramp)."""
    clock = group.clock
    if not clock.held:
        limits = group.nominal_limits(1.0, 0.0, 0.0, 0.0)
        clock.deceleration, clock.jerk = limits.deceleration * acc, limits.jerk * jerk
    # a motion that starts from rest takes them at once (restart)
    clock.override, clock.acc_factor, clock.jerk_factor = factor, acc, jerk


class MC_GroupSetPosition(ExecuteFB):
    """Shifts the group's coordinates without motion (PLCopen Part 4): every member's coordinate
    moves so that its actual position becomes ``Position[i]`` [mm], or with ``Relative`` TRUE
    by ``Position[i]`` (as MC_SetPosition on each member, all or none). ``CoordSystem``: ACS,
    MCS and PCS coincide; a group with a kinematic transformation takes only ACS (the members'
    coordinates; MCS or PCS → EParam 5). Done in the scan of the edge.

    Only while the group's path neither runs nor is held and every member is at rest (StandStill
    or Disabled): else EParam 5 (GroupMoving, GroupHoming, a held path), Eerrstop 11 in
    GroupErrorStop, EAxStop 6 in GroupStopping. A member that would lie beyond an active SW
    limit → Ecil 8; no members → 1005; a Position that is not a list of finite numbers, one per
    member, or an unknown CoordSystem → EParam 5. A refused call leaves the group as it was.
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("Position", "Relative", "CoordSystem")
    Position: Sequence[float] = ()
    Relative: bool = False
    CoordSystem: int = MC_COORD_SYSTEM.MCS

    def _begin(self) -> int:
        group = self.group
        if not group.axes:
            return ErrorID.EGroupEmpty
        position = _vector(self.Position, len(group.axes))
        if position is None or self.CoordSystem not in COORD_SYSTEMS:
            return ErrorID.EParam
        if group.kin.transform is not None and self.CoordSystem != MC_COORD_SYSTEM.ACS:
            return ErrorID.EParam
        if self.Relative:
            deltas = position
        else:
            deltas = [p - axis.actual for p, axis in zip(position, group.axes, strict=True)]
        return set_position(group, deltas)


def set_position(group: AxesGroup, deltas: Sequence[float]) -> int:
    """Shift every member's coordinate by ``deltas`` [mm] (MC_GroupSetPosition's checks and
    errors), or return the error that refuses it without changing anything."""
    error = group.busy_error()
    if error:
        return error
    rest = (AxisState.StandStill, AxisState.Disabled)
    if group.interrupted or any(axis.state not in rest for axis in group.axes):
        return ErrorID.EParam
    for axis, delta in zip(group.axes, deltas, strict=True):
        error = shift_refused(axis, delta, True)
        if error:
            return error
    for axis, delta in zip(group.axes, deltas, strict=True):
        axis.shift_coordinate(delta)
    group.shift_end(deltas)
    return 0


class _GroupReadFB(EnableFB):
    """A read-out of the members: in ACS theirs, in MCS and PCS the tool point's through the
    group's kinematic transformation (without one they coincide); 1005 when the group has no
    axes, EParam 5 for an unknown CoordSystem, EWorkspace 24 / ESingular 25 where the
    kinematics has no tool point."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("CoordSystem",)
    CoordSystem: int = MC_COORD_SYSTEM.MCS

    def _check(self) -> int:
        if not self.group.axes:
            return ErrorID.EGroupEmpty
        return 0 if self.CoordSystem in COORD_SYSTEMS else ErrorID.EParam

    def _state(
        self, q: list[float], qd: list[float], qdd: list[float]
    ) -> tuple[list[float], list[float]]:
        """Velocity and acceleration of the members moving at ``qd``, ``qdd`` from ``q`` in the
        block's CoordSystem.

        Raises:
            KinematicsError: the kinematics has no tool point there.
        """
        kin = self.group.kin
        if kin.transform is None or self.CoordSystem == MC_COORD_SYSTEM.ACS:
            return qd, qdd
        _, v, a = kin.cartesian_state(q, qd, qdd)
        return v, a


def _norm(vector: Sequence[float]) -> float:
    return math.sqrt(sum(x * x for x in vector))


class MC_GroupReadActualVelocity(_GroupReadFB):
    """Publishes the members' actual velocities ``Velocity`` [mm/s] (their filtered ``VEL``, in
    member order; in MCS of a group with a kinematic transformation the tool point's velocity
    they give) and ``PathVelocity``, the length of that vector [mm/s] (PLCopen Part 4)."""

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Velocity: list[float] = []
        self.PathVelocity = 0.0

    def _evaluate(self) -> int:
        error = self._check()
        if error:
            self._disable()
            return error
        axes = self.group.axes
        velocity = [axis.VEL for axis in axes]
        try:
            self.Velocity = self._state([a.POS for a in axes], velocity, [0.0] * len(axes))[0]
        except KinematicsError as refused:
            self._disable()
            return int(refused.error_id)
        self.PathVelocity = _norm(self.Velocity)
        return 0

    def _disable(self) -> None:
        self.Velocity = []
        self.PathVelocity = 0.0


class MC_GroupReadActualAcceleration(_GroupReadFB):
    """Publishes the members' accelerations ``Acceleration`` [mm/s²] in member order and
    ``PathAcceleration``, the rate of change of the path velocity (the acceleration along the
    direction of motion; 0 at rest) [mm/s²] (PLCopen Part 4). The library measures no
    acceleration: these are the set-point accelerations the members' loops follow (in MCS of a
    group with a kinematic transformation the tool point's acceleration they give)."""

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Acceleration: list[float] = []
        self.PathAcceleration = 0.0

    def _evaluate(self) -> int:
        error = self._check()
        if error:
            self._disable()
            return error
        axes = self.group.axes
        q = [axis.sp_pos for axis in axes]
        try:
            velocity, self.Acceleration = self._state(
                q, [axis.sp_vel for axis in axes], [axis.sp_acc for axis in axes]
            )
        except KinematicsError as refused:
            self._disable()
            return int(refused.error_id)
        speed = _norm(velocity)
        along = sum(a * v for a, v in zip(self.Acceleration, velocity, strict=True))
        self.PathAcceleration = along / speed if speed > 1.0e-9 else 0.0
        return 0

    def _disable(self) -> None:
        self.Acceleration = []
        self.PathAcceleration = 0.0


class MC_GroupReadConfiguration(_GroupReadFB):
    """Publishes the member ``IdentInGroup`` (1 = the first added, in the order of
    MC_AddAxisToGroup) as the output ``Member`` (PLCopen Part 4 names it Axis, which is the
    in-out of the axis blocks here); an IdentInGroup that names no member → EParam 5
    (``Member`` None)."""

    INPUTS: ClassVar[tuple[str, ...]] = ("IdentInGroup",)
    IdentInGroup: int = 1

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Member: Axis | None = None

    def _evaluate(self) -> int:
        error = self._check()
        axes = self.group.axes
        ident = integer(self.IdentInGroup)
        if not error and not 1 <= ident <= len(axes):
            error = ErrorID.EParam
        self.Member = None if error else axes[ident - 1]
        return error

    def _disable(self) -> None:
        self.Member = None


class MC_GroupHome(ExecuteFB):
    """Homes every member of the group (PLCopen Part 4, whose homing procedure is the vendor's):
    each member runs its own homing procedure, a sequence of this library's homing step blocks
    (:mod:`mcl.homing`: MC_StepAbsSwitch, MC_StepLimitSwitch, MC_StepBlock, MC_StepRefPulse,
    MC_StepDirect, MC_StepAbsolute, MC_FinishHoming) with their inputs bound, the later ones
    Buffered as in a single-axis procedure. ``Steps`` holds one such sequence per member, in
    member order; the block connects each step to its member and calls them every scan with
    Execute TRUE, all members at once (the group is GroupHoming meanwhile). Done once every
    member's last step is Done (the members then have Ref, the group is GroupStandby).

    Only from GroupStandby: errors of the moves (1005, Epower 10, Eerrstop 11, EAxStop 6) and
    EParam 5 while the group moves, homes or holds a path; Steps not one non-empty sequence of
    homing step blocks per member (a block used twice included) → EParam 5. A step's error ends
    the block with that step's ErrorID; the other members' steps run on to their ends. PLCopen's
    Position and HomingMode are the steps' own inputs here (SetPosition, the kind of step).
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("Steps",)
    Steps: Sequence[Sequence[MotionFB]] = ()

    def __init__(self, **inputs: Any) -> None:
        self._steps: list[list[MotionFB]] = []
        self._error = 0
        super().__init__(**inputs)

    def _begin(self) -> int:
        group = self.group
        self._steps = []
        error = group.check_ready() or group.busy_error()
        if error:
            return error
        steps = _homing_steps(self.Steps, len(group.axes))
        if steps is None:
            return ErrorID.EParam
        self._steps = steps
        self._call(False)  # a rising edge for every step
        return self._poll_error()

    def _poll(self) -> Status | None:
        self._call(True)
        error = self._poll_error()
        if error:
            return Status.Error
        self._error = 0
        if all(sequence[-1].Done for sequence in self._steps):
            self._call(False)
            return Status.Done
        return None

    def _poll_error(self) -> int:
        """The first step's error (0 = none), kept for :meth:`_error_of_poll`."""
        for sequence in self._steps:
            for step in sequence:
                if step.Error:
                    self._error = step.ErrorID
                    return self._error
        return 0

    def _error_of_poll(self) -> int:
        return self._error

    def _call(self, execute: bool) -> None:
        """One scan of every member's steps (their homing not refused as group members')."""
        for axis, sequence in zip(self.group.axes, self._steps, strict=True):
            axis.group_homing = True
            try:
                for step in sequence:
                    step(Axis=axis, Execute=execute)
            finally:
                axis.group_homing = False


def _homing_steps(value: Any, size: int) -> list[list[MotionFB]] | None:
    """MC_GroupHome's Steps as lists, or None unless one non-empty sequence of distinct homing
    step blocks per member."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence) or len(value) != size:
        return None
    result: list[list[MotionFB]] = []
    seen: list[MotionFB] = []
    for sequence in value:
        if isinstance(sequence, str | bytes) or not isinstance(sequence, Sequence):
            return None
        steps = list(sequence)
        if not steps or not all(_is_homing_step(step) for step in steps):
            return None
        if any(any(step is other for other in seen) for step in steps) or len(
            {id(step) for step in steps}
        ) != len(steps):
            return None
        seen.extend(steps)
        result.append(steps)
    return result


def _is_homing_step(step: object) -> bool:
    return isinstance(step, MotionFB) and type(step).__module__ == "mcl.homing"


__all__ = [
    "MC_GroupContinue",
    "MC_GroupHalt",
    "MC_GroupHome",
    "MC_GroupInterrupt",
    "MC_GroupReadActualAcceleration",
    "MC_GroupReadActualVelocity",
    "MC_GroupReadConfiguration",
    "MC_GroupSetOverride",
    "MC_GroupSetPosition",
    "interrupt",
    "set_override",
    "set_position",
]

"""Axes groups: AXES_GROUP_REF, the group state machine and the running of the group path.

MotionControlLib chapters 2.2–2.3 (Fig. 2.2, Tab. 2.1) and 5, PLCopen Part 4; docs/reference.md,
Axes groups and BufferMode.

An :class:`AxesGroup` holds up to three axes in the order they were added. A group motion is a
queue of path elements (:mod:`mcl.path`; shapes in :mod:`mcl.geometry`, planning in
:mod:`mcl.path_planner`), each run along a 1-D jerk-limited profile of its arc length, so the
tool point stays on the commanded path; consecutive elements may blend at their corners.

While the group moves every member runs a :class:`GroupMember` command (SynchronizedMotion):
its set point is its component of the path point, computed once per servo instant. The member
commands stay active across elements; the group ends them when the path is complete and nothing
is queued (while a PCS moves the path then rests in it: :mod:`mcl.coordinate_system`).

Aborting while moving: :meth:`AxesGroup.submit`. MC_GroupStop, MC_GroupDisable and member
faults ramp the path velocity to zero on the path (:func:`mcl.path.stop_element`), ignoring the
override; a point the kinematics refuses stops each member on its own fastest ramp.

Member faults are acted on by :meth:`AxesGroup.update` (every path evaluation and the group
blocks); reading :attr:`AxesGroup.state` never changes the group.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from typing import Final

from mcl.axis import Axis
from mcl.command import Status
from mcl.enums import AxisState, GroupState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.geometry import EPS, GeometryError, Line, Vector, along, direction, dot
from mcl.geometry import distance_to_segment as distance_to_segment
from mcl.group_kinematics import GroupKinematics, refusal
from mcl.group_member import GroupMember
from mcl.kinematics import KinematicsError
from mcl.path import Blend, Element, Move, PathCommand, stop_element
from mcl.path_clock import PathClock
from mcl.path_planner import PathPlanner
from mcl.trajectory import Limits, PlanningError, Profile

_MOTION_STATES: Final = frozenset(
    {AxisState.DiscreteMotion, AxisState.ContinuousMotion, AxisState.SynchronizedMotion}
)


class AxesGroup:
    """AXES_GROUP_REF: up to three axes moved together along a path of lines and arcs.

    The state (:attr:`state`) is derived each time it is read from the group's own flags and its
    members' states (MotionControlLib Tab. 2.1, chapter 2.3); reading it changes nothing:

    - GroupDisabled until MC_GroupEnable and after MC_GroupDisable / MC_UngroupAllAxes;
    - GroupErrorStop while a member is in ErrorStop or :attr:`GroupErrorID` is set (a member
      fault during a group motion latches ERRPOSG 8001 for a following error 2001, else the
      member's error; a member's 2001 in the error stop replaces it by 8001); left only
      through MC_GroupReset;
    - GroupStopping from MC_GroupStop until its Done AND NOT Execute (or a member in Stopping);
    - GroupHoming while a member is homing;
    - GroupMoving while a group command runs or a member moves by a command;
    - GroupStandby otherwise (all members StandStill, or the path held by MC_GroupInterrupt).

    Args:
        name: the group's name in messages.
        corner_tolerance: largest distance of the blended path from the commanded path at a
            corner [mm] (corner blending: :mod:`mcl.path`).

    Attributes:
        GroupErrorID: the group error (0 = none; 8001 ERRPOSG, or the member's error).
        axes: the members in the order they were added.
    """

    MAX_AXES: Final = 3

    def __init__(self, name: str = "group", corner_tolerance: float = 0.05) -> None:
        if not (math.isfinite(corner_tolerance) and corner_tolerance > 0.0):
            raise ValueError(
                f"corner_tolerance must be a finite number > 0, got {corner_tolerance}"
            )
        self.name = name
        self.corner_tolerance = corner_tolerance
        self.axes: list[Axis] = []
        self.enabled = False
        self.GroupErrorID = 0
        self._members: list[GroupMember | None] = []
        self._active: Element | None = None
        self._queue: deque[Element] = deque()
        self._stop: PathCommand | None = None
        self._t = -math.inf
        """Time of the cached path state [s]."""
        self._p: Vector = []
        self._v: Vector = []
        self._a: Vector = []
        self._end: Vector | None = None
        """Where the last motion ended (InPosition) [mm]."""
        self.clock = PathClock()
        """Path time, override and feed hold (:mod:`mcl.path_clock`)."""
        self.kin = GroupKinematics()
        """The kinematic transformation (:mod:`mcl.group_kinematics`)."""
        self._joint = True
        """The cached path state is in the members' coordinates (else in the MCS)."""

    def __repr__(self) -> str:
        names = ", ".join(axis.name for axis in self.axes)
        return f"AxesGroup({self.name!r}, [{names}], {self.state.name})"

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> GroupState:
        """The group state, derived from the group's flags and the members' states.

        A pure read: member faults that :meth:`update` has not acted on yet count as it will
        count them (a member whose group command ended with an error makes GroupErrorStop)."""
        if not self.enabled:
            return GroupState.GroupDisabled
        lost = self._lost()
        states = [axis.state for axis in self.axes]
        if self.GroupErrorID or self._loss_error(lost) or AxisState.ErrorStop in states:
            return GroupState.GroupErrorStop
        if self._stopping(lost) or AxisState.Stopping in states:
            return GroupState.GroupStopping
        if AxisState.Homing in states:
            return GroupState.GroupHoming
        if self._moving(lost):
            return GroupState.GroupMoving
        return GroupState.GroupStandby

    @property
    def stopping(self) -> bool:
        """MC_GroupStop is running or its Execute is still TRUE."""
        return self._stopping(self._lost())

    @property
    def moving(self) -> bool:
        """A group motion runs, or a member moves by a command of its own."""
        return self._moving(self._lost())

    def in_position(self) -> bool:
        """The group stands and every member is within its in-position window of the end point
        of the last motion (of its model position if the group never moved)."""
        if not self.axes:
            return False
        lost = self._lost()
        if self._moving(lost):
            return False
        end = self._end
        if end is None and lost and self._active is not None:
            end = self.kin.to_joints(self._p, self._joint, self.axes)  # nobody follows: ends there
        end = end if end is not None else [axis.sp_pos for axis in self.axes]
        return all(
            abs(axis.actual - e) <= axis.config.in_position
            for axis, e in zip(self.axes, end, strict=True)
        )

    def _lost(self) -> list[GroupMember]:
        """Members whose group command ended by an error or power-off since the last
        :meth:`update`: they dropped out of the group motion."""
        ended = (Status.Error, Status.Aborted)
        return [m for m in self._members if m is not None and m.status in ended]

    def _loss_error(self, lost: Sequence[GroupMember]) -> int:
        """The group error the loss of ``lost`` latches (0 = none: power-off)."""
        for member in lost:
            if member.status == Status.Error:
                return self._group_error(member.error_id)
        return 0

    def _stopping(self, lost: Sequence[GroupMember]) -> bool:
        """:attr:`stopping` once ``lost`` is acted on (the loss aborts a running MC_GroupStop)."""
        stop = self._stop
        if stop is None or self._loss_error(lost):
            return False
        return stop.hold or (stop.busy and not lost)

    def _moving(self, lost: Sequence[GroupMember]) -> bool:
        """:attr:`moving` once ``lost`` is acted on (the path goes on, as a stop ramp, only while
        some member still follows it)."""
        if lost:
            path = self._active is not None and any(
                member is not None and member not in lost for member in self._members
            )
        else:
            path = self._active is not None or bool(self._queue)
        if path and not (self.clock.held and self.clock.at_rest):
            return True
        for axis, member in zip(self.axes, self._members, strict=True):
            if axis.state in _MOTION_STATES and (member is None or not member.busy):
                return True
        return False

    def update(self) -> None:
        """Act on member faults: a member whose group command ended by an error or power-off
        stops the group (module docstring); a member in ErrorStop latches :attr:`GroupErrorID`,
        and a member's following error (2001, its loop opened) replaces it by ERRPOSG 8001.

        Runs with every path evaluation (each servo cycle while the group moves) and in the
        group blocks before they look at the state or act on the group.
        """
        lost = self._lost()
        if lost:
            for i, member in enumerate(self._members):
                if member is not None and member in lost:
                    self._members[i] = None
            self._lose(lost)
        if self.enabled and self.GroupErrorID != ErrorID.ERRPOSG:
            for axis in self.axes:  # a member's following error replaces an earlier error
                if axis.state == AxisState.ErrorStop and (
                    not self.GroupErrorID or axis.AxErrorID == ErrorID.ERRPOS
                ):
                    self.GroupErrorID = self._group_error(axis.AxErrorID)
                    break

    @staticmethod
    def _group_error(code: int) -> int:
        return int(ErrorID.ERRPOSG) if code == ErrorID.ERRPOS else int(code or ErrorID.EAxis)

    # ------------------------------------------------------------------ administration
    def add(self, axis: Axis) -> int:
        """MC_AddAxisToGroup: append ``axis``; returns an error code (0 = added).

        1004 when the axis already belongs to a group (this one included), 1001 when the group
        is full, Eerrstop 11 in GroupErrorStop, EAxStop 6 in GroupStopping and EParam 5 while the
        group moves (members change only in GroupDisabled and GroupStandby).
        """
        if axis.group is not None:
            return ErrorID.EInOtherGroup
        if len(self.axes) >= self.MAX_AXES:
            return ErrorID.EGroupFull
        error = self.busy_error()
        if error:
            return error
        axis.group = self
        self.axes.append(axis)
        self._members.append(None)
        self._end = None
        return 0

    def busy_error(self) -> int:
        """Error code that forbids a change of the members or of their coordinates now (0 =
        none): Eerrstop 11, EAxStop 6 in GroupStopping, EParam 5 moving, homing or held."""
        self.update()
        state = self.state
        if state == GroupState.GroupErrorStop:
            return ErrorID.Eerrstop
        if state == GroupState.GroupStopping:
            return ErrorID.EAxStop
        if state in (GroupState.GroupMoving, GroupState.GroupHoming) or self.interrupted:
            return ErrorID.EParam
        return 0

    def shift_end(self, deltas: Sequence[float]) -> None:
        """The members' coordinates moved by ``deltas`` [mm] (MC_GroupSetPosition)."""
        if self._end is not None:
            self._end = [e + d for e, d in zip(self._end, deltas, strict=True)]

    def enable(self) -> int:
        """MC_GroupEnable: GroupDisabled → GroupStandby; 1005 when the group has no axes."""
        if not self.axes:
            return ErrorID.EGroupEmpty
        self.enabled = True
        return 0

    def disable(self) -> int:
        """MC_GroupDisable: to GroupDisabled at once (refused in GroupErrorStop: Eerrstop 11).

        A running motion is aborted and ramps to standstill along the path with the default
        deceleration; :attr:`moving` tells when it stands.
        """
        self.update()
        if self.state == GroupState.GroupErrorStop:
            return ErrorID.Eerrstop
        self.enabled = False
        self._abort_path(Status.Aborted, 0, max_ramp=False)
        self._stop = None
        return 0

    def check_ungroup(self) -> int:
        """Errors of MC_UngroupAllAxes: 1005 empty group, Eerrstop 11 in GroupErrorStop."""
        if not self.axes:
            return ErrorID.EGroupEmpty
        self.update()
        if self.state == GroupState.GroupErrorStop:
            return ErrorID.Eerrstop
        return 0

    def ungroup(self) -> None:
        """Remove every member (call once the motion stands); the group goes GroupDisabled."""
        for member in self._members:
            if member is not None and member.busy:
                member.release()
        for axis in self.axes:
            axis.group = None
        self.axes.clear()
        self._members.clear()
        self._active = None
        self._queue.clear()
        self._stop = None
        self._end = None
        self.enabled = False

    def reset(self) -> bool:
        """MC_GroupReset: reset the members in ErrorStop and clear :attr:`GroupErrorID`.

        Returns:
            True once the group has left GroupErrorStop (members reset, stop ramps finished).
        """
        self.update()
        if self.state != GroupState.GroupErrorStop:
            return True
        done = self._active is None and not self.moving  # a refusal's ramps ended too
        for axis in self.axes:
            if axis.state == AxisState.ErrorStop and not axis.reset():
                done = False
        if done and all(axis.state != AxisState.ErrorStop for axis in self.axes):
            self.GroupErrorID = self.kin.fault = 0
            self._stop = None
            return True
        return False

    # ------------------------------------------------------------------ checks for FBs
    def check_ready(self, stopping_ok: bool = False) -> int:
        """Error code that forbids a group motion command now (0 = none).

        Order: 1005 no axes, Epower 10 group disabled, Eerrstop 11 GroupErrorStop, EAxStop 6
        GroupStopping, then per member: 1003 when the axis no longer refers to this group, then
        :meth:`Axis.check_ready` (Econst, Epower, ...).
        """
        if not self.axes:
            return ErrorID.EGroupEmpty
        if not self.enabled:
            return ErrorID.Epower
        self.update()
        state = self.state
        if state == GroupState.GroupErrorStop:
            return ErrorID.Eerrstop
        if (state == GroupState.GroupStopping or self.interrupted) and not stopping_ok:
            return ErrorID.EAxStop
        for axis in self.axes:
            if axis.group is not self:  # detached behind the group's back
                return ErrorID.ENotGroupMember
            error = axis.check_ready(stopping_ok=stopping_ok, group_ok=True)
            if error:
                return error
        return 0

    def start_point(self, buffer_mode: MC_BufferMode, joint: bool = False) -> Vector:
        """Where a new move of ``buffer_mode`` starts: the current path point when it aborts
        (the actual positions at standstill), the end of the last queued motion otherwise [mm],
        in the members' coordinates when ``joint``, else in the MCS (:mod:`mcl.group_kinematics`).

        Raises:
            KinematicsError: the point has no place in the space asked for.
        """
        if buffer_mode == MC_BufferMode.Aborting or self._idle():
            p, space = self._current()[1], self._joint
        else:
            last = self._queue[-1] if self._queue else self._active
            assert last is not None
            p, space = last.end, last.joint
        return self.kin.convert(p, space, joint)

    def nominal_limits(
        self, velocity: float, acceleration: float, deceleration: float, jerk: float
    ) -> Limits:
        """The path limits of FB inputs (validated, >= 0; 0 = the members' default) before any
        clamping to a direction or a curve (the 100 s rule of the parameter checks)."""
        zero = Line([0.0] * len(self.axes), [0.0] * len(self.axes))
        return self._planner(False).limits(zero, velocity, acceleration, deceleration, jerk)[0]

    # ------------------------------------------------------------------ commands
    def prepare(self, ticket: PathCommand, moves: Sequence[Move]) -> list[Element]:
        """The elements of a command's ``moves``, chained from where it starts
        (:meth:`start_point` of its BufferMode); only the last one reports the command Done.

        Raises:
            GeometryError: a piece describes no path (an arc that fits no circle, ...).
            KinematicsError: a piece leaves the workspace or a joint's limits
                (:meth:`GroupKinematics.hold_joints`).
        """
        start = self.start_point(ticket.buffer_mode, moves[0].joint)
        elements: list[Element] = []
        for move in moves:
            space = elements[-1].joint if elements else move.joint
            start = self.kin.convert(start, space, move.joint)
            element = self.kin.element(ticket, start, move, self.axes, self.corner_tolerance)
            element.completes = False
            elements.append(element)
            start = element.end
        elements[-1].completes = True
        return elements

    def submit(self, ticket: PathCommand, elements: Sequence[Element]) -> None:
        """Hand a validated command's elements (:meth:`prepare`) to the group (docs/reference.md,
        BufferMode).

        Aborting (or an idle group): starts now from the current path point. When the current
        velocity vector points along the first element's start (within what the path
        acceleration changes in one servo period, per axis, and no faster than the element
        allows) the element starts with that velocity; otherwise the current motion first ramps
        to standstill on its path with the first element's deceleration, then the command starts
        from there. Buffered: starts from standstill once the previous command is Done.
        Blending*: the previous element is re-planned to pass the corner at the blending
        velocity (:mod:`mcl.path_planner`).
        """
        resting = self._active is not None and self._active is self.kin.held
        if ticket.buffer_mode != MC_BufferMode.Aborting and not self._idle() and not resting:
            before = self._queue[0] if self._queue else None
            entry = before.entry_max if before is not None else 0.0
            self._queue.extend(elements)
            self._lookahead()
            first = self._queue[0]
            if first is not before or first.entry_max != entry:
                self._replan_active()
            return
        t, _, v, a = self._current()
        self._abort_tickets(except_ticket=ticket)
        self._queue.clear()
        first = elements[0]
        unit = first.geometry.tangent(0.0)
        v_along = dot(v, unit)
        jump = self.axes[0].servo_period * first.limits.acceleration
        ticket.status = Status.Active
        same = self.kin.transform is None or first.joint == self._joint
        if (
            same
            and v_along <= first.cap
            and all(abs(vi - v_along * ui) <= jump for vi, ui in zip(v, unit, strict=True))
        ):
            self._queue.extend(elements[1:])
            self._lookahead()
            self._begin(first, t, 0.0, v_along, dot(a, unit))
        else:
            _, _, deceleration, jerk = first.move.params if first.move is not None else (0, 0, 0, 0)
            ramp = self._ramp(t, deceleration, jerk, ticket, completes=False)
            self._queue.extend(elements)
            self._rechain(ramp)
            self._lookahead()
            self._active = ramp
        self._engage()

    def submit_stop(
        self, ticket: PathCommand, deceleration: float, jerk: float, halt: bool = False
    ) -> None:
        """MC_GroupStop: abort everything (a feed hold included) and ramp the path velocity to
        zero on the path with ``deceleration`` [mm/s²] and ``jerk`` [mm/s³] (0 = defaults),
        unaffected by the override; the group stays in GroupStopping until the ticket is Done
        and no longer held (it leaves a moving PCS: stops in the MCS). ``halt`` (MC_GroupHalt):
        the ramp runs on the path clock (the override acts on it), the group stays GroupMoving
        and the next move may abort it. A ramp refused: :meth:`GroupKinematics.ramp_fault`."""
        if not halt and self.kin.leave_moving_frame():
            self._active = None  # the stop runs in the MCS, from the members' own motion
        t = self._current()[0]
        self._abort_tickets(except_ticket=ticket)
        self._queue.clear()
        ramp = self._ramp(t, deceleration, jerk, ticket, unscaled=not halt)
        ticket.status = Status.Active
        if not halt:
            self._stop = ticket
        self._active = ramp
        self._engage()
        if self.kin.ramp_fault(ramp, self.axes) and not self.GroupErrorID:
            self._refused()

    def reframe(self, ticket: PathCommand, deceleration: float, jerk: float) -> None:
        """The PCS changed (:mod:`mcl.tracking`): the path restarts from the members' set points
        in it and ramps to rest there (as MC_GroupHalt; then rests in a moving PCS)."""
        self._active = None  # the queue is empty: the group rests (:attr:`holding`) or stands
        self.submit_stop(ticket, deceleration, jerk, halt=True)

    @property
    def holding(self) -> bool:
        """The path rests in a moving PCS and nothing is queued."""
        return self._active is not None and self._active is self.kin.held and not self._queue

    @property
    def has_path(self) -> bool:
        """A path runs (a stop ramp included) or is held."""
        return self._active is not None

    @property
    def interrupted(self) -> bool:
        """A feed hold is in force on a path that has not ended."""
        return self.clock.held and self._active is not None

    def cancel(self, ticket: PathCommand) -> None:
        """Withdraw the queued part of a command whose FB was restarted by a new Execute edge."""
        before = self._queue[0] if self._queue else None
        self._queue = deque(e for e in self._queue if e.ticket is not ticket)
        if ticket.status == Status.Queued:
            ticket.status = Status.Aborted
        self._rechain(self._active)
        self._lookahead()
        if (self._queue[0] if self._queue else None) is not before:
            self._replan_active()

    # ------------------------------------------------------------------ path bookkeeping
    def _idle(self) -> bool:
        return self._active is None and not self._queue

    def _current(self) -> tuple[float, Vector, Vector, Vector]:
        """Time [s] and path state (position, velocity, acceleration) a new element starts
        from: the cached path state while the path runs, else the members' model states (the
        actual position at standstill, as :meth:`Axis.start_position` gives it); with a
        kinematic transformation in the MCS where the pose has one, else in the members'
        coordinates."""
        if self._active is None:
            self._t = max(axis.t_sp for axis in self.axes)
            self._p, self._v, self._a, self._joint = self.kin.path_state(
                [axis.start_position(MC_BufferMode.Aborting) for axis in self.axes],
                [axis.sp_vel for axis in self.axes],
                [axis.sp_acc for axis in self.axes],
                self._t,
            )
            self.clock.restart(self._t)
        return self.clock.tau, list(self._p), list(self._v), list(self._a)

    def _planner(self, joint: bool = True) -> PathPlanner:
        """The path planner for pieces in the members' coordinates (``joint``) or the MCS."""
        return self.kin.planner(joint, self.axes, self.corner_tolerance)

    def _lookahead(self) -> None:
        """Update the queued elements' entry speeds (:meth:`PathPlanner.entry_speeds`)."""
        PathPlanner.entry_speeds(list(self._queue))

    def _ramp(
        self,
        t: float,
        deceleration: float,
        jerk: float,
        ticket: PathCommand | None = None,
        completes: bool = True,
        following: Sequence[bool] | None = None,
        unscaled: bool = False,
    ) -> Element:
        """A stop on the current path from path time ``t`` with ``deceleration`` and ``jerk`` (0 =
        defaults) or the ``following`` members' fastest ramp; without a path the members' own
        motion stops straight on. ``unscaled``: ignores the override (:meth:`PathClock.unscale`)."""
        active = self._active
        blends: tuple[Blend | None, Blend | None] = (None, None)
        if active is not None and active.profile is not None:
            geometry, joint = active.geometry, active.joint
            s, v, a = active.profile.at(t - active.t0)
            blends = (active.blend_in, active.blend_out)
        else:
            _, p, vel, acc = self._current()
            unit = direction(vel)
            geometry, joint = Line(p, along(p, unit, 1.0)), self._joint
            s, v, a = 0.0, dot(vel, unit), dot(acc, unit)
        planner = self._planner(joint)
        if unscaled:
            (v,), (a,) = self.clock.wall([v], [a])
            self.clock.unscale()
        if following is not None:
            limits = planner.max_ramp(geometry, following, v)
        else:
            limits = planner.stop_limits(geometry, v, deceleration, jerk)
        ramp = stop_element(geometry, s, v, a, t, limits, ticket, completes, blends)
        ramp.joint = joint
        return ramp

    def _rechain(self, previous: Element | None) -> None:
        """Let every queued move start where the element before it ends (after a withdrawal or
        an unplanned stop ramp); a piece that no longer fits from there (an arc) ends its
        command with EParam."""
        end = previous.end if previous is not None else None
        space = previous.joint if previous is not None else True
        queue: deque[Element] = deque()
        failed: list[PathCommand] = []
        for element in self._queue:
            if element.ticket in failed:
                continue
            move = element.move
            ticket = element.ticket
            if end is not None and move is not None:
                assert ticket is not None
                try:
                    start = self.kin.convert(end, space, element.joint)
                    if element.start != start:
                        rebuilt = self.kin.element(
                            ticket, start, move, self.axes, self.corner_tolerance
                        )
                        rebuilt.completes = element.completes
                        element = rebuilt
                except (GeometryError, KinematicsError) as refused:
                    ticket.status = Status.Error
                    ticket.error_id = refusal(refused)
                    failed.append(ticket)
                    continue
            queue.append(element)
            end, space = element.end, element.joint
        self._queue = deque(e for e in queue if e.ticket not in failed)

    def _begin(self, element: Element, t0: float, s0: float, v0: float, a0: float) -> None:
        """Make ``element`` the active one, starting at ``t0`` from the path state (s0, v0, a0)."""
        element.t0 = t0
        if element.move is not None:
            try:
                element.profile, element.blend_out = self._plan(element, t0, s0, v0, a0, t0)
            except PlanningError:
                if element.ticket is not None:
                    element.ticket.status = Status.Error
                    element.ticket.error_id = ErrorID.EParam
                limits = self._planner(element.joint).stop_limits(element.geometry, v0, 0.0, 0.0)
                blends = (element.blend_in, None)
                joint = element.joint
                element = stop_element(element.geometry, s0, v0, a0, t0, limits, None, True, blends)
                element.joint = joint
        self._active = element

    def _replan_active(self) -> None:
        """Re-plan the active move for its (new) successor from the current path state."""
        element = self._active
        if element is None or element.move is None or element.profile is None:
            return
        blend = element.blend_out
        t = self.clock.tau
        if blend is not None and t >= blend.begin:
            return  # the blend has begun: the corner stays as it is
        s, v, a = element.profile.at(t - element.t0)
        try:
            profile, blend = self._plan(element, t, s, v, a, t)
        except PlanningError:
            return
        element.profile, element.blend_out, element.t0 = profile, blend, t

    def _plan(
        self, element: Element, t0: float, s0: float, v0: float, a0: float, now: float
    ) -> tuple[Profile, Blend | None]:
        """Profile of a move from (s0, v0, a0) at ``t0`` and its blend into the queued successor
        (:meth:`mcl.path_planner.PathPlanner.plan`).

        Raises:
            PlanningError: the move cannot be planned.
        """
        nxt = self._queue[0] if self._queue else None
        return self._planner(element.joint).plan(element, nxt, t0, s0, v0, a0, now)

    def _next(self, element: Element) -> Element | None:
        """``element`` reached its end: report it and start what follows (at the exact end time)."""
        t_end = element.t0 + element.duration
        assert element.profile is not None
        _, v_end, _ = element.profile.at(element.duration)
        ticket = element.ticket
        if ticket is not None and element.completes and ticket.busy:
            ticket.status = Status.Done
        blend = element.blend_out
        nxt = self._queue.popleft() if self._queue else None
        if abs(v_end) > EPS and (blend is None or nxt is not blend.successor):
            # the blending successor vanished: stop on the path the blend had taken
            if nxt is not None:
                self._queue.appendleft(nxt)
            geometry = blend.geom_out if blend is not None else element.geometry
            s0 = 0.0 if blend is not None else element.length
            limits = self._planner(element.joint).stop_limits(geometry, v_end, 0.0, 0.0)
            ramp = stop_element(geometry, s0, v_end, 0.0, t_end, limits, None, True, (blend, None))
            ramp.joint = element.joint
            self._active = ramp
            return ramp
        if nxt is None:
            self._active = self.kin.hold(element.end, element.joint, t_end)
            if self._active is None:
                self._end = self.kin.to_joints(element.end, element.joint, self.axes)
            return self._active
        if nxt.move is not None and (nxt.start != element.end or nxt.joint != element.joint):
            self._queue.appendleft(nxt)
            self._rechain(element)
            if not self._queue:
                self._active = None
                self._end = self.kin.to_joints(element.end, element.joint, self.axes)
                return None
            nxt = self._queue.popleft()
        nxt.blend_in = blend
        if nxt.ticket is not None and nxt.ticket.status == Status.Queued:
            nxt.ticket.status = Status.Active
        self._begin(nxt, t_end, 0.0, blend.speed if blend is not None else 0.0, 0.0)
        return self._active

    def _advance(self, t: float) -> None:
        """Bring the path to the servo instant ``t`` [s] and cache its point."""
        if t <= self._t:
            return
        self.update()
        if self._active is not None and math.isfinite(self._t):
            self.clock.advance(t - self._t, math.sqrt(dot(self._v, self._v)))
        tau = self.clock.tau
        element = self._active
        while element is not None and tau - element.t0 >= element.duration:
            element = self._next(element)
        if element is None:
            if self._end is not None:
                self._p, self._joint = list(self._end), True
            self._v = [0.0] * len(self._p)
            self._a = [0.0] * len(self._p)
            stop = self._stop
            if stop is not None and not stop.busy and not stop.hold:
                self._stop = None
            if not self.stopping:
                for i, member in enumerate(self._members):
                    if member is not None:
                        member.release(self._p[i])
                        self._members[i] = None
        else:
            self._p, self._v, self._a = element.point(tau)
            self._joint = element.joint
        self._t = t

    def _setpoint(self, index: int, t: float) -> tuple[float, float, float]:
        """Member ``index``'s component of the path point at the servo instant ``t`` [s] (rates in
        wall-clock time: :mod:`mcl.path_clock`), through the inverse kinematics in the MCS."""
        self._advance(t)
        f, rate = self.clock.factor, self.clock.rate
        if self.kin.transform is None or self._joint:  # the members' own coordinates: no lists
            w = self._v[index]
            return self._p[index], f * w, f * f * self._a[index] + rate * w
        v = [f * x for x in self._v]
        a = [f * f * y + rate * x for x, y in zip(self._v, self._a, strict=True)]
        q, qd, qdd = self.kin.joints(self._t, self._joint, self._p, v, a, self.axes)
        if self.kin.fault and not self.GroupErrorID:
            self._refused()
        return q[index], qd[index], qdd[index]

    def _refused(self) -> None:
        """The kinematics refused the path point: the commands end with its error, every member
        ramps to standstill in its own coordinate on its fastest ramp (:meth:`Axis.max_ramp`)."""
        self.GroupErrorID = self.kin.fault
        self._abort_tickets(status=Status.Error, error_id=self.kin.fault)
        self._queue.clear()
        self._active = self._end = None
        for i, member in enumerate(self._members):
            if member is not None:
                member.stop(self.axes[i].max_ramp())
                self._members[i] = None

    def _engage(self) -> None:
        """Put every member under a GroupMember command (SynchronizedMotion)."""
        self._end = None
        for i, axis in enumerate(self.axes):
            member = self._members[i]
            if member is None or not member.busy or member.signal:
                member = GroupMember(self, i)
                self._members[i] = member
                axis.submit(member)

    def _tickets(self) -> list[PathCommand]:
        tickets: list[PathCommand] = []
        for element in (self._active, *self._queue):
            ticket = element.ticket if element is not None else None
            if ticket is not None and ticket not in tickets:
                tickets.append(ticket)
        if self._stop is not None:
            tickets.append(self._stop)
        return tickets

    def _abort_tickets(
        self,
        except_ticket: PathCommand | None = None,
        status: Status = Status.Aborted,
        error_id: int = 0,
    ) -> None:
        for ticket in self._tickets():
            if ticket is not except_ticket and ticket.busy:
                ticket.status = status
                ticket.error_id = error_id

    def _abort_path(self, status: Status, error_id: int, max_ramp: bool) -> None:
        """End every command with ``status`` and ramp a running path to standstill on the path
        (the members' fastest ramp, or the default deceleration)."""
        self._abort_tickets(status=status, error_id=error_id)
        self._queue.clear()
        if self._active is not None and self.kin.leave_moving_frame():
            self._active = None  # the stop runs in the MCS, from the members' own motion
            self._active = self._ramp(self._current()[0], 0.0, 0.0)
        if self._active is None:
            return
        following = [m is not None for m in self._members]
        if not any(following):  # nobody left to follow the path
            self._active = None
            self._end = self.kin.to_joints(self._p, self._joint, self.axes)
            return
        ramp = self._ramp(
            self.clock.tau, 0.0, 0.0, None, True, following if max_ramp else None, unscaled=True
        )
        self._active = ramp

    def _lose(self, lost: list[GroupMember]) -> None:
        """Members dropped out of the group motion (ErrorStop, power off): end the group's
        commands with the error (8001 for a following error) and stop the others on the path
        on their fastest ramp."""
        error = self._loss_error(lost)
        if error and not self.GroupErrorID:
            self.GroupErrorID = error
        self._abort_path(Status.Error if error else Status.Aborted, error, max_ramp=True)
        if error:
            self._stop = None


__all__ = ["AxesGroup", "GroupMember", "PathCommand", "distance_to_segment"]

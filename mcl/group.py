"""Axes groups: AXES_GROUP_REF, the group state machine and linear interpolation.

SPEC §2 (member states), §4 (BufferMode of group moves), §5 "Groups"; seed 000 chapters 2.2–2.3
(Obr. 2.2, Tab. 2.1) and 5.

An :class:`AxesGroup` holds up to three axes in the order they were added. A group move is a
straight segment in the space of the members' coordinates [mm]; the motion *along* the segment
is a 1-D jerk-limited profile of the path coordinate ``s`` (0 … length) planned with
:mod:`mcl.trajectory`, and member ``i`` follows ``start_i + s·u_i`` (``u`` = unit direction), so
the tool point stays on the straight line.

The members are driven through the normal axis machinery: while the group moves, every member
runs a :class:`GroupMember` command (axis state SynchronizedMotion) whose set point is the
member's component of the path point. The path point is computed once per servo instant and
cached, because every member asks for the same instant. The member commands stay active across
consecutive segments; the group ends them when the path is complete and nothing is queued.

Corner blending (BlendingLow/Previous/Next/High): the first segment is planned to reach the
corner with the blending velocity ``v_b`` and zero acceleration, the second starts there with
``v_b``. Around the corner instant ``t_c`` a window of duration ``T`` mixes the two straight
motions, each extended through the corner at ``v_b``::

    p(t) = q1(t) + σ(x)·(q2(t) − q1(t)),   x = (t − t_c + T/2) / T,   σ = 10x³ − 15x⁴ + 6x⁵

so position, velocity and acceleration stay continuous and the path speed does not drop to zero;
the path passes the corner point itself at ``t_c``. ``T = 3.75·v_b·max_i(|Δu_i| / A_i)`` (``Δu`` =
change of the unit direction) keeps the blend's own contribution to the acceleration of axis
``i`` within ``A_i``, the smaller path acceleration/deceleration of the two segments (at most the
axis' ``max_acceleration``); the window is lengthened if the sum with the segments' own
acceleration would exceed an axis' ``max_acceleration``. ``v_b`` starts at the BufferMode's
velocity (capped by every member's Vmax along both segments) and is lowered until the blended
path stays within :attr:`AxesGroup.corner_tolerance` (default 0.05 mm) of the polyline,
checked numerically over the window, and the window covers at most the second half of the
first segment and the first half of the second. If no blending velocity fits, or the corner is
a reversal (above about 177°), the path stops at the corner as with Buffered. Collinear
segments hand over at ``v_b`` without a window.

Aborting while moving: when the current velocity vector points along the new segment (each
axis' velocity differs by at most what the path acceleration changes in one servo period) the
segment starts with that velocity; otherwise the current motion first ramps to standstill along
its own direction with the new command's Deceleration, then the segment starts from the stop
point (the new block is Active during the ramp). MC_GroupStop, MC_GroupDisable and member faults
ramp the path velocity to zero along the current direction of motion (inside a corner blend:
along its tangent); a member fault uses the other members' fastest ramp (max_deceleration).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from typing import Final

from mcl import trajectory
from mcl.axis import Axis
from mcl.command import Command, Status, blend_velocity
from mcl.enums import AxisState, GroupState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.trajectory import Limits, PlanningError, Profile

Vector = list[float]
"""A point or direction in the group's coordinates, one component per member [mm]."""

_EPS: Final = 1e-9
"""Lengths and speeds below this count as zero [mm], [mm/s]."""
_REVERSAL_COS: Final = -0.999
"""Corners sharper than this cosine (about 177°) are reversals: the path stops there."""
_BLEND_SAMPLES: Final = 32
"""Samples of a blend window when its deviation from the polyline is checked."""
_BLEND_SHRINK: Final = 0.7
"""Factor that lowers the blending velocity while a blend does not fit."""
_BLEND_TRIES: Final = 16
_BLEND_STRETCH: Final = (1.0, 1.3, 1.7, 2.2)
"""Longer blend windows tried while an axis would exceed its max_acceleration."""
_FITS, _TOO_HARD, _NO_FIT = 0, 1, 2
_MOTION_STATES: Final = frozenset(
    {AxisState.DiscreteMotion, AxisState.ContinuousMotion, AxisState.SynchronizedMotion}
)


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    return sum(x * y for x, y in zip(a, b, strict=True))


def _norm(a: Sequence[float]) -> float:
    return math.sqrt(_dot(a, a))


def _along(start: Sequence[float], unit: Sequence[float], s: float) -> Vector:
    return [p + s * u for p, u in zip(start, unit, strict=True)]


def distance_to_segment(p: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    """Distance of point ``p`` from the segment ``a``–``b`` [mm]."""
    ab = [y - x for x, y in zip(a, b, strict=True)]
    ap = [y - x for x, y in zip(a, p, strict=True)]
    length2 = _dot(ab, ab)
    k = 0.0 if length2 <= 0.0 else min(1.0, max(0.0, _dot(ap, ab) / length2))
    return _norm([d - k * e for d, e in zip(ap, ab, strict=True)])


def _smooth(x: float) -> tuple[float, float, float]:
    """Quintic step σ(x) = 10x³ − 15x⁴ + 6x⁵ and its first two derivatives (0 ≤ x ≤ 1)."""
    x2 = x * x
    return (
        x2 * x * (10.0 - 15.0 * x + 6.0 * x2),
        30.0 * x2 * (1.0 - x) ** 2,
        60.0 * x * (1.0 - x) * (1.0 - 2.0 * x),
    )


class PathCommand:
    """The ticket of a group command (MC_MoveLinear*, MC_GroupStop) that its FB reads.

    Attributes:
        buffer_mode: how the command takes over the group (SPEC §4).
        status: life cycle, written by the group.
        error_id: the error that ended the command (0 = none).
        hold: MC_GroupStop only: its Execute is still TRUE (the group stays in GroupStopping).
    """

    def __init__(self, buffer_mode: MC_BufferMode = MC_BufferMode.Aborting) -> None:
        self.buffer_mode = buffer_mode
        self.status = Status.Queued
        self.error_id = 0
        self.hold = False

    @property
    def busy(self) -> bool:
        """Queued or active."""
        return self.status <= Status.Active


class _Blend:
    """A corner blend: the window of ``2·half`` seconds around ``t_c`` (module docstring)."""

    __slots__ = ("corner", "half", "speed", "successor", "t_c", "u_in", "u_out")

    def __init__(
        self,
        corner: Vector,
        u_in: Vector,
        u_out: Vector,
        speed: float,
        t_c: float,
        half: float,
        successor: _Element,
    ) -> None:
        self.corner = corner
        self.u_in = u_in
        self.u_out = u_out
        self.speed = speed
        self.t_c = t_c
        self.half = half
        self.successor = successor

    @property
    def begin(self) -> float:
        """Start of the window [s]."""
        return self.t_c - self.half

    @property
    def end(self) -> float:
        """End of the window [s]."""
        return self.t_c + self.half

    def line(self, unit: Vector, t: float) -> tuple[Vector, Vector]:
        """Position and velocity on the straight line through the corner at the blending speed."""
        ds = self.speed * (t - self.t_c)
        return _along(self.corner, unit, ds), [self.speed * u for u in unit]

    def mix(
        self,
        t: float,
        q1: tuple[Vector, Vector, Vector],
        q2: tuple[Vector, Vector, Vector],
    ) -> tuple[Vector, Vector, Vector]:
        """Blend the incoming motion ``q1`` into the outgoing ``q2`` (position, velocity,
        acceleration vectors) at time ``t`` inside the window."""
        width = 2.0 * self.half
        x = min(1.0, max(0.0, (t - self.begin) / width))
        s, ds, dds = _smooth(x)
        ds /= width
        dds /= width * width
        (p1, v1, a1), (p2, v2, a2) = q1, q2
        p, v, a = [], [], []
        for i in range(len(p1)):
            dp, dv, da = p2[i] - p1[i], v2[i] - v1[i], a2[i] - a1[i]
            p.append(p1[i] + s * dp)
            v.append(v1[i] + s * dv + ds * dp)
            a.append(a1[i] + s * da + 2.0 * ds * dv + dds * dp)
        return p, v, a


class _Element:
    """A straight piece of the path: ``start + s(t)·unit``, ``s`` a 1-D profile [mm].

    ``move`` elements come from MC_MoveLinear* and end at ``end``; ramp elements (``move`` False)
    bring the path to a standstill along ``unit`` (MC_GroupStop, aborts, faults).
    """

    __slots__ = (
        "blend_in",
        "blend_out",
        "completes",
        "end",
        "length",
        "limits",
        "move",
        "params",
        "profile",
        "start",
        "t0",
        "ticket",
        "unit",
    )

    def __init__(
        self,
        start: Vector,
        unit: Vector,
        length: float,
        limits: Limits,
        ticket: PathCommand | None,
        move: bool,
        completes: bool = True,
    ) -> None:
        self.start = start
        self.unit = unit
        self.length = length
        self.end = _along(start, unit, length)
        self.limits = limits
        self.ticket = ticket
        self.move = move
        self.completes = completes
        """Reaching the end reports the ticket Done (False for the ramp that precedes a move)."""
        self.params: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
        """FB inputs of a move: Velocity, Acceleration, Deceleration, Jerk (0 = default)."""
        self.profile: Profile | None = None
        self.t0 = 0.0
        self.blend_in: _Blend | None = None
        self.blend_out: _Blend | None = None

    @property
    def duration(self) -> float:
        """Duration of the planned profile [s]."""
        assert self.profile is not None
        return self.profile.duration

    def at(self, t: float) -> tuple[Vector, Vector, Vector]:
        """Position, velocity, acceleration vectors of the straight motion at time ``t`` [s]."""
        assert self.profile is not None
        s, v, a = self.profile.at(t - self.t0)
        unit = self.unit
        return _along(self.start, unit, s), [v * u for u in unit], [a * u for u in unit]

    def point(self, t: float) -> tuple[Vector, Vector, Vector]:
        """Path point at time ``t`` including the corner blends [mm], [mm/s], [mm/s²]."""
        q = self.at(t)
        blend = self.blend_out
        if blend is not None and blend.half > 0.0 and t > blend.begin:
            p2, v2 = blend.line(blend.u_out, t)
            q = blend.mix(t, q, (p2, v2, [0.0] * len(p2)))
        blend = self.blend_in
        if blend is not None and blend.half > 0.0 and t < blend.end:
            p1, v1 = blend.line(blend.u_in, t)
            q = blend.mix(t, (p1, v1, [0.0] * len(p1)), q)
        return q


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
        if self.signal:
            return self._last, 0.0, 0.0
        p, v, a = self.group._setpoint(self.index, self.t0 + t)
        if self.signal:  # released by this very evaluation: the path stands at its end
            return self._last, 0.0, 0.0
        self._last = p
        return p, v, a


class AxesGroup:
    """AXES_GROUP_REF: up to three axes moved together on straight lines (SPEC §5 "Groups").

    The state (:attr:`state`) is derived each time it is read from the group's own flags and its
    members' states (seed Tab. 2.1, chapter 2.3):

    - GroupDisabled until MC_GroupEnable and after MC_GroupDisable / MC_UngroupAllAxes;
    - GroupErrorStop while a member is in ErrorStop or :attr:`GroupErrorID` is set (a member
      fault during a group motion latches ERRPOSG 8001 for a following error 2001, else the
      member's error); left only through MC_GroupReset;
    - GroupStopping from MC_GroupStop until its Done AND NOT Execute (or a member in Stopping);
    - GroupHoming while a member is homing;
    - GroupMoving while a group command runs or a member moves by a command;
    - GroupStandby otherwise (all members StandStill).

    Args:
        name: the group's name in messages.
        corner_tolerance: largest distance of the blended path from the polyline at a corner
            [mm] (module docstring).

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
        self._active: _Element | None = None
        self._queue: deque[_Element] = deque()
        self._stop: PathCommand | None = None
        self._t = -math.inf
        """Time of the cached path state [s]."""
        self._p: Vector = []
        self._v: Vector = []
        self._a: Vector = []
        self._end: Vector | None = None
        """Where the last motion ended (InPosition) [mm]."""

    def __repr__(self) -> str:
        names = ", ".join(axis.name for axis in self.axes)
        return f"AxesGroup({self.name!r}, [{names}], {self.state.name})"

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> GroupState:
        """The group state, derived from the group's flags and the members' states."""
        self.update()
        if not self.enabled:
            return GroupState.GroupDisabled
        states = [axis.state for axis in self.axes]
        if self.GroupErrorID or AxisState.ErrorStop in states:
            return GroupState.GroupErrorStop
        if self.stopping or AxisState.Stopping in states:
            return GroupState.GroupStopping
        if AxisState.Homing in states:
            return GroupState.GroupHoming
        if self.moving:
            return GroupState.GroupMoving
        return GroupState.GroupStandby

    @property
    def stopping(self) -> bool:
        """MC_GroupStop is running or its Execute is still TRUE."""
        stop = self._stop
        return stop is not None and (stop.busy or stop.hold)

    @property
    def moving(self) -> bool:
        """A group motion runs, or a member moves by a command of its own."""
        if self._active is not None or self._queue:
            return True
        for axis, member in zip(self.axes, self._members, strict=True):
            if axis.state in _MOTION_STATES and (member is None or not member.busy):
                return True
        return False

    def in_position(self) -> bool:
        """The group stands and every member is within its in-position window of the end point
        of the last motion (of its model position if the group never moved)."""
        if not self.axes or self.moving:
            return False
        end = self._end if self._end is not None else [axis.sp_pos for axis in self.axes]
        return all(
            abs(axis.actual - e) <= axis.config.in_position
            for axis, e in zip(self.axes, end, strict=True)
        )

    def update(self) -> None:
        """Notice member faults (called by the FBs and every path evaluation): a member whose
        group command ended by an error or power-off stops the group (module docstring)."""
        lost: list[GroupMember] = []
        for i, member in enumerate(self._members):
            if member is not None and member.status in (Status.Error, Status.Aborted):
                lost.append(member)
                self._members[i] = None
        if lost:
            self._lose(lost)
        if self.enabled and not self.GroupErrorID:
            for axis in self.axes:
                if axis.state == AxisState.ErrorStop:
                    self.GroupErrorID = self._group_error(axis.AxErrorID)
                    break

    @staticmethod
    def _group_error(code: int) -> int:
        if code == ErrorID.ERRPOS:
            return int(ErrorID.ERRPOSG)
        return int(code) if code else int(ErrorID.EAxis)

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
        error = self._busy_error()
        if error:
            return error
        axis.group = self
        self.axes.append(axis)
        self._members.append(None)
        self._end = None
        return 0

    def _busy_error(self) -> int:
        state = self.state
        if state == GroupState.GroupErrorStop:
            return ErrorID.Eerrstop
        if state == GroupState.GroupStopping:
            return ErrorID.EAxStop
        if state in (GroupState.GroupMoving, GroupState.GroupHoming):
            return ErrorID.EParam
        return 0

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
        if self.state != GroupState.GroupErrorStop:
            return True
        done = self._active is None
        for axis in self.axes:
            if axis.state == AxisState.ErrorStop and not axis.reset():
                done = False
        if done and all(axis.state != AxisState.ErrorStop for axis in self.axes):
            self.GroupErrorID = 0
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
        state = self.state
        if state == GroupState.GroupErrorStop:
            return ErrorID.Eerrstop
        if state == GroupState.GroupStopping and not stopping_ok:
            return ErrorID.EAxStop
        for axis in self.axes:
            if axis.group is not self:  # detached behind the group's back
                return ErrorID.ENotGroupMember
            error = axis.check_ready(stopping_ok=stopping_ok, group_ok=True)
            if error:
                return error
        return 0

    def start_point(self, buffer_mode: MC_BufferMode) -> Vector:
        """Where a new move of ``buffer_mode`` starts: the current path point when it aborts
        (the actual positions at standstill), the end of the last queued motion otherwise [mm]."""
        if buffer_mode == MC_BufferMode.Aborting or self._idle():
            return list(self._current()[1])
        return list(self._last_end())

    def path_limits(
        self,
        unit: Sequence[float],
        velocity: float,
        acceleration: float,
        deceleration: float,
        jerk: float,
    ) -> Limits:
        """Limits along the path direction ``unit`` from FB inputs (validated, >= 0).

        0 means the default: the smallest default of the members (jerk: of those that have one).
        The result is clamped so that no member exceeds its Vmax, max_acceleration,
        max_deceleration or max_jerk: a limit of member ``i`` allows ``limit_i / |u_i|`` along the
        path (SPEC §3: valid values above the maxima are clamped).
        """
        configs = [axis.config for axis in self.axes]
        acc = acceleration if acceleration > 0.0 else min(c.acceleration for c in configs)
        dec = deceleration if deceleration > 0.0 else min(c.deceleration for c in configs)
        jerks = [c.jerk for c in configs if c.jerk > 0.0]
        j = jerk if jerk > 0.0 else min(jerks, default=math.inf)
        v = velocity
        for axis, u in zip(self.axes, unit, strict=True):
            cos = abs(u)
            if cos < _EPS:
                continue
            c = axis.config
            if axis.constants is not None:
                v = min(v, axis.constants.Vmax / cos)
            acc = min(acc, c.max_acceleration / cos)
            dec = min(dec, c.max_deceleration / cos)
            if c.max_jerk > 0.0:
                j = min(j, c.max_jerk / cos)
        return Limits(v, acc, dec, j)

    # ------------------------------------------------------------------ commands
    def submit_move(
        self,
        ticket: PathCommand,
        target: Sequence[float],
        velocity: float,
        acceleration: float,
        deceleration: float,
        jerk: float,
    ) -> None:
        """Hand a validated linear move to ``target`` [mm] to the group (SPEC §4).

        Aborting (or an idle group): starts now from the current path point. When the current
        velocity vector points along the new segment (within what the path acceleration changes
        in one servo period, per axis) the segment starts with that velocity; otherwise the
        current motion first ramps to standstill along its own direction with the new command's
        deceleration, then the segment starts from there. Buffered: starts from standstill once
        the previous command is Done. Blending*: the previous segment is re-planned to pass the
        corner at the blending velocity (module docstring).
        """
        params = (velocity, acceleration, deceleration, jerk)
        mode = ticket.buffer_mode
        target = [float(x) for x in target]
        if mode != MC_BufferMode.Aborting and not self._idle():
            start = self._last_end()
            element = self._move_element(ticket, start, target, params)
            self._queue.append(element)
            active = self._active
            if (
                len(self._queue) == 1
                and active is not None
                and active.move
                and mode >= MC_BufferMode.BlendingLow
            ):
                self._replan_active()
            return
        t, p, v, a = self._current()
        self._abort_tickets(except_ticket=ticket)
        self._queue.clear()
        element = self._move_element(ticket, p, target, params)
        unit = element.unit
        v_along = _dot(v, unit)
        jump = self.axes[0].servo_period * element.limits.acceleration
        if all(abs(vi - v_along * ui) <= jump for vi, ui in zip(v, unit, strict=True)):
            ticket.status = Status.Active
            self._begin(element, t, 0.0, v_along, _dot(a, unit))
        else:
            dec = self.path_limits(self._direction(v), math.inf, deceleration, deceleration, jerk)
            ramp = self._ramp_element(p, v, a, dec, ticket, completes=False)
            self._queue.append(self._move_element(ticket, ramp.end, target, params))
            ticket.status = Status.Active
            self._begin(ramp, t, 0.0, 0.0, 0.0)
        self._engage()

    def submit_stop(self, ticket: PathCommand, deceleration: float, jerk: float) -> None:
        """MC_GroupStop: abort everything and ramp the path velocity to zero along the path with
        ``deceleration`` [mm/s²] and ``jerk`` [mm/s³] (0 = defaults); the group stays in
        GroupStopping until the ticket is Done and no longer held."""
        t, p, v, a = self._current()
        self._abort_tickets(except_ticket=ticket)
        self._queue.clear()
        limits = self.path_limits(self._direction(v), math.inf, deceleration, deceleration, jerk)
        ramp = self._ramp_element(p, v, a, limits, ticket)
        ticket.status = Status.Active
        self._stop = ticket
        self._begin(ramp, t, 0.0, 0.0, 0.0)
        self._engage()

    def cancel(self, ticket: PathCommand) -> None:
        """Withdraw the queued part of a command whose FB was restarted (rule 7)."""
        before = self._queue[0] if self._queue else None
        self._queue = deque(e for e in self._queue if e.ticket is not ticket)
        if ticket.status == Status.Queued:
            ticket.status = Status.Aborted
        self._rechain(self._active)
        after = self._queue[0] if self._queue else None
        if after is not before:
            self._replan_active()

    # ------------------------------------------------------------------ path bookkeeping
    def _idle(self) -> bool:
        return self._active is None and not self._queue

    def _current(self) -> tuple[float, Vector, Vector, Vector]:
        """Time [s] and path state (position, velocity, acceleration) a new element starts
        from: the cached path state while the path runs, else the members' model states (the
        actual position at standstill, as :meth:`Axis.start_position` gives it)."""
        if self._active is None:
            self._t = max(axis.t_sp for axis in self.axes)
            self._p = [axis.start_position(MC_BufferMode.Aborting) for axis in self.axes]
            self._v = [axis.sp_vel for axis in self.axes]
            self._a = [axis.sp_acc for axis in self.axes]
        return self._t, list(self._p), list(self._v), list(self._a)

    def _last_end(self) -> Vector:
        last = self._queue[-1] if self._queue else self._active
        assert last is not None
        return list(last.end)

    @staticmethod
    def _direction(v: Sequence[float]) -> Vector:
        speed = _norm(v)
        return [x / speed for x in v] if speed > _EPS else [0.0] * len(v)

    def _move_element(
        self,
        ticket: PathCommand,
        start: Vector,
        target: Vector,
        params: tuple[float, float, float, float],
    ) -> _Element:
        delta = [b - a for a, b in zip(start, target, strict=True)]
        length = _norm(delta)
        unit = [d / length for d in delta] if length > _EPS else [0.0] * len(delta)
        element = _Element(start, unit, length, self.path_limits(unit, *params), ticket, True)
        element.end = list(target)
        element.params = params
        return element

    def _rechain(self, previous: _Element | None) -> None:
        """Let every queued move start where the element before it ends (after a withdrawal or
        an unplanned stop ramp)."""
        end = previous.end if previous is not None else None
        queue: deque[_Element] = deque()
        for element in self._queue:
            if end is not None and element.move and element.start != end:
                assert element.ticket is not None
                element = self._move_element(element.ticket, list(end), element.end, element.params)
            queue.append(element)
            end = element.end
        self._queue = queue

    def _ramp_element(
        self,
        p: Vector,
        v: Vector,
        a: Vector,
        limits: Limits,
        ticket: PathCommand | None,
        completes: bool = True,
    ) -> _Element:
        """A ramp to standstill from the state (p, v, a) along the velocity's direction."""
        unit = self._direction(v)
        profile = trajectory.stop(0.0, _norm(v), _dot(a, unit), limits.deceleration, limits.jerk)
        element = _Element(p, unit, 0.0, limits, ticket, False, completes)
        element.profile = profile
        element.length = profile.end_position
        element.end = _along(p, unit, element.length)
        return element

    def _max_ramp(self, unit: Vector, axes: Sequence[Axis]) -> Limits:
        """The fastest stop along ``unit`` the given members allow (their max_deceleration)."""
        dec = jerk = math.inf
        for axis, u in zip(self.axes, unit, strict=True):
            if axis in axes and abs(u) > _EPS:
                dec = min(dec, axis.config.max_deceleration / abs(u))
                if axis.config.max_jerk > 0.0:
                    jerk = min(jerk, axis.config.max_jerk / abs(u))
        if math.isinf(dec):  # nobody moves along ``unit``: any finite ramp will do
            dec = min((a.config.max_deceleration for a in axes), default=1.0)
        return Limits(math.inf, dec, dec, jerk)

    def _begin(self, element: _Element, t0: float, s0: float, v0: float, a0: float) -> None:
        """Make ``element`` the active one, starting at ``t0`` from the path state (s0, v0, a0)."""
        element.t0 = t0
        if element.move:
            try:
                element.profile, element.blend_out = self._plan(element, t0, s0, v0, a0, t0)
            except PlanningError:
                if element.ticket is not None:
                    element.ticket.status = Status.Error
                    element.ticket.error_id = ErrorID.EParam
                unit = element.unit
                p, v, a = (
                    _along(element.start, unit, s0),
                    [v0 * u for u in unit],
                    [a0 * u for u in unit],
                )
                element = self._ramp_element(
                    p, v, a, self.path_limits(unit, math.inf, 0, 0, 0), None
                )
                element.t0 = t0
        self._active = element

    def _replan_active(self) -> None:
        """Re-plan the active move for its (new) successor from the current path state."""
        element = self._active
        if element is None or not element.move or element.profile is None:
            return
        blend = element.blend_out
        t = self._t
        if blend is not None and t >= blend.begin:
            return  # the blend has begun: the corner stays as it is
        s, v, a = element.profile.at(t - element.t0)
        try:
            profile, blend = self._plan(element, t, s, v, a, t)
        except PlanningError:
            return
        element.profile, element.blend_out, element.t0 = profile, blend, t

    def _plan(
        self, element: _Element, t0: float, s0: float, v0: float, a0: float, now: float
    ) -> tuple[Profile, _Blend | None]:
        """Profile of a move from (s0, v0, a0) at ``t0`` and its blend into the queued successor.

        Raises:
            PlanningError: the move cannot be planned.
        """
        nxt = self._queue[0] if self._queue else None
        limits = element.limits
        if (
            nxt is None
            or not nxt.move
            or nxt.ticket is element.ticket
            or nxt.ticket is None
            or nxt.ticket.buffer_mode < MC_BufferMode.BlendingLow
            or element.length <= _EPS
            or nxt.length <= _EPS
            or _dot(element.unit, nxt.unit) <= _REVERSAL_COS
        ):
            return trajectory.move_to(s0, v0, a0, element.length, limits), None
        u1, u2 = element.unit, nxt.unit
        v_b = blend_velocity(nxt.ticket.buffer_mode, limits.velocity, nxt.limits.velocity, 1.0, 1.0)
        v_b = min(v_b, self.path_limits(u1, v_b, 0, 0, 0).velocity)
        v_b = min(v_b, self.path_limits(u2, v_b, 0, 0, 0).velocity)
        budget = min(
            limits.acceleration,
            limits.deceleration,
            nxt.limits.acceleration,
            nxt.limits.deceleration,
        )
        k = 0.0
        for axis, a, b in zip(self.axes, u1, u2, strict=True):
            k = max(k, abs(b - a) / min(budget, axis.config.max_acceleration))
        straight = k * budget < 1e-9
        for _ in range(_BLEND_TRIES):
            try:
                profile = trajectory.blend_to(s0, v0, a0, element.length, limits, v_b)
            except PlanningError:
                break
            speed = profile.end_velocity
            if speed <= _EPS:
                break
            t_c = t0 + profile.duration
            if straight:
                return profile, _Blend(element.end, u1, u2, speed, t_c, 0.0, nxt)
            for stretch in _BLEND_STRETCH:
                half = 1.875 * speed * k * stretch
                blend = _Blend(element.end, u1, u2, speed, t_c, half, nxt)
                verdict = self._blend_fits(element, nxt, profile, t0, blend, now)
                if verdict == _FITS:
                    return profile, blend
                if verdict != _TOO_HARD:
                    break  # a longer window would only deviate more
            v_b = _BLEND_SHRINK * speed
        return trajectory.move_to(s0, v0, a0, element.length, limits), None

    def _blend_fits(
        self,
        element: _Element,
        nxt: _Element,
        profile: Profile,
        t0: float,
        blend: _Blend,
        now: float,
    ) -> int:
        """Whether a blend window is acceptable: ``_FITS``, ``_TOO_HARD`` (an axis would exceed
        its max_acceleration: try a longer window) or ``_NO_FIT``.

        It fits when it starts in the future and after the element's own incoming blend, covers
        at most the second half of ``element`` and the first half of ``nxt`` (the start of
        ``nxt`` is estimated by planning it without its own successor), keeps the path within
        :attr:`corner_tolerance` of the polyline and every axis within its max_acceleration.
        """
        if blend.begin <= now or blend.begin < t0:
            return _NO_FIT
        if element.blend_in is not None and blend.begin < element.blend_in.end:
            return _NO_FIT
        if profile.at(blend.begin - t0)[0] < 0.5 * element.length:
            return _NO_FIT
        try:
            after = trajectory.move_to(0.0, blend.speed, 0.0, nxt.length, nxt.limits)
        except PlanningError:
            return _NO_FIT
        if after.at(blend.half)[0] > 0.5 * nxt.length:
            return _NO_FIT
        u1, u2 = element.unit, nxt.unit
        width = 2.0 * blend.half
        tolerance = self.corner_tolerance
        worst = 0.0
        too_hard = False
        for k in range(1, _BLEND_SAMPLES):
            t = blend.begin + width * k / _BLEND_SAMPLES
            if t <= blend.t_c:
                s, v, a = profile.at(t - t0)
                p2, v2 = blend.line(u2, t)
                q1 = (_along(element.start, u1, s), [v * u for u in u1], [a * u for u in u1])
                q2 = (p2, v2, [0.0] * len(u2))
            else:
                p1, v1 = blend.line(u1, t)
                s, v, a = after.at(t - blend.t_c)
                q1 = (p1, v1, [0.0] * len(u1))
                q2 = (_along(nxt.start, u2, s), [v * u for u in u2], [a * u for u in u2])
            p, _, acc = blend.mix(t, q1, q2)
            worst = max(
                worst,
                min(
                    distance_to_segment(p, element.start, element.end),
                    distance_to_segment(p, nxt.start, nxt.end),
                ),
            )
            if worst > tolerance:
                return _NO_FIT
            for axis, ai in zip(self.axes, acc, strict=True):
                if abs(ai) > axis.config.max_acceleration:
                    too_hard = True
        return _TOO_HARD if too_hard else _FITS

    def _next(self, element: _Element) -> _Element | None:
        """``element`` reached its end: report it and start what follows (at the exact end time)."""
        t_end = element.t0 + element.duration
        assert element.profile is not None
        _, v_end, _ = element.profile.at(element.duration)
        ticket = element.ticket
        if ticket is not None and element.completes and ticket.busy:
            ticket.status = Status.Done
        blend = element.blend_out
        nxt = self._queue.popleft() if self._queue else None
        if abs(v_end) > _EPS and (blend is None or nxt is not blend.successor):
            # the blending successor vanished: stop along the direction the blend had taken
            if nxt is not None:
                self._queue.appendleft(nxt)
            unit = blend.u_out if blend is not None else element.unit
            speed = blend.speed if blend is not None else v_end
            ramp = self._ramp_element(
                list(element.end),
                [speed * u for u in unit],
                [0.0] * len(unit),
                element.limits,
                None,
            )
            ramp.blend_in = blend
            ramp.t0 = t_end
            self._active = ramp
            return ramp
        if nxt is None:
            self._active = None
            self._end = list(element.end)
            return None
        if nxt.move and nxt.start != element.end:
            self._queue.appendleft(nxt)
            self._rechain(element)
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
        element = self._active
        while element is not None and t - element.t0 >= element.duration:
            element = self._next(element)
        if element is None:
            self._p = list(self._end) if self._end is not None else self._p
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
            self._p, self._v, self._a = element.point(t)
        self._t = t

    def _setpoint(self, index: int, t: float) -> tuple[float, float, float]:
        """Member ``index``'s component of the path point at the servo instant ``t`` [s]."""
        self._advance(t)
        return self._p[index], self._v[index], self._a[index]

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
            if element is not None and element.ticket is not None:
                tickets.append(element.ticket)
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
        """End every command with ``status`` and ramp a running path to standstill along its
        direction (the members' fastest ramp, or the default deceleration)."""
        self._abort_tickets(status=status, error_id=error_id)
        self._queue.clear()
        if self._active is None:
            return
        t, p, v, a = self._t, list(self._p), list(self._v), list(self._a)
        unit = self._direction(v)
        remaining = [ax for ax, m in zip(self.axes, self._members, strict=True) if m is not None]
        if not remaining:  # nobody left to follow the path
            self._active = None
            self._end = p
            return
        limits = (
            self._max_ramp(unit, remaining)
            if max_ramp
            else self.path_limits(unit, math.inf, 0.0, 0.0, 0.0)
        )
        ramp = self._ramp_element(p, v, a, limits, None)
        ramp.t0 = t
        self._active = ramp

    def _lose(self, lost: list[GroupMember]) -> None:
        """Members dropped out of the group motion (ErrorStop, power off): end the group's
        commands with the error (8001 for a following error) and stop the others along the path
        on their fastest ramp."""
        error = 0
        for member in lost:
            if member.status == Status.Error and not error:
                error = self._group_error(member.error_id)
        if error and not self.GroupErrorID:
            self.GroupErrorID = error
        self._abort_path(Status.Error if error else Status.Aborted, error, max_ramp=True)
        if error:
            self._stop = None


__all__ = ["AxesGroup", "GroupMember", "PathCommand", "distance_to_segment"]

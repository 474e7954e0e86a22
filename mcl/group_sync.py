"""Synchronized motion of an axes group and single axes: MC_SyncAxisToGroup, MC_MovePathSynchronized
(PLCopen Part 4 v2.0).

MC_SyncAxisToGroup couples a single axis (the slave) to a coordinate of the group's set point:
a member's position (ACS) or a coordinate of the tool point in the MCS or the PCS. The slave's
set point is ``Ratio · c(t) + Offset`` with c the coordinate at the servo instant (its velocity
and acceleration the feed-forward), whatever moves the group (a path, a stop ramp, a tracked
belt); the slave catches up from its own motion on a jerk-limited ramp of the difference.

MC_MovePathSynchronized runs a straight path of the group whose progress is a master axis'
position, not time: the path parameter s (the arc length from its start) is a function of the
master's travel x = m − MasterStart, laid out once at the edge as a jerk-limited motion S(x) from
rest to the path's end at rest whose slope is ``Ratio`` [mm of path per unit of master] between
its ramps; its curvature and its jerk are the group's Acceleration and Jerk at the master's
highest velocity. So a master at any velocity up to ``MasterVelocity`` drives the path within
the group's velocity and acceleration (plus Ratio × the master's own acceleration), the path
starts and ends at rest, stands while the master stands, and runs back when it runs back.
"""

from __future__ import annotations

__all__ = ["MC_MovePathSynchronized", "MC_SyncAxisToGroup", "MasterProfile"]

import math
from collections.abc import Sequence
from typing import Any, ClassVar

from mcl import trajectory
from mcl.axis import Axis
from mcl.command import Command, Status
from mcl.enums import MC_COORD_SYSTEM, AxisState, GroupState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import MotionFB, non_negative, number, positive
from mcl.gearing import DEFAULT_KV, MasterReader
from mcl.group import AxesGroup, PathCommand
from mcl.group_fb import COORD_SYSTEMS, GroupMotionFB, _vector, submit_moves
from mcl.kinematics import KinematicsError
from mcl.motion import ready_limits
from mcl.path import Element, Move
from mcl.path_clock import PathClock
from mcl.trajectory import Limits, PlanningError, Profile


# --------------------------------------------------------------------------- MC_SyncAxisToGroup
def group_coordinate(
    group: AxesGroup, coord: int, index: int, t: float
) -> tuple[float, float, float]:
    """Coordinate ``index`` of the group's set point at the servo instant ``t`` [s] in the
    coordinate system ``coord`` (MC_COORD_SYSTEM): position [mm, deg], velocity, acceleration.

    Raises:
        KinematicsError: the members' pose has no tool point.
        IndexError: the group has no such coordinate (it lost members).
    """
    axes = group.axes
    for axis in axes:
        axis.update_setpoint(t)
    q = [axis.sp_pos for axis in axes]
    qd = [axis.sp_vel for axis in axes]
    qdd = [axis.sp_acc for axis in axes]
    kin = group.kin
    if coord == MC_COORD_SYSTEM.ACS or kin.transform is None:
        return q[index], qd[index], qdd[index]
    p, v, a = kin.cartesian_state(q, qd, qdd)
    if coord == MC_COORD_SYSTEM.PCS and kin.frame is not None:
        p, v, a = kin.frame.from_mcs(p, v, a, t)
    return p[index], v[index], a[index]


class GroupFollow(Command):
    """MC_SyncAxisToGroup's command: the slave follows ``ratio · c + offset`` of a group
    coordinate c (:func:`group_coordinate`) after a ramp of the difference to zero (``signal``
    = InSync). A group in GroupErrorStop, or a coordinate that can no longer be read, stops the
    slave in ErrorStop with EMasterError 17."""

    state = AxisState.SynchronizedMotion
    accepts_buffered = False

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        group: AxesGroup,
        coordinate: tuple[int, int],
        gearing: tuple[float, float],
        limits: Limits,
    ) -> None:
        super().__init__(buffer_mode)
        self.group = group
        self.coord, self.index = coordinate
        self.ratio, self.offset = gearing
        self.limits = limits
        self.ramp: Profile | None = None

    def _read(self, axis: Axis) -> tuple[float, float, float] | None:
        """The coupled set point of the slave now, or None when the group fails it."""
        group = self.group
        group.update()
        if group.state == GroupState.GroupErrorStop:
            return None
        try:
            c, cv, ca = group_coordinate(group, self.coord, self.index, axis.t_cycle)
        except (KinematicsError, IndexError):
            return None
        r = self.ratio
        return r * c + self.offset, r * cv, r * ca

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        coupled = self._read(axis)
        if coupled is None:
            coupled = (p, v, a)  # the first set point stops the slave with the error
        c, cv, ca = coupled
        self.ramp = trajectory.move_to(p - c, v - cv, a - ca, 0.0, self.limits)

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        coupled = self._read(axis)
        if coupled is None:
            axis.fault(ErrorID.EMasterError)
            return axis.sp_pos, axis.sp_vel, axis.sp_acc
        p, v, a = coupled
        ramp = self.ramp
        if ramp is None:
            return p, v, a
        if t >= ramp.duration:
            self.ramp = None
            self.signal = True
            return p, v, a
        e, ev, ea = ramp.at(t)
        return p + e, v + ev, a + ea

    def finished(self) -> bool:
        return False


class MC_SyncAxisToGroup(MotionFB):
    """Couples the single axis ``Axis`` (the slave) to a coordinate of the group ``AxesGroup``'s
    set point (PLCopen Part 4): ``CoordSystem`` ACS a member's position (``Coordinate`` its
    index, 0 the first member), MCS or PCS a coordinate of the tool point (0 x, 1 y, 2 z; the
    members' coordinates where the group has no kinematic transformation). The slave's set
    point is ``Ratio`` × the coordinate + ``Offset`` [u]; it catches up from its own motion on a
    jerk-limited ramp of the difference (``Velocity``, ``Acceleration``, ``Deceleration``,
    ``Jerk`` of the difference; 0 = the slave's Vmax and defaults), then ``InSync``. It follows
    whatever moves the group and never ends by itself (Done stays FALSE): any Aborting motion
    command on the slave ends it (CommandAborted); Buffered and blending commands cannot queue
    behind it. The coupling does not limit the slave: Ratio × the coordinate's velocity beyond
    the slave's Vmax ends in its following error (ERRPOS 2001), as a geared slave's would.

    Errors at the edge (the slave and the group left alone): the slave's readiness errors as for
    every motion block (a member of a group: EGroupMember 1000); 1005 an empty group, Epower 10
    the group not enabled, Eerrstop 11 in GroupErrorStop; EParam 5 for an unknown CoordSystem,
    a Coordinate the group does not have, Ratio or Offset not finite, invalid ramp inputs;
    EWorkspace 24 / ESingular 25 when the members stand where the kinematics has no tool point.
    While it runs: the group in GroupErrorStop, or its tool point lost, stops the slave on its
    fastest ramp in ErrorStop with EMasterError 17.
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup", "Axis")
    INPUTS: ClassVar[tuple[str, ...]] = (
        "CoordSystem",
        "Coordinate",
        "Ratio",
        "Offset",
        "Velocity",
        "Acceleration",
        "Deceleration",
        "Jerk",
    )
    CoordSystem: int = MC_COORD_SYSTEM.MCS
    Coordinate: int = 0
    Ratio: float = 1.0
    Offset: float = 0.0
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.InSync = False

    def _command(self, mode: MC_BufferMode) -> Command | int:
        slave, group = self.axis, self.group
        error = slave.check_ready() or self._group_error(group)
        if error:
            return error
        assert slave.constants is not None
        velocity = number(self.Velocity) or slave.constants.Vmax
        limits = ready_limits(slave, velocity, self.Acceleration, self.Deceleration, self.Jerk)
        if isinstance(limits, int):
            return limits
        coord, index = self.CoordSystem, self.Coordinate
        cartesian = coord != MC_COORD_SYSTEM.ACS and group.kin.transform is not None
        size = 3 if cartesian else len(group.axes)
        gearing = number(self.Ratio), number(self.Offset)
        if (
            coord not in COORD_SYSTEMS
            or not 0 <= index < size
            or not all(math.isfinite(x) for x in gearing)
        ):
            return ErrorID.EParam
        try:
            group_coordinate(group, coord, index, slave.t_cycle)
        except KinematicsError as refused:
            return int(refused.error_id)
        return GroupFollow(mode, group, (coord, index), gearing, limits)

    @staticmethod
    def _group_error(group: AxesGroup) -> int:
        """1005 an empty group, Epower 10 one not enabled, Eerrstop 11 in GroupErrorStop."""
        if not group.axes:
            return ErrorID.EGroupEmpty
        if not group.enabled:
            return ErrorID.Epower
        group.update()
        return ErrorID.Eerrstop if group.state == GroupState.GroupErrorStop else 0

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        self.InSync = self._reached()


# ---------------------------------------------------------------------- MC_MovePathSynchronized
class MasterProfile(Profile):
    """The path parameter of a synchronized path as a function of the master (module
    docstring): ``at`` reads the master at its servo instant and returns s = S(x), ṡ = S'·ṁ,
    s̈ = S''·ṁ² + S'·m̈ in path time (the group's time scaling taken out, so the override
    does not act on it). Never ends until the master has travelled the whole of S; then
    ``duration`` is the path time of that instant, and the path rests at its end.

    Args:
        plan: S, over the master's travel from MasterStart [u] (its "time").
        reader: the master.
        start: MasterStart, in the reader's coordinate [u].
        clock: the group's path clock.
    """

    def __init__(self, plan: Profile, reader: MasterReader, start: float, clock: PathClock) -> None:
        super().__init__(plan.segments, math.inf)
        self.plan = plan
        self.reader = reader
        self.start = start
        self.clock = clock

    def at(self, t: float) -> tuple[float, float, float]:
        plan = self.plan
        if self.duration < math.inf:  # the end was reached: the path rests there
            return plan.end_position, 0.0, 0.0
        reader = self.reader
        reader.read(reader.master.t_cycle)
        x = reader.position - self.start
        if x >= plan.duration:
            self.duration = t
            return plan.end_position, 0.0, 0.0
        if x <= 0.0:
            return 0.0, 0.0, 0.0
        s, slope, bend = plan.at(x)
        w = reader.velocity
        v, a = slope * w, bend * w * w + slope * reader.acceleration
        f = self.clock.factor
        if f <= 0.0:
            return s, 0.0, 0.0
        v_path = v / f
        return s, v_path, (a - self.clock.rate * v_path) / (f * f)


class MC_MovePathSynchronized(GroupMotionFB):
    """A straight path of the group to ``Position`` whose progress follows the master axis
    ``Master`` (PLCopen Part 4; module docstring): the path stands at its start until the
    master passes ``MasterStart`` [u], then its arc length is S(m − MasterStart), of slope
    ``Ratio`` [mm of path per unit of master; > 0] between the ramps at its ends, laid out for
    the master up to ``MasterVelocity`` [u/s] (0 = the master's Vmax) and the path's
    ``Acceleration``, ``Deceleration`` and ``Jerk`` (0 = defaults). Done once the master has
    driven the path to its end (the group then stands, or rests in a moving PCS). The override
    and a feed hold do not act on it (the master's position is its clock); a stop
    (MC_GroupStop, MC_GroupHalt) or an Aborting move leaves the master and ramps the path to
    rest. ``CoordSystem`` and the buffer modes Aborting (the group must stand) and Buffered as
    the moves'.

    Errors (the group left alone): those of the moves (1005, Epower 10, Eerrstop 11, EAxStop 6,
    Ehome 9, Ecil 8, EWorkspace 24, ESingular 25); EParam 5 for a Position that is not one
    finite number per member, an unknown CoordSystem or MCS while a PCS is set, MasterStart not
    finite, Ratio not > 0, MasterVelocity, Acceleration, Deceleration or Jerk negative or not
    finite (MasterVelocity 0 for a master without constants), a master that is a member of the
    group, Aborting while the group moves, a blending BufferMode, a path of no length;
    EMasterError 17 for a master in ErrorStop or with a failed encoder; ETrackTooFast 26 when
    Ratio × MasterVelocity exceeds the velocity the path may have (the members' or the tool
    point's limits).
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup", "Master")
    INPUTS: ClassVar[tuple[str, ...]] = (
        "Position",
        "CoordSystem",
        "MasterStart",
        "Ratio",
        "MasterVelocity",
        "Acceleration",
        "Deceleration",
        "Jerk",
    )
    Master: Axis | None = None
    Position: Sequence[float] = ()
    CoordSystem: int = MC_COORD_SYSTEM.MCS
    MasterStart: float = 0.0
    Ratio: float = 1.0
    MasterVelocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready()
        if error:
            return error
        master = self.Master
        assert master is not None
        if master.state == AxisState.ErrorStop or not master.io.encoder_ok:
            return ErrorID.EMasterError
        mode = ticket.buffer_mode
        target = _vector(self.Position, len(group.axes))
        inputs = self._inputs(master)
        if (
            inputs is None
            or target is None
            or master in group.axes
            or mode not in (MC_BufferMode.Aborting, MC_BufferMode.Buffered)
            or (mode == MC_BufferMode.Aborting and group.has_path)
            or self.CoordSystem not in COORD_SYSTEMS
            or (self.CoordSystem == MC_COORD_SYSTEM.MCS and group.kin.frame is not None)
        ):
            return ErrorID.EParam
        start, ratio, top, a, d, j = inputs
        joint = group.kin.transform is not None and self.CoordSystem == MC_COORD_SYSTEM.ACS
        move = Move(target, (ratio * top, a, d, j), mode, joint=joint)

        def synchronize(elements: list[Element]) -> int:
            return _synchronize(elements[0], master, (start, ratio, top), group.clock)

        return submit_moves(group, ticket, [move], True, synchronize)

    def _inputs(self, master: Axis) -> tuple[float, float, float, float, float, float] | None:
        """MasterStart, Ratio, the master's top velocity, Acceleration, Deceleration, Jerk when
        valid, else None."""
        start, ratio = number(self.MasterStart), number(self.Ratio)
        top, a = number(self.MasterVelocity), number(self.Acceleration)
        d, j = number(self.Deceleration), number(self.Jerk)
        if not all(non_negative(x) for x in (top, a, d, j)):
            return None
        if not math.isfinite(start) or not positive(ratio):
            return None
        if top == 0.0:
            if master.constants is None:
                return None
            top = master.constants.Vmax
        return start, ratio, top, a, d, j


def _synchronize(
    element: Element, master: Axis, law: tuple[float, float, float], clock: PathClock
) -> int:
    """Make the checked ``element`` follow ``master`` by the law (MasterStart, Ratio, the
    master's top velocity) (:class:`MasterProfile`), or return the error that refuses it."""
    start, ratio, top = law
    limits = element.limits
    if ratio * top > min(limits.velocity, element.cap) * (1.0 + 1e-9):
        return ErrorID.ETrackTooFast
    if element.length <= 0.0:
        return ErrorID.EParam
    over_master = Limits(
        ratio,
        limits.acceleration / top**2,
        limits.deceleration / top**2,
        min(limits.jerk, element.jerk) / top**3,
    )
    try:
        plan = trajectory.move_to(0.0, 0.0, 0.0, element.length, over_master)
    except PlanningError:
        return ErrorID.EParam
    reader = MasterReader(master, DEFAULT_KV)
    element.profile = MasterProfile(plan, reader, start, clock)
    element.move = None  # laid out by the master: never planned in time again
    return 0

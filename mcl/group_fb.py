"""Function blocks of axes groups (MotionControlLib chapter 5).

Every block has the in-out ``AxesGroup`` (an :class:`mcl.group.AxesGroup`);
MC_AddAxisToGroup also has ``Axis``. Positions and distances are lists with one value per member
in the order the members were added [mm]; Velocity [mm/s], Acceleration, Deceleration [mm/s²] and
Jerk [mm/s³] act along the path (0 = default, values above what a member allows are clamped).

Beyond the Teco library: MC_GroupEnable, MC_GroupDisable, MC_GroupReset, MC_GroupStop,
MC_MoveLinearRelative, MC_MoveCircularAbsolute/Relative, MC_MoveDirectAbsolute/Relative
(PLCopen Part 4; MC_MovePath and MC_PathSelect: :mod:`mcl.path_table`, :mod:`mcl.gcode`). A
group that is not enabled refuses motion commands with ``Epower`` 10; a member change while the
group moves is refused with ``EParam`` 5.

Group paths. A group motion is a path of lines, circular arcs and helices in the members'
coordinates, each piece a function of its arc length s; the motion along it is a time-optimal
jerk-limited profile s(t), and the members follow the path point p(s(t)). The shape in space
therefore never depends on the speed: a stop (MC_GroupStop, MC_GroupDisable, an Aborting command
that must stop the motion first, a member's fault) ramps s down on the same path, so a group
stopped in an arc stands on its circle (a feed hold or an override acts on s(t) alone).

Limits along a line: a limit of member i allows limit_i / |u_i| along the path (u the direction
cosines), so no member exceeds its Vmax, max_acceleration, max_deceleration or max_jerk. Along an
arc of radius R (curvature κ = 1/R and ρ = |dK/ds| = 1/R²; a helix of sweep Θ and length L has
κ = R·(Θ/L)² and ρ = R·(Θ/L)³) every member's acceleration and jerk are components of the
vectors a = s̈·T + ṡ²·κ·N and j = s⃛·T + 3·ṡ·s̈·κ·N + ṡ³·dK/ds; the block's Acceleration A
(and Deceleration), lowered to the smallest max_acceleration and max_deceleration of the members
that move, and its Jerk J bound their lengths. So the path runs an arc at most at √(0.7·A·R)
(the centripetal acceleration v²/R takes at most 70 % of A) and at (0.5·J·R²)^(1/3) (the
centripetal jerk v³/R² at most half of J), and at each member's Vmax: this is where the path
slows for a tight arc (R = 2 mm, A = 2000 mm/s², J = 50000 mm/s³: 46 mm/s). At that velocity v
the acceleration along the arc is √(A² − (v²/R)²) and at most (J − v³/R²)·R / (6·v), the jerk
along it the rest, J − v³/R² − 3·v·s̈/R. Before a piece the path has slowed to what the pieces
behind it allow (look-ahead over every queued piece; the last one ends at standstill).

Corners. With a Blending BufferMode a corner is rounded within the group's corner tolerance, the
blending velocity given by the BufferMode (never faster than an arc's own velocity); a line
into a tangent arc has no corner but a step of the centripetal acceleration v²/R, which is
spread over a blend of reach 2.8125·v³/(R·J), so that the jerk stays within J (with a low jerk
the velocity may dip there: 200 → 140 mm/s into R 50 at J 20000 mm/s³, none at 50000). The
moves take PLCopen's ``CoordSystem`` (ACS, MCS and PCS coincide unless the
group has a kinematic transformation, :mod:`mcl.kin_fb`; PCS is MCS until
MC_SetCoordinateTransform, MC_TrackConveyorBelt or MC_TrackRotaryTable sets one,
:mod:`mcl.tracking`, and then a position in MCS is refused with EParam 5) and
``TransitionMode``: TMNone rounds the corner into the move within the group's corner tolerance,
TMMaxCornerDeviation within ``TransitionParameter[0]`` [mm], TMCornerDistance leaves the path at
most ``TransitionParameter[0]`` [mm] from the corner; TMStartVelocity and TMConstantVelocity are
not offered (EParam 5).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, ClassVar

from mcl.command import Status
from mcl.enums import (
    MC_CIRC_MODE,
    MC_CIRC_PATHCHOICE,
    MC_COORD_SYSTEM,
    MC_TRANSITION_MODE,
    GroupState,
    MC_BufferMode,
)
from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB, MotionFB, non_negative, number, positive
from mcl.geometry import GeometryError
from mcl.group import AxesGroup
from mcl.group_kinematics import refusal
from mcl.kinematics import KinematicsError
from mcl.path import ARC, Element, Move, PathCommand


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
    """Publishes the group's actual position ``Position`` (MotionControlLib §5.5): in ACS the
    members' actual positions in member order [mm, deg]; in MCS and PCS the tool point of them
    [mm] through the group's kinematic transformation (:mod:`mcl.kin_fb`; without one the
    members' positions), in PCS relative to the group's product coordinate system (moving with
    a tracked belt: :mod:`mcl.tracking`). 1005 when the group has no axes, EParam 5 for an unknown
    ``CoordSystem``, EWorkspace 24 / ESingular 25 when the members stand where the kinematics
    has no tool point."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("CoordSystem",)
    CoordSystem: int = MC_COORD_SYSTEM.MCS

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Position: list[float] = []

    def _evaluate(self) -> int:
        group = self.group
        self.Position = []
        if not group.axes:
            return ErrorID.EGroupEmpty
        if self.CoordSystem not in COORD_SYSTEMS:
            return ErrorID.EParam
        joints = [axis.POS for axis in group.axes]
        coord = self.CoordSystem
        try:
            self.Position = group.kin.convert(joints, True, coord == MC_COORD_SYSTEM.ACS)
            frame = group.kin.frame
            if coord == MC_COORD_SYSTEM.MCS and frame is not None:
                self.Position = frame.point_to_mcs(self.Position)
        except KinematicsError as refused:
            return int(refused.error_id)
        return 0

    def _disable(self) -> None:
        self.Position = []


class GroupMotionFB(MotionFB):
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


class _PathMoveFB(GroupMotionFB):
    """A group move along a piece of path: Velocity, Acceleration, Deceleration, Jerk (along the
    path; 0 = default), CoordSystem, TransitionMode and TransitionParameter (the corner into
    this move when it blends).

    Subclasses implement :meth:`_moves` (the pieces from the sampled inputs, or None for an
    invalid input).
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "Velocity",
        "Acceleration",
        "Deceleration",
        "Jerk",
        "CoordSystem",
        "TransitionMode",
        "TransitionParameter",
    )
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0
    CoordSystem: int = MC_COORD_SYSTEM.MCS
    TransitionMode: int = MC_TRANSITION_MODE.TMNone
    TransitionParameter: Sequence[float] = ()
    NEEDS_REF: ClassVar[bool] = False
    DIRECT: ClassVar[bool] = False

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready()
        if error:
            return error
        if self.CoordSystem not in COORD_SYSTEMS or self._mcs_in_pcs(group):
            return ErrorID.EParam
        params = self._dynamics(group)
        transition = transition_of(self.TransitionMode, self.TransitionParameter)
        if params is None or transition is None:
            return ErrorID.EParam
        try:
            moves = self._moves(group, ticket.buffer_mode, params)
        except KinematicsError as refused:
            return int(refused.error_id)
        if moves is None:
            return ErrorID.EParam
        joint = self._joint_space(group)
        for move in moves:
            move.tolerance, move.reach = transition
            move.joint = joint
            if joint and not self._in_acs:  # a direct move to a target given in MCS
                try:
                    move.end = group.kin.convert(move.end, False, True)
                except KinematicsError as refused:
                    return int(refused.error_id)
        return submit_moves(group, ticket, moves, self.NEEDS_REF)

    def _mcs_in_pcs(self, group: AxesGroup) -> bool:
        """A position in MCS while the group's path runs in a PCS of its own
        (:mod:`mcl.tracking`): refused."""
        return self.CoordSystem == MC_COORD_SYSTEM.MCS and group.kin.frame is not None

    @property
    def _in_acs(self) -> bool:
        """The block's positions are the members' own coordinates."""
        return self.CoordSystem == MC_COORD_SYSTEM.ACS

    def _joint_space(self, group: AxesGroup) -> bool:
        """The move runs in the members' coordinates (a direct move, or a move in ACS, of a
        group with a kinematic transformation: :mod:`mcl.group_kinematics`)."""
        return group.kin.transform is not None and (self.DIRECT or self._in_acs)

    def _dynamics(self, group: AxesGroup) -> tuple[float, float, float, float] | None:
        """Velocity, Acceleration, Deceleration, Jerk when valid (SPEC section 3), else None."""
        v, a = number(self.Velocity), number(self.Acceleration)
        d, j = number(self.Deceleration), number(self.Jerk)
        if not positive(v) or not (non_negative(a) and non_negative(d) and non_negative(j)):
            return None
        transform = group.kin.transform
        if transform is not None and not self._joint_space(group):
            if v < 0.01 * transform.tcp.velocity:
                return None
        elif any(axis.velocity_too_low(v) for axis in group.axes):
            return None
        limits = group.nominal_limits(v, a, d, j)
        if min(limits.acceleration, limits.deceleration) * 100.0 < v:
            return None
        return v, a, d, j

    def _moves(
        self, group: AxesGroup, mode: MC_BufferMode, params: tuple[float, float, float, float]
    ) -> list[Move] | None:
        raise NotImplementedError


COORD_SYSTEMS = frozenset(int(c) for c in MC_COORD_SYSTEM)


def transition_of(mode: int, parameters: Any) -> tuple[float, float] | None:
    """The corner tolerance and reach [mm] of a TransitionMode (0 = the group's defaults), or
    None when it is invalid: TMNone; TMMaxCornerDeviation and TMCornerDistance take
    TransitionParameter[0] > 0; TMStartVelocity and TMConstantVelocity are not offered."""
    if mode == MC_TRANSITION_MODE.TMNone:
        return 0.0, 0.0
    if mode not in (MC_TRANSITION_MODE.TMCornerDistance, MC_TRANSITION_MODE.TMMaxCornerDeviation):
        return None
    values = _vector(parameters, len(parameters)) if isinstance(parameters, Sequence) else None
    if not values or not positive(values[0]):
        return None
    if mode == MC_TRANSITION_MODE.TMMaxCornerDeviation:
        return values[0], 0.0
    return 0.0, values[0]


def submit_moves(
    group: AxesGroup,
    ticket: PathCommand,
    moves: list[Move],
    needs_ref: bool,
    adapt: Callable[[list[Element]], int] | None = None,
) -> int:
    """Build the elements of ``moves`` and hand them to the group, or return the error that
    refuses them without touching the group: Ehome 9 (``needs_ref`` and a member without Ref),
    EParam 5 (a piece that describes no path), Ecil 8 (a piece that passes a member's SW
    limit), EWorkspace 24 / ESingular 25 (a Cartesian piece the kinematics refuses), or the
    error of ``adapt``, which may change the checked elements before they are handed over."""
    axes = group.axes
    if needs_ref and not all(axis.Ref for axis in axes):
        return ErrorID.Ehome
    try:
        elements = group.prepare(ticket, moves)
    except (GeometryError, KinematicsError) as refused:
        return refusal(refused)
    for element in elements:
        if group.kin.cartesian(element.joint):
            continue  # checked point by point (GroupKinematics.hold_joints)
        for axis, (lo, hi) in zip(axes, element.geometry.bounds(), strict=True):
            error = axis.check_target(lo) or axis.check_target(hi)
            if error:
                return error
    error = adapt(elements) if adapt is not None else 0
    if error:
        return error
    group.submit(ticket, elements)
    return 0


class MC_MoveLinearAbsolute(_PathMoveFB):
    """Linear interpolation of the group to the absolute point ``Position`` [mm]
    (MotionControlLib §5.6).

    The tool point stays on the straight line from the start point; all buffer modes
    (Blending*: the corner is rounded within the group's corner tolerance, or as
    TransitionMode says). Needs Ref on every member (Ehome 9); a target beyond a member's SW
    limit → Ecil 8; a Position that is not a list of finite numbers, one per member → EParam 5.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Position",)
    Position: Sequence[float] = ()
    NEEDS_REF: ClassVar[bool] = True

    def _moves(
        self, group: AxesGroup, mode: MC_BufferMode, params: tuple[float, float, float, float]
    ) -> list[Move] | None:
        target = _vector(self.Position, len(group.axes))
        return None if target is None else [Move(target, params, mode, direct=self.DIRECT)]


class MC_MoveLinearRelative(_PathMoveFB):
    """Linear interpolation of the group by ``Distance`` [mm] (PLCopen Part 4).

    The distance counts from the current path point when the move aborts (the actual positions
    when the group stands), from the end of the last queued move otherwise. No Ref needed.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Distance",)
    Distance: Sequence[float] = ()

    def _moves(
        self, group: AxesGroup, mode: MC_BufferMode, params: tuple[float, float, float, float]
    ) -> list[Move] | None:
        distance = _vector(self.Distance, len(group.axes))
        if distance is None:
            return None
        start = group.start_point(mode, self._in_acs)
        target = [s + d for s, d in zip(start, distance, strict=True)]
        return [Move(target, params, mode, direct=self.DIRECT)]


class MC_MoveDirectAbsolute(MC_MoveLinearAbsolute):
    """Synchronized point-to-point move of the group to the absolute ``Position`` [mm] in the
    members' own coordinates (PLCopen Part 4): every member starts and ends together.

    Velocity, Acceleration, Deceleration and Jerk bind every member's own motion (each lowered to
    that member's maxima; 0 = the member's default), not the path: the member that needs longest
    runs at them and the others are slowed to arrive with it. With a kinematic transformation a
    Position in MCS is turned into the members' coordinates first (:mod:`mcl.kin_fb`); without
    one the members' coordinates are the machine's and the tool point moves on the straight
    line, faster than MC_MoveLinearAbsolute's path velocity where several members move. Needs
    Ref; errors as MC_MoveLinearAbsolute.
    """

    CoordSystem: int = MC_COORD_SYSTEM.ACS
    DIRECT: ClassVar[bool] = True


class MC_MoveDirectRelative(MC_MoveLinearRelative):
    """Synchronized point-to-point move of the group by ``Distance`` [mm] (PLCopen Part 4):
    every member starts and ends together, the limits as MC_MoveDirectAbsolute. No Ref needed."""

    CoordSystem: int = MC_COORD_SYSTEM.ACS
    DIRECT: ClassVar[bool] = True


class _MoveCircularFB(_PathMoveFB):
    """Common inputs of the arcs: CircMode, AuxPoint, EndPoint, PathChoice, and beyond PLCopen
    Plane and Turns."""

    INPUTS: ClassVar[tuple[str, ...]] = (
        "CircMode",
        "AuxPoint",
        "EndPoint",
        "PathChoice",
        "Plane",
        "Turns",
    )
    CircMode: int = MC_CIRC_MODE.BORDER
    AuxPoint: Sequence[float] = ()
    EndPoint: Sequence[float] = ()
    PathChoice: int = MC_CIRC_PATHCHOICE.CLOCKWISE
    Plane: int = 0
    Turns: int = 0
    RELATIVE: ClassVar[bool] = False

    def _moves(
        self, group: AxesGroup, mode: MC_BufferMode, params: tuple[float, float, float, float]
    ) -> list[Move] | None:
        size = len(group.axes)
        end = _vector(self.EndPoint, size)
        radius = self.CircMode == MC_CIRC_MODE.RADIUS
        aux_value = self.AuxPoint
        aux_size = len(aux_value) if radius and isinstance(aux_value, Sequence) else size
        aux = _vector(aux_value, aux_size) if aux_size else None
        if end is None or aux is None:
            return None
        aux = (aux + [0.0] * size)[:size]
        if self.RELATIVE:
            start = group.start_point(mode, self._in_acs)
            end = [s + e for s, e in zip(start, end, strict=True)]
            if not radius:
                aux = [s + x for s, x in zip(start, aux, strict=True)]
        move = Move(
            end,
            params,
            mode,
            ARC,
            aux,
            self.CircMode,
            self.PathChoice,
            self.Plane,
            self.Turns,
        )
        return [move]


class MC_MoveCircularAbsolute(_MoveCircularFB):
    """Circular interpolation of the group from where the previous motion ends to the absolute
    ``EndPoint`` [mm] (PLCopen Part 4): an arc, a full circle or several turns, in any plane of
    the members, or a helix.

    ``CircMode`` says what the absolute ``AuxPoint`` is: BORDER a point on the arc (the three
    points give the plane and the direction; PathChoice is ignored; no full circle), CENTER the
    centre (``EndPoint`` equal to the start: a full circle; ``Turns`` adds full turns), RADIUS
    the radius as its first value (> 0: the arc of at most 180°, < 0: the longer one).
    ``PathChoice`` CLOCKWISE or COUNTERCLOCKWISE, seen from the positive normal of the plane.
    ``Plane`` (beyond PLCopen): 0 the plane the points give (else that of members 1 and 2), 17
    members 1–2 (XY), 18 members 3–1 (ZX), 19 members 2–3 (YZ); the remaining member moves
    linearly to its end coordinate (a helix). Velocity, Acceleration, Deceleration and Jerk act
    along the path; the velocity is lowered where the curvature needs it so that every member
    stays within its limits (docs/reference.md, Group paths). Needs Ref (Ehome 9); an arc
    passing a member's SW limit → Ecil 8; points that are not finite, BORDER points on a line
    (a circle over 1000 times its chord), a radius shorter than half the chord, an end point
    off the circle (CENTER, beyond 0.1 % of the radius), an arc of zero length, an unknown
    CircMode, PathChoice or Plane → EParam 5.
    """

    NEEDS_REF: ClassVar[bool] = True


class MC_MoveCircularRelative(_MoveCircularFB):
    """MC_MoveCircularAbsolute with ``EndPoint`` and (BORDER and CENTER) ``AuxPoint`` relative to
    the start point [mm]: the current path point when the move aborts, the end of the last
    queued move otherwise (PLCopen Part 4). No Ref needed."""

    RELATIVE: ClassVar[bool] = True


class MC_GroupStop(GroupMotionFB):
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
    "COORD_SYSTEMS",
    "GroupMotionFB",
    "MC_AddAxisToGroup",
    "MC_GroupDisable",
    "MC_GroupEnable",
    "MC_GroupReadActualPosition",
    "MC_GroupReadError",
    "MC_GroupReadStatus",
    "MC_GroupReset",
    "MC_GroupStop",
    "MC_MoveCircularAbsolute",
    "MC_MoveCircularRelative",
    "MC_MoveDirectAbsolute",
    "MC_MoveDirectRelative",
    "MC_MoveLinearAbsolute",
    "MC_MoveLinearRelative",
    "MC_UngroupAllAxes",
    "submit_moves",
    "transition_of",
]

"""Path tables: MC_PATH_DATA_REF, MC_MovePath and MC_PathSelect (PLCopen Part 4).

A path table (PLCopen leaves MC_PATH_DATA_REF to the vendor) is a list of segments, lines and
arcs, each described as MC_MoveLinear* and MC_MoveCircular* describe them:
``mcl.MC_PATH_DATA_REF(Segments=[mcl.MC_PATH_SEGMENT(EndPoint=[x, y], Velocity=50.0), …])``;
an ST program passes a STRUCT of its own with the same fields (``NumberOfSegments`` set, and
``Segments`` an ARRAY of STRUCTs with the segment fields it needs: a field it lacks keeps the
default). :func:`mcl.read_gcode` (or MC_PathSelect, :mod:`mcl.gcode`) makes one from a small
G-code subset, which is how a CAD/CAM system hands a contour over.

A segment's ``EndPoint`` has one value per member (further values must be NaN, or 0 when
relative: G-code's Z on a group of two); a NaN keeps that member's coordinate (relative: moves it
by 0). ``Relative`` makes ``EndPoint`` relative to where
the segment starts, ``AuxRelative`` does the same for a BORDER or CENTER ``AuxPoint`` (G-code's
I, J, K). ``Velocity`` 0 is a rapid move (G00): the line at :data:`RAPID_SHARE` of the Vmax of
the member that moves most. ``BufferMode`` says how the segment follows the one before
(default BlendingLow: no stop, the corner rounded within the group's corner tolerance;
Buffered: an exact stop); the first segment follows MC_MovePath's own BufferMode.

MC_MovePath checks the whole table on the rising edge of ``Execute``, from where the path starts
(the current path point when it aborts, the end of the last queued motion otherwise), before it
touches the group: every segment must describe a valid line or arc with valid dynamics (else
EParam 5) within the members' SW limits (Ecil 8). It is Done when the last segment ends.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar, Final

from mcl.enums import (
    MC_CIRC_MODE,
    MC_CIRC_PATHCHOICE,
    MC_COORD_SYSTEM,
    MC_TRANSITION_MODE,
    MC_BufferMode,
)
from mcl.errors import ErrorID
from mcl.fb import non_negative, number
from mcl.group import AxesGroup
from mcl.group_fb import COORD_SYSTEMS, GroupMotionFB, submit_moves, transition_of
from mcl.kinematics import KinematicsError
from mcl.path import ARC, LINE, Move, PathCommand
from mcl.profiles import TableRef

RAPID_SHARE: Final = 0.8
"""A rapid segment (Velocity 0) runs the member that moves most at this share of its Vmax."""
MAX_SEGMENTS: Final = 10000
"""The most segments one table may hold (a longer one → EParam)."""


@dataclass
class MC_PATH_SEGMENT:
    """One segment of a path table (module docstring); the fields are MC_MoveLinear*'s and
    MC_MoveCircular*'s inputs.

    Attributes:
        Circular: an arc (CircMode, AuxPoint, PathChoice, Plane, Turns); FALSE: a line.
        EndPoint: where the segment ends [mm] (NaN: the member's coordinate unchanged).
        AuxPoint: the arc's auxiliary point, centre, or radius first [mm].
        Relative: EndPoint is relative to the segment's start.
        AuxRelative: a BORDER or CENTER AuxPoint is relative to the segment's start.
        Velocity: along the path [mm/s]; 0: rapid.
        Acceleration, Deceleration, Jerk: along the path; 0: the default.
        BufferMode: how the segment follows the one before (the first: MC_MovePath's).
        Source: where it came from, for messages (``file:line``).
    """

    Circular: bool = False
    EndPoint: Sequence[float] = ()
    AuxPoint: Sequence[float] = ()
    CircMode: int = MC_CIRC_MODE.BORDER
    PathChoice: int = MC_CIRC_PATHCHOICE.CLOCKWISE
    Plane: int = 0
    Turns: int = 0
    Relative: bool = False
    AuxRelative: bool = False
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0
    BufferMode: int = MC_BufferMode.BlendingLow
    Source: str = ""


@dataclass
class MC_PATH_DATA_REF:
    """A path table: ``Segments`` (:class:`MC_PATH_SEGMENT`), of which MC_MovePath runs the first
    ``NumberOfSegments`` (None: all); ``Name`` says where it came from."""

    Segments: list[Any] = field(default_factory=list)
    NumberOfSegments: int | None = None
    Name: str = ""


_DEFAULT_SEGMENT = MC_PATH_SEGMENT()
"""The fields a segment of a program's own STRUCT lacks (read from an instance: the class of a
compiled dataclass holds descriptors, not the defaults)."""


def _field(segment: Any, name: str) -> Any:
    return getattr(segment, name, getattr(_DEFAULT_SEGMENT, name, None))


def _values(value: Any) -> list[float] | None:
    """A point field as floats (NaN allowed), None unless a sequence of numbers."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        return None
    return [number(x) for x in value]


def _point(value: Any, start: Sequence[float], relative: bool) -> list[float] | None:
    """A segment point resolved against ``start``: NaN keeps the coordinate (relative: adds 0);
    None when it has fewer values than members, a value beyond them that moves (not NaN, nor a
    relative 0), or an infinity."""
    values = _values(value)
    size = len(start)
    if values is None or len(values) < size or any(math.isinf(x) for x in values):
        return None
    if any(not (math.isnan(x) or (relative and x == 0.0)) for x in values[size:]):
        return None  # the segment moves a member the group does not have
    point = []
    for s, x in zip(start, values[:size], strict=True):
        if math.isnan(x):
            point.append(s)
        else:
            point.append(s + x if relative else x)
    return point


def segments_of(table: Any) -> list[Any] | None:
    """The segments MC_MovePath runs from ``table``, or None when it is no valid table."""
    segments = getattr(table, "Segments", None)
    if isinstance(segments, str | bytes) or not isinstance(segments, Sequence):
        return None
    count = getattr(table, "NumberOfSegments", None)
    count = len(segments) if count is None else count
    if not isinstance(count, int) or not 0 < count <= min(len(segments), MAX_SEGMENTS):
        return None
    return list(segments[:count])


def _rapid(group: AxesGroup, start: Sequence[float], end: Sequence[float]) -> float:
    """The velocity of a rapid line: :data:`RAPID_SHARE` of the Vmax of the member that moves
    most (its share of the path) [mm/s]."""
    length = math.dist(start, end)
    speed = slowest = math.inf
    for axis, a, b in zip(group.axes, start, end, strict=True):
        if axis.constants is not None:
            slowest = min(slowest, RAPID_SHARE * axis.constants.Vmax)
            if abs(b - a) > 0.0:
                speed = min(speed, RAPID_SHARE * axis.constants.Vmax * length / abs(b - a))
    return speed if math.isfinite(speed) else slowest


def path_moves(
    group: AxesGroup, segments: Sequence[Any], mode: MC_BufferMode, start: Sequence[float]
) -> list[Move] | None:
    """The moves of a table's ``segments`` from ``start`` [mm] (module docstring), the first in
    ``mode``; None when a segment is invalid (its points, dynamics or BufferMode)."""
    moves: list[Move] = []
    here = list(start)
    for i, segment in enumerate(segments):
        relative = bool(_field(segment, "Relative"))
        end = _point(_field(segment, "EndPoint"), here, relative)
        params = [
            number(_field(segment, n)) for n in ("Velocity", "Acceleration", "Deceleration", "Jerk")
        ]
        try:
            follow = mode if i == 0 else MC_BufferMode(_field(segment, "BufferMode"))
        except ValueError:
            return None
        if end is None or not all(non_negative(x) for x in params):
            return None
        if params[0] == 0.0:
            params[0] = _rapid(group, here, end)
        if any(axis.velocity_too_low(params[0]) for axis in group.axes):
            return None
        limits = group.nominal_limits(*params)
        if min(limits.acceleration, limits.deceleration) * 100.0 < params[0]:
            return None
        dynamics = (params[0], params[1], params[2], params[3])
        if bool(_field(segment, "Circular")):
            move = _arc_move(segment, here, end, dynamics, follow)
            if move is None:
                return None
        else:
            move = Move(end, dynamics, follow, LINE)
        moves.append(move)
        here = end
    return moves


def _arc_move(
    segment: Any,
    start: Sequence[float],
    end: list[float],
    params: tuple[float, float, float, float],
    mode: MC_BufferMode,
) -> Move | None:
    circ_mode = _field(segment, "CircMode")
    aux_value = _field(segment, "AuxPoint")
    if circ_mode == MC_CIRC_MODE.RADIUS:
        values = _values(aux_value)
        if not values or not math.isfinite(values[0]):
            return None
        aux = [values[0]] + [0.0] * (len(start) - 1)
    else:
        found = _point(aux_value, start, bool(_field(segment, "AuxRelative")))
        if found is None:
            return None
        aux = found
    return Move(
        end,
        params,
        mode,
        ARC,
        aux,
        int(circ_mode),
        int(_field(segment, "PathChoice")),
        int(_field(segment, "Plane")),
        int(_field(segment, "Turns")),
    )


class MC_MovePath(GroupMotionFB):
    """Runs a path table (``PathData``, an MC_PATH_DATA_REF) on the group (PLCopen Part 4): its
    lines and arcs one after the other, blended or stopping as each segment's BufferMode says.

    The table is checked as a whole on the rising edge of ``Execute`` from where the path
    starts, before the group is touched: a table that is not one, or a segment without a valid
    shape or dynamics → EParam 5, a segment beyond a member's SW limit → Ecil 8, an absolute
    segment on a member without Ref → Ehome 9. ``TransitionMode`` and ``TransitionParameter``
    apply to every corner of the path (as for MC_MoveLinearAbsolute). Done when the last
    segment ends; Active while the path runs.
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "PathData",
        "CoordSystem",
        "TransitionMode",
        "TransitionParameter",
    )
    PathData: TableRef = None
    CoordSystem: int = MC_COORD_SYSTEM.MCS
    TransitionMode: int = MC_TRANSITION_MODE.TMNone
    TransitionParameter: Sequence[float] = ()

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready()
        if error:
            return error
        segments = segments_of(self.PathData)
        transition = transition_of(self.TransitionMode, self.TransitionParameter)
        if segments is None or transition is None or self.CoordSystem not in COORD_SYSTEMS:
            return ErrorID.EParam
        joint = group.kin.transform is not None and self.CoordSystem == MC_COORD_SYSTEM.ACS
        try:
            start = group.start_point(ticket.buffer_mode, joint)
        except KinematicsError as refused:
            return int(refused.error_id)
        moves = path_moves(group, segments, ticket.buffer_mode, start)
        if moves is None:
            return ErrorID.EParam
        for move in moves:
            move.tolerance, move.reach = transition
            move.joint = joint
        absolute = any(not bool(_field(s, "Relative")) for s in segments)
        return submit_moves(group, ticket, moves, absolute)


__all__ = [
    "MAX_SEGMENTS",
    "MC_PATH_DATA_REF",
    "MC_PATH_SEGMENT",
    "RAPID_SHARE",
    "MC_MovePath",
    "path_moves",
    "segments_of",
]

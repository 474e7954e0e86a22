"""Product coordinate systems of an axes group: MC_SetCoordinateTransform,
MC_SetCartesianTransform, MC_TrackConveyorBelt, MC_TrackRotaryTable (PLCopen Part 4 v2.0).

A fixed PCS (MC_SetCoordinateTransform, MC_SetCartesianTransform) or one that moves with a
conveyor belt (MC_TrackConveyorBelt) or turns with a rotary table (MC_TrackRotaryTable) from a
part's latched position.

Both need a group with a kinematic transformation (:mod:`mcl.kin_fb`) that stands or rests in a
moving PCS (:attr:`mcl.group.AxesGroup.holding`). They set the group's PCS
(:class:`mcl.coordinate_system.ProductFrame`), then the path restarts from the members' set points
expressed in it and ramps to rest there (as MC_GroupHalt, ``Acceleration`` and ``Jerk``; 0 = the
tool point's defaults): starting to track, the tool point speeds up with the belt; ending it, slows
down to a standstill in the MCS. The block is Done once the path rests in the new PCS; from then on
Cartesian moves in PCS (MC_MoveLinear*, MC_MoveCircular*) land on the moving part (on a table in the
PCS that turns with it), each checked along the part's travel while it runs
(:mod:`mcl.group_kinematics`), and the group keeps following it between them (MC_GroupHalt stops the
motion relative to the part; MC_GroupStop ends the tracking and brings the tool point to rest in the
MCS, as MC_GroupDisable does). While a PCS is set a position in MCS is refused (EParam 5);
MC_GroupReadActualPosition reads in either.
"""

from __future__ import annotations

__all__ = [
    "MC_SetCartesianTransform",
    "MC_SetCoordinateTransform",
    "MC_TrackConveyorBelt",
    "MC_TrackRotaryTable",
]

import math
from collections.abc import Sequence
from typing import Any, ClassVar

from mcl.axis import Axis
from mcl.coordinate_system import ProductFrame
from mcl.enums import AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import non_negative, number
from mcl.group import AxesGroup, PathCommand
from mcl.group_fb import GroupMotionFB, _vector
from mcl.kinematics import KinematicsError, KinTransform, derivatives

HORIZON_STEP = 2.0
"""Largest travel of the part between the points of its track that are checked [mm]."""
_MAX_CHECKS = 2000


def _frame_input(value: Any) -> tuple[list[float], float] | None:
    """A frame input [x, y, z] or [x, y, z, rz] (mm, deg) as origin and angle; None when it is
    not 3 or 4 finite numbers."""
    size = len(value) if isinstance(value, Sequence) and not isinstance(value, str) else 0
    numbers = _vector(value, size) if size in (3, 4) else None
    if numbers is None:
        return None
    return numbers[:3], numbers[3] if size == 4 else 0.0


class _FrameFB(GroupMotionFB):
    """Sets the group's PCS and ramps its path to rest in it (module docstring)."""

    INPUTS: ClassVar[tuple[str, ...]] = ("Acceleration", "Jerk")
    Acceleration: float = 0.0
    Jerk: float = 0.0

    def _frame(self, group: AxesGroup) -> ProductFrame | int:
        """The new PCS, or the error that refuses the inputs."""
        raise NotImplementedError

    def _submit(self, ticket: PathCommand) -> int:
        group = self.group
        error = group.check_ready()
        if error:
            return error
        ramp = number(self.Acceleration), number(self.Jerk)
        if (
            group.kin.transform is None
            or ticket.buffer_mode != MC_BufferMode.Aborting
            or not (non_negative(ramp[0]) and non_negative(ramp[1]))
        ):
            return ErrorID.EParam
        if group.has_path and not group.holding:
            return ErrorID.EParam  # a move runs: the PCS changes only at rest in it
        frame = self._frame(group)
        if isinstance(frame, int):
            return frame
        group.kin.frame = (
            frame if frame.moving or frame.origin != [0.0] * 3 or frame.angle else None
        )
        group.reframe(ticket, ramp[0], ramp[1])
        return 0


class MC_SetCoordinateTransform(_FrameFB):
    """Sets a fixed PCS (PLCopen Part 4): ``CoordTransform`` [x, y, z] or [x, y, z, rz] its
    origin in the MCS [mm] and rotation about z [deg] (zeros: the PCS is the MCS). Ends a
    conveyor tracking: the tool point slows down to a standstill (module docstring). Done once
    the group stands in it. Errors: those of the moves (1005, Epower 10, Eerrstop 11, EAxStop 6);
    EParam 5 for a group without kinematic transformation, a move running, CoordTransform not 3
    or 4 finite numbers, Acceleration or Jerk negative or not finite, a BufferMode other than
    Aborting."""

    INPUTS: ClassVar[tuple[str, ...]] = ("CoordTransform",)
    CoordTransform: Sequence[float] = (0.0, 0.0, 0.0)

    def _frame(self, group: AxesGroup) -> ProductFrame | int:
        frame = _frame_input(self.CoordTransform)
        if frame is None:
            return ErrorID.EParam
        return ProductFrame(frame[0], frame[1])


class MC_SetCartesianTransform(_FrameFB):
    """Sets a fixed PCS with PLCopen Part 4's inputs: ``TransX``, ``TransY``, ``TransZ`` its
    origin in the MCS [mm], ``RotAngle1`` its rotation about z [deg] (a delta robot's tool
    point does not turn: ``RotAngle2`` and ``RotAngle3`` must be 0); otherwise as
    MC_SetCoordinateTransform. EParam 5 for inputs that are not finite numbers or a rotation
    about x or y."""

    INPUTS: ClassVar[tuple[str, ...]] = (
        "TransX",
        "TransY",
        "TransZ",
        "RotAngle1",
        "RotAngle2",
        "RotAngle3",
    )
    TransX: float = 0.0
    TransY: float = 0.0
    TransZ: float = 0.0
    RotAngle1: float = 0.0
    RotAngle2: float = 0.0
    RotAngle3: float = 0.0

    def _frame(self, group: AxesGroup) -> ProductFrame | int:
        values = [number(x) for x in (self.TransX, self.TransY, self.TransZ, self.RotAngle1)]
        if not all(math.isfinite(x) for x in values) or number(self.RotAngle2) != 0.0:
            return ErrorID.EParam
        if number(self.RotAngle3) != 0.0:
            return ErrorID.EParam
        return ProductFrame(values[:3], values[3])


class _TrackFB(_FrameFB):
    """Makes the PCS move with a master axis from a part's latched position: the inputs and
    checks MC_TrackConveyorBelt and MC_TrackRotaryTable share; subclasses name the master and
    its frame (:meth:`_carrier`) and list the inputs (the master's first, as PLCopen orders
    them)."""

    InitialObjectPosition: Sequence[float] = (0.0, 0.0, 0.0)
    LatchedPosition: float = 0.0
    Horizon: float = 0.0
    ROTARY: ClassVar[bool] = False

    def _carrier(self) -> tuple[object, Any]:
        """The master axis input and its frame input."""
        raise NotImplementedError

    def _frame(self, group: AxesGroup) -> ProductFrame | int:
        master, frame_input = self._carrier()
        origin = _frame_input(frame_input)
        offset = _vector(self.InitialObjectPosition, 3)
        latch, horizon = number(self.LatchedPosition), number(self.Horizon)
        if (
            not isinstance(master, Axis)
            or master in group.axes
            or master.state in (AxisState.Disabled, AxisState.ErrorStop)
            or origin is None
            or offset is None
            or not math.isfinite(latch)
            or not non_negative(horizon)
        ):
            return ErrorID.EParam
        frame = ProductFrame(origin[0], origin[1], offset, master, latch, self.ROTARY)
        transform = group.kin.transform
        assert transform is not None
        return _reachable(frame, transform, group.axes, horizon) or frame


class MC_TrackConveyorBelt(_TrackFB):
    """Makes the PCS move with the belt ``ConveyorBelt`` (an axis, mm) (PLCopen Part 4).

    ``ConveyorBeltOrigin`` [x, y, z] or [x, y, z, rz]: the belt frame in the MCS [mm, deg], its x
    the belt's direction of travel; ``InitialObjectPosition`` [x, y, z]: the part's position in
    the belt frame when the belt stood at ``LatchedPosition`` [mm of belt] (the touch probe's
    RecordedPosition), the PCS origin. Done once the tool point moves with the part (module
    docstring). ``Horizon`` [s] (≥ 0): the part is refused unless its PCS origin stays within
    the workspace for that long at the belt's velocity, and the joints can follow it there.

    Errors (the group left alone): those of the moves (1005, Epower 10, Eerrstop 11, EAxStop 6);
    EParam 5 for a group without kinematic transformation, a move running, a ConveyorBelt that
    is no powered axis, origin or position not finite numbers, Horizon, Acceleration or Jerk
    negative or not finite, a BufferMode other than Aborting; EWorkspace 24 / ESingular 25 when
    the part is, or within Horizon comes, beyond reach; ETrackTooFast 26 when the belt is faster
    than the tool point's velocity limit or a joint's Vmax can follow.
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "ConveyorBelt",
        "ConveyorBeltOrigin",
        "InitialObjectPosition",
        "LatchedPosition",
        "Horizon",
    )
    ConveyorBelt: Axis | None = None
    ConveyorBeltOrigin: Sequence[float] = (0.0, 0.0, 0.0)

    def _carrier(self) -> tuple[object, Any]:
        return self.ConveyorBelt, self.ConveyorBeltOrigin


class MC_TrackRotaryTable(_TrackFB):
    """Makes the PCS turn with the rotary table ``RotaryTable`` (an axis, deg) (PLCopen Part 4).

    ``RotaryTableOrigin`` [x, y, z] or [x, y, z, rz]: the table frame in the MCS [mm, deg], its
    origin the table's centre, its z the axis the table turns about (a positive table angle
    turns counter-clockwise seen from above); ``InitialObjectPosition`` [x, y, z]: the part's
    position in the table frame when the table stood at ``LatchedPosition`` [deg] (the touch
    probe's RecordedPosition), the PCS origin; the PCS turns with the table, so a move in PCS
    lands on the part and keeps its place on the table. Done once the tool point moves with the
    part (module docstring). ``Horizon`` [s] (≥ 0): the part is refused unless its PCS origin
    stays within the workspace for that long at the table's angular velocity, and the joints
    can follow it there.

    Errors (the group left alone): as MC_TrackConveyorBelt's, with RotaryTable for
    ConveyorBelt; ETrackTooFast 26 when the part's speed on the turning table exceeds the tool
    point's velocity limit or what a joint's Vmax can follow.
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "RotaryTable",
        "RotaryTableOrigin",
        "InitialObjectPosition",
        "LatchedPosition",
        "Horizon",
    )
    RotaryTable: Axis | None = None
    RotaryTableOrigin: Sequence[float] = (0.0, 0.0, 0.0)
    ROTARY: ClassVar[bool] = True

    def _carrier(self) -> tuple[object, Any]:
        return self.RotaryTable, self.RotaryTableOrigin


def _reachable(
    frame: ProductFrame, transform: KinTransform, axes: Sequence[Axis], horizon: float
) -> int:
    """0 when the PCS origin stays within the workspace from now for ``horizon`` [s] at the
    master's velocity and every joint can follow it there, else the error that refuses it."""
    _, w, _ = frame.travel()
    _, velocity = frame.ahead(0.0)
    speed = math.hypot(*velocity)
    if speed > transform.tcp.velocity:
        return ErrorID.ETrackTooFast
    count = min(_MAX_CHECKS, max(1, math.ceil(speed * horizon / HORIZON_STEP)))
    zero = (0.0, 0.0, 0.0)
    for k in range(count + 1):
        p, vel = frame.ahead(w * horizon * k / count)
        try:
            _, qd, _ = derivatives(transform, p, vel, zero)
        except KinematicsError as refused:
            return int(refused.error_id)
        for axis, speed in zip(axes, qd, strict=True):
            if axis.constants is not None and abs(speed) > axis.constants.Vmax:
                return ErrorID.ETrackTooFast
    return 0

"""A group's kinematic transformation: the paths of an axes group in the machine's Cartesian
frame (MCS) while its members are the joints of a robot (PLCopen Part 4; docs/reference.md,
Kinematic transformation).

Without a transformation the members' coordinates are the machine's and a path runs in them. With
one (MC_SetKinTransform), a piece of path runs in one of two spaces:

- Cartesian (MC_MoveLinear*, MC_MoveCircular* in MCS or PCS): the path point is the tool point
  [mm]; every servo cycle the inverse kinematics turns it into the members' set points, and the
  joint velocities and accelerations follow from the tool point's
  (:func:`mcl.kinematics.derivatives`);
- joint (MC_MoveDirect*, and any move in ACS): the path point is the members' positions; a
  direct move's target given in MCS is turned into joints once.

A Cartesian piece is checked before it is accepted, at points at most :data:`SAMPLE_STEP` apart:
every point within the workspace and away from singular poses (EWorkspace 24, ESingular 25),
every joint within its SW limits (Ecil 8). Along it the path velocity, acceleration and jerk are
lowered so that no joint exceeds its Vmax, max_acceleration/max_deceleration and max_jerk: with
q' = dq/ds and q'' = d²q/ds² the largest over the piece, the path velocity v ≤ Vmax/|q'| and
v ≤ √(0.3·a_max/|q''|), its acceleration ≤ 0.7·a_max/|q'| (so |q̈| = |q'·s̈ + q''·ṡ²| ≤ a_max),
its jerk ≤ j_max/|q'|. The Cartesian limits of the tool point (:class:`mcl.kinematics.TcpLimits`)
bind the path as a member's machine data binds it without a transformation. Pieces of different
spaces never blend: the path stops between them.

The Cartesian space of a path is the product coordinate system (:attr:`GroupKinematics.frame`,
:mod:`mcl.coordinate_system`): the MCS until MC_SetCoordinateTransform, MC_TrackConveyorBelt or
MC_TrackRotaryTable sets one. A moving PCS enters the set points with its velocity and acceleration,
and a path that ends rests in the PCS. In a moving PCS a piece is also checked along the PCS's
positions while it runs (:meth:`GroupKinematics.sweep`: its profile from rest to rest started when
it is accepted, the belt moving on at its velocity then): every point within the workspace and the
SW limits, every joint's velocity, the belt's share included, within its Vmax (else ETrackTooFast
26); the belt's share of a joint's velocity lowers the path velocity too, v ≤ (Vmax −
|q̇_belt|)/|q'|.

A stop ramp (MC_GroupStop, MC_GroupHalt, a PCS set) is checked when it is planned the same way
(:meth:`GroupKinematics.sweep`): one that would leave the workspace or a SW limit is refused at
once, as a point refused during a motion (every member stops on its own fastest ramp).
"""

from __future__ import annotations

__all__ = ["SAMPLE_STEP", "GroupKinematics", "refusal"]

import math
from collections.abc import Callable, Sequence
from typing import Final

from mcl.axis import Axis
from mcl.axis_config import AxisConfig
from mcl.coordinate_system import ProductFrame, rest_element
from mcl.errors import ErrorID
from mcl.geometry import Geometry, GeometryError
from mcl.joint_check import JointCheck
from mcl.kinematics import KinematicsError, KinTransform, derivatives
from mcl.path import Element, Move, PathCommand
from mcl.path_planner import PathPlanner
from mcl.trajectory import Limits, PlanningError, Profile, move_to

SAMPLE_STEP: Final = 2.0
"""Largest distance between the checked points of a Cartesian piece [mm]."""

_MAX_SAMPLES: Final = 2000
_VELOCITY_SHARE: Final = 0.3
"""Share of a joint's acceleration the path velocity may take through the curvature q''."""
_VMAX_TOLERANCE: Final = 1e-3
"""A joint's velocity along a swept piece may exceed its Vmax by this share (the path velocity
is lowered from the joints' slopes between points :data:`SAMPLE_STEP` apart)."""


class GroupKinematics:
    """The transformation of one group and the conversions between its spaces.

    Attributes:
        transform: the kinematic transformation (None: the members' coordinates are the MCS).
        fault: the ErrorID of a tool point the inverse kinematics refused during a motion (the
            members then ramp to standstill in joint space; 0 = none).
    """

    def __init__(self) -> None:
        self.transform: KinTransform | None = None
        self.fault = 0
        self.frame: ProductFrame | None = None
        """The PCS (None: it is the MCS)."""
        self.held: Element | None = None
        """The last element that rests in a moving PCS (:meth:`hold`)."""
        self._t = -math.inf
        self._q: list[float] = []
        self._qd: list[float] = []
        self._qdd: list[float] = []

    def cartesian(self, joint: bool) -> bool:
        """A piece of this space (``joint``: in the members' coordinates) runs in the MCS."""
        return self.transform is not None and not joint

    def convert(self, p: Sequence[float], joint: bool, to_joint: bool) -> list[float]:
        """The point ``p`` given in the joint (``joint``) or Cartesian space, in the other one
        when ``to_joint`` differs.

        Raises:
            KinematicsError: the transformation refuses the point.
        """
        transform = self.transform
        if transform is None or joint == to_joint:
            return list(p)
        frame = self.frame
        if to_joint:
            return transform.inverse(p if frame is None else frame.point_to_mcs(p))
        tcp = transform.forward(p)
        return tcp if frame is None else frame.point_from_mcs(tcp)

    def to_joints(self, p: Sequence[float], joint: bool, axes: Sequence[Axis]) -> list[float]:
        """The path point ``p`` in the members' coordinates (their set points where the
        transformation refuses it)."""
        try:
            return self.convert(p, joint, True)
        except KinematicsError:
            return [axis.sp_pos for axis in axes]

    def planner(self, joint: bool, axes: Sequence[Axis], tolerance: float) -> PathPlanner:
        """The path planner for pieces in the members' coordinates (``joint``: their machine
        data and servo constants) or in the MCS (the tool point's limits along each Cartesian
        axis; its corner blends within the joints' limits too); ``tolerance`` the corner tolerance
        [mm]."""
        transform = self.transform
        if transform is None or joint:
            vmax = [axis.constants.Vmax if axis.constants is not None else None for axis in axes]
            return PathPlanner([axis.config for axis in axes], vmax, tolerance)
        tcp = transform.tcp
        config = AxisConfig(
            acceleration=tcp.acceleration,
            deceleration=tcp.acceleration,
            jerk=tcp.jerk,
            max_acceleration=tcp.max_acceleration,
            max_deceleration=tcp.max_acceleration,
            max_jerk=tcp.jerk,
        )
        tcp_vmax: list[float | None] = [tcp.velocity] * 3
        velocity = [axis.constants.Vmax if axis.constants else math.inf for axis in axes]
        acceleration = [min(a.config.max_acceleration, a.config.max_deceleration) for a in axes]
        joints = JointCheck(transform, velocity, acceleration)
        return PathPlanner([config] * 3, tcp_vmax, tolerance, joints)

    def element(
        self,
        ticket: PathCommand,
        start: Sequence[float],
        move: Move,
        axes: Sequence[Axis],
        tolerance: float,
    ) -> Element:
        """The element of ``move`` from ``start`` in its space, a Cartesian one checked and
        held to the joints' limits (:meth:`hold_joints`).

        Raises:
            GeometryError: the piece describes no path.
            KinematicsError: the piece leaves the workspace or a joint's limits.
        """
        element = self.planner(move.joint, axes, tolerance).element(ticket, start, move)
        if self.cartesian(move.joint):
            error = self.hold_joints(element, axes)
            if error:
                raise KinematicsError(ErrorID(error), f"the piece to {move.end} is refused")
        return element

    def joints(
        self,
        t: float,
        joint: bool,
        p: Sequence[float],
        v: Sequence[float],
        a: Sequence[float],
        axes: Sequence[Axis],
    ) -> tuple[list[float], list[float], list[float]]:
        """The members' set points (position, velocity, acceleration) of the path state (p, v,
        a) at the servo instant ``t`` [s], computed once per instant. A refused tool point holds
        the last set points (of ``axes`` if none was computed yet) at rest and records
        :attr:`fault`."""
        transform = self.transform
        if transform is None or joint:
            return list(p), list(v), list(a)
        if t != self._t:
            if self.frame is not None:
                p, v, a = self.frame.to_mcs(p, v, a, t)
            try:
                self._q, self._qd, self._qdd = derivatives(transform, p, v, a)
            except KinematicsError as refused:
                self.fault = int(refused.error_id)
                self._q = [axis.sp_pos for axis in axes]
                self._qd = [0.0] * len(self._q)
                self._qdd = [0.0] * len(self._q)
            self._t = t
        return self._q, self._qd, self._qdd

    def path_state(
        self, q: list[float], qd: list[float], qdd: list[float], t: float | None = None
    ) -> tuple[list[float], list[float], list[float], bool]:
        """The path state a new path starts from at the members' state (q, qd, qdd) at the
        servo instant ``t``: in the PCS (:meth:`cartesian_state`) where the transformation
        gives the pose a tool point, else in the members' coordinates; the flag says the latter."""
        if self.transform is not None:
            try:
                p, v, a = self.cartesian_state(q, qd, qdd)
                if self.frame is not None:
                    p, v, a = self.frame.from_mcs(p, v, a, t)
                return p, v, a, False
            except KinematicsError:
                pass  # no tool point: the path state stays in the members' coordinates
        return q, qd, qdd, True

    def cartesian_state(
        self, q: Sequence[float], qd: Sequence[float], qdd: Sequence[float], h: float = 1e-4
    ) -> tuple[list[float], list[float], list[float]]:
        """The tool point [mm], its velocity [mm/s] and acceleration [mm/s²] of the joints at
        ``q`` moving with ``qd`` and ``qdd`` (central differences of the forward kinematics at
        q ± qd·h + qdd·h²/2).

        Raises:
            KinematicsError: the transformation refuses the pose.
        """
        transform = self.transform
        assert transform is not None
        p = transform.forward(q)
        if not any(qd) and not any(qdd):
            return p, [0.0] * len(p), [0.0] * len(p)
        half = 0.5 * h * h
        moves = list(zip(q, qd, qdd, strict=True))
        ahead = transform.forward([x + v * h + a * half for x, v, a in moves])
        back = transform.forward([x - v * h + a * half for x, v, a in moves])
        v = [(f - b) / (2.0 * h) for f, b in zip(ahead, back, strict=True)]
        a = [(f - 2.0 * c + b) / (h * h) for f, c, b in zip(ahead, p, back, strict=True)]
        return p, v, a

    def hold(self, end: Sequence[float], joint: bool, t0: float) -> Element | None:
        """The element the path that reached ``end`` (in the joint space when ``joint``) at path
        time ``t0`` [s] rests in while the PCS moves (:func:`rest_element`); None otherwise."""
        frame = self.frame
        if joint or self.transform is None or frame is None or not frame.moving:
            return None
        self.held = rest_element(end, t0)
        return self.held

    def leave_moving_frame(self) -> bool:
        """Drop a moving PCS (the group stops or fails: it stops in the MCS); True if it did."""
        if self.frame is None or not self.frame.moving:
            return False
        self.frame = None
        return True

    def hold_joints(self, element: Element, axes: Sequence[Axis]) -> int:
        """Check a Cartesian piece and lower its limits to the joints' (module docstring).

        Returns:
            0, or the error that refuses the piece (EWorkspace 24, ESingular 25, Ecil 8).
        """
        transform = self.transform
        assert transform is not None
        geometry = element.geometry
        try:
            qs, step = _samples(lambda p: self.convert(p, False, True), geometry)
        except KinematicsError as refused:
            return int(refused.error_id)
        for q in qs:
            for axis, value in zip(axes, q, strict=True):
                error = axis.check_target(value)
                if error:
                    return error
        if step <= 0.0:
            return 0
        slopes = [0.0] * len(axes)
        bends = [0.0] * len(axes)
        carried = self.carried(geometry, axes)
        if carried is None:
            return ErrorID.ETrackTooFast
        for k in range(1, len(qs)):
            for i in range(len(axes)):
                slopes[i] = max(slopes[i], abs(qs[k][i] - qs[k - 1][i]) / step)
                if k + 1 < len(qs):
                    second = (qs[k + 1][i] - 2.0 * qs[k][i] + qs[k - 1][i]) / (step * step)
                    bends[i] = max(bends[i], abs(second))
        _lower(element, axes, slopes, bends, carried)
        if self.frame is None or not self.frame.moving:
            return 0
        try:
            profile = move_to(0.0, 0.0, 0.0, geometry.length, element.limits)
        except PlanningError:
            return 0  # the profile is planned when the piece starts; it refuses it then
        return self.sweep(element, profile, axes, velocity=True)

    def carried(self, geometry: Geometry, axes: Sequence[Axis]) -> list[float] | None:
        """Each joint's largest velocity [u/s] the moving PCS alone gives it at the points of
        ``geometry`` (zeros in a fixed PCS); None when it reaches a joint's Vmax."""
        frame, transform = self.frame, self.transform
        shares = [0.0] * len(axes)
        if frame is None or not frame.moving or transform is None:
            return shares
        zero = (0.0, 0.0, 0.0)
        for p in _points(geometry):
            point, velocity, _ = frame.to_mcs(p, zero, zero)
            try:
                _, qd, _ = derivatives(transform, point, velocity, zero)
            except KinematicsError:
                continue  # the point is refused by the samples' check
            shares = [max(x, abs(w)) for x, w in zip(shares, qd, strict=True)]
        for axis, share in zip(axes, shares, strict=True):
            if axis.constants is not None and share >= axis.constants.Vmax:
                return None
        return shares

    def sweep(
        self, element: Element, profile: Profile, axes: Sequence[Axis], velocity: bool
    ) -> int:
        """Check ``element`` (Cartesian) run along ``profile`` (path time 0 = now, arc length)
        at the PCS's positions meanwhile (the master moving on at its velocity): 0, or the error
        of the first point refused (EWorkspace 24, ESingular 25, Ecil 8), with ``velocity`` also
        ETrackTooFast 26 for a joint faster than its Vmax (the belt's share included)."""
        transform, frame = self.transform, self.frame
        if transform is None or element.joint:
            return 0
        duration = profile.duration
        start = profile.at(0.0)[0]
        travel = abs(profile.end_position - start)
        if frame is not None:  # the PCS origin's travel meanwhile [mm]
            travel += math.hypot(*frame.ahead(0.0)[1]) * duration
        count = min(_MAX_SAMPLES, max(16, math.ceil(travel / SAMPLE_STEP)))
        zero = [0.0, 0.0, 0.0]
        for k in range(count + 1):
            tau = duration * k / count
            s, v, _ = profile.at(tau)
            p, vel, _ = element.state(s, v if velocity else 0.0, 0.0)
            if frame is not None:
                p, vel = frame.moved_on(p, vel, tau)
            try:
                q, qd, _ = derivatives(transform, p, vel, zero)
            except KinematicsError as refused:
                return int(refused.error_id)
            for axis, x, w in zip(axes, q, qd, strict=True):
                error = axis.check_target(x)
                if error:
                    return error
                vmax = axis.constants.Vmax if axis.constants is not None else math.inf
                if velocity and abs(w) > vmax * (1.0 + _VMAX_TOLERANCE):
                    return ErrorID.ETrackTooFast
        return 0

    def ramp_fault(self, ramp: Element, axes: Sequence[Axis]) -> int:
        """Check a stop ramp when it is planned (module docstring); its error is recorded in
        :attr:`fault` (the group then stops every member on its fastest ramp). Returns it."""
        error = 0
        if ramp.profile is not None and ramp.profile.duration > 0.0:
            error = self.sweep(ramp, ramp.profile, axes, velocity=False)
        self.fault = error or self.fault
        return error


def _points(geometry: Geometry) -> list[list[float]]:
    """Points of ``geometry`` at most :data:`SAMPLE_STEP` apart (its start alone when it has no
    length)."""
    length = geometry.length
    if length <= 0.0:
        return [list(geometry.start)]
    count = min(_MAX_SAMPLES, max(16, math.ceil(length / SAMPLE_STEP)))
    return [geometry.point(k * length / count) for k in range(count + 1)]


def _samples(
    inverse: Callable[[Sequence[float]], list[float]], geometry: Geometry
) -> tuple[list[list[float]], float]:
    """The joints (``inverse``) at points of ``geometry`` at most :data:`SAMPLE_STEP` apart, and
    that step [mm] (0 for a piece of no length)."""
    points = _points(geometry)
    step = geometry.length / (len(points) - 1) if len(points) > 1 else 0.0
    return [inverse(p) for p in points], step


def _lower(
    element: Element,
    axes: Sequence[Axis],
    slopes: Sequence[float],
    bends: Sequence[float],
    carried: Sequence[float],
) -> None:
    """Lower ``element``'s limits so that no joint exceeds its own (module docstring);
    ``carried`` each joint's velocity the moving PCS alone gives it [u/s]."""
    limits = element.limits
    v, acc, dec, jerk = limits.velocity, limits.acceleration, limits.deceleration, limits.jerk
    cap = element.cap
    for axis, slope, bend, share in zip(axes, slopes, bends, carried, strict=True):
        config = axis.config
        if slope > 0.0:
            if axis.constants is not None:
                cap = min(cap, (axis.constants.Vmax - share) / slope)
            acc = min(acc, (1.0 - _VELOCITY_SHARE) * config.max_acceleration / slope)
            dec = min(dec, (1.0 - _VELOCITY_SHARE) * config.max_deceleration / slope)
            if config.max_jerk > 0.0:
                jerk = min(jerk, config.max_jerk / slope)
        if bend > 0.0:
            top = min(config.max_acceleration, config.max_deceleration)
            cap = min(cap, math.sqrt(_VELOCITY_SHARE * top / bend))
    element.limits = Limits(min(v, cap), acc, dec, jerk)
    element.cap = cap
    element.jerk = min(element.jerk, jerk)


def refusal(error: GeometryError | KinematicsError) -> int:
    """The ErrorID of a piece refused: its KinematicsError's, EParam for a GeometryError."""
    return int(error.error_id) if isinstance(error, KinematicsError) else int(ErrorID.EParam)

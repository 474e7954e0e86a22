"""Time-locked motion profiles: the axis follows a table of points in time.

MC_PositionProfile, MC_VelocityProfile and MC_AccelerationProfile of PLCopen Part 1 v2.0
(sections 3.14–3.16), beyond the Teco library, which announced them. Each point of a table
comes a ``DeltaTime`` [s] after the previous one (> 0) and carries a value; the tables are PLCopen's
example types of its vendor-specific MC_TP_REF, MC_TV_REF and MC_TA_REF:
``mcl.MC_TP_REF(MC_TP_Array=[mcl.MC_TP(DeltaTime, Position), ...], NumberOfPairs=None,
IsAbsolute=False)``, ``mcl.MC_TV_REF(MC_TV_Array=[mcl.MC_TV(DeltaTime, Velocity), ...])``,
``mcl.MC_TA_REF(MC_TA_Array=[mcl.MC_TA(DeltaTime, Acceleration), ...])``; a point may also be a
``(DeltaTime, value)`` pair, ``NumberOfPairs`` None uses the whole array (at most 256 points).
An ST program passes a STRUCT of its own with the same fields (``DeltaTime`` an LREAL in
seconds, ``NumberOfPairs`` set).
Point 0 is implicit: the axis' model state where the profile takes over (its position,
velocity and acceleration), so the profile starts without a jump. The block reads the table on
the rising edge of ``Execute`` (a later change of the table does not touch the running profile).

Each table becomes a :class:`~mcl.trajectory.Profile` (phases of constant jerk) and is checked
as a whole before the axis is touched: velocity within the axis' Vmax, acceleration within its
``max_acceleration`` (speeding up) and ``max_deceleration`` (slowing down), each lowered by the
application maximum written with MC_WriteParameter (MaxVelocityAppl 9, MaxAccelerationAppl 13,
MaxDecelerationAppl 15) as for every motion command, and, on a referenced axis, every position
the table moves to within the software limits in force (as GT_SetConstant, GT_SWLim or
MC_WriteParameter 2–5 left them; not the one it starts at: after a software-limit stop, which
leaves the axis just beyond the limit, a table back inward runs, as a move back inward does).
A table outside the maxima is refused with ``EParam`` 5, one crossing a software limit with
``Ecil`` 8; in both cases the axis goes on as it was. The jerk is
not limited (MaxJerk does not apply): the table sets it. The maxima are those in force at the
Execute edge; where the start state is known only when the profile takes over (queued behind
a motion that does not end at rest), the check is repeated then, against the software limits
in force then; a table that fails it ends with ``EParam`` 5 and the axis stops on its maximum
ramp.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Final

from mcl.command import ProfileCommand, Status
from mcl.enums import AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import MotionFB, number, positive
from mcl.trajectory import Limits, PlanningError, Profile, Segment

if TYPE_CHECKING:
    from mcl.axis import Axis

TableRef = Any
"""The type of a table input: an :class:`MC_TP_REF`, :class:`MC_TV_REF` or :class:`MC_TA_REF`,
or any object with the same fields (an ST STRUCT)."""

MAX_PAIRS: Final = 256
"""The most points a profile table may use (a longer one → EParam)."""

POSITION: Final = 0
VELOCITY: Final = 1
ACCELERATION: Final = 2


# ------------------------------------------------------------------------------ the tables
@dataclass
class MC_TP:
    """One point of a position table: ``DeltaTime`` [s] after the previous point (> 0),
    ``Position`` [u]."""

    DeltaTime: float = 0.0
    Position: float = 0.0


@dataclass
class MC_TP_REF:
    """A time/position table (PLCopen's example of MC_TP_REF).

    Attributes:
        MC_TP_Array: the points (:class:`MC_TP`, or ``(DeltaTime, Position)`` pairs).
        NumberOfPairs: how many of them the profile uses; None: all.
        IsAbsolute: the positions are absolute [u] (the profile needs Ref); FALSE: relative to
            where the profile starts.
    """

    MC_TP_Array: Sequence[Any] = ()
    NumberOfPairs: int | None = None
    IsAbsolute: bool = False


@dataclass
class MC_TV:
    """One point of a velocity table: ``DeltaTime`` [s] after the previous point (> 0),
    ``Velocity`` [u/s] (signed)."""

    DeltaTime: float = 0.0
    Velocity: float = 0.0


@dataclass
class MC_TV_REF:
    """A time/velocity table (PLCopen's example of MC_TV_REF).

    Attributes:
        MC_TV_Array: the points (:class:`MC_TV`, or ``(DeltaTime, Velocity)`` pairs).
        NumberOfPairs: how many of them the profile uses; None: all.
    """

    MC_TV_Array: Sequence[Any] = ()
    NumberOfPairs: int | None = None


@dataclass
class MC_TA:
    """One point of an acceleration table: ``DeltaTime`` [s] after the previous point (> 0),
    ``Acceleration`` [u/s²] (signed)."""

    DeltaTime: float = 0.0
    Acceleration: float = 0.0


@dataclass
class MC_TA_REF:
    """A time/acceleration table (PLCopen's example of MC_TA_REF).

    Attributes:
        MC_TA_Array: the points (:class:`MC_TA`, or ``(DeltaTime, Acceleration)`` pairs).
        NumberOfPairs: how many of them the profile uses; None: all.
    """

    MC_TA_Array: Sequence[Any] = ()
    NumberOfPairs: int | None = None


def read_table(table: Any, array: str, value: str) -> tuple[list[float], list[float]] | None:
    """The delta times [s] and values of a table, or None when it is not a valid one: missing,
    empty, longer than :data:`MAX_PAIRS`, ``NumberOfPairs`` not 1 … the array's length, a
    delta time not > 0 (time not strictly increasing), or a value that is not finite.

    Args:
        table: an MC_TP_REF, MC_TV_REF or MC_TA_REF (or an object with the same fields).
        array: the name of its array field (``MC_TP_Array`` …).
        value: the name of the value in a point (``Position`` …).
    """
    points = getattr(table, array, None)
    if isinstance(points, str | bytes) or not isinstance(points, Sequence):
        return None
    count = getattr(table, "NumberOfPairs", None)
    used = len(points) if count is None else count
    if isinstance(used, bool) or not isinstance(used, int) or not 1 <= used <= len(points):
        return None
    if used > MAX_PAIRS:
        return None
    deltas: list[float] = []
    values: list[float] = []
    for point in points[:used]:
        if hasattr(point, "DeltaTime"):
            dt, x = number(point.DeltaTime), number(getattr(point, value, math.nan))
        elif isinstance(point, Sequence) and not isinstance(point, str | bytes) and len(point) == 2:
            dt, x = number(point[0]), number(point[1])
        else:
            return None
        if not (positive(dt) and math.isfinite(x)):
            return None
        deltas.append(dt)
        values.append(x)
    return deltas, values


# ------------------------------------------------------------------------------ interpolation
def spline(times: list[float], positions: list[float], v0: float) -> Profile:
    """The clamped cubic spline through (``times[i]``, ``positions[i]``): continuous position,
    velocity and acceleration; velocity ``v0`` at the first point and 0 at the last, where the
    profile then stands.

    Args:
        times: strictly increasing [s], ``times[0]`` = 0.
        positions: one per time [u].
        v0: the velocity at ``times[0]`` [u/s].
    """
    n = len(times) - 1
    h = [times[i + 1] - times[i] for i in range(n)]
    d = [(positions[i + 1] - positions[i]) / h[i] for i in range(n)]
    m = [0.0] * (n + 1)
    m[0] = v0
    # C2 at the inner points: h[i] m[i-1] + 2 (h[i-1] + h[i]) m[i] + h[i-1] m[i+1]
    # = 3 (h[i] d[i-1] + h[i-1] d[i]); a tridiagonal system (Thomas algorithm)
    diag = [0.0] * (n + 1)
    rhs = [0.0] * (n + 1)
    for i in range(1, n):
        diag[i] = 2.0 * (h[i - 1] + h[i])
        rhs[i] = 3.0 * (h[i] * d[i - 1] + h[i - 1] * d[i])
    if n > 1:
        rhs[1] -= h[1] * m[0]
    for i in range(2, n):
        w = h[i] / diag[i - 1]
        diag[i] -= w * h[i - 2]
        rhs[i] -= w * rhs[i - 1]
    for i in range(n - 1, 0, -1):
        upper = h[i - 1] * m[i + 1] if i < n - 1 else 0.0
        m[i] = (rhs[i] - upper) / diag[i]
    segments: list[Segment] = []
    for i in range(n):
        c2 = (3.0 * d[i] - 2.0 * m[i] - m[i + 1]) / h[i]
        c3 = (m[i] + m[i + 1] - 2.0 * d[i]) / (h[i] * h[i])
        segments.append((times[i], positions[i], m[i], 2.0 * c2, 6.0 * c3))
    segments.append((times[n], positions[n], 0.0, 0.0, 0.0))
    return Profile(segments, times[n])


def ramps(times: list[float], values: list[float], p0: float, v0: float, order: int) -> Profile:
    """Values interpolated linearly between the points, integrated to positions.

    Args:
        times: strictly increasing [s], ``times[0]`` = 0.
        values: velocities (``order`` 1) [u/s] or accelerations (``order`` 2) [u/s²], one per
            time, ``values[0]`` the axis' own at the start.
        p0: the position at the start [u].
        v0: the velocity at the start [u/s] (``order`` 2).
        order: 1 velocity table, 2 acceleration table.

    After the last point the profile goes on at its last velocity, without acceleration.
    """
    segments: list[Segment] = []
    p, v = p0, values[0] if order == 1 else v0
    for i in range(len(times) - 1):
        dt = times[i + 1] - times[i]
        slope = (values[i + 1] - values[i]) / dt
        if order == 1:
            segments.append((times[i], p, v, slope, 0.0))
            p += dt * (v + values[i + 1]) / 2.0
            v = values[i + 1]
        else:
            a = values[i]
            segments.append((times[i], p, v, a, slope))
            p += dt * (v + dt * (a / 2.0 + dt * slope / 6.0))
            v += dt * (a + values[i + 1]) / 2.0
    segments.append((times[-1], p, v, 0.0, 0.0))
    return Profile(segments, times[-1])


# ------------------------------------------------------------------------------ limits
def _inside(lo: float, hi: float, roots: tuple[float, ...]) -> list[float]:
    return [r for r in roots if lo < r < hi]


def _quadratic_roots(c0: float, c1: float, c2: float) -> tuple[float, ...]:
    """The real roots of c0 + c1·t + c2·t²."""
    if c2 == 0.0:
        return (-c0 / c1,) if c1 != 0.0 else ()
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return ()
    root = math.sqrt(disc)
    return ((-c1 - root) / (2.0 * c2), (-c1 + root) / (2.0 * c2))


def table_limits(axis: Axis) -> Limits:
    """The most a table may ask of ``axis`` now: velocity, acceleration (speeding up) and
    deceleration (slowing down) within the system's maxima (Vmax, ``max_acceleration``,
    ``max_deceleration``) and the application's below them (MaxVelocityAppl 9,
    MaxAccelerationAppl 13, MaxDecelerationAppl 15 of MC_WriteParameter); the jerk is the
    table's own."""
    p, c = axis.parameters, axis.config
    return Limits(
        axis.max_velocity(),
        min(c.max_acceleration, p.max_acceleration_appl),
        min(c.max_deceleration, p.max_deceleration_appl),
    )


def check_limits(profile: Profile, axis: Axis, limits: Limits) -> int:
    """``EParam`` when the profile leaves ``limits`` (the velocity; the acceleration speeding
    up, the deceleration slowing down), ``Ecil`` when it moves to a position beyond a software
    limit in force now (with Ref; :meth:`~mcl.axis.Axis.sw_limit_range`), else 0. Its start,
    where the axis stands, is not checked: after a software-limit stop a table back inward
    runs. Exact for phases of constant jerk: the extremes lie at the phase ends or where the
    derivative vanishes."""
    low, high = axis.sw_limit_range()
    low -= 0.5 * axis.config.resolution
    high += 0.5 * axis.config.resolution
    vmax = limits.velocity * (1.0 + 1e-9)
    segments = profile.segments
    for k in range(len(segments) - 1):
        t0, p, v, a, j = segments[k]
        h = segments[k + 1][0] - t0
        v_zero = _inside(0.0, h, _quadratic_roots(v, a, j / 2.0))
        a_zero = _inside(0.0, h, (-a / j,) if j != 0.0 else ())
        for tau in (0.0, h, *a_zero):
            if abs(v + tau * (a + tau * j / 2.0)) > vmax:
                return ErrorID.EParam
        for tau in (h, *v_zero):  # its start is the end of the one before
            if not low <= p + tau * (v + tau * (a / 2.0 + tau * j / 6.0)) <= high:
                return ErrorID.Ecil
        cuts = sorted((0.0, h, *v_zero, *a_zero))
        for lo, hi in itertools.pairwise(cuts):
            mid = 0.5 * (lo + hi)
            speeding = (v + mid * (a + mid * j / 2.0)) * (a + mid * j) > 0.0
            limit = limits.acceleration if speeding else limits.deceleration
            if max(abs(a + lo * j), abs(a + hi * j)) > limit * (1.0 + 1e-9):
                return ErrorID.EParam
    return 0


# ------------------------------------------------------------------------------ the command
class TableMotion(ProfileCommand):
    """The motion of a profile table; ``signal`` = the table's end (Done).

    A position table ends at rest (DiscreteMotion, then StandStill); a velocity or acceleration
    table goes on at its last velocity, never ending by itself (ContinuousMotion). Not
    overridden (MC_SetOverride): the table is time-locked.

    Args:
        buffer_mode: Aborting or Buffered.
        limits: what the table may ask of the axis (:func:`table_limits` at the Execute edge;
            checked by :func:`check_limits`).
        kind: :data:`POSITION`, :data:`VELOCITY` or :data:`ACCELERATION`.
        deltas: the delta times, already scaled by TimeScale [s].
        values: the values, already scaled and offset.
        absolute: a position table with absolute positions.
    """

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        limits: Limits,
        kind: int,
        deltas: list[float],
        values: list[float],
        absolute: bool,
    ) -> None:
        super().__init__(buffer_mode, limits)
        self.velocity = 0.0
        self.kind = kind
        self.values = values
        self.absolute = absolute
        self.times = [0.0]
        for dt in deltas:
            self.times.append(self.times[-1] + dt)
        if kind != POSITION:
            self.state = AxisState.ContinuousMotion

    def plan(self, axis: Axis, p: float, v: float, a: float) -> Profile | int:
        """The profile from the model state (p, v, a), or the error that refuses it."""
        if self.kind == POSITION:
            base = p
            if self.absolute:
                modulo = axis.config.modulo
                base = p - p % modulo if modulo else 0.0
            profile = spline(self.times, [p] + [base + x for x in self.values], v)
        elif self.kind == VELOCITY:
            profile = ramps(self.times, [v, *self.values], p, v, 1)
        else:
            profile = ramps(self.times, [a, *self.values], p, v, 2)
        error = check_limits(profile, axis, self.limits)
        return error if error else profile

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        planned = self.plan(axis, p, v, a)
        if isinstance(planned, int):
            raise PlanningError(f"the table leaves the axis' limits (error {planned})")
        self.profile = planned
        if self.kind == POSITION:
            self.target = planned.end_position

    def finished(self) -> bool:
        return self.signal and self.kind == POSITION


# ------------------------------------------------------------------------------ the blocks
class _ProfileFB(MotionFB):
    """Common part of the profile blocks: a table, TimeScale, a value scale and offset."""

    INPUTS: ClassVar[tuple[str, ...]] = ("TimeScale",)
    TimeScale: float = 1.0
    KIND: ClassVar[int] = POSITION
    TABLE: ClassVar[tuple[str, str, str]] = ("TimePosition", "MC_TP_Array", "Position")
    """The table input, its array field and the value field of a point."""

    def _scaling(self) -> tuple[float, float]:
        """The value scale and offset inputs."""
        raise NotImplementedError

    def _command(self, mode: MC_BufferMode) -> TableMotion | int:
        axis = self.axis
        error = axis.check_ready()
        if error:
            return error
        name, array, value = self.TABLE
        table = getattr(self, name)
        read = read_table(table, array, value)
        time_scale = number(self.TimeScale)
        scale, offset = self._scaling()
        scale, offset = number(scale), number(offset)
        if read is None or not positive(time_scale):
            return ErrorID.EParam
        if not (math.isfinite(scale) and math.isfinite(offset)):
            return ErrorID.EParam
        deltas, values = read
        absolute = self.KIND == POSITION and bool(getattr(table, "IsAbsolute", False))
        if absolute and not axis.Ref:
            return ErrorID.Ehome
        if mode >= MC_BufferMode.BlendingLow:
            mode = MC_BufferMode.Buffered  # a time-locked table has no blending velocity
        cmd = TableMotion(
            mode,
            table_limits(axis),
            self.KIND,
            [time_scale * dt for dt in deltas],
            [scale * x + offset for x in values],
            absolute,
        )
        immediate = mode == MC_BufferMode.Aborting or (axis.active is None and not axis.queue)
        start = axis.start_position(mode)
        v, a = (axis.sp_vel, axis.sp_acc) if immediate else (0.0, 0.0)
        planned = cmd.plan(axis, start, v, a)
        if isinstance(planned, int):
            return planned
        if self.KIND == POSITION:
            cmd.target = planned.end_position
        return cmd

    def _poll(self) -> Status | None:
        cmd = self._cmd
        if isinstance(cmd, TableMotion) and cmd.signal:
            return Status.Done  # a velocity or acceleration table goes on: Done all the same
        return super()._poll()


class MC_PositionProfile(_ProfileFB):
    """Follows the time/position table ``TimePosition`` (an :class:`MC_TP_REF`) (PLCopen Part 1
    v2.0 section 3.14).

    Point i is reached ``TimeScale`` × (DeltaTime of points 1 … i) [s] after the start, at
    ``PositionScale`` × Position + ``Offset`` [u]: relative to where the profile starts, or,
    with ``IsAbsolute``, absolute (needs Ref, ``Ehome`` 9; on a modulo axis counted from the
    start of the period the axis is in). Between the points a clamped cubic spline (continuous
    velocity and acceleration) that starts with the axis' velocity and ends at rest at the last
    point. DiscreteMotion; ``Done`` at the last point, the axis then stands (StandStill).

    A table that is missing, empty, longer than 256 points, not strictly increasing in time or
    not finite, a ``TimeScale`` not > 0, a scale or offset not finite → ``EParam`` 5; a spline
    beyond the axis' Vmax or maximum acceleration/deceleration (or the application maxima
    MaxVelocityAppl, MaxAccelerationAppl, MaxDecelerationAppl below them) → ``EParam`` 5 (the
    table is refused, not slowed down); beyond an active SW limit (with Ref) → ``Ecil`` 8. The
    axis then goes on as it was. BufferMode Aborting or Buffered; the Blending modes act as
    Buffered (a time-locked table has no velocity to blend at). MC_SetOverride does not act on
    it. PLCopen's ``ContinuousUpdate`` is not implemented, and the table is an input here, not
    an in-out, read on the rising edge.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("TimePosition", "PositionScale", "Offset")
    TimePosition: TableRef = None
    PositionScale: float = 1.0
    Offset: float = 0.0

    def _scaling(self) -> tuple[float, float]:
        return self.PositionScale, self.Offset


class MC_VelocityProfile(_ProfileFB):
    """Follows the time/velocity table ``TimeVelocity`` (an :class:`MC_TV_REF`) (PLCopen Part 1
    v2.0 section 3.15).

    Point i is reached ``TimeScale`` × (DeltaTime of points 1 … i) [s] after the start with the
    velocity ``VelocityScale`` × Velocity + ``Offset`` [u/s] (signed); between the points the
    velocity changes linearly, from the axis' own velocity at the start (the acceleration is
    constant between two points and steps at them). ContinuousMotion; ``Done`` at the last
    point, where the axis goes on at the last velocity (PLCopen: it is maintained) until
    another command takes over. No Ref needed.

    Errors and modes as for MC_PositionProfile: an invalid table or input → ``EParam`` 5; a
    velocity above Vmax or a slope beyond the maximum acceleration/deceleration → ``EParam``
    5 (the application maxima as for MC_PositionProfile); a position the table passes beyond an
    active SW limit (with Ref) → ``Ecil`` 8 (after
    the table the SW limit supervision stops the axis, as for MC_MoveVelocity). A Buffered
    successor starts at ``Done``, from the last velocity.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("TimeVelocity", "VelocityScale", "Offset")
    TimeVelocity: TableRef = None
    VelocityScale: float = 1.0
    Offset: float = 0.0
    KIND: ClassVar[int] = VELOCITY
    TABLE: ClassVar[tuple[str, str, str]] = ("TimeVelocity", "MC_TV_Array", "Velocity")

    def _scaling(self) -> tuple[float, float]:
        return self.VelocityScale, self.Offset


class MC_AccelerationProfile(_ProfileFB):
    """Follows the time/acceleration table ``TimeAcceleration`` (an :class:`MC_TA_REF`)
    (PLCopen Part 1 v2.0 section 3.16).

    Point i is reached ``TimeScale`` × (DeltaTime of points 1 … i) [s] after the start with the
    acceleration ``AccelerationScale`` × Acceleration + ``Offset`` [u/s²] (signed); between the
    points the acceleration changes linearly (constant jerk), from the axis' own acceleration
    at the start. After the last point the acceleration goes to 0 at once and the axis goes on
    at the velocity it has (PLCopen); ContinuousMotion, ``Done`` at the last point. No Ref
    needed. Errors and modes as for MC_VelocityProfile (the velocity the table reaches must
    stay within Vmax, its accelerations within the maxima).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("TimeAcceleration", "AccelerationScale", "Offset")
    TimeAcceleration: TableRef = None
    AccelerationScale: float = 1.0
    Offset: float = 0.0
    KIND: ClassVar[int] = ACCELERATION
    TABLE: ClassVar[tuple[str, str, str]] = ("TimeAcceleration", "MC_TA_Array", "Acceleration")

    def _scaling(self) -> tuple[float, float]:
        return self.AccelerationScale, self.Offset


__all__ = [
    "MC_TA",
    "MC_TA_REF",
    "MC_TP",
    "MC_TP_REF",
    "MC_TV",
    "MC_TV_REF",
    "MC_AccelerationProfile",
    "MC_PositionProfile",
    "MC_VelocityProfile",
]

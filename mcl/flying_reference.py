"""Flying reference: the coordinate set at an edge met while another command moves the axis.

MC_StepRefFlyingSwitch and MC_StepRefFlyingRefPulse (PLCopen Part 5 v2.0; announced in the
MotionControlLib, Tab. 2.2) command no motion; they set the coordinate and ``Ref`` at the edge,
and the motion goes on undisturbed. The armed job (:class:`FlyingReference`) is watched by the
axis every servo cycle.
"""

from __future__ import annotations

__all__ = ["FlyingReference", "MC_StepRefFlyingRefPulse", "MC_StepRefFlyingSwitch"]

import math
from typing import TYPE_CHECKING, Any, ClassVar

from mcl.command import Status
from mcl.enums import AxisState, MC_SwitchMode
from mcl.errors import ErrorID
from mcl.fb import ExecuteFB, non_negative, number

if TYPE_CHECKING:
    from mcl.axis import Axis


class FlyingReference:
    """A flying reference armed on an axis (MC_StepRefFlyingSwitch, MC_StepRefFlyingRefPulse).

    It commands no motion. The axis watches it in every servo cycle right after reading its
    inputs (:meth:`watch`): at the edge the position is latched at that servo instant (the
    index pulse: the count the encoder hardware latched at its rising edge; the REF switch: the
    actual position in the first cycle that sees the new level) and the coordinate is shifted
    with :meth:`Axis.shift_coordinate` (the mechanism of MC_SetPosition) so that the latched
    point gets ``position``; ``Ref`` is set. ``mode`` None: the index pulse; else the REF edge
    condition (an edge mode: MC_EdgeOn, MC_EdgeOff, MC_EdgeSwitchPositive/Negative).
    """

    def __init__(
        self, position: float, mode: MC_SwitchMode | None, time_limit: float, distance: float
    ) -> None:
        self.position = position
        self.mode = mode
        self.time_limit = time_limit
        self.distance_limit = distance
        self.status = Status.Active
        self.error_id = 0
        self.latched: float | None = None
        """The coordinate the edge had before the correction [u] (None: not yet)."""
        self.shift = 0.0
        """The correction applied, ``position − latched`` [u]."""
        self._t0 = 0.0
        self._counts0 = 0
        self._counts = 0
        self._seq = 0
        self._level = False

    @property
    def busy(self) -> bool:
        return self.status == Status.Active

    def arm(self, axis: Axis) -> None:
        """Start watching from the inputs the axis read last."""
        io = axis.io
        self._t0 = axis.t_cycle
        self._counts0 = self._counts = io.counts
        self._seq = io.index_seq
        self._level = io.ref

    def end(self, status: Status, error_id: int = 0) -> None:
        self.status, self.error_id = status, error_id

    def interrupted(self, axis: Axis) -> tuple[Status, int] | None:
        """How the axis state ends the waiting now, or None: an axis error (Error with the
        axis' code), a stop, power-off, a homing step or joining a group (Aborted)."""
        state = axis.state
        if state == AxisState.ErrorStop:
            return Status.Error, axis.AxErrorID or ErrorID.Eerrstop
        if state in (AxisState.Disabled, AxisState.Stopping, AxisState.Homing):
            return Status.Aborted, 0
        if axis.group is not None:
            return Status.Aborted, 0
        return None

    def watch(self, axis: Axis, t: float) -> bool:
        """One servo cycle (after the inputs are read); True once the job has ended."""
        ended = self.interrupted(axis)
        if ended is not None:
            self.end(*ended)
            return True
        io = axis.io
        travel = io.counts - self._counts
        self._counts = io.counts
        edge = self._index_edge(axis) if self.mode is None else self._switch_edge(axis, travel)
        if edge is not None:
            shift = self.position - edge
            referenced, axis.Ref = axis.Ref, True  # the limits as they act once referenced
            error = axis.shift_coordinate(shift)
            if error:
                axis.Ref = referenced
                self.end(Status.Error, error)
                return True
            self.latched, self.shift = edge, shift
            self.end(Status.Done)
            return True
        if self.time_limit and t - self._t0 > self.time_limit:
            self.end(Status.Error, ErrorID.ETime)
            return True
        travelled = abs(io.counts - self._counts0) * axis.config.resolution
        if self.distance_limit and travelled > self.distance_limit:
            self.end(Status.Error, ErrorID.EDistance)
            return True
        return False

    def _index_edge(self, axis: Axis) -> float | None:
        io = axis.io
        if io.index_seq == self._seq:
            return None
        return io.index_count * axis.config.resolution + axis.offset

    def _switch_edge(self, axis: Axis, travel: int) -> float | None:
        level = axis.io.ref
        previous, self._level = self._level, level
        if level == previous:
            return None
        mode = self.mode
        if mode in (MC_SwitchMode.MC_EdgeSwitchPositive, MC_SwitchMode.MC_EdgeSwitchNegative):
            direction = float(travel) if travel else axis.sp_vel
            if direction == 0:
                return None  # no way of telling which side of the switch this edge is
            positive = (direction > 0) == (mode == MC_SwitchMode.MC_EdgeSwitchPositive)
            mode = MC_SwitchMode.MC_EdgeOn if positive else MC_SwitchMode.MC_EdgeOff
        if (mode == MC_SwitchMode.MC_EdgeOn) != level:
            return None
        return axis.actual


class _FlyingFB(ExecuteFB):
    """Common part of the flying reference blocks: SetPosition, TimeLimit, DistanceLimit."""

    INPUTS: ClassVar[tuple[str, ...]] = ("SetPosition", "TimeLimit", "DistanceLimit")
    SetPosition: float = 0.0
    TimeLimit: float = 0.0
    DistanceLimit: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        self.Active = False
        self.CommandAborted = False
        self.RecordedPosition = 0.0
        self._job: FlyingReference | None = None
        super().__init__(**inputs)

    def _mode(self) -> tuple[MC_SwitchMode | None, int]:
        """The REF condition (None: the index pulse) and 0, or (None, EParam)."""
        return None, 0

    def _begin(self) -> int:
        axis = self.axis
        self._job = None
        error = axis.check_ready()
        if error:
            return error
        position, time, distance = (
            number(x) for x in (self.SetPosition, self.TimeLimit, self.DistanceLimit)
        )
        if not (math.isfinite(position) and non_negative(time) and non_negative(distance)):
            return ErrorID.EParam
        mode, error = self._mode()
        if error:
            return error
        job = FlyingReference(position, mode, time, distance)
        axis.arm_flying(job)
        self._job = job
        return 0

    def _poll(self) -> Status | None:
        job = self._job
        if job is None or job.busy:
            return None
        if job.status == Status.Done and job.latched is not None:
            self.RecordedPosition = job.latched
        return job.status

    def _error_of_poll(self) -> int:
        return self._job.error_id if self._job is not None else 0

    def _withdraw(self) -> None:
        job = self._job
        if job is not None and job.busy:
            self.axis.disarm_flying(job)
        self._job = None

    def _show_more(self, visible: bool, final: Status | None) -> None:
        self.Active = self._running  # armed: nothing is buffered, Active = Busy
        self.CommandAborted = visible and final == Status.Aborted


class MC_StepRefFlyingSwitch(_FlyingFB):
    """Flying reference on the REF switch (PLCopen Part 5 v2.0; announced in the
    MotionControlLib, Tab. 2.2): while another command moves the axis, the coordinate is set so
    that the REF edge has the coordinate ``SetPosition`` [u]. The block commands no motion and
    aborts none: the running command goes on physically undisturbed, its path and target move
    with the coordinate (as with MC_SetPosition), the axis state does not change.

    Inputs (sampled on the rising edge of Execute): ``SwitchMode``, the edge: MC_EdgeOn,
    MC_EdgeOff, or MC_EdgeSwitchPositive / MC_EdgeSwitchNegative (the edge met travelling in
    the positive / negative direction: on or off by the direction of travel at the edge);
    ``SetPosition`` [u]; ``TimeLimit`` [s] and ``DistanceLimit`` [u] of travel (encoder counts
    from the arming), 0 = off. The Direction of PLCopen's searching steps does not apply: the
    running motion decides it. BufferMode neither: the block is no motion command.

    The REF input is a level sampled once per servo cycle: the edge is latched as the actual
    position of the first servo cycle that sees the new level, as MC_StepAbsSwitch captures it,
    so at velocity v the latched point lies up to v × servo period beyond the switch edge
    (0.2 mm at 200 mm/s, 1 ms); a reference that must agree to the count uses the index pulse
    (MC_StepRefFlyingRefPulse). The correction and ``Ref`` are set in that servo cycle;
    ``Done`` (with ``RecordedPosition``, the coordinate the edge had before the correction)
    from the next scan, while Execute is TRUE or for one scan. ``Busy`` (and ``Active``, the
    block is armed) while waiting.

    On a standing axis (StandStill) the block is armed all the same and waits for the edge
    rather than being refused: flying referencing needs motion, but the motion may be started
    after the block (arming first is the safe order: no edge is missed while the program waits
    for the motion to run), or the axis may be moved by the machine. Refused as a motion command
    is: ErrorStop ``Eerrstop`` 11, Stopping ``EAxStop`` 6, Disabled ``Epower`` 10, constants
    missing ``Econst`` 12, a group member 1000, Homing ``Ehome`` 9 (the homing procedure sets
    the coordinate), an encoder-only axis ``ENoDrive`` 14. MC_On / MC_Off (a level is no point
    on the axis), an unknown SwitchMode, a SetPosition that is not finite or a negative/not finite
    limit: ``EParam``; a refused call leaves the axis as it was. A shift that puts the axis or
    the running command's target beyond an active software limit (as the limits act once Ref
    is set) ends it at the edge with ``Ecil`` 8: the coordinate and Ref stay as they were, the
    motion goes on.

    Exceeding TimeLimit or DistanceLimit before the edge: ``Error`` ``ETime`` 1 /
    ``EDistance`` 2 on the block only; the motion, which the block does not own, goes on
    unchanged (the program decides whether to stop; the searching steps, which own their
    motion, stop the axis with these errors instead). While waiting, an axis error ends it with
    ``Error`` and the axis' code; a stop, power-off, a homing step, joining a group or another
    flying reference armed on the axis end it with ``CommandAborted``; a new motion command
    (MC_Halt too) does not: the block stays armed.
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("SwitchMode",)
    SwitchMode: int = MC_SwitchMode.MC_EdgeOn

    def _mode(self) -> tuple[MC_SwitchMode | None, int]:
        try:
            mode = MC_SwitchMode(int(number(self.SwitchMode)))
        except (ValueError, OverflowError):
            return None, ErrorID.EParam
        if mode in (MC_SwitchMode.MC_On, MC_SwitchMode.MC_Off):
            return None, ErrorID.EParam
        return mode, 0


class MC_StepRefFlyingRefPulse(_FlyingFB):
    """Flying reference on the encoder index pulse NI (PLCopen Part 5 v2.0; announced in the
    MotionControlLib, Tab. 2.2): while another command moves the axis, the coordinate is set so
    that the next rising edge of the index pulse has the coordinate ``SetPosition`` [u]. The edge
    is the count the encoder latched at it in hardware, exact to the count at any velocity. No
    motion, no abort, state unchanged, Ref set, the outputs, the standing axis, the limits and
    the refusals as for MC_StepRefFlyingSwitch.
    """

"""How commands take over an axis' motion and hand it on (docs/reference.md, BufferMode).

A command handed to the axis (:func:`submit`) starts at once from the model state (Aborting, or
nothing running) or queues behind the active command; a blending mode re-plans the active command
so that it ends at the blending velocity (:func:`replan_for_successor`). An administrative command
in mcQueued waits in the same queue (:func:`submit_deferred`). When the active command reaches its
activating signal, :func:`hand_over` applies the administrative commands at the head of the queue
and starts the successor from the state where the command hands over.
"""

from __future__ import annotations

__all__ = [
    "hand_over",
    "handover_velocity",
    "profile_state",
    "replan_for_successor",
    "start",
    "submit",
    "submit_deferred",
]

from typing import TYPE_CHECKING

from mcl.command import Command, Deferred, MoveTo, MoveVelocity, Status, blend_velocity
from mcl.enums import AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.trajectory import PlanningError

if TYPE_CHECKING:
    from mcl.axis import Axis


def _sign(x: float) -> float:
    return 1.0 if x > 0.0 else -1.0 if x < 0.0 else 0.0


def submit(axis: Axis, cmd: Command) -> None:
    """Hand a validated motion command to ``axis`` according to its BufferMode.

    Aborting: starts now (the active command and the queue report Aborted). Buffered and
    blending: queued behind the active command; a blending mode re-plans the active command
    so that it ends at its target with the blending velocity. A command that cannot be planned,
    or that would queue behind one that takes no successor (MC_GearIn), ends with Error
    ``EParam`` and leaves the axis as it was.
    """
    cmd.status = Status.Queued
    if cmd.buffer_mode == MC_BufferMode.Aborting or (axis.active is None and not axis.queue):
        standstill = axis.state == AxisState.StandStill
        held = axis.sp_pos
        if standstill:
            axis.sp_pos = axis.actual  # zero the residual loop error
        overridden = profile_state(axis)
        try:
            start(axis, cmd, axis.sp_pos, axis.sp_vel, axis.sp_acc, axis.t_sp, None, overridden)
        except PlanningError:
            axis.sp_pos = held
            cmd.status = Status.Error
            cmd.error_id = ErrorID.EParam
            return
        axis._abort_all(except_cmd=cmd)
        axis.active = cmd
        axis.state = cmd.state
        return
    last = axis.queue[-1] if axis.queue else axis.active
    if last is not None and not last.accepts_buffered:
        cmd.status, cmd.error_id = Status.Error, ErrorID.EParam
        return
    axis.queue.append(cmd)
    if len(axis.queue) == 1 and axis.active is not None:
        replan_for_successor(axis, axis.active)


def submit_deferred(axis: Axis, cmd: Deferred) -> None:
    """An administrative command in mcQueued (MC_SetPosition, MC_WriteParameter): apply it
    now when no command is active or queued, else queue it like a Buffered command
    (refused with ``EParam`` behind a command that takes no successor, MC_GearIn). Its
    status tells the result: Done once applied, Error when refused then (nothing changed),
    Aborted when an Aborting command, a stop or power-off ends the queue first (an axis
    error: Error with its code)."""
    if axis.active is None and not axis.queue:
        cmd.apply(axis)
        return
    last = axis.queue[-1] if axis.queue else axis.active
    if last is not None and not last.accepts_buffered:
        cmd.status, cmd.error_id = Status.Error, ErrorID.EParam
        return
    cmd.status = Status.Queued
    axis.queue.append(cmd)


def start(
    axis: Axis,
    cmd: Command,
    p: float,
    v: float,
    a: float,
    t0: float,
    successor: Command | None,
    profile: tuple[float, float] | None = None,
) -> None:
    """Activate ``cmd`` from the model state at ``t0``; it ends at the blending velocity
    toward ``successor``. ``profile``: the velocity and acceleration in the profile time of
    the overridden motion it takes over (None: that motion was not overridden).

    Raises:
        PlanningError: the motion cannot be planned.
    """
    v_end = handover_velocity(cmd, successor, p) if successor is not None else 0.0
    scale = axis._time_scale
    factor = 1.0
    if scale is not None:
        factor, v, a = scale.entry(cmd.overridable, v, a, profile)
    cmd.t0 = t0
    cmd.start(axis, p, v, a, v_end)
    cmd.status = Status.Active
    if scale is not None:
        scale.factor = factor
        if scale.idle:
            axis._time_scale = None


def handover_velocity(first: Command, second: Command, start: float) -> float:
    """Signed velocity at which ``first`` (starting at ``start`` [u]) hands over to
    ``second`` [u/s] (docs/reference.md, BufferMode)."""
    if not first.blendable or first.target is None:
        return 0.0
    end = first.target
    if isinstance(second, MoveVelocity):
        direction2 = _sign(second.commanded)
    else:
        direction2 = _sign(second.target - end) if second.target is not None else 0.0
    return blend_velocity(
        second.buffer_mode, first.velocity, second.velocity, _sign(end - start), direction2
    )


def replan_for_successor(axis: Axis, cmd: Command) -> None:
    """Re-plan the active ``cmd`` to end at the blending velocity toward the first queued
    command; it keeps its plan when that velocity is 0 or the re-plan fails."""
    if not isinstance(cmd, MoveTo) or not axis.queue:
        return
    v_end = handover_velocity(cmd, axis.queue[0], axis.sp_pos)
    if v_end == 0.0:
        return
    v, a = profile_state(axis) or (axis.sp_vel, axis.sp_acc)
    try:
        cmd.plan(axis.sp_pos, v, a, v_end)
    except PlanningError:
        return  # keeps its plan: the successor then starts from standstill
    cmd.t0 = axis.t_sp


def profile_state(axis: Axis) -> tuple[float, float] | None:
    """The running command's velocity and acceleration in its profile time at the last set
    point, where it is overridden (None: it is not)."""
    scale = axis._time_scale
    return scale.profile_state(axis.t_sp) if scale is not None else None


def hand_over(
    axis: Axis, cmd: Command, t: float, p: float, v: float, a: float, factor: float | None = None
) -> tuple[float, float, float]:
    """``cmd`` reached its activating signal at ``t`` [s] with the set point (p, v, a): report it
    and start the successor (if any); returns the set point at ``t``. ``factor``: the override's
    applied factor where ``cmd`` is overridden (None: it is not).

    Queued administrative commands (mcQueued) at the head of the queue are applied first;
    when nothing else is queued behind them, ``cmd`` goes on (a velocity motion) or ends as
    it would without them."""
    queue = axis.queue
    if queue and isinstance(queue[0], Deferred):
        while queue and isinstance(queue[0], Deferred):
            head = queue.popleft()
            assert isinstance(head, Deferred)
            p += head.apply(axis)
        if not queue and not cmd.finished():
            return p, v, a
    te, pe, ve, ae = cmd.handover_state(t - cmd.t0, p, v, a)
    t_end = cmd.t0 + te
    cmd.status = Status.Done if cmd.finished() else Status.Aborted
    at_end = None
    if factor is not None:  # the hand-over state in profile time, and as a set point
        at_end, ve, ae = (ve, ae), factor * ve, factor * factor * ae
    failed = False
    while axis.queue:
        nxt = axis.queue.popleft()
        try:
            start(axis, nxt, pe, ve, ae, t_end, axis.queue[0] if axis.queue else None, at_end)
        except PlanningError:
            nxt.status, nxt.error_id = Status.Error, ErrorID.EParam
            failed = True
            continue
        axis.active = nxt
        axis.state = nxt.state
        return nxt.setpoint(axis, t - t_end)
    axis.active = None
    if failed and ve != 0.0:  # a blending successor failed to start: stop on the max ramp
        axis.sp_pos, axis.sp_vel, axis.sp_acc, axis.t_sp = pe, ve, ae, t_end
        return axis._ramp_down(AxisState.DiscreteMotion).setpoint(axis, t - t_end)
    if axis._powering_off:
        axis._open_loop()
    elif axis.state == AxisState.ErrorStop:
        axis._hold(AxisState.ErrorStop)
    else:
        axis.state = cmd.end_state
    return pe, 0.0, 0.0

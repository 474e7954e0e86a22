"""The saved state of an axis: :class:`AxisSnapshot`, taken at rest and restored bit for bit
(:meth:`mcl.Axis.snapshot`, :meth:`mcl.Axis.restore`). Positions [u], velocities [u/s], times
[s], volts [V]."""

from __future__ import annotations

__all__ = ["AxisSnapshot", "check", "rest_problem", "restore", "take"]

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from mcl.axis_config import AxisConfig, AxisParameters
from mcl.channel import ChannelSnapshot
from mcl.command import Hold, Status
from mcl.enums import AxisState
from mcl.errors import StateError
from mcl.servo import ServoConstants

if TYPE_CHECKING:
    from mcl.axis import Axis


@dataclass(frozen=True, slots=True)
class AxisSnapshot:
    """Everything an :class:`Axis` and its channel carry at one instant at rest
    (:meth:`Axis.snapshot`): power and loop, reference (homing) and coordinate offset, error,
    servo constants and regulator memory, the model (set point) state, the measured values
    and the channel (:class:`~mcl.channel.ChannelSnapshot`). Positions [u], velocities [u/s],
    times [s], volts [V].

    Function blocks, axes groups and an armed touch probe belong to the PLC program, not to the
    axis: they are not part of it.
    """

    name: str
    config: AxisConfig
    channel: ChannelSnapshot
    state: AxisState
    AxErrorID: int
    POS: float
    VEL: float
    Ref: bool
    opt_select: tuple[int, int]
    constants: ServoConstants | None
    regulator: tuple[float, float, float, float] | None
    """Integral action [V] and last following error [u] (None: no constants yet)."""
    speed_mode: int
    loop_closed: bool
    volts: float
    offset: float
    actual: float
    sp_pos: float
    sp_vel: float
    sp_acc: float
    t_sp: float
    sp_time: float
    t_cycle: float
    quick_stop_until: float
    following_error: float
    captured: float
    probe_position: float | None
    hold: tuple[float, float] | None
    """The position held in ErrorStop and the hold's start time (None: no hold)."""
    estop_latched: bool
    pos_prev: float
    lim_prev: tuple[bool, ...]
    override: float = 1.0
    """The velocity factor MC_SetOverride wrote (1.0 = 100 %)."""
    parameters: AxisParameters | None = None
    """The run-time parameters (software limits, application maxima, following-error
    supervision; None: those of the machine data and the constants)."""


_AT_REST = (AxisState.Disabled, AxisState.StandStill, AxisState.ErrorStop)
"""The axis states in which a state can be saved."""


def rest_problem(axis: Axis) -> str:
    """Why the axis' state cannot be saved now, e.g. ``"axis X is in DiscreteMotion"``;
    empty when it can (Disabled, StandStill or ErrorStop with no command running)."""
    state = axis.state
    if state not in _AT_REST:
        return f"axis {axis.name} is in {state.name}"
    active = axis.active
    if axis.queue or (active is not None and not isinstance(active, Hold)):
        return f"axis {axis.name} is in {state.name} with its stop ramp still running"
    if axis.analog_volts is not None:
        return f"axis {axis.name} is driven by GT_Analog ({axis.analog_volts:g} V)"
    return ""


def take(axis: Axis) -> AxisSnapshot:
    """The axis and its channel now, as an immutable value (see :meth:`restore`).

    Function blocks are not part of it: they belong to the PLC program.

    Raises:
        StateError: a command is running (the message says which state the axis is in).
    """
    problem = rest_problem(axis)
    if problem:
        raise StateError(
            f"cannot save the state: {problem}; stop it first (MC_Halt or MC_Stop, "
            f"GT_Analog off) and wait until it is in StandStill, Disabled or ErrorStop"
        )
    io = axis.io
    regulator = axis.regulator
    hold = axis.active
    return AxisSnapshot(
        name=axis.name,
        config=axis.config,
        channel=io.snapshot(),
        state=axis.state,
        AxErrorID=axis.AxErrorID,
        POS=axis.POS,
        VEL=axis.VEL,
        Ref=axis.Ref,
        opt_select=axis.opt_select,
        constants=replace(axis.constants) if axis.constants is not None else None,
        regulator=regulator.memory() if regulator is not None else None,
        speed_mode=axis.speed_mode,
        loop_closed=axis.loop_closed,
        volts=axis.volts,
        offset=axis.offset,
        actual=axis.actual,
        sp_pos=axis.sp_pos,
        sp_vel=axis.sp_vel,
        sp_acc=axis.sp_acc,
        t_sp=axis.t_sp,
        sp_time=axis._sp_time,
        t_cycle=axis.t_cycle,
        quick_stop_until=axis._quick_stop_until,
        following_error=axis.following_error,
        captured=axis.captured,
        probe_position=axis.probe.position,
        hold=(hold.position, hold.t0) if isinstance(hold, Hold) else None,
        estop_latched=axis.estop_latched,
        pos_prev=axis._pos_prev,
        lim_prev=axis._lim_prev,
        override=axis.override_factor,
        parameters=replace(axis.parameters),
    )


def check(axis: Axis, snapshot: AxisSnapshot) -> None:
    """Raise :class:`~mcl.errors.StateError` unless ``snapshot`` is of this axis: the same
    name, machine data and channel settings."""
    if snapshot.name != axis.name:
        raise StateError(
            f"the state of axis {snapshot.name!r} cannot be restored into axis {axis.name!r}"
        )
    if snapshot.config != axis.config:
        raise StateError(
            f"axis {axis.name}: the state was saved with other machine data "
            f"({snapshot.config}); this axis has {axis.config}"
        )
    axis.io.check_snapshot(snapshot.channel)


def restore(axis: Axis, snapshot: AxisSnapshot) -> None:
    """Return the axis and its channel to the moment ``snapshot`` was taken.

    Positions, velocities, set point, regulator, reference, power, errors and the channel
    come back exactly, so the same program gives the same motion as after the snapshot.
    Whatever the PLC program had on the axis is let go, as after a power cycle of the
    program: running and queued commands end Aborted (their blocks show CommandAborted), a
    waiting touch probe and a waiting flying reference are cancelled, GT_EStop holds are
    released and an axes group the axis belongs to is taken apart. A program built afterwards
    finds the axis as saved (a powered axis stays powered until its MC_Power is called with
    Enable FALSE).

    Raises:
        StateError: the snapshot is of another axis (nothing is changed then).
    """
    check(axis, snapshot)
    s = snapshot
    axis._abort_all()
    axis._stops.clear()
    axis._estops.clear()
    group = axis.group
    if group is not None:
        from mcl.group import AxesGroup

        if isinstance(group, AxesGroup):
            group._abort_tickets()  # its blocks show CommandAborted
            group.ungroup()
        axis.group = None
    axis.probe.restore(s.probe_position, s.channel.tp_seq)  # a waiting block: CommandAborted
    axis.disarm_flying(axis.flying)  # a waiting flying reference sees CommandAborted
    axis.io.restore(s.channel)
    if s.constants is not None:
        axis.set_constants(replace(s.constants))
        assert axis.regulator is not None and s.regulator is not None
        axis.regulator.set_memory(s.regulator)
    else:
        axis.constants = None
        axis.regulator = None
        axis.sw_limits_active = False
        axis._vel_alpha = 1.0
    axis.state = s.state
    axis.AxErrorID = s.AxErrorID
    axis.POS, axis.VEL = s.POS, s.VEL
    axis.Ref = s.Ref
    axis.opt_select = s.opt_select
    axis.speed_mode = s.speed_mode
    axis.loop_closed = s.loop_closed
    axis.analog_volts = None
    axis.volts = s.volts
    axis.offset, axis.actual = s.offset, s.actual
    axis.sp_pos, axis.sp_vel, axis.sp_acc, axis.t_sp = s.sp_pos, s.sp_vel, s.sp_acc, s.t_sp
    axis._sp_time, axis.t_cycle = s.sp_time, s.t_cycle
    axis._quick_stop_until = s.quick_stop_until
    axis.following_error = s.following_error
    axis.captured = s.captured
    axis.estop_latched = s.estop_latched
    axis._powering_off = False
    axis._pos_prev = s.pos_prev
    axis._lim_prev = s.lim_prev
    axis._time_scale = None
    axis.set_override(s.override)
    axis.parameters = (
        replace(s.parameters) if s.parameters is not None else _parameters(axis, s.constants)
    )
    axis.update_sw_limits()
    axis.queue.clear()
    axis.active = None
    if s.hold is not None:
        hold = Hold(s.hold[0], s.state)
        hold.t0 = s.hold[1]
        hold.status = Status.Active
        axis.active = hold


def _parameters(axis: Axis, constants: ServoConstants | None) -> AxisParameters:
    """The run-time parameters of a snapshot that holds none: from the machine data, the
    software limits from the constants."""
    parameters = AxisParameters.of(axis.config)
    if constants is not None:
        parameters.sw_limit_pos, parameters.sw_limit_neg = constants.LimPos, constants.LimNeg
        parameters.sw_enable_pos = parameters.sw_enable_neg = constants.sw_limits_active
    return parameters

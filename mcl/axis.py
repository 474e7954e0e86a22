"""The axis: AXIS_REF, its state machine, command queue and servo cycle.

Function blocks talk to an :class:`Axis` through a few methods (``submit``, ``power``, ``reset``,
``check_ready`` ...); the runtime calls :meth:`Axis.servo_cycle` once per servo period. Positions
are in user units (u = mm or degrees), velocities in u/s, time in seconds. How a command starts,
queues and hands over to the next is in :mod:`mcl.handover`.
"""

from __future__ import annotations

import math
from collections import deque
from typing import TYPE_CHECKING

from mcl import axis_state, handover, software_limits
from mcl.axis_config import AxisConfig, AxisParameters
from mcl.axis_state import AxisSnapshot
from mcl.channel import AxisChannel
from mcl.command import (
    Command,
    CoordinateShift,
    Deferred,
    Halt,
    Hold,
    Status,
    Stop,
)
from mcl.enums import AxisState, MC_BufferMode, MC_Direction
from mcl.errors import ErrorID
from mcl.probe_latch import ProbeLatch
from mcl.servo import Regulator, ServoConstants
from mcl.time_scale import TimeScale
from mcl.trajectory import Limits

if TYPE_CHECKING:
    from mcl.flying_reference import FlyingReference
    from mcl.module import Module

__all__ = ["Axis", "AxisConfig", "AxisSnapshot"]


class Axis:
    """AXIS_REF of one servo axis of a GT-x75x module.

    Public fields a PLC program may read: ``AxErrorID``, ``POS`` (actual position [u]),
    ``VEL`` (actual velocity, filtered [u/s]), ``OPT1n``, ``OPT2n`` (selected by GT_SInfo).
    Besides: ``state``, ``Ref``, ``name``.

    Args:
        io: the axis channel (simulated axis, MuJoCo plant, ...).
        config: machine data.
        name: the axis' name in messages and traces.
    """

    def __init__(
        self, io: AxisChannel, config: AxisConfig | None = None, name: str = "axis"
    ) -> None:
        self.io = io
        self.config = config = config if config is not None else AxisConfig()
        self.name = name
        self.has_drive = bool(io.has_drive)
        """False for an encoder-only axis: it measures (a gearing master) but cannot move."""
        self.servo_period = config.servo_period
        self.module: Module | None = None
        self.group: object | None = None
        self.group_homing = False
        """MC_GroupHome runs this member's homing steps now: they are not refused (1000)."""
        """The AxesGroup this axis belongs to (None: single axis)."""

        self.AxErrorID = 0
        self.POS = 0.0
        self.VEL = 0.0
        self.state = AxisState.Disabled
        self.Ref = False
        self.opt_select = (20, 21)
        """GT_SInfo selection of OPT1n and OPT2n."""

        self.constants: ServoConstants | None = None
        self.parameters = AxisParameters.of(config)
        """What MC_WriteParameter, MC_WriteBoolParameter and GT_SWLim change at run time."""
        self.sw_limits_active = False
        """A software limit is on and the axis is linear (supervised once it has Ref)."""
        self.regulator: Regulator | None = None
        self.speed_mode = 0
        self.loop_closed = False
        self.analog_volts: float | None = None
        """GT_Analog: the DAC value written directly while Disabled [V] (None: inactive)."""
        self.volts = 0.0
        """Analog command written in the last servo cycle [V]."""

        self.offset = 0.0
        """Coordinate offset: actual position = counts · resolution + offset [u]."""
        self.actual = io.counts * config.resolution
        """Actual position, continuous (not wrapped on modulo axes) [u]."""
        self.sp_pos = self.actual
        self.sp_vel = 0.0
        self.sp_acc = 0.0
        self.t_sp = 0.0
        """Time of the model state (sp_pos, sp_vel, sp_acc) [s]."""
        self._sp_time = -math.inf
        self.t_cycle = 0.0
        """The current servo instant [s] (a command that reads another axis passes it on)."""
        self._quick_stop_until = -math.inf
        self.override_factor = 1.0
        """The velocity factor MC_SetOverride commanded (1.0 = 100 %)."""
        self._time_scale: TimeScale | None = None
        """The override's scaling while its factor is not 1.0 or still ramping (None: off)."""
        self.following_error = 0.0
        self.captured = 0.0
        """Position captured at InSync [u] (GT_SInfo 24)."""

        self.probe = ProbeLatch()
        """The touch-probe latch (MC_TouchProbe, MC_GearInPos' zeroing)."""
        self.flying: FlyingReference | None = None
        """The armed flying reference (MC_StepRefFlying*), watched every servo cycle."""

        self.active: Command | None = None
        self.queue: deque[Command] = deque()
        self.estop_latched = False
        """An emergency stop happened and MC_Power has not been switched off since."""
        self._estops: list[object] = []
        """The GT_EStop blocks whose Enable is TRUE: the axis cannot be powered."""
        self._stops: list[Stop] = []
        """The MC_Stop commands that hold the axis in Stopping while their FB's Execute is TRUE."""
        self._powering_off = False
        self._pos_prev = self.actual
        self._vel_alpha = 1.0
        self._lim_prev: tuple[bool, ...] = (
            (io.lim_pos, io.lim_neg) if io.lim_pos or io.lim_neg else ()
        )
        """Limit switch levels of the last cycle; empty while both are off (fast path)."""

    # ------------------------------------------------------------------ public read-outs
    @property
    def OPT1n(self) -> float:
        """Optional value 1 (GT_SInfo What1; default 20 = model position)."""
        return self.optional(self.opt_select[0])

    @property
    def OPT2n(self) -> float:
        """Optional value 2 (GT_SInfo What2; default 21 = model velocity)."""
        return self.optional(self.opt_select[1])

    def optional(self, what: int) -> float:
        """Value of a GT_SInfo selector: 20 model position [u], 21 model velocity [u/s],
        22 encoder status (bits: 0 index, 1 LIM+, 2 LIM−, 3 REF, 4 TP, 5 encoder line fault),
        23 following error [u], 24 position captured at InSync [u]."""
        if what == 20:
            return self._wrap(self.sp_pos)
        if what == 21:
            return self.sp_vel
        if what == 22:
            io = self.io
            status = io.index | io.lim_pos << 1 | io.lim_neg << 2 | io.ref << 3 | io.tp << 4
            return float(status | (not io.encoder_ok) << 5)
        if what == 23:
            return self.following_error
        if what == 24:
            return self.captured
        raise ValueError(f"GT_SInfo selector must be 20..24, got {what}")

    @property
    def DI(self) -> tuple[bool, ...]:
        """Digital inputs as sampled this servo cycle: LIM+, LIM−, REF, TP, then further ones."""
        io = self.io
        return (io.lim_pos, io.lim_neg, io.ref, io.tp, *io.inputs)

    @property
    def DO(self) -> tuple[bool, ...]:
        """Digital outputs as the program set them (MC_WriteDigitalOutput)."""
        return tuple(self.io.outputs)

    @property
    def AI(self) -> tuple[float, ...]:
        """Analog inputs [V] as sampled this servo cycle."""
        return tuple(self.io.analog)

    @property
    def moving(self) -> bool:
        """The model is in motion."""
        return self.sp_vel != 0.0 or self.sp_acc != 0.0

    def _wrap(self, position: float) -> float:
        m = self.config.modulo
        return position % m if m else position

    # ------------------------------------------------------------------ configuration
    def set_constants(self, constants: ServoConstants, sw_limits: bool = True) -> None:
        """Write the servo constants (GT_SetConstant); the regulator restarts from zero.
        ``sw_limits``: take the software limits from LimPos/LimNeg, both switched on when
        LimPos > LimNeg, else both off (False: keep the axis' limits, e.g. MC_WriteParameter
        of one constant)."""
        self.constants = constants
        if sw_limits:
            p = self.parameters
            p.sw_limit_pos, p.sw_limit_neg = constants.LimPos, constants.LimNeg
            p.sw_enable_pos = p.sw_enable_neg = constants.sw_limits_active
        self.update_sw_limits()
        previous = self.regulator
        self.regulator = Regulator(constants, self.servo_period)
        if previous is not None:
            self.regulator.carry_over(previous)
        tau = constants.Filter * 1e-3
        self._vel_alpha = self.servo_period / (self.servo_period + tau)

    def update_sw_limits(self) -> None:
        """The parameters' software limits changed: whether the servo cycle supervises any."""
        p = self.parameters
        self.sw_limits_active = (p.sw_enable_pos or p.sw_enable_neg) and not self.config.modulo

    def set_sw_limits(self, pos: float, neg: float, enable_pos: bool, enable_neg: bool) -> int:
        """Set the software limits at run time (GT_SWLim, MC_WriteParameter 2–5): supervised
        from the next servo cycle. Values must be finite.

        Refused, nothing changed: ``EParam`` when both limits are on and ``pos`` <= ``neg``;
        ``Ecil`` when (with Ref, on a linear axis) a limit switched on or moved would lie behind
        the axis (its set point, or its actual position by more than the following-error budget
        MaxPositionLag) or before the target of the running or a queued command, so a move that
        would cross the new limit is never stopped by it halfway; a limit left as it is is not
        checked again (:func:`mcl.software_limits.change_refused`). A velocity motion (no
        target) heading for a new limit is stopped there by the supervision (ERRSWP / ERRSWN on
        the maximum ramp), as by a limit set before it started.
        """
        error = software_limits.change_refused(self, pos, neg, enable_pos, enable_neg)
        if error:
            return error
        p = self.parameters
        p.sw_limit_pos, p.sw_limit_neg = pos, neg
        p.sw_enable_pos, p.sw_enable_neg = enable_pos, enable_neg
        self.update_sw_limits()
        return 0

    def sw_limit_range(self) -> tuple[float, float]:
        """The positions allowed by the software limits now: (negative, positive) [u]
        (:func:`mcl.software_limits.allowed_range`)."""
        return software_limits.allowed_range(self)

    def max_velocity(self) -> float:
        """The velocity commanded motion may reach: Vmax, or MaxVelocityAppl below it [u/s]."""
        assert self.constants is not None
        return min(self.constants.Vmax, self.parameters.max_velocity_appl)

    def limits(
        self, velocity: float, acceleration: float, deceleration: float, jerk: float
    ) -> Limits:
        """Motion limits from FB inputs: 0 means the axis default, values above the maxima are
        clamped (docs/reference.md, Units): Vmax and MaxVelocityAppl, MaxAccelerationAppl,
        MaxDecelerationAppl, MaxJerk (the application maxima of :attr:`parameters`, at most the
        machine data's). Inputs must be validated (finite, velocity > 0, others >= 0)."""
        c = self.config
        p = self.parameters
        acc = acceleration if acceleration > 0.0 else c.acceleration
        dec = deceleration if deceleration > 0.0 else c.deceleration
        j = jerk if jerk > 0.0 else c.jerk
        max_jerk = p.max_jerk
        if max_jerk > 0.0:
            j = min(j, max_jerk) if j > 0.0 else max_jerk
        return Limits(
            velocity=min(velocity, self.max_velocity()),
            acceleration=min(acc, c.max_acceleration, p.max_acceleration_appl),
            deceleration=min(dec, c.max_deceleration, p.max_deceleration_appl),
            jerk=j if j > 0.0 else math.inf,
        )

    def max_ramp(self) -> Limits:
        """The axis' fastest stop (error stops, power-off)."""
        c = self.config
        vmax = self.constants.Vmax if self.constants else 1.0
        jerk = c.max_jerk if c.max_jerk > 0.0 else math.inf
        return Limits(vmax, c.max_deceleration, c.max_deceleration, jerk)

    # ------------------------------------------------------------------ checks for FBs
    def check_ready(
        self, *, stopping_ok: bool = False, homing_ok: bool = False, group_ok: bool = False
    ) -> int:
        """Error code that forbids a motion command now (0 = none), in this order:
        drive (an encoder-only axis has none), constants, power, ErrorStop, Stopping, group
        membership, Homing."""
        if not self.has_drive:
            return ErrorID.ENoDrive
        if self.constants is None:
            return ErrorID.Econst
        state = self.state
        if state == AxisState.Disabled:
            return ErrorID.Epower
        if state == AxisState.ErrorStop:
            return ErrorID.Eerrstop
        if state == AxisState.Stopping and not stopping_ok:
            return ErrorID.EAxStop
        if self.group is not None and not (group_ok or (homing_ok and self.group_homing)):
            return ErrorID.EGroupMember
        if state == AxisState.Homing and not homing_ok:
            return ErrorID.Ehome
        return 0

    def check_target(self, target: float) -> int:
        """``Ecil`` 8 when the target lies beyond an active software limit (only with Ref)."""
        if not self.sw_limits_active or not self.Ref:
            return 0
        low, high = self.sw_limit_range()
        return 0 if low <= target <= high else ErrorID.Ecil

    def velocity_too_low(self, velocity: float) -> bool:
        """Below 1 % of the axis reference velocity Vmax (→ EParam)."""
        return self.constants is not None and velocity < 0.01 * self.constants.Vmax

    # ------------------------------------------------------------------ positions
    def planned_ends(self) -> list[float]:
        """Where each command with a target (the active one, then the queued ones) ends [u], in
        the coordinate a queued MC_SetPosition (mcQueued) will have set by then."""
        end = self.sp_pos
        ends = []
        for cmd in (self.active, *self.queue):
            if isinstance(cmd, Deferred):
                end = cmd.moved(end)
            elif cmd is not None and cmd.target is not None:
                end = cmd.target
            else:
                continue
            ends.append(end)
        return ends

    def last_target(self) -> float:
        """Where the commanded motion ends: the last queued/active target, else the model [u]."""
        ends = self.planned_ends()
        return ends[-1] if ends else self.sp_pos

    def modulo_target(self, position: float, direction: int, start: float) -> float:
        """Continuous model target for an absolute position on a modulo axis.

        Args:
            position: target within one period [u] (wrapped if outside).
            direction: an ``MC_Direction`` value: positive, negative, shortest or current.
            start: where the motion starts (continuous) [u].
        """
        m = self.config.modulo
        base = start - start % m + position % m
        ahead = base if base >= start else base + m
        behind = ahead - m if ahead - m <= start else ahead - 2 * m
        if direction == MC_Direction.MC_Current and self.sp_vel != 0.0:
            direction = MC_Direction.MC_Positive if self.sp_vel > 0 else MC_Direction.MC_Negative
        if direction == MC_Direction.MC_Positive:
            return ahead
        if direction == MC_Direction.MC_Negative:
            return behind
        return ahead if ahead - start <= start - behind else behind

    def rebase(self, delta: float) -> None:
        """Shift the coordinate system by ``delta`` [u] (homing, a gearing block zeroing its
        master): actual and model move together, and the active command's motion goes on
        physically unchanged."""
        self.offset += delta
        self.actual += delta
        self._pos_prev += delta
        self.sp_pos += delta
        self.POS = self._wrap(self.actual)
        if self.active is not None:
            self.active.rebase(delta)

    # ------------------------------------------------------------------ coordinate (MC_SetPosition)
    def check_coordinate(self) -> int:
        """Error code that forbids MC_SetPosition now (0 = none): ErrorStop (``Eerrstop``),
        Stopping (``EAxStop``), a group member (1000: the group's path is laid out in its
        members' coordinates), Homing (``Ehome``: the homing procedure sets the coordinate).
        Disabled, StandStill and the motion states allow it; an encoder-only axis too."""
        state = self.state
        if state == AxisState.ErrorStop:
            return ErrorID.Eerrstop
        if state == AxisState.Stopping:
            return ErrorID.EAxStop
        if self.group is not None:
            return ErrorID.EGroupMember
        if state == AxisState.Homing:
            return ErrorID.Ehome
        return 0

    def shift_coordinate(self, delta: float, queued: bool = True) -> int:
        """MC_SetPosition: move the coordinate system by ``delta`` [u] at once, without motion.

        Actual position, model (set point), the running command's path and target and the
        queued commands' targets move by ``delta`` together (up to a queued absolute
        MC_SetPosition, whose successors are already in its coordinate): every command handed
        to the axis goes on physically as before. The software limits keep their values: they
        are positions of the new coordinate system. ``Ecil`` (nothing changed) when the axis or
        a target of its commands would then lie beyond an active software limit (with Ref).
        ``queued`` False: the queued commands are in the new coordinate already (a queued
        MC_SetPosition applied when the command before it signals) and stay as they are.
        """
        error = software_limits.shift_refused(self, delta, queued)
        if error:
            return error
        self.rebase(delta)
        for cmd in self.queue if queued else ():
            if isinstance(cmd, CoordinateShift) and not cmd.relative:
                break
            cmd.rebase(delta)
        self.captured += delta
        self.probe.shift(delta)
        return 0

    # ------------------------------------------------------------------ commands
    def submit(self, cmd: Command) -> None:
        """Hand a validated motion command to the axis according to its BufferMode: start it
        now or queue it (:func:`mcl.handover.submit`; docs/reference.md, BufferMode)."""
        handover.submit(self, cmd)

    def submit_deferred(self, cmd: Deferred) -> None:
        """An administrative command in mcQueued (MC_SetPosition, MC_WriteParameter): apply it
        now or queue it like a Buffered command (:func:`mcl.handover.submit_deferred`)."""
        handover.submit_deferred(self, cmd)

    def start_position(self, buffer_mode: MC_BufferMode) -> float:
        """Where a new command of ``buffer_mode`` starts: the model position when it aborts, the
        end of the last queued motion when it is buffered [u]."""
        if buffer_mode == MC_BufferMode.Aborting or (self.active is None and not self.queue):
            return self.actual if self.state == AxisState.StandStill else self.sp_pos
        return self.last_target()

    def set_override(self, factor: float) -> None:
        """MC_SetOverride: scale the overridable motion by ``factor`` (validated: 0 ..
        :data:`~mcl.time_scale.MAX_FACTOR`), ramped (:mod:`mcl.time_scale`)."""
        self.override_factor = factor
        scale = self._time_scale
        if scale is None:
            if factor != 1.0:
                self._time_scale = TimeScale(factor)
            return
        scale.target = factor
        if scale.idle:
            self._time_scale = None

    def _abort_all(
        self, except_cmd: Command | None = None, status: Status = Status.Aborted, error_id: int = 0
    ) -> None:
        for cmd in (self.active, *self.queue):
            if cmd is not None and cmd is not except_cmd and cmd.busy:
                cmd.status = status
                cmd.error_id = error_id
        self.queue.clear()
        self.active = None

    def cancel(self, cmd: Command) -> None:
        """Withdraw a command of an FB that was restarted (no Done/Aborted will be reported)."""
        if cmd in self.queue:
            self.queue.remove(cmd)
        cmd.status = Status.Aborted

    # ------------------------------------------------------------------ power, reset, errors
    def power(self, enable: bool, speed_mode: int = 0) -> None:
        """MC_Power, level-sensitive: close or open the loop (docs/reference.md, Axis state
        machine).

        After an emergency stop the axis stays Disabled while a GT_EStop holds it and until
        ``power(False)`` has acknowledged the stop: keeping Enable TRUE never restarts it.
        """
        if enable:
            if self.estop_latched or self._estops:
                return
            if self.state == AxisState.Disabled and not self._powering_off:
                self.analog_volts = None
                self.speed_mode = speed_mode
                self.Ref = False
                self._close_loop()
                if self.AxErrorID:
                    self.state = AxisState.ErrorStop
                    self._hold(AxisState.ErrorStop)
                else:
                    self.state = AxisState.StandStill
            return
        self.estop_latched = False
        if self.state == AxisState.Disabled or self._powering_off:
            return
        self._abort_all()
        if self.moving and self.loop_closed:
            self._powering_off = True
            self._ramp_down(AxisState.Stopping)
        else:
            self._open_loop()

    def _close_loop(self) -> None:
        assert self.regulator is not None
        self.regulator.reset()
        self.loop_closed = True
        self.sp_pos, self.sp_vel, self.sp_acc = self.actual, 0.0, 0.0

    def _open_loop(self) -> None:
        self._quick_stop_until = -math.inf
        self._stops.clear()
        self.loop_closed = False
        self._powering_off = False
        self.active = None
        self.queue.clear()
        self.state = AxisState.Disabled
        self.sp_vel = self.sp_acc = 0.0

    def _hold(self, state: AxisState) -> None:
        hold = self.active = Hold(self.sp_pos, state)
        hold.t0, hold.status = self.t_sp, Status.Active

    def _ramp_down(self, state: AxisState) -> Halt:
        """Stop on the maximum ramp from the model state; the ramp becomes the active command."""
        ramp = Halt(MC_BufferMode.Aborting, self.max_ramp())
        ramp.state = state
        handover.start(self, ramp, self.sp_pos, self.sp_vel, self.sp_acc, self.t_sp, None)
        self.active = ramp
        self.state = state
        return ramp

    def fault(self, code: int, open_loop: bool = False, stop_pushing: bool = False) -> None:
        """Axis error: latch ``code`` in AxErrorID, end all commands with it, go to ErrorStop.
        In ErrorStop only an error that opens the loop is taken (it replaces the code).

        Args:
            code: the error (2001 following error, 2004/2005 limit switches, ...).
            open_loop: open the position loop (drive disabled) instead of a stop ramp.
            stop_pushing: hold the actual position with a cleared integrator instead of a ramp
                (the axis is pressing against something, e.g. a homing TorqueLimit error).
        """
        state = self.state  # the supervision's open_loop error comes with the loop closed
        if state == AxisState.Disabled or (state == AxisState.ErrorStop and not open_loop):
            return
        self.AxErrorID = int(code)
        self._stops.clear()
        self._abort_all(status=Status.Error, error_id=int(code))
        self._powering_off = False
        self.state = AxisState.ErrorStop
        if open_loop:
            self.loop_closed = False
            self.sp_vel = self.sp_acc = 0.0
            self._quick_stop_until = self.t_sp + self.config.quick_stop_time
        elif stop_pushing:
            self._rest_at_actual()
            self._hold(AxisState.ErrorStop)
        else:
            self._ramp_down(AxisState.ErrorStop)

    def _rest_at_actual(self) -> None:
        """Model at the actual position, at rest, integrator cleared: the drive stops pushing."""
        self.sp_pos, self.sp_vel, self.sp_acc = self.actual, 0.0, 0.0
        if self.regulator is not None:
            self.regulator.reset()

    def reset(self) -> bool:
        """MC_Reset: clear the axis error; ErrorStop → StandStill (Disabled if the loop opened).

        Returns:
            True once done; False while the error stop ramp is still running, or the
            amplifier's quick stop after an opened loop (the drive is still enabled then).
        """
        if self.state == AxisState.ErrorStop:
            if self.active is not None and not isinstance(self.active, Hold):
                return False
            if not self.loop_closed and self.drive_enabled:
                return False
            self.AxErrorID = 0
            self.active = None
            if self.loop_closed:
                self._rest_at_actual()  # whatever the error left pushing is released
                self.state = AxisState.StandStill
            else:
                self.state = AxisState.Disabled
            return True
        if self.state == AxisState.Disabled:
            self.AxErrorID = 0
        return True

    def emergency_stop(self) -> None:
        """GT_EStop on this axis: immediate stop, loop open, brake on, errors cleared, Disabled;
        latched until ``power(False)`` (see :meth:`power`)."""
        self.estop_latched = True
        self._abort_all()
        self.AxErrorID = 0
        self.analog_volts = None
        self._open_loop()

    def hold_estop(self, source: object, active: bool) -> None:
        """A GT_EStop (``source``) holds the axis Disabled while ``active`` (its Enable)."""
        estops = self._estops
        if active and source not in estops:
            estops.append(source)
        elif not active and source in estops:
            estops.remove(source)

    def begin_stop(self, cmd: Stop) -> None:
        """MC_Stop: aborts everything, ramps down and holds the axis in Stopping.

        Every Stop keeps holding the axis while its ``hold`` (its FB's Execute) is TRUE, also
        after a later Stop has taken over the ramp: the axis leaves Stopping for StandStill only
        once the last ramp is done and no Stop holds it any more (docs/reference.md, MC_Stop).
        """
        stops = self._stops = [s for s in self._stops if s.hold]
        stops.append(cmd)
        self.submit(cmd)
        if cmd.status == Status.Error:
            stops.remove(cmd)

    def set_analog(self, volts: float | None) -> None:
        """GT_Analog: drive the DAC directly while Disabled (None ends it)."""
        self.analog_volts = volts

    # ------------------------------------------------------------------ servo cycle
    def servo_cycle(self, t: float) -> None:
        """One servo cycle of this axis alone at time ``t`` [s]: measure, set point, act.

        A runtime with several axes runs each phase over all axes instead (see
        :class:`mcl.runtime.Runtime`), so that one axis can use another's values of the same
        instant.
        """
        self.measure(t)
        self.update_setpoint(t)
        self.act(t)

    def measure(self, t: float) -> None:
        """Phase 1: read the sampled inputs: actual position ``POS`` and velocity ``VEL``."""
        self.t_cycle = t
        io = self.io
        config = self.config
        actual = io.counts * config.resolution + self.offset
        self.actual = actual
        self.VEL += ((actual - self._pos_prev) / self.servo_period - self.VEL) * self._vel_alpha
        self._pos_prev = actual
        self.POS = actual % config.modulo if config.modulo else actual
        probe = self.probe
        if probe.armed and io.tp_seq != probe.seq:
            probe.latched(io.tp_seq, self._wrap(io.tp_count * config.resolution + self.offset))
        flying = self.flying
        if flying is not None and flying.watch(self, t):
            self.flying = None

    # ------------------------------------------------------------------ flying reference
    def arm_flying(self, job: FlyingReference) -> None:
        """Arm a flying reference (MC_StepRefFlyingSwitch / MC_StepRefFlyingRefPulse); one
        waiting already ends Aborted."""
        self.disarm_flying(self.flying)
        job.arm(self)
        self.flying = job

    def disarm_flying(self, job: FlyingReference | None) -> None:
        """Withdraw ``job`` if it is the one armed (it ends Aborted)."""
        if job is not None and job is self.flying:
            job.end(Status.Aborted)
            self.flying = None

    # ------------------------------------------------------------------ touch probe
    def arm_probe(self, window: tuple[float, float] | None = None) -> int:
        """Arm the touch-probe latch for the next TP edge (within ``window`` [u], if given);
        returns the arming's generation (:class:`mcl.probe_latch.ProbeLatch`)."""
        return self.probe.arm(self.io.tp_seq, window)

    def update_setpoint(self, t: float) -> None:
        """Phase 2: the model state (``sp_pos``, ``sp_vel``, ``sp_acc``) at time ``t`` [s].

        Computed once per instant: a gearing slave calls it on its master first, so it reads
        the master's set point of the same instant whatever the order of the axes.
        """
        if self._sp_time == t:
            return
        self._sp_time = t
        if not self.loop_closed:
            self.sp_pos, self.sp_vel, self.sp_acc, self.t_sp = self.actual, 0.0, 0.0, t
            return
        cmd = self.active
        if cmd is None:
            p, v, a = self.sp_pos, 0.0, 0.0
        elif self._time_scale is not None and cmd.overridable:
            p, v, a = self._time_scale.setpoint(self, cmd, t)
        else:
            p, v, a = cmd.setpoint(self, t - cmd.t0)
            if cmd.signal and (self.queue or cmd.finished()):
                p, v, a = handover.hand_over(self, cmd, t, p, v, a)
        self.sp_pos, self.sp_vel, self.sp_acc, self.t_sp = p, v, a, t
        stops = self._stops
        if stops and self.active is None and not any(s.hold for s in stops):
            stops.clear()
            if self.state == AxisState.Stopping:
                self.state = AxisState.StandStill

    def _enable_at(self, t: float) -> bool:
        """The drive enable the module writes at time ``t`` [s]: on while the loop is closed,
        while GT_Analog drives the DAC and during the quick stop after ERRPOS 2001."""
        return self.loop_closed or self.analog_volts is not None or t < self._quick_stop_until

    @property
    def drive_enabled(self) -> bool:
        """The drive enable the module writes in the current servo cycle (MC_Power.Status)."""
        return self._enable_at(self.t_cycle)

    def act(self, t: float) -> None:
        """Phase 3: supervise, regulate and write the analog output."""
        io = self.io
        if not self.loop_closed:
            self.following_error = 0.0
            volts = self.analog_volts
            self.volts = volts if volts is not None else 0.0
            io.write(self.volts, self._enable_at(t))
            self._lim_prev = (io.lim_pos, io.lim_neg) if io.lim_pos or io.lim_neg else ()
            return
        config = self.config
        actual = self.actual  # a homing step may have just set the coordinate
        e = self.sp_pos - actual
        self.following_error = e
        lim_pos, lim_neg = io.lim_pos, io.lim_neg
        if (
            lim_pos
            or lim_neg
            or self._lim_prev
            or abs(e) > self.parameters.max_position_lag
            or (self.sw_limits_active and self.Ref)
            or not io.encoder_ok
        ):
            self._supervise(e, self.sp_vel, actual, lim_pos, lim_neg)
        if not self.loop_closed:  # opened by the supervision: quick stop by the amplifier
            self.volts = 0.0
            io.write(0.0, self._enable_at(t))
            return
        regulator = self.regulator
        assert regulator is not None
        if self.speed_mode:
            self.volts = regulator.open_loop(self.sp_vel)
        else:
            settle = self.sp_vel == 0.0 and abs(e) > config.in_position
            self.volts = regulator.output(e, self.sp_vel, self.sp_acc, settle)
        io.write(self.volts, True)

    # ------------------------------------------------------------------ saved state
    def rest_problem(self) -> str:
        """Why the axis' state cannot be saved now, e.g. ``"axis X is in DiscreteMotion"``;
        empty when it can (Disabled, StandStill or ErrorStop with no command running)."""
        return axis_state.rest_problem(self)

    def snapshot(self) -> AxisSnapshot:
        """The axis and its channel now, as an immutable value (see :meth:`restore`).

        Raises:
            StateError: a command is running (the message says which state the axis is in).
        """
        return axis_state.take(self)

    def check_snapshot(self, snapshot: AxisSnapshot) -> None:
        """Raise :class:`~mcl.errors.StateError` unless ``snapshot`` is of this axis: the same
        name, machine data and channel settings."""
        axis_state.check(self, snapshot)

    def restore(self, snapshot: AxisSnapshot) -> None:
        """Return the axis and its channel to the moment ``snapshot`` was taken; whatever the
        PLC program had on the axis is let go (see :func:`mcl.axis_state.restore`).

        Raises:
            StateError: the snapshot is of another axis (nothing is changed then).
        """
        axis_state.restore(self, snapshot)

    def _supervise(self, e: float, v: float, actual: float, lim_pos: bool, lim_neg: bool) -> None:
        """Following error, limit switches and software limits: the servo core's supervision."""
        prev_pos, prev_neg = self._lim_prev or (False, False)
        self._lim_prev = (lim_pos, lim_neg) if lim_pos or lim_neg else ()
        p = self.parameters
        lag = p.lag_monitoring and abs(e) > p.max_position_lag and not self.speed_mode
        if not self.io.encoder_ok or lag:
            self.fault(ErrorID.ERRPOS, open_loop=True)
            return
        if self.state == AxisState.ErrorStop:  # stopped already: only the loop is supervised
            return
        active = self.active
        homing = self.state == AxisState.Homing  # not referenced: the search handles switches
        if not homing and (active is None or not active.ignores_limit_switches):
            if lim_pos and (v > 0.0 or not prev_pos):
                self.fault(ErrorID.ERRLIP)
                return
            if lim_neg and (v < 0.0 or not prev_neg):
                self.fault(ErrorID.ERRLIN)
                return
        if self.Ref and self.sw_limits_active:
            error = software_limits.crossed(self, v, actual)
            if error:
                self.fault(error)

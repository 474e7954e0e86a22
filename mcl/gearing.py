"""Master/slave function blocks (MotionControlLib §4): MC_GearIn, MC_GearInPos, MC_GearOut.

The slave runs the block's command; the master is only read, once per servo instant, after its own
set point of that instant (so the order of the axes does not matter). A master whose position loop
is closed is read by its set point (position, velocity, acceleration), exactly.

Any other master (an encoder-only axis such as a measuring wheel, or a driven axis that is not
powered) is read by its encoder through a type-3 tracking filter (position, velocity and
acceleration, an alpha-beta-gamma observer) with a triple pole at ``Kv``:
``x̂⁻ = x̂ + v̂·T + â·T²/2``, ``v̂⁻ = v̂ + â·T``, ``ρ = x − x̂⁻``, ``x̂ = x̂⁻ + α·ρ``,
``v̂ = v̂⁻ + β·ρ/T``, ``â = â + γ·ρ/T²`` with ``r = exp(−Kv·T)``, ``α = 1 − r³``,
``β = 1.5·(1 − r)²·(1 + r)``, ``γ = (1 − r)³`` (T the servo period). It follows a master that
runs at a constant velocity or ramps with a constant acceleration without lag and smooths the
encoder's quantization. Its three estimates are each right but not one trajectory (the
position estimate jumps by ``α·ρ``, the velocity by ``β·ρ/T``): a slave servo fed them runs off
its set point while the master changes speed. The master is therefore read through a
set-point model locked on the filter, ``a_m = â + (k_x·(x̂ − x_m)/T + k_v·(v̂ − v_m))/T``,
held until the next instant, ``x_m`` and ``v_m`` integrated from it, with a double pole at ``3·Kv``
(``q = exp(−3·Kv·T)``, ``k_x = (1 − q)²``, ``k_v = (1 − q)·(3 + q)/2``): position, velocity and
acceleration of one trajectory, which follows a constant acceleration of the master without
lag. Its acceleration is the slave's acceleration set point (the servo's Ka feed-forward), so a
geared slave follows a line that changes speed.

Master positions are taken in the master's coordinate at the moment the command takes over the
slave; a later change of that coordinate (homing, another block's zeroing) does not move a sync
point, and a geared slave does not jump with it.

Errors while a command runs stop the slave on its maximum ramp in ErrorStop, with the code in
``AxErrorID`` (MC_Reset clears it), so that no cut is made out of sync.
``ESyncUnreachable`` 15: MC_GearInPos cannot bring the slave into sync before MasterSyncPosition
within Velocity, Acceleration, Deceleration and Jerk without backing up (the master is too fast or
too close, ratio × master velocity exceeds Velocity, or the master passed MasterSyncPosition before
the synchronisation could start). ``EMasterReversed`` 16: the master moved back during the
synchronisation (between StartSync and InSync) by more than its in-position window, at least four
encoder counts. ``EMasterError`` 17: the master went to ErrorStop or its encoder failed.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar, Final

from mcl import trajectory
from mcl.axis import Axis as AxisRef
from mcl.command import Command, MoveVelocity, Status
from mcl.enums import AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import ExecuteFB, MotionFB, non_negative
from mcl.motion import ready_limits
from mcl.trajectory import Limits, PlanningError, Profile

DEFAULT_KV: Final = 100.0
"""Bandwidth of the master tracking filter when ``Kv`` is 0 [1/s]: a wheel of 0.025 mm per count
read every 2 ms at 200 mm/s gives the slave's velocity set point 0.24 % rms of quantization
noise (0.35 % at 200 1/s)."""
MODEL: Final = 3.0
"""Bandwidth of the set-point model locked on the tracking filter, in units of ``Kv``."""
REPLAN: Final = 0.05
"""MC_GearInPos plans its synchronisation again when the master runs this much faster than
planned (a relative speed-up); slower masters are followed on the same plan."""
INT_MIN: Final = -32768
INT_MAX: Final = 32767

_WAIT_MARK: Final = 0
_WAIT_START: Final = 1
_SYNC: Final = 2
_LOCKED: Final = 3


def _sign(x: float) -> float:
    return 1.0 if x > 0.0 else -1.0 if x < 0.0 else 0.0


class MasterReader:
    """The master's position [u], velocity [u/s] and acceleration [u/s²] at each servo instant,
    in the master coordinate of the reader's creation (see the module text).

    Args:
        master: the master axis.
        kv: bandwidth of the tracking filter for a master read by its encoder [1/s].
    """

    def __init__(self, master: AxisRef, kv: float) -> None:
        self.master = master
        self.offset0 = master.offset
        r = math.exp(-kv * master.servo_period)
        self.alpha = 1.0 - r * r * r
        self.beta = 1.5 * (1.0 - r) * (1.0 - r) * (1.0 + r)
        self.gamma = (1.0 - r) * (1.0 - r) * (1.0 - r)
        q = math.exp(-MODEL * kv * master.servo_period)
        self.k_x = (1.0 - q) * (1.0 - q)
        self.k_v = 0.5 * (1.0 - q) * (3.0 + q)
        self.t = master.t_cycle
        self.x = master.actual
        self.v = master.VEL
        self.a = 0.0
        """The filter's estimate: position [u], velocity [u/s], acceleration [u/s²]."""
        self.xm, self.vm, self.am = self.x, self.v, 0.0
        """The set-point model's state: position [u], velocity [u/s], acceleration [u/s²]."""
        self.position = self.x
        self.velocity = self.v
        self.acceleration = 0.0
        if master.has_drive and master.loop_closed:
            self.position, self.velocity, self.acceleration = (
                master.sp_pos,
                master.sp_vel,
                master.sp_acc,
            )
            self.v = self.vm = master.sp_vel

    @property
    def shift(self) -> float:
        """How far the master coordinate moved since the reader was made [u]."""
        return self.master.offset - self.offset0

    def read(self, t: float) -> None:
        """Update to the servo instant ``t`` [s] (once per instant)."""
        if t == self.t:
            return
        master = self.master
        master.update_setpoint(t)
        shift = master.offset - self.offset0
        dt = t - self.t
        self.t = t
        if dt > 0.0:
            a = self.a
            predicted = self.x + (self.v + 0.5 * a * dt) * dt
            residual = master.actual - shift - predicted
            self.x = predicted + self.alpha * residual
            self.v += a * dt + self.beta * residual / dt
            self.a = a + self.gamma * residual / (dt * dt)
            am = self.am  # held since the last instant
            self.xm += (self.vm + 0.5 * am * dt) * dt
            self.vm += am * dt
            self.am = (
                self.a + (self.k_x * (self.x - self.xm) / dt + self.k_v * (self.v - self.vm)) / dt
            )
        if master.has_drive and master.loop_closed:
            self.position = master.sp_pos - shift
            self.velocity = master.sp_vel
            self.acceleration = master.sp_acc
        else:
            self.position = self.xm
            self.velocity = self.vm
            self.acceleration = self.am

    def error(self) -> int:
        """``EMasterError`` when the master is in ErrorStop or its encoder failed, else 0."""
        master = self.master
        if master.state == AxisState.ErrorStop or not master.io.encoder_ok:
            return ErrorID.EMasterError
        return 0


class GearIn(Command):
    """MC_GearIn's command: the slave's velocity ramps to ratio × master velocity, then the
    slave is locked to the master's position (``signal`` = InGear).

    The ramp is planned on the difference of the two velocities, ``e(t)`` from
    ``(0, v − R·vm, a − R·am)`` to rest with the Acceleration (the slave speeds up) or the
    Deceleration (it slows down) and the Jerk; the set point is
    ``s = s0 + R·(m − m0) + e(t)``, so a master that changes speed during the ramp is followed
    at once, and the distance ``e`` lost while ramping stays lost.
    """

    state = AxisState.SynchronizedMotion
    accepts_buffered = False

    def __init__(
        self, buffer_mode: MC_BufferMode, master: AxisRef, ratio: float, limits: Limits
    ) -> None:
        super().__init__(buffer_mode)
        self.master = master
        self.ratio = ratio
        self.limits = limits
        self.reader: MasterReader | None = None
        self.ramp: Profile | None = None
        self.base = 0.0
        """Slave position minus ratio × master position [u]."""

    def start(self, axis: AxisRef, p: float, v: float, a: float, v_end: float) -> None:
        master = self.master
        master.update_setpoint(master.t_cycle)
        reader = self.reader = MasterReader(master, DEFAULT_KV)
        ratio, limits = self.ratio, self.limits
        self.base = p - ratio * reader.position
        gear_v = ratio * reader.velocity
        rate = limits.acceleration if abs(v) < abs(gear_v) else limits.deceleration
        self.ramp = trajectory.velocity_to(
            0.0,
            v - gear_v,
            a - ratio * reader.acceleration,
            0.0,
            Limits(limits.velocity, rate, rate, limits.jerk),
        )

    def setpoint(self, axis: AxisRef, t: float) -> tuple[float, float, float]:
        reader = self.reader
        assert reader is not None
        reader.read(axis.t_cycle)
        error = reader.error()
        if error:
            axis.fault(error)
            return axis.sp_pos, axis.sp_vel, axis.sp_acc
        ratio = self.ratio
        p = self.base + ratio * reader.position
        v = ratio * reader.velocity
        a = ratio * reader.acceleration
        ramp = self.ramp
        if ramp is None:
            return p, v, a
        if t >= ramp.duration:
            self.base += ramp.end_position
            self.ramp = None
            self.signal = True
            return p + ramp.end_position, v, a
        e, ev, ea = ramp.at(t)
        return p + e, v + ev, a + ea

    def finished(self) -> bool:
        return False

    def rebase(self, delta: float) -> None:
        self.base += delta


class GearInPos(Command):
    """MC_GearInPos' command: wait, synchronise, then run locked (``signal`` = InSync).

    Phases: (Zeroing 2: wait for the touch-probe latch on the master and zero the master at the
    mark), wait for the start point while the previous motion of the slave goes on, synchronise
    along a plan laid out over the master's travel, then run locked:
    ``s = SlaveSyncPosition + R·(m − MasterSyncPosition)``.

    The plan: at StartSync, master at ``m_a`` moving with speed ``w`` toward the sync point
    ``u_total`` ahead, a jerk-limited motion ``P(τ)`` from the slave's state to
    (SlaveSyncPosition, R·vm, 0) taking ``T = u_total/w`` and never moving against the master
    (:func:`mcl.trajectory.sync_to`). It is followed by the master's progress ``u = d·(m − m_a)``
    (d = ±1, the master's direction), not by time: ``τ = u·k`` with ``k = duration/u_total``,
    ``s = P(τ)``, ``ṡ = P′(τ)·k·d·vm``, ``s̈ = P″(τ)·(k·d·vm)² + P′(τ)·k·d·am``. So the slave
    reaches the gear exactly when the master reaches MasterSyncPosition however the master's speed
    ripples or drops on the way; a master more than :data:`REPLAN` faster than planned gets a
    new plan from the slave's current state.
    """

    state = AxisState.SynchronizedMotion

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        master: AxisRef,
        ratio: float,
        master_sync: float,
        slave_sync: float,
        start_distance: float,
        limits: Limits,
        kv: float,
        zeroing: int,
        delay: float,
    ) -> None:
        super().__init__(buffer_mode)
        self.master = master
        self.ratio = ratio
        self.master_sync = master_sync
        self.slave_sync = slave_sync
        self.start_distance = start_distance
        self.limits = limits
        self.kv = kv
        self.zeroing = zeroing
        self.delay = delay
        """Sensor delay of the touch probe [s]."""
        self.direction = _sign(start_distance)
        """The master's direction of synchronisation (0: decided at the start)."""
        self.reader: MasterReader | None = None
        self.previous: Command | None = None
        """The slave's previous motion, continued until the synchronisation starts."""
        self.hold = 0.0
        self.phase = _WAIT_START
        self.generation = 0
        self.sync_at = 0.0
        """MasterSyncPosition in the reader's coordinate [u]."""
        self.start_at = 0.0
        self.started = False
        """StartSync: the synchronisation began."""
        self.profile: Profile | None = None
        self.m_a = 0.0
        self.u_total = 0.0
        self.k = 0.0
        self.w = 0.0
        self.u_max = 0.0
        self.tolerance = max(master.config.in_position, 4.0 * master.config.resolution)

    # ------------------------------------------------------------------ Command interface
    def start(self, axis: AxisRef, p: float, v: float, a: float, v_end: float) -> None:
        master = self.master
        master.update_setpoint(master.t_cycle)
        self.reader = MasterReader(master, self.kv)
        previous = axis.active
        self.previous = previous if previous is not None and previous is not self else None
        self.hold = p
        if self.zeroing == 2:
            self.generation = master.arm_probe()
            self.phase = _WAIT_MARK
        else:
            self._targets(0.0)
            self.phase = _WAIT_START

    def setpoint(self, axis: AxisRef, t: float) -> tuple[float, float, float]:
        reader = self.reader
        assert reader is not None
        reader.read(axis.t_cycle)
        error = reader.error()
        if error:
            return self._fail(axis, error)
        if self.phase <= _WAIT_START:
            p, v, a = self._previous_motion(axis)
            if self.status != Status.Active:
                return p, v, a
            if self.phase == _WAIT_MARK:
                self._await_mark()
            if self.phase == _WAIT_START:
                error = self._try_start(p, v, a)
                if error:
                    return self._fail(axis, error)
            if self.phase == _WAIT_START or self.phase == _WAIT_MARK:
                return p, v, a
        if self.phase == _SYNC:
            error = self._follow_plan()
            if error:
                return self._fail(axis, error)
            if self.phase == _SYNC:
                return self._on_plan()
        return self._locked(axis)

    def finished(self) -> bool:
        return False

    def rebase(self, delta: float) -> None:
        self.slave_sync += delta
        self.hold += delta
        if self.profile is not None:
            self.profile = self.profile.shifted(delta)
        if self.previous is not None:
            self.previous.rebase(delta)

    # ------------------------------------------------------------------ phases
    def _fail(self, axis: AxisRef, error: int) -> tuple[float, float, float]:
        axis.fault(error)
        return axis.sp_pos, axis.sp_vel, axis.sp_acc

    def _previous_motion(self, axis: AxisRef) -> tuple[float, float, float]:
        previous = self.previous
        if previous is None:
            return self.hold, 0.0, 0.0
        return previous.setpoint(axis, axis.t_cycle - previous.t0)

    def _targets(self, origin: float) -> None:
        """Sync and start points in the reader's coordinate; ``origin``: where the master
        coordinate's zero lies for this command (the mark with Zeroing 2) [u]."""
        reader = self.reader
        assert reader is not None
        sync = origin + self.master_sync
        period = self.master.config.modulo
        if period and self.zeroing != 2:
            # the next time the master passes the sync position (in its direction)
            d = self.direction or _sign(reader.velocity) or 1.0
            m = reader.position
            sync += period * math.floor((m - sync) / period)
            while d * (sync - m) <= 0.0:
                sync += d * period
        self.sync_at = sync
        self.start_at = sync - self.start_distance

    def _await_mark(self) -> None:
        """Zeroing 2: once the probe latched, set the master coordinate to 0 at the mark."""
        master, reader = self.master, self.reader
        assert reader is not None
        latched = master.probe.position
        if latched is None or master.probe.generation != self.generation:
            return
        period = master.config.modulo
        if period:
            latched += period * round((master.actual - latched) / period)
        shift = reader.shift
        mark = latched - shift - self.delay * reader.velocity
        master.rebase(-(mark + shift))
        self._targets(mark)
        self.phase = _WAIT_START

    def _try_start(self, p: float, v: float, a: float) -> int:
        """StartSync once the master passed the start point in its direction and a motion that
        never backs up reaches the sync in time; an error code when it never can."""
        reader = self.reader
        assert reader is not None
        m, vm = reader.position, reader.velocity
        d = self.direction
        if d == 0.0:
            d = _sign(self.sync_at - m)
            if d == 0.0:
                return ErrorID.ESyncUnreachable
            self.direction = d
        if self.start_distance != 0.0 and d * (m - self.start_at) < 0.0:
            return 0
        remaining = d * (self.sync_at - m)
        if remaining <= 0.0:
            return ErrorID.ESyncUnreachable
        speed = d * vm
        ds = d * _sign(self.ratio)
        if speed <= 0.0 or ds * v < 0.0:
            return 0  # the master stands or runs back, or the slave still moves back: wait
        try:
            self._plan(p, v, a, m, remaining, speed)
        except PlanningError:
            return ErrorID.ESyncUnreachable if v == 0.0 and a == 0.0 else 0
        except _TooLate:
            return ErrorID.ESyncUnreachable
        self.phase = _SYNC
        self.started = True
        self.previous = None
        return 0

    def _plan(self, p: float, v: float, a: float, m: float, remaining: float, speed: float) -> None:
        """Plan the synchronisation from the slave state (p, v, a), the master at ``m`` [u]
        moving with ``speed`` > 0 [u/s] toward the sync point ``remaining`` [u] ahead.

        Raises:
            PlanningError: no motion that never backs up.
            _TooLate: the motion needs more time than the master takes to the sync point, or
                ratio × master velocity exceeds Velocity.
        """
        limits = self.limits
        v_end = self.ratio * self.direction * speed
        if abs(v_end) > limits.velocity:
            raise _TooLate
        duration = remaining / speed
        profile = trajectory.sync_to(p, v, a, self.slave_sync, v_end, limits, duration)
        if profile.duration > duration * (1.0 + 1e-9) + 1e-9:
            raise _TooLate
        self.profile = profile
        self.m_a = m
        self.u_total = remaining
        self.k = profile.duration / remaining
        self.w = speed
        self.u_max = 0.0

    def _follow_plan(self) -> int:
        """Track the master's progress along the plan; LOCKED at the sync point."""
        reader = self.reader
        assert reader is not None
        d = self.direction
        u = d * (reader.position - self.m_a)
        if u < self.u_max - self.tolerance:
            return ErrorID.EMasterReversed
        if u >= self.u_total:
            self.phase = _LOCKED
            return 0
        self.u_max = max(u, self.u_max)
        speed = d * reader.velocity
        if speed > self.w * (1.0 + REPLAN):
            p, v, a = self._on_plan()
            done = self.u_max
            try:
                self._plan(p, v, a, self.m_a + d * done, self.u_total - done, speed)
            except (PlanningError, _TooLate):
                return ErrorID.ESyncUnreachable
        return 0

    def _on_plan(self) -> tuple[float, float, float]:
        """The slave set point on the plan at the master's furthest progress."""
        reader, profile = self.reader, self.profile
        assert reader is not None and profile is not None
        d, k = self.direction, self.k
        u = d * (reader.position - self.m_a)
        rate = k * max(0.0, d * reader.velocity) if u >= self.u_max else 0.0
        p, v, a = profile.at(self.u_max * k)
        return p, v * rate, a * rate * rate + v * k * d * reader.acceleration

    def _locked(self, axis: AxisRef) -> tuple[float, float, float]:
        reader = self.reader
        assert reader is not None
        ratio = self.ratio
        p = self.slave_sync + ratio * (reader.position - self.sync_at)
        if not self.signal:
            self.signal = True  # InSync
            self.profile = None
            axis.captured = axis.actual
            if self.zeroing == 1:
                self.master.rebase(-(self.sync_at + reader.shift))
        return p, ratio * reader.velocity, ratio * reader.acceleration


class _TooLate(Exception):
    """The synchronisation cannot be reached in time (→ ``ESyncUnreachable``)."""


# --------------------------------------------------------------------------- function blocks


class _GearFB(MotionFB):
    """Common in-outs and inputs of MC_GearIn and MC_GearInPos."""

    REFS: ClassVar[tuple[str, ...]] = ("Master", "Slave")
    OWNER: ClassVar[str] = "Slave"
    INPUTS: ClassVar[tuple[str, ...]] = (
        "RatioNumerator",
        "RatioDenominator",
        "Acceleration",
        "Deceleration",
        "Jerk",
    )
    Master: AxisRef | None = None
    Slave: AxisRef | None = None
    RatioNumerator: int = 1
    RatioDenominator: int = 1
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0

    def _ratio(self) -> float | None:
        """RatioNumerator / RatioDenominator, both INT (−32768 … 32767), the denominator not 0."""
        n, d = self.RatioNumerator, self.RatioDenominator
        if not (INT_MIN <= n <= INT_MAX and INT_MIN <= d <= INT_MAX) or d == 0:
            return None
        return n / d

    def _master(self) -> AxisRef | int:
        """The master, or an error code: EParam when it is the slave, EMasterError when it is in
        ErrorStop or its encoder failed."""
        master = self.Master
        assert master is not None
        if master is self.Slave:
            return ErrorID.EParam
        if master.state == AxisState.ErrorStop or not master.io.encoder_ok:
            return ErrorID.EMasterError
        return master

    def _flag(self, reached: bool, shown: bool) -> bool:
        """An output that is reset by the falling edge of Execute but shown for one scan when
        reached after it."""
        return reached and (self.Execute or not shown)


class MC_GearIn(_GearFB):
    """Gear the slave's velocity to the master's: ratio = RatioNumerator / RatioDenominator
    (MotionControlLib §4.1).

    The slave's velocity ramps (Acceleration, Deceleration [u/s²], Jerk [u/s³]; 0 = axis
    default) to ratio × master velocity and then locks to the master's position; the distance
    lost while ramping is not caught up. ``InGear`` the first time the ratio is reached. A new
    MC_GearIn changes the ratio on the fly; any Aborting motion command on the slave ends it.
    Buffered and blending commands cannot queue behind it (``EParam`` 5). No Ref needed.
    Errors at the edge (the slave is left alone): ``EParam`` for a denominator of 0, a ratio
    term outside INT, invalid ramps or Master = Slave; ``EMasterError`` 17 for a master in
    ErrorStop; the slave's readiness errors as for every motion block.
    """

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.InGear = False
        self._in_gear_shown = False

    def _command(self, mode: MC_BufferMode) -> Command | int:
        slave = self.axis
        error = slave.check_ready()
        if error:
            return error
        assert slave.constants is not None
        limits = ready_limits(
            slave, slave.constants.Vmax, self.Acceleration, self.Deceleration, self.Jerk
        )
        if isinstance(limits, int):
            return limits
        ratio = self._ratio()
        if ratio is None:
            return ErrorID.EParam
        master = self._master()
        if isinstance(master, int):
            return master
        return GearIn(mode, master, ratio, limits)

    def _command_started(self) -> None:
        self._in_gear_shown = False

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        cmd = self._cmd
        reached = self.Active and isinstance(cmd, GearIn) and cmd.signal
        self.InGear = self._flag(reached, self._in_gear_shown)
        self._in_gear_shown = self._in_gear_shown or self.InGear


class MC_GearInPos(_GearFB):
    """Synchronise the slave to the master at given positions: the flying shear / flying saw
    (MotionControlLib §4.2).

    The previous motion of the slave goes on until the master passes ``MasterSyncPosition −
    MasterStartDistance`` [u] in the direction given by the sign of MasterStartDistance (0: from
    where the master is, toward MasterSyncPosition) and a motion that never moves against the master
    brings the slave in time; then ``StartSync``. The slave reaches ratio × master velocity and
    ``SlaveSyncPosition`` [u] exactly when the master reaches MasterSyncPosition, following the
    master's actual progress (Velocity [u/s], Acceleration, Deceleration [u/s²], Jerk [u/s³] at the
    master speed of the plan; 0 = axis default). When the master is there: ``InSync`` (StartSync
    falls), GT_SInfo 24 captures the slave's position, and the slave runs locked, ``s =
    SlaveSyncPosition + ratio·(m − MasterSyncPosition)``, in any direction until another command
    takes over. A master that slows down or stops on the way is followed on the plan; one more than
    5 % faster gets a new plan.

    ``Zeroing``: 0 none; 1 the master coordinate is set so that MasterSyncPosition reads 0 at
    InSync (MasterSyncPosition is then the cut length of the next cut); 2 the block arms the
    master's touch probe and sets the master coordinate to 0 at the mark: latched position
    minus ``Delay`` [ms] × master velocity (the sensor's delay); MasterSyncPosition then counts
    from the mark. ``Kv`` [1/s]: bandwidth of the filter through which a master without closed
    position loop (a measuring wheel) is read (0 = 100 1/s).

    Needs Ref on the slave (``Ehome`` 9); SlaveSyncPosition beyond a SW limit gives ``Ecil`` 8.
    ``EParam`` for a ratio of 0 or a denominator of 0, non-finite positions, Zeroing not 0…2,
    negative Kv or Delay, Master = Slave. While running: ``ESyncUnreachable`` 15,
    ``EMasterReversed`` 16, ``EMasterError`` 17 (the slave stops, ErrorStop). A Stop, or any
    Aborting command, before or after InSync gives CommandAborted. Buffered commands start at
    InSync.
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "MasterSyncPosition",
        "SlaveSyncPosition",
        "MasterStartDistance",
        "Velocity",
        "Kv",
        "Zeroing",
        "Delay",
    )
    MasterSyncPosition: float = 0.0
    SlaveSyncPosition: float = 0.0
    MasterStartDistance: float = 0.0
    Velocity: float = 0.0
    Kv: float = 0.0
    Zeroing: int = 0
    Delay: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.StartSync = False
        self.InSync = False
        self._start_shown = False
        self._in_sync_shown = False

    def _command(self, mode: MC_BufferMode) -> Command | int:
        slave = self.axis
        limits = ready_limits(slave, self.Velocity, self.Acceleration, self.Deceleration, self.Jerk)
        if isinstance(limits, int):
            return limits
        ratio = self._ratio()
        master_sync, slave_sync = self.MasterSyncPosition, self.SlaveSyncPosition
        start_distance, kv, delay = self.MasterStartDistance, self.Kv, self.Delay
        if (
            not ratio
            or not (
                math.isfinite(master_sync)
                and math.isfinite(slave_sync)
                and math.isfinite(start_distance)
            )
            or not (non_negative(kv) and non_negative(delay))
            or self.Zeroing not in (0, 1, 2)
        ):
            return ErrorID.EParam
        master = self._master()
        if isinstance(master, int):
            return master
        if not slave.Ref:
            return ErrorID.Ehome
        error = slave.check_target(slave_sync)
        if error:
            return error
        return GearInPos(
            mode,
            master,
            ratio,
            master_sync,
            slave_sync,
            start_distance,
            limits,
            kv if kv > 0.0 else DEFAULT_KV,
            self.Zeroing,
            delay * 1e-3,
        )

    def _command_started(self) -> None:
        self._start_shown = self._in_sync_shown = False

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        cmd = self._cmd
        started = in_sync = False
        if self.Active and isinstance(cmd, GearInPos):
            started, in_sync = cmd.started and not cmd.signal, cmd.signal
        self.StartSync = self._flag(started, self._start_shown)
        self._start_shown = self._start_shown or self.StartSync
        self.InSync = self._flag(in_sync, self._in_sync_shown)
        self._in_sync_shown = self._in_sync_shown or self.InSync


class MC_GearOut(ExecuteFB):
    """Ungear the slave (PLCopen Part 1): it keeps the velocity it has, with its acceleration
    brought to 0 on the axis' maximum jerk, as a never-ending velocity motion (ContinuousMotion,
    like MC_MoveVelocity); stop it with MC_Halt or MC_Stop. ``Done`` at once.

    ``ENotGeared`` 18 when no MC_GearIn / MC_GearInPos runs on the slave; the slave's readiness
    errors as for every motion block.
    """

    REFS: ClassVar[tuple[str, ...]] = ("Slave",)
    OWNER: ClassVar[str] = "Slave"
    Slave: AxisRef | None = None

    def _begin(self) -> int:
        slave = self.axis
        error = slave.check_ready()
        if error:
            return error
        if not isinstance(slave.active, (GearIn, GearInPos)):
            return ErrorID.ENotGeared
        return release_slave(slave)


def release_slave(slave: AxisRef) -> int:
    """Let a coupled slave go on at the velocity it has, its acceleration brought to 0 on the
    axis' maximum jerk, as a never-ending velocity motion (MC_GearOut, MC_CamOut); an error code
    when it is refused."""
    ramp = slave.max_ramp()
    v, a = slave.sp_vel, slave.sp_acc
    velocity = v + a * abs(a) / (2.0 * ramp.jerk) if math.isfinite(ramp.jerk) else v
    limits = Limits(ramp.velocity, slave.config.max_acceleration, ramp.deceleration, ramp.jerk)
    cmd = MoveVelocity(MC_BufferMode.Aborting, limits, velocity)
    slave.submit(cmd)
    if cmd.status == Status.Error:
        return cmd.error_id
    return 0


__all__ = ["MC_GearIn", "MC_GearInPos", "MC_GearOut"]

"""The cam coupling: what a selected cam table is (:class:`CamSelection`, by ``CamTableID``) and
the command that drives a cammed slave every servo cycle (:class:`CamIn`, MC_CamIn's command),
with its period boundaries, its takeover by the next cam, its ramp-in and the phase shift
MC_Phasing gives it (:class:`PhaseJob`). The blocks and the behaviour they promise are in
:mod:`mcl.cam`.

Per servo cycle the cam reads the master (:class:`mcl.gearing.MasterReader`, plus the phase
shift), maps it into the table (``τ = τ_c + MasterScaling·(m − m_c)``), and sets the slave to
``base + SlaveScaling·CAM(τ)`` with velocity ``slope·v_m`` and acceleration
``curvature·v_m² + slope·a_m`` (the chain rule); the cam's peak slope and curvature at the
master's speed must stay within the slave's Vmax and maximum acceleration (else ``ECamLimit``).
"""

from __future__ import annotations

__all__ = [
    "SELECTED",
    "SLOW",
    "CamIn",
    "CamRegistry",
    "CamSelection",
    "MC_StartMode",
    "PhaseJob",
    "selection",
]

import math
from enum import IntEnum
from typing import Final

from mcl import trajectory
from mcl.axis import Axis as AxisRef
from mcl.cam_table import Cam, polynomial, quintic
from mcl.command import Command, Status
from mcl.enums import AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.gearing import DEFAULT_KV, MasterReader
from mcl.trajectory import Limits, PlanningError, Profile

SLOW: Final = 1e-9
"""A master slower than this [u/s] is taken as standing when a coupling converts the slave's
velocity into a slope."""

_WAIT_BOUNDARY: Final = 0
_WAIT_START: Final = 1
_COUPLED: Final = 2


class MC_StartMode(IntEnum):
    """How MC_CamIn couples the slave (PLCopen MC_START_MODE)."""

    mcAbsolute = 0
    mcRelative = 1
    mcRampIn = 2
    mcRampInPos = 3
    mcRampInNeg = 4


class CamSelection:
    """What a ``CamTableID`` stands for: a checked cam for a master and a slave."""

    def __init__(
        self,
        cam: Cam,
        master: AxisRef,
        slave: AxisRef,
        master_absolute: bool,
        slave_absolute: bool,
        table_id: int,
        name: str,
    ) -> None:
        self.cam = cam
        self.table_id = table_id
        """The CamTableID it was selected under."""
        self.name = name
        """The table's ``Name`` ("": none)."""
        self.master = master
        self.slave = slave
        self.master_absolute = master_absolute
        self.slave_absolute = slave_absolute


class CamRegistry:
    """The selected cam tables by CamTableID (one ID per MC_CamTableSelect instance)."""

    def __init__(self) -> None:
        self.tables: dict[int, CamSelection] = {}
        self.last = 0

    def new_id(self) -> int:
        """A CamTableID not given before."""
        self.last += 1
        return self.last


SELECTED: Final = CamRegistry()
"""The tables MC_CamTableSelect selected."""


def selection(table_id: int) -> CamSelection | None:
    """The cam table selected under ``table_id`` (None: no such ID)."""
    return SELECTED.tables.get(table_id)


class PhaseJob:
    """An MC_Phasing's shift of the master position the cam reads, in master units."""

    def __init__(self) -> None:
        self.status = Status.Active
        self.error_id = 0
        self.owner: CamIn | None = None
        """The cam whose master it shifts (a cam that takes over at a boundary adopts it)."""


class CamIn(Command):
    """MC_CamIn's command (``signal`` = InSync). See the module text."""

    state = AxisState.SynchronizedMotion

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        chosen: CamSelection,
        master_offset: float,
        slave_offset: float,
        master_scaling: float,
        slave_scaling: float,
        start_mode: int,
        start_distance: float,
        sync_position: float,
        limits: Limits,
    ) -> None:
        super().__init__(buffer_mode)
        self.chosen = chosen
        self.cam = chosen.cam
        self.master = chosen.master
        self.master_offset = master_offset
        self.slave_offset = slave_offset
        self.master_scaling = master_scaling
        self.slave_scaling = slave_scaling
        self.start_mode = start_mode
        self.start_distance = start_distance
        self.sync_position = sync_position
        self.limits = limits
        """The slave's Vmax and maximum acceleration the cam must stay within."""
        self.reader: MasterReader | None = None
        self.previous: Command | None = None
        """The slave's previous motion, continued until this cam takes over."""
        self.phase = _COUPLED
        self.m_c = 0.0
        """Master position (reader coordinate, phase shift included) of the coupling [u]."""
        self.tau_c = 0.0
        """Table master coordinate at the coupling."""
        self.base = 0.0
        """Slave position for a table value of 0 [u]."""
        self.ramp: list[float] | None = None
        """The blend's quintic in the table coordinate from ``tau_c`` (None: none)."""
        self.ramp_length = 0.0
        self.direction = 1.0
        self.cycle = 0
        self.ends = 0
        """How often the master passed a period boundary (the end of a non-periodic table)."""
        self.tau_start = 0.0
        """Where a ramp-in with MasterAbsolute starts (table coordinate)."""
        self.hold = 0.0
        """Where the slave waits for a ramp-in when nothing moved it before [u]."""
        self.shift = 0.0
        """The phase shift reached by the finished MC_Phasing commands [master u]."""
        self.shift_profile: Profile | None = None
        self.shift_t0 = 0.0
        self.shift_job: PhaseJob | None = None
        self.shift_target = 0.0
        """Where the running shift ends, beyond :attr:`shift` [master u]."""
        self.successor: CamIn | None = None
        """The cam that waits for this one's period boundary to take over."""

    # ------------------------------------------------------------------ Command interface
    def start(self, axis: AxisRef, p: float, v: float, a: float, v_end: float) -> None:
        master = self.master
        master.update_setpoint(master.t_cycle)
        previous = axis.active
        if isinstance(previous, CamIn) and previous.master is master:
            if previous.phase != _COUPLED:  # a newer cam replaces a waiting one
                waiting = previous
                previous = waiting.previous
                if waiting.phase == _WAIT_START:
                    p = waiting.hold if previous is None else p
            if isinstance(previous, CamIn) and previous.master is master:
                self.reader = previous.reader
                self.previous = previous
                previous.successor = self
                self.phase = _WAIT_BOUNDARY
                return
        reader = self.reader = MasterReader(master, DEFAULT_KV)
        m, vm, am = reader.position, reader.velocity, reader.acceleration
        self.previous = previous if previous is not None and previous is not self else None
        if self._ramp_in() and self.chosen.master_absolute and self.start_distance > 0.0:
            tau = self.master_scaling * m + self.master_offset
            self.direction = -1.0 if self.master_scaling * vm < 0.0 else 1.0
            start = self.sync_position - self.direction * self.start_distance
            cam = self.cam
            if cam.periodic and cam.period > 0.0:
                start += cam.period * math.ceil(self.direction * (tau - start) / cam.period)
            self.tau_start = start
            self.phase = _WAIT_START
            self.hold = p
            return
        slope = v / vm if abs(vm) > SLOW else 0.0
        curvature = (a - slope * am) / (vm * vm) if abs(vm) > SLOW else 0.0
        self._couple(axis, m, vm, p, slope, curvature, self.start_distance)

    def setpoint(self, axis: AxisRef, t: float) -> tuple[float, float, float]:
        reader = self.reader
        assert reader is not None
        reader.read(axis.t_cycle)
        error = reader.error()
        if error:
            return self._fail(axis, error)
        m, vm, am = self._master_seen(axis.t_cycle)
        if self.phase == _WAIT_BOUNDARY:
            previous = self.previous
            assert isinstance(previous, CamIn)
            cycle, ends = previous.cycle, previous.ends
            p, v, a = previous.setpoint(axis, axis.t_cycle - previous.t0)
            if axis.state == AxisState.ErrorStop:
                return p, v, a
            if previous.ends == ends:
                return p, v, a
            boundary = previous.boundary(cycle)
            s, slope, curvature = previous.shape(boundary)
            m_b = previous.master_at(boundary)
            self._adopt_shift(previous)
            self.previous = None
            m, vm, am = self._master_seen(axis.t_cycle)
            self._couple(axis, m_b, vm, s, slope, curvature, self.start_distance)
        elif self.phase == _WAIT_START:
            tau = self.master_scaling * m + self.master_offset
            previous = self.previous
            if previous is not None:
                p, v, a = previous.setpoint(axis, axis.t_cycle - previous.t0)
            else:
                p, v, a = self.hold, 0.0, 0.0
            if self.direction * (tau - self.tau_start) < 0.0:
                return p, v, a
            self.previous = None
            slope = v / vm if abs(vm) > SLOW else 0.0
            curvature = (a - slope * am) / (vm * vm) if abs(vm) > SLOW else 0.0
            length = self.direction * (self.tau_start + self.direction * self.start_distance - tau)
            self._couple(axis, m, vm, p, slope, curvature, max(length, 0.0))
        tau = self.tau_c + self.master_scaling * (m - self.m_c)
        cycle = self.cam.cycle(tau)
        if cycle != self.cycle:
            self.cycle = cycle
            self.ends += 1
        elif not self.cam.periodic and self.ends == 0 and tau >= self.cam.start + self.cam.period:
            self.ends = 1
        s, slope, curvature = self.shape(tau)
        speed = self.master_scaling * vm
        peak_v = abs(self.slave_scaling * self.cam.peak_slope * speed)
        peak_a = abs(self.slave_scaling * self.cam.peak_curvature) * speed * speed
        limits = self.limits
        if peak_v > limits.velocity or peak_a > limits.acceleration:
            return self._fail(axis, ErrorID.ECamLimit)
        if self.ramp is None:
            self.signal = True
        return (
            s,
            slope * speed,
            curvature * speed * speed + slope * self.master_scaling * am,
        )

    def finished(self) -> bool:
        return False

    def rebase(self, delta: float) -> None:
        self.base += delta
        if self.phase == _WAIT_START:
            self.hold += delta
        if self.previous is not None:
            self.previous.rebase(delta)

    # ------------------------------------------------------------------ the cam
    def shape(self, tau: float) -> tuple[float, float, float]:
        """Slave position [u], slope ds/dτ and curvature d²s/dτ² at table coordinate ``tau``,
        the blend included; the slope and curvature per table unit."""
        g, g1, g2 = self.cam.at(tau)
        k = self.slave_scaling
        s, slope, curvature = self.base + k * g, k * g1, k * g2
        ramp = self.ramp
        if ramp is not None:
            u = self.direction * (tau - self.tau_c)
            if u >= self.ramp_length:
                self.ramp = None
            else:
                e, e1, e2 = polynomial(ramp, max(u, 0.0))
                d = self.direction
                s, slope, curvature = s + e, slope + d * e1, curvature + e2
        return s, slope, curvature

    def boundary(self, cycle: float) -> float:
        """The table coordinate of the boundary passed since period ``cycle`` (or the end of a
        non-periodic table)."""
        cam = self.cam
        if not cam.periodic:
            return cam.start + cam.period
        return cam.start + cam.period * (cycle + 1 if self.cycle > cycle else cycle)

    def master_at(self, tau: float) -> float:
        """The master position (as the cam sees it) at table coordinate ``tau`` [u]."""
        return self.m_c + (tau - self.tau_c) / self.master_scaling

    def _couple(
        self,
        axis: AxisRef,
        m: float,
        vm: float,
        s: float,
        slope: float,
        curvature: float,
        length: float,
    ) -> None:
        """Take over at master position ``m`` from slave position ``s`` with ``slope`` and
        ``curvature`` per master unit; blend the difference over ``length`` table units."""
        chosen, cam = self.chosen, self.cam
        ms, ks = self.master_scaling, self.slave_scaling
        self.m_c = m
        tau = (
            ms * m + self.master_offset
            if chosen.master_absolute
            else cam.start + self.master_offset
        )
        self.tau_c = tau
        self.cycle = cam.cycle(tau)
        g, g1, g2 = cam.at(tau)
        relative = not chosen.slave_absolute or self.start_mode == MC_StartMode.mcRelative
        if relative:
            self.base = s - ks * g + self.slave_offset
        else:
            self.base = self.slave_offset
            period = axis.config.modulo
            if period:
                self.base += period * self._turns((s - ks * g - self.base) / period)
        self.direction = -1.0 if ms * vm < 0.0 else 1.0
        d = self.direction
        e = s - (self.base + ks * g)
        if not self._ramp_in():
            e = 0.0  # absolute, relative: the slave jumps to the table where it is elsewhere
        e1 = slope / ms - ks * g1
        e2 = curvature / (ms * ms) - ks * g2
        if length > 0.0 and (e != 0.0 or e1 != 0.0 or e2 != 0.0):
            self.ramp = list(quintic(length, -e, d * e1, e2, 0.0, 0.0))
            self.ramp[0] = e
            self.ramp_length = length
        else:
            self.ramp = None
        self.phase = _COUPLED

    def _turns(self, x: float) -> float:
        """Whole periods a modulo slave's cam is moved by to meet its position (ramp-in modes:
        toward the nearest, mcRampInPos: forward, mcRampInNeg: backward)."""
        if self.start_mode == MC_StartMode.mcRampInPos:
            return float(math.floor(x))
        if self.start_mode == MC_StartMode.mcRampInNeg:
            return float(math.ceil(x))
        return float(round(x))

    def _ramp_in(self) -> bool:
        return self.start_mode >= MC_StartMode.mcRampIn

    def _fail(self, axis: AxisRef, error: int) -> tuple[float, float, float]:
        axis.fault(error)
        return axis.sp_pos, axis.sp_vel, axis.sp_acc

    # ------------------------------------------------------------------ phase shift
    def _master_seen(self, t: float) -> tuple[float, float, float]:
        """Master position, velocity and acceleration as the cam reads them: the reader's,
        shifted by the phase."""
        reader = self.reader
        assert reader is not None
        m, vm, am = reader.position + self.shift, reader.velocity, reader.acceleration
        profile = self.shift_profile
        if profile is None:
            return m, vm, am
        p, v, a = profile.at(t - self.shift_t0)
        if t - self.shift_t0 >= profile.duration:
            self.shift += p
            self.shift_profile = None
            job = self.shift_job
            if job is not None:
                job.status = Status.Done
            return m + p, vm, am
        return m + p, vm + v, am + a

    def _adopt_shift(self, previous: CamIn) -> None:
        """Take over the phase shift of the cam this one replaces, a running MC_Phasing
        included."""
        self.shift, self.shift_profile = previous.shift, previous.shift_profile
        self.shift_t0, self.shift_target = previous.shift_t0, previous.shift_target
        self.shift_job, previous.shift_job = previous.shift_job, None
        if self.shift_job is not None:
            self.shift_job.owner = self
        previous.successor = None

    def waiting_for_boundary(self) -> bool:
        """The cam waits for the running cam's period boundary to take over from it."""
        return self.phase == _WAIT_BOUNDARY

    def coupled(self) -> bool:
        """The cam drives the slave (it is not waiting for a boundary or a ramp-in's start)."""
        return self.phase == _COUPLED

    def running(self) -> bool:
        """The cam drives the slave: active, or continued by a successor waiting for its
        boundary."""
        successor = self.successor
        return self.status == Status.Active or (successor is not None and successor.running())

    def phase_shift(self, t: float, distance: float, limits: Limits, job: PhaseJob) -> int:
        """MC_Phasing: shift the master position the cam reads by ``distance`` [master u] from
        the time ``t`` [s] along a profile within ``limits``; a running shift is taken over
        from where it is (its job Aborted). An error code when it cannot be planned."""
        p = v = a = 0.0
        target = distance
        profile = self.shift_profile
        if profile is not None:
            p, v, a = profile.at(t - self.shift_t0)
            target += self.shift_target
        try:
            planned = trajectory.move_to(p, v, a, target, limits)
        except PlanningError:
            return ErrorID.EParam
        old = self.shift_job
        if old is not None and old.status == Status.Active:
            old.status = Status.Aborted
        self.shift_profile = planned
        self.shift_t0 = t
        self.shift_job = job
        job.owner = self
        self.shift_target = target
        return 0

    def total_shift(self, t: float) -> float:
        """The phase shift now, finished and running shifts together [master u]."""
        profile = self.shift_profile
        if profile is None:
            return self.shift
        return self.shift + profile.at(t - self.shift_t0)[0]


# --------------------------------------------------------------------------- function blocks

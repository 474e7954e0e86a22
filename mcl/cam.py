"""Electronic cams (PLCopen Part 1 v2.0): MC_CamTableSelect, MC_CamIn, MC_CamOut, MC_Phasing.

MC_CamTableSelect checks a cam table (:mod:`mcl.cam_table`) for a master and a slave and gives
it a ``CamTableID``; MC_CamIn couples the slave to the master through it: the slave is in
SynchronizedMotion and follows, every servo cycle,

``τ = MasterScaling·m + MasterOffset`` (MasterAbsolute TRUE; FALSE: the table's first master
point at the master position where the coupling starts, ``τ = τ0 + MasterScaling·(m − m_c) +
MasterOffset``), ``s = SlaveScaling·CAM(τ) + SlaveOffset`` (SlaveAbsolute TRUE; FALSE, or
StartMode mcRelative: relative to the slave's position at the coupling).

The master is read as the gearing blocks read it (:class:`mcl.gearing.MasterReader`): by its set
point when its position loop is closed, else (an encoder-only measuring wheel) through the
tracking filter; a master in ErrorStop or with a failed encoder stops the slave
(``EMasterError`` 17). The slave's velocity and acceleration set points are the chain rule of the
table's slope and curvature with the master's velocity and acceleration.

A new MC_CamIn on a slave already cammed to the same master (a new table, new offsets or
scalings) waits for the running cam's period boundary (the end of the profile when it is not
periodic) and takes over exactly there: its master coordinate starts at the boundary (MasterAbsolute
FALSE) and its slave position continues from the running cam's (SlaveAbsolute FALSE), so the
slave does not jump; a difference of slope or curvature between the two tables at the boundary
(and, in the ramp-in modes, of position) is blended out over ``MasterStartDistance`` of table
travel by a quintic in the master position (position, velocity and acceleration stay continuous).

A cam table is ``mcl.MC_CAM_REF(Points=[mcl.MC_CamPoint(Master, Slave, Velocity, Acceleration,
Law), ...], NumberOfPoints=None)`` (an ST program passes a STRUCT with these fields): up to 10 000
points, ``Master`` strictly increasing, ``Velocity`` the slope ds/dm and ``Acceleration`` the
curvature d²s/dm² at the point (NaN: not given, 0 for the motion laws), ``Law`` (``mcl.CamLaw``,
below) the interpolation of the segment that starts at the point. MC_CamTableSelect refuses a
table with ``EParam`` and its reason in ``ErrorText``: fewer than 2 or more than 10 000 points, a
value that is not finite, the master not increasing, an unknown law, a modified law whose end
slopes differ or whose points carry an acceleration, a jump of the slope at a point next to a
segment that is not Linear, a jump of the curvature between two motion-law segments, and, for a
periodic table, the same across the period boundary; the slave position is continuous by
construction. ``Name`` (optional) is what the viewer's cam view and ``python -m scenes cam`` call
the table.

``mcl.rotary_knife(cut_length, circumference, blades, sync_angle, law)`` builds the cam of a
rotary cross cutter: master = web position over one cut length [mm], slave = drum angle over
360°/blades [°], the cut at the period boundary; over ``sync_angle`` [°] of drum rotation around
each cut the blade tip runs at the web's speed (slope 360°/circumference), between two sync zones
the drum speeds up (a cut shorter than circumference/blades) or slows down along the law. A cut
the drum cannot make (a sync zone longer than the piece, a transition that would turn the drum
backwards, invalid values) gives a table whose ``Problem`` says why; MC_CamTableSelect refuses it
with ``EParam`` and that text. What the drum's motor cannot do at the line speed is refused by
MC_CamIn (``ECamLimit``) before the blade reaches the web.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import Any, ClassVar, Final

from mcl import trajectory
from mcl.axis import Axis as AxisRef
from mcl.cam_table import Cam, compile_cam, polynomial, quintic
from mcl.command import Command, Status
from mcl.enums import AxisState, MC_BufferMode, MC_ExecutionMode
from mcl.errors import ErrorID
from mcl.fb import ExecuteFB, MotionFB, non_negative, positive
from mcl.gearing import DEFAULT_KV, MasterReader, release_slave
from mcl.profiles import TableRef
from mcl.trajectory import Limits, PlanningError, Profile

REFERENCE_TABLE: Final = (
    ("CamLaw", "value", "the segment from its point to the next"),
    (
        ("Linear", "0", "a straight line; the slope may jump at its ends"),
        (
            "CubicSpline",
            "1",
            "one cubic spline through consecutive spline segments, continuous in slope and "
            "curvature; at its ends the point's Velocity where given, else natural; a periodic "
            "table of spline segments only is one periodic spline",
        ),
        (
            "Polynomial5",
            "2",
            "the quintic with the Velocity and Acceleration of both points (VDI 2143; rest to "
            "rest 10z³ − 15z⁴ + 6z⁵, Cv 1.875, Ca 5.77)",
        ),
        (
            "ModifiedSine",
            "3",
            "VDI 2143 modified sine on the deviation from the end slope (the same at both "
            "points); Cv 1.76, Ca 5.53",
        ),
        (
            "ModifiedTrapezoid",
            "4",
            "VDI 2143 modified trapezoid, likewise; Cv 2.00, Ca 4.89",
        ),
    ),
)
"""The interpolations of a cam segment, for the reference."""

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


class _Registry:
    """The selected cam tables by CamTableID (one ID per MC_CamTableSelect instance)."""

    def __init__(self) -> None:
        self.tables: dict[int, CamSelection] = {}
        self.last = 0

    def new_id(self) -> int:
        self.last += 1
        return self.last


_SELECTED: Final = _Registry()


def selection(table_id: int) -> CamSelection | None:
    """The cam table selected under ``table_id`` (None: no such ID)."""
    return _SELECTED.tables.get(table_id)


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
class MC_CamTableSelect(ExecuteFB):
    """Select a cam table for a master and a slave (PLCopen Part 1): check it and give its
    ``CamTableID`` for MC_CamIn.

    ``CamTable``: an ``mcl.MC_CAM_REF`` (or a STRUCT with its fields, see the module
    text of the cam tables); ``Periodic`` TRUE repeats it (the slave advances the table's rise
    every period); ``MasterAbsolute`` FALSE starts the table at the master position where
    MC_CamIn couples, ``SlaveAbsolute`` FALSE adds the table to the slave's position there.
    ``ExecutionMode``: mcImmediately or mcQueued (both select at once: a running cam keeps the
    table it took at its edge). ``Done`` in the scan of the edge. A table that fails its check
    gives ``EParam`` and says why in ``ErrorText`` (empty otherwise). Each instance keeps one
    ``CamTableID``: selecting again replaces its table for the MC_CamIn edges that follow.
    """

    REFS: ClassVar[tuple[str, ...]] = ("Master", "Slave")
    OWNER: ClassVar[str] = "Slave"
    INPUTS: ClassVar[tuple[str, ...]] = (
        "CamTable",
        "Periodic",
        "MasterAbsolute",
        "SlaveAbsolute",
        "ExecutionMode",
    )
    Master: AxisRef | None = None
    Slave: AxisRef | None = None
    CamTable: TableRef = None
    Periodic: bool = True
    MasterAbsolute: bool = True
    SlaveAbsolute: bool = True
    ExecutionMode: int = MC_ExecutionMode.mcImmediately

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.CamTableID = 0
        self.ErrorText = ""
        self._id = 0

    def _command_started(self) -> None:
        self.ErrorText = ""

    def _begin(self) -> int:
        master, slave = self.Master, self.Slave
        assert master is not None and slave is not None
        if self.ExecutionMode not in (MC_ExecutionMode.mcImmediately, MC_ExecutionMode.mcQueued):
            self.ErrorText = f"ExecutionMode {self.ExecutionMode} is not mcImmediately or mcQueued"
            return ErrorID.EParam
        if master is slave:
            self.ErrorText = "Master and Slave are the same axis"
            return ErrorID.EParam
        cam = compile_cam(self.CamTable, self.Periodic)
        if isinstance(cam, str):
            self.ErrorText = cam
            return ErrorID.EParam
        if not self._id:
            self._id = _SELECTED.new_id()
        _SELECTED.tables[self._id] = CamSelection(
            cam,
            master,
            slave,
            self.MasterAbsolute,
            self.SlaveAbsolute,
            self._id,
            str(getattr(self.CamTable, "Name", "") or ""),
        )
        self.CamTableID = self._id
        return 0


class MC_CamIn(MotionFB):
    """Couple the slave to the master through a selected cam table (PLCopen Part 1).

    ``CamTableID`` from MC_CamTableSelect (for these Master and Slave). ``MasterOffset`` [table
    units], ``MasterScaling`` (not 0): the table is read at ``MasterScaling`` × master position
    + MasterOffset; ``SlaveOffset`` [u], ``SlaveScaling``: the slave is at SlaveScaling × table
    value + SlaveOffset (see the module text for the relative modes). ``StartMode``
    (``MC_StartMode``: 0 mcAbsolute, 1 mcRelative, 2 mcRampIn, 3 mcRampInPos, 4 mcRampInNeg):
    mcAbsolute and mcRelative couple at once (the slave jumps to the table
    where it is not on it); mcRampIn, mcRampInPos, mcRampInNeg blend the slave's position,
    velocity and acceleration into the cam over ``MasterStartDistance`` (> 0) of table travel
    (Pos/Neg: on a modulo slave the cam is met forward / backward); with MasterAbsolute the
    previous motion goes on until the table coordinate reaches ``MasterSyncPosition`` −
    MasterStartDistance and the slave is on the cam at ``MasterSyncPosition``.

    ``InSync`` once the slave is on the cam; ``EndOfProfile`` for one scan each time the master
    passes a period boundary (the end of a non-periodic table). A new MC_CamIn on the cammed
    slave takes over at the running cam's next period boundary without a jump (the running one
    reports CommandAborted at the edge, the new one is Active and follows the old table until
    then). Buffered commands start at InSync; an Aborting motion command ends the cam.

    Errors at the edge (the slave is left alone): ``EParam`` for an unknown CamTableID or one
    selected for other axes, a scaling of 0, non-finite values, an unknown StartMode, a ramp-in
    without MasterStartDistance; ``ECamLimit`` 23 when the table at the master's present speed
    needs more than the slave's Vmax or maximum acceleration (also while running: the slave
    stops in ErrorStop); ``EMasterError`` 17; the slave's readiness errors. No Ref needed.
    """

    REFS: ClassVar[tuple[str, ...]] = ("Master", "Slave")
    OWNER: ClassVar[str] = "Slave"
    INPUTS: ClassVar[tuple[str, ...]] = (
        "CamTableID",
        "MasterOffset",
        "SlaveOffset",
        "MasterScaling",
        "SlaveScaling",
        "StartMode",
        "MasterStartDistance",
        "MasterSyncPosition",
    )
    Master: AxisRef | None = None
    Slave: AxisRef | None = None
    CamTableID: int = 0
    MasterOffset: float = 0.0
    SlaveOffset: float = 0.0
    MasterScaling: float = 1.0
    SlaveScaling: float = 1.0
    StartMode: int = MC_StartMode.mcAbsolute
    MasterStartDistance: float = 0.0
    MasterSyncPosition: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.InSync = False
        self.EndOfProfile = False
        self._in_sync_shown = False
        self._ends = 0

    def _command(self, mode: MC_BufferMode) -> Command | int:
        slave = self.axis
        error = slave.check_ready()
        if error:
            return error
        chosen = selection(self.CamTableID)
        master = self.Master
        if chosen is None or chosen.master is not master or chosen.slave is not slave:
            return ErrorID.EParam
        values = (
            self.MasterOffset,
            self.SlaveOffset,
            self.MasterScaling,
            self.SlaveScaling,
            self.MasterSyncPosition,
        )
        distance = self.MasterStartDistance
        if (
            not all(math.isfinite(x) for x in values)
            or self.MasterScaling == 0.0
            or not non_negative(distance)
            or self.StartMode not in tuple(MC_StartMode)
            or (self.StartMode >= MC_StartMode.mcRampIn and distance == 0.0)
        ):
            return ErrorID.EParam
        assert master is not None
        if master.state == AxisState.ErrorStop or not master.io.encoder_ok:
            return ErrorID.EMasterError
        assert slave.constants is not None
        limits = slave.limits(slave.max_velocity(), 0.0, 0.0, 0.0)
        limits = Limits(limits.velocity, slave.config.max_acceleration, 0.0, 0.0)
        speed = abs(self.MasterScaling * master.VEL)
        if master.has_drive and master.loop_closed:
            speed = abs(self.MasterScaling * master.sp_vel)
        cam = chosen.cam
        if (
            abs(self.SlaveScaling * cam.peak_slope) * speed > limits.velocity
            or abs(self.SlaveScaling * cam.peak_curvature) * speed * speed > limits.acceleration
        ):
            return ErrorID.ECamLimit
        return CamIn(
            mode,
            chosen,
            self.MasterOffset,
            self.SlaveOffset,
            self.MasterScaling,
            self.SlaveScaling,
            self.StartMode,
            distance,
            self.MasterSyncPosition,
            limits,
        )

    def _command_started(self) -> None:
        self._in_sync_shown = False
        self._ends = 0

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        cmd = self._cmd
        in_sync = ended = False
        if self.Active and isinstance(cmd, CamIn):
            in_sync = cmd.signal
            ended = cmd.ends != self._ends
            self._ends = cmd.ends
        self.InSync = in_sync and (self.Execute or not self._in_sync_shown)
        self._in_sync_shown = self._in_sync_shown or self.InSync
        self.EndOfProfile = ended


class MC_CamOut(ExecuteFB):
    """Uncouple the slave from its cam (PLCopen Part 1): it keeps the velocity it has, with its
    acceleration brought to 0 on the axis' maximum jerk, as a never-ending velocity motion
    (ContinuousMotion); stop it with MC_Halt or MC_Stop. ``Done`` at once.

    ``ENotGeared`` 18 when no MC_CamIn runs on the slave; the slave's readiness errors as for
    every motion block.
    """

    REFS: ClassVar[tuple[str, ...]] = ("Slave",)
    OWNER: ClassVar[str] = "Slave"
    Slave: AxisRef | None = None

    def _begin(self) -> int:
        slave = self.axis
        error = slave.check_ready()
        if error:
            return error
        if not isinstance(slave.active, CamIn):
            return ErrorID.ENotGeared
        return release_slave(slave)


class MC_Phasing(ExecuteFB):
    """Shift the master position the slave's cam reads (PLCopen Part 1): the slave runs as if
    the master were ``PhaseShift`` [master u] further; the master itself is not moved.

    The shift follows a profile in time within ``Velocity`` [master u/s] (> 0), ``Acceleration``,
    ``Deceleration`` [master u/s²] and ``Jerk`` [master u/s³] (0: the master axis' defaults)
    and adds to the shifts before it; ``Done`` when it is reached, ``AbsolutePhaseShift`` [master
    u] the total shift of the running cam. A new MC_Phasing takes over a running shift from where
    it is (the first reports CommandAborted), and so does the end of the cam. While a new MC_CamIn
    waits for the period boundary, the shift applies to the cam that runs, and the new cam takes
    it over (a running shift goes on). ``BufferMode``:
    Aborting only (others ``EParam``).

    ``ENotGeared`` 18 when no MC_CamIn of this Master runs on the slave; ``EParam`` for
    invalid values; the slave's readiness errors.
    """

    REFS: ClassVar[tuple[str, ...]] = ("Master", "Slave")
    OWNER: ClassVar[str] = "Slave"
    INPUTS: ClassVar[tuple[str, ...]] = (
        "PhaseShift",
        "Velocity",
        "Acceleration",
        "Deceleration",
        "Jerk",
        "BufferMode",
    )
    Master: AxisRef | None = None
    Slave: AxisRef | None = None
    PhaseShift: float = 0.0
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Deceleration: float = 0.0
    Jerk: float = 0.0
    BufferMode: int = MC_BufferMode.Aborting

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Active = False
        self.CommandAborted = False
        self.AbsolutePhaseShift = 0.0
        self._job: PhaseJob | None = None

    def _begin(self) -> int:
        slave = self.axis
        error = slave.check_ready()
        if error:
            return error
        cmd = slave.active
        if isinstance(cmd, CamIn) and cmd.phase == _WAIT_BOUNDARY:
            cmd = cmd.previous  # shift the cam that drives the slave until the boundary
        if not isinstance(cmd, CamIn) or cmd.master is not self.Master:
            return ErrorID.ENotGeared
        v, a, d, j = self.Velocity, self.Acceleration, self.Deceleration, self.Jerk
        if (
            self.BufferMode != MC_BufferMode.Aborting
            or not math.isfinite(self.PhaseShift)
            or not positive(v)
            or not (non_negative(a) and non_negative(d) and non_negative(j))
        ):
            return ErrorID.EParam
        master = cmd.master
        config = master.config
        limits = Limits(
            v,
            a if a > 0.0 else config.acceleration,
            d if d > 0.0 else config.deceleration,
            j if j > 0.0 else (config.jerk if config.jerk > 0.0 else math.inf),
        )
        job = PhaseJob()
        error = cmd.phase_shift(slave.t_cycle, self.PhaseShift, limits, job)
        if error:
            return error
        self._job = job
        return 0

    def _poll(self) -> Status | None:
        job = self._job
        if job is None:
            return Status.Aborted
        owner = job.owner
        if job.status == Status.Active and (owner is None or not owner.running()):
            job.status = Status.Aborted
        return None if job.status == Status.Active else job.status

    def _withdraw(self) -> None:
        self._job = None

    def _show_more(self, visible: bool, final: Status | None) -> None:
        self.Active = self._running
        self.CommandAborted = visible and final == Status.Aborted
        job = self._job
        cam = job.owner if job is not None else None
        if cam is not None:
            self.AbsolutePhaseShift = cam.total_shift(cam.master.t_cycle)


__all__ = ["MC_CamIn", "MC_CamOut", "MC_CamTableSelect", "MC_Phasing", "MC_StartMode"]

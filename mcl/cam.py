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

What a display or a tool reads of cams (:mod:`mcl.cam_readout`; reading changes nothing):
``mcl.cam_profile(table, count=1001)`` samples a table over one period, ``table`` being the
``CamTableID`` MC_CamTableSelect gave (``ValueError`` for an ID no table was selected under) or a
checked table (``mcl.Cam``), at ``count`` (at least 2) evenly spaced master positions plus the
table's own points when it has no more: an ``mcl.CamProfile`` of ``master`` (the table coordinate
τ), ``slave`` CAM(τ), ``velocity`` ds/dτ and ``acceleration`` d²s/dτ² (numpy arrays in table
units, before MC_CamIn's scalings), ``points``, ``laws``, ``periodic``, ``period`` and ``rise``.
``mcl.running_cam(axis)`` is the cam that drives the axis now (None: it is not cammed; while a new
MC_CamIn waits for the period boundary, the running one), an ``mcl.RunningCam``: ``table``,
``table_id``, ``name``, ``master`` (the master axis), ``coupled``, ``in_sync`` (InSync), the
operating point ``table_master`` (τ reduced to one period, phase shift and scaling included; NaN
while not coupled), ``table_slave`` (CAM there), ``set_slave`` and ``actual_slave`` (the slave's
set point and actual position in table units: SlaveOffset, the relative start and SlaveScaling
undone, in the same period), ``cycle`` (the period number), the offsets, the scalings and
``phase_shift`` [master u].
"""

from __future__ import annotations

import math
from typing import Any, ClassVar, Final

from mcl.axis import Axis as AxisRef
from mcl.cam_coupling import SELECTED, CamIn, CamSelection, MC_StartMode, PhaseJob, selection
from mcl.cam_table import compile_cam
from mcl.command import Command, Status
from mcl.enums import AxisState, MC_BufferMode, MC_ExecutionMode
from mcl.errors import ErrorID
from mcl.fb import ExecuteFB, MotionFB, non_negative, positive
from mcl.gearing import release_slave
from mcl.profiles import TableRef
from mcl.trajectory import Limits

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
            self._id = SELECTED.new_id()
        SELECTED.tables[self._id] = CamSelection(
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
        if isinstance(cmd, CamIn) and cmd.waiting_for_boundary():
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

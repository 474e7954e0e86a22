"""The cam blocks on simulated axes: MC_CamTableSelect, MC_CamIn, MC_CamOut, MC_Phasing.

A driven master (M) runs at a constant speed; the slave (S, a carriage; K, a knife drum in
degrees, modulo 360°) follows a cam table. The slave's set point is compared with the table
exactly; where the physics matters (the drum's surface speed against the web, the carriage on an
encoder-only master) the simulated axes' own positions and velocities are measured.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import pytest

import mcl
from mcl.cam_table import Cam, CamLaw, MC_CamPoint, compile_cam
from mcl.simaxis import SimAxis, SimPlant
from tests.helpers import PLC, configure, make_machine, power_on, scan
from tests.mcl.test_gearing import Line, rippling

FAR = 1.0e9
"""Travel of the web and the drum: no stops, no limit switches [m]."""
SPEED = 100.0
"""Master speed [mm/s]."""
RAMP = 100.0
"""Web travel over which the knife drum ramps into its first cam [mm]."""

LIFT = mcl.MC_CAM_REF(
    Points=[
        MC_CamPoint(0.0, 0.0, 0.0, 0.0, CamLaw.ModifiedSine),
        MC_CamPoint(80.0, 40.0, 0.0, 0.0, CamLaw.Linear),
        MC_CamPoint(100.0, 40.0, 0.0, 0.0, CamLaw.Polynomial5),
        MC_CamPoint(200.0, 0.0, 0.0, 0.0),
    ]
)
"""A returning cam over 200 mm of master travel: a modified-sine lift of 40 mm, a dwell, a
quintic return."""
_CAM = compile_cam(LIFT, True)
assert not isinstance(_CAM, str), _CAM
CAM: Cam = _CAM


@dataclass(frozen=True)
class Sample:
    """One servo instant: master set point [mm], slave set point [u] and velocity [u/s]."""

    t: float
    master: float
    slave: float
    slave_velocity: float


class Recorder:
    """Samples of every servo instant of a machine's runtime."""

    def __init__(self, machine: mcl.Machine, master: mcl.Axis, slave: mcl.Axis) -> None:
        self.samples: list[Sample] = []
        self.master, self.slave = master, slave
        machine.runtime.observers.append(self._instant)

    def _instant(self, t: float) -> None:
        m, s = self.master, self.slave
        self.samples.append(Sample(t, m.sp_pos, s.sp_pos, s.sp_vel))


def master_running(machine: mcl.SimMachine) -> mcl.MC_MoveVelocity:
    move = mcl.MC_MoveVelocity(Axis=machine.axes["M"], Velocity=SPEED, Acceleration=2000.0)
    machine.run(lambda: move(Execute=True), until=lambda: move.InVelocity, timeout=1.0)
    return move


def select(master: mcl.Axis, slave: mcl.Axis, table: object, **inputs: bool) -> int:
    fb = mcl.MC_CamTableSelect(Master=master, Slave=slave, CamTable=table, **inputs)
    fb(Execute=True)
    assert fb.Done, fb.ErrorText
    return fb.CamTableID


def cam_in(
    master: mcl.Axis,
    slave: mcl.Axis,
    table: object = LIFT,
    *,
    absolute: bool = False,
    periodic: bool = True,
    **inputs: object,
) -> mcl.MC_CamIn:
    """MC_CamIn (with ``inputs``) of ``table`` selected for master and slave: ``periodic``, master
    and slave both ``absolute`` or both relative."""
    table_id = select(
        master, slave, table, Periodic=periodic, MasterAbsolute=absolute, SlaveAbsolute=absolute
    )
    return mcl.MC_CamIn(Master=master, Slave=slave, CamTableID=table_id, **inputs)


@pytest.fixture
def machine() -> mcl.SimMachine:
    machine = make_machine("MS")
    master_running(machine)
    return machine


def test_cam_in_follows_the_table_and_pulses_end_of_profile_once_per_period(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    cam = cam_in(M, S)
    start: list[tuple[float, float]] = []
    scans: list[tuple[float, bool, bool]] = []

    def program() -> None:
        if not start:
            start.append((M.sp_pos, S.sp_pos))
        cam(Execute=True)
        scans.append((M.sp_pos, cam.EndOfProfile, cam.InSync))

    recorder = Recorder(machine, M, S)
    machine.run(program, timeout=5.0)
    assert cam.Busy and cam.Active and cam.InSync and not cam.Error
    assert S.state == mcl.AxisState.SynchronizedMotion
    m_c, s_c = start[0]
    worst = max(
        abs(x.slave - (s_c + CAM.at(x.master - m_c)[0])) for x in recorder.samples if x.t > 0.0
    )
    assert worst < 1e-9
    pulses = [i for i, (_, end, _) in enumerate(scans) if end]
    crossings = [
        i
        for i in range(1, len(scans))
        if math.floor((scans[i][0] - m_c) / 200.0) != math.floor((scans[i - 1][0] - m_c) / 200.0)
    ]
    assert len(pulses) == 2 and pulses == crossings, "one scan per period boundary"
    # the carriage itself follows within its servo's following error
    assert abs(S.actual - S.sp_pos) < 0.05


def test_ramp_in_meets_the_absolute_cam_at_the_sync_position_without_a_jump(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    cam = cam_in(
        M,
        S,
        absolute=True,
        StartMode=mcl.MC_StartMode.mcRampIn,
        MasterSyncPosition=50.0,
        MasterStartDistance=40.0,
        SlaveOffset=20.0,
    )
    s0 = S.sp_pos
    tau0 = M.sp_pos % 200.0
    sync = (M.sp_pos - tau0) + 50.0 + (200.0 if tau0 > 10.0 else 0.0)
    recorder = Recorder(machine, M, S)
    in_sync_at: list[float] = []

    def program() -> None:
        cam(Execute=True)
        if cam.InSync and not in_sync_at:
            in_sync_at.append(M.sp_pos)

    machine.run(program, timeout=4.5)
    samples = recorder.samples
    before = [x for x in samples if x.master < sync - 40.0]
    assert before and all(x.slave == s0 for x in before), "the slave waits for the start"
    assert in_sync_at and sync <= in_sync_at[0] <= sync + SPEED * 2 * PLC
    after = [x for x in samples if x.master >= sync]
    assert after and max(abs(x.slave - 20.0 - CAM.at(x.master)[0]) for x in after) < 1e-9
    steps = [abs(b.slave_velocity - a.slave_velocity) for a, b in itertools.pairwise(samples)]
    assert max(steps) < 2.0, "no jump of the set-point velocity [mm/s per servo cycle]"


def test_cam_out_leaves_the_slave_at_constant_velocity(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    slope = mcl.MC_CAM_REF(Points=[(0.0, 0.0), (200.0, 100.0)])
    cam = cam_in(M, S, slope)
    out = mcl.MC_CamOut(Slave=S)
    machine.run(lambda: cam(Execute=True), timeout=0.5)
    assert cam.InSync and S.sp_vel == pytest.approx(0.5 * SPEED)
    machine.run(scan(lambda: cam(Execute=True), lambda: out(Execute=True)), timeout=PLC)
    assert out.Done
    machine.run(scan(lambda: cam(Execute=True), lambda: out(Execute=True)), timeout=PLC)
    assert cam.CommandAborted and not cam.Active
    assert S.state == mcl.AxisState.ContinuousMotion
    machine.run(scan(lambda: cam(Execute=True), lambda: out(Execute=True)), timeout=1.0)
    assert S.sp_vel == pytest.approx(0.5 * SPEED, abs=1e-9)
    assert machine.sims["S"].v * 1e3 == pytest.approx(0.5 * SPEED, rel=0.01)


def test_phasing_shifts_the_master_phase_by_exactly_phase_shift(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    cam = cam_in(M, S, absolute=True, StartMode=mcl.MC_StartMode.mcRampIn, MasterStartDistance=20.0)
    phasing = mcl.MC_Phasing(Master=M, Slave=S, Velocity=50.0, Acceleration=500.0)
    machine.run(lambda: cam(Execute=True), until=lambda: cam.InSync, timeout=3.0)
    machine.run(
        scan(lambda: cam(Execute=True), lambda: phasing(Execute=True, PhaseShift=30.0)),
        until=lambda: phasing.Done,
        timeout=2.0,
    )
    assert phasing.AbsolutePhaseShift == pytest.approx(30.0, abs=1e-9)
    assert S.sp_pos == pytest.approx(CAM.at(M.sp_pos + 30.0)[0], abs=1e-9)
    machine.run(scan(lambda: cam(Execute=True), lambda: phasing(Execute=False)), timeout=0.5)
    assert S.sp_pos == pytest.approx(CAM.at(M.sp_pos + 30.0)[0], abs=1e-9)
    assert M.sp_vel == SPEED, "the master itself is not moved"
    back = mcl.MC_Phasing(Master=M, Slave=S, PhaseShift=-12.5, Velocity=50.0)
    machine.run(
        scan(lambda: cam(Execute=True), lambda: back(Execute=True)),
        until=lambda: back.Done,
        timeout=2.0,
    )
    assert back.AbsolutePhaseShift == pytest.approx(17.5, abs=1e-9)
    assert S.sp_pos == pytest.approx(CAM.at(M.sp_pos + 17.5)[0], abs=1e-9)
    assert cam.Active and cam.InSync


class Knife(mcl.Machine):
    """A web (M, driven, mm) and a knife drum (K, degrees, modulo 360°) on simulated axes."""

    def __init__(self) -> None:
        far = mcl.SimAxisParams(stop_neg=-FAR, stop_pos=FAR, lim_neg=-FAR, lim_pos=FAR, start=0.0)
        self.sims = {"M": SimAxis(far), "K": SimAxis(far)}
        self.axes = {
            "M": mcl.Axis(self.sims["M"], mcl.AxisConfig(), "M"),
            "K": mcl.Axis(self.sims["K"], mcl.AxisConfig(modulo=360.0), "K"),
        }
        self.runtime = mcl.Runtime(SimPlant(list(self.sims.values())), self.axes.values(), PLC)
        for axis in self.axes.values():
            configure(axis)
            power_on(self, axis)


def test_a_new_knife_table_takes_over_at_the_period_boundary_without_a_jump():
    knife = Knife()
    M, K = knife.axes["M"], knife.axes["K"]
    web = mcl.MC_MoveVelocity(Axis=M, Velocity=300.0, Acceleration=3000.0)
    knife.run(lambda: web(Execute=True), until=lambda: web.InVelocity, timeout=1.0)
    short = mcl.rotary_knife(600.0, 1000.0, 1, 60.0)
    long = mcl.rotary_knife(1800.0, 1000.0, 1, 60.0)
    inputs = dict(Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    first = mcl.MC_CamIn(
        Master=M,
        Slave=K,
        CamTableID=select(M, K, short, **inputs),
        StartMode=mcl.MC_StartMode.mcRampIn,
        MasterStartDistance=RAMP,
    )
    second = mcl.MC_CamIn(Master=M, Slave=K, CamTableID=select(M, K, long, **inputs))
    start: list[tuple[float, float]] = []
    edge: list[float] = []
    t_edge = knife.time + 0.5
    recorder = Recorder(knife, M, K)
    drum: list[tuple[float, float, float]] = []
    knife.runtime.observers.append(
        lambda t: drum.append((M.sp_pos, knife.sims["M"].v * 1e3, knife.sims["K"].v * 1e3))
    )

    def program() -> None:
        if not start:
            start.append((M.sp_pos, K.sp_pos))
        first(Execute=True)
        if knife.time >= t_edge and not edge:
            edge.append(M.sp_pos)
        second(Execute=bool(edge))

    knife.run(program, timeout=6.0)
    assert first.CommandAborted and second.Active and second.InSync
    m_c, s_c = start[0]
    boundary = m_c + 600.0 * math.ceil((edge[0] - m_c) / 600.0)
    cam1, cam2 = compile_cam(short, True), compile_cam(long, True)
    assert not isinstance(cam1, str) and not isinstance(cam2, str)
    s_b = s_c + cam1.at(boundary - m_c)[0]
    samples = [x for x in recorder.samples if x.t > 0.0 and x.master > m_c + RAMP]
    for x in samples:
        expected = s_c + cam1.at(x.master - m_c)[0] if x.master < boundary else s_b
        if x.master >= boundary:
            expected += cam2.at(x.master - boundary)[0]
        assert x.slave == pytest.approx(expected, abs=1e-6)
    steps = [abs(b.slave_velocity - a.slave_velocity) for a, b in itertools.pairwise(samples)]
    assert max(steps) < 5.0, "no jump of the drum's set-point velocity [°/s per servo cycle]"
    # in the sync zones (±30° about each cut) the blade tip runs with the web
    k = 360.0 / 1000.0
    mismatch = []
    for m, v_web, v_drum in drum[len(drum) // 3 :]:
        tau = m - m_c if m < boundary else m - boundary
        length = 600.0 if m < boundary else 1800.0
        phase = tau % length
        if min(phase, length - phase) < 0.5 * 60.0 / k - 5.0 and v_web > 0.9 * 300.0:
            mismatch.append(abs(v_drum / k - v_web) / v_web)
    assert mismatch and max(mismatch) < 0.01


def test_cam_in_follows_an_encoder_only_master():
    line = Line(rippling(SPEED))
    M, S = line.axes["M"], line.axes["S"]
    cam = cam_in(M, S)
    line.run(lambda: None, timeout=0.3)  # the wheel runs
    start: list[tuple[float, float]] = []

    def program() -> None:
        if not start:
            start.append((line.records[-1].material, line.records[-1].slave))
        cam(Execute=True)

    line.run(program, timeout=4.0)
    assert cam.InSync and not cam.Error
    m_c, s_c = start[0]
    late = [r for r in line.records if r.t > line.time - 3.0]
    worst = max(abs(r.slave - s_c - CAM.at(r.material - m_c)[0]) for r in late)
    assert worst < 0.3, f"the carriage is {worst:.3f} mm off the cam of the material"


BAD: dict[str, tuple[dict[str, object], int]] = {
    "no table": ({"CamTableID": 0}, mcl.ErrorID.EParam),
    "unknown table": ({"CamTableID": 10**6}, mcl.ErrorID.EParam),
    "master scaling 0": ({"MasterScaling": 0.0}, mcl.ErrorID.EParam),
    "slave scaling NaN": ({"SlaveScaling": math.nan}, mcl.ErrorID.EParam),
    "offset infinite": ({"MasterOffset": math.inf}, mcl.ErrorID.EParam),
    "start mode": ({"StartMode": 7}, mcl.ErrorID.EParam),
    "ramp-in without distance": ({"StartMode": 2}, mcl.ErrorID.EParam),
    "negative distance": ({"StartMode": 2, "MasterStartDistance": -1.0}, mcl.ErrorID.EParam),
    "buffer mode": ({"BufferMode": 9}, mcl.ErrorID.EParam),
    "beyond the slave's limits": ({"SlaveScaling": 100.0}, mcl.ErrorID.ECamLimit),
}


@pytest.fixture(scope="module")
def moving() -> mcl.SimMachine:
    """M at SPEED, S running MC_MoveVelocity at 20 mm/s (the axis to be left alone)."""
    machine = make_machine("MS")
    master_running(machine)
    move = mcl.MC_MoveVelocity(Axis=machine.axes["S"], Velocity=20.0)
    machine.run(lambda: move(Execute=True), until=lambda: move.InVelocity, timeout=1.0)
    return machine


def _left_alone(machine: mcl.SimMachine, run: Callable[[], None]) -> None:
    S = machine.axes["S"]
    command = S.active
    machine.run(run, timeout=3 * PLC)
    assert S.active is command and S.state == mcl.AxisState.ContinuousMotion
    assert S.sp_vel == 20.0


@pytest.mark.parametrize("case", list(BAD))
def test_bad_cam_in_inputs_give_error_and_leave_the_axis_alone(moving, case):
    M, S = moving.axes["M"], moving.axes["S"]
    inputs, code = BAD[case]
    table_id = select(M, S, LIFT, Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    cam = mcl.MC_CamIn(Master=M, Slave=S, **{"CamTableID": table_id, **inputs})
    _left_alone(moving, lambda: cam(Execute=True))
    assert cam.Error and cam.ErrorID == code and not cam.Busy and not cam.Active


def test_a_table_of_other_axes_and_blocks_without_a_cam_are_refused(moving):
    M, S = moving.axes["M"], moving.axes["S"]
    reversed_id = select(S, M, LIFT)
    cam = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=reversed_id)
    out = mcl.MC_CamOut(Slave=S)
    phasing = mcl.MC_Phasing(Master=M, Slave=S, PhaseShift=1.0, Velocity=10.0)
    _left_alone(
        moving,
        scan(lambda: cam(Execute=True), lambda: out(Execute=True), lambda: phasing(Execute=True)),
    )
    assert cam.ErrorID == mcl.ErrorID.EParam
    assert out.ErrorID == mcl.ErrorID.ENotGeared
    assert phasing.ErrorID == mcl.ErrorID.ENotGeared


@pytest.mark.parametrize(
    "inputs",
    [{"Velocity": 0.0}, {"PhaseShift": math.nan}, {"Jerk": -1.0}, {"BufferMode": 1}],
    ids=["velocity 0", "shift NaN", "jerk negative", "buffered"],
)
def test_bad_phasing_inputs_give_eparam_and_leave_the_cam_alone(machine, inputs):
    M, S = machine.axes["M"], machine.axes["S"]
    cam = cam_in(M, S)
    phasing = mcl.MC_Phasing(Master=M, Slave=S, **{"PhaseShift": 5.0, "Velocity": 10.0, **inputs})
    machine.run(lambda: cam(Execute=True), timeout=0.1)
    command = S.active
    machine.run(scan(lambda: cam(Execute=True), lambda: phasing(Execute=True)), timeout=3 * PLC)
    assert phasing.Error and phasing.ErrorID == mcl.ErrorID.EParam
    assert S.active is command and cam.Active and cam.InSync


ST_PROGRAM = """
TYPE Point : STRUCT
  Master : LREAL; Slave : LREAL; Velocity : LREAL; Acceleration : LREAL; Law : DINT;
END_STRUCT END_TYPE
TYPE Table : STRUCT Points : ARRAY[0..3] OF Point; NumberOfPoints : DINT := 4; END_STRUCT END_TYPE
PROGRAM cams
VAR
  lift : Table;
  sel : MC_CamTableSelect;
  cam : MC_CamIn;
  id : DINT;
  synced : BOOL;
END_VAR
lift.Points[0].Law := ModifiedSine;
lift.Points[1].Master := 80.0; lift.Points[1].Slave := 40.0;
lift.Points[2].Master := 100.0; lift.Points[2].Slave := 40.0; lift.Points[2].Law := Polynomial5;
lift.Points[3].Master := 200.0;
sel(Master := M, Slave := S, CamTable := lift, Execute := TRUE, Periodic := TRUE,
    MasterAbsolute := TRUE, SlaveAbsolute := TRUE, CamTableID => id);
cam(Master := M, Slave := S, Execute := sel.Done, CamTableID := id, StartMode := mcRampIn,
    MasterStartDistance := 20.0, InSync => synced);
END_PROGRAM
"""


def test_an_st_program_cams_the_slave_as_python_does(machine):
    import plc.st

    M, S = machine.axes["M"], machine.axes["S"]
    program = plc.st.from_source(ST_PROGRAM, machine)
    machine.run(program, until=lambda: bool(program.synced), timeout=3.0)
    machine.run(program, timeout=0.2)
    assert program.synced and S.state == mcl.AxisState.SynchronizedMotion
    assert S.sp_pos == pytest.approx(CAM.at(M.sp_pos)[0], abs=1e-9)


def test_a_steeper_table_is_blended_in_at_the_boundary_over_master_start_distance(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    inputs = dict(Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    gentle = select(M, S, mcl.MC_CAM_REF(Points=[(0.0, 0.0), (100.0, 20.0)]), **inputs)
    steep = select(M, S, mcl.MC_CAM_REF(Points=[(0.0, 0.0), (100.0, 60.0)]), **inputs)
    first = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=gentle)
    second = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=steep, MasterStartDistance=50.0)
    start: list[tuple[float, float]] = []

    def program() -> None:
        if not start:
            start.append((M.sp_pos, S.sp_pos))
        first(Execute=True)  # couples at once: a velocity jump from 0 to 20 mm/s
        second(Execute=M.sp_pos > start[0][0] + 30.0)

    recorder = Recorder(machine, M, S)
    machine.run(program, timeout=3.0)
    m_c, s_c = start[0]
    boundary = m_c + 100.0
    samples = [x for x in recorder.samples if x.master > m_c + 1.0]
    assert first.CommandAborted and second.InSync
    for x in samples:
        if x.master < boundary - 1e-6:
            assert x.slave == pytest.approx(s_c + 0.2 * (x.master - m_c), abs=1e-9)
        elif x.master >= boundary + 50.0:
            assert x.slave == pytest.approx(s_c + 20.0 + 0.6 * (x.master - boundary), abs=1e-9)
    steps = [abs(b.slave_velocity - a.slave_velocity) for a, b in itertools.pairwise(samples)]
    assert max(steps) < 0.5, "20 → 60 mm/s over 50 mm of master travel, no jump"


def test_a_non_periodic_table_ends_once_and_the_slave_goes_on_along_its_end_slope(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    ramp = mcl.MC_CAM_REF(
        Points=[MC_CamPoint(0.0, 0.0, 0.0, 0.0, CamLaw.Polynomial5), MC_CamPoint(100.0, 30.0, 0.5)]
    )
    cam = cam_in(M, S, ramp, periodic=False)
    ends: list[float] = []
    start: list[float] = []

    def program() -> None:
        start.append(start[0] if start else M.sp_pos)
        cam(Execute=True)
        if cam.EndOfProfile:
            ends.append(M.sp_pos)

    machine.run(program, timeout=2.0)
    assert len(ends) == 1 and 0.0 <= ends[0] - start[0] - 100.0 <= SPEED * PLC
    assert cam.Active and S.state == mcl.AxisState.SynchronizedMotion
    assert S.sp_vel == pytest.approx(0.5 * SPEED)


def test_a_master_too_fast_for_the_cam_stops_the_slave_with_ecamlimit(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    cam = cam_in(M, S, SlaveScaling=1.5)
    faster = mcl.MC_MoveVelocity(Axis=M, Velocity=400.0, Acceleration=500.0)
    machine.run(lambda: cam(Execute=True), timeout=0.1)
    assert cam.InSync  # 1.5 × 0.88 × 100 mm/s = 132 mm/s at the steepest
    machine.run(
        scan(lambda: cam(Execute=True), lambda: faster(Execute=True)),
        until=lambda: cam.Error,
        timeout=2.0,
    )
    assert cam.ErrorID == S.AxErrorID == mcl.ErrorID.ECamLimit
    assert S.state == mcl.AxisState.ErrorStop
    assert 1.5 * CAM.peak_slope * M.sp_vel > 0.99 * S.constants.Vmax  # refused at 500 mm/s


def test_a_cam_waiting_for_the_boundary_is_replaced_and_a_phase_shift_carries_over(machine):
    M, S = machine.axes["M"], machine.axes["S"]
    inputs = dict(Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    table_id = select(M, S, LIFT, **inputs)
    first = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=table_id)
    second = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=table_id, SlaveScaling=1.2)
    third = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=table_id, SlaveScaling=0.8)
    phasing = mcl.MC_Phasing(Master=M, Slave=S, PhaseShift=10.0, Velocity=40.0)
    start: list[tuple[float, float]] = []
    seen: list[str] = []

    def program() -> None:
        if not start:
            start.append((M.sp_pos, S.sp_pos))
        travel = M.sp_pos - start[0][0]
        first(Execute=True)
        second(Execute=travel > 20.0)
        third(Execute=travel > 40.0)
        phasing(Execute=travel > 60.0)  # while the third waits: it shifts the first cam
        if second.CommandAborted and "second aborted" not in seen:
            seen.append("second aborted")
        if phasing.Done and "phased" not in seen:
            seen.append("phased" if not third.InSync else "phased late")

    recorder = Recorder(machine, M, S)
    machine.run(program, timeout=3.5)
    m_c, s_c = start[0]
    assert seen == ["second aborted", "phased"], seen
    assert first.CommandAborted and third.Active and third.InSync and not second.Active
    assert phasing.AbsolutePhaseShift == pytest.approx(10.0, abs=1e-9)
    # the third cam starts at the first one's boundary (master seen 200 mm on) and keeps the shift
    assert S.sp_pos == pytest.approx(s_c + 0.8 * CAM.at(M.sp_pos + 10.0 - m_c - 200.0)[0], abs=1e-9)
    samples = [x for x in recorder.samples if x.master > m_c + 1.0]
    steps = [abs(b.slave_velocity - a.slave_velocity) for a, b in itertools.pairwise(samples)]
    assert max(steps) < 2.0, "no jump of the set-point velocity [mm/s per servo cycle]"


def _lift_and_return(rise: float, length: float) -> mcl.MC_CAM_REF:
    """A 3-4-5 lift of ``rise`` [mm] over ``length`` [mm] of master and the same return: its
    steepest curvature is 10/√3 · rise/length² (VDI 2143), inside each segment."""
    P5 = CamLaw.Polynomial5
    return mcl.MC_CAM_REF(
        Points=[(0.0, 0.0, 0.0, 0.0, P5), (length, rise, 0.0, 0.0, P5), (2.0 * length, 0.0)]
    )


@pytest.mark.parametrize("share", [1.005, 0.995], ids=["0.5 % beyond", "0.5 % within"])
def test_a_table_beyond_only_the_slaves_acceleration_is_refused_and_the_move_goes_on(share):
    """At 100 mm/s of master a lift needing ``share`` × the slave's maximum acceleration (its
    speed well within Vmax): beyond it, MC_CamIn gives ECamLimit at the edge and the slave's
    running MC_MoveVelocity goes on untouched; within it, the slave is cammed."""
    machine = make_machine("MS")
    master_running(machine)
    M, S = machine.axes["M"], machine.axes["S"]
    move = mcl.MC_MoveVelocity(Axis=S, Velocity=20.0)
    machine.run(lambda: move(Execute=True), until=lambda: move.InVelocity, timeout=1.0)
    length = 2.0
    rise = share * S.config.max_acceleration / (10.0 / math.sqrt(3.0) / length**2 * SPEED**2)
    lift = _lift_and_return(rise, length)
    assert S.constants is not None
    assert 1.875 * rise / length * SPEED < 0.5 * S.constants.Vmax, "the speed is not the limit"
    cam = cam_in(M, S, lift)
    if share > 1.0:
        _left_alone(machine, lambda: cam(Execute=True))
        assert cam.Error and cam.ErrorID == mcl.ErrorID.ECamLimit and not cam.Active
    else:
        machine.run(lambda: cam(Execute=True), timeout=0.2)
        assert cam.InSync and not cam.Error and S.state == mcl.AxisState.SynchronizedMotion


def test_the_slaves_acceleration_set_point_adds_slope_times_the_masters_acceleration(machine):
    """While the master speeds up from 100 to 400 mm/s at 500 mm/s², the slave's set point
    acceleration is the chain rule at every servo instant: curvature · (MasterScaling·v)² +
    slope · MasterScaling · a (table coordinate τ = MasterScaling · master travel)."""
    M, S = machine.axes["M"], machine.axes["S"]
    table_id = select(M, S, LIFT, Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    cam = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=table_id, MasterScaling=0.5)
    faster = mcl.MC_MoveVelocity(Axis=M, Velocity=400.0, Acceleration=500.0)
    start: list[float] = []
    samples: list[tuple[float, float, float, float]] = []

    def record(t: float) -> None:
        if start:
            samples.append((M.sp_pos, M.sp_vel, M.sp_acc, S.sp_acc))

    def program() -> None:
        if not start:
            start.append(M.sp_pos)
        cam(Execute=True)
        faster(Execute=True)

    machine.runtime.observers.append(record)
    machine.run(program, until=lambda: faster.InVelocity, timeout=1.0)
    ramp = [x for x in samples[1:] if x[2] > 400.0]
    assert len(ramp) > 100 and cam.InSync and not cam.Error
    for m, v, a, slave_acceleration in ramp:
        _, slope, curvature = CAM.at(0.5 * (m - start[0]))
        expected = curvature * (0.5 * v) ** 2 + slope * 0.5 * a
        assert slave_acceleration == pytest.approx(expected, abs=1e-6)
    assert max(abs(CAM.at(0.5 * (m - start[0]))[1] * 0.5 * a) for m, _, a, _ in ramp) > 100.0


def test_slave_offset_shifts_a_relative_slave(machine):
    """SlaveAbsolute FALSE: the slave follows the table from where it stood plus SlaveOffset
    (ramped in over MasterStartDistance), s = s_c + SlaveOffset + CAM(τ)."""
    M, S = machine.axes["M"], machine.axes["S"]
    table_id = select(M, S, LIFT, Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    cam = mcl.MC_CamIn(
        Master=M,
        Slave=S,
        CamTableID=table_id,
        SlaveOffset=5.0,
        StartMode=mcl.MC_StartMode.mcRampIn,
        MasterStartDistance=20.0,
    )
    start: list[tuple[float, float]] = []

    def program() -> None:
        if not start:
            start.append((M.sp_pos, S.sp_pos))
        cam(Execute=True)

    machine.run(program, timeout=0.5)
    m_c, s_c = start[0]
    assert M.sp_pos - m_c > 40.0 and cam.InSync
    assert S.sp_pos == pytest.approx(s_c + 5.0 + CAM.at(M.sp_pos - m_c)[0], abs=1e-9)


def test_in_sync_falls_with_execute_while_the_cam_stays_active(machine):
    """InSync follows Execute: once shown it falls when Execute falls, the cam going on
    (Active, the slave in SynchronizedMotion); a cam whose Execute fell before it was in sync
    (the next one, waiting for the period boundary, then ramping in) shows InSync for one
    scan."""
    M, S = machine.axes["M"], machine.axes["S"]
    inputs = dict(Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    table_id = select(M, S, LIFT, **inputs)
    cam = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=table_id)
    machine.run(lambda: cam(Execute=True), until=lambda: cam.InSync, timeout=0.1)
    seen: list[tuple[bool, bool]] = []
    machine.run(
        scan(lambda: cam(Execute=False), lambda: seen.append((cam.Active, cam.InSync))),
        timeout=5 * PLC,
    )
    assert seen and all(active and not in_sync for active, in_sync in seen), seen
    assert S.state == mcl.AxisState.SynchronizedMotion
    ramp = mcl.MC_CamIn(
        Master=M,
        Slave=S,
        CamTableID=table_id,
        StartMode=mcl.MC_StartMode.mcRampIn,
        MasterStartDistance=20.0,
    )
    machine.run(lambda: ramp(Execute=True), timeout=PLC)
    assert ramp.Active and not ramp.InSync
    shown: list[bool] = []
    machine.run(scan(lambda: ramp(Execute=False), lambda: shown.append(ramp.InSync)), timeout=3.0)
    assert shown.count(True) == 1 and ramp.Active, shown

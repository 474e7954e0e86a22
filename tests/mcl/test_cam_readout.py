"""Reading cams out (mcl.cam_readout): a selected table's profile over one period, and where a
cammed slave is on its table, checked against the table and the axes' own set points."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mcl
from tests.mcl.test_cam import CAM, LIFT, machine, select

__all__ = ["machine"]  # the fixture of the cam blocks' tests: a master running at 100 mm/s


def test_the_profile_of_a_selected_table_is_the_table_over_one_period(
    machine: mcl.SimMachine,
) -> None:
    table_id = select(machine.axes["M"], machine.axes["S"], LIFT, Periodic=True)
    profile = mcl.cam_profile(table_id, count=101)
    # the grid and the table's own points, in order, over exactly one period
    assert profile.master.tolist() == np.linspace(0.0, 200.0, 101).tolist()
    assert {0.0, 80.0, 100.0, 200.0} <= set(profile.master.tolist())
    for m, s, v, a in zip(
        profile.master, profile.slave, profile.velocity, profile.acceleration, strict=True
    ):
        assert (s, v, a) == pytest.approx(CAM.at(float(m)), abs=1e-12), m
    assert profile.slave.max() == pytest.approx(40.0) and profile.slave[-1] == pytest.approx(0.0)
    assert profile.points == (0.0, 80.0, 100.0, 200.0)
    assert profile.laws == ("ModifiedSine", "Linear", "Polynomial5")
    assert (profile.periodic, profile.period, profile.rise) == (True, 200.0, 0.0)
    same = mcl.cam_profile(CAM, count=101)
    for name in ("master", "slave", "velocity", "acceleration"):
        assert np.array_equal(getattr(profile, name), getattr(same, name)), name
    # a grid coarser than the table: its points are among the samples all the same
    coarse = mcl.cam_profile(CAM, count=7)
    assert coarse.master.tolist() == sorted({*np.linspace(0.0, 200.0, 7).tolist(), 80.0, 100.0})


def test_a_profile_of_no_table_or_of_too_few_points_is_refused() -> None:
    with pytest.raises(ValueError, match="no cam table was selected under CamTableID 999999"):
        mcl.cam_profile(999999)
    with pytest.raises(ValueError, match="at least 2 points, got 1"):
        mcl.cam_profile(CAM, count=1)
    ends = mcl.cam_profile(CAM, count=2)  # fewer samples than points: the grid alone
    assert ends.master.tolist() == [0.0, 200.0] and ends.slave.tolist() == [0.0, 0.0]


def test_the_running_cam_tells_the_table_and_the_operating_point_on_it(
    machine: mcl.SimMachine,
) -> None:
    M, S = machine.axes["M"], machine.axes["S"]
    assert mcl.running_cam(S) is None, "not cammed"
    table_id = select(M, S, LIFT, Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    cam_in = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=table_id, SlaveScaling=0.5)
    cam_in.MasterOffset = 30.0
    start: list[tuple[float, float]] = []

    def program() -> None:
        if not start:
            start.append((M.sp_pos, S.sp_pos))
        cam_in(Execute=True)

    machine.run(program, until=lambda: cam_in.InSync, timeout=1.0)
    assert mcl.running_cam(M) is None, "the master is not cammed"
    m_c, s_c = start[0]
    base = s_c - 0.5 * CAM.at(30.0)[0]  # relative: the slave goes on from where it was
    seen = []
    for _ in range(30):  # 3 s at 100 mm/s: the master passes a period boundary
        machine.run(program, timeout=0.1)
        cam = mcl.running_cam(S)
        assert cam is not None
        seen.append(cam)
        tau = 30.0 + M.sp_pos - m_c  # relative master: the table from MasterOffset at the edge
        assert cam.cycle == math.floor(tau / 200.0)
        assert cam.table_master == pytest.approx(tau % 200.0, abs=1e-9)
        assert cam.table_slave == pytest.approx(CAM.at(tau % 200.0)[0], abs=1e-9)
        assert cam.set_slave == pytest.approx((S.sp_pos - base) / 0.5, abs=1e-9)
        assert cam.set_slave == pytest.approx(cam.table_slave, abs=1e-9)
        assert cam.actual_slave == pytest.approx((S.actual - base) / 0.5, abs=1e-9)
        assert abs(cam.actual_slave - cam.set_slave) < 0.1  # the servo's following error
    assert {c.cycle for c in seen} == {0, 1}
    cam = seen[-1]
    assert mcl.cam_profile(cam.table).laws == ("ModifiedSine", "Linear", "Polynomial5")
    assert (cam.table_id, cam.name, cam.master, cam.coupled, cam.in_sync) == (
        table_id,
        "",
        M,
        True,
        True,
    )
    assert (cam.master_offset, cam.slave_offset) == (30.0, 0.0)
    assert (cam.master_scaling, cam.slave_scaling, cam.phase_shift) == (1.0, 0.5, 0.0)
    out = mcl.MC_CamOut(Slave=S)
    machine.run(lambda: out(Execute=True), until=lambda: out.Done, timeout=0.1)
    assert mcl.running_cam(S) is None, "uncoupled"


def test_while_a_new_cam_waits_for_the_boundary_the_running_one_is_read_out(
    machine: mcl.SimMachine,
) -> None:
    M, S = machine.axes["M"], machine.axes["S"]
    first = select(M, S, LIFT, Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    lift = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=first)
    machine.run(lambda: lift(Execute=True), until=lambda: lift.InSync, timeout=1.0)
    named = mcl.MC_CAM_REF(Points=LIFT.Points, Name="the same, named")
    second = select(M, S, named, Periodic=True, MasterAbsolute=False, SlaveAbsolute=False)
    after = mcl.MC_CamIn(Master=M, Slave=S, CamTableID=second, SlaveOffset=1.0)

    def program() -> None:
        lift(Execute=True)
        after(Execute=True)

    machine.run(program, timeout=0.1)
    assert after.Busy and not after.InSync, "it waits for the period boundary"
    cam = mcl.running_cam(S)
    assert cam is not None
    assert (cam.table_id, cam.name, cam.slave_offset, cam.in_sync) == (first, "", 0.0, True)
    machine.run(program, until=lambda: after.InSync, timeout=3.0)
    cam = mcl.running_cam(S)
    assert cam is not None
    assert (cam.table_id, cam.name, cam.slave_offset) == (second, "the same, named", 1.0)

"""MC_TrackRotaryTable (mcl.tracking) and the turning product frame (mcl.coordinate_system): the
PCS of a delta robot's group turns with a rotary table axis (deg) about the table's centre from
the latched part position; a move in PCS lands on the turning part and the group keeps following
it; the frame's feed-forward is the derivative of its positions; bad input and a part out of
reach or too fast give their ErrorID and leave the group alone. Scan by scan on simulated axes
(three arms in deg, the table T in deg)."""

from __future__ import annotations

import math

import pytest

import mcl
from mcl import ErrorID, MC_BufferMode
from mcl.coordinate_system import ProductFrame
from mcl.enums import MC_COORD_SYSTEM
from tests.helpers import in_velocity, make_machine, scan
from tests.mcl.test_group import build_group
from tests.mcl.test_group_kinematics import ARMS, DELTA, MOVE

TABLE = "T"
CENTRE = [-450.0, 0.0, -760.0]
"""The table frame in the MCS [mm]: its centre; the part lies 150 mm from it, at x = −300."""
PART = [150.0, 0.0, 0.0]


def table_machine(speed: float = 30.0) -> tuple[mcl.SimMachine, mcl.AxesGroup, mcl.Axis]:
    """The arms grouped with the delta kinematics and the table turning at ``speed`` [°/s]."""
    machine = make_machine(ARMS + TABLE)
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    assert kin.Done
    table = machine.axes[TABLE]
    if speed:
        in_velocity(machine, table, speed)
    return machine, group, table


def tool(group: mcl.AxesGroup) -> list[float]:
    """The tool point of the arms' set points [mm, MCS]."""
    return DELTA.forward([axis.sp_pos for axis in group.axes])


def args(table: mcl.Axis, **inputs: object) -> dict[str, object]:
    """MC_TrackRotaryTable's inputs for the part at :data:`PART`, latched now."""
    return {
        "RotaryTable": table,
        "RotaryTableOrigin": CENTRE,
        "InitialObjectPosition": PART,
        "LatchedPosition": table.sp_pos,
    } | inputs


def angle_about_centre(point: list[float]) -> float:
    """The angle of ``point`` about the table's centre [deg]."""
    return math.degrees(math.atan2(point[1] - CENTRE[1], point[0] - CENTRE[0]))


def test_a_move_in_the_turning_pcs_lands_on_the_part_and_turns_with_it() -> None:
    machine, group, table = table_machine(30.0)
    fb = mcl.MC_TrackRotaryTable()
    inputs = args(table)
    machine.run(
        scan(lambda: fb(AxesGroup=group, Execute=True, **inputs)),
        until=lambda: fb.Done or fb.Error,
        timeout=2.0,
    )
    assert fb.Done and not fb.Error and not fb.Busy, fb.ErrorID
    frame = group.kin.frame
    assert frame is not None and frame.rotary and frame.master is table
    move = mcl.MC_MoveLinearAbsolute()
    pcs = dict(CoordSystem=MC_COORD_SYSTEM.PCS, **MOVE)
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, 0.0], **pcs)),
        until=lambda: move.Done or move.Error,
        timeout=3.0,
    )
    assert move.Done, move.ErrorID
    travelled = table.sp_pos - inputs["LatchedPosition"]  # type: ignore[operator]
    on_part = tool(group)
    assert math.dist(on_part, frame.point_to_mcs([0.0, 0.0, 0.0])) < 1e-6
    assert math.hypot(on_part[0] - CENTRE[0], on_part[1] - CENTRE[1]) == pytest.approx(150.0)
    assert angle_about_centre(on_part) == pytest.approx(travelled, abs=1e-6)
    machine.run(lambda: None, timeout=0.5)  # 15° on: the tool point turned with the part
    later = tool(group)
    assert angle_about_centre(later) - angle_about_centre(on_part) == pytest.approx(15.0, abs=0.1)
    assert math.hypot(later[0] - CENTRE[0], later[1] - CENTRE[1]) == pytest.approx(150.0)
    assert group.holding and group.state == mcl.GroupState.GroupMoving


@pytest.mark.parametrize("rotary", [False, True])
def test_the_frames_feed_forward_is_the_derivative_of_its_positions(rotary: bool) -> None:
    """A master that speeds up (mid-ramp of MC_MoveVelocity) carries a PCS state that moves
    too: the MCS velocity and acceleration equal the central differences of the MCS points of
    the same motion, and from_mcs inverts to_mcs."""
    machine = make_machine(TABLE)
    master = machine.axes[TABLE]
    ramp = mcl.MC_MoveVelocity()
    machine.run(lambda: ramp(Axis=master, Execute=True, Velocity=200.0), timeout=0.05)
    assert abs(master.sp_acc) > 100.0 and not ramp.InVelocity
    frame = ProductFrame([10.0, -20.0, -700.0], 30.0, [120.0, 40.0, 5.0], master, 1.0, rotary)
    p0, v0, a0 = [5.0, -3.0, 2.0], [40.0, 10.0, -5.0], [300.0, -200.0, 100.0]
    t0, h = master.t_sp + 1.0e-4, 1.0e-4

    def at(dt: float) -> list[float]:
        p = [p + v * dt + 0.5 * a * dt * dt for p, v, a in zip(p0, v0, a0, strict=True)]
        return frame.point_to_mcs(p, t0 + dt)

    point, velocity, acceleration = frame.to_mcs(p0, v0, a0, t0)
    ahead, back = at(h), at(-h)
    for k in range(3):
        assert velocity[k] == pytest.approx((ahead[k] - back[k]) / (2 * h), abs=1e-4)
        second = (ahead[k] - 2 * point[k] + back[k]) / (h * h)
        assert acceleration[k] == pytest.approx(second, abs=0.5)
    p, v, a = frame.from_mcs(point, velocity, acceleration, t0)
    for got, want in ((p, p0), (v, v0), (a, a0)):
        assert got == pytest.approx(want, abs=1e-9)


def test_the_turning_pcs_origin_is_the_part_turned_by_the_tables_travel() -> None:
    machine = make_machine(TABLE)
    table = machine.axes[TABLE]
    frame = ProductFrame(CENTRE, 90.0, PART, table, table.sp_pos - 30.0, rotary=True)
    # the table frame turned 90° in the MCS, the table 30° on since the latch: 120° in all
    point = frame.point_to_mcs([0.0, 0.0, 10.0])
    expected = [CENTRE[0] + 150.0 * math.cos(math.radians(120.0)), 150.0 * 0.8660254037844386]
    assert point == pytest.approx([expected[0], expected[1], CENTRE[2] + 10.0], abs=1e-9)
    point, velocity = frame.ahead(60.0)  # 60° further: 180°
    assert point == pytest.approx([CENTRE[0] - 150.0, 0.0, CENTRE[2]], abs=1e-9)
    assert velocity == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)  # the table stands


def _bad(group: mcl.AxesGroup, table: mcl.Axis) -> list[tuple[dict[str, object], int]]:
    return [
        ({"RotaryTable": None}, ErrorID.EParam),
        ({"RotaryTable": group.axes[0]}, ErrorID.EParam),
        ({"RotaryTableOrigin": [0.0, 0.0]}, ErrorID.EParam),
        ({"RotaryTableOrigin": [0.0, math.inf, -760.0, 0.0]}, ErrorID.EParam),
        ({"InitialObjectPosition": [1.0, 2.0]}, ErrorID.EParam),
        ({"LatchedPosition": math.nan}, ErrorID.EParam),
        ({"Horizon": -0.5}, ErrorID.EParam),
        ({"Jerk": -1.0}, ErrorID.EParam),
        ({"BufferMode": MC_BufferMode.BlendingLow}, ErrorID.EParam),
        ({"InitialObjectPosition": [-300.0, 0.0, 0.0]}, ErrorID.EWorkspace),
        ({"Horizon": 7.0}, ErrorID.EWorkspace),  # 210° on, the part is out of reach
    ]


@pytest.mark.parametrize("case", range(11))
def test_bad_input_or_a_part_out_of_reach_is_refused_and_the_group_left_alone(case: int) -> None:
    _, group, table = table_machine(30.0)
    inputs, error = _bad(group, table)[case]
    fb = mcl.MC_TrackRotaryTable()
    fb(AxesGroup=group, Execute=True, **args(table, **inputs))
    assert fb.Error and fb.ErrorID == error and not fb.Busy and not fb.Done
    assert group.kin.frame is None and not group.has_path
    assert group.state == mcl.GroupState.GroupStandby
    fb(Execute=False)
    assert not fb.Error and fb.ErrorID == 0


def test_a_horizon_within_reach_is_accepted() -> None:
    _, group, table = table_machine(30.0)
    fb = mcl.MC_TrackRotaryTable()
    fb(AxesGroup=group, Execute=True, **args(table, Horizon=2.0))  # 60° on: still in reach
    assert fb.Busy and not fb.Error and group.kin.frame is not None


def test_a_table_too_fast_to_follow_is_refused() -> None:
    """The part 150 mm from the centre at 150 °/s runs at 393 mm/s, the tool point's velocity
    is limited to 300 mm/s; at 100 °/s (262 mm/s) it is followed."""
    _, group, table = table_machine(150.0)
    slow = mcl.DeltaKinematics(
        base_radius=200.0,
        effector_radius=50.0,
        upper_arm=350.0,
        forearm=800.0,
        tcp=mcl.TcpLimits(velocity=300.0),
    )
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=slow)
    assert kin.Done
    fb = mcl.MC_TrackRotaryTable()
    fb(AxesGroup=group, Execute=True, **args(table))
    assert fb.Error and fb.ErrorID == ErrorID.ETrackTooFast and group.kin.frame is None
    assert group.state == mcl.GroupState.GroupStandby
    _, group, table = table_machine(100.0)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=slow)
    fb = mcl.MC_TrackRotaryTable()
    fb(AxesGroup=group, Execute=True, **args(table))
    assert fb.Busy and not fb.Error


def test_tracking_a_table_needs_a_kinematic_transformation_and_a_powered_table() -> None:
    machine = make_machine(ARMS + TABLE)
    group = build_group(machine, ARMS)
    fb = mcl.MC_TrackRotaryTable()
    fb(AxesGroup=group, Execute=True, RotaryTable=machine.axes[TABLE], RotaryTableOrigin=CENTRE)
    assert fb.Error and fb.ErrorID == ErrorID.EParam
    machine, group, table = table_machine(0.0)
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=table, Enable=False), timeout=0.02)
    assert table.state == mcl.AxisState.Disabled
    fb = mcl.MC_TrackRotaryTable()
    fb(AxesGroup=group, Execute=True, **args(table))
    assert fb.Error and fb.ErrorID == ErrorID.EParam and group.kin.frame is None

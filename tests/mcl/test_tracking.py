"""Product coordinate systems (mcl.tracking, mcl.coordinate_system): MC_TrackConveyorBelt makes
the PCS of a delta robot's group move with a belt axis, a move in PCS lands on the moving part
and the group keeps following it; MC_SetCoordinateTransform ends the tracking; bad input and a
part out of reach or too fast give their ErrorID and leave the group alone. Scan by scan on
simulated axes (three arms in deg, the belt D in mm)."""

from __future__ import annotations

import math

import pytest

import mcl
from mcl import ErrorID, MC_BufferMode
from mcl.enums import MC_COORD_SYSTEM
from tests.helpers import configure, in_velocity, make_machine, scan
from tests.mcl.test_group import build_group
from tests.mcl.test_group_kinematics import ARMS, DELTA, MOVE

BELT = "D"
ORIGIN = [-300.0, -100.0, -760.0]
"""The belt frame in the MCS [mm] (x along the belt)."""
PCS = {"CoordSystem": MC_COORD_SYSTEM.PCS}


def tracking_machine(speed: float = 200.0) -> tuple[mcl.SimMachine, mcl.AxesGroup, mcl.Axis]:
    """The arms grouped with the delta kinematics and the belt running at ``speed`` [mm/s]."""
    machine = make_machine(ARMS + BELT)
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    assert kin.Done
    belt = machine.axes[BELT]
    if speed:
        in_velocity(machine, belt, speed)
    return machine, group, belt


def tool(group: mcl.AxesGroup) -> list[float]:
    """The tool point of the arms' set points [mm, MCS]."""
    return DELTA.forward([axis.sp_pos for axis in group.axes])


def track(
    machine: mcl.SimMachine, group: mcl.AxesGroup, belt: mcl.Axis, **inputs: object
) -> mcl.MC_TrackConveyorBelt:
    """MC_TrackConveyorBelt of a part at the belt frame's origin, latched now; called every
    scan (with the belt's MC_MoveVelocity kept on) until Done or Error (at most 2 s)."""
    fb = mcl.MC_TrackConveyorBelt()
    args = dict(
        AxesGroup=group,
        ConveyorBelt=belt,
        ConveyorBeltOrigin=ORIGIN,
        InitialObjectPosition=[0.0, 0.0, 0.0],
        LatchedPosition=belt.sp_pos,
    )
    args |= inputs
    machine.run(
        scan(lambda: fb(Execute=True, **args)), until=lambda: fb.Done or fb.Error, timeout=2.0
    )
    return fb


def test_a_move_in_the_tracked_pcs_lands_on_the_moving_part_and_follows_it() -> None:
    machine, group, belt = tracking_machine(200.0)
    fb = track(machine, group, belt)
    assert fb.Done and not fb.Error and group.kin.frame is not None
    frame = group.kin.frame
    # in sync: the tool point moves with the belt
    machine.run(lambda: None, timeout=0.05)
    start = tool(group)
    machine.run(lambda: None, timeout=0.1)
    assert tool(group)[0] - start[0] == pytest.approx(200.0 * 0.1, abs=0.05)
    assert group.holding and group.state == mcl.GroupState.GroupMoving
    move = mcl.MC_MoveLinearAbsolute()
    machine.run(
        scan(
            lambda: move(
                AxesGroup=group,
                Execute=True,
                Position=[0.0, 0.0, 0.0],
                CoordSystem=MC_COORD_SYSTEM.PCS,
                **MOVE,
            )
        ),
        until=lambda: move.Done or move.Error,
        timeout=3.0,
    )
    assert move.Done, move.ErrorID
    for _ in range(5):  # on the part while it moves on
        machine.run(lambda: None, timeout=0.02)
        part = frame.point_to_mcs([0.0, 0.0, 0.0])
        assert math.dist(tool(group), part) < 1e-6
    read = mcl.MC_GroupReadActualPosition(AxesGroup=group, CoordSystem=MC_COORD_SYSTEM.PCS)
    read(Enable=True)
    assert read.Valid and math.dist(read.Position, [0.0, 0.0, 0.0]) < 0.5
    read(Enable=True, CoordSystem=MC_COORD_SYSTEM.MCS)
    assert math.dist(read.Position, part) < 0.5


def test_set_coordinate_transform_ends_the_tracking_at_a_standstill() -> None:
    machine, group, belt = tracking_machine(300.0)
    assert track(machine, group, belt).Done
    end = mcl.MC_SetCoordinateTransform()
    machine.run(
        scan(lambda: end(AxesGroup=group, Execute=True, CoordTransform=[0.0, 0.0, 0.0])),
        until=lambda: end.Done or end.Error,
        timeout=2.0,
    )
    assert end.Done and group.kin.frame is None
    machine.run(lambda: None, timeout=0.05)
    assert group.state == mcl.GroupState.GroupStandby
    assert all(abs(axis.sp_vel) < 1e-9 for axis in group.axes)
    stood = tool(group)
    machine.run(lambda: None, timeout=0.1)
    assert math.dist(tool(group), stood) < 1e-9


def test_a_buffered_move_after_the_part_was_reached_starts() -> None:
    machine, group, belt = tracking_machine(100.0)
    assert track(machine, group, belt).Done
    move = mcl.MC_MoveLinearAbsolute()
    pcs = dict(CoordSystem=MC_COORD_SYSTEM.PCS, BufferMode=MC_BufferMode.Buffered, **MOVE)
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, 20.0], **pcs)),
        until=lambda: move.Done or move.Error,
        timeout=3.0,
    )
    assert move.Done, move.ErrorID


def test_a_fixed_pcs_shifts_and_turns_the_moves() -> None:
    machine, group, _ = tracking_machine(0.0)
    fixed = mcl.MC_SetCoordinateTransform()
    fixed(AxesGroup=group, Execute=True, CoordTransform=[50.0, -20.0, -700.0, 90.0])
    machine.run(lambda: fixed(Execute=True), until=lambda: fixed.Done or fixed.Error, timeout=1)
    assert fixed.Done
    move = mcl.MC_MoveLinearAbsolute()
    pcs = dict(CoordSystem=MC_COORD_SYSTEM.PCS, **MOVE)
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=[30.0, 0.0, -10.0], **pcs)),
        until=lambda: move.Done or move.Error,
        timeout=3.0,
    )
    assert move.Done, move.ErrorID
    # PCS x is MCS y (turned 90°)
    assert math.dist(tool(group), [50.0, 10.0, -710.0]) < 1e-6
    mcs = mcl.MC_MoveLinearAbsolute()
    mcs(AxesGroup=group, Execute=True, Position=[0.0, 0.0, -700.0], **MOVE)
    assert mcs.Error and mcs.ErrorID == ErrorID.EParam


def _bad(group: mcl.AxesGroup, belt: mcl.Axis) -> list[tuple[dict[str, object], int]]:
    return [
        ({"ConveyorBelt": None}, ErrorID.EParam),
        ({"ConveyorBelt": group.axes[0]}, ErrorID.EParam),
        ({"ConveyorBeltOrigin": [0.0, 0.0]}, ErrorID.EParam),
        ({"ConveyorBeltOrigin": [0.0, math.nan, -700.0]}, ErrorID.EParam),
        ({"InitialObjectPosition": "abc"}, ErrorID.EParam),
        ({"LatchedPosition": math.inf}, ErrorID.EParam),
        ({"Horizon": -1.0}, ErrorID.EParam),
        ({"Acceleration": -1.0}, ErrorID.EParam),
        ({"BufferMode": MC_BufferMode.Buffered}, ErrorID.EParam),
        ({"ConveyorBeltOrigin": [-900.0, 0.0, -760.0]}, ErrorID.EWorkspace),
        ({"Horizon": 5.0}, ErrorID.EWorkspace),  # 1000 mm on, the part is out of reach
    ]


@pytest.mark.parametrize("case", range(11))
def test_bad_input_or_a_part_out_of_reach_is_refused_and_the_group_left_alone(case: int) -> None:
    _, group, belt = tracking_machine(200.0)
    inputs, error = _bad(group, belt)[case]
    fb = mcl.MC_TrackConveyorBelt()
    args = dict(
        AxesGroup=group,
        ConveyorBelt=belt,
        ConveyorBeltOrigin=ORIGIN,
        InitialObjectPosition=[0.0, 0.0, 0.0],
        LatchedPosition=belt.sp_pos,
    )
    fb(Execute=True, **(args | inputs))
    assert fb.Error and fb.ErrorID == error and not fb.Busy and not fb.Done
    assert group.kin.frame is None and not group.has_path
    assert group.state == mcl.GroupState.GroupStandby


def test_a_belt_too_fast_to_follow_is_refused() -> None:
    """The belt at 400 mm/s, the tool point's velocity limited to 300 mm/s."""
    _, group, belt = tracking_machine(400.0)
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
    fb = mcl.MC_TrackConveyorBelt()
    fb(
        AxesGroup=group,
        Execute=True,
        ConveyorBelt=belt,
        ConveyorBeltOrigin=ORIGIN,
        LatchedPosition=belt.sp_pos,
    )
    assert fb.Error and fb.ErrorID == ErrorID.ETrackTooFast and group.kin.frame is None
    assert group.state == mcl.GroupState.GroupStandby


def test_tracking_needs_a_kinematic_transformation_and_a_group_at_rest() -> None:
    machine = make_machine(ARMS + BELT)
    group = build_group(machine, ARMS)
    fb = mcl.MC_TrackConveyorBelt()
    fb(AxesGroup=group, Execute=True, ConveyorBelt=machine.axes[BELT], ConveyorBeltOrigin=ORIGIN)
    assert fb.Error and fb.ErrorID == ErrorID.EParam
    machine, group, belt = tracking_machine(0.0)
    move = mcl.MC_MoveLinearAbsolute()
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, -700.0], **MOVE)),
        timeout=0.02,
    )
    assert move.Busy
    fb = mcl.MC_TrackConveyorBelt()
    fb(AxesGroup=group, Execute=True, ConveyorBelt=belt, ConveyorBeltOrigin=ORIGIN)
    assert fb.Error and fb.ErrorID == ErrorID.EParam and group.kin.frame is None
    assert move.Busy


def test_set_cartesian_transform_takes_plcopen_inputs_and_refuses_a_tilt() -> None:
    machine, group, _ = tracking_machine(0.0)
    fb = mcl.MC_SetCartesianTransform()
    fb(AxesGroup=group, Execute=True, TransX=10.0, TransY=0.0, TransZ=-700.0, RotAngle2=5.0)
    assert fb.Error and fb.ErrorID == ErrorID.EParam and group.kin.frame is None
    fb(Execute=False)
    fb(Execute=True, RotAngle2=0.0, TransY=math.nan)
    assert fb.Error and fb.ErrorID == ErrorID.EParam and group.kin.frame is None
    fb(Execute=False)
    fb(Execute=True, TransY=0.0, RotAngle1=30.0)
    machine.run(lambda: fb(Execute=True), until=lambda: fb.Done or fb.Error, timeout=1.0)
    assert fb.Done and group.kin.frame is not None and group.kin.frame.angle == 30.0
    read = mcl.MC_GroupReadActualPosition(AxesGroup=group, CoordSystem=MC_COORD_SYSTEM.PCS)
    read(Enable=True)
    mcs = tool(group)
    assert math.dist(group.kin.frame.point_to_mcs(read.Position), mcs) < 1e-3


def test_a_disable_while_tracking_stops_the_group_in_the_mcs() -> None:
    machine, group, belt = tracking_machine(300.0)
    assert track(machine, group, belt).Done
    disable = mcl.MC_GroupDisable()
    disable(AxesGroup=group, Execute=True)
    assert group.kin.frame is None
    machine.run(lambda: disable(Execute=True), until=lambda: disable.Done, timeout=1.0)
    assert disable.Done
    assert all(abs(axis.sp_vel) < 1e-9 for axis in group.axes)
    stood = tool(group)
    machine.run(lambda: None, timeout=0.1)
    assert math.dist(tool(group), stood) < 1e-9
    assert not group.has_path


def test_a_group_stop_while_tracking_stops_the_tool_in_the_mcs() -> None:
    """MC_GroupStop while the group follows the part: the tool point ramps from the belt's
    velocity to a standstill in the MCS with the stop's deceleration and jerk (the PCS is no
    longer followed) and stays there."""
    machine, group, belt = tracking_machine(300.0)
    assert track(machine, group, belt).Done
    machine.run(lambda: None, timeout=0.05)
    stop = mcl.MC_GroupStop()
    stop(AxesGroup=group, Execute=True, Deceleration=3000.0, Jerk=1.0e5)
    start = tool(group)
    assert group.kin.frame is None and group.state == mcl.GroupState.GroupStopping
    machine.run(lambda: stop(Execute=True), until=lambda: stop.Done or stop.Error, timeout=2.0)
    assert stop.Done
    distance = mcl.trajectory.stop(0.0, 300.0, 0.0, 3000.0, 1.0e5).end_position
    assert math.dist(tool(group), start) == pytest.approx(distance, abs=0.5)
    stood = tool(group)
    machine.run(lambda: stop(Execute=False), timeout=0.1)
    assert math.dist(tool(group), stood) < 1e-9
    assert group.state == mcl.GroupState.GroupStandby and not group.has_path


def test_a_move_in_the_tracked_pcs_is_checked_along_the_belts_travel() -> None:
    """A slow move in PCS to a point within reach where the part is now: at 50 mm/s it takes
    1.3 s, while the belt carries the part 260 mm on, out of reach. It is refused with
    EWorkspace when it is given, and the group keeps following the part."""
    machine, group, belt = tracking_machine(200.0)
    assert track(machine, group, belt).Done
    slow = dict(Velocity=50.0, Acceleration=5000.0, Deceleration=5000.0, Jerk=2.0e5)
    move = mcl.MC_MoveLinearAbsolute()
    move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, 60.0], **PCS, **slow)
    assert move.Error and move.ErrorID == ErrorID.EWorkspace
    assert group.holding and group.kin.frame is not None
    move(Execute=False)
    move(Execute=True, Velocity=500.0)  # fast enough: done before the part leaves the reach
    machine.run(lambda: move(Execute=True), until=lambda: move.Done or move.Error, timeout=2.0)
    assert move.Done


def test_the_belts_share_of_a_joints_velocity_lowers_the_path_velocity() -> None:
    """The arms' Vmax 80 deg/s, the belt at 300 mm/s: a move of 200 mm along the belt in PCS
    runs slower, so that path and belt together keep every arm within its Vmax (without the
    belt's share the arms were asked for more than they can give: ERRPOSG 8001)."""
    machine, group, belt = tracking_machine(300.0)
    assert track(machine, group, belt).Done
    for axis in group.axes:
        configure(axis, Vmax=80.0)
    move = mcl.MC_MoveLinearAbsolute()
    fast = dict(Velocity=1000.0, Acceleration=20000.0, Deceleration=20000.0, Jerk=2.0e6)
    peak = 0.0

    def program() -> None:
        nonlocal peak
        move(AxesGroup=group, Execute=True, Position=[200.0, 0.0, 0.0], **PCS, **fast)
        peak = max(peak, *(abs(axis.sp_vel) for axis in group.axes))

    machine.run(program, until=lambda: move.Done or move.Error, timeout=3.0)
    assert move.Done and group.GroupErrorID == 0
    assert 40.0 < peak <= 80.0


def test_a_move_is_refused_where_the_belt_alone_is_too_fast_for_a_joint() -> None:
    """The belt sped up after the part was tracked: the belt's share of an arm's velocity
    alone reaches its Vmax at the move's points: ETrackTooFast, the group left following."""
    machine, group, belt = tracking_machine(300.0)
    assert track(machine, group, belt).Done
    for axis in group.axes:
        configure(axis, Vmax=30.0)
    move = mcl.MC_MoveLinearAbsolute()
    move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, 20.0], **PCS, **MOVE)
    assert move.Error and move.ErrorID == ErrorID.ETrackTooFast
    assert group.holding

"""A group with a kinematic transformation (mcl.kin_fb, mcl.group_kinematics): MC_SetKinTransform
and MC_ReadKinTransform, Cartesian linear and direct moves of a delta robot's three arms through
the inverse kinematics each servo cycle, refusals with an ErrorID, and
MC_GroupReadActualPosition in ACS and MCS, scan by scan on three simulated axes (the arms'
angles in deg)."""

from __future__ import annotations

import dataclasses
import itertools
import math
import types
from collections.abc import Sequence

import pytest

import mcl
from mcl import ErrorID, MC_BufferMode
from mcl.enums import MC_COORD_SYSTEM
from mcl.group import distance_to_segment
from tests.helpers import make_machine, scan
from tests.mcl.test_group import build_group

ARMS = "ABC"
DELTA = mcl.DeltaKinematics(base_radius=200.0, effector_radius=50.0, upper_arm=350.0, forearm=800.0)
MOVE = dict(Velocity=500.0, Acceleration=5000.0, Deceleration=5000.0, Jerk=200000.0)
HOME = DELTA.forward([0.0, 0.0, 0.0])
"""The tool point with every arm at 0 deg [mm] (z = -624.5)."""


def delta_group(machine: mcl.SimMachine) -> mcl.AxesGroup:
    """The arms A, B, C grouped, enabled and given the delta's kinematics."""
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    assert kin.Done and not kin.Error
    return group


class Joints:
    """Every servo cycle: the arms' model positions, velocities and accelerations."""

    def __init__(self, axes: Sequence[mcl.Axis]) -> None:
        self.axes = axes
        self.q: list[list[float]] = []
        self.qd: list[list[float]] = []
        self.qdd: list[list[float]] = []

    def __call__(self, t: float) -> None:
        self.q.append([a.sp_pos for a in self.axes])
        self.qd.append([a.sp_vel for a in self.axes])
        self.qdd.append([a.sp_acc for a in self.axes])


def record(machine: mcl.SimMachine) -> Joints:
    joints = Joints([machine.axes[n] for n in ARMS])
    machine.runtime.observers.append(joints)
    return joints


def run_move(machine: mcl.SimMachine, group: mcl.AxesGroup, fb: mcl.MotionFB, **inputs) -> None:
    """Call ``fb`` every scan until Done (at most 5 s)."""
    machine.run(
        scan(lambda: fb(AxesGroup=group, Execute=True, **inputs)),
        until=lambda: fb.Done or fb.Error,
        timeout=5.0,
    )
    assert fb.Done and not fb.Error, fb.ErrorID


def test_set_and_read_the_kinematic_transformation() -> None:
    machine = make_machine(ARMS)
    group = build_group(machine, ARMS)
    read = mcl.MC_ReadKinTransform()
    read(AxesGroup=group, Enable=True)
    assert read.Valid and read.Name == "identity" and read.Parameters == {}
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    assert kin.Done and kin.ErrorID == 0
    read(Enable=True)
    assert read.Valid and read.KinTransform is DELTA and read.Name == "delta"
    assert read.Parameters["forearm"] == 800.0 and read.Parameters["upper_arm"] == 350.0
    kin(Execute=False)
    kin(Execute=True, KinTransform=mcl.KinTransform())  # the identity takes it away
    assert kin.Done and group.kin.transform is None
    read(Enable=True)
    assert read.Name == "identity"
    read(Enable=False)
    assert not read.Valid and type(read.KinTransform) is mcl.KinTransform and read.Name == ""


@pytest.mark.parametrize(
    ("names", "transform", "error_id"),
    [
        ("ABC", "not a transformation", ErrorID.EParam),
        ("ABC", None, ErrorID.EParam),
        ("AB", DELTA, ErrorID.EParam),  # two members for three joints
        ("", DELTA, ErrorID.EGroupEmpty),
    ],
)
def test_set_kin_transform_refuses_bad_input(names: str, transform: object, error_id: int) -> None:
    machine = make_machine(ARMS)
    group = build_group(machine, names, enable=False)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=transform)
    assert kin.Error and kin.ErrorID == error_id and not kin.Done
    assert group.kin.transform is None


def test_set_kin_transform_is_refused_while_the_group_moves() -> None:
    machine = make_machine(ARMS)
    group = delta_group(machine)
    move, kin = mcl.MC_MoveLinearAbsolute(), mcl.MC_SetKinTransform()
    target = [100.0, 0.0, -700.0]
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE)), timeout=0.05
    )
    assert move.Busy
    kin(AxesGroup=group, Execute=True, KinTransform=mcl.KinTransform())
    assert kin.Error and kin.ErrorID == ErrorID.EParam
    assert group.kin.transform is DELTA


def test_read_actual_position_in_acs_and_mcs() -> None:
    machine = make_machine(ARMS)
    group = delta_group(machine)
    read = mcl.MC_GroupReadActualPosition()
    read(AxesGroup=group, Enable=True, CoordSystem=MC_COORD_SYSTEM.ACS)
    assert read.Valid and read.Position == [machine.axes[n].POS for n in ARMS]
    read(CoordSystem=MC_COORD_SYSTEM.MCS)
    assert read.Valid
    expected = DELTA.forward([machine.axes[n].POS for n in ARMS])
    assert read.Position == pytest.approx(expected, abs=1e-12)
    assert read.Position[2] == pytest.approx(-624.5, abs=0.01)
    read(CoordSystem=7)
    assert read.Error and read.ErrorID == ErrorID.EParam and read.Position == []


def test_read_actual_position_of_a_pose_without_a_tool_point() -> None:
    """Arms beyond the kinematics' range: MCS gives EWorkspace, ACS still the angles."""
    narrow = mcl.DeltaKinematics(200.0, 50.0, 350.0, 800.0, theta_min=10.0, theta_max=60.0)
    machine = make_machine(ARMS)
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=narrow)
    read = mcl.MC_GroupReadActualPosition()
    read(AxesGroup=group, Enable=True)
    assert read.Error and read.ErrorID == ErrorID.EWorkspace and read.Position == []
    read(CoordSystem=MC_COORD_SYSTEM.ACS)
    assert read.Valid and len(read.Position) == 3


def test_linear_move_in_mcs_keeps_the_tool_point_on_the_line() -> None:
    """Every servo cycle the arms' set points put the tool point on the straight line (forward
    kinematics of the model positions), and the move ends at the target."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    joints = record(machine)
    target = [250.0, -150.0, -760.0]
    move = mcl.MC_MoveLinearAbsolute()
    run_move(machine, group, move, Position=target, **MOVE)
    worst = max(distance_to_segment(DELTA.forward(q), HOME, target) for q in joints.q)
    assert worst < 1e-6
    assert len(joints.q) > 100
    assert DELTA.forward(joints.q[-1]) == pytest.approx(target, abs=1e-9)
    moved = [max(abs(q[i] - joints.q[0][i]) for q in joints.q) for i in range(3)]
    assert min(moved) > 2.0  # every arm turns: the line is no joint-space line
    # the tool point's speed along the line reaches the commanded velocity
    speeds = [
        math.dist(DELTA.forward(a), DELTA.forward(b)) / 0.001
        for a, b in zip(joints.q, joints.q[1:], strict=False)
    ]
    assert max(speeds) == pytest.approx(500.0, rel=0.01)
    read = mcl.MC_GroupReadActualPosition()
    machine.run(scan(lambda: read(AxesGroup=group, Enable=True)), timeout=0.3)
    assert read.Position == pytest.approx(target, abs=0.05)


def test_the_joints_velocity_and_acceleration_feed_the_servo() -> None:
    """The set-point velocity and acceleration of each arm are the derivatives of its set point
    (the inverse kinematics' Jacobian, not the path's Cartesian components)."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    joints = record(machine)
    move = mcl.MC_MoveLinearAbsolute()
    run_move(machine, group, move, Position=[-200.0, 200.0, -700.0], **MOVE)
    dt = 0.001
    worst = 0.0
    for k in range(1, len(joints.q) - 1):
        for i in range(3):
            central = (joints.q[k + 1][i] - joints.q[k - 1][i]) / (2 * dt)
            worst = max(worst, abs(central - joints.qd[k][i]))
    peak = max(abs(v) for qd in joints.qd for v in qd)
    assert peak > 20.0
    assert worst < 0.01 * peak


def test_joint_velocity_and_acceleration_are_held_to_the_arms_limits() -> None:
    """A path velocity the arms cannot follow is lowered so that no arm exceeds its Vmax or its
    max_acceleration (here 60 deg/s and 20000 deg/s²)."""
    slow = {name: mcl.SimAxisParams(start=0.2, vmax=0.06) for name in ARMS}  # 60 deg/s at 10 V
    machine = make_machine(slow, Vmax=60.0)
    group = delta_group(machine)
    joints = record(machine)
    move = mcl.MC_MoveLinearAbsolute()
    fast = dict(Velocity=3000.0, Acceleration=50000.0, Deceleration=50000.0, Jerk=2.0e6)
    run_move(machine, group, move, Position=[300.0, 100.0, -800.0], **fast)
    peak = max(abs(v) for qd in joints.qd for v in qd)
    assert 50.0 < peak <= 60.0 * 1.001
    config = machine.axes["A"].config
    assert max(abs(a) for qdd in joints.qdd for a in qdd) <= config.max_acceleration * 1.01


@pytest.mark.parametrize(
    ("target", "error_id"),
    [
        ([0.0, 0.0, -300.0], ErrorID.EWorkspace),  # above the reach
        ([900.0, 0.0, -700.0], ErrorID.EWorkspace),  # beside it
        ([math.nan, 0.0, -700.0], ErrorID.EParam),
        ([0.0, 0.0], ErrorID.EParam),
    ],
)
def test_a_target_beyond_the_workspace_is_refused(target: list[float], error_id: int) -> None:
    machine = make_machine(ARMS)
    group = delta_group(machine)
    joints = record(machine)
    move = mcl.MC_MoveLinearAbsolute()
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE)), timeout=0.05
    )
    assert move.Error and move.ErrorID == error_id and not move.Busy
    assert all(q == [0.0, 0.0, 0.0] for q in joints.q)  # nothing moved
    assert group.state == mcl.GroupState.GroupStandby


def test_a_line_through_a_hole_of_the_workspace_is_refused() -> None:
    """Both ends are reachable, the middle is not (arm A would turn beyond -60 deg): refused
    before anything moves; then a move around it is taken."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    start = [50.0, 0.0, -480.0]
    to_start = mcl.MC_MoveLinearAbsolute()
    run_move(machine, group, to_start, Position=start, **MOVE)
    joints = record(machine)
    move = mcl.MC_MoveLinearAbsolute()
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=[500.0, 0.0, -480.0], **MOVE)),
        timeout=0.05,
    )
    assert move.Error and move.ErrorID == ErrorID.EWorkspace
    assert max(abs(a - b) for q in joints.q for a, b in zip(q, joints.q[0], strict=True)) < 1e-9
    around = mcl.MC_MoveLinearAbsolute()
    run_move(machine, group, around, Position=[500.0, 0.0, -560.0], **MOVE)


def test_a_line_beyond_a_joints_sw_limit_is_refused() -> None:
    """Arm A's SW limit at 20 deg: a line to a point that needs more is refused with Ecil."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    limit = mcl.GT_SWLim()
    machine.run(
        scan(
            lambda: limit(
                Axis=machine.axes["A"],
                Execute=True,
                LimPos=20.0,
                LimNeg=-60.0,
                EnableLimitPos=True,
                EnableLimitNeg=True,
            )
        ),
        until=lambda: limit.Done,
        timeout=0.1,
    )
    assert DELTA.inverse([-300.0, 0.0, -750.0])[0] > 20.0
    move = mcl.MC_MoveLinearAbsolute()
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=[-300.0, 0.0, -750.0], **MOVE)),
        timeout=0.05,
    )
    assert move.Error and move.ErrorID == ErrorID.Ecil


def test_direct_move_to_a_cartesian_target_interpolates_the_joints() -> None:
    """MC_MoveDirectAbsolute with CoordSystem MCS: the arms run synchronised (start and end
    together, a straight line in joint space) to the inverse kinematics of the target."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    joints = record(machine)
    target = [200.0, 100.0, -750.0]
    goal = DELTA.inverse(target)
    move = mcl.MC_MoveDirectAbsolute()
    run_move(machine, group, move, Position=target, CoordSystem=MC_COORD_SYSTEM.MCS, **MOVE)
    assert joints.q[-1] == pytest.approx(goal, abs=1e-9)
    for q in joints.q:
        share = [qi / gi for qi, gi in zip(q, goal, strict=True)]
        assert max(share) - min(share) < 1e-9
    bent = max(distance_to_segment(DELTA.forward(q), HOME, target) for q in joints.q)
    assert bent > 1.0  # the tool point leaves the Cartesian line


def test_direct_move_in_acs_and_a_linear_move_buffered_after_it() -> None:
    """A direct move in ACS, then a buffered linear move in MCS from where it ends: the group
    stops between them (different spaces never blend) and the line is straight."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    direct, line = mcl.MC_MoveDirectAbsolute(), mcl.MC_MoveLinearAbsolute()
    joints = record(machine)
    first = [20.0, 30.0, 40.0]
    target = [-100.0, 50.0, -700.0]

    def program() -> None:
        direct(AxesGroup=group, Execute=True, Position=first, **MOVE)
        line(
            AxesGroup=group,
            Execute=True,
            Position=target,
            BufferMode=MC_BufferMode.BlendingLow,
            **MOVE,
        )

    machine.run(program, until=lambda: line.Done or line.Error, timeout=5.0)
    assert direct.Done and line.Done, (direct.ErrorID, line.ErrorID)
    corner = DELTA.forward(first)
    k = min(range(len(joints.q)), key=lambda k: math.dist(joints.q[k], first))
    assert joints.q[k] == pytest.approx(first, abs=1e-6)
    assert joints.qd[k] == pytest.approx([0.0, 0.0, 0.0], abs=0.01)  # stood at the corner
    assert max(abs(v) for qd in joints.qd for v in qd) > 20.0
    worst = max(distance_to_segment(DELTA.forward(q), corner, target) for q in joints.q[k + 1 :])
    assert worst < 1e-6
    assert DELTA.forward(joints.q[-1]) == pytest.approx(target, abs=1e-9)


def test_relative_linear_move_counts_in_mcs() -> None:
    machine = make_machine(ARMS)
    group = delta_group(machine)
    joints = record(machine)
    move = mcl.MC_MoveLinearRelative()
    run_move(machine, group, move, Distance=[0.0, 0.0, -100.0], **MOVE)
    end = DELTA.forward(joints.q[-1])
    assert end == pytest.approx([HOME[0], HOME[1], HOME[2] - 100.0], abs=1e-9)
    assert joints.q[-1][0] == pytest.approx(joints.q[-1][1], abs=1e-9)  # straight down


def test_group_stop_on_a_cartesian_line_stops_on_the_line() -> None:
    machine = make_machine(ARMS)
    group = delta_group(machine)
    joints = record(machine)
    move, stop = mcl.MC_MoveLinearAbsolute(), mcl.MC_GroupStop()
    target = [300.0, 0.0, -800.0]
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE)), timeout=0.2
    )
    machine.run(
        scan(move, lambda: stop(AxesGroup=group, Execute=True, Deceleration=5000.0)),
        until=lambda: stop.Done,
        timeout=1.0,
    )
    assert move.CommandAborted
    worst = max(distance_to_segment(DELTA.forward(q), HOME, target) for q in joints.q)
    assert worst < 1e-6
    assert joints.qd[-1] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    assert math.dist(DELTA.forward(joints.q[-1]), target) > 10.0


def test_velocity_and_acceleration_read_in_mcs_are_the_tool_points() -> None:
    """Halfway along a line at constant path velocity: in MCS the velocity points along the line
    at 500 mm/s and the acceleration is 0, while the arms accelerate (ACS)."""
    machine = make_machine(ARMS)
    group = delta_group(machine)
    target = [400.0, 0.0, -624.5]
    move = mcl.MC_MoveLinearAbsolute()
    velocity, acceleration = mcl.MC_GroupReadActualVelocity(), mcl.MC_GroupReadActualAcceleration()
    joint_acc = mcl.MC_GroupReadActualAcceleration(CoordSystem=MC_COORD_SYSTEM.ACS)
    machine.run(
        scan(
            lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE),
            lambda: velocity(AxesGroup=group, Enable=True),
            lambda: acceleration(AxesGroup=group, Enable=True),
            lambda: joint_acc(AxesGroup=group, Enable=True),
        ),
        timeout=0.5,
    )
    assert move.Busy and velocity.Valid and acceleration.Valid
    assert velocity.PathVelocity == pytest.approx(500.0, rel=0.02)
    assert abs(velocity.Velocity[1]) < 5.0 and abs(velocity.Velocity[2]) < 5.0
    assert max(abs(a) for a in acceleration.Acceleration) < 1.0
    assert max(abs(a) for a in joint_acc.Acceleration) > 10.0


def test_set_position_of_a_transformed_group_takes_only_acs() -> None:
    machine = make_machine(ARMS)
    group = delta_group(machine)
    shift = mcl.MC_GroupSetPosition()
    shift(AxesGroup=group, Execute=True, Position=[0.0, 0.0, -700.0])
    assert shift.Error and shift.ErrorID == ErrorID.EParam
    assert [machine.axes[n].POS for n in ARMS] == pytest.approx([0.0, 0.0, 0.0], abs=0.01)
    acs = mcl.MC_GroupSetPosition()
    acs(AxesGroup=group, Execute=True, Position=[1.0, 2.0, 3.0], CoordSystem=MC_COORD_SYSTEM.ACS)
    assert acs.Done


def test_a_path_point_refused_during_a_motion_ramps_the_arms_to_standstill() -> None:
    """The kinematics refuses a point while the group moves (here its range narrowed under
    the running path): the move ends with EWorkspace, every arm ramps from its last set point to
    standstill on its own fastest ramp (no step of its velocity, within its stop distance) and
    the group is in GroupErrorStop until MC_GroupReset, which waits for the ramps."""
    machine = make_machine(ARMS)
    delta = mcl.DeltaKinematics(200.0, 50.0, 350.0, 800.0)
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=delta)
    joints = record(machine)
    errors: list[int] = []  # the group's error, every servo cycle
    machine.runtime.observers.append(lambda t: errors.append(group.GroupErrorID))
    move = mcl.MC_MoveLinearAbsolute()
    target = [0.0, 0.0, -800.0]  # straight down: every arm turns from 0 to 25.4 deg
    program = scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE))
    machine.run(program, timeout=0.1)
    assert move.Busy
    delta.theta_max = max(joints.q[-1]) + 0.5  # the arms may go 0.5 deg further
    machine.run(program, until=lambda: move.Error, timeout=0.5)
    assert move.ErrorID == ErrorID.EWorkspace and group.GroupErrorID == ErrorID.EWorkspace
    assert group.state == mcl.GroupState.GroupErrorStop
    k = next(k for k, error in enumerate(errors) if error) - 1  # the last point of the path
    last, speed, acc = joints.q[k], joints.qd[k], joints.qdd[k]
    assert min(speed) > 10.0  # the arms ran when the point was refused
    reset = mcl.MC_GroupReset()
    reset(AxesGroup=group, Execute=True)
    assert not reset.Done and group.state == mcl.GroupState.GroupErrorStop  # still ramping
    machine.run(scan(reset), until=lambda: reset.Done, timeout=1.0)
    assert group.state == mcl.GroupState.GroupStandby and group.GroupErrorID == 0
    assert all(v == 0.0 for v in joints.qd[-1])
    axes = [machine.axes[n] for n in ARMS]
    period = axes[0].servo_period
    for i, axis in enumerate(axes):
        ramp = axis.max_ramp()
        steps = [abs(b[i] - a[i]) for a, b in itertools.pairwise(joints.qd[k:])]
        assert max(steps) <= ramp.deceleration * period * 1.001, (i, max(steps))
        stop = mcl.trajectory.stop(last[i], speed[i], acc[i], ramp.deceleration, ramp.jerk)
        assert joints.q[-1][i] == pytest.approx(stop.end_position, abs=1e-9)
        assert joints.q[-1][i] > last[i]  # it went on a little: no hold at the last set point


def test_a_blended_corner_keeps_every_arm_within_its_acceleration() -> None:
    """The standard pick cycle (up 25, across 305, down 25 mm) blended with a 10 mm corner
    tolerance, the tool point allowed 60 m/s² but the arms only 1000 deg/s²: the corners' curves
    keep every arm within its max_acceleration and Vmax, not only the straight pieces."""
    machine = make_machine(ARMS)
    for name in ARMS:
        axis = machine.axes[name]
        axis.config = dataclasses.replace(
            axis.config,
            acceleration=1000.0,
            deceleration=1000.0,
            max_acceleration=1000.0,
            max_deceleration=1000.0,
        )
    group = build_group(machine, ARMS)
    group.corner_tolerance = 10.0
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    joints = record(machine)
    cycle = ([0.0, -150.0, -775.0], [305.0, -150.0, -775.0], [305.0, -150.0, -800.0])
    moves = [mcl.MC_MoveLinearAbsolute() for _ in cycle]
    fast = dict(Velocity=3000.0, Acceleration=60000.0, Deceleration=60000.0, Jerk=1e7)

    def program() -> None:
        for k, (move, target) in enumerate(zip(moves, cycle, strict=True)):
            mode = MC_BufferMode.BlendingNext if k else MC_BufferMode.Aborting
            move(AxesGroup=group, Execute=True, Position=target, BufferMode=mode, **fast)

    machine.run(program, until=lambda: moves[-1].Done or any(m.Error for m in moves), timeout=5)
    assert all(m.Done for m in moves)
    assert DELTA.forward(joints.q[-1]) == pytest.approx(cycle[-1], abs=1e-6)
    peak = max(abs(a) for row in joints.qdd for a in row)
    assert peak <= 1000.0 * 1.001, peak
    constants = machine.axes["A"].constants
    assert constants is not None
    assert max(abs(v) for row in joints.qd for v in row) <= constants.Vmax


def test_set_kin_transform_takes_a_structure_of_a_deltas_parameters() -> None:
    """MC_KIN_REF as a structure read by name: the delta's lengths, its arms' range (0° a value
    like any other) and the tool point's limits (0 or missing: the default)."""
    machine = make_machine(ARMS)
    group = build_group(machine, ARMS)
    fields = dict(BaseRadius=200.0, EffectorRadius=50.0, UpperArm=350.0, Forearm=800.0)
    described = types.SimpleNamespace(**fields, ThetaMin=0.0, MaxVelocity=1500.0, Jerk=0.0)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=described)
    assert kin.Done and not kin.Error
    transform = group.kin.transform
    assert isinstance(transform, mcl.DeltaKinematics)
    assert transform.parameters()["forearm"] == 800.0
    assert transform.theta_min == 0.0 and transform.theta_max == 100.0
    assert transform.tcp.velocity == 1500.0 and transform.tcp.jerk == mcl.TcpLimits().jerk
    kin(Execute=False)  # the range's upper end alone, the lower one missing: its default
    kin(Execute=True, KinTransform=types.SimpleNamespace(**fields, ThetaMax=80.0))
    assert kin.Done
    transform = group.kin.transform
    assert isinstance(transform, mcl.DeltaKinematics)
    assert transform.theta_min == -60.0 and transform.theta_max == 80.0
    bad_ones: list[dict[str, object]] = [
        dict(fields, Forearm=math.nan),
        dict(fields, UpperArm="long"),
        dict(fields, BaseRadius=True),  # a BOOL is no length
        {},
    ]
    for bad in bad_ones:
        kin(Execute=False)
        kin(Execute=True, KinTransform=types.SimpleNamespace(**bad))
        assert kin.Error and kin.ErrorID == ErrorID.EParam, bad
    assert group.kin.transform is transform


def test_a_stop_ramp_beyond_the_workspace_stops_the_arms_at_once() -> None:
    """MC_GroupStop with a gentle deceleration on a line that ends 0.5 deg inside the arms'
    range: the ramp would run on along the line beyond it. It is checked when it is planned:
    the stop ends with EWorkspace on the scan it starts, every arm ramps to standstill on its
    own fastest ramp from there and stays within the range (checked only when reached, the
    ramp took them beyond it)."""
    machine = make_machine(ARMS)
    target = [300.0, 0.0, -800.0]
    delta = mcl.DeltaKinematics(200.0, 50.0, 350.0, 800.0)
    delta.theta_max = max(delta.inverse(target)) + 0.5
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=delta)
    joints = record(machine)
    move, stop = mcl.MC_MoveLinearAbsolute(), mcl.MC_GroupStop()
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE)), timeout=0.3
    )
    assert move.Busy
    stop(AxesGroup=group, Execute=True, Deceleration=500.0)
    move(Execute=True)
    assert stop.Error and stop.ErrorID == ErrorID.EWorkspace and move.CommandAborted
    assert group.state == mcl.GroupState.GroupErrorStop
    machine.run(lambda: None, timeout=0.5)
    assert all(v == 0.0 for v in joints.qd[-1])
    assert max(max(q) for q in joints.q) < delta.theta_max

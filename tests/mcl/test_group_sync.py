"""MC_SyncAxisToGroup and MC_MovePathSynchronized (mcl.group_sync), scan by scan on simulated
axes: a delta robot's group (arms A, B, C in deg), a single axis S coupled to it, a belt D as the
master of a synchronized path. The slave follows the group's coordinate after its ramp-in
(InSync), a failing group stops it; the path's progress is the master's position, it stands
with the master and ends at rest; bad input and a master too fast for the path give their
ErrorID and leave the axes alone; the outputs follow Tab. 2.3."""

from __future__ import annotations

import itertools
import math

import pytest

import mcl
from mcl import ErrorID, MC_BufferMode, trajectory
from mcl.enums import MC_COORD_SYSTEM
from mcl.gearing import DEFAULT_KV, MasterReader
from mcl.group_sync import MasterProfile
from mcl.path_clock import PathClock
from mcl.trajectory import Limits
from tests.helpers import carriage_mm, make_machine, scan
from tests.mcl.test_group import build_group
from tests.mcl.test_group_kinematics import ARMS, DELTA, MOVE

SLAVE = "S"
BELT = "D"
START = [0.0, 0.0, -700.0]
"""Where the tool point stands before a test moves it [mm, MCS]."""


def robot(extra: str) -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    """The arms grouped with the delta kinematics, the tool point moved to :data:`START`, and
    the ``extra`` single axes."""
    machine = make_machine(ARMS + extra)
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    assert kin.Done
    move_to(machine, group, START)
    return machine, group


def move_to(machine: mcl.SimMachine, group: mcl.AxesGroup, target: list[float]) -> None:
    """MC_MoveLinearAbsolute to ``target`` [mm, MCS], called until Done (at most 3 s)."""
    move = mcl.MC_MoveLinearAbsolute()
    machine.run(
        scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE)),
        until=lambda: move.Done or move.Error,
        timeout=3.0,
    )
    assert move.Done, move.ErrorID


def tool(group: mcl.AxesGroup) -> list[float]:
    """The tool point of the arms' set points [mm, MCS]."""
    return DELTA.forward([axis.sp_pos for axis in group.axes])


# ------------------------------------------------------------------------- MC_SyncAxisToGroup
def test_the_slave_follows_the_groups_x_after_its_ramp_in() -> None:
    machine, group = robot(SLAVE)
    slave = machine.axes[SLAVE]
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=slave, Ratio=0.5, Offset=50.0)
    sync(Execute=True)
    assert sync.Busy and not sync.InSync and not sync.Done and not sync.Error
    machine.run(lambda: sync(Execute=True), until=lambda: sync.InSync, timeout=2.0)
    assert sync.InSync and sync.Active and sync.Busy
    assert slave.state == mcl.AxisState.SynchronizedMotion
    assert slave.sp_pos == pytest.approx(0.5 * tool(group)[0] + 50.0, abs=1e-6)
    move = mcl.MC_MoveLinearAbsolute()
    seen: list[float] = []

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[80.0, -30.0, -720.0], **MOVE)
        sync(Execute=True)
        seen.append(slave.sp_pos - (0.5 * tool(group)[0] + 50.0))

    machine.run(program, until=lambda: move.Done or move.Error, timeout=3.0)
    assert move.Done
    assert max(abs(x) for x in seen) < 1e-3  # the tool point's x through the kinematics
    assert slave.sp_pos == pytest.approx(90.0, abs=1e-3)
    assert carriage_mm(machine, SLAVE) == pytest.approx(90.0, abs=0.5)  # the physics followed
    assert sync.InSync and not sync.Done
    sync(Execute=False)  # never-ending: Busy and Active stay, InSync goes with Execute
    assert sync.Busy and sync.Active and not sync.InSync


def test_the_slave_follows_a_members_position_in_acs() -> None:
    machine, group = robot(SLAVE)
    slave = machine.axes[SLAVE]
    sync = mcl.MC_SyncAxisToGroup(
        AxesGroup=group, Axis=slave, CoordSystem=MC_COORD_SYSTEM.ACS, Coordinate=1, Ratio=-1.0
    )
    machine.run(lambda: sync(Execute=True), until=lambda: sync.InSync, timeout=2.0)
    move_to(machine, group, [50.0, 60.0, -700.0])
    machine.run(lambda: sync(Execute=True), timeout=0.02)
    assert abs(group.axes[1].sp_pos) > 1.0
    assert slave.sp_pos == pytest.approx(-group.axes[1].sp_pos, abs=1e-9)


def test_an_aborting_command_on_the_slave_ends_the_sync_with_command_aborted() -> None:
    machine, group = robot(SLAVE)
    slave = machine.axes[SLAVE]
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=slave)
    machine.run(lambda: sync(Execute=True), until=lambda: sync.InSync, timeout=2.0)
    halt = mcl.MC_Halt(Axis=slave)
    halt(Execute=True)
    machine.run(lambda: sync(Execute=True), timeout=0.004)
    assert sync.CommandAborted and not sync.Busy and not sync.Active and not sync.InSync
    sync(Execute=False)
    assert not sync.CommandAborted  # held only while Execute is TRUE


def test_a_group_in_error_stop_stops_the_slave_with_a_master_error() -> None:
    machine, group = robot(SLAVE)
    slave = machine.axes[SLAVE]
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=slave, Offset=10.0)
    machine.run(lambda: sync(Execute=True), until=lambda: sync.InSync, timeout=2.0)
    group.axes[0].fault(ErrorID.EAxis)
    machine.run(lambda: sync(Execute=True), until=lambda: sync.Error, timeout=0.1)
    assert sync.Error and sync.ErrorID == ErrorID.EMasterError and not sync.Busy
    assert slave.state == mcl.AxisState.ErrorStop and slave.AxErrorID == ErrorID.EMasterError


def _bad_sync(machine: mcl.SimMachine) -> list[tuple[dict[str, object], int]]:
    return [
        ({"CoordSystem": 7}, ErrorID.EParam),
        ({"Coordinate": 3}, ErrorID.EParam),
        ({"Coordinate": -1}, ErrorID.EParam),
        ({"CoordSystem": MC_COORD_SYSTEM.ACS, "Coordinate": 3}, ErrorID.EParam),
        ({"Ratio": math.nan}, ErrorID.EParam),
        ({"Offset": math.inf}, ErrorID.EParam),
        ({"Velocity": -1.0}, ErrorID.EParam),
        ({"Jerk": -1.0}, ErrorID.EParam),
        ({"Axis": machine.axes["A"]}, ErrorID.EGroupMember),
    ]


@pytest.mark.parametrize("case", range(9))
def test_bad_sync_input_is_refused_and_the_slave_left_alone(case: int) -> None:
    machine, group = robot(SLAVE)
    slave = machine.axes[SLAVE]
    inputs, error = _bad_sync(machine)[case]
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=slave)
    sync(Execute=True, **inputs)
    assert sync.Error and sync.ErrorID == error and not sync.Busy and not sync.Active
    machine.run(lambda: sync(Execute=True), timeout=0.02)
    assert slave.state == mcl.AxisState.StandStill and slave.sp_vel == 0.0
    assert group.state == mcl.GroupState.GroupStandby
    sync(Execute=False)
    assert not sync.Error and sync.ErrorID == 0


def test_the_group_must_be_enabled_and_not_in_error_stop() -> None:
    machine = make_machine(ARMS + SLAVE)
    empty = mcl.AxesGroup("empty")
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=empty, Axis=machine.axes[SLAVE])
    sync(Execute=True)
    assert sync.Error and sync.ErrorID == ErrorID.EGroupEmpty
    group = mcl.AxesGroup()
    for name in ARMS:
        assert group.add(machine.axes[name]) == 0
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes[SLAVE])
    sync(Execute=True)
    assert sync.Error and sync.ErrorID == ErrorID.Epower
    assert group.enable() == 0
    group.axes[0].fault(ErrorID.EAxis)
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes[SLAVE])
    sync(Execute=True)
    assert sync.Error and sync.ErrorID == ErrorID.Eerrstop


# -------------------------------------------------------------------- MC_MovePathSynchronized
TARGET = [100.0, 0.0, -700.0]


def path_block(
    group: mcl.AxesGroup, belt: mcl.Axis, **inputs: object
) -> mcl.MC_MovePathSynchronized:
    """MC_MovePathSynchronized from :data:`START` to :data:`TARGET`, the path starting when the
    belt is 20 mm on, half a millimetre of path per millimetre of belt."""
    args = dict(Master=belt, Position=TARGET, MasterStart=belt.sp_pos + 20.0, Ratio=0.5)
    return mcl.MC_MovePathSynchronized(AxesGroup=group, **(args | inputs))


def test_the_paths_progress_follows_the_master() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    latched = belt.sp_pos
    path = path_block(group, belt)
    path(Execute=True)
    assert path.Busy and path.Active and not path.Done and not path.Error
    machine.run(lambda: path(Execute=True), timeout=0.004)
    start = tool(group)  # the path starts from the actual position, within 0.1 mm of START
    assert math.dist(start, START) < 0.1
    machine.run(lambda: path(Execute=True), timeout=0.1)  # the belt stands: so does the path
    assert math.dist(tool(group), start) < 1e-9 and path.Busy
    drive = mcl.MC_MoveVelocity(Axis=belt, Velocity=200.0)
    trace: list[tuple[float, float, float]] = []

    def program() -> None:
        drive(Execute=True)
        path(Execute=True)
        trace.append((belt.sp_pos - latched, tool(group)[0] - start[0], belt.sp_vel))

    machine.run(program, until=lambda: path.Done or path.Error, timeout=5.0)
    assert path.Done and not path.Busy and not path.Active, path.ErrorID
    assert math.dist(tool(group), TARGET) < 1e-6
    assert all(s == 0.0 for x, s, _ in trace if x <= 20.0)  # stood until MasterStart
    # between its ramps the path runs at Ratio × the belt: 0.5 mm per mm of belt
    middle = [(x, s) for x, s, _ in trace if 45.0 < s < 55.0]
    (x0, s0), (x1, s1) = middle[0], middle[-1]
    assert (s1 - s0) / (x1 - x0) == pytest.approx(0.5, abs=1e-6)
    assert all(s < TARGET[0] - start[0] + 1e-9 for _, s, _ in trace)  # never past the end
    assert trace[-1][0] > 220.0  # 200 mm of belt for 100 mm of path, and the ramps
    machine.run(lambda: path(Execute=True), timeout=0.05)
    assert group.state == mcl.GroupState.GroupStandby
    assert math.dist(tool(group), TARGET) < 1e-9  # the belt runs on, the path rests at its end
    path(Execute=False)
    assert not path.Done


def test_the_path_stands_when_the_master_stands_and_goes_on_with_it() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    path = path_block(group, belt, MasterStart=belt.sp_pos)
    move = mcl.MC_MoveRelative(Axis=belt, Distance=120.0, Velocity=200.0)
    machine.run(
        scan(lambda: move(Execute=True), lambda: path(Execute=True)),
        until=lambda: move.Done,
        timeout=3.0,
    )
    held = tool(group)
    assert 30.0 < held[0] < 70.0 and path.Busy
    machine.run(lambda: path(Execute=True), timeout=0.2)
    assert math.dist(tool(group), held) < 1e-9 and path.Busy and not path.Done
    assert all(abs(axis.sp_vel) < 1e-9 for axis in group.axes)
    on = mcl.MC_MoveRelative(Axis=belt, Distance=200.0, Velocity=200.0)
    machine.run(
        scan(lambda: on(Execute=True), lambda: path(Execute=True)),
        until=lambda: path.Done or path.Error,
        timeout=3.0,
    )
    assert path.Done and math.dist(tool(group), TARGET) < 1e-6


def test_a_group_stop_aborts_the_synchronized_path_and_ramps_it_to_rest() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    path = path_block(group, belt, MasterStart=belt.sp_pos)
    drive = mcl.MC_MoveVelocity(Axis=belt, Velocity=200.0)
    machine.run(
        scan(lambda: drive(Execute=True), lambda: path(Execute=True)),
        until=lambda: tool(group)[0] > 40.0,
        timeout=3.0,
    )
    stop = mcl.MC_GroupStop(AxesGroup=group)
    machine.run(
        scan(lambda: drive(Execute=True), lambda: stop(Execute=True), lambda: path(Execute=True)),
        until=lambda: stop.Done,
        timeout=2.0,
    )
    assert path.CommandAborted and not path.Busy and not path.Done
    stood = tool(group)
    machine.run(scan(lambda: drive(Execute=True), lambda: stop(Execute=True)), timeout=0.1)
    assert math.dist(tool(group), stood) < 1e-9 and stood[0] < TARGET[0]


def test_the_override_does_not_act_on_the_synchronized_path() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    override = mcl.MC_GroupSetOverride(AxesGroup=group, VelFactor=0.5)
    override(Enable=True)
    assert override.Enabled
    path = path_block(group, belt, MasterStart=belt.sp_pos)
    drive = mcl.MC_MoveVelocity(Axis=belt, Velocity=200.0)
    speeds: list[float] = []

    def program() -> None:
        drive(Execute=True)
        path(Execute=True)
        override(Enable=True)
        if 45.0 < tool(group)[0] < 55.0:
            step = DELTA.forward([a.sp_pos + a.sp_vel * 1e-6 for a in group.axes])
            speeds.append((step[0] - tool(group)[0]) / 1e-6)

    machine.run(program, until=lambda: path.Done or path.Error, timeout=5.0)
    assert path.Done and speeds
    assert all(s == pytest.approx(100.0, rel=1e-3) for s in speeds)  # 0.5 × 200 mm/s


def test_a_master_too_fast_for_the_path_is_refused() -> None:
    """Belt Vmax 500 mm/s × Ratio 10 = 5000 mm/s > the tool point's 3000 mm/s; laid out for
    the belt up to 200 mm/s (MasterVelocity) it is accepted."""
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    path = path_block(group, belt, Ratio=10.0)
    path(Execute=True)
    assert path.Error and path.ErrorID == ErrorID.ETrackTooFast and not group.has_path
    path = path_block(group, belt, Ratio=10.0, MasterVelocity=200.0)
    path(Execute=True)
    assert path.Busy and not path.Error and group.has_path


def _bad_path(machine: mcl.SimMachine) -> list[tuple[dict[str, object], int]]:
    return [
        ({"Position": [1.0, 2.0]}, ErrorID.EParam),
        ({"Position": [1.0, math.nan, -700.0]}, ErrorID.EParam),
        ({"Position": "here"}, ErrorID.EParam),  # a path of no length
        ({"MasterStart": math.inf}, ErrorID.EParam),
        ({"Ratio": 0.0}, ErrorID.EParam),
        ({"Ratio": -0.5}, ErrorID.EParam),
        ({"MasterVelocity": -1.0}, ErrorID.EParam),
        ({"Acceleration": -1.0}, ErrorID.EParam),
        ({"Deceleration": math.nan}, ErrorID.EParam),
        ({"Jerk": -1.0}, ErrorID.EParam),
        ({"BufferMode": MC_BufferMode.BlendingLow}, ErrorID.EParam),
        ({"CoordSystem": 9}, ErrorID.EParam),
        ({"Master": machine.axes["A"]}, ErrorID.EParam),
        ({"Position": [-900.0, 0.0, -700.0]}, ErrorID.EWorkspace),
    ]


@pytest.mark.parametrize("case", range(14))
def test_bad_path_input_is_refused_and_the_group_left_alone(case: int) -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    inputs, error = _bad_path(machine)[case]
    if inputs.get("Position") == "here":
        inputs["Position"] = group.start_point(MC_BufferMode.Aborting)
    path = path_block(group, belt, **inputs)
    path(Execute=True)
    assert path.Error and path.ErrorID == error and not path.Busy and not path.Active
    assert not group.has_path and group.state == mcl.GroupState.GroupStandby
    assert math.dist(tool(group), START) < 1e-9


def test_a_failed_master_or_a_moving_group_is_refused() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    move = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=TARGET, **MOVE)
    machine.run(lambda: move(Execute=True), timeout=0.02)
    path = path_block(group, belt)
    path(Execute=True)
    assert path.Error and path.ErrorID == ErrorID.EParam and move.Busy  # Aborting: must stand
    buffered = path_block(group, belt, BufferMode=MC_BufferMode.Buffered, Position=START)
    buffered(Execute=True)
    assert buffered.Busy and not buffered.Active  # queued behind the move
    belt.fault(ErrorID.EAxis)
    failed = path_block(group, belt)
    failed(Execute=True)
    assert failed.Error and failed.ErrorID == ErrorID.EMasterError


# ------------------------------------------------------------------- details of the two blocks
def test_the_slave_follows_a_pcs_coordinate_and_an_mcs_one_while_a_pcs_is_set() -> None:
    """A fixed PCS turned 90° and shifted: the PCS x of the tool point is its MCS y − 20."""
    machine, group = robot(SLAVE + "R")
    fixed = mcl.MC_SetCoordinateTransform(AxesGroup=group, CoordTransform=[0.0, 20.0, 0.0, 90.0])
    machine.run(lambda: fixed(Execute=True), until=lambda: fixed.Done, timeout=1.0)
    pcs = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes[SLAVE])
    pcs(CoordSystem=MC_COORD_SYSTEM.PCS)
    mcs = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes["R"], Offset=300.0)
    both = scan(lambda: pcs(Execute=True), lambda: mcs(Execute=True))
    machine.run(both, until=lambda: pcs.InSync and mcs.InSync, timeout=2.0)
    move = mcl.MC_MoveLinearAbsolute(AxesGroup=group, CoordSystem=MC_COORD_SYSTEM.PCS, **MOVE)
    machine.run(
        scan(lambda: move(Execute=True, Position=[60.0, 40.0, -700.0]), both),
        until=lambda: move.Done,
        timeout=3.0,
    )
    tcp = tool(group)
    assert tcp[1] == pytest.approx(80.0, abs=1e-6) and tcp[0] == pytest.approx(-40.0, abs=1e-6)
    assert machine.axes[SLAVE].sp_pos == pytest.approx(60.0, abs=1e-6)  # PCS x
    assert machine.axes["R"].sp_pos == pytest.approx(300.0 - 40.0, abs=1e-6)  # MCS x


def test_the_slave_rests_on_a_tracked_part_in_pcs() -> None:
    """The tool point rests on a part on the running belt: its PCS x stands, so does the
    slave (the belt's set point of the same servo instant, whatever the axes' order)."""
    machine, group = robot(SLAVE + BELT)
    belt = machine.axes[BELT]
    drive = mcl.MC_MoveVelocity(Axis=belt, Velocity=200.0)
    machine.run(lambda: drive(Execute=True), until=lambda: drive.InVelocity, timeout=2.0)
    track = mcl.MC_TrackConveyorBelt(
        AxesGroup=group,
        ConveyorBelt=belt,
        ConveyorBeltOrigin=[-300.0, -100.0, -760.0],
        LatchedPosition=belt.sp_pos,
    )
    sync = mcl.MC_SyncAxisToGroup(
        AxesGroup=group, Axis=machine.axes[SLAVE], CoordSystem=MC_COORD_SYSTEM.PCS, Offset=-250.0
    )
    program = scan(
        lambda: drive(Execute=True), lambda: track(Execute=True), lambda: sync(Execute=True)
    )
    machine.run(program, until=lambda: track.Done and sync.InSync, timeout=3.0)
    slave = machine.axes[SLAVE]
    held = slave.sp_pos
    machine.run(program, timeout=0.1)
    assert slave.sp_pos == pytest.approx(held, abs=1e-6) and abs(slave.sp_vel) < 1e-6


def test_the_ramp_in_starts_from_the_slaves_motion_and_lands_without_a_step() -> None:
    """The group runs along x at 150 mm/s when the slave (at rest) is coupled: its velocity
    starts at 0 and grows, its set point never steps, and at InSync it moves with the group."""
    machine, group = robot(SLAVE)
    slave = machine.axes[SLAVE]
    move = mcl.MC_MoveLinearAbsolute(
        AxesGroup=group, Position=[350.0, 0.0, -700.0], Velocity=150.0, Acceleration=2000.0
    )
    machine.run(lambda: move(Execute=True), until=lambda: tool(group)[0] > 40.0, timeout=2.0)
    sync = mcl.MC_SyncAxisToGroup(
        AxesGroup=group, Axis=slave, Offset=20.0, Velocity=300.0, Jerk=50000.0
    )
    states: list[tuple[float, float]] = []

    def program() -> None:
        move(Execute=True)
        sync(Execute=True)
        states.append((slave.sp_pos, slave.sp_vel))

    machine.run(program, until=lambda: sync.InSync, timeout=2.0)
    assert sync.InSync and move.Busy
    assert abs(states[0][1]) < 5.0  # no step of its velocity: it starts from rest
    period = 0.002
    for (p0, v0), (p1, v1) in itertools.pairwise(states):
        assert abs((p1 - p0) / period - 0.5 * (v0 + v1)) < 1.0  # the velocity is the slope
        assert abs(v1 - v0) < 40.0  # no step (acceleration within 20 m/s²)
    assert slave.sp_vel == pytest.approx(150.0, abs=1e-6)
    machine.run(program, timeout=0.01)
    assert slave.sp_pos == pytest.approx(tool(group)[0] + 20.0, abs=1e-6)


def test_coordinates_beyond_a_group_without_kinematics_are_refused() -> None:
    machine = make_machine("XYS")
    group = build_group(machine, "XY")
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes[SLAVE], Coordinate=2)
    sync(Execute=True)  # MCS is the members' coordinates: two of them
    assert sync.Error and sync.ErrorID == ErrorID.EParam
    assert mcl.MC_SyncAxisToGroup().InSync is False
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes[SLAVE], Coordinate=1)
    machine.run(lambda: sync(Execute=True), until=lambda: sync.InSync, timeout=2.0)
    assert machine.axes[SLAVE].sp_pos == pytest.approx(machine.axes["Y"].sp_pos, abs=1e-9)


def test_a_pose_without_a_tool_point_refuses_the_coupling() -> None:
    machine = make_machine(ARMS + SLAVE)
    moves = [mcl.MC_MoveAbsolute(Axis=machine.axes[n], Position=98.0, Velocity=200.0) for n in ARMS]
    machine.run(
        scan(*[lambda m=m: m(Execute=True) for m in moves]),
        until=lambda: all(m.Done for m in moves),
        timeout=3.0,
    )
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform(AxesGroup=group, KinTransform=DELTA)
    kin(Execute=True)
    sync = mcl.MC_SyncAxisToGroup(AxesGroup=group, Axis=machine.axes[SLAVE])
    sync(Execute=True)
    assert sync.Error and sync.ErrorID == ErrorID.ESingular
    assert machine.axes[SLAVE].state == mcl.AxisState.StandStill


def test_the_master_profile_is_the_plan_over_the_masters_travel() -> None:
    """MasterProfile.at: before MasterStart the path stands at 0; on the plan s = S(x),
    ṡ = S'·ṁ, s̈ = S''·ṁ² + S'·m̈, in path time of the clock's factor; beyond the plan it
    rests at its end from then on."""
    machine = make_machine(BELT)
    belt = machine.axes[BELT]
    ramp = mcl.MC_MoveVelocity(Axis=belt, Velocity=300.0, Acceleration=1000.0)
    machine.run(lambda: ramp(Execute=True), timeout=0.1)
    assert belt.sp_acc > 100.0 and belt.sp_vel > 50.0
    plan = trajectory.move_to(0.0, 0.0, 0.0, 10.0, Limits(0.5, 0.02, 0.02, 0.001))
    clock = PathClock()
    reader = MasterReader(belt, DEFAULT_KV)
    m, w, acc = belt.sp_pos, belt.sp_vel, belt.sp_acc
    early = MasterProfile(plan, reader, m + 0.5, clock)
    assert early.at(0.0) == (0.0, 0.0, 0.0)
    x = plan.duration * 0.3
    profile = MasterProfile(plan, reader, m - x, clock)
    s, slope, bend = plan.at(x)
    assert profile.at(0.0) == pytest.approx((s, slope * w, bend * w * w + slope * acc))
    clock.factor, clock.rate = 0.5, 0.2
    v = slope * w / 0.5
    expected = (s, v, (bend * w * w + slope * acc - 0.2 * v) / 0.25)
    assert profile.at(0.0) == pytest.approx(expected)
    clock.factor = 0.0  # held: the path follows the master's positions, no feed-forward
    assert profile.at(0.0) == pytest.approx((s, 0.0, 0.0))
    assert profile.duration == math.inf
    done = MasterProfile(plan, reader, m - plan.duration - 1.0, clock)
    assert done.at(0.25) == (10.0, 0.0, 0.0) and done.duration == 0.25
    assert MasterProfile(plan, reader, m - x - 0.6, clock).at(0.0)[0] > s  # 0.6 further on
    assert MasterProfile(plan, reader, m - 0.5, clock).at(0.0)[0] > 0.0  # just past the start
    done.start = m + 100.0  # the master back before MasterStart: the end was reached
    assert done.at(0.3) == (10.0, 0.0, 0.0)


def test_the_paths_acceleration_stays_within_the_groups_at_the_masters_top_speed() -> None:
    """Laid out for the belt at 200 mm/s (MasterVelocity) with Acceleration 1000 mm/s² and
    Jerk 20000 mm/s³: driven at 200 mm/s, the path's acceleration reaches 1000 mm/s² and no more,
    its set point never steps, and a short path (0.5 mm) is a path too."""
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    drive = mcl.MC_MoveVelocity(Axis=belt, Velocity=200.0, Acceleration=5000.0)
    machine.run(lambda: drive(Execute=True), until=lambda: drive.InVelocity, timeout=1.0)
    path = path_block(
        group,
        belt,
        MasterStart=belt.sp_pos + 5.0,
        Ratio=1.0,
        MasterVelocity=200.0,
        Acceleration=1000.0,
        Deceleration=1000.0,
        Jerk=20000.0,
    )
    along: list[float] = []

    def program() -> None:
        drive(Execute=True)
        path(Execute=True)
        along.append(tool(group)[0])

    machine.run(program, until=lambda: path.Done or path.Error, timeout=3.0)
    assert path.Done, path.ErrorID
    period = 0.002
    speeds = [(b - a) / period for a, b in itertools.pairwise(along)]
    accelerations = [(b - a) / period for a, b in itertools.pairwise(speeds)]
    assert max(speeds) == pytest.approx(200.0, rel=1e-3)  # Ratio × the belt
    assert 900.0 < max(abs(x) for x in accelerations) < 1000.0 * 1.05
    short = path_block(group, belt, Position=[100.5, 0.0, -700.0], MasterStart=belt.sp_pos)
    short(Execute=True)
    assert short.Busy and not short.Error


def test_path_refusals_of_the_group_and_of_its_coordinates() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    fixed = mcl.MC_SetCoordinateTransform(AxesGroup=group, CoordTransform=[0.0, 0.0, -700.0])
    machine.run(lambda: fixed(Execute=True), until=lambda: fixed.Done, timeout=1.0)
    path = path_block(group, belt)  # MCS while a PCS is set
    path(Execute=True)
    assert path.Error and path.ErrorID == ErrorID.EParam
    pcs = path_block(group, belt, CoordSystem=MC_COORD_SYSTEM.PCS, Position=[50.0, 0.0, 0.0])
    pcs(Execute=True)
    assert pcs.Busy and not pcs.Error
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    group.axes[1].Ref = False
    path = path_block(group, belt)
    path(Execute=True)
    assert path.Error and path.ErrorID == ErrorID.Ehome
    disable = mcl.MC_GroupDisable(AxesGroup=group)
    machine.run(lambda: disable(Execute=True), until=lambda: disable.Done, timeout=1.0)
    path = path_block(group, belt)
    path(Execute=True)
    assert path.Error and path.ErrorID == ErrorID.Epower


def test_a_synchronized_path_in_acs_ends_on_the_joint_target() -> None:
    machine, group = robot(BELT)
    belt = machine.axes[BELT]
    joints = [20.0, 25.0, 30.0]
    path = path_block(group, belt, CoordSystem=MC_COORD_SYSTEM.ACS, Position=joints, Ratio=0.2)
    path(MasterStart=belt.sp_pos)
    drive = mcl.MC_MoveVelocity(Axis=belt, Velocity=300.0)
    machine.run(
        scan(lambda: drive(Execute=True), lambda: path(Execute=True)),
        until=lambda: path.Done or path.Error,
        timeout=5.0,
    )
    assert path.Done, path.ErrorID
    assert [axis.sp_pos for axis in group.axes] == pytest.approx(joints, abs=1e-9)

"""What each member axis does when a group's path lets it go (mcl.group_member): at the end of a
path, when the kinematics refuses a path point (after its ramp to rest; at the very first point
at once) and when the axes are ungrouped after a group stop, every member holds its last set
point exactly, with set velocity and acceleration 0, from the cycle it is let go on; on
simulated axes."""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import mcl
from mcl import AxisState, ErrorID, GroupState
from tests.helpers import make_machine, scan
from tests.mcl.test_group import MOVE, NAMES, build_group
from tests.mcl.test_group_kinematics import ARMS, DELTA


class Members:
    """Every servo cycle: each member's state and model position, velocity, acceleration."""

    def __init__(self, axes: Sequence[mcl.Axis]) -> None:
        self.axes = axes
        self.rows: list[list[tuple[AxisState, float, float, float]]] = []

    def __call__(self, t: float) -> None:
        self.rows.append([(a.state, a.sp_pos, a.sp_vel, a.sp_acc) for a in self.axes])

    def released(self, i: int) -> list[tuple[AxisState, float, float, float]]:
        """Member ``i``'s rows from the first cycle it is no longer in SynchronizedMotion after
        having been in it."""
        column = [row[i] for row in self.rows]
        first = next(k for k, r in enumerate(column) if r[0] == AxisState.SynchronizedMotion)
        last = next(
            k for k in range(first, len(column)) if column[k][0] != AxisState.SynchronizedMotion
        )
        return column[last:]


def watch(machine: mcl.SimMachine, names: str) -> Members:
    members = Members([machine.axes[n] for n in names])
    machine.runtime.observers.append(members)
    return members


def test_at_the_end_of_a_path_every_member_stands_at_its_target_with_zero_rates() -> None:
    machine = make_machine(NAMES)
    group = build_group(machine)
    members = watch(machine, NAMES)
    move = mcl.MC_MoveLinearAbsolute()
    target = [40.0, -25.0, 10.0]
    program = scan(lambda: move(AxesGroup=group, Execute=True, Position=target, **MOVE))
    machine.run(program, until=lambda: move.Done, timeout=3.0)
    machine.run(program, timeout=0.02)
    for i, goal in enumerate(target):
        released = members.released(i)
        assert released, f"member {NAMES[i]} was never let go"
        assert all(r == (AxisState.StandStill, goal, 0.0, 0.0) for r in released), released[:3]


def delta_move(machine: mcl.SimMachine) -> tuple[mcl.AxesGroup, mcl.DeltaKinematics]:
    """The delta's arms grouped with a kinematics of their own (its range may be narrowed)."""
    delta = mcl.DeltaKinematics(
        DELTA.base_radius, DELTA.effector_radius, DELTA.upper_arm, DELTA.forearm
    )
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=delta)
    assert kin.Done
    return group, delta


def test_a_refused_path_point_ramps_every_arm_to_rest_and_leaves_it_there() -> None:
    """The kinematics refuses a point: each arm ramps from its last set point to standstill on
    its own fastest ramp (no velocity step beyond it), is let go at the ramp's end and holds it
    with zero rates."""
    machine = make_machine(ARMS)
    group, delta = delta_move(machine)
    members = watch(machine, ARMS)
    move = mcl.MC_MoveLinearAbsolute()
    program = scan(lambda: move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, -800.0], **MOVE))
    machine.run(program, timeout=0.1)
    delta.theta_max = max(a.sp_pos for a in group.axes) + 0.5
    machine.run(program, until=lambda: move.Error, timeout=0.5)
    machine.run(program, timeout=0.02)
    assert move.ErrorID == ErrorID.EWorkspace
    for i, axis in enumerate(group.axes):
        released = members.released(i)
        held = released[0][1]  # where the ramp ended
        assert all(r[1:] == (held, 0.0, 0.0) for r in released), released[:3]
        column = [row[i] for row in members.rows]
        ramp = axis.max_ramp().deceleration * axis.servo_period * (1.0 + 1e-9)
        assert all(abs(b[2] - a[2]) <= ramp for a, b in itertools.pairwise(column))
        before = column[len(column) - len(released) - 1]
        assert before[0] == AxisState.SynchronizedMotion and before[2] > 0.0  # still ramping


def test_a_path_refused_at_its_first_point_leaves_the_arms_where_they_stand() -> None:
    """The range narrowed under the arms between the scan that starts the move and the first
    servo cycle: they hold the set points they had, at rest."""
    machine = make_machine(ARMS)
    group, delta = delta_move(machine)
    members = watch(machine, ARMS)
    before = [a.sp_pos for a in group.axes]
    move = mcl.MC_MoveLinearAbsolute()
    move(AxesGroup=group, Execute=True, Position=[0.0, 0.0, -800.0], **MOVE)
    assert move.Busy and all(a.state == AxisState.SynchronizedMotion for a in group.axes)
    delta.theta_max = -1.0  # every arm stands at 0 deg: the first point is already refused
    machine.run(scan(lambda: move(AxesGroup=group, Execute=True)), timeout=0.02)
    assert move.ErrorID == ErrorID.EWorkspace
    assert all(row[i][1:] == (before[i], 0.0, 0.0) for row in members.rows for i in range(3))


def test_ungrouping_after_a_group_stop_leaves_every_member_at_its_set_point() -> None:
    """A group stop holds the members in SynchronizedMotion at the stop point; ungrouping lets
    them go there, at rest."""
    machine = make_machine(NAMES)
    group = build_group(machine)
    members = watch(machine, NAMES)
    move, stop = mcl.MC_MoveLinearAbsolute(), mcl.MC_GroupStop()
    ungroup = mcl.MC_UngroupAllAxes()
    move(AxesGroup=group, Execute=True, Position=[200.0, 100.0, 50.0], **MOVE)
    machine.run(scan(lambda: move(AxesGroup=group, Execute=True)), timeout=0.3)
    machine.run(
        scan(lambda: stop(AxesGroup=group, Execute=True, Deceleration=4000.0)),
        until=lambda: stop.Done,
        timeout=1.0,
    )
    assert group.state == GroupState.GroupStopping
    assert all(a.state == AxisState.SynchronizedMotion for a in group.axes)
    held = [a.sp_pos for a in group.axes]
    axes = list(group.axes)
    machine.run(scan(lambda: ungroup(AxesGroup=group, Execute=True)), until=lambda: ungroup.Done)
    machine.run(timeout=0.02)
    for i in range(len(NAMES)):
        released = members.released(i)
        assert all(r == (AxisState.StandStill, held[i], 0.0, 0.0) for r in released), released[:3]
    assert all(a.group is None for a in axes)


def test_a_move_buffered_in_the_scan_that_ungroups_starts_from_rest_at_the_held_point() -> None:
    """The member let go by the ungrouping is still active for one cycle: a buffered move
    queued behind it starts where it holds, from set velocity and acceleration 0."""
    machine = make_machine(NAMES)
    group = build_group(machine)
    x = machine.axes["X"]
    members = watch(machine, "X")
    move, stop = mcl.MC_MoveLinearAbsolute(), mcl.MC_GroupStop()
    ungroup, relative = mcl.MC_UngroupAllAxes(), mcl.MC_MoveRelative()
    move(AxesGroup=group, Execute=True, Position=[200.0, 100.0, 50.0], **MOVE)
    machine.run(scan(lambda: move(AxesGroup=group, Execute=True)), timeout=0.3)
    machine.run(
        scan(lambda: stop(AxesGroup=group, Execute=True, Deceleration=4000.0)),
        until=lambda: stop.Done,
        timeout=1.0,
    )
    held = x.sp_pos

    def program() -> None:
        ungroup(AxesGroup=group, Execute=True)
        relative(
            Axis=x,
            Execute=ungroup.Done,
            Distance=10.0,
            Velocity=50.0,
            Acceleration=500.0,
            Deceleration=500.0,
            Jerk=10000.0,
            BufferMode=mcl.MC_BufferMode.Buffered,
        )

    program()
    assert ungroup.Done and relative.Busy and x.state == AxisState.SynchronizedMotion
    machine.run(program, until=lambda: relative.Done, timeout=2.0)
    first = members.released(0)[0]
    assert first == (AxisState.DiscreteMotion, held, 0.0, 0.0)
    assert x.sp_pos == held + 10.0

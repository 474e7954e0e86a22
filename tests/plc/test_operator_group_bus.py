"""The group front end of the operator program on simulated axes and a real signal table (the
gantry's group block): grouping by the enable level, a line held Done until the master clears its
bit, a pulse, an error held with its ErrorID, the path table's commands, a method call held until
the next command (a held stop released before it), the master out of control. Positions are
measured on the simulated carriages."""

from __future__ import annotations

from typing import Any

import pytest

import mcl
import plc.operator.group
from mcl.enums import MC_COORD_SYSTEM
from plc.operator.group import GroupOperator, GroupOrders
from plc.operator.group_bus import GROUP_CONTROL_BITS, GROUP_STATUS_BITS, GroupWords
from scenes.bridge.table import AxisRegisters
from tests.helpers import carriage_mm, make_machine
from tests.mcl.test_group_kinematics import ARMS, DELTA
from tests.plc.test_operator_bus import Bus

MOVE = {"velocity": 200.0, "acceleration": 2000.0, "deceleration": 2000.0, "jerk": 20000.0}


def bits(*names: str) -> int:
    return sum(1 << GROUP_CONTROL_BITS.index(name) for name in names)


class GroupBus(Bus):
    """The gantry's table over three simulated axes X, Y, Z (powered by their own MC_Power,
    referenced at 0 mm), the group driven by its command words; published after every scan."""

    BLOCK = "group"
    STATUS = GROUP_STATUS_BITS

    def front_end(self, axes: list[mcl.Axis]) -> Any:
        self.operator = GroupOperator("group", axes)
        return GroupWords(self.operator, AxisRegisters(self.table, self.BLOCK))

    def at(self) -> list[float]:
        """The carriages X, Y, Z [mm]."""
        return [carriage_mm(self.machine, a) for a in "XYZ"]


@pytest.fixture
def bus() -> GroupBus:
    bus = GroupBus()
    assert not bus.status("enabled")
    bus.write(control=bits("enable"), **MOVE)
    bus.run(0.05)
    return bus


def test_the_enable_level_groups_the_axes_and_its_fall_takes_them_apart(bus: GroupBus) -> None:
    assert bus.status("enabled") and bus.get("state") == mcl.GroupState.GroupStandby
    assert bus.operator.group.axes == [bus.machine.axes[a] for a in "XYZ"]
    assert bus.get("command_count") == 0  # the level starts no command
    bus.write(control=0)
    bus.run(0.05)
    assert not bus.status("enabled") and not bus.operator.group.axes


def test_a_line_is_held_done_until_the_master_clears_its_bit(bus: GroupBus) -> None:
    bus.write(end_1=30.0, end_2=40.0, end_3=-10.0, control=bits("enable", "move_linear"))
    bus.run(0.01)
    assert bus.status("busy") and bus.status("active") and bus.get("command_count") == 1
    assert bus.get("command") == 1 + GROUP_CONTROL_BITS.index("move_linear")
    assert bus.words.current is bus.operator.linear[0]  # absolute
    bus.run(1.5)
    assert bus.at() == pytest.approx([30.0, 40.0, -10.0], abs=0.05)
    assert bus.status("done") and not bus.status("busy") and bus.status("in_position")
    actual = [bus.get(f"actual_{k}") for k in (1, 2, 3)]
    assert actual == pytest.approx([30.0, 40.0, -10.0], abs=0.05)
    bus.write(control=bits("enable"))  # the acknowledgement
    bus.run(0.004)
    assert not bus.status("done") and bus.get("command_count") == 1


def test_a_pulse_keeps_its_result_until_the_next_command(bus: GroupBus) -> None:
    bus.write(relative=1, end_1=20.0, end_2=-20.0, control=bits("enable", "move_linear"))
    bus.write(control=bits("enable"))  # cleared before a scan saw the bit
    bus.run(1.0)
    assert bus.at() == pytest.approx([20.0, -20.0, 0.0], abs=0.05)
    assert bus.words.current is bus.operator.linear[1]  # relative
    assert bus.status("done")  # not acknowledged: never published while the bit was set
    bus.write(control=bits("enable", "move_linear"))
    bus.run(0.004)
    assert not bus.status("done") and bus.get("command_count") == 2
    bus.run(1.0)
    assert bus.at() == pytest.approx([40.0, -40.0, 0.0], abs=0.05)


def test_an_error_is_held_with_its_id_until_acknowledged(bus: GroupBus) -> None:
    bus.write(circ_mode=mcl.MC_CIRC_MODE.BORDER, aux_1=10.0, end_1=20.0)  # collinear
    bus.write(relative=1, control=bits("enable", "move_circular"))
    bus.run(0.01)
    assert bus.status("error") and bus.get("error_id") == mcl.ErrorID.EParam
    assert bus.at() == pytest.approx([0.0, 0.0, 0.0], abs=0.01)
    bus.run(0.1)
    assert bus.status("error")
    bus.write(control=bits("enable"))
    bus.run(0.01)
    assert not bus.status("error") and bus.get("error_id") == 0


def test_the_path_table_is_appended_cleared_and_refuses_a_segment_too_many(
    bus: GroupBus, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(plc.operator.group, "MAX_SEGMENTS", 2)
    table = bus.table
    bus.write(relative=1)
    table.request("group", "append_line", {"end_1": 10.0})
    bus.run(0.004)
    assert bus.status("done") and bus.get("segments") == 1
    table.request("group", "append_arc", {"end_1": 20.0, "aux_1": 5.0, "circ_mode": 2})
    bus.run(0.004)
    assert bus.get("segments") == 2 and bus.get("command_count") == 2
    segment = bus.operator.path.Segments[1]
    assert segment.Circular and segment.Relative and segment.CircMode == 2
    assert list(segment.AuxPoint) == [5.0, 0.0, 0.0] and segment.Velocity == MOVE["velocity"]
    table.request("group", "append_line", {"end_1": 30.0})  # full
    bus.run(0.004)
    assert bus.status("error") and bus.get("error_id") == mcl.ErrorID.EParam
    assert bus.get("segments") == 2
    bus.write(control=bits("enable", "clear_path"))
    bus.run(0.004)
    assert bus.status("done") and not bus.status("error") and bus.get("segments") == 0
    assert bus.get("command") == 1 + GROUP_CONTROL_BITS.index("clear_path")


def test_a_path_runs_its_segments(bus: GroupBus) -> None:
    table = bus.table
    bus.write(relative=1, buffer_mode=mcl.MC_BufferMode.BlendingLow)
    for end in ((20.0, 0.0), (0.0, 15.0), (-5.0, 0.0)):
        table.request("group", "append_line", {"end_1": end[0], "end_2": end[1]})
        bus.run(0.004)
    table.request("group", "move_path")
    bus.run(2.0)
    assert bus.status("done") and bus.get("error_id") == 0
    assert bus.at() == pytest.approx([15.0, 15.0, 0.0], abs=0.05)


def test_a_called_stop_holds_the_group_until_the_next_command_which_is_taken(
    bus: GroupBus,
) -> None:
    table = bus.table
    table.request("group", "move_linear", {"relative": 1, "end_1": 500.0})
    bus.run(0.3)
    assert bus.status("busy") and bus.operator.linear[1].Execute
    table.request("group", "stop")
    bus.run(0.5)
    assert bus.status("done") and bus.get("state") == mcl.GroupState.GroupStopping
    start = bus.at()
    assert 0.0 < start[0] < 500.0
    bus.write(relative=1, end_1=10.0, control=bits("enable", "move_linear"))
    bus.run(0.002)  # one scan: the stop's Execute falls first, the move waits
    assert not bus.operator.stop.Execute and not bus.operator.linear[1].Execute
    bus.run(0.002)
    assert bus.operator.linear[1].Execute and bus.status("busy")
    assert bus.get("state") == mcl.GroupState.GroupMoving
    bus.run(1.0)
    assert bus.status("done") and bus.get("error_id") == 0
    assert bus.at()[0] - start[0] == pytest.approx(10.0, abs=0.05)


def test_out_of_control_the_group_is_left_alone_and_old_edges_are_dropped(bus: GroupBus) -> None:
    bus.write(relative=1, end_1=20.0, control=bits("enable", "move_linear"))
    bus.table.in_control = False
    bus.run(1.0)
    assert bus.at() == pytest.approx([0.0, 0.0, 0.0], abs=0.01)
    bus.table.in_control = True
    bus.run(0.5)  # the bit was set while out of control: no edge
    assert bus.at() == pytest.approx([0.0, 0.0, 0.0], abs=0.01)
    assert bus.get("command_count") == 0


def test_a_start_passes_every_field_to_its_block_and_segment(bus: GroupBus) -> None:
    """The fields of a start reach the block's inputs (the arc's and the ramps') and the
    segment appended; a refused append's Error and ErrorID clear when its bit falls."""
    fields = {
        "circ_mode": mcl.MC_CIRC_MODE.CENTER,
        "path_choice": mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE,
        "plane": 17,
        "turns": 1,
        "aux_1": 10.0,
        "aux_2": 2.0,
        "end_1": 3.0,
        "buffer_mode": mcl.MC_BufferMode.BlendingHigh,
        "velocity": 120.0,
        "acceleration": 1500.0,
        "deceleration": 1700.0,
        "jerk": 19000.0,
        "relative": 1,
    }
    bus.write(**fields)
    inputs = {
        "CircMode": fields["circ_mode"],
        "PathChoice": fields["path_choice"],
        "Plane": 17,
        "Turns": 1,
        "Velocity": 120.0,
        "Acceleration": 1500.0,
        "Deceleration": 1700.0,
        "Jerk": 19000.0,
        "BufferMode": fields["buffer_mode"],
    }
    bus.table.request("group", "append_arc")
    bus.run(0.004)
    segment = bus.operator.path.Segments[0]
    assert {name: getattr(segment, name) for name in inputs} == inputs
    assert segment.Relative and segment.AuxRelative and segment.Circular
    assert list(segment.AuxPoint) == [10.0, 2.0, 0.0] and list(segment.EndPoint) == [3.0, 0, 0]
    bus.write(control=bits("enable", "move_circular"))
    bus.run(0.004)
    block = bus.operator.circular[1]
    assert {name: getattr(block, name) for name in inputs} == inputs
    assert list(block.AuxPoint) == [10.0, 2.0, 0.0]
    bus.write(control=bits("enable", "stop"))
    bus.run(0.004)
    assert (bus.operator.stop.Deceleration, bus.operator.stop.Jerk) == (1700.0, 19000.0)
    bus.write(control=bits("enable"))
    bus.run(0.5)
    append = bus.operator.append_line
    bus.operator.path.Segments[:] = [segment] * plc.operator.group.MAX_SEGMENTS  # full
    bus.write(control=bits("enable", "append_line"))
    bus.run(0.004)
    assert append.Error and append.ErrorID == mcl.ErrorID.EParam and not append.Done
    bus.write(control=bits("enable"))
    bus.run(0.004)
    assert not append.Error and append.ErrorID == 0 and not append.Done
    bus.operator.path.Segments.clear()
    bus.write(control=bits("enable", "append_line"))
    bus.run(0.004)
    assert append.Done and not append.Error
    bus.write(control=bits("enable"))
    bus.run(0.004)
    assert not append.Done


def test_the_bridges_group_moves_a_robot_in_acs_or_mcs() -> None:
    """The operator program of a group with the delta's kinematics (the bridge's group block):
    enabled, it sets the kinematics; a line with coord_system MCS runs the tool point to its
    target, one with ACS the arms to theirs."""
    machine = make_machine(ARMS)
    operator = GroupOperator("delta", [machine.axes[n] for n in ARMS], DELTA)
    orders = GroupOrders(True, frozenset({"move_linear"}))
    machine.run(lambda: operator(GroupOrders(enable=True)), timeout=0.05)
    assert operator.group.kin.transform is DELTA
    target = [100.0, -50.0, -700.0]
    for coord, end, where in (
        (MC_COORD_SYSTEM.MCS, target, DELTA.forward),
        (MC_COORD_SYSTEM.ACS, [10.0, 20.0, 5.0], list),
    ):
        values = {"coord_system": float(coord), "velocity": 500.0, "acceleration": 5000.0}
        values |= {"deceleration": 5000.0, "jerk": 200000.0, "buffer_mode": 0.0, "relative": 0.0}
        values |= {f"end_{k + 1}": x for k, x in enumerate(end)}
        start = GroupOrders(True, frozenset({"move_linear"}), {"move_linear": values.__getitem__})
        operator(start)
        machine.run(lambda: operator(orders), until=lambda: operator.move_linear.Done, timeout=2)
        assert where([machine.axes[n].sp_pos for n in ARMS]) == pytest.approx(end, abs=1e-6)


def test_the_bridges_group_tracks_a_belt_and_sets_a_fixed_frame() -> None:
    """track_belt: the PCS moves with the belt (its axis number among the operator's axes) from
    the frame, the part and the latch of its parameters; the tool point then follows the part.
    A belt number of no axis gives no belt: EParam. set_frame: a fixed PCS turned about z."""
    machine = make_machine(ARMS + "D")
    axes = [machine.axes[n] for n in ARMS + "D"]
    operator = GroupOperator("delta", axes[:3], DELTA, axes)
    machine.run(lambda: operator(GroupOrders(enable=True)), timeout=0.05)
    belt = axes[3]
    run = mcl.MC_MoveVelocity(Axis=belt, Velocity=100.0, Acceleration=2000.0)
    machine.run(lambda: run(Execute=True), until=lambda: run.InVelocity, timeout=1.0)
    values = {"frame_1": -300.0, "frame_2": -100.0, "frame_3": -760.0, "frame_rz": 10.0}
    values |= {"object_1": 5.0, "object_2": -4.0, "object_3": 3.0, "horizon": 0.5}
    values |= {"belt": 7.0, "latched_position": belt.sp_pos - 20.0}
    values |= {"acceleration": 3000.0, "jerk": 1.0e5}

    def track(belt_number: float) -> mcl.MC_TrackConveyorBelt:
        params = {**values, "belt": belt_number}.__getitem__
        operator(GroupOrders(True, frozenset({"track_belt"}), {"track_belt": params}))
        orders = GroupOrders(True, frozenset({"track_belt"}))
        fb = operator.track_belt

        def scan() -> None:
            operator(orders)
            run()

        machine.run(scan, until=lambda: fb.Done or fb.Error, timeout=2)
        return fb

    for number in (4.0, -1.0, 0.0):  # no axis (4 axes: 0 … 3); a member of the group
        assert track(number).ErrorID == mcl.ErrorID.EParam and operator.group.kin.frame is None
        operator(GroupOrders(enable=True))
    assert track(3.0).Done
    frame = operator.group.kin.frame
    assert frame is not None and frame.master is belt and frame.latch == values["latched_position"]
    assert (frame.origin, frame.angle, frame.offset) == (
        [-300.0, -100.0, -760.0],
        10.0,
        [5.0, -4.0, 3.0],
    )
    fixed = {**values, "frame_1": 20.0, "frame_2": 0.0, "frame_3": -700.0, "frame_rz": -30.0}
    operator(GroupOrders(enable=True))
    operator(GroupOrders(True, frozenset({"set_frame"}), {"set_frame": fixed.__getitem__}))
    orders = GroupOrders(True, frozenset({"set_frame"}))
    done = lambda: operator.set_frame.Done or operator.set_frame.Error  # noqa: E731

    def scan() -> None:
        operator(orders)
        run()

    machine.run(scan, until=done, timeout=2)
    frame = operator.group.kin.frame
    assert operator.set_frame.Done and frame is not None and not frame.moving
    assert (frame.origin, frame.angle) == ([20.0, 0.0, -700.0], -30.0)

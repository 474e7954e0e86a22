"""The control blocks of axes groups (PLCopen Part 4: MC_GroupHalt, MC_GroupInterrupt,
MC_GroupContinue, MC_GroupSetOverride, MC_GroupSetPosition, MC_GroupReadActualVelocity,
MC_GroupReadActualAcceleration, MC_GroupReadConfiguration) on simulated axes, scan by scan: the
blocks' outputs (Tab. 2.3), the group state, the feed hold and the override on the path, and the
inputs that are refused without touching the group."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import Any

import pytest

import mcl
from mcl import MC_CIRC_MODE, MC_CIRC_PATHCHOICE, AxisState, ErrorID, GroupState
from tests.helpers import make_machine
from tests.mcl.test_fb_rules import exclusive
from tests.mcl.test_group import Recorder, build_group, record

V, ACC, JERK = 100.0, 2000.0, 50000.0
DYN = dict(Velocity=V, Acceleration=ACC, Deceleration=ACC, Jerk=JERK)
DT = 0.001
"""The servo period of the simulated axes [s]."""
HOLD_DEC, HOLD_JERK = 1000.0, 20000.0
"""The feed hold's deceleration [mm/s²] and jerk [mm/s³] along the path."""
CENTRE, RADIUS = (0.0, 10.0), 10.0


@pytest.fixture
def xy() -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    """Two powered, referenced axes X, Y at 0 mm in an enabled group."""
    machine = make_machine("XY")
    return machine, build_group(machine, "XY")


def full_circle(group: mcl.AxesGroup) -> mcl.MC_MoveCircularAbsolute:
    """A full counter-clockwise circle of radius 10 mm around (0, 10) from and to (0, 0)."""
    return mcl.MC_MoveCircularAbsolute(
        AxesGroup=group,
        CircMode=MC_CIRC_MODE.CENTER,
        AuxPoint=list(CENTRE),
        EndPoint=[0.0, 0.0],
        PathChoice=MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE,
        **DYN,
    )


def radius_error(rec: Recorder) -> float:
    return max(abs(math.dist(p, CENTRE) - RADIUS) for p in rec.model)


def scans(machine: mcl.SimMachine, program: Callable[[], None], seconds: float) -> None:
    end = machine.runtime.time + seconds
    machine.run(program, until=lambda: machine.runtime.time >= end - 1e-9, timeout=seconds + 1)


class FeedHold:
    """A program: a full circle, MC_GroupInterrupt and MC_GroupContinue with their Execute set
    by the test, every block checked for Tab. 2.3's exclusive outputs on every scan."""

    def __init__(self, group: mcl.AxesGroup, **hold: Any) -> None:
        self.move = full_circle(group)
        ramp = {"Deceleration": HOLD_DEC, "Jerk": HOLD_JERK, **hold}
        self.hold = mcl.MC_GroupInterrupt(AxesGroup=group, **ramp)
        self.cont = mcl.MC_GroupContinue(AxesGroup=group)
        self.interrupt = False
        self.resume = False

    def __call__(self) -> None:
        self.move(Execute=True)
        self.hold(Execute=self.interrupt)
        self.cont(Execute=self.resume)
        for block in (self.move, self.hold, self.cont):
            exclusive(block)


# ---------------------------------------------------------------------- feed hold
def test_feed_hold_on_an_arc_resumes_from_the_held_point_to_the_same_end(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """MC_GroupInterrupt mid-circle: the group slows down on the circle within the hold's
    deceleration, stands (GroupStandby, Interrupt Done) while the interrupted move stays Busy and
    Active without CommandAborted; MC_GroupContinue resumes it from the held point and the circle
    ends where it ends without the hold, never leaving the circle."""
    machine, group = xy
    rec = record(machine, "XY")
    program = FeedHold(group)
    scans(machine, program, 0.25)
    assert math.hypot(*rec.velocity[-1]) == pytest.approx(V)
    program.interrupt = True
    program()
    assert program.hold.Busy and not program.hold.Done
    ramp = len(rec.model)
    machine.run(program, until=lambda: program.hold.Done, timeout=2.0)
    assert group.state == GroupState.GroupStandby
    assert all(a.state == AxisState.SynchronizedMotion for a in group.axes)
    move = program.move
    assert move.Busy and move.Active and not (move.CommandAborted or move.Done or move.Error)
    speeds = rec.speeds()
    assert speeds[-1] == 0.0
    rates = [(b - a) / DT for a, b in itertools.pairwise(speeds[ramp - 1 :])]
    assert min(rates) >= -HOLD_DEC * 1.001  # slowed down with the hold's deceleration
    assert min(rates) < -HOLD_DEC * 0.95
    jerks = [(b - a) / DT for a, b in itertools.pairwise(rates)]
    assert max(abs(j) for j in jerks) <= HOLD_JERK * 1.5 + 1.0  # jerk-limited (module doc)
    held = rec.model[-1]
    held_at = len(rec.model)
    scans(machine, program, 0.3)  # the hold
    assert all(p == held for p in rec.model[held_at:])
    assert move.Busy and move.Active and group.state == GroupState.GroupStandby
    program.interrupt = False
    program.resume = True
    resumed_at = len(rec.model)
    machine.run(program, until=lambda: move.Done, timeout=5.0)
    first = next(p for p in rec.model[resumed_at:] if p != held)
    assert math.dist(first, held) < 0.010  # resumed from the held point
    assert program.cont.Done or not program.cont.Busy
    assert rec.model[-1] == pytest.approx((0.0, 0.0), abs=1e-9)
    assert radius_error(rec) < 1e-9
    assert max(rec.speeds()[resumed_at:]) == pytest.approx(V)
    travelled = sum(math.dist(a, b) for a, b in itertools.pairwise(rec.model))
    assert travelled == pytest.approx(2 * math.pi * RADIUS, abs=0.01)  # no part run twice
    machine.run(program, timeout=0.02)
    assert group.state == GroupState.GroupStandby
    assert all(a.state == AxisState.StandStill for a in group.axes)


def test_interrupt_and_continue_outputs(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """Done of the interrupt held while Execute stays TRUE, one scan after an early falling
    edge; Continue Done once the path runs at full speed again; neither reports an error."""
    machine, group = xy
    program = FeedHold(group)
    scans(machine, program, 0.2)
    program.interrupt = True
    program()
    program.interrupt = False
    dones: list[bool] = []

    def scan() -> None:
        program()
        dones.append(program.hold.Done)

    machine.run(scan, until=lambda: not program.hold.Busy, timeout=2.0)
    scans(machine, scan, 0.05)
    assert dones.count(True) == 1 and not program.hold.Error
    program.resume = True
    program()
    assert program.cont.Busy and not program.cont.Done
    machine.run(program, until=lambda: program.cont.Done, timeout=2.0)
    assert math.hypot(*(a.sp_vel for a in group.axes)) == pytest.approx(V)
    assert program.move.Busy and not program.move.Done


def test_moves_are_refused_while_held_and_a_stop_ends_the_hold() -> None:
    """While held: a move, MC_GroupHalt, a second interrupt → EAxStop, MC_GroupSetPosition and
    MC_AddAxisToGroup → EParam, the group left as it was; MC_GroupStop ends the hold and the
    interrupted move (CommandAborted), MC_GroupContinue then has nothing to resume (EParam)."""
    machine = make_machine("XYZ")
    group = build_group(machine, "XY")
    program = FeedHold(group)
    scans(machine, program, 0.2)
    program.interrupt = True
    machine.run(program, until=lambda: program.hold.Done, timeout=2.0)
    held = [a.sp_pos for a in group.axes]
    line = mcl.MC_MoveLinearRelative(AxesGroup=group, Distance=[1.0, 0.0], **DYN)
    halt = mcl.MC_GroupHalt(AxesGroup=group)
    again = mcl.MC_GroupInterrupt(AxesGroup=group)
    shift = mcl.MC_GroupSetPosition(AxesGroup=group, Position=[0.0, 0.0])
    for block in (line, halt, again):
        block(Execute=True)
        assert block.Error and block.ErrorID == ErrorID.EAxStop
    shift(Execute=True)
    assert shift.Error and shift.ErrorID == ErrorID.EParam
    add = mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=machine.axes["Z"])
    add(Execute=True)
    assert add.Error and add.ErrorID == ErrorID.EParam and len(group.axes) == 2
    scans(machine, program, 0.05)
    assert [a.sp_pos for a in group.axes] == held and program.move.Active
    stop = mcl.MC_GroupStop(AxesGroup=group)
    stop(Execute=True)
    scans(machine, program, 0.01)
    assert program.move.CommandAborted and not program.move.Busy
    assert group.state == GroupState.GroupStopping
    assert [a.sp_pos for a in group.axes] == pytest.approx(held, abs=1e-12)
    stop(Execute=False)
    program.interrupt = False
    program.resume = True
    program()
    assert program.cont.Error and program.cont.ErrorID == ErrorID.EParam
    assert group.state == GroupState.GroupStandby


@pytest.mark.parametrize("ender", [mcl.MC_GroupStop, mcl.MC_GroupDisable])
def test_a_stop_during_the_hold_ramp_aborts_the_interrupt(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], ender: Any
) -> None:
    machine, group = xy
    program = FeedHold(group)
    scans(machine, program, 0.2)
    program.interrupt = True
    scans(machine, program, 0.02)
    stop = ender(AxesGroup=group)
    stop(Execute=True)
    program()
    assert program.hold.CommandAborted and not program.hold.Done
    assert program.move.CommandAborted


@pytest.mark.parametrize(
    ("inputs", "code"),
    [
        ({"Deceleration": -1.0}, ErrorID.EParam),
        ({"Jerk": math.nan}, ErrorID.EParam),
    ],
)
def test_interrupt_parameter_errors_leave_the_group_alone(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], inputs: dict[str, float], code: int
) -> None:
    machine, group = xy
    program = FeedHold(group, **inputs)
    scans(machine, program, 0.2)
    program.interrupt = True
    scans(machine, program, 0.2)
    assert program.hold.Error and program.hold.ErrorID == code
    assert math.hypot(*(a.sp_vel for a in group.axes)) == pytest.approx(V)


def test_interrupt_of_a_standing_group_is_done_at_once(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    _, group = xy
    hold = mcl.MC_GroupInterrupt(AxesGroup=group)
    hold(Execute=True)
    assert hold.Done and not group.interrupted
    disabled = mcl.AxesGroup()
    hold = mcl.MC_GroupInterrupt(AxesGroup=disabled)
    hold(Execute=True)
    assert hold.Error and hold.ErrorID == ErrorID.EGroupEmpty


# ---------------------------------------------------------------------- override
def test_override_halves_the_speed_on_the_same_contour(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """VelFactor 0.5 in the middle of a circle: the path velocity ramps (within the members'
    default deceleration) to half the commanded one and the circle is drawn exactly; back to
    1.0 it ramps up again; the move ends at its end point."""
    machine, group = xy
    rec = record(machine, "XY")
    move = full_circle(group)
    override = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, VelFactor=1.0)

    def program() -> None:
        move(Execute=True)
        override()

    scans(machine, program, 0.25)
    assert math.hypot(*rec.velocity[-1]) == pytest.approx(V)
    override.VelFactor = 0.5
    program()
    assert override.Enabled and override.Busy and not override.Error
    start = len(rec.model)
    scans(machine, program, 0.25)
    assert math.hypot(*rec.velocity[-1]) == pytest.approx(V / 2)
    rates = [(b - a) / DT for a, b in itertools.pairwise(rec.speeds()[start - 1 :])]
    decel = group.axes[0].config.deceleration
    assert max(abs(r) for r in rates) <= decel * 1.001
    assert group.state == GroupState.GroupMoving
    override.VelFactor = 1.0
    machine.run(program, until=lambda: move.Done, timeout=5.0)
    assert rec.model[-1] == pytest.approx((0.0, 0.0), abs=1e-9)
    assert radius_error(rec) < 1e-9
    travelled = sum(math.dist(a, b) for a, b in itertools.pairwise(rec.model))
    assert travelled == pytest.approx(2 * math.pi * RADIUS, abs=0.01)


def test_override_from_rest_takes_effect_at_once(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    override = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, VelFactor=0.5)
    override()
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[30.0, 40.0], **DYN)
    peak = 0.0

    def program() -> None:
        nonlocal peak
        line(Execute=True)
        override()
        peak = max(peak, math.hypot(*(a.sp_vel for a in group.axes)))

    machine.run(program, until=lambda: line.Done, timeout=5.0)
    assert peak == pytest.approx(V / 2)
    assert [a.sp_pos for a in group.axes] == pytest.approx([30.0, 40.0], abs=1e-9)


@pytest.mark.parametrize(
    "inputs",
    [
        {"VelFactor": -0.1},
        {"VelFactor": 2.5},
        {"VelFactor": math.inf},
        {"AccFactor": -1.0},
        {"JerkFactor": math.nan},
    ],
)
def test_override_errors_keep_the_previous_factor(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], inputs: dict[str, float]
) -> None:
    _, group = xy
    good = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, VelFactor=0.8)
    good()
    bad = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, **inputs)
    bad()
    assert bad.Error and bad.ErrorID == ErrorID.EParam and not (bad.Enabled or bad.Busy)
    assert group.clock.override == 0.8
    bad(Enable=False)
    assert not (bad.Error or bad.Enabled)
    empty = mcl.MC_GroupSetOverride(AxesGroup=mcl.AxesGroup(), Enable=True)
    empty()
    assert empty.Error and empty.ErrorID == ErrorID.EGroupEmpty


# ---------------------------------------------------------------------- halt
def test_halt_stops_on_the_circle_and_returns_to_standby(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """MC_GroupHalt aborts the circle (CommandAborted), ramps down on it with its deceleration,
    the group GroupMoving meanwhile (not GroupStopping), GroupStandby once Done."""
    machine, group = xy
    rec = record(machine, "XY")
    move = full_circle(group)
    halt = mcl.MC_GroupHalt(AxesGroup=group, Deceleration=500.0)
    scans(machine, lambda: move(Execute=True), 0.2)
    halt(Execute=True)
    move()
    assert move.CommandAborted and halt.Busy and halt.Active
    assert group.state == GroupState.GroupMoving
    start = len(rec.model)
    machine.run(lambda: halt(), until=lambda: halt.Done, timeout=2.0)
    assert group.state == GroupState.GroupStandby
    rates = [(b - a) / DT for a, b in itertools.pairwise(rec.speeds()[start - 1 :])]
    assert min(rates) >= -500.0 * 1.001
    assert radius_error(rec) < 1e-9
    halt(Execute=False)
    assert not (halt.Done or halt.Busy)


def test_a_move_aborts_a_halt(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """Unlike MC_GroupStop, MC_GroupHalt does not block: a move during its ramp aborts it."""
    machine, group = xy
    move = full_circle(group)
    halt = mcl.MC_GroupHalt(AxesGroup=group, Deceleration=200.0)
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[5.0, 5.0], **DYN)
    scans(machine, lambda: move(Execute=True), 0.2)
    scans(machine, lambda: halt(Execute=True), 0.05)
    assert halt.Busy
    line(Execute=True)
    halt()
    assert not line.Error and line.Busy and halt.CommandAborted
    machine.run(lambda: line(), until=lambda: line.Done, timeout=3.0)
    assert [a.sp_pos for a in group.axes] == pytest.approx([5.0, 5.0], abs=1e-9)


def test_halt_errors(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    _, group = xy
    for inputs in ({"Deceleration": -1.0}, {"Jerk": math.inf}, {"BufferMode": 1}):
        halt = mcl.MC_GroupHalt(AxesGroup=group, **inputs)
        halt(Execute=True)
        assert halt.Error and halt.ErrorID == ErrorID.EParam
    stop = mcl.MC_GroupStop(AxesGroup=group)
    stop(Execute=True)
    halt = mcl.MC_GroupHalt(AxesGroup=group)
    halt(Execute=True)
    assert halt.Error and halt.ErrorID == ErrorID.EAxStop
    group.disable()
    halt(Execute=False)
    halt(Execute=True)
    assert halt.Error and halt.ErrorID == ErrorID.Epower


# ---------------------------------------------------------------------- set position
def test_set_position_shifts_the_group_coordinates(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """Absolute: the actual positions become Position; Relative: they move by it; a following
    move runs in the new coordinates; no motion."""
    machine, group = xy
    x, y = group.axes
    shift = mcl.MC_GroupSetPosition(AxesGroup=group, Position=[100.0, -50.0])
    shift(Execute=True)
    assert shift.Done and not shift.Busy
    assert (x.actual, y.actual) == pytest.approx((100.0, -50.0), abs=1e-9)
    shift(Execute=False)
    shift(Execute=True)  # again from there: the same coordinates
    assert (x.actual, y.actual) == pytest.approx((100.0, -50.0), abs=1e-9)
    shown = (x.POS, y.POS)
    assert shown == pytest.approx((100.0, -50.0), abs=1e-9)
    shift(Execute=False)
    assert not shift.Done
    relative = mcl.MC_GroupSetPosition(AxesGroup=group, Position=[1.0, 2.0], Relative=True)
    relative(Execute=True)
    shown = (x.POS, y.POS)
    assert shown == pytest.approx((101.0, -48.0), abs=1e-9)
    assert x.state == y.state == AxisState.StandStill
    assert group.state == GroupState.GroupStandby
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[111.0, -48.0], **DYN)
    machine.run(lambda: line(Execute=True), until=lambda: line.Done, timeout=3.0)
    assert x.actual == pytest.approx(111.0, abs=0.05) and y.actual == pytest.approx(-48.0, abs=0.05)


@pytest.mark.parametrize(
    "inputs",
    [
        {"Position": [1.0]},
        {"Position": [1.0, math.nan]},
        {"Position": "ab"},
        {"Position": [0.0, 0.0], "CoordSystem": 7},
    ],
)
def test_set_position_parameter_errors(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], inputs: dict[str, Any]
) -> None:
    _, group = xy
    before = [a.actual for a in group.axes]
    shift = mcl.MC_GroupSetPosition(AxesGroup=group, **inputs)
    shift(Execute=True)
    assert shift.Error and shift.ErrorID == ErrorID.EParam
    assert [a.actual for a in group.axes] == before


def test_set_position_is_refused_while_the_group_moves(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    move = full_circle(group)
    scans(machine, lambda: move(Execute=True), 0.1)
    shift = mcl.MC_GroupSetPosition(AxesGroup=group, Position=[0.0, 0.0])
    before = [a.sp_pos for a in group.axes]
    shift(Execute=True)
    assert shift.Error and shift.ErrorID == ErrorID.EParam
    assert [a.sp_pos for a in group.axes] == before and move.Active
    stop = mcl.MC_GroupStop(AxesGroup=group)
    stop(Execute=True)
    machine.run(lambda: stop(), until=lambda: stop.Done, timeout=2.0)
    shift(Execute=False)
    shift(Execute=True)
    assert shift.Error and shift.ErrorID == ErrorID.EAxStop  # GroupStopping
    empty = mcl.MC_GroupSetPosition(AxesGroup=mcl.AxesGroup(), Position=[])
    empty(Execute=True)
    assert empty.Error and empty.ErrorID == ErrorID.EGroupEmpty


def test_set_position_beyond_a_software_limit_changes_nothing() -> None:
    machine = make_machine("XY", LimPos=50.0, LimNeg=-50.0)
    x, y = (machine.axes[n] for n in "XY")
    group = build_group(machine, "XY")
    shift = mcl.MC_GroupSetPosition(AxesGroup=group, Position=[10.0, 80.0])
    before = (x.actual, y.actual)
    shift(Execute=True)
    assert shift.Error and shift.ErrorID == ErrorID.Ecil
    assert (x.actual, y.actual) == before


# ---------------------------------------------------------------------- read-outs
def test_read_velocity_acceleration_and_configuration(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    x, y = group.axes
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[30.0, 40.0], **DYN)
    velocity = mcl.MC_GroupReadActualVelocity(AxesGroup=group, Enable=True)
    acceleration = mcl.MC_GroupReadActualAcceleration(AxesGroup=group, Enable=True)
    configuration = mcl.MC_GroupReadConfiguration(AxesGroup=group, Enable=True, IdentInGroup=2)
    samples: list[tuple[float, float]] = []

    def program() -> None:
        line(Execute=True)
        velocity()
        acceleration()
        samples.append((velocity.PathVelocity, acceleration.PathAcceleration))

    scans(machine, program, 0.01)
    acceleration()
    assert acceleration.Valid and acceleration.Acceleration == [x.sp_acc, y.sp_acc]
    assert acceleration.PathAcceleration == pytest.approx(math.hypot(x.sp_acc, y.sp_acc))
    assert acceleration.PathAcceleration > 0.0
    machine.run(program, until=lambda: line.Done, timeout=3.0)
    assert velocity.Valid and not velocity.Error
    peak = max(samples)[0]
    assert peak == pytest.approx(V, rel=0.05)
    assert min(s[1] for s in samples) < 0.0  # slowing down reads negative
    scans(machine, program, 0.3)
    velocity()
    assert velocity.Velocity == [x.VEL, y.VEL]
    assert velocity.PathVelocity == pytest.approx(0.0, abs=1e-3)
    assert acceleration.PathAcceleration == 0.0
    configuration()
    assert configuration.Valid and configuration.Member is y
    configuration(IdentInGroup=3)
    assert configuration.Error and configuration.ErrorID == ErrorID.EParam
    assert configuration.Member is None and not configuration.Valid
    configuration(IdentInGroup=1, CoordSystem=9)
    assert configuration.ErrorID == ErrorID.EParam
    configuration(CoordSystem=mcl.MC_COORD_SYSTEM.PCS)
    assert configuration.Member is x
    velocity(Enable=False)
    assert velocity.Velocity == [] and velocity.PathVelocity == 0.0 and not velocity.Valid
    acceleration(CoordSystem=9)
    assert acceleration.ErrorID == ErrorID.EParam and acceleration.Acceleration == []
    acceleration(Enable=False, CoordSystem=mcl.MC_COORD_SYSTEM.ACS)
    assert acceleration.PathAcceleration == 0.0 and not acceleration.Error
    configuration(Enable=False)
    assert configuration.Member is None
    empty = mcl.MC_GroupReadActualVelocity(AxesGroup=mcl.AxesGroup(), Enable=True)
    empty()
    assert empty.Error and empty.ErrorID == ErrorID.EGroupEmpty and empty.Velocity == []


# ---------------------------------------------------------------------- homing
NEG, POS = mcl.MC_Direction.MC_Negative, mcl.MC_Direction.MC_Positive


def homing(set_position: float, velocity: float = 100.0) -> list[mcl.MotionFB]:
    """A REF switch and index pulse procedure: the coordinate ``set_position`` at the pulse."""
    return [
        mcl.MC_StepAbsSwitch(
            Direction=NEG, Velocity=velocity, SwitchMode=mcl.MC_SwitchMode.MC_EdgeOn
        ),
        mcl.MC_StepRefPulse(
            Direction=POS,
            Velocity=20.0,
            SetPosition=set_position,
            BufferMode=mcl.MC_BufferMode.Buffered,
        ),
    ]


def test_group_home_homes_every_member() -> None:
    """Both members run their procedures at once (GroupHoming), get Ref and the coordinate of
    their last step; Done held while Execute is TRUE; then the group moves absolutely."""
    machine = make_machine("XY", referenced=False)
    group = build_group(machine, "XY")
    x, y = group.axes
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[10.0, 10.0], **DYN)
    line(Execute=True)
    assert line.Error and line.ErrorID == ErrorID.Ehome
    home = mcl.MC_GroupHome(AxesGroup=group, Steps=[homing(5.0), homing(-3.0)])
    states: set[tuple[GroupState, AxisState, AxisState]] = set()

    def program() -> None:
        home(Execute=True)
        exclusive(home)
        states.add((group.state, x.state, y.state))

    program()
    assert home.Busy and group.state == GroupState.GroupHoming
    machine.run(program, until=lambda: home.Done or home.Error, timeout=20.0)
    assert home.Done and not home.Error
    assert (GroupState.GroupHoming, AxisState.Homing, AxisState.Homing) in states
    assert x.Ref and y.Ref
    shown = (x.POS, y.POS)
    assert shown == pytest.approx((5.0, -3.0), abs=0.01)
    assert group.state == GroupState.GroupStandby
    scans(machine, program, 0.02)
    assert home.Done
    home(Execute=False)
    assert not (home.Done or home.Busy)
    line(Execute=False)
    machine.run(lambda: line(Execute=True), until=lambda: line.Done, timeout=3.0)
    assert [x.actual, y.actual] == pytest.approx([10.0, 10.0], abs=0.05)


def test_group_home_errors_leave_the_group_alone() -> None:
    machine = make_machine("XY", referenced=False)
    group = build_group(machine, "XY")
    shared = homing(0.0)
    bad_steps: list[Any] = [
        [homing(0.0)],
        [homing(0.0), []],
        [homing(0.0), [mcl.MC_MoveRelative(Distance=1.0, Velocity=10.0)]],
        [shared, shared],
        [homing(0.0), "ab"],
        7,
    ]
    for steps in bad_steps:
        home = mcl.MC_GroupHome(AxesGroup=group, Steps=steps)
        home(Execute=True)
        assert home.Error and home.ErrorID == ErrorID.EParam, steps
    assert group.state == GroupState.GroupStandby
    failing = mcl.MC_GroupHome(AxesGroup=group, Steps=[homing(0.0), homing(0.0, velocity=0.0)])
    machine.run(lambda: failing(Execute=True), until=lambda: not failing.Busy, timeout=5.0)
    assert failing.Error and failing.ErrorID == ErrorID.EParam
    group.disable()
    machine.run(timeout=1.0)
    home = mcl.MC_GroupHome(AxesGroup=group, Steps=[homing(0.0), homing(0.0)])
    home(Execute=True)
    assert home.Error and home.ErrorID == ErrorID.Epower


def test_group_home_is_refused_while_the_group_moves(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    move = full_circle(group)
    scans(machine, lambda: move(Execute=True), 0.1)
    home = mcl.MC_GroupHome(AxesGroup=group, Steps=[homing(0.0), homing(0.0)])
    home(Execute=True)
    assert home.Error and home.ErrorID == ErrorID.EParam
    assert move.Active and all(a.state == AxisState.SynchronizedMotion for a in group.axes)
    single = mcl.MC_StepAbsSwitch(Axis=group.axes[0], Direction=NEG, Velocity=100.0)
    single(Execute=True)
    assert single.Error and single.ErrorID == ErrorID.EGroupMember


@pytest.mark.parametrize("ender", [mcl.MC_GroupStop, mcl.MC_GroupDisable])
def test_a_stop_during_the_resume_aborts_the_continue(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], ender: Any
) -> None:
    """MC_GroupStop or MC_GroupDisable while MC_GroupContinue ramps the path up again."""
    machine, group = xy
    program = FeedHold(group)
    scans(machine, program, 0.2)
    program.interrupt = True
    machine.run(program, until=lambda: program.hold.Done, timeout=2.0)
    program.interrupt = False
    program.resume = True
    scans(machine, program, 0.02)
    assert program.cont.Busy
    stop = ender(AxesGroup=group)
    stop(Execute=True)
    program()
    assert program.cont.CommandAborted and not program.cont.Done
    assert program.move.CommandAborted


def test_fresh_blocks_show_nothing(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """Before their first call every output is FALSE, 0, empty or None."""
    _, group = xy
    override = mcl.MC_GroupSetOverride(AxesGroup=group)
    assert not (override.Enabled or override.Busy or override.Error) and override.ErrorID == 0
    for block in (mcl.MC_GroupInterrupt(), mcl.MC_GroupContinue()):
        assert not (block.CommandAborted or block.Done or block.Busy or block.Error)
    home = mcl.MC_GroupHome()
    assert not (home.Done or home.Busy or home.Error) and home.ErrorID == 0
    velocity = mcl.MC_GroupReadActualVelocity()
    assert velocity.Velocity == [] and velocity.PathVelocity == 0.0
    acceleration = mcl.MC_GroupReadActualAcceleration()
    assert acceleration.Acceleration == [] and acceleration.PathAcceleration == 0.0
    assert mcl.MC_GroupReadConfiguration().Member is None
    full = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, VelFactor=2.0)
    full()
    assert full.Enabled and group.clock.override == 2.0

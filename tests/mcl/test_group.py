"""Axes groups (MotionControlLib chapters 2.2–2.3 and 5; docs/reference.md, BufferMode): the group
state machine, the group blocks' outputs and errors, linear interpolation, corner blending,
MC_GroupStop, member faults and ungrouping, on three simulated axes X, Y, Z."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import pytest

import mcl
from mcl import AxisState, ErrorID, GroupState, MC_BufferMode
from mcl.group import distance_to_segment
from tests.helpers import configure, make_machine, power_on, scan

NAMES = "XYZ"
V = 200.0
ACC = 2000.0
JERK = 50000.0
MOVE = dict(Velocity=V, Acceleration=ACC, Deceleration=ACC, Jerk=JERK)
"""Path velocity [mm/s], acceleration/deceleration [mm/s²] and jerk [mm/s³] of the moves."""
CONTOUR_LIMIT = 0.050
"""Largest distance of the actual tool point from a straight segment [mm]."""


@pytest.fixture
def xyz() -> mcl.SimMachine:
    """Three powered, referenced axes X, Y, Z at 0 mm."""
    return make_machine(NAMES)


def build_group(machine: mcl.SimMachine, names: str = NAMES, enable: bool = True) -> mcl.AxesGroup:
    """A group of the named axes (in that order), enabled through MC_GroupEnable."""
    group = mcl.AxesGroup("G")
    add = mcl.MC_AddAxisToGroup()
    for name in names:
        add(AxesGroup=group, Axis=machine.axes[name], Execute=True)
        assert add.Done, add.ErrorID
        add(Execute=False)
    if enable:
        en = mcl.MC_GroupEnable()
        en(AxesGroup=group, Execute=True)
        assert en.Done
    return group


@dataclass
class Recorder:
    """Samples every servo cycle: time, actual and model positions, model velocities."""

    axes: Sequence[mcl.Axis]
    t: list[float] = field(default_factory=list)
    actual: list[tuple[float, ...]] = field(default_factory=list)
    model: list[tuple[float, ...]] = field(default_factory=list)
    velocity: list[tuple[float, ...]] = field(default_factory=list)

    def __call__(self, t: float) -> None:
        self.t.append(t)
        self.actual.append(tuple(a.actual for a in self.axes))
        self.model.append(tuple(a.sp_pos for a in self.axes))
        self.velocity.append(tuple(a.sp_vel for a in self.axes))

    def speeds(self) -> list[float]:
        """Path speed of the model [mm/s]."""
        return [math.hypot(*v) for v in self.velocity]


def record(machine: mcl.SimMachine, names: str = NAMES) -> Recorder:
    recorder = Recorder([machine.axes[n] for n in names])
    machine.runtime.observers.append(recorder)
    return recorder


def polyline_distance(p: Sequence[float], points: Sequence[Sequence[float]]) -> float:
    """Distance of ``p`` from the polyline through ``points`` [mm]."""
    return min(distance_to_segment(p, a, b) for a, b in itertools.pairwise(points))


def run_until(
    machine: mcl.SimMachine,
    program: Callable[[], None],
    until: Callable[[], bool],
    timeout: float = 5.0,
) -> None:
    machine.run(program, until=until, timeout=timeout)


# ---------------------------------------------------------------------- state machine
def test_group_state_machine(xyz: mcl.SimMachine) -> None:
    """Disabled → (Enable) Standby → (move) Moving with members in SynchronizedMotion →
    Standby with members in StandStill → (Disable) Disabled → (Ungroup) empty, Disabled."""
    group = mcl.AxesGroup("G")
    assert group.state == GroupState.GroupDisabled
    group = build_group(xyz, enable=False)
    assert group.state == GroupState.GroupDisabled
    assert [a.name for a in group.axes] == list(NAMES)
    assert all(xyz.axes[n].group is group for n in NAMES)
    enable = mcl.MC_GroupEnable()
    enable(AxesGroup=group, Execute=True)
    assert enable.Done and group.state == GroupState.GroupStandby

    move = mcl.MC_MoveLinearAbsolute()

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[50.0, 20.0, -10.0], **MOVE)

    program()
    assert move.Busy and move.Active
    assert group.state == GroupState.GroupMoving
    assert all(xyz.axes[n].state == AxisState.SynchronizedMotion for n in NAMES)
    run_until(xyz, program, lambda: move.Done)
    assert group.state == GroupState.GroupStandby
    assert all(xyz.axes[n].state == AxisState.StandStill for n in NAMES)
    assert not move.Busy and not move.Active

    disable = mcl.MC_GroupDisable()
    disable(AxesGroup=group, Execute=True)
    assert disable.Done and group.state == GroupState.GroupDisabled
    enable(Execute=False)
    enable(Execute=True)
    assert group.state == GroupState.GroupStandby

    ungroup = mcl.MC_UngroupAllAxes()
    ungroup(AxesGroup=group, Execute=True)
    assert ungroup.Done
    assert group.state == GroupState.GroupDisabled and group.axes == []
    assert all(xyz.axes[n].group is None for n in NAMES)


def test_add_axis_errors() -> None:
    """1004 axis already in a group (another one or this one), 1001 group full; members keep
    their order; a disabled group refuses motion (Epower 10), an empty one (1005)."""
    machine = make_machine("XYZW")
    group = build_group(machine, "XYZ")
    add = mcl.MC_AddAxisToGroup()
    add(AxesGroup=group, Axis=machine.axes["W"], Execute=True)
    assert add.Error and add.ErrorID == ErrorID.EGroupFull == 1001
    add(Execute=False)
    assert not add.Error

    other = mcl.AxesGroup("H")
    add(AxesGroup=other, Axis=machine.axes["X"], Execute=True)
    assert add.Error and add.ErrorID == ErrorID.EInOtherGroup == 1004
    add(Execute=False)
    add(AxesGroup=group, Axis=machine.axes["Y"], Execute=True)
    assert add.ErrorID == 1004
    add(Execute=False)
    add(AxesGroup=other, Axis=machine.axes["W"], Execute=True)
    assert add.Done and other.axes == [machine.axes["W"]]

    move = mcl.MC_MoveLinearAbsolute()
    move(AxesGroup=other, Execute=True, Position=[10.0], **MOVE)
    assert move.Error and move.ErrorID == ErrorID.Epower  # group not enabled

    empty = mcl.AxesGroup("E")
    for fb in (mcl.MC_UngroupAllAxes(), mcl.MC_GroupEnable(), mcl.MC_GroupReset()):
        fb(AxesGroup=empty, Execute=True)
        assert fb.Error and fb.ErrorID == ErrorID.EGroupEmpty == 1005, type(fb).__name__
    move = mcl.MC_MoveLinearAbsolute()
    move(AxesGroup=empty, Execute=True, Position=[], **MOVE)
    assert move.ErrorID == 1005
    read = mcl.MC_GroupReadActualPosition()
    read(AxesGroup=empty, Enable=True)
    assert not read.Valid and read.Error and read.ErrorID == 1005


def test_group_blocks_need_a_group() -> None:
    """Wiring a block to something that is not an AxesGroup is a programming error."""
    machine = make_machine("X")
    with pytest.raises(TypeError, match="AxesGroup"):
        mcl.MC_GroupEnable()(AxesGroup=machine.axes["X"], Execute=True)
    with pytest.raises(TypeError, match="Axis"):
        mcl.MC_AddAxisToGroup()(AxesGroup=mcl.AxesGroup(), Axis=mcl.AxesGroup(), Execute=True)
    with pytest.raises(TypeError, match="no input"):
        mcl.MC_MoveLinearAbsolute()(AxesGroup=mcl.AxesGroup(), Positions=[1.0])


def test_member_refuses_single_axis_commands_until_ungrouped(xyz: mcl.SimMachine) -> None:
    """A member refuses single-axis motion (1000); after MC_UngroupAllAxes it accepts it."""
    group = build_group(xyz)
    X = xyz.axes["X"]
    single = mcl.MC_MoveAbsolute()
    single(Axis=X, Execute=True, Position=10.0, Velocity=100.0)
    assert single.Error and single.ErrorID == ErrorID.EGroupMember == 1000
    single(Axis=X, Execute=False)
    stop = mcl.MC_Stop()
    stop(Axis=X, Execute=True)
    assert stop.ErrorID == 1000

    ungroup = mcl.MC_UngroupAllAxes()
    ungroup(AxesGroup=group, Execute=True)
    assert ungroup.Done and X.group is None

    def program() -> None:
        single(Axis=X, Execute=True, Position=10.0, Velocity=100.0)

    run_until(xyz, program, lambda: single.Done)
    assert X.state == AxisState.StandStill and abs(X.sp_pos - 10.0) < 1e-9


def test_ungroup_waits_for_the_motion_to_stop(xyz: mcl.SimMachine) -> None:
    """MC_UngroupAllAxes is Busy while the group moves and Done once it stands (MotionControlLib
    §5.2)."""
    group = build_group(xyz)
    move = mcl.MC_MoveLinearAbsolute()
    ungroup = mcl.MC_UngroupAllAxes()
    states: list[GroupState] = []

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[60.0, 30.0, 0.0], **MOVE)
        ungroup(AxesGroup=group, Execute=True)
        states.append(group.state)

    program()
    assert ungroup.Busy and not ungroup.Done
    run_until(xyz, program, lambda: ungroup.Done)
    assert move.Done or not move.Busy
    assert GroupState.GroupMoving in states
    assert group.state == GroupState.GroupDisabled
    assert all(xyz.axes[n].group is None for n in NAMES)
    xyz.run(program, timeout=0.01)
    assert all(xyz.axes[n].state == AxisState.StandStill for n in NAMES)
    assert abs(xyz.axes["X"].sp_pos - 60.0) < 1e-9


# ---------------------------------------------------------------------- read blocks
def test_read_blocks(xyz: mcl.SimMachine) -> None:
    """MC_GroupReadStatus flags and InPosition, MC_GroupReadActualPosition, MC_GroupReadError."""
    group = build_group(xyz)
    status = mcl.MC_GroupReadStatus()
    position = mcl.MC_GroupReadActualPosition()
    error = mcl.MC_GroupReadError()
    move = mcl.MC_MoveLinearAbsolute()
    target = [40.0, -30.0, 20.0]
    seen: list[tuple[bool, bool, bool]] = []

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=target, **MOVE)
        status(AxesGroup=group, Enable=True)
        position(AxesGroup=group, Enable=True)
        error(AxesGroup=group, Enable=True)
        seen.append((status.GroupMoving, status.GroupStandby, status.InPosition))

    program()
    assert status.Valid and status.GroupMoving and not status.GroupStandby
    assert not status.InPosition
    assert position.Valid and len(position.Position) == 3
    assert error.Valid and error.GroupErrorID == 0 and not error.Error
    run_until(xyz, program, lambda: move.Done)
    xyz.run(program, timeout=0.3)
    assert status.GroupStandby and not status.GroupMoving and status.InPosition
    assert not (status.GroupDisabled or status.GroupErrorStop or status.GroupStopping)
    assert not status.GroupHoming
    assert position.Position == pytest.approx(target, abs=0.005)
    assert any(m and not s and not p for m, s, p in seen)

    status(Enable=False)
    position(Enable=False)
    error(Enable=False)
    assert not status.Valid and not status.GroupStandby and not status.InPosition
    assert not position.Valid and position.Position == []
    assert not error.Valid


# ---------------------------------------------------------------------- parameter errors
@pytest.mark.parametrize(
    ("inputs", "code"),
    [
        (dict(Position=[1.0, 2.0]), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0, 4.0]), ErrorID.EParam),
        (dict(Position=[1.0, math.nan, 3.0]), ErrorID.EParam),
        (dict(Position=[1.0, math.inf, 3.0]), ErrorID.EParam),
        (dict(Position="abc"), ErrorID.EParam),
        (dict(Position=5.0), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0], Velocity=0.0), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0], Velocity=-5.0), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0], Velocity=math.nan), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0], Velocity=1.0), ErrorID.EParam),  # < 1 % of Vmax
        (dict(Position=[1.0, 2.0, 3.0], Acceleration=-1.0), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0], Jerk=math.nan), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 3.0], Deceleration=1.0), ErrorID.EParam),  # 100 s rule
        (dict(Position=[1.0, 2.0, 3.0], BufferMode=9), ErrorID.EParam),
        (dict(Position=[1.0, 2.0, 500.0]), ErrorID.Ecil),
    ],
)
def test_parameter_errors_do_not_touch_the_group(inputs: dict[str, object], code: int) -> None:
    """A refused command reports Error/ErrorID and the running motion goes on: a parameter error
    leaves the group alone."""
    machine = make_machine(NAMES, LimPos=300.0, LimNeg=-300.0)
    group = build_group(machine)
    first = mcl.MC_MoveLinearAbsolute()
    bad = mcl.MC_MoveLinearAbsolute()
    target = [80.0, 40.0, 20.0]

    def program() -> None:
        first(AxesGroup=group, Execute=True, Position=target, **MOVE)

    program()
    machine.run(program, timeout=0.1)
    bad(AxesGroup=group, Execute=True, **{**MOVE, **inputs})
    assert bad.Error and bad.ErrorID == code
    assert not bad.Busy and not bad.Active
    assert first.Active and group.state == GroupState.GroupMoving
    run_until(machine, program, lambda: first.Done)
    assert [a.sp_pos for a in group.axes] == pytest.approx(target, abs=1e-9)
    bad(Execute=False)
    assert not bad.Error and bad.ErrorID == 0


def test_member_not_ready_errors(xyz: mcl.SimMachine) -> None:
    """Ehome 9 (absolute move, a member without Ref; a relative move needs none), Epower 10
    (member not powered), Eerrstop 11 (member in ErrorStop → GroupErrorStop), 1003 (a member
    that no longer refers to the group), Econst 12."""
    group = build_group(xyz)
    move = mcl.MC_MoveLinearAbsolute()
    xyz.axes["Y"].Ref = False
    move(AxesGroup=group, Execute=True, Position=[1.0, 1.0, 1.0], **MOVE)
    assert move.Error and move.ErrorID == ErrorID.Ehome
    move(Execute=False)
    relative = mcl.MC_MoveLinearRelative()

    def program() -> None:
        relative(AxesGroup=group, Execute=True, Distance=[5.0, -5.0, 2.0], **MOVE)

    run_until(xyz, program, lambda: relative.Done)
    assert [a.sp_pos for a in group.axes] == pytest.approx([5.0, -5.0, 2.0], abs=0.01)
    relative(Execute=False)

    X = xyz.axes["X"]
    X.group = None  # detached behind the group's back
    move(AxesGroup=group, Execute=True, Position=[1.0, 1.0, 1.0], **MOVE)
    assert move.ErrorID == ErrorID.ENotGroupMember == 1003
    move(Execute=False)
    X.group = group

    power = mcl.MC_Power()
    power(Axis=xyz.axes["Z"], Enable=False)
    xyz.run(lambda: power(Axis=xyz.axes["Z"], Enable=False), timeout=0.01)
    move(AxesGroup=group, Execute=True, Position=[1.0, 1.0, 1.0], **MOVE)
    assert move.ErrorID == ErrorID.Epower
    move(Execute=False)

    xyz.axes["Z"].fault(ErrorID.ERRLIP)  # a disabled axis ignores faults
    assert xyz.axes["Z"].state == AxisState.Disabled and xyz.axes["Z"].AxErrorID == 0
    power(Axis=xyz.axes["Z"], Enable=True)
    xyz.axes["Z"].fault(ErrorID.ERRLIP)
    assert group.state == GroupState.GroupErrorStop
    move(AxesGroup=group, Execute=True, Position=[1.0, 1.0, 1.0], **MOVE)
    assert move.ErrorID == ErrorID.Eerrstop

    fresh = mcl.SimMachine({n: mcl.SimAxisParams(start=0.2) for n in "AB"})
    configure(fresh.axes["A"])
    power_on(fresh, fresh.axes["A"])  # B: no GT_SetConstant yet
    group2 = build_group(fresh, "AB")
    move2 = mcl.MC_MoveLinearRelative()
    move2(AxesGroup=group2, Execute=True, Distance=[1.0, 1.0], **MOVE)
    assert move2.ErrorID == ErrorID.Econst


# ---------------------------------------------------------------------- linear interpolation
def test_straight_line_in_space_stays_on_the_line(xyz: mcl.SimMachine) -> None:
    """A 3-D MC_MoveLinearAbsolute at 200 mm/s: the actual tool point stays within 50 µm of the
    straight segment and every member reaches the end point."""
    group = build_group(xyz)
    rec = record(xyz)
    start = [a.actual for a in group.axes]
    target = [150.0, -100.0, 250.0]
    move = mcl.MC_MoveLinearAbsolute()

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=target, **MOVE)

    run_until(xyz, program, lambda: move.Done)
    xyz.run(program, timeout=0.3)
    contour = max(distance_to_segment(p, start, target) for p in rec.actual)
    model = max(distance_to_segment(p, start, target) for p in rec.model)
    print(f"straight 3-D line: contour error {contour * 1000:.1f} µm (model {model * 1e3:.4f} µm)")
    assert model < 1e-6
    assert contour < CONTOUR_LIMIT
    assert max(rec.speeds()) == pytest.approx(V, rel=1e-6)
    for axis, x in zip(group.axes, target, strict=True):
        assert axis.sp_pos == pytest.approx(x, abs=1e-9)
        assert abs(axis.actual - x) <= axis.config.in_position
    # every member's velocity is the path velocity times its direction cosine
    length = math.dist(start, target)
    for v in rec.velocity[:: len(rec.velocity) // 20]:
        speed = math.hypot(*v)
        for vi, s, e in zip(v, start, target, strict=True):
            assert vi == pytest.approx(speed * (e - s) / length, abs=1e-6)


def test_path_velocity_is_clamped_to_every_member() -> None:
    """Valid parameters above what a member allows are clamped: along a diagonal the path may be
    faster than one axis' Vmax, but no member exceeds its own Vmax."""
    machine = make_machine("XY", Vmax=300.0)
    group = build_group(machine, "XY")
    rec = record(machine, "XY")
    move = mcl.MC_MoveLinearAbsolute()

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[300.0, 100.0], **{**MOVE, "Velocity": 1000.0})

    run_until(machine, program, lambda: move.Done)
    peak_x = max(abs(v[0]) for v in rec.velocity)
    assert peak_x == pytest.approx(300.0, rel=1e-6)
    assert max(rec.speeds()) == pytest.approx(300.0 * math.hypot(3.0, 1.0) / 3.0, rel=1e-6)


LIMITED = mcl.AxisConfig(max_acceleration=2000.0, max_deceleration=1500.0, max_jerk=40000.0)
"""Machine data whose maxima the FB inputs of the clamp test exceed."""


@pytest.mark.parametrize("target", [(180.0, 60.0), (-180.0, -60.0), (-180.0, 60.0)])
def test_path_limits_are_clamped_to_every_member_in_either_direction(
    target: tuple[float, float],
) -> None:
    """Velocity, acceleration, deceleration and jerk far above the maxima are clamped so that
    no member exceeds its Vmax (300 mm/s), max_acceleration, max_deceleration or max_jerk,
    whichever way it moves; X, which carries most of the path, reaches the Vmax — in the
    simulated carriage too."""
    params = {n: mcl.SimAxisParams(start=0.2) for n in "XY"}
    machine = mcl.SimMachine(params, config=LIMITED)
    for axis in machine.axes.values():
        configure(axis, Vmax=300.0)
        power_on(machine, axis)
    group = build_group(machine, "XY")
    X, sim = machine.axes["X"], machine.sims["X"]
    samples: list[tuple[float, float, float]] = []  # X: set velocity, set acceleration, real v
    machine.runtime.observers.append(lambda t: samples.append((X.sp_vel, X.sp_acc, sim.v)))
    move = mcl.MC_MoveLinearAbsolute()
    huge = dict(Velocity=5000.0, Acceleration=1e6, Deceleration=1e6, Jerk=1e9)

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=list(target), **huge)

    run_until(machine, program, lambda: move.Done or move.Error)
    machine.run(program, timeout=0.3)
    assert move.Done and not move.Error, (move.ErrorID, X.AxErrorID)
    sign = math.copysign(1.0, target[0])
    velocity = [v * sign for v, _, _ in samples]
    acceleration = [a * sign for _, a, _ in samples]  # > 0 speeding up, < 0 slowing down
    servo = LIMITED.servo_period
    jerk = [abs(b - a) / servo for (_, a, _), (_, b, _) in itertools.pairwise(samples)]
    assert max(velocity) == pytest.approx(300.0, rel=1e-6)
    assert max(abs(v) * 1000.0 for _, _, v in samples) < 300.0 * 1.03, "the carriage itself"
    assert max(acceleration) <= LIMITED.max_acceleration * (1 + 1e-6)
    assert max(acceleration) > 0.9 * LIMITED.max_acceleration
    assert -min(acceleration) <= LIMITED.max_deceleration * (1 + 1e-6)
    assert -min(acceleration) > 0.9 * LIMITED.max_deceleration
    assert max(jerk) <= LIMITED.max_jerk * (1 + 1e-6)
    assert (sim.x - 0.2) * 1000.0 == pytest.approx(target[0], abs=0.01)


POLYLINE = [
    [0.0, 0.0, 0.0],
    [120.0, 0.0, 0.0],
    [120.0, 90.0, 30.0],
    [40.0, 140.0, 80.0],
    [0.0, 20.0, 10.0],
]
"""Four segments with corners of about 95°, 120° and 100°."""


def run_polyline(
    machine: mcl.SimMachine, group: mcl.AxesGroup, mode: MC_BufferMode
) -> tuple[Recorder, list[mcl.MC_MoveLinearAbsolute], list[tuple[bool, ...]]]:
    """The four segments issued in one scan, the later ones with ``mode``."""
    rec = record(machine)
    moves = [mcl.MC_MoveLinearAbsolute() for _ in POLYLINE[1:]]
    outputs: list[tuple[bool, ...]] = []

    def program() -> None:
        for i, fb in enumerate(moves):
            fb(
                AxesGroup=group,
                Execute=True,
                Position=POLYLINE[i + 1],
                BufferMode=MC_BufferMode.Aborting if i == 0 else mode,
                **MOVE,
            )
        outputs.append(tuple(fb.CommandAborted or fb.Error for fb in moves))

    run_until(machine, program, lambda: moves[-1].Done, timeout=10.0)
    machine.run(program, timeout=0.3)
    return rec, moves, outputs


def corner_indices(rec: Recorder) -> list[int]:
    """Servo samples where the model passes closest to each interior corner."""
    indices = range(len(rec.model))
    return [min(indices, key=lambda i: math.dist(rec.model[i], c)) for c in POLYLINE[1:-1]]


def test_blended_polyline_does_not_stop_at_corners(xyz: mcl.SimMachine) -> None:
    """BlendingLow: the path speed stays > 0 through the interior corners, the tool point stays
    within the corner tolerance of the polyline, the end point is reached, the blocks report
    Done one after the other and none is aborted."""
    group = build_group(xyz)
    rec, moves, outputs = run_polyline(xyz, group, MC_BufferMode.BlendingLow)
    assert all(fb.Done for fb in moves[-1:])
    assert not any(any(o) for o in outputs)
    speeds = rec.speeds()
    start, end = POLYLINE[0], POLYLINE[-1]
    interior = [  # farther than 10 mm from the start and the end point
        v
        for v, p in zip(speeds, rec.model, strict=True)
        if math.dist(p, start) > 10.0 and math.dist(p, end) > 10.0
    ]
    assert min(interior) > 5.0
    for i in corner_indices(rec):
        assert speeds[i] > 5.0
    model = max(polyline_distance(p, POLYLINE) for p in rec.model)
    actual = max(polyline_distance(p, POLYLINE) for p in rec.actual)
    print(
        f"blended polyline: model deviation {model * 1e3:.1f} µm, actual {actual * 1e3:.1f} µm "
        f"(corner tolerance {group.corner_tolerance * 1e3:.0f} µm); min path speed "
        f"{min(interior):.1f} mm/s"
    )
    assert model <= group.corner_tolerance + 1e-6
    assert actual <= group.corner_tolerance + CONTOUR_LIMIT
    for axis, x in zip(group.axes, POLYLINE[-1], strict=True):
        assert axis.sp_pos == pytest.approx(x, abs=1e-9)
        assert abs(axis.actual - x) <= axis.config.in_position
    # the velocity of every axis is continuous: no jump beyond what max_acceleration allows
    for a, b in itertools.pairwise(rec.velocity):
        for axis, va, vb in zip(group.axes, a, b, strict=True):
            assert abs(vb - va) <= axis.config.max_acceleration * axis.servo_period * 1.01
    assert all(axis.state == AxisState.StandStill for axis in group.axes)


def test_blended_polyline_is_faster_than_buffered() -> None:
    """The same polyline takes less time blended than buffered."""
    times = {}
    for mode in (MC_BufferMode.Buffered, MC_BufferMode.BlendingHigh):
        machine = make_machine(NAMES)
        group = build_group(machine)
        rec, _, _ = run_polyline(machine, group, mode)
        moving = [t for t, v in zip(rec.t, rec.speeds(), strict=True) if v > 0.0]
        times[mode] = moving[-1] - moving[0]
    assert times[MC_BufferMode.BlendingHigh] < times[MC_BufferMode.Buffered]


def test_buffered_polyline_stops_at_each_corner(xyz: mcl.SimMachine) -> None:
    """Buffered: every segment starts from standstill once the previous one is Done; the members
    stay in SynchronizedMotion in between and the path is exactly the polyline."""
    group = build_group(xyz)
    states: list[AxisState] = []
    xyz.runtime.observers.append(lambda t: states.append(xyz.axes["X"].state))
    rec, moves, outputs = run_polyline(xyz, group, MC_BufferMode.Buffered)
    assert all(fb.Done for fb in moves[-1:]) and not any(any(o) for o in outputs)
    speeds = rec.speeds()
    for i, corner in zip(corner_indices(rec), POLYLINE[1:-1], strict=True):
        assert math.dist(rec.model[i], corner) < 1e-6
        assert speeds[i] < 0.1
    assert max(polyline_distance(p, POLYLINE) for p in rec.model) < 1e-9
    first = states.index(AxisState.SynchronizedMotion)
    last = len(states) - 1 - states[::-1].index(AxisState.SynchronizedMotion)
    assert all(s == AxisState.SynchronizedMotion for s in states[first : last + 1])


def test_aborting_mid_segment(xyz: mcl.SimMachine) -> None:
    """Aborting: the first block reports CommandAborted, never Done. A new target ahead on the
    same line continues without stopping; a target off the line first ramps to standstill along
    the current line, then moves straight to the new target."""
    group = build_group(xyz)
    rec = record(xyz)
    first = mcl.MC_MoveLinearAbsolute()
    ahead = mcl.MC_MoveLinearAbsolute()
    aside = mcl.MC_MoveLinearAbsolute()
    a, b, c = [100.0, 50.0, 0.0], [200.0, 100.0, 0.0], [100.0, 150.0, 40.0]
    go: dict[str, bool] = {"ahead": False, "aside": False}
    first_done: list[bool] = []

    def program() -> None:
        first(AxesGroup=group, Execute=True, Position=a, **MOVE)
        ahead(AxesGroup=group, Execute=go["ahead"], Position=b, **MOVE)
        aside(AxesGroup=group, Execute=go["aside"], Position=c, **MOVE)
        first_done.append(first.Done)

    xyz.run(program, timeout=0.3)
    go["ahead"] = True
    program()
    program()  # ``first`` is scanned before ``ahead``: it shows the abort one scan later
    assert first.CommandAborted and not first.Busy and ahead.Active
    n = len(rec.t)
    xyz.run(program, timeout=0.4)
    assert min(rec.speeds()[n:]) > 0.5 * V  # no stop on the way ahead
    assert max(distance_to_segment(p, [0.0] * 3, b) for p in rec.model) < 1e-9
    go["aside"] = True
    program()
    program()
    assert ahead.CommandAborted and aside.Active
    stop_from = len(rec.t)
    run_until(xyz, program, lambda: aside.Done)
    assert not any(first_done)
    # the ramp stays on the first line; then a straight segment from the stop point to c
    path = rec.model[stop_from:]
    stop_index = next(i for i, v in enumerate(rec.speeds()[stop_from:]) if v < 1e-9)
    stop_point = path[stop_index]
    assert distance_to_segment(stop_point, [0.0] * 3, b) < 1e-9
    assert max(distance_to_segment(p, [0.0] * 3, b) for p in path[:stop_index]) < 1e-9
    assert max(distance_to_segment(p, stop_point, c) for p in path[stop_index:]) < 1e-9
    assert [ax.sp_pos for ax in group.axes] == pytest.approx(c, abs=1e-9)


def test_relative_moves_buffered_count_from_the_last_target(xyz: mcl.SimMachine) -> None:
    """MC_MoveLinearRelative: from the actual point at standstill, Buffered from the end of the
    previous move."""
    group = build_group(xyz)
    m1, m2 = mcl.MC_MoveLinearRelative(), mcl.MC_MoveLinearRelative()

    def program() -> None:
        m1(AxesGroup=group, Execute=True, Distance=[30.0, 0.0, -10.0], **MOVE)
        m2(
            AxesGroup=group,
            Execute=True,
            Distance=[0.0, 20.0, 10.0],
            BufferMode=MC_BufferMode.Buffered,
            **MOVE,
        )

    program()
    assert m1.Active and m2.Busy and not m2.Active
    run_until(xyz, program, lambda: m2.Done)
    assert [ax.sp_pos for ax in group.axes] == pytest.approx([30.0, 20.0, 0.0], abs=1e-9)


def test_restarted_block_withdraws_its_queued_move(xyz: mcl.SimMachine) -> None:
    """A new Execute edge on a block whose move is still queued withdraws that move."""
    group = build_group(xyz)
    first, second = mcl.MC_MoveLinearAbsolute(), mcl.MC_MoveLinearAbsolute()
    target2 = [0.0, 40.0, 0.0]

    def program() -> None:
        first(AxesGroup=group, Execute=True, Position=[50.0, 0.0, 0.0], **MOVE)
        second(
            AxesGroup=group,
            Execute=True,
            Position=target2,
            BufferMode=MC_BufferMode.BlendingLow,
            **MOVE,
        )

    program()
    xyz.run(program, timeout=0.05)
    second(Execute=False)
    target2[:] = [50.0, 30.0, 0.0]
    program()  # restart: the queued move to (0, 40, 0) is withdrawn
    run_until(xyz, program, lambda: second.Done)
    assert [ax.sp_pos for ax in group.axes] == pytest.approx(target2, abs=1e-9)
    assert first.Done or not first.CommandAborted


# ---------------------------------------------------------------------- stop, disable, faults
def test_group_stop(xyz: mcl.SimMachine) -> None:
    """MC_GroupStop ramps the path velocity to zero along the path; the move reports
    CommandAborted; GroupStopping holds while Execute is TRUE (other moves: EAxStop 6) and ends
    with Done AND NOT Execute."""
    group = build_group(xyz)
    rec = record(xyz)
    move = mcl.MC_MoveLinearAbsolute()
    other = mcl.MC_MoveLinearAbsolute()
    stop = mcl.MC_GroupStop()
    target = [200.0, 100.0, 50.0]
    stop_execute = {"on": False}

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=target, **MOVE)
        stop(AxesGroup=group, Execute=stop_execute["on"], Deceleration=4000.0, Jerk=JERK)

    xyz.run(program, timeout=0.5)
    stop_execute["on"] = True
    program()
    program()
    assert move.CommandAborted and stop.Busy and stop.Active
    assert group.state == GroupState.GroupStopping
    assert all(ax.state == AxisState.SynchronizedMotion for ax in group.axes)
    run_until(xyz, program, lambda: stop.Done, timeout=1.0)
    assert max(rec.speeds()[-2:]) == 0.0
    assert max(distance_to_segment(p, [0.0] * 3, target) for p in rec.model) < 1e-9
    xyz.run(program, timeout=0.1)
    assert group.state == GroupState.GroupStopping and stop.Done
    other(AxesGroup=group, Execute=True, Position=[0.0, 0.0, 0.0], **MOVE)
    assert other.Error and other.ErrorID == ErrorID.EAxStop
    stop_execute["on"] = False
    xyz.run(program, timeout=0.01)
    assert group.state == GroupState.GroupStandby
    assert all(ax.state == AxisState.StandStill for ax in group.axes)
    other(Execute=False)
    run_until(xyz, lambda: other(AxesGroup=group, Execute=True), lambda: other.Done)


def test_group_disable_while_moving(xyz: mcl.SimMachine) -> None:
    """MC_GroupDisable aborts a running move, the path ramps down, Done once it stands."""
    group = build_group(xyz)
    move = mcl.MC_MoveLinearAbsolute()
    disable = mcl.MC_GroupDisable()
    go = {"disable": False}

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[200.0, 0.0, 0.0], **MOVE)
        disable(AxesGroup=group, Execute=go["disable"])

    xyz.run(program, timeout=0.4)
    go["disable"] = True
    program()
    program()
    assert move.CommandAborted and disable.Busy
    assert group.state == GroupState.GroupDisabled
    run_until(xyz, program, lambda: disable.Done)
    xyz.run(program, timeout=0.01)
    assert all(ax.state == AxisState.StandStill for ax in group.axes)


def test_member_following_error_stops_the_group(xyz: mcl.SimMachine) -> None:
    """A blocked member trips ERRPOS 2001: the group goes GroupErrorStop with GroupErrorID
    ERRPOSG 8001, the move reports Error 8001, the other members stop along the path;
    MC_GroupReset leaves GroupErrorStop; the group can then be ungrouped."""
    group = build_group(xyz)
    X, Y, Z = (xyz.axes[n] for n in NAMES)
    xyz.sims["X"].blocked_at = 0.2 + 0.050  # an obstacle 50 mm ahead of X [m]
    rec = record(xyz)
    move = mcl.MC_MoveLinearAbsolute()
    read = mcl.MC_GroupReadError()
    status = mcl.MC_GroupReadStatus()
    target = [150.0, 100.0, 50.0]

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=target, **MOVE)
        read(AxesGroup=group, Enable=True)
        status(AxesGroup=group, Enable=True)

    run_until(xyz, program, lambda: move.Error, timeout=3.0)
    assert move.ErrorID == ErrorID.ERRPOSG == 8001
    assert X.state == AxisState.ErrorStop and X.AxErrorID == ErrorID.ERRPOS
    assert group.state == GroupState.GroupErrorStop and group.GroupErrorID == 8001
    assert read.GroupErrorID == 8001 and status.GroupErrorStop
    xyz.run(program, timeout=0.2)
    assert Y.state == Z.state == AxisState.StandStill
    assert Y.sp_vel == Z.sp_vel == 0.0
    assert Y.sp_pos < target[1] and Z.sp_pos < target[2]
    # Y and Z stopped on the path (the line through the start and the target)
    yz = [(p[1], p[2]) for p in rec.model]
    assert max(distance_to_segment(p, (0.0, 0.0), target[1:]) for p in yz) < 1e-9

    for fb in (mcl.MC_UngroupAllAxes(), mcl.MC_GroupDisable()):
        fb(AxesGroup=group, Execute=True)
        assert fb.Error and fb.ErrorID == ErrorID.Eerrstop
    other = mcl.MC_MoveLinearAbsolute()
    other(AxesGroup=group, Execute=True, Position=[0.0, 0.0, 0.0], **MOVE)
    assert other.ErrorID == ErrorID.Eerrstop

    xyz.sims["X"].blocked_at = math.inf
    reset = mcl.MC_GroupReset()
    run_until(xyz, lambda: reset(AxesGroup=group, Execute=True), lambda: reset.Done)
    assert group.GroupErrorID == 0 and group.state == GroupState.GroupStandby
    assert X.state == AxisState.Disabled  # the following error opened its loop
    read(Enable=True)
    assert read.GroupErrorID == 0
    ungroup = mcl.MC_UngroupAllAxes()
    ungroup(AxesGroup=group, Execute=True)
    assert ungroup.Done and X.group is None


def test_member_powered_off_aborts_the_group_move(xyz: mcl.SimMachine) -> None:
    """Switching a member off during a group move: the move reports CommandAborted, the other
    members stop, no group error is latched."""
    group = build_group(xyz)
    move = mcl.MC_MoveLinearAbsolute()
    power = mcl.MC_Power()
    on = {"Z": True}

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[150.0, 100.0, 50.0], **MOVE)
        power(Axis=xyz.axes["Z"], Enable=on["Z"])

    xyz.run(program, timeout=0.3)
    on["Z"] = False
    run_until(xyz, program, lambda: not move.Busy)
    assert move.CommandAborted and not move.Error
    xyz.run(program, timeout=0.3)
    assert group.GroupErrorID == 0
    assert xyz.axes["Z"].state == AxisState.Disabled
    assert xyz.axes["X"].state == xyz.axes["Y"].state == AxisState.StandStill
    assert group.state == GroupState.GroupStandby


def test_member_limit_switch_error_is_the_group_error() -> None:
    """A member error other than the following error (LIM+ 2004) becomes the group error and
    the move's ErrorID as it is; the other members stop on the path."""
    machine = make_machine(
        {
            "X": mcl.SimAxisParams(start=0.2, lim_pos=0.26),  # LIM+ 60 mm ahead of X
            "Y": mcl.SimAxisParams(start=0.2),
        }
    )
    group = build_group(machine, "XY")
    move = mcl.MC_MoveLinearAbsolute()

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[150.0, 150.0], **MOVE)

    run_until(machine, program, lambda: move.Error, timeout=3.0)
    assert move.ErrorID == ErrorID.ERRLIP == group.GroupErrorID
    assert group.state == GroupState.GroupErrorStop
    machine.run(program, timeout=0.3)
    X, Y = machine.axes["X"], machine.axes["Y"]
    assert Y.state == AxisState.StandStill and Y.sp_pos < 100.0
    reset = mcl.MC_GroupReset()
    run_until(machine, lambda: reset(AxesGroup=group, Execute=True), lambda: reset.Done)
    assert X.state == Y.state == AxisState.StandStill
    assert group.state == GroupState.GroupStandby


# ---------------------------------------------------------------------- reading the state
def group_snapshot(group: mcl.AxesGroup) -> tuple[object, ...]:
    """Everything a read could change: flags, members, the path and the commands' tickets."""
    members = list(group._members)
    return (
        group.enabled,
        group.GroupErrorID,
        list(group.axes),
        members,
        [(m.status, m.error_id, m.signal) for m in members if m is not None],
        group._active,
        list(group._queue),
        group._stop,
        group._end,
        group._t,
        [(t.status, t.error_id) for t in group._tickets()],
    )


def read_everything(group: mcl.AxesGroup, times: int = 100) -> GroupState:
    """Read state, repr, moving, stopping and InPosition ``times`` times; they never change."""
    seen = {
        (group.state, repr(group), group.moving, group.stopping, group.in_position())
        for _ in range(times)
    }
    assert len(seen) == 1, seen
    return seen.pop()[0]


def _fault_x(machine: mcl.SimMachine) -> None:
    machine.axes["X"].fault(ErrorID.ERRLIP)  # what the supervision does on LIM+


def _power_off_z(machine: mcl.SimMachine) -> None:
    mcl.MC_Power()(Axis=machine.axes["Z"], Enable=False)  # the axis ramps down in Stopping


def _emergency_stop(machine: mcl.SimMachine) -> None:
    mcl.GT_EStop()(Axis=machine.axes["X"], Enable=True)  # every axis of the module: Disabled


@pytest.mark.parametrize(
    ("event", "expected"),
    [
        (_fault_x, GroupState.GroupErrorStop),
        (_power_off_z, GroupState.GroupStopping),
        (_emergency_stop, GroupState.GroupStandby),
    ],
    ids=["member-ErrorStop", "member-powered-off", "all-members-off"],
)
def test_reading_the_state_does_not_change_the_group(
    xyz: mcl.SimMachine, event: Callable[[mcl.SimMachine], None], expected: GroupState
) -> None:
    """Between two scans a member drops out of a running group move. Reading state, repr,
    moving, stopping and InPosition any number of times changes nothing in the group (no member
    dropped, no error latched, no command ended) and tells the state the group goes to; the
    next scan of a group block acts on the fault, and the state it reaches is what was read."""
    group = build_group(xyz)
    move = mcl.MC_MoveLinearAbsolute()

    def program() -> None:
        move(AxesGroup=group, Execute=True, Position=[150.0, 100.0, 50.0], **MOVE)

    xyz.run(program, timeout=0.2)
    assert move.Active and group.state == GroupState.GroupMoving
    event(xyz)
    before = group_snapshot(group)
    assert read_everything(group) == expected
    assert group_snapshot(group) == before
    assert group.GroupErrorID == 0 and move.Active

    program()  # the scan: the move block's poll lets the group act on the fault
    assert group_snapshot(group) != before
    assert not move.Busy and (move.Error or move.CommandAborted)
    assert group.state == expected
    if expected == GroupState.GroupErrorStop:
        assert group.GroupErrorID == move.ErrorID == ErrorID.ERRLIP
    else:
        assert group.GroupErrorID == 0 and move.CommandAborted
    xyz.run(timeout=0.5)
    final = read_everything(group)
    assert final == (expected if expected == GroupState.GroupErrorStop else GroupState.GroupStandby)


def test_a_member_error_while_the_group_is_disabled_is_not_latched_by_the_group(
    xyz: mcl.SimMachine,
) -> None:
    """The group not enabled, X's LIM+ input sticks: X stops with ERRLIP 2004, the group shows
    GroupDisabled and no group error. With the switch free again and X reset, MC_GroupEnable
    gives GroupStandby (nothing of X's error stays with the group) and a group move runs."""
    group = build_group(xyz, enable=False)
    X = xyz.axes["X"]
    read, status = mcl.MC_GroupReadError(), mcl.MC_GroupReadStatus()

    def program() -> None:
        read(AxesGroup=group, Enable=True)
        status(AxesGroup=group, Enable=True)

    stuck = mcl.faults.SwitchStuck("lim_pos", True)
    xyz.faults.set("X", stuck)
    run_until(xyz, program, lambda: X.state == AxisState.ErrorStop, timeout=0.5)
    xyz.run(program, timeout=0.1)
    assert X.AxErrorID == ErrorID.ERRLIP
    assert status.GroupDisabled and read.GroupErrorID == 0 and group.GroupErrorID == 0
    xyz.faults.clear("X", stuck)
    reset = mcl.MC_Reset(Axis=X)
    run_until(xyz, scan(program, lambda: reset(Execute=True)), lambda: reset.Done)
    assert X.state == AxisState.StandStill
    enable = mcl.MC_GroupEnable(AxesGroup=group)
    enable(Execute=True)
    assert enable.Done
    xyz.run(program, timeout=0.05)
    assert status.GroupStandby and read.GroupErrorID == 0
    move = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[50.0, 20.0, 10.0], **MOVE)
    run_until(xyz, scan(program, lambda: move(Execute=True)), lambda: move.Done)
    assert abs(X.POS - 50.0) < 0.05

"""Arcs of an axes group (PLCopen Part 4 MC_MoveCircularAbsolute/Relative; docs/reference.md,
Group paths) on simulated axes: the block's outputs scan by scan (Tab. 2.3) and the group state,
each CircMode and direction, full circles and turns, planes and helices, the speed an arc's
curvature allows, blends into and out of arcs, every BufferMode and TransitionMode, stops on the
circle, and the inputs that are refused without touching the group."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from typing import Any

import pytest

import mcl
from mcl import MC_CIRC_MODE, MC_CIRC_PATHCHOICE, AxisState, ErrorID, GroupState
from mcl import MC_BufferMode as B
from mcl.geometry import Line, arc
from tests.helpers import make_machine
from tests.mcl.test_fb_rules import exclusive
from tests.mcl.test_group import Recorder, build_group, record

BORDER, CENTER, RADIUS = MC_CIRC_MODE.BORDER, MC_CIRC_MODE.CENTER, MC_CIRC_MODE.RADIUS
CW, CCW = MC_CIRC_PATHCHOICE.CLOCKWISE, MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
V, ACC, JERK = 100.0, 2000.0, 50000.0
DYN = dict(Velocity=V, Acceleration=ACC, Deceleration=ACC, Jerk=JERK)
"""Path velocity [mm/s], acceleration/deceleration [mm/s²] and jerk [mm/s³] of the moves."""
CONTOUR_LIMIT = 0.050
"""Largest distance of the actual tool point from a commanded arc of the simulated axes [mm]
(as for their straight lines: the spike where an axis reverses against its friction, at the
quadrants of a circle, is most of it)."""
DT = 0.001
"""The servo period of the simulated axes [s]."""


@pytest.fixture
def xy() -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    """Two powered, referenced axes X, Y at 0 mm in an enabled group."""
    machine = make_machine("XY")
    return machine, build_group(machine, "XY")


@pytest.fixture
def xyz() -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    machine = make_machine("XYZ")
    return machine, build_group(machine, "XYZ")


def circle(**inputs: Any) -> mcl.MC_MoveCircularAbsolute:
    return mcl.MC_MoveCircularAbsolute(**{**DYN, **inputs})


def run(
    machine: mcl.SimMachine, *blocks: Any, until: Callable[[], bool], timeout: float = 10.0
) -> None:
    """Scan the blocks (Execute TRUE, their inputs bound) until ``until``."""

    def program() -> None:
        for block in blocks:
            block(Execute=True)

    machine.run(program, until=until, timeout=timeout)


def derivative(values: Sequence[Sequence[float]]) -> list[list[float]]:
    """Per-cycle differences over the servo period."""
    return [
        [(b - a) / DT for a, b in zip(p, q, strict=True)] for p, q in itertools.pairwise(values)
    ]


def radius_error(rec: Recorder, centre: Sequence[float], radius: float) -> float:
    """Largest distance of the model positions from the circle [mm]."""
    return max(abs(math.dist(p[:2], centre) - radius) for p in rec.model)


# ---------------------------------------------------------------------- outputs and state
def test_outputs_scan_by_scan_and_the_group_state(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """Busy and Active rise with the Execute edge, the group moves (members SynchronizedMotion);
    Done rises in the scan the arc ends, exclusive of the others on every scan, held while
    Execute stays TRUE and reset by its falling edge; then the group stands (Tab. 2.3 rules 2,
    5, 6)."""
    machine, group = xy
    move = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[0.0, 20.0],
        EndPoint=[20.0, 20.0],
        PathChoice=CCW,
    )
    scans: list[tuple[bool, bool, bool, tuple[float, float]]] = []

    def program() -> None:
        move(Execute=True)
        exclusive(move)
        scans.append(
            (move.Busy, move.Active, move.Done, (group.axes[0].sp_pos, group.axes[1].sp_pos))
        )

    program()
    assert move.Busy and move.Active and not move.Done
    assert group.state == GroupState.GroupMoving
    assert all(a.state == AxisState.SynchronizedMotion for a in group.axes)
    machine.run(program, until=lambda: move.Done, timeout=5.0)
    done = next(i for i, s in enumerate(scans) if s[2])
    assert all(s[0] and s[1] and not s[2] for s in scans[:done])
    assert scans[done][3] == pytest.approx((20.0, 20.0), abs=1e-9)
    assert scans[done - 1][3] != pytest.approx((20.0, 20.0), abs=1e-6)
    machine.run(program, timeout=0.02)
    assert move.Done and not move.Busy and not move.Active  # held while Execute is TRUE
    assert group.state == GroupState.GroupStandby
    assert all(a.state == AxisState.StandStill for a in group.axes)
    move(Execute=False)
    assert not (move.Done or move.Busy or move.Active or move.Error or move.CommandAborted)


def test_done_shows_for_one_scan_after_an_early_falling_edge(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    move = circle(AxesGroup=group, CircMode=RADIUS, AuxPoint=[15.0], EndPoint=[20.0, 0.0])
    move(Execute=True)
    move(Execute=False)
    assert move.Busy and move.Active
    dones: list[bool] = []

    def scan() -> None:
        move()
        dones.append(move.Done)

    machine.run(scan, until=lambda: not move.Busy, timeout=5)
    machine.run(scan, timeout=0.01)
    assert dones.count(True) == 1 and not move.Done


def test_an_arc_aborted_by_a_stop_stops_on_its_circle(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """MC_GroupStop in the middle of a full circle: the arc reports CommandAborted (never Done),
    and the group ramps down on the circle, not along the tangent."""
    machine, group = xy
    rec = record(machine, "XY")
    move = circle(
        AxesGroup=group, CircMode=CENTER, AuxPoint=[0.0, 10.0], EndPoint=[0.0, 0.0], PathChoice=CCW
    )
    stop = mcl.MC_GroupStop(AxesGroup=group, Deceleration=500.0)
    run(machine, move, until=lambda: machine.runtime.time > 0.25)
    assert move.Active
    speed = math.hypot(*rec.velocity[-1])
    assert speed == pytest.approx(V)
    run(machine, move, stop, until=lambda: stop.Done)
    assert move.CommandAborted and not move.Done and not move.Busy
    assert radius_error(rec, [0.0, 10.0], 10.0) < 1e-9
    travelled = sum(math.dist(a, b) for a, b in itertools.pairwise(rec.model[-300:]))
    assert travelled > speed**2 / (2 * 500.0) * 0.9  # the ramp ran on along the circle
    assert group.state == GroupState.GroupStopping
    stop(Execute=False)
    assert group.state == GroupState.GroupStandby


# ---------------------------------------------------------------------- the circles
@pytest.mark.parametrize(
    ("mode", "aux", "end", "choice", "centre", "radius"),
    [
        (BORDER, [20.0, 20.0], [40.0, 0.0], CW, [20.0, 0.0], 20.0),
        (CENTER, [20.0, 0.0], [40.0, 0.0], CCW, [20.0, 0.0], 20.0),
        (RADIUS, [20.0, 0.0], [40.0, 0.0], CW, [20.0, 0.0], 20.0),
        (RADIUS, [-25.0, 0.0], [30.0, 0.0], CCW, [15.0, -20.0], 25.0),
    ],
)
def test_each_circ_mode_draws_its_circle(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
    mode: int,
    aux: list[float],
    end: list[float],
    choice: int,
    centre: list[float],
    radius: float,
) -> None:
    """The model stays on the circle, the end point is reached, the actual tool point follows
    within the contour limit, and the path runs at the commanded velocity."""
    machine, group = xy
    rec = record(machine, "XY")
    move = circle(AxesGroup=group, CircMode=mode, AuxPoint=aux, EndPoint=end, PathChoice=choice)
    run(machine, move, until=lambda: move.Done)
    machine.run(lambda: move(), timeout=0.2)
    assert radius_error(rec, centre, radius) < radius * 1e-12
    contour = max(abs(math.dist(p, centre) - radius) for p in rec.actual)
    print(f"CircMode {mode}: contour error {contour * 1e3:.2f} µm")
    assert contour < CONTOUR_LIMIT
    assert [a.sp_pos for a in group.axes] == pytest.approx(end, abs=1e-9)
    assert max(rec.speeds()) == pytest.approx(V, rel=1e-6)


@pytest.mark.parametrize(("choice", "sign"), [(CW, -1.0), (CCW, 1.0)])
def test_path_choice_turns_clockwise_or_counter_clockwise(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], choice: int, sign: float
) -> None:
    """Seen from +Z: the angular velocity about the centre is negative clockwise."""
    machine, group = xy
    rec = record(machine, "XY")
    move = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[10.0, 0.0],
        EndPoint=[20.0, 0.0],
        PathChoice=choice,
    )
    run(machine, move, until=lambda: move.Done)
    turning = [
        (p[0] - 10.0) * v[1] - p[1] * v[0] for p, v in zip(rec.model, rec.velocity, strict=True)
    ]
    assert all(w * sign >= -1e-9 for w in turning) and max(abs(w) for w in turning) > 100.0
    middle = rec.model[len(rec.model) // 2]
    assert middle[1] * sign < -9.0  # clockwise from (0, 0) about (10, 0) goes up through y > 0


def test_full_circle_and_more_turns_in_centre_mode(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """CENTER with the end on the start and Turns = 1: two full turns, ending at the start."""
    machine, group = xy
    rec = record(machine, "XY")
    move = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[5.0, 0.0],
        EndPoint=[0.0, 0.0],
        PathChoice=CCW,
        Turns=1,
    )
    run(machine, move, until=lambda: move.Done)
    angles = [math.atan2(p[1], p[0] - 5.0) for p in rec.model]
    turned = sum((b - a + math.pi) % (2 * math.pi) - math.pi for a, b in itertools.pairwise(angles))
    assert turned == pytest.approx(4 * math.pi, rel=1e-6)
    assert radius_error(rec, [5.0, 0.0], 5.0) < 1e-12
    assert [a.sp_pos for a in group.axes] == pytest.approx([0.0, 0.0], abs=1e-9)


def test_helix_in_a_group_of_three(xyz: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """A full turn in the XY plane (Plane 17) while Z rises 6 mm: Z linear in the angle."""
    machine, group = xyz
    rec = record(machine, "XYZ")
    move = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[10.0, 0.0, 0.0],
        EndPoint=[0.0, 0.0, 6.0],
        PathChoice=CCW,
        Plane=17,
    )
    run(machine, move, until=lambda: move.Done)
    angles = [math.atan2(p[1], p[0] - 10.0) % (2 * math.pi) for p in rec.model]
    for p, angle in zip(rec.model[5:-5], angles[5:-5], strict=True):
        fraction = ((angle - math.pi) % (2 * math.pi)) / (2 * math.pi)
        assert p[2] == pytest.approx(6.0 * fraction, abs=1e-6)
    assert radius_error(rec, [10.0, 0.0], 10.0) < 1e-12
    assert [a.sp_pos for a in group.axes] == pytest.approx([0.0, 0.0, 6.0], abs=1e-9)


@pytest.mark.parametrize(
    ("inputs", "middle"),
    [
        # ZX plane (G18): about (−10, 0, 0) counter-clockwise (Z → X) from +X to −Z
        (
            dict(
                CircMode=CENTER,
                AuxPoint=[-10.0, 0.0, 0.0],
                EndPoint=[-10.0, 0.0, -10.0],
                PathChoice=CCW,
                Plane=18,
            ),
            [-10.0 + 7.0710678, 0.0, -7.0710678],
        ),
        # a tilted plane through three points
        (dict(CircMode=BORDER, AuxPoint=[10.0, 10.0, 10.0], EndPoint=[20.0, 0.0, 0.0]), None),
    ],
)
def test_arcs_in_other_planes(
    xyz: tuple[mcl.SimMachine, mcl.AxesGroup], inputs: dict[str, Any], middle: list[float] | None
) -> None:
    machine, group = xyz
    start = [a.sp_pos for a in group.axes]
    rec = record(machine, "XYZ")
    move = circle(AxesGroup=group, **inputs)
    run(machine, move, until=lambda: move.Done)
    shape = arc(
        start,
        inputs["CircMode"],
        inputs["AuxPoint"],
        inputs["EndPoint"],
        inputs.get("PathChoice", CW),
        inputs.get("Plane", 0),
    )
    assert max(shape.distance(p) for p in rec.model) < 1e-9
    if middle is not None:
        assert shape.point(shape.length / 2) == pytest.approx(middle, abs=1e-6)
    assert [a.sp_pos for a in group.axes] == pytest.approx(inputs["EndPoint"], abs=1e-9)


def test_relative_arc_counts_from_the_current_point(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """MC_MoveCircularRelative after a move to (30, 10): its centre and end are relative to it;
    it needs no Ref."""
    machine, group = xy
    first = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[30.0, 10.0], **DYN)
    run(machine, first, until=lambda: first.Done)
    for axis in group.axes:
        axis.Ref = False
    x, y = group.start_point(B.Aborting)  # at rest: the actual position (within µm of 30, 10)
    assert math.dist((x, y), (30.0, 10.0)) < 0.02
    move = mcl.MC_MoveCircularRelative(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[0.0, 5.0],
        EndPoint=[0.0, 10.0],
        PathChoice=CW,
        **DYN,
    )
    move(Execute=True)
    rec = record(machine, "XY")
    run(machine, move, until=lambda: move.Done or move.Error)
    assert move.Done
    assert radius_error(rec, [x, y + 5.0], 5.0) < 1e-12
    assert [a.sp_pos for a in group.axes] == pytest.approx([x, y + 10.0], abs=1e-9)
    assert min(p[0] for p in rec.model) < x - 4.9  # clockwise from below the centre: leftwards


# ---------------------------------------------------------------------- dynamics
def test_a_tight_arc_slows_the_path_so_every_axis_keeps_its_limits(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """R = 2 mm at 200 mm/s, three turns: the path slows to the smaller of √(0.7·A·R) and
    (0.5·J·R²)^(1/3) on the arc; every axis' acceleration stays within A and its jerk within J
    (each 1 % for the finite differences)."""
    machine, group = xy
    rec = record(machine, "XY")
    move = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[2.0, 0.0],
        EndPoint=[0.0, 0.0],
        PathChoice=CCW,
        Turns=2,
        Velocity=200.0,
    )
    run(machine, move, until=lambda: move.Done)
    cap = min(math.sqrt(0.7 * ACC * 2.0), (0.5 * JERK * 2.0**2) ** (1.0 / 3.0))
    assert max(rec.speeds()) == pytest.approx(cap, rel=1e-6)
    acc = derivative(rec.velocity)
    jerk = derivative(acc)
    assert max(max(abs(x) for x in a) for a in acc) <= ACC * 1.01
    assert max(max(abs(x) for x in j) for j in jerk[1:]) <= JERK * 1.01


def test_tangent_line_arc_line_blends_without_a_velocity_dip(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """A line, a tangent quarter circle, a tangent line, blended: the path speed stays at V
    through both tangent corners (0.5 %), the jerk within J, and the set point within the
    corner tolerance of the commanded path."""
    machine, group = xy
    rec = record(machine, "XY")
    line1 = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[50.0, 0.0], **DYN)
    bend = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[50.0, 20.0],
        EndPoint=[70.0, 20.0],
        PathChoice=CCW,
        BufferMode=B.BlendingLow,
    )
    line2 = mcl.MC_MoveLinearAbsolute(
        AxesGroup=group, Position=[70.0, 60.0], BufferMode=B.BlendingLow, **DYN
    )
    run(machine, line1, bend, line2, until=lambda: line2.Done)
    speeds = rec.speeds()
    cruise = [i for i, s in enumerate(speeds) if s > V * 0.999]
    assert min(speeds[cruise[0] : cruise[-1]]) > V * 0.995
    jerk = derivative(derivative(rec.velocity))
    assert max(max(abs(x) for x in j) for j in jerk[1:]) <= JERK * 1.01
    pieces = [
        Line([0.0, 0.0], [50.0, 0.0]),
        arc([50.0, 0.0], CENTER, [50.0, 20.0], [70.0, 20.0], CCW),
        Line([70.0, 20.0], [70.0, 60.0]),
    ]
    deviation = max(min(g.distance(p) for g in pieces) for p in rec.model)
    assert deviation <= group.corner_tolerance * 0.9
    contour = max(min(g.distance(p) for g in pieces) for p in rec.actual)
    print(f"line-arc-line: set point {deviation * 1e3:.2f} µm, actual {contour * 1e3:.2f} µm")
    assert contour < CONTOUR_LIMIT


def test_a_corner_into_an_arc_is_rounded_within_the_tolerance(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """A line into an arc at a right angle, BlendingLow: the tool does not stop at the corner
    and the set point stays within 90 % of the corner tolerance; Buffered stops there."""
    pieces = [Line([0.0, 0.0], [40.0, 0.0]), arc([40.0, 0.0], CENTER, [60.0, 0.0], [80.0, 0.0], CW)]
    for mode, stops in ((B.BlendingLow, False), (B.Buffered, True)):
        machine = make_machine("XY")
        group = build_group(machine, "XY")
        rec = record(machine, "XY")
        line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[40.0, 0.0], **DYN)
        bend = circle(
            AxesGroup=group,
            CircMode=CENTER,
            AuxPoint=[60.0, 0.0],
            EndPoint=[80.0, 0.0],
            PathChoice=CW,
            BufferMode=mode,
        )
        run(machine, line, bend, until=lambda: bend.Done)  # noqa: B023 (run at once)
        near = [
            s
            for p, s in zip(rec.model, rec.speeds(), strict=True)
            if math.dist(p, [40.0, 0.0]) < 1.0
        ]
        assert (min(near) < 1e-6) == stops
        deviation = max(min(g.distance(p) for g in pieces) for p in rec.model)
        assert deviation <= group.corner_tolerance * 0.9


@pytest.mark.parametrize(
    ("mode", "junction"),
    [
        (B.BlendingLow, 60.0),
        (B.BlendingPrevious, 100.0),
        (B.BlendingNext, 60.0),
        (B.BlendingHigh, 100.0),
    ],
)
def test_blending_modes_set_the_speed_where_an_arc_hands_over(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], mode: B, junction: float
) -> None:
    """An arc at 100 mm/s into a tangent line at 60 mm/s: the hand-over speed is the lower, the
    first's, the second's or the higher of the two."""
    machine, group = xy
    rec = record(machine, "XY")
    bend = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[0.0, 20.0],
        EndPoint=[20.0, 20.0],
        PathChoice=CCW,
    )
    line = mcl.MC_MoveLinearAbsolute(
        AxesGroup=group, Position=[20.0, 80.0], BufferMode=mode, **{**DYN, "Velocity": 60.0}
    )
    run(machine, bend, line, until=lambda: line.Done)
    at = min(range(len(rec.model)), key=lambda i: math.dist(rec.model[i], [20.0, 20.0]))
    assert rec.speeds()[at] == pytest.approx(junction, rel=0.01)


def test_blending_high_into_an_arc_keeps_the_arcs_velocity(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """BlendingHigh from a line at 150 mm/s into an arc at 50 mm/s: the path never runs faster
    than the arc's velocity on the arc."""
    machine, group = xy
    rec = record(machine, "XY")
    line = mcl.MC_MoveLinearAbsolute(
        AxesGroup=group, Position=[60.0, 0.0], **{**DYN, "Velocity": 150.0}
    )
    bend = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[60.0, 20.0],
        EndPoint=[80.0, 20.0],
        PathChoice=CCW,
        BufferMode=B.BlendingHigh,
        Velocity=50.0,
    )
    run(machine, line, bend, until=lambda: bend.Done)
    on_arc = [s for p, s in zip(rec.model, rec.speeds(), strict=True) if p[0] > 61.0]
    assert max(on_arc) <= 50.0 * 1.001


def test_aborting_arc_takes_over_a_moving_line_along_its_tangent(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """An Aborting arc whose start tangent is the current direction starts with the current
    speed: no stop."""
    machine, group = xy
    rec = record(machine, "XY")
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[200.0, 0.0], **DYN)
    run(machine, line, until=lambda: group.axes[0].sp_pos > 40.0)
    here = group.axes[0].sp_pos
    bend = mcl.MC_MoveCircularRelative(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[0.0, 10.0],
        EndPoint=[10.0, 10.0],
        PathChoice=CCW,
        **DYN,
    )
    run(machine, line, bend, until=lambda: bend.Done)
    assert line.CommandAborted and not line.Done
    near = [v for p, v in zip(rec.model, rec.speeds(), strict=True) if abs(p[0] - here) < 5.0]
    assert min(near) > V * 0.99  # the line's speed carries on into the arc
    assert [a.sp_pos for a in group.axes] == pytest.approx([here + 10.0, 10.0], abs=0.2)


def test_aborting_arc_against_the_motion_starts_where_the_stop_ends(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """An Aborting BORDER arc while the group moves the other way: the motion first stops on its
    path, then the arc runs from there through its points. A CENTER arc whose centre no longer
    fits the stop point ends with EParam and leaves the group standing there."""
    machine, group = xy
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[200.0, 0.0], **DYN)
    run(machine, line, until=lambda: group.axes[0].sp_pos > 40.0)
    bend = circle(AxesGroup=group, CircMode=BORDER, AuxPoint=[20.0, 30.0], EndPoint=[0.0, 0.0])
    rec = record(machine, "XY")
    run(machine, bend, until=lambda: bend.Done)
    stop = max(p[0] for p in rec.model)
    assert stop > 40.0 + V**2 / (2 * ACC) * 0.9
    assert [a.sp_pos for a in group.axes] == pytest.approx([0.0, 0.0], abs=1e-9)

    line(Execute=False)
    run(machine, line, until=lambda: group.axes[0].sp_pos > 40.0)
    x = group.start_point(B.Aborting)[0]  # a half circle from here, not from where it stops
    half = circle(
        AxesGroup=group, CircMode=CENTER, AuxPoint=[x - 10.0, 0.0], EndPoint=[x - 20.0, 0.0]
    )
    half(Execute=True)
    assert half.Error and half.ErrorID == ErrorID.EParam
    machine.run(lambda: half(Execute=True), timeout=0.3)
    assert group.state == GroupState.GroupStandby
    assert group.axes[0].sp_pos > x + V**2 / (2 * ACC) * 0.9  # it stopped on the line
    assert abs(group.axes[1].sp_pos) < 0.01


# ---------------------------------------------------------------------- TransitionMode
@pytest.mark.parametrize(
    ("transition", "parameter"),
    [
        (mcl.MC_TRANSITION_MODE.TMMaxCornerDeviation, 0.004),
        (mcl.MC_TRANSITION_MODE.TMCornerDistance, 0.05),
    ],
)
def test_transition_modes_bound_the_corner(transition: int, parameter: float) -> None:
    """The right-angle corner into a blending arc: TMMaxCornerDeviation keeps the set point
    within 90 % of TransitionParameter[0], TMCornerDistance leaves the path at most
    TransitionParameter[0] from the corner; both tighter than the group's tolerance (TMNone)."""
    corner = [40.0, 0.0]
    pieces = [Line([0.0, 0.0], corner), arc(corner, CENTER, [60.0, 0.0], [80.0, 0.0], CW)]
    deviation, reach = {}, {}
    for mode in (mcl.MC_TRANSITION_MODE.TMNone, transition):
        machine = make_machine("XY")
        group = build_group(machine, "XY")
        rec = record(machine, "XY")
        line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=corner, **DYN)
        bend = circle(
            AxesGroup=group,
            CircMode=CENTER,
            AuxPoint=[60.0, 0.0],
            EndPoint=[80.0, 0.0],
            PathChoice=CW,
            BufferMode=B.BlendingLow,
            TransitionMode=mode,
            TransitionParameter=[parameter],
        )
        run(machine, line, bend, until=lambda: bend.Done)  # noqa: B023 (run at once)
        off = [(min(g.distance(p) for g in pieces), p) for p in rec.model]
        deviation[mode] = max(d for d, _ in off)
        reach[mode] = max(math.dist(p, corner) for d, p in off if d > 1e-9)
        assert min(rec.speeds()[50:-50]) > 1.0  # blended: no stop at the corner
    if transition == mcl.MC_TRANSITION_MODE.TMCornerDistance:
        assert reach[transition] <= parameter * 1.01 < reach[mcl.MC_TRANSITION_MODE.TMNone]
    else:
        assert deviation[transition] <= parameter * 0.9
    assert deviation[transition] < deviation[mcl.MC_TRANSITION_MODE.TMNone]


# ---------------------------------------------------------------------- refused inputs
GOOD = dict(
    CircMode=CENTER,
    AuxPoint=[100.0, 30.0],
    EndPoint=[140.0, 30.0],
    PathChoice=CW,
    BufferMode=B.Buffered,
)
"""An arc behind the first move of the refusal test, which ends at (60, 30)."""


@pytest.mark.parametrize(
    ("inputs", "code"),
    [
        (dict(CircMode=BORDER, AuxPoint=[80.0, 30.0]), ErrorID.EParam),  # collinear
        (dict(CircMode=RADIUS, AuxPoint=[10.0]), ErrorID.EParam),  # R < chord / 2
        (dict(CircMode=RADIUS, AuxPoint=[10.0], EndPoint=[60.0, 30.0]), ErrorID.EParam),  # no chord
        (dict(CircMode=BORDER, AuxPoint=[70.0, 40.0], EndPoint=[60.0, 30.0]), ErrorID.EParam),
        (dict(AuxPoint=[60.0, 30.0], EndPoint=[60.0, 30.0]), ErrorID.EParam),  # zero radius
        (dict(EndPoint=[140.0, 35.0]), ErrorID.EParam),  # off the circle
        (dict(AuxPoint=[math.nan, 0.0]), ErrorID.EParam),
        (dict(EndPoint=[80.0, math.inf]), ErrorID.EParam),
        (dict(EndPoint=[80.0]), ErrorID.EParam),
        (dict(AuxPoint="40, 0"), ErrorID.EParam),
        (dict(CircMode=3), ErrorID.EParam),
        (dict(PathChoice=2), ErrorID.EParam),
        (dict(Plane=18), ErrorID.EParam),  # a group of two has no ZX plane
        (dict(Plane=5), ErrorID.EParam),
        (dict(Turns=-1), ErrorID.EParam),
        (dict(Turns=1.5), ErrorID.EParam),
        (dict(Velocity=0.0), ErrorID.EParam),
        (dict(Jerk=-1.0), ErrorID.EParam),
        (dict(CoordSystem=3), ErrorID.EParam),
        (dict(TransitionMode=mcl.MC_TRANSITION_MODE.TMStartVelocity), ErrorID.EParam),
        (dict(TransitionMode=mcl.MC_TRANSITION_MODE.TMMaxCornerDeviation), ErrorID.EParam),
        (dict(TransitionMode=9, TransitionParameter=[1.0]), ErrorID.EParam),
        (dict(BufferMode=7), ErrorID.EParam),
        (dict(AuxPoint=[60.0, 170.0], EndPoint=[60.0, 30.0]), ErrorID.Ecil),  # past LimPos 300
    ],
)
def test_bad_arcs_are_refused_and_leave_the_group_alone(inputs: dict[str, Any], code: int) -> None:
    """A refused arc reports Error/ErrorID on its first scan and the running move goes on to its
    target (Tab. 2.3 rule 9)."""
    machine = make_machine("XY", LimPos=300.0, LimNeg=-300.0)
    group = build_group(machine, "XY")
    first = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[60.0, 30.0], **DYN)
    run(machine, first, until=lambda: machine.runtime.time > 0.1)
    bad = circle(AxesGroup=group, **{**GOOD, **inputs})
    bad(Execute=True)
    assert bad.Error and bad.ErrorID == code
    assert not bad.Busy and not bad.Active
    assert first.Active and group.state == GroupState.GroupMoving
    run(machine, first, until=lambda: first.Done)
    assert [a.sp_pos for a in group.axes] == pytest.approx([60.0, 30.0], abs=1e-9)


def test_absolute_arc_needs_ref(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    _, group = xy
    group.axes[1].Ref = False
    move = circle(AxesGroup=group, **GOOD)
    move(Execute=True)
    assert move.Error and move.ErrorID == ErrorID.Ehome


def test_a_member_fault_in_a_helix_stops_the_others_on_the_circle(
    xyz: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """Z, lifting along a helix, runs into an obstacle (following error): the helix reports
    ERRPOSG 8001, and X and Y ramp down on their fastest ramp on the circle."""
    machine, group = xyz
    machine.sims["Z"].blocked_at = 0.2 + 0.003  # an obstacle 3 mm above Z's start [m]
    rec = record(machine, "XYZ")
    helix = circle(
        AxesGroup=group,
        CircMode=CENTER,
        AuxPoint=[10.0, 0.0, 0.0],
        EndPoint=[0.0, 0.0, 20.0],
        PathChoice=CCW,
        Plane=17,
        Turns=1,
    )
    run(machine, helix, until=lambda: helix.Error, timeout=5.0)
    assert helix.ErrorID == ErrorID.ERRPOSG
    machine.run(lambda: helix(Execute=True), timeout=0.3)
    x, y, _ = group.axes
    assert x.state == y.state == AxisState.StandStill
    assert radius_error(rec, [10.0, 0.0], 10.0) < 1e-9
    assert group.state == GroupState.GroupErrorStop


def test_group_disable_in_an_arc_stops_on_the_circle(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    rec = record(machine, "XY")
    move = circle(
        AxesGroup=group, CircMode=CENTER, AuxPoint=[0.0, 10.0], EndPoint=[0.0, 0.0], PathChoice=CW
    )
    run(machine, move, until=lambda: machine.runtime.time > 0.3)
    disable = mcl.MC_GroupDisable(AxesGroup=group)
    run(machine, move, disable, until=lambda: disable.Done)
    assert move.CommandAborted and group.state == GroupState.GroupDisabled
    assert radius_error(rec, [0.0, 10.0], 10.0) < 1e-9
    assert all(a.sp_vel == 0.0 for a in group.axes)

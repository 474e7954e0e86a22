"""Paths of an axes group (PLCopen Part 4 MC_MovePath, MC_PathSelect, MC_MoveDirect*;
docs/reference.md, Group paths) on simulated axes: a table of lines and arcs built in Python or
read from G-code, its outputs scan by scan, the look-ahead before a tight arc, the tables and
G-code lines that are refused, and synchronized point-to-point moves."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

import mcl
from mcl import MC_CIRC_MODE, MC_CIRC_PATHCHOICE, ErrorID, GroupState
from mcl import MC_PATH_SEGMENT as SEG
from mcl import MC_BufferMode as B
from mcl.geometry import Geometry, Line, arc
from tests.helpers import make_machine
from tests.mcl.test_fb_rules import exclusive
from tests.mcl.test_group import build_group, record
from tests.mcl.test_group_arcs import DT, derivative, run

CENTER, RADIUS, BORDER = MC_CIRC_MODE.CENTER, MC_CIRC_MODE.RADIUS, MC_CIRC_MODE.BORDER
CW, CCW = MC_CIRC_PATHCHOICE.CLOCKWISE, MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
V, ACC, JERK = 80.0, 2000.0, 50000.0
DYN = dict(Velocity=V, Acceleration=ACC, Deceleration=ACC, Jerk=JERK)


def arc_seg(end: list[float], centre: list[float], choice: int = CCW, **more: Any) -> SEG:
    return SEG(
        Circular=True,
        EndPoint=end,
        AuxPoint=centre,
        CircMode=CENTER,
        PathChoice=choice,
        **{**DYN, **more},
    )


def line_seg(end: list[float], **more: Any) -> SEG:
    return SEG(EndPoint=end, **{**DYN, **more})


ROUNDED = mcl.MC_PATH_DATA_REF(
    Segments=[
        line_seg([50.0, 0.0]),
        arc_seg([60.0, 10.0], [50.0, 10.0]),
        line_seg([60.0, 30.0]),
        arc_seg([50.0, 40.0], [50.0, 30.0]),
        line_seg([10.0, 40.0]),
        arc_seg([0.0, 30.0], [10.0, 30.0]),
        line_seg([0.0, 10.0]),
        arc_seg([10.0, 0.0], [10.0, 10.0]),
    ]
)
"""A rounded rectangle 60 × 40 mm, corner radius 10 mm, counter-clockwise from (10, 0)."""
ROUNDED_PIECES: list[Geometry] = [
    Line([10.0, 0.0], [50.0, 0.0]),
    arc([50.0, 0.0], CENTER, [50.0, 10.0], [60.0, 10.0], CCW),
    Line([60.0, 10.0], [60.0, 30.0]),
    arc([60.0, 30.0], CENTER, [50.0, 30.0], [50.0, 40.0], CCW),
    Line([50.0, 40.0], [10.0, 40.0]),
    arc([10.0, 40.0], CENTER, [10.0, 30.0], [0.0, 30.0], CCW),
    Line([0.0, 30.0], [0.0, 10.0]),
    arc([0.0, 10.0], CENTER, [10.0, 10.0], [10.0, 0.0], CCW),
]
ROUNDED_GCODE = """%
(rounded rectangle 60 x 40, R10, counter-clockwise)
N10 G21 G90 G17 G40 G94
N20 G00 X10 Y0
N30 G01 X50 F4800
N40 G03 X60 Y10 I0 J10
N50 G01 Y30
N60 G03 X50 Y40 R10
N70 G01 X10
N80 G03 X0 Y30 I0 J-10 ; a comment
N90 G01 Y10
N100 G03 X10 Y0 I10 J0
M30
%
"""
"""The same contour in G-code (F4800 mm/min = 80 mm/s), from a rapid move to its start."""


def distance(p: Any, pieces: list[Geometry]) -> float:
    return min(g.distance(p) for g in pieces)


@pytest.fixture
def xy() -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    machine = make_machine("XY")
    return machine, build_group(machine, "XY")


def go_to(machine: mcl.SimMachine, group: mcl.AxesGroup, point: list[float]) -> None:
    move = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=point, **DYN)
    run(machine, move, until=lambda: move.Done)


# ---------------------------------------------------------------------- MC_MovePath
def test_a_table_of_lines_and_arcs_runs_scan_by_scan(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """The rounded rectangle: Busy and Active from the Execute edge, Done in the scan the last
    segment ends (exclusive of the others on every scan); the path speed holds V through every
    tangent corner, the jerk within J, the set point within the corner tolerance."""
    machine, group = xy
    go_to(machine, group, [10.0, 0.0])
    rec = record(machine, "XY")
    path = mcl.MC_MovePath(AxesGroup=group, PathData=ROUNDED)
    scans: list[tuple[bool, bool, bool, float]] = []

    def program() -> None:
        path(Execute=True)
        exclusive(path)
        here = [a.sp_pos for a in group.axes]
        scans.append((path.Busy, path.Active, path.Done, math.dist(here, (10.0, 0.0))))

    program()
    assert path.Busy and path.Active and group.state == GroupState.GroupMoving
    machine.run(program, until=lambda: path.Done, timeout=10.0)
    assert all(busy and active and not done for busy, active, done, _ in scans[:-1])
    assert scans[-1][3] < 1e-12 < scans[-2][3]  # Done in the scan the path reached its end
    speeds = rec.speeds()
    cruise = [i for i, s in enumerate(speeds) if s > V * 0.999]
    assert min(speeds[cruise[0] : cruise[-1]]) > V * 0.995
    jerk = derivative(derivative(rec.velocity))
    assert max(max(abs(x) for x in j) for j in jerk[1:]) <= JERK * 1.01
    assert max(distance(p, ROUNDED_PIECES) for p in rec.model) <= group.corner_tolerance * 0.9
    machine.run(program, timeout=0.05)
    assert path.Done and group.state == GroupState.GroupStandby


def test_segments_follow_their_buffer_modes(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """A Buffered segment stops exactly at its corner; the blended ones do not stop."""
    machine, group = xy
    table = mcl.MC_PATH_DATA_REF(
        Segments=[
            line_seg([40.0, 0.0]),
            line_seg([40.0, 30.0], BufferMode=B.Buffered),
            line_seg([0.0, 30.0]),
        ]
    )
    rec = record(machine, "XY")
    path = mcl.MC_MovePath(AxesGroup=group, PathData=table)
    run(machine, path, until=lambda: path.Done)

    def slowest_near(corner: list[float]) -> float:
        near = [
            s for p, s in zip(rec.model, rec.speeds(), strict=True) if math.dist(p, corner) < 1.0
        ]
        return min(near)

    assert slowest_near([40.0, 0.0]) < 1e-9
    assert slowest_near([40.0, 30.0]) > 1.0


def test_look_ahead_slows_the_path_before_a_tight_arc(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """A fast line, a 0.5 mm line and an arc of R = 1 mm: the path has slowed to the arc's
    velocity before it enters the short line (the arc's successor alone could not), never
    exceeding it on the arc, and the table completes."""
    machine, group = xy
    table = mcl.MC_PATH_DATA_REF(
        Segments=[
            line_seg([100.0, 0.0], Velocity=300.0),
            line_seg([100.5, 0.0], Velocity=300.0),
            arc_seg([101.5, 1.0], [100.5, 1.0], Velocity=300.0),
            line_seg([101.5, 20.0], Velocity=300.0),
        ]
    )
    rec = record(machine, "XY")
    path = mcl.MC_MovePath(AxesGroup=group, PathData=table)
    run(machine, path, until=lambda: path.Done or path.Error)
    assert path.Done
    cap = min(math.sqrt(0.7 * ACC * 1.0), (0.5 * JERK * 1.0) ** (1.0 / 3.0))
    on_arc = [
        s for p, s in zip(rec.model, rec.speeds(), strict=True) if p[0] > 100.6 and p[1] < 0.9
    ]
    assert max(on_arc) <= cap * 1.001
    acc = derivative(rec.velocity)
    assert max(max(abs(x) for x in a) for a in acc) <= ACC * 1.01


@pytest.mark.parametrize(
    ("table", "code"),
    [
        (None, ErrorID.EParam),
        ("G01 X10", ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[]), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0])], NumberOfSegments=2), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0])], NumberOfSegments=0), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0])]), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0, 5.0])]), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, math.inf])]), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0], Velocity=math.nan)]), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0], Acceleration=-1.0)]), ErrorID.EParam),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0], Velocity=1.0)]), ErrorID.EParam),
        (
            mcl.MC_PATH_DATA_REF(
                Segments=[line_seg([5.0, 5.0]), line_seg([9.0, 5.0], BufferMode=8)]
            ),
            ErrorID.EParam,
        ),
        (
            mcl.MC_PATH_DATA_REF(
                Segments=[
                    line_seg([5.0, 5.0]),
                    SEG(Circular=True, EndPoint=[20.0, 5.0], AuxPoint=[10.0, 5.0], CircMode=BORDER),
                ]
            ),
            ErrorID.EParam,
        ),
        (
            mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 5.0]), arc_seg([9.0, 5.0], [5.0, 9.0])]),
            ErrorID.EParam,
        ),
        (mcl.MC_PATH_DATA_REF(Segments=[line_seg([5.0, 400.0])]), ErrorID.Ecil),
        (
            mcl.MC_PATH_DATA_REF(
                Segments=[line_seg([0.0, 250.0]), arc_seg([0.0, 250.0], [0.0, 280.0])]
            ),  # a full circle up to y = 310
            ErrorID.Ecil,
        ),
    ],
)
def test_a_bad_table_is_refused_and_leaves_the_group_alone(table: Any, code: int) -> None:
    """Checked as a whole on the Execute edge: the running move goes on to its target."""
    machine = make_machine("XY", LimPos=300.0, LimNeg=-300.0)
    group = build_group(machine, "XY")
    first = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[60.0, 30.0], **DYN)
    run(machine, first, until=lambda: machine.runtime.time > 0.1)
    path = mcl.MC_MovePath(AxesGroup=group, PathData=table, BufferMode=B.Buffered)
    path(Execute=True)
    assert path.Error and path.ErrorID == code
    assert not path.Busy and first.Active
    run(machine, first, until=lambda: first.Done)
    assert [a.sp_pos for a in group.axes] == pytest.approx([60.0, 30.0], abs=1e-9)


def test_an_absolute_table_needs_ref_a_relative_one_does_not(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    machine, group = xy
    group.axes[0].Ref = False
    path = mcl.MC_MovePath(AxesGroup=group, PathData=ROUNDED)
    path(Execute=True)
    assert path.Error and path.ErrorID == ErrorID.Ehome
    relative = mcl.MC_PATH_DATA_REF(
        Segments=[line_seg([10.0, 0.0], Relative=True), line_seg([0.0, 10.0], Relative=True)]
    )
    start = group.start_point(B.Aborting)
    other = mcl.MC_MovePath(AxesGroup=group, PathData=relative)
    run(machine, other, until=lambda: other.Done or other.Error)
    assert other.Done
    assert [a.sp_pos for a in group.axes] == pytest.approx([start[0] + 10.0, start[1] + 10.0])


# ---------------------------------------------------------------------- G-code
def test_a_gcode_contour_runs_as_its_table(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], tmp_path: Path
) -> None:
    """MC_PathSelect reads the rounded rectangle from a file, MC_MovePath runs it: a rapid move
    to the start, then the contour on the commanded path."""
    machine, group = xy
    program_file = tmp_path / "rounded.nc"
    program_file.write_text(ROUNDED_GCODE, encoding="utf-8")
    select = mcl.MC_PathSelect(PathDescription=str(program_file))
    select(Execute=True)
    assert select.Done and not select.Error and select.ErrorText == ""
    table = select.PathData
    assert len(table.Segments) == 9 and table.Segments[1].Velocity == pytest.approx(80.0)
    go_to(machine, group, [-150.0, 0.0])
    rec = record(machine, "XY")
    path = mcl.MC_MovePath(AxesGroup=group, PathData=table)
    run(machine, path, until=lambda: path.Done or path.Error)
    assert path.Done
    reached = next(i for i, p in enumerate(rec.model) if p[0] >= 10.0)  # the contour's start
    rapid = max(rec.speeds()[:reached])
    assert rapid == pytest.approx(0.8 * 500.0, rel=1e-6)  # G00: 80 % of X's Vmax
    contour = rec.model[reached:]
    assert len(contour) > 1000
    assert max(distance(p, ROUNDED_PIECES) for p in contour) <= group.corner_tolerance * 0.9
    assert [a.sp_pos for a in group.axes] == pytest.approx([10.0, 0.0], abs=1e-9)


def test_gcode_modal_words_planes_helix_and_turns() -> None:
    table = mcl.parse_gcode(
        """G91 G01 X10 F600
Y5
G90 G18 G02 X0 Z0 I-5 K0 P2
G17 G03 X0 Y0 Z3 R-4
G61 G01 X1
G64 G00 Y2
""",
        "modal.nc",
        rapid=250.0,
    )
    first, second, helix, radius, exact, rapid = table.Segments
    assert first.Relative and first.EndPoint[:1] == [10.0] and math.isnan(first.EndPoint[1])
    assert first.Velocity == pytest.approx(10.0)  # 600 mm/min
    assert second.Relative and second.EndPoint[1] == 5.0 and second.Velocity == pytest.approx(10.0)
    assert helix.Circular and helix.Plane == 18 and helix.CircMode == CENTER
    assert helix.PathChoice == CW and helix.Turns == 1 and helix.AuxRelative
    assert helix.AuxPoint == [-5.0, 0.0, 0.0] and not helix.Relative
    assert radius.CircMode == RADIUS and radius.AuxPoint[0] == -4.0 and radius.PathChoice == CCW
    assert exact.BufferMode == B.Buffered and rapid.BufferMode == B.BlendingLow
    assert rapid.Velocity == 250.0 and rapid.Source == "modal.nc:6"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("G01 X10", "1: no feed: give F"),
        ("X10 Y5", "1: coordinates without a motion"),
        ("G01 X10 F0", "1: F must be a feed > 0"),
        ("G00 X0\nG01 X1 X2 F100", "2: X appears twice"),
        ("G20", "1: G20 (inches) is not taken"),
        ("G54 G00 X1", "1: G54 is not taken; this reader takes G00, G01"),
        ("G00 X1 A5", "1: A5 is not read here"),
        ("G01 X1 I2 F100", "1: I, J, K, R and P belong to an arc"),
        ("G02 X1 Y1 F100", "1: an arc needs its centre"),
        ("G02 X1 Y1 I1 R2 F100", "1: an arc takes its centre (I, J, K) or its radius R"),
        ("G17 G02 X1 Y1 K1 F100", "1: K is no centre offset in G17: use I and J"),
        ("G02 X1 Y1 I1 P0 F100", "1: P is the number of turns"),
        ("G00 X0 Y0\nG02 X10 Y0 R2 F100", "2: no such arc: RADIUS 2 is shorter"),
        ("G00 X0 Y0\nG02 X10 Y1 I5 J0 F100", "2: no such arc: the end point"),
        ("G01 X1 (unclosed F100", "1: a comment ( … ) is not closed"),
        ("G01 X1 F100 @", "1: cannot read '@'"),
        ("G1.5 X1", "1: G1.5 is not taken"),
        ("(nothing)\n%", "no motion in it"),
    ],
)
def test_a_malformed_gcode_line_is_one_message_with_file_and_line(text: str, message: str) -> None:
    with pytest.raises(mcl.GCodeError) as caught:
        mcl.parse_gcode(text, "part.nc")
    assert str(caught.value).startswith("part.nc")
    assert message in str(caught.value)


def test_path_select_reports_what_it_cannot_read(tmp_path: Path) -> None:
    """A missing file or a malformed line: Error, EParam, the reason in ErrorText; G-code text
    with a line break is read as it is."""
    select = mcl.MC_PathSelect(PathDescription=str(tmp_path / "missing.nc"))
    select(Execute=True)
    assert select.Error and select.ErrorID == ErrorID.EParam
    assert "missing.nc: cannot read it" in select.ErrorText
    select(Execute=False)
    bad = tmp_path / "bad.nc"
    bad.write_text("G21\nG01 X5\n", encoding="utf-8")
    select(Execute=True, PathDescription=str(bad))
    assert select.Error and select.ErrorText.startswith(f"{bad}:2: no feed")
    select(Execute=False)
    assert not select.Error
    select(Execute=True, PathDescription="G01 X5 F100\nY5\n")
    assert select.Done and select.ErrorText == "" and len(select.PathData.Segments) == 2
    select(Execute=False)
    select(Execute=True, PathDescription="", RapidVelocity=0.0)
    assert select.Error and select.ErrorID == ErrorID.EParam


def test_read_gcode_reads_a_file(tmp_path: Path) -> None:
    program_file = tmp_path / "r.nc"
    program_file.write_text(ROUNDED_GCODE, encoding="utf-8")
    table = mcl.read_gcode(program_file)
    assert table.Name == str(program_file) and table.Segments[3].Source == f"{program_file}:7"


# ---------------------------------------------------------------------- MC_MoveDirect*
def test_direct_move_starts_and_ends_every_axis_together(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """X 120 mm and Y 30 mm at 100 mm/s: X, which needs longest, runs at 100 mm/s, Y at a
    quarter of it; both start in the same cycle and arrive in the same cycle; the path is
    faster than MC_MoveLinearAbsolute's at the same Velocity."""
    machine, group = xy
    rec = record(machine, "XY")
    move = mcl.MC_MoveDirectAbsolute(
        AxesGroup=group, Position=[120.0, 30.0], **{**DYN, "Velocity": 100.0}
    )
    run(machine, move, until=lambda: move.Done)
    vx = [abs(v[0]) for v in rec.velocity]
    vy = [abs(v[1]) for v in rec.velocity]
    moving_x = [i for i, v in enumerate(vx) if v > 1e-9]
    moving_y = [i for i, v in enumerate(vy) if v > 1e-9]
    assert (moving_x[0], moving_x[-1]) == (moving_y[0], moving_y[-1])
    assert max(vx) == pytest.approx(100.0, rel=1e-6) and max(vy) == pytest.approx(25.0, rel=1e-6)
    direct_time = len(moving_x) * DT
    machine2 = make_machine("XY")
    group2 = build_group(machine2, "XY")
    rec2 = record(machine2, "XY")
    linear = mcl.MC_MoveLinearAbsolute(
        AxesGroup=group2, Position=[120.0, 30.0], **{**DYN, "Velocity": 100.0}
    )
    run(machine2, linear, until=lambda: linear.Done)
    assert sum(1 for v in rec2.velocity if abs(v[0]) > 1e-9) * DT > direct_time


def test_direct_relative_move_binds_each_axis(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """MC_MoveDirectRelative by (−40, 40): both axes at the velocity, each within the
    acceleration."""
    machine, group = xy
    start = group.start_point(B.Aborting)
    rec = record(machine, "XY")
    move = mcl.MC_MoveDirectRelative(AxesGroup=group, Distance=[-40.0, 40.0], **DYN)
    run(machine, move, until=lambda: move.Done)
    assert max(abs(v[0]) for v in rec.velocity) == pytest.approx(V, rel=1e-6)
    assert max(abs(v[1]) for v in rec.velocity) == pytest.approx(V, rel=1e-6)
    acc = derivative(rec.velocity)
    assert max(max(abs(x) for x in a) for a in acc) <= ACC * 1.01
    assert [a.sp_pos for a in group.axes] == pytest.approx([start[0] - 40.0, start[1] + 40.0])
    assert all(
        abs((p[0] - start[0]) + (p[1] - start[1])) < 1e-6 for p in rec.model[5:]
    )  # on the straight line
    assert move.CoordSystem == mcl.MC_COORD_SYSTEM.ACS

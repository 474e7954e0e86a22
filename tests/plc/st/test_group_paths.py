"""Group paths from Structured Text: an ST program commands an arc (MC_MoveCircularRelative,
the CircMode and PathChoice by their PLCopen names) and a path (MC_MovePath over a table built
in ST: a STRUCT with the segment fields it needs, read by name)."""

from __future__ import annotations

import math

import pytest

import mcl
import plc.st
from mcl.geometry import Line, arc
from tests.helpers import make_machine
from tests.mcl.test_group import Recorder, record

GROUP_XY = """\
powerX(Axis := X, Enable := TRUE);
powerY(Axis := Y, Enable := TRUE);
addX(AxesGroup := grp, Axis := X, Execute := powerX.Status AND powerY.Status);
addY(AxesGroup := grp, Axis := Y, Execute := addX.Done);
enable(AxesGroup := grp, Execute := addY.Done);
"""
"""The statements that power X and Y, group them in ``grp`` and enable it (``enable.Done``)."""

ARC = f"""\
PROGRAM arcs
VAR
  go : BOOL;
  grp : AXES_GROUP_REF := (CornerTolerance := 0.02);
  powerX, powerY : MC_Power;
  addX, addY : MC_AddAxisToGroup;
  enable : MC_GroupEnable;
  circle : MC_MoveCircularRelative;
  centre : ARRAY[0..1] OF LREAL := [20.0, 0.0];
  finish : ARRAY[0..1] OF LREAL := [40.0, 0.0];
  done : BOOL;
END_VAR
{GROUP_XY}circle(AxesGroup := grp, Execute := go AND enable.Done, CircMode := CENTER,
       AuxPoint := centre, EndPoint := finish, PathChoice := COUNTERCLOCKWISE,
       Velocity := 50.0, Acceleration := 2000.0, Deceleration := 2000.0, Jerk := 50000.0);
done := circle.Done;
END_PROGRAM
"""

PATH = """\
TYPE PathSegment :
STRUCT
  Circular : BOOL;
  EndPoint : ARRAY[0..1] OF LREAL;
  AuxPoint : ARRAY[0..1] OF LREAL;
  CircMode : MC_CIRC_MODE;
  PathChoice : MC_CIRC_PATHCHOICE;
  Velocity : LREAL := 50.0;
  Acceleration : LREAL := 2000.0;
  Deceleration : LREAL := 2000.0;
  Jerk : LREAL := 50000.0;
  BufferMode : MC_BufferMode := BlendingLow;
END_STRUCT
END_TYPE
TYPE PathTable :
STRUCT
  NumberOfSegments : INT;
  Segments : ARRAY[0..3] OF PathSegment;
END_STRUCT
END_TYPE
PROGRAM paths
VAR
  go : BOOL;
  grp : AXES_GROUP_REF := (CornerTolerance := 0.02);
  powerX, powerY : MC_Power;
  refX, refY : MC_FinishHoming;
  addX, addY : MC_AddAxisToGroup;
  enable : MC_GroupEnable;
  path : MC_MovePath;
  table : PathTable;
  done : BOOL;
END_VAR
(* a slot: a line, a half circle, a line back, a half circle home *)
table.NumberOfSegments := 4;
table.Segments[0].EndPoint[0] := 40.0;
table.Segments[1].Circular := TRUE;
table.Segments[1].CircMode := CENTER;
table.Segments[1].PathChoice := COUNTERCLOCKWISE;
table.Segments[1].AuxPoint[0] := 40.0;
table.Segments[1].AuxPoint[1] := 10.0;
table.Segments[1].EndPoint[0] := 40.0;
table.Segments[1].EndPoint[1] := 20.0;
table.Segments[2].EndPoint[1] := 20.0;
table.Segments[3].Circular := TRUE;
table.Segments[3].CircMode := RADIUS;
table.Segments[3].PathChoice := COUNTERCLOCKWISE;
table.Segments[3].AuxPoint[0] := 10.0;
powerX(Axis := X, Enable := TRUE);
powerY(Axis := Y, Enable := TRUE);
refX(Axis := X, Execute := powerX.Status);
refY(Axis := Y, Execute := powerY.Status);
addX(AxesGroup := grp, Axis := X, Execute := refX.Done AND refY.Done);
addY(AxesGroup := grp, Axis := Y, Execute := addX.Done);
enable(AxesGroup := grp, Execute := addY.Done);
path(AxesGroup := grp, Execute := go AND enable.Done, PathData := table);
done := path.Done;
END_PROGRAM
"""


def _run(source: str, name: str) -> tuple[plc.st.STProgram, mcl.SimMachine, Recorder]:
    """Load ``source`` on two fresh simulated axes X, Y, let it group them, then set ``go``
    and scan it until ``done`` (or an error)."""
    machine = make_machine("XY", powered=False)
    prog = plc.st.from_source(source, machine, filename=name)
    machine.run(prog, timeout=0.05)
    rec = record(machine, "XY")
    prog.go = True
    machine.run(prog, until=lambda: prog.done or bool(prog.error), timeout=10.0)
    assert not prog.error
    return prog, machine, rec


def test_an_st_program_commands_an_arc() -> None:
    """A half circle of R = 20 mm counter-clockwise about (20, 0): Done at (40, 0), every set
    point on the circle, below the X axis (counter-clockwise from (0, 0))."""
    prog, machine, rec = _run(ARC, "arc.st")
    assert prog.circle.Done and prog.circle.ErrorID == 0
    assert [a.sp_pos for a in machine.axes.values()] == pytest.approx([40.0, 0.0], abs=1e-9)
    assert max(abs(math.dist(p, (20.0, 0.0)) - 20.0) for p in rec.model) < 1e-9
    assert min(p[1] for p in rec.model) == pytest.approx(-20.0, abs=1e-3)


def test_an_st_program_commands_a_path_from_its_own_table() -> None:
    """The slot of the ST table: a line, a half circle by its centre, a line back, a half circle
    by its radius; Done back at the start, the set point within the corner tolerance."""
    prog, machine, rec = _run(PATH, "path.st")
    assert prog.path.Done and prog.path.ErrorID == 0
    pieces = [
        Line([0.0, 0.0], [40.0, 0.0]),
        arc([40.0, 0.0], mcl.MC_CIRC_MODE.CENTER, [40.0, 10.0], [40.0, 20.0], 1),
        Line([40.0, 20.0], [0.0, 20.0]),
        arc([0.0, 20.0], mcl.MC_CIRC_MODE.RADIUS, [10.0, 0.0], [0.0, 0.0], 1),
    ]
    assert max(min(g.distance(p) for g in pieces) for p in rec.model) <= 0.02 * 0.9
    assert min(p[0] for p in rec.model) == pytest.approx(-10.0, abs=1e-3)
    assert [a.sp_pos for a in machine.axes.values()] == pytest.approx([0.0, 0.0], abs=1e-9)

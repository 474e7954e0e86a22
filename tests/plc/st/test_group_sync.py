"""MC_SyncAxisToGroup, MC_MovePathSynchronized and MC_TrackRotaryTable from Structured Text: a
program groups three simulated arms with the delta kinematics, couples a single axis to the tool
point's z, runs a path whose progress follows a belt axis, and then makes the PCS turn with a
rotary table (the master and the table passed as AXIS_REF, the frames as ARRAY OF LREAL)."""

from __future__ import annotations

import math

import pytest

import mcl
import plc.st
from tests.helpers import make_machine
from tests.mcl.test_group_kinematics import DELTA

SOURCE = """\
TYPE Kin :
STRUCT
  BaseRadius, EffectorRadius, UpperArm, Forearm : LREAL;
END_STRUCT
END_TYPE
PROGRAM synchronized
VAR
  A, B, C, S, D, T : AXIS_REF;
  grp : AXES_GROUP_REF;
  kin : Kin := (BaseRadius := 200.0, EffectorRadius := 50.0, UpperArm := 350.0,
    Forearm := 800.0);
  addA, addB, addC : MC_AddAxisToGroup;
  enable : MC_GroupEnable;
  set : MC_SetKinTransform;
  follow : MC_SyncAxisToGroup;
  belt : MC_MoveVelocity;
  path : MC_MovePathSynchronized;
  table : MC_MoveVelocity;
  track : MC_TrackRotaryTable;
  target : ARRAY[0..2] OF LREAL := [0.0, 0.0, -700.0];
  centre : ARRAY[0..2] OF LREAL := [-450.0, 0.0, -760.0];
  part : ARRAY[0..2] OF LREAL := [150.0, 0.0, 0.0];
END_VAR
addA(AxesGroup := grp, Axis := A, Execute := TRUE);
addB(AxesGroup := grp, Axis := B, Execute := addA.Done);
addC(AxesGroup := grp, Axis := C, Execute := addB.Done);
enable(AxesGroup := grp, Execute := addC.Done);
set(AxesGroup := grp, Execute := enable.Done, KinTransform := kin);
follow(AxesGroup := grp, Axis := S, Execute := set.Done, CoordSystem := MC_COORD_SYSTEM#MCS,
  Coordinate := 2, Offset := 800.0);
belt(Axis := D, Execute := follow.InSync, Velocity := 200.0);
path(AxesGroup := grp, Master := D, Execute := follow.InSync, Position := target,
  MasterStart := 10.0, Ratio := 0.25);
table(Axis := T, Execute := path.Done, Velocity := 30.0);
track(AxesGroup := grp, Execute := table.InVelocity, RotaryTable := T,
  RotaryTableOrigin := centre, InitialObjectPosition := part, LatchedPosition := T.POS);
END_PROGRAM
"""


def test_an_st_program_couples_an_axis_runs_a_synchronized_path_and_tracks_a_table() -> None:
    machine = make_machine("ABCSDT")
    prog = plc.st.from_source(SOURCE, machine, filename="synchronized.st")
    machine.run(prog, until=lambda: prog.path.Done or prog.path.Error, timeout=5.0)
    assert prog.path.Done and not prog.follow.Error, prog.path.ErrorID
    tool = DELTA.forward([machine.axes[n].sp_pos for n in "ABC"])
    assert math.dist(tool, [0.0, 0.0, -700.0]) < 1e-6
    assert prog.follow.InSync
    assert machine.axes["S"].sp_pos == pytest.approx(tool[2] + 800.0, abs=1e-3)
    machine.run(prog, until=lambda: prog.track.Done or prog.track.Error, timeout=3.0)
    assert prog.track.Done, prog.track.ErrorID
    frame = prog.grp.kin.frame
    assert isinstance(frame, mcl.ProductFrame) and frame.rotary
    assert frame.master is machine.axes["T"]

"""The delta picker's kinematics from Structured Text: MC_SetKinTransform takes a STRUCT of the
delta's parameters (MC_KIN_REF, read by name); a program homes, groups, sets the kinematics and
moves the tool point along a Cartesian line, measured on the physics; a program tracks a part on
a belt (MC_TrackConveyorBelt) and sets fixed product coordinate systems."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mcl
import plc.st
import scenes
from tests.helpers import make_machine
from tests.mcl.test_group_kinematics import DELTA

EXAMPLE = Path(__file__).parents[3] / "examples" / "st" / "delta_line.st"


def test_an_st_program_moves_the_delta_pickers_tool_point_along_a_cartesian_line() -> None:
    scene = scenes.load("delta_picker", trace_every=0)
    prog = plc.st.load(EXAMPLE, scene)
    scene.run(prog, until=lambda: prog.done or bool(prog.fault), timeout=20.0)
    assert prog.done and not prog.fault
    scene.run(prog, timeout=0.2)
    cup = 1000.0 * scene.data.site_xpos[scene.model.site("delta_picker/tool").id]
    # the MCS origin 1.6 m above the floor, the cup's face 50 mm below the tool point
    tool = cup - np.array([0.0, 0.0, 1600.0 - 50.0])
    assert np.linalg.norm(tool - np.array([250.0, 100.0, -790.0])) < 0.3
    read = mcl.MC_ReadKinTransform(AxesGroup=prog.robot, Enable=True)
    read()
    assert read.Name == "delta" and read.Parameters["forearm"] == 800.0


BAD = """\
TYPE Kin :
STRUCT
  BaseRadius, EffectorRadius, UpperArm : LREAL;
  {forearm}
END_STRUCT
END_TYPE
PROGRAM bad
VAR
  A, B, C : AXIS_REF;
  grp : AXES_GROUP_REF;
  kin : Kin := (BaseRadius := 200.0, EffectorRadius := 50.0, UpperArm := 350.0{value});
  addA, addB, addC : MC_AddAxisToGroup;
  set : MC_SetKinTransform;
END_VAR
addA(AxesGroup := grp, Axis := A, Execute := TRUE);
addB(AxesGroup := grp, Axis := B, Execute := TRUE);
addC(AxesGroup := grp, Axis := C, Execute := TRUE);
set(AxesGroup := grp, Execute := addC.Done, KinTransform := kin);
END_PROGRAM
"""


@pytest.mark.parametrize(
    ("forearm", "value"),
    [
        ("", ""),  # no forearm: no delta
        ("Forearm : LREAL;", ", Forearm := 300.0"),  # too short to close the chains
    ],
)
def test_a_kin_ref_that_describes_no_delta_is_refused(forearm: str, value: str) -> None:
    machine = make_machine("ABC")
    prog = plc.st.from_source(BAD.format(forearm=forearm, value=value), machine, filename="bad.st")
    machine.run(prog, until=lambda: prog.set.Done or prog.set.Error, timeout=0.1)
    assert prog.set.Error and prog.set.ErrorID == mcl.ErrorID.EParam
    assert prog.grp.kin.transform is None


TRACK = """\
TYPE Kin :
STRUCT
  BaseRadius, EffectorRadius, UpperArm, Forearm : LREAL;
END_STRUCT
END_TYPE
PROGRAM track
VAR
  A, B, C, D : AXIS_REF;
  grp : AXES_GROUP_REF;
  kin : Kin := (BaseRadius := 200.0, EffectorRadius := 50.0, UpperArm := 350.0, Forearm := 800.0);
  addA, addB, addC : MC_AddAxisToGroup;
  enable : MC_GroupEnable;
  set : MC_SetKinTransform;
  belt : MC_MoveVelocity;
  follow : MC_TrackConveyorBelt;
  onto : MC_MoveLinearAbsolute;
  untrack : MC_SetCoordinateTransform;
  shift : MC_SetCartesianTransform;
  origin : ARRAY[0..2] OF LREAL := [-300.0, -100.0, -760.0];
  part : ARRAY[0..2] OF LREAL := [0.0, 0.0, 0.0];
  above : ARRAY[0..2] OF LREAL := [0.0, 0.0, 20.0];
  mcs : ARRAY[0..3] OF LREAL := [0.0, 0.0, 0.0, 0.0];
END_VAR
addA(AxesGroup := grp, Axis := A, Execute := TRUE);
addB(AxesGroup := grp, Axis := B, Execute := TRUE);
addC(AxesGroup := grp, Axis := C, Execute := TRUE);
enable(AxesGroup := grp, Execute := addC.Done);
set(AxesGroup := grp, Execute := enable.Done, KinTransform := kin);
belt(Axis := D, Execute := set.Done, Velocity := 200.0, Acceleration := 2000.0);
follow(AxesGroup := grp, Execute := belt.InVelocity, ConveyorBelt := D,
       ConveyorBeltOrigin := origin, InitialObjectPosition := part, LatchedPosition := D.POS,
       Horizon := 0.2);
onto(AxesGroup := grp, Execute := follow.Done, Position := above, CoordSystem := PCS,
     Velocity := 500.0, Acceleration := 5000.0, Deceleration := 5000.0, Jerk := 200000.0);
untrack(AxesGroup := grp, Execute := onto.Done AND {untrack}, CoordTransform := mcs);
shift(AxesGroup := grp, Execute := untrack.Done, TransX := 10.0, TransZ := -700.0,
      RotAngle1 := 30.0);
END_PROGRAM
"""


def test_an_st_program_tracks_a_part_on_the_belt_and_sets_a_fixed_pcs() -> None:
    """MC_TrackConveyorBelt from ST (the belt an AXIS_REF, the frames ARRAYs): a move in PCS
    lands 20 mm above the moving part and follows it; MC_SetCoordinateTransform ends the
    tracking, MC_SetCartesianTransform sets a fixed PCS turned by 30°."""
    machine = make_machine("ABCD")
    prog = plc.st.from_source(TRACK.format(untrack="FALSE"), machine, filename="track.st")
    machine.run(prog, until=lambda: prog.onto.Done or prog.onto.Error, timeout=3.0)
    assert prog.follow.Done and prog.onto.Done, (prog.follow.ErrorID, prog.onto.ErrorID)
    frame = prog.grp.kin.frame
    assert frame is not None and frame.master is machine.axes["D"]
    for _ in range(3):  # on the part, 20 mm above it, while it moves on
        machine.run(prog, timeout=0.05)
        tool = DELTA.forward([machine.axes[a].sp_pos for a in "ABC"])
        assert np.linalg.norm(np.subtract(tool, frame.point_to_mcs([0.0, 0.0, 20.0]))) < 1e-6
    machine = make_machine("ABCD")
    prog = plc.st.from_source(TRACK.format(untrack="TRUE"), machine, filename="track.st")
    machine.run(prog, until=lambda: prog.shift.Done or prog.shift.Error, timeout=5.0)
    assert prog.untrack.Done and prog.shift.Done, (prog.untrack.ErrorID, prog.shift.ErrorID)
    frame = prog.grp.kin.frame
    assert frame is not None and not frame.moving
    assert frame.origin == [10.0, 0.0, -700.0] and frame.angle == 30.0

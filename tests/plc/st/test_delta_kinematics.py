"""The delta picker's kinematics from Structured Text: MC_SetKinTransform takes a STRUCT of the
delta's parameters (MC_KIN_REF, read by name); a program homes, groups, sets the kinematics and
moves the tool point along a Cartesian line, measured on the physics."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mcl
import plc.st
import scenes
from tests.helpers import make_machine

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

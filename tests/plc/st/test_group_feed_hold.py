"""A feed hold from Structured Text: an ST program interrupts a group's arc with
MC_GroupInterrupt, reads the held state with MC_GroupReadStatus and resumes it with
MC_GroupContinue; the arc ends where it would have ended. MC_GroupSetOverride's AccFactor
limits a line's path acceleration from ST."""

from __future__ import annotations

import itertools
import math

import pytest

import mcl
import plc.st
from tests.helpers import make_machine
from tests.mcl.test_group import record
from tests.plc.st.test_group_paths import GROUP_XY

HOLD = f"""\
PROGRAM hold
VAR
  go, pause, resume : BOOL;
  grp : AXES_GROUP_REF;
  powerX, powerY : MC_Power;
  addX, addY : MC_AddAxisToGroup;
  enable : MC_GroupEnable;
  circle : MC_MoveCircularRelative;
  interrupt : MC_GroupInterrupt;
  proceed : MC_GroupContinue;
  status : MC_GroupReadStatus;
  centre : ARRAY[0..1] OF LREAL := [0.0, 10.0];
  finish : ARRAY[0..1] OF LREAL := [0.0, 0.0];
  held, done : BOOL;
END_VAR
{GROUP_XY}circle(AxesGroup := grp, Execute := go AND enable.Done, CircMode := CENTER,
       AuxPoint := centre, EndPoint := finish, PathChoice := COUNTERCLOCKWISE,
       Velocity := 100.0, Acceleration := 2000.0, Deceleration := 2000.0, Jerk := 50000.0);
interrupt(AxesGroup := grp, Execute := pause, Deceleration := 1000.0, Jerk := 20000.0);
proceed(AxesGroup := grp, Execute := resume);
status(AxesGroup := grp, Enable := TRUE);
held := interrupt.Done AND status.GroupStandby AND circle.Busy AND NOT circle.CommandAborted;
done := circle.Done;
END_PROGRAM
"""


def test_an_st_program_holds_and_resumes_an_arc() -> None:
    machine = make_machine("XY", powered=False)
    prog = plc.st.from_source(HOLD, machine, filename="hold.st")
    machine.run(prog, timeout=0.05)
    rec = record(machine, "XY")
    prog.go = True
    machine.run(prog, until=lambda: machine.runtime.time > 0.3, timeout=1.0)
    prog.pause = True
    machine.run(prog, until=lambda: prog.held or bool(prog.error), timeout=2.0)
    assert prog.held and not prog.error
    held = rec.model[-1]
    machine.run(prog, timeout=0.2)
    assert rec.model[-1] == held and not prog.done
    prog.pause = False
    prog.resume = True
    machine.run(prog, until=lambda: prog.done or bool(prog.error), timeout=5.0)
    assert prog.done and prog.proceed.ErrorID == 0
    assert rec.model[-1] == pytest.approx((0.0, 0.0), abs=1e-9)
    assert max(abs(math.dist(p, (0.0, 10.0)) - 10.0) for p in rec.model) < 1e-9


FACTORS = f"""\
PROGRAM factors
VAR
  go : BOOL;
  acc : LREAL := 0.25;
  grp : AXES_GROUP_REF;
  powerX, powerY : MC_Power;
  addX, addY : MC_AddAxisToGroup;
  enable : MC_GroupEnable;
  override : MC_GroupSetOverride;
  line : MC_MoveLinearRelative;
  target : ARRAY[0..1] OF LREAL := [30.0, 40.0];
  done : BOOL;
END_VAR
{GROUP_XY}override(AxesGroup := grp, Enable := enable.Done, VelFactor := 1.0, AccFactor := acc,
         JerkFactor := 1.0);
line(AxesGroup := grp, Execute := go AND override.Enabled, Distance := target,
     Velocity := 100.0, Acceleration := 2000.0, Deceleration := 2000.0, Jerk := 50000.0);
done := line.Done;
END_PROGRAM
"""


def test_an_st_program_limits_the_path_acceleration_by_acc_factor() -> None:
    """MC_GroupSetOverride with AccFactor 0.25 from ST: the line's path acceleration stays
    within a quarter of its Acceleration (it runs at half its Velocity) to its end; AccFactor 0
    gives the block EParam."""
    machine = make_machine("XY", powered=False)
    prog = plc.st.from_source(FACTORS, machine, filename="factors.st")
    machine.run(prog, timeout=0.05)
    assert prog.override.Enabled
    rec = record(machine, "XY")
    prog.go = True
    machine.run(prog, until=lambda: prog.done or bool(prog.error), timeout=5.0)
    assert prog.done and not prog.error
    speeds = rec.speeds()
    assert max(speeds) == pytest.approx(50.0)
    assert max(abs(b - a) / 0.001 for a, b in itertools.pairwise(speeds)) <= 500.0 * 1.0001
    assert rec.model[-1] == pytest.approx((30.0, 40.0), abs=1e-9)
    prog.acc = 0.0
    machine.run(prog, timeout=0.01)
    assert prog.override.Error and prog.override.ErrorID == mcl.ErrorID.EParam

"""A run-time fault (or a scan beyond the task's watchdog) in an ST program on the gantry while X
moves: the PLC stops, every axis
ramps down to standstill (measured on the joints), the message names file:line, and after a
restart of the program and homing (the stop switched the drives off) the machine moves again."""

import pytest

import mcl
import plc.st
from scenes.tools.testing import home, physical_position

SOURCE = """PROGRAM mover
VAR
  Start : BOOL;
  divisor : INT := 1;
  speed : LREAL;
  table : ARRAY[1..3] OF LREAL := [100.0, 200.0, 300.0];
  pick : INT := 1; hang : BOOL;
  power : MC_Power;
  reset : MC_Reset;
  move : MC_MoveAbsolute;
END_VAR
power(Enable := TRUE, Axis := X);
reset(Execute := power.Status, Axis := X);
speed := table[pick] / divisor;
move(Execute := Start, Position := 800.0, Velocity := speed, Axis := X);
WHILE hang DO pick := pick; END_WHILE
END_PROGRAM
"""


@pytest.fixture
def moving():
    """The homed gantry with X moving at 300 mm/s under the program."""
    import scenes

    gantry = scenes.load("gantry")
    home(gantry, "X", "Y", "Z")
    prog = plc.st.from_source(SOURCE, gantry, filename="mover.st")
    prog.pick, prog.Start = 3, True
    gantry.run(prog, until=lambda: gantry.axes["X"].VEL > 299.0, timeout=3.0)
    return gantry, prog


def joint_speeds(gantry):
    """Joint speeds [mm/s] of every axis, from the physics."""
    return [abs(gantry.data.joint(f"gantry/{a}").qvel[0]) * 1000.0 for a in gantry.axes]


@pytest.mark.parametrize(
    ("fault", "message"),
    [
        ({"divisor": 0}, "mover.st:14: division by zero"),
        ({"pick": 4}, "mover.st:14: array index 4 outside 1..3"),
        ({"hang": True}, "mover.st:16: the scan ran over the task's watchdog of 100 ms"),
    ],
)
def test_a_fault_while_x_moves_stops_the_program_and_every_axis(moving, fault, message):
    gantry, prog = moving
    assert max(joint_speeds(gantry)) > 250.0
    for name, value in fault.items():
        setattr(prog, name, value)
    gantry.run(prog, timeout=1.0)
    assert prog.stopped and prog.error.startswith(message)
    assert prog.error.endswith("; the program stopped")
    assert max(joint_speeds(gantry)) < 0.01  # every joint at standstill [mm/s]
    assert all(a.state == mcl.AxisState.Disabled for a in gantry.axes.values())
    stopped_at = physical_position(gantry, "X")
    gantry.run(prog, timeout=0.5)
    assert physical_position(gantry, "X") == pytest.approx(stopped_at, abs=0.01)


def test_after_a_restart_the_same_program_moves_x_to_its_target(moving):
    gantry, prog = moving
    prog.divisor = 0
    gantry.run(prog, timeout=1.0)
    assert prog.stopped
    prog.restart()
    assert not prog.stopped and prog.divisor == 1 and not prog.Start
    home(gantry, "X")  # the drive was switched off: its reference is gone (MC_Power)
    gantry.run(prog, until=lambda: prog.power.Status, timeout=1.0)
    prog.Start = True
    gantry.run(prog, until=lambda: prog.move.Done, timeout=10.0)
    assert physical_position(gantry, "X") == pytest.approx(800.0, abs=0.05)
    assert not prog.move.Error

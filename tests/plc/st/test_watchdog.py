"""The task's watchdog (IEC 61131-3 2.7.2, 3rd ed. 6.8.2): a scan whose loop runs past it stops
the program with a run-time fault naming file:line and the loop, and the axes ramp down as
after any fault; a TASK's ``WATCHDOG := T#..`` sets its limit (default: 100 ms of wall time)."""

from __future__ import annotations

import mcl
import plc.st
from tests.plc.st.iec import program, refused, run

MOVING = """PROGRAM jog
VAR power : MC_Power; move : MC_MoveVelocity; i : DINT; hang : BOOL; END_VAR
power(Axis := X, Enable := TRUE);
move(Axis := X, Execute := power.Status, Velocity := 50.0);
hang := SIM_TIME() > 0.3;
REPEAT i := i + 1; UNTIL NOT hang END_REPEAT;
END_PROGRAM
"""


def test_a_hanging_loop_stops_the_program_and_the_axis_ramps_down(X: mcl.Axis, machine):
    """The REPEAT hangs once X moves at 50 mm/s: the program stops at the loop's line, X ramps
    down to standstill and is disabled, the machine runs on."""
    prog = plc.st.from_source(MOVING, machine, filename="jog.st")
    machine.run(prog, until=lambda: X.VEL > 49.0, timeout=1.0)
    machine.run(prog, until=lambda: prog.stopped, timeout=1.0)
    assert prog.error == (
        "jog.st:6: the scan ran over the task's watchdog of 100 ms in the REPEAT loop of line 6"
        "; the program stopped"
    )
    machine.run(prog, timeout=1.0)
    assert abs(X.VEL) < 1e-6 and X.state == mcl.AxisState.Disabled


def _tasked(watchdog: str, body: str) -> str:
    config = (
        "CONFIGURATION c RESOURCE r ON PLC "
        f"TASK t(INTERVAL := T#10ms{watchdog}); PROGRAM main WITH t : t; "
        "END_RESOURCE END_CONFIGURATION\n"
    )
    return program("i : DINT; n : DINT;", body) + config


def test_the_task_sets_its_watchdog():
    """WATCHDOG := T#20ms is the TASK's limit, named in the fault."""
    prog = plc.st.from_source(_tasked(", WATCHDOG := T#20ms", "FOR i := 1 TO 2 DO i := 1; END_FOR"))
    prog()
    assert prog.fault.startswith(
        "program.st:5: the scan ran over the task's watchdog of 20 ms in the FOR loop of line 5"
    )


def test_a_long_loop_within_its_watchdog_runs_to_its_end():
    """A finite loop well within the TASK's WATCHDOG ends as written."""
    body = "WHILE n < 20000 DO n := n + 1; END_WHILE"
    prog = plc.st.from_source(_tasked(", WATCHDOG := T#10s", body))
    prog()
    assert not prog.fault and prog.n == 20000


def test_a_loop_in_a_block_names_the_blocks_line():
    """The fault names the line of the loop where the scan was, inside a FUNCTION_BLOCK."""
    spin = (
        "FUNCTION_BLOCK Spin\nVAR k : INT; END_VAR\nWHILE TRUE DO k := k + 1; END_WHILE\n"
        "END_FUNCTION_BLOCK"
    )
    prog = plc.st.from_source(program("s : Spin;", "s();", spin), filename="spin.st")
    prog()
    assert prog.fault.startswith("spin.st:3: the scan ran over the task's watchdog of 100 ms")
    prog()  # stopped: no longer scanned
    assert prog.stopped


def test_a_watchdog_is_a_time():
    """WATCHDOG := 5 is refused at its file:line:column."""
    message = refused(_tasked(", WATCHDOG := 5", ""))
    assert "TASK t WATCHDOG 5; expected a TIME > 0, T#50ms" in message
    assert message.startswith("iec.st:7:")


def test_a_loop_that_ends_costs_no_fault():
    """Loops that end (WHILE, REPEAT, FOR, EXIT, CONTINUE) are unaffected."""
    body = (
        "FOR i := 1 TO 10 DO IF i = 3 THEN CONTINUE; END_IF; n := n + i; END_FOR;"
        "REPEAT n := n + 1; UNTIL n > 60 END_REPEAT;"
        "WHILE TRUE DO n := n + 1; IF n > 70 THEN EXIT; END_IF; END_WHILE"
    )
    assert run(program("i : INT; n : INT;", body)).n == 71

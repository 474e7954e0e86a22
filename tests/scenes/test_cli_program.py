"""``python -m scenes run MACHINE --program FILE`` as a user runs it, in a separate process
reading its output: the program replaces the machine's demo and scans from the first PLC cycle,
and a run-time fault (or the watchdog) is reported once the axes have ramped down to rest,
with the fault's file:line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import ROOT

FIRST_SCANS = """PROGRAM FirstScans
VAR
  status : MC_ReadStatus;
  step : STRING(120);
  n : DINT;
  done : BOOL;
END_VAR
status(Axis := X, Enable := TRUE);
n := n + 1;
IF n = 1 THEN
  step := CONCAT('scan 1: X at ', LREAL_TO_STRING(X.POS));
  IF status.Disabled THEN
    step := CONCAT(step, ' mm, Disabled');
  END_IF
ELSE
  step := CONCAT('scan ', DINT_TO_STRING(n));
END_IF
done := n >= 3;
END_PROGRAM
"""

MOVING = """PROGRAM Moving
VAR
  power : MC_Power;
  run : MC_MoveVelocity;
  n, zero, k : DINT;
  done : BOOL;
END_VAR
power(Axis := X, Enable := TRUE);
run(Axis := X, Execute := power.Status, Velocity := 400.0, Acceleration := 2000.0,
    Deceleration := 2000.0);
IF run.InVelocity THEN
  n := n + 1;
END_IF
IF n > 50 THEN
  {fault}
END_IF
END_PROGRAM
"""


def _run(machine: str, program: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """``python -m scenes run`` of this checkout in a process of its own."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    command = [sys.executable, "-m", "scenes", "run", machine, "--program", str(program), *args]
    return subprocess.run(command, capture_output=True, text=True, env=env, timeout=600)


def test_the_program_replaces_the_demo_and_scans_from_the_first_cycle(tmp_path):
    """The gantry with a program of three scans: its first scan is at t = 0 with X Disabled at
    the coordinate 0 (placed at the demo's start, not homed), one scan per PLC period (2 ms),
    and none of the demo's steps runs."""
    from scenes.machines.gantry.demo import Demo

    path = tmp_path / "first.st"
    path.write_text(FIRST_SCANS)
    done = _run("gantry", path)
    assert done.returncode == 0, done.stderr
    assert "== t= 0.000 s  scan 1: X at 0.0 mm, Disabled\n" in done.stdout
    assert "== t= 0.002 s  scan 2\n" in done.stdout
    assert "== t= 0.004 s  scan 3\n" in done.stdout
    assert not [step for step in Demo.STEPS if step in done.stdout]


@pytest.mark.parametrize(
    ("fault", "message"),
    [
        ("k := 100 / zero;", "integer division by zero"),
        (
            "WHILE TRUE DO k := k + 1; END_WHILE",
            "the scan ran over the task's watchdog of 100 ms in the WHILE loop of line 15",
        ),
    ],
)
def test_a_run_time_fault_is_reported_once_the_axes_are_at_rest(tmp_path, fault, message):
    """X runs at 400 mm/s when the program stops (a division by zero, a WHILE the watchdog
    ends): the summary shows X at rest (Disabled, not still Stopping), and the message names
    the fault's file:line and says the axes ramped down to rest."""
    path = tmp_path / "moving.st"
    path.write_text(MOVING.replace("{fault}", fault))
    done = _run("single_axis", path, "--timeout", "5")
    assert done.returncode == 1
    summary = done.stdout.split("== summary\n", 1)[1]
    assert summary.startswith("X: POS ") and ", state Disabled," in summary.splitlines()[0]
    assert f"{path}:15: {message}; the program stopped" in done.stderr
    assert "; the axes ramped down and were at rest at t=" in done.stderr
    assert "Traceback" not in done.stderr

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


SEQUENCE = """TYPE E_Step : (Init, Run); END_TYPE
PROGRAM Sequence
VAR
  step : E_Step;
  note : STRING;
  a : ARRAY[1..3] OF INT;
  i : INT := 1;
  n : INT;
END_VAR
CASE step OF
  Init: step := Run;
  Run:
    n := n + 1;
    IF n > 10 THEN
      i := i + 1;
      a[i] := n;
    END_IF
END_CASE
END_PROGRAM
"""
"""A sequence that starts in Init, runs, and stops on an array index out of range (line 16)
in its 14th scan (t = 0.026 s on the single axis's 2 ms)."""


def _report(tmp_path, capsys, source: str) -> tuple[int, list[str], str]:
    """``python -m scenes run single_axis --program`` of ``source`` (in this process): the
    exit status, the report's lines, standard error."""
    from scenes.tools.cli import main

    path = tmp_path / "sequence.st"
    path.write_text(source)
    status = main(["run", "single_axis", "--program", str(path), "--timeout", "0.2"])
    out, err = capsys.readouterr()
    return status, out.splitlines(), err


def test_every_step_line_has_its_time_and_a_fault_a_line_of_its_own(tmp_path, capsys):
    """The first step (before the first scan) is timed as every other; the fault that stops
    the program is its own line (``fault: file:line: ...``), not a step."""
    status, lines, err = _report(tmp_path, capsys, SEQUENCE)
    path = tmp_path / "sequence.st"
    fault = f"{path}:16: array index 4 outside 1..3; the program stopped"
    assert status == 1 and fault in err
    steps = [line for line in lines if line.startswith("== ") and line != "== summary"]
    assert steps == ["== t= 0.000 s  Init", "== t= 0.000 s  Run"]
    assert f"t=  0.026 s  fault: {fault}" in lines


def test_an_empty_step_prints_no_step_line(tmp_path, capsys):
    """A STRING ``step`` still empty (before the program writes one) is no step: no line
    ``== `` alone; the step it writes is a timed line."""
    source = SEQUENCE.replace("step : E_Step;", "step : STRING; s : E_Step;")
    source = source.replace("CASE step OF", "CASE s OF").replace(
        "Init: step := Run;", "Init: s := Run;"
    )
    source = source.replace("n := n + 1;", "n := n + 1; step := 'counting';")
    status, lines, _ = _report(tmp_path, capsys, source)
    steps = [line for line in lines if line.startswith("==") and line != "== summary"]
    assert status == 1
    assert steps == ["== t= 0.002 s  counting"]

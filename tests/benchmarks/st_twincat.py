"""A generated TwinCAT-style project for the ST load benchmark (:mod:`tests.benchmarks.st`):
``count`` motion stations, each a FUNCTION_BLOCK in its own ``.TcPOU`` (an axis it powers,
homes, moves between two positions and watches, with its step enumeration and data structure
in ``.TcDUT`` files), a ``.TcGVL`` of the plant's settings, and the PROGRAM that runs every
station on the machine's axis ``X``; as an engineer's IDE exports it."""

from __future__ import annotations

from pathlib import Path

OBJECT = """<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">
{}</TcPlcObject>
"""

STEPS = """TYPE E_Step{i} :
(
  S{i}_Idle := 0,
  S{i}_Powering,
  S{i}_Homing,
  S{i}_ToWork,
  S{i}_ToBase,
  S{i}_Done,
  S{i}_Fault
);
END_TYPE
"""

DATA = """TYPE ST_Station{i} :
STRUCT
  workPosition : LREAL := {work};   (* [mm] *)
  basePosition : LREAL := 0.0;      (* [mm] *)
  cycles : DINT;
  lastError : DINT;
  settled : BOOL;
END_STRUCT
END_TYPE
"""

GLOBALS = """VAR_GLOBAL
  gVelocity : LREAL := 100.0;        (* [mm/s] *)
  gAcceleration : LREAL := 1000.0;   (* [mm/s²] *)
  gCycles : DINT := 2;
  gStop : BOOL;
END_VAR
"""

DECLARATION = """(* station {i}: powers its axis, homes it, then moves between its base and work
   positions gCycles times; any block's error stops it with the ErrorID *)
FUNCTION_BLOCK FB_Station{i}
VAR_INPUT
  Execute : BOOL;
  Velocity : LREAL := 100.0;         (* [mm/s] *)
  HomePosition : LREAL := 0.0;       (* [mm] *)
END_VAR
VAR_IN_OUT
  Axis : AXIS_REF;
END_VAR
VAR_OUTPUT
  Done : BOOL;
  Busy : BOOL;
  Error : BOOL;
  ErrorID : DINT;
END_VAR
VAR
  step : E_Step{i};
  data : ST_Station{i};
  power : MC_Power;
  home : MC_StepDirect;
  move : MC_MoveAbsolute;
  halt : MC_Halt;
  status : MC_ReadStatus;
  position : MC_ReadActualPosition;
  start : R_TRIG;
  settle : TON;
  history : ARRAY[1..8] OF LREAL;
  k : INT;
  mean : LREAL;
END_VAR
"""

IMPLEMENTATION = """start(CLK := Execute);
power(Axis := Axis, Enable := step <> S{i}_Idle AND step <> S{i}_Fault);
home(Axis := Axis, Execute := step = S{i}_Homing, SetPosition := HomePosition);
move(Axis := Axis, Execute := step = S{i}_ToWork OR step = S{i}_ToBase,
     Position := SEL(step = S{i}_ToWork, data.basePosition, data.workPosition),
     Velocity := MIN(Velocity, gVelocity), Acceleration := gAcceleration,
     Deceleration := gAcceleration, BufferMode := Aborting);
halt(Axis := Axis, Execute := gStop, Deceleration := gAcceleration);
status(Axis := Axis, Enable := TRUE);
position(Axis := Axis, Enable := TRUE);
settle(IN := move.Done, PT := T#20MS);
CASE step OF
  S{i}_Idle:
    Done := FALSE;
    IF start.Q THEN
      data.cycles := 0;
      step := S{i}_Powering;
    END_IF
  S{i}_Powering:
    IF power.Status THEN
      step := S{i}_Homing;
    END_IF
  S{i}_Homing:
    IF home.Done THEN
      step := S{i}_ToWork;
    END_IF
  S{i}_ToWork:
    IF settle.Q THEN
      step := S{i}_ToBase;
    END_IF
  S{i}_ToBase:
    IF settle.Q THEN
      data.cycles := data.cycles + 1;
      IF data.cycles >= gCycles THEN
        step := S{i}_Done;
      ELSE
        step := S{i}_ToWork;
      END_IF
    END_IF
  S{i}_Done:
    Done := TRUE;
    IF NOT Execute THEN
      step := S{i}_Idle;
    END_IF
  S{i}_Fault:
    IF NOT Execute THEN
      Error := FALSE;
      ErrorID := 0;
      step := S{i}_Idle;
    END_IF
END_CASE
IF power.Error OR home.Error OR move.Error OR status.Error THEN
  Error := TRUE;
  IF power.Error THEN
    ErrorID := power.ErrorID;
  ELSIF home.Error THEN
    ErrorID := home.ErrorID;
  ELSIF move.Error THEN
    ErrorID := move.ErrorID;
  ELSE
    ErrorID := status.ErrorID;
  END_IF
  data.lastError := ErrorID;
  step := S{i}_Fault;
END_IF
FOR k := 1 TO 7 DO
  history[k] := history[k + 1];
END_FOR
history[8] := position.Position;
mean := 0.0;
FOR k := 1 TO 8 DO
  mean := mean + history[k];
END_FOR
mean := mean / 8.0;
data.settled := ABS(mean - position.Position) < 0.01;
Busy := step <> S{i}_Idle AND step <> S{i}_Done AND step <> S{i}_Fault;
"""


def _pou(name: str, declaration: str, implementation: str) -> str:
    """A ``.TcPOU`` file's text."""
    return OBJECT.format(
        f'  <POU Name="{name}" Id="{{00000000-0000-0000-0000-{abs(hash(name)) % 10**12:012d}}}"'
        ' SpecialFunc="None">\n'
        f"    <Declaration><![CDATA[{declaration}]]></Declaration>\n"
        f"    <Implementation>\n      <ST><![CDATA[{implementation}]]></ST>\n"
        "    </Implementation>\n  </POU>\n"
    )


def _dut(name: str, text: str) -> str:
    """A ``.TcDUT`` file's text."""
    declaration = f"<Declaration><![CDATA[{text}]]></Declaration>"
    return OBJECT.format(f'  <DUT Name="{name}">{declaration}</DUT>\n')


def write_project(folder: Path, count: int = 48) -> int:
    """Write the project of ``count`` stations into ``folder``; its ST lines."""
    folder.mkdir(parents=True, exist_ok=True)
    lines = 0
    for i in range(count):
        steps, data = STEPS.format(i=i), DATA.format(i=i, work=50.0 + i)
        declaration, implementation = DECLARATION.format(i=i), IMPLEMENTATION.format(i=i)
        (folder / f"E_Step{i}.TcDUT").write_text(_dut(f"E_Step{i}", steps))
        (folder / f"ST_Station{i}.TcDUT").write_text(_dut(f"ST_Station{i}", data))
        (folder / f"FB_Station{i}.TcPOU").write_text(
            _pou(f"FB_Station{i}", declaration, implementation)
        )
        lines += sum(t.count("\n") for t in (steps, data, declaration, implementation))
    (folder / "GVL_Plant.TcGVL").write_text(
        OBJECT.format(
            f'  <GVL Name="GVL_Plant"><Declaration><![CDATA[{GLOBALS}]]></Declaration>\n  </GVL>\n'
        )
    )
    instances = "".join(f"  station{i} : FB_Station{i};\n" for i in range(count))
    calls = "".join(
        f"station{i}(Axis := X, Execute := active = {i}, Velocity := 100.0);\n"
        f"IF station{i}.Done OR station{i}.Error THEN active := {i + 1}; END_IF\n"
        for i in range(count)
    )
    declaration = f"PROGRAM Plant\nVAR\n{instances}  active : INT;\n  done : BOOL;\nEND_VAR\n"
    implementation = f"{calls}done := active >= {count};\n"
    (folder / "Plant.TcPOU").write_text(_pou("Plant", declaration, implementation))
    return lines + len(GLOBALS.splitlines()) + declaration.count("\n") + calls.count("\n") + 1

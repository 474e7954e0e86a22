"""Conformance of the binding to the machine and of the projects engineers keep: AXIS_REF
through VAR_EXTERNAL (IEC 61131-3 2.4.3, 3rd ed. 6.5.2), the axis' fields, the library's
enumeration inputs (2.3.3.1, 3rd ed. 6.4.4.2), the group blocks' arrays, the program's own
variables named like the runtime's, the task's watchdog (2.7.2, 3rd ed. 6.8.2) and the projects
of TwinCAT and PLCopen XML (TC6)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

import mcl
import plc.st
import scenes
from tests.helpers import ROOT
from tests.plc.st.iec import program, refused

MOVE = """
VAR_GLOBAL X : AXIS_REF; END_VAR
PROGRAM mover
VAR_EXTERNAL X : AXIS_REF; END_VAR
VAR power : MC_Power; p : LREAL; v : LREAL; e : DINT; END_VAR
power(Axis := X, Enable := TRUE);
p := X.POS; v := X.VEL; e := X.AxErrorID;
END_PROGRAM
"""


def test_an_axis_binds_through_var_external(machine: mcl.SimMachine):
    """2.4.3 (6.5.2): a VAR_EXTERNAL names the VAR_GLOBAL AXIS_REF, bound to the axis X."""
    prog = plc.st.from_source(MOVE, machine, filename="mover.st")
    machine.run(prog, timeout=0.02)
    assert not prog.error and prog.power.Status


def test_a_program_reads_the_axis_position_velocity_and_error(X: mcl.Axis, machine):
    """The fields of AXIS_REF a program may read: POS [mm], VEL [mm/s], AxErrorID."""
    prog = plc.st.from_source(MOVE, machine, filename="mover.st")
    machine.run(prog, timeout=0.02)
    assert prog.p == X.POS and prog.v == X.VEL and prog.e == 0


def test_an_axis_binds_through_var_external_alone(X: mcl.Axis, machine):
    """2.4.3 (6.5.2): a VAR_EXTERNAL AXIS_REF with no VAR_GLOBAL is the machine's axis."""
    source = MOVE.replace("VAR_GLOBAL X : AXIS_REF; END_VAR\n", "")
    prog = plc.st.from_source(source, machine, filename="mover.st")
    machine.run(prog, timeout=0.02)
    assert not prog.error and prog.power.Status and prog.p == X.POS


def test_a_var_external_of_another_type_is_refused(machine):
    """2.4.3 (6.5.2): a VAR_EXTERNAL declares the type of its VAR_GLOBAL."""
    source = MOVE.replace("VAR_EXTERNAL X : AXIS_REF;", "VAR_EXTERNAL X : INT;")
    with pytest.raises(plc.st.STError, match=r"mover\.st:4:\d+: VAR_EXTERNAL X : INT.*AXIS_REF"):
        plc.st.from_source(source, machine, filename="mover.st")


@pytest.mark.parametrize("field", ["POS", "VEL", "AxErrorID"])
def test_the_axis_fields_are_read_only(machine, field):
    """A program reads the axis' fields; a write is refused at its file:line:column."""
    source = MOVE.replace("p := X.POS;", f"X.{field} := 0;")
    with pytest.raises(plc.st.STError, match=rf"mover\.st:7:1: X\.{field} is read-only"):
        plc.st.from_source(source, machine, filename="mover.st")


def test_an_axis_has_no_other_field(machine):
    """An AXIS_REF has POS, VEL and AxErrorID only."""
    source = MOVE.replace("X.POS;", "X.Pos2;")
    with pytest.raises(plc.st.STError, match="AXIS_REF has no field 'Pos2'; expected POS, VEL"):
        plc.st.from_source(source, machine, filename="mover.st")


def test_the_group_position_follows_the_axes():
    """The array read from MC_GroupReadActualPosition holds the members' positions [mm]."""
    scene = scenes.load("gantry")
    source = program(
        "gantry : AXES_GROUP_REF; gp : MC_GroupReadActualPosition; a : ARRAY[1..3] OF LREAL;"
        "add : ARRAY[1..3] OF MC_AddAxisToGroup;",
        "add[1](AxesGroup := gantry, Axis := X, Execute := TRUE);"
        "add[2](AxesGroup := gantry, Axis := Y, Execute := TRUE);"
        "gp(AxesGroup := gantry, Enable := TRUE); a := gp.Position;",
    )
    prog = plc.st.from_source(source, scene)
    scene.run(prog, timeout=0.05)
    axes = scene.axes
    assert not prog.error
    assert prog.a == pytest.approx([axes["X"].POS, axes["Y"].POS, 0.0], abs=0.01)
    assert prog.a[2] == 0.0  # two members: the third element is none's


def _home(switch_mode: str) -> str:
    decls = "home : MC_StepAbsSwitch;"
    body = f"home(Axis := X, Execute := TRUE, SwitchMode := {switch_mode});"
    return program(decls, body)


def test_an_enumeration_input_takes_a_value_of_its_enumeration(machine):
    """2.3.3.1 (6.4.4.2): MC_Direction.MC_Negative is a value of MC_Direction."""
    source = program(
        "jog : MC_MoveVelocity;",
        "jog(Axis := X, Execute := FALSE, Direction := MC_Direction.MC_Negative);",
    )
    assert plc.st.from_source(source, machine)


def test_a_value_of_another_enumeration_is_refused(machine):
    """2.3.3.1 (6.4.4.2): MC_Negative (an MC_Direction) is no MC_SwitchMode."""
    with pytest.raises(plc.st.STError, match="MC_SwitchMode"):
        plc.st.from_source(_home("MC_Negative"), machine)


def test_a_buffer_mode_is_no_direction(machine):
    """2.3.3.1 (6.4.4.2): Aborting (an MC_BufferMode) is no MC_Direction."""
    source = program("jog : MC_MoveVelocity;", "jog(Axis := X, Direction := Aborting);")
    with pytest.raises(plc.st.STError, match="MC_Direction"):
        plc.st.from_source(source, machine)


@pytest.mark.parametrize(
    ("decls", "body", "message"),
    [
        (
            "jog : MC_MoveVelocity;",
            "jog(Axis := X, Execute := FALSE, Direction := MC_Negtive);",
            r"iec\.st:5:47: unknown variable 'MC_Negtive' \(did you mean MC_Negative.*"
            r"expected a value of MC_Direction: MC_Positive",
        ),
        (
            "b : MC_BufferMode;",
            "b := Abortng;",
            r"iec\.st:5:6: unknown variable 'Abortng' \(did you mean Aborting\?\); "
            r"expected a value of MC_BufferMode: Aborting, Buffered",
        ),
        (
            "d : MC_Direction; n : INT;",
            "IF d = MC_Positve THEN n := 1; END_IF",
            r"iec\.st:5:8: unknown variable 'MC_Positve' \(did you mean MC_Positive.*"
            r"expected a value of MC_Direction",
        ),
    ],
)
def test_a_misspelled_enumeration_value_names_the_nearest(machine, decls, body, message):
    """2.3.3.1 (6.4.4.2): a misspelled value of the library's enumerations is refused at
    file:line:column with the values it may have meant."""
    with pytest.raises(plc.st.STError, match=message):
        plc.st.from_source(program(decls, body), machine, filename="iec.st")


def test_a_misspelled_value_of_the_programs_enumeration_names_the_nearest():
    """2.3.3.1: a misspelled value where the program's enumeration is expected."""
    source = program("c : Color;", "c := Gren;", "TYPE Color : (Red, Green, Blue); END_TYPE")
    message = refused(source)
    assert message.startswith("iec.st:6:6: unknown variable 'Gren' (did you mean Green")
    assert message.endswith("expected a value of Color: Red, Green, Blue")


def test_a_group_position_is_an_array():
    """A group block's per-axis output reads into an ARRAY of LREAL."""
    scene = scenes.load("gantry")
    source = program(
        "gantry : AXES_GROUP_REF; gp : MC_GroupReadActualPosition; a : ARRAY[1..3] OF LREAL;",
        "gp(AxesGroup := gantry, Enable := TRUE); a := gp.Position;",
    )
    assert plc.st.from_source(source, scene)


def test_the_programs_own_scans_and_name_variables():
    """A program's variables named scans and name are its own, read as written."""
    prog = plc.st.from_source(program("scans : INT := 7; name : STRING := 'x';", ""))
    prog()
    assert prog.scans == 7 and prog.name == "x"


def test_the_programs_own_restart_variables_and_stopped_variables():
    """A program's variables named like the runtime's methods (restart, variables, stopped) are
    its own, read and written as every other; plc.st's functions reach the runtime's."""
    decls = "restart : BOOL; variables : INT := 4; stopped : INT; n : INT;"
    prog = plc.st.from_source(program(decls, "n := n + variables; stopped := n;"))
    prog()
    assert prog.restart is False and prog.variables == 4 and prog.stopped == 4
    prog.restart, prog.variables = True, 10
    prog()
    assert prog.restart is True and prog.n == 14 and prog.stopped == 14
    assert plc.st.variables(prog)["n"] == 14 and not plc.st.stopped(prog)
    plc.st.restart(prog)
    assert prog.n == 0 and prog.variables == 4 and prog.restart is False


def test_the_runtimes_restart_variables_and_stopped_without_such_variables():
    """Without variables of those names, prog.restart(), prog.variables(), prog.stopped are the
    runtime's."""
    prog = plc.st.from_source(program("n : INT;", "n := n + 1;"))
    prog()
    assert prog.variables() == {"n": 1} and not prog.stopped
    prog.restart()
    assert prog.n == 0


LOOP = "PROGRAM loop\nVAR i : DINT; END_VAR\nWHILE TRUE DO i := i + 1; END_WHILE\nEND_PROGRAM\n"
HANG = f"""
import plc.st, scenes
scene = scenes.load("single_axis")
prog = plc.st.from_source({LOOP!r}, scene, filename="loop.st")
scene.run(prog, timeout=0.1)
print(prog.error)
"""


@pytest.mark.once
def test_a_scan_beyond_the_watchdog_stops_the_program_naming_its_loop():
    """2.7.2 (6.8.2): a scan that never ends trips the task's watchdog: the program stops with
    file:line, the process goes on."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, "-c", HANG], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0 and "loop.st:3" in done.stdout


TCPOU = """<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">
  <POU Name="counter" Id="{0b0e7a4c-4d3a-4a40-9b5e-2c1d3f5a6b7c}" SpecialFunc="None">
    <Declaration><![CDATA[PROGRAM counter
VAR
  n : INT;
END_VAR
]]></Declaration>
    <Implementation>
      <ST><![CDATA[n := n + 1;]]></ST>
    </Implementation>
  </POU>
</TcPlcObject>
"""


def test_a_twincat_pou_runs(tmp_path):
    """A TwinCAT project's .TcPOU runs as its PROGRAM."""
    path = tmp_path / "counter.TcPOU"
    path.write_text(TCPOU)
    prog = plc.st.load(path)
    prog()
    prog()
    assert prog.n == 2


PLCOPEN = """<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0201">
  <types>
    <dataTypes>
      <dataType name="Pair">
        <baseType><struct>
          <variable name="a"><type><INT/></type></variable>
          <variable name="b"><type><INT/></type></variable>
        </struct></baseType>
      </dataType>
    </dataTypes>
    <pous>
      <pou name="main" pouType="program">
        <interface>
          <localVars>
            <variable name="p"><type><derived name="Pair"/></type></variable>
            <variable name="n"><type><INT/></type></variable>
          </localVars>
        </interface>
        <body><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">
p.a := 2; n := p.a + 1;
        </xhtml></ST></body>
      </pou>
    </pous>
  </types>
</project>
"""


def test_a_plcopen_xml_export_runs(tmp_path):
    """A PLCopen XML (TC6) export runs with its data types."""
    path = tmp_path / "project.xml"
    path.write_text(PLCOPEN)
    prog = plc.st.load(path)
    prog()
    assert prog.n == 3

"""Global variable lists as TwinCAT and CODESYS keep them: a named VAR_GLOBAL block (a GVL) is
read and written as ``GVL_Axes.X``, its axes bind through it, and a GVL with
``{attribute 'qualified_only'}`` refuses the bare name, naming what to write instead; from a
plain .st file, a TwinCAT project folder and a PLCopen XML export."""

from __future__ import annotations

import pytest

import plc.st
import scenes
from tests.plc.st.iec import refused, run
from tests.plc.st.test_projects import OBJECT, _pou

AXES = """{attribute 'qualified_only'}
{attribute 'gvl' := 'GVL_Axes'}
VAR_GLOBAL
  X : AXIS_REF;
  speed : LREAL := 200.0;
END_VAR
"""
"""A qualified_only GVL of the gantry's axis X and a speed (the PROGRAM starts on line 7)."""

MOVE = """PROGRAM Main
VAR power : MC_Power; move : MC_MoveRelative; p : LREAL; done : BOOL; END_VAR
power(Axis := GVL_Axes.X, Enable := TRUE);
move(Axis := GVL_Axes.X, Execute := power.Status, Distance := 100.0,
     Velocity := GVL_Axes.speed, Acceleration := 2000.0, Deceleration := 2000.0);
p := GVL_Axes.X.POS;
done := move.Done;
END_PROGRAM
"""
"""A PROGRAM that moves X by 100 mm through the GVL (its body from line 3)."""


def _moved(load) -> tuple[plc.st.STProgram, scenes.Scene]:
    """The program ``load(scene)`` gives, run on the gantry until its ``done``."""
    scene = scenes.load("gantry", start={"X": 0.3})
    prog = load(scene)
    scene.run(prog, until=lambda: prog.done, timeout=5.0)
    return prog, scene


def _refused(source: str) -> str:
    """The message ``source`` (``gvl.st``) is refused with on the gantry."""
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(source, scenes.load("gantry"), filename="gvl.st")
    return str(error.value)


def test_an_axis_of_a_qualified_only_gvl_moves_through_its_qualified_name():
    """``MC_Power(Axis := GVL_Axes.X)``: the machine's X moves 100 mm; ``GVL_Axes.X.POS``
    and ``GVL_Axes.speed`` read it and the GVL's LREAL."""
    prog, scene = _moved(lambda s: plc.st.from_source(AXES + MOVE, s, filename="gvl.st"))
    assert prog.done and not prog.error, prog.error
    assert pytest.approx(100.0, abs=1e-6) == scene.axes["X"].POS
    assert prog.p == pytest.approx(100.0, abs=1e-6)
    assert plc.st.variables(prog)["GVL_Axes.speed"] == 200.0


def test_the_bare_name_of_a_qualified_only_gvl_is_refused_with_the_name_to_write():
    """``Axis := X`` beside a qualified_only GVL_Axes: refused at its column, saying to write
    GVL_Axes.X (not bound to the machine's X behind the list's back)."""
    source = AXES + MOVE.replace("power(Axis := GVL_Axes.X", "power(Axis := X")
    assert _refused(source) == (
        "gvl.st:9:15: X is declared in GVL_Axes with {attribute 'qualified_only'}: write GVL_Axes.X"
    )


def test_a_gvl_without_qualified_only_takes_both_names():
    """A named GVL without qualified_only: ``count`` and ``GVL_Main.count`` are one variable,
    read and written either way."""
    source = """{attribute 'gvl' := 'GVL_Main'}
VAR_GLOBAL count : INT; step : INT := 3; END_VAR
PROGRAM t
VAR a : INT; END_VAR
GVL_Main.count := GVL_Main.count + 1;
count := count + GVL_Main.step;
a := gvl_main.COUNT;
END_PROGRAM
"""
    prog = run(source, scans=2)
    assert prog.a == 8 and plc.st.variables(prog)["count"] == 8


def test_two_qualified_only_gvls_may_declare_the_same_name():
    """Two qualified_only lists each with a ``speed``: two variables."""
    source = """{attribute 'qualified_only'}
{attribute 'gvl' := 'GVL_A'}
VAR_GLOBAL speed : INT := 1; END_VAR
{attribute 'qualified_only'}
{attribute 'gvl' := 'GVL_B'}
VAR_GLOBAL speed : INT := 2; END_VAR
PROGRAM t
VAR a : INT; END_VAR
GVL_B.speed := GVL_B.speed * 10;
a := GVL_A.speed + GVL_B.speed;
END_PROGRAM
"""
    assert run(source).a == 21
    assert refused(source.replace("a := GVL_A", "a := speed + GVL_A")) == (
        "iec.st:10:6: speed is declared in GVL_A, GVL_B with {attribute 'qualified_only'}: "
        "write GVL_A.speed or GVL_B.speed"
    )


def test_the_lists_of_a_configuration_and_of_its_resource_keep_their_attributes():
    """A CONFIGURATION's and its RESOURCE's VAR_GLOBAL, each after its two attributes (one
    written over two lines): named and qualified_only as at the top of a file."""
    source = """PROGRAM t
VAR a : INT; END_VAR
GVL_B.speed := GVL_B.speed * 10;
a := GVL_C.speed + GVL_B.speed;
END_PROGRAM
CONFIGURATION c
{attribute 'qualified_only'}
{attribute 'gvl' := 'GVL_C'}
VAR_GLOBAL speed : INT := 1; END_VAR
RESOURCE r ON PLC
{attribute 'gvl' := 'GVL_B'}
{attribute
    'qualified_only'}
VAR_GLOBAL speed : INT := 2; END_VAR
TASK cyclic(INTERVAL := T#10ms);
PROGRAM main WITH cyclic : t;
END_RESOURCE
END_CONFIGURATION
"""
    assert run(source).a == 21
    assert refused(source.replace("a := GVL_C", "a := speed + GVL_C")) == (
        "iec.st:4:6: speed is declared in GVL_C, GVL_B with {attribute 'qualified_only'}: "
        "write GVL_C.speed or GVL_B.speed"
    )


WRONG = (
    AXES
    + """{attribute 'gvl' := 'GVL_Limits'}
VAR_GLOBAL CONSTANT limit : LREAL := 5.0; END_VAR
PROGRAM t
VAR a : LREAL; END_VAR
"""
)
"""The GVL_Axes list, a CONSTANT one, and a PROGRAM whose statement is on line 11."""


@pytest.mark.parametrize(
    ("statement", "message"),
    [
        (
            "a := GVL_Axes.sped;",
            "11:15: the GVL GVL_Axes has no variable 'sped' (did you mean speed?); "
            "expected GVL_Axes.X, GVL_Axes.speed",
        ),
        ("GVL_Limits.limit := 1.0;", "11:1: limit is a CONSTANT; expected a variable"),
        ("GVL_Axes.X := GVL_Axes.X;", "11:1: GVL_Axes.X cannot be assigned; expected a variable"),
        ("a := GVL_Axes;", "11:6: unknown variable 'GVL_Axes'"),
    ],
)
def test_a_wrong_use_of_a_gvl_names_its_variables(statement, message):
    """A name the list lacks gets the nearest of its variables; its CONSTANT and its axis are
    not written."""
    assert _refused(f"{WRONG}{statement}\nEND_PROGRAM\n").startswith(f"gvl.st:{message}")


def test_qualified_only_without_a_name_is_refused():
    """``{attribute 'qualified_only'}`` on a VAR_GLOBAL no name names: refused, naming the
    pragma that names it."""
    source = "{attribute 'qualified_only'}\nVAR_GLOBAL g : INT; END_VAR\n"
    source += "PROGRAM t\ng := 1;\nEND_PROGRAM\n"
    assert refused(source) == (
        "iec.st:2:1: a qualified_only VAR_GLOBAL without a name; expected its name before it, "
        "{attribute 'gvl' := 'GVL_Name'} (a TwinCAT GVL has its own)"
    )


def _twincat(folder, body_axis: str) -> None:
    """A TwinCAT folder: a qualified_only GVL_Axes.TcGVL and Main.TcPOU passing ``body_axis``."""
    (folder / "GVL_Axes.TcGVL").write_text(
        OBJECT.format(
            '  <GVL Name="GVL_Axes" Id="{65034cb3-54d5-47fb-8101-955f16845057}">\n'
            f"    <Declaration><![CDATA[{AXES.split(chr(10), 2)[0]}\n{AXES.split(chr(10), 2)[2]}"
            "]]></Declaration>\n  </GVL>\n"
        )
    )
    declaration, _, body = MOVE.partition("END_VAR\n")
    body = body.replace("END_PROGRAM\n", "").replace("power(Axis := GVL_Axes.X", body_axis)
    (folder / "Main.TcPOU").write_text(_pou("Main", declaration + "END_VAR\n", body))


def test_a_twincat_gvl_with_qualified_only_binds_its_axes(tmp_path):
    """A .TcGVL with ``{attribute 'qualified_only'}`` (its name the GVL's): the .TcPOU moves X
    through ``GVL_Axes.X``; the bare ``X`` is refused at its line and column in the .TcPOU."""
    _twincat(tmp_path, "power(Axis := GVL_Axes.X")
    prog, scene = _moved(lambda s: plc.st.load(tmp_path, s))
    assert prog.done and not prog.error, prog.error
    assert pytest.approx(100.0, abs=1e-6) == scene.axes["X"].POS
    _twincat(tmp_path, "power(Axis := X")
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path, scenes.load("gantry"))
    assert str(error.value) == (
        f"{tmp_path / 'Main.TcPOU'}:8:34: X is declared in GVL_Axes with "
        "{attribute 'qualified_only'}: write GVL_Axes.X"
    )


PLCOPEN = """<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0200">
  <types><dataTypes/><pous>
    <pou name="Main" pouType="program">
      <interface><localVars>
        <variable name="power"><type><derived name="MC_Power"/></type></variable>
        <variable name="move"><type><derived name="MC_MoveRelative"/></type></variable>
        <variable name="p"><type><LREAL/></type></variable>
        <variable name="done"><type><BOOL/></type></variable>
      </localVars></interface>
      <body><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">BODY</xhtml></ST></body>
    </pou>
  </pous></types>
  <instances><configurations/></instances>
  <addData>
    <data name="http://www.3s-software.com/plcopenxml/globalvars" handleUnknown="implementation">
      <globalVars name="GVL_Axes">
        <variable name="X"><type><derived name="AXIS_REF"/></type></variable>
        <variable name="speed"><type><LREAL/></type>
          <initialValue><simpleValue value="200.0"/></initialValue></variable>
        <addData>
          <data name="http://www.3s-software.com/plcopenxml/attributes">
            <Attributes><Attribute Name="qualified_only" Value=""/></Attributes>
          </data>
        </addData>
      </globalVars>
    </data>
  </addData>
</project>
"""
"""A CODESYS export of a PROGRAM and a qualified_only GVL (the body's first line is line 11)."""


def test_a_plcopen_gvl_with_qualified_only_binds_its_axes(tmp_path):
    """CODESYS' export of a GVL (``<addData>``'s ``<globalVars name>`` with its
    ``qualified_only`` attribute): ``GVL_Axes.X`` moves X, the bare ``X`` is refused at its
    line in the XML."""
    body = MOVE.partition("END_VAR\n")[2].replace("END_PROGRAM\n", "")
    path = tmp_path / "cell.xml"
    path.write_text(PLCOPEN.replace("BODY", body))
    prog, scene = _moved(lambda s: plc.st.load(path, s))
    assert prog.done and not prog.error, prog.error
    assert pytest.approx(100.0, abs=1e-6) == scene.axes["X"].POS
    path.write_text(
        PLCOPEN.replace("BODY", body.replace("power(Axis := GVL_Axes.X", "power(Axis := X"))
    )
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(path, scenes.load("gantry"))
    assert str(error.value).startswith(f"{path}:11:")
    assert str(error.value).endswith(
        "X is declared in GVL_Axes with {attribute 'qualified_only'}: write GVL_Axes.X"
    )


def test_a_mapping_binds_the_qualified_name_of_an_axis():
    """``mapping={"GVL_Axes.Ax1": "X"}`` binds the GVL's AXIS_REF Ax1 to the machine's X."""
    source = AXES.replace("X : AXIS_REF", "Ax1 : AXIS_REF") + MOVE.replace(
        "GVL_Axes.X", "GVL_Axes.Ax1"
    )
    prog, scene = _moved(
        lambda s: plc.st.from_source(source, s, {"GVL_Axes.Ax1": "X"}, filename="gvl.st")
    )
    assert prog.done and pytest.approx(100.0, abs=1e-6) == scene.axes["X"].POS


def test_a_named_global_list_of_a_plcopen_configuration_is_a_gvl(tmp_path):
    """A ``<configuration>``'s ``<globalVars name="GVL_Axes">`` (beside its resource) is the
    GVL ``GVL_Axes``: ``GVL_Axes.X`` moves X."""
    body = MOVE.partition("END_VAR\n")[2].replace("END_PROGRAM\n", "")
    start, _, rest = PLCOPEN.partition("  <instances><configurations/></instances>\n")
    gvl = rest[rest.index("      <globalVars") : rest.index("\n    </data>") + 1]
    configuration = (
        '  <instances><configurations><configuration name="c">\n'
        f"{gvl}"
        '    <resource name="r"><pouInstance name="i" typeName="Main"/></resource>\n'
        "  </configuration></configurations></instances>\n</project>\n"
    )
    path = tmp_path / "cell.xml"
    path.write_text((start + configuration).replace("BODY", body))
    prog, scene = _moved(lambda s: plc.st.load(path, s))
    assert prog.done and not prog.error, prog.error
    assert abs(scene.axes["X"].POS - 100.0) < 1e-6


SECTIONS = """{attribute 'qualified_only'}
VAR_GLOBAL CONSTANT
    cNumTargets : INT := 3;
END_VAR
VAR_GLOBAL
    fVelocity : LREAL := 50.0;
    nCount : INT;
END_VAR
"""
"""A GVL of two sections as TwinCAT writes it: its constants, then its variables."""

USES = """PROGRAM MAIN
VAR
    fV : LREAL;
    n : INT;
END_VAR
GVL_Param.nCount := GVL_Param.nCount + GVL_Param.cNumTargets;
fV := GVL_Param.fVelocity;
n := GVL_Param.nCount;
END_PROGRAM
"""
"""A PROGRAM that reads and writes both sections of GVL_Param by their qualified names."""


def _gvl_file(folder, declaration: str) -> None:
    """A TwinCAT folder: GVL_Param.TcGVL of ``declaration`` and MAIN.TcPOU of :data:`USES`."""
    (folder / "GVL_Param.TcGVL").write_text(
        OBJECT.format(
            '  <GVL Name="GVL_Param" Id="{65034cb3-54d5-47fb-8101-955f16845057}">\n'
            f"    <Declaration><![CDATA[{declaration}]]></Declaration>\n  </GVL>\n"
        )
    )
    declared, _, body = USES.partition("END_VAR\n")
    (folder / "MAIN.TcPOU").write_text(
        _pou("MAIN", declared + "END_VAR\n", body.replace("END_PROGRAM\n", ""))
    )


@pytest.mark.parametrize("swapped", [False, True])
def test_every_section_of_a_twincat_gvl_is_the_gvl(tmp_path, swapped):
    """A .TcGVL of ``VAR_GLOBAL CONSTANT ... END_VAR`` then ``VAR_GLOBAL ... END_VAR`` (or the
    other way round): both sections are GVL_Param's, read and written qualified."""
    constants, _, variables = SECTIONS.partition("END_VAR\n")
    head, _, constants = constants.partition("\n")
    _gvl_file(tmp_path, f"{head}\n{variables}{constants}END_VAR\n" if swapped else SECTIONS)
    prog = plc.st.load(tmp_path, period=0.01)
    prog()
    prog()
    assert not prog.fault, prog.fault
    assert (prog.fV, prog.n) == (50.0, 6)
    assert plc.st.variables(prog)["GVL_Param.nCount"] == 6


def test_the_bare_name_of_a_second_section_of_a_qualified_only_gvl_is_refused(tmp_path):
    """``{attribute 'qualified_only'}`` at the top of a .TcGVL holds for its second section
    too: the bare ``fVelocity`` is refused at its line in MAIN.TcPOU, saying what to write."""
    _gvl_file(tmp_path, SECTIONS)
    pou = tmp_path / "MAIN.TcPOU"
    pou.write_text(pou.read_text().replace("fV := GVL_Param.fVelocity", "fV := fVelocity"))
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path, period=0.01)
    assert str(error.value) == (
        f"{pou}:12:7: fVelocity is declared in GVL_Param with {{attribute 'qualified_only'}}: "
        "write GVL_Param.fVelocity"
    )


def test_every_section_after_a_gvl_pragma_is_the_gvl_up_to_the_next_pou():
    """In a .st file, the VAR_GLOBAL sections after ``{attribute 'gvl' := 'GVL'}`` up to the
    next POU are the GVL (``GVL.nCount``); one after a POU is a global of no list."""
    source = """{attribute 'gvl' := 'GVL'}
VAR_GLOBAL CONSTANT
    cStep : INT := 2;
END_VAR
VAR_GLOBAL
    nCount : INT;
END_VAR
FUNCTION Twice : INT
VAR_INPUT x : INT; END_VAR
Twice := 2 * x;
END_FUNCTION
VAR_GLOBAL
    nOther : INT;
END_VAR
PROGRAM MAIN
VAR n : INT; END_VAR
GVL.nCount := GVL.nCount + GVL.cStep;
nCount := nCount + 1;
nOther := Twice(GVL.nCount);
n := nOther;
END_PROGRAM
"""
    assert run(source, scans=2).n == 12
    assert refused(source.replace("n := nOther", "n := GVL.nOther")) == (
        "iec.st:20:10: the GVL GVL has no variable 'nOther' (did you mean nCount?); "
        "expected GVL.cStep, GVL.nCount"
    )

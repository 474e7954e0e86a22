"""Projects as engineers keep them: a TwinCAT project's source files (.TcPOU, .TcDUT, .TcGVL,
read with blark) run as the .st file they hold, and messages name the project's files."""

from __future__ import annotations

import pytest

import plc.st
import scenes
from tests.helpers import ROOT
from tests.plc.st.test_demos import run_to_done, st_demo

TWINCAT = ROOT / "examples" / "st" / "gantry_twincat"

OBJECT = """<?xml version="1.0" encoding="utf-8"?>
<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">
{}</TcPlcObject>
"""


def _pou(name: str, declaration: str, implementation: str, extra: str = "") -> str:
    return OBJECT.format(
        f'  <POU Name="{name}" Id="{{0b0e7a4c-4d3a-4a40-9b5e-2c1d3f5a6b7c}}" SpecialFunc="None">\n'
        f"    <Declaration><![CDATA[{declaration}]]></Declaration>\n"
        f"    <Implementation>\n      <ST><![CDATA[{implementation}]]></ST>\n"
        f"    </Implementation>\n{extra}  </POU>\n"
    )


def test_the_gantry_demo_as_a_twincat_folder_traces_as_the_st_demo():
    """The TwinCAT folder of the gantry demo: the same scans, every trace sample equal."""
    st_scans, _, st_scene = run_to_done(
        "gantry", lambda s: plc.st.load(ROOT / "examples" / "st" / "gantry_demo.st", s)
    )
    tc_scans, tc_prog, tc_scene = run_to_done("gantry", lambda s: plc.st.load(TWINCAT, s))
    assert tc_prog.done and not tc_prog.error, tc_prog.error
    assert tc_scans == st_scans
    assert tc_scene.trace.rows == st_scene.trace.rows


@pytest.mark.parametrize("machine", ["press", "flying_shear"])
def test_the_press_and_flying_shear_demos_as_twincat_folders_trace_as_the_st_demos(machine):
    """The TwinCAT folders of the press and flying shear demos: the same scans, every trace
    sample equal."""
    from scenes.tools.cli import machine_blocks

    folder = ROOT / "examples" / "st" / f"{machine}_twincat"
    st_scans, _, st_scene = run_to_done(machine, st_demo)
    tc_scans, tc_prog, tc_scene = run_to_done(
        machine, lambda s: plc.st.load(folder, s, blocks=machine_blocks(s))
    )
    assert tc_prog.done and not tc_prog.error, tc_prog.error
    assert tc_scans == st_scans
    assert tc_scene.trace.rows == st_scene.trace.rows


def test_a_folder_with_a_type_and_globals(tmp_path):
    """A .TcDUT's TYPE and a .TcGVL's VAR_GLOBAL serve the .TcPOU's PROGRAM."""
    (tmp_path / "Pair.TcDUT").write_text(
        OBJECT.format(
            '  <DUT Name="Pair"><Declaration><![CDATA[TYPE Pair : STRUCT a, b : INT; END_STRUCT'
            "\nEND_TYPE\n]]></Declaration></DUT>\n"
        )
    )
    (tmp_path / "GVL.TcGVL").write_text(
        OBJECT.format(
            '  <GVL Name="GVL"><Declaration><![CDATA[VAR_GLOBAL\n  g : INT := 5;\nEND_VAR\n'
            "]]></Declaration></GVL>\n"
        )
    )
    (tmp_path / "main.TcPOU").write_text(
        _pou("main", "PROGRAM main\nVAR p : Pair; END_VAR\n", "p.a := g; p.b := p.a + 1;\n")
    )
    prog = plc.st.load(tmp_path)
    prog()
    assert (prog.p.a, prog.p.b) == (5, 6)


def test_an_error_names_the_twincat_file_and_line(tmp_path):
    """A type error in a .TcPOU names its line in that file."""
    path = tmp_path / "main.TcPOU"
    path.write_text(_pou("main", "PROGRAM main\nVAR n : INT; END_VAR\n", "n := 1;\nn := TRUE;\n"))
    with pytest.raises(plc.st.STError, match=rf"^{path}:9:1: a BOOL value where INT"):
        plc.st.load(path)


def test_a_fault_names_the_twincat_file_and_line(tmp_path):
    """A run-time fault in a .TcPOU names its line in that file."""
    path = tmp_path / "main.TcPOU"
    path.write_text(_pou("main", "PROGRAM main\nVAR n : INT; END_VAR\n", "n := 1;\nn := n / 0;\n"))
    prog = plc.st.load(path)
    prog()
    assert prog.fault.startswith(f"{path}:9: integer division by zero")


def test_a_method_is_refused(tmp_path):
    """TwinCAT's METHODs are outside IEC 61131-3 2nd ed.: one message at the file."""
    method = (
        '    <Method Name="m" Id="{1b0e7a4c-4d3a-4a40-9b5e-2c1d3f5a6b7c}">\n'
        "      <Declaration><![CDATA[METHOD m : BOOL\n]]></Declaration>\n"
        "      <Implementation><ST><![CDATA[m := TRUE;]]></ST></Implementation>\n"
        "    </Method>\n"
    )
    path = tmp_path / "fb.TcPOU"
    path.write_text(_pou("fb", "FUNCTION_BLOCK fb\n", "\n", method))
    with pytest.raises(
        plc.st.STError, match=r"fb.TcPOU:11:1: a METHOD \(fb.m\); expected a PROGRAM"
    ):
        plc.st.load(path)


def test_an_empty_folder_is_refused(tmp_path):
    with pytest.raises(plc.st.STError, match="no TwinCAT source here"):
        plc.st.load(tmp_path)


def test_the_scene_runs_a_twincat_pou(tmp_path):
    """A .TcPOU binds to the scene's axes as a .st file."""
    scene = scenes.load("single_axis")
    path = tmp_path / "p.TcPOU"
    path.write_text(_pou("main", "PROGRAM main\nVAR pos : LREAL; END_VAR\n", "pos := X.POS;\n"))
    prog = plc.st.load(path, scene)
    scene.run(prog, timeout=0.02)
    assert not prog.error and prog.pos == pytest.approx(scene.axes["X"].POS, abs=1e-3)

"""PLCopen XML projects (IEC 61131-10, TC6 XML as CODESYS, Beremiz and OpenPLC export them):
data types, POUs and configurations run as the .st file they hold; messages name the XML
file's line; an XML file that declares entities is refused before any expands."""

from __future__ import annotations

import pytest

import plc.st
from plc.st.frontend.plcopen import iec_duration
from scenes.tools import cli
from tests.helpers import ROOT
from tests.plc.st.test_demos import run_to_done, st_demo

EXAMPLES = ROOT / "examples" / "st"
PLCOPEN = EXAMPLES / "plcopen"

PROJECT = (ROOT / "tests" / "plc" / "st" / "plcopen_project.xml").read_text()
"""A project of two data types, a FUNCTION, a FUNCTION_BLOCK, a PROGRAM and a configuration."""


def _write(tmp_path, text: str, name: str = "project.xml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_project_of_types_pous_globals_and_a_task_runs(tmp_path):
    """An enumeration, a structure, a FUNCTION, a FUNCTION_BLOCK, a PROGRAM with arrays of
    structures and constants, a configuration's global and its task: run as written."""
    prog = plc.st.load(_write(tmp_path, PROJECT), period=0.01)
    assert prog.name == "main" and prog.every == 2  # T#20ms on a 10 ms PLC
    for _ in range(4):
        prog()
    assert prog.n == 6 and prog.y == 2.0 * 3.0 * 10.0 + 1.5
    assert prog.points[1].tag == "ab" and prog.tags == [7, 7] and prog.mode == 2
    assert prog.gain == 10.0


def test_the_task_of_an_xml_project_sets_the_plc_period(tmp_path):
    """The CLI builds the machine at the PLCopen task's interval, as for a .st file."""
    task = cli.st_task(str(_write(tmp_path, PROJECT)))
    assert task is not None and task.interval == 0.02 and task.program == "main"
    assert task.where.startswith(f"{tmp_path / 'project.xml'}:")


def test_a_codesys_export_with_an_xml_schema_interval_and_no_type_name_runs(tmp_path):
    """CODESYS exports a task's interval as an XML Schema duration (``PT0.02S``) and its
    program instance with an empty ``typeName`` (the POU of the instance's name)."""
    pou = '<pouInstance name="main" typeName=""/>'
    text = PROJECT.replace('interval="T#20ms"', 'interval="PT0.02S"')
    text = text.replace('<pouInstance name="Main1" typeName="main"/>', pou)
    task = cli.st_task(str(_write(tmp_path, text)))
    assert task is not None and task.interval == 0.02 and task.program == "main"
    prog = plc.st.load(_write(tmp_path, text), period=0.01)
    assert prog.name == "main" and prog.every == 2


@pytest.mark.parametrize(
    ("given", "iec"),
    [
        ("PT0.004S", "T#4ms"),
        ("P0DT0H0M0.010S", "T#10ms"),
        ("PT1M", "T#60000ms"),
        ("pt0.0005s", "T#0.5ms"),
        ("T#4ms", "T#4ms"),
        ("P", "P"),
        (None, None),
    ],
)
def test_an_xml_schema_duration_becomes_an_iec_time(given, iec):
    assert iec_duration(given) == iec


def test_a_type_error_names_the_xml_line_and_column(tmp_path):
    """A type error in an ST body names its line (and column) in the XML file."""
    text = PROJECT.replace("n := counter.count;", "n := counter.count;\nn := TRUE;")
    path = _write(tmp_path, text)
    line = text.splitlines().index("n := TRUE;") + 1
    with pytest.raises(plc.st.STError, match=rf"^{path}:{line}:1: a BOOL value where DINT"):
        plc.st.load(path)


def test_an_error_on_the_first_body_line_counts_the_columns_of_the_tag(tmp_path):
    """The first ST line begins after ``<xhtml:p><![CDATA[``: its column is the XML file's."""
    text = PROJECT.replace("counter(step := STEP);", "counter(step := nope);")
    path = _write(tmp_path, text)
    row = next(i for i, t in enumerate(text.splitlines()) if "nope" in t)
    column = text.splitlines()[row].index("nope") + 1
    with pytest.raises(plc.st.STError, match=rf"^{path}:{row + 1}:{column}: unknown variable"):
        plc.st.load(path)


def test_a_declaration_error_names_the_variable_element(tmp_path):
    """A variable of an unknown type is refused at its <variable> element's line."""
    text = PROJECT.replace('<derived name="Mode"/>', '<derived name="Moda"/>')
    path = _write(tmp_path, text)
    line = next(i for i, t in enumerate(text.splitlines(), 1) if '"Moda"' in t)
    with pytest.raises(plc.st.STError, match=rf"^{path}:{line}:\d+: unknown type 'Moda'"):
        plc.st.load(path)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "<ST><p>Twice := 2.0 * v;</p></ST>",
            "<FBD/>",
            r"a <FBD> body \(Twice\); expected an <ST>",
        ),
        (
            "<LREAL/></type></variable></inputVars>",
            "<FOO/></type></variable></inputVars>",
            "the type <FOO>",
        ),
        ('pouType="function"', 'pouType="method"', "pouType 'method'"),
        ("</pous>", "</pou>", "not well-formed XML"),
    ],
)
def test_what_the_reader_does_not_take_is_one_message_at_its_line(tmp_path, old, new, message):
    path = _write(tmp_path, PROJECT.replace(old, new, 1))
    with pytest.raises(plc.st.STError, match=rf"^{path}:\d+:\d+: .*{message}"):
        plc.st.load(path)


LAUGHS = """<?xml version="1.0"?>
<!DOCTYPE project [
  <!ENTITY a "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa">
  <!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">
  <!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">
  <!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">
  <!ENTITY e "&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;">
  <!ENTITY f "&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;">
]>
<project><types><pous><pou name="p" pouType="program">
  <body><ST>&f;</ST></body>
</pou></pous></types></project>
"""


def test_an_entity_declaration_is_refused_before_it_expands(tmp_path):
    """The billion laughs (20^5 copies of 60 characters, 190 MB) is refused at its first
    entity declaration."""
    path = _write(tmp_path, LAUGHS)
    with pytest.raises(plc.st.STError, match=rf"^{path}:3:\d+: an entity declaration"):
        plc.st.load(path)


def test_another_xml_document_is_no_project(tmp_path):
    path = ROOT / "models" / "gantry.xml"
    with pytest.raises(plc.st.STError, match=r"gantry\.xml:\d+:1: a <mujoco> document"):
        plc.st.load(path)


@pytest.mark.parametrize("machine", ["gantry", "press", "flying_shear"])
def test_the_demos_plcopen_export_traces_as_the_st_demo(machine):
    """The PLCopen XML export of each ST demo: the same scans, every trace sample equal."""
    st_scans, _, st_scene = run_to_done(machine, st_demo)
    xml = PLCOPEN / f"{machine}_demo.xml"
    blocks = cli.machine_blocks
    xml_scans, prog, xml_scene = run_to_done(
        machine, lambda s: plc.st.load(xml, s, blocks=blocks(s))
    )
    assert prog.done and not prog.error, prog.error
    assert xml_scans == st_scans
    assert xml_scene.trace.rows == st_scene.trace.rows


def test_the_project_of_several_pous_and_types_traces_as_its_st_file():
    """axis_cycle: two data types, a FUNCTION, a FUNCTION_BLOCK, a PROGRAM, a configuration's
    globals and task; the XML export and the .st file give the same trace on the single axis."""
    st_scans, st_prog, st_scene = run_to_done(
        "single_axis", lambda s: plc.st.load(EXAMPLES / "axis_cycle.st", s)
    )
    xml_scans, prog, xml_scene = run_to_done(
        "single_axis", lambda s: plc.st.load(PLCOPEN / "axis_cycle.xml", s)
    )
    assert st_prog.done and prog.done and not prog.error, prog.error
    assert xml_scans == st_scans > 1000 and prog.round == 2
    assert len(xml_scene.trace.rows["X"]) > 1000
    assert xml_scene.trace.rows == st_scene.trace.rows


def test_the_cli_runs_a_plcopen_project(capsys):
    """``python -m scenes run single_axis --program axis_cycle.xml``: its task's period."""
    assert cli.run("single_axis", st_program=str(PLCOPEN / "axis_cycle.xml")) == 0
    assert "Finished" in capsys.readouterr().out

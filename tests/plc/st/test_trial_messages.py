"""What an engineer new to the ST front end met, as they read it: a TwinCAT file's messages
at the file's own line and column (after a multi-line comment too, and on the line of
``<ST><![CDATA[``), a TIME in µs, ``=`` written for an assignment and ``:=`` for a
comparison, each said as what is wrong and what would be right."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from plc.st.check import check, check_source
from plc.st.frontend.tctask import WHOLE_MS
from tests.plc.st.iec import refused

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "st"
GANTRY = {"X": None, "Y": None, "Z": None}


def _twincat(tmp_path: Path, file: str, line: int, old: str, new: str) -> Path:
    """A copy of the gantry's TwinCAT project, ``old`` on line ``line`` of ``file`` made
    ``new``; the changed file."""
    folder = tmp_path / "gantry_twincat"
    shutil.copytree(EXAMPLES / "gantry_twincat", folder)
    changed = folder / file
    lines = changed.read_text().split("\n")
    assert old in lines[line - 1]
    lines[line - 1] = lines[line - 1].replace(old, new)
    changed.write_text("\n".join(lines))
    return changed


def test_a_missing_semicolon_in_a_twincat_file_is_at_its_line(tmp_path):
    """``Done := pulse.Done`` (line 35 of HomeAxis.TcPOU) without its ';': line 35, not the
    END_IF of line 34 (the POU begins with a comment of two lines)."""
    home = _twincat(tmp_path, "HomeAxis.TcPOU", 35, "Done := pulse.Done;", "Done := pulse.Done")
    assert check(home.parent, GANTRY).errors == [f"{home}:35:19: missing ';' at the end of line 35"]


def test_a_missing_semicolon_after_a_comment_of_several_lines():
    source = "(* two\n   lines *)\nPROGRAM P\nVAR n : INT; END_VAR\nn := 1\nn := 2;\nEND_PROGRAM\n"
    assert check_source(source, "p.st").errors == ["p.st:5:7: missing ';' at the end of line 5"]


def test_a_column_on_the_cdata_line_is_the_files_own(tmp_path):
    """``      <ST><![CDATA[IF aa <> 0 THEN``: ``aa`` is at column 23 of the file's line 9."""
    first = _twincat(tmp_path, "FirstError.TcPOU", 9, "IF a <> 0", "IF aa <> 0")
    assert check(first.parent, GANTRY).errors == [
        f"{first}:9:23: unknown variable 'aa' (did you mean a?); expected a declared variable"
    ]


def test_a_column_on_the_next_line_stays(tmp_path):
    first = _twincat(tmp_path, "FirstError.TcPOU", 10, "ELSIF b <> 0", "ELSIF bb <> 0")
    assert check(first.parent, GANTRY).errors == [
        f"{first}:10:7: unknown variable 'bb' (did you mean b?); expected a declared variable"
    ]


def _program(body: str) -> str:
    return (
        f"PROGRAM P\nVAR t : TIME; n : INT; x : TON; p : REF_TO INT; END_VAR\n{body}\nEND_PROGRAM\n"
    )


@pytest.mark.parametrize(
    ("literal", "unit", "ltime"),
    [
        ("T#500us", "µs", "LTIME#500us"),
        ("TIME#1s500US", "µs", "LTIME#1s500US"),
        ("t#5ns", "ns", "LTIME#5ns"),
    ],
)
def test_a_time_in_micros(literal, unit, ltime):
    assert refused(_program(f"t := {literal};"), "a.st") == (
        f"a.st:3:6: {literal}: a TIME is held in whole ms here; "
        f"expected T#1ms, or {ltime} for a duration in {unit}"
    )


def test_a_task_interval_in_micros():
    source = (
        "CONFIGURATION c RESOURCE r ON PLC TASK t(INTERVAL := T#500us); PROGRAM main WITH t "
        ": P; END_RESOURCE END_CONFIGURATION\n" + _program("n := n + 1;")
    )
    assert refused(source, "a.st") == (
        f"a.st:1:54: INTERVAL := T#500us: {WHOLE_MS}; expected T#1ms, T#2ms, ..."
    )


@pytest.mark.parametrize(
    ("statement", "column", "target"),
    [
        ("n = n + 1;", 3, "n"),
        ("x.PT = T#1s;", 6, "x.PT"),
        ("  n  = 2;", 6, "n"),
        ("p^ = 3;", 4, "p^"),
    ],
)
def test_equals_written_for_an_assignment(statement, column, target):
    assert refused(_program(statement), "a.st") == (
        f"a.st:3:{column}: '=' compares; an assignment is ':=' ({target} := ...)"
    )


def test_an_assignment_written_for_a_comparison():
    source = _program("x(IN := TRUE, PT := T#1s);\nIF x.Q := TRUE THEN n := 1; END_IF")
    assert refused(source, "a.st") == "a.st:4:4: ':=' assigns; a comparison is '='"


@pytest.mark.parametrize("label", ["PowerOn:", "Idle, PowerOn:", "0..1:"])
def test_a_missing_semicolon_before_a_case_label(label):
    """``step := PowerOn`` then the next CASE label: the ';' missing at the end of line 6, not
    "unexpected 'PowerOn'" at the label."""
    source = (
        "TYPE Steps : (Idle, PowerOn); END_TYPE\nPROGRAM P\nVAR step : Steps; END_VAR\n"
        f"CASE step OF\n  Idle:\n    step := PowerOn\n  {label}\n    step := Idle;\n"
        "END_CASE\nEND_PROGRAM\n"
    )
    assert refused(source, "a.st") == "a.st:6:20: missing ';' at the end of line 6"


def test_an_axis_of_another_name_without_its_mapping():
    """``examples/st/manual_move.st`` moves ``Pohon.Ax1``: without its mapping the message
    says how to bind it."""
    program = EXAMPLES / "manual_move.st"
    assert check(program, GANTRY).errors == [
        f"{program}:15:11: unknown variable 'Pohon'; expected a declared variable, or a mapping "
        "of Pohon.Ax1 onto an axis (--map Pohon.Ax1=X)"
    ]
    assert check(program, GANTRY, {"Pohon.Ax1": "X"}).errors == []


def test_a_time_of_another_unit_keeps_its_message():
    assert refused(_program("t := T#5y;"), "a.st") == (
        "a.st:3:9: unexpected 'y'; expected 'd', 'h', 'm', 'ms', 's'"
    )


def test_the_messages_in_the_second_item_of_a_check():
    """Each item is parsed on its own: the lines named are the file's."""
    block = "FUNCTION_BLOCK FB\nVAR n : INT; END_VAR\nn := 1;\nEND_FUNCTION_BLOCK\n"
    report = check_source(
        block + _program("t := T#500us;") + block.replace("FB", "FC").replace(":=", "="), "a.st"
    )
    assert report.errors == [
        "a.st:7:6: T#500us: a TIME is held in whole ms here; expected T#1ms, or LTIME#500us "
        "for a duration in µs",
        "a.st:11:3: '=' compares; an assignment is ':=' (n := ...)",
    ]

"""Checking a program without running it (:mod:`plc.st.check`): every item's error, one
``file:line:column`` line each, a syntax error in one POU hiding none in another, and a
summary (the command: tests/scenes/test_check_command.py)."""

from __future__ import annotations

import shutil
from pathlib import Path

from plc.st import External
from plc.st.check import Report, check, check_source

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "st"

SOURCE = """FUNCTION_BLOCK FB_A
VAR_INPUT x : INT; END_VAR
VAR y : INT; END_VAR
y := x +;
END_FUNCTION_BLOCK

FUNCTION_BLOCK FB_B
VAR y : INT; END_VAR
y := undefined_thing;
END_FUNCTION_BLOCK

FUNCTION_BLOCK FB_C
VAR y : BOOL; END_VAR
y := 3.5;
END_FUNCTION_BLOCK

FUNCTION F_ok : INT
F_ok := 1;
END_FUNCTION

PROGRAM Main
VAR a : FB_A; b : FB_B; c : INT; END_VAR
a(x := 1);
c := F_ok();
c := nope;
END_PROGRAM
"""
"""Five items: a syntax error in FB_A, a type error in FB_B, in FB_C and in Main (which uses
FB_A and FB_B), none in F_ok."""

ERRORS = [
    "m.st:4:9: unexpected ';'; expected an expression",
    "m.st:9:6: unknown variable 'undefined_thing'; expected a declared variable",
    "m.st:14:1: an ANY_REAL value where BOOL is expected: convert it with TO_BOOL(...)",
    "m.st:25:6: unknown variable 'nope' (did you mean TMNone, done?); expected a declared variable",
]


def test_every_item_gives_its_error():
    """The syntax error of FB_A hides neither the type errors of FB_B and FB_C nor Main's,
    which uses both: their declarations go on without their bodies."""
    report = check_source(SOURCE.replace("c : INT;", "c : INT; done : BOOL;"), "m.st")
    assert report.errors == ERRORS
    assert report.summary() == "4 errors in 4 of 5 items"


def test_an_item_set_aside_leaves_no_errors_of_its_own_making():
    """FB_A's declarations have the error: FB_A is set aside, and Main's use of it is no
    second error (``unknown type 'FB_A'``): Main, which declares an FB_A, is set aside too."""
    source = SOURCE.replace("VAR_INPUT x : INT; END_VAR", "VAR_INPUT x : NoType; END_VAR")
    report = check_source(source.replace("y := x +;", "y := 1;"), "m.st")
    assert [e.split(":")[1] for e in report.errors] == ["2", "9", "14"]
    assert not any("FB_A" in e for e in report.errors)


def test_a_program_without_errors():
    report = check_source("PROGRAM Main\nVAR n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n", "m.st")
    assert (report.errors, report.summary()) == ([], "no errors in 1 item")


def test_a_twincat_project_names_its_files(tmp_path):
    """A syntax error in HomeAxis.TcPOU and a type error in GantryDemo.TcPOU (which uses
    HomeAxis): both, at their files' lines."""
    folder = tmp_path / "gantry_twincat"
    shutil.copytree(EXAMPLES / "gantry_twincat", folder)
    home, demo = folder / "HomeAxis.TcPOU", folder / "GantryDemo.TcPOU"
    home.write_text(home.read_text().replace("IF approach.Error THEN", "IF THEN"))
    demo.write_text(demo.read_text().replace("SPEED : LREAL := 200.0;", "SPEED : LREAL := 'x';"))
    report = check(folder, {"X": None, "Y": None, "Z": None})
    assert [e.split(": ")[0] for e in report.errors] == [f"{home}:30:4", f"{demo}:6:20"]
    assert report.errors[0].endswith(
        "missing the IF's condition before THEN; expected IF x > 0 THEN"
    )
    assert report.summary() == "2 errors in 2 of 4 items"


def test_a_file_that_cannot_be_read(tmp_path):
    report = check(tmp_path / "missing.st")
    assert report.errors[0].startswith(f"{tmp_path / 'missing.st'}: cannot read it")
    assert report.errors[0].endswith("; expected a UTF-8 ST file")
    assert report.summary() == "1 error in 1 of 1 item"


def test_a_source_without_a_program():
    report = check_source(
        "FUNCTION_BLOCK FB\nVAR y : INT; END_VAR\ny := 1;\nEND_FUNCTION_BLOCK\n", "m.st"
    )
    assert report.errors == ["m.st:1:1: no PROGRAM in the file; expected a PROGRAM ... END_PROGRAM"]


def test_a_syntax_error_in_a_block_a_program_calls():
    """The block's declarations go on: the program's call of it is no error."""
    source = (
        "FUNCTION_BLOCK FB\nVAR_INPUT y : INT; END_VAR\ny := ;\nEND_FUNCTION_BLOCK\n"
        "PROGRAM P\nVAR f : FB; END_VAR\nf(y := 2);\nEND_PROGRAM\n"
    )
    report = check_source(source, "m.st")
    assert report.errors == ["m.st:3:6: unexpected ';'; expected an expression"]
    assert report.summary() == "1 error in 1 of 2 items"


def test_a_mapping_onto_no_axis(tmp_path):
    program = EXAMPLES / "manual_move.st"
    report = check(program, {"X": None}, {"Pohon.Ax1": "Q"})
    assert report.errors == [
        f"{program}: the mapping Pohon.Ax1 -> 'Q' names no axis; expected one of X"
    ]
    assert check(program, {"X": None}, {"Pohon.Ax1": "X"}).errors == []


def test_reports_add_up():
    report = Report(["a"], 2, 1)
    report.add(Report(["b", "c"], 3, 2))
    assert (report.errors, report.summary()) == (["a", "b", "c"], "3 errors in 3 of 5 items")
    assert Report([], 2, 0).summary() == "no errors in 2 items"


def test_syntax_errors_in_two_items_and_their_users():
    """FB_A's declarations and FB_B's body cannot be read: both errors; Main, which declares
    an FB_A, gives no ``unknown type 'FB_A'``, and its call of FB_B is checked."""
    source = (
        "FUNCTION_BLOCK FB_A\nVAR_INPUT x : ; END_VAR\nEND_FUNCTION_BLOCK\n"
        "FUNCTION_BLOCK FB_B\nVAR_INPUT y : INT; END_VAR\ny := ;\nEND_FUNCTION_BLOCK\n"
        "PROGRAM Main\nVAR a : FB_A; b : FB_B; END_VAR\nb(y := TRUE);\nEND_PROGRAM\n"
    )
    report = check_source(source, "m.st")
    assert [e.split(": ")[0] for e in report.errors] == ["m.st:2:15", "m.st:6:6"]
    assert report.summary() == "2 errors in 2 of 3 items"


def test_a_block_without_declarations_and_an_error_in_its_body():
    source = (
        "FUNCTION_BLOCK FB\ny := ;\nEND_FUNCTION_BLOCK\n"
        "PROGRAM Main\nVAR n : INT; END_VAR\nn := m;\nEND_PROGRAM\n"
    )
    report = check_source(source, "m.st")
    assert [e.split(": ")[0] for e in report.errors] == ["m.st:2:6", "m.st:6:6"]


def test_an_error_on_the_first_line_of_an_item():
    """The error is the item's own (``FUNCTION F : NoType``), not the one before it."""
    source = (
        "FUNCTION_BLOCK FB\nVAR n : INT; END_VAR\nn := 1;\nEND_FUNCTION_BLOCK\n"
        "FUNCTION F : NoType\nF := 1;\nEND_FUNCTION\n"
        "PROGRAM Main\nVAR f : FB; END_VAR\nf();\nEND_PROGRAM\n"
    )
    report = check_source(source, "m.st")
    assert len(report.errors) == 1 and report.errors[0].startswith("m.st:5:")
    assert report.summary() == "1 error in 1 of 3 items"


def test_the_machines_own_blocks():
    """A block type the machine offers (:class:`plc.st.External`) is known to the check."""
    source = "PROGRAM Main\nVAR g : FS_Gauge; END_VAR\ng(Index := 1);\nEND_PROGRAM\n"
    gauge = External(lambda: None, {"Index": ("DINT", "input"), "Count": ("DINT", "output")})
    assert check_source(source, "m.st", blocks={"FS_Gauge": gauge}).errors == []
    assert check_source(source, "m.st").errors[0].startswith("m.st:2:")


def test_a_twincat_project_without_errors():
    report = check(EXAMPLES / "gantry_twincat", {"X": None, "Y": None, "Z": None})
    assert (report.errors, report.summary()) == ([], "no errors in 4 items")
    assert check(EXAMPLES / "gantry_twincat").errors != []  # no axes: X is unknown

"""What a user reads for a syntax error: ``file:line:column``, what the parser met and what
would have been valid there, the closing keyword first (the parse entry tries the LALR
parser, and the full parser gives the message)."""

from __future__ import annotations

import pytest

import plc.st
from plc.st.frontend import parse as st_parse

DECLARED = "PROGRAM p\nVAR x : INT; END_VAR\n"

STATEMENTS = "'%', ';', 'CASE', 'CONTINUE', 'EXIT', 'FOR', 'IF'"
"""The first words of the statements a body may go on with."""
OPERATORS = "':=', ';', an operator"
"""What may follow an operand: the grammar's operators in a word."""

CASES = [
    (
        "x := 1;\n",
        f"3:8: unexpected end of the source; expected 'END_PROGRAM', {STATEMENTS}",
    ),
    ("x := 3 ? 4;\nEND_PROGRAM\n", f"3:8: unexpected '?'; expected {OPERATORS}"),
    ("x := 1\nx := 2;\nEND_PROGRAM\n", "3:7: missing ';' at the end of line 3"),
    ("x := (1 + 2;\nEND_PROGRAM\n", "3:12: unexpected ';'; expected ')', ':=', an operator"),
    (
        "CASE x OF\n1: x := 2;\nEND_PROGRAM\n",
        "3:1: CASE at 3:1 has no END_CASE; expected END_CASE before 'END_PROGRAM' at 5:1",
    ),
    (
        "FOR x := 1 TO 3 DO\nx := x;\nEND_PROGRAM\n",
        "3:1: FOR at 3:1 has no END_FOR; expected END_FOR before 'END_PROGRAM' at 5:1",
    ),
    (
        "WHILE x < 3 DO x := x + 1;\nEND_PROGRAM\n",
        "3:1: WHILE at 3:1 has no END_WHILE; expected END_WHILE before 'END_PROGRAM' at 4:1",
    ),
]


@pytest.mark.parametrize(("body", "message"), CASES)
def test_a_syntax_error_names_its_place_what_was_met_and_what_was_expected(body, message):
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(DECLARED + body, filename="bad.st")
    assert str(error.value) == f"bad.st:{message}"


def test_a_declaration_without_its_colon():
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source("PROGRAM p\nVAR x INT; END_VAR\nx := 1;\nEND_PROGRAM\n", filename="d.st")
    assert str(error.value) == "d.st:2:7: unexpected 'INT'; expected ',', ':', 'AT', '^'"


@pytest.mark.parametrize(
    ("source", "message"),
    [
        (  # a C habit on the first line: the file's very first character
            '#include "axes.h"\nPROGRAM Main\nVAR x : INT; END_VAR\nx := 1;\nEND_PROGRAM\n',
            "1:1: unexpected '#'; expected ';', 'ACTION', 'CONFIGURATION', 'FUNCTION', "
            "'FUNCTION_BLOCK', 'INTERFACE', 'METHOD', 'PROGRAM'",
        ),
        (  # the file ends inside an IF: named where the IF begins
            "(* Conveyor *)\nPROGRAM Main\nVAR x : INT; END_VAR\nIF x > 0 THEN\n    x := 0;\n",
            "4:1: IF at 4:1 has no END_IF; expected END_IF before the end at 5:12",
        ),
    ],
)
def test_a_file_that_breaks_off_or_begins_wrong_names_its_place(source, message):
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(source, filename="main.st")
    assert str(error.value) == f"main.st:{message}"


BLOCK = "FUNCTION_BLOCK f\nVAR_INPUT a : INT; END_VAR\na := 1;\nEND_FUNCTION_BLOCK\n"


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("x := ;\nEND_PROGRAM\n", "7:6: unexpected ';'; expected an expression"),
        ("x := 1\nx := 2;\nEND_PROGRAM\n", "7:7: missing ';' at the end of line 7"),
        (
            "x := 1;\n",
            f"7:8: unexpected end of the source; expected 'END_PROGRAM', {STATEMENTS}",
        ),
        (
            "IF x > 0 THEN\nx := 1;\nEND_PROGRAM\n",
            "7:1: IF at 7:1 has no END_IF; expected END_IF before 'END_PROGRAM' at 9:1",
        ),
    ],
)
def test_an_error_in_a_later_item_names_its_line_in_the_file(body, message):
    """The items parse one by one: an error in the PROGRAM after a FUNCTION_BLOCK names the
    file's line (a missing ';' in its place and in its words), an unexpected end the end of the
    file's last line."""
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(BLOCK + DECLARED + body, filename="two.st")
    assert str(error.value) == f"two.st:{message}"


@pytest.mark.parametrize(
    ("setting", "jobs"), [("3", 3), (" 2 ", 2), ("1", 1), ("0", None), ("many", None), ("", None)]
)
def test_the_parsing_processes_are_the_setting_else_the_cpus(monkeypatch, setting, jobs):
    """``MCL_ST_JOBS=n`` sets how many processes parse (a positive whole number; anything else:
    one per CPU this process may use)."""
    import os

    monkeypatch.setenv("MCL_ST_JOBS", setting)
    assert st_parse.jobs() == (jobs or len(os.sched_getaffinity(0)))

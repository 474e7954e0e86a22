"""A syntax error as the one who wrote the program reads it: a statement or a declaration
that lacks its ';' is reported at the end of its line ("missing ';' at the end of line 11"),
not at the next line in the parser's terms; the words a message expects are words ("an
operator"), never the grammar's rule names (add_operator)."""

from __future__ import annotations

import re

import pytest

import plc.st
from tests.plc.st.iec import refused
from tests.plc.st.test_projects import _pou

SMALL_TIME = """PROGRAM SmallTime
VAR
    tStep : TON;
    nCount : INT;
    fPos : LREAL;
    done : BOOL;
END_VAR
tStep(IN := NOT tStep.Q, PT := T#500MS);
IF tStep.Q THEN
    nCount := nCount + 1;
    fPos := fPos + 2.5
END_IF
done := nCount >= 10;
END_PROGRAM
"""
"""A program whose statement on line 11 lacks its ';' (END_IF on line 12 shows it)."""


def test_a_statement_without_its_semicolon_is_reported_at_the_end_of_its_line():
    """``fPos := fPos + 2.5`` then END_IF: ``small_time.st:11:23: missing ';' at the end of
    line 11`` (not "unexpected 'END_IF'" at 12:1 with the grammar's terminals)."""
    assert refused(SMALL_TIME, "small_time.st") == (
        "small_time.st:11:23: missing ';' at the end of line 11"
    )


@pytest.mark.parametrize(
    ("before", "after", "message"),
    [
        ("    nCount : INT;", "    nCount : INT", "4:17: missing ';' at the end of line 4"),
        (
            "done := nCount >= 10;",
            "done := nCount >= 10 // enough",
            "13:21: missing ';' at the end of line 13",
        ),
        (
            "tStep(IN := NOT tStep.Q, PT := T#500MS);",
            "tStep(IN := NOT tStep.Q, PT := T#500MS) (* every 0.5 s *)",
            "8:40: missing ';' at the end of line 8",
        ),
    ],
)
def test_a_declaration_or_a_call_without_its_semicolon(before, after, message):
    """A declaration, a statement with a comment after it, a call: each at the end of its own
    line (a comment is no part of the statement)."""
    source = SMALL_TIME.replace("fPos + 2.5\n", "fPos + 2.5;\n").replace(before, after)
    assert refused(source, "small_time.st") == f"small_time.st:{message}"


def test_a_semicolon_missing_in_a_twincat_pou_names_the_line_in_its_file(tmp_path):
    """In a .TcPOU the line named is the file's (the implementation's line 4 is line 16 of
    the XML), in the place and in the message."""
    declared, _, body = SMALL_TIME.partition("END_VAR\n")
    path = tmp_path / "SmallTime.TcPOU"
    path.write_text(_pou("SmallTime", declared + "END_VAR\n", body.replace("END_PROGRAM\n", "")))
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path, period=0.01)
    assert str(error.value) == f"{path}:16:23: missing ';' at the end of line 16"


@pytest.mark.parametrize(
    "statement",
    [
        "nCount := 3 ? 4;",
        "nCount := (1 + 2;",
        "nCount := nCount +;",
        "IF nCount THEN nCount := 1 END_IF;",
        "fPos := fPos * (2.0 3.0);",
        "tStep(IN := , PT := T#1S);",
        "nCount := nCount MOD;",
        "FOR nCount := 1 TO DO END_FOR;",
    ],
)
def test_an_expected_word_is_never_a_rule_name_of_the_grammar(statement):
    """Whatever is wrong, what the message expects is quoted text or words ("an operator",
    "an expression", "a name"), no snake_case name of the grammar (add_operator)."""
    source = SMALL_TIME.replace("done := nCount >= 10;", statement)
    source = source.replace("fPos + 2.5\n", "fPos + 2.5;\n")
    message = refused(source, "small_time.st")
    expected = message.partition("; expected ")[2]
    unquoted = re.sub(r"'[^']*'", "", expected)
    assert not re.search(r"\b[a-z]+_[a-z_]+\b", unquoted), message
    assert "missing ';'" in message or expected, message


def test_a_semicolon_the_statement_may_go_without_is_not_reported_missing():
    """After ``END_IF`` a ';' may follow or not: a VAR block among the statements on the next
    line is reported as itself, not as a ';' missing after END_IF."""
    source = SMALL_TIME.replace("fPos + 2.5\n", "fPos + 2.5;\n")
    source = source.replace("done := nCount >= 10;", "VAR x : INT; END_VAR")
    message = refused(source, "small_time.st")
    assert message.startswith("small_time.st:13:1: unexpected 'VAR'; expected "), message

"""A syntax error as the one who wrote the program reads it: a statement or a declaration
that lacks its ';' is reported at the end of its line ("missing ';' at the end of line 11"),
not at the next line in the parser's terms; the words a message expects are words ("an
operator"), never the grammar's rule names (add_operator)."""

from __future__ import annotations

import re

import pytest

import plc.st
from plc.st.frontend import parse as st_parse
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


BODY = SMALL_TIME.replace("fPos + 2.5\n", "fPos + 2.5;\n")
"""SMALL_TIME with every ';' in place."""


@pytest.mark.parametrize(
    ("source", "message"),
    [
        (
            "TYPE Pos : STRUCT\n    x : LREAL;\nEND_STRUCT\nfSpeed\nEND_TYPE\n" + BODY,
            "4:1: unexpected 'fSpeed'; expected 'END_TYPE', ';'",
        ),
        (
            "TYPE Mode : (Idle, Run)\nfSpeed\nEND_TYPE\n" + BODY,
            "2:1: unexpected 'fSpeed'; expected 'END_TYPE', ':=', ';', a type",
        ),
        (
            "TYPE Mode : (Idle, Run);\nEND_TYPE\nfSpeed\n" + BODY,
            "3:1: unexpected 'fSpeed'; expected ';', 'ACTION', 'CONFIGURATION', 'FUNCTION', "
            "'FUNCTION_BLOCK', 'INTERFACE', 'METHOD', 'PROGRAM'",
        ),
    ],
)
def test_a_semicolon_a_type_may_go_without_is_not_reported_missing(source, message):
    """A ';' after END_STRUCT, after a type's declaration before END_TYPE or after END_TYPE
    may be left out: a stray word on the next line is reported as itself, with what may come
    there (END_TYPE first), not as a ';' missing on the line before."""
    assert refused(source, "types.st") == f"types.st:{message}"


def test_a_word_on_the_line_of_the_statement_is_reported_as_itself():
    """Two statements on one line, the first without its ';': the second's first word is
    unexpected where it stands (no line ends there for a ';' to be missing at)."""
    source = BODY.replace("done := nCount >= 10;", "done := nCount >= 10 nCount := 0;")
    assert refused(source, "small_time.st") == (
        "small_time.st:13:22: unexpected 'nCount'; expected ':=', ';', an operator"
    )


def test_a_source_that_ends_inside_a_statement_ends_there():
    """The file ends after a statement without its ';' and a comment (END_PROGRAM missing
    too): the message is the end of the source, at the end of its last line, and what the
    statement could go on with."""
    source = BODY.replace("END_PROGRAM\n", "nCount := 1\n(* the last\n   count *)\n")
    assert refused(source, "small_time.st") == (
        "small_time.st:16:12: unexpected end of the source; expected ':=', ';', an operator"
    )


def test_every_terminal_a_message_may_expect_has_words():
    """Whatever a message may list of what was expected (any terminal of the grammar), it is
    its quoted text or words, never a rule name (``ADD_OPERATOR``), and none is missing."""
    for terminal in st_parse.parser().terminals:
        if terminal.name.startswith("__"):
            continue  # an unnamed pattern (%I*): left out of the list
        word = st_parse._word(terminal.name)
        unquoted = re.sub(r"'[^']*'", "", word)
        assert not re.search(r"\w+_\w+", unquoted), (terminal.name, word)
        assert word or terminal.name in ("WS", "SINGLE_LINE_COMMENT", "MULTI_LINE_COMMENT")

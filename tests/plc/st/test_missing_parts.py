"""A statement missing a part (a FOR's end value, an IF's condition, ...) is reported as that
part, where it belongs; a call's input given no value (``IN := ,``) as that input."""

from __future__ import annotations

import pytest

import plc.st
from plc.st.frontend.missing import missing_part

DECLARED = "PROGRAM p\nVAR t : TON; n : INT; x : INT; END_VAR\n"

FOR = "FOR n := 1 TO 10 DO"

CASES = [
    (
        "FOR n := 1 TO DO x := 1; END_FOR;",
        f"3:15: missing the FOR's end value after TO; expected {FOR}",
    ),
    (
        "FOR n := 1 TO BY 2 DO x := 1; END_FOR;",
        "3:15: missing the FOR's end value after TO; expected FOR n := 1 TO 10 BY 2 DO",
    ),
    (
        "FOR n := TO 10 DO x := 1; END_FOR;",
        f"3:10: missing the FOR's start value after ':='; expected {FOR}",
    ),
    (
        "FOR n := 1 TO 10 BY DO x := 1; END_FOR;",
        "3:21: missing the FOR's step after BY; expected FOR n := 1 TO 10 BY 2 DO, or no BY",
    ),
    (
        "IF THEN x := 1; END_IF;",
        "3:4: missing the IF's condition before THEN; expected IF x > 0 THEN",
    ),
    (
        "IF x > 1 THEN x := 1; ELSIF THEN x := 2; END_IF;",
        "3:29: missing the ELSIF's condition before THEN; expected ELSIF x > 0 THEN",
    ),
    (
        "WHILE DO x := 1; END_WHILE;",
        "3:7: missing the WHILE's condition before DO; expected WHILE x < 10 DO",
    ),
    (
        "REPEAT x := 1; UNTIL END_REPEAT;",
        "3:22: missing the REPEAT's condition after UNTIL; expected UNTIL x >= 10 END_REPEAT",
    ),
    (
        "CASE OF 1: x := 1; END_CASE;",
        "3:6: missing the CASE's selector before OF; expected CASE step OF",
    ),
    (
        "FOR n := DO x := 1; END_FOR;",
        f"3:10: missing the FOR's start value after ':='; expected {FOR}",
    ),
    # an assignment without its value keeps its message: an expression at the ';'
    ("x := ;", "3:6: unexpected ';'; expected an expression"),
    # (* a comment *) between the keywords is no part of the statement
    ("IF (* none *) THEN x := 1; END_IF;", "3:15: missing the IF's condition before THEN"),
]


@pytest.mark.parametrize(("body", "message"), CASES)
def test_a_missing_part_is_named_where_it_belongs(body, message):
    with pytest.raises(plc.st.STError) as error:
        plc.st.compile_source(f"{DECLARED}{body}\nEND_PROGRAM\n", "m.st")
    assert str(error.value).startswith(f"m.st:{message}")


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ("t(IN := , PT := T#1S);", "3:3: the input IN has no value"),
        ("t(IN := TRUE, PT := );", "3:15: the input PT has no value"),
        ("x := LIMIT(MN := 1, IN := , MX := 3);", "3:21: the input IN has no value"),
    ],
)
def test_an_input_without_its_value_is_named(call, message):
    with pytest.raises(plc.st.STError) as error:
        plc.st.compile_source(f"{DECLARED}{call}\nEND_PROGRAM\n", "m.st")
    name = message.split()[3]
    assert str(error.value) == f"m.st:{message}; expected {name} := value, or no {name} := at all"


def test_an_input_without_its_value_in_a_later_item():
    """The input's line counts the items before it (each item is parsed on its own)."""
    block = "FUNCTION_BLOCK FB\nVAR_INPUT a : INT; END_VAR\nEND_FUNCTION_BLOCK\n"
    source = f"{block}{DECLARED}t(IN := , PT := T#1S);\nEND_PROGRAM\n"
    with pytest.raises(plc.st.STError) as error:
        plc.st.compile_source(source, "m.st")
    assert str(error.value).startswith("m.st:6:3: the input IN has no value")


def test_the_part_is_found_within_the_word_the_parser_stopped_in():
    """The parser stops at the ``HEN`` of ``THEN`` (``T#...``): the message names THEN's place,
    the first line of the text unless lines come before it."""
    assert missing_part("IF THEN", 4, "HEN") == (
        1,
        4,
        "missing the IF's condition before THEN; expected IF x > 0 THEN",
    )
    later = missing_part("IF THEN", 4, "HEN", lines_before=2)
    assert later is not None and later[:2] == (3, 4)
    assert missing_part("CASE_x OF", 7, "OF") is None
    assert missing_part("IF x THEN", 5, "THEN") is None
    assert missing_part("THEN", 1, "HEN") is None  # nothing before it

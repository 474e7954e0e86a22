"""A syntax error in the words of the one who wrote the program: a statement or declaration
that lacks its ``;`` (the parser meets the next line) is ``missing ';' at the end of line 11``
at the place the ``;`` belongs, and the grammar's terminals a message lists are words
(``an operator``, ``a number``), never the grammar's rule names."""

from __future__ import annotations

__all__ = ["equals_as_assignment", "micros_in_time", "missing_semicolon", "terminal_words"]

import re

from plc.st.errors import place
from plc.st.frontend.tctask import WHOLE_MS
from plc.st.frontend.unclosed import code_only

_OPERATOR = "an operator"
_TYPE = "a type"
_NUMBER = "a number"
_STRING = "a string"

_WORDS = {
    "ADD_OPERATOR": _OPERATOR,
    "MULTIPLY_OPERATOR": _OPERATOR,
    "COMPARE_OP": _OPERATOR,
    "EQUALS_OP": _OPERATOR,
    "LOGICAL_AND": _OPERATOR,
    "LOGICAL_AND_THEN": _OPERATOR,
    "LOGICAL_OR": _OPERATOR,
    "LOGICAL_OR_ELSE": _OPERATOR,
    "LOGICAL_XOR": _OPERATOR,
    "OPERATOR_FUNCTION": _OPERATOR,
    "UNARY_OPERATOR": "an expression",
    "LOGICAL_NOT": "an expression",
    "IDENTIFIER": "a name",
    "DOTTED_IDENTIFIER": "a name",
    "LABEL": "a name",
    "INTEGER": _NUMBER,
    "SIGNED_INTEGER": _NUMBER,
    "FIXED_POINT": _NUMBER,
    "BIT_STRING": _NUMBER,
    "OCTAL_STRING": _NUMBER,
    "TRUE_VALUE": "'TRUE'",
    "FALSE_VALUE": "'FALSE'",
    "TYPED_ENUM_VALUE": "a value",
    "SINGLE_BYTE_CHARACTER_STRING": _STRING,
    "DOUBLE_BYTE_CHARACTER_STRING": _STRING,
    "BIT_STRING_TYPE_NAME": _TYPE,
    "DATE_TYPE_NAME": _TYPE,
    "ENUM_DATA_TYPE_NAME": _TYPE,
    "INTEGER_TYPE_NAME": _TYPE,
    "NUMERIC_TYPE_NAME": _TYPE,
    "REAL_TYPE_NAME": _TYPE,
    "STRING": "'STRING'",
    "WSTRING": "'WSTRING'",
    "FUNCTION_BLOCK": "'FUNCTION_BLOCK'",
    "END_FUNCTION_BLOCK": "'END_FUNCTION_BLOCK'",
    "ACCESS_SPECIFIER": "an access specifier",
    "GLOBAL_VAR_ATTRIB": "'CONSTANT', 'RETAIN'",
    "VAR_ATTRIB": "'CONSTANT', 'RETAIN'",
    "LOCATION_PREFIX": "'I', 'Q', 'M'",
    "SIZE_PREFIX": "'X', 'B', 'W', 'D', 'L'",
    "POINTER_TO": "'POINTER TO'",
    "REFERENCE_TO": "'REFERENCE TO'",
    "REF_TO": "'REF_TO'",
    "R_EDGE": "'R_EDGE'",
    "F_EDGE": "'F_EDGE'",
    "PRAGMA": "a pragma",
    "MULTI_LINE_COMMENT": "",
    "SINGLE_LINE_COMMENT": "",
    "WS": "",
}
"""The grammar's terminals whose pattern is no one word, as a message says them ("" none)."""

_OPERATORS = frozenset(["'**'"])
"""Operators the grammar writes as themselves: listed with the others, as ``an operator``."""


def terminal_words(terminal: str, literal: str) -> str:
    """A terminal of the grammar as a message says it: ``literal`` (its text, quoted) where it
    has one, else a word for it (``an operator``, ``a number``; "" for a comment): every
    terminal of the grammar without a text has its words in ``_WORDS``."""
    if literal in _OPERATORS:
        return _OPERATOR
    if literal:
        return literal
    return _WORDS[terminal.upper()]


_CASE_LABEL = re.compile(r"[\w#.+-]+(?:\s*(?:,|\.\.)\s*[\w#.+-]+)*\s*:(?!=)")
"""A CASE label (``PowerOn:``, ``1, 2:``, ``3..5:``) where the parser met its first word."""


def missing_semicolon(
    text: str, position: int, expected: set[str], lines_before: int
) -> tuple[int, int, str] | None:
    """The missing ``;`` a syntax error at ``position`` of ``text`` is: (the line and column
    where it belongs, the message), or None where the error is another (the parser could
    take no ``;`` there or could go on without one, as after END_IF; or the word it met is on
    the line of what goes before it).

    Args:
        text: the parsed text (its comments in it).
        position: where the unexpected word begins (``len(text)`` at its end).
        expected: the terminals the parser expected there (``SEMICOLON`` among them).
        lines_before: the lines before ``text`` in its file (for the lines named).
    """
    optional = "IDENTIFIER" in expected or any(n.startswith("_") for n in expected)
    if optional and _CASE_LABEL.match(text, position):
        optional = False  # the next CASE label: the statement before it lacks its ';'
    if "SEMICOLON" not in expected or optional or position >= len(text):
        return None
    before = code_only(text[:position]).rstrip()
    if not before or "\n" not in text[len(before) : position]:
        return None
    line = before.count("\n") + 1 + lines_before
    column = len(before) - (before.rfind("\n") + 1) + 1
    return line, column, f"missing ';' at the end of line {line}"


_TARGET = re.compile(r"(\w+(?:\s*\.\s*\w+|\[[^\]\n]*\]|\^)*)\s*\Z")
"""The variable a statement begins with, at the end of the text before its ``=``."""


def equals_as_assignment(
    text: str, position: int, word: str, expected: set[str], lines_before: int
) -> tuple[int, int, str] | None:
    """``nVisited = nVisited + 1;``: a ``=`` where the parser could take the ``:=`` of an
    assignment (the line and column of the ``=``, the message), else None."""
    if word != "=" or "ASSIGNMENT" not in expected:
        return None
    target = _TARGET.search(code_only(text[:position]))
    name = target[1] if target else "x"
    line, column = place(text, position)
    return line + lines_before, column, f"'=' compares; an assignment is ':=' ({name} := ...)"


_TIME_BEFORE = re.compile(
    r"(?P<interval>\bINTERVAL\s*:=\s*)?(?P<literal>\b(?:TIME|T)#[\w.+-]*)\Z", re.I
)
"""A TIME literal (a task's INTERVAL) up to the unit the parser did not take."""


def micros_in_time(
    text: str, position: int, word: str, lines_before: int
) -> tuple[int, int, str] | None:
    """``T#500us``: a TIME literal in µs or ns, which TIME (held in whole ms here) cannot hold
    (the line and column of the literal, the message), else None."""
    unit = word.lower()
    found = _TIME_BEFORE.search(text[:position]) if unit in ("us", "ns") else None
    if found is None:
        return None
    value = found["literal"] + word
    line, column = place(text, found.start("literal"))
    if found["interval"]:
        problem = f"INTERVAL := {value}: {WHOLE_MS}"
        right = "T#1ms, T#2ms, ..."
    else:
        problem = f"{value}: a TIME is held in whole ms here"
        duration = "µs" if unit == "us" else "ns"
        right = f"T#1ms, or LTIME#{value.partition('#')[2]} for a duration in {duration}"
    return line + lines_before, column, f"{problem}; expected {right}"

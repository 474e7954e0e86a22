"""A syntax error that is a keyword used as a name: ``VAR by : INT; END_VAR`` shows only as an
unexpected ``by`` where a name may stand; it is reported as the reserved keyword it is, with a
name that would do (IEC 61131-3 2.1.2: keywords are no identifiers).

The keywords are the words blark's grammar refuses as a name (those IEC reserves; TwinCAT's
own words and IEC's ``ON``, ``TASK``, ``STEP`` that programs use as names are not among them).
"""

from __future__ import annotations

__all__ = ["keywords", "reserved_name"]

import importlib.resources
import re
from functools import cache

from plc.st.errors import place
from plc.st.frontend import grammar

_AFTER_NAME = re.compile(r"\s*[:,)]")
"""What follows a name where one is declared or assigned: ``:``, ``:=``, ``,``, ``)``."""

_WORD_BEFORE = re.compile(r"(\w*)[ \t]*\Z")

_DECLARATION_WORDS = frozenset({"AT", "PERSISTENT"})
"""Keywords that may begin a declaration: a name that is one is read as that keyword."""

_NAMED = {"PROGRAM": "a PROGRAM", "FUNCTION_BLOCK": "a FUNCTION_BLOCK", "FUNCTION": "a FUNCTION"}
"""The keywords a name follows, and what the name names (else a variable)."""


@cache
def keywords() -> frozenset[str]:
    """The words that cannot be a name, upper case."""
    text = grammar.extended(importlib.resources.files("blark").joinpath("iec.lark").read_text())
    found = re.search(r"^IDENTIFIER: /\\b\(\?!\(([A-Z_|]+)\)", text, re.M)
    assert found is not None
    return frozenset(found[1].split("|"))


def reserved_name(
    text: str, position: int, word: str, expected: set[str], lines_before: int
) -> tuple[int, int, str] | None:
    """The keyword used as a name a syntax error at ``position`` of ``text`` is: (its line, its
    column, the message), or None where the error is another.

    Args:
        text: the parsed text.
        position: where the unexpected ``word`` begins.
        word: the text the parser did not expect there.
        expected: the terminals it expected there (blark's names: ``IDENTIFIER``).
        lines_before: the lines before ``text`` in its file (for the line named).
    """
    before = _word_before(text, position)
    start = position
    if before[1].upper() in _DECLARATION_WORDS and word == ":":
        start, word = before.start(1), before[1]  # "at : INT": read as the AT of an address
        before = _word_before(text, start)
        if before[1] and not before[1].upper().startswith("VAR"):
            return None  # "x AT : BOOL": the address is missing
    elif "IDENTIFIER" not in expected:
        return None
    named = _NAMED.get(before[1].upper())
    if word.upper() not in keywords() or not (named or _AFTER_NAME.match(text, start + len(word))):
        return None
    line, column = place(text, start)
    other = f"{word}_VALUE" if word.isupper() else f"{word}Value"
    problem = f"{word.upper()} is a reserved keyword of IEC 61131-3 and cannot name"
    message = f"{problem} {named or 'a variable'}; expected another name, such as {other}"
    return line + lines_before, column, message


def _word_before(text: str, end: int) -> re.Match[str]:
    """The word before ``end`` on its line (group 1; empty if there is none)."""
    found = _WORD_BEFORE.search(text[:end])
    assert found is not None
    return found

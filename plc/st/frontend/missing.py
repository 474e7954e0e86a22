"""A syntax error that is a part of a statement left out: ``FOR n := 1 TO DO`` shows only as an
unexpected ``O`` (the parser reads ``D`` as the start of a date, ``D#...``), ``IF THEN`` as an
unexpected ``HEN``; it is reported as the part that is missing and where it belongs,
``missing the FOR's end value after TO; expected FOR n := 1 TO 10 DO``."""

from __future__ import annotations

__all__ = ["missing_part"]

import re
import string

from plc.st.errors import place
from plc.st.frontend.unclosed import code_only

_PARTS = {
    ("TO", "DO"): ("the FOR's end value after TO", "FOR n := 1 TO 10 DO"),
    ("TO", "BY"): ("the FOR's end value after TO", "FOR n := 1 TO 10 BY 2 DO"),
    ("BY", "DO"): ("the FOR's step after BY", "FOR n := 1 TO 10 BY 2 DO, or no BY"),
    ("IF", "THEN"): ("the IF's condition before THEN", "IF x > 0 THEN"),
    ("ELSIF", "THEN"): ("the ELSIF's condition before THEN", "ELSIF x > 0 THEN"),
    ("WHILE", "DO"): ("the WHILE's condition before DO", "WHILE x < 10 DO"),
    ("UNTIL", "END_REPEAT"): ("the REPEAT's condition after UNTIL", "UNTIL x >= 10 END_REPEAT"),
    ("CASE", "OF"): ("the CASE's selector before OF", "CASE step OF"),
}
"""(the word before the gap, the word after it): what is missing, a statement that has it."""

_WORD_CHARACTERS = string.ascii_letters + string.digits + "_"
"""What a word is made of (the parser may stop within one: its start is before)."""
_LAST = re.compile(r"(\w+|:=|\S)\s*\Z")
_FOR_START = re.compile(r"\bFOR\s+\w+\s*\Z", re.I)


def missing_part(
    text: str, position: int, word: str, lines_before: int = 0
) -> tuple[int, int, str] | None:
    """The part of a statement a syntax error at ``position`` of ``text`` is the lack of:
    (the line and column where it belongs, the message), or None where the error is another.

    Args:
        text: the parsed text (its comments in it).
        position: where the unexpected ``word`` begins (within a word: the parser may have
            read its first letter as a prefix, ``D#``, ``T#``).
        word: the text the parser did not expect there.
        lines_before: the lines before ``text`` in its file (for the line named).
    """
    start = len(text[:position].rstrip(_WORD_CHARACTERS))
    after = re.match(r"\w+", text[start:])
    met = after[0].upper() if after else word
    code = code_only(text[:start])
    last = _LAST.search(code)
    if last is None:
        return None
    before = last[1].upper()
    found = _PARTS.get((before, met)) or (
        _assigned(code[: last.start()]) if before == ":=" else None
    )
    if found is None:
        return None
    line, column = place(text, start)
    return line + lines_before, column, f"missing {found[0]}; expected {found[1]}"


def _assigned(before: str) -> tuple[str, str] | None:
    """What is missing after a ``:=`` (``before`` the code before it): a FOR's start value
    (``x := ;`` keeps its own message: an expression expected at ``;``)."""
    if _FOR_START.search(before):
        return "the FOR's start value after ':='", "FOR n := 1 TO 10 DO"
    return None

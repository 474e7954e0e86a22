"""A syntax error that is a statement left open: an IF without its END_IF (likewise CASE, FOR,
WHILE, REPEAT) shows only where the parser meets what closes the construct around it (an
END_CASE, the END_PROGRAM, the next CASE label); it is reported where the open statement
begins, ``IF at 5:6 has no END_IF``."""

from __future__ import annotations

__all__ = ["code_only", "unclosed"]

import re

from plc.st.errors import place

_CLOSERS = {
    "IF": "END_IF",
    "CASE": "END_CASE",
    "FOR": "END_FOR",
    "WHILE": "END_WHILE",
    "REPEAT": "UNTIL",
}
"""The statements that open a block, and the keyword the parser waits for to close it."""

_CLOSED_BY = {"END_IF": "IF", "END_CASE": "CASE", "END_FOR": "FOR", "END_WHILE": "WHILE"}
_CLOSED_BY["END_REPEAT"] = "REPEAT"

_KEYWORD = re.compile(
    r"\b(?:END_IF|END_CASE|END_FOR|END_WHILE|END_REPEAT|IF|CASE|FOR|WHILE|REPEAT)\b", re.I
)
_OPAQUE = re.compile(
    r"'(?:\$.|[^'$\n])*'|\"(?:\$.|[^\"$\n])*\"|\(\*.*?\*\)|/\*.*?\*/|//[^\n]*|\{[^}]*\}", re.S
)
"""Strings, comments and pragmas: no keyword in them opens or closes a statement."""
_LABEL = re.compile(r"\s*(?:\.\.\s*[\w#.+-]+\s*)?(?:,[^:;]*)?:(?!=)")
"""What follows a CASE label's first value: ``..high``, more values, then ``:``."""


_NOT_BREAK = re.compile(r"[^\n]")


def code_only(text: str) -> str:
    """``text`` with its strings, comments and pragmas blanked (each character a space, each
    line break kept: a line counted in it is the line in ``text``)."""
    return _OPAQUE.sub(lambda m: _NOT_BREAK.sub(" ", m[0]), text)


def unclosed(
    text: str, position: int, token: str, expected: set[str], lines_before: int = 0
) -> tuple[int, int, str] | None:
    """The open statement a syntax error at ``position`` of ``text`` is:
    (its line, its column, the message), or None where the error is another.

    Args:
        text: the parsed text (its comments in it).
        position: where the unexpected ``token`` begins (``len(text)`` at its end).
        token: the text the parser did not expect (empty at the end of the text).
        expected: the terminals it expected there (blark's names: ``_END_IF``, ``SEMICOLON``).
        lines_before: the lines before ``text`` in its file (for the lines named).
    """
    openers: list[re.Match[str]] = []
    for match in _KEYWORD.finditer(code_only(text[:position])):
        word = match[0].upper()
        if word in _CLOSERS:
            openers.append(match)
        elif openers and openers[-1][0].upper() == _CLOSED_BY[word]:
            openers.pop()
    if not openers:
        return None
    top = openers[-1]
    opener = top[0].upper()
    closer = _CLOSERS[opener]
    if closer not in {name.lstrip("_").upper() for name in expected}:
        return None
    word = token.upper()
    label = any(o[0].upper() == "CASE" for o in openers[:-1]) and _LABEL.match(
        text, position + len(token)
    )
    if not (word == "" or word.startswith("END_") or word in ("UNTIL", "ELSE", "ELSIF") or label):
        return None
    line, column = place(text, top.start())
    at_line, at_column = place(text, position)
    line, at_line = line + lines_before, at_line + lines_before
    needed = "UNTIL ... END_REPEAT" if opener == "REPEAT" else closer
    met = f"'{token}'" if token else "the end"
    before = f"before {met} at {at_line}:{at_column}"
    return line, column, f"{opener} at {line}:{column} has no {needed}; expected {needed} {before}"

"""Errors of ST programs: a mistake in a source (:class:`STError`, ``file:line:column: what is
wrong; expected ...``) and a run-time fault that stops the program (:class:`PLCFault`)."""

from __future__ import annotations

__all__ = ["PLCFault", "STError", "indefinite", "nearest", "place"]

import difflib
import re
from collections.abc import Iterable


class STError(ValueError):
    """A mistake in an ST source: one line, ``file:line:column: problem; expected what``."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.lines = message.splitlines()
        """One line per mistake (as :class:`scenes.errors.UserError`)."""

    @classmethod
    def at(cls, where: str, problem: str, expected: str = "") -> STError:
        """The error ``where: problem; expected expected`` (``expected`` may be empty)."""
        return cls(
            f"{where}: {problem}; expected {expected}" if expected else f"{where}: {problem}"
        )


class PLCFault(RuntimeError):
    """A run-time error stopped the program (division by zero, array index out of range); the
    message names the ST file and line."""


def place(text: str, position: int) -> tuple[int, int]:
    """The line and the column (from 1) of the character at ``position`` of ``text``."""
    before = text[:position]
    return before.count("\n") + 1, len(before) - before.rfind("\n")


def nearest(name: str, choices: Iterable[str], n: int = 3) -> list[str]:
    """The valid names closest to ``name`` (case-insensitive), best first."""
    by_lower = {c.lower(): c for c in choices}
    close = difflib.get_close_matches(name.lower(), list(by_lower), n=n, cutoff=0.5)
    return [by_lower[c] for c in close]


_SPELLED = frozenset(
    [
        "LREAL",
        "LINT",
        "LWORD",
        "LTIME",
        "LDATE",
        "LTOD",
        "LDT",
        "SINT",
        "DINT",
        "UDINT",
        "UINT",
        "USINT",
        "ULINT",
        "DWORD",
        "WSTRING",
        "WCHAR",
        "TOD",
        "DT",
    ]
)
"""Type names whose first letter is said as a letter: "el-real", "es-int", "you-dint"."""

_LETTER_VOWEL = frozenset("AEFHILMNORSX")
"""Letters whose spoken names begin with a vowel sound: "an LREAL", "an SINT", "an FB_Home"."""

_WORD_VOWEL = frozenset("AEIO")
"""Letters that begin a word with a vowel sound (not U: "a UNION", as "you")."""

_PREFIX = re.compile(r"([A-Z]{1,3})_")


def indefinite(name: str) -> str:
    """``name`` with "a" or "an" as it is spoken: a word by its first letter ("an INT", "an
    ARRAY", "a REAL", "a UDINT": U is said "you"), a spelled prefix by its letter ("an LREAL",
    "an SINT", "an ST_Point", "an E_Step", "an RS", "a DINT")."""
    word = re.split(r"[^A-Za-z0-9_]", name.strip(), maxsplit=1)[0]
    upper = word.upper()
    prefix = _PREFIX.match(word)
    spelled = (
        upper in _SPELLED
        or (prefix is not None and (len(prefix[1]) == 1 or not set(prefix[1]) & set("AEIOU")))
        or (word.isupper() and len(word) <= 3 and not set(upper) & set("AEIOUY"))
    )
    vowel = upper[:1] in (_LETTER_VOWEL if spelled else _WORD_VOWEL)
    return f"{'an' if vowel else 'a'} {name}"

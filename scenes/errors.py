"""Errors of the testbench.

A user's mistake (in a sweep file, a trace file, a machine's MJCF model, a command-line value) is
a :class:`UserError`: its message is one line per mistake, ``where: key: what is wrong; expected
...``, where ``where`` is ``file:line`` when the line is known. ``python -m scenes`` prints it
and exits with status 2, without a traceback.
"""

from __future__ import annotations

__all__ = ["ModelError", "UserError", "WiringError", "located", "suggest"]

import difflib
from collections.abc import Iterable, Sequence


class UserError(ValueError):
    """A user's mistake; the message (one line per mistake) says where, what and what would be
    right."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.lines = message.splitlines()
        """One line per mistake."""

    @classmethod
    def at(cls, where: str, key: str, problem: str, expected: str) -> UserError:
        """The error ``where: key: problem; expected expected`` (``key`` may be empty)."""
        return cls(located(where, key, problem, expected))

    @classmethod
    def of(cls, lines: Sequence[str]) -> UserError:
        """One error holding several mistakes, one line each."""
        return cls("\n".join(lines))


class WiringError(UserError):
    """The model does not provide what an axis needs; the message says what and what would fit."""


class ModelError(WiringError):
    """A machine's MJCF file is malformed or does not fit its machine definition; the message
    names the file and line."""


def located(where: str, key: str, problem: str, expected: str) -> str:
    """One line: ``where: key: problem; expected expected``."""
    head = f"{where}: {key}: " if key else f"{where}: "
    return f"{head}{problem}; expected {expected}"


def suggest(name: str, choices: Iterable[str]) -> str:
    """``" (did you mean 'x'?)"`` for the closest of ``choices``, or ``""``."""
    close = difflib.get_close_matches(name, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""

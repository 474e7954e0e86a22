"""Errors of ST programs: a mistake in a source (:class:`STError`, ``file:line:column: what is
wrong; expected ...``) and a run-time fault that stops the program (:class:`PLCFault`)."""

from __future__ import annotations

__all__ = ["PLCFault", "STError", "nearest"]

import difflib
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


def nearest(name: str, choices: Iterable[str], n: int = 3) -> list[str]:
    """The valid names closest to ``name`` (case-insensitive), best first."""
    by_lower = {c.lower(): c for c in choices}
    close = difflib.get_close_matches(name.lower(), list(by_lower), n=n, cutoff=0.5)
    return [by_lower[c] for c in close]

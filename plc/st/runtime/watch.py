"""The watch table of a running ST program, as the online view of a PLC IDE shows it: the
PROGRAM's variables (and the globals) with type and value, the outputs of its block instances
(``Head_X.Done``), and forcing: a forced BOOL or number variable is written before (and after)
every scan until it is unforced.

:class:`WatchedProgram` is the demo program the session runs for an ST file; it is touched only
in the simulation thread, which publishes its :class:`WatchRow` tuples for the pages.
"""

from __future__ import annotations

__all__ = ["FORCEABLE", "WATCHED_SECTIONS", "WatchRow", "WatchedProgram", "value_text"]

import math
from dataclasses import dataclass
from typing import Any

from plc.st import STProgram
from plc.st.runtime import functions as F  # noqa: N812
from plc.st.runtime.program import program_name, stored
from plc.st.semantics.scope import Var
from plc.st.semantics.types import BlockType, Elementary, EnumType, Member

FORCEABLE = ("bool", "int", "bits", "real")
"""The kinds of elementary variable a page may force."""

WATCHED_SECTIONS = ("input", "output", "in_out", "local", "global")
"""The declaration sections shown (VAR_TEMP is not kept between scans)."""


@dataclass(frozen=True)
class WatchRow:
    """One line of the watch table.

    Attributes:
        name: the variable (``Start``, ``Head_X.Done``).
        type: its ST type name (``BOOL``, ``LREAL``).
        value: its value now, as text (``TRUE``, ``300.000``).
        forced: it is forced (written before every scan).
        forceable: a page may force it (a BOOL or number variable of the program).
    """

    name: str
    type: str
    value: str
    forced: bool = False
    forceable: bool = False


def value_text(value: Any) -> str:
    """A value as an ST IDE shows it: ``TRUE``/``FALSE``, reals with 3 decimals."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, float):
        return f"{value:.3f}"
    return str(value)


class WatchedProgram:
    """An ST program run as the viewer's demo, its variables watched and forceable.

    Args:
        program: the loaded program.
    """

    def __init__(self, program: STProgram) -> None:
        self.program = program
        self._forced: dict[str, Any] = {}
        module = program.module
        self._vars: dict[str, Var] = {
            v.name: v
            for v in {**module.globals, **module.programs[program_name(program)]}.values()
            if v.section in WATCHED_SECTIONS and ("." in v.code or v.constant is not None)
        }

    @property
    def done(self) -> bool:
        """The program's ``done``."""
        return self.program.done

    @property
    def step(self) -> str:
        """The program's ``step`` (its fault once one stopped it)."""
        return self.program.step

    @property
    def error(self) -> str:
        """The run-time fault (``file:line: ...``) or the program's ``error``."""
        return self.program.error

    def __call__(self) -> None:
        """One PLC scan: the forced variables written, the program, and the forced variables
        written again (as CODESYS forces: at the start and the end of the cycle, so that the
        program's own writes never show outside it)."""
        program, forced = self.program, self._forced  # the dict is replaced, never changed
        for name, value in forced.items():
            setattr(program, name, value)
        program()
        for name, value in forced.items():
            setattr(program, name, value)

    def forceable(self) -> tuple[str, ...]:
        """The variables a page may force, in declaration order."""
        return tuple(n for n, v in self._vars.items() if _forceable(v))

    def force(self, name: str, value: bool | float) -> None:
        """Force ``name`` to ``value`` (written before every scan until :meth:`unforce`).

        Raises:
            ValueError: no forceable variable ``name``, or a value its type cannot take.
        """
        var = self._vars.get(name)
        if var is None or not _forceable(var):
            raise ValueError(
                f"{name!r} is no BOOL or number variable of {program_name(self.program)}"
            )
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(f"{name}: {value!r} is no number")
        try:
            forced = {**self._forced, name: stored(value, var)}
        except TypeError as error:
            raise ValueError(str(error)) from None
        self._forced = forced  # a new dict: a scan in the simulation thread never sees it change

    def unforce(self, name: str) -> bool:
        """Stop forcing ``name`` (it keeps its value until the program writes it); whether it
        was forced."""
        forced = dict(self._forced)
        was = forced.pop(name, None) is not None
        self._forced = forced
        return was

    def rows(self) -> tuple[WatchRow, ...]:
        """The watch table now: each variable, then each output of a block instance."""
        program, forced = self.program, self._forced
        rows: list[WatchRow] = []
        for name, var in self._vars.items():
            value = getattr(program, name)
            t = var.type
            if isinstance(t, BlockType):
                rows.extend(
                    WatchRow(
                        f"{name}.{_spelled(member, m)}",
                        m.type.name,
                        value_text(getattr(value, m.python)),
                    )
                    for member, m in t.members.items()
                    if m.direction == "output"
                )
            elif isinstance(t, EnumType):
                named = next((n for n, v in t.values.items() if v == value), str(value))
                rows.append(WatchRow(name, t.name, named))
            elif isinstance(t, Elementary) and t.kind in ("date", "tod", "dt"):
                rows.append(WatchRow(name, t.name, getattr(F, f"{t.kind}_text")(value)))
            elif isinstance(t, Elementary):
                rows.append(
                    WatchRow(name, t.name, value_text(value), name in forced, _forceable(var))
                )
        return tuple(rows)


def _forceable(var: Var) -> bool:
    """A variable a page may force: a BOOL or number, not a CONSTANT."""
    t = var.type
    return isinstance(t, Elementary) and t.kind in FORCEABLE and var.constant is None


def _spelled(member: str, m: Member) -> str:
    """A block output's name as its block spells it (``Done``; ``member`` is upper case)."""
    return m.python if m.python.upper() == member else member

"""Global variable lists (GVLs, as TwinCAT and CODESYS keep globals): a VAR_GLOBAL block that
has a name, so that a program may write ``GVL_Axes.X`` as well as ``X``; a GVL with
``{attribute 'qualified_only'}`` only so.

A block's name and attributes are pragmas before its VAR_GLOBAL: ``{attribute 'gvl' :=
'GVL_Axes'}`` names it (the TwinCAT and PLCopen readers write it from the GVL's name),
``{attribute 'qualified_only'}`` asks for the qualified name. A GVL may have several sections
(``VAR_GLOBAL CONSTANT ... END_VAR VAR_GLOBAL ... END_VAR``, as a ``.TcGVL`` holds them): a
VAR_GLOBAL without a name of its own belongs to the GVL before it, up to the next POU.
"""

from __future__ import annotations

__all__ = ["GVL", "NAME_PRAGMA", "attributes", "gvl_of", "pragmas", "sections"]

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import blark.transform as tf

from plc.st.errors import STError, nearest

NAME_PRAGMA = "{{attribute 'gvl' := '{}'}}"
"""The pragma that names the VAR_GLOBAL block after it (``.format(name)``)."""

_ATTRIBUTE = re.compile(r"\{\s*attribute\s+'([^']*)'\s*(?::=\s*'([^']*)'\s*)?\}", re.I)


@dataclass
class GVL:
    """A named VAR_GLOBAL block.

    Attributes:
        name: as declared.
        qualified_only: its variables are written ``name.var`` only.
        vars: its variables by lower-case name (:class:`~plc.st.semantics.scope.Var`).
    """

    name: str
    qualified_only: bool = False
    vars: dict[str, Any] = field(default_factory=dict)

    def var(self, name: str, where: str) -> Any:
        """The variable ``name`` of this list.

        Raises:
            STError: it declares none of that name.
        """
        found = self.vars.get(name.lower())
        if found is None:
            declared = [v.name.rpartition(".")[2] for v in self.vars.values()]
            close = nearest(name, declared)
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise STError.at(
                where,
                f"the GVL {self.name} has no variable {name!r}{hint}",
                ", ".join(f"{self.name}.{n}" for n in declared) or "a variable it declares",
            )
        return found


def attributes(pragmas: list[str]) -> dict[str, str]:
    """The ``{attribute 'name' := 'value'}`` pragmas among ``pragmas`` (lower-case name →
    value, empty without one)."""
    found = {}
    for text in pragmas:
        match = _ATTRIBUTE.fullmatch(text.strip())
        if match is not None:
            found[match[1].lower()] = match[2] or ""
    return found


def pragmas(node: Any) -> list[str]:
    """The pragmas written before ``node`` (blark keeps them with its comments)."""
    comments = getattr(getattr(node, "meta", None), "comments", None) or []
    return [str(c) for c in comments if getattr(c, "type", "") == "PRAGMA"]


def sections(items: list[Any], where: Callable[[Any], str]) -> list[tuple[Any, GVL | None]]:
    """The VAR_GLOBAL blocks among a file's ``items``, each with the GVL it is a section of
    (None: an unnamed global block); a POU or a CONFIGURATION ends a GVL."""
    found: list[tuple[Any, GVL | None]] = []
    current: GVL | None = None
    for item in items:
        if isinstance(item, tf.GlobalVariableDeclarations):
            current = gvl_of(item, where(item), current)
            found.append((item, current))
        elif not isinstance(item, tf.DataTypeDeclaration):
            current = None
    return found


def gvl_of(block: Any, where: str, before: GVL | None = None) -> GVL | None:
    """The GVL a VAR_GLOBAL block is: the one its pragma names, else ``before`` (the GVL whose
    section it follows), else None (an unnamed global block).

    Raises:
        STError: ``qualified_only`` on a block without a name.
    """
    found = attributes(pragmas(block))
    name = found.get("gvl", "").strip()
    qualified = "qualified_only" in found
    if not name and before is not None:
        return before
    if not name and qualified:
        raise STError.at(
            where,
            "a qualified_only VAR_GLOBAL without a name",
            f"its name before it, {NAME_PRAGMA.format('GVL_Name')} (a TwinCAT GVL has its own)",
        )
    return GVL(name, qualified) if name else None

"""Names in an ST source as the translator resolves them (case-insensitively, as IEC):
variables of a POU and the globals (:class:`Scope`), and what the whole file declares
(:class:`Unit`: types, functions, blocks, the machine's axes a name may be bound to)."""

from __future__ import annotations

__all__ = ["Callable_", "Scope", "Unit", "Var"]

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from plc.st.errors import STError, nearest
from plc.st.runtime.io import Address, Channels, address, location_text
from plc.st.semantics.catalog import builtin_names, builtin_type, mcl_enums
from plc.st.semantics.gvl import GVL
from plc.st.semantics.types import BlockType, EnumType, Type


@dataclass
class Var:
    """A declared variable.

    Attributes:
        name: as declared.
        type: its data type.
        code: the Python expression that reads it (and is assigned to write it).
        section: ``input``, ``output``, ``in_out``, ``local``, ``temp``, ``global``.
        constant: its value when declared CONSTANT (inlined where it is read), else None.
        read_only: a CONSTANT ARRAY or STRUCT (a variable no statement may write).
    """

    name: str
    type: Type
    code: str
    section: str = "local"
    constant: Any = None
    read_only: bool = False


class Scope:
    """The variables of one POU, falling back to the globals."""

    def __init__(self, parent: Scope | None = None) -> None:
        self.vars: dict[str, Var] = {}
        self.parent = parent

    def add(self, var: Var, where: str) -> None:
        """Declare ``var``; a second declaration of a name is an error."""
        key = var.name.lower()
        if "__" in var.name:  # IEC 61131-3 2.1.2: no multiple embedded underscores
            raise STError.at(where, f"the name {var.name} has two underscores in a row", "one")
        if key in self.vars:
            raise STError.at(where, f"{var.name!r} is declared twice", "each name once")
        self.vars[key] = var

    def get(self, name: str) -> Var | None:
        """The variable ``name`` here or in the globals."""
        found = self.vars.get(name.lower())
        if found is None and self.parent is not None:
            return self.parent.get(name)
        return found

    def names(self) -> list[str]:
        """Every name visible here (for suggestions)."""
        own = [v.name for v in self.vars.values()]
        return own + (self.parent.names() if self.parent is not None else [])


@dataclass
class Callable_:
    """A user FUNCTION: its inputs in order with their defaults, its in-outs and outputs, its
    result type. The Python function takes the inputs, then the in-outs; it returns the
    result, or with in-outs or outputs the tuple (result, in-outs..., outputs...)."""

    name: str
    python: str
    inputs: list[tuple[str, Type, str]]
    """(name, type, default code) of each VAR_INPUT, in declaration order."""
    result: Type
    in_outs: list[tuple[str, Type]] = field(default_factory=list)
    """(name, type) of each VAR_IN_OUT, in declaration order."""
    outputs: list[tuple[str, Type]] = field(default_factory=list)
    """(name, type) of each VAR_OUTPUT, in declaration order."""
    order: list[str] = field(default_factory=list)
    """The names of the inputs, in-outs and outputs in declaration order (a call without
    names lists them so)."""


@dataclass
class Unit:
    """What one ST file declares, and the machine it is bound to.

    Attributes:
        filename: for messages (``file:line:column``).
        axes: the machine's axes by name (their Python access code ``_axes['X']``).
        mapping: ST name (``Pohon.Ax1``) → axis name.
    """

    filename: str
    axes: Mapping[str, str] = field(default_factory=dict)
    mapping: Mapping[str, str] = field(default_factory=dict)
    types: dict[str, Type] = field(default_factory=dict)
    initials: dict[str, Any] = field(default_factory=dict)
    """The initial value of each derived type that declares one (upper name → its value's
    node, :func:`plc.st.semantics.declarations.default_node`)."""
    functions: dict[str, Callable_] = field(default_factory=dict)
    globals: Scope = field(default_factory=Scope)
    bound: dict[str, str] = field(default_factory=dict)
    """The axes the program uses: Python name in ``_g`` → axis name."""
    channels: Channels = field(default_factory=dict)
    """The I/O counts of each axis (:func:`plc.st.runtime.io.channels`)."""
    reads: list[str] = field(default_factory=list)
    """Lines that read the located inputs of the globals when a scan begins."""
    writes: list[str] = field(default_factory=list)
    """Lines that write the located outputs of the globals when a scan ends."""
    gvls: dict[str, GVL] = field(default_factory=dict)
    """The named VAR_GLOBAL blocks by lower-case name (``GVL_Axes.X``)."""

    def qualified_only(self, name: str) -> list[str]:
        """``GVL.name`` of each qualified_only GVL that declares ``name``."""
        return [
            g.vars[name.lower()].name
            for g in self.gvls.values()
            if g.qualified_only and name.lower() in g.vars
        ]

    def where(self, node: Any) -> str:
        """``file:line:column`` of a tree node or token."""
        meta = getattr(node, "meta", None)
        line = getattr(meta, "line", None) or getattr(node, "line", None) or 1
        column = getattr(meta, "column", None) or getattr(node, "column", None) or 1
        return f"{self.filename}:{line}:{column}"

    def line(self, node: Any) -> int:
        """The source line of a node."""
        meta = getattr(node, "meta", None)
        return int(getattr(meta, "line", None) or getattr(node, "line", None) or 0)

    def type_named(self, name: str, node: Any) -> Type:
        """The type ``name``: the file's own, else a built-in one.

        Raises:
            STError: unknown, with the nearest valid names.
        """
        found = self.types.get(name.upper()) or builtin_type(name)
        if found is None:
            close = nearest(name, [*(t.name for t in self.types.values()), *builtin_names()])
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            if name.upper() == "MC_HOME":
                hint = (
                    ": the library homes with the step blocks MC_StepAbsSwitch then a Buffered "
                    "MC_StepRefPulse (or MC_StepBlock then MC_StepDirect); docs/st.md, Homing"
                )
            raise STError.at(
                self.where(node), f"unknown type {name!r}{hint}", "a data type or block type"
            )
        return found

    def block_named(self, name: str) -> BlockType | None:
        """A block type by name, or None."""
        found = self.types.get(name.upper()) or builtin_type(name)
        return found if isinstance(found, BlockType) else None

    def enum_value(self, name: str) -> tuple[EnumType, int] | None:
        """An unqualified enumeration value (the file's enums first, then mcl's)."""
        lower = name.lower()
        for t in [*self.types.values(), *mcl_enums().values()]:
            if isinstance(t, EnumType):
                value = t.by_lower_name.get(lower)
                if value is not None:
                    return t, value
        return None

    def enum_names(self) -> list[str]:
        """The values of the file's enumerations and of mcl's (for suggestions)."""
        types = [*self.types.values(), *mcl_enums().values()]
        return [n for t in types if isinstance(t, EnumType) for n in t.values]

    def axis(self, name: str) -> str | None:
        """The Python access code of the axis an ST name is bound to (the mapping first, then
        an axis of that name), or None; records it in :attr:`bound`."""
        target = next((a for k, a in self.mapping.items() if k.lower() == name.lower()), None)
        if target is None:
            target = next((a for a in self.axes if a.lower() == name.lower()), None)
        if target is None or target not in self.axes:
            return None
        return self.bind(target)

    def bind(self, axis: str) -> str:
        """The Python access code of axis ``axis`` (in ``_g``); records it in :attr:`bound`."""
        python = "ax_" + "".join(c if c.isalnum() else "_" for c in axis)
        self.bound[python] = axis
        return f"_g.{python}"

    def io_point(self, name: str, location: Any, where: str) -> Address | None:
        """The I/O point variable ``name`` is located at (``AT %IX0.2``, or the mapping names
        an address for it), or None.

        Raises:
            STError: an address the machine lacks.
        """
        if location is not None:
            text = location_text(location)
        else:
            text = next((a for k, a in self.mapping.items() if k.lower() == name.lower()), "")
            if not (text.startswith("%") or "." in text):
                return None
        point, problem = address(text, self.channels)
        if point is None:
            raise STError.at(where, f"{name} AT {text}: {problem}", "an I/O point of the machine")
        return point

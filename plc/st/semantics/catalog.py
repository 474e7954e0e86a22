"""What an ST program may name besides its own declarations: mcl's function blocks and
enumerations, the standard blocks, the elementary types; and the Python names the generated
code uses for ST identifiers."""

from __future__ import annotations

__all__ = [
    "ANY",
    "builtin_names",
    "builtin_type",
    "mcl_block",
    "mcl_blocks",
    "mcl_enums",
    "python_name",
    "standard_blocks",
]

import enum
import keyword
from functools import cache
from typing import Any

import mcl
from mcl import reference
from plc.st.runtime.blocks import STANDARD
from plc.st.semantics.types import (
    ANY_STRUCT,
    AXIS,
    BOOL,
    DINT,
    ELEMENTARY,
    GROUP,
    LREAL,
    SEQUENCE,
    STRING,
    BlockType,
    EnumType,
    Member,
    Type,
)

ANY = Type("ANY")
"""An mcl output of no elementary type (read as it is)."""

_PYTHON_TYPES: dict[str, Type] = {
    "bool": BOOL,
    "int": DINT,
    "float": LREAL,
    "str": STRING,
    "Axis": AXIS,
    "Axis | None": AXIS,
    "AxesGroup": GROUP,
    "Sequence[float]": SEQUENCE,
    "list": SEQUENCE,
    "TableRef": ANY_STRUCT,
    "MC_PATH_DATA_REF": ANY_STRUCT,
    "KinRef": ANY_STRUCT,
}


def python_name(name: str) -> str:
    """The Python identifier of an ST identifier (a Python keyword gets a trailing ``_``)."""
    return f"{name}_" if keyword.iskeyword(name) or keyword.issoftkeyword(name) else name


@cache
def _mcl_classes() -> dict[str, Any]:
    """mcl's function block classes by upper-case name (:func:`mcl.reference.function_blocks`)."""
    return {cls.__name__.upper(): cls for cls in reference.function_blocks()}


@cache
def _refs() -> frozenset[str]:
    """The names of every block's references (a compiled block shows them all as
    attributes)."""
    return frozenset(ref for cls in _mcl_classes().values() for ref in cls.REFS)


@cache
def mcl_block(upper: str) -> BlockType | None:
    """mcl's function block of upper-case name ``upper`` with its in-outs, inputs and
    outputs (made when a program first names it), or None."""
    cls = _mcl_classes().get(upper)
    if cls is None:
        return None
    members: dict[str, Member] = {}
    defaults = reference.declared_inputs(cls)
    for name, kind, _ in reference.inputs(cls):
        direction = "in_out" if name in cls.REFS else "input"
        t = _enumeration_of(name, defaults.get(name)) or _PYTHON_TYPES.get(kind, ANY)
        members[name.upper()] = Member(t, direction, name)
    for name, kind, _ in reference.outputs(cls):
        if name.upper() not in members and name not in _refs() and not name.isupper():
            members[name.upper()] = Member(_PYTHON_TYPES.get(kind, ANY), "output", name)
    return BlockType(cls.__name__, "mcl", members, cls.__name__)


def mcl_blocks() -> dict[str, BlockType]:
    """mcl's function blocks by upper-case name, with their in-outs, inputs and outputs."""
    return {upper: block for upper in _mcl_classes() if (block := mcl_block(upper)) is not None}


_ENUM_INPUTS = {
    "BufferMode": "MC_BUFFERMODE",
    "Direction": "MC_DIRECTION",
    "SwitchMode": "MC_SWITCHMODE",
    "ExecutionMode": "MC_EXECUTIONMODE",
    "StartMode": "MC_STARTMODE",
    "CircMode": "MC_CIRC_MODE",
    "PathChoice": "MC_CIRC_PATHCHOICE",
    "TransitionMode": "MC_TRANSITION_MODE",
    "CoordSystem": "MC_COORD_SYSTEM",
}
"""The enumeration of an integer input by its PLCopen name, where the initial value does not
say it (a compiled block stores an enumeration's value as a plain INT)."""


def _enumeration_of(name: str, default: object) -> EnumType | None:
    """The enumeration of an input whose initial value is a value of one of mcl's
    enumerations (``SwitchMode``: MC_SwitchMode), or an INT input of an enumeration's PLCopen
    name, else None."""
    if isinstance(default, enum.IntEnum):
        return mcl_enums().get(type(default).__name__.upper())
    if isinstance(default, int) and not isinstance(default, bool) and name in _ENUM_INPUTS:
        return mcl_enums().get(_ENUM_INPUTS[name])
    return None


@cache
def standard_blocks() -> dict[str, BlockType]:
    """The IEC standard function blocks by name."""
    return {
        name: BlockType(
            name,
            "std",
            {m: Member(ELEMENTARY[t], d, m) for m, (t, d) in members.items()},
            name,
        )
        for name, (_, members) in STANDARD.items()
    }


@cache
def mcl_enums() -> dict[str, EnumType]:
    """mcl's enumerations (MC_BufferMode, MC_Direction, MC_SwitchMode, MC_ExecutionMode, the
    group paths' MC_CIRC_MODE, MC_CIRC_PATHCHOICE, MC_TRANSITION_MODE, MC_COORD_SYSTEM, ...) by
    upper-case name."""
    found: dict[str, EnumType] = {}
    for name in (
        "MC_BufferMode",
        "MC_Direction",
        "MC_SwitchMode",
        "MC_ExecutionMode",
        "MC_StartMode",
        "CamLaw",
        "MC_CIRC_MODE",
        "MC_CIRC_PATHCHOICE",
        "MC_TRANSITION_MODE",
        "MC_COORD_SYSTEM",
    ):
        cls = getattr(mcl, name)
        if isinstance(cls, type) and issubclass(cls, enum.IntEnum):
            found[name.upper()] = EnumType(name, {m.name: int(m.value) for m in cls})
    return found


def builtin_type(name: str) -> Type | None:
    """An elementary type, AXIS_REF, an mcl enumeration or block, a standard block by name."""
    upper = name.upper()
    if upper in ELEMENTARY:
        return ELEMENTARY[upper]
    if upper == "AXIS_REF":
        return AXIS
    if upper in ("AXES_GROUP_REF", "AXESGROUP_REF"):
        return GROUP
    return mcl_enums().get(upper) or standard_blocks().get(upper) or mcl_block(upper)


def builtin_names() -> list[str]:
    """Every type name :func:`builtin_type` knows (for suggestions)."""
    return [
        *ELEMENTARY,
        "AXIS_REF",
        "AXES_GROUP_REF",
        *(t.name for t in mcl_enums().values()),
        *(t.name for t in standard_blocks().values()),
        *(cls.__name__ for cls in _mcl_classes().values()),
    ]

"""What an ST program may name besides its own declarations: mcl's function blocks and
enumerations, the standard blocks, the elementary types; and the Python names the generated
code uses for ST identifiers."""

from __future__ import annotations

import ast
import enum
import inspect
import keyword
from functools import cache

import mcl
from mcl import reference
from mcl.st.blocks import STANDARD
from mcl.st.types import (
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
    "AxesGroup": GROUP,
    "Sequence[float]": SEQUENCE,
}


def python_name(name: str) -> str:
    """The Python identifier of an ST identifier (a Python keyword gets a trailing ``_``)."""
    return f"{name}_" if keyword.iskeyword(name) or keyword.issoftkeyword(name) else name


@cache
def mcl_blocks() -> dict[str, BlockType]:
    """mcl's function blocks by upper-case name, with their in-outs, inputs and outputs."""
    blocks: dict[str, BlockType] = {}
    classes = reference.function_blocks()
    refs = {ref for cls in classes for ref in cls.REFS}
    for cls in classes:
        members: dict[str, Member] = {}
        for name, kind, _ in reference.inputs(cls):
            direction = "in_out" if name in cls.REFS else "input"
            kind = kind or _declared(cls, name)  # a compiled class keeps no annotations
            members[name.upper()] = Member(_PYTHON_TYPES.get(kind, ANY), direction, name)
        for name, kind in _outputs(cls, {*members, *(r.upper() for r in refs)}):
            members[name.upper()] = Member(_PYTHON_TYPES.get(kind, ANY), "output", name)
        blocks[cls.__name__.upper()] = BlockType(cls.__name__, "mcl", members, cls.__name__)
    return blocks


def _declared(cls: type, name: str) -> str:
    """The annotation of input ``name`` as the source declares it (the most derived class),
    read from the modules' sources: what ``reference.inputs`` gives in pure Python."""
    for klass in cls.__mro__:
        found = _source_annotations(klass.__module__, klass.__qualname__).get(name)
        if found is not None:
            return found
    return ""


@cache
def _source_annotations(module: str, qualname: str) -> dict[str, str]:
    """The annotated class attributes of class ``qualname`` in ``module``'s source file."""
    from mcl.native import ROOT

    source = ROOT.joinpath(*module.split(".")).with_suffix(".py")
    if not source.is_file():
        return {}
    tree = ast.parse(source.read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name == qualname:
            return {
                item.target.id: ast.unparse(item.annotation)
                for item in node.body
                if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name)
            }
    return {}


def _outputs(cls: type, taken: set[str]) -> list[tuple[str, str]]:
    """(name, Python type name) of the outputs of an mcl block: the public capitalised
    attributes of a fresh instance (not all capitals: constants) and properties that are not in
    ``taken`` (upper-case names). The same in both modes: a compiled class has no instance
    ``__dict__``, its attributes are descriptors of the class."""
    instance = cls()
    own = getattr(instance, "__dict__", None)
    found = []
    for name in dir(instance):
        if not name[:1].isupper() or name.isupper() or name.upper() in taken:
            continue
        static = inspect.getattr_static(cls, name, None)
        if inspect.isroutine(static) or isinstance(static, type):
            continue
        if own is not None and name not in own and not isinstance(static, property):
            continue  # a class constant of the pure-Python class
        if own is None and not hasattr(static, "__get__"):
            continue  # a class constant of the compiled class
        found.append((name, type(getattr(instance, name)).__name__))
    return found


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
    """mcl's enumerations (MC_BufferMode, MC_Direction, MC_SwitchMode) by upper-case name."""
    found: dict[str, EnumType] = {}
    for name in ("MC_BufferMode", "MC_Direction", "MC_SwitchMode"):
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
    return mcl_enums().get(upper) or standard_blocks().get(upper) or mcl_blocks().get(upper)


def builtin_names() -> list[str]:
    """Every type name :func:`builtin_type` knows (for suggestions)."""
    return [
        *ELEMENTARY,
        "AXIS_REF",
        "AXES_GROUP_REF",
        *(t.name for t in mcl_enums().values()),
        *(t.name for t in standard_blocks().values()),
        *(t.name for t in mcl_blocks().values()),
    ]

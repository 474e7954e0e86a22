"""Declarations in ST: TYPE (STRUCT, enumeration, subrange, ARRAY, alias), the type of a
variable declaration, and the Python code that gives a variable its initial value."""

from __future__ import annotations

__all__ = [
    "STErrorAt",
    "constant_of",
    "declare_type",
    "default",
    "enum_type",
    "initial",
    "spec_type",
]

from typing import Any

import blark.transform as tf

from plc.st.codegen.expressions import E, Expressions
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.catalog import python_name
from plc.st.semantics.scope import Scope, Unit
from plc.st.semantics.types import ArrayType, BlockType, Elementary, EnumType, StructType, Type


def constant_of(unit: Unit, node: Any, scope: Scope | None = None) -> E:
    """A constant expression (bounds, CASE labels, CONSTANT values)."""
    e = Expressions(unit, scope or unit.globals).expr(node)
    if not e.const:
        raise STErrorAt(unit, node, "a value that is not constant", "a constant expression")
    return e


def STErrorAt(unit: Unit, node: Any, problem: str, expected: str) -> Exception:
    """An STError at ``node``."""
    from plc.st.errors import STError

    return STError.at(unit.where(node), problem, expected)


def spec_type(unit: Unit, spec: Any, scope: Scope | None = None) -> Type:
    """The type a declaration names: ``INT``, ``STRING(20)``, ``ARRAY[..] OF ..``, a name."""
    if isinstance(spec, tf.TypeInitialization | tf.ArrayTypeInitialization):
        return spec_type(unit, spec.spec, scope)
    if isinstance(spec, tf.StringTypeInitialization | tf.StringTypeSpecification):
        inner = getattr(spec, "spec", spec)
        length = getattr(inner, "length", None)
        size = T.STRING.bits
        if length is not None:
            size = int(constant_of(unit, getattr(length, "length", length), scope).value)
        return T.string_of(size)
    if isinstance(spec, tf.SimpleSpecification):
        inner = spec.type
        if isinstance(inner, tf.StringTypeSpecification):
            return spec_type(unit, inner, scope)
        return unit.type_named(str(inner), spec)
    if isinstance(spec, tf.IndirectSimpleSpecification):
        return spec_type(unit, spec.type, scope)
    if isinstance(spec, tf.DataType):
        return unit.type_named(str(spec.type_name), spec)
    if isinstance(spec, tf.ArraySpecification):
        dims = []
        for sub in spec.subranges:
            if not isinstance(sub, tf.PartialSubrange):
                raise STErrorAt(unit, spec, "an ARRAY of open size", "bounds lo..hi")
            low = int(constant_of(unit, sub.start, scope).value)
            high = int(constant_of(unit, sub.stop, scope).value)
            if high < low:
                raise STErrorAt(unit, sub, f"bounds {low}..{high}", "lo <= hi")
            dims.append((low, high))
        element = spec_type(unit, spec.type, scope)
        shape = ", ".join(f"{lo}..{hi}" for lo, hi in dims)
        return ArrayType(f"ARRAY[{shape}] OF {element.name}", element, tuple(dims))
    if isinstance(spec, tf.EnumeratedTypeInitialization | tf.EnumeratedSpecification):
        inner = getattr(spec, "spec", spec)
        if inner.values:
            return enum_type(unit, "(enumeration)", inner)
        return unit.type_named(str(inner.type_name), spec)
    if isinstance(spec, tf.SubrangeTypeInitialization | tf.SubrangeSpecification):
        inner = getattr(spec, "spec", spec)
        return unit.type_named(str(inner.type_name), spec)
    if isinstance(spec, tf.InitializedStructure):
        return unit.type_named(str(spec.name), spec)
    if isinstance(spec, tf.FunctionBlockNameDeclaration | tf.FunctionBlockInvocationDeclaration):
        return unit.type_named(str(getattr(spec, "spec", spec)), spec)
    raise STErrorAt(unit, spec, f"the declaration {type(spec).__name__}", "a supported type")


def enum_type(unit: Unit, name: str, spec: tf.EnumeratedSpecification) -> EnumType:
    """An enumeration; values without ``:=`` count on from the previous one."""
    values: dict[str, int] = {}
    nxt = 0
    for v in spec.values:
        if v.value is not None:
            nxt = int(constant_of(unit, v.value).value)
        values[str(v.name)] = nxt
        nxt += 1
    base = spec.type_name
    base_type = unit.type_named(str(base), spec) if base is not None else T.ELEMENTARY["INT"]
    return EnumType(name, values, base_type if isinstance(base_type, Elementary) else T.DINT)


def declare_type(unit: Unit, decl: tf.DataTypeDeclaration) -> list[str]:
    """Register a TYPE declaration; the Python lines of a STRUCT's class."""
    d = decl.declaration
    name = str(d.name)
    if isinstance(d, tf.StructureTypeDeclaration):
        python = f"S_{name}"
        t = StructType(name, {}, python)
        unit.types[name.upper()] = t
        slots = _slots(unit, d, t)
        inits = dict(_field_inits(d))
        lines = [f"class {python}:", f"    __slots__ = {slots!r}", "", "    def __init__(self):"]
        for field_name, field_type in t.fields.items():
            body = initial(unit, f"self.{field_name}", field_type, inits.get(field_name))
            lines += [f"        {x}" for x in body]
        if not t.fields:
            lines.append("        pass")
        lines += ["", "    def _copy(self):", f"        c = {python}.__new__({python})"]
        lines += [f"        c.{f} = _f.clone(self.{f})" for f in t.fields]
        lines += ["        return c", "", ""]
        return lines
    if isinstance(d, tf.EnumeratedTypeDeclaration):
        unit.types[name.upper()] = enum_type(unit, name, d.init.spec)
    elif isinstance(
        d,
        (
            tf.SubrangeTypeDeclaration | tf.ArrayTypeDeclaration,
            tf.SimpleTypeDeclaration | tf.StringTypeDeclaration,
        ),
    ):
        unit.types[name.upper()] = spec_type(unit, d.init)
    else:
        raise STErrorAt(unit, d, f"TYPE {type(d).__name__}", "STRUCT, enumeration, ARRAY, alias")
    return []


def _slots(unit: Unit, d: tf.StructureTypeDeclaration, t: StructType) -> tuple[str, ...]:
    """Fill in the fields of ``t``; their Python names."""
    for element in d.declarations:
        field_type = spec_type(unit, element.init)
        for v in element.variables:
            t.fields[python_name(str(getattr(v.variable, "name", v)))] = field_type
    return tuple(t.fields)


def _field_inits(d: tf.StructureTypeDeclaration) -> list[tuple[str, Any]]:
    """The initial values given in a STRUCT declaration."""
    found = []
    for element in d.declarations:
        value = getattr(element.init, "value", None)
        if value is not None:
            for v in element.variables:
                found.append((python_name(str(getattr(v.variable, "name", v))), value))
    return found


def default(unit: Unit, t: Type) -> str:
    """Python code of a fresh value of type ``t``."""
    if isinstance(t, Elementary):
        return {"bool": "False", "real": "0.0", "string": "''"}.get(t.kind, "0")
    if isinstance(t, EnumType):
        return repr(next(iter(t.values.values()), 0))
    if isinstance(t, ArrayType):
        code = default(unit, t.element)
        for low, high in reversed(t.dims):
            code = f"[{code} for _ in range({high - low + 1})]"
        return code
    if isinstance(t, StructType):
        return f"{t.python}()"
    if isinstance(t, BlockType):
        if t.origin == "mcl":
            return f"_mcl.{t.python}()"
        if t.origin == "std":
            return f"_std.{t.python}(_clock)"
        if t.origin == "ext":
            return f"_ext[{t.name!r}]()"
        return f"{t.python}()"
    return "None"


def initial(unit: Unit, target: str, t: Type, value: Any, scope: Scope | None = None) -> list[str]:
    """Lines giving ``target`` its initial value (``value`` the declaration's, or None)."""
    if t is T.GROUP:
        return [_group(unit, target, value, scope)]
    lines = [f"{target} = {default(unit, t)}"]
    if value is None:
        return lines
    if isinstance(value, tf.ArrayInitialization):
        if not isinstance(t, ArrayType):
            raise STErrorAt(unit, value, "an array initial value", f"a {t.name} value")
        return lines + _array_init(unit, target, t, value, scope)
    if isinstance(value, tf.StructureInitialization) and isinstance(t, BlockType):
        return lines + _block_init(unit, target, t, value, scope)
    if isinstance(value, tf.StructureInitialization):
        if not isinstance(t, StructType):
            raise STErrorAt(unit, value, "a structure initial value", f"a {t.name} value")
        for element in value.elements:
            name = next((f for f in t.fields if f.lower() == str(element.name).lower()), None)
            if name is None:
                raise STErrorAt(unit, element, f"{t.name} has no field {element.name!r}", "a field")
            lines += initial(unit, f"{target}.{name}", t.fields[name], element.value, scope)
        return lines
    x = Expressions(unit, scope or unit.globals)
    e = x.expr(value)
    return [f"{target} = {x.convert(e, t, value)}", *lines[1:]]


def _block_init(
    unit: Unit, target: str, t: BlockType, value: tf.StructureInitialization, scope: Scope | None
) -> list[str]:
    """A block instance's initial inputs: ``home : HomeAxis := (SetPosition := 120.0);``."""
    lines: list[str] = []
    x = Expressions(unit, scope or unit.globals)
    for element in value.elements:
        member = t.members.get(str(element.name).upper())
        if member is None or member.direction != "input":
            inputs = [m.python for m in t.members.values() if m.direction == "input"]
            raise STErrorAt(
                unit, element, f"{t.name} has no input {element.name!r}", ", ".join(inputs)
            )
        e = x.expr(element.value)
        lines.append(f"{target}.{member.python} = {x.convert(e, member.type, element)}")
    return lines


def _group(unit: Unit, target: str, value: Any, scope: Scope | None) -> str:
    """An AXES_GROUP_REF variable declares its group: ``g : AXES_GROUP_REF;`` or, with the
    largest distance of a blended corner from the polyline [mm], ``g : AXES_GROUP_REF :=
    (CornerTolerance := 0.02);`` (``mcl.AxesGroup``)."""
    name = target.rpartition(".")[2]
    options = ""
    for element in getattr(value, "elements", None) or []:
        if str(element.name).lower() != "cornertolerance":
            raise STErrorAt(
                unit, element, f"AXES_GROUP_REF has no {element.name}", "CornerTolerance"
            )
        tolerance = Expressions(unit, scope or unit.globals).expr(element.value)
        numeric = isinstance(tolerance.type, Elementary) and tolerance.type.numeric
        if not (tolerance.const and numeric and tolerance.value > 0):
            raise STErrorAt(
                unit, element, f"CornerTolerance {tolerance.code}", "a constant > 0 [mm]"
            )
        options = f", corner_tolerance={float(tolerance.value)!r}"
    if value is not None and not hasattr(value, "elements"):
        raise STErrorAt(unit, value, "a value for an AXES_GROUP_REF", "(CornerTolerance := 0.02)")
    return f"{target} = _mcl.AxesGroup({name!r}{options})"


def _array_init(
    unit: Unit, target: str, t: ArrayType, value: tf.ArrayInitialization, scope: Scope | None
) -> list[str]:
    """``[1, 2, 3(7)]``: the elements in row-major order, the rest keep their default."""
    x = Expressions(unit, scope or unit.globals)
    flat: list[str] = []

    def walk(init: tf.ArrayInitialization) -> None:
        for element in init.elements:
            count = int(constant_of(unit, element.count).value) if element.count else 1
            for _ in range(count):
                if isinstance(element.element, tf.ArrayInitialization):
                    walk(element.element)
                else:
                    flat.append(x.convert(x.expr(element.element), t.element, element))

    walk(value)
    sizes = [high - low + 1 for low, high in t.dims]
    total = 1
    for s in sizes:
        total *= s
    if len(flat) > total:
        raise STErrorAt(unit, value, f"{len(flat)} initial values", f"at most {total}")
    lines = []
    for k, code in enumerate(flat):
        index, rest = [], k
        for s in reversed(sizes):
            index.append(rest % s)
            rest //= s
        lines.append(f"{target}{''.join(f'[{i}]' for i in reversed(index))} = {code}")
    return lines

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

import math
from dataclasses import dataclass
from typing import Any

import blark.transform as tf

from plc.st.codegen.expressions import E, Expressions
from plc.st.errors import indefinite, nearest
from plc.st.frontend.grammar import RefTo
from plc.st.runtime import functions as F  # noqa: N812
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


def folded(unit: Unit, t: Type, value: Any, spec: Any, scope: Scope | None = None) -> Any:
    """The value of a CONSTANT of elementary or enumeration type ``t`` (``value`` its initial
    value's node or None), as ``t`` holds it; None for a CONSTANT of another type (an ARRAY or
    STRUCT: a variable that no statement may write)."""
    if not isinstance(t, Elementary | EnumType):
        return None
    if value is None:
        value = default_node(unit, spec)
    x = Expressions(unit, scope or unit.globals)
    if value is None:
        return eval(default(unit, t))
    e = x.expr_as(value, t)
    if not e.const:
        raise STErrorAt(unit, value, "a value that is not constant", "a constant expression")
    return eval(x.convert(e, t, value), {"_f": F, "_m": math})


def STErrorAt(unit: Unit, node: Any, problem: str, expected: str) -> Exception:
    """An STError at ``node``."""
    from plc.st.errors import STError

    return STError.at(unit.where(node), problem, expected)


def spec_type(unit: Unit, spec: Any, scope: Scope | None = None) -> Type:
    """The type a declaration names: ``INT``, ``STRING(20)``, ``ARRAY[..] OF ..``, a name,
    ``REF_TO`` one of them."""
    t = _named_type(unit, spec, scope)
    indirection = getattr(spec, "indirection", None)
    if indirection is None or not indirection.is_indirect:
        return t
    if not isinstance(indirection, RefTo):
        raise STErrorAt(unit, spec, f"{indirection} (a vendor's pointer)", "REF_TO (IEC 3rd ed.)")
    return T.ReferenceType(f"REF_TO {t.name}", t)


def _named_type(unit: Unit, spec: Any, scope: Scope | None) -> Type:
    """The type of ``spec`` itself (its REF_TO aside)."""
    if isinstance(spec, tf.TypeInitialization | tf.ArrayTypeInitialization):
        return spec_type(unit, spec.spec, scope)
    if isinstance(spec, tf.StringTypeInitialization | tf.StringTypeSpecification):
        inner = getattr(spec, "spec", spec)
        length = getattr(inner, "length", None)
        size = T.STRING.bits
        if length is not None:
            size = _length(unit, getattr(length, "length", length), scope)
        return T.string_of(size)
    if isinstance(spec, tf.SimpleSpecification):
        inner = spec.type
        if isinstance(inner, tf.StringTypeSpecification):
            return spec_type(unit, inner, scope)
        return unit.type_named(str(inner), spec)
    if isinstance(spec, tf.IndirectSimpleSpecification):
        t = spec_type(unit, spec.type, scope)
        arguments = spec.init_parameters or []
        if not arguments:
            return t
        if t.kind == "string" and len(arguments) == 1 and arguments[0].name is None:
            return T.string_of(_length(unit, arguments[0].value, scope))  # STRING(100) as a call
        raise STErrorAt(unit, spec, f"the type {spec}", "a data type")
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
        if inner.values:  # an inline enumeration: its values name themselves, as a TYPE's
            t = enum_type(unit, f"({', '.join(str(v.name) for v in inner.values)})", inner)
            unit.types.setdefault(t.name.upper(), t)
            return unit.types[t.name.upper()]
        return unit.type_named(str(inner.type_name), spec)
    if isinstance(spec, tf.SubrangeTypeInitialization | tf.SubrangeSpecification):
        inner = getattr(spec, "spec", spec)
        t = unit.type_named(str(inner.type_name), spec)
        if isinstance(inner.subrange, tf.PartialSubrange):
            return _subrange(unit, t, inner.subrange, scope)
        return t
    if isinstance(spec, tf.InitializedStructure):
        return unit.type_named(str(spec.name), spec)
    if isinstance(spec, tf.FunctionBlockNameDeclaration | tf.FunctionBlockInvocationDeclaration):
        return unit.type_named(str(getattr(spec, "spec", spec)), spec)
    raise STErrorAt(unit, spec, f"the declaration {type(spec).__name__}", "a supported type")


def _subrange(unit: Unit, t: Type, sub: tf.PartialSubrange, scope: Scope | None) -> Type:
    """``INT (low..high)``: bounds within the integer type, ``low <= high``."""
    low = constant_of(unit, sub.start, scope).value
    high = constant_of(unit, sub.stop, scope).value
    if not (isinstance(t, Elementary) and t.base == "int" and not isinstance(t, T.Subrange)):
        raise STErrorAt(unit, sub, f"a subrange of {t.name}", "an integer type (INT (1..10))")
    if not (isinstance(low, int) and isinstance(high, int)) or not (
        T.wrap_value(low, t) == low <= high == T.wrap_value(high, t)
    ):
        raise STErrorAt(unit, sub, f"the subrange {low}..{high} of {t.name}", "low <= high")
    name = f"{t.name} ({low}..{high})"
    return T.Subrange(name, t.base, t.bits, t.signed, low, high, t.name)


def _length(unit: Unit, node: Any, scope: Scope | None) -> int:
    """A STRING's length, ``(n)`` or ``[n]``: a constant > 0."""
    if isinstance(node, tf.BracketedExpression):
        node = node.expression
    length = constant_of(unit, node, scope)
    if not (isinstance(length.value, int) and length.value > 0) or isinstance(length.value, bool):
        raise STErrorAt(unit, node, f"a STRING of length {length.code}", "a length > 0")
    return length.value


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
        inits = dict(_field_inits(unit, d))
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
    spec = getattr(d, "init", None) or getattr(d, "string_type", None)
    if isinstance(d, tf.EnumeratedTypeDeclaration) and d.init.spec.values:
        unit.types[name.upper()] = enum_type(unit, name, d.init.spec)
    elif isinstance(
        d,
        (
            tf.SubrangeTypeDeclaration | tf.ArrayTypeDeclaration | tf.EnumeratedTypeDeclaration,
            tf.SimpleTypeDeclaration | tf.StringTypeDeclaration,
        ),
    ):
        unit.types[name.upper()] = spec_type(unit, spec)
    else:
        raise STErrorAt(unit, d, f"TYPE {type(d).__name__}", "STRUCT, enumeration, ARRAY, alias")
    value = d.value if isinstance(d, tf.StringTypeDeclaration) else getattr(spec, "value", None)
    found = value if value is not None else default_node(unit, spec)
    if found is not None:  # a variable of the type starts there (IEC 2.3.3.2)
        initial(unit, "_", unit.types[name.upper()], found)  # checked where it is declared
        unit.initials[name.upper()] = found
    return []


@dataclass(frozen=True)
class Fill:
    """An array whose every element starts at ``element`` (its type's initial value)."""

    element: Any


def default_node(unit: Unit, spec: Any) -> Any:
    """The initial value a declaration without ``:=`` takes from its type (IEC 61131-3 2.4.2,
    2.3.3.2; 3rd ed. 6.4.4): a derived type's declared value, a subrange's lower limit, an array
    of such elements (a :class:`Fill`); None: the type's default (0, FALSE, '', the first
    value of an enumeration)."""
    if isinstance(spec, tf.TypeInitialization | tf.ArrayTypeInitialization):
        return None if getattr(spec, "indirection", None) else default_node(unit, spec.spec)
    if isinstance(spec, tf.IndirectSimpleSpecification):
        return None if spec.indirection else default_node(unit, spec.type)
    if isinstance(spec, tf.SimpleSpecification | tf.DataType):
        name = spec.type if isinstance(spec, tf.SimpleSpecification) else spec.type_name
        return unit.initials.get(str(name).upper()) if isinstance(name, str) else None
    if isinstance(spec, tf.SubrangeTypeInitialization | tf.SubrangeSpecification):
        inner = getattr(spec, "spec", spec)
        if isinstance(inner.subrange, tf.PartialSubrange):
            return inner.subrange.start
        return unit.initials.get(str(inner.type_name).upper())
    if isinstance(spec, tf.EnumeratedTypeInitialization | tf.EnumeratedSpecification):
        inner = getattr(spec, "spec", spec)
        return None if inner.values else unit.initials.get(str(inner.type_name).upper())
    if isinstance(spec, tf.ArraySpecification):
        element = default_node(unit, spec.type)
        return Fill(element) if element is not None else None
    return None


def _slots(unit: Unit, d: tf.StructureTypeDeclaration, t: StructType) -> tuple[str, ...]:
    """Fill in the fields of ``t``; their Python names."""
    for element in d.declarations:
        field_type = spec_type(unit, element.init)
        for v in element.variables:
            t.fields[python_name(str(getattr(v.variable, "name", v)))] = field_type
    return tuple(t.fields)


def _field_inits(unit: Unit, d: tf.StructureTypeDeclaration) -> list[tuple[str, Any]]:
    """The initial values of a STRUCT's fields: given in its declaration, else their types'."""
    found = []
    for element in d.declarations:
        init = element.init
        value = init.init if isinstance(init, tf.InitializedStructure) else None
        value = getattr(init, "value", None) if value is None else value
        if value is None:
            value = default_node(unit, element.init)
        if value is not None:
            for v in element.variables:
                found.append((python_name(str(getattr(v.variable, "name", v))), value))
    return found


def default(unit: Unit, t: Type) -> str:
    """Python code of a fresh value of type ``t``."""
    if isinstance(t, Elementary):
        if t.kind in ("date", "dt"):  # D#0001-01-01 (IEC 61131-3 2.4.2, Table 13)
            return repr(F.FIRST_DAY)
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
    if isinstance(t, T.ReferenceType):
        return "_f.NULL"
    if isinstance(t, BlockType):
        if t.origin == "mcl":
            return f"_mcl.{t.python}()"
        if t.origin == "std":
            return f"_std.{t.python}(_clock)"
        if t.origin == "ext":
            return f"_ext[{t.name!r}]()"
        return f"{t.python}()"
    return "None"


def initial(
    unit: Unit, target: str, t: Type, value: Any, scope: Scope | None = None, spec: Any = None
) -> list[str]:
    """Lines giving ``target`` its initial value: ``value`` the declaration's, or None (then
    the one its type ``spec`` declares, else the type's default)."""
    if t is T.GROUP:
        return [_group(unit, target, value, scope)]
    if value is None and spec is not None:
        value = default_node(unit, spec)
    lines = [f"{target} = {default(unit, t)}"]
    if value is None:
        return lines
    if isinstance(value, tf.ArrayInitialization | Fill):
        if not isinstance(t, ArrayType):
            raise STErrorAt(unit, value, "an array initial value", f"{indefinite(t.name)} value")
        return _array_init(unit, target, t, value, scope, lines)
    if isinstance(value, tf.StructureInitialization) and isinstance(t, BlockType):
        return lines + _block_init(unit, target, t, value, scope)
    if isinstance(value, tf.StructureInitialization):
        if not isinstance(t, StructType):
            raise STErrorAt(unit, value, "a structure initial value", f"{indefinite(t.name)} value")
        for element in value.elements:
            name = next((f for f in t.fields if f.lower() == str(element.name).lower()), None)
            if name is None:
                close = nearest(str(element.name), t.fields)
                hint = f" (did you mean {', '.join(close)}?)" if close else ""
                raise STErrorAt(
                    unit, element, f"{t.name} has no field '{element.name}'{hint}", "a field"
                )
            lines += initial(unit, f"{target}.{name}", t.fields[name], element.value, scope)
        return lines
    x = Expressions(unit, scope or unit.globals)
    e = x.expr_as(value, t)
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
    unit: Unit,
    target: str,
    t: ArrayType,
    value: tf.ArrayInitialization | Fill,
    scope: Scope | None,
    lines: list[str],
) -> list[str]:
    """``[1, 2, 3(7)]``: the elements in row-major order, the rest keep their default
    (``lines``); a :class:`Fill` gives every element one value."""
    sizes = [high - low + 1 for low, high in t.dims]
    total = 1
    for s in sizes:
        total *= s
    if isinstance(value, Fill):
        one = initial(unit, "_", t.element, value.element, scope)
        if len(one) == 1:  # an elementary value: the same one in every element
            code = one[0].split(" = ", 1)[1]
            for size in reversed(sizes):
                code = f"[{code} for _ in range({size})]"
            return [f"{target} = {code}"]
        flat = [value.element] * total
    else:
        flat = []
        _flatten(unit, value, flat)
    if len(flat) > total:
        raise STErrorAt(unit, value, f"{len(flat)} initial values", f"at most {total}")
    for k, node in enumerate(flat):
        index, rest = [], k
        for s in reversed(sizes):
            index.append(rest % s)
            rest //= s
        element = f"{target}{''.join(f'[{i}]' for i in reversed(index))}"
        lines += initial(unit, element, t.element, node, scope)
    return lines


def _flatten(unit: Unit, init: tf.ArrayInitialization, flat: list[Any]) -> None:
    """The element nodes of an array initial value in row-major order, repetitions
    ``3(7)`` and nested brackets opened."""
    for element in init.elements:
        count = int(constant_of(unit, element.count).value) if element.count else 1
        for _ in range(count):
            if isinstance(element.element, tf.ArrayInitialization):
                _flatten(unit, element.element, flat)
            else:
                flat.append(element.element)

"""Arithmetic with IEC types (``+ - * / MOD **`` on integers, reals and TIME) and the implicit
conversion of a value stored into a variable (:func:`coerce`).

Integers are exact within an expression up to 32 bits (as the 32-bit registers of CODESYS and
TwinCAT targets), wider results wrap to their type; a store wraps to the target's width. A REAL
operation rounds its result to 32 bits, so REAL arithmetic is IEEE single precision.
"""

from __future__ import annotations

__all__ = ["arithmetic", "coerce", "duration_advice", "result_type"]

from typing import TYPE_CHECKING, Any

from plc.st.errors import indefinite
from plc.st.runtime import functions as F  # noqa: N812
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import Elementary, Type

if TYPE_CHECKING:
    from plc.st.codegen.expressions import E, Expressions


def _fold(op: str, a: Any, b: Any, integral: bool) -> Any:
    """``a op b`` of constants, IEC semantics."""
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        return F.div(a, b) if integral else F.fdiv(a, b)
    if op == "MOD":
        return F.mod(a, b)
    return F.expt(a, b)


def result_type(x: Expressions, node: Any, op: str, a: E, b: E) -> Elementary:
    """The type of ``a op b``, or a type error."""
    ta, tb = T.plain(a.type), T.plain(b.type)
    if not (isinstance(ta, Elementary) and isinstance(tb, Elementary)):
        raise x.error(node, f"{ta.name} {op} {tb.name}", "numbers")
    if op == "**":
        if ta.numeric and tb.numeric:
            return T.REAL if ta is T.REAL else T.LREAL
    elif {ta.kind, tb.kind} & {"date", "tod", "dt"}:
        from plc.st.codegen.dates import result_type as date_result

        found = date_result(op, ta, tb)
        if found is not None:
            return found
    elif ta.kind == "time" or tb.kind == "time":
        if ta.kind == tb.kind == "time" and op in "+-":
            return ta if ta is not T.TIME else tb
        if ta.kind == "time" and tb.numeric and op in ("*", "/"):
            return ta
        if tb.kind == "time" and ta.numeric and op == "*":
            return tb
    elif op == "+" and ta.kind == tb.kind == "string":
        raise x.error(node, "STRING + STRING", "CONCAT(a, b)")
    elif ta.numeric and tb.numeric:
        if op == "MOD" and not (ta.integral and tb.integral):
            raise x.error(node, f"{ta.name} MOD {tb.name}", "integer operands")
        if ta.kind == "real" or tb.kind == "real":
            return T.real_of(ta, tb)
        return T.wider(ta, tb)
    mixed = time_and_integer(op, a, b)
    if mixed:
        raise x.error(node, mixed)
    raise x.error(node, f"{ta.name} {op} {tb.name}", "numeric operands")


def time_and_integer(op: str, a: E, b: E) -> str:
    """The message of ``a op b`` where one is a TIME and the other an integer literal
    (``TIME > the integer 500: write a duration literal: T#500MS``), else ""."""
    for e, other, problem in (
        (a, b, f"the integer {a.value} {op} {b.type.name}"),
        (b, a, f"{a.type.name} {op} the integer {b.value}"),
    ):
        advice = duration_advice(e, T.plain(other.type))
        if advice:
            return f"{problem}: {advice}"
    return ""


def duration_advice(e: E, to: Type) -> str:
    """What to write for ``e`` where a TIME or LTIME (``to``) is expected, if ``e`` is an
    integer literal (IEC converts no integer to a TIME implicitly: ``T#20S`` for ``20000``,
    the integer read as ms); else ""."""
    if to.kind != "time" or e.type is not T.ANY_INT or not e.const:
        return ""
    return "write a duration literal: " + _duration(int(e.value), to)


def _duration(value: int, to: Type) -> str:
    """The duration literal of ``value`` ms in seconds (and in ms), ``T#1.5S (or T#1500MS)``;
    under a second in ms."""
    prefix = "T#" if to is T.TIME else f"{to.name}#"
    in_ms = f"{prefix}{value}MS"
    if abs(value) < 1000:
        return in_ms
    whole, part = divmod(abs(value), 1000)
    seconds = f"{'-' * (value < 0)}{whole}" + (f".{part:03d}".rstrip("0") if part else "")
    return f"{prefix}{seconds}S (or {in_ms})"


def arithmetic(x: Expressions, node: Any, op: str, a: E, b: E) -> E:
    """``a op b`` translated."""
    from plc.st.codegen.expressions import E, const

    t = result_type(x, node, op, a, b)
    integral = t.integral or t.kind in ("time", "date", "tod", "dt")
    if a.const and b.const:
        try:
            value = _fold(op, a.value, b.value, integral and op != "**")
        except F.STFault as fault:
            raise x.error(node, str(fault), "a divisor other than 0") from None
        if t is T.TOD:
            value %= F.DAY
        elif not t.integral and integral:
            value = int(value)
        elif integral:
            value = T.wrap_value(value, t)
        return const(x.round_real(float(value), t) if t.kind == "real" else value, t)
    ca, cb = a.code, b.code
    if op == "**":
        code = f"_f.expt({ca}, {cb})"
    elif op == "MOD":
        code = f"_f.mod({ca}, {cb})"
    elif op == "/":
        if integral:
            code = f"_f.div({ca}, {cb})"
            if t.kind == "time" and b.type.kind == "real":
                code = f"_f.to_int(_f.fdiv({ca}, {cb}))"
        else:
            code = f"_f.fdiv({ca}, {cb})"
    else:
        code = f"({ca} {op} {cb})"
        if t.kind == "time" and "real" in (a.type.kind, b.type.kind):
            code = f"_f.to_int{code}"
        elif t is T.TOD:
            code = f"({code} % {F.DAY})"
    if t is T.REAL:
        code = f"_f.f32({code})"
    elif t.integral and t.bits >= 32 and op in "+-*":
        code = T.wrap_code(code, t)
    elif t.integral and op in ("+", "-", "*"):
        return E(code, t, wide=True)
    return E(code, t)


def coerce(x: Expressions, e: E, to: Type, node: Any) -> str:
    """Python code of ``e`` stored into a variable of type ``to``."""
    src = e.type
    if src == to and isinstance(to, Elementary) and to.kind != "string" and not e.wide:
        return e.code
    if isinstance(to, T.Subrange):
        return _within(x, e, to, coerce(x, e, to.parent, node), node)
    if isinstance(to, Elementary) and isinstance(src, Elementary):
        code = _elementary(x, e, src, to, node)
        if code is not None:
            return code
    elif to.kind == src.kind and to.kind in ("axis", "group", "block"):
        return e.code
    elif isinstance(to, T.ArrayType) and src is T.SEQUENCE:
        if len(to.dims) == 1 and to.element is T.LREAL:  # a group block's per-axis values
            low, high = to.dims[0]
            return f"_f.reals({e.code}, {high - low + 1})"
    elif isinstance(to, T.ArrayType) and isinstance(src, T.ArrayType):
        if _shape(to) == _shape(src):
            return f"_f.clone({e.code})"
    elif isinstance(to, T.EnumType) and isinstance(src, T.EnumType) and to.name == src.name:
        return e.code
    elif isinstance(to, T.ReferenceType) and isinstance(src, T.ReferenceType):
        if src is T.NULL or _same_target(to, src):
            return e.code
    elif to is T.ANY_STRUCT and src.kind == "struct":
        return e.code  # a profile table: the block reads it on its rising edge
    elif to.kind == "struct" and src.name == to.name:
        return f"_f.clone({e.code})"
    elif to.kind in ("int",) and src.kind == "enum":
        return e.code
    literal = duration_advice(e, to)
    if literal:
        raise x.error(node, f"the integer {e.value} where {to.name} is expected: {literal}")
    raise x.error(
        node, f"{indefinite(src.name)} value where {to.name} is expected: {advice(src, to)}"
    )


def advice(src: Type, to: Type) -> str:
    """What turns a value of ``src`` into one of ``to``: the standard conversion function
    (``TO_INT`` for a literal), or that none exists."""
    if isinstance(src, Elementary) and isinstance(to, Elementary) and _converts(src, to):
        into = _plain_name(to)
        name = f"TO_{into}" if src.name.startswith("ANY_") else f"{_plain_name(src)}_TO_{into}"
        rounds = " (it rounds to the nearest integer)" if src.kind == "real" else ""
        return f"convert it with {name}(...){rounds if to.integral else ''}"
    if isinstance(to, T.EnumType):
        return f"no conversion makes {indefinite(to.name)}: write one of its values, {_values(to)}"
    return f"no conversion makes {indefinite(to.name)} of it"


def _converts(src: Elementary, to: Elementary) -> bool:
    """``SRC_TO_DST`` exists (:func:`plc.st.codegen.standard.conversion`)."""
    from plc.st.codegen.dates import conversion as date_conversion
    from plc.st.codegen.expressions import E

    if {src.kind, to.kind} & {"date", "tod", "dt"}:
        return date_conversion(None, None, E("v", src), to) is not None  # type: ignore[arg-type]
    return {src.kind, to.kind} <= {"int", "bits", "real", "bool", "time", "string"}


def _plain_name(t: Elementary) -> str:
    """An elementary type's name without its length (``STRING`` of ``STRING(25)``)."""
    return t.name.split("(")[0].strip()


def _values(t: T.EnumType) -> str:
    """The first values of an enumeration, qualified."""
    names = [f"{t.name}.{n}" for n in t.values]
    return ", ".join(names[:3]) + (", ..." if len(names) > 3 else "")


def _elementary(x: Expressions, e: E, src: Elementary, to: Elementary, node: Any) -> str | None:
    """The conversion between elementary types, or None where IEC allows none."""
    if to.integral and src.integral:
        if e.const:
            return repr(T.wrap_value(e.value, to))
        fits = src.bits and src.bits <= to.bits and (src.signed == to.signed or not src.signed)
        if not e.wide and ((fits and src.bits < to.bits) or src == to):
            return e.code
        return T.wrap_code(e.code, to)
    if to.kind == "real" and (src.integral or src.kind == "real"):
        if e.const:
            from plc.st.codegen.expressions import literal_code

            return literal_code(x.round_real(float(e.value), to))
        if to is T.REAL and src is not T.REAL:
            return f"_f.f32({e.code})"
        return e.code if src.kind == "real" else f"float({e.code})"
    if to.kind == src.kind and to.kind in ("time", "date", "tod", "dt"):
        return e.code
    if to.kind == src.kind == "bool":
        return e.code
    if to.kind == src.kind == "string":
        if e.const:
            return repr(e.value[: to.bits])
        return e.code if src.bits <= to.bits else f"{e.code}[:{to.bits}]"
    return None


def _within(x: Expressions, e: E, to: T.Subrange, code: str, node: Any) -> str:
    """``code`` (``e`` as the subrange's integer type) checked against the subrange: a
    constant outside is an error, a value at run time a fault (IEC 61131-3 2.3.3.1)."""
    if e.const:
        if not to.low <= T.wrap_value(int(e.value), to.parent) <= to.high:
            raise x.error(node, f"{e.value} outside {to.name}", f"{to.low}..{to.high}")
        return code
    src = e.type
    if isinstance(src, T.Subrange) and to.low <= src.low and src.high <= to.high and not e.wide:
        return code
    return f"_f.within({code}, {to.low}, {to.high})"


def _same_target(a: T.ReferenceType, b: T.ReferenceType) -> bool:
    """Two REF_TO types refer to the same type (arrays: the same bounds and elements)."""
    ta, tb = a.target, b.target
    if isinstance(ta, T.ArrayType) and isinstance(tb, T.ArrayType):
        return _shape(ta) == _shape(tb)
    return ta == tb


def _shape(t: T.ArrayType) -> tuple[Any, ...]:
    """What two arrays must share to be assigned: the bounds and the element type."""
    return (t.dims, t.element.name)

"""The standard functions with a fixed signature (LIMIT, SEL, shifts, string functions, EXPT,
TRUNC, MOVE) and the type conversions ``*_TO_*``, translated to Python."""

from __future__ import annotations

__all__ = ["conversion", "standard"]

from typing import TYPE_CHECKING, Any

from plc.st.errors import indefinite
from plc.st.runtime import functions as F  # noqa: N812
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import Elementary

if TYPE_CHECKING:
    from plc.st.codegen.expressions import E, Expressions

_STRING_RESULT = {"LEFT", "RIGHT", "MID", "INSERT", "DELETE", "REPLACE"}


def standard(x: Expressions, node: Any, upper: str, args: list[E]) -> E:
    """A standard function call ``upper(args)`` (arguments in the IEC order)."""
    from plc.st.codegen.expressions import E, const

    codes = [a.code for a in args]
    if upper == "LIMIT":
        t = x.calls.common(node, args)
        code = f"_f.limit({', '.join(codes)})"
    elif upper == "SEL":
        _kind(x, node, args[0], "bool", upper)
        t = x.calls.common(node, args[1:])
        code = f"({codes[2]} if {codes[0]} else {codes[1]})"
    elif upper in ("SHL", "SHR", "ROL", "ROR"):
        t = args[0].type
        if not (isinstance(t, Elementary) and t.integral and t.bits):
            raise x.error(node, f"{upper} of {t.name}", "a bit string (BYTE, WORD, DWORD, LWORD)")
        code = f"_f.{upper.lower()}({codes[0]}, {codes[1]}, {t.bits})"
    elif upper == "LEN":
        _kind(x, node, args[0], "string", upper)
        t, code = T.ELEMENTARY["INT"], f"len({codes[0]})"
    elif upper == "FIND":
        t, code = T.ELEMENTARY["INT"], f"_f.find({codes[0]}, {codes[1]})"
    elif upper in _STRING_RESULT:
        _kind(x, node, args[0], "string", upper)
        t, code = T.STRING, f"_f.{upper.lower()}({', '.join(codes)})"
    elif upper == "EXPT":
        t = T.REAL if args[0].type is T.REAL else T.LREAL
        code = f"_f.expt({codes[0]}, {codes[1]})"
        code = f"_f.f32({code})" if t is T.REAL else code
    elif upper == "TRUNC":
        _kind(x, node, args[0], "real", upper)
        t, code = T.DINT, T.wrap_code(f"_f.trunc({codes[0]})", T.DINT)
    else:  # MOVE
        t, code = args[0].type, codes[0]
    if all(a.const for a in args):
        return const(eval(code, {"_f": F, "len": len}), t)
    return E(code, t)


def _kind(x: Expressions, node: Any, arg: E, kind: str, function: str) -> None:
    """The argument of ``function`` must be of ``kind``."""
    if arg.type.kind != kind:
        raise x.error(node, f"{function} of {indefinite(arg.type.name)}", kind.upper())


def conversion(x: Expressions, node: Any, arg: E, to: Elementary) -> E:
    """``arg`` converted to ``to`` (explicitly: every mix of elementary types has a rule)."""
    from plc.st.codegen.expressions import E, const

    src = arg.type
    c = arg.code
    if not isinstance(src, Elementary):
        if src.kind == "enum" and to.integral:
            return E(c, to)
        raise x.error(node, f"{indefinite(src.name)} converted to {to.name}", "an elementary value")
    kind = src.kind
    if {kind, to.kind} & {"date", "tod", "dt"}:
        from plc.st.codegen.dates import conversion as date_conversion

        found = date_conversion(x, node, arg, to)
        if found is None:
            raise x.error(
                node, f"{indefinite(src.name)} converted to {to.name}", "DT_TO_DATE, DT_TO_TOD"
            )
        return const(eval(found, {"_f": F}), to) if arg.const else E(found, to)
    if to.integral:
        if kind == "real":
            code = T.wrap_code(f"_f.to_int({c})", to)
        elif kind == "bool":
            code = f"int({c})"
        elif kind == "string":
            code = T.wrap_code(f"_f.to_number({c}, True)", to)
        else:
            code = T.wrap_code(c, to)
    elif to.kind == "real":
        code = f"_f.to_number({c}, False)" if kind == "string" else f"float({c})"
        code = f"_f.f32({code})" if to is T.REAL else code
    elif to.kind == "bool":
        code = f"({c} != '')" if kind == "string" else f"bool({c})"
    elif to.kind == "time":
        code = f"_f.to_int({c})" if kind == "real" else f"int({c})"
        if kind == "time" and src is not to:
            code = f"({c} * 1000000)" if to is T.LTIME else f"({c} // 1000000)"
    elif to.kind == "string":
        code = {
            "real": f"_f.real_text({c}, True)" if src is T.REAL else f"_f.real_text({c})",
            "bool": f"('TRUE' if {c} else 'FALSE')",
            "time": f"_f.time_text({c})",
            "string": c,
        }.get(kind, f"str({c})")
    else:
        raise x.error(node, f"{indefinite(src.name)} converted to {to.name}", "an elementary type")
    if arg.const:
        return const(eval(code, {"_f": F}), to)
    return E(code, to)

"""The standard functions that are operators called by name (IEC 61131-3 2.5.1.5.2-4, 3rd ed.
6.6.2.5.8-12): ``ADD(1, 2, 3)``, ``SUB``, ``MUL``, ``DIV``, ``MOD``, ``EXPT``, ``AND``, ``OR``,
``XOR``, ``GT``, ``GE``, ``EQ``, ``LE``, ``LT``, ``NE``; their typed forms ``ADD_INT``
(2.5.1.4, Table 21); the functions of time data types (2.5.1.5.6, 3rd ed. 6.6.2.5.14):
``ADD_TIME``, ``ADD_TOD_TIME``, ``SUB_DT_DT``, ``MULTIME``, ``CONCAT_DATE_TOD``, ...; and the
typed truncation ``TRUNC_INT`` (3rd ed. 6.6.2.5.2)."""

from __future__ import annotations

__all__ = ["OPERATORS", "names", "operator_call"]

import itertools
import re
from typing import TYPE_CHECKING, Any

from plc.st.errors import indefinite
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import ELEMENTARY, Elementary

if TYPE_CHECKING:
    from plc.st.codegen.expressions import E, Expressions

OPERATORS = {"ADD": "+", "SUB": "-", "MUL": "*", "DIV": "/", "MOD": "MOD", "EXPT": "**"}
OPERATORS |= {"AND": "AND", "OR": "OR", "XOR": "XOR"}
OPERATORS |= {"GT": ">", "GE": ">=", "EQ": "=", "LE": "<=", "LT": "<", "NE": "<>"}
"""Each function named like an operator: the operator."""

_EXTENSIBLE = {"ADD", "MUL", "AND", "OR", "XOR", "GT", "GE", "EQ", "LE", "LT"}
"""The functions of any number (≥ 2) of inputs; the others take two."""

_TIME = {
    "ADD_TIME": ("+", "TIME", "TIME"),
    "ADD_TOD_TIME": ("+", "TOD", "TIME"),
    "ADD_DT_TIME": ("+", "DT", "TIME"),
    "SUB_TIME": ("-", "TIME", "TIME"),
    "SUB_DATE_DATE": ("-", "DATE", "DATE"),
    "SUB_TOD_TIME": ("-", "TOD", "TIME"),
    "SUB_TOD_TOD": ("-", "TOD", "TOD"),
    "SUB_DT_TIME": ("-", "DT", "TIME"),
    "SUB_DT_DT": ("-", "DT", "DT"),
    "MUL_TIME": ("*", "TIME", ""),
    "MULTIME": ("*", "TIME", ""),
    "DIV_TIME": ("/", "TIME", ""),
    "DIVTIME": ("/", "TIME", ""),
}
"""The functions of time data types: operator and the types of IN1 and IN2 ("": a number)."""

_TRUNC = re.compile(r"^(?:([A-Z]+)_)?TRUNC_([A-Z]+)$")


def names() -> list[str]:
    """Every function this module knows by its plain name (for suggestions)."""
    return [*OPERATORS, *_TIME, "CONCAT_DATE_TOD"]


def operator_call(x: Expressions, node: Any, upper: str) -> E | None:
    """The call ``upper(...)`` if it is one of these functions, else None."""
    if upper in OPERATORS:
        return _apply(x, node, upper, _arguments(x, node, upper in _EXTENSIBLE))
    if upper in _TIME:
        op, first, second = _TIME[upper]
        a, b = _arguments(x, node, False)
        _expect(x, node, upper, a, ELEMENTARY[first])
        if second:
            _expect(x, node, upper, b, ELEMENTARY[second])
        elif not (isinstance(b.type, Elementary) and b.type.numeric):
            raise x.error(node, f"{upper} by {indefinite(b.type.name)}", "a number as IN2")
        return x.combine(node, op, a, b)
    if upper == "CONCAT_DATE_TOD":
        from plc.st.codegen.expressions import E

        a, b = _arguments(x, node, False)
        _expect(x, node, upper, a, T.DATE)
        _expect(x, node, upper, b, T.TOD)
        return E(f"({a.code} + {b.code})", T.DT)
    trunc = _TRUNC.match(upper)
    if trunc and trunc.group(2) in ELEMENTARY and (trunc.group(1) or "REAL") in ELEMENTARY:
        return _trunc(x, node, trunc.group(1), ELEMENTARY[trunc.group(2)])
    function, _, type_name = upper.rpartition("_")
    if function in OPERATORS and type_name in ELEMENTARY:
        return _typed(x, node, function, ELEMENTARY[type_name])
    return None


def _arguments(x: Expressions, node: Any, extensible: bool) -> list[E]:
    """The inputs IN1, IN2[, ...] in order (named or not)."""
    count = len(node.parameters or [])
    names = tuple(f"IN{i}" for i in range(1, max(count, 2) + 1))
    args = x.calls.arguments(node, names)
    if len(args) < 2 or (len(args) > 2 and not extensible):
        name = str(getattr(node.name, "name", node.name))
        raise x.error(node, f"{name} with {len(args)} argument(s)", "2" + " or more" * extensible)
    return args


def _apply(x: Expressions, node: Any, upper: str, args: list[E]) -> E:
    """The operator of ``upper`` over the inputs: left to right for arithmetic and logic; each
    neighbouring pair compared, ANDed, for a comparison (``GT(a, b, c)``: a > b AND b > c)."""
    op = OPERATORS[upper]
    if op in ("=", "<>", "<", ">", "<=", ">="):
        pairs = [x.combine(node, op, a, b) for a, b in itertools.pairwise(args)]
        result = pairs[0]
        for pair in pairs[1:]:
            result = x.combine(node, "AND", result, pair)
        return result
    result = args[0]
    for b in args[1:]:
        result = x.combine(node, op, result, b)
    return result


def _typed(x: Expressions, node: Any, function: str, t: Elementary) -> E:
    """``ADD_INT(a, b)``: the function with its inputs and result of type ``t``."""
    from plc.st.codegen.expressions import E

    args = _arguments(x, node, function in _EXTENSIBLE)
    typed = []
    for a in args:
        if not (isinstance(a.type, Elementary) and a.type.kind == t.kind) and a.type not in (
            T.ANY_INT,
            T.ANY_REAL,
        ):
            raise x.error(
                node, f"{function}_{t.name} of {indefinite(a.type.name)}", f"{t.name} inputs"
            )
        typed.append(_as(x, a, t, node))
    result = _apply(x, node, function, typed)
    if result.type.kind == "bool" or result.type is t:
        return result
    return E(x.convert(result, t, node), t, None)


def _as(x: Expressions, a: E, t: Elementary, node: Any) -> E:
    """``a`` converted to ``t`` (a constant stays one)."""
    from plc.st.codegen.expressions import E, const

    if not a.const:
        return E(x.convert(a, t, node), t)
    if t.integral:
        return const(T.wrap_value(int(a.value), t), t)
    return const(x.round_real(float(a.value), t) if t.kind == "real" else a.value, t)


def _trunc(x: Expressions, node: Any, source: str | None, to: Elementary) -> E:
    """``TRUNC_INT(r)``, ``REAL_TRUNC_INT(r)``: toward zero, as ``to``."""
    from plc.st.codegen.expressions import E, const
    from plc.st.runtime import functions as F  # noqa: N812

    (arg,) = x.calls.arguments(node, ("IN",))
    if arg.type.kind != "real" or not to.integral or (source and ELEMENTARY[source].kind != "real"):
        raise x.error(node, f"TRUNC of {indefinite(arg.type.name)} to {to.name}", "a REAL or LREAL")
    if arg.const:
        return const(T.wrap_value(F.trunc(arg.value), to), to)
    return E(T.wrap_code(f"_f.trunc({arg.code})", to), to)


def _expect(x: Expressions, node: Any, function: str, arg: E, t: Elementary) -> None:
    """An input of a time function must be of type ``t``."""
    if arg.type is not t:
        raise x.error(node, f"{function} of {indefinite(arg.type.name)}", f"{t.name}")

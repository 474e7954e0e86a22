"""ST expressions translated to Python expressions with their IEC types (:class:`Expressions`);
constants are folded so that a literal costs nothing at run time."""

from __future__ import annotations

__all__ = ["E", "Expressions", "const", "duration_ns", "literal_code"]

import math
import re
from dataclasses import dataclass
from typing import Any

import blark.transform as tf

from plc.st.errors import STError, indefinite, nearest
from plc.st.runtime.functions import f32
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.catalog import mcl_enums
from plc.st.semantics.scope import Scope, Unit, Var
from plc.st.semantics.types import AXIS_FIELDS, Elementary, Type


@dataclass(frozen=True)
class E:
    """A translated expression: Python code, IEC type, the value when constant."""

    code: str
    type: Type
    value: Any = None
    wide: bool = False
    """Integer arithmetic narrower than 32 bits, not yet wrapped (a store wraps it)."""
    part: tuple[E, int, int] | None = None
    """A part of a variable (``w.3``, ``w.%B1``): the variable, the part's shift and width
    [bits] (:mod:`plc.st.codegen.access` writes it)."""

    @property
    def const(self) -> bool:
        """Known at translation time."""
        return self.value is not None


def literal_code(value: Any) -> str:
    """Python code of a constant (infinities and NaN included)."""
    if isinstance(value, float) and not math.isfinite(value):
        return "_m.nan" if math.isnan(value) else ("_m.inf" if value > 0 else "(-_m.inf)")
    return repr(value)


def const(value: Any, t: Type) -> E:
    """A constant expression."""
    return E(literal_code(value), t, value)


_STRINGS = re.compile(r"'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\"")
_IMPURE = re.compile(r"[\w\])]\(|\[|/|%|\*\*|@|:=|\blambda\b")
"""What may have an effect or fault when evaluated: a call, an index, a division, a power."""
_OPERATOR_WORDS = re.compile(r"\b(?:not|and|or)\s*\(")


def _plain(code: str) -> bool:
    """The expression only reads variables and members, compares and combines them: evaluating
    it has no effect and cannot fault, so AND/OR may skip it (the value is the same)."""
    return not _IMPURE.search(_OPERATOR_WORDS.sub(" (", _STRINGS.sub("''", code)))


_COMPARE = {"=": "==", "<>": "!=", "<": "<", ">": ">", "<=": "<=", ">=": ">="}
_LOGIC = {"AND": "&", "&": "&", "OR": "|", "XOR": "^"}


class Expressions:
    """Translates the expressions of one POU (its :class:`Scope`) in a :class:`Unit`."""

    def __init__(self, unit: Unit, scope: Scope) -> None:
        self.unit = unit
        self.scope = scope
        from plc.st.codegen.calls import Calls

        self.calls = Calls(self)

    def error(self, node: Any, problem: str, expected: str = "") -> STError:
        """An :class:`STError` at ``node``."""
        return STError.at(self.unit.where(node), problem, expected)

    # ------------------------------------------------------------------ dispatch
    def expr(self, node: Any) -> E:
        """The translation of expression ``node``."""
        if isinstance(node, tf.Literal):
            return self.literal(node)
        if isinstance(node, tf.ParenthesizedExpression):
            return self.expr(node.expr)
        if isinstance(node, tf.BinaryOperation):
            return self.binary(node)
        if isinstance(node, tf.UnaryOperation):
            return self.unary(node)
        if isinstance(node, tf.FunctionCall):
            return self.calls.function(node)
        if isinstance(node, tf.SimpleVariable | tf.MultiElementVariable):
            return self.variable(node)
        if isinstance(node, tf.EnumeratedValue):
            return self.enum_literal(node)
        raise self.error(node, f"{type(node).__name__} is not supported here", "an expression")

    def expr_as(self, node: Any, t: Type) -> E:
        """``node`` where a value of type ``t`` is expected: a bare name that is a value of the
        enumeration ``t`` is that value (IEC names are case-insensitive across kinds: ``HomeZ``
        beside a block ``homeZ``), unless a variable of type ``t`` has that name."""
        name = _bare_name(node)
        if name is not None and isinstance(t, T.EnumType):
            var = self.scope.get(name)
            if var is None or var.type != t:
                for value_name, value in t.values.items():
                    if value_name.lower() == name.lower():
                        return const(value, t)
                close = nearest(name, t.values)
                if var is None and close and not self._known(name):
                    hint = f" (did you mean {', '.join(close)}?)"
                    expected = f"a value of {t.name}: {_listed(t)}"
                    raise self.error(node, f"unknown variable {name!r}{hint}", expected)
        return self.expr(node)

    def _known(self, name: str) -> bool:
        """``name`` is an enumeration value, an axis or an axis' mapped name."""
        names = {n.lower() for n in (*self.unit.axes, *self.unit.mapping)}
        return self.unit.enum_value(name) is not None or name.lower() in names

    # ------------------------------------------------------------------ literals
    def literal(self, node: Any) -> E:
        """A literal: integer (any base), real, BOOL, TIME/LTIME, STRING."""
        if isinstance(node, tf.Boolean):
            return const(str(node.value).upper() in ("TRUE", "1"), T.BOOL)
        if isinstance(node, tf.Integer | tf.BitString):
            text = str(node.value).replace("_", "")
            base = {tf.BinaryInteger: 2, tf.OctalInteger: 8, tf.HexInteger: 16}.get(type(node), 10)
            for cls, b in ((tf.BinaryBitString, 2), (tf.OctalBitString, 8), (tf.HexBitString, 16)):
                if isinstance(node, cls):
                    base = b
            value = int(text, base)
            typed = getattr(node, "type_name", None)
            t = self.unit.type_named(str(typed), node) if typed else T.ANY_INT
            if isinstance(t, Elementary) and t.kind == "bool":
                return const(bool(value), T.BOOL)
            if isinstance(t, Elementary) and t.kind == "real":
                return const(self.round_real(float(value), t), t)
            return const(T.wrap_value(value, t) if isinstance(t, Elementary) else value, t)
        if isinstance(node, tf.Real):
            real = float(str(node.value).replace("_", ""))
            typed = getattr(node, "type_name", None)
            t = self.unit.type_named(str(typed), node) if typed else T.ANY_REAL
            return const(self.round_real(real, t), t)
        if isinstance(node, tf.Lduration):
            return const(_duration(node, 1_000_000), T.LTIME)
        if isinstance(node, tf.Duration):
            return const(_duration(node, 1), T.TIME)
        if isinstance(node, tf.String):
            return const(_string(str(node.value)), T.STRING)
        if isinstance(node, tf.Date | tf.TimeOfDay | tf.DateTime):
            from plc.st.codegen.dates import literal

            return literal(self, node)
        raise self.error(node, f"the literal {node} is not supported", "a number, TIME or STRING")

    @staticmethod
    def round_real(value: float, t: Type) -> float:
        """A real constant as type ``t`` holds it (REAL: 32 bits)."""
        return f32(value) if t is T.REAL else value

    def enum_literal(self, node: tf.EnumeratedValue) -> E:
        """``Type#Value``, ``Type.Value`` or a bare value (in an array's initial value)."""
        type_name, name = node.type_name, str(node.name)
        if type_name is None and "." in name:
            type_name, _, name = name.rpartition(".")
        if type_name is None:
            simple = tf.SimpleVariable(node.name, False)
            simple.meta = node.meta
            return self.name(simple)
        t = self.unit.type_named(str(type_name), node)
        if not isinstance(t, T.EnumType):
            raise self.error(node, f"{t.name} is not an enumeration", "an enumeration type")
        for value_name, value in t.values.items():
            if value_name.lower() == name.lower():
                return const(value, t)
        close = nearest(name, t.values)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise self.error(node, f"{t.name} has no value {name!r}{hint}", _listed(t))

    # ------------------------------------------------------------------ variables
    def variable(self, node: Any) -> E:
        """A variable read (or a target): a name, then field selections and subscripts."""
        if isinstance(node, tf.SimpleVariable):
            return self.name(node)
        head = node.name
        var = self.in_gvl(node)
        if var is not None:  # GVL_Axes.X
            current = self._value(var, node.elements[0])
            return self._selected(current, node.elements[1:])
        dotted = self._dotted(node)
        if dotted is not None and self.scope.get(str(head.name)) is None:
            axis = self.unit.axis(dotted)
            if axis is not None:
                return E(axis, T.AXIS)
            upper = str(head.name).upper()
            t = self.unit.types.get(upper) or mcl_enums().get(upper)
            if isinstance(t, T.EnumType) and len(node.elements) == 1:
                value = tf.EnumeratedValue(head.name, node.elements[0].field.name, None)
                value.meta = node.meta
                return self.enum_literal(value)
        return self._selected(self.name(head, dotted), node.elements)

    def _selected(self, current: E, elements: list[Any]) -> E:
        """``current`` then its field selections and subscripts ``elements``."""
        for element in elements:
            if isinstance(element, tf.FieldSelector):
                current = self.field(self._deref(current, element), element)
            else:
                current = self._deref(self.subscript(current, element), element)
        return current

    def in_gvl(self, node: Any) -> Var | None:
        """The global ``GVL.name`` a variable begins with, where ``GVL`` is a named VAR_GLOBAL
        block and no variable (None: it does not).

        Raises:
            STError: the GVL declares no such name.
        """
        if not isinstance(node, tf.MultiElementVariable) or not node.elements:
            return None
        head, first = str(node.name.name), node.elements[0]
        gvl = self.unit.gvls.get(head.lower())
        if gvl is None or self.scope.get(head) is not None:
            return None
        if not isinstance(first, tf.FieldSelector) or not isinstance(
            first.field, tf.SimpleVariable
        ):
            raise self.error(first, f"{head} is a GVL", f"{head}.<variable>")
        found: Var = gvl.var(str(first.field.name), self.unit.where(first.field.name))
        return found

    def _value(self, var: Var, node: Any) -> E:
        """The value of variable ``var`` named at ``node`` (a constant's value inlined)."""
        if var.constant is not None:
            return E(literal_code(var.constant), var.type, var.constant)
        return self._deref(E(var.code, var.type), node)

    def _deref(self, e: E, element: Any) -> E:
        """``e^`` where ``element`` (a name, ``.field`` or ``[i]``) carries the ``^``."""
        if not getattr(element, "dereferenced", False):
            return e
        from plc.st.codegen.access import dereference

        return dereference(self, e, element)

    @staticmethod
    def _dotted(node: tf.MultiElementVariable) -> str | None:
        """``A.B.C`` when the variable is only field selections, else None."""
        parts = [str(node.name.name)]
        for element in node.elements:
            if not (
                isinstance(element, tf.FieldSelector)
                and isinstance(element.field, tf.SimpleVariable)
            ):
                return None
            parts.append(str(element.field.name))
        return ".".join(parts)

    def name(self, node: tf.SimpleVariable, dotted: str | None = None) -> E:
        """A simple name: a variable, a constant, an enumeration value or a bound axis
        (``dotted``: the name of fields it begins, ``Pohon.Ax1``, for the message where it is
        none)."""
        name = str(node.name)
        var = self.scope.get(name)
        if var is not None:
            return self._value(var, node)
        qualified = self.unit.qualified_only(name)
        if qualified:
            gvls = ", ".join(q.partition(".")[0] for q in qualified)
            raise self.error(
                node,
                f"{name} is declared in {gvls} with {{attribute 'qualified_only'}}: "
                f"write {' or '.join(qualified)}",
            )
        found = self.unit.enum_value(name)
        if found is not None:
            return const(found[1], found[0])
        axis = self.unit.axis(name)
        if axis is not None:
            return E(axis, T.AXIS)
        if name.upper() == "NULL":  # the reference to nothing (IEC 3rd ed. 6.4.4.10.2)
            return E("_f.NULL", T.NULL)
        close = nearest(name, [*self.scope.names(), *self.unit.enum_names()])
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        expected = "a declared variable"
        if dotted is not None and not close:  # Pohon.Ax1: an axis of another name
            expected += f", or a mapping of {dotted} onto an axis (--map {dotted}=X)"
        raise self.error(node, f"unknown variable {name!r}{hint}", expected)

    def field(self, base: E, element: tf.FieldSelector) -> E:
        """``base.field`` of a STRUCT or a block's member; ``base.3``, ``base.%B1`` a part."""
        if not isinstance(element.field, tf.SimpleVariable):
            from plc.st.codegen.access import partial

            return partial(self, base, element.field, element)
        name = str(element.field.name)
        t = base.type
        if isinstance(t, T.StructType):
            for field_name, field_type in t.fields.items():
                if field_name.lower() == name.lower():
                    return E(f"{base.code}.{field_name}", field_type)
            raise self.error(element, f"{t.name} has no field {name!r}", ", ".join(t.fields))
        if isinstance(t, T.BlockType):
            member = t.members.get(name.upper())
            if member is None:
                close = nearest(name, [m.python for m in t.members.values()])
                hint = f" (did you mean {', '.join(close)}?)" if close else ""
                raise self.error(element, f"{t.name} has no member {name!r}{hint}", "its outputs")
            return E(f"{base.code}.{member.python}", member.type)
        if t.kind == "axis":
            field = AXIS_FIELDS.get(name.upper())
            if field is None:
                raise self.error(element, f"AXIS_REF has no field {name!r}", "POS, VEL, AxErrorID")
            return E(f"{base.code}.{field[0]}", field[1])
        raise self.error(element, f"{base.type.name} has no fields", "a STRUCT or a block")

    def subscript(self, base: E, element: tf.SubscriptList) -> E:
        """``base[i, j]``: every index checked against the bounds (a fault outside)."""
        t = base.type
        if not isinstance(t, T.ArrayType):
            raise self.error(element, f"{t.name} is not an ARRAY", "an ARRAY variable")
        if len(element.subscripts) > len(t.dims):
            raise self.error(element, f"{len(element.subscripts)} indices", f"{len(t.dims)}")
        code = base.code
        for sub, (low, high) in zip(element.subscripts, t.dims, strict=False):
            i = self.expr(sub)
            if not (isinstance(i.type, Elementary) and i.type.integral):
                raise self.error(sub, f"an index of type {i.type.name}", "an integer")
            if i.const:
                if not low <= i.value <= high:
                    raise self.error(sub, f"index {i.value} outside {low}..{high}", "an index")
                code = f"{code}[{i.value - low}]"
            else:
                code = f"{code}[_f.index({i.code}, {low}, {high - low + 1})]"
        rest = t.dims[len(element.subscripts) :]
        return E(code, T.ArrayType(t.name, t.element, rest) if rest else t.element)

    # ------------------------------------------------------------------ operators
    def unary(self, node: tf.UnaryOperation) -> E:
        """``-x``, ``+x``, ``NOT x`` (bitwise on bit strings and integers)."""
        e = self.expr(node.expr)
        op = str(node.op).upper()
        t = T.plain(e.type)
        if not isinstance(t, Elementary):
            raise self.error(node, f"{op} on {t.name}", "a number or BOOL")
        if op == "NOT":
            if t.kind == "bool":
                return const(not e.value, t) if e.const else E(f"(not {e.code})", t)
            if t.integral:
                if e.const:
                    return const(T.wrap_value(~e.value, t), t)
                return E(f"({e.code} ^ {T.mask(t)})" if not t.signed else f"(~{e.code})", t)
            raise self.error(node, f"NOT on {t.name}", "BOOL or a bit string")
        if not (t.numeric or t.kind == "time"):
            raise self.error(node, f"{op} on {t.name}", "a number")
        if op == "+":
            return e
        if e.const:
            value = -e.value
            return const(T.wrap_value(value, t) if t.integral and t.bits else value, t)
        return E(f"(-{e.code})", t, wide=t.integral)

    def binary(self, node: tf.BinaryOperation) -> E:
        """A binary operation with its IEC result type (a comparison with a value of an
        enumeration reads a bare name on the other side as that enumeration's value)."""
        op = str(node.op).upper()
        if op == ":=":  # IF t.Q := TRUE THEN
            raise self.error(node, "':=' assigns; a comparison is '='")
        a = self.expr(node.left)
        b = self.expr_as(node.right, a.type) if op in _COMPARE else self.expr(node.right)
        if op in _COMPARE and isinstance(b.type, T.EnumType) and a.type != b.type:
            a = self.expr_as(node.left, b.type)
        return self.combine(node, op, a, b)

    def combine(self, node: Any, op: str, a: E, b: E) -> E:
        """``a op b`` (``op`` an ST operator in upper case) with its IEC result type."""
        if op in _COMPARE:
            return self.compare(node, op, a, b)
        if op in _LOGIC:
            return self.logic(node, op, a, b)
        if op in ("AND_THEN", "OR_ELSE"):
            self.require(node, a, "bool")
            self.require(node, b, "bool")
            word = "and" if op == "AND_THEN" else "or"
            return E(f"({a.code} {word} {b.code})", T.BOOL)
        from plc.st.codegen.arithmetic import arithmetic

        return arithmetic(self, node, op, a, b)

    def require(self, node: Any, e: E, kind: str) -> None:
        """``e`` must be of ``kind`` (``bool``, ...)."""
        if e.type.kind != kind:
            raise self.error(node, f"{indefinite(e.type.name)} operand", kind.upper())

    def compare(self, node: Any, op: str, a: E, b: E) -> E:
        """A comparison: numbers with numbers, else equal types."""
        ta, tb = a.type, b.type
        numeric = all(isinstance(t, Elementary) and t.numeric for t in (ta, tb))
        same = ta.kind == tb.kind and (ta.kind not in ("enum", "struct", "array") or ta == tb)
        if not (numeric or same) or ta.kind in ("block", "array", "struct"):
            from plc.st.codegen.arithmetic import time_and_integer

            mixed = time_and_integer(op, a, b)
            if mixed:
                raise self.error(node, mixed)
            raise self.error(node, f"{ta.name} {op} {tb.name}", "operands of one type")
        if ta.kind == "ref" and (op not in ("=", "<>") or (T.NULL not in (ta, tb) and ta != tb)):
            raise self.error(node, f"{ta.name} {op} {tb.name}", "= or <> of references alike")
        if a.const and b.const:
            return const(bool(eval(f"{a.value!r} {_COMPARE[op]} {b.value!r}")), T.BOOL)
        return E(f"({a.code} {_COMPARE[op]} {b.code})", T.BOOL)

    def logic(self, node: Any, op: str, a: E, b: E) -> E:
        """AND, OR, XOR: on BOOL, else bitwise on integers and bit strings."""
        ta, tb = T.plain(a.type), T.plain(b.type)
        if ta.kind == "bool" and tb.kind == "bool":
            t: Elementary = T.BOOL
        elif (
            isinstance(ta, Elementary)
            and isinstance(tb, Elementary)
            and ta.integral
            and tb.integral
        ):
            t = T.wider(ta, tb)
        else:
            raise self.error(node, f"{ta.name} {op} {tb.name}", "BOOL or bit-string operands")
        py = _LOGIC[op]
        if a.const and b.const:
            value = eval(f"{a.value!r} {py} {b.value!r}")
            return const(bool(value) if t is T.BOOL else T.wrap_value(value, t), t)
        if t is T.BOOL and py != "^" and _plain(b.code):  # the same value, b read only if needed
            py = "and" if py == "&" else "or"
        return E(f"({a.code} {py} {b.code})", t)

    # ------------------------------------------------------------------ conversion
    def convert(self, e: E, to: Type, node: Any) -> str:
        """Python code storing ``e`` into a variable of type ``to`` (implicit conversion:
        integers wrap to the target's width, integers become reals, LREAL rounds to REAL,
        STRING is cut to its length); other mixes are a type error."""
        from plc.st.codegen.arithmetic import coerce

        return coerce(self, e, to, node)


def _bare_name(node: Any) -> str | None:
    """The name of a plain name node (a variable or an enumeration value), else None."""
    if isinstance(node, tf.SimpleVariable) and not node.dereferenced:
        return str(node.name)
    if isinstance(node, tf.EnumeratedValue) and node.type_name is None and "." not in node.name:
        return str(node.name)
    return None


def duration_ns(node: Any) -> int:
    """A TIME literal in ns (where a fraction of a ms shows)."""
    return _duration(node, 1_000_000)


def _duration(node: Any, scale: int) -> int:
    """A TIME literal in ms (``scale`` 1) or an LTIME literal in ns (``scale`` 10**6)."""
    total = 0.0
    for name, ms in (
        ("days", 86_400_000.0),
        ("hours", 3_600_000.0),
        ("minutes", 60_000.0),
        ("seconds", 1000.0),
        ("milliseconds", 1.0),
        ("microseconds", 1e-3),
        ("nanoseconds", 1e-6),
    ):
        value = getattr(node, name, None)
        if value is not None:
            total += float(str(value).replace("_", "")) * ms
    result = round(total * scale)
    return -result if getattr(node, "negative", False) else result


_ESCAPES = {"$$": "$", "$'": "'", '$"': '"', "$L": "\n", "$N": "\n", "$P": "\f", "$R": "\r"}


def _string(text: str) -> str:
    """A STRING literal's value: quotes removed, ``$`` escapes resolved."""
    body = text[1:-1]
    out: list[str] = []
    i = 0
    while i < len(body):
        pair = body[i : i + 2].upper() if body[i] == "$" else ""
        if pair in _ESCAPES or pair == "$T":
            out.append("\t" if pair == "$T" else _ESCAPES[pair if pair in _ESCAPES else "$$"])
            i += 2
        elif body[i] == "$" and len(body) >= i + 3:
            out.append(chr(int(body[i + 1 : i + 3], 16)))
            i += 3
        else:
            out.append(body[i])
            i += 1
    return "".join(out)


def _listed(t: T.EnumType) -> str:
    """The values of an enumeration, for a message."""
    return ", ".join(t.values)

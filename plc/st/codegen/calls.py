"""Calls in ST: the standard functions and conversions, the user's FUNCTIONs (expressions) and
block invocations (statements: ``inst(In := x, Out => y)``; an omitted input keeps its value,
outputs are copied after the call, ``instance.Output`` reads the same member)."""

from __future__ import annotations

__all__ = ["Calls"]

import re
from typing import TYPE_CHECKING, Any

import blark.transform as tf

from plc.st.errors import nearest
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import ELEMENTARY, Elementary, Type

if TYPE_CHECKING:
    from plc.st.codegen.expressions import E, Expressions

_MATH = {
    "ABS": ("abs", None),
    "SQRT": ("_f.sqrt", "real"),
    "LN": ("_f.ln", "real"),
    "LOG": ("_f.log10", "real"),
    "EXP": ("_m.exp", "real"),
    "SIN": ("_m.sin", "real"),
    "COS": ("_m.cos", "real"),
    "TAN": ("_m.tan", "real"),
    "ASIN": ("_m.asin", "real"),
    "ACOS": ("_m.acos", "real"),
    "ATAN": ("_m.atan", "real"),
}
"""One-argument numeric functions: Python callable, result kind (None: the argument's type)."""

_PARAMS = {
    "LIMIT": ("MN", "IN", "MX"),
    "SEL": ("G", "IN0", "IN1"),
    "SHL": ("IN", "N"),
    "SHR": ("IN", "N"),
    "ROL": ("IN", "N"),
    "ROR": ("IN", "N"),
    "LEN": ("IN",),
    "LEFT": ("IN", "L"),
    "RIGHT": ("IN", "L"),
    "MID": ("IN", "L", "P"),
    "INSERT": ("IN1", "IN2", "P"),
    "DELETE": ("IN", "L", "P"),
    "REPLACE": ("IN1", "IN2", "L", "P"),
    "FIND": ("IN1", "IN2"),
    "EXPT": ("IN1", "IN2"),
    "TRUNC": ("IN",),
    "MOVE": ("IN",),
}
"""Parameter names of the standard functions with a fixed signature, in order."""

_VARIADIC = ("MIN", "MAX", "CONCAT", "MUX")
"""The standard functions of any number of inputs."""

_CONVERSION = re.compile(r"^(?:([A-Z]+)_)?TO_([A-Z]+)$")


class Calls:
    """Function calls and block invocations of one POU."""

    def __init__(self, x: Expressions) -> None:
        self.x = x

    # ------------------------------------------------------------------ functions
    def arguments(self, node: tf.FunctionCall, names: tuple[str, ...] = ()) -> list[E]:
        """The arguments in order: positional ones, then named ones placed by ``names``."""
        args: list[Any] = []
        for p in node.parameters or []:
            if isinstance(p, tf.OutputParameterAssignment):
                raise self.x.error(p, "an output (=>) in a function call", "inputs only")
            if p.name is None:
                args.append(self.x.expr(p.value))
                continue
            key = str(p.name.name).upper()
            if key not in names:
                raise self.x.error(p, f"no parameter {p.name.name!r}", ", ".join(names) or "none")
            position = names.index(key)
            while len(args) <= position:
                args.append(None)
            args[position] = self.x.expr(p.value)
        if any(a is None for a in args):
            raise self.x.error(node, "a parameter is missing", ", ".join(names))
        return args

    def function(self, node: tf.FunctionCall) -> E:
        """A function call in an expression."""
        name = str(getattr(node.name, "name", node.name))
        upper = name.upper()
        user = self.x.unit.functions.get(upper)
        if user is not None:
            return self.user_function(node, user)
        conversion = _CONVERSION.match(upper)
        if conversion and conversion.group(2) in ELEMENTARY:
            (arg,) = self._count(node, self.arguments(node, ("IN",)), 1)
            return self.convert(node, arg, ELEMENTARY[conversion.group(2)], conversion.group(1))
        if upper == "SIM_TIME":  # the machine's simulated time [s], as Python reads scene.time
            from plc.st.codegen.expressions import E

            self._count(node, self.arguments(node), 0)
            return E("_now()", T.LREAL)
        if upper in _MATH:
            return self.math(node, upper)
        if upper in _VARIADIC:
            return self.variadic(node, upper)
        if upper in _PARAMS:
            from plc.st.codegen.standard import standard

            return standard(self.x, node, upper, self.arguments(node, _PARAMS[upper]))
        if self.x.unit.block_named(name) is not None or self.x.scope.get(name) is not None:
            raise self.x.error(node, f"{name} is a function block", "a call as a statement")
        known = [*self.x.unit.functions, *_MATH, *_PARAMS, *_VARIADIC, "SIM_TIME"]
        close = nearest(name, known)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise self.x.error(node, f"unknown function {name!r}{hint}", "a declared function")

    def _count(self, node: Any, args: list[E], n: int) -> list[E]:
        if len(args) != n:
            raise self.x.error(node, f"{len(args)} arguments", f"{n}")
        return args

    def user_function(self, node: tf.FunctionCall, f: Any) -> E:
        """A call of the file's FUNCTION: every input in order, a missing one its default."""
        names = tuple(n.upper() for n, _, _ in f.inputs)
        given: dict[int, E] = {}
        for i, p in enumerate(node.parameters or []):
            if isinstance(p, tf.OutputParameterAssignment):
                raise self.x.error(p, "an output (=>) in a function call", "inputs only")
            key = str(p.name.name).upper() if p.name is not None else None
            if key is not None and key not in names:
                raise self.x.error(p, f"{f.name} has no input {key!r}", ", ".join(names))
            position = names.index(key) if key is not None else i
            if position >= len(names):
                raise self.x.error(p, f"too many arguments to {f.name}", f"{len(names)}")
            given[position] = self.x.expr(p.value)
        codes = [
            self.x.convert(given[i], t, node) if i in given else default
            for i, (_, t, default) in enumerate(f.inputs)
        ]
        from plc.st.codegen.expressions import E

        return E(f"{f.python}({', '.join(codes)})", f.result)

    def math(self, node: tf.FunctionCall, upper: str) -> E:
        """ABS, SQRT, LN, ... on one number."""
        from plc.st.codegen.expressions import E, const

        (arg,) = self._count(node, self.arguments(node, ("IN",)), 1)
        function, kind = _MATH[upper]
        t = arg.type
        if not (isinstance(t, Elementary) and t.numeric):
            raise self.x.error(node, f"{upper} of {t.name}", "a number")
        result: Elementary = t if kind is None else (T.REAL if t is T.REAL else T.LREAL)
        code = f"{function}({arg.code})"
        if upper == "ABS" and t.integral:
            code = T.wrap_code(code, t) if t.bits else code
        if result is T.REAL and upper != "ABS":
            code = f"_f.f32({code})"
        if arg.const:
            from plc.st.runtime import functions as _f

            value = eval(code, {"_f": _f, "_m": __import__("math"), "abs": abs})
            return const(value, result)
        return E(code, result)

    def variadic(self, node: tf.FunctionCall, upper: str) -> E:
        """MIN, MAX, CONCAT, MUX: any number of inputs."""
        from plc.st.codegen.expressions import E

        args = [self.x.expr(p.value) for p in node.parameters or []]
        if len(args) < 2:
            raise self.x.error(node, f"{upper} with {len(args)} argument(s)", "at least 2")
        codes = [a.code for a in args]
        if upper == "CONCAT":
            if any(a.type.kind != "string" for a in args):
                raise self.x.error(node, "CONCAT of a non-STRING", "STRING arguments")
            return E(f"({' + '.join(codes)})", T.STRING)
        if upper == "MUX":
            t = args[1].type
            return E(f"_f.mux({', '.join(codes)})", t)
        t = self.common(node, args)
        return E(f"{upper.lower()}({', '.join(codes)})", t)

    def common(self, node: Any, args: list[E]) -> Type:
        """The common type of arguments that must be alike (numbers widen)."""
        t = args[0].type
        for a in args[1:]:
            u = a.type
            if isinstance(t, Elementary) and isinstance(u, Elementary) and t.numeric and u.numeric:
                t = T.real_of(t, u) if "real" in (t.kind, u.kind) else T.wider(t, u)
            elif u.kind != t.kind:
                raise self.x.error(node, f"{t.name} and {u.name} mixed", "arguments of one type")
        return t

    def convert(self, node: Any, arg: E, to: Elementary, source: str | None) -> E:
        """``SRC_TO_DST(x)`` / ``TO_DST(x)``."""
        from plc.st.codegen.standard import conversion

        if source is not None and source in ELEMENTARY:
            declared = ELEMENTARY[source]
            if arg.type.kind != declared.kind and not (
                arg.type in (T.ANY_INT, T.ANY_REAL) and declared.numeric
            ):
                raise self.x.error(node, f"{source}_TO_{to.name} of a {arg.type.name}", source)
        return conversion(self.x, node, arg, to)

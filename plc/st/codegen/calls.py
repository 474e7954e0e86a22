"""Calls in ST: the standard functions and conversions, the user's FUNCTIONs (expressions) and
block invocations (statements: ``inst(In := x, Out => y)``; an omitted input keeps its value,
outputs are copied after the call, ``instance.Output`` reads the same member)."""

from __future__ import annotations

__all__ = ["Calls"]

import re
from typing import TYPE_CHECKING, Any

import blark.transform as tf

from plc.st.errors import indefinite, nearest
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

_CONVERSION = re.compile(r"^(?:([A-Z_]+?)_)?TO_([A-Z_]+)$")


class Calls:
    """Function calls and block invocations of one POU."""

    def __init__(self, x: Expressions) -> None:
        self.x = x
        self.temps = 0
        """Temporaries taken for calls with outputs (``_c1``, ...)."""

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
        if any(a is None for a in args) or len(args) < len(names):
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
        if upper == "REF":
            from plc.st.codegen.access import reference

            (param,) = self._count(node, list(node.parameters or []), 1)
            value = param.value
            target = self.x.variable(value) if _is_variable(value) else self.x.expr(value)
            return reference(self.x, target, value)
        from plc.st.codegen import operators

        found = operators.operator_call(self.x, node, upper)
        if found is not None:
            return found
        if self.x.unit.block_named(name) is not None or self.x.scope.get(name) is not None:
            raise self.x.error(node, f"{name} is a function block", "a call as a statement")
        known = [*self.x.unit.functions, *_MATH, *_PARAMS, *_VARIADIC, "SIM_TIME", "REF"]
        known += operators.names()
        close = nearest(name, known)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise self.x.error(node, f"unknown function {name!r}{hint}", "a declared function")

    def _count(self, node: Any, args: list[E], n: int) -> list[E]:
        if len(args) != n:
            raise self.x.error(node, f"{len(args)} arguments", f"{n}")
        return args

    def user_function(self, node: tf.FunctionCall, f: Any) -> E:
        """A call of the file's FUNCTION: its inputs (a missing one its default), its in-outs
        (variables: copied in, and back after the call), its outputs (``o => v``: copied after
        the call); a call without names lists them in declaration order."""
        from plc.st.codegen.access import store_expression
        from plc.st.codegen.expressions import E

        given = self._parameters(node, f)
        codes = []
        for n, t, default in f.inputs:
            p = given.get(n.upper())
            value = None if p is None else self.x.expr_as(p.value, t)
            codes.append(default if value is None else self.x.convert(value, t, p))
        targets: list[tuple[int, E, Any]] = []
        for k, (n, t) in enumerate([*f.in_outs, *f.outputs], start=1):
            p = given.get(n.upper())
            if p is None and k <= len(f.in_outs):
                raise self.x.error(node, f"{f.name}'s VAR_IN_OUT {n} is not given", f"{n} := x")
            if p is None or p.value is None:
                continue
            target = self.x.variable(p.value) if _is_variable(p.value) else None
            if target is None or target.const:
                raise self.x.error(p, f"{p.value} cannot take {f.name}'s {n}", "a variable")
            if k <= len(f.in_outs):
                codes.append(self.x.convert(target, t, p))
            targets.append((k, target, p))
        call = f"{f.python}({', '.join(codes)})"
        if not (f.in_outs or f.outputs):
            return E(call, f.result)
        self.temps += 1
        temp = f"_c{self.temps}"
        params = [*f.in_outs, *f.outputs]
        stores = []
        for k, target, p in targets:
            value = E(f"{temp}[{k}]", params[k - 1][1])
            stores.append(store_expression(target, self.x.convert(value, target.type, p)))
        return E(f"(({temp} := {call}), {''.join(s + ', ' for s in stores)})[0][0]", f.result)

    def _parameters(self, node: tf.FunctionCall, f: Any) -> dict[str, Any]:
        """The parameters of a call of FUNCTION ``f`` by its upper-case names."""
        kinds = {n.upper(): "input" for n, _, _ in f.inputs}
        kinds |= {n.upper(): "in_out" for n, _ in f.in_outs}
        kinds |= {n.upper(): "output" for n, _ in f.outputs}
        order = [n.upper() for n in f.order]
        given: dict[str, Any] = {}
        for i, p in enumerate(node.parameters or []):
            key = str(p.name.name).upper() if p.name is not None else None
            if key is None and i >= len(order):
                raise self.x.error(p, f"too many arguments to {f.name}", f"{len(order)}")
            key = key or order[i]
            if key not in kinds:
                raise self.x.error(p, f"{f.name} has no parameter {key!r}", ", ".join(order))
            output = isinstance(p, tf.OutputParameterAssignment)
            if p.name is not None and output != (kinds[key] == "output"):
                expected = f"{key} => variable" if kinds[key] == "output" else f"{key} := value"
                raise self.x.error(p, f"{key} is {'not ' * output}an output of {f.name}", expected)
            given[key] = p
        return given

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
                raise self.x.error(
                    node, f"{source}_TO_{to.name} of {indefinite(arg.type.name)}", source
                )
        return conversion(self.x, node, arg, to)


def _is_variable(node: Any) -> bool:
    """A node naming a variable (that a call can write)."""
    return isinstance(node, tf.SimpleVariable | tf.MultiElementVariable)

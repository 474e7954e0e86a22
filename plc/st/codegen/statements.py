"""ST statements translated to Python lines (:class:`Statements`), each line tagged with its ST
source line so that a run-time fault names ``file:line``."""

from __future__ import annotations

__all__ = ["Emitter", "Statements"]

import dataclasses
from typing import Any

import blark.transform as tf

from plc.st.codegen.access import store
from plc.st.codegen.expressions import E, Expressions
from plc.st.errors import STError, indefinite
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import BlockType


class Emitter:
    """Python lines with their indentation and ST line."""

    def __init__(self) -> None:
        self.lines: list[tuple[int, str, int]] = []
        self.depth = 0
        self.st_line = 0

    def emit(self, text: str) -> None:
        """One line at the current depth."""
        self.lines.append((self.depth, text, self.st_line))


class Statements:
    """Translates the body of one POU into an :class:`Emitter`."""

    def __init__(self, x: Expressions, out: Emitter, result: str = "") -> None:
        self.x = x
        self.out = out
        self.result = result
        """The function's result variable (RETURN returns it), empty in a block/program."""
        self.loops: list[str] = []
        """Per enclosing loop: the increment a CONTINUE must run first (FOR), else ``""``."""
        self.temps = 0
        self.hoisted: dict[tuple[str, str], str] = {}
        """Block inputs set once when the instance is made (:mod:`plc.st.codegen.hoist`)."""
        self.uncopied: set[tuple[str, str]] = set()
        """Array inputs passed without a copy (:func:`plc.st.codegen.hoist.uncopied`)."""

    def block(self, statements: Any) -> None:
        """A statement list (``pass`` when empty)."""
        items = list(getattr(statements, "statements", None) or [])
        start = len(self.out.lines)
        for s in items:
            self.statement(s)
        if len(self.out.lines) == start:
            self.out.emit("pass")

    def nested(self, header: str, statements: Any) -> None:
        """``header:`` and the statements indented under it."""
        self.out.emit(header)
        self.out.depth += 1
        self.block(statements)
        self.out.depth -= 1

    def temp(self) -> str:
        """A fresh Python temporary."""
        self.temps += 1
        return f"_t{self.temps}"

    def statement(self, s: Any) -> None:
        """One statement."""
        self.out.st_line = self.x.unit.line(s) or self.out.st_line
        handler = getattr(self, f"do_{type(s).__name__}", None)
        if handler is None:
            raise self.x.error(s, f"{type(s).__name__} is not supported", "an IEC statement")
        try:
            handler(s)
        except STError:
            raise
        except Exception as error:  # a construct not foreseen: its line, never a traceback
            raise self.x.error(
                s,
                f"the statement cannot be translated ({type(error).__name__}: {error})",
                "an IEC 61131-3 statement",
            ) from None

    def condition(self, node: Any) -> str:
        """A BOOL expression."""
        e = self.x.expr(node)
        if e.type.kind != "bool":
            raise self.x.error(node, f"a condition of type {e.type.name}", "BOOL")
        return e.code

    # ------------------------------------------------------------------ statements
    def do_AssignmentStatement(self, s: tf.AssignmentStatement) -> None:
        targets = [self.target(target) for target in s.variables]
        value = self.x.expr_as(s.expression, targets[0].type)
        for node, t in zip(s.variables, targets, strict=True):
            self.out.emit(store(t, self.x.convert(value, t.type, node)))

    def target(self, node: Any) -> E:
        """A variable written to (not a constant, not a block instance)."""
        head = node.name if isinstance(node, tf.MultiElementVariable) else node
        if isinstance(head, tf.SimpleVariable):
            var = self.x.in_gvl(node) or self.x.scope.get(str(head.name))
            if var is not None and (var.constant is not None or var.read_only):
                raise self.x.error(node, f"{var.name} is a CONSTANT", "a variable")
        self._not_an_output(node)
        t = self.x.variable(node)
        if (
            t.const
            or isinstance(t.type, BlockType)
            or (t.type.kind == "axis" and t.code[:3] == "_g.")
        ):
            raise self.x.error(node, f"{node} cannot be assigned", "a variable")
        return t

    def _not_an_output(self, node: Any) -> None:
        """An output of a block instance is the block's to write (IEC 61131-3 2.5.2.1: read
        it, ``inst.Q``, or take it with ``inst(Q => v)``)."""
        if not isinstance(node, tf.MultiElementVariable):
            return
        last = node.elements[-1]
        if not isinstance(last, tf.FieldSelector) or not isinstance(last.field, tf.SimpleVariable):
            return
        inner = node.elements[:-1]
        if not inner[1:] and self.x.in_gvl(node) is not None:
            return  # GVL_Main.count: a global, no member
        base = self.x.variable(dataclasses.replace(node, elements=inner) if inner else node.name)
        members = base.type.members if isinstance(base.type, BlockType) else {}
        member = members.get(str(last.field.name).upper())
        if base.type.kind == "axis":
            raise self.x.error(node, f"{node} is read-only (the axis')", "a variable")
        if member is not None and member.direction == "output":
            raise self.x.error(
                node, f"{node} is an output of {base.type.name}", "an input or a variable"
            )

    def do_SetStatement(self, s: tf.SetStatement) -> None:
        self.out.emit(f"if {self.condition(s.expression)}:")
        self.out.emit(f"    {store(self.target(s.variable), 'True')}")

    def do_ResetStatement(self, s: tf.ResetStatement) -> None:
        self.out.emit(f"if {self.condition(s.expression)}:")
        self.out.emit(f"    {store(self.target(s.variable), 'False')}")

    def do_IfStatement(self, s: tf.IfStatement) -> None:
        self.nested(f"if {self.condition(s.if_expression)}:", s.statements)
        for clause in s.else_ifs or []:
            self.out.st_line = self.x.unit.line(clause) or self.out.st_line
            self.nested(f"elif {self.condition(clause.if_expression)}:", clause.statements)
        if s.else_clause is not None:
            self.nested("else:", s.else_clause.statements)

    def do_CaseStatement(self, s: tf.CaseStatement) -> None:
        selector = self.x.expr(s.expression)
        if selector.type.kind not in ("int", "bits", "enum"):
            raise self.x.error(s.expression, f"CASE on {selector.type.name}", "an integer")
        code = selector.code
        if not code.replace("_", "").isalnum():  # evaluated once, as IEC reads it
            temp = self.temp()
            self.out.emit(f"{temp} = {code}")
            code = temp
        keyword = "if"
        for case in s.cases:
            tests = [self.match(code, m, selector.type) for m in case.matches]
            self.out.st_line = self.x.unit.line(case) or self.out.st_line
            self.nested(f"{keyword} {' or '.join(tests)}:", case.statements)
            keyword = "elif"
        if s.else_clause is not None:
            if keyword == "if":
                self.block(s.else_clause.statements)
            else:
                self.nested("else:", s.else_clause.statements)

    def match(self, code: str, m: Any, t: Any) -> str:
        """One CASE label: a value or a range ``lo..hi`` (constant expressions of the
        selector's type ``t``)."""
        if isinstance(m, tf.Subrange):
            low, high = self.x.expr_as(m.start, t), self.x.expr_as(m.stop, t)
            if not (low.const and high.const):
                raise self.x.error(m, "a CASE range of variables", "constant bounds")
            self._label(m, low, t)
            self._label(m, high, t)
            return f"{low.value!r} <= {code} <= {high.value!r}"
        label = self.x.expr_as(m, t)
        if not label.const:
            raise self.x.error(m, "a CASE label that is not constant", "a constant")
        self._label(m, label, t)
        return f"{code} == {label.value!r}"

    def _label(self, m: Any, label: E, t: Any) -> None:
        """A CASE label must be of the selector's type (an integer for an integer selector,
        a value of its enumeration for an enumeration)."""
        integers = t.kind in ("int", "bits") and label.type.kind in ("int", "bits")
        if not integers and label.type != t:
            raise self.x.error(
                m, f"{indefinite(label.type.name)} label", f"{indefinite(t.name)} value"
            )

    def do_ForStatement(self, s: tf.ForStatement) -> None:
        control = self.target(s.control)
        if control.type.kind not in ("int", "bits"):
            raise self.x.error(s.control, f"a FOR variable of type {control.type.name}", "INT")
        start = self.x.convert(self.x.expr(s.from_), control.type, s.from_)
        end = self.x.expr(s.to)
        step = self.x.expr(s.step) if s.step is not None else E("1", T.ANY_INT, 1)
        end_code, step_code = end.code, step.code
        if not end.const:
            end_code = self.temp()
            self.out.emit(f"{end_code} = {end.code}")
        if not step.const:
            step_code = self.temp()
            self.out.emit(f"{step_code} = {step.code}")
        self.out.emit(f"{control.code} = {start}")
        if step.const:
            test = f"{control.code} {'<=' if step.value > 0 else '>='} {end_code}"
        else:
            c = control.code
            test = f"({c} <= {end_code} if {step_code} > 0 else {c} >= {end_code})"
        increment = f"{control.code} = {T.wrap_code(f'{control.code} + {step_code}', control.type)}"  # type: ignore[arg-type]
        self.out.emit(f"while {test}:")
        self.loops.append(increment)
        self.out.depth += 1
        self.watchdog(s, "FOR")
        self.block(s.statements)
        self.out.emit(increment)
        self.out.depth -= 1
        self.loops.pop()

    def do_WhileStatement(self, s: tf.WhileStatement) -> None:
        self.loops.append("")
        self.out.emit(f"while {self.condition(s.expression)}:")
        self.out.depth += 1
        self.watchdog(s, "WHILE")
        self.block(s.statements)
        self.out.depth -= 1
        self.loops.pop()

    def do_RepeatStatement(self, s: tf.RepeatStatement) -> None:
        self.loops.append("")
        self.out.emit("while True:")
        self.out.depth += 1
        self.watchdog(s, "REPEAT")
        self.block(s.statements)
        self.out.emit(f"if {self.condition(s.expression)}:")
        self.out.emit("    break")
        self.out.depth -= 1
        self.loops.pop()

    def watchdog(self, s: Any, kind: str) -> None:
        """The task's watchdog at the top of a loop's body (its back-edge): a scan past its
        deadline (``_deadline``, wall time [s] set when the scan begins) faults here, at the
        loop's line."""
        line = self.x.unit.line(s) or self.out.st_line
        self.out.st_line = line
        self.out.emit(f"if _perf() > _deadline: _f.watchdog({kind!r}, {line}, _watchdog)")

    def do_ExitStatement(self, s: tf.ExitStatement) -> None:
        if not self.loops:
            raise self.x.error(s, "EXIT outside a loop", "FOR, WHILE or REPEAT around it")
        self.out.emit("break")

    def do_ContinueStatement(self, s: tf.ContinueStatement) -> None:
        if not self.loops:
            raise self.x.error(s, "CONTINUE outside a loop", "FOR, WHILE or REPEAT around it")
        if self.loops[-1]:
            self.out.emit(self.loops[-1])
        self.out.emit("continue")

    def do_ReturnStatement(self, s: tf.ReturnStatement) -> None:
        self.out.emit(f"return {self.result}" if self.result else "return")

    def do_NoOpStatement(self, s: tf.NoOpStatement) -> None:
        self.x.expr(s.variable)

    def do_FunctionCallStatement(self, s: tf.FunctionCallStatement) -> None:
        from plc.st.codegen.invoke import invoke

        invoke(self, s)

"""Block inputs set once (:func:`hoisted`), and what a call need not copy (:func:`uncopied`): what
makes a translated scan cost what the same hand-written Python costs, which binds a block's
constant inputs when it builds the block (``mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0)``) and
passes only what changes per scan.

An input of a POU's own block instance is set once, when the instance is made, if every call of
that instance in the POU passes it the same constant (or the same bound axis, or the POU's own
axes group) and nothing writes it: a call sets it to the same value each scan, so setting it
once changes nothing the program can see. Inside a FUNCTION_BLOCK, an input passed on unchanged
to an inner block (``pulse(SetPosition := SetPosition)``) is set once too when the block's own
input is *fixed* (:func:`fixed_inputs`): every instance of the block in the file is a plain
variable whose calls pass that input a constant or never, and nothing writes it. Those are set
in the block's ``_bind__`` method, which runs when the block is made and again once its owner
has set the block's own constant inputs. Everything else is set at each call.
"""

from __future__ import annotations

__all__ = [
    "BIND",
    "Body",
    "Slot",
    "fixed_inputs",
    "hoisted",
    "own_fixed",
    "self_written",
    "uncopied",
]

import dataclasses
import functools
import re
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, Any

import blark.transform as tf

from plc.st.errors import STError
from plc.st.semantics.types import ArrayType, BlockType, StructType, Type

if TYPE_CHECKING:
    from plc.st.codegen.expressions import Expressions
    from plc.st.semantics.scope import Var

BIND = "_bind__"
"""The method of a user block's class that sets its inner blocks' fixed inputs (not an ST name:
IEC identifiers have no double underscore)."""

_OWN = re.compile(r"self\.\w+$")
"""An instance of the POU itself (not an array element, not a global)."""

Slot = tuple[str, str]
"""(instance code, input's Python name)."""


def _nodes(node: Any) -> Iterator[Any]:
    """Every statement and parameter in a statement tree (depth first)."""
    stack = [node]
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, list | tuple):
            stack.extend(reversed(node))
        else:
            kind: type = type(node)
            fields = _fields(kind)
            if fields:
                stack.extend(getattr(node, name) for name in reversed(fields))


@functools.cache
def _fields(cls: type) -> tuple[str, ...]:
    """The fields of a tree node's class but its position (``meta``); none for what is no
    tree node (a name, a number, a position)."""
    if not dataclasses.is_dataclass(cls) or cls is tf.Meta:
        return ()
    return tuple(f.name for f in dataclasses.fields(cls) if f.name != "meta")


class Body:
    """A POU's statements, walked once for every question this module asks of them (what
    they write, which instances they call with what, what they pass on).

    Attributes:
        x: the POU's expressions (its scope).
        statements: the POU's statements.
    """

    def __init__(self, x: Expressions, statements: Any) -> None:
        self.x = x
        self.statements = statements
        self.nodes = list(_nodes(statements))
        self._codes: dict[int, str | None] = {}
        self._written: set[str] | None = None
        self._calls: list[tuple[Var, dict[str, Any]]] | None = None
        self._passed_on: set[str] | None = None

    def code(self, node: Any) -> str | None:
        """The Python code of a variable node (of the whole variable for a part, ``w.3``),
        None where it does not translate (reported later)."""
        key = id(node)
        if key not in self._codes:
            self._codes[key] = _code(self.x, node)
        return self._codes[key]

    def written(self) -> set[str]:
        """The codes of everything the statements write (:func:`_written`)."""
        if self._written is None:
            self._written = _written(self)
        return self._written

    def calls(self) -> list[tuple[Var, dict[str, Any]]]:
        """Every call of an own block instance: the instance and its parameters by upper
        name."""
        if self._calls is None:
            self._calls = list(_own_calls(self))
        return self._calls

    def passed_on(self) -> set[str]:
        """The codes of the variables a call passes as a value (an instance passed on may be
        called elsewhere)."""
        if self._passed_on is None:
            codes = {
                self.code(node.value)
                for node in self.nodes
                if isinstance(node, tf.ParameterAssignment)
                and isinstance(node.value, tf.SimpleVariable | tf.MultiElementVariable)
            }
            self._passed_on = {c for c in codes if c is not None}
        return self._passed_on


def _code(x: Expressions, node: Any) -> str | None:
    """The Python code of a variable node (of the whole variable for a part, ``w.3``), None
    where it does not translate (reported later)."""
    try:
        e = x.variable(node)
    except (STError, AttributeError, TypeError):
        return None
    while e.part is not None:
        e = e.part[0]
    return e.code


def _instance(x: Expressions, node: tf.FunctionCallStatement) -> Var | None:
    """The block instance a call statement calls (None: a function, an array element...)."""
    name = node.name
    var = x.scope.get(str(name.name)) if isinstance(name, tf.SimpleVariable) else None
    return var if var is not None and isinstance(var.type, BlockType) else None


def _written(body: Body) -> set[str]:
    """The codes of everything a POU's statements write: assignment, S=/R= and FOR targets,
    ``=>`` outputs, what a user block's or function's in-out copies back, and every variable
    a REF() refers to (it may be written through the reference)."""
    x = body.x
    codes: set[str | None] = set()
    for node in body.nodes:
        if isinstance(node, tf.AssignmentStatement):
            codes.update(body.code(v) for v in node.variables)
        elif isinstance(node, tf.SetStatement | tf.ResetStatement):
            codes.add(body.code(node.variable))
        elif isinstance(node, tf.ForStatement):
            codes.add(body.code(node.control))
        elif isinstance(node, tf.OutputParameterAssignment):
            codes.add(body.code(node.value))
        elif isinstance(node, tf.FunctionCallStatement):
            var = _instance(x, node)
            block = var.type if var is not None else None
            members = block.members if isinstance(block, BlockType) else {}
            for p in node.parameters or []:
                if not isinstance(p.value, tf.SimpleVariable | tf.MultiElementVariable):
                    continue
                member = members.get(str(p.name.name).upper()) if p.name else None
                if member is None or (
                    member.direction == "in_out" and member.type.kind not in ("axis", "group")
                ):
                    codes.add(body.code(p.value))
        elif isinstance(node, tf.FunctionCall) and _writes_back(x, node):
            for p in node.parameters or []:
                if isinstance(p.value, tf.SimpleVariable | tf.MultiElementVariable):
                    codes.add(body.code(p.value))
    return {c.split("[")[0] for c in codes if c is not None}  # an element: the whole array


def _writes_back(x: Expressions, node: tf.FunctionCall) -> bool:
    """A call in an expression that may write its arguments: REF(), or a FUNCTION with
    VAR_IN_OUT or VAR_OUTPUT."""
    name = str(getattr(node.name, "name", node.name)).upper()
    function = x.unit.functions.get(name)
    if function is not None:
        return bool(function.in_outs or function.outputs)
    return name == "REF"


def _own_calls(body: Body) -> Iterator[tuple[Var, dict[str, Any]]]:
    """Every call of an own block instance: the instance and its parameters by upper name."""
    for node in body.nodes:
        if isinstance(node, tf.FunctionCallStatement):
            var = _instance(body.x, node)
            if var is not None and _OWN.match(var.code):
                params = node.parameters or []
                yield var, {str(p.name.name).upper(): p for p in params if p.name is not None}


def hoisted(
    body: Body,
    convert: Any,
    fixed: frozenset[str] = frozenset(),
    self_written: dict[str, set[str]] | None = None,
) -> tuple[dict[Slot, str], set[Slot]]:
    """The inputs set once: (instance code, input) → the code of its value; and every slot a
    call passes or a statement writes.

    Args:
        body: the POU's statements (with its expressions).
        convert: ``(member, value E, node) -> code`` as a call passes the input.
        fixed: the codes of the POU's own fixed inputs (``self.SetPosition``): a value that is
            one of them counts as constant.
        self_written: per user block type (upper name), the inputs its own statements write
            (:func:`self_written`): a call sets those every time.
    """
    x = body.x
    first: dict[Slot, str] = {}
    varying: set[Slot] = set()
    touched: set[Slot] = set()
    by_code = {v.code: v for v in reversed(list(x.scope.vars.values()))}  # the first wins
    for target in body.written():  # inst.Input := v: set where the program sets it
        head, _, field = target.rpartition(".")
        var = by_code.get(head)
        if var is not None and isinstance(var.type, BlockType):
            varying.add((head, field))
    touched |= varying
    for var, given in body.calls():
        assert isinstance(var.type, BlockType)
        own_writes = (self_written or {}).get(var.type.name.upper(), set())
        for key, member in var.type.members.items():
            slot = (var.code, member.python)
            p = given.get(key)
            code = None
            if member.python in own_writes:
                varying.add(slot)
            if p is not None and not isinstance(p, tf.OutputParameterAssignment):
                touched.add(slot)
                code = _constant(x, member, p, convert, fixed)
            if code is None or first.setdefault(slot, code) != code:  # a call without it too
                varying.add(slot)
    return {slot: code for slot, code in first.items() if slot not in varying}, touched


def _constant(
    x: Expressions, member: Any, p: Any, convert: Any, fixed: frozenset[str]
) -> str | None:
    """The code of an input value that is the same every scan, else None."""
    if member.direction == "output" or (
        member.direction == "in_out" and member.type.kind not in ("axis", "group")
    ):
        return None
    value = x.expr_as(p.value, member.type)
    if value.const:
        return str(convert(member, value, p))
    if value.type.kind == "axis" and value.code.startswith("_g."):
        return value.code
    if value.type.kind == "group" and _OWN.match(value.code):
        return value.code
    if value.code in fixed:
        return str(convert(member, value, p))
    return None


def _blocks_in(t: Type) -> Iterator[BlockType]:
    """The user block types a variable of type ``t`` holds (itself, an array's, a struct's)."""
    if isinstance(t, BlockType) and t.origin == "user":
        yield t
    elif isinstance(t, ArrayType):
        yield from _blocks_in(t.element)
    elif isinstance(t, StructType):
        for field_type in t.fields.values():
            yield from _blocks_in(field_type)


def self_written(blocks: Iterable[tuple[str, Body]]) -> dict[str, set[str]]:
    """Per user block type (upper name; its statements given): the members (Python names)
    its own statements write."""
    found: dict[str, set[str]] = {}
    for name, body in blocks:
        codes = [c[5:] for c in body.written() if c.startswith("self.")]
        found[name.upper()] = {c for c in codes if "." not in c}
    return found


def fixed_inputs(
    pous: Iterable[tuple[Body, bool]],
    globals_: Iterable[Var],
    self_written: dict[str, set[str]],
) -> dict[str, set[str]]:
    """Per user block type (upper name): its inputs (Python names) that every instance holds
    fixed from when its owner made it: every instance is a plain VAR of a PROGRAM or block
    whose calls pass the input the same constant or never, and nothing writes it.

    Args:
        pous: per PROGRAM, FUNCTION_BLOCK and FUNCTION: its statements (with its
            expressions), and whether it is a FUNCTION.
        globals_: the global variables.
        self_written: the members each user block type writes itself (:func:`self_written`).
    """
    fixed: dict[str, set[str]] = {}
    analysed = list(pous)
    for body, _ in analysed:  # every user block type seen
        for var in body.x.scope.vars.values():
            for block in _blocks_in(var.type):
                fixed.setdefault(block.name.upper(), set()).update(
                    m.python
                    for m in block.members.values()
                    if m.direction == "input"
                    or (m.direction == "in_out" and m.type.kind in ("axis", "group"))
                )
    for var in globals_:
        for block in _blocks_in(var.type):
            fixed[block.name.upper()] = set()
    for body, function in analysed:
        try:
            once, touched = hoisted(body, lambda m, v, p: v.code, self_written=self_written)
        except STError:  # reported where the statement is translated
            return {}
        passed_on = body.passed_on()
        for var in body.x.scope.vars.values():
            for block in _blocks_in(var.type):
                inputs = fixed.setdefault(block.name.upper(), set())
                plain = var.type is block and var.section == "local" and not function
                if not plain or not _OWN.match(var.code) or var.code in passed_on:
                    inputs.clear()
                    continue
                inputs -= {m for m in set(inputs) if (var.code, m) in touched - once.keys()}
    return fixed


def own_fixed(body: Body, name: str, fixed: dict[str, set[str]]) -> frozenset[str]:
    """The codes of block ``name``'s own fixed inputs that its own statements do not write."""
    codes = {f"self.{m}" for m in fixed.get(name.upper(), set())}
    return frozenset(codes - body.written())


def uncopied(body: Body) -> set[Slot]:
    """The array inputs a call may pass without a copy: an own instance's input (a group
    block's ``Position``) that every call of the instance passes and that no statement reads
    as ``inst.Input``. The block reads it only during its call (when every call has just set
    it), so the copy IEC makes at the call is not needed."""
    counts: dict[str, int] = {}
    passed: dict[Slot, int] = {}
    for var, given in body.calls():
        counts[var.code] = counts.get(var.code, 0) + 1
        assert isinstance(var.type, BlockType)
        for key, p in given.items():
            member = var.type.members.get(key)
            if member is not None and not isinstance(p, tf.OutputParameterAssignment):
                slot = (var.code, member.python)
                passed[slot] = passed.get(slot, 0) + 1
    read: set[str] = set()
    for node in body.nodes:
        if isinstance(node, tf.MultiElementVariable):
            code = body.code(node)
            if code is not None:
                read.add(code)
    passed_on = body.passed_on()
    return {
        slot
        for slot, n in passed.items()
        if n == counts[slot[0]]
        and f"{slot[0]}.{slot[1]}" not in read | passed_on
        and slot[0] not in passed_on
    }

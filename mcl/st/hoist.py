"""Constant block inputs set once (:func:`hoisted`): what makes a translated scan cost what the
same hand-written Python costs, which binds a block's constant inputs when it builds the block
(``mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0)``) and passes only what changes per scan.

An input of a POU's own block instance is set once, when the instance is made, if every call of
that instance in the POU passes it the same constant (or the same bound axis, or the POU's own
axes group) and no statement assigns it: a call sets it to the same value each scan, so setting
it once changes nothing the program can see. Everything else is set at each call.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import blark.transform as tf

from mcl.st.types import BlockType

if TYPE_CHECKING:
    from mcl.st.expressions import Expressions

_OWN = re.compile(r"self\.\w+$")
"""An instance of the POU itself (not an array element, not a global)."""


def _nodes(node: Any) -> Iterator[Any]:
    """Every call and assignment statement in a statement tree (depth first)."""
    if isinstance(node, tf.FunctionCallStatement | tf.AssignmentStatement):
        yield node
    if isinstance(node, list | tuple):
        for item in node:
            yield from _nodes(item)
    elif dataclasses.is_dataclass(node) and not isinstance(node, type):
        for f in dataclasses.fields(node):
            if f.name != "meta":
                yield from _nodes(getattr(node, f.name))


def hoisted(x: Expressions, body: Any, convert: Any) -> dict[tuple[str, str], str]:
    """(instance code, input's Python name) → the code of its value, for every input set once.

    Args:
        x: the POU's expressions (its scope).
        body: the POU's statements.
        convert: ``(member, value E, node) -> code`` as a call passes the input.
    """
    first: dict[tuple[str, str], str] = {}
    varying: set[tuple[str, str]] = set()
    for node in _nodes(body):
        if isinstance(node, tf.AssignmentStatement):
            for target in node.variables:  # inst.Input := v: set where the program sets it
                head, _, field = str(target).rpartition(".")
                var = x.scope.get(head) if head else None
                if var is not None and isinstance(var.type, BlockType):
                    found = var.type.members.get(field.upper())
                    varying.add((var.code, found.python if found else field))
            continue
        name = node.name
        var = x.scope.get(str(name.name)) if isinstance(name, tf.SimpleVariable) else None
        if var is None or not isinstance(var.type, BlockType) or not _OWN.match(var.code):
            continue
        given = {str(p.name.name).upper(): p for p in node.parameters or [] if p.name is not None}
        for key, member in var.type.members.items():
            slot = (var.code, member.python)
            p = given.get(key)
            code = None
            if p is not None and not isinstance(p, tf.OutputParameterAssignment):
                code = _constant(x, member, p, convert)
            if code is None or first.setdefault(slot, code) != code:
                varying.add(slot)
    return {slot: code for slot, code in first.items() if slot not in varying}


def _constant(x: Expressions, member: Any, p: Any, convert: Any) -> str | None:
    """The code of an input value that is the same every scan, else None."""
    if member.direction == "output" or (
        member.direction == "in_out" and member.type.kind not in ("axis", "group")
    ):
        return None
    value = x.expr(p.value)
    if value.const:
        return str(convert(member, value, p))
    if value.type.kind == "axis" and value.code.startswith("_g."):
        return value.code
    if value.type.kind == "group" and _OWN.match(value.code):
        return value.code
    return None

"""A call statement: a block invocation ``inst(In := x, InOut := v, Out => y)`` or a function
called for its effect.

A block is called by setting its inputs and calling it (as hand-written Python does:
``move.Execute = start; move()``); inputs left out keep their last value, inputs that are the
same every scan are set once (:mod:`plc.st.codegen.hoist`), the ``=>`` outputs are copied after the
call. An in-out of a user block is copied in before the
call and back after it.
"""

from __future__ import annotations

__all__ = ["invoke"]

from typing import TYPE_CHECKING, Any

import blark.transform as tf

from plc.st.codegen.access import store
from plc.st.codegen.expressions import E
from plc.st.errors import indefinite, nearest
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import BlockType, Member

if TYPE_CHECKING:
    from plc.st.codegen.statements import Statements


def invoke(st: Statements, s: tf.FunctionCallStatement) -> None:
    """Emit the call statement ``s``."""
    x = st.x
    head = s.name
    if isinstance(head, tf.SimpleVariable) and x.scope.get(str(head.name)) is None:
        if x.unit.block_named(str(head.name)) is not None:
            raise x.error(s, f"{head.name} is a block type", "an instance of it (declared in VAR)")
        st.out.emit(x.calls.function(s).code)
        return
    inst = x.variable(head)
    block = inst.type
    if not isinstance(block, BlockType):
        raise x.error(
            s, f"{head} is {indefinite(block.name)}, not a block instance", "a block instance"
        )
    inputs: list[tuple[Member, str]] = []
    outputs: list[tuple[Member, E]] = []
    in_outs: list[tuple[Member, E]] = []
    for p in s.parameters or []:
        if p.name is None:
            raise x.error(p, "an input without its name", "Name := value")
        member = _member(st, block, p)
        if isinstance(p, tf.OutputParameterAssignment):
            if member.direction != "output":
                raise x.error(p, f"{member.python} is not an output", f"{member.python} := value")
            outputs.append((member, st.target(p.value)))
            continue
        if member.direction == "output":
            raise x.error(p, f"{member.python} is an output", f"{member.python} => variable")
        value = x.expr_as(p.value, member.type)
        copy = (inst.code, member.python) not in st.uncopied
        inputs.append((member, _input(st, member, value, p, copy)))
        if member.direction == "in_out" and block.origin == "user" and member.type.kind != "axis":
            in_outs.append((member, st.target(p.value)))
    ref = inst.code
    inputs = [(m, c) for m, c in inputs if (ref, m.python) not in st.hoisted]
    if len(inputs) + len(outputs) > 1 and not ref.isidentifier():
        temp = st.temp()
        st.out.emit(f"{temp} = {ref}")
        ref = temp
    for member, code in inputs:
        st.out.emit(f"{ref}.{member.python} = {code}")
    # a Python class's scan as a method call: in the interpreter cheaper than calling the instance
    st.out.emit(f"{ref}.__call__()" if block.origin in ("user", "std") else f"{ref}()")
    for member, target in [*outputs, *in_outs]:
        value = E(f"{ref}.{member.python}", member.type)
        st.out.emit(store(target, x.convert(value, target.type, s)))


def _member(st: Statements, block: BlockType, p: Any) -> Member:
    """The member a parameter names (case-insensitive), or an error with the nearest names."""
    name = str(p.name.name)
    member = block.members.get(name.upper())
    if member is None:
        valid = [m.python for m in block.members.values() if m.direction != "local"]
        close = nearest(name, valid)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise st.x.error(p, f"{block.name} has no input or output {name!r}{hint}", ", ".join(valid))
    if member.direction == "local":
        raise st.x.error(p, f"{member.python} is internal to {block.name}", "an input or output")
    return member


def _input(st: Statements, member: Member, value: E, p: Any, copy: bool) -> str:
    """The code of an input value (a group block's per-member values as a tuple, or the array
    itself where ``copy`` is not needed)."""
    if member.type is T.SEQUENCE and isinstance(value.type, T.ArrayType):
        return f"tuple({value.code})" if copy else value.code
    return st.x.convert(value, member.type, p)

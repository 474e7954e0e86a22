"""Access to a part of a variable and through a reference (IEC 61131-3 3rd edition): partial
access ``w.%X3``, ``w.3``, ``d.%B1`` (6.6.1.3), dereference ``r^`` and ``REF(x)``
(6.4.4.10); and the Python that writes any variable access, as a statement or inside an
expression (:func:`store`, :func:`store_expression`).

A bit or byte of a variable is read by shifting and masking its value, and written by storing
the whole variable with that part replaced. A REF_TO value is a
:class:`plc.st.runtime.functions.Ref` to the variable's owner (the program, a block, the
globals, a STRUCT, an ARRAY) and its attribute or index; ``r^`` reads and writes ``r.v``.
"""

from __future__ import annotations

__all__ = ["dereference", "partial", "reference", "store", "store_expression"]

import re
from typing import TYPE_CHECKING, Any

from plc.st.errors import indefinite
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import Elementary

if TYPE_CHECKING:
    from plc.st.codegen.expressions import E, Expressions

_PARTS = {"X": (1, T.BOOL), "B": (8, T.ELEMENTARY["BYTE"]), "W": (16, T.ELEMENTARY["WORD"])}
_PARTS |= {"D": (32, T.ELEMENTARY["DWORD"]), "L": (64, T.ELEMENTARY["LWORD"])}
"""Partial access prefix → (width [bits], type of the part)."""

_PARTIAL = re.compile(r"%([XBWDL])(\d+)$", re.IGNORECASE)


def partial(x: Expressions, base: E, selector: Any, node: Any) -> E:
    """``base.%X3`` / ``base.3`` (a bit), ``base.%B1`` (a byte), ...: the part of an integer
    or bit string, readable and writable (:attr:`E.part`)."""
    from plc.st.codegen.expressions import E

    text = str(selector)
    found = _PARTIAL.match(text)
    prefix, index = (found.group(1).upper(), int(found.group(2))) if found else ("X", int(text))
    width, part_type = _PARTS[prefix]
    t = base.type
    if not (isinstance(t, Elementary) and t.integral and t.bits):
        raise x.error(node, f"{t.name} has no bit {text}", "a bit string or an integer")
    count = t.bits // width
    if not 0 <= index < count:
        what = "bit" if width == 1 else f"part %{prefix}"
        raise x.error(node, f"{t.name} has no {what} {index}", f"0..{count - 1}")
    shift = index * width
    if width == 1:
        code = f"(({base.code} >> {shift}) & 1 != 0)"
    else:
        code = f"(({base.code} >> {shift}) & {(1 << width) - 1})"
    return E(code, part_type, part=(base, shift, width))


def dereference(x: Expressions, base: E, node: Any) -> E:
    """``r^``: the variable a REF_TO refers to (NULL: a fault when read or written)."""
    from plc.st.codegen.expressions import E

    if not isinstance(base.type, T.ReferenceType) or base.type is T.NULL:
        raise x.error(
            node, f"{node} dereferences {indefinite(base.type.name)}", "a REF_TO variable"
        )
    return E(f"{base.code}.v", base.type.target)


def reference(x: Expressions, target: E, node: Any) -> E:
    """``REF(x)``: a reference to variable ``x`` (of a PROGRAM, FUNCTION_BLOCK, the globals, or
    an element or field of one)."""
    from plc.st.codegen.expressions import E

    code = target.code
    owner, key = _owner(code)
    if target.const or target.part is not None or owner is None or target.type.kind == "axis":
        raise x.error(
            node,
            f"REF of {node} (a constant, a part of a variable or a variable that ends with the "
            "call: VAR_TEMP, a FUNCTION's)",
            "a variable of a PROGRAM, FUNCTION_BLOCK or VAR_GLOBAL",
        )
    return E(f"_f.Ref({owner}, {key})", T.ReferenceType(f"REF_TO {target.type.name}", target.type))


def _owner(code: str) -> tuple[str | None, str]:
    """The owner and key of an assignable access ``a.b`` (``a``, ``'b'``) or ``a[i]`` (``a``,
    ``i``); (None, "") for a local name."""
    if code.endswith("]"):
        start = _opening(code)
        return code[:start], code[start + 1 : -1]
    head, dot, attr = code.rpartition(".")
    return (head, repr(attr)) if dot else (None, "")


def _opening(code: str) -> int:
    """The position of the ``[`` that the final ``]`` of ``code`` closes."""
    depth = 0
    for i in range(len(code) - 1, -1, -1):
        depth += {"]": 1, "[": -1}.get(code[i], 0)
        if depth == 0:
            return i
    raise ValueError(code)


def store(target: E, value: str) -> str:
    """The Python statement storing ``value`` (code, already of the target's type) into the
    variable access ``target``."""
    if target.part is not None:
        return store(*_whole(target, value))
    return f"{target.code} = {value}"


def store_expression(target: E, value: str) -> str:
    """A Python expression storing ``value`` into ``target`` (for a store inside an
    expression: a FUNCTION's VAR_OUTPUT and VAR_IN_OUT after the call)."""
    if target.part is not None:
        return store_expression(*_whole(target, value))
    owner, key = _owner(target.code)
    if owner is None:
        return f"({target.code} := {value})"
    if target.code.endswith("]"):
        return f"{owner}.__setitem__({key}, {value})"
    return f"setattr({owner}, {key}, {value})"


def _whole(target: E, value: str) -> tuple[E, str]:
    """The variable a part belongs to, and its new value with the part replaced."""
    base, shift, width = target.part  # type: ignore[misc]
    t = base.type
    assert isinstance(t, Elementary)
    code = f"_f.set_bits({base.code}, {shift}, {width}, {value})"
    return base, T.wrap_code(code, t) if t.signed else code

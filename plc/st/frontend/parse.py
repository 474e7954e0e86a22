"""Parse IEC 61131-3 Structured Text with blark into its typed tree (line and column on every
node); a syntax error is one :class:`~plc.st.errors.STError` naming ``file:line:column``.

blark's grammar (TwinCAT's flavour) lacks the IEC exponent operator ``**``; it is added here as
its own level between the unary operators and ``*``/``/``/``MOD`` (IEC 61131-3 ed. 3, Tab. 71),
left-associative like every IEC operator. It also lacks IEC's CONFIGURATION (B.1.7): added here
as CONFIGURATION, RESOURCE ... ON, TASK (name and ``:=`` items) and PROGRAM ... WITH; its nodes
stay lark trees (read by :mod:`plc.st.runtime.task`).
"""

from __future__ import annotations

__all__ = ["parse", "parser"]

import dataclasses
import importlib.resources
import re
from functools import cache
from pathlib import Path
from typing import Any

import blark.transform as tf
import lark
from blark import util

from plc.st.errors import STError
from plc.st.frontend import tree_cache

_TERM = "expression_term: unary_expression ( MULTIPLY_OPERATOR unary_expression )*"
_POWER = (
    "expression_term: power_expression ( MULTIPLY_OPERATOR power_expression )*\n"
    "power_expression: unary_expression ( POWER_OPERATOR unary_expression )*\n"
    'POWER_OPERATOR: "**"\n'
)
_LIBRARY = "_library_element_declaration: data_type_declaration"
_CONFIGURATION = r"""
configuration_declaration: _CONFIGURATION IDENTIFIER _configuration_body _END_CONFIGURATION ";"*
_configuration_body: [ global_var_declarations ] resource_declaration+
resource_declaration: _RESOURCE IDENTIFIER _ON IDENTIFIER _resource_body _END_RESOURCE ";"*
_resource_body: [ global_var_declarations ] task_configuration* program_configuration*
task_configuration: _TASK IDENTIFIER "(" task_initialization ( "," task_initialization )* ")" ";"+
task_initialization: IDENTIFIER ":=" expression
program_configuration: _PROGRAM IDENTIFIER [ _WITH IDENTIFIER ] ":" IDENTIFIER ";"+
_CONFIGURATION: /\bCONFIGURATION\b/i
_END_CONFIGURATION: /\bEND_CONFIGURATION\b/i
_RESOURCE: /\bRESOURCE\b/i
_END_RESOURCE: /\bEND_RESOURCE\b/i
_ON: /\bON\b/i
_TASK: /\bTASK\b/i
_WITH: /\bWITH\b/i
"""
_STARTS = ["iec_source"]
_WORD = re.compile(r"\w+|\S")

_READABLE = {
    "SEMICOLON": "';'",
    "ASSIGNMENT": "':='",
    "IDENTIFIER": "a name",
    "LPAR": "'('",
    "RPAR": "')'",
    "COMMA": "','",
    "COLON": "':'",
}
"""Names for the grammar's terminals in messages."""


class _Transformer(tf.GrammarTransformer):
    """blark's transformer, with the ``**`` level as a binary operation."""

    power_expression = tf._annotator_wrapper(tf.BinaryOperation.from_lark)


@cache
def parser() -> lark.Lark:
    """blark's Earley parser with ``**`` (built once per process)."""
    grammar = importlib.resources.files("blark").joinpath("iec.lark").read_text()
    if _TERM not in grammar or _LIBRARY not in grammar:
        raise RuntimeError("blark's grammar changed: pin the version pyproject.toml names")
    return lark.Lark(
        _extended(grammar),
        parser="earley",
        maybe_placeholders=True,
        propagate_positions=True,
        start=_STARTS,
        import_paths=[str(importlib.resources.files("blark"))],
    )


def _extended(grammar: str) -> str:
    """blark's grammar with ``**`` and CONFIGURATION."""
    library = _LIBRARY + " | configuration_declaration"
    return grammar.replace(_TERM, _POWER).replace(_LIBRARY, library) + _CONFIGURATION


def parse(source: str, filename: str) -> tf.SourceCode:
    """The typed tree of ``source`` (parsed once: kept on disk by
    :mod:`plc.st.frontend.tree_cache`).

    Raises:
        STError: a syntax error, ``filename:line:column: ...; expected ...``.
    """
    name = tree_cache.key(source, filename, _parser_identity())
    tree: tf.SourceCode = tree_cache.cached(name, lambda: _parse(source, filename))
    return tree


@cache
def _parser_identity() -> bytes:
    """What changes when the grammar or the transformer does: this module's own code."""
    return Path(__file__).read_bytes()


def _parse(source: str, filename: str) -> tf.SourceCode:
    comments, cleaned = util.find_and_clean_comments(source)
    try:
        tree = parser().parse(cleaned, start="iec_source")
    except lark.UnexpectedInput as error:
        raise STError.at(
            f"{filename}:{error.line}:{error.column}", _found(error, cleaned), _expected(error)
        ) from None
    transformer = _Transformer(comments=comments, fn=filename, source_code=source)
    result: Any = transformer.transform(tree)
    _untangle(result)
    if not isinstance(result, tf.SourceCode):
        raise STError.at(f"{filename}:1:1", "no program", "PROGRAM, FUNCTION_BLOCK or FUNCTION")
    return result


def _untangle(node: Any) -> None:
    """Undo an ambiguity of blark's grammar, in place: in ``(A := 1.0, B := 2.0, C := 3.0)``
    it may read ``1.0, B := 2.0`` as a bare array of A (TwinCAT's ``:=`` as an operator);
    such an element is split back into ``A := 1.0`` and ``B := 2.0``."""
    if isinstance(node, list):
        for item in node:
            _untangle(item)
        return
    if not dataclasses.is_dataclass(node) or isinstance(node, type):
        return
    if isinstance(node, tf.StructureInitialization):
        node.elements = [part for e in node.elements for part in _split(e)]
    for f in dataclasses.fields(node):
        if f.name != "meta":
            _untangle(getattr(node, f.name))


def _split(element: Any) -> list[Any]:
    """One structure element, or the elements a bare array of ``name := value`` hides."""
    value = getattr(element, "value", None)
    if not isinstance(value, tf.ArrayInitialization) or value.brackets:
        return [element]
    items = _flat(value)
    rest = items[1:]
    if not rest or not all(_is_assignment(i) for i in rest):
        return [element]
    parts = [dataclasses.replace(element, value=items[0])]
    for item in rest:
        parts.append(tf.StructureElementInitialization(item.left.name, item.right, item.meta))
    return parts


def _flat(array: Any) -> list[Any]:
    """The items of a bare array, its nested bare arrays opened."""
    items: list[Any] = []
    for i in array.elements:
        inner = i.element
        if isinstance(inner, tf.ArrayInitialization) and not inner.brackets and i.count is None:
            items += _flat(inner)
        else:
            items.append(inner)
    return items


def _is_assignment(node: Any) -> bool:
    """``name := value`` read as an expression."""
    return (
        isinstance(node, tf.BinaryOperation)
        and str(node.op) == ":="
        and isinstance(node.left, tf.SimpleVariable)
    )


def _found(error: lark.UnexpectedInput, text: str) -> str:
    """What the parser met."""
    if isinstance(error, lark.UnexpectedToken):
        token = error.token
        return (
            "unexpected end of the source" if token.type == "$END" else f"unexpected {str(token)!r}"
        )
    if isinstance(error, lark.UnexpectedCharacters):
        word = _WORD.match(text, error.pos_in_stream or 0)
        return f"unexpected {word.group() if word else error.char!r}"
    return "unexpected end of the source"


def _expected(error: lark.UnexpectedInput) -> str:
    """What would have been valid there, in words."""
    names: set[str] = set(getattr(error, "expected", None) or getattr(error, "allowed", ()) or ())
    if {"IDENTIFIER", "INTEGER"} <= names or {"IDENTIFIER", "SIGNED_INTEGER"} <= names:
        return "an expression"
    words = sorted({_READABLE.get(n) or _pattern(n) for n in names} - {""}, key=_closing_first)
    return ", ".join(words[:8]) if words else "a valid statement"


def _closing_first(word: str) -> tuple[bool, str]:
    """Order of the expected words: the closing keywords (``'END_IF'``) first."""
    return not word.startswith("'END_"), word


def _pattern(terminal: str) -> str:
    """A terminal as its literal text (``'END_IF'``), or its name in lower case."""
    try:
        pattern = parser().get_terminal(terminal).pattern
    except KeyError:
        return terminal.lower()
    if terminal.startswith("_"):
        return repr(terminal[1:].upper())
    if isinstance(pattern, lark.lexer.PatternStr):
        return repr(pattern.value)
    text = pattern.value
    return repr(text.split("|")[0].strip("()?:i")) if text.isupper() else terminal.lower()

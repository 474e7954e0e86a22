"""A source cut into its top-level items (each PROGRAM, FUNCTION_BLOCK, FUNCTION, TYPE,
VAR_GLOBAL and CONFIGURATION with the comments before it), so that each parses, is kept and is
found again on its own (:mod:`plc.st.frontend.parse`): a changed POU parses again, the others
come from the cache; and a parsed item's positions moved to where it stands in the source.

The cut is made on whole lines, outside comments and strings; a source it cannot cut cleanly
(anything between the items, two items sharing a line, TwinCAT's METHODs) is one piece.
"""

from __future__ import annotations

__all__ = ["Chunk", "chunks", "shifted"]

import re
from dataclasses import dataclass
from typing import Any

import blark.transform as tf
import lark
from blark import util

_ENDS = {
    "PROGRAM": "END_PROGRAM",
    "FUNCTION_BLOCK": "END_FUNCTION_BLOCK",
    "FUNCTIONBLOCK": "END_FUNCTIONBLOCK",
    "FUNCTION": "END_FUNCTION",
    "TYPE": "END_TYPE",
    "VAR_GLOBAL": "END_VAR",
    "CONFIGURATION": "END_CONFIGURATION",
}
"""The keywords that open an item and the one that closes it."""

_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|[^\sA-Za-z_;]")
_STRING = re.compile(r"'(?:\$.|[^'$])*'|\"(?:\$.|[^\"$])*\"", re.S)
_LINE_FIELDS = ("line", "end_line", "container_line", "container_end_line")
_POS_FIELDS = ("start_pos", "end_pos")


@dataclass(frozen=True)
class Chunk:
    """A piece of a source.

    Attributes:
        text: its text, whole lines.
        line: the source line it begins on (from 1).
        offset: the source character it begins at (from 0).
    """

    text: str
    line: int
    offset: int


def chunks(source: str) -> list[Chunk]:
    """``source`` cut into its items (one piece if it cannot be cut cleanly)."""
    scan = _blanked(source)
    starts = _line_starts(source)
    ends: list[int] = []  # the line each item ends on
    position = 0
    while True:
        word = _WORD.search(scan, position)
        if word is None:
            break
        closing = _ENDS.get(word.group().upper())
        if closing is None:
            return [Chunk(source, 1, 0)]
        end = re.compile(rf"\b{closing}\b", re.I).search(scan, word.end())
        if end is None:
            return [Chunk(source, 1, 0)]
        line = _line_of(starts, end.end() - 1)
        if ends and _line_of(starts, word.start()) <= ends[-1]:
            return [Chunk(source, 1, 0)]  # two items share a line
        ends.append(line)
        position = end.end()
    if len(ends) < 2:
        return [Chunk(source, 1, 0)]
    ends[-1] = len(starts)  # the last piece takes what follows
    pieces, first = [], 1
    for last in ends:
        begin = starts[first - 1]
        stop = starts[last] if last < len(starts) else len(source)
        pieces.append(Chunk(source[begin:stop], first, begin))
        first = last + 1
    return pieces


def _blanked(source: str) -> str:
    """``source`` with its comments, pragmas and strings blanked (line breaks kept)."""
    chars = list(source)
    comments, _ = util.find_and_clean_comments(source)
    for comment in comments:
        for i in range(comment.start_pos or 0, comment.end_pos or 0):
            if chars[i] != "\n":
                chars[i] = " "
    return _STRING.sub(lambda m: _blank(m.group()), "".join(chars))


def _blank(text: str) -> str:
    return re.sub(r"[^\n]", " ", text)


def _line_starts(source: str) -> list[int]:
    """The character each line begins at."""
    return [0] + [i + 1 for i, c in enumerate(source) if c == "\n" and i + 1 < len(source)]


def _line_of(starts: list[int], position: int) -> int:
    """The line (from 1) of a character."""
    low, high = 0, len(starts)
    while high - low > 1:
        middle = (low + high) // 2
        if starts[middle] <= position:
            low = middle
        else:
            high = middle
    return low + 1


def shifted(tree: Any, lines: int, chars: int) -> Any:
    """``tree`` (a parsed piece) with every position moved by ``lines`` and ``chars``, in
    place: where the piece stands in the source."""
    if lines or chars:
        _shift(tree, lines, chars, set())
    return tree


def _shift(tree: Any, lines: int, chars: int, seen: set[int]) -> None:
    """Every position under ``tree`` moved: blark's nodes (dataclasses) and their ``meta``,
    lark's trees and tokens, in lists and tuples; each object once."""
    stack = [tree]
    while stack:
        node = stack.pop()
        kind = type(node)
        if kind in _ATOMS or id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, lark.Token):
            _move(node, lines, chars)
        elif kind is list or kind is tuple:
            stack.extend(node)
        elif isinstance(node, lark.Tree):
            stack.append(node._meta)
            stack.extend(node.children)
        elif isinstance(node, lark.tree.Meta):
            _move(node, lines, chars)
        elif hasattr(kind, "__dataclass_fields__"):
            if kind is tf.Meta:
                _move(node, lines, chars)
            stack.extend(vars(node).values())


_ATOMS = frozenset({str, int, float, bool, type(None)})
"""What holds no position."""


def _move(node: Any, lines: int, chars: int) -> None:
    """One position's lines and characters moved."""
    for name, by in [*((n, lines) for n in _LINE_FIELDS), *((n, chars) for n in _POS_FIELDS)]:
        value = getattr(node, name, None)
        if isinstance(value, int) and not isinstance(value, bool):
            setattr(node, name, value + by)

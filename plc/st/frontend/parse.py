"""Parse IEC 61131-3 Structured Text with blark into its typed tree (line and column on every
node); a syntax error is one :class:`~plc.st.errors.STError` naming ``file:line:column``.

blark's grammar (TwinCAT's flavour) is extended to the IEC constructs it lacks (``**``,
CONFIGURATION, several types per TYPE block, REF_TO, ...) by :mod:`plc.st.frontend.grammar`.
"""

from __future__ import annotations

__all__ = ["jobs", "parse", "parse_each", "parse_kept", "parse_piece", "parser"]

import dataclasses
import importlib.resources
import os
import pickle
import re
import subprocess
import sys
from functools import cache
from pathlib import Path
from typing import Any

import blark.transform as tf
import lark
from blark import util

from plc.st.errors import STError, place
from plc.st.frontend import chunks, grammar, lalr, tree_cache
from plc.st.frontend.missing import missing_part
from plc.st.frontend.reserved import reserved_name
from plc.st.frontend.unclosed import unclosed
from plc.st.frontend.wording import (
    equals_as_assignment,
    micros_in_time,
    missing_semicolon,
    terminal_words,
)

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


@cache
def parser() -> lark.Lark:
    """blark's Earley parser with the IEC extensions of :mod:`plc.st.frontend.grammar` (built
    once per process)."""
    text = importlib.resources.files("blark").joinpath("iec.lark").read_text()
    return lark.Lark(
        grammar.extended(text),
        parser="earley",
        maybe_placeholders=True,
        propagate_positions=True,
        start=_STARTS,
        import_paths=[str(importlib.resources.files("blark"))],
    )


def parse(source: str, filename: str) -> tf.SourceCode:
    """The typed tree of ``source``, parsed item by item (:mod:`~plc.st.frontend.chunks`): an
    item parsed before comes from the cache (:mod:`~plc.st.frontend.tree_cache`), the others
    by the LALR parser here, and what it cannot read in parallel processes when there are
    several (:func:`jobs`).

    Raises:
        STError: a syntax error, ``filename:line:column: ...; expected ...``.
    """
    pieces = _pieces(source)
    work = [
        (c.text, filename, c.line, c.offset, tree_cache.key(c.text, filename, _parser_identity()))
        for c in pieces
    ]
    trees: list[Any] = [_kept(piece) for piece in work]
    for i, tree in enumerate(trees):  # the fast parser here first: a worker starts slower
        if tree is None:
            trees[i] = _parse_fast(*work[i])
    missing = [i for i, tree in enumerate(trees) if tree is None]
    for i, tree in zip(missing, _parse_all([work[i] for i in missing]), strict=True):
        trees[i] = tree
    items = []
    for tree in trees:
        items += tree.items
    return tf.SourceCode(items, Path(filename), source, trees[0].line_map, trees[0].meta)


def parse_each(source: str, filename: str) -> list[tuple[chunks.Chunk, tf.SourceCode | STError]]:
    """Each item of ``source`` (:func:`_pieces`) parsed on its own, in this process: its tree,
    or its syntax error (a mistake in one item hides none in another)."""
    parsed: list[tuple[chunks.Chunk, tf.SourceCode | STError]] = []
    for c in _pieces(source):
        try:
            parsed.append((c, parse_piece(c, filename)))
        except STError as error:
            parsed.append((c, error))
    return parsed


def parse_piece(piece: chunks.Chunk, filename: str) -> tf.SourceCode:
    """One piece of a source parsed (from the cache, else by the LALR parser, else by the
    Earley parser), its positions where it stands in the file.

    Raises:
        STError: a syntax error in it.
    """
    name = tree_cache.key(piece.text, filename, _parser_identity())
    work = (piece.text, filename, piece.line, piece.offset, name)
    return _kept(work) or _parse_fast(*work) or parse_kept(*work)


def _pieces(source: str) -> list[chunks.Chunk]:
    """``source`` cut into its items (:func:`~plc.st.frontend.chunks.chunks`), the cut kept in
    the cache: finding a source's comments and strings takes longer than loading its kept
    trees."""
    name = tree_cache.key(source, "", _parser_identity())
    cut = tree_cache.cached(
        name, lambda: [(c.line, c.offset) for c in chunks.chunks(source)], "cut"
    )
    ends = [offset for _, offset in cut[1:]] + [len(source)]
    return [
        chunks.Chunk(source[offset:end], line, offset)
        for (line, offset), end in zip(cut, ends, strict=True)
    ]


def jobs() -> int:
    """The processes that parse a source's items (``$MCL_ST_JOBS``, default the CPUs this
    process may use)."""
    configured = os.environ.get("MCL_ST_JOBS", "").strip()
    if configured.isdigit() and int(configured) > 0:
        return int(configured)
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)


_PARALLEL_LINES = 200
"""Below this many lines to parse, one process parses them (a worker builds its parser first:
about a second)."""


def _parse_all(work: list[Piece]) -> list[tf.SourceCode]:
    """The trees of the pieces ``work``, each kept in the cache: in worker processes
    (:mod:`plc.st.frontend.worker`, the longest pieces shared out first) when there are
    several and enough lines, else here; what a worker fails to return is parsed here.

    Raises:
        STError: a syntax error in a piece.
    """
    workers = min(jobs(), len(work))
    if workers < 2 or sum(text.count("\n") for text, *_ in work) < _PARALLEL_LINES:
        return [parse_kept(*piece) for piece in work]
    shares: list[list[int]] = [[] for _ in range(workers)]
    loads = [0] * workers
    for i in sorted(range(len(work)), key=lambda i: -len(work[i][0])):
        least = loads.index(min(loads))
        shares[least].append(i)
        loads[least] += len(work[i][0])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([_ROOT, os.environ.get("PYTHONPATH", "")])}
    command = [sys.executable, "-m", "plc.st.frontend.worker"]
    processes = []
    for share in shares:
        share.sort()  # in the file's order: a worker's first error is its earliest
        process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
        assert process.stdin is not None
        process.stdin.write(pickle.dumps([work[i] for i in share]))
        process.stdin.close()
        processes.append(process)
    trees: dict[int, Any] = {}
    for share, process in zip(shares, processes, strict=True):
        assert process.stdout is not None
        out = process.stdout.read()
        process.wait()
        try:
            trees.update(zip(share, pickle.loads(out), strict=False))
        except Exception:  # the worker died: its pieces parse here
            continue
    errors = [trees[i] for i in sorted(trees) if isinstance(trees[i], str)]
    if errors:
        raise STError(errors[0])
    return [trees[i] if i in trees else parse_kept(*work[i]) for i in range(len(work))]


Piece = tuple[str, str, int, int, str]
"""A piece to parse: its text, the file name, its first line and its first character in the
file, its cache name."""

_ROOT = str(Path(__file__).resolve().parents[3])
"""The folder the ``plc`` package is in (a worker imports it from there)."""


def parse_kept(text: str, filename: str, line: int, offset: int, name: str) -> tf.SourceCode:
    """One piece parsed, its positions where it stands in the file (its first line ``line``,
    its first character ``offset``), and kept in the cache as ``name``."""
    tree: tf.SourceCode = _parse(text, filename, line - 1)
    return _placed(tree, line, offset, name)


def _parse_fast(
    text: str, filename: str, line: int, offset: int, name: str
) -> tf.SourceCode | None:
    """:func:`parse_kept` by the LALR parser alone: None where it cannot read the piece (an
    error is left to the full parse, which reports the file's first)."""
    try:
        tree: tf.SourceCode | None = _parse(text, filename, line - 1, fast=True)
    except STError:
        return None
    return None if tree is None else _placed(tree, line, offset, name)


_PLACE = "_st_place"
"""The attribute of a kept tree that holds where its positions stand: (first line, first
character) of the piece in its file (not a field of the tree: trees compare without it)."""


def _placed(tree: tf.SourceCode, line: int, offset: int, name: str) -> tf.SourceCode:
    """A piece's tree parsed on its own moved to where it stands in the file (its first line
    ``line``, its first character ``offset``), kept in the cache as ``name`` with its place."""
    chunks.shifted(tree, line - 1, offset)
    vars(tree)[_PLACE] = (line, offset)
    tree_cache.store(name, tree)
    return tree


def _kept(piece: Piece) -> tf.SourceCode | None:
    """A piece's tree from the cache, moved to where the piece stands now (kept again where it
    moved, so that the next load need not move it); None if it is not kept."""
    _, _, line, offset, name = piece
    tree = tree_cache.load(name)
    if not isinstance(tree, tf.SourceCode):
        return None
    kept_line, kept_offset = vars(tree).get(_PLACE, (1, 0))
    if (kept_line, kept_offset) != (line, offset):
        chunks.shifted(tree, line - kept_line, offset - kept_offset)
        vars(tree)[_PLACE] = (line, offset)
        tree_cache.store(name, tree)
    return tree


@cache
def _parser_identity() -> bytes:
    """What changes when the grammar or the transformer does: this module's, the grammar's and
    the cutting's code."""
    modules = (sys.modules[__name__], grammar, chunks, lalr)
    return b"".join(Path(str(m.__file__)).read_bytes() for m in modules)


def _parse(source: str, filename: str, lines_before: int = 0, fast: bool = False) -> Any:
    """The tree of ``source``, its positions as in ``source``, read by the LALR parser
    (:mod:`~plc.st.frontend.lalr`) or, where it cannot and not ``fast``, by the Earley parser
    (``fast``: None then); an error names its line in the file (``lines_before`` the lines
    before it there)."""
    comments, cleaned = util.find_and_clean_comments(source)
    try:
        tree = lalr.parse(cleaned)
        if tree is None:
            if fast:
                return None
            tree = parser().parse(cleaned, start="iec_source")
    except lark.UnexpectedInput as error:
        raise _syntax_error(error, cleaned, filename, lines_before) from None
    _no_empty_input(tree, filename, lines_before)
    transformer = grammar.Transformer(comments=comments, fn=filename, source_code=source)
    result: Any = transformer.transform(tree)
    if isinstance(result, tf.SourceCode):  # a TYPE block of several types: one item each
        result.items = [i for item in result.items for i in _listed(item)]
        _configuration_pragmas(result.items, comments)
    _untangle(result)
    if not isinstance(result, tf.SourceCode):
        where = f"{filename}:{lines_before + 1}:1"
        raise STError.at(where, "no program", "PROGRAM, FUNCTION_BLOCK or FUNCTION")
    return result


def _no_empty_input(tree: lark.Tree[Any], filename: str, lines_before: int) -> None:
    """Raises STError at a call's input given no value (``TON(IN := , PT := T#1s)``): the
    grammar takes it, no translation could."""
    for node in tree.iter_subtrees():
        if node.data in _INPUTS and len(node.children) == 2 and node.children[1] is None:
            name = node.children[0]
            where = f"{filename}:{name.meta.line + lines_before}:{name.meta.column}"
            raise STError.at(
                where,
                f"the input {_name(name)} has no value",
                f"{_name(name)} := value, or no {_name(name)} := at all",
            )


_INPUTS = frozenset({"param_assignment", "input_param_assignment"})
"""The grammar's rules of a call's input (``IN := value``; its value may be left out)."""


def _name(node: Any) -> str:
    """The text of a name's tree (``variable_name``: its IDENTIFIER)."""
    return str(node.children[0])


def _configuration_pragmas(items: list[Any], comments: list[lark.Token]) -> None:
    """Give a CONFIGURATION's and its RESOURCEs' VAR_GLOBAL blocks the pragmas on the lines
    just before them (blark gives them to the items it makes alone), in place."""
    pragmas = {t.end_line: t for t in comments if t.type == "PRAGMA" and t.end_line}
    for item in items:
        if not isinstance(item, lark.Tree):
            continue
        for tree in [item, *item.find_data("resource_declaration")]:
            for block in tree.children:
                meta = getattr(block, "meta", None)
                if not isinstance(block, tf.GlobalVariableDeclarations) or meta is None:
                    continue
                line = meta.line - 1
                found: list[lark.Token] = []
                while line in pragmas:
                    found.insert(0, pragmas[line])
                    line = (pragmas[line].line or line) - 1
                meta.comments = found


def _listed(item: Any) -> list[Any]:
    """A list as it is, anything else as a list of one."""
    return item if isinstance(item, list) else [item]


def _untangle(node: Any) -> None:
    """Undo the ambiguities of blark's grammar, in place (TwinCAT's ``:=`` is an operator
    too): in ``(A := 1.0, B := 2.0, C := 3.0)`` it may read ``1.0, B := 2.0`` as a bare array
    of A, split back into ``A := 1.0`` and ``B := 2.0``; ``(p := (x := 1))`` may hold the
    inner structure in a bare array of one; ``(A := 1)`` may be a parenthesized assignment."""
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
            value = _structure(getattr(node, f.name))
            setattr(node, f.name, value)
            _untangle(value)


def _structure(value: Any) -> Any:
    """``(A := 1)`` read as a parenthesized assignment: the structure value it is."""
    if isinstance(value, tf.ParenthesizedExpression) and _is_assignment(value.expr):
        inner = value.expr
        element = tf.StructureElementInitialization(inner.left.name, inner.right, inner.meta)
        return tf.StructureInitialization([element], value.meta)
    return value


def _split(element: Any) -> list[Any]:
    """One structure element, or the elements a bare array of ``name := value`` hides."""
    value = getattr(element, "value", None)
    if not isinstance(value, tf.ArrayInitialization) or value.brackets:
        return [element]
    items = _flat(value)
    rest = items[1:]
    nested = tf.StructureInitialization | tf.ArrayInitialization
    if not rest and value.elements[0].count is None and isinstance(items[0], nested):
        return [dataclasses.replace(element, value=items[0])]  # (p := (x := 1, y := 2))
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
            items.append(_structure(inner))
    return items


def _is_assignment(node: Any) -> bool:
    """``name := value`` read as an expression."""
    return (
        isinstance(node, tf.BinaryOperation)
        and str(node.op) == ":="
        and isinstance(node.left, tf.SimpleVariable)
    )


def _syntax_error(
    error: lark.UnexpectedInput, text: str, filename: str, lines_before: int
) -> STError:
    """The message of a syntax error in ``text``: a part of a statement left out
    (:mod:`~plc.st.frontend.missing`), a statement left open
    (:mod:`~plc.st.frontend.unclosed`), a keyword used as a name
    (:mod:`~plc.st.frontend.reserved`), a ``;`` missing at the end of a line
    (:func:`~plc.st.frontend.wording.missing_semicolon`), else what the parser met and what it
    expected."""
    position, word, expected = _met(error, text)
    found = (
        missing_part(text, position, word, lines_before)
        or unclosed(text, position, word, expected, lines_before)
        or reserved_name(text, position, word, expected, lines_before)
        or missing_semicolon(text, position, expected, lines_before)
        or equals_as_assignment(text, position, word, expected, lines_before)
        or micros_in_time(text, position, word, lines_before)
    )
    if found is not None:
        return STError(f"{filename}:{found[0]}:{found[1]}: {found[2]}")
    line, column = place(text, position)
    met = f"unexpected {word!r}" if word else "unexpected end of the source"
    return STError.at(f"{filename}:{line + lines_before}:{column}", met, _expected(expected))


def _met(error: lark.UnexpectedInput, text: str) -> tuple[int, str, set[str]]:
    """Where in ``text`` the Earley parser met what it did not expect, that word (``""`` at the
    end of the text, placed at the end of its last line), and the terminals it expected."""
    if isinstance(error, lark.UnexpectedCharacters):
        position = error.pos_in_stream or 0
        match = _WORD.match(text, position)
        assert match is not None
        return position, match[0], set(error.allowed)
    assert isinstance(error, lark.UnexpectedEOF)
    return len(text.rstrip()), "", set(error.expected)


def _expected(names: set[str]) -> str:
    """What would have been valid there (the terminals ``names``), in words: the first eight."""
    if "IDENTIFIER" in names and "INTEGER" in names:
        return "an expression"
    words = sorted({_READABLE.get(n) or _word(n) for n in names} - {""}, key=_closing_first)
    return ", ".join(words[:8])


def _closing_first(word: str) -> tuple[bool, str]:
    """Order of the expected words: the closing keywords (``'END_IF'``) first."""
    return not word.startswith("'END_"), word


def _word(terminal: str) -> str:
    """A terminal as a message says it (:func:`~plc.st.frontend.wording.terminal_words`); an
    unnamed pattern (``%I*``) as "", left out."""
    return "" if terminal.startswith("__") else terminal_words(terminal, _pattern(terminal))


def _pattern(terminal: str) -> str:
    """A terminal as its literal text: a literal as it is written (``'('``), a keyword as its
    word (``'END_IF'``); "" for a pattern without one (a name, a number, ``%I*``)."""
    pattern = parser().get_terminal(terminal).pattern
    if isinstance(pattern, lark.lexer.PatternStr):
        return repr(pattern.value)
    if terminal.startswith("__"):
        return ""
    if terminal.startswith("_"):
        return repr(terminal[1:].upper())
    text = pattern.value
    return repr(text.split("|")[0].strip("()?:i")) if text.isupper() else ""

"""The fast path of the parser: lark's LALR(1) parser with a contextual lexer on the same
grammar as the Earley parser (:mod:`plc.st.frontend.grammar`), a few hundred times faster.

The grammar is ambiguous and not LALR(1): where two rules could reduce the same text, the rule
priorities below pick the reading the Earley parser picks; a keyword or a literal is preferred
to a name, a name without a dot to a dotted one, and ``-`` to a signed number (``-1`` is the
unary minus of 1, as Earley reads it). What the LALR parser cannot read (a construct that needs
more than one token of look-ahead, or a syntax error) is parsed by the Earley parser, which
decides and gives the message: every text the LALR parser reads, the Earley parser reads too.
"""

from __future__ import annotations

__all__ = ["parse", "parser"]

import hashlib
import importlib.resources
import itertools
import re
from collections.abc import Collection
from functools import cache
from pathlib import Path

import lark

from plc.st.frontend import grammar, tree_cache

_RULE_PRIORITIES = {
    "any_integer": 2,
    "integer": 2,
    "variable_name": 3,
    "fb_name": 2,
    "simple_type_name": 2,
    "non_generic_type_name": 2,
    "elementary_type_name": 2,
    "string_type_specification": 2,
    "located_var_declarations": 2,
    "fb_var_declaration": 2,
    "simple_spec_init": 2,
    "simple_specification": 2,
    "indirect_simple_specification": 1,
    "structure_element_initialization": 2,
    "array_spec_init": 2,
    "standard_function_block_name": 1,
    "array_initialization": -1,
    "_statement": -1,
}
"""Rule: its priority where two rules reduce the same tokens (higher wins; default 0)."""

_EDITS = [
    # Python's re refuses a global flag inside the lexer's combined pattern
    ("PRAGMA: /(?s){[^}]*?}/", "PRAGMA: /{[^}]*?}/s"),
    # a type name in VAR_EXTERNAL: the Earley parser reads it as a simple specification
    (
        '| array_specification | structure_type_name | function_block_type_name ) ";"+',
        '| array_specification ) ";"+',
    ),
    # an enumeration's name before "#": its own terminal, so that a value without it, where
    # either may come, is read as the value (a dotted name), not as the start of a typed one
    (
        'enumerated_value: [ enumerated_type_name "#" ]',
        'enumerated_value: [ ENUMERATION_NAME "#" ]',
    ),
    # a name before ":" or "," where a statement or a CASE label may come is the next label
    # (one token of look-ahead would start a statement): a tree as the Earley parser's
    (
        "?case_list_element: subrange\n                  | expression",
        "?case_list_element: subrange\n                  | expression\n | case_label",
    ),
    # a structure's type name before ":= (": its own terminal (one token of look-ahead would
    # not tell "p : Point := (x := 1)" from "e : Color := Red")
    (
        'initialized_structure: structure_type_name ":="',
        'initialized_structure: STRUCTURE_NAME ":="',
    ),
    # TYPE s : STRING(25) := 'x': the Earley parser reads a simple declaration
    ("                 | string_type_declaration\n", ""),
    # the name a TYPE declares: its kind shows after the ":" (the names are inlined: same tree)
    *(
        (f"{kind}_type_declaration: {name} ", f"{kind}_type_declaration: IDENTIFIER ")
        for kind, name in [
            ("simple", "simple_type_name"),
            ("subrange", "subrange_type_name"),
            ("enumerated", "enumerated_type_name"),
            ("array", "array_type_name"),
            ("structure", "structure_type_name_declaration"),
            ("union", "structure_type_name_declaration"),
            ("string", "string_type_name"),
        ]
    ),
]
"""(text, its replacement) in the extended grammar: each must be found once."""

_LEVELS = [
    "expression",
    "assignment_expression",
    "or_else_expression",
    "and_then_expression",
    "xor_expression",
    "and_expression",
    "comparison_expression",
    "equality_expression",
    "add_expression",
    "expression_term",
    "power_expression",
    "unary_expression",
]
"""The levels of an expression, outermost first, each a node of the Earley parser's tree."""

_ADDED = r"""
ENUMERATION_NAME: /[A-Za-z_][A-Za-z0-9_]*(?=#)/
CASE_LABEL: IDENTIFIER /(?=\s*(,|:(?!=)))/
STRUCTURE_NAME: IDENTIFIER /(?=\s*:=\s*\()/
case_label_name: CASE_LABEL [ DEREFERENCED ] -> variable_name
case_label_unary_expression: [ UNARY_OPERATOR ] case_label_name -> unary_expression
""" + "".join(
    f"case_label{'_' + outer if i else ''}: case_label_{inner} -> {outer}\n"
    for i, (outer, inner) in enumerate(itertools.pairwise(_LEVELS))
)
"""The terminals and rules the LALR parser adds: an enumeration's name before ``#``, and a
CASE label that is a name, read as the same tree as the Earley parser's (a variable as an
expression)."""

_NAMES = {"IDENTIFIER": 2, "DOTTED_IDENTIFIER": 1, "LABEL": 1}
"""The terminals that match names, with their priorities (IDENTIFIER before DOTTED_IDENTIFIER,
as the Earley parser reads ``x : Name``)."""

_PROBES = [f"{letter}zq9_" for letter in "ABCDEFGHIJKLMNOPQRSTUVWXYZ"]
"""Names a terminal must not cut short (and its own text followed by more letters)."""


def _terminal_priority(terminal: lark.lexer.TerminalDef) -> None:
    """A name is no name before ``#`` (``T#2s``); a keyword or literal goes before the names
    (``TRUE``), unless it could cut a name short (``T``, ``d``): that goes after them; the unary
    operator and a base (``16#``) go first (``-1``, ``16#FF``)."""
    pattern = terminal.pattern
    if terminal.name in _FIXED:
        terminal.priority = _FIXED[terminal.name]
    elif terminal.name in _NAMES:
        terminal.priority = _NAMES[terminal.name]
        terminal.pattern = lark.lexer.PatternRE(pattern.value + r"\b(?!#)", pattern.flags)
    elif terminal.name in _WORDS:  # TRUE, not the start of TRUEy
        terminal.priority = 3
        terminal.pattern = lark.lexer.PatternRE(
            f"(?:{pattern.to_regexp()})(?![A-Za-z0-9_])", pattern.flags
        )
    elif not any(_cuts(pattern.to_regexp(), pattern.flags, probe) for probe in _probes(pattern)):
        prefix = isinstance(pattern, lark.lexer.PatternStr) and pattern.value.endswith("#")
        terminal.priority = max(terminal.priority, 0) + (4 if prefix else 3)


_FIXED = {"UNARY_OPERATOR": 4, "POWER_OPERATOR": 4, "EQUALS_OP": 2, "COMPARE_OP": 1}
"""Operators that begin alike: ``-1`` is a unary minus, ``**`` no ``*``, ``=>`` no ``=``,
``<>`` no ``<``."""

_WORDS = frozenset({"TRUE_VALUE", "FALSE_VALUE"})
"""Literals that are words without a word boundary in blark's grammar."""


def _prioritized(text: str) -> str:
    """The extended grammar with the rule priorities and edits of the LALR parser."""
    for old, new in _EDITS:
        if text.count(old) != 1:
            raise RuntimeError("blark's grammar changed: pin the version pyproject.toml names")
        text = text.replace(old, new)
    for name, priority in _RULE_PRIORITIES.items():
        text, found = re.subn(rf"^(\??){name}:", rf"\g<1>{name}.{priority}:", text, flags=re.M)
        if found != 1:
            raise RuntimeError("blark's grammar changed: pin the version pyproject.toml names")
    return text + _ADDED


def _probes(pattern: lark.lexer.Pattern) -> list[str]:
    """Names ``pattern`` must not cut short: one per initial letter, and its text as the
    start of a name (``TIME`` of ``timer``)."""
    text = pattern.value if isinstance(pattern, lark.lexer.PatternStr) else ""
    own = [text + "zq9_"] if text[:1].isalpha() else []
    return _PROBES + own


def _cuts(regexp: str, flags: Collection[str], name: str) -> bool:
    """The pattern matches the start of ``name`` but not all of it."""
    found = re.match(regexp, name, re.I if "i" in flags else 0)
    return found is not None and found.end() < len(name)


@cache
def parser() -> lark.Lark:
    """The LALR parser (built once per process; its tables kept beside the parsed trees, so a
    process loads them in a fraction of the 2 s their construction takes)."""
    text = _prioritized(
        grammar.extended(importlib.resources.files("blark").joinpath("iec.lark").read_text())
    )
    folder = tree_cache.directory()
    kept = None
    if folder is not None:
        digest = hashlib.sha256(text.encode() + tree_cache.versions() + _identity()).hexdigest()
        kept = folder / f"lalr-{digest}.parser"
        try:
            with kept.open("rb") as file:
                return lark.Lark.load(file)
        except Exception:  # missing, damaged, or from another Python: built again
            pass
    built = lark.Lark(
        text,
        parser="lalr",
        lexer="contextual",
        maybe_placeholders=True,
        propagate_positions=True,
        start=["iec_source"],
        import_paths=[str(importlib.resources.files("blark"))],
        edit_terminals=_terminal_priority,
    )
    if kept is not None:
        tree_cache.keep(kept, built.save)
    return built


def _identity() -> bytes:
    """This module's code (its priorities change the tables)."""
    return Path(__file__).read_bytes()


def parse(text: str) -> lark.Tree | None:
    """The tree of ``text`` (comments already blanked), or None if the LALR parser cannot
    read it (the Earley parser decides)."""
    try:
        tree = parser().parse(text, start="iec_source", on_error=_as_other_name)
    except lark.exceptions.LarkError:
        return None
    for token in tree.scan_values(lambda v: isinstance(v, lark.Token) and v.type in _RENAMED):
        token.type = "IDENTIFIER"
    return tree


_RENAMED = frozenset({"CASE_LABEL", "STRUCTURE_NAME", "ENUMERATION_NAME"})
"""The terminals of names this parser adds: IDENTIFIERs in the tree, as the Earley parser's."""


def _as_other_name(error: lark.exceptions.UnexpectedInput) -> bool:
    """A name the lexer took for one kind of name (a CASE label, a dotted name) where the
    parser expects another: fed as that one; False if it is no such name."""
    if not isinstance(error, lark.exceptions.UnexpectedToken):
        return False
    token = error.token
    if token.type not in _NAME_KINDS:
        return False
    dotted = "." in token
    for kind in _NAME_KINDS:
        fits = kind == "DOTTED_IDENTIFIER" or not dotted
        if kind != token.type and fits and kind in error.interactive_parser.accepts():
            error.interactive_parser.feed_token(lark.Token.new_borrow_pos(kind, token, token))
            return True
    return False


_NAME_KINDS = ("IDENTIFIER", "CASE_LABEL", "STRUCTURE_NAME", "DOTTED_IDENTIFIER")
"""The terminals that read a name, the most common first."""

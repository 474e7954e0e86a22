"""Check an ST program without running it, as an IDE's "Check all objects": the first error of
each item, one ``file:line:column: ...`` line each, and a summary (``2 errors in 2 of 5 items``).

A source is cut into its items (each PROGRAM, FUNCTION_BLOCK, FUNCTION, TYPE, VAR_GLOBAL and
CONFIGURATION, :mod:`plc.st.frontend.chunks`), and each item is parsed on its own: a syntax
error in one hides none in another. The items that parse are translated together; at an
error in a POU's body the POU's declarations alone go on (the POUs that call it still
translate), an item with an error in its declarations is set aside, and the rest are
translated again: each item with an error gives one, and an error that only follows from an
item set aside (``unknown type 'HomeAxis'``) is left out.
"""

from __future__ import annotations

__all__ = ["Report", "check", "check_source"]

import dataclasses
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import blark.transform as tf

from plc.st.errors import STError
from plc.st.frontend.chunks import Chunk
from plc.st.frontend.parse import parse, parse_each, parse_piece
from plc.st.frontend.project import is_project, read_project, read_source
from plc.st.frontend.unclosed import code_only
from plc.st.runtime.external import External
from plc.st.runtime.program import check_mapping, translated


@dataclass
class Report:
    """What a check found.

    Attributes:
        errors: one ``file:line:column: ...`` message per error, in the order found.
        items: the items checked (POUs, types, global lists, configurations).
        failed: the items with an error.
    """

    errors: list[str] = field(default_factory=list)
    items: int = 0
    failed: int = 0

    def add(self, other: Report) -> None:
        """Count ``other``'s errors and items in this one."""
        self.errors += other.errors
        self.items += other.items
        self.failed += other.failed

    def summary(self) -> str:
        """``no errors in 5 items`` or ``2 errors in 2 of 5 items``."""
        items = _counted(self.items, "item")
        if not self.errors:
            return f"no errors in {items}"
        return f"{_counted(len(self.errors), 'error')} in {self.failed} of {items}"


def _counted(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def check(
    path: str | Path,
    axes: Mapping[str, Any] | None = None,
    mapping: Mapping[str, str] | None = None,
    blocks: Mapping[str, External] | None = None,
) -> Report:
    """Check the ST file, TwinCAT project (a source file or a folder) or PLCopen XML file
    ``path`` for a machine of ``axes`` (``mcl.Axis`` by name), ``mapping`` and ``blocks`` (as
    :func:`plc.st.load`); messages name the project's files and lines."""
    file = Path(path)
    try:
        check_mapping(str(file), axes or {}, mapping or {})
        if not is_project(file):
            return check_source(read_source(file), str(file), axes, mapping, blocks)
        project = read_project(file)
    except STError as error:
        return Report(error.lines, 1, 1)
    generated = f"{file.name}.st"
    report = check_source(project.source, generated, axes, mapping, blocks)
    report.errors = [str(project.relocated(STError(e), generated)) for e in report.errors]
    return report


def check_source(
    source: str,
    filename: str,
    axes: Mapping[str, Any] | None = None,
    mapping: Mapping[str, str] | None = None,
    blocks: Mapping[str, External] | None = None,
) -> Report:
    """Check the ST text ``source`` (named ``filename`` in messages), as :func:`check`."""
    parsed = parse_each(source, filename)
    trees: dict[int, tf.SourceCode] = {}
    failed: set[int] = set()
    errors: list[str] = []
    set_aside: set[str] = set()
    cut: set[int] = set()  # the items whose declarations alone go on
    for index, (chunk, tree) in enumerate(parsed):
        if isinstance(tree, STError):
            errors += tree.lines
            failed.add(index)
            interface = _interface(chunk, filename, tree)
            if interface is None:
                set_aside |= _names(chunk)
            else:
                trees[index] = interface
                cut.add(index)
        else:
            trees[index] = tree
    while trees:
        try:
            translated(_whole(trees, set_aside), filename, axes, mapping, blocks)
        except STError as error:
            failing = _item_of(error, filename, parsed)
            if not _follows(error, set_aside):
                errors += error.lines
                failed.add(-1 if failing is None else failing)
            if failing not in trees:
                break  # an error of the whole source: the last
            interface = None if failing in cut else _interface(parsed[failing][0], filename, error)
            if interface is None:
                set_aside |= {str(getattr(i, "name", "")).lower() for i in trees[failing].items}
                del trees[failing]
            else:
                trees[failing] = interface  # its declarations go on: the others use them
                cut.add(failing)
            continue
        break
    return Report(errors, len(parsed), len(failed))


def _whole(trees: dict[int, tf.SourceCode], set_aside: set[str]) -> tf.SourceCode:
    """The items of ``trees`` as one source (an empty PROGRAM in place of those set aside)."""
    items = [item for tree in trees.values() for item in tree.items]
    if set_aside and not any(isinstance(item, tf.Program) for item in items):
        items += _stand_in().items  # the blocks and functions left are checked still
    return dataclasses.replace(next(iter(trees.values())), items=items)


_POU = re.compile(r"\s*(PROGRAM|FUNCTION_BLOCK|FUNCTION)\b", re.I)
_END_VAR = re.compile(r"\bEND_VAR\b", re.I)


def _interface(chunk: Chunk, filename: str, error: STError) -> tf.SourceCode | None:
    """A POU's declarations alone (its body left out), where ``error`` is in its body: what
    the other POUs see of it; None where there is no such part, or it has an error."""
    code = code_only(chunk.text)
    pou = _POU.match(code)
    ends = list(_END_VAR.finditer(code))
    where = _WHERE.match(str(error))
    if pou is None or not ends or where is None:
        return None
    cut = ends[-1].end()
    if int(where["line"]) < chunk.line + code[:cut].count("\n"):
        return None  # an error in the declarations
    text = f"{chunk.text[:cut]}\nEND_{pou[1].upper()}\n"
    try:
        return parse_piece(Chunk(text, chunk.line, chunk.offset), filename)
    except STError:
        return None


_WHERE = re.compile(r"^(?P<file>.*?):(?P<line>\d+):\d+: ")
_QUOTED = re.compile(r"'([A-Za-z_][A-Za-z0-9_]*)'")


def _item_of(
    error: STError, filename: str, parsed: list[tuple[Chunk, tf.SourceCode | STError]]
) -> int | None:
    """The index of the item an error names a line of (None: no line of ``filename``)."""
    where = _WHERE.match(str(error))
    if where is None or where["file"] != filename:
        return None
    line = int(where["line"])
    found = None
    for index, (chunk, _) in enumerate(parsed):
        if chunk.line <= line:
            found = index
    return found


def _follows(error: STError, set_aside: set[str]) -> bool:
    """The error only follows from the items set aside: it names one of them (``unknown type
    'HomeAxis'``)."""
    return any(n.lower() in set_aside for n in _QUOTED.findall(str(error)))


@cache
def _stand_in() -> tf.SourceCode:
    """An empty PROGRAM, translated in the place of the PROGRAMs set aside (a source needs
    one)."""
    return parse(_STAND_IN, "<check>")


_STAND_IN = "PROGRAM Checked_\nEND_PROGRAM\n"


_DECLARED = re.compile(
    r"^\s*(?:PROGRAM|FUNCTION_BLOCK|FUNCTION|TYPE)\s+([A-Za-z_][A-Za-z0-9_]*)", re.I | re.M
)


def _names(chunk: Chunk) -> set[str]:
    """The names an item that did not parse declares (lower case), as far as they show."""
    return {name.lower() for name in _DECLARED.findall(chunk.text)}

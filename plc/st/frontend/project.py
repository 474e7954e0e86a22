"""A TwinCAT project's source files (or a PLCopen XML file, :mod:`plc.st.frontend.plcopen`)
as one ST source: ``.TcPOU`` (a PROGRAM, FUNCTION_BLOCK or
FUNCTION: its declaration and its implementation), ``.TcDUT`` (a TYPE) and ``.TcGVL`` (a
VAR_GLOBAL), read with blark's TwinCAT reader, and ``.TcTTO`` (a task: its cycle time, the
programs it calls; :mod:`plc.st.frontend.tctask`); a folder gives every such file under it. The
text keeps each line as written; :class:`Project` maps its lines back to the files, so that a
message names ``GantryDemo.TcPOU:12:5``.

A POU's METHODs, ACTIONs and PROPERTYs (TwinCAT's object-oriented extensions) are refused.
"""

from __future__ import annotations

__all__ = ["SUFFIXES", "Project", "is_project", "read_project", "read_source"]

import codecs
import re
from dataclasses import dataclass, field
from pathlib import Path

from plc.st.errors import STError, indefinite, place
from plc.st.frontend import tctask
from plc.st.semantics.gvl import NAME_PRAGMA

SUFFIXES = (".tcpou", ".tcdut", ".tcgvl")
"""The TwinCAT source files read (case-insensitive)."""

_ORDER = {".tcdut": 0, ".tcgvl": 1, ".tcpou": 2}
"""Types first, then the globals, then the POUs."""

_END = {
    "PROGRAM": "END_PROGRAM",
    "FUNCTION_BLOCK": "END_FUNCTION_BLOCK",
    "FUNCTION": "END_FUNCTION",
}

_CITED = re.compile(r" at (\d+):(\d+)\b")
"""A second place a message names in the same text (``IF at 5:6 has no END_IF``)."""

_CITED_LINE = re.compile(r" line (\d+)\b")
"""A line a message names in the same text (``missing ';' at the end of line 11``)."""

_DECLARED = re.compile(rb"""(?:\xef\xbb\xbf)?<\?xml[^>]*?\sencoding\s*=\s*["']([A-Za-z0-9._:-]+)""")
"""An XML declaration's encoding (``<?xml version="1.0" encoding="utf-8"?>``)."""

_XML_EXPECTED = 'UTF-8, or the encoding it is written in named by <?xml ... encoding="..."?>'
"""What a TwinCAT file's bytes should be."""

_WHERE = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<column>\d+): ", re.MULTILINE)


@dataclass
class Project:
    """The ST text of a project and where each of its lines comes from.

    Attributes:
        name: the file or folder, for messages.
        source: the ST text.
        origins: per line of ``source`` (index = line - 1): (file, line in it).
        columns: the column a line of ``source`` begins at in its file, where not 1 (an ST
            text that begins after an XML tag), by line of ``source``.
    """

    name: str
    source: str = ""
    origins: list[tuple[str, int]] = field(default_factory=list)
    columns: dict[int, int] = field(default_factory=dict)

    def add(self, lines: list[tuple[int, str]], filename: str) -> None:
        """Append ``lines`` ((line in ``filename``, text)) to the source."""
        self.source += "".join(f"{text}\n" for _, text in lines)
        self.origins += [(filename, number) for number, _ in lines]

    def where(self, line: int) -> str:
        """``file:line`` of a line of :attr:`source`."""
        if 0 < line <= len(self.origins):
            filename, number = self.origins[line - 1]
            return f"{filename}:{number}"
        return f"{self.name}:{line}"

    def relocated(self, error: STError, generated: str) -> STError:
        """``error`` (naming ``generated:line:column``) naming the project's file and line."""

        def place(match: re.Match[str]) -> str:
            if match["file"] != generated:
                return match[0]
            line = int(match["line"])
            column = int(match["column"]) + self.columns.get(line, 1) - 1
            return f"{self.where(line)}:{column}: "

        text = _WHERE.sub(place, str(error))
        if str(error).startswith(f"{generated}:"):
            file = text.partition(":")[0]
            text = _CITED.sub(lambda match: self._cited(match, file), text)
            text = _CITED_LINE.sub(
                lambda m: f" line {self.where(int(m[1])).rpartition(':')[2]}", text
            )
        return STError(text)

    def _cited(self, match: re.Match[str], file: str) -> str:
        """`` at line:column`` of :attr:`source` as the project's (its file named where it is
        not ``file``)."""
        line = int(match[1])
        column = int(match[2]) + self.columns.get(line, 1) - 1
        where_file, _, where_line = self.where(line).rpartition(":")
        place = where_line if where_file == file else f"{where_file}:{where_line}"
        return f" at {place}:{column}"


def is_project(path: Path) -> bool:
    """``path`` is a TwinCAT source file or a folder, or a PLCopen XML file (not an ``.st``
    file)."""
    return path.is_dir() or path.suffix.lower() in (*SUFFIXES, ".xml")


def read_source(file: Path, expected: str = "a UTF-8 ST file") -> str:
    """The text of a user's source ``file`` in its encoding (:func:`_encoding`); ``expected``
    says in a message what the file should be.

    Raises:
        STError: the file cannot be read (``file: cannot read it (why); expected ...``); a byte
            that is not of its encoding (``file:line:column: cannot read it (byte 0xE4 is not
            UTF-8); expected ...``); an encoding Python does not know (``file:1:1``).
    """
    try:
        data = file.read_bytes()
    except OSError as error:
        raise STError.at(str(file), f"cannot read it ({error})", expected) from None
    encoding = _encoding(data)
    try:
        return data.decode(encoding)
    except LookupError:
        problem = f"cannot read it (an encoding unknown here: {encoding})"
        raise STError.at(f"{file}:1:1", problem, expected) from None
    except UnicodeDecodeError as error:
        before = error.object[: error.start].decode(error.encoding)  # the bytes that are
        line, column = place(before, len(before))
        name = "UTF-8" if encoding == "utf-8-sig" else encoding.upper()
        problem = f"cannot read it (byte 0x{error.object[error.start]:02X} is not {name})"
        raise STError.at(f"{file}:{line}:{column}", problem, expected) from None


def _encoding(data: bytes) -> str:
    """The encoding of a source file's bytes: UTF-16 after its byte order mark, else the one
    an XML declaration at its start names, else UTF-8 (a byte order mark first left out)."""
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return "utf-16"
    declared = _DECLARED.match(data)
    name = declared[1].decode("ascii") if declared else "utf-8"
    return "utf-8-sig" if name.lower().replace("_", "-") in ("utf-8", "utf8") else name


def read_project(path: Path) -> Project:
    """The project of a TwinCAT source file or of every one in a folder (its sub-folders too),
    or of a PLCopen XML file (:mod:`plc.st.frontend.plcopen`).

    Raises:
        STError: no such file or no TwinCAT source in the folder, a file blark cannot read, a
            METHOD, ACTION or PROPERTY; a PLCopen XML file that is not one.
    """
    if path.suffix.lower() == ".xml":
        from plc.st.frontend.plcopen import read_plcopen

        return read_plcopen(path)
    files = [path] if path.is_file() else _sources(path)
    if not files:
        raise STError.at(str(path), "no TwinCAT source here", "a .TcPOU, .TcDUT or .TcGVL file")
    project = Project(str(path))
    for file in sorted(files, key=lambda f: (_ORDER[f.suffix.lower()], f.name.lower())):
        _read_file(project, file)
    for name, line, text in tctask.configuration(_sources(path, (tctask.SUFFIX,))):
        project.add([(line, text)], name)
    return project


def _sources(folder: Path, suffixes: tuple[str, ...] = SUFFIXES) -> list[Path]:
    """The files under ``folder`` of ``suffixes`` (the TwinCAT source files)."""
    if not folder.is_dir():
        return []
    return sorted(f for f in folder.rglob("*") if f.is_file() and f.suffix.lower() in suffixes)


def _read_file(project: Project, file: Path) -> None:
    """Append one file's declaration and implementation (and the POU's END_...); what a file
    holds is kept in the parse cache (:mod:`~plc.st.frontend.tree_cache`) by its content:
    reading TwinCAT's XML takes longer than loading the kept lines."""
    from plc.st.frontend import tree_cache

    text = read_source(file, _XML_EXPECTED)
    name = tree_cache.key(text, "TwinCAT", Path(__file__).read_bytes())
    lines = tree_cache.cached(name, lambda: _file_lines(file), "lines")
    written = dict(enumerate(text.splitlines(), 1))  # a line's column in the file (after
    for index, (number, code) in enumerate(lines, len(project.origins) + 1):  # <![CDATA[)
        project.columns[index] = max(written.get(number, "").find(code), 0) + 1
    project.add(lines, str(file))


def _file_lines(file: Path) -> list[tuple[int, str]]:
    """One file's declaration and implementation lines (and the POU's END_...): (line in the
    file, text)."""
    import blark.input
    from blark.util import SourceType

    try:
        items = blark.input.load_file_by_name(file)
    except Exception as error:  # a malformed file: one message, never a traceback
        raise STError.at(
            f"{file}:1:1", f"cannot read it ({type(error).__name__}: {error})", "TwinCAT XML"
        ) from None
    lines: list[tuple[int, str]] = []
    for item in items:
        parts = getattr(item, "parts", [item])
        for part in parts:
            if part.type in (SourceType.method, SourceType.action) or "property" in part.type.name:
                line = part.lines[0].lineno if part.lines else 1
                raise STError.at(
                    f"{file}:{line}:1",
                    f"{indefinite(part.type.name.upper())} ({str(part.identifier).split('/')[0]})",
                    "a PROGRAM, FUNCTION_BLOCK or FUNCTION without methods, actions, properties",
                )
            own = [(line.lineno, line.code) for line in part.lines]
            if part.type == SourceType.var_global and own:  # a GVL: its name before it
                name = str(part.identifier).split("/")[0]
                own.insert(0, (own[0][0], NAME_PRAGMA.format(name)))
            lines += own
        words = (line.code.split()[:1] for p in parts for line in p.lines)
        keyword = next((w[0].upper() for w in words if w and w[0].upper() in _END), "")
        if keyword:
            last = parts[-1].lines[-1].lineno if parts[-1].lines else 1
            lines.append((last, _END[keyword]))
    return lines

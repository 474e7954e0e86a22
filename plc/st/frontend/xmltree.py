"""An XML file as an :mod:`xml.etree` tree that knows the line of each element and of its text,
read with expat and guarded against entity expansion: a document that declares an entity
(the billion laughs, a quadratic blow-up, an external entity) is refused before any entity is
expanded, as ``defusedxml`` refuses it. Namespaces are dropped from the tags (``<xhtml:p>`` is
``p``), so that a path names the local names alone.
"""

from __future__ import annotations

__all__ = ["LinedTree", "read_xml"]

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from xml.parsers import expat

from plc.st.errors import STError


@dataclass
class LinedTree:
    """An XML document's root element and where each element and its text begin.

    Attributes:
        root: the document element.
        lines: the line of each element's start tag.
        text_lines: the line its text (``element.text``) begins on, if it has text.
        text_columns: the column (from 1) its text begins at.
    """

    root: ET.Element
    lines: dict[ET.Element, int] = field(default_factory=dict)
    text_lines: dict[ET.Element, int] = field(default_factory=dict)
    text_columns: dict[ET.Element, int] = field(default_factory=dict)

    def line(self, element: ET.Element) -> int:
        """The line of ``element``'s start tag (1 if unknown)."""
        return self.lines.get(element, 1)


class _Refused(Exception):
    """The document declares an entity."""


def read_xml(path: Path, expected: str) -> LinedTree:
    """The tree of the XML file ``path`` (``expected`` names what it should be, for messages).

    Raises:
        STError: the file cannot be read, is not well-formed, or declares an entity
            (``file:line:column``).
    """
    try:
        data = path.read_bytes()
    except OSError as error:
        raise STError.at(str(path), f"cannot read it ({error})", expected) from None
    parser = expat.ParserCreate(namespace_separator="}")
    stack: list[ET.Element] = []
    tree = LinedTree(ET.Element("document"))
    pending: list[ET.Element] = []

    def start(tag: str, attributes: dict[str, str]) -> None:
        name = tag.rpartition("}")[2]
        element = ET.SubElement(stack[-1], name, attributes) if stack else ET.Element(name)
        element.attrib = {k.rpartition("}")[2]: v for k, v in attributes.items()}
        tree.lines[element] = parser.CurrentLineNumber
        stack.append(element)
        pending[:] = [element]

    def end(tag: str) -> None:
        element = stack.pop()
        if not stack:
            tree.root = element
        pending[:] = []

    def text(data: str) -> None:
        if not stack:
            return
        element = stack[-1]
        if pending:
            if element not in tree.text_lines:
                tree.text_lines[element] = parser.CurrentLineNumber
                tree.text_columns[element] = parser.CurrentColumnNumber + 1
            element.text = (element.text or "") + data
        else:  # after a child's end tag: the child's tail
            child = element[-1]
            child.tail = (child.tail or "") + data

    def refuse(*_: object) -> Any:
        raise _Refused

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = text
    parser.EntityDeclHandler = refuse
    parser.UnparsedEntityDeclHandler = refuse
    parser.ExternalEntityRefHandler = refuse
    try:
        parser.Parse(data, True)
    except _Refused:
        where = f"{path}:{parser.CurrentLineNumber}:{parser.CurrentColumnNumber + 1}"
        raise STError.at(
            where, "an entity declaration (refused: it may expand)", expected
        ) from None
    except expat.ExpatError as error:
        where = f"{path}:{error.lineno}:{error.offset + 1}"
        problem = f"not well-formed XML ({expat.errors.messages[error.code]})"
        raise STError.at(where, problem, expected) from None
    return tree

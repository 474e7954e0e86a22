"""A PLCopen XML project (IEC 61131-10, TC6 XML: what CODESYS, Beremiz and OpenPLC export) as
one ST source: its data types (``<dataType>``: structures, enumerations, arrays, subranges,
aliases), its POUs (``<pou pouType="program|functionBlock|function">``: the ``<interface>``'s
variable sections and the ``<body><ST>`` text) and its configurations (``<configuration>`` and
``<resource>`` with their ``<globalVars>``, ``<task interval>`` and ``<pouInstance>``).

Each ST line keeps the XML line it comes from (:class:`~plc.st.frontend.project.Project`): a
declaration the line of its ``<variable>``, a statement its line in the ``<ST>`` text, so that
a message names ``project.xml:57:3``. A body in another language (FBD, LD, SFC, IL), a POU's
actions or transitions are refused at their element.
"""

from __future__ import annotations

import re

__all__ = ["read_plcopen"]

import xml.etree.ElementTree as ET
from pathlib import Path

from plc.st.errors import STError
from plc.st.frontend.project import Project
from plc.st.frontend.xmltree import LinedTree, read_xml
from plc.st.semantics.gvl import NAME_PRAGMA

EXPECTED = "a PLCopen XML (TC6) project"

_POU = {"program": "PROGRAM", "functionBlock": "FUNCTION_BLOCK", "function": "FUNCTION"}

_SECTIONS = {
    "inputVars": "VAR_INPUT",
    "outputVars": "VAR_OUTPUT",
    "inOutVars": "VAR_IN_OUT",
    "externalVars": "VAR_EXTERNAL",
    "globalVars": "VAR_GLOBAL",
    "localVars": "VAR",
    "tempVars": "VAR_TEMP",
}
"""The interface's variable sections and their ST keywords."""

_NOTES = ("documentation", "addData")
"""Elements that only annotate (skipped)."""

_ELEMENTARY = {
    *[
        "BOOL",
        "BYTE",
        "WORD",
        "DWORD",
        "LWORD",
        "SINT",
        "INT",
        "DINT",
        "LINT",
        "USINT",
        "UINT",
        "UDINT",
        "ULINT",
    ],
    *[
        "REAL",
        "LREAL",
        "TIME",
        "LTIME",
        "DATE",
        "TOD",
        "DT",
        "TIME_OF_DAY",
        "DATE_AND_TIME",
        "STRING",
        "WSTRING",
    ],
}


class _Writer:
    """Writes a project's elements as ST lines into a :class:`Project`."""

    def __init__(self, tree: LinedTree, file: str) -> None:
        self.tree, self.file = tree, file
        self.project = Project(file)

    def emit(self, text: str, element: ET.Element) -> None:
        """One ST line from ``element``."""
        self.project.add([(self.tree.line(element), text)], self.file)

    def error(self, element: ET.Element, problem: str, expected: str) -> STError:
        """A mistake at ``element``."""
        return STError.at(f"{self.file}:{self.tree.line(element)}:1", problem, expected)

    def required(self, element: ET.Element, attribute: str) -> str:
        """An attribute ``element`` must have."""
        value = element.get(attribute, "").strip()
        if not value:
            raise self.error(element, f"<{element.tag}> without {attribute}", f"{attribute}=...")
        return value

    # ------------------------------------------------------------------ types and values
    def type_of(self, holder: ET.Element | None) -> str:
        """The ST type of a ``<type>`` or ``<baseType>`` element (its one child)."""
        child = _first(holder)
        if holder is None or child is None:
            where = holder if holder is not None else self.tree.root
            raise self.error(where, "a variable without a type", "<type>")
        tag = child.tag
        if tag == "derived":
            return self.required(child, "name")
        if tag in ("string", "wstring"):
            length = child.get("length")
            return f"{tag.upper()}({length})" if length else tag.upper()
        if tag == "array":
            dims = [
                f"{self.required(d, 'lower')}..{self.required(d, 'upper')}"
                for d in child.findall("dimension")
            ]
            return f"ARRAY[{', '.join(dims)}] OF {self.type_of(child.find('baseType'))}"
        if tag in ("subrangeSigned", "subrangeUnsigned"):
            bounds = child.find("range")
            if bounds is None:
                raise self.error(child, f"<{tag}> without <range>", "<range lower upper>")
            low, high = self.required(bounds, "lower"), self.required(bounds, "upper")
            return f"{self.type_of(child.find('baseType'))} ({low}..{high})"
        if tag == "enum":
            values = child.findall("values/value")
            return "(" + ", ".join(_enum_value(v, self.required(v, "name")) for v in values) + ")"
        if tag.upper() in _ELEMENTARY:
            return tag.upper()
        raise self.error(
            child,
            f"the type <{tag}>",
            "an elementary type (<LREAL/>), <derived name>, <array>, <string>, <enum>",
        )

    def value_of(self, holder: ET.Element) -> str:
        """An ``<initialValue>`` (or a ``<value>`` in one) as ST text."""
        child = _first(holder)
        if child is None:
            raise self.error(holder, "an empty initial value", "<simpleValue value>")
        if child.tag == "simpleValue":
            return self.required(child, "value")
        if child.tag == "arrayValue":
            parts = []
            for value in child.findall("value"):
                count = value.get("repetitionValue")
                parts.append(f"{count}({self.value_of(value)})" if count else self.value_of(value))
            return f"[{', '.join(parts)}]"
        if child.tag == "structValue":
            members = [
                f"{self.required(v, 'member')} := {self.value_of(v)}"
                for v in child.findall("value")
            ]
            return f"({', '.join(members)})"
        raise self.error(
            child, f"the value <{child.tag}>", "<simpleValue>, <arrayValue>, <structValue>"
        )

    def variable(self, element: ET.Element, indent: str = "  ") -> None:
        """One ``<variable>`` as a declaration."""
        name = self.required(element, "name")
        address = element.get("address")
        located = f" AT {address}" if address else ""
        text = f"{indent}{name}{located} : {self.type_of(element.find('type'))}"
        initial = element.find("initialValue")
        if initial is not None:
            text += f" := {self.value_of(initial)}"
        self.emit(text + ";", element)

    def section(self, block: ET.Element, keyword: str) -> None:
        """A variable section (``<localVars constant="true">``) as ``VAR CONSTANT ... END_VAR``."""
        qualifiers = [q.upper() for q in ("constant", "retain", "persistent") if _true(block, q)]
        if keyword == "VAR_GLOBAL" and block.get("name", "").strip():  # a GVL
            attributes = block.iterfind("addData/data/Attributes/Attribute")
            if any(a.get("Name", "").lower() == "qualified_only" for a in attributes):
                self.emit("{attribute 'qualified_only'}", block)
            self.emit(NAME_PRAGMA.format(block.get("name", "").strip()), block)
        self.emit(" ".join([keyword, *qualifiers]), block)
        for variable in block.findall("variable"):
            self.variable(variable)
        self.emit("END_VAR", block)

    # ------------------------------------------------------------------ the project's parts
    def data_type(self, element: ET.Element) -> None:
        """A ``<dataType>`` as ``TYPE name : ... END_TYPE``."""
        name = self.required(element, "name")
        base = element.find("baseType")
        initial = element.find("initialValue")
        value = f" := {self.value_of(initial)}" if initial is not None else ""
        struct = _first(base)
        if struct is not None and struct.tag == "struct":
            self.emit(f"TYPE {name} :", element)
            self.emit("STRUCT", struct)
            for variable in struct.findall("variable"):
                self.variable(variable)
            self.emit("END_STRUCT", struct)
        else:
            self.emit(f"TYPE {name} : {self.type_of(base)}{value};", element)
        self.emit("END_TYPE", element)

    def pou(self, element: ET.Element) -> None:
        """A ``<pou>``: its header, interface, ST body and END_..."""
        name = self.required(element, "name")
        kind = _POU.get(element.get("pouType", ""))
        if kind is None:
            raise self.error(element, f"pouType {element.get('pouType')!r}", ", ".join(_POU))
        for extra in ("actions", "transitions"):
            found = element.find(extra)
            if found is not None and len(found):
                raise self.error(found, f"{extra} of {name}", "a POU with an ST body alone")
        interface = element.find("interface")
        header = f"{kind} {name}"
        if kind == "FUNCTION":
            header += f" : {self.type_of(_find(interface, 'returnType'))}"
        self.emit(header, element)
        for block in list(interface) if interface is not None else []:
            keyword = _SECTIONS.get(block.tag)
            if keyword is not None:
                self.section(block, keyword)
            elif block.tag not in ("returnType", *_NOTES):
                raise self.error(block, f"the section <{block.tag}>", ", ".join(_SECTIONS))
        self.body(element, name)
        self.emit(f"END_{kind}", element)

    def body(self, pou: ET.Element, name: str) -> None:
        """A POU's ``<body><ST>`` text, each line at its XML line."""
        body = pou.find("body")
        language = (
            next((c for c in body if c.tag not in _NOTES), None) if body is not None else None
        )
        if body is None or language is None:
            raise self.error(pou, f"{name} without a body", "<body><ST>...</ST></body>")
        if language.tag != "ST":
            raise self.error(language, f"a <{language.tag}> body ({name})", "an <ST> body")
        holder = language
        while len(holder) == 1 and not (holder.text or "").strip():
            holder = holder[0]  # <ST><xhtml:p>...</xhtml:p></ST>
        text = "".join(holder.itertext())
        first = self.tree.text_lines.get(holder, self.tree.line(holder))
        self.project.columns[len(self.project.origins) + 1] = self.tree.text_columns.get(holder, 1)
        lines = text.split("\n")
        self.project.add([(first + i, line) for i, line in enumerate(lines)], self.file)

    def configuration(self, element: ET.Element) -> None:
        """A ``<configuration>``: its globals, resources, tasks and program instances."""
        name = self.required(element, "name")
        resources = element.findall("resource")
        if not resources:  # globals alone: a VAR_GLOBAL of the project
            for block in element.findall("globalVars"):
                self.section(block, "VAR_GLOBAL")
            return
        self.emit(f"CONFIGURATION {name}", element)
        for block in element.findall("globalVars"):
            self.section(block, "VAR_GLOBAL")
        for resource in resources:
            self.resource(resource)
        self.emit("END_CONFIGURATION", element)

    def resource(self, element: ET.Element) -> None:
        """A ``<resource>`` as ``RESOURCE name ON PLC ... END_RESOURCE``."""
        self.emit(f"RESOURCE {self.required(element, 'name')} ON PLC", element)
        for block in element.findall("globalVars"):
            self.section(block, "VAR_GLOBAL")
        tasks = element.findall("task")
        for task in tasks:
            values = {k: task.get(k) for k in ("interval", "single", "priority")}
            values["interval"] = iec_duration(values["interval"])
            settings = [f"{k.upper()} := {v}" for k, v in values.items() if v is not None]
            self.emit(f"TASK {self.required(task, 'name')} ({', '.join(settings)});", task)
        for task in tasks:
            for instance in task.findall("pouInstance"):
                self.instance(instance, f" WITH {task.get('name')}")
        for instance in element.findall("pouInstance"):
            self.instance(instance, "")
        self.emit("END_RESOURCE", element)

    def instance(self, element: ET.Element, with_task: str) -> None:
        """A ``<pouInstance>`` as ``PROGRAM name WITH task : type;`` (CODESYS exports its
        programs with an empty ``typeName``: the POU of the instance's name)."""
        name = self.required(element, "name")
        program = element.get("typeName", "").strip() or name
        self.emit(f"PROGRAM {name}{with_task} : {program};", element)


ISO_DURATION = re.compile(
    r"P(?:(?P<d>\d+(?:\.\d*)?)D)?"
    r"(?:T(?:(?P<h>\d+(?:\.\d*)?)H)?(?:(?P<m>\d+(?:\.\d*)?)M)?(?:(?P<s>\d+(?:\.\d*)?)S)?)?",
    re.IGNORECASE,
)
"""An XML Schema duration (``PT0.004S``, ``P0DT0H0M0.010S``), CODESYS' form of a task's interval."""


def iec_duration(text: str | None) -> str | None:
    """A task interval as IEC 61131-3 writes it: an XML Schema duration (``PT0.004S``) becomes
    ``T#4ms``; an IEC literal (``T#4ms``) or anything else stays as it is (None: none)."""
    if text is None:
        return None
    match = ISO_DURATION.fullmatch(text.strip())
    if match is None or not any(match.groupdict().values()):
        return text
    scale = {"d": 86_400_000.0, "h": 3_600_000.0, "m": 60_000.0, "s": 1000.0}
    ms = sum(float(v) * scale[k] for k, v in match.groupdict().items() if v)
    return f"T#{ms:g}ms"


def read_plcopen(path: Path) -> Project:
    """The project of a PLCopen XML file: its data types, then its configurations' globals,
    then its POUs.

    Raises:
        STError: the file cannot be read, is no well-formed XML or no PLCopen project, or has
            a part this reader does not take (``file:line``).
    """
    tree = read_xml(path, EXPECTED)
    writer = _Writer(tree, str(path))
    root = tree.root
    if root.tag != "project":
        raise writer.error(root, f"a <{root.tag}> document", EXPECTED + " (<project>)")
    for data_type in root.iterfind("types/dataTypes/dataType"):
        writer.data_type(data_type)
    for configuration in root.iterfind("instances/configurations/configuration"):
        writer.configuration(configuration)
    for block in root.iterfind("addData/data/globalVars"):  # CODESYS' export of a GVL
        writer.section(block, "VAR_GLOBAL")
    pous = root.findall("types/pous/pou")
    if not pous:
        raise writer.error(root, "no POU in the project", "<types><pous><pou pouType=...>")
    for pou in pous:
        writer.pou(pou)
    return writer.project


def _first(element: ET.Element | None) -> ET.Element | None:
    """The first child element of ``element`` (None: none)."""
    return next(iter(element), None) if element is not None else None


def _find(element: ET.Element | None, tag: str) -> ET.Element | None:
    return element.find(tag) if element is not None else None


def _true(element: ET.Element, attribute: str) -> bool:
    return element.get(attribute, "").lower() in ("true", "1")


def _enum_value(value: ET.Element, name: str) -> str:
    """An enumeration's value, ``Name`` or ``Name := 3``."""
    number = value.get("value")
    return f"{name} := {number}" if number else name

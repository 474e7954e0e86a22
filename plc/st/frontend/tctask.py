"""TwinCAT's tasks (``.TcTTO`` files) as the ST of a CONFIGURATION: each task is a ``TASK
name (INTERVAL := T#10ms, PRIORITY := 20);`` of its ``<CycleTime>`` (in µs) and
``<Priority>``, and each program it calls (``<PouCall><Name>``) a ``PROGRAM MAIN WITH task :
MAIN;``, so that a TwinCAT project runs at its task's period as an ST file with that
CONFIGURATION (:mod:`plc.st.runtime.task`). Each line keeps the line of the XML it comes from,
for messages (``PlcTask.TcTTO:5:1``)."""

from __future__ import annotations

__all__ = ["SUFFIX", "WHOLE_MS", "configuration"]

import xml.etree.ElementTree as ET
from pathlib import Path

from plc.st.errors import STError
from plc.st.frontend.xmltree import read_xml

SUFFIX = ".tctto"
"""A TwinCAT task file (case-insensitive)."""

WHOLE_MS = (
    "a task's cycle is a whole number of ms here (TIME is held in ms, and a PLC cycle is a "
    "multiple of the machine's servo cycle of 1 ms)"
)
"""Why a task's cycle time of a fraction of a ms is refused (a TASK's INTERVAL too)."""

_EXPECTED = "a TwinCAT task (<TcPlcObject><Task Name=...><CycleTime>)"


def configuration(files: list[Path]) -> list[tuple[str, int, str]]:
    """The CONFIGURATION of the tasks of ``files`` (none: no line): (file, line in it, ST
    text) per line.

    Raises:
        STError: a file that is no TwinCAT task, a task without a cycle time in whole ms,
            a program call without the program's name (``file:line``).
    """
    lines: list[tuple[str, int, str]] = []
    calls: list[tuple[str, int, str]] = []
    for file in files:
        tree = read_xml(file, _EXPECTED)
        task = tree.root.find("Task")
        if tree.root.tag != "TcPlcObject" or task is None:
            raise STError.at(f"{file}:{tree.line(tree.root)}", "no <Task> in it", _EXPECTED)
        name = task.get("Name", "").strip() or file.stem
        cycle = task.find("CycleTime")
        where = tree.line(task if cycle is None else cycle)
        settings = [f"INTERVAL := {_interval(f'{file}:{where}', cycle)}"]
        priority = (task.findtext("Priority") or "").strip()
        if priority.isdigit():
            settings.append(f"PRIORITY := {priority}")
        lines.append((str(file), where, f"TASK {name} ({', '.join(settings)});"))
        for call in task.iterfind("PouCall/Name"):
            program = (call.text or "").strip()
            if not program:
                call_at = f"{file}:{tree.line(call)}"
                raise STError.at(call_at, "a <PouCall> with no program", "<Name>MAIN</Name>")
            calls.append(
                (str(file), tree.line(call), f"PROGRAM {program} WITH {name} : {program};")
            )
    if not lines:
        return []
    first, line = lines[0][:2]
    head = [(first, line, "CONFIGURATION TwinCAT"), (first, line, "RESOURCE PLC ON PLC")]
    tail = [(first, line, "END_RESOURCE"), (first, line, "END_CONFIGURATION")]
    return head + lines + calls + tail


def _interval(where: str, cycle: ET.Element | None) -> str:
    """A task's ``<CycleTime>`` [µs] as a TIME literal (``T#10ms``).

    Raises:
        STError: none, or not a whole number of µs above 0, or not of whole ms
            (:data:`WHOLE_MS`).
    """
    text = (cycle.text or "").strip() if cycle is not None else ""
    if not text.isdigit() or int(text) == 0:
        shown = f"<CycleTime>{text}</CycleTime>" if cycle is not None else "no <CycleTime>"
        raise STError.at(where, f"a task with {shown}", "its cycle time in µs, <CycleTime>2000")
    if int(text) % 1000:
        problem = f"a task with <CycleTime>{text}</CycleTime> ({int(text) / 1000:g} ms)"
        raise STError.at(where, f"{problem}: {WHOLE_MS}", "a multiple of 1000 µs, <CycleTime>1000")
    return f"T#{int(text) // 1000}ms"

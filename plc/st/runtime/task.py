"""The TASK of an ST file (IEC 61131-3 B.1.7): ``CONFIGURATION``, ``RESOURCE ... ON``, ``TASK
name(INTERVAL := T#2ms)`` and ``PROGRAM instance WITH task : type`` give the PROGRAM that runs and
its scan period (:class:`Task`); :func:`task_of` reads them from the parsed file.

One program instance runs (the one the configuration names, or the one asked for); its task's
INTERVAL is its period (a TIME of whole ms).
A task without INTERVAL (event-triggered, ``SINGLE :=``) is refused.
``WATCHDOG := T#50ms`` bounds the wall time of one scan (default :data:`WATCHDOG`): a loop
(WHILE, REPEAT, FOR) still running after it stops the program with a run-time fault.
"""

from __future__ import annotations

__all__ = [
    "WATCHDOG",
    "Task",
    "chosen_program",
    "configurations",
    "declared_task",
    "task_of",
    "task_of_file",
    "ticks",
]

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import blark.transform as tf
import lark

from plc.st.codegen.expressions import duration_ns
from plc.st.frontend.tctask import WHOLE_MS
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.declarations import STErrorAt, constant_of
from plc.st.semantics.scope import Unit

WATCHDOG = 0.1
"""The wall time a scan may take by default [s]: a loop still running after it stops the
program (a TASK's ``WATCHDOG := T#50ms`` sets its own)."""


@dataclass(frozen=True)
class Task:
    """The cyclic task a PROGRAM runs in.

    Attributes:
        name: the TASK's name.
        interval: its period [s].
        program: the PROGRAM type it runs (as the configuration spells it; empty: any).
        where: ``file:line:column`` of the TASK declaration, for messages.
        watchdog: the longest wall time a scan may take [s] (``WATCHDOG := T#50ms``; None: the
            default :data:`WATCHDOG`); a loop still running then stops the program.
    """

    name: str
    interval: float
    program: str
    where: str
    watchdog: float | None = None


def configurations(items: list[Any]) -> list[lark.Tree[Any]]:
    """The CONFIGURATION declarations among a file's items."""
    return [i for i in items if isinstance(i, lark.Tree) and i.data == "configuration_declaration"]


def task_of(unit: Unit, items: list[Any], programs: list[str]) -> Task | None:
    """The task of the file's program (None: the file declares no CONFIGURATION).

    Raises:
        STError: several configurations, a task without INTERVAL or of a non-TIME interval,
            a PROGRAM instance of an unknown type or with an undeclared task.
    """
    configs = configurations(items)
    if not configs:
        return None
    if len(configs) > 1:
        raise STErrorAt(unit, configs[1], "a second CONFIGURATION", "one per file")
    tasks: dict[str, Task] = {}
    instances: list[tuple[str, str, Any]] = []
    for resource in configs[0].find_data("resource_declaration"):
        for node in resource.find_data("task_configuration"):
            task = _task(unit, node)
            tasks[task.name.upper()] = task
        for node in resource.find_data("program_configuration"):
            _, with_task, program_type = node.children
            instances.append((str(with_task or ""), str(program_type), node))
    known = {p.upper(): p for p in programs}
    for with_task, program_type, node in instances:
        if program_type.upper() not in known:
            raise STErrorAt(unit, node, f"no PROGRAM {program_type}", ", ".join(programs))
        if with_task and with_task.upper() not in tasks:
            raise STErrorAt(unit, node, f"no TASK {with_task}", ", ".join(tasks) or "a TASK")
    if not tasks:
        return None
    if instances:
        with_task, program_type, _ = instances[0]
        task = tasks[with_task.upper()] if with_task else next(iter(tasks.values()))
        return Task(
            task.name, task.interval, known[program_type.upper()], task.where, task.watchdog
        )
    return next(iter(tasks.values()))


def chosen_program(programs: dict[str, tuple[int, int]], task: Task | None, filename: str) -> str:
    """The PROGRAM that runs when none is asked for: the TASK's, else the file's only one.

    Args:
        programs: each PROGRAM's name and its (line, column).
        task: the file's task (None: none).
        filename: for the message.

    Raises:
        STError: several PROGRAMs and no TASK that runs one of them.
    """
    from plc.st.errors import STError

    if task is not None and task.program:
        return task.program
    names = list(programs)
    if len(names) == 1:
        return names[0]
    line, column = programs[names[0]]
    listed = ", ".join(f"{n} at {ln}:{col}" for n, (ln, col) in programs.items())
    first = names[0]
    raise STError(
        f"{filename}:{line}:{column}: {len(names)} PROGRAMs ({listed}) and no TASK that runs "
        f"one of them; choose one: plc.st.load(..., program={first!r}), python -m scenes run "
        f"... --pou {first}, or a CONFIGURATION whose TASK runs it (PROGRAM main WITH t : "
        f"{first};)"
    )


def _task(unit: Unit, node: lark.Tree[Any]) -> Task:
    """One TASK declaration."""
    name, *items = node.children
    settings = {str(item.children[0]).upper(): item.children[1] for item in items}
    interval = settings.get("INTERVAL")
    if interval is None:
        raise STErrorAt(
            unit, node, f"TASK {name} without INTERVAL", "a cyclic task, INTERVAL := T#2ms"
        )
    value = constant_of(unit, interval)
    if isinstance(interval, tf.Duration) and duration_ns(interval) % 1_000_000:
        raise STErrorAt(
            unit, node, f"TASK {name} INTERVAL {interval}: {WHOLE_MS}", "T#1ms, T#2ms, ..."
        )
    if value.type is not T.TIME or not value.value > 0:
        raise STErrorAt(unit, node, f"TASK {name} INTERVAL {interval}", "a TIME > 0, T#2ms")
    watchdog = None
    if "WATCHDOG" in settings:
        limit = constant_of(unit, settings["WATCHDOG"])
        if limit.type is not T.TIME or not limit.value > 0:
            where = settings["WATCHDOG"]
            raise STErrorAt(unit, where, f"TASK {name} WATCHDOG {where}", "a TIME > 0, T#50ms")
        watchdog = limit.value / 1000.0
    return Task(str(name), value.value / 1000.0, "", unit.where(node), watchdog)


def ticks(task: Task, period: float) -> int:
    """How many scans of ``period`` [s] make one task interval.

    Raises:
        STError: the interval is no integer multiple of the scene's period (at the TASK).
    """
    from plc.st.errors import STError

    n = round(task.interval / period)
    if n < 1 or abs(n * period - task.interval) > 1e-9 * task.interval:
        raise STError.at(
            task.where,
            f"TASK {task.name} INTERVAL {task.interval * 1e3:g} ms cannot run on a PLC period "
            f"of {period * 1e3:g} ms",
            f"an integer multiple of {period * 1e3:g} ms",
        )
    return n


def task_of_file(path: str | Path) -> Task | None:
    """The task the ST file, TwinCAT project or PLCopen XML file ``path`` declares (None: no
    CONFIGURATION with a TASK), read before a machine is built for it.

    Raises:
        STError: the file cannot be read, a syntax error, or a malformed configuration (a
            project's at its file and line).
    """
    from plc.st.errors import STError
    from plc.st.frontend.project import is_project, read_project, read_source

    file = Path(path)
    if not is_project(file):
        return declared_task(read_source(file), str(file))
    project = read_project(file)
    generated = f"{file.name}.st"
    try:
        task = declared_task(project.source, generated)
    except STError as error:
        raise project.relocated(error, generated) from None
    if task is None:
        return None
    where = project.relocated(STError(f"{task.where}: "), generated)
    return dataclasses.replace(task, where=str(where).removesuffix(": "))


def declared_task(source: str, filename: str) -> Task | None:
    """The task an ST source declares (None: no CONFIGURATION with a TASK), read before a
    machine is built for it (e.g. at the TASK's period).

    Raises:
        STError: a syntax error, or a malformed configuration.
    """
    import blark.transform as tf

    from plc.st.frontend.parse import parse

    items = list(parse(source, filename).items)
    programs = [str(i.name) for i in items if isinstance(i, tf.Program)]
    return task_of(Unit(filename), items, programs)

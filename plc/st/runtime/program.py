"""A loaded ST program (:class:`STProgram`): call it once per PLC scan (``scene.run(prog)``);
its variables read and write as attributes (``prog.Start = True``, ``prog.Head_X.Done``).
Like a Python demo it reports ``done``, ``step`` and ``error`` from the program's variables of
those names (a ``step`` of an enumeration by its value's name).

A run-time fault (division by zero, an array index out of range) stops the program as a PLC
stops: it is no longer scanned, every axis of the machine ramps down and is disabled
(MC_Power's Enable dropping), and :attr:`STProgram.error` names ``file:line`` and the fault.

The program's variables come first: one named like an attribute of the runtime (``scans``,
``name``, ``fault``, ``restart``, ``variables``, ``stopped``, ...) is what ``prog.scans`` reads;
the functions :func:`restart`, :func:`variables` and :func:`stopped` reach the runtime's whatever
the program declares.
"""

from __future__ import annotations

__all__ = [
    "STProgram",
    "check_mapping",
    "compile_source",
    "from_source",
    "load",
    "program_name",
    "restart",
    "stopped",
    "stored",
    "translated",
    "variables",
]

import functools
import math
import sys
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from types import TracebackType
from typing import Any

from plc.st.codegen.translate import Module, translate
from plc.st.errors import STError, nearest
from plc.st.frontend.parse import parse
from plc.st.frontend.project import is_project, read_project, read_source
from plc.st.runtime import functions as F  # noqa: N812
from plc.st.runtime.external import External
from plc.st.runtime.io import channels
from plc.st.runtime.task import WATCHDOG, chosen_program, ticks
from plc.st.semantics.scope import Unit, Var
from plc.st.semantics.types import Elementary, EnumType


def _runtime(key: str, doc: str) -> Any:
    """An attribute of the runtime (``prog.scans``) that a program's variable of the same name
    shadows (``prog.scans`` is then the variable, as every other name)."""

    def get(self: STProgram) -> Any:
        own = self.__dict__
        var = own["_vars"].get(key)
        return self._read(var) if var is not None else own[f"_{key}"]

    return property(get, doc=doc)


def program_name(prog: STProgram) -> str:
    """The name of the PROGRAM ``prog`` runs (whatever variables it declares)."""
    return str(prog.__dict__["_name"])


class _Shadowed:
    """A method (or, ``value``, a property) of the runtime that a program's variable of the same
    name shadows: ``prog.restart`` is then the variable, as every other name; the module's
    function of that name reaches the runtime's."""

    def __init__(self, function: Callable[[Any], Any], value: bool = False) -> None:
        self.function, self.value = function, value
        self.__doc__ = function.__doc__

    def __set_name__(self, owner: type, name: str) -> None:
        self.key = name

    def __get__(self, prog: Any, owner: type | None = None) -> Any:
        if prog is None:
            return self
        var = prog.__dict__["_vars"].get(self.key)
        if var is not None:
            return prog._read(var)
        return self.function(prog) if self.value else functools.partial(self.function, prog)


def restart(prog: STProgram) -> None:
    """A cold restart of ``prog``: every variable at its initial value, every block new, the
    fault cleared; the program is scanned again (the axes as the stop left them: its MC_Power
    and MC_Reset bring them back). ``prog.restart()`` unless it declares a ``restart``."""
    own = prog.__dict__
    namespace, module = own["_namespace"], own["_module"]
    namespace["_g"] = namespace["_Globals"]()
    own["_instance"] = instance = namespace[_python(module, own["_name"])]()
    own["_fault"], own["_calls"] = "", 0
    own["_tick"] = _ticker(own, namespace, instance.__call__, prog._stop)


def variables(prog: STProgram) -> dict[str, Any]:
    """Every variable of ``prog`` and the globals, by name, with its value now
    (``prog.variables()`` unless it declares a ``variables``)."""
    return {v.name: prog._read(v) for v in prog.__dict__["_vars"].values()}


def stopped(prog: STProgram) -> bool:
    """A run-time fault stopped ``prog`` (``prog.stopped`` unless it declares a ``stopped``)."""
    return bool(prog.__dict__["_fault"])


class STProgram:
    """One PROGRAM of an ST file, translated and compiled, bound to a machine's axes.

    Args:
        module: the translated file.
        name: the PROGRAM (None: the file's first).
        axes: the machine's axes by name (``mcl.Axis``).
        clock: the simulated time [s]; None: the task's interval per run from 0.
        period: the PLC period it is called at [s] (the scene's); None: its TASK's INTERVAL
            (or 10 ms without a TASK).
        filename: the ST file, for messages.
        blocks: what makes an instance of each of the machine's own block types, by name.
    """

    def __init__(
        self,
        module: Module,
        name: str | None,
        axes: Mapping[str, Any],
        clock: Callable[[], float] | None,
        period: float | None,
        filename: str,
        blocks: Mapping[str, Callable[[], Any]] | None = None,
    ) -> None:
        programs = {n.upper(): n for n in module.programs}
        task = module.task
        if name is None:
            name = chosen_program(module.places, task, filename)
        elif name.upper() not in programs:
            raise STError.at(filename, f"no PROGRAM {name!r}", ", ".join(module.programs))
        name = programs[name.upper()]
        own = self.__dict__
        own["_name"], own["_module"], own["_filename"] = name, module, filename
        own["_fault"], own["_scans"], own["_axes"] = "", 0, dict(axes)
        if period is None:
            period = task.interval if task is not None else 0.01
        own["_every"] = ticks(task, period) if task is not None else 1
        """The PLC scans per run of the program (its TASK's INTERVAL over the scene's period)."""
        own["_where"] = f"<st {filename}>"
        own["_place"] = lambda line: f"{filename}:{line}"
        """``file:line`` of a line of the source (a project's: of its file)."""
        own["_vars"] = {
            k: v
            for k, v in {**module.globals, **module.programs[name]}.items()
            if "." in v.code or v.constant is not None
        }
        clock = clock if clock is not None else (lambda: own["_scans"] * period * own["_every"])
        namespace: dict[str, Any] = {"__name__": f"st_{Path(filename).stem}"}
        exec(compile(module.source, own["_where"], "exec"), namespace)
        namespace["_axes"] = own["_axes"]
        namespace["_clock"] = lambda: round(clock() * 1000.0)
        namespace["_now"] = clock
        namespace["_ext"] = dict(blocks or {})
        namespace["_perf"], namespace["_deadline"] = time.perf_counter, math.inf
        watchdog = task.watchdog if task is not None else None
        namespace["_watchdog"] = watchdog if watchdog is not None else WATCHDOG
        own["_namespace"] = namespace
        restart(self)

    name = _runtime("name", "The PROGRAM's name (its type, as declared).")
    module = _runtime("module", "The translated file (:class:`Module`).")
    filename = _runtime("filename", "The ST file, for messages.")
    fault = _runtime("fault", "The run-time fault that stopped the program, else empty.")
    scans = _runtime("scans", "The PLC scans the program ran.")
    every = _runtime(
        "every", "The PLC scans per run of the program (its TASK's INTERVAL over the period)."
    )
    restart = _Shadowed(restart)
    variables = _Shadowed(variables)
    stopped = _Shadowed(stopped, value=True)

    @property
    def error(self) -> str:
        """The run-time fault that stopped the program (``file:line: ...``), else the program's
        own STRING ``error`` (if it declares one: why its sequence stopped), else empty."""
        var = self._vars.get("error")
        return self.__dict__["_fault"] or (str(self._read(var)) if var is not None else "")

    @property
    def done(self) -> bool:
        """The program's BOOL ``done`` (if it declares one), else False."""
        var = self._vars.get("done")
        return bool(self._read(var)) if var is not None else False

    @property
    def step(self) -> str:
        """The program's ``step`` variable as text (if it declares one), else its name; the
        error once one stopped it."""
        var = self._vars.get("step")
        if self.error or var is None:
            return self.error or self.__dict__["_name"]
        value = self._read(var)
        if isinstance(var.type, EnumType):  # the value's name, as declared
            return next((n for n, v in var.type.values.items() if v == value), str(value))
        return str(value)

    def __call__(self) -> None:
        """One PLC scan (nothing once a fault stopped the program); the program runs every
        :attr:`every`-th scan (its TASK's INTERVAL)."""
        self._tick()

    def _stop(self, fault: Exception, tb: TracebackType | None) -> None:
        """Stop the PLC: the error names file:line; every axis ramps down and is disabled."""
        line = 0
        while tb is not None:
            if tb.tb_frame.f_code.co_filename == self._where:
                line = tb.tb_lineno
            tb = tb.tb_next
        own = self.__dict__
        st_lines = own["_module"].st_lines
        st_line = st_lines[line - 1] if 0 < line <= len(st_lines) else 0
        what = str(fault) if isinstance(fault, F.STFault) else f"{type(fault).__name__}: {fault}"
        own["_fault"] = f"{own['_place'](st_line)}: {what}; the program stopped"
        for axis in self._axes.values():
            axis.power(False)

    # ------------------------------------------------------------------ variables
    def _var(self, name: str) -> Var:
        var = self._vars.get(name.lower())
        if var is None:
            close = nearest(name, [v.name for v in self._vars.values()])
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise AttributeError(f"{program_name(self)} has no variable {name!r}{hint}")
        return var

    def _read(self, var: Var) -> Any:
        if var.constant is not None:
            return var.constant
        owner, _, attr = var.code.partition(".")
        target = self._namespace["_g"] if owner == "_g" else self._instance
        return getattr(target, attr)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return self._read(self._var(name))

    def __setattr__(self, name: str, value: Any) -> None:
        var = self._var(name)
        if var.constant is not None or var.read_only:
            raise AttributeError(f"{var.name} is a CONSTANT")
        owner, _, attr = var.code.partition(".")
        target = self._namespace["_g"] if owner == "_g" else self._instance
        setattr(target, attr, stored(value, var))


def _ticker(
    own: dict[str, Any],
    namespace: dict[str, Any],
    scan: Callable[[], None],
    stop: Callable[[Exception, TracebackType | None], None],
) -> Callable[[], None]:
    """One PLC scan of a program whose attributes are ``own``: ``scan()`` every
    ``own["_every"]``-th call, none once ``own["_fault"]`` is set, a fault to ``stop``; the
    scan's watchdog deadline (wall time [s]) set in the generated code's ``namespace``. A
    closure over the attributes: an attribute read of :class:`STProgram` (which has
    ``__getattr__``) costs more than the dictionary's."""
    every, limit, clock = own["_every"], namespace["_watchdog"], time.perf_counter

    def tick() -> None:
        if own["_fault"]:
            return
        namespace["_deadline"] = clock() + limit
        try:
            scan()
        except Exception as fault:  # any fault stops the PLC, never a traceback
            stop(fault, sys.exc_info()[2])
        own["_scans"] += 1

    def tick_every() -> None:
        calls = own["_calls"] = own["_calls"] + 1
        if not (calls - 1) % every:
            tick()

    return tick if every == 1 else tick_every


def stored(value: Any, var: Var) -> Any:
    """``value`` as variable ``var`` holds it (wrapped, rounded, cut).

    Raises:
        TypeError: a value its type cannot take.
    """
    t = var.type
    if not isinstance(t, Elementary):
        return value
    if t.kind == "bool":
        return bool(value)
    if t.kind == "string":
        return str(value)[: t.bits]
    if isinstance(value, bool | int | float) and math.isfinite(value):
        if t.integral or t.kind == "time":
            from plc.st.semantics.types import wrap_value

            return wrap_value(round(value), t) if t.integral else round(value)
        return F.f32(float(value)) if t.name == "REAL" else float(value)
    raise TypeError(f"{var.name} is {t.name}: {value!r} is no such value")


def _python(module: Module, name: str) -> str:
    from plc.st.semantics.catalog import python_name

    return python_name(name)


def compile_source(
    source: str,
    filename: str = "program.st",
    axes: Mapping[str, Any] | None = None,
    mapping: Mapping[str, str] | None = None,
    blocks: Mapping[str, External] | None = None,
) -> Module:
    """Parse and translate an ST source; ``axes`` and ``mapping`` name what AXIS_REFs bind to,
    ``blocks`` the machine's own block types (:class:`plc.st.External`).

    Raises:
        STError: a syntax or type error (``file:line:column: ...``), or a mapping onto an axis
            the machine lacks.
    """
    check_mapping(filename, axes or {}, mapping or {})
    return translated(parse(source, filename), filename, axes, mapping, blocks)


def check_mapping(filename: str, axes: Mapping[str, Any], mapping: Mapping[str, str]) -> None:
    """Raises STError where ``mapping`` binds a name onto an axis ``axes`` lacks."""
    for key, axis in mapping.items():
        if axis not in axes and not (axis.startswith("%") or "." in axis):
            raise STError.at(
                filename,
                f"the mapping {key} -> {axis!r} names no axis",
                f"one of {', '.join(axes) or 'no axes'}",
            )


def translated(
    tree: Any,
    filename: str,
    axes: Mapping[str, Any] | None = None,
    mapping: Mapping[str, str] | None = None,
    blocks: Mapping[str, External] | None = None,
) -> Module:
    """A parsed source (``tf.SourceCode``) translated, as :func:`compile_source`.

    Raises:
        STError: a type error or an unknown name (``file:line:column: ...``).
    """
    axes = dict(axes or {})
    unit = Unit(filename, {a: a for a in axes}, dict(mapping or {}), channels=channels(axes))
    unit.types.update({n.upper(): b.block_type(n) for n, b in (blocks or {}).items()})
    try:
        return translate(tree, unit)
    except STError:
        raise
    except Exception as error:  # a construct not foreseen: one message, never a traceback
        raise STError.at(
            filename,
            f"the program cannot be translated ({type(error).__name__}: {error})",
            "IEC 61131-3 Structured Text this translator supports (docs/st.md)",
        ) from None


def load(
    path: str | Path,
    machine: Any = None,
    mapping: Mapping[str, str] | None = None,
    program: str | None = None,
    period: float | None = None,
    blocks: Mapping[str, External] | None = None,
) -> STProgram:
    """Load the ST file ``path`` (or a TwinCAT project's ``.TcPOU``/``.TcDUT``/``.TcGVL``
    file, or a folder of them: :mod:`plc.st.frontend.project`) for ``machine`` (an
    :class:`mcl.Machine`, e.g. a scene, or None), with the machine's own block types
    ``blocks`` (:class:`plc.st.External`): its axes bind AXIS_REFs by name or through
    ``mapping`` (``{"Pohon.Ax1": "X"}``),
    its I/O located variables (``AT %IX0.2``) or named I/O (``{"Knife": "S.DO0"}``, see
    :mod:`plc.st.runtime.io`), its simulated time runs the timers; a TASK's INTERVAL runs the
    program
    every n-th scan of the machine's PLC period (``period`` without a machine).

    Raises:
        STError: the file is missing, has a syntax or type error, an I/O address the machine
            lacks, or a TASK INTERVAL that is no multiple of the PLC period.
    """
    file = Path(path)
    if is_project(file):
        return _load_project(file, machine, mapping, program, period, blocks)
    return from_source(read_source(file), machine, mapping, program, str(file), period, blocks)


def _load_project(
    path: Path,
    machine: Any,
    mapping: Mapping[str, str] | None,
    program: str | None,
    period: float | None,
    blocks: Mapping[str, External] | None,
) -> STProgram:
    """As :func:`load`, a TwinCAT project's source file or folder
    (:mod:`plc.st.frontend.project`); messages name its files' lines."""
    project = read_project(path)
    generated = f"{path.name}.st"
    try:
        prog = from_source(project.source, machine, mapping, program, generated, period, blocks)
    except STError as error:
        raise project.relocated(error, generated) from None
    prog.__dict__["_place"] = project.where
    return prog


def from_source(
    source: str,
    machine: Any = None,
    mapping: Mapping[str, str] | None = None,
    program: str | None = None,
    filename: str = "program.st",
    period: float | None = None,
    blocks: Mapping[str, External] | None = None,
) -> STProgram:
    """As :func:`load`, from the text of a source."""
    axes = dict(machine.axes) if machine is not None else {}
    module = compile_source(source, filename, axes, mapping, blocks)
    clock = (lambda: machine.time) if machine is not None else None
    runtime = getattr(machine, "runtime", None)
    period = runtime.plc_period if runtime is not None else period
    made = {n: b.make for n, b in (blocks or {}).items()}
    return STProgram(module, program, axes, clock, period, filename, made)

"""An ST file translated to one Python module (:func:`translate`): a class per PROGRAM and
FUNCTION_BLOCK (its variables are attributes, a call is one scan), a function per FUNCTION, a
class per STRUCT, the globals in ``_g``. Every Python line knows its ST line (:class:`Module`)."""

from __future__ import annotations

__all__ = ["POU", "Module", "translate"]

from dataclasses import dataclass, field
from typing import Any

import blark.transform as tf

from plc.st.codegen.expressions import Expressions
from plc.st.codegen.hoist import BIND, Body, fixed_inputs, own_fixed, self_written, uncopied
from plc.st.codegen.hoist import hoisted as hoisted_inputs
from plc.st.codegen.statements import Emitter, Statements
from plc.st.runtime.task import Task, configurations, task_of
from plc.st.semantics.catalog import python_name
from plc.st.semantics.declarations import STErrorAt, declare_type, folded, initial, spec_type
from plc.st.semantics.gvl import GVL, gvl_of, sections
from plc.st.semantics.scope import Callable_, Scope, Unit, Var
from plc.st.semantics.types import BlockType, Member, Type

_SECTIONS = {
    tf.InputDeclarations: "input",
    tf.OutputDeclarations: "output",
    tf.InputOutputDeclarations: "in_out",
    tf.TemporaryVariableDeclarations: "temp",
    tf.VariableDeclarations: "local",
    tf.LocatedVariableDeclarations: "local",
    tf.FunctionVariableDeclarations: "local",
    tf.StaticDeclarations: "local",
}


@dataclass
class Module:
    """The translation of one file.

    Attributes:
        source: the Python module.
        st_lines: the ST line of each Python line (index = Python line - 1).
        programs: PROGRAM name (as declared) → its class's variables (ST name → Var).
        globals: the global variables.
        bound: the axes the program uses (name in ``_g`` → axis name).
    """

    source: str
    st_lines: list[int]
    programs: dict[str, dict[str, Var]] = field(default_factory=dict)
    globals: dict[str, Var] = field(default_factory=dict)
    bound: dict[str, str] = field(default_factory=dict)
    task: Task | None = None
    """The cyclic task the configuration runs the program in (None: none declared)."""
    places: dict[str, tuple[int, int]] = field(default_factory=dict)
    """Each PROGRAM's (line, column) in the source, by name as declared."""


def _variables(block: Any) -> list[tuple[str, Any, Any, Any, Any]]:
    """(name, type spec, initial value node, location node or None, the node naming it) of
    every variable a declaration block declares."""
    found = []
    for item in block.items:
        init = getattr(item, "init", None)
        value = getattr(init, "value", None)
        if isinstance(init, tf.InitializedStructure):
            value = init.init
        if isinstance(item, tf.LocatedVariableDeclaration):  # name AT %IX0.2 : BOOL
            name = getattr(item.name, "name", item.name)
            found.append((str(name), init, value, item.location, item))
        for v in getattr(item, "variables", []):
            name = getattr(getattr(v, "variable", v), "name", v)
            at = v if getattr(v, "meta", None) is not None else item
            found.append((str(name), init, value, getattr(v, "location", None), at))
    return found


class POU:
    """One PROGRAM, FUNCTION_BLOCK or FUNCTION being translated."""

    def __init__(self, unit: Unit, node: Any) -> None:
        self.unit = unit
        self.node = node
        self.name = str(node.name)
        self.python = python_name(self.name)
        self.function = isinstance(node, tf.Function)
        self.scope = Scope(unit.globals)
        self.init: list[str] = []
        self.temps: list[str] = []
        self.members: dict[str, Member] = {}
        self.inputs: list[tuple[str, Type, str]] = []
        self.in_outs: list[tuple[str, Type]] = []
        self.outputs: list[tuple[str, Type]] = []
        self.order: list[str] = []
        """A function's inputs, in-outs and outputs in declaration order."""
        self.reads: list[str] = []
        """Lines reading the located inputs when a scan begins (a PROGRAM's)."""
        self.writes: list[str] = []
        """Lines writing the located outputs when a scan ends."""

    def declare(self) -> None:
        """Scope, members and initial values from the declaration blocks."""
        owner = "" if self.function else "self."
        for block in self.node.declarations or []:
            if isinstance(block, tf.ExternalVariableDeclarations):
                for item in block.items:
                    self.scope.add(self.external(item), self.unit.where(item))
                continue
            section = _SECTIONS.get(type(block))
            if section is None:
                raise STErrorAt(self.unit, block, f"{type(block).__name__}", "a VAR section")
            constant = "CONSTANT" in str(getattr(block, "attrs", "") or "").upper()
            for name, spec, value, location, at in _variables(block):
                self.variable(name, spec, value, section, constant, owner, at)
                self.locate(name, location, at if location is None else location)

    def external(self, item: tf.ExternalVariableDeclaration) -> Var:
        """The global a VAR_EXTERNAL names, of the type it declares; an AXIS_REF with no
        VAR_GLOBAL is the machine's axis of that name (or the mapping's)."""
        name = str(item.name)
        t = spec_type(self.unit, item.spec, self.scope)
        var = self.unit.globals.get(name)
        if var is None and t.kind == "axis" and self.unit.axis(name) is not None:
            return Var(name, t, str(self.unit.axis(name)), "global")
        if var is None:
            raise STErrorAt(self.unit, item, f"no VAR_GLOBAL {name}", "a global")
        if var.type.name.upper() != t.name.upper():
            raise STErrorAt(
                self.unit,
                item,
                f"VAR_EXTERNAL {name} : {t.name}",
                f"{var.type.name}, as the global",
            )
        return var

    def variable(
        self, name: str, spec: Any, value: Any, section: str, constant: bool, owner: str, at: Any
    ) -> None:
        """Declare one variable."""
        t = spec_type(self.unit, spec, self.scope)
        py = python_name(name)
        local = self.function or section == "temp"
        code = py if local else f"{owner}{py}"
        where = self.unit.where(at)
        if constant:
            fixed = folded(self.unit, t, value, spec, self.scope)
            if fixed is not None:
                self.scope.add(Var(name, t, code, section, fixed), where)
                return
        self.scope.add(Var(name, t, code, section, read_only=constant), where)
        if t.kind == "axis" and section not in ("in_out", "input"):
            bound = self.unit.axis(name)
            if bound is None:
                raise STErrorAt(
                    self.unit,
                    at,
                    f"AXIS_REF {name} is bound to no axis",
                    f"an axis of the machine ({', '.join(self.unit.axes) or 'none'}) or a mapping",
                )
            lines = [f"{code} = {bound}"]
        else:
            lines = initial(self.unit, code, t, value, self.scope, spec)
        (self.temps if local else self.init).extend(lines)
        if not self.function:
            self.members[name.upper()] = Member(t, section, py)
            return
        if section in ("input", "in_out", "output"):
            self.order.append(name)
        if section == "input":
            default = lines[0].split(" = ", 1)[1] if len(lines) == 1 else "None"
            self.inputs.append((name, t, default))
        elif section == "in_out":
            self.in_outs.append((name, t))
        elif section == "output":
            self.outputs.append((name, t))

    def locate(self, name: str, location: Any, at: Any) -> None:
        """Bind variable ``name`` to the I/O point it is located at (or the mapping names)."""
        var = self.scope.vars[name.lower()]
        point = self.unit.io_point(name, location, self.unit.where(at))
        if point is None:
            return
        problem = point.check_type(var.type)
        if isinstance(self.node, tf.Program) and var.section == "local" and not problem:
            io = point.code(self.unit.bind(point.axis))
            if point.output:
                self.writes.append(f"{io} = {var.code}")
            else:
                self.reads.append(f"{var.code} = {io}")
            return
        raise STErrorAt(
            self.unit,
            at,
            f"{name} on {point.kind}{point.number} of axis {point.axis}",
            problem or "a located variable in a PROGRAM's VAR or in VAR_GLOBAL",
        )

    def signature(self) -> None:
        """Register the POU's type (a block) or signature (a function) in the unit."""
        if self.function:
            result = spec_type(self.unit, self.node.return_type, self.scope)
            self.unit.functions[self.name.upper()] = Callable_(
                self.name, self.python, self.inputs, result, self.in_outs, self.outputs, self.order
            )
            self.scope.add(Var(self.name, result, "_r", "output"), self.unit.where(self.node))
            self.result = result
        elif isinstance(self.node, tf.FunctionBlock):
            block = BlockType(self.name, "user", self.members, self.python)
            self.unit.types[self.name.upper()] = block

    def body(
        self,
        out: Emitter,
        fixed: dict[str, set[str]],
        written: dict[str, set[str]],
        walked: Body,
    ) -> None:
        """The Python of the POU into ``out``; ``fixed``: the fixed inputs of every user block
        type (:func:`plc.st.codegen.hoist.fixed_inputs`), ``written``: the members each writes
        itself, ``walked``: the POU's statements as :mod:`plc.st.codegen.hoist` walked them."""
        out.st_line = self.unit.line(self.node)
        x = Expressions(self.unit, self.scope)
        if self.function:
            params = [f"{python_name(n)}={d}" for n, _, d in self.inputs]
            params += [f"{python_name(n)}=None" for n, _ in self.in_outs]
            out.emit(f"def {self.python}({', '.join(params)}):")
            out.depth += 1
            out.emit(f"_r = {_default_code(self.unit, self.result)}")
            passed = [n for n, _, _ in self.inputs] + [n for n, _ in self.in_outs]
            for line in _non_input_lines(self.temps, passed):
                out.emit(line)
            returned = [python_name(n) for n, _ in [*self.in_outs, *self.outputs]]
            result = ", ".join(["_r", *returned])  # with in-outs or outputs: a tuple
            Statements(x, out, result=result).block(self.node.body)
            out.emit(f"return {result}")
            out.depth -= 1
        else:
            block = isinstance(self.node, tf.FunctionBlock)
            own = own_fixed(walked, self.name, fixed) if block else frozenset()
            hoisted, _ = hoisted_inputs(
                walked, lambda m, v, p: x.convert(v, m.type, p), own, written
            )
            once = [f"{i}.{m} = {c}" for (i, m), c in hoisted.items()]
            bind = [line for line in once if "self." in line.split(" = ", 1)[1]] if block else []
            children = [
                f"{v.code}.{BIND}()"
                for v in self.scope.vars.values()
                if isinstance(v.type, BlockType)
                and v.type.origin == "user"
                and v.section == "local"
                and v.code == f"self.{python_name(v.name)}"
            ]
            out.emit(f"class {self.python}:")
            out.depth += 1
            out.emit("def __init__(self):")
            out.depth += 1
            lines = [*self.init, *(line for line in once if line not in bind)]
            for line in [*lines, f"self.{BIND}()"] if block else [*lines, *children]:
                out.emit(line)
            if not lines and not block:
                out.emit("pass")
            out.depth -= 1
            out.emit("")
            if block:  # the inner blocks' inputs fixed by this block's own fixed inputs
                out.emit(f"def {BIND}(self):")
                for line in [*bind, *children] or ["pass"]:
                    out.emit(f"    {line}")
                out.emit("")
            reads, writes = self.unit.reads + self.reads, self.unit.writes + self.writes
            if isinstance(self.node, tf.Program) and (reads or writes):
                out.emit("def __call__(self):")  # the process image around the scan
                for line in [*reads, "self._scan()", *writes]:
                    out.emit(f"    {line}")
                out.emit("")
                out.emit("def _scan(self):")
            else:
                out.emit("def __call__(self):")
            out.depth += 1
            for line in self.temps:
                out.emit(line)
            statements = Statements(x, out)
            statements.hoisted = hoisted
            statements.uncopied = uncopied(walked)
            statements.block(self.node.body)
            out.depth -= 2
        out.emit("")
        out.emit("")


def _default_code(unit: Unit, t: Type) -> str:
    from plc.st.semantics.declarations import default

    return default(unit, t)


def _non_input_lines(lines: list[str], passed: list[str]) -> list[str]:
    """A function's local initial lines without those of its parameters (its inputs and
    in-outs, ``passed``)."""
    names = {python_name(n) for n in passed}
    return [line for line in lines if line.split(" = ", 1)[0].split("[")[0] not in names]


def _globals(unit: Unit, blocks: list[tuple[Any, GVL | None]], out: Emitter) -> None:
    """The class of the globals (``_g``): VAR_GLOBAL variables, the bound axes; a named
    block's (a GVL's, :func:`~plc.st.semantics.gvl.sections`) variables are also
    ``GVL.name``, a qualified_only one's only so."""
    init: list[str] = []
    for block, gvl in blocks:
        constant = "CONSTANT" in str(block.attrs or "").upper()
        if gvl is not None:
            gvl = unit.gvls.setdefault(gvl.name.lower(), gvl)
        for item in block.items:
            t = spec_type(unit, item.init)
            value = getattr(item.init, "value", None)
            if isinstance(item.init, tf.InitializedStructure):
                value = item.init.init
            for name in item.spec.variables:
                st_name, py = str(name), python_name(str(name))
                if gvl is not None and gvl.qualified_only:  # two lists may share a name
                    st_name, py = f"{gvl.name}.{name}", f"{python_name(gvl.name)}__{name}"
                where = unit.where(item)
                fixed = folded(unit, t, value, item.init) if constant else None
                read_only = constant and fixed is None
                var = Var(st_name, t, f"_g.{py}", "global", fixed, read_only=read_only)
                unit.globals.add(var, where)
                if gvl is not None:
                    gvl.vars[str(name).lower()] = var
                if fixed is not None:
                    continue
                _locate_global(unit, var, item.spec.location, item)
                if t.kind == "axis":
                    init.append(f"self.{py} = {_global_axis(unit, gvl, str(name), item)}")
                else:
                    init += [
                        line.replace("_g.", "self.", 1)
                        for line in initial(unit, var.code, t, value, None, item.init)
                    ]
    out.emit("class _Globals:")
    out.emit("    def __init__(self):")
    out.depth += 2
    out.emit("for _name, _axis in _BOUND.items():")
    out.emit("    setattr(self, _name, _axes[_axis])")
    for line in init:
        out.emit(line)
    out.depth -= 2
    out.emit("")
    out.emit("")


def _global_axis(unit: Unit, gvl: GVL | None, name: str, item: Any) -> str:
    """The Python code of the axis a global AXIS_REF binds to: the mapping's for ``GVL.name``,
    else for ``name``, else the axis ``name``.

    Raises:
        STError: none.
    """
    bound = unit.axis(f"{gvl.name}.{name}") if gvl is not None else None
    bound = bound or unit.axis(name)
    if bound is None:
        raise STErrorAt(
            unit,
            item,
            f"AXIS_REF {name} is bound to no axis",
            f"an axis ({', '.join(unit.axes) or 'none'}) or a mapping",
        )
    return f"_axes[{unit.bound[bound[3:]]!r}]"


def _locate_global(unit: Unit, var: Var, location: Any, at: Any) -> None:
    """Bind global ``var`` to its I/O point (read and written around every program's scan)."""
    point = unit.io_point(var.name, location, unit.where(at))
    if point is None:
        return
    problem = point.check_type(var.type)
    if problem:
        raise STErrorAt(
            unit, at, f"{var.name} on {point.kind}{point.number} of {point.axis}", problem
        )
    io = point.code(unit.bind(point.axis))
    (unit.writes if point.output else unit.reads).append(
        f"{io} = {var.code}" if point.output else f"{var.code} = {io}"
    )


def _check_items(unit: Unit, items: list[Any], configs: list[Any]) -> None:
    """Raise STError at the first of a file's ``items`` that is none of PROGRAM,
    FUNCTION_BLOCK, FUNCTION, TYPE, VAR_GLOBAL or one of its ``configs`` (CONFIGURATION)."""
    unsupported = [
        i
        for i in items
        if i not in configs
        and not isinstance(
            i,
            tf.DataTypeDeclaration
            | tf.GlobalVariableDeclarations
            | tf.Program
            | tf.FunctionBlock
            | tf.Function,
        )
    ]
    if unsupported:
        raise STErrorAt(
            unit,
            unsupported[0],
            f"{type(unsupported[0]).__name__}",
            "PROGRAM, FUNCTION_BLOCK, FUNCTION, TYPE, VAR_GLOBAL",
        )


def translate(tree: tf.SourceCode, unit: Unit) -> Module:
    """The Python module of an ST file.

    Raises:
        STError: a type error or an unknown name, at its ``file:line:column``.
    """
    out = Emitter()
    for line in (
        "import math as _m",
        "",
        "import mcl as _mcl",
        "from plc.st.runtime import blocks as _std",
    ):
        out.emit(line)
    out.emit("from plc.st.runtime import functions as _f")
    out.emit("")
    out.emit("")
    items = list(tree.items)
    for item in items:
        if isinstance(item, tf.DataTypeDeclaration):
            out.st_line = unit.line(item)
            for line in declare_type(unit, item):
                out.emit(line)
    configs = configurations(items)
    global_blocks = sections(items, unit.where)
    for config in configs:  # a configuration's and its resources' VAR_GLOBAL
        for tree in [config, *config.find_data("resource_declaration")]:
            global_blocks += [
                (c, gvl_of(c, unit.where(c)))
                for c in tree.children
                if isinstance(c, tf.GlobalVariableDeclarations)
            ]
    pous = [
        POU(unit, i) for i in items if isinstance(i, tf.Program | tf.FunctionBlock | tf.Function)
    ]
    if not any(p.node.__class__ is tf.Program for p in pous):
        raise STErrorAt(unit, tree, "no PROGRAM in the file", "a PROGRAM ... END_PROGRAM")
    _check_items(unit, items, configs)
    body = Emitter()
    _globals(unit, global_blocks, body)
    for pou in pous:  # blocks and functions first: a program may use them
        if pou.function or isinstance(pou.node, tf.FunctionBlock):
            pou.declare()
            pou.signature()
    for pou in pous:
        if isinstance(pou.node, tf.Program):
            pou.declare()
    walked = [Body(Expressions(unit, p.scope), p.node.body) for p in pous]
    writes = self_written(
        (pou.name, w)
        for pou, w in zip(pous, walked, strict=True)
        if isinstance(pou.node, tf.FunctionBlock)
    )
    analysed = [(w, p.function) for p, w in zip(pous, walked, strict=True)]
    fixed = fixed_inputs(analysed, unit.globals.vars.values(), writes)
    for pou, w in zip(pous, walked, strict=True):
        pou.body(body, fixed, writes, w)
    out.emit(f"_BOUND = {dict(unit.bound)!r}")
    out.emit("")
    lines = out.lines + body.lines
    source = "\n".join(("    " * depth + text) if text else "" for depth, text, _ in lines) + "\n"
    module = Module(source, [st for _, _, st in lines], bound=dict(unit.bound))
    module.task = task_of(unit, items, [p.name for p in pous if isinstance(p.node, tf.Program)])
    module.globals = dict(unit.globals.vars)
    for pou in pous:
        if isinstance(pou.node, tf.Program):
            module.programs[pou.name] = dict(pou.scope.vars)
            module.places[pou.name] = (unit.line(pou.node), _column(pou.node))
    return module


def _column(node: Any) -> int:
    """The column a node begins at."""
    return int(getattr(getattr(node, "meta", None), "column", None) or 1)

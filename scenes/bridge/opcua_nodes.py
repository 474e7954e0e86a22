"""A machine's signal tables as an OPC UA node tree (asyncua 2.1), for the server of
:mod:`scenes.bridge.opcua`.

::

    Objects
    └─ <machine>                      the scene's machine (a cell: one object per part below it)
       ├─ Axes
       │  └─ <axis>                   X, Y, Z on the gantry
       │     ├─ <field>               every field of the axis' block (position … inputs)
       │     │  └─ status: done, busy, … in_force (Boolean, one per status bit)
       │     └─ MC_Power(Enable), MC_Reset(), MC_MoveAbsolute(Position, Velocity, …), …
       ├─ Group                       the axes group (where the machine names one)
       │  ├─ <field>                  every field of the group block (control … actual_3)
       │  └─ MC_GroupEnable(), MC_MoveCircularAbsolute(CircMode, AuxPoint, EndPoint, …), …
       ├─ Signals
       │  └─ <signal>                 the published signals (read-only)
       └─ Simulation: time, cycle, mode, target, control; Advance(Cycles)

A variable is a field of the table (``ns=<bridge>;s=X.actual_position``: the NodeId's string is
the field's name in the register map); REAL fields are Double, the integer ones UInt16, Int16 or
UInt32. The writable ones (the parameters, the control and output words, ``sim.target``) are
written into the table as a Modbus client writes them; every other write is refused. A method
is a PLCopen block called with its inputs: the parameters are set and its Execute rises at the
next scan (:meth:`SignalTable.request`); its Done, Busy, Error and ErrorID are the axis' status
variables from then on. Nothing here writes the physics.

A refused write or call is answered with a Bad status and changes nothing: BadTypeMismatch (not
a number, a Boolean, an axis name where one is due), BadOutOfRange (NaN, ±inf, beyond a REAL or
the integer's type), BadInvalidArgument for a call with such an argument (each one's status in
its InputArgumentResults), BadNotWritable (a read-only variable), BadInvalidState (the PLC is not
in control, or Advance while free-running).

The variables are a mirror of the tables, brought up to date after each publish of the
simulation (:attr:`Run.on_publish`, changed values only, so a subscription sees every change)
and after each client write or call.
"""

from __future__ import annotations

__all__ = [
    "ADMIN",
    "MAX_ADVANCE",
    "NAMESPACE",
    "VARIANT",
    "BridgeNodes",
    "Mirror",
    "Served",
    "Variable",
    "Writes",
    "engineering_units",
    "unit_of",
]

import asyncio
import contextlib
import logging
import math
import re
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass
from datetime import UTC
from typing import Any, Protocol

from asyncua import Server, ua
from asyncua.common.node import Node
from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.address_space import AttributeService

import mcl
from scenes.bridge.opcua_group import GROUP_METHODS, GroupMethod, group_command, point
from scenes.bridge.opcua_methods import (
    ARGUMENT_TYPE,
    RANGE,
    Argument,
    Method,
    Refused,
    boolean,
    methods_of,
    number,
)
from scenes.bridge.program import BridgeProgram
from scenes.bridge.runs import Run
from scenes.bridge.serving import acknowledge
from scenes.bridge.table import STATUS_BITS, Field, Kind, NotInControl, SignalTable, WriteRefused
from scenes.definition import MachineDef

log = logging.getLogger(__name__)

NAMESPACE = "urn:mcl-testbench:bridge"
"""The namespace of the bridge's nodes."""

MAX_ADVANCE = 100_000
"""Most PLC cycles one Advance may ask for (200 s of the gantry)."""

VARIANT: dict[Kind, ua.VariantType] = {
    "u16": ua.VariantType.UInt16,
    "i16": ua.VariantType.Int16,
    "u32": ua.VariantType.UInt32,
    "f32": ua.VariantType.Double,
}
"""The OPC UA type of each kind of field."""

_USER_UNIT = re.compile(r"\bu\b")


def unit_of(field: Field, user_unit: str) -> str:
    """A field's unit with the axis' user unit for ``u`` (``u/s`` → ``mm/s``)."""
    return _USER_UNIT.sub(user_unit, field.unit) if user_unit else field.unit


def engineering_units(unit: str) -> ua.EUInformation:
    """EngineeringUnits of a unit by its name (no UNECE code: UnitId −1)."""
    return ua.EUInformation(
        NamespaceUri="http://www.opcfoundation.org/UA/units/un/cefact",
        UnitId=-1,
        DisplayName=ua.LocalizedText(unit),
        Description=ua.LocalizedText(unit),
    )


@dataclass
class Variable:
    """A variable node of a table's field."""

    node: ua.NodeId
    table: SignalTable
    field: Field

    @property
    def variant(self) -> ua.VariantType:
        """Its OPC UA type."""
        return VARIANT[self.field.kind]


def _variant(value: float, kind: ua.VariantType) -> ua.Variant:
    if kind == ua.VariantType.Double:
        return ua.Variant(float(value), kind)
    if kind == ua.VariantType.Boolean:
        return ua.Variant(bool(value), kind)
    return ua.Variant(int(value), kind)


def _same(a: float, b: float) -> bool:
    """Whether ``a`` and ``b`` are the same value to the bit (0.0 and −0.0 differ, NaNs are
    the same)."""
    if a != a or b != b:
        return a != a and b != b
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


class Mirror:
    """The variables' values, kept equal to the tables': :meth:`refresh` writes what changed
    (and so notifies the subscriptions); :meth:`published` asks for it from the simulation
    thread, at most one pending refresh at a time.

    Args:
        server: the asyncua server.
        variables: the variables of the fields.
        bits: per status word's field name (of its table), its bit variables in bit order.
    """

    def __init__(
        self,
        server: Server,
        variables: Sequence[Variable],
        bits: dict[tuple[int, str], list[ua.NodeId]],
    ) -> None:
        self.server = server
        self.tables: list[SignalTable] = []
        self._of: list[list[Variable]] = []
        for v in variables:
            if v.table not in self.tables:
                self.tables.append(v.table)
                self._of.append([])
            self._of[self.tables.index(v.table)].append(v)
        self._bits = bits
        self._last: dict[ua.NodeId, float] = {}
        self._words: dict[tuple[int, str], int] = {}
        self._lock = asyncio.Lock()
        self._pending = False
        self._loop = asyncio.get_running_loop()
        self._tasks: set[asyncio.Task[None]] = set()

    def published(self, cycle: int) -> None:
        """A publish happened (the simulation thread): refresh soon, in the loop."""
        if self._pending:
            return
        self._pending = True
        with contextlib.suppress(RuntimeError):  # the loop closed: the server stops
            self._loop.call_soon_threadsafe(self._start)

    def _start(self) -> None:
        task = self._loop.create_task(self.refresh())
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def refresh(self) -> None:
        """Write every variable whose field changed since the last refresh."""
        async with self._lock:
            self._pending = False
            changes: list[tuple[ua.NodeId, ua.Variant]] = []
            for t, (table, variables) in enumerate(zip(self.tables, self._of, strict=True)):
                values = table.snapshot()
                for v in variables:
                    self._diff(v, values[v.field.name], changes)
                for (k, name), nodes in self._bits.items():
                    if k != t:
                        continue
                    word = int(values[name])
                    changed = word ^ self._words.get((k, name), ~word)
                    self._words[(k, name)] = word
                    changes += [
                        (node, ua.Variant(bool(word >> i & 1)))
                        for i, node in enumerate(nodes)
                        if changed >> i & 1
                    ]
            await self._write_all(changes)

    async def refresh_one(self, v: Variable) -> None:
        """Write variable ``v`` if its field changed (after a client's write of it)."""
        async with self._lock:
            changes: list[tuple[ua.NodeId, ua.Variant]] = []
            self._diff(v, v.table.get(v.field.name), changes)
            await self._write_all(changes)

    def _diff(self, v: Variable, value: float, changes: list[tuple[ua.NodeId, ua.Variant]]) -> None:
        """Add ``v`` with ``value`` to ``changes`` unless it holds it already, bit for bit."""
        last = self._last.get(v.node)
        if last is not None and _same(value, last):
            return
        self._last[v.node] = value
        changes.append((v.node, _variant(value, v.variant)))

    async def _write_all(self, changes: list[tuple[ua.NodeId, ua.Variant]]) -> None:
        """Write the changed values, all with the same timestamp (lock held)."""
        if not changes:
            return
        now = ua.DateTime.now(UTC)
        for node, variant in changes:
            await self._write(node, variant, now)

    async def _write(self, node: ua.NodeId, variant: ua.Variant, now: ua.DateTime) -> None:
        value = ua.DataValue(variant, SourceTimestamp=now, ServerTimestamp=now)
        await self.server.write_attribute_value(node, value)


ADMIN = User(role=UserRole.Admin)
"""asyncua's default user of a write (the server's own)."""


class Writes(AttributeService):
    """asyncua's attribute service with the writes of the tables' variables taken over by
    ``write_value`` (its status; None: not one of them, asyncua's rules apply)."""

    def __init__(
        self,
        service: AttributeService,
        write_value: Callable[[ua.WriteValue], Awaitable[ua.StatusCode | None]],
    ) -> None:
        super().__init__(service._aspace)
        self._write_value = write_value

    async def write(self, params: ua.WriteParameters, user: User = ADMIN) -> list[ua.StatusCode]:
        """The status of each write, in order."""
        results = []
        for item in params.NodesToWrite:
            status = None
            if item.NodeId not in self._aspace:
                status = _status(ua.StatusCodes.BadNodeIdUnknown)
            elif item.AttributeId == ua.AttributeIds.Value:
                status = await self._write_value(item)
            if status is None:
                one = ua.WriteParameters(NodesToWrite=[item])
                status = (await super().write(one, user))[0]
            results.append(status)
        return results


class Served(Protocol):
    """What a node tree serves: a machine's definition, its tables and the bridge program that
    scans them; ``run``, the simulation thread of a headless server (None: another thread scans,
    the viewer's, and tells :meth:`BridgeNodes.published`)."""

    @property
    def definition(self) -> MachineDef: ...

    @property
    def tables(self) -> list[SignalTable]: ...

    @property
    def program(self) -> BridgeProgram: ...

    @property
    def lockstep(self) -> bool: ...

    @property
    def run(self) -> Run | None: ...


class BridgeNodes:
    """The node tree of ``bridge``'s tables in ``server`` (:meth:`build` makes it) and what its
    writes and calls do.

    Args:
        server: the asyncua server (initialised, not started).
        bridge: the machine with its tables, program and run.
    """

    def __init__(self, server: Server, bridge: Served) -> None:
        self.server = server
        self.bridge = bridge
        self.tables = bridge.tables
        self.index = 0
        self.variables: dict[ua.NodeId, Variable] = {}
        self.readonly: set[ua.NodeId] = set()
        self._bits: dict[tuple[int, str], list[ua.NodeId]] = {}
        self.mirror: Mirror | None = None
        self._axes = bridge.program.front_ends

    def published(self, cycle: int) -> None:
        """The tables were published (any thread): the variables follow soon."""
        if self.mirror is not None:
            self.mirror.published(cycle)

    def node(self, name: str) -> ua.NodeId:
        """The NodeId of ``name`` in the bridge's namespace."""
        return ua.NodeId(ua.String(name), ua.Int16(self.index))

    async def build(self) -> None:
        """Make the tree, the mirror (hooked to the run's publish) and take over the writes."""
        server = self.server
        self.index = await server.register_namespace(NAMESPACE)
        name = self.bridge.definition.name
        machine = await server.nodes.objects.add_object(self.node(name), f"{self.index}:{name}")
        for k, table in enumerate(self.tables):
            parent = machine
            prefix = table.axes[0].split("/")[0] + "/" if "/" in table.axes[0] else ""
            if prefix:
                part = prefix[:-1]
                parent = await machine.add_object(self.node(part), f"{self.index}:{part}")
            await self._table(k, table, parent, prefix)
        if self.bridge.definition.parts:  # a cell's own signals, once (every table has them)
            await self._signals(self.tables[0], machine, "", own=False)
        await self._simulation(machine)
        self.mirror = Mirror(server, list(self.variables.values()), self._bits)
        await self.mirror.refresh()
        if self.bridge.run is not None:
            self.bridge.run.on_publish.append(self.mirror.published)
        iserver = server.iserver
        iserver.attribute_service = Writes(iserver.attribute_service, self.write_value)

    async def _table(self, k: int, table: SignalTable, parent: Node, prefix: str) -> None:
        """The Axes, the Group (where the machine names one) and the Signals of a table."""
        axes = await parent.add_folder(self.node(f"{prefix}Axes"), f"{self.index}:Axes")
        for axis in table.axes:
            bare = axis[len(prefix) :]
            node = await axes.add_object(self.node(axis), f"{self.index}:{bare}")
            unit = self._axes[axis].operator.axis.config.unit
            for f in table.fields:
                if f.name.startswith(f"{axis}."):
                    variable = await self._variable(node, table, f, f.name[len(axis) + 1 :], unit)
                    if f.name.endswith(".status"):
                        await self._status_bits(k, variable, f.name)
            for method in methods_of(self._axes[axis]):
                await self._method(node, table, axis, method)
        if table.group:  # the group block's fields and its methods
            group = await parent.add_object(self.node(table.group), f"{self.index}:Group")
            unit = self._axes[table.members[0]].operator.axis.config.unit
            for f in table.fields:
                if f.name.startswith(f"{table.group}."):
                    await self._variable(group, table, f, f.name[len(table.group) + 1 :], unit)
            for group_method in GROUP_METHODS:
                await self._method(group, table, table.group, group_method)
        await self._signals(table, parent, prefix)

    async def _signals(
        self, table: SignalTable, parent: Node, prefix: str, own: bool = True
    ) -> None:
        """The Signals folder: the table's published signals (a part's: those of ``prefix``),
        or (``own`` False) a cell's own, which every part's table has after the part's."""
        signals = await parent.add_folder(self.node(f"{prefix}Signals"), f"{self.index}:Signals")
        for f in table.fields:
            name = f.name.removeprefix("signal.")
            if name == f.name:
                continue
            if name.startswith(prefix) if own else "/" not in name:
                await self._variable(signals, table, f, name.removeprefix(prefix))

    async def _simulation(self, machine: Node) -> None:
        """The Simulation object: the sim fields of the first table, and Advance."""
        table = self.tables[0]
        sim = await machine.add_object(self.node("sim"), f"{self.index}:Simulation")
        for f in table.fields:
            if f.name.startswith("sim."):
                await self._variable(sim, table, f, f.name[len("sim.") :])
        cycles = ua.Argument(
            Name="Cycles",
            DataType=ua.NodeId(ua.Int32(ua.ObjectIds.UInt32)),
            ValueRank=-1,
            Description=ua.LocalizedText(f"PLC cycles to run (1…{MAX_ADVANCE})"),
        )
        cycle = ua.Argument(
            Name="Cycle",
            DataType=ua.NodeId(ua.Int32(ua.ObjectIds.UInt32)),
            ValueRank=-1,
            Description=ua.LocalizedText("the PLC cycle the tables show when it returns"),
        )
        advance = await sim.add_method(
            self.node("sim.Advance"), f"{self.index}:Advance", self._advance, [cycles], [cycle]
        )
        await _describe(advance, "lockstep: run Cycles PLC cycles, return when published")

    async def _variable(
        self, parent: Node, table: SignalTable, f: Field, name: str, user_unit: str = ""
    ) -> Node:
        """The variable of field ``f``: its type, access, description and unit."""
        kind = VARIANT[f.kind]
        value = _variant(table.get(f.name), kind)
        node = await parent.add_variable(self.node(f.name), f"{self.index}:{name}", value, kind)
        unit = unit_of(f, user_unit)
        text = f"{f.description} [{unit}]" if unit and unit != "bits" else f.description
        await _describe(node, text)
        if unit and unit != "bits":
            await node.add_property(
                self.node(f"{f.name}.EngineeringUnits"),
                "0:EngineeringUnits",
                engineering_units(unit),
            )
        if f.access == "rw":
            await node.set_writable()
        self.variables[node.nodeid] = Variable(node.nodeid, table, f)
        return node

    async def _status_bits(self, k: int, status: Node, name: str) -> None:
        """The Boolean variables of a status word's bits, below it."""
        nodes = []
        for bit in STATUS_BITS:
            node = await status.add_variable(
                self.node(f"{name}.{bit}"), f"{self.index}:{bit}", False, ua.VariantType.Boolean
            )
            await _describe(node, f"status bit {bit}")
            nodes.append(node.nodeid)
            self.readonly.add(node.nodeid)
        self._bits[(k, name)] = nodes

    async def _method(self, parent: Node, table: SignalTable, axis: str, method: Method) -> None:
        members = len(table.members)
        arguments = [
            ua.Argument(
                Name=a.name,
                DataType=ua.NodeId(ua.Int32(ARGUMENT_TYPE[a.kind].value)),
                ValueRank=1 if a.kind == "point" else -1,
                ArrayDimensions=[members] if a.kind == "point" else [],
                Description=ua.LocalizedText(a.description),
            )
            for a in method.arguments
        ]

        async def call(parent: ua.NodeId, *args: ua.Variant) -> ua.CallMethodResult:
            return await self._call(table, axis, method, args)

        node = await parent.add_method(
            self.node(f"{axis}.{method.name}"), f"{self.index}:{method.name}", call, arguments, []
        )
        await _describe(node, method.description)

    # -------------------------------------------------------------------- writes and calls

    async def write_value(self, item: ua.WriteValue) -> ua.StatusCode | None:
        """A client's write of a variable's value (None: not a variable of the tables)."""
        if item.NodeId in self.readonly:
            return _status(ua.StatusCodes.BadNotWritable)
        v = self.variables.get(item.NodeId)
        if v is None:
            return None
        name = v.field.name
        try:
            if v.field.access != "rw":
                raise Refused(ua.StatusCodes.BadNotWritable, f"{name} is read-only")
            if item.IndexRange:
                raise Refused(ua.StatusCodes.BadIndexRangeNoData, f"{name} is no array")
            value = number(item.Value.Value if item.Value else None, v.field.kind)
            for table in self.tables if name.startswith("sim.") else [v.table]:
                table.put(name, value)
        except Refused as refused:
            log.warning("refused: write of %s: %s", name, refused)
            return _status(refused.code)
        except NotInControl as refused:
            log.warning("refused: write of %s: %s", name, refused)
            return _status(ua.StatusCodes.BadInvalidState)
        except WriteRefused as refused:
            log.warning("refused: write of %s: %s", name, refused)
            return _status(ua.StatusCodes.BadNotWritable)
        run = self.bridge.run
        if name == "sim.target" and self.bridge.lockstep and run is not None:
            await acknowledge(run, int(value))
            await self._refresh()
        elif self.mirror is not None:
            await self.mirror.refresh_one(v)
        return ua.StatusCode()

    async def _refresh(self) -> None:
        if self.mirror is not None:
            await self.mirror.refresh()

    async def _call(
        self, table: SignalTable, axis: str, method: Method, args: Sequence[ua.Variant]
    ) -> ua.CallMethodResult:
        """A method call: its arguments checked, then the command into the table."""
        result = ua.CallMethodResult()
        if len(args) != len(method.arguments):
            code = ua.StatusCodes.BadArgumentsMissing
            if len(args) > len(method.arguments):
                code = ua.StatusCodes.BadTooManyArguments
            result.StatusCode = _status(code)
            return result
        values: dict[str, Any] = {}
        statuses = []
        for argument, variant in zip(method.arguments, args, strict=True):
            try:
                values[argument.name] = self._argument(table, axis, argument, variant)
                statuses.append(ua.StatusCode())
            except Refused as refused:
                log.warning("refused: %s.%s %s: %s", axis, method.name, argument.name, refused)
                statuses.append(_status(refused.code))
        if any(s.is_bad() for s in statuses):
            result.StatusCode = _status(ua.StatusCodes.BadInvalidArgument)
            result.InputArgumentResults = statuses
            return result
        try:
            self._command(table, axis, method, values)
        except NotInControl as refused:
            log.warning("refused: %s.%s: %s", axis, method.name, refused)
            result.StatusCode = _status(ua.StatusCodes.BadInvalidState)
            return result
        await self._refresh()
        result.InputArgumentResults = statuses
        return result

    def _argument(self, table: SignalTable, axis: str, argument: Argument, variant: Any) -> Any:
        """The value of one argument.

        Raises:
            Refused: it is not one.
        """
        if not isinstance(variant, ua.Variant):
            raise Refused(ua.StatusCodes.BadTypeMismatch, "no value")
        kind = argument.kind
        if kind == "bool":
            return boolean(variant)
        if kind == "point":
            return point(variant, len(table.members))
        if kind == "axis":
            if variant.VariantType != ua.VariantType.String or not isinstance(variant.Value, str):
                raise Refused(ua.StatusCodes.BadTypeMismatch, "an axis name is due")
            prefix = axis[: axis.rfind("/") + 1]
            for i, name in enumerate(table.axes):
                if variant.Value in (name, name[len(prefix) :]):
                    return i
            raise Refused(ua.StatusCodes.BadOutOfRange, f"no axis {variant.Value[:40]!r}")
        if kind == "direction":
            direction = number(variant, "i32")
            if direction not in (mcl.MC_Direction.MC_Positive, mcl.MC_Direction.MC_Negative):
                raise Refused(ua.StatusCodes.BadOutOfRange, "Direction is 1 or 3")
            return int(direction)
        return number(variant, kind)

    def _command(
        self, table: SignalTable, axis: str, method: Method, values: dict[str, Any]
    ) -> None:
        """Method ``method`` with its checked ``values`` into the table.

        Raises:
            NotInControl: the PLC is not in control.
        """
        if isinstance(method, GroupMethod):
            group_command(table, axis, method, values)
        elif method.bit == "enable":
            table.set_bit(axis, "enable", values["Enable"])
        elif method.bit == "jog":
            table.put(f"{axis}.velocity", values["JogVelo"])
            table.set_bit(axis, "jog_pos", values["JogPos"])
            table.set_bit(axis, "jog_neg", values["JogNeg"])
        elif method.bit == "outputs":
            if values["OutputNumber"] >= len(self._axes[axis].operator.outputs):
                return  # no such output: as MC_WriteDigitalOutput, nothing happens
            table.put_bit(f"{axis}.outputs", int(values["OutputNumber"]), values["Value"])
        else:
            params = {a.field: values[a.name] for a in method.arguments if a.field}
            if values.get("Direction") == mcl.MC_Direction.MC_Negative:
                params["velocity"] = -params["velocity"]
            table.request(axis, method.bit, params)

    async def _advance(self, parent: ua.NodeId, *args: ua.Variant) -> ua.CallMethodResult:
        """Advance(Cycles): lockstep, run Cycles PLC cycles; answered when they are published
        (at most :data:`scenes.bridge.serving.ACK_TIMEOUT`) with the cycle the tables show."""
        result = ua.CallMethodResult()
        if len(args) != 1:
            code = (
                ua.StatusCodes.BadArgumentsMissing
                if not args
                else ua.StatusCodes.BadTooManyArguments
            )
            result.StatusCode = _status(code)
            return result
        bridge = self.bridge
        try:
            cycles = int(number(args[0] if isinstance(args[0], ua.Variant) else None, "u32"))
            if not 0 <= cycles <= MAX_ADVANCE:
                raise Refused(ua.StatusCodes.BadOutOfRange, f"Cycles is 0…{MAX_ADVANCE}")
        except Refused as refused:
            log.warning("refused: Advance: %s", refused)
            result.StatusCode = _status(ua.StatusCodes.BadInvalidArgument)
            result.InputArgumentResults = [_status(refused.code)]
            return result
        target = bridge.program.target + cycles
        run = bridge.run
        try:
            if not bridge.lockstep or run is None:
                raise Refused(ua.StatusCodes.BadInvalidState, "free-running: no lockstep")
            if target > RANGE["u32"][1]:
                raise Refused(ua.StatusCodes.BadInvalidState, "the cycle counter is full")
            for table in self.tables:
                table.put("sim.target", target)
        except (Refused, NotInControl) as refused:
            log.warning("refused: Advance: %s", refused)
            result.StatusCode = _status(ua.StatusCodes.BadInvalidState)
            return result
        await acknowledge(run, target)
        await self._refresh()
        result.InputArgumentResults = [ua.StatusCode()]
        result.OutputArguments = [ua.Variant(run.published, ua.VariantType.UInt32)]
        return result


def _status(code: int) -> ua.StatusCode:
    """The status of ``code`` (of ua.StatusCodes)."""
    return ua.StatusCode(ua.UInt32(code))


async def _describe(node: Node, text: str) -> None:
    """Set a node's Description."""
    value = ua.DataValue(ua.Variant(ua.LocalizedText(text), ua.VariantType.LocalizedText))
    await node.write_attribute(ua.AttributeIds.Description, value)

"""The signal table of a machine: every value an external PLC reads or writes, at a fixed
Modbus register address, generated from the machine's definition.

Addresses are 16-bit holding registers, counted from 0 (the PDU address). A ``u16`` takes one
register, a ``u32`` or ``f32`` two, high word first (big-endian word order, "ABCD"; pymodbus:
``word_order="big"``). The layout is deterministic:

=========================  ======================================================================
0 …                        simulation: time [s] (f32), PLC cycle counter (u32), mode, lockstep
                           target cycle (u32)
100 + 50·i …               axis ``i`` in the definition's order (:data:`AXIS_FIELDS`)
1000 + 2·k                 published signal ``k`` in the definition's order (f32, read-only)
=========================  ======================================================================

The table holds the registers (thread-safe); the PLC program (:mod:`scenes.bridge.program`)
and the servers read and write it by field name or by address.
"""

from __future__ import annotations

import math
import struct
import threading
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Literal

from scenes.definition import MachineDef, Signal

Kind = Literal["u16", "u32", "f32"]
Access = Literal["r", "rw"]

AXIS_BASE = 100
"""Address of the first axis' control word."""
AXIS_STRIDE = 50
"""Registers between two axes."""
SIGNAL_BASE = 1000
"""Address of the first published signal."""

CONTROL_BITS = (
    "enable",
    "reset",
    "move_absolute",
    "move_relative",
    "move_velocity",
    "home",
    "stop",
    "halt",
    "jog_pos",
    "jog_neg",
)
"""Bits of an axis' control word, bit 0 first. ``enable`` and the jogs are levels; the others
are Execute inputs (a rising edge starts the command; keep the bit set until Done)."""

STATUS_BITS = (
    "done",
    "busy",
    "active",
    "error",
    "command_aborted",
    "homed",
    "lim_neg",
    "ref",
    "lim_pos",
    "power",
)
"""Bits of an axis' status word, bit 0 first: Done … CommandAborted of the current command
(the one last started by a rising edge), homed (the axis has a reference), the switches LIM−,
REF and LIM+, and MC_Power's Status."""


@dataclass(frozen=True)
class FieldSpec:
    """One value of an axis' block (offset from the axis' base address)."""

    name: str
    offset: int
    kind: Kind
    access: Access
    unit: str
    description: str


AXIS_FIELDS = (
    FieldSpec("control", 0, "u16", "rw", "bits", "control word: " + ", ".join(CONTROL_BITS)),
    FieldSpec("position", 2, "f32", "rw", "u", "MC_MoveAbsolute Position"),
    FieldSpec("distance", 4, "f32", "rw", "u", "MC_MoveRelative Distance"),
    FieldSpec("velocity", 6, "f32", "rw", "u/s", "Velocity of moves and jogs"),
    FieldSpec("acceleration", 8, "f32", "rw", "u/s²", "Acceleration"),
    FieldSpec("deceleration", 10, "f32", "rw", "u/s²", "Deceleration (also of Stop, Halt)"),
    FieldSpec("jerk", 12, "f32", "rw", "u/s³", "Jerk (0: trapezoidal)"),
    FieldSpec("status", 20, "u16", "r", "bits", "status word: " + ", ".join(STATUS_BITS)),
    FieldSpec("state", 21, "u16", "r", "", "PLCopen state number (mcl.AxisState)"),
    FieldSpec("error_id", 22, "u16", "r", "", "ErrorID of the current command"),
    FieldSpec("axis_error_id", 23, "u16", "r", "", "ErrorID of the axis (AxErrorID)"),
    FieldSpec("actual_position", 24, "f32", "r", "u", "actual position"),
    FieldSpec("actual_velocity", 26, "f32", "r", "u/s", "actual velocity"),
    FieldSpec("following_error", 28, "f32", "r", "u", "following error"),
    FieldSpec("volts", 30, "f32", "r", "V", "drive command voltage"),
    FieldSpec("command", 32, "u16", "r", "", "current command: its control bit + 1 (0: none)"),
)
"""The block of every axis."""

WIDTH = {"u16": 1, "u32": 2, "f32": 2}
"""Registers per kind."""


@dataclass(frozen=True)
class Field:
    """One value of the table at its address."""

    name: str
    address: int
    kind: Kind
    access: Access
    unit: str
    description: str

    @property
    def width(self) -> int:
        """Registers it takes."""
        return WIDTH[self.kind]


def encode(kind: Kind, value: float) -> list[int]:
    """The registers of a value (high word first)."""
    if kind == "u16":
        return [int(value) & 0xFFFF]
    if kind == "u32":
        v = int(value) & 0xFFFFFFFF
        return [v >> 16, v & 0xFFFF]
    hi, lo = struct.unpack(">HH", struct.pack(">f", value))
    return [hi, lo]


def decode(kind: Kind, registers: Sequence[int]) -> float:
    """The value of registers (high word first)."""
    if kind == "u16":
        return float(registers[0])
    if kind == "u32":
        return float(registers[0] << 16 | registers[1])
    return float(struct.unpack(">f", struct.pack(">HH", registers[0], registers[1]))[0])


def published_signals(machine: MachineDef) -> dict[str, Signal]:
    """The signals a scene of the machine publishes by name: its own, then a cell's parts'
    prefixed with the part's name (``press/force``)."""
    signals = dict(machine.signals)
    for part in machine.parts:
        signals.update({f"{part.machine.name}/{n}": s for n, s in part.machine.signals.items()})
    return signals


def machine_fields(machine: MachineDef) -> list[Field]:
    """The fields of a machine, in address order."""
    fields = [
        Field("sim.time", 0, "f32", "r", "s", "simulated time"),
        Field("sim.cycle", 2, "u32", "r", "", "PLC cycles run"),
        Field("sim.mode", 4, "u16", "r", "", "0: free-running, 1: lockstep"),
        Field("sim.target", 6, "u32", "rw", "", "lockstep: run until sim.cycle reaches it"),
    ]
    for i, axis in enumerate(machine.scene_axes):
        base = AXIS_BASE + AXIS_STRIDE * i
        fields += [
            Field(f"{axis}.{f.name}", base + f.offset, f.kind, f.access, f.unit, f.description)
            for f in AXIS_FIELDS
        ]
    for k, (name, signal) in enumerate(published_signals(machine).items()):
        text = signal.label or name
        fields.append(Field(f"signal.{name}", SIGNAL_BASE + 2 * k, "f32", "r", signal.unit, text))
    return fields


class WriteRefused(ValueError):
    """A write the table refuses (an address that is not a writable field)."""


class SignalTable:
    """The registers of a machine's signal table (thread-safe).

    Args:
        machine: its definition; gives the axes and the published signals.
    """

    def __init__(self, machine: MachineDef) -> None:
        self.machine = machine.name
        self.fields = machine_fields(machine)
        self.axes = list(machine.scene_axes)
        self.signals = list(published_signals(machine))
        self.by_name = {f.name: f for f in self.fields}
        self.size = max(f.address + f.width for f in self.fields)
        self._owner = {a: f for f in self.fields for a in range(f.address, f.address + f.width)}
        self._registers = [0] * self.size
        self._lock = threading.Lock()
        self.written = threading.Event()
        """Set by every client write (a lockstep run waits on it)."""

    def get(self, name: str) -> float:
        """The value of field ``name``."""
        f = self.by_name[name]
        with self._lock:
            return decode(f.kind, self._registers[f.address : f.address + f.width])

    def set(self, name: str, value: float) -> None:
        """Set field ``name`` (the PLC side: any access)."""
        f = self.by_name[name]
        if f.kind != "f32" and not (math.isfinite(value) and value >= 0):
            value = 0
        with self._lock:
            self._registers[f.address : f.address + f.width] = encode(f.kind, value)

    def update(self, values: Iterable[tuple[str, float]]) -> None:
        """Set several fields."""
        for name, value in values:
            self.set(name, value)

    def read(self, address: int, count: int) -> list[int]:
        """``count`` registers from ``address`` (unmapped ones read 0).

        Raises:
            WriteRefused: the range leaves the table.
        """
        if address < 0 or count < 1 or address + count > self.size:
            raise WriteRefused(f"registers {address}…{address + count - 1} lie outside the table")
        with self._lock:
            return self._registers[address : address + count]

    def write(self, address: int, values: Sequence[int]) -> None:
        """Write registers from a client: every one must belong to a writable field.

        Raises:
            WriteRefused: an address outside every writable field (nothing is written).
        """
        for a in range(address, address + len(values)):
            f = self._owner.get(a)
            if f is None or f.access != "rw":
                raise WriteRefused(f"register {a} is not writable")
        if any(not 0 <= v <= 0xFFFF for v in values):
            raise WriteRefused("a register holds 0…65535")
        with self._lock:
            self._registers[address : address + len(values)] = list(values)
        self.written.set()

    def markdown(self) -> str:
        """The register map as a Markdown table."""
        lines = [
            f"# Register map of {self.machine}",
            "",
            "Holding registers of unit id 1, PDU addresses from 0; u32 and f32 in two registers, "
            "high word first; u: the axis' user unit (mm on a slide, deg on a hinge).",
            "",
            "| address | name | type | access | unit | description |",
            "|---:|---|---|---|---|---|",
        ]
        lines += [
            f"| {f.address} | {f.name} | {f.kind} | {f.access} | {f.unit} | {f.description} |"
            for f in self.fields
        ]
        return "\n".join(lines)

    def csv(self) -> str:
        """The register map as CSV."""
        rows = ["address,name,type,access,unit,description"]
        rows += [
            f'{f.address},{f.name},{f.kind},{f.access},{f.unit},"{f.description}"'
            for f in self.fields
        ]
        return "\n".join(rows)

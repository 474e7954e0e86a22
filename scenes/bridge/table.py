"""The signal table of a machine: every value an external PLC reads or writes, at a fixed
Modbus register address, generated from the machine's definition.

Addresses are 16-bit holding registers, counted from 0 (the PDU address). A ``u16`` or ``i16``
(two's complement) takes one register, a ``u32`` or ``f32`` two, high word first (big-endian
word order, "ABCD"; pymodbus: ``word_order="big"``). The layout is deterministic:

=========================  ======================================================================
0 …                        simulation: time [s] (f32), PLC cycle counter (u32), mode, lockstep
                           target cycle (u32)
100 + 100·i …              axis ``i`` in the definition's order (:data:`AXIS_FIELDS`), a block of
                           :data:`AXIS_BLOCK` registers of the same shape on every axis: the
                           offsets that are no field of the axis are reserved (they read 0 and
                           take 0)
900 …                      the group of a machine that names one (:data:`GROUP_FIELDS`): its
                           axes moved together on lines, arcs and paths
1000 + 2·k                 published signal ``k`` in the definition's order (f32, read-only)
=========================  ======================================================================

The table holds the registers (thread-safe); the PLC program (:mod:`scenes.bridge.program`,
each axis' block as :class:`AxisRegisters`) and the servers read and write it by field name or by
address. The bits of the control and status words are the operator program's
(:mod:`plc.operator.bus`).
"""

from __future__ import annotations

__all__ = [
    "ANALOG_OFFSET",
    "AXIS_BASE",
    "AXIS_BLOCK",
    "AXIS_FIELDS",
    "AXIS_STRIDE",
    "CONTROL_BITS",
    "FORCE_FIELDS",
    "GEAR_FIELDS",
    "GROUP_BASE",
    "GROUP_BLOCK",
    "GROUP_CONTROL_BITS",
    "GROUP_STATUS_BITS",
    "LEVELS",
    "MAX_ANALOG",
    "OUTPUTS",
    "SIGNAL_BASE",
    "STATUS_BITS",
    "WIDTH",
    "Access",
    "AxisRegisters",
    "Field",
    "FieldSpec",
    "Kind",
    "NotInControl",
    "SignalTable",
    "ValueRefused",
    "WriteRefused",
    "axis_specs",
    "decode",
    "encode",
    "group_specs",
    "machine_fields",
    "published_signals",
    "tables_of",
]

import math
import struct
import threading
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

from mcl import AxisState, GroupState
from plc.operator.bus import CONTROL_BITS, LEVELS, STATUS_BITS
from plc.operator.group_bus import GROUP_CONTROL_BITS, GROUP_STATUS_BITS
from scenes.definition import AxisDef, MachineDef, Signal

Kind = Literal["u16", "i16", "u32", "f32"]
Access = Literal["r", "rw"]

AXIS_BASE = 100
"""Address of the first axis' control word."""
AXIS_STRIDE = 100
"""Registers between two axes."""
AXIS_STATES = ", ".join(f"{int(s)} {s.name}" for s in AxisState)
"""The numbers of the ``state`` register of an axis (mcl.AxisState)."""
GROUP_STATES = ", ".join(f"{int(s)} {s.name}" for s in GroupState)
"""The numbers of the ``state`` register of a group (mcl.GroupState)."""
SIGNAL_BASE = 1000
"""Address of the first published signal."""
GROUP_BASE = 900
"""Address of the group block's control word."""


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
    FieldSpec("distance", 4, "f32", "rw", "u", "MC_MoveRelative / MC_MoveAdditive Distance"),
    FieldSpec("velocity", 6, "f32", "rw", "u/s", "Velocity of moves and jogs"),
    FieldSpec("acceleration", 8, "f32", "rw", "u/s²", "Acceleration"),
    FieldSpec("deceleration", 10, "f32", "rw", "u/s²", "Deceleration (also of Stop, Halt)"),
    FieldSpec("jerk", 12, "f32", "rw", "u/s³", "Jerk (0: trapezoidal)"),
    FieldSpec("buffer_mode", 14, "u16", "rw", "", "BufferMode of moves (mcl.MC_BufferMode)"),
    FieldSpec("status", 20, "u16", "r", "bits", "status word: " + ", ".join(STATUS_BITS)),
    FieldSpec("state", 21, "u16", "r", "", f"PLCopen state (mcl.AxisState): {AXIS_STATES}"),
    FieldSpec("error_id", 22, "u16", "r", "", "ErrorID of the current command"),
    FieldSpec("axis_error_id", 23, "u16", "r", "", "ErrorID of the axis (AxErrorID)"),
    FieldSpec("actual_position", 24, "f32", "r", "u", "actual position"),
    FieldSpec("actual_velocity", 26, "f32", "r", "u/s", "actual velocity"),
    FieldSpec("following_error", 28, "f32", "r", "u", "following error"),
    FieldSpec("volts", 30, "f32", "r", "V", "drive command voltage"),
    FieldSpec("command", 32, "u16", "r", "", "current command: its control bit + 1 (0: none)"),
    FieldSpec("inputs", 33, "u16", "r", "bits", "digital inputs: LIM+, LIM−, REF, TP, further"),
    FieldSpec("command_count", 49, "u16", "r", "", "commands started (+1 each; wraps at 65536)"),
)
"""The fields of every axis."""

GEAR_FIELDS = (
    FieldSpec("master", 15, "u16", "rw", "", "gearing: the master's axis number in this table"),
    FieldSpec("ratio_numerator", 16, "f32", "rw", "", "gearing: RatioNumerator (an INT)"),
    FieldSpec("ratio_denominator", 18, "f32", "rw", "", "gearing: RatioDenominator (an INT)"),
    FieldSpec("master_sync_position", 34, "f32", "rw", "u", "MC_GearInPos MasterSyncPosition"),
    FieldSpec("slave_sync_position", 36, "f32", "rw", "u", "MC_GearInPos SlaveSyncPosition"),
    FieldSpec("master_start_distance", 38, "f32", "rw", "u", "MC_GearInPos MasterStartDistance"),
    FieldSpec("zeroing", 48, "u16", "rw", "", "MC_GearInPos Zeroing (0 none, 1 length, 2 mark)"),
)
"""The gearing fields of an axis that can be a slave."""

FORCE_FIELDS = (
    FieldSpec("force", 50, "f32", "rw", "F", "MC_ForceControl Force (F: the force unit)"),
    FieldSpec("force_ramp", 52, "f32", "rw", "F/s", "MC_ForceControl ForceRamp (0: at once)"),
    FieldSpec("gain", 54, "f32", "rw", "u/s/F", "MC_ForceControl Gain (admittance)"),
    FieldSpec("tolerance", 56, "f32", "rw", "F", "MC_ForceControl Tolerance (InForce window)"),
    FieldSpec("scale", 58, "f32", "rw", "F/V", "MC_ForceControl Scale of InputNumber"),
    FieldSpec("scale2", 60, "f32", "rw", "F/V", "MC_ForceControl Scale2 of InputNumber2"),
    FieldSpec("offset", 62, "f32", "rw", "F", "MC_ForceControl Offset"),
    FieldSpec("input_number", 64, "i16", "rw", "", "MC_ForceControl InputNumber"),
    FieldSpec("input_number2", 65, "i16", "rw", "", "MC_ForceControl InputNumber2 (−1: none)"),
    FieldSpec("actual_force", 66, "f32", "r", "F", "MC_ForceControl ActualForce"),
)
"""The force-control fields of an axis with analog inputs (velocity and acceleration are the
move's fields)."""


_MEMBER_FIELDS: tuple[tuple[str, int, Access, str, str], ...] = (
    ("end", 2, "rw", "u", "EndPoint (MC_MoveLinear*: Position, Distance)"),
    ("aux", 8, "rw", "u", "AuxPoint (RADIUS: aux_1 is the radius)"),
    ("actual", 38, "r", "u", "actual position"),
)
"""The group block's fields of each member: name, offset of member 1, access, unit, text."""


def group_specs(members: int) -> list[FieldSpec]:
    """The fields of the group block for a group of ``members`` axes, in offset order."""
    per_member: list[FieldSpec] = [
        FieldSpec(
            f"{name}_{k + 1}", offset + 2 * k, "f32", access, unit, f"{text} of member {k + 1}"
        )
        for name, offset, access, unit, text in _MEMBER_FIELDS
        for k in range(members)
    ]
    words: tuple[tuple[str, int, Access, str, str], ...] = (
        ("control", 0, "rw", "bits", "control word: " + ", ".join(GROUP_CONTROL_BITS)),
        ("circ_mode", 14, "rw", "", "CircMode (mcl.MC_CIRC_MODE: 0 BORDER, 1 CENTER, 2 RADIUS)"),
        ("path_choice", 15, "rw", "", "PathChoice (0 clockwise, 1 counter-clockwise)"),
        ("buffer_mode", 24, "rw", "", "BufferMode of moves and segments (mcl.MC_BufferMode)"),
        ("plane", 25, "rw", "", "Plane of arcs (0 automatic, 17 XY, 18 ZX, 19 YZ)"),
        ("relative", 26, "rw", "", "1: end and aux relative to the start (MC_Move*Relative)"),
        ("turns", 27, "rw", "", "Turns: more full turns of a CENTER arc"),
        ("coord_system", 28, "rw", "", "CoordSystem of moves (mcl.MC_COORD_SYSTEM: 0 ACS … 2 PCS)"),
        ("status", 30, "r", "bits", "status word: " + ", ".join(GROUP_STATUS_BITS)),
        ("state", 31, "r", "", f"group state (mcl.GroupState): {GROUP_STATES}"),
        ("error_id", 32, "r", "", "ErrorID of the current command"),
        ("group_error_id", 33, "r", "", "the group's error (MC_GroupReadError GroupErrorID)"),
        ("command", 34, "r", "", "current command: its control bit + 1 (0: none)"),
        ("command_count", 35, "r", "", "commands started (+1 each; wraps at 65536)"),
        ("segments", 36, "r", "", "segments appended to the path (append_line, append_arc)"),
    )
    reals = (
        ("velocity", 16, "u/s", "Velocity along the path"),
        ("acceleration", 18, "u/s²", "Acceleration along the path (0: default; also of frames)"),
        ("deceleration", 20, "u/s²", "Deceleration along the path (0: default; also of stop)"),
        ("jerk", 22, "u/s³", "Jerk along the path (0: default; also of stop and frames)"),
        ("vel_factor", 44, "", "VelFactor of set_override (1.0: 100 %, 0 … 2.0)"),
        ("acc_factor", 46, "", "AccFactor of set_override (0 < … ≤ 4.0)"),
        ("jerk_factor", 48, "", "JerkFactor of set_override (0 < … ≤ 8.0)"),
    )
    specs = [FieldSpec(n, o, "u16", a, u, t) for n, o, a, u, t in words]
    specs += [FieldSpec(n, o, "f32", "rw", u, t) for n, o, u, t in reals]
    return sorted(specs + per_member + _frame_specs(members), key=lambda spec: spec.offset)


_FRAME_FIELDS = (
    ("frame", 52, "set_frame CoordTransform, track_belt ConveyorBeltOrigin: the PCS origin"),
    ("object", 60, "track_belt InitialObjectPosition: the part in the belt frame at the latch"),
)
"""The group block's points of the product coordinate system (x, y, z [mm] of the MCS)."""


def _frame_specs(members: int) -> list[FieldSpec]:
    """The fields of the product coordinate system (:mod:`mcl.tracking`): its points, their
    rotation, the belt and the part's latch."""
    specs = [
        FieldSpec(f"{name}_{k + 1}", offset + 2 * k, "f32", "rw", "mm", f"{text}, {'xyz'[k]}")
        for name, offset, text in _FRAME_FIELDS
        for k in range(members)
    ]
    belt = "track_belt ConveyorBelt: the belt's axis number in this table"
    return [
        *specs,
        FieldSpec("belt", 50, "u16", "rw", "", belt),
        FieldSpec("frame_rz", 58, "f32", "rw", "deg", "the PCS's rotation about z (frame)"),
        FieldSpec("latched_position", 66, "f32", "rw", "u", "track_belt LatchedPosition (belt)"),
        FieldSpec("horizon", 68, "f32", "rw", "s", "track_belt Horizon (0: the part now)"),
    ]


GROUP_BLOCK = max(f.offset + 2 for f in group_specs(3))
"""Registers of the group block (offsets 0 … 69)."""

OUTPUTS = FieldSpec("outputs", 1, "u16", "rw", "bits", "digital outputs, bit k = output k")
"""The digital outputs of an axis that has some (MC_WriteDigitalOutput on every change)."""

ANALOG_OFFSET = 40
"""Offset of the first analog input of an axis (f32 each, at most :data:`MAX_ANALOG`)."""
MAX_ANALOG = 4

WIDTH = {"u16": 1, "i16": 1, "u32": 2, "f32": 2}
"""Registers per kind."""

AXIS_BLOCK = max(
    f.offset + WIDTH[f.kind] for f in (*AXIS_FIELDS, *GEAR_FIELDS, *FORCE_FIELDS, OUTPUTS)
)
"""Registers of an axis' block (offsets 0 … 67), the same on every axis: the offsets that are
no field of the axis (another axis' gearing, force or output fields, analog inputs it lacks)
are reserved: they read 0 and take 0, so that one write block fits every axis."""


def axis_specs(axis: AxisDef, can_gear: bool) -> list[FieldSpec]:
    """The fields of an axis' block: every axis' own, gearing where it can be a slave, its
    digital outputs and analog inputs where it has them; in offset order."""
    specs = list(AXIS_FIELDS)
    if can_gear:
        specs += GEAR_FIELDS
    if axis.digital_outputs:
        specs.append(OUTPUTS)
    if axis.analog:
        specs += FORCE_FIELDS
    specs += [
        FieldSpec(f"analog_{k}", ANALOG_OFFSET + 2 * k, "f32", "r", "V", f"analog input {name}")
        for k, name in enumerate(axis.analog[:MAX_ANALOG])
    ]
    return sorted(specs, key=lambda spec: spec.offset)


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
    if kind in ("u16", "i16"):
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
    if kind == "i16":
        return float(registers[0] - (registers[0] >> 15 << 16))
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


def machine_fields(
    machine: MachineDef, prefix: str = "", shared: Mapping[str, Signal] | None = None
) -> list[Field]:
    """The fields of a machine, in address order; ``prefix`` before its axes' and signals'
    names (a part of a cell: ``press/``); ``shared``: signals after the machine's own, under
    their own names (a cell's own, such as its interlock's, in every part's table)."""
    fields = [
        Field("sim.time", 0, "f32", "r", "s", "simulated time"),
        Field("sim.cycle", 2, "u32", "r", "", "PLC cycles run"),
        Field("sim.mode", 4, "u16", "r", "", "0: free-running, 1: lockstep"),
        Field("sim.target", 6, "u32", "rw", "", "lockstep: run until sim.cycle reaches it"),
        Field("sim.control", 8, "u16", "r", "", "1: the PLC is in control, 0: it is refused"),
    ]
    axes = {prefix + a: spec for a, spec in machine.scene_axes.items()}
    for i, (axis, spec) in enumerate(axes.items()):
        base = AXIS_BASE + AXIS_STRIDE * i
        can_gear = spec.drive != "encoder" and len(axes) > 1
        fields += [
            Field(f"{axis}.{f.name}", base + f.offset, f.kind, f.access, f.unit, f.description)
            for f in axis_specs(spec, can_gear)
        ]
    if machine.group:
        fields += [
            Field(
                f"{prefix}group.{f.name}",
                GROUP_BASE + f.offset,
                f.kind,
                f.access,
                f.unit,
                f.description,
            )
            for f in group_specs(len(machine.group))
        ]
    signals = {prefix + n: s for n, s in published_signals(machine).items()}
    signals.update(shared or {})
    for k, (name, signal) in enumerate(signals.items()):
        text = signal.label or name
        fields.append(Field(f"signal.{name}", SIGNAL_BASE + 2 * k, "f32", "r", signal.unit, text))
    return fields


def _integer(kind: Kind, value: float) -> float:
    """What an integer register of ``kind`` holds for ``value`` (0: not finite, or negative
    where unsigned)."""
    if not math.isfinite(value) or (value < 0 and kind != "i16"):
        return 0.0
    if kind == "u32":
        return float(int(value) & 0xFFFFFFFF)
    word = int(value) & 0xFFFF
    return float(word - (word >> 15 << 16)) if kind == "i16" else float(word)


class WriteRefused(ValueError):
    """A write the table refuses (an address that is not a writable field)."""


class ValueRefused(WriteRefused):
    """A write the table refuses for its value (not 0 into a reserved register)."""


class NotInControl(WriteRefused):
    """A write refused because the PLC is not in control (an operator of the viewer is)."""


class SignalTable:
    """The registers of a machine's signal table (thread-safe).

    Args:
        machine: its definition; gives the axes and the published signals.
        prefix: before the axes' and signals' names (a part of a cell: ``press/``).
        unit_id: the machine's Modbus unit id.
        shared: signals published after the machine's own (a part of a cell: the cell's own).
        units: the unit ids served beside this one (a cell's parts'), for the map.
    """

    def __init__(
        self,
        machine: MachineDef,
        prefix: str = "",
        unit_id: int = 1,
        shared: Mapping[str, Signal] | None = None,
        units: Sequence[int] = (1,),
    ) -> None:
        self.machine = machine.name
        self.definition = machine
        self.unit_id = unit_id
        self.units = tuple(units)
        """Every unit id the server serves (this one among them)."""
        self.fields = machine_fields(machine, prefix, shared)
        self.axes = [prefix + a for a in machine.scene_axes]
        self.group = f"{prefix}group" if machine.group else ""
        """The group block's name (``group``; empty: the machine has none)."""
        self.members = [prefix + a for a in machine.group]
        """The group's axes, in member order."""
        self.signals = [
            f.name[len("signal.") :] for f in self.fields if f.name.startswith("signal.")
        ]
        """The published signals' names as the scene knows them (``press/force``)."""
        self.by_name = {f.name: f for f in self.fields}
        self._owner = {a: f for f in self.fields for a in range(f.address, f.address + f.width)}
        blocks = [(AXIS_BASE + AXIS_STRIDE * i, AXIS_BLOCK) for i in range(len(self.axes))]
        if self.group:
            blocks.append((GROUP_BASE, GROUP_BLOCK))
        self.reserved = frozenset(
            a for b, n in blocks for a in range(b, b + n) if a not in self._owner
        )
        """The reserved registers of the axes' and the group's blocks: they read 0 and take 0."""
        self.size = max([f.address + f.width for f in self.fields] + [b + n for b, n in blocks])
        self._values = dict.fromkeys(self.by_name, 0.0)
        """Every field's value: the truth; registers are encoded from it when a client reads
        and decoded into it when one writes (the scan's side never packs a register)."""
        self._lock = threading.Lock()
        words = [*self.axes, self.group] if self.group else self.axes
        self._rose = dict.fromkeys(words, 0)
        self._requests: dict[str, tuple[int, int]] = dict.fromkeys(words, (0, -1))
        self.written = threading.Event()
        """Set by every client write (a lockstep run waits on it)."""
        self.set("sim.control", 1)

    def get(self, name: str) -> float:
        """The value of field ``name``."""
        return self._values[name]

    def set(self, name: str, value: float) -> None:
        """Set field ``name`` (the PLC side: any access); an integer field takes what its
        register holds (0 for a value that is not finite, or negative where unsigned)."""
        kind = self.by_name[name].kind
        self._values[name] = value if kind == "f32" else _integer(kind, value)

    def update(self, values: Iterable[tuple[str, float]]) -> None:
        """Set several fields."""
        with self._lock:
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
            return self._registers(address, count)

    def _registers(self, address: int, count: int) -> list[int]:
        """The register image of ``address`` … ``address + count − 1`` (lock held)."""
        image = [0] * count
        a = address
        while a < address + count:
            f = self._owner.get(a)
            if f is None:
                a += 1
                continue
            words = encode(f.kind, self._values[f.name])
            for k, word in enumerate(words):
                if address <= f.address + k < address + count:
                    image[f.address + k - address] = word
            a = f.address + f.width
        return image

    @property
    def in_control(self) -> bool:
        """Whether the PLC may command (``sim.control``); while not, its writes and requests
        are refused with :class:`NotInControl` and the program leaves the axes alone."""
        return self.get("sim.control") == 1

    @in_control.setter
    def in_control(self, on: bool) -> None:
        self.set("sim.control", 1 if on else 0)

    def _check_control(self) -> None:
        if not self.in_control:
            raise NotInControl("the PLC is not in control: an operator of the viewer is")

    def write(self, address: int, values: Sequence[int]) -> None:
        """Write registers from a client: every one must belong to a writable field.

        Raises:
            WriteRefused: an address outside every writable field and reserved register.
            ValueRefused: a value beyond 0…65535, or not 0 into a reserved register.
            NotInControl: the PLC is not in control (in every case nothing is written).
        """
        self._check_control()
        for a in range(address, address + len(values)):
            f = self._owner.get(a)
            if (f.access != "rw") if f is not None else (a not in self.reserved):
                raise WriteRefused(f"register {a} is not writable")
        for a, v in enumerate(values, start=address):
            if not 0 <= v <= 0xFFFF:
                raise ValueRefused("a register holds 0…65535")
            if v and a in self.reserved:
                raise ValueRefused(f"register {a} is reserved: it takes 0 only")
        end = address + len(values)
        with self._lock:
            a = address
            while a < end:
                f = self._owner.get(a)
                if f is None:  # reserved: stays 0
                    a += 1
                    continue
                lo = f.address
                image = self._registers(lo, f.width)
                for k in range(f.width):
                    if address <= lo + k < end:
                        image[k] = values[lo + k - address]
                self._store(f, decode(f.kind, image))
                a = lo + f.width
        self.written.set()

    def put(self, name: str, value: float) -> None:
        """Write field ``name`` from a client by name (an OPC UA write): as :meth:`write` does
        its registers; an integer field takes what its register would hold.

        Raises:
            WriteRefused: not a writable field; NotInControl: the PLC is not in control.
        """
        f = self._writable(name)
        with self._lock:
            self._store(f, value if f.kind == "f32" else _integer(f.kind, value))
        self.written.set()

    def put_bit(self, name: str, bit: int, on: bool) -> None:
        """Set or clear bit ``bit`` of the writable word field ``name`` from a client (a control
        or output bit), leaving its other bits as they are.

        Raises:
            WriteRefused: not a writable word field, or no bit of one; NotInControl: the PLC is
                not in control.
        """
        f = self._writable(name)
        if f.kind != "u16" or not 0 <= bit < 16:
            raise WriteRefused(f"{name} has no bit {bit}")
        with self._lock:
            word = int(self._values[name])
            self._store(f, float(word | 1 << bit if on else word & ~(1 << bit)))
        self.written.set()

    def _writable(self, name: str) -> Field:
        """Field ``name`` if a client may write it now.

        Raises:
            WriteRefused: not a writable field; NotInControl: the PLC is not in control.
        """
        f = self.by_name.get(name)
        if f is None or f.access != "rw":
            raise WriteRefused(f"{name} is not a writable field")
        self._check_control()
        return f

    def _store(self, f: Field, value: float) -> None:
        """Store a client's value of ``f`` (lock held); a control word's rising bits are kept
        for the next scan."""
        if f.name.endswith(".control"):
            axis = f.name[: -len(".control")]
            self._rose[axis] |= int(value) & ~int(self._values[f.name])
        self._values[f.name] = value

    def snapshot(self) -> dict[str, float]:
        """Every field's value at one instant, by name."""
        with self._lock:
            return dict(self._values)

    def take_control(self, axis: str) -> int:
        """The control word of ``axis`` for this scan: the bits set now and those that rose
        since the last scan (a pulse shorter than a scan still gives its rising edge)."""
        with self._lock:
            word = int(self._values[f"{axis}.control"]) | self._rose[axis]
            self._rose[axis] = 0
        return word

    def control_bits(self, block: str) -> tuple[str, ...]:
        """The control bits of ``block``: :data:`GROUP_CONTROL_BITS` of the group, an axis'
        :data:`CONTROL_BITS`."""
        return GROUP_CONTROL_BITS if block == self.group else CONTROL_BITS

    def set_bit(self, axis: str, bit: str, on: bool) -> None:
        """Set or clear control bit ``bit`` of ``axis`` (or of the group), as a client writes
        it.

        Raises:
            WriteRefused: an unknown axis or bit; NotInControl: the PLC is not in control.
        """
        if axis not in self._rose or bit not in self.control_bits(axis):
            raise WriteRefused(f"no control bit {axis}.{bit}")
        self.put_bit(f"{axis}.control", self.control_bits(axis).index(bit), on)

    def request(self, axis: str, command: str, params: Mapping[str, float] | None = None) -> None:
        """Issue Execute command ``command`` of ``axis`` (or of the group) as a method call
        does: ``params`` (field name → value) are set at once and the command's bit of the
        control word is cleared (the call takes the command over); the program raises the
        command's Execute at its next scan (after one scan low if its bit was set) and holds it
        until the axis' next command, so that its Done, Error, InVelocity and the like stay
        visible; the same command requested again gets a fresh rising edge.

        Raises:
            WriteRefused: an unknown axis, a level or unknown command, a field that is not a
                writable parameter of the axis (nothing is set); NotInControl: the PLC is not
                in control.
        """
        bits = self.control_bits(axis)
        if axis not in self._requests or command not in bits or command in LEVELS:
            raise WriteRefused(f"no command {axis}.{command}")
        self._check_control()
        fields = {}
        for name, value in (params or {}).items():
            f = self.by_name.get(f"{axis}.{name}")
            if f is None or f.access != "rw" or name == "control":
                raise WriteRefused(f"{axis} has no parameter {name!r}")
            fields[f.name] = value
        self.update(fields.items())
        bit = bits.index(command)
        with self._lock:  # the call takes the command over from the control word's bit
            self._values[f"{axis}.control"] = float(
                int(self._values[f"{axis}.control"]) & ~(1 << bit)
            )
            self._rose[axis] &= ~(1 << bit)
            self._requests[axis] = (bit, self._requests[axis][1] + 1)
        self.written.set()

    def requested(self, axis: str) -> tuple[int, int]:
        """The last request of ``axis``: its control bit and a serial number (-1: none yet)."""
        with self._lock:
            return self._requests[axis]

    def markdown(self) -> str:
        """The register map as Markdown (:mod:`scenes.bridge.register_map`)."""
        from scenes.bridge import register_map

        return register_map.markdown(self)

    def csv(self) -> str:
        """The registers as CSV."""
        from scenes.bridge import register_map

        return register_map.csv(self)


class AxisRegisters:
    """The block of axis ``axis`` (or of the group, ``group``) in ``table`` as the operator
    program's bus front ends read and write it (:class:`plc.operator.handshake.Registers`): its
    fields by their names without the block's."""

    def __init__(self, table: SignalTable, axis: str) -> None:
        self.table = table
        self.axis = axis
        self._prefix = prefix = f"{axis}."
        self._fields = {f.name[len(prefix) :] for f in table.fields if f.name.startswith(prefix)}

    @property
    def in_control(self) -> bool:
        """Whether the PLC may command (:attr:`SignalTable.in_control`)."""
        return self.table.in_control

    def has(self, name: str) -> bool:
        """Whether the axis has field ``name``."""
        return name in self._fields

    def get(self, name: str) -> float:
        """The value of field ``name`` (0.0: the axis has none)."""
        return self.table.get(self._prefix + name) if name in self._fields else 0.0

    def take_control(self) -> int:
        """This scan's control word (:meth:`SignalTable.take_control`)."""
        return self.table.take_control(self.axis)

    def requested(self) -> tuple[int, int]:
        """The last method call (:meth:`SignalTable.requested`)."""
        return self.table.requested(self.axis)

    def update(self, values: Iterable[tuple[str, float]]) -> None:
        """Set several of the axis' fields."""
        prefix = self._prefix
        self.table.update((prefix + name, value) for name, value in values)


def tables_of(machine: MachineDef) -> list[SignalTable]:
    """The signal tables of a scene of ``machine``: one, or a cell's one per part (unit ids
    1, 2, … in the cell's order; each with the simulation fields, the lockstep target being
    the largest any of them was given, and the cell's own signals after the part's)."""
    if not machine.parts:
        return [SignalTable(machine)]
    units = range(1, len(machine.parts) + 1)
    return [
        SignalTable(part.machine, f"{part.machine.name}/", unit, machine.signals, units)
        for unit, part in zip(units, machine.parts, strict=True)
    ]

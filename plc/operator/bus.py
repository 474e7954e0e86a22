"""The fieldbus front end of the operator program: a master's command words and parameter
registers as the orders of an axis (:class:`~plc.operator.axis.AxisOperator`), and the axis'
status word and actual values back into its registers.

The registers are the master's (the bridge's signal table, :mod:`scenes.bridge.table`); this
module sees an axis' registers through :class:`Registers`. The control word's bits
(:data:`CONTROL_BITS`) are the commands of :data:`~plc.operator.axis.COMMANDS` by name:
``enable`` is MC_Power's Enable and ``jog_pos``/``jog_neg`` the jog levels (|velocity| as
JogVelo); every other bit is its command's Execute, passed every scan, so its rising edge starts
the command with the parameter registers of that scan, and the block's outputs follow the
PLCopen rules. The ``outputs`` register drives the digital outputs. A command the axis cannot
take (home without a recipe, gearing on an axis without gearing registers, force control
without force registers) is refused: the status shows Error with ErrorID EParam (5).

A method call (the registers' :meth:`Registers.requested`) sets its command's Execute at the
next scan and holds it until the axis' next command; a request whose bit was high in the last
scan, or a master's command on the bit a request holds, first gets one scan low (a fresh rising
edge). A held MC_Stop keeps the axis in Stopping, so when a call of ``stop`` is held the next
command — a call or the control word's — waits one scan: the stop ends (Done AND NOT Execute)
and the axis stands still when the command starts.

The status word shows the outputs of the current command, the one last started, and
``command_count`` counts the commands started. A result of the current command (Done, Error with
its ErrorID, CommandAborted) is held in the status until the master acknowledges it — it clears
the command's bit after the result was published while the bit was set — or starts another
command: a master that polls slowly, or clears the bit early, still sees it.
"""

from __future__ import annotations

__all__ = [
    "CONTROL_BITS",
    "GEAR_BITS",
    "LEVELS",
    "RESULTS",
    "STATUS_BITS",
    "CommandWords",
    "Registers",
]

import logging
from collections.abc import Iterable
from typing import Protocol

from mcl.errors import ErrorID
from plc.operator.axis import COMMANDS, AxisOperator, Block, Orders, Parameters, whole

log = logging.getLogger(__name__)

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
    "move_additive",
    "gear_in",
    "gear_in_pos",
    "gear_out",
    "force_control",
)
"""Bits of an axis' control word, bit 0 first. ``enable`` and the jogs are levels; the others
are Execute inputs (a rising edge starts the command; keep the bit set until Done). A bit set and
cleared again between two scans still gives the command its rising edge (held for one scan)."""

LEVELS = ("enable", "jog_pos", "jog_neg")
"""Control bits that are levels, not Execute inputs."""

GEAR_BITS = ("gear_in", "gear_in_pos", "gear_out")
"""Control bits of the gearing commands (axes that can be a slave: a drive, another axis)."""

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
    "index",
    "in_velocity",
    "in_gear",
    "in_sync",
    "start_sync",
    "in_force",
)
"""Bits of an axis' status word, bit 0 first: Done … CommandAborted of the current command
(the one last started by a rising edge), homed (the axis has a reference), the switches LIM−,
REF and LIM+, MC_Power's Status, the encoder's index pulse, and InVelocity (MC_MoveVelocity),
InGear (MC_GearIn), InSync and StartSync (MC_GearInPos), InForce (MC_ForceControl) of the current
command."""

RESULTS = ("done", "error", "command_aborted")
"""The status bits of a command's result, held until the master acknowledges it."""

_MASK = {name: 1 << i for i, name in enumerate(CONTROL_BITS)}
"""Each control bit's mask."""

_STOP = CONTROL_BITS.index("stop")

_MISSING = {
    "home": "homing recipe",
    "gear_in": "gearing",
    "gear_in_pos": "gearing",
    "gear_out": "gearing",
    "force_control": "analog inputs",
}
"""What an axis lacks when it refuses a command bit."""


class Registers(Protocol):
    """An axis' registers as the front end reads and writes them, by their names without the
    axis' (``control``, ``position``, ``status``)."""

    @property
    def in_control(self) -> bool:
        """Whether the master may command (else the axis is left alone)."""
        ...

    def has(self, name: str) -> bool:
        """Whether the axis has register ``name``."""
        ...

    def get(self, name: str) -> float:
        """The value of register ``name`` (0.0: the axis has none)."""
        ...

    def take_control(self) -> int:
        """The control word for this scan: the bits set now and those that rose since the last
        scan (a pulse shorter than a scan still gives its rising edge)."""
        ...

    def requested(self) -> tuple[int, int]:
        """The last method call: its control bit and a serial number (-1: none yet)."""
        ...

    def update(self, values: Iterable[tuple[str, float]]) -> None:
        """Write status registers."""
        ...


class CommandWords:
    """The front end of one axis on the bus: its control word and registers as its orders
    (one PLC scan per call), and its status back (:meth:`publish`).

    Args:
        operator: The axis' function blocks (its masters: the axes of the master's table).
        registers: Its registers.
    """

    def __init__(self, operator: AxisOperator, registers: Registers) -> None:
        self.operator = operator
        self.registers = registers
        self.name = operator.axis.name
        self.commands = self._taken()
        """The Execute commands (control bits) the axis takes; the others are refused with
        EParam."""
        self.current: Block | None = None
        """The command last started by a rising edge (its outputs are the status)."""
        self.command = 0
        """The current command's control bit + 1 (0: none yet)."""
        self.count = 0
        """Commands started (``command_count``, modulo 65536)."""
        self._force = registers.has("force")
        self._last_word = 0
        self._last_client = 0
        self._serial = -1
        self._requested = -1
        self._deferred = -1
        self._pending = 0
        self._held: dict[str, bool] = dict.fromkeys(RESULTS, False)
        """The current command's result bits held until acknowledged."""
        self._held_error = 0
        """The ErrorID held with the error bit."""
        self._armed = False
        """The held result was published while the master's command bit was set: the bit's
        fall acknowledges it."""

    def _taken(self) -> tuple[str, ...]:
        """The Execute commands of the axis: home with a recipe, gearing and force control with
        their registers, the others always."""
        gearing = self.registers.has("master")
        takes = {
            "home": self.operator.recipe is not None,
            **dict.fromkeys(GEAR_BITS, gearing),
            "force_control": self.registers.has("force"),
        }
        return tuple(c for c in COMMANDS if takes.get(c, True))

    def _words(self) -> tuple[int, int]:
        """This scan's control word of the client and the whole control word: the client's
        with the Execute of the command last requested (a method call), held until the axis'
        next command (see the module docstring for the scans it waits)."""
        client = self.registers.take_control() | self._pending
        self._pending = 0
        bit, serial = self.registers.requested()
        if serial != self._serial:
            self._serial = serial
            self._requested = -1
            if self._last_word & (1 << bit | 1 << _STOP):  # its bit, or a stop, falls first
                self._deferred = bit
            else:
                self._requested, self._deferred = bit, -1
        elif self._deferred >= 0:
            self._requested, self._deferred = self._deferred, -1
        elif self._requested >= 0 and client & ~self._last_client & ~1:
            # the control word starts a command: the call's ends; the call's bit rising in the
            # word, or after a held stop every rising bit, waits one scan
            rising = client & ~self._last_client & ~1
            waiting = rising if self._requested == _STOP else rising & 1 << self._requested
            client &= ~waiting
            self._pending = waiting
            self._requested = -1
        requested = 1 << self._requested if self._requested >= 0 else 0
        return client, client | requested

    def __call__(self) -> None:
        """One PLC scan: control word → orders; while the master is not in control, the axis
        is left alone (:meth:`observe`)."""
        if not self.registers.in_control:
            self.observe()
            return
        client, word = self._words()
        last, self._last_word = self._last_word, word
        rising = word & ~last
        registers, operator = self.registers, self.operator
        params: Parameters = registers.get
        operator(
            Orders(
                power=bool(word & 1) if operator.axis.has_drive else None,
                execute=frozenset(c for c in self.commands if word & _MASK[c]),
                start={c: params for c in self.commands if rising & _MASK[c]},
                jog_pos=bool(word & _MASK["jog_pos"]),
                jog_neg=bool(word & _MASK["jog_neg"]),
                jog_velocity=abs(params("velocity")),
                outputs=whole(params("outputs")) if operator.outputs else None,
            )
        )
        if rising & ~1:
            self._started(rising)
        self._hold(client)

    def _started(self, rising: int) -> None:
        """The commands whose bits rose: the last is the current one (each counts); a bit the
        axis has no command for is refused with EParam."""
        for i, name in enumerate(CONTROL_BITS):
            if rising >> i & 1 and name != "enable":
                self.command = i + 1
                self.count = (self.count + 1) & 0xFFFF
                self._release()
                if name in ("jog_pos", "jog_neg"):
                    self.current = self.operator.jog
                elif name in self.commands:
                    self.current = self.operator.block(name)
                else:
                    self.current = None
                    self._held["error"], self._held_error = True, ErrorID.EParam
                    log.warning(
                        "%s: %s refused: the axis has no %s", self.name, name, _MISSING[name]
                    )

    def _hold(self, client: int) -> None:
        """Hold the current command's result; release it when the master's bit falls after
        the result was published while the bit was set (the acknowledgement)."""
        bit = 1 << (self.command - 1) if self.command else 0
        if self._armed and self._last_client & bit and not client & bit:
            self._release()
        self._last_client = client
        current = self.current
        for name, output in zip(RESULTS, ("Done", "Error", "CommandAborted"), strict=True):
            if getattr(current, output, False):
                self._held[name] = True
        if getattr(current, "Error", False):
            self._held_error = int(getattr(current, "ErrorID", 0))

    def _release(self) -> None:
        """Forget the held result (acknowledged, or another command started)."""
        self._held = dict.fromkeys(RESULTS, False)
        self._held_error = 0
        self._armed = False

    def observe(self) -> None:
        """A scan while the master is not in control: the blocks are not called; the control
        word's edges and requests are taken so that none fires later."""
        client, self._last_word = self._words()
        self._last_client = client

    def publish(self) -> None:
        """Write the axis' status and actual values into its registers."""
        axis, current, held = self.operator.axis, self.current, self._held
        io = axis.io
        if any(held.values()) and self.command:  # seen while the bit is set: its fall acks
            self._armed |= bool(self._last_client >> (self.command - 1) & 1)
        flags = {
            "done": held["done"],
            "busy": bool(getattr(current, "Busy", False)),
            "active": bool(getattr(current, "Active", False)),
            "error": held["error"],
            "command_aborted": held["command_aborted"],
            "homed": axis.Ref,
            "lim_neg": bool(io.lim_neg),
            "ref": bool(io.ref),
            "lim_pos": bool(io.lim_pos),
            "power": bool(self.operator.power.Status),
            "index": bool(io.index),
            "in_velocity": bool(getattr(current, "InVelocity", False)),
            "in_gear": bool(getattr(current, "InGear", False)),
            "in_sync": bool(getattr(current, "InSync", False)),
            "start_sync": bool(getattr(current, "StartSync", False)),
            "in_force": bool(getattr(current, "InForce", False)),
        }
        status = sum(1 << i for i, name in enumerate(STATUS_BITS) if flags[name])
        inputs = sum(1 << i for i, on in enumerate(axis.DI) if on)
        values: list[tuple[str, float]] = [
            ("status", status),
            ("state", int(axis.state)),
            ("error_id", self._held_error if held["error"] else 0),
            ("axis_error_id", axis.AxErrorID),
            ("actual_position", axis.POS),
            ("actual_velocity", axis.VEL),
            ("following_error", axis.following_error),
            ("volts", axis.volts),
            ("command", self.command),
            ("command_count", self.count),
            ("inputs", inputs),
        ]
        if self._force:
            values.append(("actual_force", self.operator.force_control.ActualForce))
        analog = axis.AI
        values += [
            (f"analog_{k}", analog[k])
            for k in range(len(analog))
            if self.registers.has(f"analog_{k}")
        ]
        self.registers.update(values)

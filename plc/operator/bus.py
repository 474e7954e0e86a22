"""The fieldbus front end of the operator program: a master's command words and parameter
registers as the orders of an axis (:class:`~plc.operator.axis.AxisOperator`), and the axis'
status word and actual values back into its registers.

The registers are the master's (the bridge's signal table, :mod:`scenes.bridge.table`); this
module sees an axis' registers through :class:`~plc.operator.handshake.Registers`. The control
word's bits (:data:`CONTROL_BITS`) are the commands of :data:`~plc.operator.axis.COMMANDS` by name:
``enable`` is MC_Power's Enable and ``jog_pos``/``jog_neg`` the jog levels (|velocity| as
JogVelo); every other bit is its command's Execute, passed every scan, so its rising edge starts
the command with the parameter registers of that scan, and the block's outputs follow the
PLCopen rules. The ``outputs`` register drives the digital outputs. A command the axis cannot
take (home without a recipe, gearing on an axis without gearing registers, force control
without force registers) is refused: the status shows Error with ErrorID EParam (5).

The control word's handshake — method calls held until the axis' next command (a held MC_Stop
released one scan before it), the status word showing the outputs of the current command, the
one last started, ``command_count`` counting the commands started, and a result held until the
master acknowledges it — is :class:`~plc.operator.handshake.Handshake`'s, which the group's front
end (:mod:`plc.operator.group_bus`) shares.
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

from plc.operator.axis import COMMANDS, AxisOperator, Block, Orders, Parameters, whole
from plc.operator.handshake import RESULTS, Handshake, Registers

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
    "home_direct",
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

_MASK = {name: 1 << i for i, name in enumerate(CONTROL_BITS)}
"""Each control bit's mask."""

_MISSING = {
    "home": "homing recipe",
    "gear_in": "gearing",
    "gear_in_pos": "gearing",
    "gear_out": "gearing",
    "force_control": "analog inputs",
}
"""What an axis lacks when it refuses a command bit."""


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
        self.handshake = Handshake(registers, CONTROL_BITS)
        """The control word and the held results."""
        self._force = registers.has("force")

    @property
    def current(self) -> Block | None:
        """The command last started by a rising edge (its outputs are the status)."""
        return self.handshake.current

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

    def __call__(self) -> None:
        """One PLC scan: control word → orders; while the master is not in control, the axis
        is left alone (the handshake only observes the word)."""
        handshake = self.handshake
        if not self.registers.in_control:
            handshake.observe()
            return
        word = handshake.take()
        rising = handshake.rising
        operator = self.operator
        params: Parameters = self.registers.get
        operator(
            Orders(
                power=bool(word & 1),
                execute=frozenset(c for c in self.commands if word & _MASK[c]),
                start={c: params for c in self.commands if rising & _MASK[c]},
                jog_pos=bool(word & _MASK["jog_pos"]),
                jog_neg=bool(word & _MASK["jog_neg"]),
                jog_velocity=abs(params("velocity")),
                outputs=whole(params("outputs")) if operator.outputs else None,
            )
        )
        for name in handshake.settle(self._block):
            log.warning("%s: %s refused: the axis has no %s", self.name, name, _MISSING[name])

    def _block(self, name: str) -> Block | None:
        """The block a rising control bit starts (None: the axis does not take it)."""
        if name in ("jog_pos", "jog_neg"):
            return self.operator.jog
        return self.operator.block(name) if name in self.commands else None

    def publish(self) -> None:
        """Write the axis' status and actual values into its registers."""
        axis, current = self.operator.axis, self.current
        io = axis.io
        held, error_id = self.handshake.result()
        power = self.operator.power
        if power.Error and not held["error"]:  # MC_Power's, while its Enable is set
            held["error"], error_id = True, int(power.ErrorID)
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
            ("error_id", error_id),
            ("axis_error_id", axis.AxErrorID),
            ("actual_position", axis.POS),
            ("actual_velocity", axis.VEL),
            ("following_error", axis.following_error),
            ("volts", axis.volts),
            ("command", self.handshake.command),
            ("command_count", self.handshake.count),
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

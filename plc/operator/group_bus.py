"""The fieldbus front end of an axes group: a master's group control word and parameter
registers as the orders of a :class:`~plc.operator.group.GroupOperator`, and the group's status
word and actual positions back into its registers.

The control word's bits (:data:`GROUP_CONTROL_BITS`) are the group's commands by name
(:data:`~plc.operator.group.GROUP_COMMANDS`): ``enable`` is the grouping level, every other bit
its command's Execute, passed every scan, so its rising edge starts the command with the
parameter registers of that scan. The handshake — method calls, ``command``, ``command_count``,
the result held until the master acknowledges it — is an axis' (:mod:`plc.operator.handshake`).
"""

from __future__ import annotations

__all__ = ["GROUP_CONTROL_BITS", "GROUP_STATUS_BITS", "GroupWords"]

import math

import mcl
from plc.operator.axis import Block, Parameters
from plc.operator.group import GROUP_COMMANDS, GroupOperator, GroupOrders
from plc.operator.handshake import Handshake, Registers

GROUP_CONTROL_BITS = ("enable", *GROUP_COMMANDS)
"""Bits of the group's control word, bit 0 first: ``enable`` is a level (the axes are added to
the group and it is enabled; cleared: disabled and ungrouped), the others Execute inputs."""

GROUP_STATUS_BITS = ("done", "busy", "active", "error", "command_aborted", "enabled", "in_position")
"""Bits of the group's status word: Done … CommandAborted of the current command, the group is
enabled, and MC_GroupReadStatus' InPosition."""

_MASK = {name: 1 << i for i, name in enumerate(GROUP_CONTROL_BITS)}
"""Each control bit's mask."""


class GroupWords:
    """The front end of one axes group on the bus: its control word and registers as its orders
    (one PLC scan per call), and its status back (:meth:`publish`).

    Args:
        operator: The group's function blocks.
        registers: The group block's registers.
    """

    def __init__(self, operator: GroupOperator, registers: Registers) -> None:
        self.operator = operator
        self.registers = registers
        self.handshake = Handshake(registers, GROUP_CONTROL_BITS)
        """The control word and the held results."""

    @property
    def current(self) -> Block | None:
        """The command last started by a rising edge (its outputs are the status)."""
        return self.handshake.current

    def __call__(self) -> None:
        """One PLC scan: control word → orders; while the master is not in control, the group
        is left alone (the handshake only observes the word)."""
        handshake = self.handshake
        if not self.registers.in_control:
            handshake.observe()
            return
        word = handshake.take()
        rising = handshake.rising
        params: Parameters = self.registers.get
        self.operator(
            GroupOrders(
                enable=bool(word & 1),
                execute=frozenset(c for c in GROUP_COMMANDS if word & _MASK[c]),
                start={c: params for c in GROUP_COMMANDS if rising & _MASK[c]},
            )
        )
        handshake.settle(self.operator.block)

    def publish(self) -> None:
        """Write the group's status, the path table's length and the members' actual positions
        into its registers."""
        operator, current = self.operator, self.current
        operator.read_status()
        held, error_id = self.handshake.result()
        state = operator.group.state
        flags = {
            **held,
            "busy": bool(getattr(current, "Busy", False)),
            "active": bool(getattr(current, "Active", False)),
            "enabled": state != mcl.GroupState.GroupDisabled,
            "in_position": bool(operator.status.InPosition),
        }
        status = sum(1 << i for i, name in enumerate(GROUP_STATUS_BITS) if flags[name])
        values: list[tuple[str, float]] = [
            ("status", status),
            ("state", int(state)),
            ("error_id", error_id),
            ("group_error_id", operator.error.GroupErrorID),
            ("command", self.handshake.command),
            ("command_count", self.handshake.count),
            ("segments", len(operator.path.Segments)),
        ]
        values += [
            (f"actual_{k + 1}", axis.POS if math.isfinite(axis.POS) else 0.0)
            for k, axis in enumerate(operator.members)
        ]
        self.registers.update(values)

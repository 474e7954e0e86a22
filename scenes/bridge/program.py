"""The PLC-side program of the bridge: the operator program (:mod:`plc.operator`) with one bus
front end per axis (:class:`plc.operator.bus.CommandWords`) on the axis' block of its signal
table, one per group (:class:`plc.operator.group_bus.GroupWords`) on the group block of a table
whose machine names a group, and the simulation fields and published signals of the tables.

Each scan every axis, then every group, reads its control word and parameters from its table and
calls the library's function blocks with them (the commands, their rules and ErrorIDs:
:mod:`plc.operator.axis`, :mod:`plc.operator.group`, docs/reference.md);
:meth:`BridgeProgram.publish` writes the status back.
"""

from __future__ import annotations

__all__ = ["BridgeProgram"]

import logging
from collections.abc import Sequence

from plc.operator.axis import AxisOperator
from plc.operator.bus import CommandWords
from plc.operator.group import GroupOperator
from plc.operator.group_bus import GroupWords
from plc.operator.program import OperatorProgram
from plc.procedures import Recipe
from scenes.bridge.table import AxisRegisters, SignalTable
from scenes.scene import Scene

log = logging.getLogger(__name__)


def _log_refusal(axis: str, text: str) -> None:
    """Log a command an axis refused or an error ended, with its reason (``S: Move velocity:
    error 5 (…: Velocity 20 mm/s below 1 % of Vmax (40 mm/s))``)."""
    log.warning("%s: %s", axis, text)


class BridgeProgram(OperatorProgram[CommandWords]):
    """The bridge's PLC program for a scene: the axes and the group of each table driven by their
    command words. Call it once per PLC scan; :meth:`publish` writes the status, the simulation
    fields and the published signals into the tables — every scan, or (``publish_every_scan``
    False) when the runner calls it, at the end of each run of scans.

    Args:
        scene: the running scene.
        tables: its signal tables (a cell: one per part).
        homing: the homing recipes by axis name.
        publish_every_scan: publish after each scan.
    """

    def __init__(
        self,
        scene: Scene,
        tables: Sequence[SignalTable],
        homing: dict[str, Recipe],
        publish_every_scan: bool = True,
    ) -> None:
        self.scene = scene
        self.tables = list(tables)
        front_ends = []
        for table in self.tables:
            masters = [scene.axes[a] for a in table.axes]  # gearing's master numbers
            for axis in masters:
                operator = AxisOperator(
                    axis, homing.get(axis.name), masters, _log_refusal, sim_time=lambda: scene.time
                )
                front_ends.append(CommandWords(operator, AxisRegisters(table, axis.name)))
        self.group_words = [
            GroupWords(
                GroupOperator(
                    table.group,
                    [scene.axes[a] for a in table.members],
                    table.definition.kinematics,
                    [scene.axes[a] for a in table.axes],
                ),
                AxisRegisters(table, table.group),
            )
            for table in self.tables
            if table.group
        ]
        """The front end of the group block of each table whose machine names a group."""
        super().__init__(front_ends)
        self.cycles = 0
        self.publish_every_scan = publish_every_scan
        self.publish()

    @property
    def target(self) -> int:
        """The lockstep target cycle: the largest any table was given."""
        return max(int(table.get("sim.target")) for table in self.tables)

    def __call__(self) -> None:
        """One PLC scan: the axes first, then the groups of their axes (those of a table whose
        PLC is not in control are left alone)."""
        super().__call__()
        for group in self.group_words:
            group()
        self.cycles += 1
        if self.publish_every_scan:
            self.publish()

    def publish(self) -> None:
        """Write every axis' and group's status, the simulation fields and the signals into the
        tables."""
        for words in self.front_ends.values():
            words.publish()
        for group in self.group_words:
            group.publish()
        scene = self.scene
        for table in self.tables:
            table.update(
                [
                    ("sim.time", scene.time),
                    ("sim.cycle", self.cycles),
                    *((f"signal.{name}", scene.signal(name)) for name in table.signals),
                ]
            )

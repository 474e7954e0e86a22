"""A production cell: the gantry and the press side by side in one world, one physics.

Its parts are the registered machines ``gantry`` and ``press`` (taken from the registry: the cell
imports neither package). Each keeps its own model, axes, devices and demo, in its own namespace
(``gantry/X``, ``press/R``; each one's code sees its own names through
:meth:`scenes.Scene.machine`). The
gantry's place position lies in a zone it shares with the press's table: the cell's demo runs
both machines' demos at once, the press over and over, under a zone interlock
(:mod:`.interlock`) read from the physics through the cell's published signals.
"""

from __future__ import annotations

import scenes
from scenes.definition import MachineDef, Part, Signal
from scenes.machines.cell.demo import RAM_UP, ZONE_X, Demo, gantry_in_zone, ram_up

COMPILED_MODULES = ("demo", "interlock")
"""The modules of the cell the compiled build covers (its program, run every PLC scan)."""

MACHINE = MachineDef(
    name="cell",
    description="a cell: the gantry and the press in one world, a zone interlock between them",
    axes={},
    parts=(Part(scenes.definition("gantry")), Part(scenes.definition("press"), (2.4, 0.0, 0.0))),
    demo=Demo,
    signals={
        "gantry_in_zone": Signal(
            "0/1", lambda scene: float(gantry_in_zone(scene)), "gantry in the press zone"
        ),
        "ram_up": Signal("0/1", lambda scene: float(ram_up(scene)), "ram up"),
    },
)
"""The cell's definition (registered as ``cell``)."""

__all__ = ["MACHINE", "RAM_UP", "ZONE_X", "Demo"]

"""A production cell: the gantry and the press side by side in one world, one physics.

Each machine keeps its own model, axes, devices and demo, in its own namespace (``gantry/X``,
``press/R``; each one's code sees its own names through :meth:`scenes.Scene.machine`). The
gantry's place position lies in a zone it shares with the press's table: the cell's demo runs
both machines' demos at once, the press over and over, under a zone interlock
(:mod:`.interlock`) read from the physics through the cell's published signals.
"""

from __future__ import annotations

from scenes.definition import MachineDef, Part, Signal
from scenes.machines import gantry, press
from scenes.machines.cell.demo import RAM_UP, ZONE_X, Demo, gantry_in_zone, ram_up

MACHINE = MachineDef(
    name="cell",
    description="a cell: the gantry and the press in one world, a zone interlock between them",
    axes={},
    parts=(Part(gantry.MACHINE), Part(press.MACHINE, (2.4, 0.0, 0.0))),
    demo=Demo,
    signals={
        "gantry_in_zone": Signal(
            "0/1", lambda scene: float(gantry_in_zone(scene)), "gantry in the press zone"
        ),
        "ram_up": Signal("0/1", lambda scene: float(ram_up(scene)), "ram up"),
    },
    demo_start={
        **{f"gantry/{a}": q for a, q in gantry.MACHINE.demo_start.items()},
        **{f"press/{a}": q for a, q in press.MACHINE.demo_start.items()},
    },
)
"""The cell's definition (registered as ``cell``)."""

__all__ = ["MACHINE", "RAM_UP", "ZONE_X", "Demo"]

"""The testbench: MuJoCo machines wired to mcl axes, machine definitions, demo programs and a CLI.

``scenes.load("gantry")`` builds a scene from the registry :data:`MACHINES`;
``scenes.demo(scene)`` gives its demo PLC program. ``python -m scenes list`` and the viewer's
chooser show the same registry. Needs the ``[physics]`` extra.

The public API is this namespace (``__all__``), :mod:`scenes.scene`, :mod:`scenes.definition`,
:mod:`scenes.registry`, :mod:`scenes.errors`, :mod:`scenes.plant` (the plant and the device
protocol of a machine's devices), the machines' packages (:mod:`scenes.machines`), the bridge
(:mod:`scenes.bridge`, the ``[bridge]`` extra) and the tools (:mod:`scenes.tools`).
Internal to the package: :mod:`scenes.namespace` (a machine's view of a scene),
:mod:`scenes.model_errors` (the messages of a broken model) and :mod:`scenes.start` (the check of
a start position).
"""

from __future__ import annotations

from typing import Any

from scenes import shadowing

shadowing.check()  # before the first import of another package of the testbench

from mcl import native
from mcl.extras import require

require("scenes", "physics")

COMPILED = native.activate("scenes", __path__)
"""The per-physics-step modules (plant, drives, devices) run compiled (see :mod:`mcl.native`)."""

from plc.procedures import Recipe
from plc.sequence import DemoProgram, StepSequence
from scenes.definition import AxisDef, MachineDef, Signal
from scenes.registry import BUILTIN, Entry, Registry
from scenes.scene import Scene

MACHINES = Registry(BUILTIN)
"""The registry: every machine by name (see :mod:`scenes.registry`)."""
MACHINES.add_entry_points()

__all__ = [
    "MACHINES",
    "AxisDef",
    "DemoProgram",
    "MachineDef",
    "Scene",
    "Signal",
    "StepSequence",
    "definition",
    "demo",
    "homing",
    "load",
    "register",
]


def register(name: str, entry: Entry) -> None:
    """Register the machine ``name``: a :class:`MachineDef`, or the ``"module:attribute"`` path
    of one (imported when the machine is first used). A machine of the same name is replaced."""
    MACHINES.register(name, entry)


def definition(name: str) -> MachineDef:
    """The registered machine ``name``.

    Raises:
        KeyError: unknown name (the message lists the valid ones).
    """
    try:
        return MACHINES[name]
    except KeyError:
        raise KeyError(f"unknown scene {name!r}; scenes: {sorted(MACHINES)}") from None


def load(name: str, **overrides: Any) -> Scene:
    """Build a scene of the registered machine ``name``.

    Args:
        name: one of :data:`MACHINES`.
        **overrides: passed to :class:`Scene`, e.g. ``start={"X": 0.3}``,
            ``plc_period=0.004``, ``trace_every=0``.

    Raises:
        KeyError: unknown scene name (the message lists the valid ones).
    """
    return Scene([definition(name)], **overrides)


def demo(scene: Scene) -> DemoProgram:
    """The demo program of a loaded scene.

    Raises:
        LookupError: the scene's machine has no demo.
    """
    factory = definition(scene.name).demo
    if factory is None:
        raise LookupError(f"scene {scene.name!r} has no demo program")
    return factory(scene)


def homing(scene: Scene) -> dict[str, Recipe]:
    """The homing recipes of a scene's axes (axis name → recipe; axes without one left out)."""
    return definition(scene.name).homing

"""The testbench: MuJoCo machines wired to mcl axes, scene builders, demo programs and a CLI.

``scenes.load("gantry")`` builds a scene; ``scenes.demo(scene)`` gives its demo PLC program.
"""

from __future__ import annotations

import importlib
from typing import Any, Protocol

from scenes.procedures import HomingRecipe
from scenes.scene import Scene

SCENES = {
    "gantry": "scenes.gantry",
}
"""Scene name → module with ``build(**overrides) -> Scene``, ``Demo`` and ``HOMING``."""


class DemoProgram(Protocol):
    """A scene's demo: a PLC program (call once per PLC cycle) that reports its progress."""

    done: bool
    step: str

    def __call__(self) -> None:
        """One PLC scan."""
        ...


def _module(name: str) -> Any:
    if name not in SCENES:
        raise KeyError(f"unknown scene {name!r}; scenes: {sorted(SCENES)}")
    return importlib.import_module(SCENES[name])


def load(name: str, **overrides: Any) -> Scene:
    """Build a scene by name.

    Args:
        name: one of :data:`SCENES`.
        **overrides: passed to the scene's ``build``, e.g. ``start={"X": 0.3}``,
            ``plc_period=0.004``, ``trace_every=0``.

    Raises:
        KeyError: unknown scene name (the message lists the valid ones).
    """
    scene: Scene = _module(name).build(**overrides)
    scene.name = name
    return scene


def demo(scene: Scene) -> DemoProgram:
    """The demo program of a loaded scene."""
    program: DemoProgram = _module(scene.name).Demo(scene)
    return program


def homing(scene: Scene) -> dict[str, HomingRecipe]:
    """The homing recipes of a scene's axes (axis name → REF + index recipe)."""
    recipes: dict[str, HomingRecipe] = _module(scene.name).HOMING
    return recipes

"""The gantry in the registry (:data:`MACHINE`), its scene and its contour test path."""

from __future__ import annotations

__all__ = ["MACHINE", "ZIGZAG", "ZIGZAG_START", "build"]

from typing import Any

from scenes.definition import MachineDef, ScopeDefaults
from scenes.machines.gantry.axes import AXES
from scenes.machines.gantry.demo import Demo
from scenes.scene import Scene

ZIGZAG_START = {"X": 0.3, "Y": 0.1, "Z": -0.1}
"""Joint coordinates [m] where the contour test path (:data:`ZIGZAG`) starts."""
ZIGZAG = (
    (150.0, 60.0, -40.0),
    (-150.0, 60.0, -40.0),
    (150.0, 60.0, 40.0),
    (-150.0, 60.0, 40.0),
    (150.0, 60.0, 0.0),
)
"""A zigzag in space: five straight segments [mm] (X, Y, Z distances), turning by 129–138° at
each corner; the contour measurement of the gantry (tests and benchmark) runs it."""


def build(start: dict[str, float] | None = None, **scene_options: Any) -> Scene:
    """The gantry scene.

    Args:
        start: joint coordinates at power-up [m] per axis, e.g. ``{"X": 0.3}``.
        **scene_options: ``servo_period``, ``plc_period``, ``trace_every`` (see :class:`Scene`).
    """
    return Scene([MACHINE], start=start, **scene_options)


MACHINE = MachineDef(
    name="gantry",
    description="three-axis Cartesian gantry: ball screws, servo amplifiers, Z brake",
    model="gantry.xml",
    axes=AXES,
    demo=Demo,
    demo_start={"X": 0.43, "Y": 0.27, "Z": -0.12},
    group=("X", "Y", "Z"),
    scope=ScopeDefaults(
        channels=("X following error", "Y following error", "Z following error"), seconds=20.0
    ),
)
"""The gantry in the registry."""

"""The three-axis gantry (models/gantry.xml) wired to three mcl axes X, Y, Z: its axes and homing
recipes (:mod:`.axes`), its demo, a pick-and-place cycle (:mod:`.demo`), and its definition in
the registry with the contour test path (:mod:`.definition`)."""

from scenes.machines.gantry.axes import AXES, HOMING, SW_MARGIN
from scenes.machines.gantry.definition import MACHINE, ZIGZAG, ZIGZAG_START, build
from scenes.machines.gantry.demo import (
    DWELL,
    PATH,
    PATH_VELOCITY,
    PICK,
    PLACE,
    SAFE_Z,
    Demo,
)

COMPILED_MODULES = ("demo",)
"""The module of this package the compiled build covers (the demo, run every PLC scan)."""

__all__ = [
    "AXES",
    "DWELL",
    "HOMING",
    "MACHINE",
    "PATH",
    "PATH_VELOCITY",
    "PICK",
    "PLACE",
    "SAFE_Z",
    "SW_MARGIN",
    "ZIGZAG",
    "ZIGZAG_START",
    "Demo",
    "build",
]

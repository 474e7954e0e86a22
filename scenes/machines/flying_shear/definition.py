"""The flying shear in the registry (:data:`MACHINE`): its axes, its Python devices (run before
every physics step), its demo and the signals it publishes."""

from __future__ import annotations

__all__ = ["DEVICES", "MACHINE"]

from scenes.definition import MachineDef, ScopeDefaults, Signal
from scenes.machines.flying_shear.axes import AXES
from scenes.machines.flying_shear.demo import Demo
from scenes.machines.flying_shear.devices import CutRecorder, EccentricRoll, KnifeCylinder
from scenes.parts import MeasuringWheel
from scenes.scene import Scene

DEVICES = {
    "ripple": EccentricRoll,
    "wheel": MeasuringWheel,
    "knife": KnifeCylinder,
    "cuts": CutRecorder,  # after the knife: it reads the knife's force of the same step
}
"""The machine's Python devices by name (each ``(model, data, prefix) -> device``)."""


def _signal_knife(scene: Scene) -> float:
    return 1000.0 * scene.joint("K").position


def _signal_valve(scene: Scene) -> float:
    return scene.device("knife", KnifeCylinder).spool


def _signal_drag(scene: Scene) -> float:
    return scene.device("knife", KnifeCylinder).drag


def _signal_piece(scene: Scene) -> float:
    return scene.device("cuts", CutRecorder).last_piece


def _signal_mark(scene: Scene) -> float:
    return scene.device("cuts", CutRecorder).last_mark


def _signal_speed(scene: Scene) -> float:
    return 60.0 * scene.joint("M").velocity


def _signal_relative(scene: Scene) -> float:
    return 1000.0 * (scene.joint("S").velocity - scene.joint("M").velocity)


MACHINE = MachineDef(
    name="flying_shear",
    description="flying shear: strip line, measuring wheel, carriage gearing in, knife cylinder",
    model="flying_shear.xml",
    axes=AXES,
    devices=DEVICES,
    demo=Demo,
    signals={
        "knife": Signal("mm", _signal_knife, "knife stroke"),
        "valve": Signal("−1…1", _signal_valve, "knife valve command"),
        "drag": Signal("N", _signal_drag, "blade drag on the strip"),
        "strip_speed": Signal("m/min", _signal_speed, "strip speed"),
        "carriage_minus_strip": Signal("mm/s", _signal_relative, "carriage − strip"),
        "last_piece": Signal("mm", _signal_piece, "last piece length"),
        "last_cut_to_mark": Signal("mm", _signal_mark, "last cut to mark"),
    },
    demo_start={"S": 0.3},
    scope=ScopeDefaults(
        channels=(
            "S velocity",
            "W velocity",
            "carriage_minus_strip",
            "S position",
            "S following error",
        ),
        seconds=10.0,
    ),
)
"""The flying shear in the registry."""

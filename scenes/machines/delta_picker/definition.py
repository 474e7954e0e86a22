"""The delta picker in the registry (:data:`MACHINE`): its axes, the vacuum gripper, its demo and
the signals it publishes."""

from __future__ import annotations

__all__ = ["DEVICES", "MACHINE"]

from scenes.definition import DeviceFactory, MachineDef, ScopeDefaults, Signal
from scenes.machines.delta_picker.axes import AXES, DELTA
from scenes.machines.delta_picker.demo import Demo
from scenes.machines.delta_picker.devices import Belt, Feeder, PhotoEye, VacuumGripper
from scenes.scene import Scene

DEVICES: dict[str, DeviceFactory] = {
    "belt": Belt,
    "vacuum": VacuumGripper,
    "feeder": Feeder,
    "eye": PhotoEye,
}
"""The machine's Python devices by name (each ``(model, data, prefix) -> device``)."""


def _signal_vacuum(scene: Scene) -> float:
    return 1.0 if scene.device("vacuum", VacuumGripper).on else 0.0


def _signal_pick_error(scene: Scene) -> float:
    grips = scene.device("vacuum", VacuumGripper).grips
    return grips[-1].error if grips else 0.0


def _signal_belt(scene: Scene) -> float:
    return 1000.0 * scene.joint("C").velocity


MACHINE = MachineDef(
    name="delta_picker",
    description="delta robot picking parts off an infeed conveyor into a tray (vacuum cup)",
    model="delta_picker.xml",
    axes=AXES,
    devices=DEVICES,
    demo=Demo,
    signals={
        "vacuum": Signal("0/1", _signal_vacuum, "vacuum valve open"),
        "last_pick_error": Signal("mm", _signal_pick_error, "cup centre to part centre at grip"),
        "belt_speed": Signal("mm/s", _signal_belt, "conveyor speed"),
    },
    group=("A1", "A2", "A3"),
    kinematics=DELTA,
    scope=ScopeDefaults(
        channels=("A1 following error", "A2 following error", "A3 following error"),
        seconds=10.0,
    ),
)
"""The delta picker in the registry."""

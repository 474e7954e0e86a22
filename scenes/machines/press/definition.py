"""The hydraulic press in the registry (:data:`MACHINE`): its axis, its device and the signals
it publishes (pressures, forces, the valve's spool)."""

from __future__ import annotations

__all__ = ["MACHINE"]

from scenes.definition import MachineDef, ScopeDefaults, Signal
from scenes.machines.press.axes import AXES, MODEL
from scenes.machines.press.demo import Demo
from scenes.machines.press.devices import CylinderDevice, make_cylinder
from scenes.machines.press.hydraulics import BAR
from scenes.scene import Scene


def _signal_pressure_a(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.p_a / BAR


def _signal_pressure_b(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.p_b / BAR


def _signal_force(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).load_force / 1000.0


def _signal_hydraulic(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.force() / 1000.0


def _signal_valve(scene: Scene) -> float:
    return scene.device("cylinder", CylinderDevice).hydraulics.spool


MACHINE = MachineDef(
    name="press",
    description="hydraulic press: servo valve, 80/56 cylinder, 200 kg ram, part on a spring",
    model=MODEL,
    axes=AXES,
    devices={"cylinder": make_cylinder},
    demo=Demo,
    signals={
        "pressure_A": Signal("bar", _signal_pressure_a, "pressure A"),
        "pressure_B": Signal("bar", _signal_pressure_b, "pressure B"),
        "force": Signal("kN", _signal_force, "load cell force"),
        "force_hydraulic": Signal("kN", _signal_hydraulic, "hydraulic force"),
        "valve": Signal("−1…1", _signal_valve, "valve spool"),
    },
    servo_period=0.001,
    plc_period=0.001,
    demo_start={"R": 0.03},
    scope=ScopeDefaults(
        channels=("force", "pressure_A", "pressure_B", "R position", "R set point"), seconds=10.0
    ),
)
"""The hydraulic press in the registry."""

"""The rotary cross cutter in the registry (:data:`MACHINE`): its axes, its Python devices (run
before every physics step), its demo and the signals it publishes."""

from __future__ import annotations

__all__ = ["DEVICES", "MACHINE"]

import math

from scenes.definition import MachineDef, ScopeDefaults, Signal
from scenes.machines.rotary_cutter.axes import AXES
from scenes.machines.rotary_cutter.cam_demo import CamDemo
from scenes.machines.rotary_cutter.devices import KnifeDrum
from scenes.parts import MeasuringWheel
from scenes.scene import Scene

DEVICES = {
    "wheel": MeasuringWheel,
    "drum": KnifeDrum,
}
"""The machine's Python devices by name (each ``(model, data, prefix) -> device``)."""


def _drum(scene: Scene) -> KnifeDrum:
    return scene.device("drum", KnifeDrum)


def _signal_speed(scene: Scene) -> float:
    return 60.0 * scene.joint("M").velocity


def _signal_tip_minus_web(scene: Scene) -> float:
    """Tip speed at the bottom of the drum (r·Ḋ) minus web speed [mm/s]."""
    drum = _drum(scene)
    return 1000.0 * (drum.radius * scene.joint("D").velocity - scene.joint("M").velocity)


def _signal_drag(scene: Scene) -> float:
    return _drum(scene).drag


def _signal_piece(scene: Scene) -> float:
    return _drum(scene).last_piece


def _signal_torque(scene: Scene) -> float:
    """The drum amplifier's torque at the drum, its cutting-force feed-forward included [N·m]."""
    amplifier = float(scene.data.actuator(scene.model_name("D_amp")).force[0])
    return amplifier + _drum(scene).feed_torque


def _signal_current(scene: Scene) -> float:
    """The motor current for the drum's torque [A rms]."""
    drum = _drum(scene)
    return abs(_signal_torque(scene)) / (drum.ratio * drum.efficiency) / drum.kt


def _signal_angle(scene: Scene) -> float:
    return math.degrees(scene.joint("D").position) % 360.0


MACHINE = MachineDef(
    name="rotary_cutter",
    description="rotary cross cutter: web line, measuring wheel, knife drum on a cam",
    model="rotary_cutter.xml",
    axes=AXES,
    devices=DEVICES,
    demo=CamDemo,
    signals={
        "web_speed": Signal("m/min", _signal_speed, "web speed"),
        "drum_angle": Signal("deg", _signal_angle, "drum angle"),
        "tip_minus_web": Signal("mm/s", _signal_tip_minus_web, "blade tip − web"),
        "drag": Signal("N", _signal_drag, "blade drag on the web"),
        "drum_torque": Signal("N·m", _signal_torque, "drum torque"),
        "motor_current": Signal("A", _signal_current, "drum motor current"),
        "last_piece": Signal("mm", _signal_piece, "last piece length"),
    },
    scope=ScopeDefaults(
        channels=("D set point", "D position", "D following error", "W position", "W velocity"),
        seconds=5.0,
    ),
)
"""The rotary cross cutter in the registry."""

"""Typed machine definitions (data only): everything the testbench, the CLI and the viewer know
of a machine.

A :class:`MachineDef` names its MJCF model (or simulated axes), its axes (drive kind, joint, unit
and scale, machine data, servo constants, homing recipe, probe), its Python devices, its demo
program and the extra signals it publishes for traces and the viewer. The registry in
:mod:`scenes.registry` holds one definition per machine; nothing else names a machine.
"""

from __future__ import annotations

__all__ = [
    "UNIT_SCALES",
    "AxisDef",
    "DeviceFactory",
    "DriveKind",
    "MachineDef",
    "Part",
    "ScopeDefaults",
    "Signal",
    "unit_and_scale",
]

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, TypeVar

import mujoco

import mcl
from plc.procedures import Recipe
from plc.sequence import DemoProgram
from scenes.namespace import Namespace
from scenes.plant.drives import Device
from scenes.plant.mujoco import Probe

if TYPE_CHECKING:
    from scenes.scene import Scene

DriveKind = Literal["electric", "device", "encoder"]
V = TypeVar("V")


DeviceFactory = Callable[[mujoco.MjModel, mujoco.MjData, str], Device]
"""Makes a device for a compiled model: ``(model, data, prefix) -> Device``; ``prefix`` is the
prefix of the machine's names in the model (``"press/"``), given by the scene: a device names
what it reads ``prefix + "R_valve"``."""


@dataclass(frozen=True)
class AxisDef:
    """One axis of a machine.

    Attributes:
        config: machine data (user units); its resolution must match the encoder's.
        constants: the GT_SetConstant values written when the scene is built (None: the program
            writes them).
        drive: ``"electric"`` (±10 V amplifier, the MJCF actuator ``<axis>_amp``), ``"device"``
            (±10 V into the Python device named ``device``) or ``"encoder"`` (no drive: an
            encoder-only axis such as a measuring wheel).
        device: the device of a ``"device"`` drive.
        joint: the axis joint in the model (default: the axis name).
        unit: user unit; default ``"mm"`` on a slide joint, ``"deg"`` on a hinge.
        scale: user units per SI unit (m or rad); default from ``unit`` (mm: 1000, deg: 180/π,
            m and rad: 1).
        switches: which of LIM−, LIM+ and REF the axis has (``"lim_neg"``, ``"lim_pos"``,
            ``"ref"``).
        homing: the axis' homing recipe (None: the axis is not homed by a procedure).
        probe: the touch-probe source of the axis (None: TP stays low).
        digital_outputs: digital outputs a program may set on the axis' channel.
        analog: names of device signals wired to the axis' analog inputs, in channel order.
        sim: the physics of a simulated axis (machines without an MJCF model only).
        sensors: the imperfections of the axis' switches, encoder and module (None: the
            defaults of :class:`mcl.Sensors`, a precision machine; :data:`mcl.IDEAL_SENSORS`:
            ideal). On a simulated axis it replaces ``sim.sensors``.
    """

    config: mcl.AxisConfig
    constants: mcl.ServoConstants | None = None
    drive: DriveKind = "electric"
    device: str = ""
    joint: str = ""
    unit: str = ""
    scale: float = 0.0
    switches: tuple[str, ...] = ("lim_neg", "lim_pos", "ref")
    homing: Recipe | None = None
    probe: Probe | None = None
    digital_outputs: int = 0
    analog: tuple[str, ...] = ()
    sim: mcl.SimAxisParams | None = None
    sensors: mcl.Sensors | None = None


UNIT_SCALES = {"mm": 1000.0, "m": 1.0, "um": 1e6, "deg": 180.0 / math.pi, "rad": 1.0}
"""User units and their scale from SI (m or rad)."""


def unit_and_scale(axis: AxisDef, rotary: bool) -> tuple[str, float]:
    """The user unit and the user units per SI unit of an axis on a slide or hinge joint.

    Raises:
        ValueError: an unknown unit without a scale, a unit that does not fit the joint, or a
            scale that is not a finite number > 0.
    """
    unit = axis.unit or ("deg" if rotary else "mm")
    if axis.scale:
        if not (math.isfinite(axis.scale) and axis.scale > 0.0):
            raise ValueError(f"scale must be a finite number > 0, got {axis.scale!r}")
        return unit, axis.scale
    if unit not in UNIT_SCALES:
        raise ValueError(f"unit {unit!r} needs a scale; known units: {sorted(UNIT_SCALES)}")
    if (unit in ("deg", "rad")) != rotary:
        kind = "a hinge (rotary)" if rotary else "a slide (linear)"
        raise ValueError(f"unit {unit!r} does not fit {kind} joint; give unit and scale")
    return unit, UNIT_SCALES[unit]


@dataclass(frozen=True)
class Signal:
    """An extra value a machine publishes for the trace and the viewer (a pressure, a force).

    Attributes:
        unit: its unit, e.g. ``"bar"``, ``"N"``, ``"mm"``, ``"−1…1"`` (a valve's spool),
            ``"0/1"`` (a flag).
        read: reads it from a running scene.
        label: what the viewer calls it (``"carriage − strip"``); empty: its name.
    """

    unit: str
    read: Callable[[Scene], float]
    label: str = ""


@dataclass(frozen=True)
class Part:
    """A machine of a cell (:attr:`MachineDef.parts`) and where its origin sits in the world.

    Attributes:
        machine: its definition; in the cell its names are prefixed with ``machine.name``.
        position: its origin in the world [m].
    """

    machine: MachineDef
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class ScopeDefaults:
    """What a viewer's scope shows first for a machine.

    Attributes:
        channels: Scope channel names (``"S velocity"``, ``"force"``: an axis' ``position``,
            ``set point``, ``velocity``, ``following error``, ``command``, or a signal's name);
            empty: the first axis' following error, command and position.
        seconds: Recording length [s] (a whole cycle of the machine).
    """

    channels: tuple[str, ...] = ()
    seconds: float = 2.0


@dataclass(frozen=True)
class MachineDef:
    """A machine: model, axes, devices, demo, published signals.

    Attributes:
        name: registry name (``"gantry"``); also the prefix of its names in a composed model.
        description: one line for listings.
        axes: axis name → its definition, in the order of the module's channels.
        model: MJCF file in ``models/`` (or absolute); ``""`` = simulated axes (``AxisDef.sim``).
        devices: Python devices integrated every physics step, by name.
        demo: makes the demo program for a built scene (None: no demo).
        signals: extra published values by name.
        start: joint coordinates at power-up [m or rad] (default: the model's qpos0).
        demo_start: joint coordinates the demo starts from (``python -m scenes run``); a
            cell's default: its parts' (``press/R``).
        servo_period, plc_period: default cycle times [s].
        parts: the machines of a cell, side by side in one world (a cell has no axes or model
            of its own: each part keeps its own, in its own namespace, e.g. ``press/R``; the
            cell's demo and signals see them all).
        group: the axes that move together on a path (a Cartesian machine's X, Y, Z), in
            member order: the bridge's group block (docs/bridge.md) groups them.
        kinematics: the group's kinematic transformation when its members are a robot's
            joints (the delta picker's arms); the bridge's group block sets it
            (MC_SetKinTransform) when it enables the group. None: the members' coordinates are
            the machine's.
        scope: the channels and recording length a viewer's scope shows first.
    """

    name: str
    description: str
    axes: Mapping[str, AxisDef]
    model: str = ""
    devices: Mapping[str, DeviceFactory] = field(default_factory=dict)
    demo: Callable[[Scene], DemoProgram] | None = None
    signals: Mapping[str, Signal] = field(default_factory=dict)
    start: Mapping[str, float] = field(default_factory=dict)
    demo_start: Mapping[str, float] = field(default_factory=dict)
    servo_period: float = 0.001
    plc_period: float = 0.002
    parts: tuple[Part, ...] = ()
    group: tuple[str, ...] = ()
    kinematics: mcl.KinTransform | None = None
    scope: ScopeDefaults = field(default_factory=ScopeDefaults)

    def __post_init__(self) -> None:
        if self.parts:
            if self.axes or self.model:
                raise ValueError(f"cell {self.name!r}: its parts have the axes and models")
            if not self.demo_start:  # frozen: set once, here
                object.__setattr__(self, "demo_start", self._of_parts(lambda m: m.demo_start))
            return
        if not self.axes:
            raise ValueError(f"machine {self.name!r} has no axes")
        unknown = [a for a in self.group if a not in self.axes]
        if unknown or len(self.group) == 1 or len(self.group) > 3:
            raise ValueError(
                f"machine {self.name!r}: group {self.group} must name 2 or 3 of its axes "
                f"{sorted(self.axes)}"
            )
        if self.kinematics is not None and self.kinematics.joints != len(self.group):
            raise ValueError(
                f"machine {self.name!r}: kinematics {self.kinematics.name!r} takes "
                f"{self.kinematics.joints} joints, the group {self.group} has {len(self.group)}"
            )
        for axis, spec in self.axes.items():
            if spec.drive not in ("electric", "device", "encoder"):
                raise ValueError(
                    f"{self.name}.{axis}: drive must be 'electric', 'device' or 'encoder', "
                    f"got {spec.drive!r}"
                )
            if spec.drive == "device" and spec.device not in self.devices:
                raise ValueError(
                    f"{self.name}.{axis}: drive 'device' names device {spec.device!r}; "
                    f"devices: {sorted(self.devices)}"
                )
            if not self.model and spec.sim is None:
                raise ValueError(f"{self.name}.{axis}: a machine without a model needs AxisDef.sim")

    @property
    def scene_axes(self) -> dict[str, AxisDef]:
        """The axes by their names in a scene of this machine: its own, or a cell's parts'
        prefixed with the part's name (``press/R``)."""
        return self._of_parts(lambda m: m.axes) if self.parts else dict(self.axes)

    def _of_parts(self, entries: Callable[[MachineDef], Mapping[str, V]]) -> dict[str, V]:
        """Every part's ``entries`` (its axes, its demo start) by their names in the cell's
        scene (``press/R``)."""
        return {
            Namespace(p.machine.name, shared=True).scene(name): value
            for p in self.parts
            for name, value in entries(p.machine).items()
        }

    @property
    def homing(self) -> dict[str, Recipe]:
        """The homing recipes by axis name (axes without one are left out; a cell's axes by
        their names in the cell, ``press/R``)."""
        return {n: a.homing for n, a in self.scene_axes.items() if a.homing is not None}

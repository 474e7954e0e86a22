"""The press's MuJoCo devices: :class:`CylinderDevice`, the valve-controlled cylinder on the ram's
slide joint (the drive of its ``"device"`` axis), with its pressure transducers and the load cell
under the part (:class:`ContactForce`); :func:`make_cylinder` makes it from the model's numerics
(models/README.md)."""

from __future__ import annotations

__all__ = [
    "ANALOG_INPUTS",
    "AnalogReader",
    "ContactForce",
    "CylinderDevice",
    "Transducer",
    "cylinder_data",
    "make_cylinder",
]

import math
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt
from mypy_extensions import i64

from scenes.errors import WiringError
from scenes.machines.press.hydraulics import Cylinder, Supply, Valve, ValveCylinder
from scenes.plant.mujoco import numeric


def cylinder_data(model: mujoco.MjModel, prefix: str = "") -> tuple[Valve, Cylinder, Supply]:
    """The valve, cylinder and supply of the model's numerics (models/README.md).

    Raises:
        WiringError: a numeric is missing, of the wrong size or out of range.
    """
    bore, rod, stroke = numeric(model, f"{prefix}R_cylinder", 3, 0.0)
    dead_a, dead_b = numeric(model, f"{prefix}R_dead_volume", 2, 0.0)
    coulomb, pressure_friction = numeric(model, f"{prefix}R_seal_friction", 2, -1e-300)
    (leakage,) = numeric(model, f"{prefix}R_internal_leakage", 1, -1e-300)
    flow, dp, frequency, damping = numeric(model, f"{prefix}R_valve", 4, 0.0)
    overlap, hysteresis, clearance, laminar = numeric(model, f"{prefix}R_valve_spool", 4, -1e-300)
    supply, tank, beta = numeric(model, f"{prefix}R_supply", 3, -1e-300)
    relief, override, relief_flow = numeric(model, f"{prefix}R_line_relief", 3, 0.0)
    return (
        Valve(flow, dp, frequency, damping, overlap, hysteresis, clearance, laminar),
        Cylinder(bore, rod, stroke, dead_a, dead_b, coulomb, pressure_friction, leakage),
        Supply(supply, tank, relief, override, relief_flow, beta),
    )


class Transducer:
    """An analog sensor as the PLC's input card reads it: a range mapped to 0–10 V, seeded
    Gaussian noise, clipped to 0–10 V and quantized to ``bits``.

    Args:
        full_scale: the value at 10 V (in the measured unit, e.g. Pa or N).
        bits: resolution of the input card.
        noise: standard deviation of the noise [V].
        seed: seed of the noise.
    """

    def __init__(self, full_scale: float, bits: int, noise: float, seed: int) -> None:
        if not (math.isfinite(full_scale) and full_scale > 0.0):
            raise ValueError(f"full_scale must be a finite number > 0, got {full_scale!r}")
        self.volts_per_unit = 10.0 / full_scale
        self.lsb = 10.0 / float((1 << bits) - 1)
        self.noise = noise
        self.state: i64 = (seed * 2654435761 + 12345) % 2147483647 or 1
        """State of the noise generator (a Lehmer generator in 64-bit integers, cheaper than a
        float modulo; part of the device state)."""

    def _uniform(self) -> float:
        s: i64 = self.state * 48271 % 2147483647
        self.state = s
        return float(s) / 2147483647.0

    def volts(self, value: float) -> float:
        """The reading of ``value`` [V]."""
        v = value * self.volts_per_unit
        if self.noise > 0.0:
            u1 = self._uniform()
            u2 = self._uniform()
            v += self.noise * math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)
        v = min(max(v, 0.0), 10.0)
        return math.floor(v / self.lsb + 0.5) * self.lsb


class ContactForce:
    """The force on a part under a tool, as a load cell under it reads it [N]: the part's spring
    (the tendon ``workpiece``) plus its hard block (the force sensor ``workpiece_block``).

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.model, self.data = model, data
        self.tendon = int(model.tendon(f"{prefix}workpiece").id)
        self.sensor = int(model.sensor(f"{prefix}workpiece_block").adr[0])
        # item access without numpy scalars (the part may be changed: rest and stiffness are read
        # from the model every time)
        self._length: Any = memoryview(data.ten_length)
        self._rest: Any = memoryview(model.tendon_lengthspring.reshape(-1))
        self._stiffness: Any = memoryview(model.tendon_stiffness)
        self._sensors: Any = memoryview(data.sensordata)

    def __call__(self) -> float:
        tendon = self.tendon
        length: float = self._length[tendon]
        rest: float = self._rest[2 * tendon]
        spring = self._stiffness[tendon] * (rest - length) if length < rest else 0.0
        force: float = spring + self._sensors[self.sensor]
        return force


ANALOG_INPUTS = ("p_A", "p_B", "load")
"""The analog inputs of a :class:`CylinderDevice`: pressure transducers A and B, the load cell."""


class CylinderDevice:
    """A valve-controlled cylinder on a MuJoCo slide joint: the drive of a ``"device"`` axis.

    Before every physics step it integrates :class:`ValveCylinder` with the joint's position
    and velocity, writes the hydraulic force into ``qfrc_applied`` and the seal friction into
    the joint's ``frictionloss``. The joint coordinate is the extension minus ``origin``
    (positive = extending). :meth:`apply` takes the ±10 V (disabled: 0 V and the load-holding
    valves closed). :meth:`analog` reads the pressure transducers ``"p_A"``, ``"p_B"`` and the
    load cell ``"load"`` as the input card sees them.

    Args:
        model, data: the compiled model and its data (positions current).
        joint: the cylinder's slide joint (prefixed name).
        valve, cylinder, supply: the hydraulic data.
        transducer: full scale [Pa], bits, noise [V] of the pressure transducers.
        load_cell: full scale [N], bits, noise [V] of the load cell.
        load: reads the true force on the load cell [N] (None: no load cell, it reads 0 V).
        origin: extension at joint coordinate 0 [m].
        seed: seed of the sensor noise.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        joint: str,
        valve: Valve,
        cylinder: Cylinder,
        supply: Supply,
        transducer: tuple[float, int, float],
        load_cell: tuple[float, int, float] = (1.0, 12, 0.0),
        load: ContactForce | None = None,
        origin: float = 0.0,
        seed: int = 0,
    ) -> None:
        j = model.joint(joint)
        if int(j.type[0]) != int(mujoco.mjtJoint.mjJNT_SLIDE):
            raise WiringError(f"cylinder joint {joint!r} must be a slide joint")
        self.qpos = int(j.qposadr[0])
        self.dof = int(j.dofadr[0])
        self.origin = origin
        self.hydraulics = h = ValveCylinder(valve, cylinder, supply, float(model.opt.timestep))
        self._qpos: Any = memoryview(data.qpos)
        self._qvel: Any = memoryview(data.qvel)
        self._applied: Any = memoryview(data.qfrc_applied)
        self._friction: Any = memoryview(model.dof_frictionloss)
        self.transducers = [Transducer(*transducer, seed=seed * 3 + i) for i in range(2)]
        self.load_cell = Transducer(*load_cell, seed=seed * 3 + 2)
        self._load = load
        # at rest the ram hangs on its oil: the pressures that hold the joint's bias force
        h.holding_pressures(-float(data.qfrc_bias[self.dof]))
        self._write()

    def extension(self) -> float:
        """Piston extension [m]."""
        q: float = self._qpos[self.qpos]
        return q + self.origin

    def _write(self) -> None:
        h = self.hydraulics
        self._applied[self.dof] = h.p_a * h.area_a - h.p_b * h.area_b
        self._friction[self.dof] = h.friction()

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Integrate valve and chambers over the coming step; set force and seal friction."""
        q: float = self._qpos[self.qpos]
        v: float = self._qvel[self.dof]
        h = self.hydraulics
        self._applied[self.dof] = h.step(q + self.origin, v)
        self._friction[self.dof] = h.friction()

    def apply(self, volts: float, enabled: bool, brake: bool) -> None:
        """Valve command [V]; disabled: 0 V; ``brake``: the load-holding valves close."""
        h = self.hydraulics
        h.command = volts if enabled else 0.0
        h.hold = brake

    @property
    def load_force(self) -> float:
        """The true force on the load cell [N] (0 without one)."""
        load = self._load
        return load() if load is not None else 0.0

    def analog(self, name: str) -> float:
        """An analog input [V]: ``"p_A"``, ``"p_B"`` (pressure transducers) or ``"load"``."""
        return self.read(self.channel(name))

    def channel(self, name: str) -> int:
        """The number of the analog input ``name`` (see :data:`ANALOG_INPUTS`).

        Raises:
            WiringError: the device has no such input.
        """
        if name not in ANALOG_INPUTS:
            raise WiringError(f"no analog input {name!r}; inputs: {', '.join(ANALOG_INPUTS)}")
        return ANALOG_INPUTS.index(name)

    def read(self, channel: int) -> float:
        """Analog input number ``channel`` [V] (0 = p_A, 1 = p_B, 2 = load)."""
        if channel == 2:
            return self.load_cell.volts(self.load_force)
        h = self.hydraulics
        return self.transducers[channel].volts(h.p_a if channel == 0 else h.p_b)

    def analog_inputs(self, names: Sequence[str]) -> AnalogReader:
        """A reader of the inputs ``names`` in this order, for a sample every servo cycle.

        Raises:
            WiringError: the device has no such input.
        """
        return AnalogReader(self, [self.channel(n) for n in names])

    def get_state(self) -> npt.NDArray[np.float64]:
        rng = [t.state for t in (*self.transducers, self.load_cell)]
        return np.array([*self.hydraulics.get_state(), *rng])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        values = [float(v) for v in state]
        self.hydraulics.set_state(values[:7])
        for t, s in zip((*self.transducers, self.load_cell), values[7:10], strict=True):
            t.state = round(s)
        self._write()


class AnalogReader:
    """The analog inputs of a :class:`CylinderDevice` an axis reads, in input order [V]."""

    def __init__(self, device: CylinderDevice, channels: list[int]) -> None:
        self.device = device
        self.channels = channels

    def __call__(self) -> list[float]:
        device = self.device
        return [device.read(c) for c in self.channels]


def make_cylinder(model: mujoco.MjModel, data: mujoco.MjData, prefix: str) -> CylinderDevice:
    """The press cylinder device of a compiled model (a :data:`DeviceFactory`)."""
    valve, cylinder, supply = cylinder_data(model, prefix)
    full, bits, noise = numeric(model, f"{prefix}R_transducer", 3, 0.0)
    cell, cell_bits, cell_noise = numeric(model, f"{prefix}R_load_cell", 3, 0.0)
    return CylinderDevice(
        model,
        data,
        f"{prefix}R",
        valve,
        cylinder,
        supply,
        (float(full), round(bits), float(noise)),
        (float(cell), round(cell_bits), float(cell_noise)),
        load=ContactForce(model, data, prefix),
    )

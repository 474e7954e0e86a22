"""Drive kinds and device models: what turns an axis' ±10 V into force on a MuJoCo joint.

A drive is what a channel's outputs drive (:class:`mcl.channel.Drive`), given to the channel at
construction:

- :class:`ElectricAmplifier`: a velocity-mode servo amplifier written as the MJCF actuator
  ``<axis>_amp`` (control = volts), with an optional holding brake (``<axis>_brake_force``);
- :class:`DeviceDrive`: the volts go into a Python :class:`Device` (a valve and a cylinder) that
  sets a force on its joint before every physics step;
- an encoder-only axis has no drive at all (``has_drive`` False on its channel).

A :class:`Device` with state integrates every physics step through the plant's hook; its state
belongs to the scene (``get_state``/``set_state``), so resets and replays are bit-identical.
"""

from __future__ import annotations

from typing import Any, Protocol

import mujoco
import numpy as np
import numpy.typing as npt
from mypy_extensions import mypyc_attr

from mcl.channel import Drive as ChannelDrive
from scenes.errors import WiringError

__all__ = [
    "Device",
    "DeviceDrive",
    "Drive",
    "DrivenDevice",
    "ElectricAmplifier",
    "SpringDamper",
    "WiringError",
]


@mypyc_attr(allow_interpreted_subclasses=True)
class Drive(ChannelDrive):
    """Applies an axis command to a MuJoCo model, with the state it changed there (a base
    class: the compiled build calls it directly)."""

    def get_state(self) -> npt.NDArray[np.float64]:
        """What the drive changed in the model (restored with :meth:`set_state`)."""
        return np.zeros(0)

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        """Restore a state taken with :meth:`get_state`."""


class Device(Protocol):
    """A Python model integrated with the physics (a valve with oil chambers, a test spring).

    The plant calls :meth:`before_step` before every ``mj_step``; the device reads ``data`` and
    writes its force (``data.qfrc_applied``, ``data.xfrc_applied``) for that step.
    """

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Integrate the device over the coming step and set its force."""
        ...

    def get_state(self) -> npt.NDArray[np.float64]:
        """The device's state (copied)."""
        ...

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        """Restore a state taken with :meth:`get_state`."""
        ...


class DrivenDevice(Device, Protocol):
    """A device that is also an axis' drive (it takes the ±10 V command)."""

    def apply(self, volts: float, enabled: bool, brake: bool) -> None:
        """Analog command [V], amplifier on, holding brake engaged."""
        ...


class ElectricAmplifier(Drive):
    """A ±10 V velocity-mode servo amplifier: the MJCF actuator ``<axis>_amp``.

    Drive enable switches the actuator's group off and on (``opt.disableactuator``); the holding
    brake, where the model has ``<axis>_brake_force``, is the joint's Coulomb friction. Both are
    this drive's state: :meth:`get_state` / :meth:`set_state` carry them through a reset.

    Args:
        model: the compiled model.
        actuator: the amplifier's actuator id.
        dof: the axis' degree of freedom.
        brake_force: holding force (torque on a hinge) of the brake [N]; 0 = no brake.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        actuator: int,
        dof: int,
        brake_force: float,
    ) -> None:
        self.model, self.data = model, data
        self._ctrl: Any = memoryview(data.ctrl)  # item access without numpy scalars
        self.actuator = actuator
        self.dof = dof
        self.group_bit = 1 << int(model.actuator_group[actuator])
        self.brake_force = brake_force
        self.friction = float(model.dof_frictionloss[dof])
        self.enabled = True
        self.braked = False
        self.apply(0.0, False, True)

    def apply(self, volts: float, enabled: bool, brake: bool) -> None:
        self._ctrl[self.actuator] = volts
        if enabled != self.enabled:
            self.enabled = enabled
            opt = self.model.opt
            if enabled:
                opt.disableactuator &= ~self.group_bit
            else:
                opt.disableactuator |= self.group_bit
        if brake != self.braked:
            self.braked = brake
            if self.brake_force:
                self.model.dof_frictionloss[self.dof] = self.brake_force if brake else self.friction

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array([float(self.enabled), float(self.braked)])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        self.apply(float(self.data.ctrl[self.actuator]), bool(state[0]), bool(state[1]))


class DeviceDrive(Drive):
    """The axis' command goes into a :class:`DrivenDevice` (e.g. a valve-controlled cylinder).

    The device itself keeps the command as part of its state; this drive only forwards it.
    """

    def __init__(self, device: DrivenDevice) -> None:
        self.device = device

    def apply(self, volts: float, enabled: bool, brake: bool) -> None:
        self.device.apply(volts, enabled, brake)


class SpringDamper:
    """A linear spring-damper on one joint, written in Python: the device hook's reference test.

    ``f = −k·(q − q0) − c·q̇`` on the joint before every step; the state is the energy it has
    dissipated [J], integrated every step (so a reset has something to restore).

    Args:
        model, data: the compiled model and its data.
        joint: the joint's name.
        stiffness: k [N/m or N·m/rad]; damping: c [N·s/m or N·m·s/rad]; rest: q0 [m or rad].
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        joint: str,
        stiffness: float,
        damping: float,
        rest: float = 0.0,
    ) -> None:
        j = model.joint(joint)
        self.qpos = int(j.qposadr[0])
        self.dof = int(j.dofadr[0])
        self.k, self.c, self.rest = stiffness, damping, rest
        self.dt = float(model.opt.timestep)
        self.dissipated = 0.0
        """Energy the damper has dissipated [J]."""

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        q, v = float(data.qpos[self.qpos]), float(data.qvel[self.dof])
        data.qfrc_applied[self.dof] = -self.k * (q - self.rest) - self.c * v
        self.dissipated += self.c * v * v * self.dt

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array([self.dissipated])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        self.dissipated = float(state[0])

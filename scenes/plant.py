"""The MuJoCo plant: the mcl I/O boundary implemented on a MuJoCo model (models/README.md).

Per axis: the ±10 V amplifier is the MJCF actuator ``<axis>_amp`` (control = volts), the drive
enable switches its actuator group, the holding brake (where the model has ``<axis>_brake_force``)
is the joint's Coulomb friction, the encoder counts the joint coordinate through the screw lead
with an index pulse per motor revolution, and LIM−/LIM+/REF come from the switch and cam sites.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from mcl.encoder import IncrementalEncoder

SWITCHES = ("lim_neg", "lim_pos", "ref")


class WiringError(ValueError):
    """The model does not provide what an axis needs; the message says what and what would fit."""


@dataclass(frozen=True, slots=True)
class AxisWiring:
    """Where one axis lives in a compiled model (names already prefixed, e.g. ``gantry/X``).

    Attributes:
        axis: the axis joint's name.
        prefix: the prefix of the machine's other names (``""`` or ``"gantry/"``).
    """

    axis: str
    prefix: str = ""


def _numeric(model: mujoco.MjModel, name: str, size: int | None = None) -> np.ndarray:
    try:
        data = np.asarray(model.numeric(name).data, dtype=float)
    except KeyError:
        names = [model.numeric(i).name for i in range(model.nnumeric)]
        raise WiringError(f"model has no custom numeric {name!r}; it has: {names}") from None
    if size is not None and data.size != size:
        raise WiringError(f"numeric {name!r} must have {size} values, has {data.size}")
    return data


def _id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    index = mujoco.mj_name2id(model, kind, name)
    if index < 0:
        count = {
            mujoco.mjtObj.mjOBJ_JOINT: model.njnt,
            mujoco.mjtObj.mjOBJ_ACTUATOR: model.nu,
            mujoco.mjtObj.mjOBJ_SITE: model.nsite,
        }[kind]
        names = [mujoco.mj_id2name(model, kind, i) for i in range(count)]
        what = kind.name.removeprefix("mjOBJ_").lower()
        raise WiringError(f"model has no {what} {name!r}; {what}s: {names}")
    return index


class MujocoAxisIO:
    """One axis channel on a MuJoCo model; implements :class:`mcl.io.AxisIO`.

    Args:
        model, data: the compiled model and its data (positions current, e.g. after mj_forward).
        wiring: which joint and names belong to the axis.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, wiring: AxisWiring) -> None:
        self.model, self.data = model, data
        self.name = wiring.axis
        p, a = wiring.prefix, wiring.axis.removeprefix(wiring.prefix)
        self.joint = _id(model, mujoco.mjtObj.mjOBJ_JOINT, wiring.axis)
        if int(model.jnt_type[self.joint]) not in (
            int(mujoco.mjtJoint.mjJNT_SLIDE),
            int(mujoco.mjtJoint.mjJNT_HINGE),
        ):
            raise WiringError(f"axis joint {wiring.axis!r} must be a slide or hinge joint")
        self.qpos_adr = int(model.jnt_qposadr[self.joint])
        self.dof = int(model.jnt_dofadr[self.joint])
        self.actuator = _id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, f"{p}{a}_amp")
        lo, hi = model.actuator_ctrlrange[self.actuator]
        if not (model.actuator_ctrllimited[self.actuator] and lo <= -10.0 and hi >= 10.0):
            raise WiringError(
                f"actuator {p}{a}_amp must have ctrlrange -10 10 (volts), has {lo:g} {hi:g}"
            )
        self.group_bit = 1 << int(model.actuator_group[self.actuator])
        lead = float(_numeric(model, f"{p}{a}_lead", 1)[0])
        per_rev = round(float(_numeric(model, f"{p}{a}_counts_per_rev", 1)[0]))
        width = round(float(_numeric(model, f"{p}{a}_index_width", 1)[0]))
        self.resolution = lead / per_rev
        """Travel per encoder count [m]."""
        self.encoder = IncrementalEncoder(self.resolution, per_rev, self.position, width)
        self._switches = [self._switch(p, a, kind) for kind in SWITCHES]
        brake = f"{p}{a}_brake_force"
        has_brake = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, brake) >= 0
        self.brake_force = float(_numeric(model, brake, 1)[0]) if has_brake else 0.0
        self.friction = float(model.dof_frictionloss[self.dof])
        self.enabled = True
        self.volts = 0.0
        self.counts = self.index_count = self.index_seq = 0
        self.index = self.lim_pos = self.lim_neg = self.ref = self.tp = False
        self.tp_count = self.tp_seq = 0
        self.analog: Sequence[float] = ()
        self.write(0.0, False)
        self.sense()

    def _switch(self, p: str, a: str, kind: str) -> tuple[float, float]:
        """Window of ``q`` in which the switch is actuated: the README formula, solved for ``q``.

        ``d = (cam − switch) · e`` moves one-to-one with the joint coordinate on a slide joint,
        so ``d = q + offset`` with the offset taken from the current geometry.
        """
        model, data = self.model, self.data
        cam = _id(model, mujoco.mjtObj.mjOBJ_SITE, f"{p}{a}_{kind}_cam")
        switch = _id(model, mujoco.mjtObj.mjOBJ_SITE, f"{p}{a}_{kind}")
        lo, hi = _numeric(model, f"{p}{a}_{kind}_window", 2)
        d = float((data.site_xpos[cam] - data.site_xpos[switch]) @ data.xaxis[self.joint])
        offset = d - self.position
        return float(lo - offset), float(hi - offset)

    @property
    def position(self) -> float:
        """Joint coordinate [m] (ground truth)."""
        return float(self.data.qpos[self.qpos_adr])

    def write(self, volts: float, enable: bool) -> None:
        """Analog command [V] to the amplifier; ``enable`` False disables it and sets the brake."""
        self.volts = volts if enable else 0.0
        self.data.ctrl[self.actuator] = self.volts
        if enable != self.enabled:
            self.enabled = enable
            opt = self.model.opt
            if enable:
                opt.disableactuator &= ~self.group_bit
            else:
                opt.disableactuator |= self.group_bit
            if self.brake_force:
                self.model.dof_frictionloss[self.dof] = (
                    self.friction if enable else self.brake_force
                )

    def sense(self) -> None:
        """Sample encoder and switches at the current instant."""
        q = float(self.data.qpos[self.qpos_adr])
        enc = self.encoder
        enc.update(q)
        self.counts = enc.counts
        self.index = enc.index
        self.index_count = enc.index_count
        self.index_seq = enc.index_seq
        (nlo, nhi), (plo, phi), (rlo, rhi) = self._switches
        self.lim_neg = nlo <= q <= nhi
        self.lim_pos = plo <= q <= phi
        self.ref = rlo <= q <= rhi


class MujocoPlant:
    """Steps a MuJoCo model; implements :class:`mcl.runtime.Plant`.

    Args:
        model, data: the compiled model and its data.
        wirings: the axes to expose as :class:`MujocoAxisIO` channels.
    """

    def __init__(
        self, model: mujoco.MjModel, data: mujoco.MjData, wirings: Sequence[AxisWiring]
    ) -> None:
        self.model, self.data = model, data
        self.timestep = float(model.opt.timestep)
        if not (math.isfinite(self.timestep) and self.timestep > 0.0):
            raise WiringError(f"model timestep must be > 0 s, got {self.timestep}")
        mujoco.mj_forward(model, data)
        self.ios = {w.axis: MujocoAxisIO(model, data, w) for w in wirings}

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self.data.time)

    def step(self) -> None:
        """One physics step."""
        mujoco.mj_step(self.model, self.data)

    def sense(self) -> None:
        """Sample every axis' inputs."""
        for io in self.ios.values():
            io.sense()

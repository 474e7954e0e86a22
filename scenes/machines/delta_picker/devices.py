"""The vacuum gripper: digital output 0 of arm ``A1`` opens the vacuum valve; the cup holds a
part by the force the model's adhesion actuator ``vacuum`` applies where the cup touches it
(the cup's pull, ``cup_force``), and loses it when the part's inertia and weight ask for more.
Every grip is recorded with the pick error measured on the physics: the cup's centre against the
part's centre when the vacuum comes on."""

from __future__ import annotations

__all__ = ["Grip", "VacuumGripper"]

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from scenes.plant.mujoco import MujocoAxisIO, numeric

HOLD = 0.005
"""A part counts as held while its top face lies within this of the cup's face [m]."""


@dataclass(frozen=True)
class Grip:
    """One grip: when [s], which part, the cup's centre against the part's centre in the
    horizontal plane and along z (cup face against the part's top face) [mm]."""

    time: float
    part: int
    error: float
    height: float


class VacuumGripper:
    """The vacuum valve and cup (module docstring).

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.prefix = prefix
        self.force = float(numeric(model, f"{prefix}cup_force", 1, 0.0)[0])
        self._actuator = int(model.actuator(f"{prefix}vacuum").id)
        self._tool = int(model.site(f"{prefix}tool").id)
        parts = []
        k = 0
        while mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{prefix}part{k}") >= 0:
            body = model.body(f"{prefix}part{k}")
            geom = int(body.geomadr[0])
            parts.append((int(body.id), float(model.geom_size[geom][2])))
            k += 1
        self._parts = parts
        self._data = data
        self.outputs: list[bool] = []
        """The A1 channel's digital outputs (set by :meth:`connect`)."""
        self.on = False
        """The vacuum valve is open."""
        self.held = -1
        """The part the cup holds (-1: none)."""
        self.grips: list[Grip] = []
        """Every grip, oldest first."""
        self.lost = 0
        """Parts the cup lost while the vacuum was on."""

    def connect(self, ios: Mapping[str, MujocoAxisIO]) -> None:
        """Wire the valve to digital output 0 of the arm A1's channel."""
        self.outputs = ios[f"{self.prefix}A1"].outputs

    def part_position(self, k: int) -> npt.NDArray[np.float64]:
        """Centre of part ``k`` in the world [m]."""
        return np.array(self._data.xpos[self._parts[k][0]])

    def _nearest(self, data: mujoco.MjData) -> tuple[int, float, float]:
        """The part under the cup: its number, horizontal and vertical distance [m]."""
        tool = data.site_xpos[self._tool]
        best, best_xy, best_z = -1, math.inf, math.inf
        for k, (body, half) in enumerate(self._parts):
            centre = data.xpos[body]
            xy = math.hypot(centre[0] - tool[0], centre[1] - tool[1])
            if xy < best_xy:
                best, best_xy, best_z = k, xy, float(tool[2] - (centre[2] + half))
        return best, best_xy, best_z

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Open or close the valve; record a grip; notice a part lost."""
        command = bool(self.outputs and self.outputs[0])
        if command != self.on:
            self.on = command
            if command:
                k, xy, z = self._nearest(data)
                if k >= 0 and abs(z) <= HOLD and xy <= 0.03:
                    self.held = k
                    self.grips.append(Grip(float(data.time), k, 1000.0 * xy, 1000.0 * z))
            else:
                self.held = -1
        data.ctrl[self._actuator] = 1.0 if command else 0.0
        if self.on and self.held >= 0:
            body, half = self._parts[self.held]
            gap = data.site_xpos[self._tool][2] - (data.xpos[body][2] + half)
            if abs(gap) > HOLD:
                self.lost += 1
                self.held = -1

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array([float(self.on), float(self.held), float(self.lost), len(self.grips)])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        self.on, self.held, self.lost = bool(state[0]), int(state[1]), int(state[2])
        del self.grips[int(state[3]) :]


"""Saved machine states of a scene: what :meth:`scenes.Scene.save_state` returns.

A state is a :class:`mcl.MachineState`: the simulated time, every axis with its channel, the
fault log and the plant. For a MuJoCo scene the plant's part is a :class:`MujocoState`: the
model's integration state (time, joint positions and velocities, actuator states, controls,
applied forces) with every drive's and every device's state (oil pressures, valve spools,
roll and wheel couplings).
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from mcl import MachineState

if TYPE_CHECKING:
    from scenes.plant.mujoco import MujocoPlant

__all__ = ["MachineState", "MujocoState", "model_identity"]


@dataclass(frozen=True, slots=True)
class MujocoState:
    """The MuJoCo plant at one instant (:meth:`MujocoPlant.get_state`): read-only copies of
    :meth:`MujocoPlant.arrays`.

    Attributes:
        arrays: the integration state of the model, then one array per drive (in the order of
            the axes), then one per device.
    """

    arrays: tuple[npt.NDArray[np.float64], ...]

    @classmethod
    def of(cls, plant: MujocoPlant) -> MujocoState:
        """The plant's state now."""
        arrays = []
        for array in plant.arrays():
            copy = np.array(array, dtype=np.float64)
            copy.flags.writeable = False
            arrays.append(copy)
        return cls(tuple(arrays))

    def restore(self, plant: MujocoPlant) -> None:
        """Return ``plant`` to this state (then ``mj_forward``)."""
        plant.set_arrays([array.copy() for array in self.arrays])


def model_identity(model: mujoco.MjModel) -> str:
    """A text that changes with the model's sizes, timestep and geometry, masses and gains
    (two scenes of one machine at other positions differ in it)."""
    parts = (
        model.body_pos,
        model.body_quat,
        model.body_mass,
        model.jnt_range,
        model.dof_damping,
        model.actuator_gainprm,
        model.actuator_biasprm,
    )
    crc = 0
    for part in parts:
        crc = zlib.crc32(np.ascontiguousarray(part, dtype=np.float64).tobytes(), crc)
    return (
        f"model of nq {model.nq}, nv {model.nv}, na {model.na}, nu {model.nu}, timestep "
        f"{float(model.opt.timestep) * 1e3:g} ms, checksum {crc:08x}"
    )

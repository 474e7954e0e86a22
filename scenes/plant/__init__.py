"""The MuJoCo plant: the mcl I/O boundary on a MuJoCo model (:mod:`.mujoco`), the drive kinds
and the device protocol (:mod:`.drives`) and the saved state of a scene (:mod:`.state`)."""

from scenes.plant.drives import Device, DeviceDrive, Drive, ElectricAmplifier, WiringError
from scenes.plant.mujoco import AxisWiring, Joint, MujocoAxisIO, MujocoPlant, Probe, numeric
from scenes.plant.state import MujocoState, model_identity

COMPILED_MODULES = ("mujoco", "drives")
"""The modules of this package that the compiled build covers (they run every physics step)."""

__all__ = [
    "AxisWiring",
    "Device",
    "DeviceDrive",
    "Drive",
    "ElectricAmplifier",
    "Joint",
    "MujocoAxisIO",
    "MujocoPlant",
    "MujocoState",
    "Probe",
    "WiringError",
    "model_identity",
    "numeric",
]

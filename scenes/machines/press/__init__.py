"""The hydraulic press (models/hydraulic_press.xml): a valve-controlled cylinder pressing a part.

One mcl axis ``R``, the ram's stroke in mm (0 = top, positive = down; :mod:`.axes`), driven by
the Python device ``cylinder`` (:class:`.devices.CylinderDevice`: servo valve, differential
cylinder, oil columns, the model of :mod:`.hydraulics`) with ±10 V. Its analog inputs:
0 = pressure A, 1 = pressure B (0–250 bar → 0–10 V, 12 bit, seeded noise), 2 = the load cell
under the part (0–150 kN → 0–10 V). :mod:`.demo` is the press cycle, :mod:`.definition` the
press in the registry; :mod:`.hydraulic_axis` a simulated hydraulic axis for unit tests.

``FORCE_INPUTS`` (read on first use): the MC_ForceControl inputs of the cylinder in the model
file (:func:`.demo.force_inputs`; the demo takes those of its scene's cylinder).
"""

from scenes.machines.press.axes import (
    AXES,
    BLOCK_HOMING,
    HOMING,
    MASS,
    MODEL,
    RAM_SSI,
    REFERENCE,
    STEP_BLOCK_INPUTS,
    WEIGHT,
)
from scenes.machines.press.definition import MACHINE
from scenes.machines.press.demo import (
    BAR_PER_VOLT,
    DECOMPRESSION,
    DWELL,
    FORCE_GAIN,
    HOLD_FORCE,
    PART,
    PRESSURE_STOP,
    STEPS,
    TOP,
    WATCHED,
    Demo,
    force_inputs,
    model_force_inputs,
)
from scenes.machines.press.devices import cylinder_data, make_cylinder

COMPILED_MODULES = ("hydraulics", "devices", "hydraulic_axis", "demo")
"""The modules of this package that the compiled build covers (the valve and the cylinder, their
device and the simulated axis, run every physics step; the demo, every PLC scan)."""

__all__ = [
    "AXES",
    "BAR_PER_VOLT",
    "BLOCK_HOMING",
    "DECOMPRESSION",
    "DWELL",
    "FORCE_GAIN",
    "FORCE_INPUTS",
    "HOLD_FORCE",
    "HOMING",
    "MACHINE",
    "MASS",
    "MODEL",
    "PART",
    "PRESSURE_STOP",
    "RAM_SSI",
    "REFERENCE",
    "STEPS",
    "STEP_BLOCK_INPUTS",
    "TOP",
    "WATCHED",
    "WEIGHT",
    "Demo",
    "cylinder_data",
    "force_inputs",
    "make_cylinder",
    "model_force_inputs",
]


def __getattr__(name: str) -> dict[str, float]:
    """``FORCE_INPUTS``, read from the model file on first use."""
    if name == "FORCE_INPUTS":
        return model_force_inputs()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

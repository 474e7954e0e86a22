"""The delta picker (models/delta_picker.xml): a three-arm rotary delta robot wired to three mcl
axes A1, A2, A3 (the upper arms, deg) grouped with the delta kinematics, an infeed conveyor ``C``
whose touch probe is the photo eye, and a vacuum cup (:mod:`.devices`); its axes and homing
recipes (:mod:`.axes`), its pick-and-place demo (:mod:`.demo`) and its definition
(:mod:`.definition`)."""

from scenes.machines.delta_picker.axes import AXES, DELTA, HOMING
from scenes.machines.delta_picker.definition import MACHINE
from scenes.machines.delta_picker.demo import PICK, SLOTS, Demo
from scenes.machines.delta_picker.devices import Grip, VacuumGripper

__all__ = ["AXES", "DELTA", "HOMING", "MACHINE", "PICK", "SLOTS", "Demo", "Grip", "VacuumGripper"]

"""One machine's view of a scene it shares with other machines (a cell): the machine's code runs
unchanged in it.

A machine's demo, devices and signals say ``scene.axes["X"]``, ``scene.device("cylinder", ...)``,
``scene.signal("force")``; in a scene of several machines those names are prefixed
(``gantry/X``, ``press/cylinder``). :class:`MachineScene` gives each machine its own names over
the shared scene: the axes, devices and signals are the scene's own objects, the physics, the
time, the runtime and the trace are the whole scene's.
"""

from __future__ import annotations

__all__ = ["MachineScene"]

import mcl
from scenes.definition import MachineDef
from scenes.scene import Scene


class MachineScene(Scene):
    """Machine ``machine``'s view of ``scene`` (see :meth:`Scene.machine`).

    It is a :class:`Scene` to the machine's code (its axes, devices, signals, joints, time and
    ``run``); what belongs to the whole scene (saving a state, faults) is done on the scene.
    """

    def __init__(self, scene: Scene, machine: MachineDef) -> None:  # shares, builds nothing
        prefix = f"{machine.name}/"
        self.whole = scene
        """The scene this view is part of."""
        self.cell = None
        self.machines = [machine]
        self.name = machine.name
        self.axes = {a: scene.axes[prefix + a] for a in machine.axes}
        self.devices = {d: scene.devices[prefix + d] for d in machine.devices}
        self.signals = dict(machine.signals)
        self.parts = {machine.name: self}
        self._signal_scenes = {}
        self.scales = {a: scene.scales[prefix + a] for a in machine.axes}
        self.modules = [m for m in scene.modules if m.axes[0] in self.axes.values()]
        self.plant, self.runtime, self.trace = scene.plant, scene.runtime, scene.trace
        self._model, self._data, self._joints = scene._model, scene._data, scene._joints

    @property
    def faults(self) -> mcl.faults.FaultLog:
        """The whole scene's fault log (its axes by their names in the scene, ``press/R``)."""
        return self.whole.faults

    def save_state(self) -> mcl.MachineState:
        """A machine of a cell is saved with the whole scene.

        Raises:
            mcl.StateError: always; save the whole scene instead.
        """
        raise mcl.StateError(
            f"machine {self.name} shares its physics with the other machines of the scene: "
            f"save the whole scene (scene.save_state()), not one machine's view of it"
        )

    def restore_state(self, state: mcl.MachineState) -> None:
        """A machine of a cell is restored with the whole scene.

        Raises:
            mcl.StateError: always; restore the whole scene instead.
        """
        raise mcl.StateError(
            f"machine {self.name} shares its physics with the other machines of the scene: "
            f"restore the whole scene, not one machine's view of it"
        )

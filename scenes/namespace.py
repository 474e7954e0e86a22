"""A machine's own names and the scene's names for them (:class:`Namespace`).

A machine's code names its joints, actuators, sites, sensors and numerics as its model file
does (``"X"``, ``"X_amp"``, ``"mark_sensor"``) and its axes, devices and signals as its
definition does (``scene.axes["X"]``, ``scene.device("cylinder", ...)``). A scene attaches every
machine's model under the machine's name (``gantry/X``, ``gantry/X_amp``), and where machines
share a scene (a cell) their axes, devices and signals take the machine's name too
(``gantry/X``, ``press/cylinder``). The scene turns a machine's names into its own, so no machine
knows its prefix.
"""

from __future__ import annotations

__all__ = ["SEPARATOR", "Namespace"]

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TypeVar

T = TypeVar("T")

SEPARATOR = "/"
"""What joins a machine's name and its own names in a scene (MJCF's scoping: no name of a model
file has it)."""


@dataclass(frozen=True)
class Namespace:
    """The names of machine ``machine`` in a scene.

    Attributes:
        machine: the machine's name; ``""`` for the whole scene of several machines, in which
            every name is already the scene's (``gantry/X``).
        shared: the machine shares the scene with others: its axes, devices and signals are
            prefixed with its name there too.
    """

    machine: str = ""
    shared: bool = False

    @property
    def prefix(self) -> str:
        """The prefix of the machine's names in the scene's model (``"gantry/"``)."""
        return self.machine + SEPARATOR if self.machine else ""

    def model(self, name: str) -> str:
        """The model's name of the machine's joint, actuator, site, sensor or numeric ``name``
        (``"X_amp"`` → ``"gantry/X_amp"``); a name with a ``/`` is the model's already."""
        return name if SEPARATOR in name else self.prefix + name

    def scene(self, name: str) -> str:
        """The scene's name of the machine's axis, device or signal ``name`` (``"X"`` alone,
        ``"gantry/X"`` in a shared scene)."""
        return self.prefix + name if self.shared else name

    def own(self, named: Mapping[str, T]) -> dict[str, T]:
        """The machine's own of a scene's axes, devices or signals ``named`` (by their names in
        the scene), by the machine's names, in their order."""
        if not self.shared:
            return dict(named)
        return {
            n.removeprefix(self.prefix): v for n, v in named.items() if n.startswith(self.prefix)
        }

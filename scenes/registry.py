"""The machine registry: every machine by name, each loaded when it is first asked for.

An entry is a :class:`~scenes.definition.MachineDef`, or the ``"package.module:ATTRIBUTE"`` path
of one, imported on first use (so listing the machines imports none of them). The project's own
machines are :data:`BUILTIN`; a user's package adds its machines without editing this project,
either by calling :func:`scenes.register` or through the entry-point group :data:`ENTRY_POINTS`
in its ``pyproject.toml``::

    [project.entry-points."mcl_testbench.machines"]
    my_cell = "my_package.my_cell:MACHINE"
"""

from __future__ import annotations

__all__ = ["BUILTIN", "ENTRY_POINTS", "Entry", "Registry", "RegistryError", "load_entry"]

import importlib
import importlib.metadata
from collections.abc import Iterator, Mapping, MutableMapping

from scenes.definition import MachineDef
from scenes.errors import UserError

ENTRY_POINTS = "mcl_testbench.machines"
"""The entry-point group through which installed packages register machines."""

BUILTIN = {
    "cell": "scenes.machines.cell:MACHINE",
    "delta_picker": "scenes.machines.delta_picker:MACHINE",
    "flying_shear": "scenes.machines.flying_shear:MACHINE",
    "gantry": "scenes.machines.gantry:MACHINE",
    "press": "scenes.machines.press:MACHINE",
    "rotary_cutter": "scenes.machines.rotary_cutter:MACHINE",
    "single_axis": "scenes.machines.single_axis:MACHINE",
}
"""The project's own machines: name → where its definition is."""

Entry = MachineDef | str
"""A registered machine: its definition, or the ``"module:attribute"`` path of it."""


class RegistryError(UserError):
    """A registered entry that does not load."""


def load_entry(name: str, entry: Entry) -> MachineDef:
    """The definition an entry stands for.

    Raises:
        RegistryError: the path does not import or names no MachineDef called ``name``.
    """
    if isinstance(entry, MachineDef):
        machine = entry
    else:
        module, _, attribute = entry.partition(":")
        try:
            machine = getattr(importlib.import_module(module), attribute)
        except (ImportError, AttributeError) as error:
            raise RegistryError(
                f"machine {name!r}: its entry {entry!r} does not load ({error}); expected "
                f"'package.module:ATTRIBUTE' naming a scenes.MachineDef"
            ) from None
    if not isinstance(machine, MachineDef) or machine.name != name:
        raise RegistryError(
            f"machine {name!r}: {entry!r} is {machine!r:.80}; expected a scenes.MachineDef "
            f"with name={name!r}"
        )
    return machine


class Registry(MutableMapping[str, MachineDef]):
    """Machines by name, in the order registered; an entry is loaded the first time it is read.

    ``registry[name] = definition`` registers (or replaces) a machine; ``del registry[name]``
    removes it.
    """

    def __init__(self, entries: Mapping[str, Entry] | None = None) -> None:
        self._entries: dict[str, Entry] = dict(entries or {})

    def register(self, name: str, entry: Entry) -> None:
        """Add the machine ``name`` (a definition or the path of one), replacing one so named."""
        if not name.isidentifier():
            raise ValueError(f"machine name {name!r}: expected a Python identifier, e.g. 'my_cell'")
        self._entries[name] = entry

    def add_entry_points(self) -> None:
        """Register the machines of the installed packages' entry points (group
        :data:`ENTRY_POINTS`); the project's own names are kept."""
        for point in importlib.metadata.entry_points(group=ENTRY_POINTS):
            self._entries.setdefault(point.name, point.value)

    def __getitem__(self, name: str) -> MachineDef:
        entry = self._entries[name]  # KeyError: not registered
        machine = load_entry(name, entry)
        self._entries[name] = machine
        return machine

    def __setitem__(self, name: str, machine: MachineDef) -> None:
        self.register(name, machine)

    def __delitem__(self, name: str) -> None:
        del self._entries[name]

    def __iter__(self) -> Iterator[str]:
        return iter(list(self._entries))

    def __len__(self) -> int:
        return len(self._entries)

    def __contains__(self, name: object) -> bool:
        return name in self._entries

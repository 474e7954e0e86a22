"""The machines, one package each: its definition (``MACHINE``), axes and homing recipes, devices
and demo. Nothing outside a machine's package names that machine; the registry
(:mod:`scenes.registry`) finds it by the path of its ``MACHINE``."""

__all__: list[str] = []

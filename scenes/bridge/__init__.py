"""The bridge: an external PLC drives a machine through its signal table (Modbus TCP, OPC UA).

Needs the ``[bridge]`` extra. The servers (:mod:`~scenes.bridge.modbus`,
:mod:`~scenes.bridge.opcua` with its node tree :mod:`~scenes.bridge.opcua_nodes`), the signal
table (:mod:`~scenes.bridge.table`), the PLC program of the command words
(:mod:`~scenes.bridge.program`), the pacing (:mod:`~scenes.bridge.pacing`) and what the servers
share (:mod:`~scenes.bridge.serving`) are its API; the OPC UA methods (``opcua_methods``), the
machine's run (``machine``) and the Markdown map (``register_map``) are internal to it.
"""

__all__: list[str] = []

from mcl.extras import require

require("scenes.bridge", "bridge")

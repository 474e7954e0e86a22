"""The bridge: an external PLC drives a machine through its signal tables (Modbus TCP, OPC UA).

Needs the ``[bridge]`` extra. The tables (:mod:`~scenes.bridge.table`) and their transports
(:mod:`~scenes.bridge.modbus`, :mod:`~scenes.bridge.opcua` with its node tree
:mod:`~scenes.bridge.opcua_nodes`, and what the servers share, :mod:`~scenes.bridge.serving`); the
PLC program that scans them (:mod:`~scenes.bridge.program`) is the operator program of
:mod:`plc.operator` driven by its bus front end; the simulation thread runs free, paced to the wall
clock, or in lockstep with the client (:mod:`~scenes.bridge.runs`). The OPC UA methods
(``opcua_methods``), the machine's run (``machine``) and the Markdown map (``register_map``) are
internal to it.
"""

__all__: list[str] = []

from mcl.extras import require

require("scenes.bridge", "bridge")

"""The bridge: an external PLC drives a machine through its signal table (Modbus TCP, OPC UA).

Needs the ``[bridge]`` extra.
"""

from mcl.extras import require

require("scenes.bridge", "bridge")

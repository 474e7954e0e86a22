"""The bridge: an external PLC drives a machine through its signal tables (Modbus TCP, OPC UA).

The tables (:mod:`~scenes.bridge.table`) and their transports (:mod:`~scenes.bridge.modbus`,
:mod:`~scenes.bridge.opcua`); the PLC program that scans them (:mod:`~scenes.bridge.program`) is
the operator program of :mod:`plc.operator` driven by its bus front end; the simulation thread
runs free, paced to the wall clock, or in lockstep with the client (:mod:`~scenes.bridge.runs`).
"""

"""The bridge: an external PLC drives a machine through its signal table (Modbus TCP)."""

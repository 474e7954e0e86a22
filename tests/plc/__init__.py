"""Tests of the PLC layer (plc): step sequences, homing procedures, operator, commissioning."""

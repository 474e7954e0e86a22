"""Tests of the fieldbus bridge (scenes.bridge): Modbus TCP and OPC UA, from the master's side."""

"""Tests of the Structured Text compiler and runtime (plc.st)."""

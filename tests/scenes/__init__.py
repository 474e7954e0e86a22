"""Tests of the testbench (scenes): plant, machines, tools, command line."""

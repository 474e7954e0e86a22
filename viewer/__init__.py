"""Browser viewer (viser) for any testbench scene."""

"""Tests of the motion library (mcl): blocks, axes, groups, servo core, cams, simulated axes."""

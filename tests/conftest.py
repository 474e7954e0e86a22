"""Shared fixtures: a simulated axis, powered and referenced (helpers: ``tests/helpers.py``)."""

from __future__ import annotations

import pytest

import mcl
from tests.helpers import CONSTANTS as CONSTANTS  # re-exported: tests/benchmarks import it here
from tests.helpers import make_machine, power_on


@pytest.fixture
def machine() -> mcl.SimMachine:
    """One simulated axis "X" (travel −10..1010 mm, REF below 100 mm), constants written."""
    return make_machine("X", powered=False)


@pytest.fixture
def X(machine: mcl.SimMachine) -> mcl.Axis:
    """The powered, referenced axis of ``machine``."""
    axis = machine.axes["X"]
    power_on(machine, axis)
    return axis

"""Shared fixtures: a simulated axis, powered and referenced (helpers: ``tests/helpers.py``);
a viser server for the viewer's tests."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
import viser

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


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    """A viser server on a free port of the loopback interface, always stopped afterwards."""
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield srv
    finally:
        srv.stop()

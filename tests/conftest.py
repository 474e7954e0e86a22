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


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under ``--dist loadgroup`` (make test): each module is one unit of work, as with
    ``loadfile``, except that the browser tests form one unit, run first: one headless Chromium
    at a time, so two pages rendering on a 2-core machine never starve each other."""
    if config.getoption("dist", "no") != "loadgroup":
        return
    for item in items:
        browser = item.get_closest_marker("browser") is not None
        group = "browser" if browser else item.nodeid.split("::", 1)[0]
        item.add_marker(pytest.mark.xdist_group(group))
    items.sort(key=lambda item: item.get_closest_marker("browser") is None)  # stable

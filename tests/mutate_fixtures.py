"""pytest plugin of ``make mutate`` (tests/mutate.py), loaded into mutmut's pytest runs: the
functions a fixture wider than a test (module, class, package or session scope) calls, and the
time its setup takes, go to every test that uses it.

mutmut records which functions each test calls (its trampolines add them to ``state()._stats``
and its own plugin credits them to the test at its teardown) and runs each mutant against only
the tests credited with the mutated function. A wide fixture runs once, in the setup of the
first test that uses it, so without this plugin only that test is credited with the functions
the fixture calls: the other tests using the fixture never run against their mutants, and
what they would catch goes uncounted. mutmut also times only a test's call phase, and sets a
mutant's timeout from the times of its tests: a fixture's seconds left out make a slow fixture
outlast the timeout, and a timeout counts as a kill. So each test is timed with its setup and
teardown, plus the setup of each wide fixture it uses (over rather than under: a mutant's
tests may not include the one that sets the fixture up).
"""

from __future__ import annotations

import time
from collections.abc import Generator
from dataclasses import dataclass, field

import pytest
from mutmut.state import state


@dataclass
class Setup:
    """What a wide fixture's setups called (mutmut's function names) and took [s]."""

    calls: set[str] = field(default_factory=set)
    seconds: float = 0.0


SETUPS: dict[object, Setup] = {}
"""Each wide fixture's :class:`Setup`, keyed by its pytest fixture definition."""


@pytest.hookimpl(wrapper=True)
def pytest_fixture_setup(
    fixturedef: pytest.FixtureDef[object], request: pytest.FixtureRequest
) -> Generator[None, object, object]:
    """A wide fixture's setup recorded in its :class:`Setup` (and credited as before to the
    test being set up)."""
    if fixturedef.scope == "function":
        return (yield)
    outer, start = state()._stats, time.perf_counter()
    state()._stats = set()
    try:
        return (yield)
    finally:
        setup = SETUPS.setdefault(fixturedef, Setup())
        setup.calls |= state()._stats
        setup.seconds = max(setup.seconds, time.perf_counter() - start)
        state()._stats = outer | state()._stats


@pytest.hookimpl(tryfirst=True)  # before mutmut's own teardown hook credits ``_stats``
def pytest_runtest_teardown(item: pytest.Item) -> None:
    """The calls and setup time of the wide fixtures ``item`` uses, credited to it."""
    for definitions in item._fixtureinfo.name2fixturedefs.values():  # type: ignore[attr-defined]
        for fixturedef in definitions:
            setup = SETUPS.get(fixturedef)
            if setup is not None:
                state()._stats |= setup.calls
                state().duration_by_test[item.nodeid] += setup.seconds


@pytest.hookimpl(tryfirst=True)  # before pytest's own, which ends the hook with its report
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> None:
    """A test's setup and teardown timed too (mutmut times its call)."""
    if call.when != "call":
        state().duration_by_test[item.nodeid] += call.duration

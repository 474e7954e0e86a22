"""pytest plugin for scenario tests of PLC programs (installed with the package; pytest loads it).

Fixtures:

- ``scene``: a factory, ``scene("gantry", start={"X": 0.3})`` → :class:`scenes.Scene`. When the
  test fails, the trace of every scene it made is plotted (PNG and HTML) into the directory of
  ``--scene-plots`` (default ``scene-plots/``), named after the test.
- ``scans``: a :class:`ScanLog` factory that records values once per PLC scan.

Helpers (plain functions, usable anywhere): :func:`run_until` (a program with a timeout in
simulated time), :func:`max_following_error`, :func:`assert_pulsed_once`,
:func:`physical_position`. Faults are injected with ``scene.faults`` (:mod:`mcl.faults`).

.. code-block:: python

    def test_x_reaches_its_target(scene):
        gantry = scene("gantry", start={"X": 0.3})
        X = gantry.axes["X"]
        power, move = mcl.MC_Power(Axis=X), mcl.MC_MoveAbsolute(Axis=X, Position=500.0,
                                                                Velocity=200.0)
        def program():
            power(Enable=True)
            move(Execute=power.Status)
        run_until(gantry, program, lambda: move.Done, timeout=5.0)
        assert physical_position(gantry, "X") == pytest.approx(500.0, abs=0.01)
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

import mcl
import scenes
from scenes.scene import Scene


def run_until(
    scene: mcl.Machine,
    program: Callable[[], None] | None,
    condition: Callable[[], bool],
    timeout: float,
) -> float:
    """Run ``program`` every PLC scan until ``condition()`` holds; returns the simulated seconds.

    Raises:
        AssertionError: the condition did not hold within ``timeout`` simulated seconds (the
            message gives the axes' states and errors).
    """
    try:
        return scene.run(program, until=condition, timeout=timeout)
    except mcl.ConditionTimeout:
        states = ", ".join(
            f"{n}: {a.state.name} AxErrorID {a.AxErrorID} POS {a.POS:.3f}"
            for n, a in scene.axes.items()
        )
        raise AssertionError(
            f"condition not met within {timeout:g} s of simulated time ({states})"
        ) from None


def max_following_error(scene: Scene, axis: str) -> float:
    """The largest |following error| of ``axis`` in the scene's trace [user units]."""
    errors = scene.trace.column(axis, "following_error")
    if not errors:
        raise AssertionError(f"no trace of axis {axis}: was the scene made with trace_every=0?")
    return max(abs(e) for e in errors)


def physical_position(scene: Scene, axis: str) -> float:
    """Where the axis' joint really is, from the physics, in the axis' user units (mm, deg)."""
    return scene.joint_position(axis) * scene.scales[axis]


class ScanLog:
    """Records named values once per PLC scan: ``log = scans(done=lambda: move.Done)``, then run
    ``log.wrap(program)`` instead of ``program``; ``log["done"]`` is the list of values."""

    def __init__(self, **probes: Callable[[], Any]) -> None:
        self.probes = probes
        self.values: dict[str, list[Any]] = {name: [] for name in probes}

    def wrap(self, program: Callable[[], None]) -> Callable[[], None]:
        """``program`` followed by one sample of every probe."""

        def scan() -> None:
            program()
            for name, probe in self.probes.items():
                self.values[name].append(probe())

        return scan

    def __getitem__(self, name: str) -> list[Any]:
        return self.values[name]


def assert_pulsed_once(values: list[Any], name: str = "signal") -> int:
    """``values`` (one per scan) is TRUE in exactly one scan; returns that scan's index."""
    high = [i for i, v in enumerate(values) if v]
    if len(high) != 1:
        runs = len([i for i in high if i - 1 not in high])
        raise AssertionError(
            f"{name} was TRUE in {len(high)} scans ({runs} pulses), expected exactly one scan"
        )
    return high[0]


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--scene-plots",
        default="scene-plots",
        help="where a failing scenario test writes the plots of its scenes' traces",
    )


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Any:
    report = yield
    if report.when == "call":
        item.stash[_FAILED] = report.failed
    return report


_FAILED = pytest.StashKey[bool]()


@pytest.fixture
def scene(request: pytest.FixtureRequest) -> Iterator[Callable[..., Scene]]:
    """A factory of scenes: ``scene(name, **overrides)`` (see :func:`scenes.load`)."""
    made: list[Scene] = []

    def make(name: str, **overrides: Any) -> Scene:
        made.append(scenes.load(name, **overrides))
        return made[-1]

    yield make
    if request.node.stash.get(_FAILED, False):
        from scenes.plot import plot

        folder = Path(request.config.getoption("--scene-plots"))
        stem = re.sub(r"[^\w.-]+", "_", request.node.name)
        for k, s in enumerate(made):
            if s.trace.samples:
                suffix = f"_{k}" if len(made) > 1 else ""
                plot(s.trace, folder / f"{stem}{suffix}", title=request.node.nodeid)


@pytest.fixture
def scans() -> type[ScanLog]:
    """The :class:`ScanLog` class: ``log = scans(done=lambda: move.Done)``."""
    return ScanLog

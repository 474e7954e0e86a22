"""pytest plugin for scenario tests of PLC programs (installed with the package; pytest loads it).

Fixtures:

- ``scene``: a factory, ``scene("gantry", start={"X": 0.3})`` → :class:`scenes.Scene`. When the
  test fails, the trace of every scene it made is plotted (PNG and HTML) into the directory of
  ``--scene-plots`` (default ``scene-plots/``), named after the test (with the ``[plot]`` extra).
- ``scans``: a :class:`ScanLog` factory that records values once per PLC scan.
- ``circle``: the circle test of ISO 230-4, :func:`scenes.tools.circle.circle_test`:
  ``circle(scene("gantry"), plane="XY", radius=50.0, feed=1000.0)`` → its figures (G, mean
  radial deviation, reversal spikes, ellipse), from the encoders and from the joints.
- ``st_program``: a factory of IEC 61131-3 Structured Text programs for a scene,
  ``st_program("move.st", gantry, mapping={"Pohon.Ax1": "X"})`` → :class:`plc.st.STProgram`
  (a relative path is found beside the test's file); its variables read and write as
  attributes (``prog.step``, ``prog.Start = True``, ``prog.Head_X.Done``), ``gantry.run(prog)``
  scans it. :func:`load_st` does the same outside a test.

Helpers (plain functions, usable anywhere): :func:`run_until` (a program with a timeout in
simulated time), :func:`home` (power and home axes with the machine's homing recipes),
:func:`max_following_error` (over the whole trace, a time window, or the run of a command
watched with :func:`window`), :func:`assert_pulsed_once`, :func:`physical_position`. Faults are
injected with ``scene.faults`` (:mod:`mcl.faults`).

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

    def test_x_follows_within_0_1_mm_once_homed(scene):
        gantry = scene("gantry", start={"X": 0.3})
        home(gantry, "X")                         # REF + index, the machine's recipe
        X = gantry.axes["X"]
        move = mcl.MC_MoveAbsolute(Axis=X, Position=500.0, Velocity=300.0)
        moving = window(gantry, move)             # the samples while the move is Busy
        run_until(gantry, lambda: move(Execute=True), lambda: move.Done, timeout=5.0)
        assert max_following_error(gantry, "X", during=moving) < 0.1
"""

from __future__ import annotations

__all__ = [
    "ScanLog",
    "Window",
    "assert_pulsed_once",
    "circle",
    "home",
    "load_st",
    "max_following_error",
    "physical_position",
    "pytest_addoption",
    "pytest_runtest_makereport",
    "run_until",
    "scans",
    "scene",
    "st_program",
    "window",
]

import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

import mcl
import plc.st
import scenes
from mcl import extras
from plc.procedures import HomeAxis, Recipe
from scenes.scene import Scene
from scenes.tools.circle import CircleResult, circle_test


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


class Window:
    """The simulated time [s] during which a command ran: from the first servo cycle at which
    its ``Busy`` was TRUE to the first at which it was FALSE again (``end`` None while it still
    runs). Made by :func:`window`; only its first run counts."""

    def __init__(self, scene: mcl.Machine, block: object) -> None:
        self.block = block
        self.start: float | None = None
        self.end: float | None = None
        scene.runtime.observers.append(self._observe)

    def _observe(self, t: float) -> None:
        busy = bool(getattr(self.block, "Busy", False))
        if self.start is None:
            if busy:
                self.start = t
        elif self.end is None and not busy:
            self.end = t


def window(scene: mcl.Machine, block: object) -> Window:
    """Watch ``block`` (an FB with a ``Busy`` output, e.g. an MC_MoveAbsolute) from now on: the
    :class:`Window` of simulated time in which it ran, for :func:`max_following_error`. Make it
    before running the program."""
    return Window(scene, block)


def max_following_error(
    scene: Scene, axis: str, during: Window | tuple[float, float] | None = None
) -> float:
    """The largest |following error| of ``axis`` in the scene's trace [user units].

    Args:
        scene: the scene.
        axis: the axis' name.
        during: only the samples of this :class:`Window` (a command, see :func:`window`) or of
            ``(start, end)`` in simulated seconds, both ends included; None: the whole trace
            (homing included).

    Raises:
        AssertionError: no trace of that axis, a command that never ran, or a window with no
            samples (e.g. older than the trace keeps).
    """
    if axis not in scene.axes:
        raise AssertionError(f"no axis {axis!r}; axes: {sorted(scene.axes)}")
    errors = scene.trace.column(axis, "following_error")
    if not errors:
        raise AssertionError(f"no trace of axis {axis}: was the scene made with trace_every=0?")
    if during is None:
        return max(abs(e) for e in errors)
    if isinstance(during, Window):
        if during.start is None:
            raise AssertionError(f"the command {type(during.block).__name__} never ran (Busy)")
        start, end = during.start, during.end if during.end is not None else scene.time
    else:
        start, end = during
    times = scene.trace.column(axis, "t")
    inside = [abs(e) for t, e in zip(times, errors, strict=True) if start <= t <= end]
    if not inside:
        raise AssertionError(
            f"no trace samples of {axis} in [{start:g}, {end:g}] s; the trace holds "
            f"[{times[0]:g}, {times[-1]:g}] s"
        )
    return max(inside)


def home(scene: Scene, *axes: str, timeout: float = 60.0, settle: float = 0.2) -> float:
    """Power and home axes of the scene with their machine's homing recipes
    (:func:`scenes.homing`, :class:`plc.procedures.HomeAxis`), one after the other in the
    order given (default: every axis that has a recipe, in the machine's order). The axes stay
    powered, holding their recipes' set positions.

    Args:
        scene: the scene.
        axes: the axes to home.
        timeout: for each axis [s of simulated time].
        settle: how long each axis is held after its homing is Done, for the regulator to come
            to rest [s] (0: go on at once).

    Returns:
        The simulated seconds it took (the settling included).

    Raises:
        AssertionError: an axis without a recipe, or a homing that failed or did not finish
            (the message gives the axis, ErrorID and the axes' states).
    """
    recipes = scenes.homing(scene)
    unknown = [a for a in axes if a not in recipes]
    if unknown:
        raise AssertionError(f"no homing recipe for {unknown}; axes with one: {sorted(recipes)}")
    powers: list[mcl.MC_Power] = []
    took = 0.0
    for name in axes or tuple(recipes):
        took += _home_axis(scene, name, recipes[name], powers, timeout, settle)
    return took


def _home_axis(
    scene: Scene,
    name: str,
    recipe: Recipe,
    powers: list[mcl.MC_Power],
    timeout: float,
    settle: float,
) -> float:
    """Home one axis, keeping the axes of ``powers`` powered (its own MC_Power joins them)."""
    axis = scene.axes[name]
    power = mcl.MC_Power(Axis=axis)
    powers.append(power)
    procedure = HomeAxis(axis, recipe)

    def program() -> None:
        for p in powers:
            p(Enable=True)
        procedure(Execute=power.Status)

    took = run_until(scene, program, lambda: procedure.Done or procedure.Error, timeout)
    if procedure.Error:
        raise AssertionError(
            f"homing {name} failed: ErrorID {procedure.ErrorID}, {axis.state.name}, "
            f"AxErrorID {axis.AxErrorID}"
        )
    if settle > 0.0:
        took += scene.run(program, timeout=settle)
    return took


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
    if request.node.stash.get(_FAILED, False) and extras.installed("plot"):
        from scenes.tools.plot import plot

        folder = Path(request.config.getoption("--scene-plots"))
        stem = re.sub(r"[^\w.-]+", "_", request.node.name)
        reporter = request.config.pluginmanager.get_plugin("terminalreporter")
        for k, s in enumerate(made):
            if s.trace.samples:
                suffix = f"_{k}" if len(made) > 1 else ""
                png, page = plot(s.trace, folder / f"{stem}{suffix}", title=request.node.nodeid)
                if reporter is not None:  # said where the failure is read, not only written
                    reporter.write_line(f"{request.node.nodeid}: plots {png} and {page}")


def load_st(
    scene: mcl.Machine,
    path: str | Path,
    mapping: dict[str, str] | None = None,
    program: str | None = None,
) -> plc.st.STProgram:
    """The ST program ``path`` loaded for ``scene`` (:func:`plc.st.load`): AXIS_REFs bound by
    name or ``mapping``, I/O by address, timers on the scene's time.

    Raises:
        STError: the file is missing or has an error (``file:line:column: ...``).
    """
    return plc.st.load(path, scene, mapping=mapping, program=program)


@pytest.fixture
def st_program(request: pytest.FixtureRequest) -> Callable[..., plc.st.STProgram]:
    """A factory of ST programs: ``st_program(path, scene, mapping=None, program=None)``; a
    relative ``path`` is found beside the test's file (see :func:`load_st`)."""
    here = Path(request.path).parent

    def make(
        path: str | Path,
        scene: mcl.Machine,
        mapping: dict[str, str] | None = None,
        program: str | None = None,
    ) -> plc.st.STProgram:
        file = Path(path)
        return load_st(scene, file if file.is_absolute() else here / file, mapping, program)

    return make


@pytest.fixture
def scans() -> type[ScanLog]:
    """The :class:`ScanLog` class: ``log = scans(done=lambda: move.Done)``."""
    return ScanLog


@pytest.fixture
def circle() -> Callable[..., CircleResult]:
    """The circle test of ISO 230-4: ``circle(scene, plane, radius, feed, direction, center)``
    (:func:`scenes.tools.circle.circle_test`)."""
    return circle_test

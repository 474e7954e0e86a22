"""Helpers shared by the tests: servo constants, simulated machines, PLC programs.

The fixtures that use them are in ``conftest.py``; tests import what they need from here.
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Callable, Coroutine
from pathlib import Path
from typing import Any, TypeVar

import mcl

ROOT = Path(__file__).resolve().parent.parent
"""The repository's root folder."""

T = TypeVar("T")

CONSTANTS = dict(
    Kp=3.0,
    Ki=150.0,
    Kd=0.0,
    Ff=1.0,
    Kc=50.0,
    Vmax=500.0,
    LimPos=0.0,
    LimNeg=0.0,
    Ki1=0.0,
    Filter=2.0,
    Ka=0.0065,
)
"""Servo constants tuned for the default simulated axis (Vmax 500 mm/s at 10 V)."""

PLC = 0.002
"""PLC cycle of the simulated machines [s]."""

POS_TOL = 0.05
"""How close the actual position is to a target when the move reports Done [mm]."""


def configure(axis: mcl.Axis, **overrides: float) -> None:
    """Write servo constants through GT_SetConstant (one call)."""
    fb = mcl.GT_SetConstant()
    fb(Axis=axis, Execute=True, **{**CONSTANTS, **overrides})
    assert fb.Done, fb.ErrorID


def power_on(machine: mcl.Machine, axis: mcl.Axis, referenced: bool = True) -> mcl.MC_Power:
    """Power the axis through MC_Power and, if ``referenced``, confirm its coordinate with
    MC_FinishHoming (the coordinate stays, Ref is set); takes 10 ms of simulated time."""
    power, finish = mcl.MC_Power(), mcl.MC_FinishHoming()

    def program() -> None:
        power(Axis=axis, Enable=True)
        finish(Axis=axis, Execute=referenced and power.Status)

    machine.run(program, timeout=0.01)
    assert power.Status and axis.Ref == referenced
    return power


def make_machine(
    axes: str | dict[str, mcl.SimAxisParams] = "X",
    *,
    powered: bool = True,
    referenced: bool = True,
    **constants: float,
) -> mcl.SimMachine:
    """Simulated axes with their constants written (:data:`CONSTANTS` with ``constants``), one
    after the other powered and, if ``referenced``, referenced (:func:`power_on`).

    Args:
        axes: axis name → physical data; a string names one axis per letter, each with
            ``SimAxisParams(start=0.2)`` (travel −10..1010 mm, REF below 100 mm, user
            coordinate 0 at 200 mm).
        powered: power the axes (False: only the constants are written).
        referenced: confirm the coordinate with MC_FinishHoming (Ref set).
    """
    params = (
        {name: mcl.SimAxisParams(start=0.2) for name in axes} if isinstance(axes, str) else axes
    )
    machine = mcl.SimMachine(params)
    for axis in machine.axes.values():
        configure(axis, **constants)
        if powered:
            power_on(machine, axis, referenced)
    return machine


def fresh_axis(referenced: bool = True, **constants: float) -> tuple[mcl.SimMachine, mcl.Axis]:
    """A new machine like the ``machine``/``X`` fixtures (for tests that need several runs)."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    axis = machine.axes["X"]
    configure(axis, **constants)
    power_on(machine, axis, referenced)
    return machine, axis


def tick(machine: mcl.SimMachine, cycles: int = 1) -> None:
    """Let ``cycles`` PLC cycles pass without calling any block."""
    machine.run(timeout=PLC * cycles)


def scan(*calls: Callable[[], object]) -> Callable[[], None]:
    """A PLC program made of calls."""

    def program() -> None:
        for call in calls:
            call()

    return program


def reset(machine: mcl.Machine, axis: mcl.Axis, power: mcl.MC_Power | None = None) -> None:
    """MC_Reset (``power``, or a new MC_Power, held enabled) brings the axis back to StandStill
    without an error within 1 s."""
    power = power or mcl.MC_Power()
    fb = mcl.MC_Reset()
    machine.run(
        scan(lambda: power(Axis=axis, Enable=True), lambda: fb(Axis=axis, Execute=True)),
        until=lambda: fb.Done,
        timeout=1,
    )
    assert axis.state == mcl.AxisState.StandStill and axis.AxErrorID == 0


def in_velocity(machine: mcl.Machine, axis: mcl.Axis, velocity: float) -> mcl.MC_MoveVelocity:
    """MC_MoveVelocity at ``velocity`` [mm/s], called every scan until InVelocity (at most 2 s);
    returns the block."""
    fb = mcl.MC_MoveVelocity()
    machine.run(
        lambda: fb(Axis=axis, Execute=True, Velocity=velocity),
        until=lambda: fb.InVelocity,
        timeout=2.0,
    )
    return fb


def carriage_mm(machine: mcl.SimMachine, name: str = "X") -> float:
    """Where the simulated carriage of axis ``name`` really is: mm from its power-up position,
    which is the coordinate 0 of an axis referenced by :func:`power_on` (the physics, not the
    encoder or the axis' coordinate)."""
    sim = machine.sims[name]
    return (sim.x - sim.params.start) * 1000.0


def carriage_mm_s(machine: mcl.SimMachine, name: str = "X") -> float:
    """The simulated carriage's real velocity [mm/s]."""
    return machine.sims[name].v * 1000.0


def run_coroutine(coroutine: Coroutine[Any, Any, T]) -> T:
    """Run ``coroutine`` to its end in a thread of its own with an event loop of its own, and
    return its result (or raise its exception): works whether or not this thread already runs
    an event loop (Playwright's sync API keeps one running while it is started)."""
    result: list[T] = []
    error: list[BaseException] = []

    def target() -> None:
        try:
            result.append(asyncio.run(coroutine))
        except BaseException as exc:  # handed to the caller
            error.append(exc)

    thread = threading.Thread(target=target, name="test-event-loop")
    thread.start()
    thread.join()
    if error:
        raise error[0]
    return result[0]


def true_position(axis: mcl.Axis) -> float:
    """The coordinate [mm] of where the simulated carriage of ``axis`` really is: its travel
    since power-up, from the physics, plus the offset its coordinate was given (homing)."""
    sim = axis.io
    assert isinstance(sim, mcl.SimAxis), f"axis {axis.name} is not a simulated axis"
    return (sim.x - sim.params.start) * 1000.0 + axis.offset


def assert_at(axis: mcl.Axis, target: float, tol: float = POS_TOL) -> None:
    """The axis reads ``target`` [mm] within ``tol`` and its simulated carriage really is there
    (within ``tol`` and the count it is read with)."""
    assert abs(axis.POS - target) <= tol, f"{axis.name}: POS {axis.POS} mm, expected {target} mm"
    real = true_position(axis)
    count = axis.config.resolution
    assert abs(real - target) <= tol + count, (
        f"{axis.name}: the carriage at {real} mm, expected {target} mm"
    )

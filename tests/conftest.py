"""Shared fixtures: a powered, referenced simulated axis and a helper to run PLC programs."""

from __future__ import annotations

from collections.abc import Callable

import pytest

import mcl

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


def configure(axis: mcl.Axis, **overrides: float) -> None:
    """Write servo constants through GT_SetConstant (one call)."""
    fb = mcl.GT_SetConstant()
    fb(Axis=axis, Execute=True, **{**CONSTANTS, **overrides})
    assert fb.Done, fb.ErrorID


def power_on(machine: mcl.SimMachine, axis: mcl.Axis, referenced: bool = True) -> mcl.MC_Power:
    """Power the axis through MC_Power and (optionally) set Ref with MC_FinishHoming-equivalent
    MC_StepDirect semantics: the coordinate stays, Ref is set."""
    power = mcl.MC_Power()
    power(Axis=axis, Enable=True)
    machine.run(lambda: power(Axis=axis, Enable=True), timeout=0.01)
    assert power.Status
    if referenced:
        axis.Ref = True
    return power


@pytest.fixture
def machine() -> mcl.SimMachine:
    """One simulated axis "X" (travel −10..1010 mm, REF below 100 mm), constants written."""
    m = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    configure(m.axes["X"])
    return m


@pytest.fixture
def X(machine: mcl.SimMachine) -> mcl.Axis:
    """The powered, referenced axis of ``machine``."""
    axis = machine.axes["X"]
    power_on(machine, axis)
    return axis


def scan(*calls: Callable[[], None]) -> Callable[[], None]:
    """A PLC program made of calls."""

    def program() -> None:
        for call in calls:
            call()

    return program

"""Every input of every function block, given what a PLC program should never send — ints beyond
float range, strings, None, complex numbers, containers, NaN — gives an Error with an ErrorID or
is ignored; it never raises and never leaves a value that is not a number on the axis."""

from __future__ import annotations

import inspect
import math
from typing import Any

import pytest

import mcl
from mcl.fb import FunctionBlock, input_names
from tests.helpers import configure, power_on

BLOCKS = sorted(
    (c for c in vars(mcl).values() if inspect.isclass(c) and issubclass(c, FunctionBlock)),
    key=lambda c: c.__name__,
)
HOSTILE: list[Any] = [10**400, -(10**400), "abc", None, 1 + 2j, math.nan, [1.0], {"a": 1}]
TRIGGERS = ("Execute", "Enable")


def machine() -> tuple[mcl.SimMachine, dict[str, Any]]:
    """Three referenced, powered axes and an enabled group X+Y: the in-outs of every block."""
    m = mcl.SimMachine({n: mcl.SimAxisParams(start=0.3) for n in ("X", "Y", "Z")})
    for axis in m.axes.values():
        configure(axis)
        power_on(m, axis)
    group = mcl.AxesGroup("G")
    adds = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=m.axes[n]) for n in ("X", "Y")]
    enable = mcl.MC_GroupEnable(AxesGroup=group)

    def program() -> None:
        for add in adds:
            add(Execute=True)
        enable(Execute=all(a.Done for a in adds))

    m.run(program, until=lambda: enable.Done, timeout=0.1)
    refs = {"Axis": m.axes["Z"], "Master": m.axes["Y"], "Slave": m.axes["Z"], "AxesGroup": group}
    return m, refs


def finite_axes(m: mcl.SimMachine) -> bool:
    return all(
        math.isfinite(v)
        for a in m.axes.values()
        for v in (a.sp_pos, a.sp_vel, a.actual, a.volts, a.following_error)
    )


@pytest.mark.parametrize("block", BLOCKS, ids=lambda c: c.__name__)
def test_hostile_values_in_every_input_never_raise(block: type[FunctionBlock]):
    m, refs = machine()
    names = input_names(block)
    bound = {name: refs[name] for name in names if name in refs}
    inputs = [n for n in names if n not in refs and n not in TRIGGERS]
    trigger = next((t for t in TRIGGERS if t in names), None)
    for name in inputs:
        for value in HOSTILE:
            fb = block(**bound)
            calls = [{name: value}]
            if trigger is not None:
                calls = [{name: value, trigger: False}, {trigger: True}]
            for call in calls:
                fb(**call)
                m.run(timeout=0.004)
            error = getattr(fb, "Error", False)
            if error:
                assert getattr(fb, "ErrorID", 0), f"{block.__name__}.{name}={value!r}"
            assert finite_axes(m), f"{block.__name__}.{name}={value!r}"
            if trigger is not None:
                fb(**{trigger: False})
            m.run(timeout=0.004)

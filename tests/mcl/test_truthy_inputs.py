"""Values a user writes where the library takes a truth value: any value Python takes as true or
false works the same compiled and in pure Python (``make test`` runs this file in both modes)."""

from __future__ import annotations

import mcl
from mcl.faults import SwitchStuck
from tests.helpers import configure


def powered_machine(**params: object) -> tuple[mcl.SimMachine, mcl.MC_Power]:
    """One simulated axis, standing at 200 mm of travel, with MC_Power enabled for 10 ms."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2, **params)})  # type: ignore[arg-type]
    configure(machine.axes["X"])
    power = mcl.MC_Power(Axis=machine.axes["X"], Enable=True)
    machine.run(power, timeout=0.01)
    return machine, power


def test_run_until_an_error_code_stops_at_the_error():
    """``until=lambda: axis.AxErrorID``: an int, truthy once the axis has an error."""
    machine, power = powered_machine()
    X = machine.axes["X"]
    assert power.Status and X.AxErrorID == 0
    machine.faults.set("X", SwitchStuck("lim_pos", 1))  # an int level, as from a PLC I/O word
    took = machine.run(power, until=lambda: X.AxErrorID, timeout=1.0)
    assert X.AxErrorID == 2004  # LIM+ reached: the run stopped at that scan
    assert took < 0.01


def test_run_until_accepts_none_and_numbers_as_false():
    machine, power = powered_machine()
    calls: list[float] = []

    def condition() -> object:
        calls.append(machine.time)
        return None if len(calls) < 3 else 0.5

    machine.run(power, until=condition, timeout=1.0)
    assert len(calls) == 3  # None, None, then 0.5: the run ends at the third PLC scan


def test_an_encoder_only_axis_can_be_given_as_zero():
    machine, power = powered_machine(has_drive=0)
    assert power.Error and not power.Status  # an encoder-only axis cannot be powered
    assert machine.axes["X"].has_drive is False

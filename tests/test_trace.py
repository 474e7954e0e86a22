"""The trace recorder: what is recorded, decimation, CSV export."""

from __future__ import annotations

import csv

import pytest

import mcl
from mcl.trace import FIELDS, Trace
from tests.helpers import configure, power_on


def test_trace_records_every_servo_cycle_and_exports_csv(tmp_path):
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    configure(X)
    power_on(machine, X)
    trace = Trace(machine.axes, truth={"X": lambda: machine.sims["X"].x})
    machine.runtime.observers.append(trace)
    move = mcl.MC_MoveRelative()
    machine.run(
        lambda: move(Axis=X, Execute=True, Distance=20.0, Velocity=100.0),
        until=lambda: move.Done,
        timeout=2.0,
    )
    times = trace.column("X", "t")
    assert len(times) == pytest.approx(machine.time / 0.001, abs=12)
    assert times == sorted(times)
    model = trace.column("X", "model")
    assert model[-1] - model[0] == pytest.approx(20.0, abs=0.01)
    truth = trace.column("X", "truth")
    assert truth[-1] * 1000.0 == pytest.approx(trace.column("X", "actual")[-1] + 200.0, abs=0.002)
    path = trace.to_csv(tmp_path / "trace.csv")
    with path.open() as f:
        rows = list(csv.reader(f))
    assert rows[0] == [f"X.{field}" for field in FIELDS]
    assert len(rows) == len(times) + 1
    assert float(rows[-1][FIELDS.index("model")]) == pytest.approx(model[-1])


def test_trace_decimation_and_errors():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    trace = Trace(machine.axes, every=10)
    machine.runtime.observers.append(trace)
    machine.run(timeout=0.1)
    assert len(trace.rows["X"]) == 10
    with pytest.raises(KeyError, match="axes"):
        trace.column("Q", "t")
    with pytest.raises(KeyError, match="fields"):
        trace.column("X", "speed")
    with pytest.raises(ValueError, match="every"):
        Trace(machine.axes, every=0)
    trace.clear()
    assert trace.rows["X"] == []

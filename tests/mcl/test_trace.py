"""The trace recorder: what is recorded, decimation, CSV export."""

from __future__ import annotations

import csv
import itertools

import numpy as np
import pytest

import mcl
import scenes
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


def test_the_trace_keeps_a_bounded_window_of_the_latest_samples():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    trace = Trace(machine.axes, keep=100)
    machine.runtime.observers.append(trace)
    machine.run(timeout=1.0)  # 1000 servo cycles
    times = trace.column("X", "t")
    assert 100 <= len(times) < 200
    assert times[-1] == pytest.approx(machine.time - 0.001)
    assert all(b - a == pytest.approx(0.001) for a, b in itertools.pairwise(times))
    assert trace.samples == 1000
    assert trace.nbytes <= 200 * len(FIELDS) * 8 * 1.2
    memory = trace.nbytes
    machine.run(timeout=2.0)
    assert trace.nbytes <= max(memory, 200 * len(FIELDS) * 8) * 1.2


def test_a_streamed_trace_writes_every_sample_once_to_its_file(tmp_path):
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    configure(X)
    power_on(machine, X)
    everything = Trace(machine.axes, keep=10**6)
    streamed = Trace(machine.axes, keep=64, stream=tmp_path / "stream.csv")
    machine.runtime.observers += [everything, streamed]
    move = mcl.MC_MoveRelative(Axis=X, Distance=50.0, Velocity=100.0)
    machine.run(lambda: move(Execute=True), timeout=0.4)
    streamed.flush()  # a flush mid-run writes nothing twice
    machine.run(lambda: move(Execute=True), timeout=0.3)
    streamed.close()
    with (tmp_path / "stream.csv").open() as f:
        rows = list(csv.reader(f))
    assert rows[0] == [f"X.{field}" for field in FIELDS]
    assert len(rows) - 1 == everything.samples == 700
    expected = everything.rows["X"]
    for got, want in zip(rows[1:], expected, strict=True):
        assert [float(v) for v in got] == pytest.approx(list(want), nan_ok=True)
    assert len(streamed.column("X", "t")) < 128  # only the window stays in memory


def test_a_scene_keeps_the_stated_seconds_of_trace():
    scene = scenes.load("single_axis", trace_seconds=0.05)
    scene.run(timeout=0.5)
    times = scene.trace.column("X", "t")
    assert 0.05 - 1e-9 <= times[-1] - times[0] + 0.001 < 0.1 + 1e-9


def test_a_trace_streamed_as_numpy_records_loads_with_named_columns(tmp_path):
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    everything = Trace(machine.axes, keep=10**6)
    streamed = Trace(machine.axes, keep=50, stream=tmp_path / "trace.npy")
    machine.runtime.observers += [everything, streamed]
    machine.run(timeout=0.3)
    streamed.flush()  # complete after each flush
    assert len(np.load(tmp_path / "trace.npy")) == 300
    machine.run(timeout=0.2)
    streamed.close()
    data = np.load(tmp_path / "trace.npy")
    assert data.dtype.names == tuple(f"X.{field}" for field in FIELDS)
    assert len(data) == 500
    assert list(data["X.t"]) == everything.column("X", "t")
    assert list(data["X.actual"]) == everything.column("X", "actual")


def test_a_stream_needs_a_csv_or_npy_file(tmp_path):
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    with pytest.raises(ValueError, match=r"\.csv .* \.npy"):
        Trace(machine.axes, stream=tmp_path / "trace.parquet")


def test_the_window_never_holds_fewer_than_keep_samples_not_even_right_after_a_trim():
    """Checked after every servo cycle: the window holds the newest ``keep`` samples at least
    (all of them before that many were recorded), at most 2·keep, gap-free up to now, its
    signal column as long as its axis columns."""
    keep = 100
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    trace = Trace(machine.axes, keep=keep, signals={"now": lambda: machine.time})
    short: list[tuple[int, int]] = []  # (samples recorded, samples held) where too few were held

    def check(t: float) -> None:
        times = trace.column("X", "t")
        if not min(trace.samples, keep) <= len(times) <= 2 * keep or times[-1] != t:
            short.append((trace.samples, len(times)))
        if len(trace.signal("now")) != len(times):
            short.append((trace.samples, -1))

    machine.runtime.observers += [trace, check]
    machine.run(timeout=0.5)  # 500 servo cycles: trims at 200, 300, 400 and 500 samples
    assert trace.samples == 500
    assert not short, f"(recorded, held) {short[:5]}"

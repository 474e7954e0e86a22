"""Touch probe: MC_TouchProbe records the position at a TP edge, after the sensor's delay;
MC_AbortTrigger cancels it. Measured on a simulated axis whose marks sit at known positions."""

from __future__ import annotations

import pytest

import mcl
from tests.helpers import configure, power_on

MARK = 0.300
"""The first mark [m] on the axis' own coordinate; the axis starts at 0.2 m (POS 0)."""
PITCH = 0.050


WIDTH = 0.002
"""Width of a mark [m]: moving down, TP rises at a mark's upper end."""


def probe_axis(delay: float = 0.0, start: float = 0.2) -> tuple[mcl.SimMachine, mcl.Axis]:
    """The powered axis, POS 0 at ``start`` [m], with marks from ``MARK`` every ``PITCH``."""
    params = mcl.SimAxisParams(
        start=start, probe=mcl.Marks(first=MARK, pitch=PITCH, width=WIDTH), probe_delay=delay
    )
    machine = mcl.SimMachine({"X": params})
    X = machine.axes["X"]
    configure(X)
    power_on(machine, X)
    return machine, X


def run_at(
    machine: mcl.SimMachine,
    X: mcl.Axis,
    probe: mcl.MC_TouchProbe,
    direction: mcl.MC_Direction = mcl.MC_Direction.MC_Positive,
    **inputs: object,
):
    """Move at 200 mm/s in ``direction`` with the probe armed until it is Done or in Error."""
    move = mcl.MC_MoveVelocity()

    def program() -> None:
        move(Axis=X, Execute=True, Velocity=200.0, Acceleration=5000.0, Direction=direction)
        probe(Axis=X, **inputs)

    machine.run(program, until=lambda: probe.Done or probe.Error, timeout=2.0)


def test_the_first_edge_after_execute_records_the_position_at_the_mark():
    machine, X = probe_axis()
    probe = mcl.MC_TouchProbe()
    run_at(machine, X, probe, Execute=True)
    assert probe.Done and not probe.Busy
    # the coordinate reads 0 at the start (0.2 m): the mark lies at 100 mm
    assert probe.RecordedPosition == pytest.approx((MARK - 0.2) * 1000.0, abs=0.0015)
    probe(Execute=False)
    assert not probe.Done  # one latch per Execute edge


def test_the_sensor_delay_shifts_the_latch_by_speed_times_delay():
    machine, X = probe_axis(delay=0.001)
    probe = mcl.MC_TouchProbe()
    run_at(machine, X, probe, Execute=True)
    speed = X.VEL
    assert speed == pytest.approx(200.0, rel=0.01)
    assert probe.RecordedPosition == pytest.approx(100.0 + speed * 0.001, abs=0.01)


def test_window_only_skips_marks_outside_the_window():
    machine, X = probe_axis()
    probe = mcl.MC_TouchProbe()
    run_at(
        machine, X, probe, Execute=True, WindowOnly=True, FirstPosition=140.0, LastPosition=160.0
    )
    assert probe.Done
    assert probe.RecordedPosition == pytest.approx(150.0, abs=0.0015)  # the second mark


def test_window_only_skips_marks_above_the_window():
    """Moving down from 0.42 m over the marks at 0.40, 0.35 and 0.30 m with the window −100 …
    −50 mm: the first mark met lies above LastPosition and is skipped; the next one, at 0.35 m,
    is recorded where its edge physically lies."""
    start = 0.42
    machine, X = probe_axis(start=start)
    probe = mcl.MC_TouchProbe()
    window = dict(WindowOnly=True, FirstPosition=-100.0, LastPosition=-50.0)
    run_at(machine, X, probe, mcl.MC_Direction.MC_Negative, Execute=True, **window)
    assert probe.Done, probe.ErrorID
    edge = MARK + PITCH + WIDTH  # the mark at 0.35 m, met from above
    assert probe.RecordedPosition == pytest.approx((edge - start) * 1000.0, abs=0.0015)
    assert machine.sims["X"].x < edge, "recorded on the way down, past the edge"


def test_abort_trigger_cancels_a_waiting_probe():
    _, X = probe_axis()
    probe, abort = mcl.MC_TouchProbe(), mcl.MC_AbortTrigger()
    probe(Axis=X, Execute=True)
    assert probe.Busy
    abort(Axis=X, Execute=True)
    probe(Execute=True)
    assert abort.Done and probe.CommandAborted and not probe.Busy and not probe.Done


@pytest.mark.parametrize(
    "inputs", [{"TriggerInput": 1}, {"WindowOnly": True, "FirstPosition": 5.0, "LastPosition": 1.0}]
)
def test_bad_inputs_give_eparam_and_arm_nothing(inputs: dict[str, object]):
    _, X = probe_axis()
    probe = mcl.MC_TouchProbe()
    probe(Axis=X, Execute=True, **inputs)
    assert probe.Error and probe.ErrorID == mcl.ErrorID.EParam
    assert X.probe.position is None and X.state == mcl.AxisState.StandStill


def test_marks_report_their_rising_edges_exactly():
    marks = mcl.Marks(first=1.0, pitch=0.5, width=0.1, errors=(0.0, 0.02))
    assert marks.rising(0.9, 1.1) == pytest.approx(0.5)
    assert marks.rising(1.45, 1.6) == pytest.approx((1.52 - 1.45) / 0.15)  # print error 20 mm
    assert marks.rising(1.2, 1.3) is None
    assert marks.rising(1.15, 1.05) == pytest.approx(0.5)  # moving down: rises at the mark's end
    assert marks.level(1.05) and not marks.level(1.2)
    with pytest.raises(ValueError, match="pitch"):
        mcl.Marks(first=0.0, pitch=0.1, width=0.2)


def test_a_mark_printed_early_is_seen_as_every_other():
    """A mark displaced below its place (a negative print error) rises and is high like any
    other: between two samples that both lie below its place, and on the level."""
    marks = mcl.Marks(first=1.0, pitch=0.5, width=0.004, errors=(0.0, -0.0002))
    assert marks.rising(1.4990, 1.4999) == pytest.approx((1.4998 - 1.4990) / 0.0009)
    assert marks.level(1.4999) and not marks.level(1.4997)
    assert marks.rising(1.4990, 1.4997) is None

"""Recordings longer than the fine ring: the scope shows up to ten minutes from the recorder's
second buffer (each channel's minimum and maximum of every 0.1 s), no peak lost, the memory
bounded."""

from __future__ import annotations

import math
from contextlib import nullcontext
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
import viser

from viewer.scope.capture import Recording, Window
from viewer.scope.panel import RECORDING_LENGTHS, PageScope
from viewer.scope.readout import recording_csv
from viewer.serving.security import BoundedLog, GuiGate
from viewer.sim.recorder import Extremes, Ring
from viewer.sim.session import HISTORY_SAMPLE, LONG_BUCKET, LONG_SECONDS, SCOPE_SECONDS, Session
from viewer.sim.snapshot import Channel, Snapshot

DT = HISTORY_SAMPLE
"""Sample period [s]."""

EVERY = round(LONG_BUCKET / DT)
"""Samples per bucket of the long buffer."""

SPIKE_AT = 420.0
"""Time [s] of the one-sample spike: five minutes before the end of the recording."""

CHANNELS = (Channel("X following error", "mm", False), Channel("X error", "", True))


def buffers() -> tuple[Ring, Extremes]:
    """The recorder's two buffers as the session makes them, for two channels."""
    fine = Ring(len(CHANNELS), round(SCOPE_SECONDS / DT) + 1)
    return fine, Extremes(fine, EVERY, round(LONG_SECONDS / LONG_BUCKET))


def feed(fine: Ring, extremes: Extremes, start: int, end: int) -> None:
    """Samples ``start`` to ``end`` (exclusive): a small sine, and one sample at
    :data:`SPIKE_AT` where the following error jumps to +5 mm and the error flag rises."""
    spike = round(SPIKE_AT / DT)
    for k in range(start, end):
        t = k * DT
        value = 1e-3 * math.sin(2.0 * math.pi * t)
        fine.append(t, [5.0 if k == spike else value, float(k == spike)])
        extremes.sampled()


def test_a_one_sample_spike_five_minutes_ago_is_in_a_ten_minute_recording() -> None:
    fine, extremes = buffers()
    end = round(12 * 60.0 / DT) + 17  # twelve minutes and 17 samples of a bucket under way
    feed(fine, extremes, 0, end)
    now = fine.latest
    t, values, bucket = extremes.samples(now - 600.0, now, [0, 1])
    assert fine.oldest > SPIKE_AT + 200.0  # the fine ring dropped the spike long ago
    assert bucket == pytest.approx(LONG_BUCKET)
    assert t[0] == pytest.approx(now - 600.0, abs=LONG_BUCKET)
    assert t[-1] == now and np.all(np.diff(t) >= 0.0)
    assert t.size <= 2 * LONG_SECONDS / LONG_BUCKET + EVERY
    at = np.flatnonzero(values[0] == 5.0)
    assert at.size == 1 and abs(t[at[0]] - SPIKE_AT) <= LONG_BUCKET  # its maximum kept
    assert np.flatnonzero(values[1] == 1.0).tolist() == at.tolist()  # the flag's one cycle
    assert values[0].min() == pytest.approx(-1e-3, rel=1e-3)  # the minimum kept, too
    assert np.all(np.diff(t[-17:]) == pytest.approx(DT))  # the newest samples as recorded
    assert t[-18] - t[-19] == pytest.approx((EVERY - 1) * DT)  # the last complete bucket


def test_a_recording_the_fine_ring_holds_is_every_sample() -> None:
    fine, extremes = buffers()
    feed(fine, extremes, 0, round(90.0 / DT))
    now = fine.latest
    t, values, bucket = extremes.samples(now - 60.0, now, [1])
    assert bucket == 0.0 and t.size >= round(60.0 / DT) and values.shape == (1, t.size)
    assert not values.any()  # the flag (its one-sample spike was at 7 min)
    assert np.all(np.diff(t) == pytest.approx(DT))
    fine, extremes = buffers()
    feed(fine, extremes, 0, round(30.0 / DT))  # the ring not full yet: all of it, as recorded
    assert extremes.samples(-570.0, 30.0, [0])[2] == 0.0


def test_the_memory_stays_bounded() -> None:
    fine, extremes = buffers()
    feed(fine, extremes, 0, round(11 * 60.0 / DT))
    arrays = (fine._t, fine._values, extremes.ring._t, extremes.ring._values)
    sizes = [a.nbytes for a in arrays]
    feed(fine, extremes, round(11 * 60.0 / DT), round(13 * 60.0 / DT))
    assert [a.nbytes for a in (fine._t, fine._values, extremes.ring._t, extremes.ring._values)] == (
        sizes
    )
    assert extremes.ring.latest - extremes.ring.oldest <= LONG_SECONDS  # ten minutes kept
    assert extremes.ring.latest - extremes.ring.oldest >= LONG_SECONDS - 2 * LONG_BUCKET
    megabytes_per_channel = sum(sizes) / 1e6 / len(CHANNELS)
    assert megabytes_per_channel < 1.0  # 60 s every 2 ms and 10 min of extremes


@pytest.fixture
def gate(server: viser.ViserServer) -> GuiGate:
    return GuiGate(server, lambda client_id: False, lambda *a: None, log=BoundedLog())


def test_the_scope_shows_ten_minutes_with_the_spike_and_says_the_resolution(
    server: viser.ViserServer, gate: GuiGate
) -> None:
    """The page is sent the spike of five minutes ago; the status line and the CSV export say
    that the samples are each 0.1 s' minimum and maximum."""
    fine, extremes = buffers()
    recorder = SimpleNamespace(
        channels=CHANNELS, ring=fine, samples=extremes.samples, oldest=-math.inf
    )
    snapshot = SimpleNamespace(channels=CHANNELS, axes={"X": None}, scene="single_axis", signals=())
    scope = PageScope(
        server.gui,
        gate,
        cast(Session, SimpleNamespace(recorder=recorder)),
        cast(Snapshot, snapshot),
        nullcontext,
    )
    assert RECORDING_LENGTHS["10 min"] == 600.0
    scope.show_channels(["X following error", "X error"])
    scope._length.value = "10 min"  # type: ignore[misc]
    scope._set_length()
    feed(fine, extremes, 0, round(12 * 60.0 / DT))
    scope.update()
    recording = scope.recording
    assert recording.window.end - recording.window.start == 600.0
    assert recording.bucket == pytest.approx(LONG_BUCKET)
    x, error, flag = (np.asarray(row) for row in scope.plot.data[:3])
    assert np.nanmax(error) == pytest.approx(5000.0)  # 5 mm in µm, in what the page draws
    assert x[np.nanargmax(error)] == pytest.approx(SPIKE_AT - recording.window.origin, abs=1.0)
    assert np.nanmax(flag) == 1.0
    assert "min and max of every 0.1 s" in scope.status
    assert recording_csv(recording).startswith("t [s] (min and max of every 0.1 s),")
    kept = scope.history.add(recording)
    assert kept.bucket == recording.bucket and kept.resolution == recording.resolution


def test_a_short_recording_says_it_is_every_sample() -> None:
    t = np.arange(0.0, 1.0, DT)
    window = Window(0.0, float(t[-1]), 0.0, None, True, "")
    recording = Recording(0, ("a",), (), t, np.zeros((1, t.size)), window)
    assert recording.resolution == "every 2 ms"
    assert Recording(0, (), (), t[:1], np.zeros((0, 1)), window).resolution == ""

"""The page scope without a browser: its pure parts (units, triggers, pre-trigger, cursors,
decimation, history) on hand-made samples, then the scope of a page on the simulated gantry
(a 400 mm/s move of X, its following error in µm, a threshold trigger, two recordings overlaid,
two pages' scopes independent of each other)."""

from __future__ import annotations

import dataclasses
import math
import time
from contextlib import nullcontext
from html.parser import HTMLParser
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
import viser

from plc.commissioning.step_test import STEP_WINDOW
from plc.operator.hmi import Move
from tests.viewer.test_overlays import Page, choose
from tests.viewer.test_session import FakeClock, run, wait_for
from viewer.pages.app import ViewerApp
from viewer.pages.layout import Page as ViewerPage
from viewer.pages.layout import Pages
from viewer.scope.capture import (
    FREE_RUN,
    Acquisition,
    History,
    Recording,
    Trigger,
    Window,
    error_trigger,
    first_crossing,
    recording_of,
    threshold_trigger,
)
from viewer.scope.panel import FREEZE, RUN, SINGLE, PageScope, plot_rows
from viewer.scope.readout import (
    MAX_POINTS,
    aligned,
    decimate,
    readout,
    readout_html,
    recording_csv,
)
from viewer.scope.units import auto_range, display_of, format_value, settled_range
from viewer.serving.security import BoundedLog, GuiGate
from viewer.sim.recorder import Ring
from viewer.sim.session import HISTORY_SAMPLE, SCOPE_SECONDS, Session
from viewer.sim.snapshot import Channel

DT = 0.002
"""Sample period [s] of the hand-made rings."""


def sine_ring(seconds: float = 4.0, frequency: float = 1.0) -> Ring:
    """A ring of two channels sampled every :data:`DT`: a sine of amplitude 10 and a flag that
    goes to 1 at t = 1.5 s."""
    n = round(seconds / DT) + 1
    ring = Ring(2, n)
    for k in range(n):
        t = k * DT
        ring.append(t, [10.0 * math.sin(2 * math.pi * frequency * t), float(t >= 1.5)])
    return ring


CHANNELS = (Channel("X position", "mm", False), Channel("X error", "", True))


# ------------------------------------------------------------------------------- units


def test_each_channel_is_shown_in_an_engineers_unit() -> None:
    fe = display_of(Channel("X following error", "mm", False))
    assert (fe.unit, fe.to_display(0.012)) == ("µm", pytest.approx(12.0))
    assert display_of(Channel("knife following error", "m", False)).factor == 1e6
    assert display_of(Channel("drag", "N", False)).to_display(2500.0) == pytest.approx(2.5)
    assert display_of(Channel("drag", "N", False)).unit == "kN"
    assert display_of(Channel("pressure_A", "bar", False)).unit == "bar"
    assert display_of(Channel("X command", "V", False)).unit == "V"
    assert display_of(Channel("X position", "mm", False)).unit == "mm"
    assert display_of(Channel("X LIM+", "", True)).unit == "0/1"


def test_an_auto_range_never_zooms_onto_a_single_dac_step() -> None:
    volts = display_of(Channel("X command", "V", False))
    low, high = auto_range(volts, np.array([1.0, 1.0 + 1e-4, 1.0]))
    assert high - low >= 0.05 and low <= 1.0 and high >= 1.0001
    fe = display_of(Channel("X following error", "mm", False))
    low, high = auto_range(fe, np.array([0.2, 0.3]))  # µm
    assert high - low >= 1.0
    low, high = auto_range(fe, np.array([-40.0, 25.0, math.nan]))
    assert low <= -40.0 and high >= 25.0 and high - low < 80.0


def test_an_auto_range_stays_while_the_traces_fit_it() -> None:
    assert settled_range(None, (0.0, 1.0)) == (0.0, 1.0)
    assert settled_range((0.0, 1.0), (0.1, 0.9)) == (0.0, 1.0)  # fits: no redraw
    assert settled_range((0.0, 1.0), (0.1, 1.2)) == (0.1, 1.2)  # grew out of it
    assert settled_range((0.0, 1.0), (0.4, 0.45)) == (0.4, 0.45)  # too small in it


# ------------------------------------------------------------------------------- triggers


def test_a_threshold_trigger_is_the_first_sample_past_the_level() -> None:
    t = np.linspace(0.0, 5 * DT, 6)
    v = np.array([0.0, 1.0, 2.0, 3.0, 2.0, 1.0])
    assert first_crossing(t, v, 2.0, True, -math.inf) == pytest.approx(2 * DT)
    assert first_crossing(t, v, 2.5, False, -math.inf) == pytest.approx(4 * DT)
    assert first_crossing(t, v, 2.0, True, after=3 * DT) is None  # before arming
    assert first_crossing(t, v, 5.0, True, -math.inf) is None


def test_a_triggered_recording_has_its_pre_trigger_and_freezes_when_single() -> None:
    ring = sine_ring()
    acquisition = Acquisition(length=0.5, pre=0.2)
    acquisition.trigger = threshold_trigger(CHANNELS, "X position", 5.0, True)
    acquisition.run(0.6, single=True)  # after the first crossing (t ≈ 0.083 s)
    window, completed = acquisition.poll(ring, 4.0)
    crossing = 1.0 + math.asin(0.5) / (2 * math.pi)  # the second period's crossing of 5
    assert completed and not acquisition.running
    assert window.trigger_at is not None
    assert 0.0 <= window.trigger_at - crossing < DT  # the first sample past the level
    assert window.start == pytest.approx(window.trigger_at - 0.1)
    assert window.end - window.start == pytest.approx(0.5)
    assert acquisition.poll(ring, 5.0) == (window, False)  # frozen


def test_a_recording_under_way_shows_its_progress_and_a_trigger_waits_armed() -> None:
    ring = sine_ring(seconds=1.0)
    acquisition = Acquisition(length=0.5, pre=0.5)
    acquisition.trigger = error_trigger(CHANNELS)
    acquisition.run(0.0)
    window, completed = acquisition.poll(ring, 1.0)  # the flag rises only at 1.5 s
    assert not completed and window.status.startswith("armed")
    ring = sine_ring(seconds=1.6)
    window, completed = acquisition.poll(ring, 1.6)
    assert not completed and "recording" in window.status
    assert window.trigger_at == pytest.approx(1.5)
    assert window.start == pytest.approx(1.25) and window.end == pytest.approx(1.6)


def test_run_rearms_after_each_recording_and_free_run_rolls() -> None:
    ring = sine_ring()
    acquisition = Acquisition(length=0.3, pre=0.0)
    acquisition.trigger = threshold_trigger(CHANNELS, "X position", 0.0, True)
    acquisition.run(0.5)
    first, completed = acquisition.poll(ring, 4.0)
    assert completed and acquisition.running
    assert first.trigger_at == pytest.approx(1.0, abs=1.5 * DT)  # the first rising zero
    second, completed = acquisition.poll(ring, 4.0)
    assert completed and second.trigger_at == pytest.approx(2.0, abs=1.5 * DT)  # the next
    free = Acquisition(length=1.0)
    window, completed = free.poll(ring, 4.0)
    assert not completed and (window.start, window.end) == (3.0, 4.0)
    single = Acquisition(length=1.0)
    single.run(2.0, single=True)  # free run, single: the next second
    window, completed = single.poll(ring, 4.0)
    assert completed and (window.start, window.end) == (2.0, 3.0)


# ------------------------------------------------------------------------------- recordings


def recorded(ring: Ring, start: float, end: float, origin: float) -> Recording:
    window = Window(start, end, origin, origin, True, "")
    displays = [display_of(c) for c in CHANNELS]
    return recording_of(ring, window, [0, 1], [c.name for c in CHANNELS], displays)


def test_the_cursors_read_each_channel_and_find_the_peak() -> None:
    recording = recorded(sine_ring(), 0.0, 1.0, 0.0)
    peak = recording.peak("X position")
    assert peak is not None and abs(peak - 0.25) <= DT / 2  # the sine's maximum
    r = readout(recording, peak, 0.75)
    assert r.at_a[0] == pytest.approx(np.max(recording.values[0]))
    assert r.at_b[0] == pytest.approx(-10.0, abs=1e-3)
    assert r.dt == pytest.approx(0.5, abs=DT) and r.rate == pytest.approx(2.0, rel=0.01)
    assert recording.peak("not a channel") is None


class _Table(HTMLParser):
    """The read-out as a page shows it: the table's rows of cells (text, tag and style) and
    the line under it, its parts that never break inside."""

    def __init__(self) -> None:
        super().__init__()
        self.rows: list[list[tuple[str, str, dict[str, str]]]] = []
        self.parts: list[str] = []
        self.stray = ""
        """Text outside the cells and the parts (only the separators between parts)."""
        self._cell: tuple[str, dict[str, str]] | None = None
        self._text = ""
        self._part = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell, self._text = (tag, {k: v or "" for k, v in attrs}), ""
        elif tag == "span" and ("style", "white-space:nowrap") in attrs:
            self._part, self._text = True, ""

    def handle_data(self, data: str) -> None:
        if self._cell is None and not self._part:
            self.stray += data
        self._text += data

    def handle_endtag(self, tag: str) -> None:
        if tag in ("td", "th") and self._cell is not None:
            self.rows[-1].append((self._text, *self._cell))
            self._cell = None
        elif tag == "span" and self._part:
            self.parts.append(self._text)
            self._part = False


def test_the_readout_reads_each_channel_under_its_name_in_four_columns() -> None:
    """Each channel's name and unit on a row of its own across the table, then its last value
    and its values at A, at B and B − A right-aligned in monospace that never wraps; under the
    table A, B, Δt [ms] and 1/Δt, each part whole."""
    recording = recorded(sine_ring(), 0.0, 1.0, 0.0)
    r = readout(recording, 0.25, 0.55, titles={"X position": "carriage X"})
    assert np.array_equal(r.last, recording.values[:, -1])
    table = _Table()
    table.feed(readout_html(r))
    assert table.stray.replace(",", "").strip() == ""
    header, *rows = table.rows
    assert [(text, tag) for text, tag, _ in header] == [
        ("last", "th"),
        ("A", "th"),
        ("B", "th"),
        ("B−A", "th"),
    ]
    assert len(rows) == 2 * len(CHANNELS)
    for k, (name_row, value_row) in enumerate(zip(rows[::2], rows[1::2], strict=True)):
        ((name, tag, attrs),) = name_row
        assert (name, tag, attrs["colspan"]) == (r.headers[k], "td", "4")
        assert "overflow-wrap:anywhere" in attrs["style"]
        expected = (r.last[k], r.at_a[k], r.at_b[k], r.at_b[k] - r.at_a[k])
        shown = [text for text, _, _ in value_row]
        assert shown == [format_value(v, r.displays[k].resolution) for v in expected]
        for _, tag, attrs in value_row:
            assert tag == "td" and "white-space:nowrap" in attrs["style"]
            assert "text-align:right" in attrs["style"] and "monospace" in attrs["style"]
    assert [row[0][0] for row in rows[::2]] == ["carriage X [mm]", "X error [0/1]"]
    assert table.parts == ["A = 0.2500 s", "B = 0.5500 s", "Δt = 300.000 ms", "1/Δt = 3.333 Hz"]


def test_the_readout_of_an_empty_recording_has_no_last_value() -> None:
    """A recording without samples yet: every channel's last value is not a number (shown as
    none), one per channel."""
    recording = recorded(sine_ring(), 0.0, 1.0, 0.0)
    empty = dataclasses.replace(recording, t=recording.t[:0], values=recording.values[:, :0])
    r = readout(empty, 0.25, 0.75)
    assert r.last.shape == (len(CHANNELS),) and np.isnan(r.last).all()


def test_decimation_keeps_every_peak_and_bounds_the_points() -> None:
    n = 30_001
    x = np.linspace(0.0, (n - 1) * DT, n)
    rows = np.vstack([np.sin(x), np.zeros(n)])
    rows[1, 12_345] = 7.0  # a one-sample spike
    rows[0, 100] = math.nan
    xs, values = decimate(x, rows)
    assert xs.size <= MAX_POINTS and values.shape == (2, xs.size)
    assert np.nanmax(values[1]) == 7.0
    assert np.nanmax(values[0]) == pytest.approx(np.nanmax(rows[0]))
    assert np.all(np.diff(xs) >= 0.0)
    short = decimate(x[:100], rows[:, :100])
    assert short[0].size == 100


def test_an_overlay_is_aligned_at_its_trigger_and_exported_with_units() -> None:
    ring = sine_ring()
    live = recorded(ring, 1.9, 2.4, 2.0)
    earlier = recorded(ring, 0.9, 1.2, 1.0)  # one period before: the same sine, shorter
    rows = aligned(live, earlier)
    inside = np.isfinite(rows[0])
    assert np.allclose(rows[0][inside], live.values[0][inside], atol=1e-9)
    assert np.isnan(rows[0][live.x > 0.2 + 1e-9]).all()  # beyond the overlay's end
    history = History(length=2)
    for recording in (earlier, live, live):
        history.add(recording)
    assert [r.number for r in history.recordings] == [2, 3]
    shown = history.recordings[0]
    assert history.find(shown.label) is shown
    text = recording_csv(live, shown)
    header, *lines = text.splitlines()
    assert header == (
        "t [s] (every 2 ms),X position [mm],X error [0/1],X position [mm] (#2),X error [0/1] (#2)"
    )
    assert len(lines) == live.t.size


# ------------------------------------------------------------------------------- the page


@pytest.fixture
def gate(server: viser.ViserServer) -> GuiGate:
    return GuiGate(server, lambda client_id: False, lambda *a: None, log=BoundedLog())


@pytest.fixture
def gantry() -> tuple[Session, FakeClock]:
    clock = FakeClock()
    return Session("gantry", clock=clock), clock


def scope_of(server: viser.ViserServer, gate: GuiGate, session: Session) -> PageScope:
    return PageScope(server.gui, gate, session, session.snapshot, nullcontext)


def test_the_recorder_samples_often_enough_and_holds_the_longest_recording(
    gantry: tuple[Session, FakeClock],
) -> None:
    session, clock = gantry
    run(session, clock, 0.2)
    t, _ = session.recorder.series()
    assert np.max(np.diff(t)) <= 0.002 + 1e-9 and HISTORY_SAMPLE <= 0.002
    assert session.recorder.ring.length * np.median(np.diff(t)) >= SCOPE_SECONDS


def test_the_peak_following_error_of_a_400_mm_s_move_read_with_the_cursor(
    server: viser.ViserServer, gate: GuiGate, gantry: tuple[Session, FakeClock]
) -> None:
    session, clock = gantry
    scope = scope_of(server, gate, session)
    assert scope.channels[0] == "X following error"
    session.requests("X").set_power(True)
    run(session, clock, 0.3)
    start = session.snapshot.time
    scope.capture(["X following error", "X velocity"], start, 1.5, pre=0.1)
    session.requests("X").move(Move("relative", 200.0, 400.0, 4000.0))
    fe = []  # the axis' own following error, every PLC cycle [mm]
    for _ in range(1500):
        session.advance(1)
        fe.append(session.scene.axes["X"].following_error)
    scope.update()
    recording = scope.recording
    assert recording.window.complete and recording.headers()[0] == "X following error [µm]"
    assert scope.history.recordings[-1].window == recording.window
    assert max(abs(v) for v in recording.values[1]) == pytest.approx(400.0, rel=0.02)
    at = scope.cursor_to_peak()
    assert at is not None
    peak = readout(recording, at, at).at_a[0]
    assert abs(peak) == pytest.approx(np.max(np.abs(recording.values[0])), abs=1e-9)
    assert abs(abs(peak) - 1e3 * max(abs(v) for v in fe)) < 1.0  # µm
    assert abs(peak) > 1.0  # a following error worth reading (µm)
    _, rows = plot_rows(recording, None, scope.cursors, scope.peak_slot)
    assert np.nanmax(np.abs(rows[-2])) == pytest.approx(abs(peak))  # marker A on the peak
    low, high = scope.ranges()[0]
    assert low <= np.min(recording.values[0]) and high >= np.max(recording.values[0])


def test_a_threshold_trigger_on_x_position_catches_the_crossing_within_one_sample(
    server: viser.ViserServer, gate: GuiGate, gantry: tuple[Session, FakeClock]
) -> None:
    session, clock = gantry
    scope = scope_of(server, gate, session)
    session.requests("X").set_power(True)
    run(session, clock, 0.3)
    x0 = session.snapshot.axes["X"].position
    scope._source.value = "X position"  # type: ignore[misc]
    scope._level.value = x0 + 50.0
    scope._length.value = "0.5 s"  # type: ignore[misc]
    scope._trigger.value = "threshold"  # type: ignore[misc]
    scope._act(SINGLE)
    session.requests("X").move(Move("relative", 100.0, 400.0, 4000.0))
    level = x0 + 50.0
    crossed = math.inf  # the physics: the first PLC cycle with X past the level
    for _ in range(1000):
        session.advance(1)
        x = session.scene.axes["X"].POS
        if x >= level:
            crossed = min(crossed, session.scene.runtime.time)
    scope.update()
    window = scope.recording.window
    assert window.complete and window.trigger_at is not None
    t, values = session.recorder.series()
    names = [c.name for c in session.recorder.channels]
    position = values[names.index("X position")]
    first = t[np.flatnonzero(position >= x0 + 50.0)[0]]
    assert window.trigger_at == first  # the first recorder sample past the level
    assert 0.0 <= window.trigger_at - crossed < HISTORY_SAMPLE  # within one sample
    assert window.start == pytest.approx(first - 0.05)  # 10 % pre-trigger


def test_two_recordings_overlay_and_a_freeze_enters_the_history(
    server: viser.ViserServer, gate: GuiGate, gantry: tuple[Session, FakeClock]
) -> None:
    session, clock = gantry
    scope = scope_of(server, gate, session)
    session.requests("X").set_power(True)
    run(session, clock, 0.3)
    for distance in (50.0, -50.0):
        scope.capture(["X following error", "X position"], session.snapshot.time, 0.5)
        session.requests("X").move(Move("relative", distance, 400.0, 4000.0))
        run(session, clock, 0.6)
        scope.update()
    first, _ = scope.history.recordings
    scope.choose_overlay(first.number)
    scope.update()
    assert len(scope.plot.series) == 1 + 2 + 2 + 2  # x, live, overlay (dashed), cursors
    assert scope.plot.series[3]["dash"] == (6, 4)
    overlay = np.asarray(scope.plot.data[3])
    assert np.nanmax(np.abs(overlay)) == pytest.approx(np.max(np.abs(first.values[0])))
    header = recording_csv(scope.recording, scope.overlay).splitlines()[0]
    assert header.count("X following error [µm]") == 2 and f"(#{first.number})" in header
    scope._act(RUN)
    scope._trigger.value = FREE_RUN  # type: ignore[misc]
    run(session, clock, 0.2)
    scope.update()
    scope._act(FREEZE)
    assert not scope.acquisition.running and len(scope.history.recordings) == 3


def test_a_watchers_scope_settings_leave_the_operators_scope_alone(
    server: viser.ViserServer, gate: GuiGate, gantry: tuple[Session, FakeClock]
) -> None:
    session, clock = gantry
    operator, watcher = scope_of(server, gate, session), scope_of(server, gate, session)
    run(session, clock, 0.3)
    watcher._slots[0].value = "Y position"  # type: ignore[misc]
    watcher._length.value = "10 s"  # type: ignore[misc]
    watcher._act(FREEZE)
    run(session, clock, 0.2)
    operator.update()
    watcher.update()
    assert operator.channels[0] == "X following error" and operator.acquisition.running
    assert operator.acquisition.length == 20.0 and operator.recording.window.end > 0.45
    assert watcher.channels[0] == "Y position" and not watcher.acquisition.running


def test_a_page_connected_gets_its_own_scope_and_its_bad_values_are_refused(
    server: viser.ViserServer, gantry: tuple[Session, FakeClock], caplog: pytest.LogCaptureFixture
) -> None:
    session, _ = gantry
    app = ViewerApp(session, server)
    page = Page(server, (2.0, -2.0, 2.0))
    try:
        wait_for(lambda: app.pages.get(page.client_id) is not None)
        mine = app.pages.get(page.client_id)
        assert mine is not None and mine.scope is not None
        scope = mine.scope
        for handle, bad in (
            (scope._slots[0], "__import__('os')"),
            (scope._pre, math.nan),
            (scope._level, 1e300),
            (scope._length, 7),
        ):
            before = handle.value
            choose(page, handle, bad)
            time.sleep(0.2)
            assert handle.value == before
        choose(page, scope._slots[0], "Z velocity")  # a good value passes the gate
        wait_for(lambda: scope.channels[0] == "Z velocity")
        for label in ("Ch 1", "Pre-trigger [%]", "Level", "Recording"):
            assert f"refused '{label}': invalid value" in caplog.text
        session.load("single_axis")  # a new scene: the page's scope is built anew
        session.advance(1)
        app.frame()
        rebuilt = app.pages.get(page.client_id)
        assert rebuilt is not None and rebuilt.scope is not None and rebuilt.scope is not scope
        assert rebuilt.scope._all == session.snapshot.channels != scope._all
        assert set(rebuilt.scope.channels) <= {c.name for c in session.snapshot.channels}
    finally:
        page.close()
    wait_for(lambda: app.pages.get(page.client_id) is None)


def test_a_trigger_is_no_trigger_until_chosen() -> None:
    assert Trigger().kind == FREE_RUN
    assert error_trigger(CHANNELS).rows == (1,)


def test_a_step_test_from_a_page_is_recorded_in_that_pages_scope(
    server: viser.ViserServer, gate: GuiGate, gantry: tuple[Session, FakeClock]
) -> None:
    session, clock = gantry
    pages = Pages(session, gate)
    scope = scope_of(server, gate, session)
    pages._pages[7] = cast(ViewerPage, SimpleNamespace(scope=scope))
    session.on_step = pages.show_step
    session.requests("X").set_power(True)
    run(session, clock, 0.5)
    before = session.scene.joint_position("X")
    session.requests("X").step_test(1.0, client_id=7)
    for _ in range(int(1.2 * STEP_WINDOW / session.scene.runtime.plc_period)):
        session.advance(1)
    scope.update()
    recording = scope.recording
    assert recording.window.complete
    assert [h.split(" [")[0] for h in recording.headers()] == [
        "X set point",
        "X position",
        "X following error",
    ]
    position = np.asarray(recording.values[1])
    assert position[-1] - position[0] == pytest.approx(1.0, abs=0.01)  # the step [mm]
    moved = 1e3 * (session.scene.joint_position("X") - before)  # on the joint [mm]
    assert moved == pytest.approx(1.0, abs=0.01)

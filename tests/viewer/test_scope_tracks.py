"""The scope's layout and its machine defaults without a browser: channels of a unit on one y
axis, stacked tracks in bands of their own, values rounded to the channel's resolution; a
recording triggered by an axis error still shown (and kept) after 30 s more of samples; the
history's memory bounded; each machine's scope channels and recording length."""

from __future__ import annotations

import itertools
import math
from contextlib import nullcontext
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
import viser

import scenes
from viewer.pages.layout import COLUMN_WIDTH
from viewer.scope.capture import ON_ERROR, History, Recording, Window
from viewer.scope.panel import CHART_WIDTH, RECORDING_LENGTHS, RUN, PageScope, length_of
from viewer.scope.tracks import (
    ASPECT,
    CHART_FRAME,
    DIGITAL_BAND,
    MIN_TRACK,
    SHARED,
    STACKED,
    aspect_of,
    layout_of,
    nice_ticks,
    unit_groups,
)
from viewer.scope.units import display_of, format_value
from viewer.serving.security import BoundedLog, GuiGate
from viewer.sim.recorder import Ring
from viewer.sim.session import (
    HISTORY_SAMPLE,
    LONG_BUCKET,
    LONG_SECONDS,
    SCOPE_SECONDS,
    Session,
)
from viewer.sim.snapshot import Channel, Snapshot

DT = 0.002
"""Sample period [s] of the hand-made ring."""

EIGHT = (
    Channel("X position", "mm", False),
    Channel("X set point", "mm", False),
    Channel("X velocity", "mm/s", False),
    Channel("X following error", "mm", False),
    Channel("X command", "V", False),
    Channel("Y following error", "mm", False),
    Channel("Y position", "mm", False),
    Channel("X error", "", True),
)
"""Eight channels in five display units (mm, mm/s, µm, V, 0/1)."""

COLORS = ("#000",) * 8


def fraction(value: float, scale: tuple[float, float]) -> float:
    """Where ``value`` is drawn on a scale, a fraction of the plot's height from below."""
    return (value - scale[0]) / (scale[1] - scale[0])


def test_channels_of_a_unit_share_one_y_axis_and_the_digital_ones_a_band_below() -> None:
    displays = [display_of(c) for c in EIGHT]
    ranges = [(-1.0, 1.0), (0.0, 3.0), (-5.0, 5.0), (-20.0, 20.0), (-2.0, 2.0)]
    ranges += [(-40.0, 10.0), (-2.0, 0.5), (-0.1, 1.1)]
    layout = layout_of(SHARED, displays, ranges, COLORS)
    assert [len(g) for g in unit_groups(displays)] == [3, 1, 2, 1, 1]  # mm, mm/s, µm, V, 0/1
    assert len(layout.axes) == 4  # one per analog unit
    assert [a["label"] for a in layout.axes] == ["[mm]", "[mm/s]", "[µm]", "[V]"]
    assert [a["side"] for a in layout.axes] == [3, 1, 3, 1]  # alternately left and right
    mm = layout.ranges[layout.scales[0]]
    assert layout.scales[0] == layout.scales[1] == layout.scales[6]
    for low, high in (ranges[0], ranges[1], ranges[6]):  # each inside the shared range
        assert fraction(low, mm) >= DIGITAL_BAND - 1e-9 and fraction(high, mm) <= 1.0 + 1e-9
    assert fraction(-2.0, mm) == pytest.approx(DIGITAL_BAND)  # the unit's lowest value
    assert fraction(3.0, mm) == pytest.approx(1.0)  # and its highest span the height
    digital = layout.ranges[layout.scales[7]]
    assert fraction(-0.1, digital) >= 0.0 and fraction(1.1, digital) <= DIGITAL_BAND
    ticks = layout.axes[2]["splits"]
    assert ticks == nice_ticks(-40.0, 20.0) and layout.axes[2]["values"][0] == "−40"


def test_in_a_narrow_chart_each_unit_gets_a_track_and_the_plot_keeps_its_width() -> None:
    """Eight channels in four analog units in the 261 px chart of the page's 300 px column:
    their axes do not fit in 40 % of the width, so each unit gets a track of its own (the
    channels of a unit on one scale, first unit on top), one axis labelling every track's top
    in its unit; a wide chart draws the four units' axes."""
    displays = [display_of(c) for c in EIGHT]
    ranges = [(-1.0, 1.0), (0.0, 3.0), (-5.0, 5.0), (-20.0, 20.0), (-2.0, 2.0)]
    ranges += [(-40.0, 10.0), (-2.0, 0.5), (-0.1, 1.1)]
    wide = layout_of(SHARED, displays, ranges, COLORS, 1000.0)
    assert len(wide.axes) == 4 and len(set(wide.scales)) == 5  # four units and the digital
    narrow = layout_of(SHARED, displays, ranges, COLORS, CHART_WIDTH)
    assert len(narrow.axes) == 1 and narrow.axes[0]["size"] <= 0.4 * CHART_WIDTH
    units = [d.unit for d in displays]
    for k, j in itertools.combinations(range(len(EIGHT)), 2):  # a scale per unit
        assert (narrow.scales[k] == narrow.scales[j]) == (units[k] == units[j]), (k, j)
    tracks = []
    for key in dict.fromkeys(narrow.scales):  # the units in their first channel's order
        members = [k for k, s in enumerate(narrow.scales) if s == key]
        low = min(ranges[k][0] for k in members)
        high = max(ranges[k][1] for k in members)
        tracks.append((fraction(low, narrow.ranges[key]), fraction(high, narrow.ranges[key])))
    assert len(tracks) == 5
    for (low, high), (below, _) in itertools.pairwise(tracks):  # top down, apart
        assert 0.0 <= below < high <= 1.0 and below >= 0.0 and high - low >= 0.15
        assert below < low
    texts = [t for t in narrow.axes[0]["values"] if t]
    assert texts == ["3.000 mm", "5.00 mm/s", "20.0 µm", "2.000 V", "1"], texts  # the tops
    assert CHART_WIDTH == COLUMN_WIDTH - 39  # the chart in the left column


def test_stacked_tracks_each_have_a_band_of_their_own_first_on_top() -> None:
    displays = [display_of(c) for c in EIGHT]
    ranges = [(-1.0, 1.0)] * 7 + [(-0.1, 1.1)]
    layout = layout_of(STACKED, displays, ranges, COLORS)
    bands = [
        (fraction(low, layout.ranges[key]), fraction(high, layout.ranges[key]))
        for key, (low, high) in zip(layout.scales, ranges, strict=True)
    ]
    assert len(set(layout.scales)) == 8 and len(layout.axes) == 1
    for (low, high), (next_low, next_high) in itertools.pairwise(bands):
        assert next_high < low  # below the previous track, not overlapping
        assert high - low == pytest.approx(next_high - next_low)
    assert bands[0][1] <= 1.0 and bands[-1][0] >= 0.0
    assert layout.axes[0]["values"][1] == "1.000 mm"  # the top of the first track, with its unit


def test_the_chart_grows_so_that_each_track_keeps_its_least_height() -> None:
    """On shared axes the chart keeps its aspect; each track it is cut into needs
    :data:`MIN_TRACK`, the chart grows taller (the page's column then scrolls)."""
    assert aspect_of(1, CHART_WIDTH) == ASPECT  # 137 px: one plot of 57 px
    for tracks in (3, 5, 8):
        height = CHART_WIDTH / aspect_of(tracks, CHART_WIDTH)
        assert height - CHART_FRAME == pytest.approx(tracks * MIN_TRACK)
    assert aspect_of(3, 1000.0) == ASPECT  # a wide chart is tall enough for three
    displays = [display_of(c) for c in EIGHT]
    ranges = [(-1.0, 1.0)] * 7 + [(-0.1, 1.1)]
    assert layout_of(STACKED, displays, ranges, COLORS).tracks == 8
    assert layout_of(SHARED, displays, ranges, COLORS, 1000.0).tracks == 1
    assert layout_of(SHARED, displays, ranges, COLORS, CHART_WIDTH).tracks == 5


@pytest.mark.parametrize(
    ("value", "resolution", "unit", "shown"),
    [
        (-1.98952e-10, 0.001, "mm", "0 mm"),
        (-0.00004, 0.001, "mm", "0 mm"),
        (-12.3456, 0.1, "µm", "−12.3 µm"),
        (0.25, 0.001, "V", "0.250 V"),
        (1.0, 1.0, "0/1", "1"),
        (math.nan, 0.1, "mm", "—"),
        (12345.6, 0.0, "N·m", "1.235e+04 N·m"),
    ],
)
def test_a_value_is_rounded_to_its_resolution_with_its_unit(
    value: float, resolution: float, unit: str, shown: str
) -> None:
    assert format_value(value, resolution, unit) == shown


def test_every_unit_the_scope_shows_has_a_resolution() -> None:
    for channel in EIGHT:
        assert display_of(channel).resolution > 0.0
    assert display_of(Channel("X following error", "mm", False)).text(-1.98952e-10) == "0 µm"


# ------------------------------------------------------------------------------- error trigger


@pytest.fixture
def gate(server: viser.ViserServer) -> GuiGate:
    return GuiGate(server, lambda client_id: False, lambda *a: None, log=BoundedLog())


def test_an_error_recording_is_still_shown_and_kept_30_s_after_the_error(
    server: viser.ViserServer, gate: GuiGate
) -> None:
    """Samples arrive as from the simulation (a sine and an error flag rising at 5 s), the
    scope updated every 0.1 s; the ring holds 20 s only, so after 35 s the error's samples are
    gone from it but not from the scope."""
    channels = (Channel("X position", "mm", False), Channel("X error", "", True))
    ring = Ring(2, round(20.0 / DT))
    session = SimpleNamespace(recorder=OneRing(channels, ring))
    snapshot = SimpleNamespace(channels=channels, axes={"X": None}, scene="single_axis", signals=())
    scope = PageScope(
        server.gui, gate, cast(Session, session), cast(Snapshot, snapshot), nullcontext
    )
    scope.show_channels(["X position", "X error"])
    scope._length.value = "2 s"  # type: ignore[misc]
    scope._pre.value = 50  # type: ignore[misc]
    scope._set_length()
    scope._trigger.value = ON_ERROR  # type: ignore[misc]
    scope._act(RUN)
    for k in range(round(40.0 / DT) + 1):
        t = k * DT
        ring.append(t, [math.sin(t), float(t >= 5.0)])
        if k % 50 == 0:
            scope.update()
    assert ring.oldest > 19.0  # the error's samples left the ring long ago
    recording = scope.recording
    assert recording.window.trigger_at == pytest.approx(5.0)
    assert recording.window.complete and scope.acquisition.running  # re-armed, still shown
    x, error = recording.x, recording.values[1]
    assert x[0] == pytest.approx(-1.0) and x[-1] == pytest.approx(1.0)  # 50 % before
    assert np.all(error[x < 0.0] == 0.0) and np.all(error[x >= 0.0] == 1.0)
    assert np.allclose(recording.values[0], np.sin(recording.t))
    kept = scope.history.recordings
    assert len(kept) == 1 and kept[0].window.trigger_at == pytest.approx(5.0)
    assert "triggered at t = 5.0000 s" in kept[0].window.status


class OneRing:
    """A recorder of ``channels`` with a fine ring only (no long buffer)."""

    def __init__(self, channels: tuple[Channel, ...], ring: Ring) -> None:
        self.channels, self.ring, self.samples = channels, ring, ring.samples

    @property
    def oldest(self) -> float:
        return self.ring.oldest


def test_the_history_of_minute_long_recordings_is_bounded() -> None:
    """The most samples a recording holds: a minute's, every 2 ms (a longer recording holds
    each 0.1 s' minimum and maximum: fewer)."""
    history = History()
    samples = round(SCOPE_SECONDS / HISTORY_SAMPLE) + 1
    for number in range(20):
        t = np.arange(samples, dtype=np.float64) * HISTORY_SAMPLE + number * 60.0
        values = np.zeros((8, samples))
        window = Window(t[0], t[-1], t[0], None, True, "")
        history.add(Recording(0, ("a",) * 8, (), t, values, window))
    kept = history.recordings
    assert len(kept) == 5 and kept[-1].number == 20
    megabytes = sum(r.t.nbytes + r.values.nbytes for r in kept) / 1e6
    assert megabytes < 12.0  # five minute-long recordings of eight channels
    assert max(RECORDING_LENGTHS.values()) <= LONG_SECONDS
    assert samples > 2 * LONG_SECONDS / LONG_BUCKET + LONG_BUCKET / HISTORY_SAMPLE  # 10 min: fewer


# ------------------------------------------------------------------------------- defaults

DEFAULTS = {
    "flying_shear": ("S velocity", "W velocity", "carriage_minus_strip"),
    "press": ("force", "pressure_A", "pressure_B", "R position"),
    "rotary_cutter": ("D set point", "D position", "W position"),
    "gantry": ("X following error", "Y following error", "Z following error"),
}
"""Channels each machine's scope must show first."""


@pytest.mark.parametrize("name", sorted(DEFAULTS))
def test_each_machine_opens_its_scope_on_its_own_channels_and_record_length(
    name: str, server: viser.ViserServer, gate: GuiGate
) -> None:
    session = Session(name)
    defaults = scenes.definition(name).scope
    names = {c.name for c in session.snapshot.channels}
    assert set(defaults.channels) <= names  # every default a channel of the machine
    assert set(DEFAULTS[name]) <= set(defaults.channels)
    scope = PageScope(server.gui, gate, session, session.snapshot, nullcontext)
    assert scope.channels == list(defaults.channels)
    assert scope.acquisition.length == length_of(defaults.seconds) >= defaults.seconds
    assert scope._length.value == next(
        k for k, v in RECORDING_LENGTHS.items() if v == scope.acquisition.length
    )

"""The scope of one page: up to eight of the recorder's channels in their display units, on
y axes shared by unit or in stacked tracks on one time axis (:mod:`~viewer.scope.tracks`; auto
or manual range per channel); recording length, Run / Single / Freeze, a trigger
(threshold crossing, any axis error) with pre-trigger; cursors A and B with a read-out; the
last recordings to overlay on the live one; CSV export. Its settings belong to its page."""

from __future__ import annotations

__all__ = [
    "AUTO",
    "COLORS",
    "CURSOR_COLORS",
    "CURSOR_LIMIT",
    "EDGES",
    "FREEZE",
    "MANUAL",
    "MAX_CHANNELS",
    "NO_CHANNEL",
    "NO_OVERLAY",
    "RECORDING_LENGTHS",
    "RUN",
    "SINGLE",
    "SLOTS",
    "TRIGGERS",
    "VALUE_LIMIT",
    "PageScope",
    "length_of",
    "plot_rows",
    "plot_style",
]

import math
import threading
from collections.abc import Callable, Mapping, Sequence
from contextlib import AbstractContextManager
from typing import Any

import numpy as np
import numpy.typing as npt
import viser
import viser.uplot

import scenes
from viewer.pages.panels import scope_status_html
from viewer.pages.widgets import SceneGui
from viewer.scope.capture import (
    AT_TIME,
    FREE_RUN,
    ON_ERROR,
    THRESHOLD,
    Acquisition,
    History,
    Recording,
    Trigger,
    Window,
    error_trigger,
    recording_of,
    threshold_trigger,
)
from viewer.scope.readout import aligned, decimate, readout, readout_html, recording_csv
from viewer.scope.tracks import ASPECT, LAYOUTS, SHARED, aspect_of, layout_of
from viewer.scope.units import auto_range, display_of, settled_range
from viewer.serving.retire import retire
from viewer.serving.security import GuiGate, choice_of, number_in
from viewer.sim.recorder import Recorder
from viewer.sim.session import Session
from viewer.sim.snapshot import Snapshot

MAX_CHANNELS = 8
"""Channels a scope shows at once."""

CHART_WIDTH = 261.0
"""Width of the scope's chart [CSS px]: the page's left column (``viewer.pages.layout``'s
COLUMN_WIDTH, 300 px) less its padding."""

RECORDING_LENGTHS = {
    "0.5 s": 0.5,
    "1 s": 1.0,
    "2 s": 2.0,
    "5 s": 5.0,
    "10 s": 10.0,
    "20 s": 20.0,
    "60 s": 60.0,
    "2 min": 120.0,
    "5 min": 300.0,
    "10 min": 600.0,
}
"""Recording lengths (time bases) the scope offers [s] (beyond the last 60 s, the minimum and
maximum of every 0.1 s: :class:`~viewer.sim.recorder.Extremes`)."""

NO_CHANNEL = "—"
"""Channel choice: nothing."""

NO_OVERLAY = "none"
"""Overlay choice: nothing."""

AUTO, MANUAL = "auto", "manual"
"""Y range choices."""

RUN, SINGLE, FREEZE = "Run", "Single", "Freeze"
"""The acquisition buttons."""

TRIGGERS = (FREE_RUN, THRESHOLD, ON_ERROR)
"""Trigger choices."""

EDGES = ("rising", "falling")
"""Threshold directions."""

SLOTS = tuple(f"Ch {k + 1}" for k in range(MAX_CHANNELS))
"""The channel slots, as the y-scale and peak choices name them."""

COLORS = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")
"""Colour of each channel slot (its trace and its y axis)."""

CURSOR_COLORS = {"A": "#000000", "B": "#7f7f7f"}
"""Colour of each cursor's marker."""

VALUE_LIMIT = 1e9
"""Largest |level| or |range| a page may send [display unit]."""

CURSOR_LIMIT = 1200.0
"""Largest |cursor time| a page may send [s from the origin]."""


class PageScope:
    """One page's scope (thread-safe: its controls' callbacks and the update thread).

    Args:
        gui: The page's GUI (``client.gui``); elements go to its current container.
        gate: Checks what the page sends.
        session: The session whose recorder the scope reads.
        snapshot: The scene's snapshot (its channels).
        atomic: Groups the plot's updates into one message (``client.atomic``).
        redraw: Asks for the scope to be updated at the next frame.
    """

    def __init__(
        self,
        gui: viser.GuiApi,
        gate: GuiGate,
        session: Session,
        snapshot: Snapshot,
        atomic: Callable[[], AbstractContextManager[None]],
        redraw: Callable[[], None] = lambda: None,
    ) -> None:
        self.session, self._atomic, self._redraw = session, atomic, redraw
        self._lock = threading.RLock()
        self._all = snapshot.channels
        self._index = {c.name: k for k, c in enumerate(self._all)}
        self._displays = {c.name: display_of(c) for c in self._all}
        self._titles = {s.name: s.label for s in snapshot.signals if s.label}
        defaults = scenes.definition(snapshot.scene).scope
        first = next(iter(snapshot.axes), "")
        wanted = defaults.channels or (
            f"{first} following error",
            f"{first} command",
            f"{first} position",
        )
        self.channels = [n for n in wanted if n in self._index][:MAX_CHANNELS] or [
            self._all[0].name
        ]
        """The channels shown (names): the machine's defaults at first."""
        self.manual: dict[str, tuple[float, float]] = {}
        """Manual y ranges by channel [display unit] (the others are auto-ranged)."""
        self.acquisition = Acquisition(length_of(defaults.seconds))
        """When the scope records (the machine's recording length at first)."""
        self.history = History()
        """The last recordings."""
        self.overlay: Recording | None = None
        """The recording overlaid (dashed) on the live one."""
        self.cursors = {"A": 0.0, "B": 0.1}
        """Cursor times [s from the recording's origin]."""
        self.peak_slot = 0
        """The slot "to peak" looks at (and the cursor markers sit on)."""
        self.layout = SHARED
        """How the channels share the plot's height (:data:`~viewer.scope.tracks.LAYOUTS`)."""
        self.recording = Recording(0, (), (), np.zeros(0), np.zeros((0, 0)), _EMPTY)
        """What the scope shows now."""
        self.status = ""
        """The state line."""
        self._syncing = False
        self._sent: tuple[Any, ...] = ()
        self._style: tuple[Any, ...] = ()
        self._text: dict[str, str] = {}
        self._auto: dict[str, tuple[float, float]] = {}
        self._ui = SceneGui(gate, gui=gui)
        self._elements: list[Any] = []
        self._build(gui)

    # ------------------------------------------------------------------------- building

    def _build(self, gui: viser.GuiApi) -> None:
        """Status, plot, read-out, acquisition buttons; tabs: channels, time and trigger,
        cursors, history."""
        self._status = gui.add_html("")
        self.plot = gui.add_uplot(
            data=(np.zeros(2), np.zeros(2)),
            series=(viser.uplot.Series(label="t [s]"), viser.uplot.Series(label="")),
            scales={"x": viser.uplot.Scale(time=False, auto=True)},
            legend={"live": False},
            aspect=ASPECT,
        )
        self._readout = gui.add_html("")
        self._acquire = gui.add_button_group("Acquisition", (RUN, SINGLE, FREEZE))
        self._ui.gate.allow(self._acquire, choice_of((RUN, SINGLE, FREEZE)), False)
        self._acquire.on_click(lambda event: self._act(str(self._acquire.value)))
        tabs = gui.add_tab_group()
        self._elements += [self._status, self.plot, self._readout, self._acquire, tabs]
        with tabs.add_tab("Channels", viser.Icon.CHART_LINE):
            self._build_channels()
        with tabs.add_tab("Trigger", viser.Icon.BOLT):
            self._build_trigger()
        with tabs.add_tab("Cursors", viser.Icon.RULER_MEASURE):
            self._build_cursors()
        with tabs.add_tab("History", viser.Icon.HISTORY):
            self._build_history()

    def _build_channels(self) -> None:
        """A choice per slot; the y range of a chosen slot (auto, or manual min and max)."""
        ui, options = self._ui, [NO_CHANNEL, *self._index]
        self._slots = []
        for k, label in enumerate(SLOTS):
            initial = self.channels[k] if k < len(self.channels) else NO_CHANNEL
            slot = ui.dropdown(label, options, initial, control=False)
            slot.on_update(self._when(self._choose_channels))
            self._slots.append(slot)
        self._layout = ui.dropdown("Y axes", LAYOUTS, self.layout, control=False)
        self._layout.on_update(self._when(self._choose_layout))
        self._scale_of = ui.dropdown("Y scale of", SLOTS, SLOTS[0], control=False)
        self._range = ui.dropdown("Y range", (AUTO, MANUAL), AUTO, control=False)
        self._low = ui.number("Y min", -1.0, -VALUE_LIMIT, VALUE_LIMIT, 1e-3, control=False)
        self._high = ui.number("Y max", 1.0, -VALUE_LIMIT, VALUE_LIMIT, 1e-3, control=False)
        self._scale_of.on_update(self._when(self._show_range))
        for handle in (self._range, self._low, self._high):
            handle.on_update(self._when(self._set_range))

    def _build_trigger(self) -> None:
        """Recording length, trigger, source, edge, level, pre-trigger."""
        ui = self._ui
        analog = [c.name for c in self._all if not c.digital]
        length = next(k for k, v in RECORDING_LENGTHS.items() if v == self.acquisition.length)
        self._length = ui.dropdown("Recording", list(RECORDING_LENGTHS), length, control=False)
        self._trigger = ui.dropdown("Trigger", TRIGGERS, FREE_RUN, control=False)
        self._source = ui.dropdown("Source", analog, analog[0] if analog else "", control=False)
        self._edge = ui.dropdown("Edge", EDGES, EDGES[0], control=False)
        self._level = ui.number("Level", 0.0, -VALUE_LIMIT, VALUE_LIMIT, 1e-3, control=False)
        self._pre = ui.api.add_slider("Pre-trigger [%]", 0, 90, 5, 10)
        ui.gate.allow(self._pre, number_in(0, 90), False)
        ui.inputs.append(self._pre)
        self._length.on_update(self._when(self._set_length))
        self._pre.on_update(self._when(self._set_length))
        for handle in (self._trigger, self._source, self._edge, self._level):
            handle.on_update(self._when(self._arm))

    def _build_cursors(self) -> None:
        """Cursor times, the slot "to peak" looks at, and the button."""
        ui = self._ui
        self._cursor = {
            name: ui.number(
                f"Cursor {name} [s]", value, -CURSOR_LIMIT, CURSOR_LIMIT, 1e-4, control=False
            )
            for name, value in self.cursors.items()
        }
        self._peak_of = ui.dropdown("Peak of", SLOTS, SLOTS[0], control=False)
        to_peak = ui.button("A to peak", control=False, icon=viser.Icon.ARROW_BAR_TO_UP)
        for handle in (*self._cursor.values(), self._peak_of):
            handle.on_update(self._when(self._set_cursors))
        to_peak.on_click(self._when(self.cursor_to_peak))

    def _build_history(self) -> None:
        """The overlay choice and Export CSV."""
        ui = self._ui
        self._overlay = ui.dropdown("Overlay", (NO_OVERLAY,), NO_OVERLAY, control=False)
        self._overlay.on_update(self._when(self._choose_overlay))
        export = ui.button("Export CSV", control=False, icon=viser.Icon.DOWNLOAD)
        export.on_click(self._export)

    def remove(self) -> None:
        """Remove the scope from its page (and the gate's rules of its controls)."""
        with self._lock:
            self._ui.gate.forget([*self._ui.inputs, self._acquire])
            retire(self._elements)
            self._elements = []

    # ------------------------------------------------------------------------- controls

    def _when(self, change: Callable[[], object]) -> Callable[[Any], None]:
        """A callback that applies ``change`` (not while the scope sets its own controls)."""

        def callback(event: Any) -> None:
            with self._lock:
                if not self._syncing:
                    change()
            self._redraw()

        return callback

    def _set(self, handle: Any, value: Any) -> None:
        """Show ``value`` in a control of this page without acting on it."""
        self._syncing = True
        try:
            handle.value = value
        finally:
            self._syncing = False

    @property
    def _now(self) -> float:
        return self.session.recorder.ring.latest

    def _act(self, action: str) -> None:
        """Run, Single (one recording, then frozen) or Freeze (what is shown stays and is
        kept in the history)."""
        with self._lock:
            if action == FREEZE and self.acquisition.running:
                self.acquisition.freeze()
                if self.recording.t.size and not self.recording.window.complete:
                    self._keep(self.recording)  # a stopped capture
            elif action in (RUN, SINGLE):
                self.acquisition.trigger = self._chosen_trigger()
                self.acquisition.run(self._now, single=action == SINGLE)
        self._redraw()

    def _choose_channels(self) -> None:
        names = [s.value for s in self._slots]
        self.channels = [n for n in names if n in self._index]

    def _choose_layout(self) -> None:
        self.layout = str(self._layout.value)

    def set_layout(self, layout: str) -> None:
        """Show the channels on shared axes or in stacked tracks (``layout``, one of
        :data:`~viewer.scope.tracks.LAYOUTS`)."""
        with self._lock:
            self.layout = layout if layout in LAYOUTS else SHARED
            self._set(self._layout, self.layout)
        self._redraw()

    def _slot_channel(self, slot: int) -> str | None:
        value = self._slots[slot].value
        return value if value in self._index else None

    def _show_range(self) -> None:
        """Show the y range of the slot chosen in Y scale of."""
        name = self._slot_channel(SLOTS.index(self._scale_of.value))
        if name is None:
            return
        manual = self.manual.get(name)
        low, high = manual or self._auto_range(name)
        self._set(self._range, MANUAL if manual else AUTO)
        self._set(self._low, low)
        self._set(self._high, high)

    def _set_range(self) -> None:
        name = self._slot_channel(SLOTS.index(self._scale_of.value))
        if name is None:
            return
        low, high = float(self._low.value), float(self._high.value)
        if self._range.value == MANUAL and high > low:
            self.manual[name] = (low, high)
        else:
            self.manual.pop(name, None)

    def _set_length(self) -> None:
        self.acquisition.length = RECORDING_LENGTHS.get(str(self._length.value), 2.0)
        self.acquisition.pre = float(self._pre.value) / 100.0
        if self.acquisition.running:
            self.acquisition.run(self._now, self.acquisition.single)

    def _arm(self) -> None:
        self.acquisition.set_trigger(self._chosen_trigger(), self._now)

    def _chosen_trigger(self) -> Trigger:
        """The trigger the Trigger tab describes (levels converted to recorded units)."""
        kind = self._trigger.value
        if kind == ON_ERROR:
            return error_trigger(self._all)
        source = str(self._source.value)
        if kind != THRESHOLD or source not in self._displays:
            return Trigger()
        display = self._displays[source]
        level = float(self._level.value)
        shown = f"{level:g} {display.unit}"
        rising = self._edge.value == EDGES[0]
        return threshold_trigger(self._all, source, display.to_recorded(level), rising, shown)

    def _set_cursors(self) -> None:
        self.cursors = {name: float(handle.value) for name, handle in self._cursor.items()}
        self.peak_slot = SLOTS.index(self._peak_of.value)

    def cursor_to_peak(self) -> float | None:
        """Put cursor A at the largest |value| of the "Peak of" slot's channel; its time [s
        from the origin] (None: that slot shows nothing)."""
        with self._lock:
            name = self._slot_channel(self.peak_slot)
            at = self.recording.peak(name) if name is not None else None
            if at is not None:
                self.cursors["A"] = at
                self._set(self._cursor["A"], round(at, 6))
            return at

    def _choose_overlay(self) -> None:
        self.overlay = self.history.find(str(self._overlay.value))

    def _keep(self, recording: Recording) -> None:
        """Keep a complete or frozen recording in the history (the overlay choices follow)."""
        self.history.add(recording)
        labels = [NO_OVERLAY, *(r.label for r in reversed(self.history.recordings))]
        self._ui.gate.allow(self._overlay, choice_of(labels), False)
        self._overlay.options = labels
        if self.overlay is not None and self.overlay.label not in labels:
            self.overlay = None
            self._set(self._overlay, NO_OVERLAY)

    def choose_overlay(self, number: int | None) -> None:
        """Overlay history recording ``number`` (None: no overlay)."""
        with self._lock:
            found = [r for r in self.history.recordings if r.number == number]
            self.overlay = found[0] if found else None
            self._set(self._overlay, found[0].label if found else NO_OVERLAY)
        self._redraw()

    def show_channels(self, channels: Sequence[str]) -> None:
        """Show ``channels`` (names; unknown ones left out, at most :data:`MAX_CHANNELS`)."""
        with self._lock:
            names = [n for n in channels if n in self._index][:MAX_CHANNELS]
            for k, slot in enumerate(self._slots):
                self._set(slot, names[k] if k < len(names) else NO_CHANNEL)
            self.channels = names
        self._redraw()

    def capture(
        self, channels: Sequence[str], start: float, length: float, pre: float = 0.1
    ) -> None:
        """Record ``channels`` from simulated time ``start - pre * length`` [s] for ``length``
        [s]; the recording freezes when complete and enters the history (a step test)."""
        self.show_channels(channels)
        with self._lock:
            self.acquisition.length, self.acquisition.pre = float(length), float(pre)
            self.acquisition.trigger = Trigger(AT_TIME, time=float(start), label="a step test")
            self.acquisition.run(self._now, single=True)
        self._redraw()

    def _export(self, event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
        """Export CSV: the page downloads the recording shown (and the overlay)."""
        with self._lock:
            content = recording_csv(self.recording, self.overlay).encode()
        if event.client is not None:
            event.client.send_file_download("scope.csv", content, save_immediately=True)

    # ------------------------------------------------------------------------- updating

    def update(self) -> None:
        """Record, trigger and send the plot, read-out and status if they changed (the
        update thread calls it at the plot rate)."""
        with self._lock:
            recorder = self.session.recorder
            if recorder.channels != self._all:
                return  # the session moved on to another scene: the page rebuilds
            now = recorder.ring.latest
            if not math.isfinite(now):
                return
            window, completed = self.acquisition.poll(recorder.ring, now)
            self.recording = self._read(recorder, window)
            if completed:
                self._keep(self.recording)
            self.status = window.status
            if self.recording.bucket:
                self.status += f" · {self.recording.resolution}"
            self._show("status", self._status, scope_status_html(self.status))
            r = readout(self.recording, self.cursors["A"], self.cursors["B"], self._titles)
            self._show("readout", self._readout, readout_html(r))
            self._send()

    def _read(self, recorder: Recorder, window: Window) -> Recording:
        """The recording of the chosen channels over ``window`` (the one shown if it is the
        same, or if the recorder no longer holds the frozen window's samples)."""
        shown = self.recording
        names = tuple(self.channels)
        if _span(shown.window) == _span(window) and (
            shown.names == names or recorder.oldest > window.start
        ):
            if shown.window == window:
                return shown
            return Recording(
                0, shown.names, shown.displays, shown.t, shown.values, window, shown.bucket
            )
        rows = [self._index[n] for n in names]
        displays = [self._displays[n] for n in names]
        return recording_of(recorder, window, rows, names, displays)

    def _show(self, name: str, handle: viser.GuiHtmlHandle, content: str) -> None:
        if self._text.get(name) != content:
            self._text[name] = handle.content = content

    def _auto_range(self, name: str) -> tuple[float, float]:
        """The auto y range of channel ``name`` over the live recording and the overlay."""
        display = self._displays[name]
        parts = [self._values_of(self.recording, name)]
        if self.overlay is not None:
            parts.append(self._values_of(self.overlay, name))
        return auto_range(display, np.concatenate(parts))

    @staticmethod
    def _values_of(recording: Recording, name: str) -> npt.NDArray[np.float64]:
        if name not in recording.names:
            return np.zeros(0)
        return recording.values[recording.names.index(name)]

    def ranges(self) -> tuple[tuple[float, float], ...]:
        """The y range of each channel shown [display unit]: manual, or auto (kept while the
        traces fit it well)."""
        shown = []
        for name in self.recording.names:
            manual = self.manual.get(name)
            if manual is None:
                manual = settled_range(self._auto.get(name), self._auto_range(name))
                self._auto[name] = manual
            shown.append(manual)
        return tuple(shown)

    def _send(self) -> None:
        """Send the plot when anything it shows changed."""
        rec, overlay = self.recording, self.overlay
        ranges = self.ranges()
        last = float(rec.t[-1]) if rec.t.size else math.nan
        cursors = tuple(self.cursors.values())
        key = (
            rec.window,
            rec.names,
            last,
            overlay and overlay.number,
            ranges,
            cursors,
            self.peak_slot,
            self.layout,
        )
        if key == self._sent or not rec.names or rec.t.size < 2:
            return
        self._sent = key
        x, rows = plot_rows(rec, overlay, self.cursors, self.peak_slot)
        w = rec.window
        x_range = (w.start - w.origin, w.start - w.origin + self.acquisition.length)
        style = (rec.names, overlay is not None, ranges, w.trigger_at, self.layout, x_range)
        with self._atomic():
            if style != self._style:
                self._style = style
                series, axes, scales, tracks = plot_style(
                    rec, overlay, ranges, self.peak_slot, x_range, self.layout, self._titles
                )
                self.plot.series, self.plot.axes, self.plot.scales = series, axes, scales
                aspect = aspect_of(tracks, CHART_WIDTH)
                if self.plot.aspect != aspect:
                    self.plot.aspect = aspect
            self.plot.data = (x, *rows)


def _span(window: Window) -> tuple[float, float, float, float | None, bool]:
    """What a window covers (its status aside)."""
    return (window.start, window.end, window.origin, window.trigger_at, window.complete)


def length_of(seconds: float) -> float:
    """The shortest recording length offered that holds ``seconds`` (the longest if none)."""
    fitting = [v for v in RECORDING_LENGTHS.values() if v >= seconds - 1e-9]
    return min(fitting) if fitting else max(RECORDING_LENGTHS.values())


_EMPTY = Window(0.0, 0.0, 0.0, None, False, "")
"""The window of an empty recording."""


def plot_rows(
    recording: Recording,
    overlay: Recording | None,
    cursors: dict[str, float],
    peak_slot: int,
) -> tuple[npt.NDArray[np.float64], list[npt.NDArray[np.float64]]]:
    """The plot's x and rows: the live channels, the overlay's (if any), then a marker per
    cursor on the peak slot's channel (NaN but at the cursor), decimated to
    :data:`~viewer.scope.readout.MAX_POINTS` (peaks kept)."""
    rows = recording.values
    if overlay is not None:
        rows = np.vstack([rows, aligned(recording, overlay)])
    x, rows = decimate(recording.x, rows)
    slot = peak_slot if peak_slot < len(recording.names) else 0
    markers = []
    for at in cursors.values():
        marker = np.full(x.size, math.nan)
        if x.size and math.isfinite(at) and x[0] <= at <= x[-1]:
            marker[int(np.argmin(np.abs(x - at)))] = recording.at(at)[slot]
        markers.append(marker)
    return x, [*rows, *markers]


def plot_style(
    recording: Recording,
    overlay: Recording | None,
    ranges: Sequence[tuple[float, float]],
    peak_slot: int,
    x_range: tuple[float, float],
    layout: str = SHARED,
    titles: Mapping[str, str] | None = None,
) -> tuple[
    tuple[viser.uplot.Series, ...],
    tuple[viser.uplot.Axis, ...],
    dict[str, viser.uplot.Scale],
    int,
]:
    """Series (live, overlay dashed, cursor markers), axes (the time axis, then the y axes of
    the ``layout``: one per unit, or one for the stacked tracks), scales and tracks (bands of
    the height) of the plot; a channel is named by its title (``titles``: a published signal's
    label) and its unit."""
    headers = recording.headers(titles)
    placed = layout_of(layout, recording.displays, ranges, COLORS, CHART_WIDTH)
    origin = "trigger" if recording.window.trigger_at is not None else "start"
    series = [viser.uplot.Series(label=f"t [s] (0: {origin})")]
    for k, header in enumerate(headers):
        series.append(_trace(header, COLORS[k], placed.scales[k]))
    if overlay is not None:
        for k, header in enumerate(headers):
            label = f"{header} #{overlay.number}"
            series.append(_trace(label, COLORS[k], placed.scales[k], dashed=True))
    marker_scale = placed.scales[peak_slot if peak_slot < len(headers) else 0]
    for name, color in CURSOR_COLORS.items():
        series.append(
            viser.uplot.Series(
                label=f"cursor {name}",
                stroke=color,
                width=1.0,
                scale=marker_scale,
                points={"show": True, "size": 9.0, "fill": color, "stroke": color},
            )
        )
    axes = (viser.uplot.Axis(label=series[0]["label"]), *placed.axes)
    scales: dict[str, viser.uplot.Scale] = {
        "x": viser.uplot.Scale(time=False, auto=False, range=x_range)
    }
    for key, (low, high) in placed.ranges.items():
        scales[key] = viser.uplot.Scale(auto=False, range=(low, high))
    return tuple(series), axes, scales, placed.tracks


def _trace(label: str, color: str, scale: str, dashed: bool = False) -> viser.uplot.Series:
    if dashed:
        return viser.uplot.Series(label=label, stroke=color, width=1.0, scale=scale, dash=(6, 4))
    return viser.uplot.Series(label=label, stroke=color, width=1.5, scale=scale)

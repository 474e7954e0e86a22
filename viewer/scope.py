"""The scope: up to four channels of the session's recorder on one time base, run and pause, a
trigger (any axis error, a rising digital channel) that freezes a capture, CSV export."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt
import viser
import viser.uplot

from viewer.panels import scope_status_html
from viewer.recorder import Recorder
from viewer.session import Session
from viewer.snapshot import Channel, Snapshot
from viewer.widgets import SceneGui

SCOPE_TRACES = 4
"""Signals the scope shows at once."""

SCOPE_WINDOWS = ("1 s", "2 s", "4 s", "10 s")
"""Time bases the scope offers."""

FREE_RUN = "free run"
"""Scope trigger choice: no trigger."""

ON_ERROR = "on any axis error"
"""Scope trigger choice: the rising edge of any axis' error flag."""

NO_TRACE = "—"
"""Scope channel choice: nothing."""

Shown = tuple[tuple[str, ...], npt.NDArray[np.float64], npt.NDArray[np.float64]]
"""What the scope shows: (trace names with units, t [s], values (traces × samples))."""


def scope_csv(
    names: Sequence[str], t: npt.NDArray[np.float64], values: npt.NDArray[np.float64]
) -> str:
    """The scope's traces as CSV: ``t [s]`` then one column per trace (header with units)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["t [s]", *names])
    for k in range(t.size):
        writer.writerow([f"{t[k]:.6f}", *(f"{v:.9g}" for v in values[:, k])])
    return out.getvalue()


class Scope:
    """The scope of the current scene (for every page; the choices are the same for all).

    Its controls call ``redraw`` (plot at the next frame); :meth:`update` (the update thread)
    plots the traces.

    Args:
        session: The session whose recorder the scope reads.
        server: The viser server.
        redraw: Asks for the scope to be plotted at the next frame.
    """

    def __init__(
        self, session: Session, server: viser.ViserServer, redraw: Callable[[], None]
    ) -> None:
        self.session, self.server, self._redraw = session, server, redraw
        self.plot: viser.GuiUplotHandle | None = None
        self.traces: list[viser.GuiDropdownHandle[str]] = []
        """The trace choices."""
        self.window: viser.GuiDropdownHandle[str] | None = None
        self.trigger: viser.GuiDropdownHandle[str] | None = None
        """The trigger choice."""
        self.run: viser.GuiButtonHandle | None = None
        self._status: viser.GuiHtmlHandle | None = None
        self.paused = False
        """The capture is frozen (paused, or a trigger's capture is complete)."""
        self.armed_since = -math.inf
        """Simulated time [s] since when the trigger looks for an edge."""
        self.trigger_at: float | None = None
        """Simulated time [s] of the trigger edge (None: not triggered)."""
        self._style: tuple[str, ...] = ()
        self.shown: Shown = ((), np.zeros(0), np.zeros((0, 0)))
        """What the scope shows: (trace names with units, t [s], values (traces × samples))."""

    @property
    def status(self) -> str:
        """The scope's state line (running, paused, armed, triggered at …)."""
        return self._status.content if self._status is not None else ""

    def build(self, gui: SceneGui, snapshot: Snapshot) -> None:
        """The Scope folder of a scene: traces, time base, trigger, Run / Pause, Export CSV."""
        names = [c.name for c in snapshot.channels]
        digital = [c.name for c in snapshot.channels if c.digital]
        first = next(iter(snapshot.axes))
        defaults = [
            f"{first} following error",
            f"{first} command",
            f"{first} position",
            NO_TRACE,
        ]
        defaults = [d if d in names else NO_TRACE for d in defaults]
        options = [NO_TRACE, *names]
        triggers = [FREE_RUN, ON_ERROR, *(f"rising: {n}" for n in digital)]
        self.paused = False
        self.trigger_at = None
        self._style = ()
        with gui.folder("Scope", order=5):
            self._status = gui.api.add_html("")
            self.plot = gui.api.add_uplot(
                data=(np.zeros(1), np.zeros(1)),
                series=(viser.uplot.Series(label="t [s]"), viser.uplot.Series(label="")),
                scales={"x": viser.uplot.Scale(time=False, auto=True)},
                title="",
                aspect=1.2,
            )
            self.traces = [
                gui.dropdown(f"Trace {k + 1}", options, defaults[k], control=False)
                for k in range(SCOPE_TRACES)
            ]
            self.window = gui.dropdown("Time base", SCOPE_WINDOWS, "4 s", control=False)
            self.trigger = gui.dropdown("Trigger", triggers, FREE_RUN, control=False)
            self.run = gui.button("Run / Pause", control=False, icon=viser.Icon.PLAYER_PAUSE)
            export = gui.button("Export CSV", control=False, icon=viser.Icon.DOWNLOAD)
        self.run.on_click(self._run_pause)
        export.on_click(self._export)
        self.trigger.on_update(self._rearm)
        for trace in self.traces:
            trace.on_update(lambda event: self._redraw())
        self.window.on_update(lambda event: self._redraw())

    def _run_pause(self, event: Any) -> None:
        """Run / Pause: freeze what is shown, or run on (and rearm the trigger)."""
        if self.paused:
            self.paused = False
            self.trigger_at = None
            self.armed_since = self.session.snapshot.time
        else:
            self.paused = True
        self._redraw()

    def _export(self, event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
        """Export CSV: the page downloads what the scope shows."""
        names, t, values = self.shown
        if event.client is not None:
            content = scope_csv(names, t, values).encode()
            event.client.send_file_download("scope.csv", content, save_immediately=True)

    def _rearm(self, event: Any) -> None:
        """A new trigger choice: look for an edge from now on, running."""
        self.trigger_at = None
        self.armed_since = self.session.snapshot.time
        self.paused = False
        self._redraw()

    def update(self, snapshot: Snapshot) -> None:
        """The traces over the time base; frozen while paused or after a trigger."""
        plot, window_choice, trigger = self.plot, self.window, self.trigger
        if plot is None or window_choice is None or trigger is None:
            return
        window = float(window_choice.value.split()[0])
        channels = snapshot.channels
        index = {c.name: k for k, c in enumerate(channels)}
        chosen = [t.value for t in self.traces if t.value in index]
        recorder = self.session.recorder
        if recorder.channels != channels:
            return  # the session moved on to another scene: the next snapshot rebuilds
        if self.paused:
            status = self._status_of_frozen()
            names = tuple(self.shown[0])
            if names == tuple(_trace_name(channels[index[n]]) for n in chosen):
                self._show_status(status)
                return
            t, values = self._frozen_window(recorder, window)
        else:
            t, values = recorder.series(since=snapshot.time - window)
            status, t, values = self._triggered(trigger.value, index, window, recorder, t, values)
        rows = [index[n] for n in chosen]
        shown = values[rows] if rows else np.zeros((0, t.size))
        names = tuple(_trace_name(channels[k]) for k in rows)
        self.shown = (names, t, shown)
        self._show_status(status)
        if t.size < 2 or not rows:
            return
        units = tuple("0/1" if channels[k].digital else channels[k].unit for k in rows)
        with self.server.atomic():
            if (names, units) != (self._style[: len(names)], self._style[len(names) :]):
                self._style = (*names, *units)
                plot.series, plot.axes, plot.scales = _scope_style(names, units)
                plot.title = " · ".join(names)
            plot.data = (t, *shown)

    def _status_of_frozen(self) -> str:
        if self.trigger_at is not None:
            return f"triggered at t = {self.trigger_at:.3f} s"
        return "paused"

    def _triggered(
        self,
        mode: str,
        index: dict[str, int],
        window: float,
        recorder: Recorder,
        t: npt.NDArray[np.float64],
        values: npt.NDArray[np.float64],
    ) -> tuple[str, npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The running scope's status and samples: a trigger's capture freezes once the edge is
        in the middle of the time base."""
        if mode == FREE_RUN or not t.size:
            return "running", t, values
        at = self._find_trigger(mode, index, t, values)
        if at is None:
            return "armed: waiting for " + mode, t, values
        self.trigger_at = at
        if t[-1] >= at + 0.5 * window:
            self.paused = True
            t, values = self._frozen_window(recorder, window)
            return f"triggered at t = {at:.3f} s", t, values
        return f"triggered at t = {at:.3f} s, recording", t, values

    def _frozen_window(
        self, recorder: Recorder, window: float
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The samples of a triggered capture (trigger in the middle) or the last window."""
        at = self.trigger_at
        t_shown = self.shown[1]
        if at is None:
            end = float(t_shown[-1]) if t_shown.size else self.session.snapshot.time
            t, values = recorder.series(since=end - window)
            keep = t <= end
            return t[keep], values[:, keep]
        t, values = recorder.series(since=at - 0.5 * window)
        keep = t <= at + 0.5 * window
        return t[keep], values[:, keep]

    def _find_trigger(
        self,
        mode: str,
        index: dict[str, int],
        t: npt.NDArray[np.float64],
        values: npt.NDArray[np.float64],
    ) -> float | None:
        """Time [s] of the first trigger edge after arming (None: none yet)."""
        if self.trigger_at is not None:
            return self.trigger_at
        if mode == ON_ERROR:
            rows = [k for n, k in index.items() if n.endswith(" error") and "following" not in n]
        else:
            name = mode.removeprefix("rising: ")
            rows = [index[name]] if name in index else []
        fresh = t > self.armed_since
        for k in rows:
            level = values[k] > 0.5
            edges = np.flatnonzero(level[1:] & ~level[:-1] & fresh[1:]) + 1
            if edges.size:
                return float(t[edges[0]])
        return None

    def _show_status(self, status: str) -> None:
        if self._status is None:
            return
        content = scope_status_html(status)
        if self._status.content != content:
            self._status.content = content


def _trace_name(channel: Channel) -> str:
    """A scope trace's label: name and unit."""
    return f"{channel.name} [{channel.unit}]" if channel.unit else f"{channel.name} [0/1]"


def _scope_style(
    names: Sequence[str], units: Sequence[str]
) -> tuple[
    tuple[viser.uplot.Series, ...], tuple[viser.uplot.Axis, ...], dict[str, viser.uplot.Scale]
]:
    """Series, axes and scales of the scope: one y scale per unit, the first two with axes."""
    colors = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd")
    distinct = list(dict.fromkeys(units))
    series = [viser.uplot.Series(label="t [s]")]
    for k, (name, unit) in enumerate(zip(names, units, strict=True)):
        series.append(
            viser.uplot.Series(label=name, stroke=colors[k % len(colors)], width=1.5, scale=unit)
        )
    axes = [viser.uplot.Axis(label="t [s]")]
    for k, unit in enumerate(distinct[:2]):
        axes.append(
            viser.uplot.Axis(
                scale=unit, label=f"[{unit}]", side=3 if k == 0 else 1, grid={"show": k == 0}
            )
        )
    scales = {"x": viser.uplot.Scale(time=False, auto=True)}
    for unit in distinct:
        scales[unit] = (
            viser.uplot.Scale(auto=False, range=(-0.1, 1.1))
            if unit == "0/1"
            else viser.uplot.Scale(auto=True)
        )
    return tuple(series), tuple(axes), scales

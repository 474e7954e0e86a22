"""The HTML of the read-out panels: axis panels, status line, demo, signals, results,
error history (every text from the simulation escaped)."""

from __future__ import annotations

__all__ = [
    "EVENTS_SHOWN",
    "NO_MODEL_NOTE",
    "SPEEDS",
    "SWITCH_LAMPS",
    "VALUE_WIDTH",
    "axis_panel_html",
    "demo_html",
    "events_html",
    "lamp_dot",
    "results_html",
    "scope_status_html",
    "signals_html",
    "speed_label",
    "status_html",
    "utc",
]

import html
import math
import time
from collections.abc import Sequence

from viewer.sim.snapshot import AxisView, DemoView, SignalView, Snapshot

SPEEDS: dict[str, float] = {
    "0.1×": 0.1,
    "0.25×": 0.25,
    "0.5×": 0.5,
    "1×": 1.0,
    "2×": 2.0,
    "5×": 5.0,
    "10×": 10.0,
    "max": math.inf,
}
"""Speed choices: label → simulated seconds per wall second (``inf``: as fast as possible)."""

_LAMP_HTML = {
    "on_limit": "#e53935",
    "on_ref": "#ffb300",
    "on_info": "#43a047",
    "on_output": "#1e88e5",
    "off": "#cfd8dc",
}

SWITCH_LAMPS = (
    ("lim_neg", "LIM−", "on_limit"),
    ("ref", "REF", "on_ref"),
    ("lim_pos", "LIM+", "on_limit"),
)
"""Panel lamps of the switch inputs: (AxisView field, label, lamp kind), left to right."""

NO_MODEL_NOTE = "simulated axes: no 3-D model"
"""Shown in the 3-D view for a machine without a MuJoCo model."""

EVENTS_SHOWN = 15
"""Entries of the error history the panel shows (newest first)."""


def speed_label(speed: float) -> str:
    """Dropdown label of a speed factor (``"1×"``, ``"max"``, or e.g. ``"3×"``)."""
    for label, value in SPEEDS.items():
        if value == speed:
            return label
    return f"{speed:g}×"


def utc(wall: float) -> str:
    """Wall-clock time as ``HH:MM:SS.mmm`` UTC."""
    return time.strftime("%H:%M:%S", time.gmtime(wall)) + f".{int(wall % 1.0 * 1000):03d}"


def _box(content: str) -> str:
    """A panel's text block (long words wrap anywhere rather than widen the panel)."""
    return f'<div style="font-size:0.85em;padding:0 0.75em;overflow-wrap:anywhere">{content}</div>'


def lamp_dot(on: bool, kind: str) -> str:
    """A round lamp: lit in the colour of ``kind`` (``"on_limit"``, ``"on_ref"``,
    ``"on_info"``, ``"on_output"``), grey when off."""
    color = _LAMP_HTML[kind] if on else _LAMP_HTML["off"]
    return (
        f'<span style="display:inline-block;width:0.75em;height:0.75em;border-radius:50%;'
        f'background:{color};border:1px solid #90a4ae;vertical-align:-0.1em"></span>'
    )


def _lamp(on: bool, label: str, kind: str) -> str:
    return (
        f'<span style="white-space:nowrap;margin-right:0.7em">{lamp_dot(on, kind)} {label}</span>'
    )


VALUE_WIDTH = "58%"
"""Width of the value column of a read-out table (the names wrap in the rest)."""


def _table(rows: Sequence[tuple[str, str]]) -> str:
    """A two-column read-out table of fixed layout: names left (they wrap), values right in
    monospace in a column of fixed width (never pushed out of the panel; too long a value is
    cut off)."""
    body = "".join(
        f'<tr data-row="{name}"><td style="padding:0 0.5em 0 0">{name}</td>'
        f'<td data-value="{name}" style="text-align:right;font-family:monospace;'
        f'white-space:pre;overflow:hidden;text-overflow:ellipsis">{value}</td></tr>'
        for name, value in rows
    )
    return (
        f'<table style="width:100%;table-layout:fixed;border-collapse:collapse">'
        f'<colgroup><col><col style="width:{VALUE_WIDTH}"></colgroup>{body}</table>'
    )


def _axis_rows(view: AxisView) -> list[tuple[str, str]]:
    """The read-out rows of an axis panel (the command only with a drive)."""
    unit = html.escape(view.unit)
    rows = [
        ("Position", f"{view.position:10.3f} {unit}"),
        ("Velocity", f"{view.velocity:10.2f} {unit}/s"),
    ]
    if view.has_drive:
        rows += [
            ("Following error", f"{view.following_error:10.4f} {unit}"),
            ("Command", f"{view.volts:10.3f} V"),
        ]
    else:
        rows.append(("Drive", "none (encoder only)"))
    rows.append(("State", f"<b>{html.escape(view.state or '—')}</b>"))
    if view.group:
        rows.append(("Group", html.escape(view.group)))
    return rows


def _texts(view: AxisView) -> str:
    """The axis error and the last failed command (labelled Refused or Aborted), each on a line
    of its own under the values (wrapped: however long, they never push the values out of the
    panel)."""
    alarm = bool(view.error_id or view.error)
    error = f"{view.error_id} {html.escape(view.error)}" if alarm else "—"
    lines = [("Error", error, alarm)]
    if view.last_error:
        lines.append((view.last_error_kind, html.escape(view.last_error), True))
    return "".join(
        f'<div data-text="{label}" style="margin-top:0.2em">{label}: '
        f'<span style="color:{"#c62828" if alarm else "inherit"}">{text}</span></div>'
        for label, text, alarm in lines
    )


def axis_panel_html(view: AxisView) -> str:
    """The read-outs of one axis as HTML: values in the axis' unit, state, error text, lamps.

    Only what the axis has is shown: the switches of its machine definition, its digital inputs
    (``DI``) and outputs (``DO``, read-only), the command only if it has a drive. The error and
    a refused command's text go under the values, wrapped; the last command's outcome under the
    lamps, unless it is that refusal.

    Args:
        view: The axis view of a snapshot.

    Returns:
        An HTML fragment (texts escaped).
    """
    lamps = "".join(
        _lamp(bool(getattr(view, field)), label, kind)
        for field, label, kind in SWITCH_LAMPS
        if field in view.switches
    )
    lamps += _lamp(view.index, "Index", "on_info") + _lamp(view.referenced, "Homed", "on_info")
    lamps += "".join(_lamp(on, f"DI{i}", "on_info") for i, on in enumerate(view.inputs))
    outputs = "".join(_lamp(on, f"DO{i}", "on_output") for i, on in enumerate(view.outputs))
    if outputs:
        outputs = f'<div style="line-height:1.6">Outputs: {outputs}</div>'
    said = view.message and view.message != view.last_error  # a refusal is said once
    message = html.escape(view.message) if said else "&nbsp;"
    return _box(
        f"{_table(_axis_rows(view))}{_texts(view)}"
        f'<div style="margin-top:0.4em;line-height:1.6">{lamps}</div>{outputs}'
        f'<div style="color:#546e7a;margin-top:0.2em">{message}</div>'
    )


def signals_html(snapshot: Snapshot) -> str:
    """The machine's published signals as HTML: label with unit, value (texts escaped)."""
    rows = [
        (html.escape(_signal_label(s)), f"{round(s.value, 3) + 0.0:12.3f}")  # no "-0.000"
        for s in snapshot.signals
    ]
    return _box(_table(rows))


def _signal_label(signal: SignalView) -> str:
    """A signal's label with its unit: ``"carriage − strip [mm/s]"``."""
    label = signal.label or signal.name
    return f"{label} [{signal.unit}]" if signal.unit else label


def status_html(snapshot: Snapshot) -> str:
    """The simulation status line: simulated time, speed, achieved real-time factor."""
    if snapshot.fault:
        state = f'<span style="color:#c62828">stopped: {html.escape(snapshot.fault)}</span>'
    elif snapshot.paused:
        state = "paused"
    else:
        state = (
            f"running at {speed_label(snapshot.speed)} (achieved {snapshot.realtime_factor:.2f}×)"
        )
    note = "" if snapshot.model is not None else f" · {NO_MODEL_NOTE}"
    return _box(
        f"<b>{html.escape(snapshot.scene)}</b> · t = {snapshot.time:9.3f} s · {state}"
        f'<div style="color:#546e7a">{html.escape(snapshot.description)}{note}</div>'
    )


def demo_html(snapshot: Snapshot) -> str:
    """The demo program's step (or what ended it) and the axes groups."""
    demo = snapshot.demo
    if not demo.available:
        text = "This scene has no demo program."
    elif demo.error:
        text = f'<span style="color:#c62828">{html.escape(demo.error)}</span>'
    elif demo.step:
        text = _step_text(demo)
    else:
        text = "Not started."
    if snapshot.groups:
        text += "<br>Axes group: " + html.escape(", ".join(snapshot.groups))
    return _box(text)


def _step_text(demo: DemoView) -> str:
    """The demo's step (escaped): "Done" once (or "Done: " and its last step where that is
    not "done"), "Step: " while it runs, "Ended at: " where it stopped."""
    step = html.escape(demo.step)
    if demo.done:
        return "Done" if demo.step.strip().lower() == "done" else f"Done: {step}"
    return ("Step: " if demo.running else "Ended at: ") + step


def events_html(snapshot: Snapshot, shown: int = EVENTS_SHOWN) -> str:
    """The error history of the machine shown, newest first: per entry a line of UTC time,
    simulated time and source, and under it the text, wrapped (texts escaped); how many
    errors earlier machines had is said under it."""
    mine = [e for e in snapshot.events if e.scene in ("", snapshot.scene)]
    others = len(snapshot.events) - len(mine)
    earlier = (
        f'<div data-earlier style="color:#546e7a">{others} more on other machines'
        " (before this one was chosen)</div>"
        if others
        else ""
    )
    events = mine[-shown:][::-1]
    if not events:
        return _box(f"No errors on {html.escape(snapshot.scene)}.{earlier}")
    entries = "".join(
        f'<div data-event style="margin-bottom:0.3em">'
        f'<div style="color:#546e7a;font-family:monospace;white-space:nowrap;overflow:hidden;'
        f'text-overflow:ellipsis">{utc(e.wall)} t={e.time:.3f} {html.escape(e.source)}</div>'
        f"<div>{html.escape(e.text)}</div></div>"
        for e in events
    )
    return (
        f'<div style="font-size:0.8em;padding:0 0.75em;overflow-wrap:anywhere">{entries}'
        f"{earlier}</div>"
    )


def results_html(snapshot: Snapshot) -> str:
    """The demo's results table (last rows; texts escaped): it scrolls sideways inside the
    panel when it is wider than the panel."""
    columns, rows = snapshot.results
    if not columns:
        return _box("No results yet.")
    head = "".join(
        f'<th style="padding:0 0.4em;white-space:nowrap">{html.escape(c)}</th>' for c in columns
    )
    body = "".join(
        "<tr>"
        + "".join(
            f'<td style="text-align:right;font-family:monospace;padding:0 0.4em;'
            f'white-space:nowrap">{html.escape(v)}</td>'
            for v in row
        )
        + "</tr>"
        for row in rows
    )
    return (
        f'<div data-results style="font-size:0.8em;margin:0 0.75em;max-width:100%;'
        f'overflow-x:auto"><table style="border-collapse:collapse"><tr>{head}</tr>{body}'
        f"</table></div>"
    )


def scope_status_html(status: str) -> str:
    """The scope's state line."""
    return _box(f"Scope: {html.escape(status)}")

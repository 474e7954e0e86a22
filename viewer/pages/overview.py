"""The all-axes overview: one row per axis of the current scene, as an engineer's online view.

Each row: set and actual position [u], set and actual velocity [u/s], the following error and
its peak since the last reset (µm for axes in mm or m), the command in percent of ±10 V, a status
word of lamps, and under the row a line of its own for the error text. The table has fixed
column widths (``table-layout: fixed``): a value never moves, whatever the error text's length
(it wraps into two lines at most, then ends in an ellipsis; the full text is its tooltip).
Encoder-only axes show "—" where they have no set point and no output.

Interface used by the per-page layout (:mod:`viewer.pages.layout`): ``Overview(gui)`` adds its
element
to the current container of ``gui`` (a page's ``client.gui``); :meth:`Overview.update` sends the
table when it changed. The peaks are reset by :meth:`viewer.sim.session.Session.reset_peaks` (the
layout binds it to a button).
"""

from __future__ import annotations

__all__ = [
    "CHAR_WIDTH",
    "ERROR_LINES",
    "FE_UNITS",
    "FULL_SCALE_VOLTS",
    "LAMPS",
    "LAMP_KINDS",
    "LAMP_WIDTH",
    "NAME_WIDTH",
    "NONE",
    "VALUE_COLUMNS",
    "Overview",
    "fe_scale",
    "name_width",
    "overview_html",
    "status_word",
]

import html
import math

import viser

from viewer.pages.panels import lamp_dot
from viewer.serving.retire import retire
from viewer.sim.snapshot import AxisView, Snapshot

FULL_SCALE_VOLTS = 10.0
"""The analog command at 100 % [V] (the output is ±10 V)."""

NONE = "—"
"""What a cell shows that the axis does not have (an encoder-only axis' set point)."""

FE_UNITS: dict[str, tuple[float, str]] = {"mm": (1e3, "µm"), "m": (1e6, "µm"), "deg": (1e3, "mdeg")}
"""Following error shown per axis unit: (factor from the axis unit, shown unit); other units
are shown as they are, with four decimals."""

VALUE_COLUMNS: tuple[tuple[str, str, float, str], ...] = (
    ("set_position", "Set pos [u]", 5.8, "set point (model position) [u]"),
    ("position", "Act pos [u]", 5.8, "actual position POS [u]"),
    ("set_velocity", "Set vel [u/s]", 5.4, "set velocity [u/s]"),
    ("velocity", "Act vel [u/s]", 5.4, "actual velocity VEL [u/s]"),
    ("following_error", "FE", 7.0, "following error: set point − actual position"),
    ("peak_following_error", "FE peak", 7.0, "largest |following error| since Reset peaks"),
    ("output", "Out [%]", 3.8, "analog command in % of ±10 V"),
)
"""The value columns: (data-field, header, width [em], tooltip); ``u`` in a header is the axes'
unit (left out when the axes differ: each row names its own)."""

LAMPS: tuple[tuple[str, str, str], ...] = (
    ("ready", "Ready", "ready: powered, no error, standstill"),
    ("enabled", "Enabled", "enabled: drive enable on"),
    ("homed", "Homed", "homed: the axis has its reference"),
    ("in_position", "In pos", "in position: standstill, |FE| within the in-position window"),
    ("moving", "Moving", "moving: the set point is in motion"),
    ("lim_neg", "LIM−", "LIM− switch"),
    ("lim_pos", "LIM+", "LIM+ switch"),
    ("sw_limit", "SW lim", "software limit reached (LimNeg or LimPos)"),
    ("error", "Error", "axis error"),
)
"""The status word: (data-field, header (written upwards), tooltip), left to right."""

NAME_WIDTH, LAMP_WIDTH = 3.6, 1.2
"""Narrowest width of the axis name column (the name with its unit) and width of each lamp
column [em of the table's font]."""

CHAR_WIDTH = 0.62
"""Width of a character of a bold axis name [em of the table's font], generous."""

ERROR_LINES = 2
"""Lines the error text may wrap into before it is cut off (always reserved)."""

_CELL = "padding:0.1em 0.2em;white-space:nowrap;overflow:hidden"
_NUMBER = f"{_CELL};text-align:right;font-family:monospace"


def fe_scale(unit: str) -> tuple[float, str, int]:
    """How the following error of an axis in ``unit`` is shown: (factor, unit, decimals)."""
    factor, shown = FE_UNITS.get(unit, (1.0, unit))
    return factor, shown, 1 if factor != 1.0 else 4


def _number(value: float, decimals: int) -> str:
    """A number with ``decimals`` decimals (no "-0.00"); "—" for NaN (the axis has no such
    value)."""
    if math.isnan(value):
        return NONE
    return f"{value if round(value, decimals) else 0.0:.{decimals}f}"


def _values(view: AxisView) -> dict[str, str]:
    """The text of each value cell of ``view``'s row (escaped)."""
    factor, fe_unit, decimals = fe_scale(view.unit)
    suffix = (
        '<span style="color:#78909c;font-family:sans-serif;font-size:0.8em">'
        f" {html.escape(fe_unit)}</span>"
    )
    drive = view.has_drive
    return {
        "set_position": _number(view.set_position, 3),
        "position": _number(view.position, 3),
        "set_velocity": _number(view.set_velocity, 2),
        "velocity": _number(view.velocity, 2),
        "following_error": _number(view.following_error * factor, decimals) + suffix
        if drive
        else NONE,
        "peak_following_error": _number(view.peak_following_error * factor, decimals) + suffix
        if drive
        else NONE,
        "output": _number(100.0 * view.volts / FULL_SCALE_VOLTS, 1) if drive else NONE,
    }


def status_word(view: AxisView) -> dict[str, bool]:
    """The lamps of ``view``'s status word, by their :data:`LAMPS` field."""
    return {
        "ready": view.powered and view.standstill and not view.error_id,
        "enabled": view.enabled,
        "homed": view.referenced,
        "in_position": view.in_position,
        "moving": view.moving,
        "lim_neg": view.lim_neg,
        "lim_pos": view.lim_pos,
        "sw_limit": view.sw_limit_neg or view.sw_limit_pos,
        "error": view.error_id != 0,
    }


LAMP_KINDS = {
    "moving": "on_output",
    "lim_neg": "on_limit",
    "lim_pos": "on_limit",
    "sw_limit": "on_ref",
    "error": "on_limit",
}
"""Colour of a lit lamp of the status word (the others: ``"on_info"``, green)."""


def _error_text(view: AxisView) -> str:
    """The axis error as number and text, and the last failed command, refused or aborted
    (empty: neither)."""
    parts = [f"{view.error_id} {view.error}".strip()] if view.error_id else []
    if view.last_error:
        parts.append(f"{view.last_error_kind.lower()}: {view.last_error}")
    return " · ".join(parts)


def _row(view: AxisView) -> str:
    """The value row and the error line of one axis."""
    name = html.escape(view.name)
    values = _values(view)
    cells = "".join(
        f'<td data-field="{field}" style="{_NUMBER}">{values[field]}</td>'
        for field, _, _, _ in VALUE_COLUMNS
    )
    word, note = status_word(view), _window_note(view)
    lamps = "".join(
        f'<td data-field="{field}" style="{_CELL};padding:0.1em 0;text-align:center" title="{tip}'
        f'{note if field == "in_position" else ""}">'
        f"{lamp_dot(word[field], LAMP_KINDS.get(field, 'on_info'))}</td>"
        for field, _, tip in LAMPS
    )
    text = _error_text(view)
    line = ERROR_LINES * 1.3
    span = 1 + len(VALUE_COLUMNS) + len(LAMPS)
    error = (
        f'<tr data-axis="{name}" data-line="error"><td colspan="{span}"'
        f' style="padding:0 0.3em 0.2em 0.3em;border-bottom:1px solid #eceff1">'
        f'<div data-field="error_text" title="{html.escape(text)}" style="height:{line}em;'
        f"line-height:1.3em;overflow:hidden;overflow-wrap:anywhere;display:-webkit-box;"
        f"-webkit-box-orient:vertical;-webkit-line-clamp:{ERROR_LINES};color:#c62828;"
        f'font-size:0.95em">{html.escape(text)}</div></td></tr>'
    )
    return (
        f'<tr data-axis="{name}" data-line="values"><td data-field="name" style="{_CELL}">'
        f'<b>{name}</b> <span data-field="unit" style="color:#78909c">'
        f"{html.escape(view.unit)}</span></td>{cells}{lamps}</tr>{error}"
    )


def _window_note(view: AxisView) -> str:
    """The in-position window in the lamp's tooltip (``" (±5.0 µm)"``)."""
    factor, unit, decimals = fe_scale(view.unit)
    return f" (±{view.in_position_window * factor:.{decimals}f} {html.escape(unit)})"


def name_width(views: list[AxisView]) -> float:
    """The width of the axis name column [em]: the longest name with its unit, whole."""
    longest = max((len(v.name) + 1 + len(v.unit) for v in views), default=0)
    return max(NAME_WIDTH, CHAR_WIDTH * longest + 0.8)


def _header(label: str, units: set[str]) -> str:
    """A value column's header: ``u`` replaced by the axes' one unit (left out for several)."""
    if len(units) == 1:
        return label.replace("[u", f"[{html.escape(next(iter(units)))}")
    return label.split(" [")[0]


def _head(views: list[AxisView]) -> tuple[str, float]:
    """The column widths and the header row; the table's width [em]."""
    widths = [name_width(views), *(w for _, _, w, _ in VALUE_COLUMNS)]
    widths += [LAMP_WIDTH] * len(LAMPS)
    units = {v.unit for v in views}
    columns = "".join(f'<col style="width:{w:.2f}em">' for w in widths)
    header = '<th style="text-align:left" title="axis and its unit u">Axis</th>'
    header += "".join(
        f'<th title="{tip}" style="text-align:right;padding:0 0.3em">{_header(label, units)}</th>'
        for _, label, _, tip in VALUE_COLUMNS
    )
    header += "".join(
        f'<th title="{tip}" style="writing-mode:vertical-rl;transform:rotate(180deg);'
        f'text-align:left;white-space:nowrap;font-weight:normal;padding:0.2em 0">{label}</th>'
        for _, label, tip in LAMPS
    )
    return f"<colgroup>{columns}</colgroup><tr>{header}</tr>", sum(widths)


def overview_html(snapshot: Snapshot) -> str:
    """The overview table of every axis of ``snapshot`` (texts escaped)."""
    views = list(snapshot.axes.values())
    head, width = _head(views)
    rows = "".join(_row(view) for view in views)
    return (
        '<div style="overflow-x:auto;padding:0 0.5em">'
        f'<table data-overview="axes" style="table-layout:fixed;width:{width:.1f}em;'
        f'border-collapse:collapse;font-size:0.75em">'
        f'<thead style="font-size:0.85em;color:#455a64;vertical-align:bottom">{head}</thead>'
        f"<tbody>{rows}</tbody></table></div>"
    )


class Overview:
    """The overview table in a page's GUI (``gui``: the page's ``client.gui``)."""

    def __init__(self, gui: viser.GuiApi) -> None:
        self._html = gui.add_html("")
        self._shown = ""

    def update(self, snapshot: Snapshot) -> None:
        """Show ``snapshot``'s axes (sends only a changed table)."""
        content = overview_html(snapshot)
        if content != self._shown:
            self._shown = self._html.content = content

    def remove(self) -> None:
        """Remove the table from the page."""
        retire([self._html])

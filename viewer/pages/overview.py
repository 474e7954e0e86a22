"""The all-axes overview: a block of lines per axis, as an engineer's online view, narrow
enough for the page's left column (300 px at 1280×800) without scrolling sideways.

Four value columns, each with two lines: position and velocity [u] (actual above, set point
below in grey), the following error and its peak since the last reset (µm for axes in mm or m,
mdeg for deg), and the command in percent of ±10 V; the axis name with its unit under it on the
left. Under the values a line of the status word: nine labelled lamps (Rdy, En, Hom, …) at fixed
places, then a line of its own for the error text. The table has fixed column widths
(``table-layout: fixed``): a value never moves, whatever the error text's length (it wraps into
two lines at most, then ends in an ellipsis; the full text is its tooltip). Encoder-only axes
show "—" where they have no set point and no output.

Interface used by the per-page layout (:mod:`viewer.pages.layout`): ``Overview(gui)`` adds its
element to the current container of ``gui`` (a page's ``client.gui``); :meth:`Overview.update`
sends the table when it changed. The peaks are reset by
:meth:`viewer.sim.session.Session.reset_peaks` (the layout binds it to a button).
"""

from __future__ import annotations

__all__ = [
    "CHAR_WIDTH",
    "COLUMNS",
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

COLUMNS: tuple[tuple[str, str, str, float], ...] = (
    ("Pos", "[u]", "act/set", 5.7),
    ("Vel", "[u/s]", "act/set", 5.1),
    ("FE", "", "now/peak", 4.6),
    ("Out", "[%]", "of ±10 V", 4.0),
)
"""The value columns: (header, unit, what its two lines are, width [em]); ``u`` is the axes'
unit (left out when the axes differ: each axis names its own under its name). The following
error's unit is the header's when every axis has the same (:func:`fe_scale`), else each value's."""

VALUE_COLUMNS: tuple[tuple[str, int, int, str], ...] = (
    ("position", 0, 0, "actual position POS [u]"),
    ("set_position", 0, 1, "set point (model position) [u]"),
    ("velocity", 1, 0, "actual velocity VEL [u/s]"),
    ("set_velocity", 1, 1, "set velocity [u/s]"),
    ("following_error", 2, 0, "following error: set point − actual position"),
    ("peak_following_error", 2, 1, "largest |following error| since Reset peaks"),
    ("output", 3, 0, "analog command in % of ±10 V"),
)
"""The values: (data-field, column of :data:`COLUMNS`, line (0 above, 1 below), tooltip)."""

LAMPS: tuple[tuple[str, str, str], ...] = (
    ("ready", "Rdy", "ready: powered, no error, standstill"),
    ("enabled", "En", "enabled: drive enable on"),
    ("homed", "Hom", "homed: the axis has its reference"),
    ("in_position", "InP", "in position: standstill, |FE| within the in-position window"),
    ("moving", "Mov", "moving: the set point is in motion"),
    ("lim_neg", "L−", "LIM− switch"),
    ("lim_pos", "L+", "LIM+ switch"),
    ("sw_limit", "SW", "software limit reached (LimNeg or LimPos)"),
    ("error", "Err", "axis error"),
)
"""The status word: (data-field, label, tooltip), left to right, each lamp at a fixed place of
the line under the axis' values."""

NAME_WIDTH = 2.6
"""Narrowest width of the axis name column (the name, its unit under it) [em of the table's
font]."""

CHAR_WIDTH = 0.56
"""Width of a character of a bold axis name [em of the table's font], generous."""

LAMP_WIDTH = 2.5
"""Narrowest place of a lamp with its label [em of the table's font]."""

ERROR_LINES = 2
"""Lines the error text may wrap into before it is cut off (always reserved)."""

_CELL = "padding:0 0.15em;white-space:nowrap;overflow:hidden"
_NUMBER = f"{_CELL};text-align:right;font-family:monospace"
_GREY = "color:#78909c"
_RULE = "border-bottom:1px solid #eceff1"


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


def _values(view: AxisView, fe_suffix: bool) -> dict[str, str]:
    """The text of each value cell of ``view``'s row (escaped); the following errors with their
    unit when ``fe_suffix``."""
    factor, fe_unit, decimals = fe_scale(view.unit)
    suffix = (
        f'<span style="{_GREY};font-family:sans-serif;font-size:0.8em">'
        f" {html.escape(fe_unit)}</span>"
        if fe_suffix
        else ""
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


def _value_line(name: str, line: int, values: dict[str, str], first: str) -> str:
    """One line of an axis' values (``line`` 0: actual, 1: set points and peak), led by
    ``first`` (the name cell on the first line, nothing on the second)."""
    cells = []
    for column in range(len(COLUMNS)):
        found = [f for f, c, k, _ in VALUE_COLUMNS if c == column and k == line]
        style = _NUMBER if line == 0 else f"{_NUMBER};{_GREY}"
        if found:
            field = found[0]
            tip = next(t for f, _, _, t in VALUE_COLUMNS if f == field)
            cells.append(
                f'<td data-field="{field}" title="{tip}" style="{style}">{values[field]}</td>'
            )
        else:
            cells.append(f'<td style="{style}"></td>')
    kind = "values" if line == 0 else "set"
    return f'<tr data-axis="{name}" data-line="{kind}">{first}{"".join(cells)}</tr>'


def _lamp_line(name: str, view: AxisView) -> str:
    """The status word under the values: each lamp with its label at a fixed place."""
    word, note = status_word(view), _window_note(view)
    lamps = "".join(
        f'<div data-field="{field}" title="{tip}{note if field == "in_position" else ""}"'
        f' style="white-space:nowrap;overflow:hidden">'
        f"{lamp_dot(word[field], LAMP_KINDS.get(field, 'on_info'))}"
        f'<span style="{_GREY};font-size:0.85em;margin-left:0.1em">{label}</span></div>'
        for field, label, tip in LAMPS
    )
    return (
        f'<tr data-axis="{name}" data-line="lamps"><td colspan="{1 + len(COLUMNS)}"'
        f' style="padding:0.1em 0.2em 0 0.2em"><div style="display:grid;'
        f'grid-template-columns:repeat({len(LAMPS)},1fr)">{lamps}</div></td></tr>'
    )


def _row(view: AxisView, fe_suffix: bool) -> str:
    """The lines of one axis: values, set points, status word and error text."""
    name = html.escape(view.name)
    values = _values(view, fe_suffix)
    first = (
        f'<td data-field="name" rowspan="2" style="{_CELL};vertical-align:top"><b>{name}</b>'
        f' <span data-field="unit" style="{_GREY};display:block">'
        f"{html.escape(view.unit)}</span></td>"
    )
    text = _error_text(view)
    line = ERROR_LINES * 1.3
    error = (
        f'<tr data-axis="{name}" data-line="error"><td colspan="{1 + len(COLUMNS)}"'
        f' style="padding:0 0.3em 0.2em 0.3em;{_RULE}">'
        f'<div data-field="error_text" title="{html.escape(text)}" style="height:{line}em;'
        f"line-height:1.3em;overflow:hidden;overflow-wrap:anywhere;display:-webkit-box;"
        f"-webkit-box-orient:vertical;-webkit-line-clamp:{ERROR_LINES};color:#c62828;"
        f'font-size:0.95em">{html.escape(text)}</div></td></tr>'
    )
    return (
        _value_line(name, 0, values, first)
        + _value_line(name, 1, values, "")
        + _lamp_line(name, view)
        + error
    )


def _window_note(view: AxisView) -> str:
    """The in-position window in the lamp's tooltip (``" (±5.0 µm)"``)."""
    factor, unit, decimals = fe_scale(view.unit)
    return f" (±{view.in_position_window * factor:.{decimals}f} {html.escape(unit)})"


def name_width(views: list[AxisView]) -> float:
    """The width of the axis name column [em]: the longest name or unit (under the name),
    whole."""
    longest = max((max(len(v.name), len(v.unit)) for v in views), default=0)
    return max(NAME_WIDTH, CHAR_WIDTH * longest + 0.4)


def _header(label: str, unit: str, units: set[str]) -> str:
    """A value column's unit: ``u`` replaced by the axes' one unit (empty for several)."""
    if "u" not in unit:
        return unit
    if len(units) == 1:
        return unit.replace("[u", f"[{html.escape(next(iter(units)))}")
    return ""


def _fe_units(views: list[AxisView]) -> set[str]:
    """The units the axes' following errors are shown in."""
    return {fe_scale(v.unit)[1] for v in views}


def _head(views: list[AxisView]) -> tuple[str, float]:
    """The column widths and the header row; the table's width [em]."""
    fe_units = _fe_units(views)
    suffix_width = 0.0 if len(fe_units) == 1 else 0.45 * max(len(u) for u in fe_units) + 0.3
    widths = [name_width(views), *(w for _, _, _, w in COLUMNS)]
    widths[3] += suffix_width
    units = {v.unit for v in views}
    columns = "".join(f'<col style="width:{w:.2f}em">' for w in widths)
    header = '<th style="text-align:left" title="axis and its unit u">Axis</th>'
    for label, unit, lines, _ in COLUMNS:
        shown = _header(label, unit, units)
        if label == "FE" and len(fe_units) == 1:
            shown = f"[{html.escape(next(iter(fe_units)))}]"
        header += (
            f'<th title="{label} {lines}" style="text-align:right;padding:0 0.2em">'
            f'{label} {shown}<div style="font-weight:normal;white-space:nowrap;{_GREY}">'
            f"{lines}</div></th>"
        )
    return f"<colgroup>{columns}</colgroup><tr>{header}</tr>", max(
        sum(widths), LAMP_WIDTH * len(LAMPS)
    )


def overview_html(snapshot: Snapshot) -> str:
    """The overview table of every axis of ``snapshot`` (texts escaped)."""
    views = list(snapshot.axes.values())
    head, width = _head(views)
    fe_suffix = len(_fe_units(views)) > 1
    rows = "".join(_row(view, fe_suffix) for view in views)
    return (
        '<div style="overflow-x:auto;padding:0 0.5em">'
        f'<table data-overview="axes" style="table-layout:fixed;width:100%;min-width:{width:.1f}em;'
        f'border-collapse:collapse;font-size:0.72em">'
        f'<thead style="font-size:0.9em;color:#455a64;vertical-align:bottom;{_RULE}">'
        f"{head}</thead><tbody>{rows}</tbody></table></div>"
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

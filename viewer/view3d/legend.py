"""What every colour of the 3-D view means: the machine's bodies, the switch lamps, the dogs and
stops, the overlays and the axis marks, as rows of a legend (:func:`legend_rows`) shown in the
View folder (:func:`legend_html`) and, for one body, when a page clicks it (:func:`body_row`).

A body's description is the model's custom text ``<body>_about`` (the static frame of a machine,
the body ``<machine>/`` that attaching it creates, reads ``<machine>/about``); a body without one
is described by the joint that moves it. The switch, dog and stop rows follow the geom names of
models/README.md (``<axis>_<kind>_geom``, ``<axis>_<kind>_cam_geom``, ``<axis>_stop_*``).
"""

from __future__ import annotations

__all__ = [
    "ERROR_TINT",
    "LAMP_LIMIT",
    "LAMP_REF",
    "MARKINGS",
    "SWITCHES",
    "LegendRow",
    "Rgb",
    "body_row",
    "body_rows",
    "legend_html",
    "legend_rows",
    "marking_rows",
    "overlay_rows",
]

import html
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from viewer.view3d.axis_marks import MARK_COLOR
from viewer.view3d.overlays import CONSTRAINT_COLOR, CONTACT_COLOR, GHOST_COLOR

Rgb = tuple[int, int, int]
"""Colour: red, green, blue in [0, 255]."""

LAMP_LIMIT = (0.95, 0.15, 0.10)
"""Colour of an actuated limit switch (red), RGB in [0, 1]."""

LAMP_REF = (1.0, 0.72, 0.0)
"""Colour of an actuated reference switch (amber), RGB in [0, 1]."""

SWITCHES = (("lim_neg", LAMP_LIMIT), ("lim_pos", LAMP_LIMIT), ("ref", LAMP_REF))
"""Switch kinds of models/README.md and their lamp colours."""

ERROR_TINT = (1.0, 0.05, 0.05)
"""Tint of the parts an axis in error moves (red), RGB in [0, 1]."""


@dataclass(frozen=True, slots=True)
class LegendRow:
    """One entry of the legend.

    Attributes:
        part: What is drawn (``"gantry/bridge"``, ``"LIM switch, actuated"``).
        color: Its colour (RGB in [0, 255]); None: the machine's own colours.
        role: What it is and does.
        body: The body id of a body's row (None: not a body).
    """

    part: str
    color: Rgb | None
    role: str
    body: int | None = None


def _rgb(color: tuple[float, ...] | np.ndarray) -> Rgb:
    """An RGB in [0, 1] (or a model rgba) as integers in [0, 255]."""
    r, g, b = (min(255, max(0, round(float(c) * 255.0))) for c in color[:3])
    return (r, g, b)


def _text(model: mujoco.MjModel, name: str) -> str:
    """The model's custom text ``name`` ("" if it has none)."""
    t = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, name)
    if t < 0:
        return ""
    adr, size = int(model.text_adr[t]), int(model.text_size[t])
    data = model.text_data[adr : adr + size]
    raw = data.tobytes() if isinstance(data, np.ndarray) else bytes(data)
    return raw.split(b"\0", 1)[0].decode("utf-8", "replace")


def _moved_by(model: mujoco.MjModel, body: int, axes: Mapping[str, str]) -> str:
    """How a body without a description moves: by the joints of its own chain."""
    names = []
    b = body
    while b > 0:
        for j in np.flatnonzero(np.asarray(model.jnt_bodyid) == b):
            joint = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, int(j)) or f"joint{j}"
            names.append(f"axis {axes[joint]}" if joint in axes else f"joint {joint}")
        b = int(model.body_parentid[b])
    return "moved by " + ", ".join(names) if names else "static"


def _main_color(model: mujoco.MjModel, body: int) -> Rgb | None:
    """Colour of the body's largest visible geom (planes aside)."""
    geoms = [
        g
        for g in np.flatnonzero(np.asarray(model.geom_bodyid) == body)
        if model.geom_rgba[g, 3] > 0 and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE
    ]
    if not geoms:
        return None
    largest = max(geoms, key=lambda g: float(model.geom_rbound[g]))
    return _rgb(model.geom_rgba[largest])


def body_rows(model: mujoco.MjModel, axes: Mapping[str, str]) -> list[LegendRow]:
    """One row per body that owns a geom: its name, main colour and description.

    Args:
        model: The compiled model.
        axes: Axis name by joint name (the axes of the scene).
    """
    with_geoms = {int(b) for b in np.asarray(model.geom_bodyid)}
    rows = []
    for b in sorted(with_geoms):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"
        frame = name.endswith("/")
        about = _text(model, f"{name}about" if frame else f"{name}_about")
        role = about or ("static frame" if frame else _moved_by(model, b, axes))
        part = f"{name} (frame)" if frame else name
        rows.append(LegendRow(part, _main_color(model, b), role, body=b))
    return rows


MARKINGS = (
    (("_lim_neg_geom", "_lim_pos_geom"), "LIM switch", "limit switch LIM− / LIM+, off", None),
    (("_lim_neg_geom", "_lim_pos_geom"), "LIM switch lit", "a limit switch is on", LAMP_LIMIT),
    (("_ref_geom",), "REF switch", "reference switch, off", None),
    (("_ref_geom",), "REF switch lit", "the reference switch is on", LAMP_REF),
    (("_cam_geom",), "dog", "switch dog (cam) on the moving part: on over it", None),
)
"""Switch and dog rows: geom name endings, part, role, lamp colour (None: the geom's own)."""


def marking_rows(model: mujoco.MjModel) -> list[LegendRow]:
    """The switches, lamps, dogs and hard-stop blocks the model has (by their geom names)."""
    names = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or "" for g in range(model.ngeom)
    ]
    rows = []
    for endings, part, role, lamp in MARKINGS:
        found = [g for g, n in enumerate(names) if n.endswith(endings)]
        if found:
            color = _rgb(lamp) if lamp is not None else _rgb(model.geom_rgba[found[0]])
            rows.append(LegendRow(part, color, role))
    stops = [g for g, n in enumerate(names) if "_stop_" in n.rsplit("/", 1)[-1]]
    if stops:
        role = "hard-stop block (drawn; the joint's range is the physics)"
        rows.append(LegendRow("hard stop", _rgb(model.geom_rgba[stops[0]]), role))
    return rows


def overlay_rows() -> list[LegendRow]:
    """The marks the viewer draws over the machine."""
    return [
        LegendRow("axis mark", MARK_COLOR, "axis name and positive direction (View: Axis labels)"),
        LegendRow(
            "axis in error",
            _rgb(ERROR_TINT),
            "the parts its joint moves tinted red, its arrow red, its label ⚠ with the error",
        ),
        LegendRow("set-point ghost", _rgb(GHOST_COLOR), "moving parts at the axes' set points"),
        LegendRow("contact force", CONTACT_COLOR, "point and normal force of a contact"),
        LegendRow("stop / tendon force", CONSTRAINT_COLOR, "hard stop or loaded tendon, in N"),
    ]


def legend_rows(model: mujoco.MjModel, axes: Mapping[str, str]) -> list[LegendRow]:
    """Every row of the legend: bodies, switches and stops, overlays.

    Args:
        model: The compiled model.
        axes: Axis name by joint name (the axes of the scene).
    """
    return body_rows(model, axes) + marking_rows(model) + overlay_rows()


def body_row(rows: list[LegendRow], body: int) -> LegendRow | None:
    """The row of body ``body`` (None: the legend has none)."""
    return next((row for row in rows if row.body == body), None)


def legend_html(rows: list[LegendRow]) -> str:
    """The legend as an HTML table: a colour swatch, the part, its role."""
    lines = ['<table style="font-size:0.8em;border-collapse:collapse">']
    for row in rows:
        swatch = ""
        if row.color is not None:
            r, g, b = row.color
            swatch = (
                f'<span style="display:inline-block;width:0.9em;height:0.9em;'
                f'background:rgb({r},{g},{b});border:1px solid #888"></span>'
            )
        lines.append(
            f'<tr><td style="padding:1px 4px">{swatch}</td>'
            f'<td style="padding:1px 4px"><b>{html.escape(row.part)}</b></td>'
            f'<td style="padding:1px 4px">{html.escape(row.role)}</td></tr>'
        )
    lines.append("</table>")
    return "\n".join(lines)

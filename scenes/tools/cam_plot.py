"""Plots of a cam table: slave position, velocity (slope ds/dm) and acceleration (curvature
d²s/dm²) against the master over one period, segment boundaries and laws marked, as PNG.

``python -m scenes cam table.csv`` plots a table file (:func:`read_table`); ``python -m scenes
cam --cut-length 600 --circumference 1000 --blades 1 --sync-angle 30`` the cam of
``mcl.rotary_knife`` for those arguments. A table file is CSV: a header line naming the columns
``master, slave`` and optionally ``velocity, acceleration, law``, then one point per line; an
empty velocity or acceleration is not given (NaN), the law is a ``CamLaw`` name or number (empty:
Linear), lines starting with ``#`` are comments.
"""

from __future__ import annotations

__all__ = ["COLUMNS", "EXPECTED", "checked", "figure", "knife_table", "plot_cam", "read_table"]

from mcl.extras import require

require("scenes.tools.cam_plot", "plot")

import csv
import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display

import matplotlib.pyplot as plt

import mcl
from mcl.cam_table import Cam, CamLaw, MC_CamPoint, compile_cam, knife_problem
from scenes.errors import UserError

COLUMNS = ("master", "slave", "velocity", "acceleration", "law")
"""The columns of a table file, the first two required."""

EXPECTED = (
    "a CSV cam table: a header 'master,slave[,velocity,acceleration,law]', then one point a "
    "line (law: " + ", ".join(law.name for law in CamLaw) + ")"
)


def read_table(path: str | Path) -> tuple[mcl.MC_CAM_REF, list[int]]:
    """The cam table of a table file and the file line of each point.

    Raises:
        UserError: a missing or malformed file (one line: file:line, what, what is expected).
    """
    path = Path(path)
    if not path.is_file():
        raise UserError.at(str(path), "", "no such file", f"{EXPECTED}, relative to {Path.cwd()}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise UserError.at(str(path), "", f"not readable ({error})", EXPECTED) from None
    lines = [
        (number, row)
        for number, row in enumerate(csv.reader(text.splitlines()), start=1)
        if row and any(cell.strip() for cell in row) and not row[0].lstrip().startswith("#")
    ]
    if not lines:
        raise UserError.at(str(path), "", "no header and no points", EXPECTED)
    number, header = lines[0]
    names = [cell.strip().lower() for cell in header]
    if names[:2] != ["master", "slave"] or any(n not in COLUMNS for n in names):
        raise UserError.at(f"{path}:{number}", "", f"the header is {header}", EXPECTED)
    points: list[MC_CamPoint] = []
    numbers: list[int] = []
    for number, row in lines[1:]:
        where = f"{path}:{number}"
        if len(row) > len(names):
            raise UserError.at(where, "", f"{len(row)} values for {len(names)} columns", EXPECTED)
        cells = dict(zip(names, (cell.strip() for cell in row), strict=False))
        values = {n: _number(where, n, cells.get(n, "")) for n in COLUMNS[:4]}
        for n in ("master", "slave"):
            if math.isnan(values[n]):
                raise UserError.at(where, n, "missing", "a finite number")
        law = _law(where, cells.get("law", ""))
        points.append(
            MC_CamPoint(
                values["master"], values["slave"], values["velocity"], values["acceleration"], law
            )
        )
        numbers.append(number)
    return mcl.MC_CAM_REF(Points=points, Name=path.stem), numbers


def _number(where: str, column: str, cell: str) -> float:
    if not cell:
        return math.nan
    try:
        value = float(cell)
    except ValueError:
        raise UserError.at(where, column, f"{cell!r} is not a number", "a number") from None
    if not math.isfinite(value):
        raise UserError.at(where, column, f"{cell!r}", "a finite number (empty: not given)")
    return value


def _law(where: str, cell: str) -> int:
    if not cell:
        return CamLaw.Linear
    by_name = {law.name.lower(): law for law in CamLaw}
    if cell.lower() in by_name:
        return by_name[cell.lower()]
    if cell.isdigit() and int(cell) in tuple(CamLaw):
        return int(cell)
    names = ", ".join(f"{law.name} ({law.value})" for law in CamLaw)
    raise UserError.at(where, "law", f"{cell!r} is not a cam law", names)


def knife_table(
    cut_length: float, circumference: float, blades: int, sync_angle: float, law: str
) -> mcl.MC_CAM_REF:
    """The cam of ``mcl.rotary_knife`` for these arguments.

    Raises:
        UserError: arguments the drum cannot cut with (one line: the arguments, why)."""
    chosen = _law("--law", law)
    problem = knife_problem(cut_length, circumference, blades, sync_angle, chosen)
    if problem:
        arguments = (
            f"--cut-length {cut_length:g} --circumference {circumference:g} "
            f"--blades {blades} --sync-angle {sync_angle:g} --law {law}"
        )
        raise UserError.at(arguments, "", problem, "a cut the drum can make")
    return mcl.rotary_knife(cut_length, circumference, blades, sync_angle, chosen)


def checked(table: mcl.MC_CAM_REF, periodic: bool, source: str, lines: list[int]) -> Cam:
    """The checked cam of ``table`` (as MC_CamTableSelect checks it).

    Raises:
        UserError: why the table is refused, at the file line of the point or segment named
            (``source``: the file, ``lines``: the line of each point)."""
    cam = compile_cam(table, periodic)
    if isinstance(cam, Cam):
        return cam
    found = re.match(r"(point|segment) (\d+)", cam)
    where = source
    if found and int(found.group(2)) < len(lines):
        where = f"{source}:{lines[int(found.group(2))]}"
    elif "period boundary" in cam and lines:
        where = f"{source}:{lines[-1]}"
    raise UserError.at(where, "", cam, "a table MC_CamTableSelect accepts (docs/reference.md)")


def figure(profile: mcl.CamProfile, title: str) -> plt.Figure:
    """Position, velocity and acceleration against the master, one panel each, the segment
    boundaries dotted and each segment's law written in the top panel."""
    fig, panels = plt.subplots(3, 1, sharex=True, figsize=(9, 7.5), layout="constrained")
    rows = (
        (profile.slave, "slave [u]"),
        (profile.velocity, "velocity ds/dm [u/u]"),
        (profile.acceleration, "acceleration d²s/dm² [u/u²]"),
    )
    for panel, (values, label) in zip(panels, rows, strict=True):
        panel.plot(profile.master, values, color="C0")
        panel.set_ylabel(label)
        panel.grid(True, alpha=0.3)
        for m in profile.points:
            panel.axvline(m, color="0.6", linestyle=":", linewidth=0.8)
    top = panels[0]
    for k, law in enumerate(profile.laws):
        middle = 0.5 * (profile.points[k] + profile.points[k + 1])
        top.annotate(
            law,
            (middle, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(0, 2),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize="x-small",
            color="0.3",
        )
    panels[-1].set_xlabel("master [u] (table coordinate)")
    kind = "periodic" if profile.periodic else "not periodic"
    fig.suptitle(
        f"{title}\n{kind}, period {profile.period:g}, rise {profile.rise:g}, "
        f"{len(profile.laws)} segments",
        fontsize="medium",
    )
    return fig


def plot_cam(table: mcl.MC_CAM_REF, cam: Cam, out: str | Path) -> Path:
    """Write the profile of the checked ``cam`` of ``table`` as ``<out>.png``; returns the
    path."""
    fig = figure(mcl.cam_profile(cam), table.Name or Path(out).stem)
    path = Path(out).with_suffix(".png")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

"""Benchmark: arcs and paths of an axes group.

Prints JSON:

- ``commanded_radius_error``: per CircMode, a full circle of R = 50 mm commanded on simulated
  axes (CENTER: one arc with its end on its start; BORDER and RADIUS, which cannot describe a
  full circle: two half circles, Buffered), the largest relative deviation of the set point
  from the radius over every servo cycle (goal: ≤ 1e-9);
- ``gantry_circle_R50``: a full circle of R = 50 mm on the gantry's physics (X, Y) at F1000,
  F3000 and F5000, counter-clockwise: the largest and mean radial deviation of the `tool` site
  [µm], and the time it took;
- ``gantry_gcode_contour_F3000``: the G-code contour of tests/scenes/test_gantry_arcs.py (lines
  and arcs, tangent and non-tangent corners): the tool's and the encoders' largest distance from
  the commanded lines and arcs [µm] (corner tolerance 20 µm).

Run: ``python -m tests.benchmarks.arcs``.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

import mcl
from tests.helpers import make_machine
from tests.mcl.test_group import build_group, record
from tests.scenes.test_gantry_arcs import CONTOUR, contour_pieces, run_on_gantry

RADIUS = 50.0
CENTER, BORDER, RADIUS_MODE = (
    mcl.MC_CIRC_MODE.CENTER,
    mcl.MC_CIRC_MODE.BORDER,
    mcl.MC_CIRC_MODE.RADIUS,
)
CCW = mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
DYNAMICS = dict(Velocity=100.0, Acceleration=2000.0, Deceleration=2000.0, Jerk=50000.0)


def _circle_blocks(group: mcl.AxesGroup, mode: int) -> list[mcl.MC_MoveCircularAbsolute]:
    """The blocks of a full circle of RADIUS about (RADIUS, 0) from (0, 0) in ``mode``."""
    far = [2.0 * RADIUS, 0.0]
    if mode == CENTER:
        specs: list[dict[str, Any]] = [dict(AuxPoint=[RADIUS, 0.0], EndPoint=[0.0, 0.0])]
    elif mode == BORDER:
        specs = [
            dict(AuxPoint=[RADIUS, -RADIUS], EndPoint=far),
            dict(AuxPoint=[RADIUS, RADIUS], EndPoint=[0.0, 0.0]),
        ]
    else:
        specs = [
            dict(AuxPoint=[RADIUS], EndPoint=far),
            dict(AuxPoint=[RADIUS], EndPoint=[0.0, 0.0]),
        ]
    return [
        mcl.MC_MoveCircularAbsolute(
            AxesGroup=group,
            CircMode=mode,
            PathChoice=CCW,
            BufferMode=mcl.MC_BufferMode.Buffered,
            **spec,
            **DYNAMICS,
        )
        for spec in specs
    ]


def commanded_radius_error() -> dict[str, float]:
    """The set point's largest relative radius error over a full circle, per CircMode."""
    out: dict[str, float] = {}
    for mode in (BORDER, CENTER, RADIUS_MODE):
        machine = make_machine("XY")
        group = build_group(machine, "XY")
        rec = record(machine, "XY")
        blocks = _circle_blocks(group, mode)

        def program(blocks: list[mcl.MC_MoveCircularAbsolute] = blocks) -> None:
            for block in blocks:
                block(Execute=True)

        machine.run(program, until=lambda: blocks[-1].Done, timeout=20.0)  # noqa: B023
        errors = [abs(math.dist(p, (RADIUS, 0.0)) - RADIUS) / RADIUS for p in rec.model]
        out[mode.name] = float(f"{max(errors):.3g}")
    return out


def gantry_circles() -> dict[str, dict[str, float]]:
    """Full circles of R = 50 mm on the gantry at three feeds."""
    out: dict[str, dict[str, float]] = {}
    for feed in (1000.0, 3000.0, 5000.0):
        block = mcl.MC_MoveCircularRelative(
            CircMode=CENTER,
            AuxPoint=[RADIUS, 0.0],
            EndPoint=[0.0, 0.0],
            PathChoice=CCW,
            Velocity=feed / 60.0,
            Acceleration=2000.0,
            Deceleration=2000.0,
            Jerk=20000.0,
        )
        points, _, _ = run_on_gantry(block)
        deviation = np.abs(np.linalg.norm(points - np.array([RADIUS, 0.0]), axis=1) - RADIUS)
        out[f"F{feed:g}"] = {
            "radial_deviation_max_um": round(float(deviation.max()) * 1e3, 2),
            "radial_deviation_mean_um": round(float(deviation.mean()) * 1e3, 2),
            "duration_s": round(len(points) * 0.001, 3),
        }
    return out


def gantry_contour() -> dict[str, float]:
    """The G-code contour at F3000 on the gantry."""
    select = mcl.MC_PathSelect(PathDescription=CONTOUR)
    select(Execute=True)
    points, encoders, _ = run_on_gantry(mcl.MC_MovePath(PathData=select.PathData))
    pieces = contour_pieces()
    tool = max(min(g.distance(p) for g in pieces) for p in points)
    feedback = max(min(g.distance(p) for g in pieces) for p in encoders)
    return {
        "tool_max_um": round(tool * 1e3, 2),
        "encoders_max_um": round(feedback * 1e3, 2),
        "corner_tolerance_um": 20.0,
    }


def main() -> None:
    """Print the benchmark as JSON."""
    report = {
        "commanded_radius_error": commanded_radius_error(),
        "gantry_circle_R50": gantry_circles(),
        "gantry_gcode_contour_F3000": gantry_contour(),
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()

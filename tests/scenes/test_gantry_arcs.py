"""Arcs and paths on the gantry's physics: X and Y in a group, a full circle
(MC_MoveCircularRelative) and a G-code contour of lines and arcs (MC_PathSelect + MC_MovePath),
measured at the `tool` site against the commanded path."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import mcl
from mcl.geometry import Geometry, Line, arc
from scenes.machines import gantry
from scenes.tools.grouping import PoweredGroup

CENTER = mcl.MC_CIRC_MODE.CENTER
CCW = mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
CIRCLE_LIMIT = 10e-6
"""Largest radial deviation of the tool from a 50 mm circle at F3000 [m] (measured ≈ 5 µm)."""
CONTOUR_LIMIT = 20e-6
"""Largest distance of the tool from the contour of lines and arcs at F3000 [m]."""
CONTOUR = """(a slot with rounded ends and a pocket corner, incremental)
G21 G91 G17
G01 X40 F3000
G03 X0 Y20 R10
G01 X-40
G03 X0 Y-20 I0 J-10
G01 X20 Y-10
G02 X10 Y10 I0 J10
"""
"""A contour of lines and arcs from where the tool stands [mm]: tangent and non-tangent
corners, arcs given by radius and by centre, both directions."""


def contour_pieces() -> list[Geometry]:
    """The contour in millimetres from (0, 0)."""
    return [
        Line([0.0, 0.0], [40.0, 0.0]),
        arc([40.0, 0.0], mcl.MC_CIRC_MODE.RADIUS, [10.0, 0.0], [40.0, 20.0], CCW),
        Line([40.0, 20.0], [0.0, 20.0]),
        arc([0.0, 20.0], CENTER, [0.0, 10.0], [0.0, 0.0], CCW),
        Line([0.0, 0.0], [20.0, -10.0]),
        arc([20.0, -10.0], CENTER, [20.0, 0.0], [30.0, 0.0], mcl.MC_CIRC_PATHCHOICE.CLOCKWISE),
    ]


def run_on_gantry(block: Any, tolerance: float = 0.02) -> tuple[np.ndarray, np.ndarray, Any]:
    """Power X and Y of a gantry, group them, run ``block`` (connected to the group by this
    function) and record the tool site every servo cycle.

    Returns:
        The tool's positions while the block ran, relative to its start [mm] (x, y), the
        members' actual positions relative to their start [mm], and the scene.
    """
    scene = gantry.build(start={"X": 0.5, "Y": 0.3, "Z": -0.1}, trace_every=0)
    axes = [scene.axes["X"], scene.axes["Y"]]
    grouped = PoweredGroup(axes, "xy", tolerance)
    group, enable = grouped.group, grouped.enable
    block.AxesGroup = group
    go = [False]

    def program() -> None:
        grouped()
        block(Execute=go[0])
        assert not block.Error, block.ErrorID

    scene.run(program, until=lambda: enable.Done, timeout=2.0)
    scene.run(program, timeout=0.2)  # settle
    site = scene.model.site("gantry/tool").id
    start = scene.data.site_xpos[site].copy()
    origin = np.array([a.actual for a in axes])
    tool: list[np.ndarray] = []
    encoders: list[np.ndarray] = []

    def observe(t: float) -> None:
        tool.append(scene.data.site_xpos[site].copy())
        encoders.append(np.array([a.actual for a in axes]))

    go[0] = True
    scene.runtime.observers.append(observe)
    scene.run(program, until=lambda: block.Done, timeout=30.0)
    scene.run(program, timeout=0.1)
    points = (np.array(tool) - start)[:, :2] * 1000.0
    return points, np.array(encoders) - origin, scene


def test_a_circle_on_the_gantry_stays_on_its_radius() -> None:
    """A full circle of R = 50 mm at F3000 (CENTER, counter-clockwise): the tool (the physics'
    site) stays within 10 µm of the radius all the way round and ends where it started."""
    block = mcl.MC_MoveCircularRelative(
        CircMode=CENTER,
        AuxPoint=[50.0, 0.0],
        EndPoint=[0.0, 0.0],
        PathChoice=CCW,
        Velocity=50.0,
        Acceleration=2000.0,
        Deceleration=2000.0,
        Jerk=20000.0,
    )
    points, _, _ = run_on_gantry(block)
    radius = np.linalg.norm(points - np.array([50.0, 0.0]), axis=1)
    deviation = np.abs(radius - 50.0) * 1e-3  # m
    print(f"circle R50 F3000: radial deviation {deviation.max() * 1e6:.2f} µm")
    assert deviation.max() < CIRCLE_LIMIT
    angles = np.unwrap(np.arctan2(points[:, 1], points[:, 0] - 50.0))
    assert angles[-1] - angles[0] == pytest.approx(2 * math.pi, abs=1e-3)
    assert np.linalg.norm(points[-1]) < 0.005


def test_a_gcode_contour_on_the_gantry_stays_on_the_path() -> None:
    """The contour of CONTOUR at F3000, read by MC_PathSelect and run by MC_MovePath: the tool
    stays within 20 µm of its lines and arcs (the corners blended within the group's 20 µm
    corner tolerance), the encoders within the same, and it ends at the contour's end."""
    select = mcl.MC_PathSelect(PathDescription=CONTOUR)
    select(Execute=True)
    assert select.Done, select.ErrorText
    block = mcl.MC_MovePath(PathData=select.PathData)
    points, encoders, _ = run_on_gantry(block)
    pieces = contour_pieces()
    tool = max(min(g.distance(p) for g in pieces) for p in points) * 1e-3
    feedback = max(min(g.distance(p) for g in pieces) for p in encoders) * 1e-3
    print(f"G-code contour F3000: tool {tool * 1e6:.2f} µm, encoders {feedback * 1e6:.2f} µm")
    assert tool < CONTOUR_LIMIT
    assert feedback < CONTOUR_LIMIT
    assert points[-1] == pytest.approx([30.0, 0.0], abs=0.005)

"""A feed hold on the gantry's physics: X and Y in a group run a full circle, MC_GroupInterrupt
holds it in the middle of the arc and MC_GroupContinue resumes it; the tool (the physics' site)
and the joints are measured against the circle and the held point."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mcl
from scenes.machines import gantry
from scenes.tools.grouping import PoweredGroup

RADIUS = 50.0
"""The circle's radius [mm] (centre 50 mm in +X of the start)."""
CIRCLE_LIMIT = 10e-6
"""Largest radial deviation of the tool from the circle, the hold included [m]."""
RESUME_LIMIT = 10e-6
"""Largest distance of the joints' point from the interrupted path point when the path goes on,
and of one servo cycle's step there [m]."""


def test_interrupt_and_continue_mid_arc_on_the_gantry() -> None:
    """The tool slows down on the circle, stands at the held point while held (the joints
    still), goes on from there and the circle ends where it started."""
    scene = gantry.build(start={"X": 0.5, "Y": 0.3, "Z": -0.1}, trace_every=0)
    axes = [scene.axes["X"], scene.axes["Y"]]
    grouped = PoweredGroup(axes, "xy", 0.02)
    group, enable = grouped.group, grouped.enable
    circle = mcl.MC_MoveCircularRelative(
        AxesGroup=group,
        CircMode=mcl.MC_CIRC_MODE.CENTER,
        AuxPoint=[RADIUS, 0.0],
        EndPoint=[0.0, 0.0],
        PathChoice=mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE,
        Velocity=50.0,
        Acceleration=2000.0,
        Deceleration=2000.0,
        Jerk=20000.0,
    )
    hold = mcl.MC_GroupInterrupt(AxesGroup=group, Deceleration=500.0, Jerk=10000.0)
    proceed = mcl.MC_GroupContinue(AxesGroup=group)
    flags = {"go": False, "hold": False, "continue": False}

    def program() -> None:
        grouped()
        circle(Execute=flags["go"])
        hold(Execute=flags["hold"])
        proceed(Execute=flags["continue"])
        for block in (circle, hold, proceed):
            assert not block.Error, block.ErrorID

    scene.run(program, until=lambda: enable.Done, timeout=2.0)
    scene.run(program, timeout=0.2)  # settle
    site = scene.model.site("gantry/tool").id
    joints = [scene.model.joint(name).qposadr[0] for name in ("gantry/X", "gantry/Y")]
    start = scene.data.site_xpos[site].copy()
    origin = np.array([a.actual for a in axes])
    q0 = scene.data.qpos[joints].copy()
    tool: list[np.ndarray] = []
    joint_points: list[np.ndarray] = []

    def observe(t: float) -> None:
        tool.append((scene.data.site_xpos[site] - start)[:2] * 1000.0)
        joint_points.append((scene.data.qpos[joints] - q0) * 1000.0)

    scene.runtime.observers.append(observe)
    flags["go"] = True
    scene.run(program, timeout=2.0)  # a third of the circle
    flags["hold"] = True
    scene.run(program, until=lambda: hold.Done, timeout=2.0)
    assert circle.Busy and circle.Active and not circle.CommandAborted
    held = np.array([a.sp_pos for a in axes]) - origin  # the interrupted path point [mm]
    scene.run(program, timeout=0.8)  # the hold
    held_joints = joint_points[-1]
    flags["hold"] = False
    flags["continue"] = True
    resumed = len(joint_points)
    scene.run(program, until=lambda: circle.Done, timeout=20.0)
    scene.run(program, timeout=0.1)
    moved = next(
        i
        for i in range(resumed, len(joint_points))
        if np.linalg.norm(joint_points[i] - held_joints) > 1e-3
    )
    resume_point = joint_points[moved - 1]  # where the joints stood when the path went on
    points = np.array(tool)
    radial = np.abs(np.linalg.norm(points - np.array([RADIUS, 0.0]), axis=1) - RADIUS) * 1e-3
    off = np.linalg.norm(resume_point - held) * 1e-3
    print(
        f"feed hold R50: radial {radial.max() * 1e6:.2f} µm, resumed {off * 1e6:.2f} µm from "
        f"the interrupted point (joints)"
    )
    assert radial.max() < CIRCLE_LIMIT
    assert off < RESUME_LIMIT
    assert np.linalg.norm(joint_points[moved] - resume_point) * 1e-3 < RESUME_LIMIT  # no jump
    angles = np.unwrap(np.arctan2(points[:, 1], points[:, 0] - RADIUS))
    assert angles[-1] - angles[0] == pytest.approx(2 * math.pi, abs=1e-3)
    assert np.linalg.norm(points[-1]) < 0.005

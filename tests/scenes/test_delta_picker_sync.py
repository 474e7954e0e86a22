"""The delta picker on the physics with MC_MovePathSynchronized: a line across the belt whose
progress is the running belt's position; the cup's face (the model's site, not the set points)
advances 0.4 mm per mm of belt between the path's ramps, stays on the line and ends on its end."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

import mcl
import scenes
from scenes.machines.delta_picker import PICK

TOOL = "delta_picker/tool"


def scan(*blocks: mcl.MotionFB) -> Callable[[], None]:
    """A scan that calls each block with Execute TRUE."""

    def program() -> None:
        for block in blocks:
            block(Execute=True)

    return program


RATIO = 0.4
"""Millimetres of path per millimetre of belt."""


def test_a_path_synchronized_to_the_belt_moves_the_cup_with_the_belt() -> None:
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.step == "over the belt", timeout=10.0)
    group = program.group  # type: ignore[attr-defined]
    belt = program.belt  # type: ignore[attr-defined]
    start = [PICK[0], PICK[1], PICK[2] + 25.0]
    over = mcl.MC_MoveLinearAbsolute(
        AxesGroup=group, Position=start, Velocity=2000.0, Acceleration=20000.0, Jerk=1.0e6
    )
    run = mcl.MC_MoveVelocity(Axis=belt, Velocity=250.0, Acceleration=2000.0)
    scene.run(scan(over, run), until=lambda: over.Done and run.InVelocity, timeout=1.0)
    scene.run(scan(over, run), timeout=0.1)  # the arms settle
    end = [start[0], start[1] + 100.0, start[2]]  # across the belt
    path = mcl.MC_MovePathSynchronized(
        AxesGroup=group, Master=belt, Position=end, MasterStart=belt.sp_pos + 10.0, Ratio=RATIO
    )
    model, data = scene.model, scene.data
    tool = model.site(TOOL).id
    offset = np.array([0.0, 0.0, 1600.0 - 50.0])  # the MCS origin and the cup's face below it
    a, b = np.array(start) + offset, np.array(end) + offset
    u = (b - a) / np.linalg.norm(b - a)
    origin = belt.sp_pos + 10.0
    samples: list[tuple[float, float, float]] = []

    def sample() -> None:
        run(Execute=True)
        path(Execute=True)
        p = 1000.0 * data.site_xpos[tool]
        along = float((p - a) @ u)
        off = float(np.linalg.norm(p - (a + along * u)))
        samples.append((belt.actual - origin, along, off))

    scene.run(sample, until=lambda: path.Done or path.Error, timeout=3.0)
    assert path.Done, path.ErrorID
    scene.run(sample, timeout=0.2)
    middle = [(x, s) for x, s, _ in samples if 40.0 < s < 60.0]
    (x0, s0), (x1, s1) = middle[0], middle[-1]
    slope = (s1 - s0) / (x1 - x0)
    worst = max(off for _, _, off in samples)
    print(f"synchronized path: {slope:.4f} mm per mm of belt, worst {worst:.3f} mm off the line")
    assert abs(slope - RATIO) < 0.01 * RATIO  # the cup moves with the belt
    assert worst < 0.5
    assert np.linalg.norm(1000.0 * data.site_xpos[tool] - b) < 0.1

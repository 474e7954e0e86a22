"""MC_GroupSetOverride's AccFactor on the gantry's physics: X and Y in a group run a line, and
the carriages' acceleration, measured at the joints, stays within AccFactor times the line's
Acceleration."""

from __future__ import annotations

import numpy as np
import pytest

import mcl
from scenes.machines import gantry
from scenes.tools.grouping import PoweredGroup

VELOCITY, ACCELERATION = 100.0, 2000.0
"""The line's Velocity [mm/s] and Acceleration = Deceleration [mm/s²]."""
WINDOW = 10
"""Servo cycles over which the joints' acceleration is taken (a velocity difference)."""


def joint_acceleration(acc_factor: float) -> tuple[float, float]:
    """A line of 60 mm in X and 80 mm in Y with ``AccFactor``: the largest path speed [mm/s]
    and path acceleration [mm/s²] of the X and Y joints (the physics' velocities)."""
    scene = gantry.build(start={"X": 0.5, "Y": 0.3, "Z": -0.1}, trace_every=0)
    grouped = PoweredGroup([scene.axes["X"], scene.axes["Y"]], "xy", 0.02)
    override = mcl.MC_GroupSetOverride(AxesGroup=grouped.group, AccFactor=acc_factor)
    line = mcl.MC_MoveLinearRelative(
        AxesGroup=grouped.group,
        Distance=[60.0, 80.0],
        Velocity=VELOCITY,
        Acceleration=ACCELERATION,
        Deceleration=ACCELERATION,
        Jerk=50000.0,
    )
    go = [False]

    def program() -> None:
        grouped()
        override(Enable=grouped.enable.Done)
        line(Execute=go[0])
        assert not (line.Error or override.Error)

    scene.run(program, until=lambda: grouped.enable.Done, timeout=2.0)
    scene.run(program, timeout=0.2)
    dofs = [scene.model.joint(f"gantry/{n}").dofadr[0] for n in "XY"]
    velocity: list[np.ndarray] = []
    scene.runtime.observers.append(lambda t: velocity.append(scene.data.qvel[dofs] * 1000.0))
    go[0] = True
    scene.run(program, until=lambda: line.Done, timeout=10.0)
    v = np.array(velocity)
    acc = np.linalg.norm(v[WINDOW:] - v[:-WINDOW], axis=1) / (WINDOW * 0.001)
    return float(np.linalg.norm(v, axis=1).max()), float(acc.max())


def test_acc_factor_limits_the_carriages_acceleration() -> None:
    """As commanded the carriages accelerate at the line's 2000 mm/s² (within 5 %) to 100 mm/s;
    with AccFactor 0.25 at a quarter of it (the path at √0.25 of its velocity)."""
    speed, acc = joint_acceleration(1.0)
    assert speed == pytest.approx(VELOCITY, rel=0.02)
    assert acc == pytest.approx(ACCELERATION, rel=0.05)
    speed, acc = joint_acceleration(0.25)
    assert speed == pytest.approx(0.5 * VELOCITY, rel=0.02)
    assert acc == pytest.approx(0.25 * ACCELERATION, rel=0.05)

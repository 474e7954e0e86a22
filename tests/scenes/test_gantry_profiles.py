"""A velocity profile and a continuous move on the gantry's X axis, judged by the physics (joint
coordinate and joint velocity of the MuJoCo model, never the encoder)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import mcl
from scenes.machines import gantry

TABLE = mcl.MC_TV_REF(
    [
        mcl.MC_TV(0.15, 300.0),
        mcl.MC_TV(0.30, 300.0),
        mcl.MC_TV(0.25, -200.0),
        mcl.MC_TV(0.30, -200.0),
        mcl.MC_TV(0.10, 0.0),
    ]
)
"""Up to 300 mm/s, held, through zero to −200 mm/s, held, to rest: 2000 mm/s² ramps whose
acceleration steps at every point (the table sets the jerk)."""


class Run:
    """X of a fresh gantry, powered and referenced in place (coordinate = joint coordinate in
    mm), with every servo instant recorded: time, set point, joint position and velocity."""

    def __init__(self) -> None:
        self.scene = scene = gantry.build(start=dict(gantry.MACHINE.demo_start), trace_every=0)
        self.X = X = scene.axes["X"]
        self.scale = scale = scene.scales["X"]
        power, direct = mcl.MC_Power(Axis=X), mcl.MC_StepDirect(Axis=X)
        self.power = power
        scene.run(lambda: power(Enable=True), until=lambda: power.Status, timeout=1.0)
        here = scene.joint_position("X") * scale

        def home() -> None:
            power(Enable=True)
            direct(Execute=True, SetPosition=here)

        scene.run(home, until=lambda: direct.Done, timeout=1.0)
        self.samples: list[tuple[float, float, float, float]] = []
        dof = scene.io("X").dof
        scene.runtime.observers.append(
            lambda t: self.samples.append(
                (
                    t,
                    X.sp_pos,
                    scene.joint_position("X") * scale,
                    float(scene.data.qvel[dof]) * scale,
                )
            )
        )

    def run(self, fb: Any, until: Any, timeout: float = 5.0, **inputs: Any) -> None:
        def program() -> None:
            self.power(Enable=True)
            fb(Execute=True, **inputs)

        self.scene.run(program, until=until, timeout=timeout)

    @property
    def array(self) -> np.ndarray:
        return np.array(self.samples)


def test_a_velocity_profile_is_followed_within_the_following_error_bound():
    """Peak following error (set point − joint) over the profile and 0.2 s after it, against
    DevMax of X; the joint runs the table's plateaus at their velocities."""
    run = Run()
    fb = mcl.MC_VelocityProfile(Axis=run.X, TimeVelocity=TABLE)
    run.run(fb, until=lambda: fb.Done or fb.Error)
    assert fb.Done, fb.ErrorID
    assert isinstance(fb._cmd, mcl.command.Command)
    t0 = fb._cmd.t0
    run.run(fb, until=None, timeout=0.2)
    t, sp, q, v = run.array.T
    during = t >= t0
    peak = float(np.abs(sp - q)[during].max())
    assert peak <= run.X.config.dev_max
    assert run.X.AxErrorID == 0 and run.X.state == mcl.AxisState.ContinuousMotion
    for start, end, velocity in ((0.25, 0.40, 300.0), (0.85, 1.00, -200.0)):
        plateau = (t >= t0 + start) & (t <= t0 + end)
        assert np.abs(v[plateau] - velocity).max() <= 0.01 * abs(velocity)
    assert abs(v[-1]) < 1.0  # at rest after the last point


def test_move_continuous_absolute_passes_the_target_at_end_velocity():
    """The joint crosses the target with the end velocity (interpolated between the two servo
    instants around the crossing), then runs on at it."""
    run = Run()
    start = run.X.POS
    target = start + 100.0
    fb = mcl.MC_MoveContinuousAbsolute(
        Axis=run.X, Position=target, Velocity=300.0, EndVelocity=150.0
    )
    run.run(fb, until=lambda: fb.InEndVelocity or fb.Error)
    assert fb.InEndVelocity, fb.ErrorID
    run.run(fb, until=lambda: run.scene.joint_position("X") * run.scale > target + 20.0)
    _, _, q, v = run.array.T
    k = int(np.argmax(q >= target))
    assert k > 0
    w = (target - q[k - 1]) / (q[k] - q[k - 1])
    crossing = v[k - 1] + w * (v[k] - v[k - 1])
    assert crossing == pytest.approx(150.0, rel=0.01)
    assert v[-1] == pytest.approx(150.0, rel=0.01)
    assert run.X.state == mcl.AxisState.ContinuousMotion and fb.Busy

"""After running into a mechanical block the gantry stops pushing, judged by the force on it.

MC_StepBlock (then a buffered MC_StepDirect) against each hard stop of X and Z, and
GT_MoveAbsBlock's TorqueLimit against the X obstacle: the axis pushes with the amplifier's force
until the block is detected; from 0.5 s after it ran into the block on, the force the block
carries (the joint-limit constraint of the hard stop, the contact of the obstacle) stays below
5 % of the amplifier's force limit, for 20 s of holding with the power on: long enough for any
integral action left working against the block to wind up.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np
import pytest

import mcl
from mcl import AxisState, MC_BufferMode, MC_Direction
from mcl.fb import MotionFB
from scenes.machines import gantry
from scenes.scene import Scene

PARK = {"X": 0.3, "Y": 0.3, "Z": -0.1}
"""Start positions of the axes a test does not move [m]."""
APPROACH = 0.06
"""Distance of the start from the block [m]."""
VELOCITY = 20.0
"""Search / approach velocity [mm/s]."""
SHARE = 0.05
"""Largest force on the block once released, as a share of the amplifier's force limit."""
RELEASED_AFTER = 0.5
"""Time from running into the block until the force must be below the share [s]."""
HOLD = 20.0
"""Holding time after Done [s]."""


def build(**start: float) -> Scene:
    return gantry.build(start={**PARK, **start}, trace_every=0)


def force_limit(scene: Scene, axis: str) -> float:
    """The amplifier's force limit [N]."""
    return float(scene.model.actuator_forcerange[scene.io(axis).actuator][1])


def stop_force(scene: Scene, axis: str) -> float:
    """Force the hard stops of ``axis`` carry: its joint-limit constraint force [N]."""
    data, joint = scene.data, scene.io(axis).joint
    rows = (data.efc_type == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT) & (data.efc_id == joint)
    return float(np.abs(data.efc_force[rows]).sum())


def obstacle_force(scene: Scene) -> float:
    """Normal force of the contacts of the X obstacle [N]."""
    model, data = scene.model, scene.data
    geom = model.geom("gantry/X_obstacle_geom").id
    wrench = np.zeros(6)
    total = 0.0
    for i in range(data.ncon):
        contact = data.contact[i]
        if geom in (contact.geom1, contact.geom2):
            mujoco.mj_contactForce(model, data, i, wrench)
            total += abs(wrench[0])
    return total


@dataclass
class ForceLog:
    """Observer: the force on the block every servo cycle."""

    measure: Callable[[], float]
    times: list[float] = field(default_factory=list)
    forces: list[float] = field(default_factory=list)

    def __call__(self, t: float) -> None:
        self.times.append(t)
        self.forces.append(self.measure())

    def first_reaching(self, level: float) -> float:
        """First instant the force reached ``level`` [N] (the axis ran into the block) [s]."""
        return next(t for t, f in zip(self.times, self.forces, strict=True) if f >= level)

    def peak(self, since: float = -np.inf, until: float = np.inf) -> float:
        """Largest force between two instants [N]."""
        pairs = zip(self.times, self.forces, strict=True)
        return max(f for t, f in pairs if since <= t <= until)

    def at(self, t: float) -> float:
        """The force at the last sample at or before ``t`` [N]."""
        pairs = zip(reversed(self.times), reversed(self.forces), strict=True)
        return next(f for s, f in pairs if s <= t)


@dataclass
class BlockRun:
    """A run into a block: the scene, its force log and the blocks that ran."""

    scene: Scene
    log: ForceLog
    fbs: dict[str, MotionFB]
    fmax: float

    def hit(self) -> float:
        """When the axis ran into the block [s]."""
        return self.log.first_reaching(SHARE * self.fmax)


def home_to_block(axis: str, direction: int, buffered: bool = True) -> BlockRun:
    """MC_StepBlock toward the hard stop in ``direction`` (+1/−1), from 60 mm before it, then
    MC_StepDirect (SetPosition 0), buffered or started once MC_StepBlock is Done; Done, then
    20 s holding."""
    probe = build()
    lo, hi = (float(x) for x in probe.model.jnt_range[probe.io(axis).joint])
    scene = build(**{axis: hi - APPROACH if direction > 0 else lo + APPROACH})
    ax = scene.axes[axis]
    log = ForceLog(lambda: stop_force(scene, axis))
    scene.runtime.observers.append(log)
    power = mcl.MC_Power(Axis=ax)
    block = mcl.MC_StepBlock(
        Axis=ax,
        Direction=MC_Direction.MC_Positive if direction > 0 else MC_Direction.MC_Negative,
        Velocity=VELOCITY,
        TorqueLimit=1.5,
    )
    mode = MC_BufferMode.Buffered if buffered else MC_BufferMode.Aborting
    direct = mcl.MC_StepDirect(Axis=ax, SetPosition=0.0, BufferMode=mode)

    def program() -> None:
        power(Enable=True)
        block(Execute=power.Status)
        direct(Execute=power.Status and (buffered or block.Done))

    scene.run(program, until=lambda: direct.Done or block.Error or direct.Error, timeout=20.0)
    scene.run(program, timeout=HOLD)
    return BlockRun(scene, log, {"block": block, "direct": direct}, force_limit(scene, axis))


def move_to_obstacle(direction: int) -> BlockRun:
    """GT_MoveAbsBlock (TorqueLimit 1 mm) of X toward the obstacle placed 50 mm away in
    ``direction``, the target 50 mm beyond it; Done, then 20 s holding. The coordinate is the
    joint coordinate in mm (MC_StepDirect at the start)."""
    start, q_block = 0.2, 0.2 + direction * 0.05
    scene = build(X=start)
    model = scene.model
    side = "blockpos" if direction > 0 else "blockneg"
    body = model.body("gantry/X_obstacle").id
    touching = model.numeric(f"gantry/X_obstacle_{side}").data
    model.body_pos[body] = touching + np.array([q_block, 0.0, 0.0])
    mujoco.mj_forward(model, scene.data)
    X = scene.axes["X"]
    log = ForceLog(lambda: obstacle_force(scene))
    scene.runtime.observers.append(log)
    power = mcl.MC_Power(Axis=X)
    direct = mcl.MC_StepDirect(Axis=X, SetPosition=start * 1000.0)
    move = mcl.GT_MoveAbsBlock(
        Axis=X,
        Position=(q_block + direction * 0.05) * 1000.0,
        Velocity=VELOCITY,
        TorqueLimit=1.0,
    )

    def program() -> None:
        power(Enable=True)
        direct(Execute=power.Status)
        move(Execute=direct.Done)

    scene.run(program, until=lambda: move.Done or move.Error or direct.Error, timeout=20.0)
    scene.run(program, timeout=HOLD)
    return BlockRun(scene, log, {"direct": direct, "move": move}, force_limit(scene, "X"))


def assert_released(run: BlockRun, axis: str) -> None:
    """The axis pushed the block with most of its force, then let go of it for good, and
    stands powered and error-free."""
    for name, fb in run.fbs.items():
        assert fb.Done, (name, fb.ErrorID, run.scene.axes[axis].AxErrorID)
    ax = run.scene.axes[axis]
    assert ax.state == AxisState.StandStill and ax.AxErrorID == 0 and ax.Ref
    hit = run.hit()
    pushed = run.log.peak(until=hit + RELEASED_AFTER)
    assert pushed >= 0.5 * run.fmax, f"found the block pushing {pushed:.0f} N of {run.fmax:.0f} N"
    after = run.log.peak(since=hit + RELEASED_AFTER)
    assert after < SHARE * run.fmax, (
        f"{after:.0f} N on the block from {RELEASED_AFTER} s after hitting it on "
        f"(limit {SHARE * run.fmax:.0f} N of {run.fmax:.0f} N)"
    )
    assert run.log.times[-1] >= hit + HOLD


@pytest.mark.parametrize(
    ("axis", "direction", "buffered"),
    [("X", -1, True), ("X", -1, False), ("X", +1, True), ("Z", -1, True), ("Z", +1, True)],
    ids=["X-neg", "X-neg-direct-after-done", "X-pos", "Z-down-onto-the-stop", "Z-up-gravity"],
)
def test_block_homing_stops_pushing_the_hard_stop(axis: str, direction: int, buffered: bool):
    run = home_to_block(axis, direction, buffered)
    assert_released(run, axis)
    # the reference point is at the stop, clear of it: the axis stands within 0.1 mm of it
    scene = run.scene
    lo, hi = (float(x) for x in scene.model.jnt_range[scene.io(axis).joint])
    gap = (hi - scene.joint_position(axis)) if direction > 0 else (scene.joint_position(axis) - lo)
    assert 0.0 <= gap < 1e-4, f"stands {gap * 1e6:.1f} µm from the stop"
    assert abs(scene.axes[axis].POS) < 0.01


@pytest.mark.parametrize("direction", [+1, -1], ids=["positive", "negative"])
def test_move_abs_block_torque_limit_stops_pushing_the_obstacle(direction: int) -> None:
    run = move_to_obstacle(direction)
    assert_released(run, "X")
    X = run.scene.axes["X"]
    q_block = (0.2 + direction * 0.05) * 1000.0
    real = run.scene.joint_position("X") * 1000.0  # the joint, from the physics [mm]
    assert abs(real - q_block) < 0.1, f"the carriage at {real:.3f} mm, the obstacle at {q_block}"
    assert abs(X.POS - real) < 0.01, "the coordinate (the joint's, in mm) reads where it is"

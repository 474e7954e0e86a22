"""Axis supervision on the MuJoCo gantry, judged by the physics.

Overrunning LIM+ during a move, an obstacle that blocks X (following error ERRPOS), and the Z
holding brake when the drive is switched off and on.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import mcl
from mcl import AxisState, MC_Direction
from mcl import faults as flt
from scenes.machines import gantry
from scenes.scene import Scene
from tests.helpers import reset, scan

PARK = {"X": 0.3, "Y": 0.3, "Z": -0.1}
"""Start positions of the axes [m]."""


def build(**start: float) -> Scene:
    return gantry.build(start={**PARK, **start}, trace_every=0)


def numeric(scene: Scene, name: str) -> float:
    return float(scene.model.numeric(f"gantry/{name}").data[0])


def amp_force(scene: Scene, axis: str) -> float:
    return float(scene.data.actuator_force[scene.io(axis).actuator])


def force_limit(scene: Scene, axis: str) -> float:
    return float(scene.model.actuator_forcerange[scene.io(axis).actuator][1])


def velocity(scene: Scene, axis: str) -> float:
    return float(scene.data.qvel[scene.io(axis).dof])


class Recorder:
    """Observer: extremes of the joint coordinate, amplifier force and speed; finiteness; the
    time and joint coordinate at the first ErrorStop."""

    def __init__(self, scene: Scene, axis: str) -> None:
        self.scene, self.axis = scene, axis
        self.q0 = scene.joint_position(axis)
        self.q_min = self.q_max = self.q0
        self.peak_force = 0.0
        self.peak_speed = 0.0
        self.finite = True
        self.t_error: float | None = None
        scene.runtime.observers.append(self)

    def __call__(self, t: float) -> None:
        scene, axis = self.scene, self.axis
        q = scene.joint_position(axis)
        self.q_min, self.q_max = min(self.q_min, q), max(self.q_max, q)
        self.peak_force = max(self.peak_force, abs(amp_force(scene, axis)))
        self.peak_speed = max(self.peak_speed, abs(velocity(scene, axis)))
        data = scene.data
        self.finite = self.finite and all(
            math.isfinite(x) for x in (*data.qpos, *data.qvel, *data.act, *data.actuator_force)
        )
        if self.t_error is None and scene.axes[axis].state == AxisState.ErrorStop:
            self.t_error = t

    @property
    def max_deviation(self) -> float:
        return max(self.q_max - self.q0, self.q0 - self.q_min)


# ----------------------------------------------------------------------------- LIM+ overrun


@pytest.mark.parametrize("command", ["MoveVelocity", "MoveRelative"])
def test_overrunning_lim_pos_stops_short_of_the_hard_stop_and_reset_recovers(command):
    scene = build(X=0.9)
    X = scene.axes["X"]
    rec = Recorder(scene, "X")
    lim_pos = numeric(scene, "X_lim_pos_trip")
    _, stop_hi = scene.model.jnt_range[scene.io("X").joint]
    power = mcl.MC_Power()
    move: mcl.MC_MoveVelocity | mcl.MC_MoveRelative
    if command == "MoveVelocity":
        move = mcl.MC_MoveVelocity()
        inputs = dict(Velocity=200.0, Direction=MC_Direction.MC_Positive)
    else:
        move = mcl.MC_MoveRelative()
        inputs = dict(Distance=200.0, Velocity=200.0)  # target 1.1 m: beyond the hard stop

    def program() -> None:
        power(Axis=X, Enable=True)
        move(Axis=X, Execute=power.Status, **inputs)

    assert not X.Ref  # not homed: the software limits do not apply, LIM+ is what stops it
    scene.run(program, until=lambda: X.state == AxisState.ErrorStop, timeout=5)
    scene.run(program, timeout=0.5)
    assert X.AxErrorID == mcl.ErrorID.ERRLIP
    assert move.Error and move.ErrorID == mcl.ErrorID.ERRLIP
    assert rec.q_max >= lim_pos
    assert rec.q_max < stop_hi, f"hit the hard stop: q_max {rec.q_max:.6f} m"
    assert abs(velocity(scene, "X")) < 1e-4
    assert rec.finite

    # MC_Reset, then back off the switch
    reset(scene, X, power)
    back = mcl.MC_MoveRelative()
    q0 = scene.joint_position("X")
    scene.run(
        scan(
            lambda: power(Axis=X, Enable=True),
            lambda: back(Axis=X, Execute=True, Distance=-100.0, Velocity=100.0),
        ),
        until=lambda: back.Done or back.Error,
        timeout=5,
    )
    assert back.Done, (back.ErrorID, X.AxErrorID)
    scene.run(lambda: power(Axis=X, Enable=True), timeout=0.3)
    assert X.state == AxisState.StandStill and X.AxErrorID == 0
    assert scene.joint_position("X") - q0 == pytest.approx(-0.100, abs=10e-6)
    assert not scene.io("X").lim_pos


# ----------------------------------------------------------------------------- obstacle


def block_x(scene: Scene, q_b: float) -> None:
    """Move the obstacle so that it blocks +X motion at joint coordinate ``q_b`` [m]."""
    m = scene.model
    blockpos = m.numeric("gantry/X_obstacle_blockpos").data
    m.body_pos[m.body("gantry/X_obstacle").id] = blockpos + np.array([q_b, 0.0, 0.0])
    mujoco.mj_forward(m, scene.data)


@pytest.mark.parametrize("speed", [50.0, 200.0, 800.0])
def test_blocked_axis_trips_errpos_at_the_obstacle_without_instability(speed):
    scene = build(X=0.3)
    X = scene.axes["X"]
    q_b = 0.5
    block_x(scene, q_b)
    rec = Recorder(scene, "X")
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()

    def program() -> None:
        power(Axis=X, Enable=True)
        move(Axis=X, Execute=True, Distance=400.0, Velocity=speed)

    scene.run(program, until=lambda: X.state == AxisState.ErrorStop, timeout=10)
    q_trip = scene.joint_position("X")
    scene.run(program, timeout=1.0)
    assert X.AxErrorID == mcl.ErrorID.ERRPOS
    assert move.Error and move.ErrorID == mcl.ErrorID.ERRPOS
    assert q_trip == pytest.approx(q_b, abs=1e-3), "tripped at the obstacle"
    assert rec.q_max < q_b + 1e-3, f"{(rec.q_max - q_b) * 1e3:.3f} mm past the obstacle"
    assert rec.finite
    fmax = force_limit(scene, "X")
    assert rec.peak_force <= fmax * (1 + 1e-9)
    assert rec.peak_speed < 1.5 * speed / 1000.0
    # at rest at the obstacle (a fast impact rebounds a few mm), and no longer pushing it
    assert q_b - 0.010 < scene.joint_position("X") < q_b + 1e-3
    assert abs(velocity(scene, "X")) < 1e-3
    assert abs(amp_force(scene, "X")) < 0.05 * fmax


# ----------------------------------------------------------------------------- Z brake


@pytest.mark.parametrize("z", [-0.1, -0.24])
def test_z_does_not_fall_when_disabled(z):
    scene = build(Z=z)
    rec = Recorder(scene, "Z")
    scene.run(None, timeout=2.0)
    assert scene.axes["Z"].state == AxisState.Disabled
    assert rec.max_deviation < 10e-6, f"sag {rec.max_deviation * 1e6:.2f} µm"


@pytest.mark.parametrize("z", [-0.1, -0.24])
def test_z_does_not_jump_when_enabled_nor_when_disabled_again(z):
    scene = build(Z=z)
    Z = scene.axes["Z"]
    power = mcl.MC_Power()
    scene.run(None, timeout=0.5)  # resting on the brake

    on = Recorder(scene, "Z")
    scene.run(lambda: power(Axis=Z, Enable=True), timeout=1.0)
    scene.runtime.observers.remove(on)
    assert Z.state == AxisState.StandStill and power.Status
    assert on.max_deviation < 50e-6, f"jump on enable {on.max_deviation * 1e6:.1f} µm"

    off = Recorder(scene, "Z")
    scene.run(lambda: power(Axis=Z, Enable=False), timeout=1.0)
    assert Z.state == AxisState.Disabled
    assert off.max_deviation < 50e-6, f"jump on disable {off.max_deviation * 1e6:.1f} µm"
    assert abs(amp_force(scene, "Z")) == 0.0, "drive disabled: no amplifier force"


def test_z_held_after_a_move_when_disabled():
    scene = build(Z=-0.2)
    Z = scene.axes["Z"]
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()

    def program() -> None:
        power(Axis=Z, Enable=True)
        move(Axis=Z, Execute=power.Status, Distance=100.0, Velocity=100.0)

    scene.run(program, until=lambda: move.Done or move.Error, timeout=5)
    assert move.Done, move.ErrorID
    scene.run(program, timeout=0.3)
    assert scene.joint_position("Z") == pytest.approx(-0.1, abs=10e-6)
    off = Recorder(scene, "Z")
    scene.run(lambda: power(Axis=Z, Enable=False), timeout=2.0)
    assert Z.state == AxisState.Disabled
    assert off.max_deviation < 50e-6, f"drop on disable {off.max_deviation * 1e6:.1f} µm"


# ----------------------------------------------------------------------------- group error stop


@pytest.mark.parametrize("member", ["X", "Y"], ids=["X in ErrorStop on LIM+", "Y standing"])
def test_a_member_of_a_group_in_its_error_stop_is_supervised(member):
    """X and Y in a group; the group's line runs X onto LIM+: X stops in ErrorStop 2004 with
    its loop closed, Y is stopped along the line and stands, the group is in GroupErrorStop.
    An encoder cable of either member then breaks: 2001 at once, 0 V, the amplifier stops the
    joint, the enable drops after quick_stop_time, and the group error becomes 8001."""
    scene = build(X=0.9)
    axes = [scene.axes["X"], scene.axes["Y"]]
    group = mcl.AxesGroup()
    powers = [mcl.MC_Power(Axis=a) for a in axes]
    adds = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=a) for a in axes]
    enable = mcl.MC_GroupEnable(AxesGroup=group)
    move = mcl.MC_MoveLinearRelative(AxesGroup=group, Distance=[200.0, 100.0], Velocity=200.0)
    status, error = mcl.MC_GroupReadStatus(AxesGroup=group), mcl.MC_GroupReadError(AxesGroup=group)

    def program() -> None:
        for power, add in zip(powers, adds, strict=True):
            power(Enable=True)
            add(Execute=power.Status)
        enable(Execute=all(add.Done for add in adds))
        move(Execute=enable.Done)
        status(Enable=True)
        error(Enable=True)

    X, Y = axes
    scene.run(program, until=lambda: X.state == AxisState.ErrorStop, timeout=5)
    scene.run(program, timeout=0.5)
    assert X.AxErrorID == mcl.ErrorID.ERRLIP and X.loop_closed
    assert Y.state == AxisState.StandStill and abs(velocity(scene, "Y")) < 1e-4
    assert status.GroupErrorStop and error.GroupErrorID == mcl.ErrorID.ERRLIP

    axis, io = scene.axes[member], scene.io(member)
    rows: list[tuple[float, int, float, bool, float, float]] = []
    scene.runtime.observers.append(
        lambda t: rows.append(
            (
                t,
                axis.AxErrorID,
                io.volts,
                io.enabled,
                scene.joint_position(member),
                velocity(scene, member),
            )
        )
    )
    t0 = scene.time
    scene.faults.set(member, flt.EncoderWireBreak())
    scene.run(program, timeout=0.4)
    t_error = next((t for t, code, *_ in rows if code == mcl.ErrorID.ERRPOS), None)
    assert t_error is not None, f"no 2001: AxErrorID {axis.AxErrorID}"
    assert t_error - t0 <= 0.001
    later = [r for r in rows if r[0] > t_error + 0.001]
    assert all(code == mcl.ErrorID.ERRPOS and volts == 0.0 for _, code, volts, *_ in later)
    on = [t for t, _, _, enabled, *_ in later if enabled]
    assert max(on) == pytest.approx(t_error + axis.config.quick_stop_time, abs=0.002)
    q = [r[4] for r in rows]
    assert max(q) - min(q) < 1e-4 and abs(rows[-1][5]) < 1e-4, "at rest, no runaway"
    assert status.GroupErrorStop and error.GroupErrorID == mcl.ErrorID.ERRPOSG

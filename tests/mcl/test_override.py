"""MC_SetOverride: the velocity override scales the time of the axis' motion, judged by the
simulated carriage (its physics) and by the set point the axis generates every servo cycle."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import Any

import pytest

import mcl
from mcl.time_scale import ramp_rate
from tests.helpers import assert_at, carriage_mm, carriage_mm_s, fresh_axis
from tests.helpers import scan as program

MOVE = dict(Velocity=200.0, Acceleration=2000.0, Deceleration=2000.0)
"""A move of the simulated axis (Vmax 500 mm/s): 200 mm/s, ramps of 0.1 s."""


class Recorder:
    """The set-point velocity of an axis in every servo cycle [mm/s]."""

    def __init__(self, machine: mcl.SimMachine, axis: mcl.Axis) -> None:
        self.axis = axis
        self.velocities: list[float] = []
        machine.runtime.observers.append(self.observe)

    def observe(self, t: float) -> None:
        self.velocities.append(self.axis.sp_vel)

    def largest_step(self) -> float:
        """The largest change of the set-point velocity from one servo cycle to the next."""
        v = self.velocities
        return max(abs(b - a) for a, b in itertools.pairwise(v))


def overridden(
    move: Any, factor: list[float], **inputs: Any
) -> tuple[mcl.MC_SetOverride, Callable[[], None]]:
    """MC_SetOverride on the axis of ``move`` and the program that calls it (Enable TRUE, VelFactor
    ``factor[0]`` as it is at that scan), then ``move`` (Execute TRUE, ``inputs``)."""
    override = mcl.MC_SetOverride(Axis=move.Axis)
    return override, program(
        lambda: override(Enable=True, VelFactor=factor[0]),
        lambda: move(Execute=True, **inputs),
    )


def mean_velocity(
    machine: mcl.SimMachine, scan: Callable[[], None] | None, seconds: float
) -> float:
    """The carriage's mean velocity over ``seconds`` of the program ``scan`` [mm/s] (from the
    physics)."""
    start = carriage_mm(machine)
    machine.run(scan, timeout=seconds)
    return (carriage_mm(machine) - start) / seconds


def test_half_override_halves_the_cruise_and_the_move_still_ends_at_its_target() -> None:
    machine, X = fresh_axis()
    recorder = Recorder(machine, X)
    move, factor = mcl.MC_MoveAbsolute(Axis=X), [1.0]
    override, scan = overridden(move, factor, Position=500.0, **MOVE)
    machine.run(scan, timeout=0.3)
    assert carriage_mm_s(machine) == pytest.approx(200.0, rel=0.01)
    factor[0] = 0.5
    ramp = 0.5 / ramp_rate(X)
    machine.run(scan, timeout=ramp + 0.05)
    assert override.Enabled and override.Busy and not override.Error
    cruise = mean_velocity(machine, scan, 0.4)
    assert cruise == pytest.approx(100.0, rel=0.01)
    assert X.state == mcl.AxisState.DiscreteMotion
    machine.run(scan, until=lambda: move.Done, timeout=5.0)
    assert X.sp_pos == 500.0
    assert_at(X, 500.0)
    # through the ramp the set point changes by at most the ramp's rate times the velocity;
    # the move's own acceleration (2000 mm/s²) is the largest change anywhere
    assert recorder.largest_step() <= 2000.0 * X.servo_period * 1.001
    assert ramp_rate(X) * 200.0 < 2000.0


def test_the_ramp_of_the_factor_limits_the_change_of_velocity() -> None:
    """A step of the factor from 100 % to 20 % during the cruise: no velocity step larger than
    the ramp (the axis' default deceleration per servo cycle), and 40 mm/s once it is over."""
    machine, X = fresh_axis()
    move, factor = mcl.MC_MoveVelocity(Axis=X), [1.0]
    _, scan = overridden(move, factor, **MOVE)
    machine.run(scan, timeout=0.2)
    recorder = Recorder(machine, X)
    factor[0] = 0.2
    machine.run(scan, timeout=0.8 / ramp_rate(X) + 0.05)
    step = recorder.largest_step()
    assert step <= ramp_rate(X) * 200.0 * X.servo_period * 1.001
    assert step >= ramp_rate(X) * 200.0 * X.servo_period * 0.999  # it is a ramp, not a wait
    assert X.sp_vel == pytest.approx(40.0)
    assert mean_velocity(machine, scan, 0.2) == pytest.approx(40.0, rel=0.01)


def test_zero_holds_the_axis_in_motion_at_standstill_and_one_resumes_to_the_target() -> None:
    machine, X = fresh_axis()
    move, factor = mcl.MC_MoveRelative(Axis=X), [1.0]
    _, scan = overridden(move, factor, Distance=300.0, **MOVE)
    machine.run(scan, timeout=0.4)
    factor[0] = 0.0
    machine.run(scan, timeout=1.0 / ramp_rate(X) + 0.1)
    held = carriage_mm(machine)
    assert 0.0 < held < 300.0
    machine.run(scan, timeout=0.5)
    assert abs(carriage_mm(machine) - held) < 0.01
    assert X.sp_vel == 0.0
    assert X.state == mcl.AxisState.DiscreteMotion
    assert move.Busy and move.Active and not move.Done
    factor[0] = 1.0
    machine.run(scan, until=lambda: move.Done, timeout=5.0)
    assert_at(X, 300.0)
    assert X.state == mcl.AxisState.StandStill


def test_velocity_move_at_80_percent_runs_at_0_8_of_its_velocity() -> None:
    machine, X = fresh_axis()
    move, override = mcl.MC_MoveVelocity(Axis=X), mcl.MC_SetOverride(Axis=X)
    scan = program(
        lambda: override(Enable=True, VelFactor=0.8),
        lambda: move(Execute=True, **MOVE),
    )
    machine.run(scan, until=lambda: move.InVelocity, timeout=1.0)
    velocity = mean_velocity(machine, scan, 0.3)
    assert velocity == pytest.approx(160.0, rel=0.01)
    assert X.state == mcl.AxisState.ContinuousMotion


@pytest.mark.parametrize(
    "wrong",
    [
        dict(VelFactor=-0.1),
        dict(VelFactor=math.nan),
        dict(VelFactor=2.01),
        dict(VelFactor=math.inf),
        dict(VelFactor="fast"),
        dict(AccFactor=-1.0),
        dict(JerkFactor=math.nan),
    ],
)
def test_wrong_factors_give_eparam_and_leave_the_axis_and_its_factor(wrong: dict) -> None:
    machine, X = fresh_axis()
    move, override = mcl.MC_MoveVelocity(Axis=X), mcl.MC_SetOverride(Axis=X)
    machine.run(
        program(lambda: override(Enable=True, VelFactor=0.5), lambda: move(Execute=True, **MOVE)),
        timeout=0.6,
    )
    assert X.override_factor == 0.5
    before = mean_velocity(machine, None, 0.1)
    override(**{"VelFactor": 0.5, "AccFactor": 1.0, "JerkFactor": 1.0, **wrong})
    assert override.Error and override.ErrorID == mcl.ErrorID.EParam
    assert not override.Busy and not override.Enabled
    assert X.override_factor == 0.5
    after = mean_velocity(machine, lambda: override(), 0.1)
    assert after == pytest.approx(before, rel=0.01) and before == pytest.approx(100.0, rel=0.01)
    assert X.state == mcl.AxisState.ContinuousMotion and move.Active
    override(VelFactor=0.5, AccFactor=1.0, JerkFactor=1.0)  # a valid value clears the error
    assert override.Enabled and not override.Error and override.ErrorID == 0


def test_enable_false_keeps_the_last_factor_and_resets_the_outputs() -> None:
    machine, X = fresh_axis()
    override = mcl.MC_SetOverride(Axis=X, VelFactor=0.3)
    override(Enable=True)
    assert override.Enabled and X.override_factor == 0.3
    override(Enable=False, VelFactor=0.9)
    assert not (override.Enabled or override.Busy or override.Error) and override.ErrorID == 0
    assert X.override_factor == 0.3
    move = mcl.MC_MoveVelocity(Axis=X)
    machine.run(lambda: move(Execute=True, **MOVE), until=lambda: move.InVelocity, timeout=1.0)
    assert mean_velocity(machine, lambda: move(), 0.2) == pytest.approx(60.0, rel=0.01)


def test_mc_stop_keeps_its_own_ramp_under_an_override() -> None:
    """At 50 % an MC_Stop with 1000 mm/s² stops from 100 mm/s in 0.1 s, not in four times that."""
    machine, X = fresh_axis()
    move, override = mcl.MC_MoveVelocity(Axis=X), mcl.MC_SetOverride(Axis=X)
    stop = mcl.MC_Stop(Axis=X, Deceleration=1000.0)
    machine.run(
        program(lambda: override(Enable=True, VelFactor=0.5), lambda: move(Execute=True, **MOVE)),
        timeout=0.6,
    )
    assert X.sp_vel == pytest.approx(100.0)
    t0 = machine.runtime.time
    machine.run(lambda: stop(Execute=True), until=lambda: X.sp_vel == 0.0, timeout=1.0)
    assert machine.runtime.time - t0 == pytest.approx(0.1, abs=0.005)
    move()
    assert move.CommandAborted


def test_blending_under_an_override_keeps_the_velocity_continuous() -> None:
    """Two blended moves at 50 %: the first hands over at half its velocity, both end Done at
    their targets, and the set point never steps by more than the moves' acceleration."""
    machine, X = fresh_axis()
    recorder = Recorder(machine, X)
    first, second = mcl.MC_MoveAbsolute(Axis=X), mcl.MC_MoveAbsolute(Axis=X)
    override = mcl.MC_SetOverride(Axis=X, VelFactor=0.5)
    passed: list[float] = []

    def scan() -> None:
        override(Enable=True)
        first(Execute=True, Position=100.0, **MOVE)
        second(Execute=True, Position=250.0, BufferMode=mcl.MC_BufferMode.BlendingLow, **MOVE)
        if first.Done and not passed:
            passed.append(X.sp_vel)

    machine.run(scan, until=lambda: second.Done, timeout=5.0)
    assert first.Done and passed[0] == pytest.approx(100.0, rel=0.01)
    assert_at(X, 250.0)
    assert recorder.largest_step() <= 0.25 * 2000.0 * X.servo_period * 1.01 + 1e-9


def test_gantry_x_at_50_percent_of_400_mm_s_runs_200_mm_s_on_the_joint() -> None:
    import scenes

    scene = scenes.load("gantry", start={"X": 0.2}, trace_every=0)
    X = scene.axes["X"]
    scale = scene.scales["X"]
    dof = scene.io("X").dof
    power, move, override = mcl.MC_Power(), mcl.MC_MoveRelative(), mcl.MC_SetOverride()
    factor = [1.0]
    worst = [0.0]
    joint: list[float] = []
    measure_from = [math.inf]

    def scan() -> None:
        power(Axis=X, Enable=True)
        override(Axis=X, Enable=power.Status, VelFactor=factor[0])
        move(Axis=X, Execute=power.Status, Distance=600.0, Velocity=400.0)

    def observe(t: float) -> None:
        worst[0] = max(worst[0], abs(X.following_error))
        if factor[0] == 0.5 and t >= measure_from[0]:
            joint.append(scene.data.qvel[dof] * scale)

    scene.runtime.observers.append(observe)
    scene.run(scan, until=lambda: move.Active, timeout=1.0)
    start = scene.joint_position("X") * scale
    scene.run(scan, timeout=0.4)
    factor[0] = 0.5
    measure_from[0] = scene.time + 0.5 / ramp_rate(X) + 0.05
    scene.run(scan, timeout=0.5 / ramp_rate(X) + 0.35)
    assert sum(joint) / len(joint) == pytest.approx(200.0, rel=0.02)
    assert min(joint) == pytest.approx(200.0, rel=0.02) and max(joint) == pytest.approx(
        200.0, rel=0.02
    )
    factor[0] = 1.0
    scene.run(scan, until=lambda: move.Done, timeout=5.0)
    assert worst[0] < X.config.dev_max, f"{worst[0] * 1e3:.1f} µm"
    scene.run(scan, timeout=0.2)
    assert scene.joint_position("X") * scale - start == pytest.approx(600.0, abs=0.01)


def test_a_saved_state_brings_back_the_factor_it_was_saved_with() -> None:
    machine, X = fresh_axis()
    mcl.MC_SetOverride(Axis=X, VelFactor=0.5)(Enable=True)
    state = machine.save_state()
    mcl.MC_SetOverride(Axis=X, VelFactor=1.0)(Enable=True)
    machine.restore_state(state)
    assert X.override_factor == 0.5
    move = mcl.MC_MoveVelocity(Axis=X)
    machine.run(lambda: move(Execute=True, **MOVE), until=lambda: move.InVelocity, timeout=1.0)
    assert mean_velocity(machine, lambda: move(), 0.2) == pytest.approx(100.0, rel=0.01)


def test_an_encoder_only_axis_refuses_the_override() -> None:
    machine = mcl.SimMachine({"W": mcl.SimAxisParams(start=0.2, has_drive=False)})
    W = machine.axes["W"]
    override = mcl.MC_SetOverride(Axis=W, VelFactor=0.5)
    override(Enable=True)
    assert override.Error and override.ErrorID == mcl.ErrorID.ENoDrive and not override.Busy
    assert W.override_factor == 1.0


def test_jogging_at_half_override_runs_at_half_and_stops_on_its_own_ramp() -> None:
    """GT_Jog at 50 % of 200 mm/s runs 100 mm/s; let go, it stops with JogDec 1000 mm/s² from
    100 mm/s in 0.1 s (the release ramp is not overridden)."""
    machine, X = fresh_axis()
    jog = mcl.GT_Jog(Axis=X, Enable=True, JogVelo=200.0, JogAcc=2000.0, JogDec=1000.0)
    override = mcl.MC_SetOverride(Axis=X, Enable=True, VelFactor=0.5)
    press = [True]
    scan = program(override, lambda: jog(JogPos=press[0]))
    machine.run(scan, timeout=0.3)
    assert mean_velocity(machine, scan, 0.2) == pytest.approx(100.0, rel=0.01)
    press[0] = False
    t0 = machine.runtime.time
    machine.run(scan, until=lambda: X.sp_vel == 0.0, timeout=1.0)
    assert machine.runtime.time - t0 == pytest.approx(0.1, abs=0.005)

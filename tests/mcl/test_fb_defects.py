"""Three block rules, judged by what the axis does.

- Several MC_Stop instances on one axis: while the Execute of any of them is TRUE the axis stays
  in Stopping and accepts no other motion; it goes to StandStill only when all are FALSE.
- Software limits: a move to exactly LimPos / LimNeg is accepted and ends Done, whatever the
  drive's overshoot at the stop (the model never passes the limit; the actual position may by
  the following error); a target beyond a limit is refused (Ecil), a velocity move across a
  limit and an open-loop drift beyond it stop with ERRSWP / ERRSWN. On simulated axes and on the
  MuJoCo gantry.
- GT_EStop latches: an MC_Power whose Enable stays TRUE does not power the axes up again;
  MC_Power with Enable FALSE acknowledges the stop, and only then does Enable TRUE power up.
"""

from __future__ import annotations

from typing import Any

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_Direction
from scenes.machines import gantry
from scenes.scene import Scene
from tests.helpers import PLC, POS_TOL, configure, fresh_axis, power_on, scan, tick


def velocity_move(machine: mcl.Machine, axis: mcl.Axis, velocity: float = 200.0) -> Any:
    """MC_MoveVelocity until InVelocity; returns the block."""
    vel = mcl.MC_MoveVelocity(Axis=axis, Velocity=abs(velocity))
    vel.Direction = MC_Direction.MC_Positive if velocity > 0 else MC_Direction.MC_Negative
    machine.run(lambda: vel(Execute=True), until=lambda: vel.InVelocity, timeout=3.0)
    return vel


def refused_move(machine: mcl.SimMachine, axis: mcl.Axis) -> None:
    """A MoveRelative of 50 mm is refused with EAxStop and the axis does not move."""
    x0 = machine.sims[axis.name].x
    move = mcl.MC_MoveRelative()
    move(Axis=axis, Execute=True, Distance=50.0, Velocity=100.0)
    assert move.Error and move.ErrorID == ErrorID.EAxStop
    tick(machine, 25)
    assert abs(machine.sims[axis.name].x - x0) < 1e-4, "moved"  # 50 ms at 100 mm/s: 5 mm
    move(Execute=False)


# ---------------------------------------------------------------- two MC_Stop instances
@pytest.mark.parametrize("first_released", ["first", "second"])
def test_every_stop_instance_holds_the_axis_while_its_execute_is_true(first_released: str):
    machine, X = fresh_axis()
    velocity_move(machine, X)
    first, second = mcl.MC_Stop(Axis=X), mcl.MC_Stop(Axis=X)
    for _ in range(5):  # the first ramps down, then the second takes over
        first(Execute=True)
        tick(machine)
    machine.run(
        scan(lambda: first(Execute=True), lambda: second(Execute=True)),
        until=lambda: second.Done,
        timeout=2.0,
    )
    assert first.CommandAborted and X.state == AxisState.Stopping
    assert abs(machine.sims["X"].v) < 1e-3, "stopped"

    released, holding = (first, second) if first_released == "first" else (second, first)
    for _ in range(50):
        released(Execute=False)
        holding(Execute=True)
        assert X.state == AxisState.Stopping, f"released by the {first_released} instance alone"
        tick(machine)
    refused_move(machine, X)
    assert X.state == AxisState.Stopping

    released(Execute=False)
    holding(Execute=False)
    tick(machine)
    assert X.state == AxisState.StandStill
    move = mcl.MC_MoveRelative()
    machine.run(
        lambda: move(Axis=X, Execute=True, Distance=50.0, Velocity=100.0),
        until=lambda: move.Done or move.Error,
        timeout=3.0,
    )
    assert move.Done and X.state == AxisState.StandStill


def test_a_restarted_stop_instance_does_not_hold_the_axis_twice():
    """A new Execute edge of the same instance replaces its earlier Stop: one falling edge
    releases the axis."""
    machine, X = fresh_axis()
    velocity_move(machine, X)
    stop = mcl.MC_Stop(Axis=X)
    machine.run(lambda: stop(Execute=True), timeout=0.05)
    stop(Execute=False)
    machine.run(lambda: stop(Execute=True), until=lambda: stop.Done, timeout=2.0)
    assert X.state == AxisState.Stopping
    machine.run(lambda: stop(Execute=False), timeout=0.01)
    assert X.state == AxisState.StandStill


# --------------------------------------------------------------------- software limits
LIMIT = 100.0
"""The SW limits of the simulated axis: LimPos = LIMIT, LimNeg = −LIMIT [mm]."""


def move_absolute(machine: mcl.Machine, axis: mcl.Axis, position: float, velocity: float) -> Any:
    """MC_MoveAbsolute until Done or Error, then 0.2 s standing; returns the block."""
    move = mcl.MC_MoveAbsolute(Axis=axis, Position=position, Velocity=velocity)
    machine.run(lambda: move(Execute=True), until=lambda: move.Done or move.Error, timeout=10.0)
    machine.run(lambda: move(Execute=True), timeout=0.2)
    return move


@pytest.mark.parametrize("velocity", [200.0, 400.0])
def test_a_move_to_exactly_a_sw_limit_ends_done_on_the_limit(velocity: float):
    """With an acceleration feed-forward that over-compensates (Ka 15 ms), the drive overshoots
    each stop by tens of µm: past the limit, yet the accepted move ends Done."""
    machine, X = fresh_axis(LimPos=LIMIT, LimNeg=-LIMIT, Ka=0.015)
    reach = {"pos": 0.0, "neg": 0.0}

    def observe(t: float) -> None:
        reach["pos"] = max(reach["pos"], X.actual - LIMIT)
        reach["neg"] = max(reach["neg"], -LIMIT - X.actual)

    machine.runtime.observers.append(observe)
    for limit in (LIMIT, -LIMIT):
        move = move_absolute(machine, X, limit, velocity)
        assert move.Done and not move.Error, (move.ErrorID, X.AxErrorID)
        assert X.state == AxisState.StandStill and X.AxErrorID == 0
        assert abs(X.POS - limit) <= POS_TOL
    assert min(reach.values()) > X.config.in_position, f"overshoot {reach} mm: the case tested"


def test_a_target_beyond_a_sw_limit_is_refused_and_the_axis_stays():
    machine, X = fresh_axis(LimPos=LIMIT, LimNeg=-LIMIT)
    x0 = machine.sims["X"].x
    for target in (LIMIT + 0.01, -LIMIT - 0.01):
        move = mcl.MC_MoveAbsolute()
        move(Axis=X, Execute=True, Position=target, Velocity=200.0)
        assert move.Error and move.ErrorID == ErrorID.Ecil
        tick(machine, 25)
        assert X.state == AxisState.StandStill and X.AxErrorID == 0
        assert abs(machine.sims["X"].x - x0) < 1e-5


@pytest.mark.parametrize(("velocity", "code"), [(200.0, ErrorID.ERRSWP), (-200.0, ErrorID.ERRSWN)])
def test_a_velocity_move_across_a_sw_limit_stops_right_behind_it(velocity: float, code: int):
    machine, X = fresh_axis(LimPos=LIMIT, LimNeg=-LIMIT)
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=abs(velocity))
    vel.Direction = MC_Direction.MC_Positive if velocity > 0 else MC_Direction.MC_Negative
    machine.run(lambda: vel(Execute=True), until=lambda: vel.Error, timeout=3.0)
    machine.run(lambda: vel(Execute=True), timeout=0.2)
    assert vel.ErrorID == code and X.AxErrorID == code and X.state == AxisState.ErrorStop
    limit = LIMIT if velocity > 0 else -LIMIT
    beyond = (X.POS - limit) * (1 if velocity > 0 else -1)
    # the maximum ramp from 200 mm/s: v²/2d = 1 mm at 20 000 mm/s²
    assert 0.0 < beyond < 2.0


@pytest.mark.parametrize(("target", "code"), [(95.0, ErrorID.ERRSWP), (-95.0, ErrorID.ERRSWN)])
def test_an_open_loop_drift_beyond_a_sw_limit_stops_the_axis(target: float, code: int):
    """SpeedMode 1 (no position loop, the following error is not supervised) on a drive that
    runs 20 % fast: a move to 95 mm carries the axis past the limit at 100 mm by more than
    DevMax while it is still under way."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2, vmax=0.6)})
    X = machine.axes["X"]
    configure(X, LimPos=LIMIT, LimNeg=-LIMIT)
    power = mcl.MC_Power(Axis=X, Enable=True, SpeedMode=1)
    finish = mcl.MC_FinishHoming(Axis=X)
    move = mcl.MC_MoveAbsolute(Axis=X, Position=target, Velocity=200.0)

    def program() -> None:
        power()
        finish(Execute=power.Status)
        move(Execute=finish.Done)

    machine.run(program, until=lambda: move.Done or move.Error, timeout=5.0)
    assert move.Error and move.ErrorID == code and X.AxErrorID == code
    limit = LIMIT if target > 0 else -LIMIT
    beyond = (X.POS - limit) * (1 if target > 0 else -1)
    assert X.config.dev_max < beyond < X.config.dev_max + 1.0


def gantry_x_with_limits(
    lim_neg: float, lim_pos: float, ka_excess: float = 0.0
) -> tuple[Scene, mcl.Axis, Any]:
    """The gantry's X powered, its coordinate = the joint coordinate [mm] (MC_StepDirect), the
    SW limits set through GT_SetConstant, the other constants as commissioned except Ka, raised
    by ``ka_excess`` [s] (an acceleration feed-forward that over-compensates: overshoot)."""
    scene = gantry.build(start={"X": 0.5, "Y": 0.3, "Z": -0.1}, trace_every=0)
    X = scene.axes["X"]
    power = mcl.MC_Power(Axis=X)
    direct = mcl.MC_StepDirect(Axis=X, SetPosition=500.0)
    scene.run(
        scan(lambda: power(Enable=True), lambda: direct(Execute=power.Status)),
        until=lambda: direct.Done,
        timeout=1.0,
    )
    c = X.constants
    assert c is not None
    constants = {name: getattr(c, name) for name in mcl.GT_SetConstant.INPUTS}
    constants.update(LimNeg=lim_neg, LimPos=lim_pos, Ka=c.Ka + ka_excess)
    write = mcl.GT_SetConstant()
    write(Axis=X, Execute=True, **constants)
    assert write.Done, write.ErrorID
    return scene, X, power


class Peak:
    """Observer: the largest joint coordinate of X [mm] and the states seen."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.q_max = self.q_min = scene.joint_position("X") * 1000.0
        self.states: set[AxisState] = set()
        scene.runtime.observers.append(self)

    def __call__(self, t: float) -> None:
        q = self.scene.joint_position("X") * 1000.0
        self.q_max, self.q_min = max(self.q_max, q), min(self.q_min, q)
        self.states.add(self.scene.axes["X"].state)


@pytest.mark.parametrize("ka_excess", [0.0, 0.003], ids=["as-commissioned", "overshooting"])
@pytest.mark.parametrize("velocity", [200.0, 500.0])
def test_gantry_moves_to_exactly_its_sw_limits_without_error(velocity: float, ka_excess: float):
    """As commissioned, and with 3 ms too much acceleration feed-forward (the drive then
    overshoots each stop by more than the in-position window, past the limit)."""
    scene, X, power = gantry_x_with_limits(200.0, 800.0, ka_excess)
    peak = Peak(scene)
    for limit in (800.0, 200.0):
        move = mcl.MC_MoveAbsolute(Axis=X, Position=limit, Velocity=velocity, Execute=True)
        program = scan(power, move)
        scene.run(program, until=lambda: move.Done or move.Error, timeout=10.0)  # noqa: B023
        scene.run(program, timeout=0.3)
        assert move.Done, (move.ErrorID, X.AxErrorID)
        assert X.state == AxisState.StandStill and X.AxErrorID == 0
        assert scene.joint_position("X") * 1000.0 == pytest.approx(limit, abs=0.01)
    assert AxisState.ErrorStop not in peak.states
    overshoot = min(peak.q_max - 800.0, 200.0 - peak.q_min)
    assert overshoot < X.config.dev_max
    if ka_excess:
        assert overshoot > X.config.in_position, f"overshoot {overshoot * 1000:.1f} µm"


@pytest.mark.parametrize(("velocity", "code"), [(300.0, ErrorID.ERRSWP), (-300.0, ErrorID.ERRSWN)])
def test_gantry_velocity_move_across_a_sw_limit_stops_right_behind_it(velocity: float, code: int):
    scene, X, power = gantry_x_with_limits(400.0, 600.0)
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=abs(velocity))
    vel.Direction = MC_Direction.MC_Positive if velocity > 0 else MC_Direction.MC_Negative
    vel.Execute = True
    program = scan(power, vel)
    scene.run(program, until=lambda: vel.Error, timeout=3.0)
    scene.run(program, timeout=0.3)
    assert vel.ErrorID == code and X.AxErrorID == code and X.state == AxisState.ErrorStop
    limit = 600.0 if velocity > 0 else 400.0
    beyond = (scene.joint_position("X") * 1000.0 - limit) * (1 if velocity > 0 else -1)
    ramp = velocity**2 / (2 * X.config.max_deceleration)
    assert 0.0 < beyond < ramp + 1.0, f"{beyond:.3f} mm beyond the limit"


# ------------------------------------------------------------------------------ GT_EStop
def two_axes_running() -> tuple[mcl.SimMachine, list[mcl.Axis], list[mcl.MC_Power], Any]:
    """X and Y on one module, powered by MC_Power blocks (Enable TRUE), X moving at 200 mm/s."""
    machine = mcl.SimMachine(
        {name: mcl.SimAxisParams(start=0.2, brake_force=500.0) for name in ("X", "Y")}
    )
    axes = [machine.axes["X"], machine.axes["Y"]]
    powers = [mcl.MC_Power(Axis=axis) for axis in axes]
    for axis in axes:
        configure(axis)
    vel = mcl.MC_MoveVelocity(Axis=axes[0], Velocity=200.0)

    def program() -> None:
        for power in powers:
            power(Enable=True)
        vel(Execute=powers[0].Status)

    machine.run(program, until=lambda: vel.InVelocity, timeout=3.0)
    return machine, axes, powers, vel


def powered(machine: mcl.SimMachine, axes: list[mcl.Axis], powers: list[mcl.MC_Power]) -> bool:
    """Every axis has its loop closed and its drive enabled, and MC_Power says so."""
    return all(
        p.Status and a.state == AxisState.StandStill and machine.sims[a.name].enabled
        for a, p in zip(axes, powers, strict=True)
    )


def still_off(machine: mcl.SimMachine, axes: list[mcl.Axis], powers: list[mcl.MC_Power]) -> None:
    """Every axis Disabled, its drive off, MC_Power's Status FALSE without an error."""
    for axis, power in zip(axes, powers, strict=True):
        assert axis.state == AxisState.Disabled, axis.name
        assert not machine.sims[axis.name].enabled and machine.sims[axis.name].volts == 0.0
        assert not power.Status and not power.Error


def test_estop_is_not_undone_by_an_enable_that_stays_true():
    machine, axes, powers, _ = two_axes_running()
    estop = mcl.GT_EStop(Axis=axes[0])
    for enable in (True, False):  # one scan with the E-stop pressed, then released
        estop(Enable=enable)
        for power in powers:
            power(Enable=True)
        tick(machine)
    x_stopped = machine.sims["X"].x
    for _ in range(250):  # 0.5 s with MC_Power.Enable held TRUE
        for power in powers:
            power(Enable=True)
        still_off(machine, axes, powers)
        tick(machine)
    assert abs(machine.sims["X"].x - x_stopped) < 0.002, "braked to a stop, no restart"
    # acknowledge: Enable FALSE for one scan, then TRUE powers up again
    for enable in (False, True, True):
        for power in powers:
            power(Enable=enable)
        tick(machine)
    assert powered(machine, axes, powers)


def test_no_axis_powers_up_while_the_estop_is_pressed():
    """Enable toggled while GT_EStop.Enable is TRUE: the axes stay off; that acknowledgement
    counts, so Enable TRUE after the release powers up."""
    machine, axes, powers, _ = two_axes_running()
    estop = mcl.GT_EStop(Axis=axes[0])
    for enable in (True, False, True, True):
        estop(Enable=True)
        for power in powers:
            power(Enable=enable)
        tick(machine)
        still_off(machine, axes, powers)
    assert estop.Done
    estop(Enable=False)
    for _ in range(3):  # Enable stays TRUE: the FALSE during the stop acknowledged it
        for power in powers:
            power(Enable=True)
        tick(machine)
    assert powered(machine, axes, powers)


def test_after_an_acknowledged_estop_the_axis_needs_ref_again():
    """Powering up again clears Ref as every power-up does: homing (or MC_FinishHoming) again."""
    machine, axes, powers, _ = two_axes_running()
    X = axes[0]
    power_on(machine, axes[1])
    assert axes[1].Ref
    estop = mcl.GT_EStop(Axis=X)
    estop(Enable=True)
    estop(Enable=False)
    for enable in (False, True, True):
        for power in powers:
            power(Enable=enable)
        tick(machine)
    assert powered(machine, axes, powers)
    assert not axes[1].Ref
    move = mcl.MC_MoveAbsolute(Axis=axes[1], Position=10.0, Velocity=100.0)
    move(Execute=True)
    assert move.Error and move.ErrorID == ErrorID.Ehome
    tick(machine, int(0.01 / PLC))


def test_a_block_bound_by_attribute_runs_when_called_without_its_level_input():
    """The bound style: ``move.Execute = x; move()`` and ``read.Enable = True; read()`` (the
    level input not passed keeps the value set on the block, in both modes)."""
    machine, X = fresh_axis()
    move = mcl.MC_MoveRelative(Axis=X, Distance=10.0, Velocity=100.0, Acceleration=1000.0)
    move.Execute = True
    read = mcl.MC_ReadParameter(Axis=X, Enable=True, ParameterNumber=1)
    start = X.POS

    def program() -> None:
        move()
        read()

    machine.run(program, until=lambda: move.Done, timeout=2.0)
    assert move.Execute
    moved = X.POS - start
    assert moved == pytest.approx(10.0, abs=POS_TOL)
    assert read.Enable and read.Valid and not read.Error

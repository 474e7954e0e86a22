"""The axis state machine, one test (group) per transition of its table (docs/reference.md).

Positions in mm of the axis coordinate system. The simulated axis "X" starts at x = 0.2 m, where
the encoder reads 0: LIM+ is actuated from POS ≈ 805 mm, LIM− from POS ≈ −205 mm, the hard stops
are at −210 / +810 mm.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

import mcl
from mcl import AxisState
from tests.helpers import (
    PLC,
    POS_TOL,
    carriage_mm,
    carriage_mm_s,
    configure,
    fresh_axis,
    make_machine,
    scan,
    tick,
)


def move_to(machine: mcl.SimMachine, axis: mcl.Axis, position: float, velocity: float = 400.0):
    """MoveAbsolute until Done."""
    fb = mcl.MC_MoveAbsolute()
    machine.run(
        lambda: fb(Axis=axis, Execute=True, Position=position, Velocity=velocity),
        until=lambda: fb.Done or fb.Error,
        timeout=10.0,
    )
    assert fb.Done, fb.ErrorID


def reset(machine: mcl.SimMachine, axis: mcl.Axis) -> mcl.MC_Reset:
    """MC_Reset with Execute held until Done (or Error)."""
    fb = mcl.MC_Reset()
    machine.run(lambda: fb(Axis=axis, Execute=True), until=lambda: fb.Done or fb.Error, timeout=2.0)
    assert fb.Done
    return fb


def power_off(machine: mcl.SimMachine, axis: mcl.Axis, seconds: float = 0.3) -> mcl.MC_Power:
    """MC_Power with Enable=FALSE for ``seconds``."""
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=axis, Enable=False), timeout=seconds)
    return power


def trip_following_error(machine: mcl.SimMachine, axis: mcl.Axis) -> mcl.MC_MoveRelative:
    """Block the simulated axis 5 mm ahead and move against the obstacle: ERRPOS 2001."""
    sim = machine.sims[axis.name]
    sim.blocked_at = sim.x + 0.005
    fb = mcl.MC_MoveRelative()
    machine.run(
        lambda: fb(Axis=axis, Execute=True, Distance=100.0, Velocity=200.0),
        until=lambda: fb.Error,
        timeout=2.0,
    )
    return fb


def busy_until_done(
    machine: mcl.SimMachine, fb: Any, state: AxisState, scans: int, **inputs: Any
) -> None:
    """Call ``fb`` on X (Execute TRUE, ``inputs``) every scan: Busy, with X in ``state``, until it
    is Done within ``scans``."""
    X = machine.axes["X"]
    for _ in range(scans):
        fb(Axis=X, Execute=True, **inputs)
        if fb.Done:
            return
        assert fb.Busy
        assert X.state == state
        tick(machine)
    raise AssertionError(f"{type(fb).__name__} not Done within {scans} scans")


def shown_states(axis: mcl.Axis) -> set[str]:
    """The state flags MC_ReadStatus shows for ``axis`` (one scan, Enable=TRUE)."""
    status = mcl.MC_ReadStatus()
    status(Axis=axis, Enable=True)
    assert status.Valid
    return {s.name for s in AxisState if getattr(status, s.name)}


# ---------------------------------------------------------------------- Disabled → StandStill
def test_power_on_goes_from_disabled_to_standstill_and_clears_ref(machine):
    X = machine.axes["X"]
    assert X.state == AxisState.Disabled
    X.Ref = True  # e.g. referenced before the drive was switched off
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=X, Enable=True), timeout=0.02)
    assert power.Status and not power.Error
    assert X.state == AxisState.StandStill
    assert not X.Ref
    assert machine.sims["X"].enabled
    assert shown_states(X) == {"StandStill"}


def test_power_on_again_clears_ref(machine, X):
    assert X.Ref
    power_off(machine, X)
    assert X.state == AxisState.Disabled
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=X, Enable=True), timeout=0.02)
    assert X.state == AxisState.StandStill and not X.Ref


# ----------------------------------------------------------------------- Disabled → ErrorStop
def test_power_on_with_axis_error_goes_to_errorstop(machine, X):
    trip_following_error(machine, X)
    power_off(machine, X)
    assert X.state == AxisState.Disabled
    assert X.AxErrorID == mcl.ErrorID.ERRPOS
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=X, Enable=True), timeout=0.02)
    assert X.state == AxisState.ErrorStop
    assert X.AxErrorID == mcl.ErrorID.ERRPOS
    assert shown_states(X) == {"ErrorStop"}
    # the loop was closed by the power-on: reset goes to StandStill
    reset(machine, X)
    assert X.state == AxisState.StandStill and X.AxErrorID == 0


# --------------------------------------------------------------------------- any → Disabled
def _scenario(state: str) -> tuple[mcl.SimMachine, mcl.Axis, Callable[[], None]]:
    """A fresh powered, referenced axis brought into ``state``; returns the program that keeps
    the blocks that brought it there being called."""
    machine, X = fresh_axis(LimPos=5.0, LimNeg=-300.0) if state == "ErrorStop" else fresh_axis()
    blocks: list[Callable[[], None]] = []
    if state == "DiscreteMotion":
        mv = mcl.MC_MoveAbsolute()
        blocks.append(lambda: mv(Axis=X, Execute=True, Position=300.0, Velocity=200.0))
    elif state in ("ContinuousMotion", "Stopping", "ErrorStop"):
        vel = mcl.MC_MoveVelocity()
        blocks.append(lambda: vel(Axis=X, Execute=True, Velocity=100.0))
        if state == "Stopping":
            machine.run(blocks[0], timeout=0.1)
            stop = mcl.MC_Stop()
            blocks.append(lambda: stop(Axis=X, Execute=True))
    elif state == "ErrorStopLoopOpen":
        trip_following_error(machine, X)
    elif state == "Disabled":
        power = mcl.MC_Power()
        blocks.append(lambda: power(Axis=X, Enable=False))

    def program() -> None:
        for block in blocks:
            block()

    machine.run(program, timeout=0.2)
    expected = AxisState.ErrorStop if state == "ErrorStopLoopOpen" else AxisState[state]
    assert X.state == expected
    return machine, X, program


STATES = [
    "StandStill",
    "DiscreteMotion",
    "ContinuousMotion",
    "Stopping",
    "ErrorStop",
    "ErrorStopLoopOpen",
    "Disabled",
]


@pytest.mark.parametrize("state", STATES)
def test_power_off_goes_to_disabled_from_every_state(state):
    machine, X, program = _scenario(state)
    power = mcl.MC_Power()
    machine.run(scan(program, lambda: power(Axis=X, Enable=False)), timeout=0.5)
    assert X.state == AxisState.Disabled
    assert not power.Status
    assert not machine.sims["X"].enabled


@pytest.mark.parametrize(
    ("fb_type", "inputs"),
    [
        (mcl.MC_MoveVelocity, {"Velocity": 300.0}),
        (mcl.MC_MoveAbsolute, {"Position": 600.0, "Velocity": 300.0}),
    ],
)
def test_power_off_while_moving_stops_on_max_ramp_then_disables_and_aborts(
    machine, X, fb_type, inputs
):
    fb = fb_type()
    machine.run(
        lambda: fb(Axis=X, Execute=True, **inputs),
        until=lambda: X.OPT2n > 299.9 and X.POS > 100.0,
        timeout=5.0,
    )
    start = X.POS
    power = mcl.MC_Power()
    loop_closed_while_fast = []
    done_or_error = False
    for _ in range(150):
        power(Axis=X, Enable=False)
        fb(Execute=True)
        done_or_error |= bool(fb.Done or fb.Error)
        if X.VEL > 100.0:
            loop_closed_while_fast.append(machine.sims["X"].enabled)
        tick(machine)
    assert X.state == AxisState.Disabled
    assert fb.CommandAborted and not done_or_error
    assert loop_closed_while_fast and all(loop_closed_while_fast), "loop opened before the stop"
    ramp = 300.0**2 / (2.0 * X.config.max_deceleration)
    # coasting with the drive off would take some 45 mm; the maximum ramp takes `ramp`
    assert X.POS - start < ramp + 2.0
    assert not machine.sims["X"].enabled
    assert abs(machine.sims["X"].v) < 1e-3


def test_power_off_keeps_the_error_code(machine, X):
    configure(X, LimPos=5.0, LimNeg=-300.0)
    vel = mcl.MC_MoveVelocity()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=100.0),
        until=lambda: X.state == AxisState.ErrorStop,
        timeout=2.0,
    )
    tick(machine, 50)
    assert X.AxErrorID == mcl.ErrorID.ERRSWP
    power_off(machine, X)
    assert X.state == AxisState.Disabled
    assert X.AxErrorID == mcl.ErrorID.ERRSWP
    err = mcl.MC_ReadAxisError()
    err(Axis=X, Enable=True)
    assert err.Valid and err.Error and err.AxisErrorID == mcl.ErrorID.ERRSWP


# -------------------------------------------------------------------------- any → ErrorStop
def test_following_error_goes_to_errorstop_with_the_loop_open(machine, X):
    power = mcl.MC_Power()
    power(Axis=X, Enable=True)
    fb = trip_following_error(machine, X)
    assert fb.ErrorID != 0 and not fb.Busy
    assert X.state == AxisState.ErrorStop
    assert X.AxErrorID == mcl.ErrorID.ERRPOS
    sim = machine.sims["X"]
    assert sim.enabled and sim.volts == 0.0  # quick stop: the amplifier brakes at 0 V
    tick(machine, round(X.config.quick_stop_time / PLC))
    assert not sim.enabled and sim.brake  # then the enable drops and the brake engages
    power(Enable=True)
    assert not power.Status
    assert shown_states(X) == {"ErrorStop"}


def _drive_onto(machine: mcl.SimMachine, X: mcl.Axis, direction: int) -> mcl.MC_MoveVelocity:
    """Drive with MoveVelocity (100 mm/s) until the axis leaves its motion state."""
    vel = mcl.MC_MoveVelocity()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=100.0, Direction=direction),
        until=lambda: X.state != AxisState.ContinuousMotion,
        timeout=5.0,
    )
    vel(Execute=True)
    return vel


POSITIVE = mcl.MC_Direction.MC_Positive
NEGATIVE = mcl.MC_Direction.MC_Negative


@pytest.mark.parametrize(
    ("approach", "direction", "code", "switch"),
    [
        (780.0, POSITIVE, mcl.ErrorID.ERRLIP, "lim_pos"),
        (-180.0, NEGATIVE, mcl.ErrorID.ERRLIN, "lim_neg"),
    ],
)
def test_limit_switch_goes_to_errorstop_with_the_loop_closed(
    machine, X, approach, direction, code, switch
):
    move_to(machine, X, approach)
    vel = _drive_onto(machine, X, direction)
    assert X.state == AxisState.ErrorStop
    assert X.AxErrorID == code
    assert getattr(machine.sims["X"], switch)
    assert vel.Error and not vel.Busy
    tick(machine, 100)
    assert X.state == AxisState.ErrorStop
    assert machine.sims["X"].enabled, "a limit switch stops without opening the loop"
    assert abs(X.VEL) < 1.0
    # ErrorStop → StandStill by MC_Reset (the loop stayed closed)
    reset(machine, X)
    assert X.state == AxisState.StandStill and X.AxErrorID == 0


def test_lim_pos_reset_then_move_back_works_and_positive_move_trips_again(machine, X):
    move_to(machine, X, 780.0)
    _drive_onto(machine, X, POSITIVE)
    assert X.AxErrorID == mcl.ErrorID.ERRLIP
    tick(machine, 50)
    reset(machine, X)
    assert machine.sims["X"].lim_pos, "still on the switch after the reset"
    tick(machine, 50)
    assert X.state == AxisState.StandStill, "standing on the switch is no new error"
    # a positive move on the switch trips 2004 again
    fwd = mcl.MC_MoveRelative()
    machine.run(
        lambda: fwd(Axis=X, Execute=True, Distance=2.0, Velocity=20.0),
        until=lambda: fwd.Done or fwd.Error,
        timeout=2.0,
    )
    assert fwd.Error and not fwd.Done
    assert X.state == AxisState.ErrorStop and X.AxErrorID == mcl.ErrorID.ERRLIP
    tick(machine, 50)
    reset(machine, X)
    # a move back (negative) works and leaves the switch
    back = mcl.MC_MoveRelative()
    machine.run(
        lambda: back(Axis=X, Execute=True, Distance=-20.0, Velocity=50.0),
        until=lambda: back.Done or back.Error,
        timeout=3.0,
    )
    assert back.Done and not back.Error
    assert X.state == AxisState.StandStill and X.AxErrorID == 0
    assert not machine.sims["X"].lim_pos


@pytest.mark.parametrize(
    ("direction", "code", "beyond"),
    [
        (POSITIVE, mcl.ErrorID.ERRSWP, lambda pos: pos > 100.0),
        (NEGATIVE, mcl.ErrorID.ERRSWN, lambda pos: pos < -100.0),
    ],
)
def test_sw_limit_goes_to_errorstop(machine, X, direction, code, beyond):
    configure(X, LimPos=100.0, LimNeg=-100.0)
    vel = _drive_onto(machine, X, direction)
    assert X.state == AxisState.ErrorStop
    assert X.AxErrorID == code
    assert beyond(X.POS)
    assert abs(X.POS) < 110.0, "stopped on the fastest ramp right behind the limit"
    assert vel.Error
    tick(machine, 50)
    assert machine.sims["X"].enabled
    reset(machine, X)
    assert X.state == AxisState.StandStill
    move_to(machine, X, 0.0, velocity=100.0)  # back inside the limits
    assert X.state == AxisState.StandStill and X.AxErrorID == 0


def test_sw_limits_are_not_checked_without_ref():
    machine, X = fresh_axis(referenced=False, LimPos=100.0, LimNeg=-100.0)
    vel = mcl.MC_MoveVelocity()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=100.0), until=lambda: X.POS > 130.0, timeout=3.0
    )
    assert X.state == AxisState.ContinuousMotion and X.AxErrorID == 0
    rel = mcl.MC_MoveRelative()
    machine.run(
        lambda: rel(Axis=X, Execute=True, Distance=50.0, Velocity=100.0),
        until=lambda: rel.Done or rel.Error,
        timeout=3.0,
    )
    assert rel.Done and X.state == AxisState.StandStill and X.POS > 170.0


# ----------------------------------------------------------------- ErrorStop → StandStill
def test_reset_reports_done_when_standstill_is_reached(machine, X):
    move_to(machine, X, 700.0)
    vel = mcl.MC_MoveVelocity()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=300.0),
        until=lambda: X.state == AxisState.ErrorStop,
        timeout=3.0,
    )
    assert X.AxErrorID == mcl.ErrorID.ERRLIP
    assert X.OPT2n > 100.0, "the error stop ramp is still running"
    busy_until_done(machine, mcl.MC_Reset(), AxisState.ErrorStop, scans=200)
    # the model ramp has ended (the actual speed lags it by a few ms: well below 300 mm/s)
    assert abs(X.VEL) < 60.0, "Done only once the stop ramp has ended"
    assert X.state == AxisState.StandStill and X.AxErrorID == 0
    tick(machine, 50)
    assert X.state == AxisState.StandStill and X.AxErrorID == 0


# ------------------------------------------------------------------ ErrorStop → Disabled
def test_reset_after_following_error_goes_to_disabled(machine, X):
    trip_following_error(machine, X)
    machine.sims["X"].blocked_at = math.inf
    fb = reset(machine, X)
    assert fb.Done
    assert X.state == AxisState.Disabled
    assert X.AxErrorID == 0
    tick(machine, round(X.config.quick_stop_time / PLC))
    assert not machine.sims["X"].enabled
    assert shown_states(X) == {"Disabled"}


# ------------------------------------------------- motion states and back to StandStill
DISCRETE_MOVES: list[tuple[type[Any], dict[str, Any]]] = [
    (mcl.MC_MoveAbsolute, {"Position": 40.0, "Velocity": 200.0}),
    (mcl.MC_MoveRelative, {"Distance": 40.0, "Velocity": 200.0}),
    (mcl.MC_MoveAdditive, {"Distance": 40.0, "Velocity": 200.0}),
    (mcl.GT_MoveAbsBlock, {"Position": 40.0, "Velocity": 200.0}),
]


@pytest.mark.parametrize(
    ("fb_type", "inputs"), DISCRETE_MOVES, ids=[t.__name__ for t, _ in DISCRETE_MOVES]
)
def test_discrete_move_goes_discrete_motion_and_back_to_standstill_when_done(
    machine, X, fb_type, inputs
):
    busy_until_done(machine, fb_type(), AxisState.DiscreteMotion, scans=1000, **inputs)
    assert X.state == AxisState.StandStill
    assert pytest.approx(40.0, abs=POS_TOL) == X.POS


def test_halt_goes_discrete_motion_then_standstill(machine, X):
    vel, halt = mcl.MC_MoveVelocity(), mcl.MC_Halt()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=100.0), until=lambda: vel.InVelocity, timeout=2.0
    )
    for _ in range(500):
        vel(Execute=True)
        halt(Axis=X, Execute=True)
        if halt.Done:
            break
        assert X.state == AxisState.DiscreteMotion
        tick(machine)
    assert halt.Done and X.state == AxisState.StandStill


def test_move_velocity_goes_continuous_motion(machine, X):
    vel = mcl.MC_MoveVelocity()
    for _ in range(300):
        vel(Axis=X, Execute=True, Velocity=100.0)
        assert X.state == AxisState.ContinuousMotion
        tick(machine)
    assert vel.InVelocity and vel.Busy
    assert X.state == AxisState.ContinuousMotion


def test_jog_goes_continuous_motion_and_back_to_standstill(machine, X):
    jog = mcl.GT_Jog()
    for _ in range(100):
        jog(Axis=X, Enable=True, JogNeg=True, JogVelo=100.0)
        assert X.state == AxisState.ContinuousMotion
        tick(machine)
    machine.run(lambda: jog(JogNeg=False), timeout=0.5)
    assert X.state == AxisState.StandStill and not jog.Busy


def test_buffered_moves_stay_in_discrete_motion_until_the_last_is_done(machine, X):
    moves = [mcl.MC_MoveRelative() for _ in range(3)]
    states = []
    for _ in range(2000):
        for i, fb in enumerate(moves):
            fb(Axis=X, Execute=True, Distance=20.0, Velocity=200.0, BufferMode=min(i, 1))
        if moves[-1].Done:
            break
        states.append(X.state)
        tick(machine)
    assert all(fb.Done for fb in moves)
    assert set(states) == {AxisState.DiscreteMotion}
    assert X.state == AxisState.StandStill
    assert pytest.approx(60.0, abs=POS_TOL) == X.POS


# ----------------------------------------------------------------------------------- Homing
def _coarse_homing() -> tuple[mcl.SimMachine, mcl.Axis, set[AxisState]]:
    """A not referenced axis after MC_StepAbsSwitch (REF at POS ≈ −100 mm): Done, in Homing.
    Returns the states seen while the step ran."""
    machine, X = fresh_axis(referenced=False)
    step = mcl.MC_StepAbsSwitch()
    seen: set[AxisState] = set()

    def program() -> None:
        step(
            Axis=X,
            Execute=True,
            Direction=NEGATIVE,
            Velocity=100.0,
            SwitchMode=mcl.MC_SwitchMode.MC_EdgeOn,
        )
        seen.add(X.state)

    machine.run(program, until=lambda: step.Done or step.Error, timeout=10.0)
    assert step.Done, step.ErrorID
    return machine, X, seen


def test_homing_step_goes_homing_and_stays_homing_when_done():
    machine, X, seen = _coarse_homing()
    assert seen == {AxisState.Homing}
    tick(machine, 50)
    assert X.state == AxisState.Homing
    assert not X.Ref
    assert shown_states(X) == {"Homing"}


FINISHING_STEPS: list[tuple[type[Any], dict[str, Any]]] = [
    (mcl.MC_FinishHoming, {}),
    (mcl.MC_StepDirect, {"SetPosition": 5.0}),
    (mcl.MC_StepRefPulse, {"Direction": POSITIVE, "Velocity": 20.0, "SetPosition": 0.0}),
]


@pytest.mark.parametrize(
    ("fb_type", "inputs"), FINISHING_STEPS, ids=[t.__name__ for t, _ in FINISHING_STEPS]
)
def test_finishing_step_leaves_homing_to_standstill_and_sets_ref(fb_type, inputs):
    machine, X, _ = _coarse_homing()
    fb = fb_type()
    seen = set()
    for _ in range(2000):
        fb(Axis=X, Execute=True, **inputs)
        seen.add(X.state)
        if fb.Done or fb.Error:
            break
        tick(machine)
    assert fb.Done and not fb.Error
    tick(machine, 100)
    assert seen <= {AxisState.Homing, AxisState.StandStill}
    assert X.state == AxisState.StandStill, f"{X.state.name}, AxErrorID {X.AxErrorID}"
    assert X.Ref and X.AxErrorID == 0
    if "SetPosition" in inputs and fb_type is not mcl.MC_StepRefPulse:
        assert pytest.approx(inputs["SetPosition"], abs=POS_TOL) == X.POS


def test_step_direct_sets_the_coordinate_without_moving_the_axis():
    machine, X, _ = _coarse_homing()
    tick(machine, 50)
    x0, pos0 = machine.sims["X"].x, X.POS
    fb = mcl.MC_StepDirect()
    machine.run(
        lambda: fb(Axis=X, Execute=True, SetPosition=pos0 + 1.0),
        until=lambda: fb.Done or fb.Error,
        timeout=1.0,
    )
    tick(machine, 100)
    assert X.state == AxisState.StandStill and X.Ref
    assert machine.sims["X"].x == pytest.approx(x0, abs=2e-5), "the axis moved"
    assert pytest.approx(pos0 + 1.0, abs=0.02) == X.POS


@pytest.mark.parametrize(
    "name",
    [
        "MC_MoveAbsolute",
        "MC_MoveRelative",
        "MC_MoveAdditive",
        "MC_MoveVelocity",
        "GT_MoveAbsBlock",
        "GT_Jog",
    ],
)
def test_motion_fbs_in_homing_are_refused(name):
    machine, X, _ = _coarse_homing()
    X.Ref = True  # so that the absolute moves are not refused for the missing Ref alone
    fb = MOTION_FBS[name](X)
    assert fb.Error and not fb.Busy
    tick(machine, 20)
    assert X.state == AxisState.Homing


# ------------------------------------------------------------------------ MC_Stop: Stopping
def test_stop_holds_stopping_while_execute_true_then_standstill(machine, X):
    vel, stop = mcl.MC_MoveVelocity(), mcl.MC_Stop()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=200.0), until=lambda: vel.InVelocity, timeout=2.0
    )
    done_scans = 0
    for _ in range(400):
        vel(Execute=True)
        stop(Axis=X, Execute=True)
        assert X.state == AxisState.Stopping
        done_scans += stop.Done
        tick(machine)
    assert done_scans > 100, "Done while Execute stays TRUE"
    assert abs(X.VEL) < 1.0
    stop(Execute=False)
    tick(machine)
    assert X.state == AxisState.StandStill
    stop(Execute=False)
    assert not stop.Done


def test_stop_with_early_falling_edge_goes_standstill_when_done(machine, X):
    vel, stop = mcl.MC_MoveVelocity(), mcl.MC_Stop()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=200.0), until=lambda: vel.InVelocity, timeout=2.0
    )
    stop(Axis=X, Execute=True)
    tick(machine)
    for _ in range(500):
        stop(Execute=False)
        if stop.Done:
            break
        assert X.state == AxisState.Stopping
        tick(machine)
    assert stop.Done
    assert X.state == AxisState.StandStill


def test_stop_from_standstill_holds_stopping(machine, X):
    stop = mcl.MC_Stop()
    machine.run(lambda: stop(Axis=X, Execute=True), timeout=0.1)
    assert stop.Done and X.state == AxisState.Stopping
    machine.run(lambda: stop(Execute=False), timeout=0.01)
    assert X.state == AxisState.StandStill


def stop_from(velocity: float, deceleration: float) -> tuple[float, float]:
    """Run at ``velocity`` [mm/s], then MC_Stop with ``deceleration`` [mm/s²]: how far [mm]
    and how long [s] the simulated carriage still travels (until below 1 mm/s)."""
    machine, X = fresh_axis()
    vel, stop = mcl.MC_MoveVelocity(), mcl.MC_Stop()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=velocity, Acceleration=5000.0),
        until=lambda: vel.InVelocity,
        timeout=2.0,
    )
    machine.run(lambda: vel(Execute=True), timeout=0.1)
    assert carriage_mm_s(machine) == pytest.approx(velocity, rel=0.01)
    x0, t0 = carriage_mm(machine), machine.time
    moving: list[float] = []
    machine.runtime.observers.append(
        lambda t: moving.append(t) if abs(carriage_mm_s(machine)) > 1.0 else None
    )

    def program() -> None:
        vel(Execute=True)
        stop(Axis=X, Execute=True, Deceleration=deceleration)

    machine.run(program, until=lambda: stop.Done, timeout=5.0)
    machine.run(program, timeout=0.3)
    assert X.state == AxisState.Stopping and X.AxErrorID == 0
    return carriage_mm(machine) - x0, moving[-1] - t0


def test_a_smaller_stop_deceleration_gives_a_longer_stop():
    """From 200 mm/s, MC_Stop with Deceleration 2000 and 500 mm/s²: the carriage travels
    v²/2D = 10 and 40 mm and takes v/D = 0.1 and 0.4 s to stop (give or take a PLC scan and the
    loop's settling)."""
    (quick, t_quick), (slow, t_slow) = (stop_from(200.0, d) for d in (2000.0, 500.0))
    assert quick == pytest.approx(10.0, abs=0.5) and slow == pytest.approx(40.0, abs=0.5)
    assert t_quick == pytest.approx(0.1, abs=0.02) and t_slow == pytest.approx(0.4, abs=0.02)


# ----------------------------------------------------- refused commands: 11 / 6 / 10 / 12 / 9
def _execute(fb_type: type[Any], **inputs: Any) -> Callable[[mcl.Axis], Any]:
    def start(axis: mcl.Axis) -> Any:
        fb = fb_type()
        fb(Axis=axis, Execute=True, **inputs)
        return fb

    return start


def _jog(axis: mcl.Axis) -> Any:
    fb = mcl.GT_Jog()
    fb(Axis=axis, Enable=True, JogPos=True, JogVelo=100.0)
    return fb


MOTION_FBS: dict[str, Callable[[mcl.Axis], Any]] = {
    "MC_MoveAbsolute": _execute(mcl.MC_MoveAbsolute, Position=50.0, Velocity=100.0),
    "MC_MoveRelative": _execute(mcl.MC_MoveRelative, Distance=50.0, Velocity=100.0),
    "MC_MoveAdditive": _execute(mcl.MC_MoveAdditive, Distance=50.0, Velocity=100.0),
    "MC_MoveVelocity": _execute(mcl.MC_MoveVelocity, Velocity=100.0),
    "GT_MoveAbsBlock": _execute(mcl.GT_MoveAbsBlock, Position=50.0, Velocity=100.0),
    "MC_Halt": _execute(mcl.MC_Halt),
    "MC_Stop": _execute(mcl.MC_Stop),
    "GT_Jog": _jog,
}


def _refused(machine: mcl.SimMachine, X: mcl.Axis, name: str, error_id: int) -> None:
    """The block is refused with ``error_id`` and the axis does not change."""
    state, pos = X.state, X.POS
    fb = MOTION_FBS[name](X)
    assert fb.Error and fb.ErrorID == error_id
    assert not fb.Busy
    tick(machine, 20)
    assert X.state == state
    assert pytest.approx(pos, abs=0.01) == X.POS


@pytest.mark.parametrize("name", list(MOTION_FBS))
def test_motion_fbs_in_errorstop_give_eerrstop(machine, X, name):
    trip_following_error(machine, X)
    _refused(machine, X, name, mcl.ErrorID.Eerrstop)


@pytest.mark.parametrize("name", [n for n in MOTION_FBS if n != "MC_Stop"])
def test_motion_fbs_in_stopping_give_eaxstop(machine, X, name):
    stop = mcl.MC_Stop()
    machine.run(lambda: stop(Axis=X, Execute=True), timeout=0.02)
    assert X.state == AxisState.Stopping
    _refused(machine, X, name, mcl.ErrorID.EAxStop)


@pytest.mark.parametrize("name", list(MOTION_FBS))
def test_motion_fbs_when_disabled_give_epower(machine, name):
    X = machine.axes["X"]
    assert X.state == AxisState.Disabled
    _refused(machine, X, name, mcl.ErrorID.Epower)


@pytest.mark.parametrize("name", list(MOTION_FBS))
def test_motion_fbs_without_constants_give_econst(name):
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    _refused(machine, X, name, mcl.ErrorID.Econst)


def test_power_without_constants_gives_econst_and_stays_disabled():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=X, Enable=True), timeout=0.02)
    assert power.Error and power.ErrorID == mcl.ErrorID.Econst and not power.Status
    assert X.state == AxisState.Disabled


@pytest.mark.parametrize("name", ["MC_MoveAbsolute", "GT_MoveAbsBlock"])
def test_absolute_moves_without_ref_give_ehome(name):
    machine, X = fresh_axis(referenced=False)
    _refused(machine, X, name, mcl.ErrorID.Ehome)


@pytest.mark.parametrize(
    "name", ["MC_MoveRelative", "MC_MoveAdditive", "MC_MoveVelocity", "GT_Jog"]
)
def test_relative_and_velocity_moves_work_without_ref(name):
    machine, X = fresh_axis(referenced=False)
    fb = MOTION_FBS[name](X)
    assert not fb.Error and fb.Busy
    tick(machine, 50)
    assert X.state in (AxisState.DiscreteMotion, AxisState.ContinuousMotion)
    assert X.POS > 1.0


# ------------------------------------------------ administrative FBs never change the state
def _admin_blocks(X: mcl.Axis) -> Callable[[int], None]:
    read_status = mcl.MC_ReadStatus()
    read_error = mcl.MC_ReadAxisError()
    read_pos = mcl.MC_ReadActualPosition()
    sinfo = mcl.GT_SInfo()
    status_str = mcl.GT_AxStatusString()
    err_cz, err_en = mcl.GT_AxErrStringCZ(), mcl.GT_AxErrStringEN()

    def call(k: int) -> None:
        read_status(Axis=X, Enable=k % 7 != 3)
        read_error(Axis=X, Enable=k % 5 != 1)
        read_pos(Axis=X, Enable=k % 3 != 0)
        sinfo(Axis=X, Execute=(k // 4) % 2 == 0, What1=20 + k % 5, What2=20 + (k + 2) % 5)
        status_str(Axis=X, Enable=k % 2 == 0)
        err_cz(Axis=X, Enable=k % 4 != 2)
        err_en(Axis=X, Enable=True)
        assert read_status.Valid == (k % 7 != 3)
        if read_status.Valid:
            assert getattr(read_status, X.state.name)
        if status_str.Valid:
            assert status_str.StatStr

    return call


def _observe(state: str, with_admin: bool) -> list[tuple[Any, ...]]:
    machine, X, program = _scenario(state)
    admin = _admin_blocks(X) if with_admin else None
    trace = []
    for k in range(300):
        if admin is not None:
            admin(k)
        program()
        if admin is not None:
            admin(k + 1000)
        trace.append(
            (
                X.state,
                X.POS,
                X.VEL,
                X.AxErrorID,
                X.Ref,
                machine.sims["X"].enabled,
                X.following_error,
            )
        )
        tick(machine)
    return trace


@pytest.mark.parametrize("state", STATES)
def test_administrative_fbs_never_change_the_state(state):
    reference = _observe(state, with_admin=False)
    trace = _observe(state, with_admin=True)
    assert [t[0] for t in trace] == [t[0] for t in reference]
    assert trace == reference


# -------------------------------------------------------------------------------- GT_EStop
def test_estop_disables_every_axis_of_the_module():
    machine = make_machine({"X": mcl.SimAxisParams(start=0.2), "Y": mcl.SimAxisParams(start=0.3)})
    X, Y = machine.axes["X"], machine.axes["Y"]
    vel = mcl.MC_MoveVelocity()
    machine.run(
        lambda: vel(Axis=X, Execute=True, Velocity=100.0), until=lambda: vel.InVelocity, timeout=2.0
    )
    trip_following_error(machine, Y)
    assert Y.state == AxisState.ErrorStop and Y.AxErrorID == mcl.ErrorID.ERRPOS
    estop = mcl.GT_EStop()
    estop(Axis=X, Enable=True)
    vel(Execute=True)
    assert vel.CommandAborted and not vel.Busy
    for _ in range(20):
        estop(Enable=True)
        assert estop.Done
        tick(machine)
    for axis in (X, Y):
        assert axis.state == AxisState.Disabled
        assert axis.AxErrorID == 0, "GT_EStop clears the errors"
        assert not machine.sims[axis.name].enabled

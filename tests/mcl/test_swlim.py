"""GT_SWLim on simulated axes: software limits set and switched at run time, a limit that a
commanded move would cross refused (Ecil) with the move going on, a velocity motion stopped at
a limit written ahead of it (judged by the simulated carriage), refused calls changing nothing.
"""

from __future__ import annotations

import math

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_BufferMode
from tests.helpers import (
    CONSTANTS,
    POS_TOL,
    carriage_mm,
    configure,
    fresh_axis,
    make_machine,
    power_on,
    tick,
)
from tests.mcl.test_fb_rules import exclusive


def swlim(axis: mcl.Axis, **inputs: float | bool) -> mcl.GT_SWLim:
    fb = mcl.GT_SWLim(Axis=axis)
    fb(Execute=True, **inputs)
    exclusive(fb)
    return fb


def test_limits_set_and_switched_at_run_time(machine, X):
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0)
    assert swlim(X, LimPos=100.0, LimNeg=-50.0).Done
    assert X.sw_limit_range() == (-50.0, 100.0)
    for target, error in ((150.0, ErrorID.Ecil), (-60.0, ErrorID.Ecil), (100.0, 0)):
        move(Execute=False)
        move(Execute=True, Position=target)
        assert move.ErrorID == error, target
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=3.0)
    # only the negative limit on: 150 is allowed now
    assert swlim(X, LimPos=100.0, LimNeg=-50.0, EnableLimitPos=False).Done
    assert X.sw_limit_range() == (-50.0, math.inf)
    move(Execute=False)
    machine.run(lambda: move(Execute=True, Position=150.0), until=lambda: move.Done, timeout=3)
    assert carriage_mm(machine) == pytest.approx(150.0, abs=POS_TOL)
    # both off
    assert swlim(X, EnableLimitPos=False, EnableLimitNeg=False).Done
    assert X.sw_limit_range() == (-math.inf, math.inf)
    # the parameters read them back
    read = mcl.MC_ReadParameter(Axis=X, Enable=True, ParameterNumber=3)
    read()
    assert read.Value == 0.0


def test_rising_edge_done_and_falling_edge(machine, X):
    fb = mcl.GT_SWLim(Axis=X, LimPos=300.0, LimNeg=-300.0)
    for value in (300.0, 200.0, 100.0):  # changed while Execute stays TRUE: not applied
        fb(Execute=True, LimPos=value)
        exclusive(fb)
        assert fb.Done and not fb.Busy
    assert X.sw_limit_range() == (-300.0, 300.0)
    fb(Execute=False)
    assert not (fb.Done or fb.Busy or fb.Error)
    fb(Execute=True)
    assert X.sw_limit_range() == (-300.0, 100.0)


@pytest.mark.parametrize(
    "inputs",
    [
        {"LimPos": math.nan, "LimNeg": -10.0},
        {"LimPos": 10.0, "LimNeg": -math.inf},
        {"LimPos": "high", "LimNeg": -10.0},
        {"LimPos": -10.0, "LimNeg": 10.0},
        {"LimPos": 10.0, "LimNeg": 10.0},
    ],
    ids=["nan", "inf", "string", "crossed", "equal"],
)
def test_parameter_errors_change_nothing_and_leave_the_move_running(machine, X, inputs):
    assert swlim(X, LimPos=500.0, LimNeg=-500.0).Done
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0, Position=200.0)
    machine.run(lambda: move(Execute=True), until=lambda: X.POS > 50.0, timeout=2.0)
    before = (X.state, X.sw_limit_range())
    bad = swlim(X, **inputs)
    assert bad.Error and bad.ErrorID == ErrorID.EParam
    assert (X.state, X.sw_limit_range()) == before
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=3.0)
    assert carriage_mm(machine) == pytest.approx(200.0, abs=POS_TOL)


def test_a_limit_the_running_move_would_cross_is_refused_and_the_move_goes_on(machine, X):
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0, Position=300.0)
    machine.run(lambda: move(Execute=True), until=lambda: X.POS > 100.0, timeout=2.0)
    assert swlim(X, LimPos=250.0, LimNeg=-10.0).ErrorID == ErrorID.Ecil
    assert swlim(X, LimPos=500.0, LimNeg=150.0).ErrorID == ErrorID.Ecil  # behind the axis
    assert X.sw_limit_range() == (-math.inf, math.inf)
    assert swlim(X, LimPos=300.0, LimNeg=-10.0).Done  # on the target: allowed
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=3.0)
    assert X.AxErrorID == 0 and X.state == AxisState.StandStill
    assert carriage_mm(machine) == pytest.approx(300.0, abs=POS_TOL)


def test_a_queued_target_beyond_the_new_limit_is_refused(machine, X):
    first = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0, Position=100.0)
    second = mcl.MC_MoveRelative(
        Axis=X, Velocity=200.0, Distance=100.0, BufferMode=MC_BufferMode.Buffered
    )
    first(Execute=True)
    second(Execute=True)
    assert swlim(X, LimPos=150.0, LimNeg=-10.0).ErrorID == ErrorID.Ecil  # 200 queued
    assert swlim(X, LimPos=200.0, LimNeg=-10.0).Done


def test_a_velocity_motion_is_stopped_at_a_limit_written_ahead_of_it(machine, X):
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0)
    machine.run(lambda: vel(Execute=True), until=lambda: X.POS > 20.0, timeout=2.0)
    assert swlim(X, LimPos=60.0, LimNeg=-100.0).Done
    machine.run(lambda: vel(Execute=True), until=lambda: vel.Error, timeout=2.0)
    assert vel.ErrorID == ErrorID.ERRSWP and X.AxErrorID == ErrorID.ERRSWP
    tick(machine, 100)
    # the maximum ramp: 100 mm/s stop in 0.25 mm at 20000 mm/s², loop lag aside
    assert carriage_mm(machine) == pytest.approx(60.0, abs=1.0)
    assert X.state == AxisState.ErrorStop


def test_without_ref_the_limits_are_stored_but_not_supervised():
    machine = make_machine("X", referenced=False)
    X = machine.axes["X"]
    assert swlim(X, LimPos=10.0, LimNeg=-10.0).Done
    assert X.parameters.sw_enable_pos and X.sw_limit_range() == (-math.inf, math.inf)
    move = mcl.MC_MoveRelative(Axis=X, Distance=50.0, Velocity=200.0)
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=3.0)
    assert X.AxErrorID == 0
    # nor checked when set: limits the axis stands beyond are taken
    assert swlim(X, LimPos=20.0, LimNeg=-10.0).Done
    assert (X.parameters.sw_limit_pos, X.parameters.sw_limit_neg) == (20.0, -10.0)


def test_needs_the_constants_and_works_in_every_state():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    assert swlim(X, LimPos=10.0, LimNeg=-10.0).ErrorID == ErrorID.Econst
    machine = make_machine("X")
    X = machine.axes["X"]
    X.fault(ErrorID.ERRLIP)
    tick(machine, 20)
    assert X.state == AxisState.ErrorStop
    assert swlim(X, LimPos=100.0, LimNeg=-100.0).Done
    assert X.sw_limit_range() == (-100.0, 100.0)


def test_gt_setconstant_sets_the_limits_anew(machine, X):
    assert swlim(X, LimPos=100.0, LimNeg=-100.0).Done
    constants = mcl.GT_SetConstant(Axis=X)
    constants(Execute=True, **{**CONSTANTS, "LimPos": 400.0, "LimNeg": -400.0})
    assert constants.Done and X.sw_limit_range() == (-400.0, 400.0)


def limits(near: float, far: float) -> dict[str, float]:
    """GT_SWLim's LimPos / LimNeg for a limit ``near`` and one ``far`` on the other side [mm]."""
    return {"LimPos": max(near, far), "LimNeg": min(near, far)}


@pytest.mark.parametrize("side", [-1.0, 1.0], ids=["negative", "positive"])
def test_after_a_software_limit_stop_the_other_limit_may_be_switched_off_or_moved(side):
    """The axis stopped just beyond SWLimitNeg (ERRSWN) or SWLimitPos (ERRSWP): switching the
    other limit off or moving it is allowed (only a limit switched on or moved is checked
    against the axis), the one it stopped at still refuses being moved further in and a target
    beyond it, and the axis moves back inward."""
    machine, X = fresh_axis()
    assert swlim(X, **limits(20.0 * side, -150.0 * side)).Done
    direction = mcl.MC_Direction.MC_Negative if side < 0 else mcl.MC_Direction.MC_Positive
    vel = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0, Direction=direction)
    machine.run(lambda: vel(Execute=True), until=lambda: vel.Error, timeout=3.0)
    assert vel.ErrorID == (ErrorID.ERRSWN if side < 0 else ErrorID.ERRSWP)
    tick(machine, 100)
    assert X.POS * side > 20.0 and carriage_mm(machine) * side > 20.0
    reset = mcl.MC_Reset(Axis=X)
    machine.run(lambda: reset(Execute=True), until=lambda: reset.Done, timeout=1.0)
    assert X.state == AxisState.StandStill
    other = 4 if side < 0 else 5  # EnableLimitPos / EnableLimitNeg
    off = mcl.MC_WriteBoolParameter(Axis=X, Execute=True, ParameterNumber=other, Value=False)
    off()
    assert off.Done and not off.Error
    assert X.sw_limit_range() == ((-20.0, math.inf) if side < 0 else (-math.inf, 20.0))
    assert swlim(X, **limits(20.0 * side, -300.0 * side)).Done
    assert X.sw_limit_range() == tuple(sorted((20.0 * side, -300.0 * side)))
    # the limit it stopped at is still on: moving it further in, or a target beyond it, is refused
    assert swlim(X, **limits(19.0 * side, -300.0 * side)).ErrorID == ErrorID.Ecil
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=100.0, Position=30.0 * side)
    move(Execute=True)
    assert move.ErrorID == ErrorID.Ecil
    move(Execute=False)
    back = 250.0 if side < 0 else -150.0  # within the travel (−210..810 mm)
    machine.run(lambda: move(Execute=True, Position=back), until=lambda: move.Done, timeout=5.0)
    assert X.AxErrorID == 0
    assert carriage_mm(machine) == pytest.approx(back, abs=POS_TOL)


def test_a_limit_switched_off_is_not_checked_whatever_value_it_carries(machine, X):
    """A limit given with its Enable FALSE is stored, not checked: a value the axis stands
    beyond is no reason to refuse the call, and the axis moves freely on that side."""
    assert swlim(X, LimPos=-10.0, LimNeg=-500.0, EnableLimitPos=False).Done
    assert X.sw_limit_range() == (-500.0, math.inf)
    assert swlim(X, LimPos=500.0, LimNeg=10.0, EnableLimitNeg=False).Done
    assert X.sw_limit_range() == (-math.inf, 500.0)
    assert X.parameters.sw_limit_neg == 10.0 and not X.parameters.sw_enable_neg
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0, Position=-5.0)
    machine.run(lambda: move(Execute=True), until=lambda: move.Done or move.Error, timeout=3.0)
    assert move.Done and X.AxErrorID == 0
    assert carriage_mm(machine) == pytest.approx(-5.0, abs=POS_TOL)


def test_a_limit_switched_on_again_behind_the_axis_is_refused(machine, X):
    """LimPos 30 switched off, the axis moved to 50, LimPos switched on again at the same 30:
    that limit is new to the axis beyond it, so the call is refused (Ecil) and the axis stays
    free to move on."""
    assert swlim(X, LimPos=30.0, LimNeg=-500.0).Done
    write = mcl.MC_WriteBoolParameter(Axis=X, ParameterNumber=4)
    write(Execute=True, Value=False)
    assert write.Done
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0, Position=50.0)
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=3.0)
    write(Execute=False)
    write(Execute=True, Value=True)
    assert write.Error and write.ErrorID == ErrorID.Ecil
    assert swlim(X, LimPos=30.0, LimNeg=-500.0).ErrorID == ErrorID.Ecil
    assert X.sw_limit_range() == (-500.0, math.inf)
    move(Execute=False)
    machine.run(lambda: move(Execute=True, Position=80.0), until=lambda: move.Done, timeout=3.0)
    assert X.AxErrorID == 0
    assert carriage_mm(machine) == pytest.approx(80.0, abs=POS_TOL)


def test_on_a_modulo_axis_the_limits_are_stored_but_never_act():
    """A referenced rotary axis at 100°: limits 10°..50° are taken (not checked against the
    axis) and stored, and the axis turns on past them."""
    params = mcl.SimAxisParams(stop_neg=-1e6, stop_pos=1e6, lim_neg=-1e6, lim_pos=1e6)
    machine = mcl.SimMachine({"R": params}, config=mcl.AxisConfig(modulo=360.0))
    R = machine.axes["R"]
    configure(R)
    power_on(machine, R)
    assert R.Ref
    turn = mcl.MC_MoveAbsolute(Axis=R, Position=100.0, Velocity=300.0)
    machine.run(lambda: turn(Execute=True), until=lambda: turn.Done, timeout=3.0)
    assert swlim(R, LimPos=50.0, LimNeg=10.0).Done
    assert R.parameters.sw_enable_pos and R.parameters.sw_limit_pos == 50.0
    assert R.sw_limit_range() == (-math.inf, math.inf)
    turn(Execute=False)
    machine.run(lambda: turn(Execute=True, Position=200.0), until=lambda: turn.Done, timeout=3.0)
    assert R.AxErrorID == 0 and abs(R.POS - 200.0) <= POS_TOL

"""MC_ReadParameter, MC_ReadBoolParameter, MC_WriteParameter, MC_WriteBoolParameter on simulated
axes: every parameter reads what the axis does, writes take effect as PLCopen says (the
application maxima limit the next move, judged by the simulated carriage; the software limits
and the following-error supervision at once), refused writes leave the axis as it was.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_ExecutionMode
from mcl.parameters import PARAMETERS, READ_ONLY
from tests.helpers import (
    CONSTANTS,
    PLC,
    carriage_mm,
    carriage_mm_s,
    configure,
    fresh_axis,
    in_velocity,
    make_machine,
    power_on,
    tick,
)
from tests.mcl.test_fb_rules import exclusive


def write(axis: mcl.Axis, number: int, value: float | bool, **inputs: Any) -> mcl.MC_WriteParameter:
    """One scan of a fresh write block (BOOL or REAL by the value's type)."""
    fb = mcl.MC_WriteBoolParameter() if isinstance(value, bool) else mcl.MC_WriteParameter()
    fb(Axis=axis, Execute=True, ParameterNumber=number, Value=value, **inputs)
    exclusive(fb)
    return fb  # type: ignore[return-value]


def valid_or_error(fb: Any) -> None:
    """The outputs of a reading block: Valid and Error exclusive, Busy only with Valid, Error
    iff ErrorID != 0."""
    assert not (fb.Valid and fb.Error)
    assert not (fb.Busy and fb.Error)
    assert bool(fb.Error) == (fb.ErrorID != 0)


def read(axis: mcl.Axis, number: int) -> float:
    fb = mcl.MC_ReadParameter(Axis=axis, Enable=True, ParameterNumber=number)
    fb()
    assert fb.Valid and fb.Busy and not fb.Error, (number, fb.ErrorID)
    return fb.Value


def peak_speed(machine: mcl.SimMachine, fb: Any, **inputs: Any) -> float:
    """Run ``fb`` to Done; the carriage's highest speed [mm/s]."""
    peak = 0.0

    def program() -> None:
        nonlocal peak
        fb(Execute=True, **inputs)
        peak = max(peak, abs(carriage_mm_s(machine)))

    machine.run(program, until=lambda: fb.Done, timeout=10.0)
    fb(Execute=False)
    return peak


# ----------------------------------------------------------------------------- reading


def test_every_real_parameter_reads_what_the_axis_holds(machine, X):
    in_velocity(machine, X, 120.0)
    config, c = X.config, X.constants
    assert c is not None
    expected = {
        1: X.OPT1n,
        2: 0.0,
        3: 0.0,
        7: config.dev_max,
        8: c.Vmax,
        9: c.Vmax,
        10: X.VEL,
        11: X.sp_vel,
        12: config.max_acceleration,
        13: config.max_acceleration,
        14: config.max_deceleration,
        15: config.max_deceleration,
        16: config.max_jerk,
        1000: 0.0,
        **{1000 + i: CONSTANTS.get(name, 0.0) for i, name in enumerate(CONSTANTS_ORDER, 1)},
    }
    expected[1004] = c.Ff
    for number, value in expected.items():
        assert read(X, number) == pytest.approx(value), number
    assert read(X, 11) == pytest.approx(120.0)


CONSTANTS_ORDER = (
    "Kp", "Ki", "Kd", "Ff", "Kc", "Vmax", "LimPos", "LimNeg", "Ki1", "Filter", "Ka", "Kf",
    "FfNeg", "Deadband", "Kfp", "Tfp", "Vf",
)  # fmt: skip


def test_the_vendor_numbers_follow_the_inputs_of_gt_setconstant():
    assert CONSTANTS_ORDER == mcl.GT_SetConstant.INPUTS
    names = {n: name for n, name, _, _, _ in PARAMETERS}
    assert [names[1000 + i] for i in range(1, 18)] == list(CONSTANTS_ORDER)


def test_bool_parameters_and_wrong_numbers(machine, X):
    rb = mcl.MC_ReadBoolParameter(Axis=X, Enable=True)
    for number, value in ((4, False), (5, False), (6, True)):
        rb(ParameterNumber=number)
        assert rb.Valid and rb.Value is value
    r = mcl.MC_ReadParameter(Axis=X, Enable=True)
    for number in (0, 4, 5, 6, 17, 999, 1018, -1):
        r(ParameterNumber=number)
        valid_or_error(r)
        assert r.Error and r.ErrorID == ErrorID.ENoParameter and not r.Valid and r.Value == 0.0
    for number in (1, 2, 7, 1001):
        rb(ParameterNumber=number)
        valid_or_error(rb)
        assert rb.ErrorID == ErrorID.ENoParameter and rb.Value is False
    r(ParameterNumber=8)  # the error goes away with a valid number (rule 10)
    assert r.Valid and not r.Error and r.Value == 500.0
    r(Enable=False)
    assert not (r.Valid or r.Busy or r.Error) and r.Value == 0.0


def test_constants_are_needed_for_vmax_and_the_servo_constants():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    r = mcl.MC_ReadParameter(Axis=X, Enable=True)
    for number in (8, 9, 1001):
        r(ParameterNumber=number)
        assert r.ErrorID == ErrorID.Econst
        assert write(X, number, 100.0).ErrorID == (
            ErrorID.EReadOnly if number == 8 else ErrorID.Econst
        )
    r(ParameterNumber=10)
    assert r.Valid


def test_actual_velocity_is_the_measured_velocity_within_a_count_per_servo_period(machine, X):
    in_velocity(machine, X, 237.0)
    r = mcl.MC_ReadParameter(ParameterNumber=10)
    count_per_period = X.config.resolution / X.servo_period  # 1 mm/s
    worst = 0.0
    for _ in range(100):
        r(Axis=X, Enable=True)
        worst = max(worst, abs(r.Value - carriage_mm_s(machine)))
        tick(machine)
    assert worst <= count_per_period, f"{worst} mm/s"


# ----------------------------------------------------------------------------- writing


def test_read_only_unknown_and_invalid_writes_are_refused_and_change_nothing(machine, X):
    before = (X.parameters, X.constants)
    for number in sorted(READ_ONLY):
        assert write(X, number, 1.0).ErrorID == ErrorID.EReadOnly, number
    for number in (0, 17, 4, 1018):
        assert write(X, number, 1.0).ErrorID == ErrorID.ENoParameter, number
    for number in (1, 7, 2):
        assert write(X, number, True).ErrorID == ErrorID.ENoParameter, number
    for number, value in [
        (9, math.nan), (9, math.inf), (9, 0.0), (9, -5.0), (7, 0.0), (13, -1.0), (15, 0.0),
        (16, -1.0), (2, math.nan), (1006, 0.0), (1001, -1.0), (1010, math.inf),
    ]:  # fmt: skip
        assert write(X, number, value).ErrorID == ErrorID.EParam, (number, value)
    for mode in (MC_ExecutionMode.mcDelayed, 9):
        assert write(X, 9, 100.0, ExecutionMode=mode).ErrorID == ErrorID.EParam
    assert (X.parameters, X.constants) == before


def test_max_velocity_appl_limits_the_next_move_not_the_running_one(machine, X):
    first, second = mcl.MC_MoveRelative(Axis=X), mcl.MC_MoveRelative(Axis=X)
    w = mcl.MC_WriteParameter(Axis=X, ParameterNumber=9, Value=150.0)
    peak = 0.0
    first(Execute=True, Distance=300.0, Velocity=300.0)
    for k in range(1000):
        first(Execute=True)
        w(Execute=k >= 20)
        if k == 20:
            assert w.Done
        peak = max(peak, carriage_mm_s(machine))
        if first.Done:
            break
        tick(machine)
    assert first.Done and peak == pytest.approx(300.0, rel=0.02), "the running move kept 300"
    assert read(X, 9) == 150.0
    limited = peak_speed(machine, second, Distance=-300.0, Velocity=400.0)
    assert limited == pytest.approx(150.0, rel=0.02)
    # above the system maximum: clamped to Vmax
    assert write(X, 9, 1e6).Done and read(X, 9) == 500.0


def test_max_acceleration_and_deceleration_appl_limit_the_next_move(machine, X):
    assert write(X, 13, 500.0).Done and write(X, 15, 250.0).Done
    move = mcl.MC_MoveRelative(Axis=X, Distance=100.0, Velocity=200.0, Acceleration=5000.0)
    acc = [0.0, 0.0]

    def program() -> None:
        move(Execute=True)
        acc[0], acc[1] = max(acc[0], X.sp_acc), min(acc[1], X.sp_acc)

    machine.run(program, until=lambda: move.Done, timeout=5.0)
    assert acc[0] == pytest.approx(500.0) and acc[1] == pytest.approx(-250.0)
    assert write(X, 13, 1e9).Done and read(X, 13) == X.config.max_acceleration


def test_max_jerk_limits_the_next_move(machine, X):
    assert write(X, 16, 20000.0).Done and read(X, 16) == 20000.0
    move = mcl.MC_MoveRelative(Axis=X, Distance=50.0, Velocity=200.0, Acceleration=2000.0)
    worst, last = 0.0, 0.0

    def program() -> None:
        nonlocal worst, last
        move(Execute=True)
        worst, last = max(worst, abs(X.sp_acc - last) / PLC), X.sp_acc

    machine.run(program, until=lambda: move.Done, timeout=5.0)
    assert worst <= 20000.0 * 1.01


def test_max_jerk_is_at_most_the_machines_and_zero_means_the_machines():
    """On a machine of max_jerk 100000 mm/s³ MaxJerk may be lowered, but a value above it, or
    0, gives the machine's: it reads back and a move asked for more runs with it."""
    config = mcl.AxisConfig(max_jerk=1e5)
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)}, config=config)
    X = machine.axes["X"]
    configure(X)
    power_on(machine, X)
    assert read(X, 16) == 1e5
    assert write(X, 16, 5e4).Done and read(X, 16) == 5e4
    assert write(X, 16, 1e7).Done and read(X, 16) == 1e5
    assert write(X, 16, 5e4).Done and write(X, 16, 0.0).Done and read(X, 16) == 1e5
    move = mcl.MC_MoveRelative(Axis=X, Distance=50.0, Velocity=200.0, Acceleration=5000.0)
    worst, last = 0.0, 0.0

    def program() -> None:
        nonlocal worst, last
        move(Execute=True, Jerk=1e7)
        worst, last = max(worst, abs(X.sp_acc - last) / PLC), X.sp_acc

    machine.run(program, until=lambda: move.Done, timeout=5.0)
    assert 0.9e5 <= worst <= 1e5 * (1.0 + 1e-9)
    assert carriage_mm(machine) == pytest.approx(50.0, abs=0.05)
    # a machine without a jerk limit: 0 is none
    machine, X = fresh_axis()
    assert X.config.max_jerk == 0.0
    assert write(X, 16, 1e7).Done and read(X, 16) == 1e7
    assert write(X, 16, 0.0).Done and read(X, 16) == 0.0


def test_software_limits_written_act_at_once_and_refuse_what_would_cross_them(machine, X):
    move = mcl.MC_MoveAbsolute(Axis=X, Velocity=200.0)
    assert write(X, 2, 100.0).Done and write(X, 3, -100.0).Done
    assert X.sw_limit_range() == (-math.inf, math.inf), "written, not yet switched on"
    assert write(X, 4, True).Done and write(X, 5, True).Done
    assert X.sw_limit_range() == (-100.0, 100.0)
    move(Execute=True, Position=150.0)
    assert move.ErrorID == ErrorID.Ecil
    move(Execute=False)
    assert write(X, 4, False).Done  # the positive limit off: 150 is allowed
    machine.run(lambda: move(Execute=True), until=lambda: X.POS > 120.0, timeout=2.0)
    # switching it on again is refused while the running target lies beyond it; a limit that
    # is off may be set anywhere, switching it on then is refused alike
    assert write(X, 4, True).ErrorID == ErrorID.Ecil
    assert write(X, 2, 140.0).Done
    assert write(X, 4, True).ErrorID == ErrorID.Ecil
    assert not X.parameters.sw_enable_pos and X.parameters.sw_limit_pos == 140.0
    machine.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=3.0)
    assert carriage_mm(machine) == pytest.approx(150.0, abs=0.05)
    # both on with SWLimitPos <= SWLimitNeg
    assert write(X, 2, 200.0).Done and write(X, 4, True).Done
    assert write(X, 3, 250.0).ErrorID == ErrorID.EParam


def test_a_velocity_motion_is_stopped_by_a_limit_written_ahead_of_it(machine, X):
    vel = mcl.MC_MoveVelocity(Axis=X)
    machine.run(lambda: vel(Execute=True, Velocity=100.0), until=lambda: X.POS > 20, timeout=2)
    assert write(X, 2, 60.0).Done and write(X, 3, -1000.0).Done
    assert write(X, 4, True).Done
    machine.run(lambda: vel(Execute=True), until=lambda: vel.Error, timeout=2.0)
    assert vel.ErrorID == ErrorID.ERRSWP and X.state == AxisState.ErrorStop
    tick(machine, 100)
    assert carriage_mm(machine) == pytest.approx(60.0, abs=1.0)


def test_gt_setconstant_and_vendor_writes_of_the_limits(machine, X):
    assert write(X, 2, 300.0).Done and write(X, 3, -300.0).Done and write(X, 4, True).Done
    assert write(X, 1001, 4.0).Done  # Kp: the limits as they were
    assert X.constants is not None and X.constants.Kp == 4.0
    assert X.sw_limit_range() == (-math.inf, 300.0)
    assert write(X, 1008, 10.0).Done  # LimNeg as GT_SetConstant: LimPos 0 <= LimNeg: both off
    assert X.sw_limit_range() == (-math.inf, math.inf)
    assert write(X, 1008, -400.0).Done
    assert write(X, 1007, 400.0).Done  # LimPos 400 > LimNeg -400: both on
    assert X.sw_limit_range() == (-400.0, 400.0)
    assert read(X, 2) == 400.0 and read(X, 1008) == -400.0


def test_lag_monitoring_off_lets_a_blocked_axis_lag_on(machine, X):
    sim = machine.sims["X"]
    sim.blocked_at = sim.x + 0.005  # an obstacle 5 mm ahead
    assert write(X, 6, False).Done
    move = mcl.MC_MoveRelative(Axis=X)
    machine.run(lambda: move(Execute=True, Distance=100.0, Velocity=100.0), timeout=0.5)
    assert X.state == AxisState.DiscreteMotion and X.following_error > 10.0
    assert X.AxErrorID == 0 and move.Busy


def _lag_at_errpos(limit: float) -> float:
    """The largest following error of a move into an obstacle before ERRPOS trips, with
    MaxPositionLag written to ``limit`` [mm]."""
    machine, X = fresh_axis()
    if limit != X.config.dev_max:
        assert write(X, 7, limit).Done
    sim = machine.sims["X"]
    sim.blocked_at = sim.x + 0.001
    move = mcl.MC_MoveRelative(Axis=X, Distance=30.0, Velocity=100.0)
    lag = 0.0

    def program() -> None:
        nonlocal lag
        move(Execute=True)
        if X.state != AxisState.ErrorStop:
            lag = max(lag, abs(X.following_error))

    machine.run(program, until=lambda: move.Error, timeout=1.0)
    assert move.ErrorID == ErrorID.ERRPOS
    return lag


def test_a_smaller_max_position_lag_trips_errpos_sooner():
    assert 1.5 < _lag_at_errpos(2.0) <= 2.0
    assert 0.3 < _lag_at_errpos(0.5) <= 0.5


def test_queued_write_takes_effect_when_the_move_before_it_is_done(machine, X):
    first, second = mcl.MC_MoveRelative(Axis=X), mcl.MC_MoveRelative(Axis=X)
    w = mcl.MC_WriteParameter(
        Axis=X, ParameterNumber=9, Value=120.0, ExecutionMode=MC_ExecutionMode.mcQueued
    )
    first(Execute=True, Distance=100.0, Velocity=300.0)
    w(Execute=True)
    assert w.Busy and read(X, 9) == 500.0

    def program() -> None:
        first(Execute=True)
        w(Execute=True)
        exclusive(w)
        assert w.Done == first.Done

    machine.run(program, until=lambda: w.Done, timeout=5.0)
    assert read(X, 9) == 120.0
    assert peak_speed(machine, second, Distance=-100.0, Velocity=300.0) == pytest.approx(
        120.0, rel=0.02
    )


def test_execute_held_writes_once_and_a_new_edge_writes_the_new_value(machine, X):
    w = mcl.MC_WriteParameter(Axis=X, ParameterNumber=9)
    for value in (100.0, 200.0, 300.0):  # changed while Execute stays TRUE: no effect
        w(Execute=True, Value=value)
        assert w.Done
    assert read(X, 9) == 100.0
    w(Execute=False)
    assert not w.Done
    w(Execute=True)
    assert read(X, 9) == 300.0


def test_saved_state_keeps_the_parameters():
    machine = make_machine("X")
    X = machine.axes["X"]
    assert write(X, 9, 111.0).Done and write(X, 6, False).Done
    state = machine.save_state()
    assert write(X, 9, 222.0).Done and write(X, 6, True).Done
    machine.restore_state(state)
    assert read(X, 9) == 111.0 and not X.parameters.lag_monitoring
    _machine2, Y = fresh_axis()
    assert read(Y, 9) == 500.0


# ----------------------------------------------------------------------------- the gantry


def test_gantry_max_velocity_appl_limits_the_next_move_and_actual_velocity_reads_the_joint():
    """On the MuJoCo gantry, judged by the X joint's velocity: a move at 400 mm/s runs at 400;
    after MC_WriteParameter(9) = 150 the next move commanded at 400 runs at 150; while it
    cruises, MC_ReadParameter(10) (VEL) equals the joint velocity within one encoder count per
    servo period."""
    from scenes.machines import gantry

    scene = gantry.build(start={"X": 0.3, "Y": 0.3, "Z": -0.1}, trace_every=0)
    X = scene.axes["X"]
    dof = scene.io("X").dof
    power, move = mcl.MC_Power(Axis=X), mcl.MC_MoveRelative(Axis=X)
    actual = mcl.MC_ReadParameter(Axis=X, ParameterNumber=10)

    def joint_mm_s() -> float:
        return float(scene.data.qvel[dof]) * 1000.0

    def run(distance: float) -> tuple[float, float]:
        """The move's peak joint speed, and the largest |ActualVelocity − joint velocity|
        while the set point cruises [mm/s]."""
        peak = worst = 0.0

        def program() -> None:
            nonlocal peak, worst
            power(Enable=True)
            move(Execute=True, Distance=distance, Velocity=400.0, Acceleration=4000.0)
            actual(Enable=True)
            assert actual.Valid
            peak = max(peak, abs(joint_mm_s()))
            if X.sp_vel != 0.0 and X.sp_acc == 0.0:
                worst = max(worst, abs(actual.Value - joint_mm_s()))

        scene.run(program, until=lambda: move.Done, timeout=5.0)
        move(Execute=False)
        return peak, worst

    scene.run(lambda: power(Enable=True), until=lambda: power.Status, timeout=1.0)
    free, worst_free = run(200.0)
    limit = write(X, 9, 150.0)
    assert limit.Done
    limited, worst_limited = run(-200.0)
    assert free == pytest.approx(400.0, rel=0.01)
    assert limited == pytest.approx(150.0, rel=0.01)
    count_per_period = X.config.resolution / X.servo_period
    assert max(worst_free, worst_limited) <= count_per_period

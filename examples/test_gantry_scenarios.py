"""Scenario tests of a small PLC program on the gantry, as a user writes them with the plugin."""

import pytest

import mcl
from scenes.tools.testing import (
    assert_pulsed_once,
    max_following_error,
    physical_position,
    run_until,
)


def test_x_moves_to_500_mm_within_its_following_error_budget(scene, scans):
    gantry = scene("gantry", start={"X": 0.3})
    X = gantry.axes["X"]
    power = mcl.MC_Power(Axis=X)
    home = mcl.MC_FinishHoming(Axis=X)  # the coordinate counts from power-up here
    move = mcl.MC_MoveAbsolute(Axis=X, Position=200.0, Velocity=300.0, Acceleration=3000.0)
    log = scans(done=lambda: move.Done)

    def program():
        power(Enable=True)
        home(Execute=power.Status)
        move(Execute=home.Done)

    run_until(gantry, log.wrap(program), lambda: move.Done, timeout=3.0)
    gantry.run(log.wrap(program), timeout=0.2)
    assert physical_position(gantry, "X") == pytest.approx(300.0 + 200.0, abs=0.005)
    assert max_following_error(gantry, "X") < 0.1
    assert log["done"][-1]  # Done stays while Execute is held


def test_a_stuck_limit_switch_ends_in_an_error_stop_at_the_hard_stop(scene):
    gantry = scene("gantry", start={"X": 0.9})
    X = gantry.axes["X"]
    gantry.faults.set("X", mcl.faults.SwitchStuck("lim_pos", False))
    power = mcl.MC_Power(Axis=X)
    jog = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0)

    def program():
        power(Enable=True)
        jog(Execute=power.Status)

    run_until(gantry, program, lambda: X.state == mcl.AxisState.ErrorStop, timeout=5.0)
    assert X.AxErrorID == mcl.ErrorID.ERRPOS  # the following error, on the hard stop
    gantry.run(program, timeout=0.5)  # the drive is off: the carriage comes to rest
    stop_mm = gantry.model.jnt_range[gantry.io("X").joint][1] * 1000.0  # the joint's end
    assert physical_position(gantry, "X") == pytest.approx(stop_mm, abs=0.1)  # resting on it


def test_reset_pulses_done_for_one_scan_after_execute_falls(scene, scans):
    machine = scene("single_axis")
    X = machine.axes["X"]
    reset = mcl.MC_Reset(Axis=X)
    log = scans(done=lambda: reset.Done)
    ticks = [0]

    def program():
        ticks[0] += 1
        reset(Execute=ticks[0] == 1)

    machine.run(log.wrap(program), timeout=0.02)
    assert assert_pulsed_once(log["done"], "MC_Reset.Done") == 0

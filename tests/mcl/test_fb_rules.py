"""The rules every function block follows (MotionControlLib Tab. 2.3; docs/reference.md, Calling a
function block and Outputs), one test group per rule, numbered as in the section comments below.

The tests drive FBs scan by scan: an FB call is one PLC scan of that block, ``tick`` lets one PLC
cycle (2 ms: two servo cycles, four plant steps) pass. Every test fails if its rule breaks.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

import mcl
from mcl.fb import ExecuteFB, input_names
from tests.helpers import (
    POS_TOL,
    assert_at,
    configure,
    fresh_axis,
    in_velocity,
    make_machine,
    tick,
    true_position,
)


def exclusive(fb: Any) -> None:
    """Rule 2, mutual exclusion, on the outputs of ``fb`` as they are now (plus: Error iff
    ErrorID != 0)."""
    aborted = bool(getattr(fb, "CommandAborted", False))
    busy_group = [bool(fb.Busy), bool(fb.Done), bool(fb.Error), aborted]
    assert sum(busy_group) <= 1, f"Busy/Done/Error/Aborted = {busy_group}"
    if hasattr(fb, "Active"):
        active_group = [bool(fb.Active), bool(fb.Done), bool(fb.Error), aborted]
        assert sum(active_group) <= 1, f"Active/Done/Error/Aborted = {active_group}"
    if hasattr(fb, "InVelocity"):
        assert not (fb.InVelocity and (fb.Error or aborted)), "InVelocity with Error/Aborted"
    assert bool(fb.Error) == (fb.ErrorID != 0), f"Error={fb.Error} ErrorID={fb.ErrorID}"


def outputs_after_execute_fell(
    machine: mcl.SimMachine, fb: Any, *names: str, seconds: float = 1.0
) -> list[tuple[bool, ...]]:
    """Call ``fb`` with Execute FALSE every scan for ``seconds`` (rule 2 checked on every scan);
    the named outputs of every scan."""
    scans: list[tuple[bool, ...]] = []

    def scan() -> None:
        fb(Execute=False)
        exclusive(fb)
        scans.append(tuple(bool(getattr(fb, name)) for name in names))

    machine.run(scan, timeout=seconds)
    return scans


def seen_while_taken_over(
    machine: mcl.SimMachine, fb: Any, successor: Any, output: str, timeout: float = 5.0
) -> bool:
    """Call ``fb`` and then ``successor`` (both Execute TRUE; rule 2 checked on ``fb``) every scan
    until ``successor`` is Done: whether ``output`` of ``fb`` was ever TRUE."""
    seen = False

    def scan() -> None:
        nonlocal seen
        fb(Execute=True)
        successor(Execute=True)
        exclusive(fb)
        seen |= bool(getattr(fb, output))

    machine.run(scan, until=lambda: successor.Done, timeout=timeout)
    return seen


# ------------------------------------------ rule 1: instances of one FB type are independent
def test_rule1_instances_of_one_type_in_one_cycle_are_independent():
    machine = make_machine({"X": mcl.SimAxisParams(start=0.2), "Y": mcl.SimAxisParams(start=0.3)})
    X, Y = machine.axes["X"], machine.axes["Y"]
    a, b = mcl.MC_MoveAbsolute(), mcl.MC_MoveAbsolute()
    a_done_scan = b_done_scan = -1
    for k in range(1500):
        a(Axis=X, Execute=True, Position=60.0, Velocity=200.0)
        b(Axis=Y, Execute=True, Position=-150.0, Velocity=100.0)
        exclusive(a)
        exclusive(b)
        if a.Done and a_done_scan < 0:
            a_done_scan = k
            assert b.Busy and not b.Done, "b must still be running when a is done"
            assert_at(X, 60.0)
        if b.Done and b_done_scan < 0:
            b_done_scan = k
            assert a.Done, "a keeps its Done while its Execute stays TRUE"
        if a_done_scan >= 0 and b_done_scan >= 0:
            break
        tick(machine)
    assert 0 < a_done_scan < b_done_scan
    assert_at(X, 60.0)
    assert_at(Y, -150.0)
    assert (a.Position, b.Position) == (60.0, -150.0)


def test_rule1_error_of_one_instance_does_not_affect_another_in_the_same_cycle(machine, X):
    good, bad = mcl.MC_MoveRelative(), mcl.MC_MoveRelative()
    r1, r2 = mcl.MC_ReadActualPosition(), mcl.MC_ReadActualPosition()
    for _ in range(400):
        good(Axis=X, Execute=True, Distance=50.0, Velocity=200.0)
        bad(Axis=X, Execute=True, Distance=50.0, Velocity=-1.0)
        r1(Axis=X, Enable=True)
        r2(Axis=X, Enable=False)
        assert bad.Error and bad.ErrorID == mcl.ErrorID.EParam
        assert not good.Error and not good.CommandAborted
        assert r1.Valid and r1.Position == X.POS
        assert not r2.Valid
        if good.Done:
            break
        tick(machine)
    assert good.Done
    assert_at(X, 50.0)


# ------------- rule 2: Busy, Done, Error, CommandAborted (and Active) are mutually exclusive
def test_rule2_outputs_exclusive_on_every_scan_of_a_busy_sequence(machine, X):
    """A busy sequence (done, buffered, early falling edges, aborts, a parameter error, a stop);
    every block is called and checked on every scan."""
    a = mcl.MC_MoveAbsolute()
    b = mcl.MC_MoveRelative()
    bad = mcl.MC_MoveRelative()
    v = mcl.MC_MoveVelocity()
    c = mcl.MC_MoveAbsolute()
    s = mcl.MC_Stop()
    blocks: list[Any] = [a, b, bad, v, c, s]
    seen: dict[str, set[int]] = {n: set() for n in ("Busy", "Active", "Done", "Error", "Aborted")}
    for k in range(800):
        a(Axis=X, Execute=k < 300, Position=60.0, Velocity=300.0)
        b(
            Axis=X,
            Execute=5 <= k < 50,
            Distance=20.0,
            Velocity=300.0,
            BufferMode=mcl.MC_BufferMode.Buffered,
        )
        bad(Axis=X, Execute=10 <= k < 15, Distance=20.0, Velocity=-1.0)
        v(Axis=X, Execute=330 <= k < 620, Velocity=100.0)
        c(Axis=X, Execute=k >= 500, Position=0.0, Velocity=200.0)
        s(Axis=X, Execute=520 <= k < 600)
        for i, fb in enumerate(blocks):
            exclusive(fb)
            for name in ("Busy", "Active", "Done", "Error"):
                if getattr(fb, name, False):
                    seen[name].add(i)
            if fb.CommandAborted:
                seen["Aborted"].add(i)
        tick(machine)
    # the sequence really went through every output of the blocks it meant to
    assert seen["Done"] >= {0, 5}  # a, s
    assert seen["Aborted"] >= {1, 3, 4}  # b by v, v by c, c by s
    assert seen["Error"] >= {2}
    assert seen["Active"] >= {0, 1, 3, 4, 5}
    assert seen["Busy"] >= {0, 1, 3, 4, 5}


# ----------------------------------------- rule 3: the inputs are sampled at the rising edge
def test_rule3_position_changed_while_busy_is_ignored_until_new_edge(machine, X):
    fb = mcl.MC_MoveAbsolute()
    fb(Axis=X, Execute=True, Position=100.0, Velocity=200.0)
    tick(machine, 1)
    peak = 0.0
    for _ in range(50):
        fb(Execute=True, Position=250.0, Velocity=400.0)
        tick(machine)
    for _ in range(1000):
        fb(Execute=True, Position=250.0, Velocity=400.0)
        peak = max(peak, abs(X.OPT2n))
        if fb.Done:
            break
        tick(machine)
    assert fb.Done
    assert_at(X, 100.0)
    assert peak <= 200.0 + 1e-6, "the velocity changed while busy was applied"
    # staying TRUE with other inputs after Done changes nothing either
    fb(Execute=True, Position=300.0)
    tick(machine, 100)
    assert_at(X, 100.0)
    assert X.state == mcl.AxisState.StandStill
    # a new edge samples the changed inputs
    fb(Execute=False)
    tick(machine)
    machine.run(lambda: fb(Execute=True), until=lambda: fb.Done, timeout=5.0)
    assert_at(X, 300.0)


def test_rule3_exception_extstop_is_read_every_scan(machine, X):
    fb = mcl.GT_MoveAbsBlock()
    fb(Axis=X, Execute=True, Position=200.0, Velocity=200.0)
    machine.run(lambda: fb(Execute=True), until=lambda: X.POS > 50.0, timeout=2.0)
    machine.run(lambda: fb(Execute=True, ExtStop=True), until=lambda: fb.Done, timeout=2.0)
    assert X.POS < 150.0
    tick(machine, 50)
    assert abs(X.VEL) < 1.0
    assert X.state == mcl.AxisState.StandStill


def test_rule3_exception_jog_buttons_are_read_every_scan(machine, X):
    jog = mcl.GT_Jog()
    machine.run(
        lambda: jog(Axis=X, Enable=True, JogPos=True, JogVelo=100.0),
        until=lambda: X.POS > 20.0,
        timeout=2.0,
    )
    assert X.state == mcl.AxisState.ContinuousMotion
    machine.run(lambda: jog(JogPos=False), timeout=0.5)
    assert X.state == mcl.AxisState.StandStill
    turn_back = X.POS - 10.0
    machine.run(lambda: jog(JogNeg=True), until=lambda: X.POS - turn_back < 0.0, timeout=2.0)
    assert X.VEL < 0.0


# ---------------------------------------- rule 4: an input left out keeps its previous value
def test_rule4_missing_input_keeps_previous_value(machine, X):
    fb = mcl.MC_MoveAbsolute()
    machine.run(
        lambda: fb(Axis=X, Execute=True, Position=50.0, Velocity=200.0),
        until=lambda: fb.Done,
        timeout=5.0,
    )
    fb(Execute=False)
    other = mcl.MC_MoveAbsolute()
    machine.run(
        lambda: other(Axis=X, Execute=True, Position=-40.0, Velocity=200.0),
        until=lambda: other.Done,
        timeout=5.0,
    )
    # neither Axis nor Position nor Velocity given: the previous call's values are used
    machine.run(lambda: fb(Execute=True), until=lambda: fb.Done or fb.Error, timeout=5.0)
    assert not fb.Error
    assert_at(X, 50.0)
    assert (fb.Position, fb.Velocity) == (50.0, 200.0)


def test_rule4_first_call_uses_the_initial_value(machine, X):
    fb = mcl.MC_MoveAbsolute()
    fb(Axis=X, Execute=True, Position=50.0)  # Velocity never given: initial value 0.0
    assert fb.Error and fb.ErrorID == mcl.ErrorID.EParam
    rel = mcl.MC_MoveRelative()
    rel(Axis=X, Execute=True, Velocity=100.0)  # Distance never given: initial value 0.0
    tick(machine, 5)
    rel(Execute=True)
    assert rel.Done and not rel.Error
    assert_at(X, 0.0)


# ---------------- rule 5: the falling edge neither stops the command nor hides its result
def test_rule5_falling_edge_does_not_stop_or_change_the_running_command(machine, X):
    fb = mcl.MC_MoveRelative()
    fb(Axis=X, Execute=True, Distance=80.0, Velocity=200.0)
    tick(machine)
    fb(Execute=False, Distance=5.0, Velocity=20.0)  # falling edge, other inputs: no effect
    assert fb.Busy
    machine.run(lambda: fb(Execute=False), until=lambda: fb.Done, timeout=5.0)
    assert_at(X, 80.0)


def test_rule5_done_pulses_one_cycle_after_early_falling_edge(machine, X):
    fb = mcl.MC_MoveRelative()
    fb(Axis=X, Execute=True, Distance=30.0, Velocity=200.0)
    tick(machine)
    done_scans = []
    for k in range(600):
        fb(Execute=False)
        exclusive(fb)
        if fb.Done:
            done_scans.append(k)
            assert_at(X, 30.0)
        tick(machine)
    assert len(done_scans) == 1, f"Done shown on scans {done_scans}"
    assert not fb.Busy


def test_rule5_done_held_while_execute_true_and_reset_by_falling_edge(machine, X):
    fb = mcl.MC_MoveRelative()
    machine.run(
        lambda: fb(Axis=X, Execute=True, Distance=30.0, Velocity=200.0),
        until=lambda: fb.Done,
        timeout=5.0,
    )
    for _ in range(20):
        fb(Execute=True)
        assert fb.Done
        tick(machine)
    fb(Execute=False)
    assert not fb.Done and not fb.Busy and not fb.Error


def test_rule5_error_held_while_execute_true_and_reset_by_falling_edge(machine, X):
    fb = mcl.MC_MoveAbsolute()
    for _ in range(10):
        fb(Axis=X, Execute=True, Position=10.0, Velocity=math.nan)
        assert fb.Error and fb.ErrorID == mcl.ErrorID.EParam
        tick(machine)
    fb(Execute=False)
    assert not fb.Error and fb.ErrorID == 0


def test_rule5_error_pulses_one_cycle_after_early_falling_edge(machine, X):
    machine.sims["X"].blocked_at = machine.sims["X"].x + 0.005  # an obstacle 5 mm ahead
    fb = mcl.MC_MoveRelative()
    fb(Axis=X, Execute=True, Distance=100.0, Velocity=200.0)
    tick(machine)
    error_scans = []
    for k in range(500):
        fb(Execute=False)
        exclusive(fb)
        if fb.Error:
            error_scans.append((k, fb.ErrorID))
        else:
            assert fb.ErrorID == 0
        tick(machine)
    assert X.state == mcl.AxisState.ErrorStop
    assert len(error_scans) == 1, f"Error shown on scans {error_scans}"
    assert error_scans[0][1] != 0
    assert not fb.Done


def test_rule5_aborted_pulses_one_cycle_after_early_falling_edge(machine, X):
    first, second = mcl.MC_MoveAbsolute(), mcl.MC_MoveAbsolute()
    first(Axis=X, Execute=True, Position=300.0, Velocity=200.0)
    tick(machine)
    first(Execute=False)
    tick(machine, 20)
    aborted_scans = []
    for k in range(300):
        first(Execute=False)
        second(Axis=X, Execute=k >= 10, Position=0.0, Velocity=200.0)
        exclusive(first)
        if first.CommandAborted:
            aborted_scans.append(k)
            assert first.Aborted
        assert not first.Done
        tick(machine)
    # shown once: in the scan of the abort or (called before the aborting block) the next one
    assert len(aborted_scans) == 1 and aborted_scans[0] in (10, 11), aborted_scans


def test_rule5_aborted_held_while_execute_true_and_reset_by_falling_edge(machine, X):
    first, second = mcl.MC_MoveAbsolute(), mcl.MC_MoveAbsolute()
    first(Axis=X, Execute=True, Position=300.0, Velocity=200.0)
    tick(machine, 20)
    second(Axis=X, Execute=True, Position=0.0, Velocity=200.0)
    for _ in range(20):
        first(Execute=True)
        assert first.CommandAborted and first.Aborted
        tick(machine)
    first(Execute=False)
    assert not first.CommandAborted and not first.Aborted and not first.Done


def test_rule5_invelocity_reset_by_falling_edge_motion_continues(machine, X):
    fb = in_velocity(machine, X, 100.0)
    fb(Execute=False)
    assert not fb.InVelocity
    tick(machine, 50)
    fb(Execute=False)
    assert not fb.InVelocity
    assert X.state == mcl.AxisState.ContinuousMotion
    assert pytest.approx(100.0, rel=0.05) == X.VEL


def test_rule5_invelocity_pulses_one_cycle_after_early_falling_edge(machine, X):
    """InVelocity is MoveVelocity's success output: reached after an early falling edge, it is
    still shown for exactly one cycle."""
    fb = mcl.MC_MoveVelocity()
    fb(Axis=X, Execute=True, Velocity=100.0)
    tick(machine)
    shown = []
    for k in range(300):
        fb(Execute=False)
        if fb.InVelocity:
            shown.append(k)
        tick(machine)
    assert pytest.approx(100.0, rel=0.05) == X.VEL  # the velocity was reached
    assert len(shown) == 1, f"InVelocity shown on scans {shown}"


# -------------------------- rule 6: Busy rises with the edge and falls with the final output
def test_rule6_busy_rises_with_edge_and_falls_when_done_rises(machine, X):
    fb = mcl.MC_MoveRelative()
    fb(Axis=X, Execute=False, Distance=40.0, Velocity=200.0)
    assert not fb.Busy
    trace = []
    for _ in range(600):
        fb(Execute=True)
        trace.append((fb.Busy, fb.Active, fb.Done))
        if fb.Done:
            break
        tick(machine)
    assert trace[0] == (True, True, False), "Busy/Active must rise in the scan of the edge"
    assert trace[-1] == (False, False, True), "Busy/Active must fall when Done rises"
    assert all(busy and active and not done for busy, active, done in trace[:-1])


def test_rule6_busy_falls_when_aborted_rises(machine, X):
    first, second = mcl.MC_MoveAbsolute(), mcl.MC_MoveAbsolute()
    first(Axis=X, Execute=True, Position=300.0, Velocity=200.0)
    tick(machine, 20)
    first(Execute=True)
    assert first.Busy and first.Active
    second(Axis=X, Execute=True, Position=0.0, Velocity=200.0)
    first(Execute=True)
    assert first.CommandAborted
    assert not first.Busy and not first.Active


def test_rule6_busy_falls_when_error_rises(machine, X):
    machine.sims["X"].blocked_at = machine.sims["X"].x + 0.005
    fb = mcl.MC_MoveRelative()
    busy_before_error = False
    for _ in range(500):
        fb(Axis=X, Execute=True, Distance=100.0, Velocity=200.0)
        if fb.Error:
            break
        busy_before_error = fb.Busy
        tick(machine)
    assert fb.Error and busy_before_error
    assert not fb.Busy and not fb.Active
    bad = mcl.MC_MoveRelative()
    bad(Axis=X, Execute=True, Distance=1.0, Velocity=0.0)  # a parameter error: never Busy
    assert bad.Error and not bad.Busy and not bad.Active


def test_rule6_active_equals_busy_for_non_buffered_commands(machine, X):
    move, vel, halt = mcl.MC_MoveRelative(), mcl.MC_MoveVelocity(), mcl.MC_Halt()
    for k in range(600):
        move(Axis=X, Execute=k < 200, Distance=40.0, Velocity=200.0)
        vel(Axis=X, Execute=250 <= k < 450, Velocity=150.0)
        halt(Axis=X, Execute=k >= 400)
        for fb in (move, vel, halt):
            assert fb.Active == fb.Busy
        tick(machine)
    assert halt.Done


def test_rule6_buffered_command_is_busy_but_not_active_while_waiting(machine, X):
    a, b = mcl.MC_MoveRelative(), mcl.MC_MoveRelative()
    trace = []
    for k in range(800):
        a(Axis=X, Execute=True, Distance=40.0, Velocity=200.0)
        if k >= 5:
            b(
                Axis=X,
                Execute=True,
                Distance=20.0,
                Velocity=200.0,
                BufferMode=mcl.MC_BufferMode.Buffered,
            )
        assert a.Active == a.Busy
        trace.append((a.Active, b.Busy, b.Active))
        if b.Done:
            break
        tick(machine)
    assert b.Done
    waiting = [t for t in trace[5:] if t[0]]
    assert waiting, "a was active while b waited"
    assert all(b_busy and not b_active for _, b_busy, b_active in waiting)
    assert any(b_active and not a_active for a_active, _, b_active in trace)
    assert_at(X, 60.0)


# ----------------------------------------- rule 7: a new edge on a busy instance restarts it
def test_rule7_new_edge_on_busy_instance_restarts_without_done_or_aborted(machine, X):
    fb = mcl.MC_MoveAbsolute()
    fb(Axis=X, Execute=True, Position=300.0, Velocity=200.0)
    tick(machine, 60)
    fb(Execute=False)
    tick(machine)
    fb(Execute=True, Position=100.0)
    assert fb.Busy and fb.Active and not fb.CommandAborted
    for _ in range(1500):
        tick(machine)
        fb(Execute=True)
        assert not fb.CommandAborted, "the restarted command reported Aborted"
        if fb.Done:
            break
    assert fb.Done
    assert_at(X, 100.0)


def test_rule7_restart_before_previous_target_never_reports_previous_done(machine, X):
    """The first command would end within the restart's scans: its Done must not show."""
    fb = mcl.MC_MoveRelative()
    fb(Axis=X, Execute=True, Distance=10.0, Velocity=200.0)
    tick(machine, 30)
    fb(Execute=False)
    tick(machine)
    fb(Execute=True, Distance=100.0)  # from about 7 mm: target about 107 mm
    start = X.POS
    first_done_pos = None
    for _ in range(1500):
        tick(machine)
        fb(Execute=True)
        assert not fb.CommandAborted
        if fb.Done:
            first_done_pos = X.POS
            break
    assert first_done_pos == pytest.approx(start + 100.0, abs=0.1)


def test_rule7_restart_of_waiting_buffered_instance_withdraws_previous(machine, X):
    a, b = mcl.MC_MoveAbsolute(), mcl.MC_MoveRelative()
    buffered = mcl.MC_BufferMode.Buffered
    a(Axis=X, Execute=True, Position=100.0, Velocity=200.0)
    b(Axis=X, Execute=True, Distance=50.0, Velocity=200.0, BufferMode=buffered)
    tick(machine)
    b(Execute=False)
    tick(machine)
    b(Execute=True, Distance=10.0)
    assert b.Busy and not b.Active
    for _ in range(2000):
        tick(machine)
        a(Execute=True)
        b(Execute=True)
        assert not b.CommandAborted
        if b.Done:
            break
    assert a.Done and b.Done
    tick(machine, 100)
    assert_at(X, 110.0)


# --------------------------- rule 8: an interrupted block reports CommandAborted, never Done
def test_rule8_interrupted_fb_reports_aborted_and_never_done(machine, X):
    first, second = mcl.MC_MoveAbsolute(), mcl.MC_MoveAbsolute()
    aborted_seen = False
    for k in range(1500):
        first(Axis=X, Execute=True, Position=300.0, Velocity=200.0)
        second(Axis=X, Execute=k >= 100, Position=-20.0, Velocity=200.0)
        assert not first.Done, "an aborted move reported Done"
        if k > 100:  # first is called before second: it sees the abort one scan later
            assert first.CommandAborted and first.Aborted
            aborted_seen = True
        if second.Done:
            break
        tick(machine)
    assert aborted_seen and second.Done
    tick(machine, 50)
    first(Execute=True)
    assert not first.Done and first.CommandAborted


def test_rule8_aborted_velocity_fb_resets_invelocity(machine, X):
    vel, move = in_velocity(machine, X, 100.0), mcl.MC_MoveAbsolute()
    move(Axis=X, Execute=True, Position=0.0, Velocity=100.0)
    vel(Execute=True)
    assert vel.CommandAborted and not vel.InVelocity and not vel.Done
    machine.run(scan_of(vel, move), until=lambda: move.Done, timeout=5.0)
    assert vel.CommandAborted and not vel.InVelocity and not vel.Done


def scan_of(*blocks: Any) -> Callable[[], None]:
    """A program calling each block with Execute=TRUE and the inputs it already has."""

    def program() -> None:
        for fb in blocks:
            fb(Execute=True)

    return program


def test_rule8_stop_aborts_the_running_move(machine, X):
    move, stop = mcl.MC_MoveAbsolute(), mcl.MC_Stop()
    move(Axis=X, Execute=True, Position=300.0, Velocity=200.0)
    tick(machine, 50)
    stop(Axis=X, Execute=True)
    machine.run(scan_of(move, stop), until=lambda: stop.Done, timeout=2.0)
    assert move.CommandAborted and not move.Done
    assert X.POS < 300.0 - 1.0


def test_rule8_aborting_command_aborts_the_buffered_queue_too(machine, X):
    a, b, c = mcl.MC_MoveAbsolute(), mcl.MC_MoveRelative(), mcl.MC_MoveAbsolute()
    a(Axis=X, Execute=True, Position=200.0, Velocity=200.0)
    b(Axis=X, Execute=True, Distance=50.0, Velocity=200.0, BufferMode=mcl.MC_BufferMode.Buffered)
    tick(machine, 30)
    c(Axis=X, Execute=True, Position=-10.0, Velocity=200.0)
    a(Execute=True)
    b(Execute=True)
    assert a.CommandAborted and b.CommandAborted
    machine.run(scan_of(a, b, c), until=lambda: c.Done, timeout=5.0)
    assert not a.Done and not b.Done and not b.Active
    tick(machine, 100)
    assert_at(X, -10.0)


# ------------------------------------------- rule 9: a parameter error leaves the axis alone
Trace = list[tuple[Any, ...]]

BAD_PARAMETERS: list[tuple[str, type[ExecuteFB], dict[str, Any], int]] = [
    ("velocity zero", mcl.MC_MoveAbsolute, {"Position": 50.0, "Velocity": 0.0}, 5),
    ("velocity negative", mcl.MC_MoveAbsolute, {"Position": 50.0, "Velocity": -100.0}, 5),
    ("velocity NaN", mcl.MC_MoveAbsolute, {"Position": 50.0, "Velocity": math.nan}, 5),
    ("velocity inf", mcl.MC_MoveAbsolute, {"Position": 50.0, "Velocity": math.inf}, 5),
    ("velocity < 1 % Vmax", mcl.MC_MoveAbsolute, {"Position": 50.0, "Velocity": 4.9}, 5),
    (
        "acceleration negative",
        mcl.MC_MoveAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "Acceleration": -1.0},
        5,
    ),
    (
        "deceleration NaN",
        mcl.MC_MoveAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "Deceleration": math.nan},
        5,
    ),
    (
        "acceleration too small",
        mcl.MC_MoveAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "Acceleration": 0.5},
        5,
    ),
    (
        "deceleration too small",
        mcl.MC_MoveAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "Deceleration": 0.5},
        5,
    ),
    (
        "jerk negative",
        mcl.MC_MoveAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "Jerk": -1.0},
        5,
    ),
    ("position NaN", mcl.MC_MoveAbsolute, {"Position": math.nan, "Velocity": 100.0}, 5),
    ("position inf", mcl.MC_MoveAbsolute, {"Position": math.inf, "Velocity": 100.0}, 5),
    (
        "buffer mode invalid",
        mcl.MC_MoveAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "BufferMode": 17},
        5,
    ),
    ("target beyond LimPos", mcl.MC_MoveAbsolute, {"Position": 450.0, "Velocity": 100.0}, 8),
    ("target beyond LimNeg", mcl.MC_MoveRelative, {"Distance": -1000.0, "Velocity": 100.0}, 8),
    ("distance NaN", mcl.MC_MoveRelative, {"Distance": math.nan, "Velocity": 100.0}, 5),
    (
        "buffered velocity zero",
        mcl.MC_MoveRelative,
        {"Distance": 10.0, "Velocity": 0.0, "BufferMode": 1},
        5,
    ),
    ("additive distance inf", mcl.MC_MoveAdditive, {"Distance": math.inf, "Velocity": 100.0}, 5),
    ("move velocity negative", mcl.MC_MoveVelocity, {"Velocity": -50.0}, 5),
    (
        "move velocity direction shortest",
        mcl.MC_MoveVelocity,
        {"Velocity": 50.0, "Direction": mcl.MC_Direction.MC_Shortest},
        5,
    ),
    (
        "block torque limit negative",
        mcl.GT_MoveAbsBlock,
        {"Position": 50.0, "Velocity": 100.0, "TorqueLimit": -1.0},
        5,
    ),
    (
        "continuous end velocity NaN",
        mcl.MC_MoveContinuousAbsolute,
        {"Position": 50.0, "Velocity": 100.0, "EndVelocity": math.nan},
        5,
    ),
    (
        "continuous target beyond LimNeg",
        mcl.MC_MoveContinuousRelative,
        {"Distance": -1000.0, "Velocity": 100.0, "EndVelocity": 10.0},
        8,
    ),
    (
        "position profile not increasing in time",
        mcl.MC_PositionProfile,
        {"TimePosition": mcl.MC_TP_REF([(0.1, 5.0), (0.0, 6.0)])},
        5,
    ),
    (
        "position profile beyond LimPos",
        mcl.MC_PositionProfile,
        {"TimePosition": mcl.MC_TP_REF([(3.0, 600.0)])},
        8,
    ),
    (
        "velocity profile empty",
        mcl.MC_VelocityProfile,
        {"TimeVelocity": mcl.MC_TV_REF([])},
        5,
    ),
    (
        "acceleration profile not finite",
        mcl.MC_AccelerationProfile,
        {"TimeAcceleration": mcl.MC_TA_REF([(0.1, math.inf)])},
        5,
    ),
    ("halt deceleration negative", mcl.MC_Halt, {"Deceleration": -1.0}, 5),
    ("stop deceleration NaN", mcl.MC_Stop, {"Deceleration": math.nan}, 5),
    ("stop jerk negative", mcl.MC_Stop, {"Jerk": -5.0}, 5),
    ("flying switch position NaN", mcl.MC_StepRefFlyingSwitch, {"SetPosition": math.nan}, 5),
    (
        "flying switch level mode",
        mcl.MC_StepRefFlyingSwitch,
        {"SwitchMode": mcl.MC_SwitchMode.MC_On},
        5,
    ),
    ("flying ref pulse time limit negative", mcl.MC_StepRefFlyingRefPulse, {"TimeLimit": -1.0}, 5),
    ("step absolute offset NaN", mcl.MC_StepAbsolute, {"Offset": math.nan}, 5),
    ("step absolute without absolute sensor", mcl.MC_StepAbsolute, {}, 21),
]


def _move_trace(intruder: tuple[type[ExecuteFB], dict[str, Any]] | None) -> tuple[Trace, Any]:
    """A MoveAbsolute 0 → 200 mm (SW limits −300..400); ``intruder`` is started at 0.12 s and
    kept TRUE. Returns the per-scan trace of the axis and the first move's outputs, and the
    intruding block."""
    machine, X = fresh_axis(LimPos=400.0, LimNeg=-300.0)
    move = mcl.MC_MoveAbsolute()
    other = intruder[0]() if intruder is not None else None
    trace: Trace = []
    for k in range(700):
        move(Axis=X, Execute=True, Position=200.0, Velocity=300.0)
        if other is not None and intruder is not None and k >= 60:
            other(Axis=X, Execute=True, **intruder[1])
        trace.append(
            (
                X.state,
                X.POS,
                X.VEL,
                X.OPT1n,
                X.OPT2n,
                X.AxErrorID,
                move.Busy,
                move.Active,
                move.Done,
                move.CommandAborted,
                true_position(X),
            )
        )
        tick(machine)
    return trace, other


@pytest.mark.parametrize(
    ("fb_type", "inputs", "error_id"),
    [pytest.param(t, i, e, id=name) for name, t, i, e in BAD_PARAMETERS],
)
def test_rule9_parameter_error_does_not_touch_the_running_move(fb_type, inputs, error_id):
    reference, _ = _move_trace(None)
    trace, other = _move_trace((fb_type, inputs))
    assert other.Error and other.ErrorID == error_id
    assert not other.Busy and not other.Active
    # the move ran exactly as without the faulty block: same state, position, velocity, model,
    # the carriage itself
    assert trace == reference
    assert trace[-1][0] == mcl.AxisState.StandStill
    assert trace[-1][1] == pytest.approx(200.0, abs=POS_TOL)
    assert trace[-1][8], "the running move reports Done"


def test_rule9_parameter_error_at_standstill_leaves_axis_standing(machine, X):
    before = X.POS
    bad = mcl.MC_MoveRelative()
    for _ in range(50):
        bad(Axis=X, Execute=True, Distance=100.0, Velocity=-5.0)
        assert bad.Error and bad.ErrorID == mcl.ErrorID.EParam
        assert X.state == mcl.AxisState.StandStill
        tick(machine)
    assert pytest.approx(before, abs=0.002) == X.POS
    assert abs(X.OPT2n) == 0.0


def test_rule9_parameter_error_leaves_the_buffered_queue_untouched(machine, X):
    a, b, bad = mcl.MC_MoveAbsolute(), mcl.MC_MoveRelative(), mcl.MC_MoveAbsolute()
    a(Axis=X, Execute=True, Position=100.0, Velocity=200.0)
    b(Axis=X, Execute=True, Distance=30.0, Velocity=200.0, BufferMode=mcl.MC_BufferMode.Buffered)
    tick(machine, 30)
    bad(Axis=X, Execute=True, Position=0.0, Velocity=math.inf)
    assert bad.Error and bad.ErrorID == mcl.ErrorID.EParam
    machine.run(scan_of(a, b, bad), until=lambda: b.Done, timeout=5.0)
    assert a.Done and not a.CommandAborted
    assert_at(X, 130.0)


def test_rule9_valid_velocity_above_vmax_is_clamped_not_refused():
    # Vmax a little below the drive's real speed at 10 V leaves the regulator some headroom
    machine, X = fresh_axis(Vmax=480.0)
    fb = mcl.MC_MoveAbsolute()
    peak = 0.0
    for _ in range(2000):
        fb(Axis=X, Execute=True, Position=600.0, Velocity=5000.0)
        assert not fb.Error
        peak = max(peak, abs(X.OPT2n))
        if fb.Done:
            break
        tick(machine)
    assert fb.Done
    assert peak == pytest.approx(480.0, rel=1e-6)
    assert_at(X, 600.0)


# ------------------------------------------------- rule 10: Enable blocks are level-sensitive
def test_rule10_read_actual_position_is_level_sensitive(machine, X):
    read = mcl.MC_ReadActualPosition()
    move = mcl.MC_MoveVelocity()
    move(Axis=X, Execute=True, Velocity=100.0)
    positions = []
    for k in range(150):
        read(Axis=X, Enable=k < 100)
        if k < 100:
            assert read.Valid and not read.Error
            assert read.Position == X.POS
            positions.append(read.Position)
        else:
            assert not read.Valid
        tick(machine)
    assert positions[-1] > positions[0] + 10.0, "Position refreshed while Enable stays TRUE"
    read(Enable=True)
    assert read.Valid and read.Position == X.POS


def test_rule10_read_status_follows_the_state_while_enabled(machine, X):
    status = mcl.MC_ReadStatus()
    move = mcl.MC_MoveRelative()

    def shown() -> set[str]:
        status(Axis=X, Enable=True)
        assert status.Valid and not status.Error
        return {s.name for s in mcl.AxisState if getattr(status, s.name)}

    assert shown() == {"StandStill"} and status.Ref
    move(Axis=X, Execute=True, Distance=20.0, Velocity=200.0)
    tick(machine)
    assert shown() == {"DiscreteMotion"}
    machine.run(scan_of(move), until=lambda: move.Done, timeout=2.0)
    assert shown() == {"StandStill"}
    status(Enable=False)
    assert not status.Valid
    assert not any(getattr(status, s.name) for s in mcl.AxisState)


def test_rule10_power_status_falls_on_error_and_comes_back():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    power = mcl.MC_Power()
    for _ in range(5):
        power(Axis=X, Enable=True)
        assert power.Error and power.ErrorID == mcl.ErrorID.Econst and not power.Status
        tick(machine)
    configure(X)  # the error goes away; Enable stays TRUE (level), no new edge
    power(Enable=True)
    tick(machine)
    power(Enable=True)
    assert power.Status and not power.Error and power.ErrorID == 0
    assert X.state == mcl.AxisState.StandStill


def test_rule10_power_valid_falls_on_parameter_error_and_comes_back(machine, X):
    power = mcl.MC_Power()
    power(Axis=X, Enable=True)
    assert power.Valid and not power.Error
    for _ in range(5):
        power(Enable=True, SpeedMode=7)
        assert power.Error and power.ErrorID == mcl.ErrorID.EParam
        assert not power.Valid, "Valid must fall while the block is in error"
        assert X.state == mcl.AxisState.StandStill  # a parameter error leaves the axis powered
        tick(machine)
    power(Enable=True, SpeedMode=0)
    assert power.Valid and not power.Error and power.ErrorID == 0


def test_rule10_power_status_falls_when_the_drive_enable_drops_and_returns_after_reset(machine, X):
    power = mcl.MC_Power()
    power(Axis=X, Enable=True)
    machine.sims["X"].blocked_at = machine.sims["X"].x + 0.005
    move, reset = mcl.MC_MoveRelative(), mcl.MC_Reset()
    move(Axis=X, Execute=True, Distance=50.0, Velocity=200.0)
    machine.run(
        lambda: power(Enable=True), until=lambda: X.state == mcl.AxisState.ErrorStop, timeout=2.0
    )
    power(Enable=True)
    assert power.Status, "the drive stays enabled for its quick stop (quick_stop_time)"
    machine.run(lambda: power(Enable=True), timeout=X.config.quick_stop_time + 0.004)
    assert not power.Status and not machine.sims["X"].enabled
    machine.sims["X"].blocked_at = math.inf
    reset(Axis=X, Execute=True)
    assert reset.Done
    for _ in range(3):
        power(Enable=True)  # the same level, no new edge
        tick(machine)
    power(Enable=True)
    assert power.Status and X.state == mcl.AxisState.StandStill


# ------------------------------------------------------------------------------ input checks
@pytest.mark.parametrize(
    ("fb_type", "inputs"),
    [
        (mcl.MC_MoveAbsolute, {"Execute": True, "Positon": 5.0}),
        (mcl.MC_MoveVelocity, {"Execute": True, "Velocty": 5.0}),
        (mcl.MC_Power, {"Enabel": True}),
        (mcl.MC_ReadStatus, {"Enable": True, "Valid": True}),
        (mcl.GT_Jog, {"Enable": True, "JogPlus": True}),
        (mcl.MC_Reset, {"execute": True}),
    ],
)
def test_unknown_input_raises_type_error_naming_the_valid_inputs(X, fb_type, inputs):
    fb = fb_type()
    with pytest.raises(TypeError) as info:
        fb(Axis=X, **inputs)
    message = str(info.value)
    wrong = next(iter(set(inputs) - set(input_names(fb_type))))
    assert wrong in message
    for valid in input_names(fb_type):
        assert valid in message, f"{valid!r} missing from {message!r}"
    assert "Axis" in message


NO_AXIS_CALLS: list[tuple[type[Any], dict[str, Any]]] = [
    (mcl.MC_MoveAbsolute, {"Execute": True, "Position": 5.0, "Velocity": 100.0}),
    (mcl.MC_MoveAbsolute, {"Execute": False}),
    (mcl.MC_MoveVelocity, {"Execute": True, "Velocity": 100.0}),
    (mcl.MC_Stop, {"Execute": False}),
    (mcl.MC_Reset, {"Execute": True}),
    (mcl.GT_SetConstant, {"Execute": False}),
    (mcl.MC_Power, {"Enable": True}),
    (mcl.MC_Power, {"Enable": False}),
    (mcl.MC_ReadStatus, {"Enable": True}),
    (mcl.MC_ReadActualPosition, {"Enable": False}),
    (mcl.GT_AxErrStringEN, {"Enable": False}),
    (mcl.GT_Jog, {"Enable": False}),
    (mcl.GT_EStop, {"Enable": False}),
    (mcl.MC_SetPosition, {"Execute": True, "Position": 5.0}),
    (mcl.MC_StepRefFlyingSwitch, {"Execute": True, "SetPosition": 5.0}),
    (mcl.MC_StepRefFlyingRefPulse, {"Execute": False}),
    (mcl.MC_StepAbsolute, {"Execute": True}),
    (mcl.MC_ReadParameter, {"Enable": True, "ParameterNumber": 1}),
    (mcl.MC_ReadBoolParameter, {"Enable": False}),
    (mcl.MC_WriteParameter, {"Execute": True, "ParameterNumber": 9, "Value": 100.0}),
    (mcl.MC_WriteBoolParameter, {"Execute": False}),
    (mcl.GT_SWLim, {"Execute": True, "LimPos": 10.0, "LimNeg": -10.0}),
]


@pytest.mark.parametrize(
    ("fb_type", "inputs"),
    [pytest.param(t, i, id=f"{t.__name__}-{i}") for t, i in NO_AXIS_CALLS],
)
def test_fb_called_without_ever_getting_axis_raises_type_error(fb_type, inputs):
    fb = fb_type()
    with pytest.raises(TypeError, match="Axis"):
        fb(**inputs)


def test_axis_of_wrong_type_raises_type_error():
    fb = mcl.MC_MoveAbsolute()
    with pytest.raises(TypeError, match="Axis"):
        fb(Axis="X", Execute=True, Position=1.0, Velocity=10.0)

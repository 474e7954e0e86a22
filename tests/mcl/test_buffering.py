"""BufferMode Aborting and Buffered (MotionControlLib Tab. 2.4): who waits for what, and where the
next motion starts."""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any

import pytest

import mcl
from mcl import MC_BufferMode
from tests.helpers import carriage_mm, carriage_mm_s

ACC = 2000.0
ONE_CYCLE = ACC * 0.001 * 1.01
"""The largest model velocity one servo cycle after (or before) a standstill [mm/s]."""


@dataclass
class Sample:
    t: float
    pos: float
    vel: float
    state: mcl.AxisState


@dataclass
class Scan:
    """Outputs of the FBs after one PLC scan, by name."""

    t: float
    out: dict[str, dict[str, Any]]

    def __getitem__(self, key: tuple[str, str]) -> Any:
        return self.out[key[0]][key[1]]


@dataclass
class Trace:
    samples: list[Sample] = field(default_factory=list)
    scans: list[Scan] = field(default_factory=list)

    def ever(self, fb: str, output: str) -> bool:
        return any(s[fb, output] for s in self.scans)

    def first(self, fb: str, output: str) -> float:
        return next(s.t for s in self.scans if s[fb, output])


OUTPUTS = ("Done", "Busy", "Active", "CommandAborted", "Error", "ErrorID", "InVelocity")


def record(machine: mcl.SimMachine, X: mcl.Axis) -> Trace:
    trace = Trace()
    machine.runtime.observers.append(
        lambda t: trace.samples.append(Sample(t, X.sp_pos, X.sp_vel, X.state))
    )
    return trace


def log(machine: mcl.SimMachine, trace: Trace, fbs: dict[str, Any]) -> None:
    trace.scans.append(
        Scan(
            machine.time,
            {name: {o: getattr(fb, o, False) for o in OUTPUTS} for name, fb in fbs.items()},
        )
    )


def common(**more: Any) -> dict[str, Any]:
    return dict(Acceleration=ACC, Deceleration=ACC, **more)


def assert_stands_at(machine: mcl.SimMachine, X: mcl.Axis, target: float) -> None:
    """The axis reads ``target`` [mm] within 5 µm, and the simulated carriage (the physics)
    really stands there, within that and the count it is read with."""
    assert abs(X.actual - target) <= 0.005, f"actual {X.actual} mm, target {target} mm"
    real = carriage_mm(machine)
    assert abs(real - target) <= 0.006, f"the carriage at {real} mm, target {target} mm"
    assert abs(carriage_mm_s(machine)) < 1.0, "the carriage still moves"


# ---------------------------------------------------------------------------------- Aborting
@pytest.mark.parametrize("mode", [MC_BufferMode.Aborting, None], ids=["Aborting", "default"])
def test_aborting_starts_at_once_and_the_active_command_is_aborted(machine, X, mode):
    trace = record(machine, X)
    first, second = mcl.MC_MoveAbsolute(), mcl.MC_MoveAbsolute()
    buffer = {} if mode is None else {"BufferMode": mode}
    issued: list[float] = []

    def program() -> None:
        first(Axis=X, Execute=True, Position=200.0, Velocity=200.0, **common())
        if not issued and X.sp_pos >= 50.0:
            issued.append(machine.time)
        second(Axis=X, Execute=bool(issued), Position=20.0, Velocity=100.0, **common(**buffer))
        log(machine, trace, {"first": first, "second": second})

    machine.run(program, until=lambda: second.Done, timeout=5.0)
    machine.run(program, timeout=0.3)
    t_issue = issued[0]
    i = next(i for i, s in enumerate(trace.scans) if s.t == t_issue)
    assert trace.scans[i]["second", "Active"], "the aborting command did not take over at once"
    # the first FB is called before the second in the scan: it shows the abort one scan later
    after = trace.scans[i + 1]
    assert after["first", "CommandAborted"]
    assert not after["first", "Busy"] and not after["first", "Active"]
    assert not trace.ever("first", "Done")
    assert not trace.ever("second", "CommandAborted")
    # the model brakes at once: it never gets further than the braking distance
    p_issue = max(s.pos for s in trace.samples if s.t < t_issue)
    assert max(s.pos for s in trace.samples) <= p_issue + 200.0**2 / (2 * ACC) + 1.0
    braking = [s.vel for s in trace.samples if t_issue <= s.t < t_issue + 0.02]
    assert all(b < a for a, b in itertools.pairwise(braking))
    assert_stands_at(machine, X, 20.0)


def test_aborting_also_aborts_the_buffered_commands(machine, X):
    trace = record(machine, X)
    fbs = {name: mcl.MC_MoveAbsolute() for name in ("first", "queued", "abort")}
    issued: list[float] = []

    def program() -> None:
        fbs["first"](Axis=X, Execute=True, Position=200.0, Velocity=200.0, **common())
        fbs["queued"](
            Axis=X, Execute=True, Position=300.0, Velocity=200.0, BufferMode=MC_BufferMode.Buffered
        )
        if not issued and X.sp_pos >= 50.0:
            issued.append(machine.time)
        fbs["abort"](Axis=X, Execute=bool(issued), Position=20.0, Velocity=100.0, **common())
        log(machine, trace, fbs)

    machine.run(program, until=lambda: fbs["abort"].Done, timeout=5.0)
    machine.run(program, timeout=1.0)
    for name in ("first", "queued"):
        assert trace.ever(name, "CommandAborted"), name
        assert not trace.ever(name, "Done"), name
    assert not trace.ever("queued", "Active")
    assert max(s.pos for s in trace.samples) < 200.0
    assert_stands_at(machine, X, 20.0)


# ---------------------------------------------------------------------------------- Buffered
FIRST_MOVES = {
    "MoveAbsolute": (mcl.MC_MoveAbsolute, {"Position": 50.0}),
    "MoveRelative": (mcl.MC_MoveRelative, {"Distance": 50.0}),
    "MoveAdditive": (mcl.MC_MoveAdditive, {"Distance": 50.0}),
}


@pytest.mark.parametrize("jerk", [0.0, 50000.0])
@pytest.mark.parametrize("kind", list(FIRST_MOVES))
def test_buffered_waits_for_done_then_starts_from_standstill(machine, X, kind, jerk):
    trace = record(machine, X)
    cls, inputs = FIRST_MOVES[kind]
    first, second = cls(), mcl.MC_MoveAbsolute()

    def program() -> None:
        first(Axis=X, Execute=True, Velocity=200.0, Jerk=jerk, **inputs, **common())
        second(
            Axis=X,
            Execute=True,
            Position=120.0,
            Velocity=100.0,
            Jerk=jerk,
            **common(BufferMode=MC_BufferMode.Buffered),
        )
        log(machine, trace, {"first": first, "second": second})

    machine.run(program, until=lambda: second.Done, timeout=5.0)
    machine.run(program, timeout=0.3)
    t_done = trace.first("first", "Done")
    waiting = [s for s in trace.scans if s.t < t_done]
    assert waiting and all(s["second", "Busy"] and not s["second", "Active"] for s in waiting)
    assert all(s["first", "Active"] for s in waiting)
    takeover = next(s for s in trace.scans if s.t == t_done)
    assert takeover["second", "Active"]
    assert not trace.ever("first", "CommandAborted")
    # standstill at the junction: the model velocity around 50 mm comes down to zero
    near = [abs(s.vel) for s in trace.samples if abs(s.pos - 50.0) < 0.01]
    assert near and min(near) <= ONE_CYCLE
    assert_stands_at(machine, X, 120.0)


def test_buffered_after_move_velocity_takes_over_at_in_velocity(machine, X):
    """MoveVelocity's activating signal is InVelocity (it never ends by itself)."""
    trace = record(machine, X)
    velocity, move = mcl.MC_MoveVelocity(), mcl.MC_MoveAbsolute()

    def program() -> None:
        velocity(Axis=X, Execute=True, Velocity=100.0, Acceleration=500.0, Deceleration=ACC)
        move(
            Axis=X,
            Execute=True,
            Position=150.0,
            Velocity=150.0,
            **common(BufferMode=MC_BufferMode.Buffered),
        )
        log(machine, trace, {"velocity": velocity, "move": move})

    machine.run(program, until=lambda: move.Done, timeout=5.0)
    t_reached = next(s.t for s in trace.samples if abs(s.vel - 100.0) < 1e-6)
    t_active = trace.first("move", "Active")
    assert t_reached <= t_active <= t_reached + 0.004
    assert all(s["move", "Busy"] for s in trace.scans if s.t < t_active)
    assert all(s.state == mcl.AxisState.ContinuousMotion for s in trace.samples if s.t < t_reached)
    assert trace.ever("velocity", "CommandAborted")
    assert not trace.ever("velocity", "Error")
    # the axis went on from 100 mm/s, not from standstill
    assert min(s.vel for s in trace.samples if t_reached <= s.t <= t_active + 0.01) > 90.0
    assert_stands_at(machine, X, 150.0)


def _start_stop(machine: mcl.SimMachine, X: mcl.Axis) -> tuple[mcl.MC_MoveVelocity, mcl.MC_Stop]:
    velocity, stop = mcl.MC_MoveVelocity(), mcl.MC_Stop()
    machine.run(lambda: velocity(Axis=X, Execute=True, Velocity=100.0, **common()), timeout=0.2)
    assert velocity.InVelocity
    return velocity, stop


def test_stop_refuses_buffered_commands_while_execute_is_true(machine, X):
    _, stop = _start_stop(machine, X)
    move = mcl.MC_MoveRelative()
    machine.run(lambda: stop(Axis=X, Execute=True, Deceleration=ACC), until=lambda: stop.Done)
    machine.run(lambda: stop(Axis=X, Execute=True), timeout=0.1)
    assert X.state == mcl.AxisState.Stopping
    p = X.sp_pos

    def program() -> None:
        stop(Axis=X, Execute=True)
        move(Axis=X, Execute=True, Distance=30.0, Velocity=100.0, BufferMode=MC_BufferMode.Buffered)

    machine.run(program, timeout=0.1)
    assert move.Error and move.ErrorID == mcl.ErrorID.EAxStop
    assert not move.Busy
    assert X.state == mcl.AxisState.Stopping
    assert X.sp_pos == p and X.sp_vel == 0.0


def test_stop_done_and_not_execute_lets_a_buffered_command_start_from_standstill(machine, X):
    _, stop = _start_stop(machine, X)
    trace = record(machine, X)
    machine.run(lambda: stop(Axis=X, Execute=True, Deceleration=ACC), until=lambda: stop.Done)
    machine.run(lambda: stop(Axis=X, Execute=False), timeout=0.004)
    assert X.state == mcl.AxisState.StandStill
    start = X.actual  # MoveRelative counts from the actual position
    move = mcl.MC_MoveRelative()
    t0 = machine.time

    def program() -> None:
        stop(Axis=X, Execute=False)
        move(
            Axis=X,
            Execute=True,
            Distance=30.0,
            Velocity=100.0,
            **common(BufferMode=MC_BufferMode.Buffered),
        )

    machine.run(program, until=lambda: move.Done, timeout=2.0)
    assert not move.Error
    assert abs(X.sp_pos - (start + 30.0)) < 0.002
    first = next(s for s in trace.samples if s.t >= t0)
    assert abs(first.vel) <= ONE_CYCLE


def test_stop_execute_falling_during_the_ramp_keeps_stopping_until_done(machine, X):
    _, stop = _start_stop(machine, X)
    move = mcl.MC_MoveRelative()
    machine.run(lambda: stop(Axis=X, Execute=True, Deceleration=500.0), timeout=0.02)
    machine.run(lambda: stop(Axis=X, Execute=False), timeout=0.02)
    assert X.state == mcl.AxisState.Stopping and X.sp_vel > 0.0

    def program() -> None:
        stop(Axis=X, Execute=False)
        move(Axis=X, Execute=True, Distance=30.0, Velocity=100.0, BufferMode=MC_BufferMode.Buffered)

    machine.run(program, timeout=0.01)
    assert move.Error and move.ErrorID == mcl.ErrorID.EAxStop
    machine.run(lambda: stop(Axis=X, Execute=False), until=lambda: X.sp_vel == 0.0, timeout=1.0)
    machine.run(lambda: stop(Axis=X, Execute=False), timeout=0.01)
    assert X.state == mcl.AxisState.StandStill


# ---------------------------------------------------------------------------------- the queue
@pytest.mark.parametrize("queued", [1, 2, 3])
def test_queued_commands_run_in_order(machine, X, queued):
    targets = [30.0, 60.0, 10.0, 80.0][: queued + 1]
    names = [f"m{i}" for i in range(len(targets))]
    fbs = {name: mcl.MC_MoveAbsolute() for name in names}
    trace = record(machine, X)
    scans = [0]

    def program() -> None:
        for i, (name, target) in enumerate(zip(names, targets, strict=True)):
            # one new command per PLC scan: the queue fills while the first one runs
            mode = MC_BufferMode.Aborting if i == 0 else MC_BufferMode.Buffered
            fbs[name](
                Axis=X,
                Execute=scans[0] >= i,
                Position=target,
                Velocity=150.0,
                **common(BufferMode=mode),
            )
            assert not fbs[name].Error, (name, fbs[name].ErrorID)
        scans[0] += 1
        log(machine, trace, fbs)

    machine.run(program, until=lambda: fbs[names[-1]].Done, timeout=10.0)
    machine.run(program, timeout=0.3)
    done = [trace.first(name, "Done") for name in names]
    assert done == sorted(done) and len(set(done)) == len(done)
    for name, t, target in zip(names, done, targets, strict=True):
        assert not trace.ever(name, "CommandAborted"), name
        model = next(s for s in trace.samples if s.t >= t - 0.002)
        assert model.pos == pytest.approx(target, abs=0.01), name
    for s in trace.scans:
        assert sum(bool(s[name, "Active"]) for name in names) <= 1
    # every waiting command is Busy but not Active until its predecessor is done
    for prev, name in itertools.pairwise(names):
        t_prev = trace.first(prev, "Done")
        waiting = [s for s in trace.scans if s.t < t_prev and s[name, "Busy"]]
        assert waiting and not any(s[name, "Active"] for s in waiting)
    assert_stands_at(machine, X, targets[-1])
    assert X.state == mcl.AxisState.StandStill

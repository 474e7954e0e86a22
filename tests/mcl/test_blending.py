"""BufferMode blending (docs/reference.md, BufferMode): the axis runs through the first target
without stopping, at the velocity the mode selects; reversals switch at zero velocity; late blends
never overshoot."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import pytest

import mcl
from mcl import MC_BufferMode
from mcl.trajectory import Limits
from tests.helpers import carriage_mm, carriage_mm_s
from tests.mcl.test_trajectory import BACKTRACK, backtrack, reachable_end_velocity

ACC = 2000.0
JERKS = [0.0, 50000.0]
"""Not jerk-limited (the default axis has no default jerk) and jerk-limited."""
P1, P2 = 100.0, 250.0
WINDOW = (30.0, 220.0)
"""Positions between the first move's start ramp and the second's final brake ramp."""
SETTLE = 0.5
"""Seconds after the last Done for the actual position to settle [s]."""

EXPECTED: dict[MC_BufferMode, Callable[[float, float], float]] = {
    MC_BufferMode.BlendingLow: min,
    MC_BufferMode.BlendingPrevious: lambda v1, v2: v1,
    MC_BufferMode.BlendingNext: lambda v1, v2: v2,
    MC_BufferMode.BlendingHigh: max,
}
MODES = list(EXPECTED)
SPEEDS = [(200.0, 100.0), (100.0, 200.0)]


@dataclass
class Sample:
    """One servo cycle: model position/velocity/acceleration, actual position and velocity,
    and the simulated carriage's real velocity ``truth`` [mm/s]."""

    t: float
    pos: float
    vel: float
    acc: float
    actual: float
    VEL: float
    truth: float


@dataclass
class Scan:
    """FB outputs after one PLC scan."""

    t: float
    done: tuple[bool, ...]
    aborted: tuple[bool, ...]
    active: tuple[bool, ...]
    busy: tuple[bool, ...]


@dataclass
class Trace:
    samples: list[Sample] = field(default_factory=list)
    scans: list[Scan] = field(default_factory=list)
    issued: float = 0.0
    """Time of the scan that issued the second move [s]."""

    def first_done(self, i: int) -> float:
        """Time of the first scan in which FB ``i`` showed Done."""
        return next(s.t for s in self.scans if s.done[i])

    def ever(self, what: str, i: int) -> bool:
        return any(getattr(s, what)[i] for s in self.scans)

    def between(self, lo: float, hi: float, actual: bool = False) -> list[Sample]:
        return [s for s in self.samples if lo < (s.actual if actual else s.pos) < hi]


def record(machine: mcl.SimMachine, X: mcl.Axis, trace: Trace) -> None:
    def observe(t: float) -> None:
        trace.samples.append(
            Sample(t, X.sp_pos, X.sp_vel, X.sp_acc, X.actual, X.VEL, carriage_mm_s(machine))
        )

    machine.runtime.observers.append(observe)


def log_scan(machine: mcl.SimMachine, trace: Trace, fbs: list) -> None:
    trace.scans.append(
        Scan(
            machine.time,
            tuple(bool(getattr(fb, "Done", False)) for fb in fbs),
            tuple(bool(fb.CommandAborted) for fb in fbs),
            tuple(bool(fb.Active) for fb in fbs),
            tuple(bool(fb.Busy) for fb in fbs),
        )
    )


def run_moves(
    machine: mcl.SimMachine,
    X: mcl.Axis,
    moves: list[dict],
    jerk: float,
    issue_second_at: float | None = None,
) -> Trace:
    """Chain MC_MoveAbsolute instances (inputs per move: Position, Velocity, BufferMode).

    The first move is issued in the first scan, the others in the same scan, or, with
    ``issue_second_at``, once the model position has passed that position. Runs until the last
    reports Done and then ``SETTLE`` seconds more.
    """
    trace = Trace()
    record(machine, X, trace)
    fbs = [mcl.MC_MoveAbsolute() for _ in moves]
    issued = [issue_second_at is None]

    def program() -> None:
        if not issued[0] and issue_second_at is not None and X.sp_pos >= issue_second_at:
            issued[0] = True
            trace.issued = machine.time
        for i, (fb, inputs) in enumerate(zip(fbs, moves, strict=True)):
            fb(
                Axis=X,
                Execute=i == 0 or issued[0],
                Acceleration=ACC,
                Deceleration=ACC,
                Jerk=jerk,
                **inputs,
            )
            assert not fb.Error, (i, fb.ErrorID)
        log_scan(machine, trace, fbs)

    machine.run(program, until=lambda: fbs[-1].Done, timeout=10.0)
    machine.run(program, timeout=SETTLE)
    return trace


def junction_velocity(samples: list[Sample], position: float) -> float:
    """Model velocity where the model passes ``position`` going forward, from the last sample
    before it (extrapolated with its acceleration over the remaining sub-cycle)."""
    i = next(i for i, s in enumerate(samples) if s.pos >= position - 1e-9)
    s = samples[i]
    if abs(s.pos - position) < 1e-9 or i == 0:
        return s.vel
    before = samples[i - 1]
    if before.vel <= 0.0:
        return 0.0
    dt = (position - before.pos) / before.vel
    return before.vel + before.acc * dt


def two_moves(
    machine: mcl.SimMachine,
    X: mcl.Axis,
    mode: MC_BufferMode,
    v1: float,
    v2: float,
    jerk: float,
    p2: float = P2,
    issue_second_at: float | None = None,
) -> Trace:
    moves = [
        dict(Position=P1, Velocity=v1, BufferMode=MC_BufferMode.Aborting),
        dict(Position=p2, Velocity=v2, BufferMode=mode),
    ]
    return run_moves(machine, X, moves, jerk, issue_second_at)


def check_both_done(trace: Trace, machine: mcl.SimMachine, p2: float = P2) -> None:
    """Both moves reported Done, the first never CommandAborted, and the carriage itself (the
    simulated physics) stands at the second target."""
    assert trace.ever("done", 0), "the first move never reported Done"
    assert not trace.ever("aborted", 0), "the first move reported CommandAborted"
    assert trace.ever("done", 1)
    real = carriage_mm(machine)
    assert abs(real - p2) <= 0.005 + 0.001, f"the carriage at {real} mm, target {p2} mm"


# ---------------------------------------------------------------------------------- the modes
@pytest.mark.parametrize("jerk", JERKS)
@pytest.mark.parametrize(("v1", "v2"), SPEEDS)
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.name)
def test_blending_junction_velocity(machine, X, mode, v1, v2, jerk):
    trace = two_moves(machine, X, mode, v1, v2, jerk)
    expected = EXPECTED[mode](v1, v2)
    v_junction = junction_velocity(trace.samples, P1)
    assert v_junction == pytest.approx(expected, rel=0.01), (
        f"{mode.name}: junction at {v_junction:.2f} mm/s, expected {expected:.0f} mm/s"
    )
    check_both_done(trace, machine)
    # the second waits (not Active) until the first is done, then takes over
    t_done = trace.first_done(0)
    assert not any(s.active[1] for s in trace.scans if s.t < t_done)
    assert all(s.busy[1] for s in trace.scans if s.t < t_done)
    assert next(s for s in trace.scans if s.t == t_done).active[1]


@pytest.mark.parametrize("jerk", JERKS)
@pytest.mark.parametrize(("v1", "v2"), SPEEDS)
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.name)
def test_blending_does_not_stop_between_the_moves(machine, X, mode, v1, v2, jerk):
    """Neither the model nor the carriage (its simulated physics) comes anywhere near standstill
    at the junction."""
    trace = two_moves(machine, X, mode, v1, v2, jerk)
    slow = min(v1, v2)
    model = min(s.vel for s in trace.between(*WINDOW))
    real = min(s.truth for s in trace.between(*WINDOW, actual=True))
    assert model > 0.5 * slow, f"model velocity drops to {model:.1f} mm/s"
    assert real > 0.5 * slow, f"the carriage slows down to {real:.1f} mm/s"


@pytest.mark.parametrize("jerk", JERKS)
@pytest.mark.parametrize(("v1", "v2"), SPEEDS)
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.name)
def test_blended_velocity_stays_within_the_commanded_velocities(machine, X, mode, v1, v2, jerk):
    """Between the ramps the model runs at v1, v2 or in between: a blend is no reason to
    undershoot both commanded velocities (the profiles are time-optimal within V/A/D/J)."""
    trace = two_moves(machine, X, mode, v1, v2, jerk)
    velocities = [s.vel for s in trace.between(*WINDOW)]
    assert min(velocities) >= 0.99 * min(v1, v2), f"dips to {min(velocities):.1f} mm/s"
    assert max(velocities) <= 1.01 * max(v1, v2)


# ---------------------------------------------------------------------------------- reversal
@pytest.mark.parametrize("jerk", JERKS)
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.name)
def test_blending_reversal_switches_at_zero_velocity(machine, X, mode, jerk):
    p2 = 20.0
    trace = two_moves(machine, X, mode, 200.0, 100.0, jerk, p2=p2)
    check_both_done(trace, machine, p2)
    positions = [s.pos for s in trace.samples]
    assert max(positions) == pytest.approx(P1, abs=1e-6)  # the first target exactly, no further
    # one sign change of the velocity, at the first target
    signs = [s.vel > 0.0 for s in trace.samples if abs(s.vel) > 1e-9]
    changes = sum(a != b for a, b in itertools.pairwise(signs))
    assert changes == 1
    near_top = [abs(s.vel) for s in trace.samples if s.pos > P1 - 0.001]
    assert max(near_top) <= ACC * 0.001 * 1.5  # at most one servo cycle of acceleration


# ---------------------------------------------------------------------------------- late
@pytest.mark.parametrize("late", [95.0, 99.0, 99.9])
@pytest.mark.parametrize("jerk", JERKS)
@pytest.mark.parametrize(
    ("mode", "v1", "v2"),
    [
        (MC_BufferMode.BlendingLow, 200.0, 100.0),
        (MC_BufferMode.BlendingHigh, 200.0, 100.0),
        (MC_BufferMode.BlendingHigh, 100.0, 200.0),
    ],
    ids=["Low-200-100", "High-200-100", "High-100-200"],
)
def test_late_blending_never_overshoots_the_first_target(machine, X, mode, v1, v2, jerk, late):
    """The blending command arrives while the first move is braking into its target: the first
    still ends exactly at its target (never beyond, never backing up), hands over at the highest
    velocity still reachable there (at most the blending velocity) and both complete."""
    trace = two_moves(machine, X, mode, v1, v2, jerk, issue_second_at=late)
    check_both_done(trace, machine)
    t_handover = trace.first_done(0) - 0.002  # the servo cycle of the hand-over is after this
    before = [s.pos for s in trace.samples if s.t < t_handover]
    assert max(before) <= P1 + 1e-6, f"overshoots the first target to {max(before):.4f}"
    back = backtrack([s.pos for s in trace.samples if s.pos < P2 - 1.0])
    assert back <= BACKTRACK, f"the model backs up by {back:.4f} mm"
    # when the first shows Done, the model has reached its target
    at_done = [s.pos for s in trace.samples if s.t < trace.first_done(0)]
    assert at_done[-1] >= P1 - 1e-6
    # the re-plan starts from the model state of the servo cycle before the issuing scan
    state = [s for s in trace.samples if s.t < trace.issued][-1]
    wanted = EXPECTED[mode](v1, v2)
    limits = Limits(v1, ACC, ACC, jerk or math.inf)
    reachable = reachable_end_velocity(state.pos, state.vel, state.acc, P1, limits, wanted)
    v_junction = junction_velocity(trace.samples, P1)
    assert v_junction <= wanted * 1.01
    assert v_junction >= 0.98 * reachable, (
        f"hands over at {v_junction:.2f} mm/s, {reachable:.1f} mm/s were reachable"
    )


# ---------------------------------------------------------------------------------- chains
@pytest.mark.parametrize("jerk", JERKS)
def test_three_chained_blended_moves(machine, X, jerk):
    moves = [
        dict(Position=50.0, Velocity=100.0, BufferMode=MC_BufferMode.Aborting),
        dict(Position=120.0, Velocity=200.0, BufferMode=MC_BufferMode.BlendingLow),
        dict(Position=200.0, Velocity=150.0, BufferMode=MC_BufferMode.BlendingLow),
    ]
    trace = run_moves(machine, X, moves, jerk)
    for i in range(3):
        assert trace.ever("done", i)
        assert not trace.ever("aborted", i)
    assert trace.first_done(0) < trace.first_done(1) < trace.first_done(2)
    assert junction_velocity(trace.samples, 50.0) == pytest.approx(100.0, rel=0.01)
    assert junction_velocity(trace.samples, 120.0) == pytest.approx(150.0, rel=0.01)
    assert min(s.vel for s in trace.between(20.0, 180.0)) > 50.0
    assert abs(X.actual - 200.0) <= 0.005
    assert carriage_mm(machine) == pytest.approx(200.0, abs=0.005 + 0.001)


@pytest.mark.parametrize("jerk", JERKS)
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.name)
def test_move_velocity_after_a_move_with_blending(machine, X, mode, jerk):
    trace = Trace()
    record(machine, X, trace)
    move, velocity = mcl.MC_MoveAbsolute(), mcl.MC_MoveVelocity()
    common = dict(Acceleration=ACC, Deceleration=ACC, Jerk=jerk)

    def program() -> None:
        move(Axis=X, Execute=True, Position=P1, Velocity=200.0, **common)
        velocity(Axis=X, Execute=True, Velocity=100.0, BufferMode=mode, **common)
        log_scan(machine, trace, [move, velocity])

    machine.run(program, until=lambda: velocity.InVelocity, timeout=5.0)
    machine.run(program, timeout=0.2)
    assert trace.ever("done", 0)
    assert not trace.ever("aborted", 0)
    assert velocity.InVelocity and velocity.Active
    assert X.state == mcl.AxisState.ContinuousMotion
    assert X.sp_vel == pytest.approx(100.0)
    expected = EXPECTED[mode](200.0, 100.0)
    assert junction_velocity(trace.samples, P1) == pytest.approx(expected, rel=0.01)
    assert min(s.vel for s in trace.samples if s.pos > 30.0) > 50.0


# ---------------------------------------------------------------------------------- additive
@pytest.mark.parametrize("mode", MODES, ids=lambda m: m.name)
def test_additive_blended_behind_a_queued_move_adds_to_its_target(machine, X, mode):
    """In ContinuousMotion (MC_MoveVelocity ramping up) with a buffered MC_MoveAbsolute to
    200 mm queued, a blending MC_MoveAdditive of 50 mm adds to that last target: the carriage
    ends at 250 mm, not 50 mm beyond where it was when the additive was issued."""
    velocity, absolute = mcl.MC_MoveVelocity(), mcl.MC_MoveAbsolute()
    additive = mcl.MC_MoveAdditive()
    common = dict(Acceleration=ACC, Deceleration=ACC)
    move = dict(Velocity=100.0, **common)
    issued_at: list[float] = []

    def program() -> None:
        velocity(Axis=X, Execute=True, Velocity=100.0, **common)
        absolute(
            Axis=X,
            Execute=True,
            Position=200.0,
            Velocity=100.0,
            BufferMode=MC_BufferMode.Buffered,
            **common,
        )
        if not issued_at and X.state == mcl.AxisState.ContinuousMotion and X.actual > 0.1:
            issued_at.append(X.actual)
        additive(Axis=X, Execute=bool(issued_at), Distance=50.0, BufferMode=mode, **move)
        assert not (velocity.Error or absolute.Error or additive.Error)

    machine.run(program, until=lambda: additive.Done, timeout=10.0)
    machine.run(program, timeout=SETTLE)
    assert issued_at[0] < 5.0, "issued early in the velocity ramp, far from both targets"
    assert absolute.Done and not absolute.CommandAborted
    assert carriage_mm(machine) == pytest.approx(250.0, abs=0.005 + 0.001)
    assert X.actual == pytest.approx(250.0, abs=0.005)

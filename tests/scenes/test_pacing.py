"""The wall-clock pacing loop on a clock the test moves by hand: the PLC cycles due at a speed,
never ahead of the wall clock, in runs of whole chunks of at most a batch of wall time; a backlog
beyond the lag is dropped; as fast as possible it lets the other threads in after each batch;
the loop runs what is due, tells its owner, waits and stops when asked."""

from __future__ import annotations

import math
import threading

import pytest

from scenes.pacing import FAST_CYCLES, MAX_WAIT, MIN_WAIT, Pacing, check_speed

PLC = 0.002


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_the_cycles_due_follow_speed_times_wall_time() -> None:
    clock = Clock()
    pacing = Pacing(2.0, clock)
    assert pacing.due(0.0, PLC) == 0  # the first look anchors
    assert pacing.wait_time(PLC) == pytest.approx(PLC / 2.0)
    clock.now += 0.0041  # 8.2 ms of simulated time due: 4 whole cycles
    assert pacing.due(0.0, PLC) == 4
    assert pacing.due(4 * PLC, PLC) == 0  # never ahead
    assert pacing.wait_time(PLC) == pytest.approx((PLC - 0.0002) / 2.0)
    clock.now += 0.2  # far behind, but within the lag: at most a batch of wall time
    assert pacing.due(4 * PLC, PLC) == int(2.0 * 0.01 / PLC) + 1


def test_a_backlog_beyond_the_lag_is_dropped_and_a_restart_counts_from_now() -> None:
    clock = Clock()
    pacing = Pacing(1.0, clock, max_lag=0.1)
    pacing.due(0.0, PLC)
    clock.now += 0.1 + 0.001
    assert pacing.due(0.0, PLC) == 0  # goes on from now
    clock.now += 0.004
    assert pacing.due(0.0, PLC) == 2
    pacing.restart(0.5)
    assert pacing.speed == 0.5 and pacing.due(0.0, PLC) == 0
    clock.now += 0.008
    assert pacing.due(0.0, PLC) == 2
    with pytest.raises(ValueError, match="speed must be > 0"):
        pacing.restart(0.0)
    with pytest.raises(ValueError, match="speed must be > 0"):
        Pacing(-1.0, clock)
    assert check_speed(math.inf) == math.inf


def test_runs_are_whole_chunks() -> None:
    clock = Clock()
    pacing = Pacing(1.0, clock, chunk=0.01, batch_wall=0.0)
    pacing.due(0.0, PLC)
    clock.now += 0.008
    assert pacing.due(0.0, PLC) == 0
    assert pacing.wait_time(PLC) == pytest.approx(0.002)  # until the chunk is due
    clock.now += 0.004
    assert pacing.due(0.0, PLC) == 5
    clock.now += 0.05  # five chunks due: one run is one chunk
    assert pacing.due(5 * PLC, PLC) == 5
    wide = Pacing(1.0, clock, chunk=0.01, batch_wall=0.025)
    wide.due(0.0, PLC)
    clock.now += 0.05
    assert wide.due(0.0, PLC) == 10  # 13 cycles a batch, in whole chunks


def test_waits_are_bounded() -> None:
    clock = Clock()
    slow = Pacing(0.001, clock)
    slow.due(0.0, PLC)
    assert slow.wait_time(PLC) == MAX_WAIT
    fast = Pacing(1000.0, clock)
    fast.due(0.0, PLC)
    assert fast.wait_time(PLC) == MIN_WAIT


def test_as_fast_as_possible_runs_batches_and_lets_others_in() -> None:
    clock = Clock()
    pacing = Pacing(math.inf, clock, batch_wall=0.01)
    assert pacing.due(0.0, PLC) == FAST_CYCLES
    assert pacing.due(1.0, PLC) == FAST_CYCLES  # the wall clock stands: runs on
    clock.now += 0.01
    assert pacing.due(1.0, PLC) == 0 and pacing.wait_time(PLC) == 0.0
    assert pacing.due(1.0, PLC) == FAST_CYCLES


class Owner:
    """A simulation owner for the loop: it records what the loop did and stops it after
    ``rounds`` waits (the clock moves on by 5 ms at each)."""

    def __init__(self, clock: Clock, stop: threading.Event, rounds: int) -> None:
        self.clock, self.stop, self.rounds = clock, stop, rounds
        self.time = 0.0
        self.log: list[str] = []
        self.holds = 1

    def simulated(self) -> tuple[float, float]:
        return self.time, PLC

    def held(self) -> bool:
        if self.holds:
            self.holds -= 1
            self.log.append("held")
            return True
        return False

    def run_cycles(self, cycles: int) -> None:
        self.time += cycles * PLC
        self.log.append(f"run {cycles}")

    def ran(self) -> None:
        self.log.append("ran")

    def idle(self, seconds: float) -> None:
        self.log.append("idle")
        self.clock.now += 0.005
        self.rounds -= 1
        if self.rounds == 0:
            self.stop.set()


def test_the_loop_runs_what_is_due_tells_its_owner_and_stops() -> None:
    clock, stop = Clock(), threading.Event()
    owner = Owner(clock, stop, rounds=2)
    Pacing(1.0, clock).run(owner, stop)
    assert owner.log == ["held", "ran", "idle", "run 2", "ran", "ran", "idle"]
    assert owner.time == pytest.approx(2 * PLC)

"""A scene run at a speed in real time: the testbench's one wall-clock pacing loop.

A scene runs on simulated time alone (``Scene.run``: no wall clock inside, so a run is
deterministic and as fast as the CPU allows). A thread that shows a scene live (the viewer's
session) or serves it to a PLC (the bridge's free run) keeps simulated time at ``speed`` ×
elapsed wall time with :meth:`Pacing.run`: it runs the PLC cycles that are due, in runs of whole
chunks (the bridge publishes its status after each 10 ms of simulated time, the viewer runs each
cycle as soon as it is due) of at most a batch of wall time, tells its owner after each run, and
waits until the next chunk is due. It never runs ahead of the wall clock; when it falls more
than ``max_lag`` of wall time behind, it goes on from now instead of bursting to catch up (the
real-time factor then drops below the speed). At ``speed = math.inf`` it runs as fast as the
CPU allows and lets other threads in after each batch of wall time.

The pacing is the testbench's, not the PLC program's (``plc``): a PLC scan never looks at the
wall clock.
"""

from __future__ import annotations

__all__ = [
    "BATCH_WALL",
    "FAST_CYCLES",
    "MAX_LAG",
    "MAX_WAIT",
    "MIN_WAIT",
    "Paced",
    "Pacing",
    "check_speed",
]

import math
import threading
import time
from collections.abc import Callable
from typing import Protocol

MAX_LAG = 0.25
"""Wall time [s] a simulation may fall behind before pacing gives up catching up."""

BATCH_WALL = 0.01
"""Wall time [s] after which a run of PLC cycles is interrupted, so that the owner can apply
commands and publish."""

FAST_CYCLES = 8
"""PLC cycles of one run at ``speed = math.inf``."""

MIN_WAIT = 0.0005
MAX_WAIT = 0.05
"""Shortest and longest wait [s] between two looks at the clock."""


class Paced(Protocol):
    """The owner of a simulation thread, as the loop sees it."""

    def simulated(self) -> tuple[float, float]:
        """Simulated time and the PLC period [s] now (the scene may change between calls)."""
        ...

    def held(self) -> bool:
        """Called before each look at the clock (to apply commands, say); True: nothing is to
        run now (paused, or it waited or stepped itself), look again."""
        ...

    def run_cycles(self, cycles: int) -> None:
        """Run ``cycles`` PLC cycles."""
        ...

    def ran(self) -> None:
        """After each run of cycles and before each idle wait (to publish, say)."""
        ...

    def idle(self, seconds: float) -> None:
        """Wait up to ``seconds`` of wall time (0: just let the other threads run)."""
        ...


def check_speed(speed: float) -> float:
    """A speed factor > 0 (``math.inf``: as fast as possible).

    Raises:
        ValueError: another.
    """
    speed = float(speed)
    if not speed > 0.0:
        raise ValueError(f"speed must be > 0 (math.inf: as fast as possible), got {speed}")
    return speed


class Pacing:
    """Simulated time at ``speed`` × wall time: the PLC cycles due and the waits between them.

    Args:
        speed: Simulated seconds per wall second (``math.inf``: as fast as possible).
        clock: Monotonic wall clock [s].
        max_lag: Wall time [s] it may fall behind before it goes on from now.
        chunk: Simulated time [s] of the shortest run (whole PLC cycles, at least one).
        batch_wall: Wall time [s] of the longest run (0: a run is one chunk).

    Raises:
        ValueError: If ``speed`` is not > 0.
    """

    def __init__(
        self,
        speed: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
        *,
        max_lag: float = MAX_LAG,
        chunk: float = 0.0,
        batch_wall: float = BATCH_WALL,
    ) -> None:
        self.speed = check_speed(speed)
        """Simulated seconds per wall second."""
        self.max_lag, self.chunk, self.batch_wall = max_lag, chunk, batch_wall
        self._clock = clock
        self._anchor: tuple[float, float] | None = None
        """(wall, simulated) time the pacing counts from; None: from the next look."""
        self._behind = 0.0

    def restart(self, speed: float | None = None) -> None:
        """Count from the next look at the clock (after a pause, on another scene), at
        ``speed`` if one is given.

        Raises:
            ValueError: If ``speed`` is not > 0.
        """
        if speed is not None:
            self.speed = check_speed(speed)
        self._anchor = None

    def due(self, sim_time: float, plc: float) -> int:
        """The PLC cycles [of ``plc`` s] to run now at simulated time ``sim_time``: every whole
        chunk due, at most a batch; 0: none yet (:meth:`wait_time`)."""
        now = self._clock()
        anchor = self._anchor
        if anchor is None:
            anchor = self._anchor = (now, sim_time)
        if math.isinf(self.speed):
            if now - anchor[0] < self.batch_wall:
                return FAST_CYCLES
            self._anchor = None  # a batch of wall time spent: let the others in, then the next
            self._behind = 0.0
            return 0
        speed = self.speed
        behind = anchor[1] + speed * (now - anchor[0]) - sim_time
        if behind > speed * self.max_lag:  # cannot keep up: drop the backlog, do not burst
            self._anchor, behind = (now, sim_time), 0.0
        self._behind = behind
        due = int(behind / plc + 1e-9)
        chunk = max(1, round(self.chunk / plc))
        if due < chunk:
            return 0
        cycles = min(due, max(chunk, int(speed * self.batch_wall / plc) + 1))
        return cycles - cycles % chunk

    def wait_time(self, plc: float) -> float:
        """Wall time [s] to wait after :meth:`due` said 0: until the next chunk is due."""
        if math.isinf(self.speed):
            return 0.0
        chunk = max(1, round(self.chunk / plc))
        return min(max((chunk * plc - self._behind) / self.speed, MIN_WAIT), MAX_WAIT)

    def run(self, paced: Paced, stop: threading.Event) -> None:
        """The loop of ``paced``'s simulation thread, until ``stop`` is set."""
        self.restart()
        while not stop.is_set():
            if paced.held():
                continue
            sim_time, plc = paced.simulated()
            cycles = self.due(sim_time, plc)
            if cycles:
                paced.run_cycles(cycles)
                paced.ran()
                continue
            paced.ran()
            paced.idle(self.wait_time(plc))

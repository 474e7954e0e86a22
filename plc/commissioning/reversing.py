"""The reversing sequence of one axis as PLC code: ``MC_MoveAbsolute`` to A, dwell, to B,
dwell, … for a number of cycles (or until stopped).

A cycle is the way out to A and back to B. Each move ends in position: after the block's Done
the sequence waits until the actual position is within the axis' in-position window of the
target (at most :data:`SETTLE_TIMEOUT`), then dwells. The sequence ends after its cycles, on
:meth:`ReversingSequence.halt` (``MC_Halt``, the axis ramps to standstill), when another
command takes the axis over (the move reports CommandAborted, or :meth:`cancel`) and on a
fault (the move reports an Error, the axis is in ErrorStop).
"""

from __future__ import annotations

__all__ = [
    "MAX_CYCLES",
    "MAX_DWELL",
    "SETTLE_TIMEOUT",
    "Outcome",
    "Reversing",
    "ReversingProgress",
    "ReversingSequence",
]

import math
from collections.abc import Callable
from dataclasses import dataclass

import mcl

MAX_DWELL = 3600.0
"""Longest dwell [s] the operator may ask for."""

MAX_CYCLES = 1_000_000
"""Most cycles the operator may ask for (0: until stopped)."""

SETTLE_TIMEOUT = 2.0
"""Simulated time [s] a move may take after its Done to come into position before the dwell
starts anyway."""

Outcome = tuple[str, int]
"""How a sequence ended: (text, ErrorID; 0: no error)."""


@dataclass(frozen=True, slots=True)
class Reversing:
    """A reversing sequence the operator asked for.

    Attributes:
        a: First target A [u].
        b: Second target B [u].
        velocity: [u/s], > 0.
        acceleration: acceleration and deceleration [u/s²], > 0.
        dwell: wait at each target once in position [s], 0 … :data:`MAX_DWELL`.
        cycles: cycles A → B to run, 0: until stopped.
    """

    a: float
    b: float
    velocity: float
    acceleration: float
    dwell: float
    cycles: int

    def __post_init__(self) -> None:
        for name in ("a", "b"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"target {name.upper()} must be a finite number")
        for name in ("velocity", "acceleration"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a finite number > 0, got {value}")
        if not (math.isfinite(self.dwell) and 0.0 <= self.dwell <= MAX_DWELL):
            raise ValueError(f"dwell must be in [0, {MAX_DWELL:g}] s, got {self.dwell}")
        if isinstance(self.cycles, bool) or not (
            isinstance(self.cycles, int) and 0 <= self.cycles <= MAX_CYCLES
        ):
            raise ValueError(f"cycles must be an integer in [0, {MAX_CYCLES}], got {self.cycles}")


@dataclass(frozen=True, slots=True)
class ReversingProgress:
    """What the panel shows of the sequence.

    Attributes:
        running: The sequence runs.
        cycle: The cycle running or last run (1-based; 0: none yet).
        cycles: Cycles asked for (0: until stopped).
        phase: ``"to A"``, ``"dwell at B"``, ``"done"``, ``"stopped"``, … (empty: never ran).
    """

    running: bool = False
    cycle: int = 0
    cycles: int = 0
    phase: str = ""

    @property
    def text(self) -> str:
        """``"cycle 2 of 5: to B"`` (``of ∞`` when it runs until stopped)."""
        if not self.phase:
            return ""
        total = str(self.cycles) if self.cycles else "∞"
        return f"cycle {self.cycle} of {total}: {self.phase}"


class ReversingSequence:
    """The reversing sequence of one axis (one PLC scan per call).

    Args:
        axis: The axis.
        sim_time: Simulated time [s] (the dwell is measured on it).
    """

    def __init__(self, axis: mcl.Axis, sim_time: Callable[[], float]) -> None:
        self.axis = axis
        self._time = sim_time
        self.move = mcl.MC_MoveAbsolute(Axis=axis)
        self.halting = mcl.MC_Halt(Axis=axis)
        self._spec: Reversing | None = None
        self._to_b = False
        self._phase = "move"
        self._since = 0.0
        self.progress = ReversingProgress()
        """Progress, replaced (never changed) every scan it changes."""

    @property
    def running(self) -> bool:
        """The sequence runs."""
        return self._spec is not None

    def start(self, spec: Reversing) -> None:
        """Start ``spec`` afresh at its first move (to A)."""
        self._release_move()
        self._spec = spec
        self._to_b = False
        self._phase = "move"
        self.progress = ReversingProgress(True, 1, spec.cycles, "to A")

    def cancel(self, phase: str = "aborted") -> Outcome | None:
        """End the sequence without a motion command (another command takes the axis over);
        how it ended (None: it did not run)."""
        if self._spec is None:
            return None
        self._release_move()
        return self._end(phase)

    def halt(self) -> Outcome | None:
        """End the sequence: ``MC_Halt`` ramps the axis to standstill (over the next scans)."""
        outcome = self.cancel("stopped")
        if outcome is not None and self.axis.state != mcl.AxisState.Disabled:
            self.halting(Axis=self.axis, Execute=False)
            self.halting(Axis=self.axis, Execute=True)
        return outcome

    def __call__(self) -> Outcome | None:
        """One scan; how the sequence ended in this scan (None: it runs on or did not run)."""
        if self.halting.Execute:
            self.halting(Axis=self.axis, Execute=self.halting.Busy)
        spec = self._spec
        if spec is None:
            return None
        axis = self.axis
        if axis.state == mcl.AxisState.ErrorStop:
            self._release_move()
            return self._end("fault", axis.AxErrorID)
        target = spec.b if self._to_b else spec.a
        if self._phase == "move":
            return self._scan_move(spec, target)
        now = self._time()
        if self._phase == "settle":
            settled = abs(axis.POS - target) <= axis.config.in_position
            if settled or now - self._since >= SETTLE_TIMEOUT:
                self._phase, self._since = "dwell", now
                self._show(f"dwell at {self._name()}")
            return None
        if now - self._since < spec.dwell - 1e-9:
            return None
        cycle = self.progress.cycle
        if self._to_b:
            if spec.cycles and cycle >= spec.cycles:
                return self._end("done")
            cycle += 1
        self._to_b = not self._to_b
        self._phase = "move"
        self.progress = ReversingProgress(True, cycle, spec.cycles, f"to {self._name()}")
        return self._scan_move(spec, spec.b if self._to_b else spec.a)

    def _scan_move(self, spec: Reversing, target: float) -> Outcome | None:
        """Call the move to ``target``; on its Done the settling starts."""
        move = self.move
        move(
            Axis=self.axis,
            Execute=True,
            Position=target,
            Velocity=spec.velocity,
            Acceleration=spec.acceleration,
            Deceleration=spec.acceleration,
        )
        if move.Error:
            error = move.ErrorID
            self._release_move()
            return self._end("error", error)
        if move.CommandAborted:
            self._release_move()
            return self._end("aborted")
        if move.Done:
            self._release_move()
            self._phase, self._since = "settle", self._time()
            self._show(f"settle at {self._name()}")
        return None

    def _name(self) -> str:
        return "B" if self._to_b else "A"

    def _show(self, phase: str) -> None:
        p = self.progress
        self.progress = ReversingProgress(p.running, p.cycle, p.cycles, phase)

    def _release_move(self) -> None:
        """Drop the move's Execute (a fresh rising edge for the next move)."""
        if self.move.Execute:
            self.move(Axis=self.axis, Execute=False)

    def _end(self, phase: str, error_id: int = 0) -> Outcome:
        p = self.progress
        self._spec = None
        self.progress = ReversingProgress(False, p.cycle, p.cycles, phase)
        if phase == "done":
            return f"done ({p.cycle} cycles)", 0
        return phase, error_id

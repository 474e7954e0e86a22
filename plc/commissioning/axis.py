"""The commissioning functions of one axis as PLC code: the reversing sequence
(:mod:`plc.commissioning.reversing`), the step test (:mod:`plc.commissioning.step_test`) and the
velocity override
(``MC_SetOverride``), started and ended from the operator's requests, called once per PLC scan
by the axis' operator program.

The override is the library's: until the operator first sets it, ``MC_SetOverride`` is not
called (a demo program keeps its own); from then on it is called every scan with Enable, the
operator's VelFactor and AccFactor, JerkFactor as they follow from it (VelFactor², VelFactor³).

A jog, a move, a homing or Stop of the operator ends a running sequence or step test (the
operator takes the axis over); a step test starts only while no sequence runs, and a sequence
ends a running step test.
"""

from __future__ import annotations

__all__ = [
    "MAX_OVERRIDE",
    "NO_COMMISSIONING",
    "AxisCommissioning",
    "CommissioningRequests",
    "CommissioningView",
    "Note",
]

import logging
from collections.abc import Callable
from dataclasses import dataclass

import mcl
from plc.commissioning.reversing import Outcome, Reversing, ReversingProgress, ReversingSequence
from plc.commissioning.step_test import STEP_WINDOW, StepListener, StepResponse, StepTest

log = logging.getLogger(__name__)

MAX_OVERRIDE = 150.0
"""Largest velocity override the operator may set [%]."""

Note = Callable[[str, str, int], None]
"""Hears what became of a command: (command, text, ErrorID). ErrorID 0 with a text that starts
with ``"refused"``: the program refused it; 0 otherwise: it ended (or started) well."""


@dataclass(frozen=True, slots=True)
class CommissioningRequests:
    """What the operator wants from the commissioning functions of one axis in one scan.

    Attributes:
        reversing: a reversing sequence to start; None: none.
        end_reversing: a Stop sequence press (MC_Halt).
        step: a step test press: (amplitude [u], client id of the page); None: none.
        override: velocity override [%], 0 … :data:`MAX_OVERRIDE`; None: not set yet.
    """

    reversing: Reversing | None = None
    end_reversing: bool = False
    step: tuple[float, int] | None = None
    override: float | None = None


NO_COMMISSIONING = CommissioningRequests()
"""No press of the commissioning controls."""


@dataclass(frozen=True, slots=True)
class CommissioningView:
    """What the commissioning controls of an axis show.

    Attributes:
        reversing: Progress of the reversing sequence.
        step_running: A step test records.
        step: Figures of the last step test (None: none yet).
        jog_slow: The slow jog speed is chosen.
        override: The override the axis follows [%] (100 until the operator sets one).
    """

    reversing: ReversingProgress
    step_running: bool
    step: StepResponse | None
    jog_slow: bool
    override: float = 100.0


class AxisCommissioning:
    """Reversing sequence and step test of one axis (one PLC scan per call).

    Args:
        axis: The axis.
        sim_time: Simulated time [s].
        note: Hears what became of each command.
        on_step: Hears that a step test starts (called in the simulation thread).
    """

    def __init__(
        self,
        axis: mcl.Axis,
        sim_time: Callable[[], float],
        note: Note,
        on_step: StepListener | None = None,
    ) -> None:
        self.axis = axis
        self.reversing = ReversingSequence(axis, sim_time)
        self.step_test = StepTest(axis, sim_time)
        self.override = mcl.MC_SetOverride(Axis=axis)
        self.on_step = on_step
        self._note = note

    def view(self, jog_slow: bool) -> CommissioningView:
        """What the commissioning controls show now (``jog_slow``: the jog speed chosen)."""
        test = self.step_test
        return CommissioningView(
            self.reversing.progress,
            test.running,
            test.result,
            jog_slow,
            100.0 * self.axis.override_factor,
        )

    def __call__(self, r: CommissioningRequests, taken_over: bool) -> None:
        """One scan: start and end as requested (``taken_over``: the operator jogs, moves,
        homes or stops the axis in this scan), then run."""
        if taken_over:
            self._outcome("Reversing", self.reversing.cancel())
            self._outcome("Step test", self.step_test.cancel())
        if r.end_reversing:
            self._outcome("Reversing", self.reversing.halt())
        if r.reversing is not None:
            self._outcome("Step test", self.step_test.cancel())
            self.reversing.start(r.reversing)
            self._note("Reversing", "started", 0)
        if r.step is not None:
            self._start_step(*r.step)
        self._outcome("Reversing", self.reversing())
        self._outcome("Step test", self.step_test())
        if r.override is not None:
            self._scan_override(r.override / 100.0)

    def _scan_override(self, factor: float) -> None:
        """MC_SetOverride with ``factor`` (1.0 = 100 %); a refusal is reported once."""
        block = self.override
        refused = block.Error
        block(
            Axis=self.axis,
            Enable=True,
            VelFactor=factor,
            AccFactor=factor**2,
            JerkFactor=factor**3,
        )
        if block.Error and not refused:
            self._note("Override", "refused", block.ErrorID)

    def _start_step(self, amplitude: float, client_id: int) -> None:
        """Start a step test (refused unless the axis stands still in position)."""
        test = self.step_test
        why = "the reversing sequence runs" if self.reversing.running else test.refusal(amplitude)
        if why:
            self._note("Step test", f"refused: {why}", 0)
            return
        error = test.begin(amplitude)
        if error:
            self._note("Step test", "refused", error)
            return
        self._note("Step test", "recording", 0)
        if self.on_step is not None:
            try:
                self.on_step(client_id, self.axis.name, test.start_time, STEP_WINDOW)
            except Exception:  # a listener of the page must not stop the simulation
                log.exception("step test listener failed")

    def _outcome(self, command: str, outcome: Outcome | None) -> None:
        if outcome is not None:
            self._note(command, *outcome)

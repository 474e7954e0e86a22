"""Touch probe: the axis position recorded at a trigger edge.

PLCopen MC_TouchProbe and MC_AbortTrigger, beyond the Teco library. The channel latches the
encoder count at the edge of the TP input, as the module's hardware does for the index pulse; the
sensor's own delay is part of the plant, so the recorded position is where the axis was when the
delayed edge arrived. A program that knows the delay compensates it.
"""

from __future__ import annotations

__all__ = ["MC_AbortTrigger", "MC_TouchProbe"]

import math
from typing import Any, ClassVar

from mcl.command import Status
from mcl.errors import ErrorID
from mcl.fb import ExecuteFB, number


class MC_TouchProbe(ExecuteFB):
    """Records the position [u] at the next rising edge of the touch-probe input TP.

    Inputs: TriggerInput (0 = the axis' TP input), WindowOnly (accept only edges with the
    position within FirstPosition … LastPosition [u]). One latch per rising edge of Execute.
    Outputs: Done with RecordedPosition [u], Busy while waiting, CommandAborted when
    MC_AbortTrigger cancels it (or a new arming of the same axis replaces it), Error/ErrorID
    (EParam 5: TriggerInput not 0, or a window that is not finite with First <= Last).
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "TriggerInput",
        "WindowOnly",
        "FirstPosition",
        "LastPosition",
    )
    TriggerInput: int = 0
    WindowOnly: bool = False
    FirstPosition: float = 0.0
    LastPosition: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.RecordedPosition = 0.0
        self.CommandAborted = False
        self._generation = 0

    def _begin(self) -> int:
        if number(self.TriggerInput) != 0.0:
            return ErrorID.EParam
        window: tuple[float, float] | None = None
        if self.WindowOnly:
            first, last = number(self.FirstPosition), number(self.LastPosition)
            if not (math.isfinite(first) and math.isfinite(last) and first <= last):
                return ErrorID.EParam
            window = (first, last)
        self._generation = self.axis.arm_probe(window)
        return 0

    def _poll(self) -> Status | None:
        axis = self.axis
        if axis.probe.generation != self._generation:
            return Status.Aborted
        if axis.probe.position is None:
            return None
        self.RecordedPosition = axis.probe.position
        return Status.Done

    def _withdraw(self) -> None:
        self.axis.probe.abort()

    def _show_more(self, visible: bool, final: Status | None) -> None:
        self.CommandAborted = visible and final == Status.Aborted


class MC_AbortTrigger(ExecuteFB):
    """Cancels a waiting MC_TouchProbe of the axis (its CommandAborted rises). Done at once.

    Inputs: TriggerInput (0 = the axis' TP input; else EParam 5).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("TriggerInput",)
    TriggerInput: int = 0

    def _begin(self) -> int:
        if number(self.TriggerInput) != 0.0:
            return ErrorID.EParam
        self.axis.probe.abort()
        return 0

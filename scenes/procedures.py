"""Reusable PLC procedures built from mcl function blocks (what a machine builder writes once)."""

from __future__ import annotations

from dataclasses import dataclass

import mcl


@dataclass(frozen=True)
class HomingRecipe:
    """REF switch + index pulse homing of one axis (docs/reference.md, Homing step blocks).

    Attributes:
        direction: start direction of the REF search (an MC_Direction, e.g. MC_SwitchNegative).
        switch_mode: REF condition (an MC_SwitchMode).
        search_velocity: REF search velocity [mm/s].
        index_direction: direction of the index search (MC_Positive / MC_Negative).
        index_velocity: index search velocity [mm/s].
        set_position: coordinate at the index pulse [mm].
    """

    direction: int = mcl.MC_Direction.MC_SwitchNegative
    switch_mode: int = mcl.MC_SwitchMode.MC_EdgeOff
    search_velocity: float = 50.0
    index_direction: int = mcl.MC_Direction.MC_Positive
    index_velocity: float = 10.0
    set_position: float = 0.0


class HomeAxis:
    """Homing procedure: MC_StepAbsSwitch, then a buffered MC_StepRefPulse.

    Call it every PLC scan like an FB: ``home(Execute=...)``; outputs Done, Busy, Error, ErrorID.
    """

    def __init__(self, axis: mcl.Axis, recipe: HomingRecipe) -> None:
        self.axis = axis
        self.recipe = r = recipe
        self.approach = mcl.MC_StepAbsSwitch(
            Axis=axis,
            Direction=r.direction,
            SwitchMode=r.switch_mode,
            Velocity=r.search_velocity,
        )
        self.pulse = mcl.MC_StepRefPulse(
            Axis=axis,
            Direction=r.index_direction,
            Velocity=r.index_velocity,
            SetPosition=r.set_position,
            BufferMode=mcl.MC_BufferMode.Buffered,
        )
        self.Done = self.Busy = self.Error = False
        self.ErrorID = 0

    def __call__(self, Execute: bool) -> None:
        """One PLC scan."""
        approach, pulse = self.approach, self.pulse
        approach.Execute = pulse.Execute = Execute
        approach()
        pulse()
        failed = self.approach if self.approach.Error else self.pulse
        self.Error = failed.Error
        self.ErrorID = failed.ErrorID
        self.Done = self.pulse.Done
        self.Busy = self.approach.Busy or self.pulse.Busy

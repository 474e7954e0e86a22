"""Reusable PLC procedures built from mcl function blocks (what a machine builder writes once)."""

from __future__ import annotations

__all__ = ["BlockHoming", "HomeAxis", "HomingRecipe", "Recipe"]

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


@dataclass(frozen=True)
class BlockHoming:
    """Homing to a mechanical block (docs/reference.md, MC_StepBlock): drive against the stop
    until the axis stands with a following error above ``threshold``, back off clear of it, and
    set ``set_position`` there (MC_StepDirect). For axes without REF switch or index pulse, e.g.
    a hydraulic ram against its top stop.

    Attributes:
        direction: towards the block (MC_Positive or MC_Negative).
        velocity: approach velocity [mm/s].
        threshold: following error that means "on the block" (MC_StepBlock's TorqueLimit,
            0 < threshold < DevMax) [mm].
        time_limit: the search gives up after this long [s].
        set_position: coordinate where the axis is then held, clear of the block [mm].
    """

    direction: int = mcl.MC_Direction.MC_Negative
    velocity: float = 10.0
    threshold: float = 1.0
    time_limit: float = 40.0
    set_position: float = 0.0


Recipe = HomingRecipe | BlockHoming
"""A machine's homing recipe for one axis."""


class HomeAxis:
    """Homing procedure of a recipe: MC_StepAbsSwitch then a buffered MC_StepRefPulse (REF and
    index, :class:`HomingRecipe`), or MC_StepBlock then a buffered MC_StepDirect
    (:class:`BlockHoming`).

    Call it every PLC scan like an FB: ``home(Execute=...)``; outputs Done, Busy, Error, ErrorID.
    """

    def __init__(self, axis: mcl.Axis, recipe: Recipe) -> None:
        self.axis = axis
        self.recipe = r = recipe
        # typed as their common base: its inputs and outputs are native attributes when compiled
        self.approach: mcl.MotionFB  # MC_StepAbsSwitch or MC_StepBlock
        self.pulse: mcl.MotionFB  # MC_StepRefPulse or MC_StepDirect
        if isinstance(r, BlockHoming):
            self.approach = mcl.MC_StepBlock(
                Axis=axis,
                Direction=r.direction,
                Velocity=r.velocity,
                TorqueLimit=r.threshold,
                TimeLimit=r.time_limit,
            )
            self.pulse = mcl.MC_StepDirect(
                Axis=axis, SetPosition=r.set_position, BufferMode=mcl.MC_BufferMode.Buffered
            )
        else:
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

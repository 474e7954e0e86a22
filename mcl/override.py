"""Velocity override of an axis: MC_SetOverride (PLCopen Part 1, beyond the Teco library)

The override scales time: an overridden command keeps its planned path, and its profile time
advances by `VelFactor`·dt per servo cycle instead of dt. The axis therefore runs at VelFactor
times the planned velocity, VelFactor² times its acceleration and VelFactor³ times its jerk, and a
move still ends exactly at its target with Done (it takes 1/VelFactor times as long). VelFactor 0
holds the axis at standstill on its path without aborting the command: the axis stays in its
motion state (DiscreteMotion, ContinuousMotion), and goes on when the factor rises. The factor
acts on the running motion and on every later one, until another value is written.

A change of the factor is ramped, never stepped: the applied factor follows VelFactor at no more
than the axis' default deceleration over its Vmax per second (`AxisConfig.deceleration` /
`Vmax` [1/s]), so the set-point velocity changes through the ramp by at most that deceleration
and never jumps. A command that starts from rest takes the factor at once.

Overridden: MC_MoveAbsolute, MC_MoveRelative, MC_MoveAdditive, MC_MoveVelocity, GT_Jog's motion
and the velocity motion MC_GearOut leaves. Not overridden (they run in real time with their own
ramps): MC_Stop, MC_Halt and GT_Jog's release ramp, error and power-off stops, a geared slave
(MC_GearIn, MC_GearInPos: it follows its master), the homing steps (their search velocities set
how exactly a switch is found), GT_MoveAbsBlock (its block detection and release are timed),
MC_ForceControl and group motion (its override is MC_GroupSetOverride's). A command that takes
over a motion that was not overridden starts at 100 % and ramps to the factor. MC_GearInPos, while
it waits for its start point, continues the slave's previous motion without the override.

`AccFactor` and `JerkFactor` are accepted and checked (finite, >= 0) but not applied separately:
with time scaling they follow from VelFactor (VelFactor² and VelFactor³).
"""

from __future__ import annotations

from typing import Any, ClassVar

from mcl.errors import ErrorID
from mcl.fb import FunctionBlock, non_negative, number
from mcl.time_scale import MAX_FACTOR


class MC_SetOverride(FunctionBlock):
    """Sets the velocity override of the axis: its motion runs at ``VelFactor`` (1.0 = 100 %,
    0 … 2.0) times the planned velocity.

    Level-sensitive: while ``Enable`` is TRUE the factors are written in every call; with
    ``Enable`` FALSE the axis keeps the last factor written. ``Enabled`` and ``Busy`` while the
    axis follows this block's factor. A factor that is negative, not finite or (VelFactor) above
    2.0 gives ``EParam`` 5 while it is applied, and the axis keeps its previous override; an
    encoder-only axis gives ``ENoDrive``. ``AccFactor`` and ``JerkFactor`` are checked but not
    applied separately (they follow from VelFactor, see above).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("Enable", "VelFactor", "AccFactor", "JerkFactor")
    Enable: bool = False
    VelFactor: float = 1.0
    AccFactor: float = 1.0
    JerkFactor: float = 1.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Enabled = False
        self.Busy = False
        self.Error = False
        self.ErrorID = 0

    def __call__(self, **inputs: Any) -> None:
        """One PLC scan: while Enable, write the factors to the axis."""
        self._scan(inputs)
        error = self._write() if self.Enable else 0
        active = bool(self.Enable) and not error
        self.Enabled = self.Busy = active
        self.Error = bool(error)
        self.ErrorID = error

    def _write(self) -> int:
        """Check the factors and hand VelFactor to the axis; the error code (0 = written)."""
        axis = self.axis
        if not axis.has_drive:
            return ErrorID.ENoDrive
        vel, acc, jerk = number(self.VelFactor), number(self.AccFactor), number(self.JerkFactor)
        if not (non_negative(vel) and vel <= MAX_FACTOR):
            return ErrorID.EParam
        if not (non_negative(acc) and non_negative(jerk)):
            return ErrorID.EParam
        if vel != axis.override_factor:
            axis.set_override(vel)
        return 0


__all__ = ["MC_SetOverride"]

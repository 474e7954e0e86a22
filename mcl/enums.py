"""Enumerations of the PLCopen / Teco interface."""

from __future__ import annotations

__all__ = [
    "MOTION_STATES",
    "AxisState",
    "GroupState",
    "MC_BufferMode",
    "MC_Direction",
    "MC_ExecutionMode",
    "MC_SwitchMode",
]

from enum import IntEnum


class MC_BufferMode(IntEnum):
    """When a motion command takes over the axis (Teco/PLCopen numbering)."""

    Aborting = 0
    Buffered = 1
    BlendingLow = 2
    BlendingPrevious = 3
    BlendingNext = 4
    BlendingHigh = 5


class MC_Direction(IntEnum):
    """Direction of a move (modulo axes, MoveVelocity) or start direction of a homing search."""

    MC_Positive = 1
    MC_Shortest = 2
    MC_Negative = 3
    MC_Current = 4
    MC_SwitchPositive = 5
    MC_SwitchNegative = 6


class MC_SwitchMode(IntEnum):
    """Switch condition that ends a homing search (MotionControlLib Tab. 6.2)."""

    MC_On = 0
    MC_Off = 1
    MC_EdgeOn = 2
    MC_EdgeOff = 3
    MC_EdgeSwitchPositive = 4
    MC_EdgeSwitchNegative = 5


class MC_ExecutionMode(IntEnum):
    """When an administrative command takes effect (PLCopen Part 1 v2.0, MC_EXECUTION_MODE):
    at once, or queued behind the motion commands given before it (as if Buffered)."""

    mcImmediately = 0
    mcDelayed = 1
    mcQueued = 2


class AxisState(IntEnum):
    """The eight states of a single axis (MotionControlLib Fig. 2.1)."""

    Disabled = 0
    StandStill = 1
    Homing = 2
    DiscreteMotion = 3
    ContinuousMotion = 4
    SynchronizedMotion = 5
    Stopping = 6
    ErrorStop = 7


class GroupState(IntEnum):
    """The states of an axes group (MotionControlLib Fig. 2.2)."""

    GroupDisabled = 0
    GroupStandby = 1
    GroupMoving = 2
    GroupHoming = 3
    GroupStopping = 4
    GroupErrorStop = 5


MOTION_STATES = frozenset(
    {
        AxisState.DiscreteMotion,
        AxisState.ContinuousMotion,
        AxisState.SynchronizedMotion,
    }
)
"""States in which a new motion command may take over the axis (besides StandStill)."""


class MC_CIRC_MODE(IntEnum):
    """How the AuxPoint of MC_MoveCircularAbsolute/Relative describes the arc (PLCopen Part 4)."""

    BORDER = 0
    CENTER = 1
    RADIUS = 2


class MC_CIRC_PATHCHOICE(IntEnum):
    """The direction of an arc, seen from the positive normal of its plane (PLCopen Part 4)."""

    CLOCKWISE = 0
    COUNTERCLOCKWISE = 1


class MC_TRANSITION_MODE(IntEnum):
    """How a blending group motion rounds the corner into it (PLCopen Part 4)."""

    TMNone = 0
    TMStartVelocity = 1
    TMConstantVelocity = 2
    TMCornerDistance = 3
    TMMaxCornerDeviation = 4


class MC_COORD_SYSTEM(IntEnum):
    """The coordinate system of a group motion's positions (PLCopen Part 4)."""

    ACS = 0
    MCS = 1
    PCS = 2

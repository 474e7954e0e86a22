"""Machine data of one axis (:class:`AxisConfig`): what the module knows besides the servo
constants of GT_SetConstant. Positions in user units u (mm or degrees), times in seconds."""

from __future__ import annotations

__all__ = ["AxisConfig", "AxisParameters"]

import math
from dataclasses import dataclass

from mcl.errors import check_finite


@dataclass(frozen=True, slots=True)
class AxisConfig:
    """Machine data of one axis: what the module knows besides the GT_SetConstant constants.

    Attributes:
        resolution: travel per encoder count [u/count].
        dev_max: following-error limit DevMax [u]; beyond it ERRPOS 2001 opens the loop.
        in_position: in-position window [u] (settling integral Ki1, group InPosition).
        acceleration, deceleration: defaults when an FB passes 0 [u/s²].
        jerk: default jerk when an FB passes 0 [u/s³]; 0 = not jerk-limited.
        max_acceleration, max_deceleration: maxima; larger FB inputs are clamped [u/s²].
            ``max_deceleration`` is also the "maximum ramp" of error and power-off stops.
        max_jerk: maximum jerk [u/s³]; 0 = unlimited.
        modulo: period of a rotary (modulo) axis [u]; 0 = linear axis.
        servo_period: servo cycle [s].
        unit: the user unit u, for messages, traces and the viewer (``"mm"``, ``"deg"``).
        quick_stop_time: after ERRPOS 2001 the position loop opens but the drive stays enabled
            at 0 V this long [s], so the velocity-mode amplifier brakes the axis with its own
            velocity loop before the enable drops and the holding brake engages (0 = the enable
            drops at once and the axis coasts).
        release_time: after running into a mechanical block (MC_StepBlock, GT_MoveAbsBlock's
            TorqueLimit) the drive lets go this long [s] with the integral action off, so the
            compressed block springs the axis back (or a load sags onto Kp alone) before the
            axis backs off by the in-position window and is held clear of the block.
    """

    resolution: float = 0.001
    dev_max: float = 2.0
    in_position: float = 0.005
    acceleration: float = 1000.0
    deceleration: float = 1000.0
    jerk: float = 0.0
    max_acceleration: float = 20000.0
    max_deceleration: float = 20000.0
    max_jerk: float = 0.0
    modulo: float = 0.0
    servo_period: float = 0.001
    quick_stop_time: float = 0.1
    release_time: float = 0.05
    unit: str = "mm"

    def __post_init__(self) -> None:
        positive = (
            "resolution",
            "dev_max",
            "in_position",
            "acceleration",
            "deceleration",
            "max_acceleration",
            "max_deceleration",
            "servo_period",
        )
        check_finite(self, positive, True)
        check_finite(self, ("jerk", "max_jerk", "modulo", "quick_stop_time", "release_time"), False)


@dataclass(slots=True)
class AxisParameters:
    """The axis parameters a program may change at run time (MC_WriteParameter,
    MC_WriteBoolParameter, GT_SWLim; PLCopen Part 1 v2.0 parameter numbers in brackets).
    GT_SetConstant sets the software limits from its LimPos/LimNeg; the rest starts from the
    machine data (:class:`AxisConfig`).

    Attributes:
        sw_limit_pos: positive software limit SWLimitPos (2) [u].
        sw_limit_neg: negative software limit SWLimitNeg (3) [u].
        sw_enable_pos: EnableLimitPos (4): the positive limit is supervised (with Ref).
        sw_enable_neg: EnableLimitNeg (5): the negative limit is supervised (with Ref).
        lag_monitoring: EnablePosLagMonitoring (6): the following error is supervised.
        max_position_lag: MaxPositionLag (7), DevMax: the following-error limit [u].
        max_velocity_appl: MaxVelocityAppl (9): a limit of the commanded velocity below the
            system's Vmax [u/s] (inf: Vmax).
        max_acceleration_appl: MaxAccelerationAppl (13) [u/s²].
        max_deceleration_appl: MaxDecelerationAppl (15) [u/s²].
        max_jerk: MaxJerk (16) of commanded motion [u/s³]; 0 = unlimited.
    """

    sw_limit_pos: float = 0.0
    sw_limit_neg: float = 0.0
    sw_enable_pos: bool = False
    sw_enable_neg: bool = False
    lag_monitoring: bool = True
    max_position_lag: float = 2.0
    max_velocity_appl: float = math.inf
    max_acceleration_appl: float = 20000.0
    max_deceleration_appl: float = 20000.0
    max_jerk: float = 0.0

    @classmethod
    def of(cls, config: AxisConfig) -> AxisParameters:
        """The parameters at power-up: from the machine data, no software limits."""
        return cls(
            max_position_lag=config.dev_max,
            max_acceleration_appl=config.max_acceleration,
            max_deceleration_appl=config.max_deceleration,
            max_jerk=config.max_jerk,
        )

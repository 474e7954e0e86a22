"""Force or pressure limit and hold: MC_ForceControl (beyond the Teco library and PLCopen).

In the manner of PLCopen MC_TorqueControl, for an axis whose force is measured on its analog
inputs (pressure transducers of a cylinder, a load cell): the axis moves in the direction of
the force set point at no more than ``Velocity`` until the measured force reaches the set point,
then holds it. mcl knows nothing of the actuator: the force is a linear combination of one or
two analog inputs, and the position loop of the axis stays closed underneath.

The force loop is an admittance: every servo cycle the model velocity is
``v = clip(Gain·(F_ref − F), ±Velocity)`` (its change limited by ``Acceleration``) and the model
position integrates it. Through the position regulator this is a PI force controller: the
velocity feed-forward gives the proportional part ``(10 V/Vmax)·Ff·Gain`` [V per force unit],
the position gain the integral part ``Kp·Gain`` [V per force unit and second]; the position loop's
supervision (following error, limits) stays as it is. The model starts at the actual position
(not where the previous motion's model stood) with the regulator's integral action cleared: what
the previous motion wound up against the part is not pressed into it. ``F_ref`` ramps
from the force measured at the start to ``Force`` at ``ForceRamp`` (0: at once), so a lower set
point with a ramp decompresses a press gently before its return stroke.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar

from mcl.command import Command, Status
from mcl.enums import AxisState, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import MotionFB, non_negative, number, positive
from mcl.motion import ready_limits

if TYPE_CHECKING:
    from mcl.axis import Axis


class ForceHold(Command):
    """The command of MC_ForceControl: the admittance set point (module docstring).

    ``signal`` (InForce) while the set point has reached ``force`` and the measured force lies
    within ``tolerance`` of it.
    """

    state = AxisState.ContinuousMotion

    def __init__(
        self,
        buffer_mode: MC_BufferMode,
        force: float,
        ramp: float,
        velocity: float,
        acceleration: float,
        gain: float,
        inputs: tuple[int, int],
        scales: tuple[float, float],
        offset: float,
        tolerance: float,
    ) -> None:
        super().__init__(buffer_mode)
        self.force = force
        self.ramp = ramp
        self.limit = velocity
        self.acceleration = acceleration
        self.gain = gain
        self.inputs = inputs
        self.scales = scales
        self.offset = offset
        self.tolerance = tolerance
        self.reference = 0.0
        """The ramped force set point F_ref [force unit]."""
        self.measured = 0.0
        """The force measured this servo cycle [force unit]."""
        self._p = self._v = 0.0
        self._t = 0.0

    def measure(self, axis: Axis) -> float:
        """The force from the analog inputs sampled this servo cycle [force unit]."""
        analog = axis.io.analog
        first, second = self.inputs
        force = self.offset + self.scales[0] * analog[first]
        if second >= 0:
            force += self.scales[1] * analog[second]
        return force

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        # from the actual position: the following error the previous motion left (a press
        # lags its model under load) must not be pressed into the part
        self._p, self._v, self._t = axis.actual, v, 0.0
        if axis.regulator is not None:  # the force loop owns the integral action now
            axis.regulator.clear_integral()
        self.measured = self.reference = self.measure(axis)

    def finished(self) -> bool:
        return False

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        dt = t - self._t
        self._t = t
        measured = self.measured = self.measure(axis)
        ref, force = self.reference, self.force
        if ref != force:
            step = self.ramp * dt if self.ramp > 0.0 else math.inf
            ref = min(force, ref + step) if force > ref else max(force, ref - step)
            self.reference = ref
        limit = self.limit
        v_cmd = max(-limit, min(limit, self.gain * (ref - measured)))
        v = self._v
        dv = self.acceleration * dt
        v_new = max(v - dv, min(v + dv, v_cmd))
        a = (v_new - v) / dt if dt > 0.0 else 0.0
        self._p += 0.5 * (v + v_new) * dt
        self._v = v_new
        self.signal = ref == force and abs(force - measured) <= self.tolerance
        return self._p, v_new, a

    def rebase(self, delta: float) -> None:
        self._p += delta


class MC_ForceControl(MotionFB):
    """Limit and hold a force measured on the axis' analog inputs (beyond the Teco library; in
    the manner of PLCopen MC_TorqueControl).

    Inputs (sampled on the rising edge of Execute; a new edge takes the new values):

    - ``Force``: set point [force unit, e.g. kN or bar], signed: a positive force pushes the
      axis in its positive direction.
    - ``ForceRamp``: rate at which the set point moves from the force measured at the start to
      ``Force`` [force unit/s]; 0 = at once.
    - ``Velocity``: speed limit [u/s] (> 0, at least 1 % of Vmax): the axis moves toward the
      force at no more than this, e.g. until the tool touches the part.
    - ``Acceleration``: limit of the model's velocity changes [u/s²]; 0 = the axis default.
    - ``Gain``: admittance [u/s per force unit] (> 0): model velocity per force error.
    - ``InputNumber``, ``Scale``: the analog input and its scale [force unit/V];
      ``InputNumber2``, ``Scale2``: a second input added (−1: none; a differential cylinder:
      ``p_A·A_A − p_B·A_B`` with a negative ``Scale2``); ``Offset`` [force unit] is added too
      (e.g. the weight of a vertical ram).
    - ``Tolerance``: InForce window [force unit] (>= 0).

    Outputs: ``InForce`` (the set point has reached Force and the measured force is within
    Tolerance), ``ActualForce`` (the measured force [force unit]), Busy, Active,
    CommandAborted, Error, ErrorID. Like MC_MoveVelocity it never ends by itself: another motion
    command aborts it. The axis is in ContinuousMotion. Invalid inputs (an input number the axis
    does not have, a scale or gain that is not a finite number, …) give EParam and leave the axis
    alone.
    """

    INPUTS: ClassVar[tuple[str, ...]] = (
        "Force",
        "ForceRamp",
        "Velocity",
        "Acceleration",
        "Gain",
        "InputNumber",
        "Scale",
        "InputNumber2",
        "Scale2",
        "Offset",
        "Tolerance",
    )
    Force: float = 0.0
    ForceRamp: float = 0.0
    Velocity: float = 0.0
    Acceleration: float = 0.0
    Gain: float = 0.0
    InputNumber: int = 0
    Scale: float = 1.0
    InputNumber2: int = -1
    Scale2: float = 0.0
    Offset: float = 0.0
    Tolerance: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.InForce = False
        self.ActualForce = 0.0

    def _command(self, mode: MC_BufferMode) -> Command | int:
        axis = self.axis
        limits = ready_limits(axis, self.Velocity, self.Acceleration, self.Acceleration, 0.0)
        if isinstance(limits, int):
            return limits
        force, ramp, gain = number(self.Force), number(self.ForceRamp), number(self.Gain)
        scale, scale2, offset = number(self.Scale), number(self.Scale2), number(self.Offset)
        tolerance = number(self.Tolerance)
        count = len(axis.io.analog)
        first, second = self.InputNumber, self.InputNumber2
        if not (
            math.isfinite(force)
            and non_negative(ramp)
            and positive(gain)
            and math.isfinite(scale)
            and scale != 0.0
            and math.isfinite(scale2)
            and math.isfinite(offset)
            and non_negative(tolerance)
            and 0 <= first < count
            and (second == -1 or 0 <= second < count)
        ):
            return ErrorID.EParam
        return ForceHold(
            mode,
            force,
            ramp,
            limits.velocity,
            limits.acceleration,
            gain,
            (first, second),
            (scale, scale2 if second >= 0 else 0.0),
            offset,
            tolerance,
        )

    def _show_more(self, visible: bool, final: Status | None) -> None:
        super()._show_more(visible, final)
        cmd = self._cmd
        if self._running and isinstance(cmd, ForceHold):
            self.InForce = cmd.signal
            self.ActualForce = cmd.measured
        else:
            self.InForce = False


__all__ = ["ForceHold", "MC_ForceControl"]

"""Servo core of one GT-x75x axis: position regulator and DAC.

``u = Kp·e + Ki·∫e + Kd·ė + (10 V/Vmax)·(Ff·v + Ka·a) + Kf·clip(v/Vf, ±1)`` (for ``v < 0``
the feed-forward scaled by FfNeg/Ff; Vf = 0: the band ``Kf·Vmax/10``; plus the deadband
compensation and the friction pulse at a reversal of the model velocity, ``Kfp`` decaying with
``Tfp``), with
back-calculation anti-windup (``Kc``) when the 12-bit DAC output saturates at ±10 V, and ``Ki1``
integral action that only works while the model stands still and the axis is outside its
in-position window.
"""

from __future__ import annotations

__all__ = [
    "DAC_CODES",
    "DAC_FULL_SCALE",
    "VOLT_LIMIT",
    "Regulator",
    "ServoConstants",
    "dac",
    "dac_code_volts",
]

import math
from dataclasses import dataclass
from typing import Final

DAC_CODES: Final = 4095
"""Largest DAC code; ±4095 ↔ ±10.5 V."""
DAC_FULL_SCALE: Final = 10.5
"""Voltage at the largest DAC code [V]."""
VOLT_LIMIT: Final = 10.0
"""Clip of the analog command in closed loop [V]."""
_VOLTS_PER_CODE: Final = DAC_FULL_SCALE / DAC_CODES


def dac(volts: float) -> float:
    """Quantize a voltage to the 12-bit DAC (±4095 ↔ ±10.5 V) and clip it to ±10 V [V].

    A non-finite request (a diverged regulator) outputs 0 V rather than crash the servo cycle.
    """
    if volts != volts:
        return 0.0
    if volts >= VOLT_LIMIT:
        volts = VOLT_LIMIT
    elif volts <= -VOLT_LIMIT:
        volts = -VOLT_LIMIT
    return math.floor(volts / _VOLTS_PER_CODE + 0.5) * _VOLTS_PER_CODE


def dac_code_volts(code: int) -> float:
    """Voltage of a raw DAC code as GT_Analog writes it: −4095 → +10.5 V, +4095 → −10.5 V.

    The MotionControlLib manual documents this inverted mapping for GT_Analog; it is kept as
    documented.
    """
    code = max(-DAC_CODES, min(DAC_CODES, int(code)))
    return -code * _VOLTS_PER_CODE


@dataclass(slots=True)
class ServoConstants:
    """Constants written by GT_SetConstant (MotionControlLib §3.1), in user units.

    Attributes:
        Kp: proportional gain [V/u].
        Ki: integral gain [V/(u·s)].
        Kd: derivative gain [V·s/u].
        Ff: velocity feed-forward [-] (1.0 = the full model velocity).
        Kc: anti-windup back-calculation gain [1/s].
        Vmax: axis velocity at 10 V, also the axis' maximum velocity [u/s].
        LimPos: positive software limit [u]; LimPos <= LimNeg disables both.
        LimNeg: negative software limit [u].
        Ki1: settling integral gain, active at model standstill outside the window [V/(u·s)].
        Filter: time constant of the low-pass on the measured velocity VEL [ms].
        Ka: acceleration feed-forward [s]: the drive's lag plus half a servo period
            (beyond the Teco library; it keeps the following error small while accelerating).
        Kf: friction feed-forward [V]: the voltage that makes up for the drive's Coulomb
            friction while the axis moves, so the integrator need not build it up at each
            start; it adds ``Kf·clip(v/Vf, ±1)`` (v = model velocity): it fades in over the
            first ``Vf`` of speed (beyond the Teco library).
        Kfp: friction pulse [V]: when the model velocity changes its sign, ``±Kfp`` (the new
            direction) is added and decays with the time constant Tfp, so that the drive
            breaks loose from the Coulomb friction at once instead of standing until the
            following error has built up the force (the reversal spikes of a circle test);
            Kf alone passes through 0 V there. 0 = off (beyond the Teco library).
        Tfp: decay time constant of the friction pulse [s].
        Vf: friction band [u/s]: the friction feed-forward is full from ``|v| = Vf`` on; 0 = the
            band ``Kf·Vmax/10`` (the speed whose velocity feed-forward is Kf, where Kf passes
            through 0 V slowly and the axis stands in its friction at a reversal: the quadrant
            spikes of a circle test). A narrow band switches the voltage where the model
            velocity reverses, as the Coulomb friction switches where the axis does (beyond the
            Teco library).
        FfNeg: velocity feed-forward for negative model velocities [-]; 0 = the same as Ff.
            For a drive whose speed per volt differs by direction (a differential cylinder:
            extend and retract differ by the area ratio); the acceleration feed-forward is
            scaled alike, by FfNeg/Ff (beyond the Teco library).
        Deadband: valve overlap compensation [V]: ``Deadband·clip(10·u/Deadband, ±1)`` is
            added to the command ``u``, so an overlapped spool opens as soon as the loop asks
            for flow; it rises linearly over ``|u| < Deadband/10`` so that it does not chatter
            around 0 V (beyond the Teco library).
    """

    Kp: float = 0.0
    Ki: float = 0.0
    Kd: float = 0.0
    Ff: float = 1.0
    Kc: float = 0.0
    Vmax: float = 0.0
    LimPos: float = 0.0
    LimNeg: float = 0.0
    Ki1: float = 0.0
    Filter: float = 0.0
    Ka: float = 0.0
    Kf: float = 0.0
    FfNeg: float = 0.0
    Deadband: float = 0.0
    Kfp: float = 0.0
    Tfp: float = 0.0
    Vf: float = 0.0

    @property
    def sw_limits_active(self) -> bool:
        """Whether the software limits are set (LimPos above LimNeg)."""
        return self.LimPos > self.LimNeg


class Regulator:
    """Discrete PID position regulator with feed-forward, anti-windup and DAC output."""

    __slots__ = (
        "_band",
        "_direction",
        "_e_prev",
        "_ff",
        "_integral",
        "_neg",
        "_pulse",
        "c",
        "period",
    )

    def __init__(self, constants: ServoConstants, period: float) -> None:
        """Args: constants: the axis' servo constants; period: servo period [s]."""
        self.c = constants
        self.period = period
        self._ff = 10.0 / constants.Vmax if constants.Vmax > 0.0 else 0.0
        ff, neg = constants.Ff, constants.FfNeg
        self._neg = neg / ff if neg > 0.0 and ff > 0.0 else 1.0
        """Feed-forward factor for negative model velocities (FfNeg/Ff)."""
        self._band = constants.Kf / constants.Vf if constants.Vf > 0.0 else self._ff
        """The friction feed-forward's slope inside its band [V·s/u]."""
        self._integral = 0.0
        self._e_prev = 0.0
        self._pulse = 0.0
        """The friction pulse now [V]."""
        self._direction = 0.0
        """The sign of the last non-zero model velocity (0: none yet)."""

    def reset(self) -> None:
        """Clear the integrator, the derivative memory and the friction pulse (loop (re)closed)."""
        self._integral = 0.0
        self._e_prev = 0.0
        self._pulse = 0.0
        self._direction = 0.0

    def clear_integral(self) -> None:
        """Clear the integral action (Ki and Ki1 share one integrator); the derivative memory
        stays, so no derivative kick follows."""
        self._integral = 0.0

    def memory(self) -> tuple[float, float, float, float]:
        """The regulator's state: integral action [V], the last following error [u], the
        friction pulse [V] and the sign of the last model velocity."""
        return self._integral, self._e_prev, self._pulse, self._direction

    def set_memory(self, memory: tuple[float, float, float, float]) -> None:
        """Restore a state taken with :meth:`memory`."""
        self._integral, self._e_prev, self._pulse, self._direction = memory

    def carry_over(self, other: Regulator) -> None:
        """Take over the state of the regulator this one replaces (no bump)."""
        self.set_memory(other.memory())

    def output(self, e: float, v_model: float, a_model: float, settle: bool) -> float:
        """One regulator step.

        Args:
            e: following error, model minus actual position [u].
            v_model: model velocity [u/s].
            a_model: model acceleration [u/s²].
            settle: the model stands still and the axis is outside its in-position window
                (enables ``Ki1``).

        Returns:
            The quantized analog command [V], within ±10 V.
        """
        c = self.c
        period = self.period
        ff = self._ff
        feed = ff * (c.Ff * v_model + c.Ka * a_model)
        u = (
            c.Kp * e
            + self._integral
            + c.Kd * (e - self._e_prev) / period
            + (feed * self._neg if v_model < 0.0 else feed)
            + max(-c.Kf, min(c.Kf, self._band * v_model))
            + self._friction_pulse(v_model)
        )
        db = c.Deadband
        if db > 0.0:
            u += max(-db, min(db, 10.0 * u))
        out = dac(u)
        ki = c.Ki + c.Ki1 if settle else c.Ki
        # back-calculation, at most the whole excess per cycle (stable for any Kc)
        self._integral += period * ki * e + min(1.0, c.Kc * period) * (out - u)
        self._e_prev = e
        return out

    def _friction_pulse(self, v_model: float) -> float:
        """The friction pulse of this cycle [V]: ``±Kfp`` from the cycle the model velocity
        changes its sign, decaying by ``exp(−period/Tfp)`` per cycle."""
        c = self.c
        if c.Kfp <= 0.0:
            return 0.0
        sign = 1.0 if v_model > 0.0 else -1.0 if v_model < 0.0 else 0.0
        if sign != 0.0 and sign != self._direction:
            if self._direction != 0.0:
                self._pulse = sign * c.Kfp
            self._direction = sign
        pulse = self._pulse
        self._pulse = pulse * math.exp(-self.period / c.Tfp) if c.Tfp > 0.0 else 0.0
        return pulse

    def open_loop(self, v_model: float) -> float:
        """SpeedMode 1: the analog command proportional to the model velocity [V]."""
        return dac(self._ff * v_model)

"""The measuring wheel of a web line and its errors (:class:`MeasuringWheel`), rolling on the web
through a rolling contact the wheel rewrites before every physics step
(:class:`RollingCoupling`); compiled with the plant where a C compiler exists.

The wheel is a device of a machine whose model has the web line's joints and numerics
(models/README.md, the flying shear's "Measuring-wheel errors"): the web ``M``, the wheel ``W``,
the equality ``wheel_roll`` and the numerics ``W_radius``, ``W_slip``, ``W_slip_speed``,
``W_slip_random``, ``W_diameter``, ``W_runout``, ``W_liftoff`` and ``M_stretch``.
"""

from __future__ import annotations

__all__ = ["MeasuringWheel", "RollingCoupling"]

import math
import random
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from scenes.plant.mujoco import numeric


class RollingCoupling:
    """A rolling contact in the model: the equality ``follower = a0 + a1·leader`` (a linear
    joint coupling, MuJoCo's ``<joint>`` equality with its polynomial coefficients), rewritten
    by a device before a physics step. A new slope ``a1`` moves ``a0`` so that the follower
    stays where it is at the leader's position: the coupling stays continuous.

    Args:
        model: the compiled model.
        equality: the equality's (prefixed) name.
        a1: the slope at the start.
        follower, leader: the two joint coordinates now.
    """

    def __init__(
        self, model: mujoco.MjModel, equality: str, a1: float, follower: float, leader: float
    ) -> None:
        eq = int(model.equality(equality).id)
        self._coef: Any = memoryview(model.eq_data.reshape(-1))
        self._base = eq * model.eq_data.shape[1]
        self.a1 = a1
        """Follower per leader travel."""
        self.a0 = follower - a1 * leader
        """Follower at leader 0."""
        self.write()

    def slope(self, a1: float, leader: float) -> bool:
        """Set the slope ``a1`` at the leader's coordinate ``leader``; False: it was that."""
        if a1 == self.a1:
            return False
        self.a0 += (self.a1 - a1) * leader
        self.a1 = a1
        self.write()
        return True

    def write(self) -> None:
        """Write ``a0`` and ``a1`` into the model's equality."""
        self._coef[self._base] = self.a0
        self._coef[self._base + 1] = self.a1


class MeasuringWheel:
    """The measuring wheel as it rolls on the strip, with the errors a commissioning engineer
    tunes against; the strip (M) stays the truth of every length.

    The wheel's angle per strip travel is ``(1 + slip)·(1 + ε) / r_roll`` (the encoder's
    scale assumes the nominal radius ``r``, so the axis W reads ``r/r_roll`` of the travel):

    - ``diameter``: relative deviation of the true rolling radius from the nominal one
      (tolerance and wear of the tread; +0.0004: the wheel is larger and reads 0.04 % short);
    - ``runout`` [m]: radial runout, ``r_roll = r·(1 + diameter) + runout·cos(θ + φ)`` (θ the
      wheel angle): a once-per-turn position error of ±runout;
    - ``slip`` (constant, −0.001 = the wheel reads 0.1 % short), ``slip_per_speed`` [1/(m/s)]
      (the creep of a dragged elastomer tread grows with speed) and ``random`` (rms of a seeded
      sum of sines between 0.2 and 3 Hz, a function of time only);
    - lift-off on strip flutter: at random strip positions (``liftoff_rate`` per metre of strip,
      seeded), the wheel leaves the strip for ``liftoff_time`` [s] and coasts, braked by its
      bearing and encoder drag ``drag_torque`` [N·m]: it loses ``½·(drag_torque·r/J)·t²`` of
      travel each time;
    - strip stretch ``ε = tension / stiffness``: the wheel rolls on strip stretched by the
      line tension ``tension`` [N] (``stiffness`` = E·A [N]); the cut piece relaxes, so the
      wheel reads ``ε`` long.

    :meth:`ideal` turns every error off (a perfect wheel on a rigid strip). The wheel rolls on
    the strip through the equality ``wheel_roll`` (``W = a0 + a1·M``, a :class:`RollingCoupling`),
    rewritten before every step. Every parameter may change at any time.

    Args:
        model, data: the compiled model and its data (positions current).
        prefix: the machine's name prefix in the model.
        seed: seed of the random slip's frequencies and phases and of the lift-off positions.
    """

    PARTS = 8
    """Sines in the random part."""

    def __init__(
        self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "", seed: int = 1
    ) -> None:
        self.radius = float(numeric(model, f"{prefix}W_radius", 1, 0.0)[0])
        self.slip = float(numeric(model, f"{prefix}W_slip", 1, -0.5, 0.5)[0])
        """Constant slip [-] (−0.005 = −0.5 %)."""
        self.slip_per_speed = float(numeric(model, f"{prefix}W_slip_speed", 1, -0.5, 0.5)[0])
        """Slip per strip speed [1/(m/s)]."""
        self.random = float(numeric(model, f"{prefix}W_slip_random", 1, -1e-12, 0.1)[0])
        """Rms of the random part of the slip [-]."""
        self.diameter = float(numeric(model, f"{prefix}W_diameter", 1, -0.1, 0.1)[0])
        """Relative deviation of the rolling radius from the nominal radius [-]."""
        runout, phase = numeric(model, f"{prefix}W_runout", 2, -1.0)
        self.runout, self.runout_phase = float(runout), float(phase)
        """Radial runout [m] and its angle on the wheel [rad]."""
        rate, duration, drag = numeric(model, f"{prefix}W_liftoff", 3, -1e-12)
        self.liftoff_rate, self.liftoff_time = float(rate), float(duration)
        """Lift-offs per metre of strip [1/m]; how long each lasts [s]."""
        self.drag_torque = float(drag)
        """Bearing and encoder drag torque on the wheel [N·m] (brakes it while lifted)."""
        tension, stiffness = numeric(model, f"{prefix}M_stretch", 2, -1e-12)
        self.tension, self.stiffness = float(tension), float(stiffness)
        """Line tension at the wheel [N]; the strip's E·A [N] (0: a rigid strip)."""
        wheel = model.joint(f"{prefix}W")
        self.inertia = float(model.dof_armature[wheel.dofadr[0]]) + float(
            model.body_inertia[wheel.bodyid[0]][1]
        )
        """The wheel's moment of inertia about its axle [kg·m²]."""
        self.seed = seed
        rng = random.Random(seed)
        self._sines = [
            (2.0 * math.pi * rng.uniform(0.2, 3.0), rng.uniform(0.0, 2.0 * math.pi))
            for _ in range(self.PARTS)
        ]
        self._gain = math.sqrt(2.0 / self.PARTS)
        self._wheel = int(wheel.qposadr[0])
        strip = model.joint(f"{prefix}M")
        self._strip, self._strip_dof = int(strip.qposadr[0]), int(strip.dofadr[0])
        self._qpos: Any = memoryview(data.qpos)
        self._qvel: Any = memoryview(data.qvel)
        self.liftoffs = 0
        """Lift-offs so far."""
        m = float(data.qpos[self._strip])
        self.next_liftoff = m + self._gap(0)
        """Strip position of the next lift-off [m]."""
        self.lifted = (-math.inf, 0.0)
        """The current (or last) lift-off: when it began [s], the strip speed then [m/s]."""
        self.applied = self.slip
        """The slip in effect [-] (lift-off included)."""
        angle = float(data.qpos[self._wheel])
        self.roll = RollingCoupling(
            model, f"{prefix}wheel_roll", self._slope(self.applied, angle), angle, m
        )
        """The wheel's angle on the strip's travel."""

    def ideal(self) -> None:
        """Turn every error source off: the wheel reads the strip's travel exactly."""
        self.slip = self.slip_per_speed = self.random = 0.0
        self.diameter = self.runout = 0.0
        self.liftoff_rate = 0.0
        self.tension = 0.0
        self.lifted = (-math.inf, 0.0)

    @property
    def stretch(self) -> float:
        """The strip's elastic strain at the wheel ``tension / stiffness`` [-]."""
        return self.tension / self.stiffness if self.stiffness > 0.0 else 0.0

    def _gap(self, k: int) -> float:
        """Strip travel before lift-off ``k`` + 1 [m] (exponential, seeded; inf: none)."""
        if self.liftoff_rate <= 0.0:
            return math.inf
        return random.Random(self.seed * 1_000_003 + k).expovariate(self.liftoff_rate)

    def _slope(self, slip: float, angle: float) -> float:
        """Wheel angle per strip travel [rad/m] at the wheel angle ``angle``."""
        rolling = self.radius * (1.0 + self.diameter)
        if self.runout:
            rolling += self.runout * math.cos(angle + self.runout_phase)
        return (1.0 + slip) * (1.0 + self.stretch) / rolling

    def slip_at(self, t: float, speed: float = 0.0) -> float:
        """The slip at time ``t`` [s] and strip speed ``speed`` [m/s], lift-off aside [-]."""
        slip = self.slip + self.slip_per_speed * abs(speed)
        if not self.random:
            return slip
        noise = 0.0  # summed in order, as sum() does (an explicit loop compiles natively)
        for w, phase in self._sines:
            noise += math.sin(w * t + phase)
        return slip + self.random * self._gain * noise

    def _liftoff(self, t: float, m: float, v: float) -> float:
        """The slip a lift-off adds now [-]: the coasting wheel against the strip speed."""
        if m >= self.next_liftoff:
            self.liftoffs += 1
            self.lifted = (t, v)
            if self.liftoff_rate > 0.0:
                self.next_liftoff = m + self._gap(self.liftoffs)
            else:
                self.next_liftoff = math.inf
        began, v0 = self.lifted
        if t - began >= self.liftoff_time or v == 0.0:
            return 0.0
        braking = self.drag_torque * self.radius / self.inertia
        coasting = v0 - math.copysign(braking * (t - began), v0)
        if coasting * v0 < 0.0:
            coasting = 0.0
        return coasting / v - 1.0

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """The wheel's rolling for the coming step, its angle kept continuous."""
        t = float(data.time)
        m: float = self._qpos[self._strip]
        v: float = self._qvel[self._strip_dof]
        slip = self.slip_at(t, v)
        if self.liftoff_rate > 0.0 and self.next_liftoff == math.inf:  # rate set at run time
            self.next_liftoff = m + self._gap(self.liftoffs)
        if self.liftoff_rate > 0.0 or t - self.lifted[0] < self.liftoff_time:
            slip += self._liftoff(t, m, v)
        if self.roll.slope(self._slope(slip, self._qpos[self._wheel]), m):
            self.applied = slip

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array(
            [
                self.roll.a0,
                self.roll.a1,
                self.applied,
                self.slip,
                self.random,
                self.slip_per_speed,
                self.diameter,
                self.runout,
                self.runout_phase,
                self.liftoff_rate,
                self.liftoff_time,
                self.drag_torque,
                self.tension,
                self.stiffness,
                float(self.liftoffs),
                self.next_liftoff,
                self.lifted[0],
                self.lifted[1],
            ]
        )

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        values = [float(v) for v in state]
        self.roll.a0, self.roll.a1, self.applied, self.slip, self.random = values[:5]
        self.slip_per_speed, self.diameter, self.runout, self.runout_phase = values[5:9]
        self.liftoff_rate, self.liftoff_time, self.drag_torque = values[9:12]
        self.tension, self.stiffness = values[12:14]
        self.liftoffs, self.next_liftoff = round(values[14]), values[15]
        self.lifted = (values[16], values[17])
        self.roll.write()

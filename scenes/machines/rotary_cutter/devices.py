"""The rotary cross cutter's devices, integrated before every physics step (compiled with the
plant where a C compiler exists): the knife drum's blades in the web (the cutting force, the
blade's grip along the web, every cut taken from the physics). The measuring wheel and its
errors are the web line's (:class:`scenes.parts.MeasuringWheel`).
"""

from __future__ import annotations

__all__ = ["CUT_FIELDS", "Cut", "KnifeDrum", "cut_of", "cut_values"]

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from scenes.plant.mujoco import numeric


def _wrap(angle: float) -> float:
    """An angle in [−π, π) [rad]."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@dataclass
class Cut:
    """One blade pass through the web, measured from the physics.

    Attributes:
        time: when the blade went through the web (its tip reached the web's underside) [s];
            for a pass that did not go through, when it left the web.
        blade: which blade (1 or 2).
        position: material coordinate under the blade's tip then [mm] (distance from the web's
            origin, counted upstream: a later cut lies further upstream).
        length: the piece from the previous cut [mm] (None for the first cut and a miss).
        through: the blade went through the web (False: a miss, the web is not separated).
        depth: deepest the tip went below the web's top [mm] (the web is ``thickness`` thick).
        mismatch: largest |tip − web velocity along the web| / web velocity while the tip was in
            the web [-].
        drag: largest |force of the blade on the web along it| [N].
        torque: largest |drum torque| (the amplifier's, its feed-forward included, at the
            drum) since the previous cut [N·m].
        motor_torque: that torque at the motor, ``torque / (ratio·efficiency)`` [N·m].
        current: the motor current for it, ``motor_torque / Kt`` [A].
        rms_current: the rms motor current since the previous cut [A].
    """

    time: float
    blade: int
    position: float = math.nan
    length: float | None = None
    through: bool = False
    depth: float = 0.0
    mismatch: float = 0.0
    drag: float = 0.0
    torque: float = 0.0
    motor_torque: float = 0.0
    current: float = 0.0
    rms_current: float = 0.0


CUT_FIELDS = 12
"""Numbers per cut in a drum's state."""


def cut_values(cut: Cut) -> list[float]:
    """A cut as numbers (no length: NaN)."""
    return [
        cut.time,
        float(cut.blade),
        cut.position,
        math.nan if cut.length is None else cut.length,
        float(cut.through),
        cut.depth,
        cut.mismatch,
        cut.drag,
        cut.torque,
        cut.motor_torque,
        cut.current,
        cut.rms_current,
    ]


def cut_of(v: list[float]) -> Cut:
    """The cut of numbers made by :func:`cut_values`."""
    return Cut(
        v[0],
        round(v[1]),
        v[2],
        None if math.isnan(v[3]) else v[3],
        bool(v[4]),
        v[5],
        v[6],
        v[7],
        v[8],
        v[9],
        v[10],
        v[11],
    )


class KnifeDrum:
    """The knife drum's blades in the web, and every cut, from the physics.

    Blade k (``D_cut_angles[k]`` the drum angle at which it points straight down) has its tip
    on the radius ``r_k = r + e·cos(α_k − φ)`` (``D_tip_radius``; the drum's runout
    ``D_runout`` = e, φ: eccentricity of the tip circle and its angle on the drum). Its depth
    below the web's top is ``δ = h_top − z_tip``, from the drum angle. While δ > 0 the blade is in
    the web:

    - while it goes down through the web (0 < δ < thickness, δ growing) the web resists with the
      cutting force ``F_c = D_cut_force·width`` against the tip's motion into it (the torque
      ``F_c·∂z_tip/∂D`` on the drum; the anvil takes the web's side);
    - it grips the web along the line: a spring-damper between tip and web (``D_grip`` = μ,
      stiffness, damping) that slips above μ·F_c; its force acts on the web and, through the
      tip's lever, on the drum: a blade faster or slower than the web drags both.

    A cut is made when the tip reaches the web's underside (δ ≥ thickness: the blade went
    through); a pass that leaves the web before is a miss (``misses``; the piece goes on). Per
    cut the recorder keeps the material coordinate under the tip, the piece length, the largest
    speed mismatch and drag while in the web, the drum's peak torque and the motor's torque and
    current since the previous cut (:class:`Cut`).

    ``blades`` (1 or 2) may change at rest; ``ideal()`` removes the drum's runout.

    The drive's cutting-force feed-forward (``feed_forward``, the force it is told the web
    resists with [N]; 0: off, the default): a torque feed-forward input of the amplifier, as a
    servo drive takes one known from the process. From its own angle, 1 ms ahead along its
    speed (its current loop's lag), and the nominal blade (no runout) it adds
    ``feed_forward·r·sin β`` while a tip goes down through the web, through the current loop's
    1 ms lag, within the amplifier's torque limit (:attr:`feed_torque`).

    Args:
        model, data: the compiled model and its data (positions current).
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.prefix = prefix
        self.model = model
        self.radius = float(numeric(model, f"{prefix}D_tip_radius", 1, 0.0)[0])
        """Nominal tip radius r [m]."""
        self.cut_angles = tuple(float(a) for a in numeric(model, f"{prefix}D_cut_angles", 2))
        """Drum angle at which each blade points straight down [rad]."""
        runout, phase = numeric(model, f"{prefix}D_runout", 2, -1.0, 1.0)
        self.runout, self.runout_phase = float(runout), float(phase)
        """Eccentricity of the tip circle [m] and its angle on the drum [rad]."""
        self.thickness, self.width = (float(v) for v in numeric(model, f"{prefix}M_web", 2, 0.0))
        """Web thickness and width [m]."""
        self.cut_force = float(numeric(model, f"{prefix}D_cut_force", 1, 0.0)[0]) * self.width
        """Force the web resists the blade's way through it with [N]."""
        mu, stiffness, damping = numeric(model, f"{prefix}D_grip", 3, 0.0)
        self.mu, self.stiffness, self.damping = float(mu), float(stiffness), float(damping)
        ratio, efficiency = numeric(model, f"{prefix}D_gear", 2, 0.0)
        self.ratio, self.efficiency = float(ratio), min(1.0, float(efficiency))
        """Gearbox ratio (motor turns per drum turn) and efficiency [-]."""
        kt, rated, peak, rated_i, peak_i = numeric(model, f"{prefix}D_motor", 5, 0.0)
        self.kt = float(kt)
        """Motor torque constant [N·m/A rms]."""
        self.rated_torque, self.peak_torque = float(rated), float(peak)
        """The motor's catalogue torques [N·m]."""
        self.rated_current, self.peak_current = float(rated_i), float(peak_i)
        """The motor's catalogue currents [A rms]."""
        drum, web = model.joint(f"{prefix}D"), model.joint(f"{prefix}M")
        self._d, self._d_dof = int(drum.qposadr[0]), int(drum.dofadr[0])
        self._m, self._m_dof = int(web.qposadr[0]), int(web.dofadr[0])
        self._amp = int(model.actuator(f"{prefix}D_amp").id)
        self.torque_limit = float(model.actuator_forcerange[self._amp][1])
        """The amplifier's torque limit at the drum [N·m]."""
        self.lag = float(model.actuator_dynprm[self._amp][0])
        """The amplifier's current-loop lag [s]."""
        self.feed_forward = 0.0
        """The cutting force the drive's torque feed-forward is set for [N] (0: off)."""
        self.feed_torque = 0.0
        """The feed-forward torque the amplifier adds now, at the drum [N·m]."""
        self._qpos: Any = memoryview(data.qpos)
        self._qvel: Any = memoryview(data.qvel)
        self._force: Any = memoryview(data.qfrc_applied)
        self._actuator: Any = memoryview(data.actuator_force)
        scratch = mujoco.MjData(model)  # kinematics of the current positions
        scratch.qpos[:] = data.qpos
        mujoco.mj_kinematics(model, scratch)
        web_geom = model.geom(f"{prefix}web_geom").id
        top = float(scratch.geom_xpos[web_geom][2] + model.geom_size[web_geom][2])
        axis = scratch.xanchor[drum.id]
        self.height = float(axis[2]) - top
        """Drum axis above the web's top [m]."""
        m = float(data.qpos[self._m])
        self.web_offset = float(scratch.xpos[model.body(f"{prefix}web").id][0]) - m - float(axis[0])
        """Material coordinate of the point under the drum axis minus M [m] (a constant)."""
        self._blade_geoms = [model.geom(f"{prefix}blade_{k + 1}").id for k in range(2)]
        self._blade_rgba = [model.geom_rgba[g].copy() for g in self._blade_geoms]
        self._blades = 2
        self.blades = round(float(numeric(model, f"{prefix}D_blades", 1, 0.0, 2.0)[0]))
        self.cuts: list[Cut] = []
        """Every cut, in order."""
        self.misses: list[Cut] = []
        """Every blade pass that did not go through the web."""
        self.current: Cut | None = None
        """The blade pass in progress (a tip in the web)."""
        self.engaged = False
        self.anchor = 0.0
        """Tip minus web travel along the line at which the grip spring is relaxed [m]."""
        self.deepest = 0.0
        self.drag = 0.0
        """Force of the blade on the web along the line [N] (+ = downstream)."""
        self.peak = 0.0
        """Largest |drum torque| since the last cut [N·m]."""
        self._square = 0.0
        self._count = 0

    # ------------------------------------------------------------------ configuration
    @property
    def blades(self) -> int:
        """Blades fitted: 1 (blade 1) or 2 (blades 1 and 2, 180° apart)."""
        return self._blades

    @blades.setter
    def blades(self, count: int) -> None:
        if count not in (1, 2):
            raise ValueError(
                f"rotary cutter: {count!r} blades fitted; the drum takes 1 or 2 (numeric "
                f"{self.prefix}D_blades)"
            )
        self._blades = count
        for k, g in enumerate(self._blade_geoms):
            rgba = self._blade_rgba[k].copy()
            if k >= count:
                rgba[3] = 0.0  # not fitted: not drawn
            self.model.geom_rgba[g] = rgba

    @property
    def pitch(self) -> float:
        """Tip circumference per blade [m]: the piece in geared mode (tip speed = web speed)."""
        return 2.0 * math.pi * self.radius / self._blades

    def ideal(self) -> None:
        """No runout: every blade's tip on the nominal radius."""
        self.runout = 0.0

    def tip_radius(self, k: int) -> float:
        """Tip radius of blade ``k`` (0 or 1) with the runout [m]."""
        alpha = -0.5 * math.pi - self.cut_angles[k]  # its angle on the drum
        return self.radius + self.runout * math.cos(alpha - self.runout_phase)

    # ------------------------------------------------------------------ physics
    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """The blades in the web for the coming step: forces, cuts."""
        qpos, qvel = self._qpos, self._qvel
        angle: float = qpos[self._d]
        rate: float = qvel[self._d_dof]
        amplifier: float = self._actuator[self._amp]
        if self.feed_forward or self.feed_torque:
            self._feed(angle, rate, amplifier, float(model.opt.timestep))
        torque = amplifier + self.feed_torque
        self.peak = max(self.peak, abs(torque))
        self._square += torque * torque
        self._count += 1
        self._force[self._d_dof] = self.feed_torque
        reach = self.height / (self.radius + abs(self.runout))  # cos β where a tip may touch
        blade, beta, c = -1, 0.0, 0.0
        for k in range(self._blades):
            beta = _wrap(angle - self.cut_angles[k])  # 0: pointing down
            c = math.cos(beta)
            if c > reach:
                blade = k
                break
        if blade < 0:
            if self.engaged:
                self._leave(float(data.time))
            return
        r = self.tip_radius(blade)
        s = math.sin(beta)
        depth = r * c - self.height
        if depth <= 0.0:
            if self.engaged:
                self._leave(float(data.time))
            return
        t = float(data.time)
        web: float = qpos[self._m]
        v_web: float = qvel[self._m_dof]
        x_tip = r * s  # along the line from the axis
        v_tip = r * c * rate
        relative = x_tip - web
        if not self.engaged:
            self.engaged, self.anchor, self.deepest = True, relative, 0.0
            self.current = Cut(time=t, blade=blade + 1)
        cut = self.current
        assert cut is not None
        torque_on_drum = 0.0
        if depth < self.thickness and depth > self.deepest and not cut.through:
            # going down through the web: the cutting force against the tip's way (up on it)
            torque_on_drum += self.cut_force * r * s  # ∂z_tip/∂D = r·sin β
        limit = self.mu * self.cut_force
        drag = self.stiffness * (relative - self.anchor) + self.damping * (v_tip - v_web)
        if abs(drag) > limit:  # the blade slips on the web: the spring stays at the limit
            drag = math.copysign(limit, drag)
            self.anchor = relative - drag / self.stiffness
        self.drag = drag
        torque_on_drum -= drag * r * c  # ∂x_tip/∂D = r·cos β
        self._force[self._m_dof] = drag
        self._force[self._d_dof] = torque_on_drum + self.feed_torque
        self.deepest = max(self.deepest, depth)
        cut.depth = 1000.0 * self.deepest
        if v_web:
            cut.mismatch = max(cut.mismatch, abs(v_tip - v_web) / abs(v_web))
        cut.drag = max(cut.drag, abs(drag))
        if not cut.through and depth >= self.thickness:
            self._through(cut, t, web - x_tip)

    def _feed(self, angle: float, rate: float, amplifier: float, dt: float) -> None:
        """The drive's cutting-force feed-forward for the coming step (:attr:`feed_torque`):
        its target from the angle a lag ahead, reached through the current loop's lag."""
        ahead = angle + rate * self.lag
        target = 0.0
        for k in range(self._blades):
            beta = _wrap(ahead - self.cut_angles[k])
            depth = self.radius * math.cos(beta) - self.height
            if 0.0 < depth < self.thickness and beta * rate < 0.0:  # on its way down
                target = -self.feed_forward * self.radius * math.sin(beta)
        lag = self.lag
        follow = 1.0 - math.exp(-dt / lag) if lag > 0.0 else 1.0
        torque = self.feed_torque + follow * (target - self.feed_torque)
        limit = self.torque_limit
        self.feed_torque = max(-limit - amplifier, min(limit - amplifier, torque))

    def _through(self, cut: Cut, t: float, travel: float) -> None:
        """The blade went through the web: a cut at web travel minus tip ``travel`` [m]."""
        cut.through, cut.time = True, t
        cut.position = 1000.0 * (self.web_offset + travel)
        if self.cuts:
            cut.length = cut.position - self.cuts[-1].position
        cut.torque = self.peak
        cut.motor_torque = self.peak / (self.ratio * self.efficiency)
        cut.current = cut.motor_torque / self.kt
        if self._count:
            rms = math.sqrt(self._square / self._count)
            cut.rms_current = rms / (self.ratio * self.efficiency) / self.kt
        self.peak, self._square, self._count = 0.0, 0.0, 0
        self.cuts.append(cut)

    def _leave(self, t: float) -> None:
        """The tip left the web: forces off; a pass that did not go through is a miss."""
        self.engaged, self.drag = False, 0.0
        self._force[self._m_dof] = 0.0
        self._force[self._d_dof] = self.feed_torque
        cut = self.current
        self.current = None
        if cut is not None and not cut.through:
            cut.time = t
            self.misses.append(cut)

    # ------------------------------------------------------------------ readings
    @property
    def last_piece(self) -> float:
        """Length of the last piece [mm] (NaN before the second cut)."""
        last = self.cuts[-1].length if self.cuts else None
        return math.nan if last is None else last

    def get_state(self) -> npt.NDArray[np.float64]:
        """Configuration, the pass in progress and every cut and miss, flat."""
        current = [] if self.current is None else cut_values(self.current)
        head = [
            float(self._blades),
            self.runout,
            self.runout_phase,
            float(self.engaged),
            self.anchor,
            self.deepest,
            self.peak,
            self._square,
            float(self._count),
            float(len(self.cuts)),
            float(len(self.misses)),
            float(self.current is not None),
            self.feed_forward,
            self.feed_torque,
        ]
        rows = [x for c in [*self.cuts, *self.misses] for x in cut_values(c)]
        return np.array([*head, *current, *rows])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        """Return to a state taken with :meth:`get_state`."""
        v = [float(x) for x in state]
        self.blades = round(v[0])
        self.runout, self.runout_phase = v[1], v[2]
        self.engaged, self.anchor, self.deepest, self.peak = bool(v[3]), v[4], v[5], v[6]
        self._square, self._count = v[7], round(v[8])
        cuts, misses, has_current = round(v[9]), round(v[10]), bool(v[11])
        self.feed_forward, self.feed_torque = v[12], v[13]
        i = 14
        self.current = None
        if has_current:
            self.current = cut_of(v[i : i + CUT_FIELDS])
            i += CUT_FIELDS
        rows = [cut_of(v[j : j + CUT_FIELDS]) for j in range(i, len(v), CUT_FIELDS)]
        self.cuts, self.misses = rows[:cuts], rows[cuts : cuts + misses]
        self.drag = 0.0

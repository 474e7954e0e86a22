"""Valve-controlled hydraulic cylinder: valve, cylinder and oil columns in plain floats.

MuJoCo has no hydraulic actuator. :class:`ValveCylinder` holds the whole hydraulic model in plain
floats (SI units, pressures in Pa gauge):

- **Valve**: a 4/3 servo or proportional valve. The ±10 V command (after an optional hysteresis,
  a play of ``hysteresis`` of the spool stroke) drives the spool ``x`` (−1 … +1 of its stroke)
  through second-order dynamics ``ẍ = ω²·(u/10 − x) − 2ζω·ẋ``, integrated exactly for a command
  held over the step, the spool stopped at its ends. Positive ``x`` opens P→A and B→T (the
  cylinder extends, the axis' positive direction), negative ``x`` opens P→B and A→T. An edge
  opens ``max(|x| − overlap, 0)`` plus its clearance leakage ``leakage``; its flow is
  ``Q = Q_N · opening · root(Δp/Δp_N)`` (rated per edge: ``Q_N`` at ``Δp_N`` = 35 bar), with the
  sign-safe root ``root(r) = r/(r² + r_lam²)^¼``: ``sign(r)·√|r|`` for ``|Δp|`` well above the
  laminar transition ``Δp_lam``, linear (laminar) below it, smooth and finite in slope at 0.
- **Cylinder**: differential, areas ``A_A = π/4·D²`` (piston) and ``A_B = A_A − π/4·d²``
  (annulus); chamber volumes ``V_A = V0_A + A_A·s`` and ``V_B = V0_B + A_B·(stroke − s)``, ``s``
  the extension, the dead volumes ``V0`` (hoses, valve, cylinder ends) never zero.
- **Chambers**: ``dp/dt = β/V·(Q_valve − Q_relief ∓ A·v ∓ Q_internal)``, ``β`` the effective
  bulk modulus; internal leakage across the piston ``Q_internal = C_i·(p_A − p_B)``; a line
  relief (anti-shock) valve on each cylinder port opens at its setting ``p_relief`` and passes
  its rated flow ``Q_r`` at ``p_relief + Δp_o`` (its pressure override), a linear
  characteristic ``Q_relief = Q_r/Δp_o·(p − p_relief)``; a chamber cannot fall below tank
  pressure (it cavitates and refills through the anti-cavitation check valves of the same
  cartridges). The load-holding valves, closed while the drive is disabled, shut both cylinder
  ports leak-free between the servo valve and the line relief valves: the valve's clearance
  flow at 0 V then reaches neither chamber.
- **Force** on the piston ``F = p_A·A_A − p_B·A_B`` (+ = extending); seal friction (Coulomb)
  ``F_c = F_0 + f_p·(p_A·A_A + p_B·A_B)`` grows with the pressures on the seals.

**Integration.** Per physics step ``dt``: the spool first (exact), then each chamber with the
backward (implicit) Euler method, solved by a safeguarded Newton iteration on the scalar,
strictly increasing residual ``p − p_n − dt·β/V·Q_net(p)``. Implicit, because a chamber pressed
solid builds 200 bar in about a millisecond: its pressure equation is stiff (eigenvalue
``β/V·∂Q/∂p`` of some 10⁴ 1/s against a step of 5·10⁻⁴ s), and the relief valve's characteristic is
stiffer still; backward Euler is stable for any stiffness and reaches the steady pressure in
one step where an explicit step would overshoot. The piston velocity and the chamber volumes are
taken at the start of the step (the mechanics then integrates with the new force: a symplectic
splitting, stable for ``ω_h·dt < 2``; here ``ω_h·dt`` ≤ 0.7). The internal leakage uses the
pressures of the start of the step (its time constant is seconds).

Everything that evolves is the state (:meth:`ValveCylinder.get_state`), so a reset or replay is
bit-identical. The MuJoCo device that runs it is :mod:`.devices`, a simulated hydraulic axis
for unit tests :mod:`.hydraulic_axis`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from mcl.errors import check_finite

BAR = 1.0e5
"""One bar [Pa]."""
LPM = 1.0e-3 / 60.0
"""One litre per minute [m³/s]."""

__all__ = [
    "BAR",
    "LPM",
    "Cylinder",
    "Supply",
    "Valve",
    "ValveCylinder",
    "natural_frequency",
    "steady_state",
]


@dataclass(frozen=True)
class Valve:
    """A 4/3 servo or proportional valve (each of the four control edges rated alike).

    Attributes:
        rated_flow: flow of one fully open edge at ``rated_dp`` [m³/s].
        rated_dp: pressure drop per edge of the rating [Pa] (35 bar).
        frequency: natural frequency of the spool dynamics [Hz].
        damping: damping ratio of the spool dynamics (0 < ζ < 1).
        overlap: spool overlap (deadband) as a fraction of the spool stroke [-] (0 = zero lap).
        hysteresis: full width of the command's play as a fraction of the stroke [-].
        leakage: clearance of each edge as an equivalent opening [-] (flow at 0 V).
        laminar_dp: pressure drop below which an edge's flow turns laminar [Pa].
    """

    rated_flow: float = 40.0 * LPM
    rated_dp: float = 35.0 * BAR
    frequency: float = 60.0
    damping: float = 0.7
    overlap: float = 0.0
    hysteresis: float = 0.0
    leakage: float = 0.0
    laminar_dp: float = 0.2 * BAR

    def __post_init__(self) -> None:
        check_finite(self, ("rated_flow", "rated_dp", "frequency", "laminar_dp"), True)
        if not 0.0 < self.damping < 1.0:
            raise ValueError(f"Valve.damping must be in (0, 1), got {self.damping!r}")
        for name in ("overlap", "hysteresis", "leakage"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0.0 <= value < 0.5):
                raise ValueError(f"Valve.{name} must be in [0, 0.5), got {value!r}")


@dataclass(frozen=True)
class Cylinder:
    """A differential cylinder.

    Attributes:
        bore: piston diameter D [m].
        rod: rod diameter d [m].
        stroke: stroke [m].
        dead_volume_a, dead_volume_b: oil volume of each side at its end of the stroke
            (hoses, valve, cylinder end) [m³].
        coulomb: seal friction without pressure [N].
        pressure_friction: seal friction per newton of hydraulic force on the seals [-].
        internal_leakage: leakage across the piston per pressure difference [m³/(s·Pa)].
    """

    bore: float = 0.080
    rod: float = 0.056
    stroke: float = 0.300
    dead_volume_a: float = 1.0e-4
    dead_volume_b: float = 1.0e-4
    coulomb: float = 250.0
    pressure_friction: float = 0.005
    internal_leakage: float = 0.0

    def __post_init__(self) -> None:
        check_finite(self, ("bore", "stroke", "dead_volume_a", "dead_volume_b"), True)
        if not 0.0 <= self.rod < self.bore:
            raise ValueError(f"Cylinder.rod must be in [0, bore), got {self.rod!r}")
        check_finite(self, ("coulomb", "pressure_friction", "internal_leakage"), False)

    @property
    def area_a(self) -> float:
        """Piston area A_A [m²]."""
        return math.pi / 4.0 * self.bore * self.bore

    @property
    def area_b(self) -> float:
        """Annulus area A_B [m²]."""
        return math.pi / 4.0 * (self.bore * self.bore - self.rod * self.rod)


@dataclass(frozen=True)
class Supply:
    """Supply, tank, the line relief valves on the cylinder ports, and the oil.

    Attributes:
        supply: constant supply pressure (pump with accumulator) [Pa].
        tank: tank pressure [Pa].
        relief: setting (cracking pressure) of the line relief valve on each port [Pa].
        relief_override: its pressure override: the rise above the setting at its rated flow
            [Pa]; a chamber stays below ``relief + relief_override`` while the valve passes at
            most ``relief_flow``.
        relief_flow: its rated flow [m³/s].
        bulk_modulus: effective bulk modulus β of the oil with hoses and air [Pa].
    """

    supply: float = 200.0 * BAR
    tank: float = 0.0
    relief: float = 220.0 * BAR
    relief_override: float = 22.0 * BAR
    relief_flow: float = 120.0 * LPM
    bulk_modulus: float = 1.2e9

    def __post_init__(self) -> None:
        if not (math.isfinite(self.tank) and self.tank >= 0.0):
            raise ValueError(f"Supply.tank must be finite and >= 0, got {self.tank!r}")
        if not (math.isfinite(self.supply) and self.supply > self.tank):
            raise ValueError(f"Supply.supply must be above the tank pressure, got {self.supply!r}")
        if not (math.isfinite(self.relief) and self.relief > self.tank):
            raise ValueError(f"Supply.relief must be above the tank pressure, got {self.relief!r}")
        check_finite(self, ("relief_override", "relief_flow", "bulk_modulus"), True)

    @property
    def relief_gain(self) -> float:
        """Relief flow per pressure above the setting [m³/(s·Pa)]."""
        return self.relief_flow / self.relief_override

    @property
    def relief_limit(self) -> float:
        """The highest chamber pressure while a relief valve passes its rated flow [Pa]."""
        return self.relief + self.relief_override


def natural_frequency(cylinder: Cylinder, supply: Supply, extension: float, mass: float) -> float:
    """Hydraulic natural frequency of a mass on the two oil columns, valve closed [Hz]:
    ``ω_h = √(β/m · (A_A²/V_A + A_B²/V_B))``.

    Args:
        cylinder, supply: the cylinder and the oil.
        extension: piston extension s [m].
        mass: moving mass [kg].
    """
    v_a = cylinder.dead_volume_a + cylinder.area_a * extension
    v_b = cylinder.dead_volume_b + cylinder.area_b * (cylinder.stroke - extension)
    stiffness = supply.bulk_modulus * (cylinder.area_a**2 / v_a + cylinder.area_b**2 / v_b)
    return math.sqrt(stiffness / mass) / (2.0 * math.pi)


class ValveCylinder:
    """The hydraulic state of one valve and cylinder, integrated one physics step at a time.

    Args:
        valve, cylinder, supply: the hydraulic data.
        dt: the step [s].
    """

    def __init__(self, valve: Valve, cylinder: Cylinder, supply: Supply, dt: float) -> None:
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"step must be a finite number > 0 s, got {dt!r}")
        self.valve, self.cylinder, self.supply, self.dt = valve, cylinder, supply, dt
        self.area_a = cylinder.area_a
        self.area_b = cylinder.area_b
        self.command = 0.0
        """Valve command [V] (0 while the drive is disabled)."""
        self.hold = True
        """The load-holding valves shut both cylinder ports (drive disabled)."""
        self.spool = 0.0
        """Spool position x [-], −1 … +1 of its stroke."""
        self.spool_rate = 0.0
        """Spool velocity [1/s]."""
        self.play = 0.0
        """Output of the hysteresis play: the command the spool follows [-]."""
        self.p_a = 0.0
        """Pressure in chamber A [Pa]."""
        self.p_b = 0.0
        """Pressure in chamber B [Pa]."""
        w = 2.0 * math.pi * valve.frequency
        z = valve.damping
        wd = w * math.sqrt(1.0 - z * z)
        e = math.exp(-z * w * dt)
        c, s = math.cos(wd * dt), math.sin(wd * dt)
        self._phi = (
            e * (c + z * w / wd * s),
            e * s / wd,
            -e * w * w / wd * s,
            e * (c - z * w / wd * s),
        )
        self._qn = valve.rated_flow
        self._inv_dpn = 1.0 / valve.rated_dp
        self._lam2 = (valve.laminar_dp / valve.rated_dp) ** 2
        self._kr = supply.relief_gain
        self.iterations = 0
        """Newton iterations of the last step (both chambers)."""

    # ------------------------------------------------------------------ flows
    def root(self, dp: float) -> float:
        """The sign-safe root of the flow law: ``root(Δp/Δp_N)`` [-]."""
        r = dp * self._inv_dpn
        return r / math.sqrt(math.sqrt(r * r + self._lam2))

    def _root_slope(self, dp: float) -> float:
        """d root(Δp/Δp_N) / dΔp [1/Pa]."""
        r = dp * self._inv_dpn
        s = r * r + self._lam2
        return (0.5 * r * r + self._lam2) / (s * math.sqrt(math.sqrt(s))) * self._inv_dpn

    def openings(self) -> tuple[float, float, float, float]:
        """Equivalent openings of the edges P→A, A→T, P→B, B→T [-] at the current spool."""
        valve = self.valve
        x, lap, leak = self.spool, valve.overlap, valve.leakage
        pos = x - lap if x > lap else 0.0
        neg = -x - lap if -x > lap else 0.0
        return pos + leak, neg + leak, neg + leak, pos + leak

    def flow_a(self, p: float) -> float:
        """Valve and relief flow into chamber A at pressure ``p`` [m³/s] (current spool and
        load-holding valves)."""
        pa_in, at_out, _, _ = self.openings()
        if self.hold:
            return self._valve_flow(p, 0.0, 0.0)
        return self._valve_flow(p, pa_in, at_out)

    def flow_b(self, p: float) -> float:
        """Valve and relief flow into chamber B at pressure ``p`` [m³/s] (current spool and
        load-holding valves)."""
        _, _, pb_in, bt_out = self.openings()
        if self.hold:
            return self._valve_flow(p, 0.0, 0.0)
        return self._valve_flow(p, pb_in, bt_out)

    def _valve_flow(self, p: float, inlet: float, outlet: float) -> float:
        supply = self.supply
        q = self._qn * (inlet * self.root(supply.supply - p) - outlet * self.root(p - supply.tank))
        if p > supply.relief:
            q -= self._kr * (p - supply.relief)
        return q

    # ------------------------------------------------------------------ integration
    def force(self) -> float:
        """Hydraulic force on the piston, + = extending [N]."""
        return self.p_a * self.area_a - self.p_b * self.area_b

    def friction(self) -> float:
        """Seal friction at the current pressures (Coulomb, magnitude) [N]."""
        c = self.cylinder
        return c.coulomb + c.pressure_friction * (self.p_a * self.area_a + self.p_b * self.area_b)

    def volumes(self, extension: float) -> tuple[float, float]:
        """Chamber volumes V_A, V_B at an extension [m³] (the dead volume at least)."""
        c = self.cylinder
        s = min(max(extension, 0.0), c.stroke)
        return c.dead_volume_a + self.area_a * s, c.dead_volume_b + self.area_b * (c.stroke - s)

    def step(self, extension: float, velocity: float) -> float:
        """Integrate valve and chambers over one step; returns the new hydraulic force [N].

        Args:
            extension: piston extension s at the start of the step [m].
            velocity: extension velocity at the start of the step [m/s].
        """
        self._spool_step()
        v_a, v_b = self.volumes(extension)
        beta_dt = self.supply.bulk_modulus * self.dt
        leak = self.cylinder.internal_leakage * (self.p_a - self.p_b)
        pa_in, at_out, pb_in, bt_out = self.openings()
        if self.hold:
            pa_in = at_out = pb_in = bt_out = 0.0
        self.iterations = 0
        p_a = self._chamber(self.p_a, beta_dt / v_a, pa_in, at_out, -self.area_a * velocity - leak)
        p_b = self._chamber(self.p_b, beta_dt / v_b, pb_in, bt_out, self.area_b * velocity + leak)
        self.p_a, self.p_b = p_a, p_b
        return p_a * self.area_a - p_b * self.area_b

    def _spool_step(self) -> None:
        valve = self.valve
        u = 0.1 * self.command
        h = 0.5 * valve.hysteresis
        play = self.play
        if u > play + h:
            play = u - h
        elif u < play - h:
            play = u + h
        self.play = play
        d = self.spool - play
        r = self.spool_rate
        f11, f12, f21, f22 = self._phi
        x = play + f11 * d + f12 * r
        r = f21 * d + f22 * r
        if x > 1.0:
            x, r = 1.0, 0.0
        elif x < -1.0:
            x, r = -1.0, 0.0
        self.spool, self.spool_rate = x, r

    def _chamber(self, p0: float, k: float, inlet: float, outlet: float, q_ext: float) -> float:
        """Backward Euler for one chamber: the root of ``g(p) = p − p0 − k·(Q(p) + q_ext)``.

        ``g`` increases strictly (the inflow falls and the outflow and relief flow rise with
        ``p``), so the root is unique; Newton steps that leave the bracket are replaced by
        bisection. A root below tank pressure means cavitation: the tank pressure.
        """
        supply = self.supply
        ps, pt, relief, kr = supply.supply, supply.tank, supply.relief, self._kr
        inv, c = self._inv_dpn, self._lam2
        a_in, a_out = self._qn * inlet, self._qn * outlet
        lo = pt
        r = (ps - pt) * inv
        hi = max(p0, pt) + k * (a_in * r / math.sqrt(math.sqrt(r * r + c)) + max(q_ext, 0.0)) + 1.0
        p = min(max(p0, lo), hi)
        iterations = 0
        for _ in range(60):
            iterations += 1
            r1 = (ps - p) * inv
            s1 = r1 * r1 + c
            f1 = math.sqrt(math.sqrt(s1))
            r2 = (p - pt) * inv
            s2 = r2 * r2 + c
            f2 = math.sqrt(math.sqrt(s2))
            q = a_in * r1 / f1 - a_out * r2 / f2
            slope = (
                a_in * (0.5 * r1 * r1 + c) / (s1 * f1) + a_out * (0.5 * r2 * r2 + c) / (s2 * f2)
            ) * inv
            if p > relief:
                q -= kr * (p - relief)
                slope += kr
            g = p - p0 - k * (q + q_ext)
            if g >= 0.0:
                if p <= pt:
                    p = pt  # the chamber cavitates at tank pressure
                    break
                hi = p
            else:
                lo = p
            step = g / (1.0 + k * slope)
            if -1.0e-3 < step < 1.0e-3:
                p -= step
                break
            p -= step
            if p <= lo or p >= hi:
                p = pt if p <= lo == pt else 0.5 * (lo + hi)
                if hi - lo < 1.0e-3:
                    break
        self.iterations += iterations
        return p if p > pt else pt

    # ------------------------------------------------------------------ state
    def get_state(self) -> list[float]:
        """Everything that evolves: command, hold, spool, spool rate, play, p_A, p_B."""
        return [
            self.command,
            1.0 if self.hold else 0.0,
            self.spool,
            self.spool_rate,
            self.play,
            self.p_a,
            self.p_b,
        ]

    def set_state(self, state: list[float]) -> None:
        """Restore a state taken with :meth:`get_state`."""
        self.command = state[0]
        self.hold = state[1] != 0.0
        self.spool, self.spool_rate, self.play, self.p_a, self.p_b = state[2:7]

    def holding_pressures(self, load: float) -> None:
        """Set the pressures that hold ``load`` [N] (+ = pulling the piston out) at rest with
        the other chamber at tank pressure (a ram hanging on its oil)."""
        tank = self.supply.tank
        if load > 0.0:
            self.p_a, self.p_b = tank, tank + load / self.area_b if self.area_b > 0.0 else tank
        else:
            self.p_a, self.p_b = tank - load / self.area_a, tank


def steady_state(
    hydraulics: ValveCylinder, spool: float, load: float, extension: float = 0.0
) -> tuple[float, float, float]:
    """The flow law's steady state: a spool held at ``spool`` moving a piston against a constant
    ``load`` [N] (+ = pulling it out) and its seal friction. Returns ``(velocity [m/s], p_A,
    p_B [Pa])``; velocity 0 where the friction holds the piston.

    Solved by bisection on the velocity, the two chamber pressures by bisection of their flow
    balance (valve, relief and internal leakage, the load-holding valves open).
    """
    h = ValveCylinder(hydraulics.valve, hydraulics.cylinder, hydraulics.supply, hydraulics.dt)
    h.spool, h.hold = spool, False
    supply, cylinder = h.supply, h.cylinder
    ci = cylinder.internal_leakage
    top = max(supply.supply, supply.relief) * 2.0

    def pressures(v: float) -> tuple[float, float]:
        # flow balance of both chambers; the internal leakage couples them (fixed point)
        cell = [0.5 * supply.supply, 0.5 * supply.supply]  # p_A, p_B

        def into_a(p: float) -> float:
            return h.flow_a(p) - ci * (p - cell[1]) - h.area_a * v

        def into_b(p: float) -> float:
            return h.flow_b(p) + ci * (cell[0] - p) + h.area_b * v

        for _ in range(50):
            previous = cell[0]
            cell[0] = _bisect(into_a, top)
            cell[1] = _bisect(into_b, top)
            if abs(cell[0] - previous) < 1.0e-3:
                break
        return cell[0], cell[1]

    def net(v: float, sign: float) -> float:
        p_a, p_b = pressures(v)
        h.p_a, h.p_b = p_a, p_b
        return p_a * h.area_a - p_b * h.area_b + load - sign * h.friction()

    vmax = 4.0 * h._qn * (1.0 + h.valve.leakage) * math.sqrt(top / h.valve.rated_dp) / h.area_b
    if net(0.0, 1.0) <= 0.0 <= net(0.0, -1.0):
        p_a, p_b = pressures(0.0)
        return 0.0, p_a, p_b
    if net(0.0, 1.0) > 0.0:
        lo, hi = 0.0, vmax
        sign = 1.0
    else:
        lo, hi = -vmax, 0.0
        sign = -1.0
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if net(mid, sign) > 0.0:
            lo = mid
        else:
            hi = mid
    v = 0.5 * (lo + hi)
    p_a, p_b = pressures(v)
    return v, p_a, p_b


def _bisect(flow: Callable[[float], float], top: float) -> float:
    """The pressure in [0, top] where a decreasing ``flow(p)`` crosses zero [Pa]."""
    lo, hi = 0.0, top
    if flow(lo) <= 0.0:
        return lo
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if flow(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)

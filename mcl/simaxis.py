"""Simulated axes in pure Python: the plant for unit tests and logic checks without physics.

A ±10 V velocity-mode servo amplifier (velocity loop with current-loop lag and force limit)
drives a moving mass with viscous and Coulomb friction, a constant load (gravity on a vertical
axis), an optional holding brake, stiff end stops, LIM±/REF switches at positions and an
incremental encoder with an index pulse per motor revolution. SI units inside; the encoder is the
boundary to the axis' user units.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from mcl.axis import Axis, AxisConfig
from mcl.encoder import IncrementalEncoder
from mcl.module import Module
from mcl.runtime import Machine, Runtime


@dataclass(frozen=True, slots=True)
class SimAxisParams:
    """Physical data of a simulated axis (SI units).

    Attributes:
        mass: moving mass incl. reflected motor and screw inertia [kg].
        vmax: velocity commanded by +10 V [m/s].
        amp_gain: velocity-loop gain of the amplifier [N/(m/s)].
        current_lag: current-loop time constant [s].
        force_limit: peak amplifier force [N].
        viscous: viscous friction [N·s/m].
        coulomb: Coulomb friction [N].
        load: constant external force, e.g. −m·g on a vertical axis [N].
        brake_force: holding force of the brake engaged while the drive is disabled [N]; 0 = none.
        stop_neg, stop_pos: hard stops [m].
        stop_stiffness: end-stop stiffness [N/m].
        lim_neg, lim_pos: LIM− actuated at or below ``lim_neg``, LIM+ at or above ``lim_pos`` [m].
        ref_low, ref_high: REF is actuated between these positions [m].
        lead: travel per motor revolution (one index pulse each) [m].
        resolution: travel per encoder count [m].
        start: position at power-up [m] (the encoder reads 0 there).
    """

    mass: float = 20.0
    vmax: float = 0.5
    amp_gain: float = 4000.0
    current_lag: float = 0.001
    force_limit: float = 2000.0
    viscous: float = 20.0
    coulomb: float = 15.0
    load: float = 0.0
    brake_force: float = 0.0
    stop_neg: float = -0.010
    stop_pos: float = 1.010
    stop_stiffness: float = 2.0e7
    lim_neg: float = -0.005
    lim_pos: float = 1.005
    ref_low: float = -math.inf
    ref_high: float = 0.100
    lead: float = 0.010
    resolution: float = 1.0e-6
    start: float = 0.0


@dataclass(slots=True)
class SimAxis:
    """One simulated axis; implements :class:`mcl.io.AxisIO`."""

    params: SimAxisParams = field(default_factory=SimAxisParams)
    x: float = 0.0
    """Position [m]."""
    v: float = 0.0
    """Velocity [m/s]."""
    force: float = 0.0
    """Amplifier force [N]."""
    volts: float = 0.0
    enabled: bool = False
    blocked_at: float = math.inf
    """An obstacle: the axis cannot pass this position in the positive direction [m]."""
    counts: int = 0
    index_count: int = 0
    index_seq: int = 0
    index: bool = False
    lim_pos: bool = False
    lim_neg: bool = False
    ref: bool = False
    tp: bool = False
    tp_count: int = 0
    tp_seq: int = 0
    analog: Sequence[float] = ()
    _encoder: IncrementalEncoder = field(init=False)

    def __post_init__(self) -> None:
        p = self.params
        self.x = p.start
        self._encoder = IncrementalEncoder(p.resolution, round(p.lead / p.resolution), p.start)
        self.sense()

    def write(self, volts: float, enable: bool) -> None:
        """Analog command [V] and drive enable (False: no force, brake engaged)."""
        self.volts = volts
        self.enabled = enable

    def step(self, dt: float) -> None:
        """Integrate over ``dt`` seconds (semi-implicit Euler, friction at velocity level)."""
        p = self.params
        v = self.v
        if self.enabled:
            f_cmd = p.amp_gain * (self.volts * 0.1 * p.vmax - v)
            if f_cmd > p.force_limit:
                f_cmd = p.force_limit
            elif f_cmd < -p.force_limit:
                f_cmd = -p.force_limit
        else:
            f_cmd = 0.0
        self.force += (f_cmd - self.force) * min(1.0, dt / p.current_lag)
        f = self.force + p.load - p.viscous * v
        x = self.x
        if x > p.stop_pos:
            f -= p.stop_stiffness * (x - p.stop_pos)
        elif x < p.stop_neg:
            f -= p.stop_stiffness * (x - p.stop_neg)
        v += f / p.mass * dt
        friction = p.coulomb + (0.0 if self.enabled else p.brake_force)
        dv = friction / p.mass * dt
        if v > dv:
            v -= dv
        elif v < -dv:
            v += dv
        else:
            v = 0.0
        x += v * dt
        if x > self.blocked_at:
            x, v = self.blocked_at, min(v, 0.0)
        self.x, self.v = x, v

    def sense(self) -> None:
        """Sample encoder and switches at the current position (the index latch stays exact)."""
        p, x = self.params, self.x
        enc = self._encoder
        enc.update(x)
        self.counts = enc.counts
        self.index = enc.index
        self.index_count = enc.index_count
        self.index_seq = enc.index_seq
        self.lim_pos = x >= p.lim_pos
        self.lim_neg = x <= p.lim_neg
        self.ref = p.ref_low <= x <= p.ref_high


class SimPlant:
    """Steps a set of simulated axes in lockstep; implements :class:`mcl.runtime.Plant`."""

    def __init__(self, axes: Sequence[SimAxis], timestep: float = 0.0005) -> None:
        """Args: axes: the simulated axes; timestep: integration step [s]."""
        if not timestep > 0.0:
            raise ValueError(f"timestep must be > 0 s, got {timestep}")
        self.axes = list(axes)
        self.timestep = timestep
        self.time = 0.0
        self._ticks = 0

    def step(self) -> None:
        """Advance every axis by one timestep."""
        dt = self.timestep
        for axis in self.axes:
            axis.step(dt)
        self._ticks += 1
        self.time = self._ticks * dt

    def sense(self) -> None:
        """Sample every axis' inputs."""
        for axis in self.axes:
            axis.sense()


class SimMachine(Machine):
    """Simulated axes wired to mcl axes (six to a module), with their lockstep runtime.

    The same surface as a MuJoCo scene: ``machine.axes["X"]``, ``machine.run(program, until,
    timeout)``, ``machine.time``.

    Args:
        axes: axis name → physical data of its simulated axis.
        config: machine data shared by the axes (resolution must match the simulated encoder).
        timestep: plant integration step [s].
        plc_period: PLC cycle [s].
    """

    def __init__(
        self,
        axes: dict[str, SimAxisParams] | None = None,
        config: AxisConfig | None = None,
        timestep: float = 0.0005,
        plc_period: float = 0.002,
    ) -> None:
        params = axes if axes is not None else {"X": SimAxisParams()}
        config = config if config is not None else AxisConfig()
        self.sims = {name: SimAxis(p) for name, p in params.items()}
        for name, p in params.items():
            if abs(p.resolution * 1000.0 - config.resolution) > 1e-12:
                raise ValueError(
                    f"axis {name!r}: AxisConfig.resolution {config.resolution} mm must equal the "
                    f"simulated encoder's {p.resolution * 1000.0} mm per count"
                )
        self.plant = SimPlant(list(self.sims.values()), timestep)
        self.axes = {name: Axis(sim, config, name) for name, sim in self.sims.items()}
        members = list(self.axes.values())
        self.modules = [
            Module(members[i : i + Module.MAX_AXES])
            for i in range(0, len(members), Module.MAX_AXES)
        ]
        """The axes in order, six to a servo module."""
        self.runtime = Runtime(self.plant, self.axes.values(), plc_period)

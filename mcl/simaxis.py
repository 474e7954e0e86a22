"""Simulated axes in pure Python: the plant for unit tests and logic checks without physics.

A ±10 V velocity-mode servo amplifier (velocity loop with current-loop lag and force limit)
drives a moving mass with viscous and Coulomb friction, a constant load (gravity on a vertical
axis), an optional holding brake, stiff end stops, LIM±/REF switches at positions and an
incremental encoder with an index pulse per motor revolution. SI units inside; the encoder is the
boundary to the axis' user units.
"""

from __future__ import annotations

__all__ = ["SimAxis", "SimAxisParams", "SimMachine", "SimPlant", "SimPlantState", "after_friction"]

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

from mcl.axis import Axis, AxisConfig
from mcl.channel import IDEAL, AxisChannel, Marks, Sensors
from mcl.module import Module
from mcl.runtime import Machine, Runtime


def after_friction(v: float, dv: float) -> float:
    """Velocity ``v`` [m/s] after Coulomb friction took up to ``dv`` [m/s] of it in one step;
    it stops at zero rather than reverse."""
    if v > dv:
        return v - dv
    if v < -dv:
        return v + dv
    return 0.0


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
        probe: marks on the axis' own position that trigger the touch probe (None: none).
        probe_delay: sensor delay of the touch probe [s].
        has_drive: False: an encoder-only axis (a measuring wheel); writes are ignored.
        digital_outputs: number of digital outputs a program may set.
        analog: voltages of the analog inputs (constant transducer readings) [V].
        sensors: the imperfections of its sensors and module (None: ideal ones,
            :data:`mcl.channel.IDEAL`: the simulated axis checks logic; ``mcl.Sensors()`` gives
            those of a real machine).
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
    probe: Marks | None = None
    probe_delay: float = 0.0
    has_drive: bool | int = True
    digital_outputs: int = 0
    analog: tuple[float, ...] = ()
    sensors: Sensors | None = None


class SimAxis(AxisChannel):
    """One simulated axis: the physics behind an :class:`~mcl.channel.AxisChannel`.

    Args:
        params: its physical data.
    """

    def __init__(self, params: SimAxisParams | None = None) -> None:
        p = self.params = params if params is not None else SimAxisParams()
        super().__init__(
            "sim",
            p.resolution,
            round(p.lead / p.resolution),
            p.start,
            probe=p.probe,
            probe_delay=p.probe_delay,
            has_drive=bool(p.has_drive),
            digital_outputs=p.digital_outputs,
            windows=((p.lim_pos, math.inf), (-math.inf, p.lim_neg), (p.ref_low, p.ref_high)),
            sensors=IDEAL if p.sensors is None else p.sensors,
        )
        self.x = p.start
        """Position [m]."""
        self.v = 0.0
        """Velocity [m/s]."""
        self.force = 0.0
        """Amplifier force [N]."""
        self.blocked_at = math.inf
        """An obstacle: the axis cannot pass this position in the positive direction [m]."""
        self.sense()

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
        friction = p.coulomb + (p.brake_force if self.brake else 0.0)
        v = after_friction(v, friction / p.mass * dt)
        x += v * dt
        if x > self.blocked_at:
            x, v = self.blocked_at, min(v, 0.0)
        self.x, self.v = x, v

    def sense(self, t: float | None = None) -> None:
        """Sample encoder, switches and probe at the current position and time ``t`` [s]."""
        p, x = self.params, self.x
        self.sample(self.t if t is None else t, x, x, x, x, analog=p.analog)

    @property
    def position(self) -> float:
        """True position now [m] (:attr:`x`)."""
        return self.x


@dataclass(frozen=True, slots=True)
class SimPlantState:
    """The physics of a :class:`SimPlant` at one instant.

    Attributes:
        ticks: timesteps integrated since the start.
        axes: per axis, in the plant's order: position [m], velocity [m/s], amplifier force
            [N] and the obstacle ``blocked_at`` [m].
    """

    ticks: int
    axes: tuple[tuple[float, float, float, float], ...]


class SimPlant:
    """Steps a set of simulated axes in lockstep; implements :class:`mcl.runtime.Plant`.

    The axes are given no drive: their physics reads the outputs of their own channel."""

    def __init__(self, axes: Sequence[SimAxis], timestep: float = 0.0005) -> None:
        """Args: axes: the simulated axes; timestep: integration step [s]."""
        if not timestep > 0.0:
            raise ValueError(f"timestep must be > 0 s, got {timestep}")
        self.axes = list(axes)
        self.timestep = timestep
        self.time = 0.0
        self._ticks = 0

    def step(self, n: int = 1) -> None:
        """Advance every axis by ``n`` timesteps."""
        dt = self.timestep
        for _ in range(n):
            for axis in self.axes:
                axis.step(dt)
        self._ticks += n
        self.time = self._ticks * dt

    def sense(self) -> None:
        """Sample every axis' inputs."""
        t = self.time
        for axis in self.axes:
            axis.sense(t)

    def identity(self) -> tuple[str, ...]:
        """What a state must match to be restored here: the timestep and every axis' physical
        data (but the power-up position, which the encoder's state keeps)."""
        params = (repr(replace(axis.params, start=0.0)) for axis in self.axes)
        return (f"timestep {self.timestep * 1e3:g} ms", *params)

    def get_state(self) -> SimPlantState:
        """The physics now (the axes' channels keep their own state)."""
        return SimPlantState(
            self._ticks, tuple((a.x, a.v, a.force, a.blocked_at) for a in self.axes)
        )

    def set_state(self, state: SimPlantState) -> None:
        """Return to a state taken with :meth:`get_state`.

        Raises:
            ValueError: the state is of a plant with another number of axes.
        """
        if len(state.axes) != len(self.axes):
            raise ValueError(
                f"the state has {len(state.axes)} simulated axes, this plant {len(self.axes)}"
            )
        for axis, (x, v, force, blocked_at) in zip(self.axes, state.axes, strict=True):
            axis.x, axis.v, axis.force, axis.blocked_at = x, v, force, blocked_at
        self._ticks = state.ticks
        self.time = state.ticks * self.timestep


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

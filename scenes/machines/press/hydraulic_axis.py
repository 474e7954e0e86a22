"""A simulated hydraulic axis for unit tests: :class:`HydraulicAxis`, the press's valve and
cylinder (:class:`.hydraulics.ValveCylinder`) moving a mass without a physics engine, and
:class:`HydraulicPlant`, which steps it."""

from __future__ import annotations

__all__ = ["HydraulicAxis", "HydraulicPlant", "ValveDrive"]

from mcl.channel import IDEAL, AxisChannel, Drive, Sensors
from mcl.simaxis import after_friction
from scenes.machines.press.hydraulics import BAR, ValveCylinder


class ValveDrive(Drive):
    """The axis' command goes to the valve; the brake is the load-holding valves."""

    def __init__(self, hydraulics: ValveCylinder) -> None:
        self.hydraulics = hydraulics

    def apply(self, volts: float, enabled: bool, brake: bool) -> None:
        h = self.hydraulics
        h.command = volts if enabled else 0.0
        h.hold = brake


class HydraulicAxis(AxisChannel):
    """A simulated hydraulic axis for unit tests: the same :class:`ValveCylinder` moving a mass
    (semi-implicit Euler, seal friction at velocity level, stiff end stops at 0 and the stroke),
    with pressure transducers on analog inputs 0 (A) and 1 (B) [V, 0–10 V for 0–250 bar].

    The position is the extension [m]; positive volts extend.

    Args:
        hydraulics: the valve and cylinder (its step is the axis' timestep).
        mass: moving mass [kg].
        load: constant external force, + = pulling the piston out (a hanging weight) [N].
        viscous: viscous friction [N·s/m].
        resolution: travel per encoder count [m].
        start: extension at power-up [m].
        sensors: sensor imperfections (default: ideal).
    """

    STOP_STIFFNESS = 5.0e8
    """End-stop stiffness [N/m] (a stiff contact, stable at the step for masses ≥ 50 kg)."""

    def __init__(
        self,
        hydraulics: ValveCylinder,
        mass: float,
        load: float = 0.0,
        viscous: float = 0.0,
        resolution: float = 5.0e-6,
        start: float = 0.0,
        sensors: Sensors | None = None,
    ) -> None:
        valve = ValveDrive(hydraulics)
        super().__init__(
            "hydraulic",
            resolution,
            10000,
            start,
            sensors=IDEAL if sensors is None else sensors,
            drive=valve,
        )
        self.hydraulics = hydraulics
        self.valve = valve
        self.mass, self.load, self.viscous = mass, load, viscous
        self.x = start
        """Extension [m]."""
        self.v = 0.0
        """Extension velocity [m/s]."""
        hydraulics.holding_pressures(load)
        self.full_scale = 250.0 * BAR
        self.sense()

    def drive(self, volts: float, enabled: bool, brake: bool) -> None:
        """Set the valve directly (what the module's outputs do through the axis' drive)."""
        self.valve.apply(volts, enabled, brake)

    def step(self) -> None:
        """Integrate one step of the hydraulics' timestep."""
        h = self.hydraulics
        dt = h.dt
        f = h.step(self.x, self.v) + self.load - self.viscous * self.v
        x = self.x
        stroke = h.cylinder.stroke
        if x < 0.0:
            f -= self.STOP_STIFFNESS * x
        elif x > stroke:
            f -= self.STOP_STIFFNESS * (x - stroke)
        v = after_friction(self.v + f / self.mass * dt, h.friction() / self.mass * dt)
        self.v = v
        self.x = x + v * dt

    def sense(self, t: float | None = None) -> None:
        """Sample encoder and pressures at time ``t`` [s]."""
        h = self.hydraulics
        scale = 10.0 / self.full_scale
        analog = (min(max(h.p_a * scale, 0.0), 10.0), min(max(h.p_b * scale, 0.0), 10.0))
        self.sample(self.t if t is None else t, self.x, self.x, self.x, self.x, analog=analog)


class HydraulicPlant:
    """Steps one :class:`HydraulicAxis`; implements :class:`mcl.runtime.Plant`."""

    def __init__(self, axis: HydraulicAxis) -> None:
        self.axis = axis
        self.timestep = axis.hydraulics.dt
        self._ticks = 0

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._ticks * self.timestep

    def step(self, n: int = 1) -> None:
        """``n`` steps."""
        for _ in range(n):
            self.axis.step()
        self._ticks += n

    def sense(self) -> None:
        """Sample the axis' inputs."""
        self.axis.sense(self.time)

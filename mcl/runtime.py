"""Lockstep runtime: physics steps, servo and PLC cycles on simulated time.

No wall clock: a scenario is deterministic and runs as fast as the CPU allows. Each period is an
integer multiple of the plant's timestep, checked at construction. At a PLC instant the program
runs first (FB calls queue commands). Then every servo cycle runs in phases, each over all axes
before the next (see :meth:`Runtime.run`): latch, sense, measure, set point, act, observe. Then
the plant integrates one servo period.
"""

from __future__ import annotations

__all__ = ["Machine", "MachineState", "Physics", "Plant", "Runtime", "ticks_per"]

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, Protocol

from mypy_extensions import mypyc_attr

from mcl.axis import Axis, AxisSnapshot
from mcl.channel import AxisChannel
from mcl.errors import ConditionTimeout, StateError
from mcl.faults import FaultLog, FaultLogState, Injectable


class Physics(Protocol):
    """What a runtime steps: simulated axes or a MuJoCo model."""

    timestep: float
    """Integration step [s]."""

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        ...

    def step(self, n: int = 1) -> None:
        """Advance the plant by ``n`` timesteps."""
        ...

    def sense(self) -> None:
        """Sample every axis' inputs for the servo cycle at the current instant."""
        ...


class Plant(Physics, Protocol):
    """The physics of a :class:`Machine`: what a runtime steps, with its saved state and
    identity (:class:`mcl.SimPlant`, the MuJoCo plant of ``scenes``). Each of its channels
    reports the true position of its axis (:attr:`mcl.channel.AxisChannel.position`)."""

    def identity(self) -> tuple[str, ...]:
        """What a saved state must match to be restored here (timestep, model, physical data),
        as texts."""
        ...

    def get_state(self) -> Any:
        """The physics now with everything the plant adds to it (drives, devices), as an
        immutable value that :meth:`set_state` restores any number of times."""
        ...

    def set_state(self, state: Any) -> None:
        """Return to a state taken with :meth:`get_state` of a plant of the same identity."""
        ...


def ticks_per(period: float, timestep: float, what: str) -> int:
    """How many timesteps make one ``period``; raises ValueError unless an integer multiple."""
    if not period > 0.0:
        raise ValueError(f"{what} must be > 0 s, got {period}")
    n = round(period / timestep)
    if n < 1 or abs(n * timestep - period) > 1e-9 * period:
        raise ValueError(
            f"{what} {period * 1e3:g} ms is not an integer multiple of the physics timestep "
            f"{timestep * 1e3:g} ms; use e.g. {max(n, 1) * timestep * 1e3:g} ms"
        )
    return n


class Runtime:
    """Runs a PLC program against axes on a plant, all in lockstep.

    Every servo cycle runs these phases, each over all axes before the next:

    1. latch: the module's output latch, where an axis' sensors delay the output by one cycle
       (``Sensors.output_delay`` 1): the command written in the last cycle reaches the drive;
    2. sense: the plant samples every input at this instant;
    3. measure: every axis reads its position and velocity;
    4. set point: every axis computes its model state (memoised per instant, so a slave may
       read its master's set point of the same instant in any declaration order);
    5. act: every axis supervises, regulates and writes its output (with no output delay it
       reaches the drive at once);
    6. observe: the observers (a trace) record the instant.

    Then the plant integrates one servo period.

    Args:
        plant: what integrates the physics.
        axes: the axes whose servo cycles run here; their ``servo_period`` must be a multiple
            of the plant timestep.
        plc_period: PLC cycle [s], an integer multiple of the servo period.
    """

    def __init__(self, plant: Physics, axes: Iterable[Axis], plc_period: float = 0.002) -> None:
        self.plant = plant
        self.axes = list(axes)
        if not self.axes:
            raise ValueError("a runtime needs at least one axis")
        self._latched = [axis.io for axis in self.axes if axis.io.delayed]
        """The channels whose outputs the module latches for a cycle."""
        servo_period = self.axes[0].servo_period
        if any(abs(ax.servo_period - servo_period) > 1e-12 for ax in self.axes):
            raise ValueError("all axes of a runtime must share one servo period")
        self._dt = plant.timestep
        """The plant's timestep [s] (fixed: the periods are whole multiples of it)."""
        self._servo_ticks = ticks_per(servo_period, plant.timestep, "servo period")
        servo_per_plc = ticks_per(plc_period, servo_period, "PLC period")
        self._plc_ticks = self._servo_ticks * servo_per_plc
        self.plc_period = plc_period
        self.servo_period = servo_period
        self._tick = 0
        self.faults: FaultLog | None = None
        """Scheduled faults, applied at the servo instants (set by the machine)."""
        self.observers: list[Callable[[float], None]] = []
        """Called after every servo cycle with the time [s] (e.g. a trace recorder)."""

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._tick * self._dt

    def run(
        self,
        program: Callable[[], None] | None = None,
        until: Callable[[], object] | None = None,
        timeout: float = 10.0,
    ) -> float:
        """Run PLC cycles until ``until()`` is true (checked every PLC cycle) or for ``timeout``.

        Args:
            program: one PLC scan (calls FB instances); None runs no program.
            until: stop condition, any value Python takes as true (``lambda: move.Done``,
                ``lambda: axis.AxErrorID``); None runs for exactly ``timeout`` seconds.
            timeout: simulated seconds at most.

        Returns:
            The simulated seconds that elapsed.

        Raises:
            ConditionTimeout: ``until`` was given and did not become true in time.
        """
        plant, axes = self.plant, self.axes
        servo_ticks, plc_ticks = self._servo_ticks, self._plc_ticks
        dt = plant.timestep
        start = self._tick
        end = start + round(timeout / dt)
        observers = self.observers
        faults = self.faults
        latched = self._latched
        tick = self._tick
        while tick < end:
            plc_cycle = tick % plc_ticks == 0
            if plc_cycle and program is not None:
                program()
            t = tick * dt
            if faults is not None and faults.pending:
                faults.due(t)
            if latched:
                now = plant.time  # the instant the plant samples at
                for io in latched:
                    io.latch(now)
            plant.sense()
            for axis in axes:
                axis.measure(t)
            for axis in axes:
                axis.update_setpoint(t)
            for axis in axes:
                axis.act(t)
            for observe in observers:
                observe(t)
            plant.step(servo_ticks)
            tick += servo_ticks
            self._tick = tick
            if plc_cycle and until is not None and until():
                return (tick - start) * dt
        if until is not None and not until():
            raise ConditionTimeout(f"condition not met within {timeout:g} s of simulated time")
        return (tick - start) * dt


@dataclass(frozen=True, slots=True)
class MachineState:
    """A machine at one instant with every axis at rest (:meth:`Machine.save_state`).

    It holds the simulated time, the plant (physics, drives and devices), every axis with its
    channel (:class:`~mcl.axis.AxisSnapshot`) and the fault log, all as copies, so one state
    can be restored any number of times, into the machine it was saved from or into another
    machine built the same way. The PLC program (function blocks, axes groups) is not part of
    it.

    Attributes:
        machine: what the state was saved from (machine, model, periods): it is restored only
            into a machine built the same way.
        time: simulated time [s].
        tick: physics timesteps since the start.
        plant: the plant's own state.
        axes: every axis with its channel, in the machine's order.
        faults: the injected faults' log: changes so far and those still scheduled.
    """

    machine: tuple[str, ...]
    time: float
    tick: int
    plant: Any
    axes: tuple[AxisSnapshot, ...]
    faults: FaultLogState


@mypyc_attr(allow_interpreted_subclasses=True)
class Machine:
    """Named axes on a plant with their lockstep runtime: the surface scenarios program against.

    Subclasses (:class:`mcl.SimMachine`, ``scenes.Scene``) set ``axes``, ``plant`` and
    ``runtime``.
    """

    axes: dict[str, Axis]
    plant: Plant
    runtime: Runtime

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.runtime.time

    @property
    def faults(self) -> FaultLog:
        """Fault injection on the axes' channels: ``set``, ``clear``, ``schedule``; every change
        is in ``faults.events`` (see :mod:`mcl.faults`)."""
        log = self.runtime.faults
        if log is None:
            channels: dict[str, Injectable] = {}
            for name, axis in self.axes.items():
                io = axis.io
                if not isinstance(io, AxisChannel):
                    raise TypeError(f"axis {name}: its I/O ({type(io).__name__}) takes no faults")
                channels[name] = io
            log = self.runtime.faults = FaultLog(channels, lambda: self.runtime.time)
        return log

    def run(
        self,
        program: Callable[[], None] | None = None,
        until: Callable[[], object] | None = None,
        timeout: float = 10.0,
    ) -> float:
        """Run PLC cycles; see :meth:`Runtime.run`. Returns the simulated seconds."""
        return self.runtime.run(program, until, timeout)

    # ------------------------------------------------------------------ saved state
    def save_state(self) -> MachineState:
        """Save the machine as it is now, e.g. once it is homed (see :class:`MachineState`).

        Raises:
            StateError: an axis is not at rest (not Disabled, StandStill or ErrorStop, or a
                command still runs): the message names every such axis and its state.
        """
        problems = [p for p in (axis.rest_problem() for axis in self.axes.values()) if p]
        if problems:
            raise StateError(
                f"cannot save the machine state while a motion command runs: "
                f"{'; '.join(problems)}. Stop it first (MC_Halt or MC_Stop; MC_GroupStop for "
                f"a group, MC_GearOut for gearing; wait for homing to finish) and save once "
                f"every axis is in StandStill, Disabled or ErrorStop"
            )
        runtime = self.runtime
        log = runtime.faults
        return MachineState(
            machine=self._identity(),
            time=runtime.time,
            tick=runtime._tick,
            plant=self._plant_state(),
            axes=tuple(axis.snapshot() for axis in self.axes.values()),
            faults=log.snapshot() if log is not None else FaultLogState(),
        )

    def restore_state(self, state: MachineState) -> None:
        """Return the machine to a state saved with :meth:`save_state`: positions, velocities,
        controllers, reference, power, errors, faults and the simulated time are as they were
        then, and the same program gives the same motion, bit for bit.

        Function blocks of a program are not part of the state: those still holding an axis
        are let go (their commands end Aborted; see :meth:`mcl.Axis.restore`) and axes groups
        are taken apart, so build the program anew after a restore.

        Raises:
            StateError: the state is of another machine or model (nothing is changed then).
        """
        identity = self._identity()
        if state.machine != identity:
            raise StateError(
                f"the state was saved from {', '.join(state.machine)}; it cannot be restored "
                f"into {', '.join(identity)}: restore a state into the machine it was saved "
                f"from (or one built the same way)"
            )
        names = tuple(snapshot.name for snapshot in state.axes)
        if names != tuple(self.axes):
            raise StateError(f"the state has the axes {names}, this machine {tuple(self.axes)}")
        for axis, snapshot in zip(self.axes.values(), state.axes, strict=True):
            axis.check_snapshot(snapshot)
        self._restore_plant(state.plant)
        for axis, snapshot in zip(self.axes.values(), state.axes, strict=True):
            axis.restore(snapshot)
        runtime = self.runtime
        runtime._tick = state.tick
        if runtime.faults is not None or state.faults.events or state.faults.pending:
            self.faults.restore(state.faults)
        self._restored()

    def _identity(self) -> tuple[str, ...]:
        """What a saved state must match: the machine, its periods and its plant, as texts."""
        runtime = self.runtime
        return (
            f"{type(self).__name__} with axes {', '.join(self.axes)}",
            f"servo period {runtime.servo_period * 1e3:g} ms",
            f"PLC period {runtime.plc_period * 1e3:g} ms",
            *self.plant.identity(),
        )

    def _plant_state(self) -> object:
        """The plant's own state (:meth:`Plant.get_state`)."""
        return self.plant.get_state()

    def _restore_plant(self, state: object) -> None:
        """Restore the plant's state taken with :meth:`_plant_state`."""
        self.plant.set_state(state)

    def _restored(self) -> None:
        """Called at the end of :meth:`restore_state` (e.g. to clear a trace)."""

"""A scene: machines built from their definitions, wired to mcl axes, run in lockstep.

``Scene`` is what scenario tests and the viewer use: ``scene.axes["X"]`` (mcl.Axis),
``scene.run(program, until, timeout)``, ``scene.time``, ``scene.model`` / ``scene.data`` (MuJoCo
ground truth, where ``scene.has_model``), ``scene.joint("X")`` (a joint of the model by the
machine's own name), ``scene.trace`` (recorded signals, CSV export), ``scene.faults`` (fault
injection), ``scene.signal(name)`` (published values), ``scene.save_state()`` /
``scene.restore_state(state)`` (a homed machine kept for later runs).

A scene is a look at its :class:`~scenes.world.World` through a
:class:`~scenes.namespace.Namespace`: the whole scene's, or one machine's own
(:meth:`Scene.machine`, a :class:`MachineScene`), in which that machine's code runs unchanged.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TypeVar, cast

import mujoco

import mcl
from scenes.definition import MachineDef
from scenes.namespace import Namespace
from scenes.plant.drives import WiringError
from scenes.plant.mujoco import Joint, MujocoAxisIO
from scenes.world import MODELS, World, compose, model_path

__all__ = ["MODELS", "MachineScene", "Scene", "WiringError", "compose", "model_path"]

D = TypeVar("D")
"""A class of device (:meth:`Scene.device`)."""


class Scene(mcl.Machine):
    """Machines driven by mcl axes (one servo module per machine).

    Args:
        machines: the machine definitions (several MJCF machines compose into one model; a
            machine of simulated axes stands alone).
        start: joint coordinates at power-up [m or rad] by axis name (overrides the machines').
        servo_period: servo cycle [s] (integer multiple of the model timestep); default: the
            first machine's.
        plc_period: PLC cycle [s] (integer multiple of the servo period); default: the first
            machine's.
        trace_every: record the trace every N servo cycles (0 = no trace).
        trace_seconds: how much of the trace is kept in memory: the last ``trace_seconds`` of
            simulated time [s] (older samples are dropped, or streamed with ``trace_file``).
        trace_file: a CSV file that receives every trace sample (keep everything on disk);
            complete after ``scene.trace.flush()`` or ``scene.trace.close()``.
        positions: where each machine's origin sits in the world [m], by machine name.
        sensors: the sensors of every axis, instead of each axis' own (e.g.
            ``mcl.IDEAL_SENSORS`` to compare a scenario against ideal switches and encoders).

    Raises:
        WiringError: the model does not provide what an axis needs (the message says what).
        ValueError: periods that do not fit, simulated axes mixed with other machines, or a
            start that puts bodies into one another or past an end stop (the message names the
            axis and the range it may start in).
    """

    def __init__(
        self,
        machines: Sequence[MachineDef],
        start: Mapping[str, float] | None = None,
        servo_period: float | None = None,
        plc_period: float | None = None,
        trace_every: int = 1,
        positions: Mapping[str, Sequence[float]] | None = None,
        sensors: mcl.Sensors | None = None,
        trace_seconds: float = 30.0,
        trace_file: str | Path | None = None,
    ) -> None:
        world = World(
            self,
            machines,
            start,
            servo_period,
            plc_period,
            trace_every,
            positions,
            sensors,
            trace_seconds,
            trace_file,
        )
        self._see(world, world.namespace)
        alone = len(world.machines) == 1
        world.show({m.name: self if alone else MachineScene(world, m) for m in world.machines})

    def _see(self, world: World, names: Namespace) -> None:
        """Look at ``world`` through ``names``: the axes, devices and signals are the world's
        own objects by the names a program here uses; the physics, the runtime and the trace
        are the world's."""
        self.world = world
        """What the machines of the scene share (:class:`~scenes.world.World`)."""
        self.namespace = names
        """The names of this scene: a machine's own (``"X"`` is ``gantry/X`` in the model)."""
        self.plant, self.runtime, self.trace = world.plant, world.runtime, world.trace
        self.axes = names.own(world.axes)
        """The axes by name (in a scene of several machines, ``press/R``)."""
        self.devices = names.own(world.devices)
        """The Python devices by name (in a scene of several machines, ``press/cylinder``)."""
        self.signals = names.own(world.signals)
        """Published values by name (in a scene of several machines, ``press/pressure_A``)."""
        self.scales = names.own(world.scales)
        """User units per SI unit of each axis (mm per m, deg per rad)."""
        self.modules = [m for m in world.modules if m.axes[0] in self.axes.values()]
        """The servo modules of the axes (six axes to a module)."""
        self._joints: dict[str, Joint] = {}
        """The joints read so far by the names they were asked for (:meth:`joint`)."""

    @property
    def whole(self) -> Scene:
        """The scene of all the machines (this scene, unless it is one machine's view)."""
        return self.world.whole

    @property
    def name(self) -> str:
        """The registry name of the machine or cell ("scene" for machines composed ad hoc; a
        machine's view: the machine's)."""
        return self.world.name if self is self.whole else self.namespace.machine

    @property
    def cell(self) -> MachineDef | None:
        """The cell definition the scene was built from (None: plain machines, or a view)."""
        return self.world.cell if self is self.whole else None

    @property
    def machines(self) -> list[MachineDef]:
        """The machines of the scene (a machine's view: that machine)."""
        return [m for m in self.world.machines if self is self.whole or m.name == self.name]

    @property
    def parts(self) -> dict[str, Scene]:
        """Each machine's own view of the scene by machine name (see :meth:`machine`)."""
        return self.world.views if self is self.whole else {self.name: self}

    @property
    def has_model(self) -> bool:
        """The scene runs on a MuJoCo model (False: simulated axes)."""
        return self.world.model is not None

    @property
    def model(self) -> mujoco.MjModel:
        """The compiled MuJoCo model (ground truth).

        Raises:
            TypeError: the scene runs simulated axes (see :attr:`has_model`).
        """
        if self.world.model is None:
            raise TypeError(f"scene {self.name!r} runs simulated axes; it has no MuJoCo model")
        return self.world.model

    @property
    def data(self) -> mujoco.MjData:
        """The MuJoCo data (ground truth).

        Raises:
            TypeError: the scene runs simulated axes (see :attr:`has_model`).
        """
        if self.world.data is None:
            raise TypeError(f"scene {self.name!r} runs simulated axes; it has no MuJoCo data")
        return self.world.data

    def machine(self, name: str) -> Scene:
        """The view of the scene that machine ``name``'s own code sees: its axes, devices,
        signals and model names by its own names (``axes["X"]``, ``joint("X")``), the physics
        and the time the scene's. In a scene of one machine that is the scene itself.

        Raises:
            KeyError: no such machine in the scene (the message lists them).
        """
        parts = self.parts
        try:
            return parts[name]
        except KeyError:
            raise KeyError(f"no machine {name!r} in the scene; machines: {list(parts)}") from None

    def signal(self, name: str) -> float:
        """The current value of a published signal (e.g. ``"pressure_A"``).

        Raises:
            KeyError: unknown name (the message lists the valid ones).
        """
        try:
            signal = self.signals[name]
        except KeyError:
            raise KeyError(f"no signal {name!r}; signals: {sorted(self.signals)}") from None
        return signal.read(self.signal_owner(name))

    def signal_owner(self, name: str) -> Scene:
        """The scene a published signal is read on: this one, or in a world of several
        machines the machine's own (``"press/pressure_A"`` reads on the press)."""
        return self.world.scene_of(self.namespace.scene(name))

    def io(self, axis: str) -> MujocoAxisIO:
        """The MuJoCo channel of an axis (joint position, amplifier, switches)."""
        if not self.has_model:
            raise TypeError(f"axis {axis} is a simulated axis, not on a MuJoCo model")
        return cast(MujocoAxisIO, self.axes[axis].io)  # a model's channels are MujocoAxisIO

    def device(self, name: str, kind: type[D]) -> D:
        """The machine's Python device ``name``, of class ``kind``.

        Raises:
            WiringError: there is no such device, or it is of another class.
        """
        device = self.devices.get(name)
        if not isinstance(device, kind):
            found = "none" if device is None else type(device).__name__
            raise WiringError(
                f"device {name!r} must be a {kind.__name__}, found {found}; "
                f"devices: {sorted(self.devices)}"
            )
        return device

    def model_name(self, name: str) -> str:
        """The model's name of the machine's own joint, actuator, site, sensor or numeric
        ``name``, for MuJoCo's accessors: ``scene.data.actuator(scene.model_name("D_amp"))``
        (``"D_amp"`` is ``"rotary_cutter/D_amp"`` in the model). A name with a ``/`` is the
        model's already (``"gantry/X"``), and so is every name in a scene of several machines."""
        return self.namespace.model(name)

    def joint(self, name: str) -> Joint:
        """Ground truth of the machine's joint ``name`` (its own name, ``"K"``, or the model's,
        ``"flying_shear/K"``: :meth:`model_name`), cheap to read every cycle (published signals
        are).

        Raises:
            TypeError: the scene runs simulated axes.
            WiringError: the model has no such joint (the message lists the scene's joints).
        """
        joint = self._joints.get(name)
        if joint is None:
            model, full = self.model, self.model_name(name)
            if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, full) < 0:
                prefix = self.namespace.prefix  # the joints by the names asked for here
                joints = [model.joint(j).name for j in range(model.njnt)]
                own = [j.removeprefix(prefix) for j in joints if j.startswith(prefix)]
                raise WiringError(f"{self.name} has no joint {name!r}; joints: {own}")
            joint = self._joints[name] = Joint(model, self.data, full)
        return joint

    def joint_position(self, axis: str) -> float:
        """Ground-truth joint coordinate of an axis [m or rad]."""
        return self.axes[axis].io.position

    # ------------------------------------------------------------------ saved state
    def save_state(self) -> mcl.MachineState:
        """Save the scene as it is now, e.g. once it is homed: the simulated time, the physics
        with every drive and device (oil pressures, valves), every axis with its channel
        (reference, power, errors, regulator, encoder, switches, sensor noise) and the
        injected faults. Function blocks are not part of it (they belong to the program).

        Raises:
            mcl.StateError: an axis is not at rest; the message names each such axis and its
                state (stop it first).
        """
        return super().save_state()

    def restore_state(self, state: mcl.MachineState) -> None:
        """Return to a state saved with :meth:`save_state` (of this scene, or of another scene
        built from the same machines, model, periods and sensors); the same program then gives
        the same motion, bit for bit.

        The trace window is cleared, so it shows only what happens after the restore (a
        streamed trace file keeps what it received and goes on from the restored time). Blocks
        of a program that still hold an axis are let go (their commands end Aborted) and axes
        groups are taken apart: build the program anew after a restore.

        Raises:
            mcl.StateError: the state is of another machine or model (the message says which);
                the scene is left unchanged.
        """
        super().restore_state(state)

    def _identity(self) -> tuple[str, ...]:
        machines = ", ".join(f"{m.name} ({m.model or 'simulated axes'})" for m in self.machines)
        return (f"machine {machines}", *super()._identity())

    def _restored(self) -> None:
        self.trace.clear()


class MachineScene(Scene):
    """Machine ``machine``'s own view of a scene it shares with other machines (a cell), made
    by the scene (:meth:`Scene.machine`): the machine's code runs unchanged in it.

    Its axes, devices, signals and model names are the machine's own (``axes["R"]``,
    ``joint("R")`` for ``press/R``), over the scene's physics, time, runtime and trace; what
    belongs to the whole scene (saving a state, faults) is done on the scene.

    Args:
        world: the scene's world.
        machine: one of the world's machines.
    """

    def __init__(self, world: World, machine: MachineDef) -> None:
        self._see(world, world.names[machine.name])

    @property
    def faults(self) -> mcl.faults.FaultLog:
        """The whole scene's fault log (its axes by their names in the scene, ``press/R``)."""
        return self.whole.faults

    def save_state(self) -> mcl.MachineState:
        """A machine of a cell is saved with the whole scene.

        Raises:
            mcl.StateError: always; save the whole scene instead.
        """
        raise mcl.StateError(
            f"machine {self.name} shares its physics with the other machines of the scene: "
            f"save the whole scene (scene.save_state()), not one machine's view of it"
        )

    def restore_state(self, state: mcl.MachineState) -> None:
        """A machine of a cell is restored with the whole scene.

        Raises:
            mcl.StateError: always; restore the whole scene instead.
        """
        raise mcl.StateError(
            f"machine {self.name} shares its physics with the other machines of the scene: "
            f"restore the whole scene, not one machine's view of it"
        )

"""A scene: machines built from their definitions, wired to mcl axes, run in lockstep.

``Scene`` is what scenario tests and the viewer use: ``scene.axes["X"]`` (mcl.Axis),
``scene.run(program, until, timeout)``, ``scene.time``, ``scene.model`` / ``scene.data`` (MuJoCo
ground truth, where ``scene.has_model``), ``scene.trace`` (recorded signals, CSV export),
``scene.faults`` (fault injection), ``scene.signal(name)`` (published values),
``scene.save_state()`` / ``scene.restore_state(state)`` (a homed machine kept for later runs).
"""

from __future__ import annotations

__all__ = ["LOOKS", "MODELS", "WORLD", "Scene", "compose", "model_path"]

import os
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, TypeVar, cast

import mujoco

import mcl
from mcl.trace import Trace
from scenes import model_errors
from scenes import start as start_check
from scenes.definition import AxisDef, MachineDef, Signal, unit_and_scale
from scenes.plant.drives import Device, WiringError
from scenes.plant.mujoco import AxisWiring, Joint, MujocoAxisIO, MujocoPlant

D = TypeVar("D")
"""A class of device (:meth:`Scene.device`)."""

MODELS = (Path(__file__).resolve().parent / "models").resolve()
"""The folder of the MJCF machine models: ``models/`` (``scenes/models`` links to it; an installed
copy holds the files there)."""


def model_path(file: str) -> Path:
    """The MJCF file of a machine (relative to ``models/`` or absolute).

    Raises:
        FileNotFoundError: it does not exist (the message lists the models).
    """
    path = Path(file)
    path = path if path.is_absolute() else MODELS / path
    if not path.is_file():
        raise FileNotFoundError(
            f"machine model {path} does not exist; models: "
            f"{sorted(p.name for p in MODELS.glob('*.xml'))}"
        )
    return path


def compose(
    machines: Sequence[MachineDef], positions: Mapping[str, Sequence[float]] | None = None
) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Attach the machines' models to an empty world and compile the result.

    Args:
        machines: the machines; each model is prefixed with its machine's name.
        positions: where each machine's origin sits in the world [m] (default: the origin).

    Raises:
        FileNotFoundError: a model file does not exist.
        WiringError: the models cannot be combined (e.g. too many actuator groups).
        ModelError: a model file is malformed, MuJoCo refuses it, or it lacks a joint its
            machine definition names (one line each: the machine's file and line).
    """
    os.environ.setdefault("MUJOCO_GL", "disable")  # dm_control must not look for a display
    from dm_control import mjcf

    root = mjcf.RootElement(model="scene")
    groups = 0
    files: dict[str, Path] = {}
    lacking: dict[str, list[str]] = {}
    for machine in machines:
        files[machine.name] = path = model_path(machine.model)
        child = model_errors.parse(path, mjcf.from_path)
        joints = {s.joint or a: f"axis {a} (AxisDef.joint)" for a, s in machine.axes.items()}
        have = [j.name for j in child.find_all("joint") if j.name]
        model_errors.check_names(path, machine.name, "joint", joints, have)
        amplifiers = {
            f"{s.joint or a}_amp": f"the amplifier of axis {a}"
            for a, s in machine.axes.items()
            if s.drive == "electric"
        }
        actuators = [e.name for e in child.find_all("actuator") if e.name]
        lacking[machine.name] = model_errors.absent(machine.name, "actuator", amplifiers, actuators)
        child.model = machine.name
        for actuator in child.find_all("actuator"):
            groups += 1
            actuator.group = groups  # one drive-enable group per amplifier, unique in the scene
        if groups > 30:
            raise WiringError("at most 30 amplifiers fit in one scene (MuJoCo actuator groups)")
        _share_world(root, child, machine.name, path, alone=len(machines) == 1)
        frame = root.attach(child)
        frame.pos = tuple((positions or {}).get(machine.name, (0.0, 0.0, 0.0)))
    xml = root.to_xml_string()
    model = model_errors.compiled(
        lambda: mujoco.MjModel.from_xml_string(xml, root.get_assets()), files, xml, lacking
    )
    return model, mujoco.MjData(model)


WORLD = ("option", "compiler", "size")
"""The elements of a model that belong to the whole world: machines sharing one physics must
agree on them."""
LOOKS = ("statistic", "visual")
"""The elements of a model that only set how it is shown: the first machine's are kept (but for
the statistic of several machines, which MuJoCo then computes from the whole world)."""


def _share_world(root: Any, child: Any, machine: str, path: Path, alone: bool) -> None:
    """Prepare ``child`` to join ``root``'s world: the settings of the whole world (timestep,
    integrator, compiler) taken over by the first machine and checked against the others; the
    view settings (statistic, headlight) the first machine's, the others' dropped."""
    if not alone:
        child.statistic.set_attributes(**dict.fromkeys(child.statistic.get_attributes()))
    for tag in (*WORLD, *LOOKS):
        mine, world = getattr(child, tag), getattr(root, tag)
        for element, into in zip(
            [mine, *mine.all_children()], [world, *world.all_children()], strict=True
        ):
            for key, value in element.get_attributes().items():
                held = into.get_attributes().get(key)
                if held is None:
                    into.set_attributes(**{key: value})
                elif tag in WORLD and str(held) != str(value):
                    raise WiringError(
                        f'{path}: <{element.tag} {key}="{value}">: machine {machine} needs '
                        f"{key} {value}, another machine of the scene {held}; expected machines "
                        f"that share one physics to agree on <{tag}>"
                    )
                element.set_attributes(**{key: None})


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
        if not machines:
            raise ValueError("a scene needs at least one machine")
        self.cell = next((m for m in machines if m.parts), None)
        """The cell definition the scene was built from (None: plain machines)."""
        machines, positions = self._parts_of(machines, positions)
        if sensors is not None:
            machines = [
                replace(m, axes={a: replace(x, sensors=sensors) for a, x in m.axes.items()})
                for m in machines
            ]
        self.machines = list(machines)
        single = len(self.machines) == 1
        self.name = self.cell.name if self.cell else self.machines[0].name if single else "scene"
        """The registry name of the machine or cell ("scene" for machines composed ad hoc)."""
        first = self.machines[0]
        self._model: mujoco.MjModel | None = None
        self._data: mujoco.MjData | None = None
        self.devices: dict[str, Device] = {}
        self._joints: dict[str, Joint] = {}
        names = {
            (m.name, a): a if single else f"{m.name}/{a}" for m in self.machines for a in m.axes
        }
        starts = dict(start or {})
        self.plant: mcl.Plant
        if any(not m.model for m in self.machines):
            if not single:
                raise ValueError("a machine of simulated axes cannot share a scene")
            ios, self.plant, scales = self._simulated(first, starts)
        else:
            try:
                ios, self.plant, scales = self._mujoco(starts, positions, names)
            except WiringError as error:  # a name the machine's file lacks: name the file
                files = [model_path(m.model) for m in self.machines]
                raise model_errors.in_files(error, files) from None
        servo_period = first.servo_period if servo_period is None else servo_period
        self._make_axes(ios, scales, names, servo_period)
        self.scales = {name: scale for name, (_, scale) in scales.items()}
        """User units per SI unit of each axis (mm per m, deg per rad)."""
        owners = self._publish(single)
        self._signal_scenes: dict[str, Scene] = {}
        plc_period = first.plc_period if plc_period is None else plc_period
        self.runtime = mcl.Runtime(self.plant, self.axes.values(), plc_period)
        self.trace = Trace(
            self.axes,
            every=max(trace_every, 1),
            truth={n: self._truth(n) for n in self.axes},
            signals={n: self._reader(n) for n in self.signals},
            events=lambda: self.faults.events,
            keep=max(1, round(trace_seconds / (self.runtime.servo_period * max(trace_every, 1)))),
            stream=trace_file if trace_every else None,
        )
        if trace_every:
            self.runtime.observers.append(self.trace)
        self.parts: dict[str, Scene] = {m.name: self for m in self.machines} if single else {}
        """Each machine's own view of the scene by machine name (see :meth:`machine`)."""
        if not single:
            from scenes.namespace import MachineScene

            self.parts = {m.name: MachineScene(self, m) for m in self.machines}
            self._signal_scenes.update({s: self.parts[m] for s, m in owners.items()})

    def _parts_of(
        self, machines: Sequence[MachineDef], positions: Mapping[str, Sequence[float]] | None
    ) -> tuple[Sequence[MachineDef], Mapping[str, Sequence[float]] | None]:
        """The machines of the scene and where they stand: a cell's parts in its place."""
        if self.cell is None:
            return machines, positions
        if len(machines) > 1:
            raise ValueError(f"cell {self.cell.name!r} stands alone in its scene")
        places = {p.machine.name: p.position for p in self.cell.parts}
        return [p.machine for p in self.cell.parts], {**places, **(positions or {})}

    def _make_axes(
        self,
        ios: Mapping[str, mcl.channel.AxisChannel],
        scales: Mapping[str, tuple[str, float]],
        names: Mapping[tuple[str, str], str],
        servo_period: float,
    ) -> None:
        """An mcl axis on each channel, with its machine data; six to a servo module."""
        self.axes: dict[str, mcl.Axis] = {}
        self.modules: list[mcl.Module] = []
        for m in self.machines:
            members = []
            for a, spec in m.axes.items():
                name = names[(m.name, a)]
                unit, scale = scales[name]
                config = replace(spec.config, servo_period=servo_period, unit=unit)
                _check_resolution(ios[name].resolution * scale, config, name)
                axis = mcl.Axis(ios[name], config, name=name)
                if spec.constants is not None:
                    axis.set_constants(spec.constants)
                self.axes[name] = axis
                members.append(axis)
            size = mcl.Module.MAX_AXES
            self.modules += [
                mcl.Module(members[i : i + size]) for i in range(0, len(members), size)
            ]

    def _publish(self, single: bool) -> dict[str, str]:
        """Every machine's published signals (prefixed in a composed scene) and the cell's;
        returns which machine each machine signal belongs to."""
        self.signals: dict[str, Signal] = {}
        """Published values by name (prefixed with the machine's name in a composed scene)."""
        owners = {}
        for m in self.machines:
            for s, signal in m.signals.items():
                self.signals[s if single else f"{m.name}/{s}"] = signal
                owners[s if single else f"{m.name}/{s}"] = m.name
        self.signals.update(self.cell.signals if self.cell is not None else {})
        return owners

    def _simulated(
        self, machine: MachineDef, starts: Mapping[str, float]
    ) -> tuple[dict[str, mcl.channel.AxisChannel], mcl.SimPlant, dict[str, tuple[str, float]]]:
        sims: dict[str, mcl.SimAxis] = {}
        for a, spec in machine.axes.items():
            assert spec.sim is not None
            params = spec.sim
            position = starts.get(a, machine.start.get(a))
            if position is not None:
                if not params.stop_neg <= position <= params.stop_pos:
                    span = (params.stop_neg, params.stop_pos)
                    raise ValueError(
                        start_check.message(a, position, "m", "past the axis' hard stop", span)
                    )
                params = replace(params, start=position)
            if spec.sensors is not None:
                params = replace(params, sensors=spec.sensors)
            sims[a] = mcl.SimAxis(params)
        plant = mcl.SimPlant(list(sims.values()))
        scales = {a: unit_and_scale(spec, rotary=False) for a, spec in machine.axes.items()}
        return dict(sims), plant, scales

    def _mujoco(
        self,
        starts: Mapping[str, float],
        positions: Mapping[str, Sequence[float]] | None,
        names: Mapping[tuple[str, str], str],
    ) -> tuple[dict[str, mcl.channel.AxisChannel], MujocoPlant, dict[str, tuple[str, float]]]:
        model, data = compose(self.machines, positions)
        self._model, self._data = model, data
        placed: dict[str, tuple[str, float]] = {}
        homes: dict[str, float] = {}
        for m in self.machines:
            key = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, f"{m.name}/home")
            for a, spec in m.axes.items():
                q = starts.get(names[(m.name, a)], m.start.get(a))
                if q is not None:
                    joint = data.joint(f"{m.name}/{spec.joint or a}")
                    joint.qpos[0] = q
                    placed[names[(m.name, a)]] = (joint.name, q)
                    adr = int(model.joint(joint.name).qposadr[0])
                    homes[names[(m.name, a)]] = float(
                        model.key_qpos[key, adr] if key >= 0 else model.qpos0[adr]
                    )
        mujoco.mj_forward(model, data)
        if placed:
            start_check.check(model, data, placed, homes)
        for m in self.machines:
            for d, factory in m.devices.items():
                self.devices[d if len(self.machines) == 1 else f"{m.name}/{d}"] = factory(
                    model, data, f"{m.name}/"
                )
        wirings = []
        for m in self.machines:
            for a, spec in m.axes.items():
                wirings.append(self._wiring(m, a, spec))
        plant = MujocoPlant(model, data, wirings, self.devices)
        for device in self.devices.values():
            connect = getattr(device, "connect", None)
            if connect is not None:  # a device that reads channel outputs (a knife valve)
                connect(plant.ios)
        ios: dict[str, mcl.channel.AxisChannel] = {}
        scales: dict[str, tuple[str, float]] = {}
        for m in self.machines:
            for a, spec in m.axes.items():
                io = plant.ios[f"{m.name}/{spec.joint or a}"]
                name = names[(m.name, a)]
                ios[name] = io
                try:
                    scales[name] = unit_and_scale(spec, io.rotary)
                except ValueError as error:
                    raise WiringError(f"axis {name}: {error}") from None
        return ios, plant, scales

    def _wiring(self, m: MachineDef, a: str, spec: AxisDef) -> AxisWiring:
        device_name = spec.device if len(self.machines) == 1 else f"{m.name}/{spec.device}"
        analog = None
        if spec.analog:
            inputs = getattr(self.devices.get(device_name), "analog_inputs", None)
            if inputs is None:
                raise WiringError(
                    f"axis {a}: analog inputs {spec.analog} need the device {spec.device!r} "
                    f"with analog_inputs(names) -> a reader of volts; devices: "
                    f"{sorted(self.devices)}"
                )
            analog = inputs(spec.analog)
        return AxisWiring(
            f"{m.name}/{spec.joint or a}",
            f"{m.name}/",
            drive=spec.drive,
            device=device_name,
            switches=spec.switches,
            probe=spec.probe,
            digital_outputs=spec.digital_outputs,
            analog=analog,
            sensors=spec.sensors,
        )

    def _truth(self, axis: str) -> mcl.trace.Reader:
        io = self.axes[axis].io
        return lambda: io.position

    @property
    def has_model(self) -> bool:
        """The scene runs on a MuJoCo model (False: simulated axes)."""
        return self._model is not None

    @property
    def model(self) -> mujoco.MjModel:
        """The compiled MuJoCo model (ground truth).

        Raises:
            TypeError: the scene runs simulated axes (see :attr:`has_model`).
        """
        if self._model is None:
            raise TypeError(f"scene {self.name!r} runs simulated axes; it has no MuJoCo model")
        return self._model

    @property
    def data(self) -> mujoco.MjData:
        """The MuJoCo data (ground truth).

        Raises:
            TypeError: the scene runs simulated axes (see :attr:`has_model`).
        """
        if self._data is None:
            raise TypeError(f"scene {self.name!r} runs simulated axes; it has no MuJoCo data")
        return self._data

    def _reader(self, name: str) -> mcl.trace.Reader:
        signal, scenes = self.signals[name], self._signal_scenes  # views are made after the trace
        return lambda: signal.read(scenes.get(name, self))

    def machine(self, name: str) -> Scene:
        """The view of the scene that machine ``name``'s own code sees: its axes, devices and
        signals by their own names (``axes["X"]``), the physics and the time the scene's. In a
        scene of one machine that is the scene itself.

        Raises:
            KeyError: no such machine in the scene (the message lists them).
        """
        try:
            return self.parts[name]
        except KeyError:
            raise KeyError(
                f"no machine {name!r} in the scene; machines: {list(self.parts)}"
            ) from None

    def signal(self, name: str) -> float:
        """The current value of a published signal (e.g. ``"pressure_A"``).

        Raises:
            KeyError: unknown name (the message lists the valid ones).
        """
        try:
            signal = self.signals[name]
        except KeyError:
            raise KeyError(f"no signal {name!r}; signals: {sorted(self.signals)}") from None
        return signal.read(self._signal_scenes.get(name, self))

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

    def joint(self, name: str) -> Joint:
        """Ground truth of the model's joint ``name`` (its full name, e.g. ``"flying_shear/K"``),
        cheap to read every cycle (published signals are).

        Raises:
            TypeError: the scene runs simulated axes.
            WiringError: the model has no such joint (the message lists them).
        """
        joint = self._joints.get(name)
        if joint is None:
            joint = self._joints[name] = Joint(self.model, self.data, name)
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


def _check_resolution(model_resolution: float, config: mcl.AxisConfig, axis: str) -> None:
    if abs(model_resolution - config.resolution) > 1e-9 * model_resolution:
        raise WiringError(
            f"axis {axis}: AxisConfig.resolution {config.resolution} {config.unit}/count "
            f"does not match the model's encoder ({model_resolution:g} {config.unit}/count)"
        )

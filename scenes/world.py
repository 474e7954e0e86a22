"""The world of a scene: what its machines share, built from their definitions.

:class:`World` composes the machines' models into one physics (:func:`compose`; or a machine of
simulated axes), makes each machine's devices and an mcl axis on each channel, and the one
runtime and trace that run them all. Every name in it is the scene's: each machine's own names
turned into the scene's by the machine's :class:`~scenes.namespace.Namespace`. A program sees the
world through a :class:`scenes.Scene`: the whole scene's, or one machine's own view of it.
"""

from __future__ import annotations

__all__ = ["LOOKS", "MODELS", "WORLD", "World", "compose", "model_path"]

import os
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco

import mcl
from mcl.trace import Trace
from scenes import model_errors
from scenes import start as start_check
from scenes.definition import AxisDef, MachineDef, Signal, unit_and_scale
from scenes.namespace import Namespace
from scenes.plant.drives import Device, WiringError
from scenes.plant.mujoco import AxisWiring, MujocoPlant

if TYPE_CHECKING:
    from scenes.scene import Scene

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


class World:
    """What the machines of a scene share: one physics, their devices and axes, one runtime and
    one trace; every axis, device and signal by its name in the scene.

    Args:
        whole: the scene of all the machines (a cell's signals are read on it, its faults are the
            trace's events).
        machines, start, servo_period, plc_period, trace_every, positions, sensors,
            trace_seconds, trace_file: as :class:`scenes.Scene`'s (the scene gives every one).

    Raises:
        WiringError, ValueError: as :class:`scenes.Scene`.
    """

    def __init__(
        self,
        whole: Scene,
        machines: Sequence[MachineDef],
        start: Mapping[str, float] | None,
        servo_period: float | None,
        plc_period: float | None,
        trace_every: int,
        positions: Mapping[str, Sequence[float]] | None,
        sensors: mcl.Sensors | None,
        trace_seconds: float,
        trace_file: str | Path | None,
    ) -> None:
        if not machines:
            raise ValueError("a scene needs at least one machine")
        self.whole = whole
        """The scene of all the machines."""
        self.cell = next((m for m in machines if m.parts), None)
        """The cell definition the scene was built from (None: plain machines)."""
        machines, positions = self._parts_of(machines, positions)
        if sensors is not None:
            machines = [
                replace(m, axes={a: replace(x, sensors=sensors) for a, x in m.axes.items()})
                for m in machines
            ]
        self.machines = list(machines)
        alone = len(self.machines) == 1
        self.name = self.cell.name if self.cell else self.machines[0].name if alone else "scene"
        """The registry name of the machine or cell ("scene" for machines composed ad hoc)."""
        self.names = {m.name: Namespace(m.name, shared=not alone) for m in self.machines}
        """Each machine's names in the scene, by machine name."""
        self.namespace = self.names[self.machines[0].name] if alone else Namespace()
        """The whole scene's names: its one machine's, or (several machines) the scene's own."""
        first = self.machines[0]
        self.model: mujoco.MjModel | None = None
        self.data: mujoco.MjData | None = None
        self.devices: dict[str, Device] = {}
        starts = dict(start or {})
        self.plant: mcl.Plant
        if any(not m.model for m in self.machines):
            if not alone:
                raise ValueError("a machine of simulated axes cannot share a scene")
            ios, self.plant, scales = self._simulated(first, starts)
        else:
            try:
                ios, self.plant, scales = self._mujoco(starts, positions)
            except WiringError as error:  # a name the machine's file lacks: name the file
                files = [model_path(m.model) for m in self.machines]
                raise model_errors.in_files(error, files) from None
        servo_period = first.servo_period if servo_period is None else servo_period
        self._make_axes(ios, scales, servo_period)
        self.scales = {name: scale for name, (_, scale) in scales.items()}
        """User units per SI unit of each axis (mm per m, deg per rad)."""
        self._publish()
        self.views: dict[str, Scene] = {}
        """Each machine's own view of the scene by machine name (:meth:`show`)."""
        plc_period = first.plc_period if plc_period is None else plc_period
        self.runtime = mcl.Runtime(self.plant, self.axes.values(), plc_period)
        self.trace = Trace(
            self.axes,
            every=max(trace_every, 1),
            truth={n: self._truth(n) for n in self.axes},
            signals={n: self._reader(n) for n in self.signals},
            events=lambda: whole.faults.events,
            keep=max(1, round(trace_seconds / (self.runtime.servo_period * max(trace_every, 1)))),
            stream=trace_file if trace_every else None,
        )
        if trace_every:
            self.runtime.observers.append(self.trace)

    def show(self, views: Mapping[str, Scene]) -> None:
        """Take each machine's own view of the scene, by machine name (the scene makes them once
        the world stands): a machine's signals are read on its view."""
        self.views = dict(views)
        self._read_on.update({s: self.views[m] for s, m in self._owners.items()})

    def scene_of(self, signal: str) -> Scene:
        """The scene a published signal (by its name in the scene) is read on: its machine's
        view, or the whole scene (a cell's signals)."""
        return self._read_on.get(signal, self.whole)

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
        servo_period: float,
    ) -> None:
        """An mcl axis on each channel, with its machine data; six to a servo module."""
        self.axes: dict[str, mcl.Axis] = {}
        """Every machine's axes by their names in the scene."""
        self.modules: list[mcl.Module] = []
        """The servo modules: each machine's axes, six to a module."""
        for m in self.machines:
            members = []
            for a, spec in m.axes.items():
                name = self.names[m.name].scene(a)
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

    def _publish(self) -> None:
        """Every machine's published signals and the cell's, and which machine each machine
        signal belongs to."""
        self.signals: dict[str, Signal] = {}
        """Published values by their names in the scene."""
        self._owners: dict[str, str] = {}
        for m in self.machines:
            for s, signal in m.signals.items():
                name = self.names[m.name].scene(s)
                self.signals[name] = signal
                self._owners[name] = m.name
        self.signals.update(self.cell.signals if self.cell is not None else {})
        self._read_on: dict[str, Scene] = {}

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
        self, starts: Mapping[str, float], positions: Mapping[str, Sequence[float]] | None
    ) -> tuple[dict[str, mcl.channel.AxisChannel], MujocoPlant, dict[str, tuple[str, float]]]:
        model, data = compose(self.machines, positions)
        self.model, self.data = model, data
        self._place(model, data, starts)
        for m in self.machines:
            names = self.names[m.name]
            for d, factory in m.devices.items():
                self.devices[names.scene(d)] = factory(model, data, names.prefix)
        wirings = [self._wiring(m, a, spec) for m in self.machines for a, spec in m.axes.items()]
        plant = MujocoPlant(model, data, wirings, self.devices)
        for device in self.devices.values():
            connect = getattr(device, "connect", None)
            if connect is not None:  # a device that reads channel outputs (a knife valve)
                connect(plant.ios)
        ios: dict[str, mcl.channel.AxisChannel] = {}
        scales: dict[str, tuple[str, float]] = {}
        for m in self.machines:
            names = self.names[m.name]
            for a, spec in m.axes.items():
                io = plant.ios[names.model(spec.joint or a)]
                name = names.scene(a)
                ios[name] = io
                try:
                    scales[name] = unit_and_scale(spec, io.rotary)
                except ValueError as error:
                    raise WiringError(f"axis {name}: {error}") from None
        return ios, plant, scales

    def _place(
        self, model: mujoco.MjModel, data: mujoco.MjData, starts: Mapping[str, float]
    ) -> None:
        """Put the axes' joints where the scene or their machine starts them, and check that
        no bodies are then in one another or past an end stop."""
        placed: dict[str, tuple[str, float]] = {}
        homes: dict[str, float] = {}
        for m in self.machines:
            names = self.names[m.name]
            key = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, names.model("home"))
            for a, spec in m.axes.items():
                q = starts.get(names.scene(a), m.start.get(a))
                if q is not None:
                    joint = data.joint(names.model(spec.joint or a))
                    joint.qpos[0] = q
                    placed[names.scene(a)] = (joint.name, q)
                    adr = int(model.joint(joint.name).qposadr[0])
                    homes[names.scene(a)] = float(
                        model.key_qpos[key, adr] if key >= 0 else model.qpos0[adr]
                    )
        mujoco.mj_forward(model, data)
        if placed:
            start_check.check(model, data, placed, homes)

    def _wiring(self, m: MachineDef, a: str, spec: AxisDef) -> AxisWiring:
        names = self.names[m.name]
        device_name = names.scene(spec.device)
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
        source = None
        if spec.probe is not None and spec.probe.device:
            source = getattr(
                self.devices.get(names.scene(spec.probe.device)), "probe_coordinate", None
            )
            if source is None:
                raise WiringError(
                    f"axis {a}: its probe needs the device {spec.probe.device!r} with "
                    f"probe_coordinate() -> metres; devices: {sorted(self.devices)}"
                )
        return AxisWiring(
            names.model(spec.joint or a),
            names.prefix,
            drive=spec.drive,
            device=device_name,
            switches=spec.switches,
            probe=spec.probe,
            probe_source=source,
            digital_outputs=spec.digital_outputs,
            analog=analog,
            sensors=spec.sensors,
        )

    def _truth(self, axis: str) -> mcl.trace.Reader:
        io = self.axes[axis].io
        return lambda: io.position

    def _reader(self, name: str) -> mcl.trace.Reader:
        signal, read_on, whole = self.signals[name], self._read_on, self.whole
        return lambda: signal.read(read_on.get(name, whole))  # the views come after the trace


def _check_resolution(model_resolution: float, config: mcl.AxisConfig, axis: str) -> None:
    if abs(model_resolution - config.resolution) > 1e-9 * model_resolution:
        raise WiringError(
            f"axis {axis}: AxisConfig.resolution {config.resolution} {config.unit}/count "
            f"does not match the model's encoder ({model_resolution:g} {config.unit}/count)"
        )

"""A scene: machine models composed with dm_control.mjcf, wired to mcl axes, run in lockstep.

``Scene`` is what scenario tests and the viewer use: ``scene.axes["X"]`` (mcl.Axis),
``scene.run(program, until, timeout)``, ``scene.time``, ``scene.model`` / ``scene.data`` (MuJoCo
ground truth), ``scene.trace`` (recorded signals, CSV export).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import mujoco

import mcl
from mcl.trace import Trace
from scenes.plant import AxisWiring, MujocoAxisIO, MujocoPlant, WiringError

MODELS = Path(__file__).resolve().parent.parent / "models"
"""The folder of the MJCF machine models."""


@dataclass(frozen=True)
class AxisSpec:
    """Commissioning data of one axis: machine data and servo constants (user units: mm).

    Attributes:
        config: machine data (encoder resolution must match the model's encoder).
        constants: the GT_SetConstant values written when the scene is built.
    """

    config: mcl.AxisConfig
    constants: mcl.ServoConstants


@dataclass(frozen=True)
class Machine:
    """One machine model placed in a scene.

    Attributes:
        name: prefix of its names in the scene (``"gantry"`` → ``gantry/X``).
        file: MJCF file (relative to ``models/`` or absolute).
        axes: axis name (as in the model) → commissioning data.
        pos: where the machine's origin sits in the world [m].
    """

    name: str
    file: str
    axes: Mapping[str, AxisSpec]
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    start: Mapping[str, float] = field(default_factory=dict)
    """Joint coordinates at power-up [m] (default: the model's qpos0)."""


def compose(machines: Sequence[Machine]) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Attach the machine models to an empty world and compile the result.

    Raises:
        FileNotFoundError: a model file does not exist.
        WiringError: the models cannot be combined (e.g. too many actuator groups).
    """
    os.environ.setdefault("MUJOCO_GL", "disable")  # dm_control must not look for a display
    from dm_control import mjcf

    root = mjcf.RootElement(model="scene")
    groups = 0
    for machine in machines:
        path = Path(machine.file)
        path = path if path.is_absolute() else MODELS / path
        if not path.is_file():
            raise FileNotFoundError(
                f"machine model {path} does not exist; models: "
                f"{sorted(p.name for p in MODELS.glob('*.xml'))}"
            )
        child = mjcf.from_path(str(path))
        child.model = machine.name
        for actuator in child.find_all("actuator"):
            groups += 1
            actuator.group = groups  # one drive-enable group per amplifier, unique in the scene
        if groups > 30:
            raise WiringError("at most 30 amplifiers fit in one scene (MuJoCo actuator groups)")
        frame = root.attach(child)
        frame.pos = machine.pos
    model = mujoco.MjModel.from_xml_string(root.to_xml_string(), root.get_assets())
    data = mujoco.MjData(model)
    for machine in machines:
        for axis, q in machine.start.items():
            data.joint(f"{machine.name}/{axis}").qpos[0] = q
    mujoco.mj_forward(model, data)
    return model, data


class Scene(mcl.Machine):
    """Machines in MuJoCo driven by mcl axes (one servo module per machine).

    Args:
        machines: the machines to compose.
        servo_period: servo cycle [s] (integer multiple of the model timestep).
        plc_period: PLC cycle [s] (integer multiple of the servo period).
        trace_every: record the trace every N servo cycles (0 = no trace).
    """

    def __init__(
        self,
        machines: Sequence[Machine],
        servo_period: float = 0.001,
        plc_period: float = 0.002,
        trace_every: int = 1,
    ) -> None:
        self.name = "scene"
        """The registry name (set by :func:`scenes.load`)."""
        self.machines = list(machines)
        self.model, self.data = compose(self.machines)
        wirings = [AxisWiring(f"{m.name}/{a}", f"{m.name}/") for m in self.machines for a in m.axes]
        self.plant = MujocoPlant(self.model, self.data, wirings)
        self.axes: dict[str, mcl.Axis] = {}
        self.modules: list[mcl.Module] = []
        for m in self.machines:
            members = []
            for a, spec in m.axes.items():
                io = self.plant.ios[f"{m.name}/{a}"]
                _check_resolution(io, spec, a)
                config = _with_period(spec.config, servo_period)
                axis = mcl.Axis(io, config, name=a)
                axis.set_constants(spec.constants)
                name = a if len(self.machines) == 1 else f"{m.name}/{a}"
                self.axes[name] = axis
                members.append(axis)
            self.modules.append(mcl.Module(members))
        self.runtime = mcl.Runtime(self.plant, self.axes.values(), plc_period)
        self.trace = Trace(
            self.axes,
            every=max(trace_every, 1),
            truth={n: _truth(ax.io) for n, ax in self.axes.items()},
        )
        if trace_every:
            self.runtime.observers.append(self.trace)

    def io(self, axis: str) -> MujocoAxisIO:
        """The MuJoCo channel of an axis (joint position, amplifier, switches)."""
        io = self.axes[axis].io
        assert isinstance(io, MujocoAxisIO)
        return io

    def joint_position(self, axis: str) -> float:
        """Ground-truth joint coordinate of an axis [m]."""
        return self.io(axis).position


def _truth(io: mcl.AxisIO) -> Callable[[], float]:
    assert isinstance(io, MujocoAxisIO)
    return lambda: io.position


def _with_period(config: mcl.AxisConfig, servo_period: float) -> mcl.AxisConfig:
    from dataclasses import replace

    return replace(config, servo_period=servo_period)


def _check_resolution(io: MujocoAxisIO, spec: AxisSpec, axis: str) -> None:
    model_mm = io.resolution * 1000.0
    if abs(model_mm - spec.config.resolution) > 1e-9 * model_mm:
        raise WiringError(
            f"axis {axis}: AxisConfig.resolution {spec.config.resolution} mm/count "
            f"does not match the model's encoder ({model_mm:g} mm/count)"
        )

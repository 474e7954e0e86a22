"""The MuJoCo plant: the mcl I/O boundary on a MuJoCo model (the contract is models/README.md).

Per axis a :class:`MujocoAxisIO` (an :class:`mcl.channel.AxisChannel`) reads the joint: the
encoder counts the joint coordinate through ``<axis>_lead`` with an index pulse per motor
revolution, LIM−/LIM+/REF come from switch and cam sites (on slide and hinge joints alike), the
touch probe from marks on a coordinate. :class:`MujocoPlant` builds each axis' drive
(:mod:`scenes.plant.drives`: the amplifier, a device, or none) and gives it to the channel at
construction; it steps the model: devices with state integrate before every physics step; without
devices one ``mj_step(model, data, n)`` call runs a whole servo period.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from mcl.channel import AxisChannel, Marks, Sensors
from scenes.plant.drives import (
    Device,
    DeviceDrive,
    Drive,
    DrivenDevice,
    ElectricAmplifier,
    WiringError,
)
from scenes.plant.state import MujocoState, model_identity

SWITCHES = ("lim_neg", "lim_pos", "ref")
"""The switch kinds of an axis, in the order of :attr:`MujocoAxisIO.windows`."""

__all__ = ["SWITCHES", "AxisWiring", "MujocoAxisIO", "MujocoPlant", "Probe", "WiringError"]


@dataclass(frozen=True, slots=True)
class Probe:
    """A touch-probe source: marks on a joint's coordinate, seen after a sensor delay.

    Attributes:
        marks: the marks, in the joint's SI coordinate [m or rad].
        joint: the joint the marks are on (unprefixed); None = the axis' own joint.
        delay: sensor delay between a mark and the latch [s].
        device: a device whose ``probe_coordinate()`` [m] the marks lie on instead of a joint's
            (a photo eye that sees bodies cross its beam); empty: a joint's.
    """

    marks: Marks
    joint: str | None = None
    delay: float = 0.0
    device: str = ""


@dataclass(frozen=True, slots=True)
class AxisWiring:
    """Where one axis lives in a compiled model (names already prefixed, e.g. ``gantry/X``).

    Attributes:
        axis: the axis joint's name.
        prefix: the prefix of the machine's other names (``""`` or ``"gantry/"``).
        drive: ``"electric"`` (the actuator ``<axis>_amp``), ``"device"`` (the device named
            ``device`` takes the volts) or ``"encoder"`` (no drive: a measuring wheel).
        device: the device of a ``"device"`` drive.
        switches: the switch kinds the axis has (each needs its sites and window).
        probe: the touch-probe source (None: TP stays low).
        probe_source: reads the probe's trigger coordinate from a device (:attr:`Probe.device`).
        digital_outputs: digital outputs a program may set.
        analog: reads the analog inputs [V] once per servo cycle (None: none).
        sensors: the imperfections of the axis' sensors (None: the defaults of
            :class:`mcl.channel.Sensors`).
    """

    axis: str
    prefix: str = ""
    drive: str = "electric"
    device: str = ""
    switches: tuple[str, ...] = SWITCHES
    probe: Probe | None = None
    probe_source: Callable[[], float] | None = None
    digital_outputs: int = 0
    analog: Callable[[], Sequence[float]] | None = None
    sensors: Sensors | None = None


def numeric(
    model: mujoco.MjModel, name: str, size: int, low: float = -math.inf, high: float = math.inf
) -> npt.NDArray[np.float64]:
    """A custom numeric checked for its size and range (``low < value <= high``).

    Raises:
        WiringError: missing, of the wrong size, not finite or out of range; the message names
            the numeric, the bad value and what would be valid.
    """
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, name) < 0:
        names = [model.numeric(i).name for i in range(model.nnumeric)]
        raise WiringError(f"model has no custom numeric {name!r}; it has: {names}")
    data = np.array(model.numeric(name).data, dtype=float)
    if data.size != size:
        raise WiringError(f"numeric {name!r} must have {size} values, has {data.size}")
    for value in data:
        if not (math.isfinite(value) and low < value <= high):
            raise WiringError(
                f"numeric {name!r} is {value!r}; it must be a finite number in ({low:g}, {high:g}]"
            )
    return data


def _id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    index = mujoco.mj_name2id(model, kind, name)
    if index < 0:
        count = {
            mujoco.mjtObj.mjOBJ_JOINT: model.njnt,
            mujoco.mjtObj.mjOBJ_ACTUATOR: model.nu,
            mujoco.mjtObj.mjOBJ_SITE: model.nsite,
        }[kind]
        names = [mujoco.mj_id2name(model, kind, i) for i in range(count)]
        what = kind.name.removeprefix("mjOBJ_").lower()
        raise WiringError(f"model has no {what} {name!r}; {what}s: {names}")
    return index


def _wrap(angle: float) -> float:
    """An angle in [−π, π) [rad]."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class MujocoAxisIO(AxisChannel):
    """One axis channel on a MuJoCo model; implements :class:`mcl.io.AxisIO`.

    Args:
        model, data: the compiled model and its data (positions current, e.g. after mj_forward).
        wiring: which joint and names belong to the axis.
        drive: what its outputs drive (:func:`drive_for`; None: an encoder-only axis).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        wiring: AxisWiring,
        drive: Drive | None = None,
    ) -> None:
        self.model, self.data = model, data
        p, a = wiring.prefix, wiring.axis.removeprefix(wiring.prefix)
        self.joint = _id(model, mujoco.mjtObj.mjOBJ_JOINT, wiring.axis)
        kind = int(model.jnt_type[self.joint])
        if kind not in (int(mujoco.mjtJoint.mjJNT_SLIDE), int(mujoco.mjtJoint.mjJNT_HINGE)):
            raise WiringError(f"axis joint {wiring.axis!r} must be a slide or hinge joint")
        self.rotary = kind == int(mujoco.mjtJoint.mjJNT_HINGE)
        """A hinge joint: the coordinate is an angle [rad]."""
        self.qpos_adr = int(model.jnt_qposadr[self.joint])
        self._qpos: Any = memoryview(data.qpos)  # item access without numpy scalars
        self.dof = int(model.jnt_dofadr[self.joint])
        if wiring.drive == "electric":
            self.actuator = _id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, f"{p}{a}_amp")
            """The amplifier's actuator id (an electric drive)."""
        lead = float(numeric(model, f"{p}{a}_lead", 1, 0.0)[0])
        per_rev = float(numeric(model, f"{p}{a}_counts_per_rev", 1, 0.0, 1e9)[0])
        width = float(numeric(model, f"{p}{a}_index_width", 1, 0.0, per_rev - 1)[0])
        if per_rev != round(per_rev) or width != round(width):
            raise WiringError(
                f"numerics {p}{a}_counts_per_rev and {p}{a}_index_width must be whole counts, "
                f"got {per_rev:g} and {width:g}"
            )
        self.lead = lead
        """Joint travel per motor revolution [m or rad] (one index pulse each)."""
        self.resolution = lead / per_rev
        """Joint travel per encoder count [m or rad]."""
        probe = wiring.probe
        self._probe_qpos = (
            int(model.jnt_qposadr[_id(model, mujoco.mjtObj.mjOBJ_JOINT, p + probe.joint)])
            if probe is not None and probe.joint is not None
            else None
        )
        windows = [
            self._window(p, a, kind) if kind in wiring.switches else (math.inf, -math.inf, 0.0)
            for kind in SWITCHES
        ]
        self.windows: tuple[tuple[float, float], ...] = tuple((lo, hi) for lo, hi, _ in windows)
        """Per switch kind (:data:`SWITCHES`), the window in which it is actuated: of the joint
        coordinate on a slide; on a hinge, of the angle ``wrap(q + offsets[i])`` [rad]."""
        self.offsets: tuple[float, ...] = tuple(offset for _, _, offset in windows)
        """Per switch kind, the angle from the switch to its cam at ``q = 0`` (hinge) [rad]."""
        neg, pos, ref = self.windows
        super().__init__(
            wiring.axis,
            self.resolution,
            round(per_rev),
            self.position,
            round(width),
            probe=probe.marks if probe is not None else None,
            probe_delay=probe.delay if probe is not None else 0.0,
            has_drive=wiring.drive != "encoder",
            digital_outputs=wiring.digital_outputs,
            windows=(pos, neg, ref),
            sensors=wiring.sensors,
            drive=drive,
        )
        self._analog = wiring.analog
        self._probe_source = wiring.probe_source
        self.write(0.0, False)
        self.sense(float(data.time))

    def _window(self, p: str, a: str, kind: str) -> tuple[float, float, float]:
        """Window of ``q`` in which the switch is actuated: the README formula, solved for ``q``.

        On a slide joint ``d = (cam − switch) · e`` moves one-to-one with the joint coordinate,
        so ``d = q + offset``; on a hinge ``d`` is the angle from the switch to the cam about the
        joint axis, ``d = wrap(q + offset)``. The offset comes from the current geometry.
        """
        model = self.model
        cam = _id(model, mujoco.mjtObj.mjOBJ_SITE, f"{p}{a}_{kind}_cam")
        switch = _id(model, mujoco.mjtObj.mjOBJ_SITE, f"{p}{a}_{kind}")
        lo, hi = numeric(model, f"{p}{a}_{kind}_window", 2)
        if not lo <= hi:
            raise WiringError(f"numeric {p}{a}_{kind}_window must be [lo, hi] with lo <= hi")
        d = self.site_distance(switch, cam)
        if self.rotary:
            return float(lo), float(hi), _wrap(d - self.position)
        offset = d - self.position
        return float(lo - offset), float(hi - offset), 0.0

    def site_distance(self, switch: int, cam: int) -> float:
        """The switch formula's ``d`` for two sites at the current positions [m or rad]."""
        data = self.data
        e = data.xaxis[self.joint]
        if not self.rotary:
            return float((data.site_xpos[cam] - data.site_xpos[switch]) @ e)
        anchor = data.xanchor[self.joint]
        s = data.site_xpos[switch] - anchor
        c = data.site_xpos[cam] - anchor
        s = s - (s @ e) * e
        c = c - (c @ e) * e
        return float(math.atan2(float(np.cross(s, c) @ e), float(s @ c)))

    @property
    def position(self) -> float:
        """Joint coordinate [m or rad] (ground truth)."""
        q: float = self._qpos[self.qpos_adr]
        return q

    def sense(self, t: float) -> None:
        """Sample encoder, switches, probe and analog inputs at time ``t`` [s]."""
        qpos = self._qpos
        q: float = qpos[self.qpos_adr]
        if self.rotary:
            offsets = self.offsets
            n, pos, r = _wrap(q + offsets[0]), _wrap(q + offsets[1]), _wrap(q + offsets[2])
        else:
            n = pos = r = q
        self.sample(
            t,
            q,
            pos,
            n,
            r,
            self._probe_coordinate(qpos),
            () if self._analog is None else self._analog(),
        )

    def _probe_coordinate(self, qpos: Any) -> float | None:
        """The probe's trigger coordinate: a device's, a joint's, or None (the axis')."""
        if self._probe_source is not None:
            return self._probe_source()
        return None if self._probe_qpos is None else float(qpos[self._probe_qpos])


def drive_for(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    wiring: AxisWiring,
    devices: Mapping[str, Device],
) -> Drive | None:
    """The drive of an axis: its amplifier ``<axis>_amp`` (``"electric"``), the device that
    takes its volts (``"device"``) or none (``"encoder"``).

    Raises:
        WiringError: the model or the devices lack what the drive needs (the message says what).
    """
    if wiring.drive == "encoder":
        return None
    if wiring.drive == "device":
        device = devices.get(wiring.device)
        if device is None or not hasattr(device, "apply"):
            raise WiringError(
                f"axis {wiring.axis}: drive 'device' needs a device named {wiring.device!r} "
                f"that takes volts (apply); devices: {sorted(devices)}"
            )
        driven: DrivenDevice = device  # type: ignore[assignment]
        return DeviceDrive(driven)
    if wiring.drive != "electric":
        raise WiringError(
            f"axis {wiring.axis}: drive must be 'electric', 'device' or 'encoder', "
            f"got {wiring.drive!r}"
        )
    amp = f"{wiring.axis}_amp"
    actuator = _id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, amp)
    lo, hi = model.actuator_ctrlrange[actuator]
    if not (model.actuator_ctrllimited[actuator] and lo <= -10.0 and hi >= 10.0):
        raise WiringError(f"actuator {amp} must have ctrlrange -10 10 (volts), has {lo:g} {hi:g}")
    for i, name in enumerate(("gain", "bias")):
        prm = (model.actuator_gainprm if i == 0 else model.actuator_biasprm)[actuator][:3]
        if not np.all(np.isfinite(prm)):
            raise WiringError(f"actuator {amp}: {name}prm {prm} must be finite")
    dof = int(model.jnt_dofadr[_id(model, mujoco.mjtObj.mjOBJ_JOINT, wiring.axis)])
    if not math.isfinite(float(model.dof_armature[dof])):
        raise WiringError(f"joint {wiring.axis}: armature must be finite")
    brake = f"{wiring.axis}_brake_force"
    has_brake = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, brake) >= 0
    force = float(numeric(model, brake, 1, 0.0)[0]) if has_brake else 0.0
    return ElectricAmplifier(model, data, actuator, dof, force)


class Joint:
    """Ground truth of one joint of a model, cheap enough to read every servo cycle.

    Args:
        model, data: the compiled model and its data.
        name: the joint's full name (with the machine's prefix).

    Raises:
        WiringError: the model has no such joint.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, name: str) -> None:
        j = _id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        self.name = name
        self.qpos_adr = int(model.jnt_qposadr[j])
        self.dof_adr = int(model.jnt_dofadr[j])
        self._qpos: Any = memoryview(data.qpos)  # item access without numpy scalars
        self._qvel: Any = memoryview(data.qvel)

    @property
    def position(self) -> float:
        """Joint coordinate [m or rad]."""
        q: float = self._qpos[self.qpos_adr]
        return q

    @property
    def velocity(self) -> float:
        """Joint velocity [m/s or rad/s]."""
        v: float = self._qvel[self.dof_adr]
        return v


class MujocoPlant:
    """Steps a MuJoCo model; implements :class:`mcl.runtime.Plant`.

    Args:
        model, data: the compiled model and its data.
        wirings: the axes to expose as :class:`MujocoAxisIO` channels.
        devices: Python devices integrated before every physics step, by name.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        wirings: Sequence[AxisWiring],
        devices: Mapping[str, Device] | None = None,
    ) -> None:
        self.model, self.data = model, data
        self.timestep = float(model.opt.timestep)
        if not (math.isfinite(self.timestep) and self.timestep > 0.0):
            raise WiringError(f"model timestep must be > 0 s, got {self.timestep}")
        self.devices = dict(devices or {})
        self._hooks = [d.before_step for d in self.devices.values()]
        mujoco.mj_forward(model, data)
        self.ios: dict[str, MujocoAxisIO] = {}
        self._drives: list[Drive | None] = []
        """Every axis' drive, in the order of the axes (their state is the plant's)."""
        for wiring in wirings:
            drive = drive_for(model, data, wiring, self.devices)
            self.ios[wiring.axis] = MujocoAxisIO(model, data, wiring, drive)
            self._drives.append(drive)
        self._channels = list(self.ios.values())
        self._spec = mujoco.mjtState.mjSTATE_INTEGRATION
        self._time = 0.0
        """``data.time`` [s], read once after each step or restore (it changes only there; the
        runtime and then every channel ask for it each servo cycle, and a read through the
        bindings is costly)."""
        self._time_read = False

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        if not self._time_read:
            self._time = float(self.data.time)
            self._time_read = True
        return self._time

    def step(self, n: int = 1) -> None:
        """``n`` physics steps; each device integrates before every step."""
        model, data = self.model, self.data
        hooks = self._hooks
        step = mujoco.mj_step
        if not hooks:
            step(model, data, n)
        else:
            for _ in range(n):
                for hook in hooks:
                    hook(model, data)
                step(model, data)
        self._time_read = False

    def sense(self) -> None:
        """Sample every axis' inputs."""
        t = self.time
        for io in self._channels:
            io.sense(t)

    def identity(self) -> tuple[str, ...]:
        """What a state must match to be restored here: the model (:func:`model_identity`)."""
        return (model_identity(self.model),)

    def get_state(self) -> MujocoState:
        """The physics state with everything Python adds to it (read-only copies)."""
        return MujocoState.of(self)

    def set_state(self, state: MujocoState) -> None:
        """Restore a state taken with :meth:`get_state` (then ``mj_forward``)."""
        state.restore(self)

    def arrays(self) -> list[npt.NDArray[np.float64]]:
        """The integration state of ``data``, then every drive's and every device's state
        (copies)."""
        size = mujoco.mj_stateSize(self.model, self._spec)
        physics = np.empty(size)
        mujoco.mj_getState(self.model, self.data, physics, self._spec)
        drives = [d.get_state() if d is not None else np.zeros(0) for d in self._drives]
        return [physics, *drives, *(d.get_state() for d in self.devices.values())]

    def set_arrays(self, arrays: Sequence[npt.NDArray[np.float64]]) -> None:
        """Restore arrays taken with :meth:`arrays` (then ``mj_forward``)."""
        physics, *rest = arrays
        mujoco.mj_setState(self.model, self.data, physics, self._spec)
        drives = self._drives
        for drive, drive_state in zip(drives, rest[: len(drives)], strict=True):
            if drive is not None:
                drive.set_state(drive_state)
        for device, device_state in zip(self.devices.values(), rest[len(drives) :], strict=True):
            device.set_state(device_state)
        mujoco.mj_forward(self.model, self.data)
        self._time_read = False

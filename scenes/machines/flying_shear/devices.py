"""The flying shear's devices, integrated before every physics step (compiled with the plant
where a C compiler exists): the eccentric pinch roll (line-speed ripple), the knife's valve,
cylinder and grip on the strip, and the recorder that takes every cut from the physics. The
measuring wheel and its errors are the web line's (:mod:`scenes.parts.measuring_wheel`). The
machine definition and the PLC program are in :mod:`scenes.machines.flying_shear`.
"""

from __future__ import annotations

__all__ = [
    "CUT_FIELDS",
    "MARKS",
    "MARK_FIRST",
    "MARK_PITCH",
    "PRINT_ERRORS",
    "TOUCH",
    "Cut",
    "CutRecorder",
    "EccentricRoll",
    "KnifeCylinder",
    "blade_down",
    "cut_of",
    "cut_values",
    "mark_at",
]

import math
import random
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

import mcl
from scenes.parts.measuring_wheel import RollingCoupling
from scenes.plant.mujoco import MujocoAxisIO, numeric

MARK_PITCH = 1.5
"""Print-mark pitch on the strip [m] (one mark per piece)."""
MARK_FIRST = 2.0
"""Strip travel M [m] at which the first mark passes the sensor."""
PRINT_ERRORS = tuple(round(random.Random(10).uniform(-3e-4, 3e-4), 6) for _ in range(64))
"""Print error of each mark [m] (±0.3 mm, seeded), cycled over the marks."""
MARKS = mcl.Marks(first=MARK_FIRST, pitch=MARK_PITCH, width=0.005, errors=PRINT_ERRORS)
"""The print marks on the strip coordinate M: mark k passes the sensor at
``M = first + k·pitch + error_k``; 5 mm long."""


def mark_at(marks: mcl.Marks, k: int) -> float:
    """Strip travel M [m] at which mark ``k`` passes the mark sensor."""
    error = marks.errors[k % len(marks.errors)] if marks.errors else 0.0
    return marks.first + k * marks.pitch + error


# ---------------------------------------------------------------------------------- devices
class EccentricRoll:
    """The driven pinch roll is eccentric: strip speed = r·(1 + e·sin(n·L))·L̇, the line-speed
    ripple (±e, n times per roll turn: 2.08 Hz at 60 m/min for n = 1).

    The roll drives the strip through the equality ``pinch`` (``M = a0 + a1·L``, a
    :class:`RollingCoupling`); before every step its slope becomes the roll's effective radius
    at its angle. ``eccentricity`` and ``per_turn`` may change at any time.

    Args:
        model, data: the compiled model and its data (positions current).
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.radius = float(numeric(model, f"{prefix}L_radius", 1, 0.0)[0])
        self.eccentricity = float(numeric(model, f"{prefix}L_eccentricity", 1, -1.0, 0.5)[0])
        """Relative amplitude of the speed ripple [-] (0.01 = ±1 %)."""
        self.per_turn = 1
        """Ripple periods per roll turn (1: an eccentric roll, 2: an oval one)."""
        self._roll = int(model.joint(f"{prefix}L").qposadr[0])
        self._qpos: Any = memoryview(data.qpos)
        strip = float(data.qpos[int(model.joint(f"{prefix}M").qposadr[0])])
        q = self._angle()
        self.pinch = RollingCoupling(model, f"{prefix}pinch", self._radius_at(q), strip, q)
        """The strip's travel on the roll's angle."""

    def _angle(self) -> float:
        angle: float = self._qpos[self._roll]
        return angle

    def _radius_at(self, angle: float) -> float:
        """The roll's effective radius at its angle [m]."""
        return self.radius * (1.0 + self.eccentricity * math.sin(self.per_turn * angle))

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """New slope at the roll's angle, offset kept continuous."""
        q = self._angle()
        self.pinch.slope(self._radius_at(q), q)

    def get_state(self) -> npt.NDArray[np.float64]:
        pinch = self.pinch
        return np.array([pinch.a0, pinch.a1, self.eccentricity, float(self.per_turn)])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        pinch = self.pinch
        pinch.a0, pinch.a1, self.eccentricity = (float(v) for v in state[:3])
        self.per_turn = round(float(state[3]))
        pinch.write()


TOUCH = 1.0e-5
"""The blade touches the strip within this distance above ``K_contact`` [m]."""


def blade_down(knife: float, contact: float) -> bool:
    """The blade is down on the strip: knife coordinate ``knife`` at most ``TOUCH`` above the
    contact coordinate ``contact`` [m]."""
    return knife <= contact + TOUCH


class KnifeCylinder:
    """The knife: directional valve, hydraulic cylinder and the blade's grip on the strip.

    Digital output 0 of the carriage axis ``S`` switches the valve (True = knife down). The
    valve follows after a dead time ``K_valve_delay`` with a first-order spool lag
    ``K_valve_tau``; the cylinder pushes with ``spool · K_force − c·v`` (down for +1), the flow
    through the valve limiting the stroke speed to ``K_speed`` (``c = K_force/K_speed``).

    While the blade is down on the strip (``K <= K_contact``; MuJoCo's contact carries the
    normal force) it grips the strip along the line: a stiff spring-damper between carriage and
    strip (``K_grip`` = friction coefficient μ, stiffness [N/m], damping [N·s/m]) that slips
    when its force exceeds μ·(cylinder force + knife weight). Its force acts on the strip and,
    opposite, on the carriage: an unsynchronised cut drags both. :attr:`drag` is that force on
    the strip [N] (+ = pulled downstream).

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.prefix = prefix
        self.force = float(numeric(model, f"{prefix}K_force", 1, 0.0)[0])
        self.delay = float(numeric(model, f"{prefix}K_valve_delay", 1, -1e-12)[0])
        self.tau = float(numeric(model, f"{prefix}K_valve_tau", 1, 0.0)[0])
        self.flow = self.force / float(numeric(model, f"{prefix}K_speed", 1, 0.0)[0])
        """Flow resistance of the valve [N·s/m]."""
        self.contact = float(numeric(model, f"{prefix}K_contact", 1, -1.0, 0.0)[0])
        mu, stiffness, damping = numeric(model, f"{prefix}K_grip", 3, 0.0)
        self.mu, self.stiffness, self.damping = float(mu), float(stiffness), float(damping)
        knife = model.joint(f"{prefix}K")
        self.weight = float(model.body_subtreemass[knife.bodyid[0]] * -model.opt.gravity[2])
        """Weight of the knife [N] (it presses on the strip too)."""
        self._decay = 1.0 - math.exp(-float(model.opt.timestep) / self.tau)
        self._k_dof, self._k_qpos = int(knife.dofadr[0]), int(knife.qposadr[0])
        carriage, strip = model.joint(f"{prefix}S"), model.joint(f"{prefix}M")
        self._s_dof, self._s_qpos = int(carriage.dofadr[0]), int(carriage.qposadr[0])
        self._m_dof, self._m_qpos = int(strip.dofadr[0]), int(strip.qposadr[0])
        self._force: Any = memoryview(data.qfrc_applied)
        self._qpos: Any = memoryview(data.qpos)
        self._qvel: Any = memoryview(data.qvel)
        self.outputs: list[bool] = []
        """The carriage channel's digital outputs (set by :meth:`connect`)."""
        self.command = False
        """The output as the valve last saw it."""
        self.changed = -math.inf
        """When the output last changed [s]."""
        self.spool = -1.0
        """Spool position: −1 knife up … +1 knife down."""
        self.engaged = False
        """The blade is down on the strip."""
        self.anchor = 0.0
        """Carriage minus strip travel at which the grip spring is relaxed [m]."""
        self.drag = 0.0
        """Force of the blade on the strip along the line [N] (+ = downstream)."""

    def connect(self, ios: Mapping[str, MujocoAxisIO]) -> None:
        """Wire the valve to digital output 0 of the carriage channel."""
        self.outputs = ios[f"{self.prefix}S"].outputs

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Valve dead time and spool lag, the cylinder force, the blade's grip."""
        t = float(data.time)
        command = bool(self.outputs and self.outputs[0])
        if command != self.command:
            self.command, self.changed = command, t
        settled = t - self.changed >= self.delay  # else the valve still holds the old side
        down = self.command if settled else not self.command
        self.spool += ((1.0 if down else -1.0) - self.spool) * self._decay
        qpos, qvel, force = self._qpos, self._qvel, self._force
        force[self._k_dof] = -self.spool * self.force - self.flow * qvel[self._k_dof]
        engaged = blade_down(qpos[self._k_qpos], self.contact)
        if not engaged:
            if self.engaged:
                self.engaged, self.drag = False, 0.0
                force[self._s_dof] = force[self._m_dof] = 0.0
            return
        relative = qpos[self._s_qpos] - qpos[self._m_qpos]
        if not self.engaged:
            self.engaged, self.anchor = True, relative
        limit = self.mu * max(0.0, self.spool * self.force + self.weight)
        drag = self.stiffness * (relative - self.anchor) + self.damping * (
            qvel[self._s_dof] - qvel[self._m_dof]
        )
        if abs(drag) > limit:  # the blade slips: the spring stays at the friction limit
            drag = math.copysign(limit, drag)
            self.anchor = relative - drag / self.stiffness
        self.drag = drag
        force[self._m_dof] = drag
        force[self._s_dof] = -drag

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array(
            [float(self.command), self.changed, self.spool, float(self.engaged), self.anchor]
        )

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        self.command, self.changed, self.spool = bool(state[0]), float(state[1]), float(state[2])
        self.engaged, self.anchor = bool(state[3]), float(state[4])
        self.drag = 0.0


# ---------------------------------------------------------------------------------- cuts
@dataclass
class Cut:
    """One cut, measured from the physics while the blade touched the strip.

    Attributes:
        time: first contact of the blade with the strip [s].
        position: material coordinate of the cut [mm]: distance from the strip's origin,
            counted upstream (a later cut lies further upstream, so lengths are positive).
        length: piece length from the previous cut [mm] (None for the first cut).
        mark: distance of the cut from the nearest print mark [mm] (+ = upstream of it).
        contact: how long the blade touched the strip [s].
        slide: how far the blade moved along the strip while touching it [mm] (max − min of
            the material coordinate under the knife).
        speed_mismatch: largest |carriage − strip velocity| / strip velocity while touching
            [-].
        drag: largest |force of the blade on the strip along the line| [N].
    """

    time: float
    position: float
    length: float | None = None
    mark: float = math.nan
    contact: float = 0.0
    slide: float = 0.0
    speed_mismatch: float = 0.0
    drag: float = 0.0
    _low: float = field(default=math.inf, repr=False)
    _high: float = field(default=-math.inf, repr=False)


CUT_FIELDS = (
    "time",
    "position",
    "length",
    "mark",
    "contact",
    "slide",
    "speed_mismatch",
    "drag",
    "_low",
    "_high",
)
"""The fields of a :class:`Cut` in a recorder's state, in order."""


def cut_values(cut: Cut) -> list[float]:
    """A cut's :data:`CUT_FIELDS` as numbers (no length: NaN)."""
    length = math.nan if cut.length is None else cut.length
    return [
        cut.time,
        cut.position,
        length,
        cut.mark,
        cut.contact,
        cut.slide,
        cut.speed_mismatch,
        cut.drag,
        cut._low,
        cut._high,
    ]


def cut_of(values: list[float]) -> Cut:
    """The cut of numbers made by :func:`cut_values`."""
    time, position, length, mark, contact, slide, mismatch, drag, low, high = values
    return Cut(
        time,
        position,
        None if math.isnan(length) else length,
        mark,
        contact,
        slide,
        mismatch,
        drag,
        low,
        high,
    )


class CutRecorder:
    """Records every cut from the physics; a device (it looks before every physics step).

    A cut begins when the blade comes down on the strip and ends when it leaves it
    (:func:`blade_down`); its position is the material coordinate under the knife edge then,
    ``s = c + M − S`` (``c`` from the geometry at load: the knife moves with S along the line);
    the drag is the blade's grip force on the strip (what the knife device applies to M).

    Args:
        model, data: the compiled model and its data (positions current).
        prefix: the machine's name prefix in the model.
        marks: the print marks (on the strip coordinate M, as seen at the mark sensor).
    """

    def __init__(
        self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "", marks: mcl.Marks = MARKS
    ) -> None:
        self.marks = marks
        self.contact = float(numeric(model, f"{prefix}K_contact", 1, -1.0, 0.0)[0])
        strip, carriage = model.joint(f"{prefix}M"), model.joint(f"{prefix}S")
        self._k = int(model.joint(f"{prefix}K").qposadr[0])
        self._m, self._m_dof = int(strip.qposadr[0]), int(strip.dofadr[0])
        self._s, self._s_dof = int(carriage.qposadr[0]), int(carriage.dofadr[0])
        self._qpos: Any = memoryview(data.qpos)
        self._qvel: Any = memoryview(data.qvel)
        self._force: Any = memoryview(data.qfrc_applied)
        scratch = mujoco.MjData(model)  # kinematics of the current positions
        scratch.qpos[:] = data.qpos
        mujoco.mj_kinematics(model, scratch)
        e = scratch.xaxis[strip.id]
        body = scratch.xpos[model.body(f"{prefix}strip").id]
        m, q = float(data.qpos[self._m]), float(data.qpos[self._s])
        edge = scratch.site_xpos[model.site(f"{prefix}knife_edge").id]
        sensor = scratch.site_xpos[model.site(f"{prefix}mark_sensor").id]
        self.knife_offset = float((body - edge) @ e) - m + q
        """Material coordinate under the knife edge minus (M − S) [m] (a constant)."""
        self.sensor_offset = float((body - sensor) @ e) - m
        """Material coordinate under the mark sensor minus M [m] (a constant)."""
        self.cuts: list[Cut] = []
        self.current: Cut | None = None
        """The cut in progress (blade on the strip)."""

    def knife_position(self) -> float:
        """Material coordinate under the knife edge now [m]."""
        return self.knife_offset + self._qpos[self._m] - self._qpos[self._s]

    def mark_position(self, k: int) -> float:
        """Material coordinate [m] of print mark ``k``."""
        return self.sensor_offset + mark_at(self.marks, k)

    def nearest_mark(self, position: float) -> float:
        """Material coordinate [m] of the print mark nearest to ``position`` [m]."""
        pitch = self.marks.pitch or 1.0
        k0 = round((position - self.mark_position(0)) / pitch)
        return min(
            (self.mark_position(k) for k in range(max(0, k0 - 1), k0 + 2)),
            key=lambda m: abs(m - position),
        )

    @property
    def last_piece(self) -> float:
        """Length of the last piece [mm] (NaN before the second cut)."""
        last = self.cuts[-1].length if self.cuts else None
        return math.nan if last is None else last

    @property
    def last_mark(self) -> float:
        """Distance of the last cut from its print mark [mm] (NaN before the first cut)."""
        return self.cuts[-1].mark if self.cuts else math.nan

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Observe the state the coming step starts from."""
        cut = self.current
        if not blade_down(self._qpos[self._k], self.contact):
            if cut is not None:
                self._finish(cut, float(data.time))
            return
        position = self.knife_position()
        if cut is None:
            cut = self.current = Cut(time=float(data.time), position=position * 1000.0)
        v_strip: float = self._qvel[self._m_dof]
        v_carriage: float = self._qvel[self._s_dof]
        if v_strip:
            cut.speed_mismatch = max(cut.speed_mismatch, abs(v_carriage - v_strip) / abs(v_strip))
        cut.drag = max(cut.drag, abs(self._force[self._m_dof]))
        cut._low, cut._high = min(cut._low, position), max(cut._high, position)

    def _finish(self, cut: Cut, t: float) -> None:
        cut.contact = t - cut.time
        cut.slide = (cut._high - cut._low) * 1000.0
        if self.cuts:
            cut.length = cut.position - self.cuts[-1].position
        cut.mark = (cut.position / 1000.0 - self.nearest_mark(cut.position / 1000.0)) * 1000.0
        self.cuts.append(cut)
        self.current = None

    def get_state(self) -> npt.NDArray[np.float64]:
        """Every cut so far and the one in progress, flat: a flag (a cut is in progress), then
        each cut's fields (:func:`cut_values`)."""
        cuts = [*self.cuts, *([self.current] if self.current is not None else [])]
        return np.array(
            [float(self.current is not None), *(x for c in cuts for x in cut_values(c))]
        )

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        """Return to the cuts of a state taken with :meth:`get_state`."""
        values = [float(v) for v in state]
        n = len(CUT_FIELDS)
        cuts = [cut_of(values[i : i + n]) for i in range(1, len(values), n)]
        self.current = cuts.pop() if values[0] else None
        self.cuts = cuts

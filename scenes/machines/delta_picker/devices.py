"""The delta picker's devices.

- The vacuum gripper: digital output 0 of arm ``A1`` opens the vacuum valve; the cup holds a
  part by the force the model's adhesion actuator ``vacuum`` applies where the cup touches it
  (the cup's pull, ``cup_force``), and loses it when the part's inertia and weight ask for more.
  Every grip is recorded with the pick error measured on the physics: the cup's centre against
  the part's centre when the vacuum comes on.
- The photo eye: a beam across the belt that sees the parts' bodies (:class:`PhotoEye`), the
  touch probe of the conveyor ``C``; a light curtain beside it measures each part's lateral
  position.
- The belt: its top run stays over the conveyor's frame while the belt moves (:class:`Belt`).
- The feeder: parts taken from the tray, and parts that fell off the belt's end, come back on the
  belt at random spacing and lateral position (:class:`Feeder`).
"""

from __future__ import annotations

__all__ = ["BEAM", "Belt", "Feeder", "Grip", "PhotoEye", "VacuumGripper"]

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

import mcl
from scenes.plant.mujoco import MujocoAxisIO, numeric

HOLD = 0.005
"""A part counts as held while its top face lies within this of the cup's face [m]."""
PART_LENGTH = 0.060
"""A part's length along the belt [m]."""
SPACING = (0.240, 0.370)
"""The range of the random distance between consecutive parts' centres [m]."""
LATERAL = 0.025
"""The parts' random lateral offset from the belt's centre line lies within ±this [m] (the belt
is 180 mm wide, a part 60 mm)."""
UPSTREAM = 0.4
"""A part is laid at least this far before the photo eye [m]."""
SEED = 37
"""The seed of the parts' random spacing and lateral position."""
BEAM = mcl.Marks(first=0.0, width=0.2)
"""The touch probe's mark on the eye's trigger coordinate (:meth:`PhotoEye.probe_coordinate`):
high while a part's body covers the beam."""
TAKEN = 1.0
"""The outfeed takes a part away this long after it came to rest in the tray [s]."""
CHECK = 0.01
"""How often the outfeed looks at the tray [s]."""
FALLEN = 0.1
"""A part whose centre lies this far below the belt's top has fallen off the belt [m]."""


def _random(j: int) -> tuple[float, float]:
    """Part ``j``'s spacing behind the part before it and its lateral offset [m]."""
    rng = np.random.default_rng(SEED * 1000 + j)
    return float(rng.uniform(*SPACING)), float(rng.uniform(-LATERAL, LATERAL))


def _box_parts(model: mujoco.MjModel, prefix: str) -> list[tuple[int, npt.NDArray[np.float64]]]:
    """The parts ``part0`` … : body id and the half sizes of their box [m]."""
    parts = []
    k = 0
    while mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{prefix}part{k}") >= 0:
        body = model.body(f"{prefix}part{k}")
        parts.append((int(body.id), np.array(model.geom_size[int(body.geomadr[0])])))
        k += 1
    return parts


class PhotoEye:
    """A through-beam across the belt at ``eye_x``, 5 mm above the belt's top: it is cut while a
    part's body (its box, as turned) spans the beam's x and lies on the belt.

    Its trigger coordinate (:meth:`probe_coordinate`) is how far the leading edge of the part
    nearest the beam and not yet past it has crossed the beam [m] (negative before); the touch
    probe of ``C`` (mark :data:`BEAM`) latches the belt's encoder where it rises through 0. A
    light curtain beside the beam measures the part's lateral position when the beam is cut
    (:attr:`lateral`, the centre's y in the MCS [mm]), as a camera over the belt would.

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.eye_x = float(numeric(model, f"{prefix}eye_x", 1)[0])
        self.belt_top = float(numeric(model, f"{prefix}belt_top", 1)[0])
        mujoco.mj_kinematics(model, data)
        self.belt_y = float(data.xpos[model.body(f"{prefix}belt").id][1])
        self._parts = _box_parts(model, prefix)
        slides = [
            int(model.joint(f"{prefix}part{k}_x").qposadr[0]) for k in range(len(self._parts))
        ]
        self._slides = np.array([[q, q + 1, q + 2] for q in slides], dtype=np.intp)
        """The qpos addresses of each part's slides x, y, z."""
        self._base = (
            np.array([data.xpos[body] for body, _ in self._parts]) - data.qpos[self._slides]
        )
        """Each part's centre at zero slides [m]: its centre now is this plus its slides' qpos
        (``xpos`` is that of the step before: a part at 1 m/s lies 0.5 mm further on)."""
        self._data = data
        self.lateral: list[float] = []
        """Each part's lateral position when it cut the beam, in order [mm, MCS y]."""
        self._seen = -1
        """The body that cuts the beam (-1: the beam is free)."""

    def _cut(self) -> tuple[int, float, float]:
        """The part nearest the beam not yet past it: body, leading edge past the beam [m] (-1
        when none) and its centre's y [m]."""
        data = self._data
        best, lead, y = -1, -1.0, 0.0
        centres = (self._base + data.qpos[self._slides]).tolist()
        for (body, half), centre in zip(self._parts, centres, strict=True):
            if abs(centre[2] - half[2] - self.belt_top) > 0.005:
                continue  # not on the belt (held by the cup, in the tray)
            if abs(centre[1] - self.belt_y) > 0.09:
                continue
            turn = np.abs(data.xmat[body].reshape(3, 3)[0])
            extent = float(turn @ half)
            front = centre[0] + extent - self.eye_x
            if front - 2.0 * extent > 0.0:
                continue  # its trailing edge is past the beam
            if best < 0 or front > lead:
                best, lead, y = body, front, centre[1]
        return best, lead, y

    def probe_coordinate(self) -> float:
        """The trigger coordinate of the touch probe [m] (class docstring)."""
        return self._cut()[1]

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Measure a part's lateral position when it cuts the beam (once per pass: a part the
        feeder lays on the belt again is measured again when it comes back)."""
        body, lead, y = self._cut()
        if lead < 0.0:
            self._seen = -1  # the beam is free (no part is near it: lead -1)
        elif body != self._seen:
            self._seen = body
            self.lateral.append(1000.0 * y)

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array([len(self.lateral), self._seen], dtype=float)

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        del self.lateral[int(state[0]) :]
        self._seen = int(state[1])


@dataclass(frozen=True)
class Grip:
    """One grip: when [s], which part, the cup's centre against the part's centre in the
    horizontal plane and along z (cup face against the part's top face) [mm]."""

    time: float
    part: int
    error: float
    height: float


class VacuumGripper:
    """The vacuum valve and cup (module docstring).

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self.prefix = prefix
        self.force = float(numeric(model, f"{prefix}cup_force", 1, 0.0)[0])
        self._actuator = int(model.actuator(f"{prefix}vacuum").id)
        self._tool = int(model.site(f"{prefix}tool").id)
        parts = []
        k = 0
        while mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{prefix}part{k}") >= 0:
            body = model.body(f"{prefix}part{k}")
            geom = int(body.geomadr[0])
            parts.append((int(body.id), float(model.geom_size[geom][2])))
            k += 1
        self._parts = parts
        self._data = data
        self.outputs: list[bool] = []
        """The A1 channel's digital outputs (set by :meth:`connect`)."""
        self.on = False
        """The vacuum valve is open."""
        self.held = -1
        """The part the cup holds (-1: none)."""
        self.grips: list[Grip] = []
        """Every grip, oldest first."""
        self.lost = 0
        """Parts the cup lost while the vacuum was on."""

    def connect(self, ios: Mapping[str, MujocoAxisIO]) -> None:
        """Wire the valve to digital output 0 of the arm A1's channel."""
        self.outputs = ios[f"{self.prefix}A1"].outputs

    def part_position(self, k: int) -> npt.NDArray[np.float64]:
        """Centre of part ``k`` in the world [m]."""
        return np.array(self._data.xpos[self._parts[k][0]])

    def _nearest(self, data: mujoco.MjData) -> tuple[int, float, float]:
        """The part under the cup: its number, horizontal and vertical distance [m]."""
        tool = data.site_xpos[self._tool]
        best, best_xy, best_z = -1, math.inf, math.inf
        for k, (body, half) in enumerate(self._parts):
            centre = data.xpos[body]
            xy = math.hypot(centre[0] - tool[0], centre[1] - tool[1])
            if xy < best_xy:
                best, best_xy, best_z = k, xy, float(tool[2] - (centre[2] + half))
        return best, best_xy, best_z

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Open or close the valve; record a grip; notice a part lost."""
        command = bool(self.outputs and self.outputs[0])
        if command != self.on:
            self.on = command
            if command:
                k, xy, z = self._nearest(data)
                if k >= 0 and abs(z) <= HOLD and xy <= 0.03:
                    self.held = k
                    self.grips.append(Grip(float(data.time), k, 1000.0 * xy, 1000.0 * z))
            else:
                self.held = -1
        data.ctrl[self._actuator] = 1.0 if command else 0.0
        if self.on and self.held >= 0:
            body, half = self._parts[self.held]
            gap = data.site_xpos[self._tool][2] - (data.xpos[body][2] + half)
            if abs(gap) > HOLD:
                self.lost += 1
                self.held = -1

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.array([float(self.on), float(self.held), float(self.lost), len(self.grips)])

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        self.on, self.held, self.lost = bool(state[0]), int(state[1]), int(state[2])
        del self.grips[int(state[3]) :]


class Belt:
    """The conveyor's top run: the collision box ``belt_geom`` of the body on the slide ``C``
    is held where the conveyor's frame is (its place at C = 0) however far the belt has moved,
    so the belt never runs out and a part that rides past its end falls off there. The parts
    ride on it at the body's velocity: friction acts on the velocity of the body at the contact,
    not on where the box lies in it. The box is hidden (group 3); the static ``belt_top_run``
    shows it.

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        self._q = int(model.joint(f"{prefix}C").qposadr[0])
        self._pos = model.geom_pos[int(model.geom(f"{prefix}belt_geom").id)]
        """The box's place in its body (a view into the model) [m]."""
        self._home = float(self._pos[0])
        """Its place in the body when C is 0: the model's [m]."""
        self._data = data
        self._place()

    def _place(self) -> None:
        """Put the box back by the distance the belt has moved."""
        self._pos[0] = self._home - self._data.qpos[self._q]

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Hold the box in place for the coming step."""
        self._place()

    def get_state(self) -> npt.NDArray[np.float64]:
        return np.zeros(0)

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        self._place()  # the plant restored C's position before


class Feeder:
    """The infeed and outfeed: a part at rest in the tray for :data:`TAKEN` is taken away, a
    part that fell off the belt (:data:`FALLEN` below its top: off its end, not picked) is
    taken from the bin under it, and each comes back on the belt as the next part of the
    infeed, moving with the belt, its centre a random :data:`SPACING` behind the part laid
    before it (never less than :data:`UPSTREAM` before the photo eye) and a random lateral
    offset within ±:data:`LATERAL` of the centre line (seeded by its sequence number; the
    model's parts start at ``part_x``, each with its lateral offset).

    Args:
        model, data: the compiled model and its data.
        prefix: the machine's name prefix in the model.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, prefix: str = "") -> None:
        part_x = tuple(float(x) for x in numeric(model, f"{prefix}part_x", 8))
        eye_x = float(numeric(model, f"{prefix}eye_x", 1)[0])
        self.eye_x = eye_x
        self.belt_top = float(numeric(model, f"{prefix}belt_top", 1)[0])
        belt = model.joint(f"{prefix}C")
        self._belt_q, self._belt_v = int(belt.qposadr[0]), int(belt.dofadr[0])
        tray = int(model.geom(f"{prefix}tray").id)
        mujoco.mj_kinematics(model, data)
        self._tray_y = float(data.geom_xpos[tray][1])
        self._tray_z = float(data.geom_xpos[tray][2])
        self._due = 0.0
        """When the tray is looked at next [s]."""
        self._parts = []
        for k in range(len(part_x)):
            x = model.joint(f"{prefix}part{k}_x")
            body = model.body(f"{prefix}part{k}")
            self._parts.append((int(x.qposadr[0]), int(x.dofadr[0]), int(body.id)))
            data.qpos[int(x.qposadr[0]) + 1] = _random(k)[1]
        self.next = list(range(len(part_x)))
        """The sequence number each part has on the belt now."""
        self.laid = len(part_x)
        """How many parts were laid on the belt (the model's included)."""
        self.rest = [-1.0] * len(part_x)
        """Since when each part lies at rest in the tray [s] (-1: it does not)."""
        self._last = eye_x - min(part_x)
        """Belt coordinate at which the centre of the part laid last reaches the eye [m]."""
        self._origin = [np.array(model.body_pos[body]) for _, _, body in self._parts]
        self.fallen = 0
        """Parts taken from under the belt."""

    def _in_tray(self, data: mujoco.MjData, body: int, dof: int) -> bool:
        """Part ``body`` lies still over the tray."""
        if abs(data.xpos[body][1] - self._tray_y) >= 0.08 or data.xpos[body][2] <= self._tray_z:
            return False
        qvel = data.qvel
        return all(abs(qvel[dof + i]) < 1e-3 for i in range(6))

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Every :data:`CHECK` [s]: take away a part at rest in the tray for TAKEN, or one that
        fell off the belt, and lay it on the belt as the next one."""
        t = float(data.time)
        if t < self._due:
            return
        self._due = t + CHECK
        for k, (_, dof, body) in enumerate(self._parts):
            if data.xpos[body][2] < self.belt_top - FALLEN:
                self.fallen += 1
                self._lay_next(data, k)
                continue
            if not self._in_tray(data, body, dof):
                self.rest[k] = -1.0
                continue
            if self.rest[k] < 0.0:
                self.rest[k] = t
            if t - self.rest[k] >= TAKEN:
                self._lay_next(data, k)

    def _lay_next(self, data: mujoco.MjData, k: int) -> None:
        """Lay part ``k`` on the belt as the next part of the infeed."""
        self.next[k] = self.laid
        self.laid += 1
        self._lay(data, k, *self._parts[k])
        self.rest[k] = -1.0

    def _lay(self, data: mujoco.MjData, k: int, q: int, dof: int, body: int) -> None:
        """Put part ``k`` on the belt as the next of the infeed, at the belt's speed."""
        spacing, lateral = _random(self.next[k])
        belt = float(data.qpos[self._belt_q])
        self._last = max(self._last + spacing, belt + UPSTREAM)
        centre_x = self.eye_x - (self._last - belt)
        frame = data.xpos[body] - data.qpos[q : q + 3] - self._origin[k]
        origin = self._origin[k] + frame
        data.qpos[q] = centre_x - origin[0]
        data.qpos[q + 1] = lateral
        data.qpos[q + 2] = 0.0005
        data.qpos[q + 3 : q + 7] = (1.0, 0.0, 0.0, 0.0)
        data.qvel[dof : dof + 6] = 0.0
        data.qvel[dof] = data.qvel[self._belt_v]

    def get_state(self) -> npt.NDArray[np.float64]:
        state = [*self.next, *self.rest, self._due, self.laid, self._last, self.fallen]
        return np.array(state, dtype=float)

    def set_state(self, state: npt.NDArray[np.float64]) -> None:
        n = len(self._parts)
        self.next = [int(x) for x in state[:n]]
        self.rest = [float(x) for x in state[n : 2 * n]]
        self._due = float(state[2 * n])
        self.laid = int(state[2 * n + 1])
        self._last = float(state[2 * n + 2])
        self.fallen = int(state[2 * n + 3])

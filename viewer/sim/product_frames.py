"""Where the product coordinate system (PCS) of each robot group stands in the world: the frame
MC_SetCoordinateTransform sets, or the one MC_TrackConveyorBelt (MC_TrackRotaryTable) carries
along with the belt (table) from a part's latched position (:mod:`mcl.coordinate_system`).

A PCS lies in the machine's Cartesian frame (MCS, in mm), which the model does not name; the
MCS is parallel to the world and the tool point is the origin of the body that carries the
model's ``tool`` site (the delta's effector centre). So a point ``P`` of the MCS lies in the
world at ``body + (P − forward(q)) / 1000`` with ``q`` the members' actual positions (measured
while they stand still): the physics the robot stands in, whatever its base's height.
"""

from __future__ import annotations

__all__ = ["STANDING", "FrameView", "ProductFrames"]

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

import mcl

STANDING = 0.5
"""Joint speed [axis unit/s] below which a member stands still."""


@dataclass(frozen=True, slots=True)
class FrameView:
    """A group's PCS as the 3-D view draws it.

    Attributes:
        group: The group's name.
        origin: The PCS origin in the world [m].
        x_axis: The PCS x axis in the world (unit, horizontal).
        master: The axis that carries the PCS (``""``: it stands still).
    """

    group: str
    origin: tuple[float, float, float]
    x_axis: tuple[float, float, float]
    master: str


def _tool_body(model: mujoco.MjModel) -> int:
    """The body carrying the model's ``tool`` (or ``…/tool``) site; -1 without one."""
    for s in range(model.nsite):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, s) or ""
        if name.split("/")[-1] == "tool":
            return int(model.site_bodyid[s])
    return -1


class ProductFrames:
    """The groups' PCS in the world of each snapshot (:meth:`__call__`); each group's MCS
    origin in the world is measured once while its members stand still (while they move, the
    parallelograms' give would shake the drawn frame by a millimetre) and kept for the model."""

    def __init__(self) -> None:
        self._model: mujoco.MjModel | None = None
        self._body = -1
        self._mcs: dict[str, np.ndarray] = {}
        """Per group: the MCS origin in the world [m], measured at a standstill."""

    def _mcs_origin(self, group: mcl.AxesGroup, data: mujoco.MjData) -> np.ndarray | None:
        """The MCS origin of ``group`` in the world [m] (None: its pose has no tool point)."""
        kept = self._mcs.get(group.name)
        if kept is not None:
            return kept
        transform = group.kin.transform
        assert transform is not None
        try:
            tcp = transform.forward([axis.actual for axis in group.axes])
        except mcl.KinematicsError:
            return None
        origin = np.asarray(data.xpos[self._body]) - np.asarray(tcp) / 1000.0
        if all(abs(axis.VEL) < STANDING for axis in group.axes):
            self._mcs[group.name] = origin
        return origin

    def __call__(
        self,
        groups: Sequence[mcl.AxesGroup],
        model: mujoco.MjModel | None,
        data: mujoco.MjData | None,
    ) -> tuple[FrameView, ...]:
        """The PCS of each of ``groups`` that has one (and a kinematic transformation), in the
        world of ``data``; none without a model or a ``tool`` site."""
        if model is not self._model:
            self._model, self._mcs = model, {}
            self._body = -1 if model is None else _tool_body(model)
        if model is None or data is None or self._body < 0:
            return ()
        found = []
        for group in groups:
            if group.kin.transform is None:
                continue
            mcs = self._mcs_origin(group, data)  # measured at a standstill before tracking
            frame = group.kin.frame
            if frame is None:
                continue
            origin = frame.point_to_mcs((0.0, 0.0, 0.0))
            along = np.asarray(frame.point_to_mcs((1.0, 0.0, 0.0))) - np.asarray(origin)
            if mcs is None or not np.all(np.isfinite([*origin, *along])):
                continue
            world = mcs + np.asarray(origin) / 1000.0
            along /= max(float(np.linalg.norm(along)), 1e-12)
            master = frame.master
            found.append(
                FrameView(
                    group.name,
                    (float(world[0]), float(world[1]), float(world[2])),
                    (float(along[0]), float(along[1]), float(along[2])),
                    "" if master is None else master.name,
                )
            )
        return tuple(found)

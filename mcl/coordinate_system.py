"""The product coordinate system (PCS) of an axes group: a frame in the machine's Cartesian
frame (MCS), fixed (MC_SetCoordinateTransform) or moving with a conveyor belt from a part's
latched position (MC_TrackConveyorBelt; :mod:`mcl.tracking`).

A :class:`ProductFrame` has an origin in the MCS, a rotation about the MCS z axis and, when it
tracks a belt, the belt axis whose x is the belt frame's x axis. The MCS point of the PCS point
``p`` [mm] at the servo instant ``t`` [s] is::

    P(t) = origin + R · (offset + p + (b(t) − latch) · x̂)

with R the rotation, ``offset`` the part's position in the belt frame when the belt stood at
``latch``, and b(t) the belt axis' set point extrapolated to ``t`` (its velocity and acceleration
are the feed-forward of the group's set points). While a group's PCS moves, a path that reached
its end rests there in the PCS (:func:`rest_element`): the members keep following the part.
"""

from __future__ import annotations

__all__ = ["ProductFrame", "rest_element"]

import math
from collections.abc import Sequence

from mcl.axis import Axis
from mcl.geometry import Line
from mcl.path import Element
from mcl.trajectory import Limits, Profile

Vec = list[float]


class ProductFrame:
    """A PCS in the MCS (module docstring).

    Args:
        origin: the frame's origin in the MCS [mm] (x, y, z).
        angle: its rotation about the MCS z axis [deg].
        offset: the PCS origin in the frame at ``latch`` [mm] (x, y, z).
        belt: the belt axis the PCS moves with along the frame's x (None: fixed).
        latch: the belt position at which the PCS origin lay at ``offset`` [mm].
    """

    def __init__(
        self,
        origin: Sequence[float],
        angle: float = 0.0,
        offset: Sequence[float] = (0.0, 0.0, 0.0),
        belt: Axis | None = None,
        latch: float = 0.0,
    ) -> None:
        self.origin = [float(x) for x in origin]
        self.angle = float(angle)
        self.offset = [float(x) for x in offset]
        self.belt = belt
        self.latch = float(latch)
        self._c = math.cos(math.radians(self.angle))
        self._s = math.sin(math.radians(self.angle))

    @property
    def moving(self) -> bool:
        """The PCS moves with a belt."""
        return self.belt is not None

    def travel(self, t: float | None = None) -> tuple[float, float, float]:
        """The belt's travel since the latch [mm], its velocity [mm/s] and acceleration [mm/s²]
        at the servo instant ``t`` [s] (None: at its latest set point); zeros when fixed."""
        belt = self.belt
        if belt is None:
            return 0.0, 0.0, 0.0
        if t is not None and belt.t_cycle == t:
            belt.update_setpoint(t)  # the belt's set point of the same instant (as gearing)
        dt = 0.0 if t is None else t - belt.t_sp
        v, a = belt.sp_vel, belt.sp_acc
        return belt.sp_pos + dt * (v + 0.5 * dt * a) - self.latch, v + dt * a, a

    def _turn(self, x: float, y: float, sign: float) -> tuple[float, float]:
        c, s = self._c, sign * self._s
        return c * x - s * y, s * x + c * y

    def to_mcs(
        self, p: Sequence[float], v: Sequence[float], a: Sequence[float], t: float | None = None
    ) -> tuple[Vec, Vec, Vec]:
        """The MCS point [mm], velocity [mm/s] and acceleration [mm/s²] of the PCS state
        (``p``, ``v``, ``a``) at the servo instant ``t`` [s]."""
        d, dv, da = self.travel(t)
        o = self.offset
        px, py = self._turn(o[0] + p[0] + d, o[1] + p[1], 1.0)
        vx, vy = self._turn(v[0] + dv, v[1], 1.0)
        ax, ay = self._turn(a[0] + da, a[1], 1.0)
        origin = self.origin
        point = [origin[0] + px, origin[1] + py, origin[2] + o[2] + p[2]]
        return point, [vx, vy, v[2]], [ax, ay, a[2]]

    def from_mcs(
        self, p: Sequence[float], v: Sequence[float], a: Sequence[float], t: float | None = None
    ) -> tuple[Vec, Vec, Vec]:
        """The PCS state of the MCS state (``p``, ``v``, ``a``) at the servo instant ``t`` [s]
        (the inverse of :meth:`to_mcs`)."""
        d, dv, da = self.travel(t)
        o, origin = self.offset, self.origin
        px, py = self._turn(p[0] - origin[0], p[1] - origin[1], -1.0)
        vx, vy = self._turn(v[0], v[1], -1.0)
        ax, ay = self._turn(a[0], a[1], -1.0)
        point = [px - o[0] - d, py - o[1], p[2] - origin[2] - o[2]]
        return point, [vx - dv, vy, v[2]], [ax - da, ay, a[2]]

    def point_to_mcs(self, p: Sequence[float], t: float | None = None) -> Vec:
        """The MCS point of the PCS point ``p`` [mm] at ``t`` (None: the belt's latest)."""
        return self.to_mcs(p, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), t)[0]

    def point_from_mcs(self, p: Sequence[float], t: float | None = None) -> Vec:
        """The PCS point of the MCS point ``p`` [mm] at ``t`` (None: the belt's latest)."""
        return self.from_mcs(p, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), t)[0]


def rest_element(end: Sequence[float], t0: float) -> Element:
    """A path element that rests at ``end`` in the PCS from path time ``t0`` [s] on and never
    ends (a move aborts it): the path's end while the PCS moves."""
    geometry = Line(list(end), [end[0] + 1.0, *end[1:]])
    element = Element(geometry, Limits(1.0, 1.0, 1.0, 1.0), 0.0, None, None)
    element.profile = Profile([(0.0, 0.0, 0.0, 0.0, 0.0)], math.inf)
    element.t0 = t0
    element.end = list(end)
    return element

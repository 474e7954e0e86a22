"""The product coordinate system (PCS) of an axes group: a frame in the machine's Cartesian
frame (MCS), fixed (MC_SetCoordinateTransform) or carried by a master axis from a part's latched
position: a conveyor belt (MC_TrackConveyorBelt) or a rotary table (MC_TrackRotaryTable;
:mod:`mcl.tracking`).

A :class:`ProductFrame` has an origin in the MCS, a rotation about the MCS z axis and, when it
is carried, the master axis. The MCS point of the PCS point ``p`` [mm] at the servo instant
``t`` [s] is::

    belt:   P(t) = origin + R · (offset + p + (b(t) − latch) · x̂)
    table:  P(t) = origin + R · Rz(b(t) − latch) · (offset + p)

with R the rotation, ``offset`` the part's position in the belt (table) frame when the master
stood at ``latch``, and b(t) the master axis' set point extrapolated to ``t`` (a belt's in mm
along the frame's x, a table's in degrees about the frame's z through its origin, the table's
centre); its velocity and acceleration are the feed-forward of the group's set points (on a
table with the centripetal and Coriolis terms). While a group's PCS moves, a path that reached
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
        master: the axis that carries the PCS (None: fixed): a belt along the frame's x [mm],
            or with ``rotary`` a table about the frame's z through its origin [deg].
        latch: the master position at which the PCS origin lay at ``offset`` [mm, deg].
        rotary: the master turns the PCS (a rotary table) instead of shifting it (a belt).
    """

    def __init__(
        self,
        origin: Sequence[float],
        angle: float = 0.0,
        offset: Sequence[float] = (0.0, 0.0, 0.0),
        master: Axis | None = None,
        latch: float = 0.0,
        rotary: bool = False,
    ) -> None:
        self.origin = [float(x) for x in origin]
        self.angle = float(angle)
        self.offset = [float(x) for x in offset]
        self.master = master
        self.latch = float(latch)
        self.rotary = rotary
        self._c = math.cos(math.radians(self.angle))
        self._s = math.sin(math.radians(self.angle))

    @property
    def moving(self) -> bool:
        """A master axis carries the PCS."""
        return self.master is not None

    def travel(self, t: float | None = None) -> tuple[float, float, float]:
        """The master's travel since the latch [mm, deg], its velocity [/s] and acceleration
        [/s²] at the servo instant ``t`` [s] (None: at its latest set point); zeros when fixed."""
        master = self.master
        if master is None:
            return 0.0, 0.0, 0.0
        if t is not None and master.t_cycle == t:
            master.update_setpoint(t)  # the master's set point of the same instant (as gearing)
        dt = 0.0 if t is None else t - master.t_sp
        v, a = master.sp_vel, master.sp_acc
        return master.sp_pos + dt * (v + 0.5 * dt * a) - self.latch, v + dt * a, a

    def _turn(self, x: float, y: float, sign: float) -> tuple[float, float]:
        c, s = self._c, sign * self._s
        return c * x - s * y, s * x + c * y

    def _carry(
        self,
        r: Sequence[float],
        v: Sequence[float],
        a: Sequence[float],
        d: float,
        dv: float,
        da: float,
    ) -> tuple[Vec, Vec, Vec]:
        """The state (``r``, ``v``, ``a``) given in the frame at the latch, carried by the
        master's travel ``d`` with its velocity ``dv`` and acceleration ``da``."""
        if not self.rotary:
            return [r[0] + d, r[1], r[2]], [v[0] + dv, v[1], v[2]], [a[0] + da, a[1], a[2]]
        phi, w, alpha = math.radians(d), math.radians(dv), math.radians(da)
        c, s = math.cos(phi), math.sin(phi)
        qx, qy = c * r[0] - s * r[1], s * r[0] + c * r[1]
        vx, vy = c * v[0] - s * v[1], s * v[0] + c * v[1]
        ax, ay = c * a[0] - s * a[1], s * a[0] + c * a[1]
        velocity = [vx - w * qy, vy + w * qx, v[2]]
        acceleration = [
            ax - 2.0 * w * vy - alpha * qy - w * w * qx,
            ay + 2.0 * w * vx + alpha * qx - w * w * qy,
            a[2],
        ]
        return [qx, qy, r[2]], velocity, acceleration

    def _uncarry(
        self,
        q: Sequence[float],
        v: Sequence[float],
        a: Sequence[float],
        d: float,
        dv: float,
        da: float,
    ) -> tuple[Vec, Vec, Vec]:
        """The inverse of :meth:`_carry`."""
        if not self.rotary:
            return [q[0] - d, q[1], q[2]], [v[0] - dv, v[1], v[2]], [a[0] - da, a[1], a[2]]
        phi, w, alpha = math.radians(d), math.radians(dv), math.radians(da)
        c, s = math.cos(phi), -math.sin(phi)
        vx, vy = v[0] + w * q[1], v[1] - w * q[0]
        ax = a[0] + 2.0 * w * vy + alpha * q[1] + w * w * q[0]
        ay = a[1] - 2.0 * w * vx - alpha * q[0] + w * w * q[1]
        point = [c * q[0] - s * q[1], s * q[0] + c * q[1], q[2]]
        return (
            point,
            [c * vx - s * vy, s * vx + c * vy, v[2]],
            [c * ax - s * ay, s * ax + c * ay, a[2]],
        )

    def to_mcs(
        self, p: Sequence[float], v: Sequence[float], a: Sequence[float], t: float | None = None
    ) -> tuple[Vec, Vec, Vec]:
        """The MCS point [mm], velocity [mm/s] and acceleration [mm/s²] of the PCS state
        (``p``, ``v``, ``a``) at the servo instant ``t`` [s]."""
        return self._placed(p, v, a, *self.travel(t))

    def ahead(self, distance: float) -> tuple[Vec, Vec]:
        """The MCS point [mm] and velocity [mm/s] of the PCS origin once the master has moved
        ``distance`` [mm, deg] beyond its latest set point at its latest velocity."""
        d, dv, _ = self.travel()
        zero = (0.0, 0.0, 0.0)
        point, velocity, _ = self._placed(zero, zero, zero, d + distance, dv, 0.0)
        return point, velocity

    def moved_on(self, p: Sequence[float], v: Sequence[float], seconds: float) -> tuple[Vec, Vec]:
        """The MCS point [mm] and velocity [mm/s] of the PCS state (``p``, ``v``) once the
        master has moved on for ``seconds`` [s] beyond its latest set point at its velocity."""
        d, dv, _ = self.travel()
        point, velocity, _ = self._placed(p, v, (0.0, 0.0, 0.0), d + dv * seconds, dv, 0.0)
        return point, velocity

    def _placed(
        self,
        p: Sequence[float],
        v: Sequence[float],
        a: Sequence[float],
        d: float,
        dv: float,
        da: float,
    ) -> tuple[Vec, Vec, Vec]:
        """:meth:`to_mcs` at the master's travel ``d``, velocity ``dv``, acceleration ``da``."""
        o = self.offset
        r = [o[0] + p[0], o[1] + p[1], o[2] + p[2]]
        q, qv, qa = self._carry(r, v, a, d, dv, da)
        px, py = self._turn(q[0], q[1], 1.0)
        vx, vy = self._turn(qv[0], qv[1], 1.0)
        ax, ay = self._turn(qa[0], qa[1], 1.0)
        origin = self.origin
        point = [origin[0] + px, origin[1] + py, origin[2] + q[2]]
        return point, [vx, vy, qv[2]], [ax, ay, qa[2]]

    def from_mcs(
        self, p: Sequence[float], v: Sequence[float], a: Sequence[float], t: float | None = None
    ) -> tuple[Vec, Vec, Vec]:
        """The PCS state of the MCS state (``p``, ``v``, ``a``) at the servo instant ``t`` [s]
        (the inverse of :meth:`to_mcs`)."""
        d, dv, da = self.travel(t)
        o, origin = self.offset, self.origin
        qx, qy = self._turn(p[0] - origin[0], p[1] - origin[1], -1.0)
        vx, vy = self._turn(v[0], v[1], -1.0)
        ax, ay = self._turn(a[0], a[1], -1.0)
        r, rv, ra = self._uncarry(
            [qx, qy, p[2] - origin[2]], [vx, vy, v[2]], [ax, ay, a[2]], d, dv, da
        )
        return [r[0] - o[0], r[1] - o[1], r[2] - o[2]], rv, ra

    def point_to_mcs(self, p: Sequence[float], t: float | None = None) -> Vec:
        """The MCS point of the PCS point ``p`` [mm] at ``t`` (None: the master's latest)."""
        return self.to_mcs(p, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), t)[0]

    def point_from_mcs(self, p: Sequence[float], t: float | None = None) -> Vec:
        """The PCS point of the MCS point ``p`` [mm] at ``t`` (None: the master's latest)."""
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

"""Kinematic transformations of an axes group: the machine's Cartesian frame (MCS) from the
members' own coordinates (ACS) and back (PLCopen Part 4, MC_SetKinTransform).

A :class:`KinTransform` maps the joint positions of the members (their units: deg for a rotary
arm) to the tool point [mm] in the MCS (:meth:`KinTransform.forward`) and back
(:meth:`KinTransform.inverse`). A point it cannot reach, or reaches only in or near a singular
pose, is refused with :class:`KinematicsError`, whose ``error_id`` the blocks report; neither
direction ever returns a NaN. The Cartesian limits of the tool point (:attr:`KinTransform.tcp`)
bind the group's Cartesian paths besides each joint's own limits (:mod:`mcl.group_kinematics`).

The three-arm rotary delta is :class:`mcl.delta_kinematics.DeltaKinematics`.
"""

from __future__ import annotations

__all__ = ["KinTransform", "KinematicsError", "TcpLimits", "derivatives"]

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

from mcl.errors import ErrorID


class KinematicsError(ValueError):
    """A point or joint position the transformation refuses.

    Attributes:
        error_id: :attr:`ErrorID.EWorkspace` (beyond reach or a joint's range) or
            :attr:`ErrorID.ESingular` (in or too near a singular pose).
    """

    def __init__(self, error_id: ErrorID, message: str) -> None:
        super().__init__(message)
        self.error_id = error_id


@dataclass(frozen=True, slots=True)
class TcpLimits:
    """Limits of the tool point along each Cartesian axis of the MCS.

    Attributes:
        velocity: fastest velocity [mm/s].
        acceleration: default acceleration and deceleration when a block passes 0 [mm/s²].
        max_acceleration: largest acceleration and deceleration [mm/s²].
        jerk: default and largest jerk [mm/s³].
    """

    velocity: float = 3000.0
    acceleration: float = 20000.0
    max_acceleration: float = 100000.0
    jerk: float = 2.0e6

    def __post_init__(self) -> None:
        for name in ("velocity", "acceleration", "max_acceleration", "jerk"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"TcpLimits.{name} must be a finite number > 0, got {value!r}")


class KinTransform:
    """A kinematic transformation between the members' coordinates and the MCS; this base is
    the identity (MC_SetKinTransform with it takes a group's transformation away).

    Subclasses implement :meth:`forward` and :meth:`inverse` for ``joints`` members.

    Attributes:
        name: the kinematics' name (MC_ReadKinTransform reports it).
        joints: how many members the transformation takes.
        tcp: the tool point's Cartesian limits.
    """

    name: ClassVar[str] = "identity"
    joints: ClassVar[int] = 3

    def __init__(self, tcp: TcpLimits | None = None) -> None:
        self.tcp = tcp if tcp is not None else TcpLimits()

    def forward(self, q: Sequence[float]) -> list[float]:
        """The tool point [mm] of the joint positions ``q``.

        Raises:
            KinematicsError: ``q`` is outside the joints' ranges, or the pose is singular.
        """
        return list(q)

    def inverse(self, p: Sequence[float]) -> list[float]:
        """The joint positions of the tool point ``p`` [mm].

        Raises:
            KinematicsError: ``p`` is beyond reach, beyond a joint's range, or too near a
                singular pose.
        """
        return list(p)

    def parameters(self) -> dict[str, float]:
        """The geometry, by name (MC_ReadKinTransform)."""
        return {}


def derivatives(
    transform: KinTransform,
    p: Sequence[float],
    v: Sequence[float],
    a: Sequence[float],
    h: float = 1e-4,
) -> tuple[list[float], list[float], list[float]]:
    """Joint positions, velocities and accelerations of a tool point moving at ``p`` [mm] with
    velocity ``v`` [mm/s] and acceleration ``a`` [mm/s²].

    The joints at p(t ± h) = p ± v·h + a·h²/2 (the path's Taylor expansion over ``h`` [s])
    give q̇ and q̈ by central differences (error O(h²)).

    Raises:
        KinematicsError: one of the three points is refused.
    """
    q = transform.inverse(p)
    if not any(v) and not any(a):
        return q, [0.0] * len(q), [0.0] * len(q)
    half = 0.5 * h * h
    ahead = transform.inverse([pi + vi * h + ai * half for pi, vi, ai in zip(p, v, a, strict=True)])
    back = transform.inverse([pi - vi * h + ai * half for pi, vi, ai in zip(p, v, a, strict=True)])
    qd = [(f - b) / (2.0 * h) for f, b in zip(ahead, back, strict=True)]
    qdd = [(f - 2.0 * c + b) / (h * h) for f, c, b in zip(ahead, q, back, strict=True)]
    return q, qd, qdd

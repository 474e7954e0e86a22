"""Whether a tool point's motion keeps a robot's joints within their limits: the check of a
Cartesian corner blend (:mod:`mcl.path_planner`), whose curve the pieces' own checks
(:mod:`mcl.group_kinematics`) do not cover."""

from __future__ import annotations

__all__ = ["JointCheck"]

from collections.abc import Sequence

from mcl.kinematics import KinematicsError, KinTransform, derivatives


class JointCheck:
    """The joints' limits behind a Cartesian path.

    Args:
        transform: the kinematic transformation.
        velocity: each joint's largest velocity [u/s] (its Vmax).
        acceleration: each joint's largest acceleration and deceleration [u/s²].
    """

    __slots__ = ("acceleration", "transform", "velocity")

    def __init__(
        self, transform: KinTransform, velocity: Sequence[float], acceleration: Sequence[float]
    ) -> None:
        self.transform = transform
        self.velocity = list(velocity)
        self.acceleration = list(acceleration)

    def exceeds(self, p: Sequence[float], v: Sequence[float], a: Sequence[float]) -> bool:
        """A joint exceeds its velocity or acceleration while the tool point passes ``p`` [mm]
        with velocity ``v`` [mm/s] and acceleration ``a`` [mm/s²], or the point is refused."""
        try:
            _, qd, qdd = derivatives(self.transform, p, v, a)
        except KinematicsError:
            return True
        return any(
            abs(w) > w_max or abs(b) > b_max
            for w, w_max, b, b_max in zip(qd, self.velocity, qdd, self.acceleration, strict=True)
        )

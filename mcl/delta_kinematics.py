"""Kinematics of the three-arm rotary delta robot (Clavel's delta).

Frame: the MCS origin is the centre of the base plane, z up, the effector below it (z < 0).
Arm i (i = 0, 1, 2) turns about a horizontal axis tangent to the base circle of radius
``base_radius`` at the azimuth φᵢ = i·120° (arm 0 points along +x). Its angle θᵢ [deg] is 0
with the upper arm horizontal and pointing outward, positive downward. The elbow is at
(R + L·cos θ)·uᵢ − L·sin θ·ez (uᵢ the arm's radial direction, R the base radius, L the upper
arm); the forearm, a parallelogram of length l, ends at the effector's joint p + r·uᵢ (r the
effector radius), so ‖p + r·uᵢ − elbowᵢ‖ = l for every arm.

Inverse: per arm, with a, b, c the components of p + (r − R)·uᵢ along uᵢ, the tangent and z,
the constraint reads −2aL·cos θ + 2cL·sin θ = l² − a² − b² − c² − L²; of its two solutions the
one with the elbow outward is taken. Forward: the effector centre is where the three spheres of
radius l about elbowᵢ − r·uᵢ meet, the lower of their two points.

Singularities, refused with :class:`mcl.kinematics.KinematicsError`:

- the workspace boundary (serial singularity): an upper arm and the projection of its forearm
  into the arm's plane stretched or folded within ``margin`` [deg] (ESingular), beyond: out of
  reach (EWorkspace);
- the parallel singularity: the three forearms near one plane, |det(f₀, f₁, f₂)|/l³ below
  ``parallel_margin`` (ESingular);
- an arm angle outside [``theta_min``, ``theta_max``] [deg] (EWorkspace).
"""

from __future__ import annotations

__all__ = ["DeltaKinematics"]

import math
from collections.abc import Sequence
from typing import ClassVar

from mcl.errors import ErrorID
from mcl.kinematics import KinematicsError, KinTransform, TcpLimits

_AZIMUTHS = (0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0)


def _det(f0: Sequence[float], f1: Sequence[float], f2: Sequence[float]) -> float:
    return (
        f0[0] * (f1[1] * f2[2] - f1[2] * f2[1])
        - f0[1] * (f1[0] * f2[2] - f1[2] * f2[0])
        + f0[2] * (f1[0] * f2[1] - f1[1] * f2[0])
    )


class DeltaKinematics(KinTransform):
    """The three-arm rotary delta (module docstring).

    Args:
        base_radius: centre of the base to an arm's axis R [mm].
        effector_radius: centre of the effector to a forearm's lower joint r [mm].
        upper_arm: upper arm, axis to elbow L [mm].
        forearm: forearm (parallelogram) length l [mm].
        theta_min, theta_max: range of the arm angles [deg].
        margin: refuse an arm within this angle of stretched or folded [deg].
        parallel_margin: refuse |det(f₀, f₁, f₂)|/l³ below it (forearms near one plane).
        tcp: the tool point's Cartesian limits.
    """

    name: ClassVar[str] = "delta"
    joints: ClassVar[int] = 3

    def __init__(
        self,
        base_radius: float,
        effector_radius: float,
        upper_arm: float,
        forearm: float,
        theta_min: float = -60.0,
        theta_max: float = 100.0,
        margin: float = 3.0,
        parallel_margin: float = 0.05,
        tcp: TcpLimits | None = None,
    ) -> None:
        super().__init__(tcp)
        lengths = {
            "base_radius": base_radius,
            "effector_radius": effector_radius,
            "upper_arm": upper_arm,
            "forearm": forearm,
        }
        for key, value in lengths.items():
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{key} must be a finite number > 0 [mm], got {value!r}")
        if not (math.isfinite(theta_min) and math.isfinite(theta_max) and theta_min < theta_max):
            raise ValueError(
                f"theta_min < theta_max must be finite [deg], got {theta_min!r}, {theta_max!r}"
            )
        if not (math.isfinite(margin) and 0.0 < margin < 45.0):
            raise ValueError(f"margin must be in (0, 45) [deg], got {margin!r}")
        if not (math.isfinite(parallel_margin) and 0.0 < parallel_margin < 1.0):
            raise ValueError(f"parallel_margin must be in (0, 1), got {parallel_margin!r}")
        if forearm <= upper_arm + abs(base_radius - effector_radius):
            raise ValueError(
                f"forearm {forearm} mm must be longer than upper_arm + |base_radius - "
                f"effector_radius| = {upper_arm + abs(base_radius - effector_radius)} mm"
            )
        self.base_radius = float(base_radius)
        self.effector_radius = float(effector_radius)
        self.upper_arm = float(upper_arm)
        self.forearm = float(forearm)
        self.theta_min = float(theta_min)
        self.theta_max = float(theta_max)
        self.margin = float(margin)
        self.parallel_margin = float(parallel_margin)
        self._cos_margin = math.cos(math.radians(margin))

    def parameters(self) -> dict[str, float]:
        return {
            "base_radius": self.base_radius,
            "effector_radius": self.effector_radius,
            "upper_arm": self.upper_arm,
            "forearm": self.forearm,
            "theta_min": self.theta_min,
            "theta_max": self.theta_max,
        }

    # ------------------------------------------------------------------ geometry
    def elbow(self, i: int, theta: float) -> list[float]:
        """The elbow of arm ``i`` at the angle ``theta`` [deg]: its position (x, y, z) [mm]."""
        t = math.radians(theta)
        reach = self.base_radius + self.upper_arm * math.cos(t)
        phi = _AZIMUTHS[i]
        return [reach * math.cos(phi), reach * math.sin(phi), -self.upper_arm * math.sin(t)]

    def _check_range(self, q: Sequence[float]) -> None:
        for i, theta in enumerate(q):
            if not (self.theta_min <= theta <= self.theta_max):
                raise KinematicsError(
                    ErrorID.EWorkspace,
                    f"arm {i} at {theta!r} deg is outside [{self.theta_min}, {self.theta_max}] deg",
                )

    def _check_parallel(self, p: Sequence[float], q: Sequence[float]) -> None:
        """The forearms' vectors must not lie near one plane."""
        forearms = []
        for i in range(3):
            e = self.elbow(i, q[i])
            phi = _AZIMUTHS[i]
            r = self.effector_radius
            joint = [p[0] + r * math.cos(phi), p[1] + r * math.sin(phi), p[2]]
            forearms.append([joint[k] - e[k] for k in range(3)])
        det = abs(_det(forearms[0], forearms[1], forearms[2])) / self.forearm**3
        if det < self.parallel_margin:
            raise KinematicsError(
                ErrorID.ESingular,
                f"the forearms lie near one plane at {list(p)} mm (|det|/l³ = {det:.4f} < "
                f"{self.parallel_margin})",
            )

    # ------------------------------------------------------------------ transforms
    def inverse(self, p: Sequence[float]) -> list[float]:
        if len(p) != 3 or not all(math.isfinite(x) for x in p):
            raise KinematicsError(ErrorID.EParam, f"a point is 3 finite numbers [mm], got {p!r}")
        big_l, l2 = self.upper_arm, self.forearm * self.forearm
        q: list[float] = []
        for i, phi in enumerate(_AZIMUTHS):
            cos_phi, sin_phi = math.cos(phi), math.sin(phi)
            x = p[0] + (self.effector_radius - self.base_radius) * cos_phi
            y = p[1] + (self.effector_radius - self.base_radius) * sin_phi
            a = x * cos_phi + y * sin_phi
            b = -x * sin_phi + y * cos_phi
            c = p[2]
            coef_cos, coef_sin = -2.0 * a * big_l, 2.0 * c * big_l
            k = l2 - a * a - b * b - c * c - big_l * big_l
            norm = math.hypot(coef_cos, coef_sin)
            ratio = k / norm if norm > 0.0 else math.inf
            if abs(ratio) > 1.0:
                raise KinematicsError(ErrorID.EWorkspace, f"arm {i} cannot reach {list(p)} mm")
            if abs(ratio) > self._cos_margin:
                raise KinematicsError(
                    ErrorID.ESingular,
                    f"arm {i} is within {self.margin} deg of stretched or folded at {list(p)} mm",
                )
            base = math.atan2(coef_sin, coef_cos)
            spread = math.acos(ratio)
            # the two solutions base ± spread: the elbow outward has the larger cos θ
            first, second = base + spread, base - spread
            theta = first if math.cos(first) >= math.cos(second) else second
            q.append(math.degrees(math.atan2(math.sin(theta), math.cos(theta))))
        self._check_range(q)
        self._check_parallel(p, q)
        return q

    def forward(self, q: Sequence[float]) -> list[float]:
        if len(q) != 3 or not all(math.isfinite(x) for x in q):
            raise KinematicsError(ErrorID.EParam, f"joints are 3 finite numbers [deg], got {q!r}")
        self._check_range(q)
        centres = []
        for i, phi in enumerate(_AZIMUTHS):
            e = self.elbow(i, q[i])
            r = self.effector_radius
            centres.append([e[0] - r * math.cos(phi), e[1] - r * math.sin(phi), e[2]])
        p = self._trilaterate(centres)
        back = self.inverse(p)  # the margins of the serial and parallel singularities
        if max(abs(a - b) for a, b in zip(back, q, strict=True)) > 1e-6:
            raise KinematicsError(
                ErrorID.EWorkspace, f"the pose {list(q)} deg has an elbow folded inward"
            )
        return p

    def _trilaterate(self, c: list[list[float]]) -> list[float]:
        """The lower point at the distance l from the three centres ``c`` [mm]."""
        d21 = [c[1][k] - c[0][k] for k in range(3)]
        d31 = [c[2][k] - c[0][k] for k in range(3)]
        d = math.sqrt(sum(x * x for x in d21))
        ex = [x / d for x in d21]
        i = sum(ex[k] * d31[k] for k in range(3))
        rest = [d31[k] - i * ex[k] for k in range(3)]
        j = math.sqrt(sum(x * x for x in rest))
        if j < 1e-9 * self.forearm:
            raise KinematicsError(ErrorID.ESingular, "the elbows lie on one line")
        ey = [x / j for x in rest]
        ez = [
            ex[1] * ey[2] - ex[2] * ey[1],
            ex[2] * ey[0] - ex[0] * ey[2],
            ex[0] * ey[1] - ex[1] * ey[0],
        ]
        x = d / 2.0
        y = (i * i + j * j - 2.0 * i * x) / (2.0 * j)
        z2 = self.forearm * self.forearm - x * x - y * y
        if z2 < 0.0:
            raise KinematicsError(ErrorID.EWorkspace, "the forearms cannot close")
        z = math.sqrt(z2)
        up = [c[0][k] + x * ex[k] + y * ey[k] + z * ez[k] for k in range(3)]
        down = [c[0][k] + x * ex[k] + y * ey[k] - z * ez[k] for k in range(3)]
        return down if down[2] <= up[2] else up

"""A cam table's profile over one period, sampled for drawing: slave position, slope and
curvature against the table's master coordinate, with its segments' laws (the viewer's cam view
and ``python -m scenes cam``)."""

from __future__ import annotations

__all__ = ["PROFILE_POINTS", "CamProfile", "sample"]

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mcl.cam_table import Cam, CamLaw

PROFILE_POINTS = 1001
"""Points the profile is sampled at over one period (the table's own points added when it has
no more than these)."""


@dataclass(frozen=True, slots=True)
class CamProfile:
    """A cam table sampled over one period, in table units (before the MC_CamIn's scalings).

    Attributes:
        master: Table master coordinate τ, increasing [master u].
        slave: Table value CAM(τ) [slave u].
        velocity: Slope ds/dτ [slave u / master u].
        acceleration: Curvature d²s/dτ² [slave u / master u²].
        points: The table's master points (segment boundaries) [master u].
        laws: The law of each segment (``CamLaw`` names), one fewer than ``points``.
        periodic: The table repeats (its slave advancing ``rise`` each period).
        period: Master length of the table [master u].
        rise: What the slave advances per period [slave u].
    """

    master: npt.NDArray[np.float64]
    slave: npt.NDArray[np.float64]
    velocity: npt.NDArray[np.float64]
    acceleration: npt.NDArray[np.float64]
    points: tuple[float, ...]
    laws: tuple[str, ...]
    periodic: bool
    period: float
    rise: float


def sample(cam: Cam, count: int = PROFILE_POINTS) -> CamProfile:
    """``cam`` over one period at ``count`` evenly spaced master positions, and at its own
    points when it has no more than ``count``."""
    grid = np.linspace(cam.start, cam.start + cam.period, count)
    master = grid
    if len(cam.masters) <= count:  # a long table: the grid alone (its points are that dense)
        master = np.union1d(grid, np.asarray(cam.masters, dtype=np.float64))
    values = np.array([cam.at(float(m)) for m in master[:-1]]).reshape(-1, 3)
    end = cam.segment(len(cam.kinds) - 1, cam.masters[-1] - cam.masters[-2])
    values = np.vstack([values, end])
    return CamProfile(
        master=master,
        slave=values[:, 0].copy(),
        velocity=values[:, 1].copy(),
        acceleration=values[:, 2].copy(),
        points=tuple(cam.masters),
        laws=tuple(CamLaw(law).name for law in cam.laws),
        periodic=cam.periodic,
        period=cam.period,
        rise=cam.rise,
    )

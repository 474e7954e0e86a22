"""What a display or a tool reads of cams (docs/reference.md, Electronic cams).

:func:`cam_profile` samples a checked cam table over one period: slave position, slope and
curvature against the table's master coordinate, with its segments' laws. :func:`running_cam`
tells which table drives a cammed axis now and where on it the axis is: the operating point, the
offsets, the scalings and the phase shift. Both only read: calling them does not change the motion.
"""

from __future__ import annotations

__all__ = ["PROFILE_POINTS", "CamProfile", "RunningCam", "cam_profile", "running_cam"]

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mcl.axis import Axis
from mcl.cam_coupling import CamIn, selection
from mcl.cam_table import Cam, CamLaw

PROFILE_POINTS = 1001
"""Points a profile is sampled at over one period (the table's own points added when it has
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


def cam_profile(table: Cam | int, count: int = PROFILE_POINTS) -> CamProfile:
    """A table over one period at ``count`` evenly spaced master positions, and at its own
    points when it has no more than ``count``.

    Args:
        table: a checked table (:attr:`RunningCam.table`, :func:`mcl.cam_table.compile_cam`) or
            the ``CamTableID`` MC_CamTableSelect gave it.
        count: sample points over the period (at least 2).

    Raises:
        ValueError: no table was selected under that CamTableID, or ``count`` is below 2.
    """
    if count < 2:
        raise ValueError(f"count must be at least 2 points, got {count}")
    if isinstance(table, int):
        chosen = selection(table)
        if chosen is None:
            raise ValueError(f"no cam table was selected under CamTableID {table}")
        table = chosen.cam
    cam = table
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


@dataclass(frozen=True, slots=True)
class RunningCam:
    """The cam that drives an axis, read at one servo instant (:func:`running_cam`).

    Attributes:
        table: The checked table (for :func:`cam_profile`).
        table_id: The CamTableID MC_CamTableSelect gave it.
        name: The table's ``Name`` (empty: none).
        master: The master axis.
        coupled: The slave follows the table (False while a ramp-in waits for its start).
        in_sync: The slave is on the table (no blend running): MC_CamIn's InSync.
        table_master: The master position in the table as the cam sees it, reduced to one
            period (phase shift and scaling included) [master u]; NaN while not coupled.
        table_slave: The table's value there, CAM(``table_master``) [slave u].
        set_slave: The slave's set point in table units, (set point − offset)/SlaveScaling,
            reduced to the same period [slave u].
        actual_slave: The slave's actual position in table units, likewise (a modulo slave's
            continuous position, not its wrapped POS) [slave u].
        cycle: The period number of the table coordinate.
        master_offset: MC_CamIn's MasterOffset [master u].
        slave_offset: MC_CamIn's SlaveOffset [slave u].
        master_scaling: MC_CamIn's MasterScaling.
        slave_scaling: MC_CamIn's SlaveScaling.
        phase_shift: The phase shift of MC_Phasing now [master u].
    """

    table: Cam
    table_id: int
    name: str
    master: Axis
    coupled: bool
    in_sync: bool
    table_master: float
    table_slave: float
    set_slave: float
    actual_slave: float
    cycle: int
    master_offset: float
    slave_offset: float
    master_scaling: float
    slave_scaling: float
    phase_shift: float


def running_cam(axis: Axis) -> RunningCam | None:
    """The cam that drives ``axis`` now, at its current servo instant (None: it is not cammed).

    While a new MC_CamIn waits for the running cam's period boundary (or its ramp-in's start),
    the cam that still drives the axis is the one read out.
    """
    cmd = axis.active
    if not isinstance(cmd, CamIn):
        return None
    while not cmd.coupled() and isinstance(cmd.previous, CamIn):
        cmd = cmd.previous
    cam = cmd.cam
    shift = cmd.total_shift(axis.t_cycle)
    coupled = cmd.coupled() and cmd.reader is not None
    tau = table_slave = set_slave = actual_slave = math.nan
    cycle = 0
    if coupled:
        assert cmd.reader is not None
        m = cmd.reader.position + shift
        tau_abs = cmd.tau_c + cmd.master_scaling * (m - cmd.m_c)
        cycle = cam.cycle(tau_abs)
        tau = tau_abs - cycle * cam.period
        base = cycle * cam.rise
        table_slave = cam.at(tau_abs)[0] - base
        k = cmd.slave_scaling
        set_slave = (axis.sp_pos - cmd.base) / k - base
        actual_slave = (axis.actual - cmd.base) / k - base  # continuous, as the set point
    return RunningCam(
        table=cam,
        table_id=cmd.chosen.table_id,
        name=cmd.chosen.name,
        master=cmd.master,
        coupled=coupled,
        in_sync=coupled and cmd.signal,
        table_master=tau,
        table_slave=table_slave,
        set_slave=set_slave,
        actual_slave=actual_slave,
        cycle=cycle,
        master_offset=cmd.master_offset,
        slave_offset=cmd.slave_offset,
        master_scaling=cmd.master_scaling,
        slave_scaling=cmd.slave_scaling,
        phase_shift=shift,
    )

"""What the cam view shows of a cammed axis: its table's profile over one period and the
operating point moving along it, copied by the simulation thread between two PLC cycles.

A slave is cammed when its active command is an MC_CamIn's
(:class:`mcl.cam_coupling.CamIn`); while a new MC_CamIn waits for the running cam's period
boundary, the running one is shown. The profile
is sampled once per selected table (:class:`ProfileCache`), not per snapshot: the simulation
thread only reads the operating point every snapshot.
"""

from __future__ import annotations

__all__ = ["TABLES_KEPT", "CamView", "ProfileCache", "cam_views", "running_cam"]

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mcl
from mcl.cam_coupling import CamIn
from mcl.cam_table import Cam
from scenes.tools.cam_profile import CamProfile, sample

TABLES_KEPT = 16
"""Sampled profiles a cache keeps (the least recently used dropped)."""


@dataclass(frozen=True, slots=True)
class CamView:
    """One cammed slave: its table's profile and where it is on it.

    Attributes:
        slave: The slave's axis name.
        master: The master's axis name in the scene (empty if it is not one of its axes).
        slave_unit: The slave's user unit.
        master_unit: The master's user unit.
        table_id: The CamTableID of the table.
        name: The table's ``Name`` (empty: none).
        profile: The table sampled over one period.
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

    slave: str
    master: str
    slave_unit: str
    master_unit: str
    table_id: int
    name: str
    profile: CamProfile
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


class ProfileCache:
    """The sampled profile of each cam table seen, sampled once (the newest kept)."""

    def __init__(self) -> None:
        self._profiles: dict[int, tuple[Cam, CamProfile]] = {}

    def profile(self, cam: Cam) -> CamProfile:
        """The profile of ``cam`` (sampled the first time it is asked for)."""
        key = id(cam)
        known = self._profiles.pop(key, None)
        if known is None or known[0] is not cam:
            known = (cam, sample(cam))
        self._profiles[key] = known
        while len(self._profiles) > TABLES_KEPT:
            del self._profiles[next(iter(self._profiles))]
        return known[1]


def running_cam(axis: mcl.Axis) -> CamIn | None:
    """The cam that drives ``axis`` now (the running one while a successor waits), or None."""
    cmd = axis.active
    if not isinstance(cmd, CamIn):
        return None
    while not cmd.coupled() and isinstance(cmd.previous, CamIn):
        cmd = cmd.previous
    return cmd


def cam_views(axes: Mapping[str, mcl.Axis], cache: ProfileCache) -> tuple[CamView, ...]:
    """A view of every cammed axis of ``axes``, in their order (empty: none is cammed)."""
    names = {id(axis): name for name, axis in axes.items()}
    views = []
    for name, axis in axes.items():
        cmd = running_cam(axis)
        if cmd is not None:
            views.append(_view(name, axis, cmd, names.get(id(cmd.master), ""), cache))
    return tuple(views)


def _view(name: str, axis: mcl.Axis, cmd: CamIn, master: str, cache: ProfileCache) -> CamView:
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
    return CamView(
        slave=name,
        master=master,
        slave_unit=axis.config.unit,
        master_unit=cmd.master.config.unit,
        table_id=cmd.chosen.table_id,
        name=cmd.chosen.name,
        profile=cache.profile(cam),
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

"""What the cam view shows of a cammed axis: its table's profile over one period and the
operating point moving along it, copied by the simulation thread between two PLC cycles.

Both come from mcl's read-outs (:func:`mcl.running_cam`, :func:`mcl.cam_profile`): while a new
MC_CamIn waits for the running cam's period boundary, the running one is shown. The profile is
sampled once per selected table (:class:`ProfileCache`), not per snapshot: the simulation thread
only reads the operating point every snapshot.
"""

from __future__ import annotations

__all__ = ["TABLES_KEPT", "CamView", "ProfileCache", "cam_views"]

from collections.abc import Mapping
from dataclasses import dataclass

import mcl

TABLES_KEPT = 16
"""Sampled profiles a cache keeps (the least recently used dropped)."""


@dataclass(frozen=True, slots=True)
class CamView:
    """One cammed slave: its table's profile and where it is on it, for the page.

    Attributes:
        slave: The slave's axis name.
        master: The master's axis name in the scene (empty if it is not one of its axes).
        slave_unit: The slave's user unit.
        master_unit: The master's user unit.
        profile: The table sampled over one period (:func:`mcl.cam_profile`).

    The other attributes are those of :class:`mcl.RunningCam` of the same name: the table's ID
    and name, whether the slave is coupled and InSync, the operating point (``table_master``,
    ``table_slave``, ``set_slave``, ``actual_slave``, ``cycle``), the offsets, the scalings and
    the phase shift.
    """

    slave: str
    master: str
    slave_unit: str
    master_unit: str
    table_id: int
    name: str
    profile: mcl.CamProfile
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
        self._profiles: dict[int, tuple[mcl.Cam, mcl.CamProfile]] = {}

    def profile(self, cam: mcl.Cam) -> mcl.CamProfile:
        """The profile of ``cam`` (sampled the first time it is asked for)."""
        key = id(cam)
        known = self._profiles.pop(key, None)
        if known is None or known[0] is not cam:
            known = (cam, mcl.cam_profile(cam))
        self._profiles[key] = known
        while len(self._profiles) > TABLES_KEPT:
            del self._profiles[next(iter(self._profiles))]
        return known[1]


def cam_views(axes: Mapping[str, mcl.Axis], cache: ProfileCache) -> tuple[CamView, ...]:
    """A view of every cammed axis of ``axes``, in their order (empty: none is cammed)."""
    names = {id(axis): name for name, axis in axes.items()}
    views = []
    for name, axis in axes.items():
        cam = mcl.running_cam(axis)
        if cam is not None:
            views.append(_view(name, axis, cam, names.get(id(cam.master), ""), cache))
    return tuple(views)


def _view(
    name: str, axis: mcl.Axis, cam: mcl.RunningCam, master: str, cache: ProfileCache
) -> CamView:
    return CamView(
        slave=name,
        master=master,
        slave_unit=axis.config.unit,
        master_unit=cam.master.config.unit,
        table_id=cam.table_id,
        name=cam.name,
        profile=cache.profile(cam.table),
        coupled=cam.coupled,
        in_sync=cam.in_sync,
        table_master=cam.table_master,
        table_slave=cam.table_slave,
        set_slave=cam.set_slave,
        actual_slave=cam.actual_slave,
        cycle=cam.cycle,
        master_offset=cam.master_offset,
        slave_offset=cam.slave_offset,
        master_scaling=cam.master_scaling,
        slave_scaling=cam.slave_scaling,
        phase_shift=cam.phase_shift,
    )

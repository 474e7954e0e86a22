"""Kinematic transformation of an axes group: MC_SetKinTransform, MC_ReadKinTransform (PLCopen
Part 4 v2.0, beyond the Teco library).

A group whose members are the joints of a robot gets its kinematics with MC_SetKinTransform (a
:class:`mcl.kinematics.KinTransform`, e.g. :class:`mcl.delta_kinematics.DeltaKinematics`); from
then on MC_MoveLinear* and MC_MoveCircular* in MCS (or PCS, which coincides with MCS) move the
tool point on their path in the machine's Cartesian frame [mm], MC_MoveDirect* and any move in
ACS move the joints, and MC_GroupReadActualPosition reports either (:mod:`mcl.group_kinematics`).
A target or a point of a path the kinematics refuses gives ``EWorkspace`` 24 or ``ESingular`` 25;
a joint it would drive beyond its SW limit ``Ecil`` 8. The identity (a plain
:class:`~mcl.kinematics.KinTransform`) takes the transformation away.
"""

from __future__ import annotations

__all__ = ["MC_ReadKinTransform", "MC_SetKinTransform"]

from typing import Any, ClassVar

from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB
from mcl.kinematics import KinTransform


class MC_SetKinTransform(ExecuteFB):
    """Sets the group's kinematic transformation ``KinTransform`` (PLCopen Part 4); Done at once.

    Only while the group stands (GroupDisabled or GroupStandby: EParam 5 while it moves or is
    held, EAxStop 6 in GroupStopping, Eerrstop 11 in GroupErrorStop); 1005 when the group has no
    axes; EParam 5 when ``KinTransform`` is no kinematic transformation or takes another number
    of joints than the group has members.
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("KinTransform",)
    KinTransform: object = None

    def _begin(self) -> int:
        group = self.group
        transform = self.KinTransform
        if not group.axes:
            return ErrorID.EGroupEmpty
        if not isinstance(transform, KinTransform):
            return ErrorID.EParam
        if type(transform) is not KinTransform and transform.joints != len(group.axes):
            return ErrorID.EParam
        error = group.busy_error()
        if error:
            return error
        group.kin.transform = None if type(transform) is KinTransform else transform
        return 0


class MC_ReadKinTransform(EnableFB):
    """Publishes the group's kinematic transformation (PLCopen Part 4): ``KinTransform`` (the
    identity :class:`~mcl.kinematics.KinTransform` when it has none, and while Valid is FALSE),
    its ``Name`` and its geometry ``Parameters`` [mm, deg] by name; 1005 when the group has no
    axes."""

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.KinTransform = KinTransform()
        self.Name = ""
        self.Parameters: dict[str, float] = {}

    def _evaluate(self) -> int:
        group = self.group
        if not group.axes:
            self._disable()
            return ErrorID.EGroupEmpty
        transform = group.kin.transform
        if transform is None:
            transform = KinTransform()
        self.KinTransform = transform
        self.Name = transform.name
        self.Parameters = transform.parameters()
        return 0

    def _disable(self) -> None:
        self.KinTransform = KinTransform()
        self.Name = ""
        self.Parameters = {}

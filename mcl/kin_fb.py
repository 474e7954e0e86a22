"""Kinematic transformation of an axes group: MC_SetKinTransform, MC_ReadKinTransform (PLCopen
Part 4 v2.0, beyond the Teco library).

A group whose members are the joints of a robot gets its kinematics with MC_SetKinTransform (a
:class:`mcl.kinematics.KinTransform`, e.g. :class:`mcl.delta_kinematics.DeltaKinematics`); from
then on MC_MoveLinear* and MC_MoveCircular* in MCS, or in PCS (the MCS until a product
coordinate system is set: :mod:`mcl.tracking`), move the tool point on their path in the
machine's Cartesian frame [mm], MC_MoveDirect* and any move in ACS move the joints, and
MC_GroupReadActualPosition reports either (:mod:`mcl.group_kinematics`). A target or a point of
a path the kinematics refuses gives ``EWorkspace`` 24 or ``ESingular`` 25; a joint it would
drive beyond its SW limit ``Ecil`` 8. The identity (a plain
:class:`~mcl.kinematics.KinTransform`) takes the transformation away.

PLCopen leaves MC_KIN_REF, the description of a kinematics, to the vendor: besides a
:class:`~mcl.kinematics.KinTransform`, ``KinTransform`` takes a structure (an ST program's own
STRUCT) with a delta robot's parameters read by name: ``BaseRadius``, ``EffectorRadius``,
``UpperArm``, ``Forearm`` [mm] (required), the arms' range ``ThetaMin``, ``ThetaMax`` [deg] and
the tool point's ``MaxVelocity`` [mm/s], ``Acceleration``, ``MaxAcceleration`` [mm/s²], ``Jerk``
[mm/s³] (a field it lacks keeps the default, as does a tool point's limit of 0).
"""

from __future__ import annotations

__all__ = ["MC_ReadKinTransform", "MC_SetKinTransform", "transform_of"]

import math
from typing import Any, ClassVar

from mcl.delta_kinematics import DeltaKinematics
from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB
from mcl.kinematics import KinTransform, TcpLimits

KinRef = Any
"""MC_KIN_REF: a :class:`~mcl.kinematics.KinTransform` or a structure of a delta's parameters."""

_DELTA_FIELDS: dict[str, str] = {
    "BaseRadius": "base_radius",
    "EffectorRadius": "effector_radius",
    "UpperArm": "upper_arm",
    "Forearm": "forearm",
    "ThetaMin": "theta_min",
    "ThetaMax": "theta_max",
}
_TCP_FIELDS: dict[str, str] = {
    "MaxVelocity": "velocity",
    "Acceleration": "acceleration",
    "MaxAcceleration": "max_acceleration",
    "Jerk": "jerk",
}


def transform_of(value: object) -> KinTransform | None:
    """The kinematic transformation ``value`` describes, None if it describes none.

    A :class:`~mcl.kinematics.KinTransform` is itself; a structure with the fields
    ``BaseRadius``, ``EffectorRadius``, ``UpperArm`` and ``Forearm`` [mm] (all > 0) is a delta
    robot (:class:`~mcl.delta_kinematics.DeltaKinematics`), its arms' range ``ThetaMin`` and
    ``ThetaMax`` [deg] and the tool point's ``MaxVelocity`` [mm/s], ``Acceleration``,
    ``MaxAcceleration`` [mm/s²] and ``Jerk`` [mm/s³] optional (a field missing keeps the
    default, as does a tool point's limit of 0).
    """
    if isinstance(value, KinTransform):
        return value
    if value is None or not all(hasattr(value, name) for name in list(_DELTA_FIELDS)[:4]):
        return None
    try:
        delta = _floats(value, _DELTA_FIELDS, unset=None)
        tcp = _floats(value, _TCP_FIELDS, unset=0.0)
        return DeltaKinematics(**delta, tcp=TcpLimits(**tcp))
    except (TypeError, ValueError):
        return None


def _floats(value: object, fields: dict[str, str], unset: float | None) -> dict[str, float]:
    """The fields of ``value`` named in ``fields`` by their keywords, but those it lacks and
    those of the value ``unset``.

    Raises:
        ValueError: a field is no finite number.
    """
    found: dict[str, float] = {}
    for name, keyword in fields.items():
        number = getattr(value, name, None)
        if number is None or number == unset:
            continue
        if isinstance(number, bool) or not isinstance(number, (int, float)):
            raise ValueError(f"{name} is no number")
        if not math.isfinite(number):
            raise ValueError(f"{name} is not finite")
        found[keyword] = float(number)
    return found


class MC_SetKinTransform(ExecuteFB):
    """Sets the group's kinematic transformation ``KinTransform`` (PLCopen Part 4); Done at once.

    Only while the group stands (GroupDisabled or GroupStandby: EParam 5 while it moves or is
    held, EAxStop 6 in GroupStopping, Eerrstop 11 in GroupErrorStop); 1005 when the group has no
    axes; EParam 5 when ``KinTransform`` is no kinematic transformation or takes another number
    of joints than the group has members; ``KinTransform`` is an MC_KIN_REF (the
    section's introduction).
    """

    REFS: ClassVar[tuple[str, ...]] = ("AxesGroup",)
    INPUTS: ClassVar[tuple[str, ...]] = ("KinTransform",)
    KinTransform: KinRef = None

    def _begin(self) -> int:
        group = self.group
        transform = transform_of(self.KinTransform)
        if not group.axes:
            return ErrorID.EGroupEmpty
        if transform is None:
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

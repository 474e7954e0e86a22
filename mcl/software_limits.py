"""Software limits of an axis (LimPos/LimNeg of GT_SetConstant, GT_SWLim, MC_WriteParameter 2–5).

They act only on a referenced linear axis (Ref set, not modulo). Here: the range they allow, the
checks that refuse a change of the limits or a shift of the coordinate, and their supervision in
the servo cycle; the values live in :attr:`mcl.axis.Axis.parameters`.
"""

from __future__ import annotations

__all__ = ["allowed_range", "change_refused", "crossed", "shift_refused"]

import math
from typing import TYPE_CHECKING

from mcl.command import CoordinateShift
from mcl.errors import ErrorID

if TYPE_CHECKING:
    from mcl.axis import Axis


def allowed_range(axis: Axis) -> tuple[float, float]:
    """The positions the software limits allow now: (negative, positive) [u]; ±inf for a limit
    that is off, and both while the axis has no Ref or is modulo."""
    p = axis.parameters
    if not axis.Ref or not axis.sw_limits_active:
        return -math.inf, math.inf
    return (
        p.sw_limit_neg if p.sw_enable_neg else -math.inf,
        p.sw_limit_pos if p.sw_enable_pos else math.inf,
    )


def change_refused(axis: Axis, pos: float, neg: float, enable_pos: bool, enable_neg: bool) -> int:
    """Why the limits (``pos``, ``neg`` [u], each on or off) cannot be set now, else 0:
    ``EParam`` when both are on and ``pos`` <= ``neg``; ``Ecil`` when (with Ref, on a linear
    axis) a limit that changes (switched on, or moved while on) would lie behind the axis (its
    set point, or its actual position by more than the following-error budget MaxPositionLag)
    or before the end of the running or a queued command, so that a move crossing the new limit
    is never stopped by it halfway. A limit that stays on where it is is not checked again:
    after a software-limit stop beyond it the other limit may still be switched or moved."""
    if enable_pos and enable_neg and pos <= neg:
        return ErrorID.EParam
    p = axis.parameters
    new_pos = enable_pos and not (p.sw_enable_pos and p.sw_limit_pos == pos)
    new_neg = enable_neg and not (p.sw_enable_neg and p.sw_limit_neg == neg)
    if not axis.Ref or axis.config.modulo or not (new_pos or new_neg):
        return 0
    high = pos if new_pos else math.inf
    low = neg if new_neg else -math.inf
    margin = 0.5 * axis.config.resolution
    budget = axis.parameters.max_position_lag
    if not low - margin <= axis.sp_pos <= high + margin:
        return ErrorID.Ecil
    if not low - budget <= axis.actual <= high + budget:
        return ErrorID.Ecil
    if any(not low <= end <= high for end in axis.planned_ends()):
        return ErrorID.Ecil
    return 0


def shift_refused(axis: Axis, delta: float, queued: bool) -> int:
    """``Ecil`` when a coordinate shift by ``delta`` [u] puts the actual position or the target
    of a command it moves (the active one; the queued ones if ``queued``, up to an absolute
    MC_SetPosition queued) beyond an active software limit (only with Ref), else 0."""
    low, high = allowed_range(axis)
    if low == -math.inf and high == math.inf:
        return 0
    positions = [axis.actual]
    for cmd in (axis.active, *axis.queue) if queued else (axis.active,):
        if isinstance(cmd, CoordinateShift) and not cmd.relative:
            break
        if cmd is not None and cmd.target is not None:
            positions.append(cmd.target)
    for position in positions:
        if not low <= position + delta <= high:
            return ErrorID.Ecil
    return 0


def crossed(axis: Axis, v: float, actual: float) -> int:
    """The servo cycle's check: ``ERRSWP`` / ``ERRSWN`` when the axis passes a limit moving
    outward at set-point velocity ``v`` [u/s], else 0. The model must not pass it (half a count:
    rounding of the profile); the ``actual`` position [u] may lag or overshoot the model by the
    following-error budget MaxPositionLag (beyond it only where that is not supervised)."""
    low, high = allowed_range(axis)
    model, budget = axis.sp_pos, axis.parameters.max_position_lag
    margin = 0.5 * axis.config.resolution
    if v > 0.0 and (model > high + margin or actual > high + budget):
        return ErrorID.ERRSWP
    if v < 0.0 and (model < low - margin or actual < low - budget):
        return ErrorID.ERRSWN
    return 0

"""Start positions checked against the physics: a start must not put bodies into one another.

A start is a joint coordinate written into ``qpos`` before the first step. Placed inside a
part or past an end stop, the first step's constraint force ejects the body (the press's punch
started 25 mm inside its part leaves at 14.5 m/s). :func:`check` refuses such a start; the
message names the axis, the value and the range it may start in, found by scanning and
bisecting the joint from its home (keyframe ``<machine>/home``) with the other axes at their
starts.

What counts as interpenetration, after ``mj_forward`` at the pose (lengths in m):

- a contact deeper than :data:`TOLERANCE` (``dist < −TOLERANCE``; a geom's ``margin`` is the
  distance at which its contacts start to act, not a penetration it allows);
- a limited joint or tendon past its range;
- a tendon's deadband spring (``springlength`` lo < hi, stiffness > 0) outside its deadband: a
  contact modelled as a spring, e.g. the press's part (the punch is inside it).
"""

from __future__ import annotations

__all__ = [
    "EDGE",
    "SAMPLES",
    "TOLERANCE",
    "Overlap",
    "allowed_range",
    "check",
    "message",
    "overlaps",
]

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import mujoco

TOLERANCE = 1.0e-6
"""Interpenetration a start may have [m or rad]: rounding, not a physical overlap."""
EDGE = 1.0e-9
"""Interpenetration that marks the end of the allowed range in its search [m or rad]."""
SAMPLES = 200
"""Poses scanned from home to each end of a joint's range."""


@dataclass(frozen=True)
class Overlap:
    """One interpenetration at a pose: what, and how deep [m; rad past a hinge's stop]."""

    what: str
    depth: float
    angle: bool = False

    def describe(self) -> str:
        """``what`` with its depth in mm (rad for an angle)."""
        if self.angle:
            return f"{self.what} by {self.depth:.4g} rad"
        return f"{self.what} by {1000.0 * self.depth:.4g} mm"


def overlaps(
    model: mujoco.MjModel, data: mujoco.MjData, tolerance: float = TOLERANCE
) -> list[Overlap]:
    """The interpenetrations deeper than ``tolerance`` at the current pose (``mj_forward``
    done), deepest first."""
    found: list[Overlap] = []
    for i in range(data.ncon):
        contact = data.contact[i]
        if contact.dist < -tolerance:
            g1, g2 = model.geom(contact.geom1).name, model.geom(contact.geom2).name
            found.append(Overlap(f"the geoms {g1} and {g2} interpenetrate", -contact.dist))
    for j in range(model.njnt):
        kind = int(model.jnt_type[j])
        if not model.jnt_limited[j] or kind not in (
            mujoco.mjtJoint.mjJNT_SLIDE,
            mujoco.mjtJoint.mjJNT_HINGE,
        ):
            continue
        q = float(data.qpos[model.jnt_qposadr[j]])
        lo, hi = (float(v) for v in model.jnt_range[j])
        depth = max(lo - q, q - hi)
        if depth > tolerance:
            what = f"the joint {model.joint(j).name} is past its end stop ({lo:g} … {hi:g})"
            found.append(Overlap(what, depth, kind == mujoco.mjtJoint.mjJNT_HINGE))
    for t in range(model.ntendon):
        name = model.tendon(t).name
        length = float(data.ten_length[t])
        if model.tendon_limited[t]:
            lo, hi = (float(v) for v in model.tendon_range[t])
            depth = max(lo - length, length - hi)
            if depth > tolerance:
                found.append(Overlap(f"the tendon {name} is past its range limit", depth))
        lo, hi = (float(v) for v in model.tendon_lengthspring[t])
        if lo < hi and model.tendon_stiffness[t] > 0.0:
            depth = max(lo - length, length - hi)
            if depth > tolerance:
                what = f"the tendon {name} is inside the contact of its deadband spring"
                found.append(Overlap(what, depth))
    return sorted(found, key=lambda o: -o.depth)


def allowed_range(
    inside: Callable[[float], bool], home: float, lo: float, hi: float
) -> tuple[float, float] | None:
    """The interval around ``home`` within [lo, hi] where ``inside(q)`` is False: scanned in
    :data:`SAMPLES` poses to each end, the first overlap bisected to 10⁻⁹ of the span. None
    when ``home`` itself overlaps."""
    if inside(home):
        return None
    ends = []
    for end in (lo, hi):
        good = home
        for k in range(1, SAMPLES + 1):
            q = home + (end - home) * k / SAMPLES
            if inside(q):
                bad = q
                while abs(bad - good) > 1.0e-9 * max(hi - lo, 1.0e-3):
                    mid = 0.5 * (good + bad)
                    if inside(mid):
                        bad = mid
                    else:
                        good = mid
                break
            good = q
        ends.append(good)
    return ends[0], ends[1]


def message(axis: str, q: float, unit: str, reason: str, span: tuple[float, float] | None) -> str:
    """The refusal of a start: the axis, its value, why, and where it may start."""
    where = ""
    if span is not None:
        where = f"; {axis} may start in {_fmt(span[0])} … {_fmt(span[1])} {unit}"
    return f"start {axis} = {q:g} {unit} is physically impossible: {reason}{where}"


def _fmt(value: float) -> str:
    """A range end for the message, to 1 µm (1 µrad)."""
    text = f"{round(value, 6):g}"
    return "0" if text == "-0" else text


def check(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    starts: Mapping[str, tuple[str, float]],
    homes: Mapping[str, float],
) -> None:
    """Refuse starts that put bodies into one another.

    Args:
        model, data: the model with every start written into ``qpos`` and ``mj_forward`` done.
        starts: by axis name, the joint's (full) name and the start [m or rad].
        homes: by axis name, the joint coordinate of its home [m or rad].

    Raises:
        ValueError: a start makes bodies interpenetrate (the message names the axis, its
            start, what overlaps and the range the axis may start in).
    """
    found = overlaps(model, data)
    if not found:
        return
    reason = found[0].describe()
    saved = data.qpos.copy()
    try:
        for axis, (joint, q) in starts.items():
            j = model.joint(joint)
            adr = int(j.qposadr[0])
            hinge = int(j.type[0]) == mujoco.mjtJoint.mjJNT_HINGE
            unit = "rad" if hinge else "m"
            if j.limited[0]:
                lo, hi = (float(v) for v in j.range)
            else:
                reach = 2.0 * math.pi if hinge else 10.0
                lo, hi = homes[axis] - reach, homes[axis] + reach

            def inside(value: float, adr: int = adr) -> bool:
                data.qpos[adr] = value
                mujoco.mj_forward(model, data)
                return bool(overlaps(model, data, EDGE))

            span = allowed_range(inside, homes[axis], lo, hi)
            data.qpos[:] = saved
            if span is not None and not span[0] - TOLERANCE <= q <= span[1] + TOLERANCE:
                raise ValueError(message(axis, q, unit, reason, span))
    finally:
        data.qpos[:] = saved
        mujoco.mj_forward(model, data)
    axes = ", ".join(f"{a} = {q:g}" for a, (_, q) in starts.items())
    raise ValueError(f"start {axes} is physically impossible together: {reason}")

"""Why a move's ramp inputs are refused with EParam (:func:`mcl.motion.motion_refusal`): each
rule of :func:`mcl.motion.motion_limits` named with the value, and nothing for inputs taken."""

from __future__ import annotations

import math

import mcl
from mcl.motion import motion_refusal
from tests.helpers import fresh_axis


def test_each_refused_ramp_input_is_named_and_a_taken_one_is_not() -> None:
    _, axis = fresh_axis()
    assert axis.constants is not None
    least = 0.01 * axis.constants.Vmax
    below = least * 0.5
    assert motion_refusal(axis, least, 0.0, 0.0, 0.0) == ""  # 1 % of Vmax is taken
    assert motion_refusal(axis, 10 * least, 100.0, 100.0, 1000.0) == ""
    assert motion_refusal(axis, below, 0.0, 0.0, 0.0) == (
        f"Velocity {below:g} mm/s below 1 % of Vmax ({least:g} mm/s)"
    )
    assert motion_refusal(axis, 0.0, 0.0, 0.0, 0.0) == "Velocity 0 mm/s is not > 0"
    assert motion_refusal(axis, math.nan, 0.0, 0.0, 0.0) == "Velocity nan mm/s is not > 0"
    assert motion_refusal(axis, least, -1.0, 0.0, 0.0) == "Acceleration -1 is not >= 0"
    assert motion_refusal(axis, least, 0.0, -2.0, 0.0) == "Deceleration -2 is not >= 0"
    assert motion_refusal(axis, least, 0.0, 0.0, math.inf) == "Jerk inf is not >= 0"
    velocity = 100 * least
    slow = velocity / 200.0  # 200 s to reach it
    assert motion_refusal(axis, velocity, slow, 0.0, 0.0) == (
        f"Acceleration {slow:g} mm/s² takes over 100 s to {velocity:g} mm/s"
    )
    assert motion_refusal(axis, velocity, 0.0, slow, 0.0) == (
        f"Deceleration {slow:g} mm/s² takes over 100 s to {velocity:g} mm/s"
    )
    edge = velocity / 100.0  # exactly 100 s: taken
    assert motion_refusal(axis, velocity, edge, edge, 0.0) == ""


def test_the_refusals_are_the_blocks_eparam() -> None:
    _, axis = fresh_axis()
    assert axis.constants is not None
    move = mcl.MC_MoveVelocity()
    move(Axis=axis, Execute=True, Velocity=0.005 * axis.constants.Vmax)
    assert move.Error and move.ErrorID == mcl.ErrorID.EParam
    move(Axis=axis, Execute=False)
    move(Axis=axis, Execute=True, Velocity=0.01 * axis.constants.Vmax)
    assert not move.Error and move.Busy

"""The gantry as a real machine, judged by the physics: catalogue drive train, commissioned
position loops, limit switches that protect the hard stops, contour at the tool.

Figures come from joint coordinates, joint velocities, the joint-limit (hard stop) constraint
force and the `tool` site, never from the encoder.
"""

from __future__ import annotations

import math
from functools import cache

import mujoco
import numpy as np
import pytest

import mcl
from scenes.machines import gantry
from scenes.scene import model_path
from scenes.tools import commissioning
from scenes.tools.contour import Contour, run_path

AXES = ("X", "Y", "Z")
MOVE_VELOCITY = 400.0
"""Velocity of the point-to-point moves [mm/s]."""


@cache
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(model_path(gantry.MACHINE.model)))


def numeric(name: str) -> float:
    return float(model().numeric(name).data[0])


# ----------------------------------------------------------------------------- drive train


@pytest.mark.parametrize("axis", AXES)
def test_every_motor_runs_3000_rpm_at_10_volts(axis: str) -> None:
    vmax, lead = numeric(f"{axis}_vmax"), numeric(f"{axis}_lead")
    assert vmax / lead * 60.0 == pytest.approx(3000.0)
    constants = gantry.AXES[axis].constants
    assert constants is not None
    assert constants.Vmax == pytest.approx(vmax * 1000.0)


def test_x_inertia_holds_its_steel_screw_and_a_servo_motor() -> None:
    """J of X is at least a Ø25 × 1.1 m steel screw plus a 750 W motor's rotor (1.59e-4)."""
    screw = 7850.0 * math.pi * 0.025**4 * 1.1 / 32.0
    assert screw == pytest.approx(3.3e-4, rel=0.01)
    assert numeric("X_J") >= screw + 1.59e-4


@pytest.fixture(scope="module")
def responses() -> dict[str, commissioning.DriveResponse]:
    return {a: commissioning.identify(gantry.MACHINE, a) for a in AXES}


@pytest.mark.parametrize("axis", AXES)
def test_velocity_loop_of_a_real_amplifier(
    responses: dict[str, commissioning.DriveResponse], axis: str
) -> None:
    """Velocity steps on the amplifier (joint velocity): 100–300 Hz, the gain within 1 % of
    Vmax/10 V, and a hanging Z drifts down at 0 V while X and Y stand."""
    r = responses[axis]
    assert 100.0 <= r.bandwidth <= 300.0, f"{r.bandwidth:.0f} Hz"
    vmax = numeric(f"{axis}_vmax") * 1000.0
    assert r.gain == pytest.approx(vmax / 10.0, rel=0.01)
    if axis == "Z":
        assert r.drift < -0.1
    else:
        assert abs(r.drift) < 0.01


@pytest.mark.parametrize("axis", AXES)
def test_shipped_gains_are_what_the_commissioning_procedure_derives(
    responses: dict[str, commissioning.DriveResponse], axis: str
) -> None:
    spec = gantry.AXES[axis]
    derived = commissioning.derive(spec, responses[axis], gantry.MACHINE.servo_period)
    shipped = spec.constants
    assert shipped is not None
    for name in ("Kp", "Ki", "Ff", "Ka"):
        assert getattr(shipped, name) == pytest.approx(
            getattr(derived.constants, name), rel=0.01
        ), name


# ----------------------------------------------------------------------------- tuning


@pytest.mark.parametrize(
    ("axis", "start", "distance"),
    [
        ("X", 0.30, 200.0),
        ("X", 0.55, -200.0),
        ("Y", 0.20, 200.0),
        ("Y", 0.45, -200.0),
        ("Z", -0.22, 200.0),  # up, against the weight
        ("Z", -0.02, -200.0),
    ],
)
def test_400_mm_per_s_moves_follow_within_30_um_and_stop_without_overshoot(
    axis: str, start: float, distance: float
) -> None:
    """A jerk-limited MC_MoveRelative at 400 mm/s (the axis' default ramps): peak following
    error ≤ 30 µm, overshoot at the stop ≤ 5 µm, within ±5 µm of the target 50 ms after the set
    point stopped, measured on the joint."""
    scene = gantry.build(start={**gantry.MACHINE.demo_start, axis: start}, trace_every=0)
    fig = commissioning.measure_move(scene, axis, distance, MOVE_VELOCITY, settle=0.3)
    assert fig.peak_error <= 0.030, f"{fig.peak_error * 1e3:.1f} µm"
    assert fig.overshoot <= 0.005, f"{fig.overshoot * 1e3:.1f} µm"
    assert fig.settling <= 0.050, f"{fig.settling * 1e3:.0f} ms"
    assert abs(fig.final) <= 0.005


# ----------------------------------------------------------------------------- limit switches


@pytest.mark.parametrize(
    ("axis", "direction", "start"),
    [
        ("X", 1, 0.75),
        ("X", -1, 0.25),
        ("Y", 1, 0.35),
        ("Y", -1, 0.25),
        ("Z", 1, -0.15),
        ("Z", -1, -0.10),
    ],
)
def test_from_vmax_into_a_limit_switch_the_axis_stops_before_the_hard_stop(
    axis: str, direction: int, start: float
) -> None:
    """MC_MoveVelocity at Vmax onto LIM: error 2004/2005, the stop ramp ends ≥ 5 mm before the
    hard stop, which never pushes back (no joint-limit force); the software limits, which stop
    with the same ramp, lie inside the LIM trip points with room for that ramp too."""
    scene = gantry.build(start={**gantry.MACHINE.demo_start, axis: start}, trace_every=0)
    vmax = numeric(f"{axis}_vmax")
    stop = commissioning.run_into_limit(scene, axis, direction, acceleration=10000.0)
    assert stop.error_id == (mcl.ErrorID.ERRLIP if direction > 0 else mcl.ErrorID.ERRLIN)
    assert stop.speed == pytest.approx(vmax, rel=0.02)
    assert stop.stop_force == 0.0
    assert stop.margin >= 0.005, f"{stop.margin * 1e3:.1f} mm left"
    assert abs(scene.data.qvel[scene.io(axis).dof]) < 1e-3

    c = gantry.AXES[axis].constants
    assert c is not None and c.sw_limits_active
    trip = numeric(f"{axis}_lim_{'pos' if direction > 0 else 'neg'}_trip") * 1000.0
    soft = c.LimPos if direction > 0 else c.LimNeg
    travel = scene.model.numeric(f"gantry/{axis}_travel").data * 1000.0
    end = travel[1] if direction > 0 else travel[0]
    assert direction * end < direction * soft < direction * trip
    assert abs(stop.hard_stop * 1000.0 - soft) > stop.distance * 1000.0 + 5.0


# ----------------------------------------------------------------------------- contour


def zigzag(mode: mcl.MC_BufferMode, velocity: float, tolerance: float) -> Contour:
    scene = gantry.build(start=gantry.ZIGZAG_START, trace_every=0)
    modes = [mode] * len(gantry.ZIGZAG)
    return run_path(
        scene, AXES, "gantry/tool", gantry.ZIGZAG, modes, velocity, corner_tolerance=tolerance
    )


@pytest.mark.parametrize("velocity", [200.0, 300.0])
def test_buffered_zigzag_stays_within_20_um_right_after_each_corner(velocity: float) -> None:
    """Each Buffered segment starts when the previous set point ends; the stop leaves no
    overshoot for the next segment to show as contour error."""
    contour = zigzag(mcl.MC_BufferMode.Buffered, velocity, tolerance=0.05)
    corners = contour.vertices[1:-1]
    after = np.zeros(len(contour.points), dtype=bool)
    for c in corners:  # the first 5 mm after each corner: where an overshoot would show
        after |= np.linalg.norm(contour.points - c, axis=1) < 0.005
    assert after.sum() > 50
    errors = contour.errors
    assert errors.max() <= 20e-6, f"{errors.max() * 1e6:.1f} µm"
    assert errors[after].max() <= 20e-6


@pytest.mark.parametrize("velocity", [200.0, 300.0])
def test_blended_zigzag_keeps_the_corner_tolerance_at_the_tool(velocity: float) -> None:
    """BlendingLow with a 50 µm corner tolerance: the tool keeps moving through each corner,
    stays within the tolerance there and within 20 µm on the straight parts."""
    tolerance = 0.050  # mm
    contour = zigzag(mcl.MC_BufferMode.BlendingLow, velocity, tolerance)
    speed = np.linalg.norm(np.diff(contour.points, axis=0), axis=1) / 0.001
    for c in contour.vertices[1:-1]:
        near = np.linalg.norm(contour.points[1:] - c, axis=1) < 0.002
        assert near.any() and speed[near].min() > 0.005, "the tool stopped at a blended corner"
    assert contour.corner_error(0.005) <= tolerance * 1e-3, (
        f"{contour.corner_error(0.005) * 1e6:.1f} µm"
    )
    assert contour.straight_error(0.005) <= 20e-6


def test_blended_corners_lie_on_the_inside_of_the_turn() -> None:
    """With a 0.5 mm corner tolerance at 300 mm/s the tool rounds each corner between the two
    segments: near corner c every point is c − a·u1 + b·u2 with a, b ≥ 0 (u1, u2 the segment
    directions), within 10 µm, while the rounding itself is some 100 µm deep."""
    contour = zigzag(mcl.MC_BufferMode.BlendingLow, 300.0, tolerance=0.5)
    v = contour.vertices
    deepest = 0.0
    for prev, c, nxt in zip(v[:-2], v[1:-1], v[2:], strict=True):
        u1 = (c - prev) / np.linalg.norm(c - prev)
        u2 = (nxt - c) / np.linalg.norm(nxt - c)
        near = contour.points[np.linalg.norm(contour.points - c, axis=1) < 0.005]
        coef, *_ = np.linalg.lstsq(np.stack([-u1, u2], axis=1), (near - c).T, rcond=None)
        assert coef.min() >= -10e-6, f"{coef.min() * 1e6:.1f} µm outside the turn"
        deepest = max(deepest, float(contour.errors.max()))
    assert deepest > 100e-6

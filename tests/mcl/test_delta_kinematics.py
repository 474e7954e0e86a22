"""The rotary delta's kinematics (mcl.delta_kinematics): forward ∘ inverse is the identity over
the working cylinder, and every point or pose it cannot take is refused with an ErrorID."""

from __future__ import annotations

import math
from typing import Any

import pytest

from mcl.delta_kinematics import DeltaKinematics
from mcl.errors import ErrorID
from mcl.kinematics import KinematicsError, KinTransform, TcpLimits, derivatives

DELTA = DeltaKinematics(base_radius=200.0, effector_radius=50.0, upper_arm=350.0, forearm=800.0)


def _cylinder(radius: float = 400.0, top: float = -650.0, height: float = 200.0):
    """A grid over the working cylinder Ø800 × 200 mm [mm]."""
    for zi in range(9):
        z = top - height * zi / 8
        yield [0.0, 0.0, z]
        for ri in range(1, 9):
            r = radius * ri / 8
            for ai in range(36):
                a = 2.0 * math.pi * ai / 36
                yield [r * math.cos(a), r * math.sin(a), z]


def test_forward_of_inverse_is_the_identity_over_the_working_cylinder() -> None:
    worst = 0.0
    count = 0
    for p in _cylinder():
        back = DELTA.forward(DELTA.inverse(p))
        worst = max(worst, max(abs(a - b) for a, b in zip(back, p, strict=True)))
        count += 1
    assert count == 9 * (1 + 8 * 36)
    assert worst < 1e-9


def test_inverse_of_forward_is_the_identity_over_the_joint_range() -> None:
    worst = 0.0
    for a in range(-20, 81, 10):
        for b in range(-20, 81, 10):
            for c in range(-20, 81, 10):
                q = [float(a), float(b), float(c)]
                back = DELTA.inverse(DELTA.forward(q))
                worst = max(worst, max(abs(x - y) for x, y in zip(back, q, strict=True)))
    assert worst < 1e-9


def test_the_arms_of_a_centred_effector_are_equal_and_each_arm_closes() -> None:
    q = DELTA.inverse([0.0, 0.0, -750.0])
    assert q[0] == pytest.approx(q[1], abs=1e-12) == pytest.approx(q[2], abs=1e-12)
    p = [120.0, -80.0, -700.0]
    for i, theta in enumerate(DELTA.inverse(p)):
        phi = 2.0 * math.pi * i / 3.0
        joint = [p[0] + 50.0 * math.cos(phi), p[1] + 50.0 * math.sin(phi), p[2]]
        assert math.dist(joint, DELTA.elbow(i, theta)) == pytest.approx(800.0, abs=1e-9)


@pytest.mark.parametrize(
    ("point", "error_id"),
    [
        ([0.0, 0.0, -300.0], ErrorID.EWorkspace),  # above the reach
        ([0.0, 0.0, -1200.0], ErrorID.EWorkspace),  # below it
        ([900.0, 0.0, -700.0], ErrorID.EWorkspace),  # beside it
        ([500.0, 0.0, -950.0], ErrorID.EWorkspace),  # an arm stretched beyond its reach
        ([0.0, 0.0, math.nan], ErrorID.EParam),
        ([0.0, 0.0], ErrorID.EParam),
    ],
)
def test_a_point_beyond_reach_is_refused(point: list[float], error_id: ErrorID) -> None:
    with pytest.raises(KinematicsError) as refused:
        DELTA.inverse(point)
    assert refused.value.error_id == error_id


def test_a_point_at_the_edge_of_reach_is_refused_as_singular() -> None:
    """Along z the reach ends between -1100 and -1150 mm; the last millimetres before it are
    within the margin of a stretched arm."""
    z = -1100.0
    while True:
        try:
            DELTA.inverse([0.0, 0.0, z])
        except KinematicsError as refused:
            assert refused.error_id == ErrorID.ESingular
            break
        z -= 0.5
    with pytest.raises(KinematicsError) as beyond:
        DELTA.inverse([0.0, 0.0, -1200.0])
    assert beyond.value.error_id == ErrorID.EWorkspace


def test_the_joint_range_bounds_the_workspace() -> None:
    narrow = DeltaKinematics(200.0, 50.0, 350.0, 800.0, theta_min=-10.0, theta_max=60.0)
    with pytest.raises(KinematicsError) as refused:
        narrow.inverse([0.0, 0.0, -550.0])  # every arm at -13.6 deg
    assert refused.value.error_id == ErrorID.EWorkspace
    with pytest.raises(KinematicsError) as pose:
        narrow.forward([70.0, 0.0, 0.0])
    assert pose.value.error_id == ErrorID.EWorkspace


def test_forearms_near_one_plane_are_refused_as_parallel_singular() -> None:
    """With the effector high the forearms flatten toward one plane: |det|/l³ is 0.57 at
    z = -450 mm and 0.79 at -650 mm; a margin of 0.6 refuses the first and takes the second."""
    strict = DeltaKinematics(200.0, 50.0, 350.0, 800.0, theta_min=-90.0, parallel_margin=0.6)
    with pytest.raises(KinematicsError) as refused:
        strict.inverse([0.0, 0.0, -450.0])
    assert refused.value.error_id == ErrorID.ESingular
    assert len(strict.inverse([0.0, 0.0, -650.0])) == 3


def test_no_point_anywhere_gives_a_nan() -> None:
    for x in range(-1500, 1501, 100):
        for z in range(-1600, 401, 100):
            try:
                q = DELTA.inverse([float(x), 0.3 * x, float(z)])
            except KinematicsError:
                continue
            assert all(math.isfinite(v) for v in q)
    for a in range(-60, 101, 20):
        for b in range(-60, 101, 20):
            try:
                p = DELTA.forward([float(a), float(b), 30.0])
            except KinematicsError:
                continue
            assert all(math.isfinite(v) for v in p)


def test_joint_velocity_and_acceleration_follow_the_tool_point() -> None:
    """q̇, q̈ from the central differences match those of the joints along a straight move."""
    p0, v, a = [100.0, 50.0, -700.0], [800.0, -300.0, 200.0], [2000.0, 1000.0, -500.0]
    q, qd, qdd = derivatives(DELTA, p0, v, a)

    def q_at(t: float) -> list[float]:
        return DELTA.inverse(
            [p + vi * t + 0.5 * ai * t * t for p, vi, ai in zip(p0, v, a, strict=True)]
        )

    h = 1e-5
    for i in range(3):
        assert qd[i] == pytest.approx((q_at(h)[i] - q_at(-h)[i]) / (2 * h), rel=1e-5)
        second = (q_at(1e-4)[i] - 2 * q[i] + q_at(-1e-4)[i]) / 1e-8
        assert qdd[i] == pytest.approx(second, rel=1e-3, abs=1e-3)


@pytest.mark.parametrize(
    "geometry",
    [
        {"base_radius": 0.0},
        {"forearm": 300.0},
        {"upper_arm": math.inf},
        {"theta_min": 10.0, "theta_max": 0.0},
        {"margin": 0.0},
        {"parallel_margin": 1.5},
    ],
)
def test_an_invalid_geometry_is_refused(geometry: dict[str, float]) -> None:
    args: dict[str, Any] = {
        "base_radius": 200.0,
        "effector_radius": 50.0,
        "upper_arm": 350.0,
        "forearm": 800.0,
    }
    args.update(geometry)
    with pytest.raises(ValueError, match=next(iter(geometry))):
        DeltaKinematics(**args)


def test_tcp_limits_must_be_positive() -> None:
    with pytest.raises(ValueError, match="velocity"):
        TcpLimits(velocity=0.0)


@pytest.mark.parametrize(
    ("point", "measure"), [([0.0, 0.0, -450.0], 0.57339), ([150.0, -80.0, -520.0], 0.74629)]
)
def test_the_parallel_margin_compares_the_forearms_determinant(
    point: list[float], measure: float
) -> None:
    """|det(f₀, f₁, f₂)|/l³ of the forearms' vectors (computed independently here: 0.57339 at
    the centred pose, 0.74629 off it): a margin just below it takes the point, just above it
    refuses it as singular."""
    q = DeltaKinematics(200.0, 50.0, 350.0, 800.0, theta_min=-90.0).inverse(point)
    forearms = []
    for i, theta in enumerate(q):
        phi = 2.0 * math.pi * i / 3.0
        joint = [point[0] + 50.0 * math.cos(phi), point[1] + 50.0 * math.sin(phi), point[2]]
        elbow = DELTA.elbow(i, theta)
        forearms.append([joint[k] - elbow[k] for k in range(3)])
    (a, b, c), (d, e, f), (g, h, i_) = forearms
    det = a * (e * i_ - f * h) - b * (d * i_ - f * g) + c * (d * h - e * g)
    assert abs(det) / 800.0**3 == pytest.approx(measure, abs=1e-5)
    below = DeltaKinematics(
        200.0, 50.0, 350.0, 800.0, theta_min=-90.0, parallel_margin=measure - 1e-4
    )
    assert below.inverse(point) == pytest.approx(q, abs=1e-12)
    above = DeltaKinematics(
        200.0, 50.0, 350.0, 800.0, theta_min=-90.0, parallel_margin=measure + 1e-4
    )
    with pytest.raises(KinematicsError, match="near one plane") as refused:
        above.inverse(point)
    assert refused.value.error_id == ErrorID.ESingular


def test_the_geometry_its_limits_and_the_identity_are_reported() -> None:
    assert DELTA.parameters() == {
        "base_radius": 200.0,
        "effector_radius": 50.0,
        "upper_arm": 350.0,
        "forearm": 800.0,
        "theta_min": -60.0,
        "theta_max": 100.0,
    }
    assert DELTA.name == "delta" and DELTA.joints == 3
    assert DELTA.tcp == TcpLimits()
    slow = TcpLimits(velocity=1000.0)
    assert DeltaKinematics(200.0, 50.0, 350.0, 800.0, tcp=slow).tcp is slow
    identity = KinTransform()
    assert identity.forward([1.0, 2.0, 3.0]) == [1.0, 2.0, 3.0] == identity.inverse([1.0, 2.0, 3.0])
    assert identity.name == "identity" and identity.parameters() == {}
    with pytest.raises(KinematicsError, match="arm 0 cannot reach"):
        DELTA.inverse([0.0, 0.0, -300.0])


def test_derivatives_at_rest_and_from_rest() -> None:
    """At rest the joints stand; starting from rest (v = 0, a ≠ 0) they only accelerate."""
    p = [100.0, 50.0, -700.0]
    q, qd, qdd = derivatives(DELTA, p, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    assert q == DELTA.inverse(p) and qd == [0.0, 0.0, 0.0] and qdd == [0.0, 0.0, 0.0]
    _, qd, qdd = derivatives(DELTA, p, [0.0, 0.0, 0.0], [0.0, 0.0, -5000.0])
    assert max(abs(v) for v in qd) < 1e-6
    assert min(abs(a) for a in qdd) > 100.0

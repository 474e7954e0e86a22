"""The simulated plant: amplifier, friction, load, brake, end stops, switches, obstacle."""

from __future__ import annotations

import math

import pytest

import mcl
from mcl.simaxis import SimAxis, SimAxisParams

DT = 0.0005


def run(sim: SimAxis, seconds: float, volts: float = 0.0, enable: bool = True) -> list[float]:
    """Apply a constant command for ``seconds``; return the positions after every step (the
    inputs are sampled after every step)."""
    sim.write(volts, enable)
    xs = []
    for _ in range(round(seconds / DT)):
        sim.step(DT)
        sim.sense()
        xs.append(sim.x)
    return xs


def steady_velocity(p: SimAxisParams, volts: float) -> float:
    """amp_gain·(v_cmd − v) = viscous·v + coulomb·sign(v)."""
    v_cmd = volts * 0.1 * p.vmax
    return (p.amp_gain * v_cmd - math.copysign(p.coulomb, v_cmd)) / (p.amp_gain + p.viscous)


@pytest.mark.parametrize("volts", [10.0, -10.0, 5.0])
def test_full_scale_voltage_gives_vmax(volts):
    p = SimAxisParams(start=0.5)
    sim = SimAxis(p)
    run(sim, 0.3, volts)
    expected = steady_velocity(p, volts)
    assert sim.v == pytest.approx(expected, rel=1e-4)
    assert sim.v == pytest.approx(volts * 0.1 * p.vmax, rel=0.05)
    # friction makes it a bit slower than commanded
    assert abs(sim.v) < abs(volts) * 0.1 * p.vmax


def test_without_friction_the_velocity_is_exactly_the_commanded_one():
    p = SimAxisParams(start=0.5, viscous=0.0, coulomb=0.0)
    sim = SimAxis(p)
    run(sim, 0.3, 10.0)
    assert sim.v == pytest.approx(p.vmax, rel=1e-6)


def test_force_limit_bounds_the_acceleration():
    p = SimAxisParams(start=0.2)
    sim = SimAxis(p)
    xs = run(sim, 0.002, 10.0)
    assert len(xs) == 4
    assert abs(sim.force) <= p.force_limit * (1 + 1e-9)
    assert sim.v <= p.force_limit / p.mass * 0.002 * 1.001


def test_disabled_drive_coasts_to_rest_by_friction():
    p = SimAxisParams(start=0.3)
    sim = SimAxis(p)
    sim.v = 0.3
    xs = run(sim, 1.0, 10.0, enable=False)  # volts are ignored while disabled
    assert sim.v == 0.0
    assert sim.force == 0.0
    c, f, m, v0 = p.viscous, p.coulomb, p.mass, 0.3
    stop_time = m / c * math.log(1 + c * v0 / f)
    distance = m / c * (v0 - f / c * math.log(1 + c * v0 / f))
    assert xs[-1] - 0.3 == pytest.approx(distance, rel=0.02)
    # at rest well after the computed stop time and it stays there
    i = round(stop_time * 1.05 / DT)
    assert xs[i] == pytest.approx(xs[-1], abs=1e-9)


def test_brake_holds_a_vertical_load():
    m = 20.0
    p = SimAxisParams(start=0.5, mass=m, load=-m * 9.81, brake_force=400.0)
    assert p.brake_force > abs(p.load)
    sim = SimAxis(p)
    xs = run(sim, 1.0, 0.0, enable=False)
    assert max(abs(x - 0.5) for x in xs) == 0.0
    assert sim.counts == 0


def test_without_brake_a_vertical_load_falls():
    m = 20.0
    p = SimAxisParams(start=0.5, mass=m, load=-m * 9.81)
    sim = SimAxis(p)
    xs = run(sim, 0.2, 0.0, enable=False)
    # (g − friction/m)·t²/2 ≈ 0.17 m in 0.2 s (viscous drag makes it a little less)
    assert xs[-1] < 0.5 - 0.1
    assert sim.v < 0.0
    assert sim.counts < -100000


def test_brake_is_released_when_the_drive_is_enabled():
    m = 20.0
    p = SimAxisParams(start=0.5, mass=m, load=-m * 9.81, brake_force=400.0)
    sim = SimAxis(p)
    run(sim, 0.2, 0.0, enable=True)  # 0 V: the amplifier only holds by its velocity loop
    assert sim.x < 0.5
    # the velocity loop alone sags at load / amp_gain
    assert sim.v == pytest.approx((p.load + p.coulomb) / (p.amp_gain + p.viscous), rel=0.01)


@pytest.mark.parametrize(("volts", "start"), [(10.0, 0.95), (-10.0, 0.05)])
def test_hard_stops_stop_the_axis(volts, start):
    p = SimAxisParams(start=start)
    sim = SimAxis(p)
    xs = run(sim, 1.0, volts)
    if volts > 0:
        assert max(xs) <= p.stop_pos + 0.001
        assert xs[-1] > p.stop_pos  # pressed into the stop
    else:
        assert min(xs) >= p.stop_neg - 0.001
        assert xs[-1] < p.stop_neg
    assert abs(sim.v) < 1e-3
    # full force against the stiffness: force_limit / stiffness deep
    assert abs(xs[-1] - (p.stop_pos if volts > 0 else p.stop_neg)) == pytest.approx(
        p.force_limit / p.stop_stiffness, rel=0.05
    )


@pytest.mark.parametrize(
    ("x", "lim_neg", "lim_pos", "ref"),
    [
        (-0.0051, True, False, True),
        (-0.005, True, False, True),
        (-0.0049, False, False, True),
        (0.0999, False, False, True),
        (0.1, False, False, True),
        (0.1001, False, False, False),
        (0.5, False, False, False),
        (1.0049, False, False, False),
        (1.005, False, True, False),
        (1.0051, False, True, False),
    ],
)
def test_switches_at_their_configured_positions(x, lim_neg, lim_pos, ref):
    sim = SimAxis(SimAxisParams(start=x))
    assert (sim.lim_neg, sim.lim_pos, sim.ref) == (lim_neg, lim_pos, ref)


def test_switches_follow_custom_positions_while_moving():
    p = SimAxisParams(start=0.2, lim_pos=0.25, ref_low=0.21, ref_high=0.22)
    sim = SimAxis(p)
    sim.write(2.0, True)  # 0.1 m/s
    ref_on: list[float] = []
    lim_on: list[float] = []
    prev_ref, prev_lim = sim.ref, sim.lim_pos
    for _ in range(round(0.7 / DT)):
        x_before = sim.x
        sim.step(DT)
        sim.sense()
        if sim.ref != prev_ref:
            ref_on.append(x_before if sim.ref else sim.x)
        if sim.lim_pos and not prev_lim:
            lim_on.append(sim.x)
        prev_ref, prev_lim = sim.ref, sim.lim_pos
    step = 0.1 * DT * 1.1
    assert len(ref_on) == 2
    assert ref_on[0] == pytest.approx(0.21, abs=step)
    assert ref_on[1] == pytest.approx(0.22, abs=step)
    assert len(lim_on) == 1
    assert lim_on[0] == pytest.approx(0.25, abs=step)


def test_obstacle_blocks_positive_motion():
    sim = SimAxis(SimAxisParams(start=0.2))
    sim.blocked_at = 0.25
    xs = run(sim, 0.5, 10.0)
    assert max(xs) == 0.25
    assert xs[-1] == 0.25
    assert sim.v <= 0.0
    # it does not hold the axis back in the negative direction
    run(sim, 0.1, -10.0)
    assert sim.x < 0.25 - 0.01
    # removed: the axis passes
    sim.blocked_at = math.inf
    run(sim, 0.3, 10.0)
    assert sim.x > 0.3


def test_encoder_counts_follow_the_position():
    sim = SimAxis(SimAxisParams(start=0.2))
    run(sim, 0.2, 3.0)
    assert abs(sim.counts - (sim.x - 0.2) / 1e-6) <= 1.0
    assert sim.counts > 10000


def test_sim_machine_rejects_a_resolution_mismatch():
    with pytest.raises(ValueError):
        mcl.SimMachine({"X": SimAxisParams()}, mcl.AxisConfig(resolution=0.01))

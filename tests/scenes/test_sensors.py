"""The sensors' imperfections (:class:`mcl.Sensors`): switch hysteresis and repeatability,
encoder noise, index jitter and the module's one-cycle output latch, measured against the true
position of the axis.

A simulated axis is driven open loop at a slow constant speed back and forth across its REF and
LIM+ trip points; each switch edge is located on the true position between two samples. The
gantry checks the defaults where a user meets them: REF + index homing.
"""

from __future__ import annotations

import math
import statistics

import pytest

import mcl
import scenes
from plc.procedures import HomeAxis
from scenes.machines import gantry

REF_EDGE = 0.100
LIM_POS = 0.300
SPEED = 0.005
"""Crossing speed [m/s]: 5 µm per 1 ms sample, finer than the effects measured."""


def stage(sensors: mcl.Sensors) -> tuple[mcl.SimAxis, mcl.SimPlant]:
    params = mcl.SimAxisParams(
        start=0.2,
        ref_high=REF_EDGE,
        lim_pos=LIM_POS,
        coulomb=0.0,
        viscous=0.0,
        sensors=sensors,
    )
    axis = mcl.SimAxis(params)
    return axis, mcl.SimPlant([axis], 0.0005)


def sweep(
    axis: mcl.SimAxis, plant: mcl.SimPlant, low: float, high: float, passes: int
) -> dict[str, list[tuple[float, bool]]]:
    """Drive ``passes`` times from ``low`` to ``high`` and back; per switch the true position
    [m] of every edge (midway between the two samples around it) and its new level."""
    edges: dict[str, list[tuple[float, bool]]] = {"ref": [], "lim_pos": []}
    volts = SPEED / axis.params.vmax * 10.0
    for target, sign in [(t, s) for _ in range(passes) for t, s in ((high, 1), (low, -1))]:
        axis.write(sign * volts, True)
        while (axis.x - target) * sign < 0:
            x0, before = axis.x, {"ref": axis.ref, "lim_pos": axis.lim_pos}
            plant.step(2)
            plant.sense()
            for name, level in (("ref", axis.ref), ("lim_pos", axis.lim_pos)):
                if level != before[name]:
                    edges[name].append(((x0 + axis.x) / 2, level))
    return edges


def test_switches_trip_at_their_point_and_release_after_the_hysteresis():
    sensors = mcl.Sensors(switch_hysteresis=20e-6, switch_repeatability=0.0)
    axis, plant = stage(sensors)
    edges = sweep(axis, plant, REF_EDGE - 0.001, LIM_POS + 0.001, passes=2)
    # REF is on below its edge: it goes off moving up at the edge, on again 20 µm lower
    ref_off = [x for x, level in edges["ref"] if not level]
    ref_on = [x for x, level in edges["ref"] if level]
    assert len(ref_off) >= 1 and len(ref_on) >= 1
    for x in ref_off:
        assert x == pytest.approx(REF_EDGE + 20e-6, abs=3e-6)
    for x in ref_on:
        assert x == pytest.approx(REF_EDGE, abs=3e-6)
    lim_on = [x for x, level in edges["lim_pos"] if level]
    lim_off = [x for x, level in edges["lim_pos"] if not level]
    for x in lim_on:
        assert x == pytest.approx(LIM_POS, abs=3e-6)
    for x in lim_off:
        assert x == pytest.approx(LIM_POS - 20e-6, abs=3e-6)


def test_switch_trip_points_scatter_by_their_repeatability():
    sigma = 2e-6
    sensors = mcl.Sensors(switch_hysteresis=10e-6, switch_repeatability=sigma, seed=3)
    axis, plant = stage(sensors)
    axis.x = LIM_POS - 0.0004
    edges = sweep(axis, plant, LIM_POS - 0.0004, LIM_POS + 0.0004, passes=40)
    on = [x for x, level in edges["lim_pos"] if level]
    assert len(on) == 40
    spread = statistics.stdev(on)
    assert 0.5 * sigma < spread < 2.0 * sigma, f"trip point scatter {spread * 1e6:.2f} µm"
    assert max(on) - min(on) <= 10e-6  # within the hysteresis: no chatter


def test_ideal_switches_trip_at_the_same_point_every_pass():
    axis, plant = stage(mcl.IDEAL_SENSORS)
    axis.x = LIM_POS - 0.0004
    edges = sweep(axis, plant, LIM_POS - 0.0004, LIM_POS + 0.0004, passes=5)
    assert all(x == pytest.approx(LIM_POS, abs=3e-6) for x, _ in edges["lim_pos"])


def test_encoder_noise_dithers_the_counts_of_an_axis_at_rest():
    readings = {}
    for noise in (0.0, 0.5):
        axis, plant = stage(mcl.Sensors(encoder_noise=noise))
        axis.x = 0.2000005  # half a count from the start: a real encoder flickers here
        counts = []
        for _ in range(400):
            plant.step(2)
            plant.sense()
            counts.append(axis.counts)
        readings[noise] = counts
    (ideal,) = set(readings[0.0])
    dithered = readings[0.5]
    assert all(abs(c - ideal) <= 2 for c in dithered)
    assert len(set(dithered)) >= 2
    assert statistics.fmean(dithered) == pytest.approx(ideal, abs=0.2)


def latches(sensors: mcl.Sensors, passes: int) -> list[int]:
    """The index counts latched moving up across the index at 0.2 m, ``passes`` times."""
    axis, plant = stage(sensors)
    axis.x = 0.199
    plant.sense()
    latched = []
    volts = 0.05 / axis.params.vmax * 10.0
    for _ in range(passes):
        for sign in (1, -1):
            seq = axis.index_seq
            axis.write(sign * volts, True)
            while axis.index_seq == seq:
                plant.step(2)
                plant.sense()
            if sign > 0:
                latched.append(axis.index_count)
            plant.step(40)
    return latched


def test_the_index_latch_is_off_by_at_most_one_count():
    (exact,) = set(latches(mcl.IDEAL_SENSORS, 3))
    latched = latches(mcl.Sensors(index_jitter=0.3, seed=7), 40)
    assert all(abs(c - exact) <= 1 for c in latched), latched
    assert any(c != exact for c in latched), "a real index edge scatters"


def test_the_command_reaches_the_drive_one_servo_cycle_after_it_is_written():
    for delay in (0, 1):
        axis, plant = stage(mcl.Sensors(output_delay=delay))
        axis.write(0.0, True)
        plant.sense()
        axis.write(5.0, True)
        assert axis.volts == (5.0 if delay == 0 else 0.0)
        plant.step(2)
        plant.sense()
        assert axis.volts == 5.0


def test_the_same_seed_gives_the_same_readings():
    def run(seed: int) -> list[int]:
        axis, plant = stage(mcl.Sensors(encoder_noise=0.5, seed=seed))
        out = []
        for _ in range(50):
            plant.step(2)
            plant.sense()
            out.append(axis.counts)
        return out

    assert run(1) == run(1)
    assert run(1) != run(2)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"switch_hysteresis": -1e-6},
        {"switch_repeatability": float("nan")},
        {"encoder_noise": float("inf")},
        {"index_jitter": -0.1},
        {"output_delay": 2},
    ],
)
def test_bad_sensor_data_is_refused_with_the_reason(kwargs):
    with pytest.raises(ValueError, match=next(iter(kwargs))):
        mcl.Sensors(**kwargs)


def test_the_gantry_homes_to_within_one_count_with_its_real_sensors():
    """REF + index homing from both sides of the REF edge with the gantry's default sensors:
    the origin (averaged over 50 samples at rest, the encoder's noise averages out) lies within
    one count of the first index above the REF edge."""
    origins = []
    for start in (0.03, 0.07, 0.16, 0.3):
        scene = gantry.build(start={"X": start, "Y": 0.3, "Z": -0.1}, trace_every=0)
        X = scene.axes["X"]
        power = mcl.MC_Power(Axis=X)
        home = HomeAxis(X, scenes.homing(scene)["X"])

        def program(power: mcl.MC_Power = power, home: HomeAxis = home) -> None:
            power(Enable=True)
            home(Execute=power.Status)

        def homed(home: HomeAxis = home) -> bool:
            return home.Done or home.Error

        scene.run(program, until=homed, timeout=60.0)
        scene.run(program, timeout=0.3)
        assert home.Done and X.Ref
        samples = []
        for _ in range(50):
            scene.run(program, timeout=0.002)
            coordinate = X.POS - home.recipe.set_position  # 0 at the index found [mm]
            samples.append(scene.joint_position("X") - coordinate / 1000.0)
        origins.append(statistics.fmean(samples))
    edge = float(scene.model.numeric("gantry/X_ref_edge").data[0])
    lead = float(scene.model.numeric("gantry/X_lead").data[0])
    expected = math.ceil(edge / lead) * lead
    # a count covers [c, c + 1) µm: averaged readings place the origin half a count high
    for o in origins:
        assert abs(o - (expected + 0.5e-6)) <= 1.0e-6 + 0.25e-6, (o - expected) * 1e6

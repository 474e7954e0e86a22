"""The hydraulic model: flow law, natural frequency, leakage, stiff and blocked cases, replays;
on the press model (MuJoCo) and on the simulated hydraulic axis (the same math)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import mcl
import scenes
from scenes.machines.press import AXES, MASS, cylinder_data
from scenes.machines.press.devices import CylinderDevice
from scenes.machines.press.hydraulic_axis import HydraulicAxis, HydraulicPlant
from scenes.machines.press.hydraulics import (
    BAR,
    Cylinder,
    Supply,
    Valve,
    ValveCylinder,
    natural_frequency,
    steady_state,
)
from scenes.plant.mujoco import MujocoPlant

WEIGHT = MASS * 9.81
"""The ram's weight [N]: it pulls the piston out (the ram extends downward)."""


def press(workpiece: str = "none") -> tuple[scenes.Scene, CylinderDevice]:
    """The press scene driven directly (no PLC): ``workpiece`` "none" (the full stroke is
    free), "spring" (as built) or "solid" (the hard block at the contact)."""
    scene = scenes.load("press", trace_every=0)
    model = scene.model
    tendon = model.tendon(scene.model_name("workpiece")).id
    if workpiece == "none":
        model.tendon_lengthspring[tendon][0] = 0.0
        model.tendon_range[tendon][0] = 0.0
    elif workpiece == "solid":
        model.tendon_range[tendon][0] = model.tendon_lengthspring[tendon][0]
    dev = scene.devices["cylinder"]
    assert isinstance(dev, CylinderDevice)
    return scene, dev


def altered(
    h: ValveCylinder,
    *,
    valve: dict[str, float] | None = None,
    cylinder: dict[str, float] | None = None,
    supply: dict[str, float] | None = None,
) -> ValveCylinder:
    """``h`` with some data of its valve, cylinder and supply changed (the same step)."""
    return ValveCylinder(
        replace(h.valve, **(valve or {})),
        replace(h.cylinder, **(cylinder or {})),
        replace(h.supply, **(supply or {})),
        h.dt,
    )


def place(scene: scenes.Scene, dev: CylinderDevice, q: float) -> None:
    """Put the ram at rest at ``q`` [m], hanging on its oil."""
    import mujoco

    scene.data.qpos[0], scene.data.qvel[0] = q, 0.0
    mujoco.mj_forward(scene.model, scene.data)
    dev.hydraulics.holding_pressures(WEIGHT)


def drive(scene: scenes.Scene, dev: CylinderDevice, volts: float, seconds: float) -> np.ndarray:
    """Valve at ``volts`` (load-holding valve open) for ``seconds``; per step: t, q, v, pA, pB."""
    dev.apply(volts, True, False)
    rows = []
    for _ in range(round(seconds / scene.plant.timestep)):
        scene.plant.step(1)
        h = dev.hydraulics
        rows.append((scene.data.time, scene.data.qpos[0], scene.data.qvel[0], h.p_a, h.p_b))
    return np.array(rows)


# ------------------------------------------------------------------------------ flow law
@pytest.mark.parametrize("volts", [10.0, 5.0, -10.0, -5.0])
def test_free_running_speed_follows_the_flow_law(volts):
    scene, dev = press()
    place(scene, dev, 0.02 if volts > 0 else 0.28)
    dev.apply(volts, True, False)
    speeds: list[float] = []
    while abs(scene.data.qpos[0] - 0.15) > 0.03 or not speeds or len(speeds) < 2:
        scene.plant.step(1)
        if abs(scene.data.qpos[0] - 0.15) <= 0.03:
            speeds.append(float(scene.data.qvel[0]))
        assert scene.data.time < 2.0
    measured = float(np.mean(speeds))
    predicted, _, _ = steady_state(dev.hydraulics, volts / 10.0, WEIGHT)
    print(f"{volts:+5.1f} V: {1000 * measured:7.2f} mm/s, flow law {1000 * predicted:7.2f} mm/s")
    assert measured == pytest.approx(predicted, rel=0.05)


def test_extend_and_retract_differ_as_the_areas_say_and_the_constants_know_it():
    _, dev = press()
    h = dev.hydraulics
    # a symmetric valve on a differential cylinder, no load, no friction: the flow law gives
    # extend/retract = √(A_A/A_B) (the large side's outflow edge limits the retraction)
    ideal = altered(h, cylinder={"coulomb": 0.0, "pressure_friction": 0.0})
    extend, _, _ = steady_state(ideal, 1.0, 0.0)
    retract, _, _ = steady_state(ideal, -1.0, 0.0)
    assert extend / -retract == pytest.approx(math.sqrt(h.area_a / h.area_b), rel=0.002)
    # with the ram's weight and the seal friction: what the servo constants are set to
    extend, _, _ = steady_state(h, 1.0, WEIGHT)
    retract, _, _ = steady_state(h, -1.0, WEIGHT)
    print(f"extend {1000 * extend:.1f} mm/s, retract {-1000 * retract:.1f} mm/s")
    constants = AXES["R"].constants
    assert constants is not None
    assert constants.Vmax == pytest.approx(1000.0 * extend, rel=0.01)
    assert constants.FfNeg == pytest.approx(extend / -retract, rel=0.01)


# ------------------------------------------------------------------------------ ringing
@pytest.mark.parametrize("q0", [0.05, 0.15, 0.24])
def test_ringing_after_a_valve_step_is_the_hydraulic_natural_frequency(q0):
    scene, dev = press()
    place(scene, dev, q0)
    # a pulse upward (the closing valve then compresses side A: no cavitation on the way)
    drive(scene, dev, -10.0, 0.025)
    rows = drive(scene, dev, 0.0, 0.08)
    q = float(rows[0, 1])
    v = rows[rows[:, 0] > rows[0, 0] + 0.003, :]  # the spool has (nearly) closed
    # zero crossings of the velocity, either way: half periods (the seal friction damps the
    # ringing within two or three periods; crossings after it has died out do not count)
    cross = np.flatnonzero(np.sign(v[:-1, 2]) * np.sign(v[1:, 2]) < 0.0)
    ringing = [i for k, i in enumerate(cross[:-1]) if np.abs(v[i : cross[k + 1], 2]).max() > 2e-3]
    cross = cross[: len(ringing) + 1]
    assert len(cross) >= 3
    t = v[cross, 0] + (v[cross + 1, 0] - v[cross, 0]) * (
        -v[cross, 2] / (v[cross + 1, 2] - v[cross, 2])
    )
    measured = 1.0 / (2.0 * float(np.mean(np.diff(t[:4]))))
    _, cylinder, supply = cylinder_data(scene.model, scene.namespace.prefix)
    formula = natural_frequency(cylinder, supply, q, MASS)
    print(f"R = {1000 * q:6.1f} mm: ringing {measured:6.1f} Hz, formula {formula:6.1f} Hz")
    assert measured == pytest.approx(formula, rel=0.10)


# ------------------------------------------------------------------------------ 0 V
def test_at_0_V_without_leakage_the_ram_hangs_on_its_oil_without_sinking():
    scene, dev = press()
    tight = altered(dev.hydraulics, valve={"leakage": 0.0}, cylinder={"internal_leakage": 0.0})
    dev.hydraulics = tight
    place(scene, dev, 0.15)
    drive(scene, dev, 0.0, 0.3)
    rows = drive(scene, dev, 0.0, 1.0)
    drift = abs(rows[-1, 1] - rows[0, 1])
    print(f"0 V, no leakage: moved {1e6 * drift:.3f} µm in 1 s")
    assert drift < 1e-6
    assert tight.p_b * tight.area_b - tight.p_a * tight.area_a == pytest.approx(WEIGHT, rel=0.01)


def test_at_0_V_the_ram_drifts_as_the_leakage_model_says():
    axis = HydraulicAxis(ValveCylinder(*valve_data(), dt=0.0005), MASS, load=WEIGHT, start=0.15)
    h = axis.hydraulics
    predicted, p_a, p_b = steady_state(h, 0.0, WEIGHT)
    h.p_a, h.p_b = p_a, p_b
    axis.drive(0.0, True, False)
    plant = HydraulicPlant(axis)
    plant.step(1000)
    x0 = axis.x
    plant.step(2000)
    measured = (axis.x - x0) / 1.0
    assert predicted > 0.0  # the 2:1 areas at equal leakage push the ram out
    assert measured == pytest.approx(predicted, rel=0.05)
    assert h.p_a == pytest.approx(p_a, rel=0.01) and h.p_b == pytest.approx(p_b, rel=0.01)
    # the same on the press model: MuJoCo's seal friction and the device's coupling add nothing
    scene, dev = press()
    place(scene, dev, 0.15)
    dev.hydraulics.p_a, dev.hydraulics.p_b = p_a, p_b
    rows = drive(scene, dev, 0.0, 1.5)
    on_model = (rows[-1, 1] - rows[1000, 1]) / (rows[-1, 0] - rows[1000, 0])
    print(
        f"0 V drift: simulated axis {1e3 * measured:.4f} mm/s, press model "
        f"{1e3 * on_model:.4f} mm/s, leakage model {1e3 * predicted:.4f} mm/s"
    )
    assert on_model == pytest.approx(predicted, rel=0.05)


def valve_data() -> tuple[Valve, Cylinder, Supply]:
    scene = scenes.load("press", trace_every=0)
    return cylinder_data(scene.model, scene.namespace.prefix)


# ------------------------------------------------------------------------------ stability
def test_pressing_solid_builds_supply_pressure_fast_and_stays_still():
    scene, dev = press("solid")
    place(scene, dev, 0.2499)  # touching the block
    rows = drive(scene, dev, 10.0, 0.2)
    assert np.all(np.isfinite(rows))
    t_190 = rows[np.argmax(rows[:, 3] >= 190.0 * BAR), 0] - rows[0, 0]
    rate = np.diff(rows[:, 3]).max() / BAR / (1000.0 * scene.plant.timestep)
    print(f"pressing solid at 10 V: 190 bar after {1000 * t_190:.1f} ms, up to {rate:.0f} bar/ms")
    assert rows[:, 3].max() <= 200.0 * BAR + 1.0
    assert rows[:, 3].min() >= 0.0 and rows[:, 4].min() >= 0.0
    assert np.abs(rows[-200:, 2]).max() < 1e-3  # at rest on the block
    assert dev.hydraulics.iterations <= 12
    # the small chamber at the top end: full valve into 100 cm³
    scene, dev = press()
    place(scene, dev, 0.0)
    rows = drive(scene, dev, -10.0, 0.05)
    t_190 = rows[np.argmax(rows[:, 4] >= 190.0 * BAR), 0] - rows[0, 0]
    print(f"top stop at -10 V: side B 190 bar after {1000 * t_190:.1f} ms")
    assert rows[:, 4].max() <= 200.0 * BAR + 1.0


@pytest.mark.parametrize(("q0", "volts"), [(0.01, -10.0), (0.29, 10.0)])
def test_full_valve_into_either_end_stop_is_stable(q0, volts):
    scene, dev = press()
    place(scene, dev, q0)
    rows = drive(scene, dev, volts, 0.3)
    assert np.all(np.isfinite(rows))
    assert -0.001 < rows[-1, 1] < 0.301
    assert np.abs(rows[-100:, 2]).max() < 1e-3
    assert rows[:, 3:].max() <= 220.0 * BAR


def test_a_supply_above_the_relief_setting_is_held_at_the_setting_plus_its_override():
    scene, dev = press("solid")
    # a pump compensator set too high
    dev.hydraulics = altered(dev.hydraulics, supply={"supply": 300.0 * BAR})
    supply = dev.hydraulics.supply
    place(scene, dev, 0.2499)  # touching the block
    rows = drive(scene, dev, 10.0, 0.3)
    assert np.all(np.isfinite(rows))
    # side A would reach 300 bar; its line relief valve passes the valve's flow (57 l/min at
    # 70 bar across the open edge, half its rated 120 l/min) at 220 bar plus half its override
    relief = supply.relief + supply.relief_override * 57.0 / 120.0
    print(f"supply 300 bar into a solid part: side A {rows[-1, 3] / BAR:.1f} bar")
    assert rows[-1, 3] == pytest.approx(relief, abs=1.0 * BAR)
    assert rows[:, 3].max() <= supply.relief_limit
    assert np.abs(rows[-100:, 2]).max() < 1e-3


@pytest.mark.parametrize("volts", [10.0, -10.0])
def test_the_load_holding_valves_shut_both_ports_whatever_the_valve_does(volts):
    # the drive enabled with its brake output still on (a slow brake): the valve is open, the
    # cylinder stays shut off from it
    scene, dev = press()
    place(scene, dev, 0.15)
    dev.apply(volts, True, True)
    start = float(scene.data.qpos[0])
    for _ in range(2000):
        scene.plant.step(1)
    moved = float(scene.data.qpos[0]) - start
    print(f"{volts:+.0f} V, load-holding valves shut: moved {1e6 * moved:.3f} µm in 1 s")
    assert abs(moved) < 1e-6


# ------------------------------------------------------------------------------ state
def test_the_hydraulic_state_replays_bit_identically():
    scene, dev = press("spring")
    place(scene, dev, 0.24)
    plant = scene.plant
    assert isinstance(plant, MujocoPlant)
    start = plant.get_state()
    readings = []

    def run() -> np.ndarray:
        out = drive(scene, dev, 2.0, 0.1)
        readings.append([dev.analog(n) for n in ("p_A", "p_B", "load")])
        return np.vstack([out, drive(scene, dev, -1.0, 0.05)])

    first = run()
    plant.set_state(start)
    second = run()
    assert np.array_equal(first, second)
    assert readings[0] == readings[1]


def test_the_transducers_read_12_bit_volts_with_seeded_noise():
    scene, dev = press("spring")
    place(scene, dev, 0.2)
    drive(scene, dev, -0.5, 0.05)
    lsb = 10.0 / 4095
    values = [dev.analog("p_B") for _ in range(200)]
    truth = dev.hydraulics.p_b / (250.0 * BAR) * 10.0
    assert all(abs(v / lsb - round(v / lsb)) < 1e-9 for v in values)
    assert np.mean(values) == pytest.approx(truth, abs=lsb)
    assert 0.001 < np.std(values) < 0.004  # 2 mV of noise
    with pytest.raises(scenes.scene.WiringError, match="p_A"):
        dev.analog("p_C")


# ------------------------------------------------------------------------------ mcl on it
def sim_axis(**constants: float) -> tuple[mcl.Axis, HydraulicPlant, mcl.Runtime]:
    valve, cylinder, supply = valve_data()
    overlap = constants.pop("overlap", 0.0)
    h = ValveCylinder(replace(valve, overlap=overlap), cylinder, supply, 0.0005)
    io = HydraulicAxis(h, MASS, load=WEIGHT, start=0.1)
    plant = HydraulicPlant(io)
    config = replace(AXES["R"].config)
    axis = mcl.Axis(io, config, "R")
    base = AXES["R"].constants
    assert base is not None
    axis.set_constants(replace(base, LimPos=0.0, LimNeg=0.0, **constants))
    return axis, plant, mcl.Runtime(plant, [axis], 0.001)


def true_error(axis: mcl.Axis, since: tuple[float, float]) -> float:
    """Set-point minus where the piston is (its extension, the physics) [mm]: ``since`` the
    set-point [mm] and the extension [m] of one moment before the motion."""
    io = axis.io
    assert isinstance(io, HydraulicAxis)
    return axis.sp_pos - since[0] - 1000.0 * (io.x - since[1])


def peak_error(axis: mcl.Axis, runtime: mcl.Runtime, distance: float) -> float:
    power = mcl.MC_Power(Axis=axis)
    move = mcl.MC_MoveRelative(Axis=axis, Distance=distance, Velocity=150.0, Acceleration=2000.0)
    worst = [0.0]
    io = axis.io
    assert isinstance(io, HydraulicAxis)
    since = (axis.sp_pos, io.x)

    def observe(t: float) -> None:
        if axis.sp_acc == 0.0 and axis.sp_vel != 0.0:  # constant speed
            worst[0] = max(worst[0], abs(true_error(axis, since)))

    runtime.observers.append(observe)

    def program() -> None:
        power(Enable=True)
        move(Execute=power.Status)

    runtime.run(program, until=lambda: move.Done, timeout=3.0)
    return worst[0]


def test_direction_dependent_feed_forward_keeps_the_retraction_on_its_model():
    axis, _, runtime = sim_axis()
    with_ffneg = peak_error(axis, runtime, -100.0)
    axis, _, runtime = sim_axis(FfNeg=0.0)
    without = peak_error(axis, runtime, -100.0)
    axis, _, runtime = sim_axis()
    extending = peak_error(axis, runtime, 100.0)
    print(
        f"following error at 150 mm/s: retract {with_ffneg:.3f} mm with FfNeg, "
        f"{without:.3f} mm without; extend {extending:.3f} mm"
    )
    assert with_ffneg < without / 3.0
    assert with_ffneg < 0.2 and extending < 0.2


def test_deadband_compensation_lets_an_overlapped_valve_reach_its_window():
    results = {}
    for deadband in (0.0, 1.0):
        axis, _, runtime = sim_axis(overlap=0.1, Deadband=deadband, Ki=0.0)
        power = mcl.MC_Power(Axis=axis)
        move = mcl.MC_MoveRelative(Axis=axis, Distance=0.5, Velocity=20.0)
        io = axis.io
        assert isinstance(io, HydraulicAxis)
        start = io.x

        def program(power=power, move=move, axis=axis) -> None:
            power(Enable=True)
            move(Execute=power.Status)

        def done(move: mcl.MC_MoveRelative = move) -> bool:
            return bool(move.Done)

        runtime.run(program, until=done, timeout=2.0)
        runtime.run(program, timeout=0.3)
        results[deadband] = abs(0.5 - 1000.0 * (io.x - start))  # from the piston's extension
    print(
        f"overlapped valve (1 V): residual error {results[0.0]:.3f} mm, "
        f"compensated {results[1.0]:.3f} mm"
    )
    assert results[1.0] <= 0.05 < results[0.0]


def test_valve_hysteresis_is_a_play_of_its_width_and_the_spool_follows_at_60_hz():
    valve, cylinder, supply = valve_data()
    h = ValveCylinder(replace(valve, hysteresis=0.02), cylinder, supply, 0.0005)
    spool = {}
    for direction, volts in (
        ("up", np.linspace(0.0, 5.0, 400)),
        ("down", np.linspace(5.0, 0.0, 400)),
    ):
        for u in volts:
            h.command = float(u)
            for _ in range(20):  # 10 ms per command value: the spool settles
                h._spool_step()
            if abs(u - 3.0) < 0.007:
                spool[direction] = h.spool
    assert spool["up"] - spool["down"] == pytest.approx(-0.02, abs=1e-3)
    # a step: second order, 60 Hz, ζ 0.7 (overshoot 4.6 %)
    h = ValveCylinder(valve, cylinder, supply, 0.0005)
    h.command = 5.0
    trace = []
    for _ in range(100):
        h._spool_step()
        trace.append(h.spool)
    assert max(trace) == pytest.approx(
        0.5 * (1.0 + math.exp(-math.pi * 0.7 / math.sqrt(1 - 0.49))), rel=1e-3
    )

"""Example scenarios for sweeps (:mod:`scenes.sweep`): plain functions of their parameters and a
seed, each returning the metrics a user would study.

- :func:`homing_repeatability`: REF + index homing of the gantry's X against switch hysteresis;
- :func:`cut_length`: the flying shear's piece-length error against line speed, slip and ripple;
- :func:`payload_following_error`: a jerk-limited move of a simulated axis against payload and
  friction (cheap: for trying out sweeps and clusters).
"""

from __future__ import annotations

import statistics

import mcl
import scenes
from scenes.procedures import HomeAxis


def homing_repeatability(
    seed: int, hysteresis_um: float = 10.0, start_mm: float = 300.0
) -> dict[str, float]:
    """Home the gantry's X (REF switch, then the next index pulse) from ``start_mm``.

    Args:
        seed: the sensors' noise.
        hysteresis_um: the switches' hysteresis [µm].
        start_mm: where X stands at power-up [mm].

    Returns:
        ``origin_error_um``: where the homed coordinate's origin lies on the joint, against the
        index position [µm] (averaged over 50 samples at rest); ``ref_off_mm``: the joint
        position at which REF last went off during the search [mm]; ``homing_s``: its duration
        [s].
    """
    sensors = mcl.Sensors(switch_hysteresis=hysteresis_um * 1e-6, seed=seed)
    scene = scenes.load("gantry", start={"X": start_mm / 1000.0}, sensors=sensors, trace_every=0)
    X = scene.axes["X"]
    recipe = scenes.homing(scene)["X"]
    power, home = mcl.MC_Power(Axis=X), HomeAxis(X, recipe)
    io = scene.io("X")
    ref_off: list[float] = []  # joint positions where REF went from on to off
    level = [io.ref]

    def watch(t: float) -> None:
        if level[0] and not io.ref:
            ref_off.append(scene.joint_position("X"))
        level[0] = io.ref

    scene.runtime.observers.append(watch)

    def program() -> None:
        power(Enable=True)
        home(Execute=power.Status)

    took = scene.run(program, until=lambda: home.Done or home.Error, timeout=60.0)
    if home.Error:
        raise RuntimeError(f"homing failed with ErrorID {home.ErrorID}")
    scene.run(program, timeout=0.3)
    origins = []
    for _ in range(50):
        scene.run(program, timeout=0.002)
        origins.append(scene.joint_position("X") - (X.POS - recipe.set_position) / 1000.0)
    lead = float(scene.model.numeric("gantry/X_lead").data[0])
    edge = float(scene.model.numeric("gantry/X_ref_edge").data[0])
    index = -(-edge // lead) * lead  # the first index above the REF edge
    return {
        "origin_error_um": (statistics.fmean(origins) - index) * 1e6,
        "ref_off_mm": ref_off[-1] * 1000.0 if ref_off else float("nan"),
        "homing_s": took,
    }


def payload_following_error(
    seed: int, payload_kg: float = 0.0, friction_n: float = 15.0
) -> dict[str, float]:
    """A 100 mm, 200 mm/s move of a simulated axis carrying ``payload_kg`` against
    ``friction_n`` of Coulomb friction, with a real machine's sensors (noise seeded by ``seed``).

    Returns:
        ``peak_following_error_mm`` and ``final_error_um`` (at rest, from the physics).
    """
    params = mcl.SimAxisParams(
        start=0.2, mass=20.0 + payload_kg, coulomb=friction_n, sensors=mcl.Sensors(seed=seed)
    )
    machine = mcl.SimMachine({"X": params})
    X = machine.axes["X"]
    constants = mcl.GT_SetConstant(
        Axis=X, Kp=3.0, Ki=150.0, Ff=1.0, Kc=50.0, Vmax=500.0, Filter=2.0, Ka=0.0065
    )
    power, home = mcl.MC_Power(Axis=X), mcl.MC_FinishHoming(Axis=X)
    move = mcl.MC_MoveRelative(Axis=X, Distance=100.0, Velocity=200.0, Acceleration=2000.0)
    peak = [0.0]
    machine.runtime.observers.append(
        lambda t: peak.__setitem__(0, max(peak[0], abs(X.following_error)))
    )

    def program() -> None:
        constants(Execute=True)
        power(Enable=constants.Done)
        home(Execute=power.Status)
        move(Execute=home.Done)

    machine.run(program, until=lambda: move.Done or move.Error, timeout=5.0)
    machine.run(program, timeout=0.2)
    truth = (machine.sims["X"].x - 0.2) * 1000.0
    return {"peak_following_error_mm": peak[0], "final_error_um": (truth - 100.0) * 1000.0}


def cut_length(
    seed: int, speed_m_min: float = 60.0, slip_pct: float = 0.0, ripple_pct: float = 1.0
) -> dict[str, float]:
    """Cut to length on the flying shear: 6 cuts (5 pieces) of 1500 mm, MC_GearInPos Zeroing 1.

    Args:
        seed: the sensors' noise.
        speed_m_min: line speed [m/min].
        slip_pct: constant slip of the measuring wheel [%] (−0.5: it reads 0.5 % short).
        ripple_pct: line-speed ripple of the eccentric pinch roll [%].

    Returns:
        Piece-length error from the physics [mm]: ``mean_error_mm``, ``worst_error_mm``; the
        worst carriage/strip speed mismatch during a cut ``mismatch_pct``; ``pieces`` cut (fewer
        than 5 when the job stopped with an error, e.g. a sync out of reach).
    """
    from scenes import flying_shear as fs

    scene = scenes.load(
        "flying_shear",
        start=fs.MACHINE.demo_start,
        trace_every=0,
        sensors=mcl.Sensors(seed=seed),
    )
    scene.device("wheel", fs.MeasuringWheel).slip = slip_pct / 100.0
    scene.device("ripple", fs.EccentricRoll).eccentricity = ripple_pct / 100.0
    demo = fs.Demo(scene, fs.CutJob(speed=speed_m_min * 1000.0 / 60.0, cuts=6))
    scene.run(demo, until=lambda: demo.done or bool(demo.error), timeout=60.0)
    errors = demo.errors()
    cuts = demo.recorder.cuts
    return {
        "pieces": float(len(errors)),
        "mean_error_mm": statistics.fmean(errors) if errors else float("nan"),
        "worst_error_mm": max(errors, key=abs) if errors else float("nan"),
        "mismatch_pct": 100.0 * max((c.speed_mismatch for c in cuts), default=float("nan")),
    }

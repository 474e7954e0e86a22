"""Scenarios of the gantry for sweeps (:mod:`scenes.tools.sweep`): plain functions of their
parameters and a seed, each returning the metrics a user would study.

- :func:`homing_repeatability`: REF + index homing of X against switch hysteresis.
"""

from __future__ import annotations

__all__ = ["homing_repeatability"]

import statistics

import mcl
import scenes
from plc.procedures import HomeAxis


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
    lead = float(scene.model.numeric(scene.model_name("X_lead")).data[0])
    edge = float(scene.model.numeric(scene.model_name("X_ref_edge")).data[0])
    index = -(-edge // lead) * lead  # the first index above the REF edge
    return {
        "origin_error_um": (statistics.fmean(origins) - index) * 1e6,
        "ref_off_mm": ref_off[-1] * 1000.0 if ref_off else float("nan"),
        "homing_s": took,
    }

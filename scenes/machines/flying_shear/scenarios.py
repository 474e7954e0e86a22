"""Scenarios of the flying shear for sweeps (:mod:`scenes.tools.sweep`): plain functions of
their parameters and a seed, each returning the metrics a user would study.

- :func:`cut_length`: the piece-length error against line speed, slip and ripple.
"""

from __future__ import annotations

__all__ = ["cut_length"]

import statistics

import mcl
import scenes
from scenes.machines import flying_shear as fs


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

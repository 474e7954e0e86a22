"""Benchmark: arcs and paths of an axes group.

Prints JSON:

- ``commanded_radius_error``: per CircMode, a full circle of R = 50 mm commanded on simulated
  axes (CENTER: one arc with its end on its start; BORDER and RADIUS, which cannot describe a
  full circle: two half circles, Buffered), the largest relative deviation of the set point
  from the radius over every servo cycle (goal: ≤ 1e-9);
- ``gantry_circle_R50``: a full circle of R = 50 mm on the gantry's physics (X, Y) at F1000,
  F3000 and F5000, counter-clockwise: the largest and mean radial deviation of the `tool` site
  [µm], and the time it took;
- ``gantry_gcode_contour_F3000``: the G-code contour of tests/scenes/test_gantry_arcs.py (lines
  and arcs, tangent and non-tangent corners): the tool's and the encoders' largest distance from
  the commanded lines and arcs [µm] (corner tolerance 20 µm);
- ``gantry_circle_test``: the circle test of ISO 230-4 (:mod:`scenes.tools.circle`) in XY, R 50
  and 150 mm at F1000/F3000/F5000, both directions, measured at the joints (and G at the
  encoders): with the feed-forward on (as commissioned) G, the largest radial deviation and
  the largest reversal spike [µm]; with the velocity and acceleration feed-forward off (Ff =
  Ka = 0) the mean radius change against the first-order estimate ``−v²/(2·R·Kv²)`` (Kv =
  Kp·Vmax/10) and against the loop's linear model (:func:`loop_radius_change`); G and the
  spikes with the friction feed-forward's band off (Vf = 0: Kf's own ramp over 1.3 mm/s, as
  before the band); and, R 50, the spikes with the friction feed-forward Kf off.

Run: ``python -m tests.benchmarks.arcs`` (``--circle`` for the circle test alone).
"""

from __future__ import annotations

import copy
import json
import math
import sys
from typing import Any

import numpy as np

import mcl
from scenes.machines import gantry
from scenes.tools.circle import circle_test
from tests.helpers import make_machine
from tests.mcl.test_group import build_group, record
from tests.scenes.test_gantry_arcs import CONTOUR, contour_pieces, run_on_gantry

RADIUS = 50.0
CENTER, BORDER, RADIUS_MODE = (
    mcl.MC_CIRC_MODE.CENTER,
    mcl.MC_CIRC_MODE.BORDER,
    mcl.MC_CIRC_MODE.RADIUS,
)
CCW = mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
DYNAMICS = dict(Velocity=100.0, Acceleration=2000.0, Deceleration=2000.0, Jerk=50000.0)


def _circle_blocks(group: mcl.AxesGroup, mode: int) -> list[mcl.MC_MoveCircularAbsolute]:
    """The blocks of a full circle of RADIUS about (RADIUS, 0) from (0, 0) in ``mode``."""
    far = [2.0 * RADIUS, 0.0]
    if mode == CENTER:
        specs: list[dict[str, Any]] = [dict(AuxPoint=[RADIUS, 0.0], EndPoint=[0.0, 0.0])]
    elif mode == BORDER:
        specs = [
            dict(AuxPoint=[RADIUS, -RADIUS], EndPoint=far),
            dict(AuxPoint=[RADIUS, RADIUS], EndPoint=[0.0, 0.0]),
        ]
    else:
        specs = [
            dict(AuxPoint=[RADIUS], EndPoint=far),
            dict(AuxPoint=[RADIUS], EndPoint=[0.0, 0.0]),
        ]
    return [
        mcl.MC_MoveCircularAbsolute(
            AxesGroup=group,
            CircMode=mode,
            PathChoice=CCW,
            BufferMode=mcl.MC_BufferMode.Buffered,
            **spec,
            **DYNAMICS,
        )
        for spec in specs
    ]


def commanded_radius_error() -> dict[str, float]:
    """The set point's largest relative radius error over a full circle, per CircMode."""
    out: dict[str, float] = {}
    for mode in (BORDER, CENTER, RADIUS_MODE):
        machine = make_machine("XY")
        group = build_group(machine, "XY")
        rec = record(machine, "XY")
        blocks = _circle_blocks(group, mode)

        def program(blocks: list[mcl.MC_MoveCircularAbsolute] = blocks) -> None:
            for block in blocks:
                block(Execute=True)

        machine.run(program, until=lambda: blocks[-1].Done, timeout=20.0)  # noqa: B023
        errors = [abs(math.dist(p, (RADIUS, 0.0)) - RADIUS) / RADIUS for p in rec.model]
        out[mode.name] = float(f"{max(errors):.3g}")
    return out


def gantry_circles() -> dict[str, dict[str, float]]:
    """Full circles of R = 50 mm on the gantry at three feeds."""
    out: dict[str, dict[str, float]] = {}
    for feed in (1000.0, 3000.0, 5000.0):
        block = mcl.MC_MoveCircularRelative(
            CircMode=CENTER,
            AuxPoint=[RADIUS, 0.0],
            EndPoint=[0.0, 0.0],
            PathChoice=CCW,
            Velocity=feed / 60.0,
            Acceleration=2000.0,
            Deceleration=2000.0,
            Jerk=20000.0,
        )
        points, _, _ = run_on_gantry(block)
        deviation = np.abs(np.linalg.norm(points - np.array([RADIUS, 0.0]), axis=1) - RADIUS)
        out[f"F{feed:g}"] = {
            "radial_deviation_max_um": round(float(deviation.max()) * 1e3, 2),
            "radial_deviation_mean_um": round(float(deviation.mean()) * 1e3, 2),
            "duration_s": round(len(points) * 0.001, 3),
        }
    return out


def gantry_contour() -> dict[str, float]:
    """The G-code contour at F3000 on the gantry."""
    select = mcl.MC_PathSelect(PathDescription=CONTOUR)
    select(Execute=True)
    points, encoders, _ = run_on_gantry(mcl.MC_MovePath(PathData=select.PathData))
    pieces = contour_pieces()
    tool = max(min(g.distance(p) for g in pieces) for p in points)
    feedback = max(min(g.distance(p) for g in pieces) for p in encoders)
    return {
        "tool_max_um": round(tool * 1e3, 2),
        "encoders_max_um": round(feedback * 1e3, 2),
        "corner_tolerance_um": 20.0,
    }


CIRCLE_START = {"X": 0.5, "Y": 0.3, "Z": -0.1}
"""Joint coordinates of the circle test's centre [m]: the middle of X's and Y's travel."""


def _circle(radius: float, feed: float, **changes: float) -> Any:
    """The circle test on a fresh gantry, both directions, X's and Y's servo constants changed
    by ``changes`` (e.g. ``Ff=0.0``)."""
    scene = gantry.build(start=CIRCLE_START, trace_every=0)
    for name in ("X", "Y"):
        axis = scene.axes[name]
        assert axis.constants is not None
        constants = copy.copy(axis.constants)
        for key, value in changes.items():
            setattr(constants, key, value)
        axis.set_constants(constants)
    return circle_test(scene, "XY", radius, feed, "both"), scene


def loop_radius_change(constants: mcl.ServoConstants, radius: float, speed: float) -> float:
    """The radius change [mm] the linear model of one axis' loop predicts for a circle without
    feed-forward: ``R·(|H(jω)| − 1)``, ω = v/R, H = C·P/(1 + C·P) with the PI regulator
    ``C = Kp + Ki/s`` [V/mm], the amplifier's velocity ``P = (Vmax/10)·e^(−sT)/(s·(1 + s·τ))``,
    τ = 1/(2·Kv) (the commissioned lag that Kv = 1/(2·lag) was chosen for) and T = 1 ms
    (the module's one-cycle output delay)."""
    s = 1j * speed / radius
    kv = constants.Kp * constants.Vmax / 10.0
    tau = 1.0 / (2.0 * kv)
    c = constants.Kp + constants.Ki / s
    p = constants.Vmax / 10.0 * np.exp(-s * 0.001) / (s * (1.0 + s * tau))
    return float(radius * (abs(c * p / (1.0 + c * p)) - 1.0))


def gantry_circle_test() -> dict[str, Any]:
    """The circle test with and without feed-forward, without the friction band, and the
    spikes without Kf."""
    on: dict[str, Any] = {}
    off: dict[str, Any] = {}
    friction: dict[str, Any] = {}
    no_band: dict[str, Any] = {}
    for radius in (50.0, 150.0):
        for feed in (1000.0, 3000.0, 5000.0):
            key = f"R{radius:g}_F{feed:g}"
            result, _ = _circle(radius, feed)
            joints = result.figures["joints"]
            on[key] = {
                d: {
                    "G_um": round(f.G * 1e3, 2),
                    "G_encoders_um": round(result.figures["encoders"][d].G * 1e3, 2),
                    "radial_um": round(f.radial * 1e3, 2),
                    "spike_um": round(f.spike * 1e3, 2),
                }
                for d, f in joints.items()
            }
            on[key]["G_bidirectional_um"] = round(result.bidirectional["joints"] * 1e3, 2)
            result, scene = _circle(radius, feed, Ff=0.0, Ka=0.0)
            constants = scene.axes["X"].constants
            kv = np.mean([scene.axes[n].constants.Kp for n in "XY"]) * constants.Vmax / 10.0
            speed = feed / 60.0
            measured = np.mean([f.mean_radial for f in result.figures["joints"].values()])
            first_order = -(speed**2) / (2.0 * radius * float(kv) ** 2)
            model = np.mean(
                [loop_radius_change(scene.axes[n].constants, radius, speed) for n in "XY"]
            )
            off[key] = {
                "mean_radial_um": round(float(measured) * 1e3, 3),
                "first_order_um": round(first_order * 1e3, 3),
                "loop_model_um": round(float(model) * 1e3, 3),
                "G_um": round(max(f.G for f in result.figures["joints"].values()) * 1e3, 2),
            }
            result, _ = _circle(radius, feed, Vf=0.0)
            no_band[key] = {
                d: {"G_um": round(f.G * 1e3, 2), "spike_um": round(f.spike * 1e3, 2)}
                for d, f in result.figures["joints"].items()
            }
            if radius == 50.0:
                result, _ = _circle(radius, feed, Kf=0.0)
                friction[key] = {
                    d: round(f.spike * 1e3, 2) for d, f in result.figures["joints"].items()
                }
            print(key, on[key], off[key], no_band[key], friction.get(key), file=sys.stderr)
    return {
        "feed_forward_on": on,
        "feed_forward_off": off,
        "friction_band_off": no_band,
        "spike_without_Kf_um": friction,
    }


def main() -> None:
    """Print the benchmark as JSON."""
    if "--circle" in sys.argv[1:]:
        print(json.dumps({"gantry_circle_test": gantry_circle_test()}, indent=2))
        return
    report = {
        "commanded_radius_error": commanded_radius_error(),
        "gantry_circle_R50": gantry_circles(),
        "gantry_gcode_contour_F3000": gantry_contour(),
        "gantry_circle_test": gantry_circle_test(),
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()

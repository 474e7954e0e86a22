"""Benchmark: the delta picker, every figure measured on the MuJoCo physics.

Prints JSON:

- ``kinematics``: forward ∘ inverse over a grid of the working cylinder Ø800 × 200 mm: the
  largest error [mm] and the arms' range over it [deg];
- ``demo``: the pick-and-place demo with its real-time factor (whole stack; its ratio to the
  bare physics is ``tests.benchmarks.machines``'); per part
  the pick error (the cup's centre against the part's centre when the vacuum comes on, from the
  model's site and body) mean and worst [mm], parts lost, the cycle per part [s] and the rate
  [parts/min]; the arms' peak and rms amplifier torque [N·m at the arm] and the motor's torque
  [N·m] (÷ i·η) against the catalogue's peak (8.36) and rated (2.39) torque; the cup's peak
  speed [m/s] and acceleration [m/s²] (second differences of the site over 1 ms);

- ``tracking``: the demo picking on the fly at belt speeds 0.2, 0.5 and 1.0 m/s until it has
  picked ``--picks N`` parts (default 40): parts offered (latched), picked, refused (a part the
  robot cannot reach in time, by ErrorID: it rides off the belt's end and comes back on the
  infeed) and dropped (lost by the cup), the pick error of the picks (from the physics, as
  above) mean and worst [mm], the rate [picks/min] over the picks after the first, and the
  same torque and cup figures; then one summary per belt speed as text. The parts come at a
  fixed spacing on the belt, so the faster belt brings more parts a minute than the robot
  picks (1.0 m/s: about 200).

- ``cycle``: the standard cycle (:mod:`scenes.machines.delta_picker.cycle`: up 25 mm, across
  305 mm, down 25 mm and back, blended, a 0.1 kg part picked and placed at each end),
  ``--cycles N`` times (default 20): cycles/min, the legs' time, parts gripped and dropped, the
  cup's slowest speed between lift-off and set-down [mm/s] (0 if it stopped at a corner) and
  the same torque and cup figures.

Run: ``python -m tests.benchmarks.delta_picker [--picks N] [--speeds 200,500,1000]
[--tracking-only] [--cycles N] [--cycle-only]``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from typing import Any

import numpy as np

import scenes
from scenes.machines.delta_picker import DELTA, VacuumGripper
from scenes.machines.delta_picker.axes import ARMS
from scenes.machines.delta_picker.cycle import StandardCycle, prepare
from scenes.machines.delta_picker.demo import VACUUM_OFF, VACUUM_ON

RATIO, EFFICIENCY = 20.0, 0.9
"""The arms' gearbox (models/README.md, delta_picker)."""
PEAK, RATED = 8.36, 2.39
"""Yaskawa SGM7J-08A: instantaneous peak and rated torque [N·m]."""


def kinematics() -> dict[str, Any]:
    worst, angles = 0.0, []
    for zi in range(9):
        z = -650.0 - 25.0 * zi
        for ri in range(9):
            for ai in range(36):
                r, a = 50.0 * ri, 2.0 * math.pi * ai / 36
                p = [r * math.cos(a), r * math.sin(a), z]
                q = DELTA.inverse(p)
                angles += q
                back = DELTA.forward(q)
                worst = max(worst, max(abs(x - y) for x, y in zip(back, p, strict=True)))
    return {"fk_ik_worst_mm": worst, "arm_range_deg": [min(angles), max(angles)]}


class Recorder:
    """The arms' amplifier torques and the cup's position (the model's site) every scan."""

    def __init__(self, scene: scenes.Scene) -> None:
        model = scene.model
        self.data = scene.data
        self.tool = model.site(scene.model_name("tool")).id
        self.amps = [model.actuator(scene.model_name(f"{a}_amp")).id for a in ARMS]
        self.torques: list[list[float]] = []
        self.tips: list[np.ndarray] = []
        self.times: list[float] = []

    def __call__(self, t: float) -> None:
        self.times.append(t)
        self.torques.append([float(self.data.actuator_force[a]) for a in self.amps])
        self.tips.append(np.array(self.data.site_xpos[self.tool]))

    def figures(self) -> dict[str, Any]:
        """Peak and rms torques at the arm and the motor, the cup's peak speed and
        acceleration."""
        tau = np.abs(np.array(self.torques))
        motor = tau / (RATIO * EFFICIENCY)
        x, t = np.array(self.tips), np.array(self.times)
        dt = np.diff(t)
        speed = np.linalg.norm(np.diff(x, axis=0), axis=1) / dt
        velocity = np.diff(x, axis=0) / dt[:, None]
        acc = np.linalg.norm(np.diff(velocity, axis=0), axis=1) / dt[1:]
        return {
            "arm_torque_peak_Nm": tau.max(axis=0).tolist(),
            "arm_torque_rms_Nm": np.sqrt((tau**2).mean(axis=0)).tolist(),
            "motor_torque_peak_Nm": motor.max(axis=0).tolist(),
            "motor_torque_rms_Nm": np.sqrt((motor**2).mean(axis=0)).tolist(),
            "catalogue_peak_rated_Nm": [PEAK, RATED],
            "cup_peak_speed_m_s": float(speed.max()),
            "cup_peak_acceleration_m_s2": float(acc.max()),
        }


def standard_cycle(cycles: int = 20) -> dict[str, Any]:
    """The standard cycle (:mod:`scenes.machines.delta_picker.cycle`) ``cycles`` times: cycles
    per minute (there and back, the part picked and placed at each end), the legs' time, parts
    gripped and dropped, the cup's slowest speed between lift-off and set-down (blended corners:
    above 0), torques and the cup's peak acceleration."""
    scene = scenes.load("delta_picker", trace_every=0)
    group = prepare(scene)
    program = StandardCycle(scene, group, cycles)
    record = Recorder(scene)
    scene.runtime.observers.append(record)
    start = time.perf_counter()
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=120.0)
    wall = time.perf_counter() - start
    gripper = scene.device("vacuum", VacuumGripper)
    legs = program.legs
    span = legs[-1][1] - legs[0][0]
    t = np.array(record.times)
    z = np.array(record.tips)[:, 2] * 1000.0
    speed = np.linalg.norm(np.diff(np.array(record.tips), axis=0), axis=1) / np.diff(t) * 1000.0
    in_leg = np.zeros(len(speed), dtype=bool)
    for a, b in legs:
        in_leg |= (t[1:] >= a) & (t[1:] <= b)
    high = in_leg & (z[1:] > z.min() + 5.0)  # the cup more than 5 mm above the places: under way
    return {
        "error": program.error,
        "real_time_factor": scene.time / wall,
        "cycles": len(legs) // 2,
        "cycles_per_min": 60.0 * (len(legs) / 2.0) / span,
        "leg_s": float(np.mean([b - a for a, b in legs])),
        "vacuum_on_off_s": [VACUUM_ON, VACUUM_OFF],
        "parts_gripped": len(gripper.grips),
        "parts_dropped": gripper.lost,
        "cup_slowest_under_way_mm_s": float(speed[high].min()),
        **record.figures(),
    }


def demo(belt_speed: float | None = None, picks: int | None = None) -> dict[str, Any]:
    """The demo (at ``belt_speed`` [mm/s] until it has picked ``picks`` parts; None: its own
    speed and number of latched parts)."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    gripper = scene.device("vacuum", VacuumGripper)
    if belt_speed is not None:
        program.run.Velocity = belt_speed  # type: ignore[attr-defined]
    if picks is not None:
        program.parts = 100 * picks  # type: ignore[attr-defined]
    record = Recorder(scene)

    def scan() -> None:
        program()
        record(scene.time)

    def ended() -> bool:
        picked = picks is not None and program.picked >= picks  # type: ignore[attr-defined]
        return picked or program.done or bool(program.error)

    start = time.perf_counter()
    scene.run(scan, until=ended, timeout=3600.0)
    wall = time.perf_counter() - start
    if not gripper.grips:
        speed = program.run.Velocity  # type: ignore[attr-defined]
        raise SystemExit(
            f"the demo picked no part at a belt speed of {speed:g} mm/s: "
            f"{program.error or program.step}; belt speeds are in mm/s, e.g. --speeds 200,500,1000"
        )
    errors = [g.error for g in gripper.grips]
    rows = program.results  # type: ignore[attr-defined]
    picked = [row for row in rows if row["picked"]]
    refused: dict[str, int] = {}
    for row in rows:
        if not row["picked"]:
            refused[str(row["error id"])] = refused.get(str(row["error id"]), 0) + 1
    grip_times = [g.time for g in gripper.grips]
    cycles = list(np.diff(grip_times)) if len(grip_times) > 1 else [math.nan]
    return {
        "error": program.error,
        "real_time_factor": scene.time / wall,
        "belt_speed_mm_s": program.run.Velocity,  # type: ignore[attr-defined]
        "parts_offered": len(rows),
        "parts_picked": len(picked),
        "parts_refused": sum(refused.values()),
        "parts_refused_by_error_id": refused,
        "parts_dropped": gripper.lost,
        "pick_error_mm": {"mean": float(np.mean(errors)), "worst": float(np.max(errors))},
        "cycle_s": float(np.mean(cycles)),
        "rate_per_min": 60.0 / float(np.mean(cycles)),
        **record.figures(),
    }


def summary(run: dict[str, Any]) -> str:
    """One belt speed's figures as lines of text."""
    error = run["pick_error_mm"]
    motors = ", ".join(
        f"A{i + 1} {peak:.2f} ({peak / PEAK:.0%} of peak) rms {rms:.2f} "
        f"({rms / RATED:.0%} of rated)"
        for i, (peak, rms) in enumerate(
            zip(run["motor_torque_peak_Nm"], run["motor_torque_rms_Nm"], strict=True)
        )
    )
    return (
        f"belt {run['belt_speed_mm_s'] / 1000.0:.1f} m/s: {run['parts_offered']} offered, "
        f"{run['parts_picked']} picked, {run['parts_refused']} refused "
        f"{run['parts_refused_by_error_id']}, {run['parts_dropped']} dropped; pick error mean "
        f"{error['mean']:.3f} mm, worst {error['worst']:.3f} mm; {run['rate_per_min']:.1f} "
        f"picks/min\n  motor torque [N·m] {motors} (catalogue {PEAK} peak, {RATED} rated); "
        f"TCP peak acceleration {run['cup_peak_acceleration_m_s2']:.1f} m/s²"
    )


def main() -> None:
    """Print the benchmark as JSON, then each belt speed's figures as text."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--speeds", default="200,500,1000", help="belt speeds [mm/s], comma-separated"
    )
    parser.add_argument("--picks", type=int, default=40, help="picks per belt speed")
    parser.add_argument("--tracking-only", action="store_true", help="only the belt speeds")
    parser.add_argument("--cycles", type=int, default=20)
    parser.add_argument("--cycle-only", action="store_true", help="only the standard cycle")
    args = parser.parse_args()
    if args.cycle_only:
        print(json.dumps({"cycle": standard_cycle(args.cycles)}, indent=2))
        return
    speeds = [float(v) for v in args.speeds.split(",")]
    tracking = [demo(speed, args.picks) for speed in speeds]
    out: dict[str, Any] = {"tracking": tracking}
    if not args.tracking_only:
        out = {
            "kinematics": kinematics(),
            "cycle": standard_cycle(args.cycles),
            "demo": demo(),
            **out,
        }
    print(json.dumps(out, indent=2))
    for run in tracking:
        print(summary(run))


if __name__ == "__main__":
    main()

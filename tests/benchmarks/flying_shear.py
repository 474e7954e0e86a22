"""Benchmark: the flying shear's cut statistics and its real-time factor.

Every length comes from the physics (the strip joint M is the truth; a cut is where the knife edge
sat on the strip when the blade came down). Figures:

- cut to length, 21 cuts (20 pieces) of 1500 mm at 60 m/min with ±1 % ripple and the model's
  measuring wheel (its errors on, the cut-length correction on): length error mean, standard
  deviation, worst; per cut the carriage/strip speed mismatch, how far the blade slid on the
  strip, the drag force;
- the wheel's errors: the same job without the correction, with the correction starting from
  the scale learned before, and on the ideal wheel (the controller's own precision);
- the line slowed by 5 % at 0.5, 1.5 and 2 m/s² as soon as InSync rises (the knife comes down
  while the strip decelerates): the carriage/strip speed mismatch and the drag while the blade
  is down, on the ideal and on the model's wheel;
- 120 m/min: whether 1500 mm pieces fit the carriage's stroke and acceleration, and the figures
  at the shortest length tried that does;
- measuring-wheel slip (−0.2 %, −0.5 %, and a random part) in length mode on an otherwise ideal
  wheel without the correction: the pieces grow;
- cut to mark (Zeroing 2, Delay = sensor delay) on the ideal wheel without and with slip and on
  the model's wheel, with and without the register that learns the wheel's scale; Delay 0
  against Delay = sensor delay on the ideal wheel (zeroing error in counts, cut-to-mark shift);
- the line speed changed after StartSync (−10 % … +50 %) or at InSync, on the ideal wheel:
  what the cut does;
- an unsynchronised cut (knife dropped with the carriage standing): the drag force;
- the real-time factor of the 60 m/min scenario against the bare physics of the same model
  (MuJoCo and the machine's devices, and MuJoCo alone), measured in the same run in chunks of
  0.1 s (as ``tests.benchmarks.machines`` does).

Prints JSON per mode (compiled where built, and pure Python, each in a fresh process).
Run: ``python -m tests.benchmarks.flying_shear``.
"""

from __future__ import annotations

import statistics
from typing import Any

from tests.benchmarks import report_in_both_modes

CHUNK = 0.1
"""Simulated seconds per measured chunk [s]."""
COUNT = 0.025
"""One count of the measuring wheel [mm]."""


def _scene(ideal: bool = False, slip: float | None = None, random_slip: float = 0.0) -> Any:
    """The flying shear; ``ideal``: a perfect wheel, then ``slip`` and ``random_slip`` only."""
    import scenes
    from scenes.machines import flying_shear as fs

    scene = scenes.load("flying_shear", start=fs.MACHINE.demo_start, trace_every=0)
    wheel = scene.device("wheel", fs.MeasuringWheel)
    if ideal:
        wheel.ideal()
        wheel.random = random_slip
    if slip is not None:
        wheel.slip = slip
    return scene


def _stats(values: list[float]) -> dict[str, float]:
    if not values:
        return {}
    worst: float = max(values, key=abs)
    return {
        "mean": round(statistics.fmean(values), 4),
        "std": round(statistics.pstdev(values), 4),
        "worst": round(worst, 4),
    }


def _cuts(demo: Any) -> dict[str, Any]:
    """The figures of a finished (or stopped) demo."""
    cuts = demo.recorder.cuts
    lengths = [c.length for c in cuts if c.length is not None]
    return {
        "pieces": len(lengths),
        "error": demo.error,
        "length_mm": _stats(lengths),
        "error_mm": _stats(demo.errors()),
        "speed_mismatch_pct_worst": round(
            100 * max((c.speed_mismatch for c in cuts), default=0), 3
        ),
        "blade_slide_mm_worst": round(max((c.slide for c in cuts), default=0.0), 4),
        "drag_N_mean": round(statistics.fmean(c.drag for c in cuts), 1) if cuts else None,
        "drag_N_worst": round(max((c.drag for c in cuts), default=0.0), 1),
        "blade_contact_ms": round(1000 * statistics.fmean(c.contact for c in cuts), 1)
        if cuts
        else None,
    }


def run_job(
    job: Any,
    ideal: bool = False,
    slip: float | None = None,
    random_slip: float = 0.0,
    timeout: float = 120.0,
) -> Any:
    """The demo with ``job`` run to its end or its error (wheel as in :func:`_scene`)."""
    from scenes.machines import flying_shear as fs

    scene = _scene(ideal, slip, random_slip)
    demo = fs.Demo(scene, job)
    scene.run(demo, until=lambda: demo.done or bool(demo.error), timeout=timeout)
    return demo


def real_time_factor() -> dict[str, Any]:
    """The 60 m/min scenario (21 cuts) against the bare physics of the same model (MuJoCo and
    the machine's devices; and MuJoCo alone), chunk by chunk; with its cut figures."""
    from scenes.machines import flying_shear as fs
    from tests.benchmarks.machines import against_bare_physics

    scene = _scene()
    demo = fs.Demo(scene, fs.CutJob())
    return {
        **against_bare_physics(scene, demo, lambda: demo.done or bool(demo.error), 120.0),
        "cuts": _cuts(demo),
    }


def high_speed() -> dict[str, Any]:
    """120 m/min: 1500 mm pieces, then longer ones until they fit."""
    from scenes.machines import flying_shear as fs

    tried = {}
    for length in (1500.0, 2000.0, 2300.0, 2350.0, 2450.0):
        demo = run_job(fs.CutJob(speed=2000.0, length=length, cuts=11))
        tried[f"{length:.0f}"] = _cuts(demo)
    return tried


def slip() -> dict[str, Any]:
    """Length mode with a slipping wheel: the pieces grow by the slip."""
    from scenes.machines import flying_shear as fs

    out = {}
    for constant, rms in ((-0.002, 0.0), (-0.005, 0.0), (0.0, 0.001)):
        job = fs.CutJob(cuts=6, correction=False)
        demo = run_job(job, ideal=True, slip=constant, random_slip=rms)
        out[f"slip {constant:+.1%} random {rms:.1%}"] = _cuts(demo)
    return out


def marks() -> dict[str, Any]:
    """Cut to mark: slip and register, and the probe delay."""
    from scenes.machines import flying_shear as fs

    out: dict[str, Any] = {}
    for constant, register in ((0.0, True), (-0.005, False), (-0.005, True)):
        job = fs.CutJob(cuts=8, mode="mark", register=register)
        demo = run_job(job, ideal=True, slip=constant)
        out[f"ideal wheel, slip {constant:+.1%} register {register}"] = {
            **_cuts(demo),
            "scale_learned": round(demo.scale, 6),
        }
    for register in (False, True):
        demo = run_job(fs.CutJob(mode="mark", register=register))
        out[f"model's wheel, register {register}"] = {
            **_cuts(demo),
            "scale_learned": round(demo.scale, 6),
        }
    for delay in (fs.SENSOR_DELAY * 1000.0, 0.0):
        scene = _scene(ideal=True)
        demo = fs.Demo(scene, fs.CutJob(cuts=6, mode="mark", register=False, delay=delay))
        zeroing = fs.ZeroingRecorder(scene)
        scene.runtime.observers.append(zeroing)
        scene.run(demo, until=lambda d=demo: d.done or bool(d.error), timeout=60.0)
        out[f"Delay {delay:g} ms"] = {
            "zeroing_error_counts": [round(e / COUNT, 2) for e in zeroing.errors],
            "mark_error_mm": _stats(demo.errors()),
            "error": demo.error,
        }
    return out


def wheel_errors() -> dict[str, Any]:
    """60 m/min, 21 cuts: the model's wheel without and with the cut-length correction (from
    scale 1, and from the scale it learned), and the ideal wheel."""
    from scenes.machines import flying_shear as fs

    out: dict[str, Any] = {}
    learned = run_job(fs.CutJob())
    cases = {
        "model's wheel, no correction": (fs.CutJob(correction=False), False),
        "model's wheel, correction from scale 1": (fs.CutJob(), False),
        "model's wheel, correction from the learned scale": (
            fs.CutJob(scale=learned.scale),
            False,
        ),
        "ideal wheel": (fs.CutJob(), True),
    }
    for name, (job, ideal) in cases.items():
        demo = learned if job == fs.CutJob() and not ideal else run_job(job, ideal=ideal)
        errors = demo.errors()
        out[name] = {
            **_cuts(demo),
            "error_mm_after_the_first_piece": _stats(errors[1:]),
            "scale_learned": round(demo.scale, 6),
        }
    return out


def line_ramp() -> dict[str, Any]:
    """The line slowed by 5 % at 0.5, 1.5 and 2 m/s² as soon as InSync rises for the second
    cut: the speed mismatch [%] and the drag [N] while the blade is on the strip."""
    import mcl
    from scenes.machines import flying_shear as fs

    out = {}
    for ideal in (True, False):
        for ramp in (500.0, 1500.0, 2000.0):
            scene = _scene(ideal)
            demo = fs.Demo(scene, fs.CutJob(cuts=3))
            change = mcl.MC_MoveVelocity(
                Axis=scene.axes["L"], Velocity=950.0, Acceleration=ramp, Deceleration=ramp
            )
            started = [False]

            def program(
                demo: Any = demo, change: Any = change, started: list[bool] = started
            ) -> None:
                demo()
                started[0] = started[0] or (demo.cut == 2 and demo.gear.InSync)
                change(Execute=started[0])

            scene.run(program, until=lambda d=demo: d.done or bool(d.error), timeout=60.0)
            cut = demo.recorder.cuts[1] if len(demo.recorder.cuts) > 1 else None
            wheel = "ideal wheel" if ideal else "model's wheel"
            out[f"{wheel}, {ramp / 1000.0:g} m/s²"] = {
                "error": demo.error,
                "speed_mismatch_pct": round(100.0 * cut.speed_mismatch, 3) if cut else None,
                "drag_N": round(cut.drag, 1) if cut else None,
            }
    return out


def speed_change() -> dict[str, Any]:
    """The line speed changed (2000 mm/s²) as soon as StartSync rises for the second cut, or
    as soon as InSync rises (the knife then comes down while the line accelerates)."""
    import mcl
    from scenes.machines import flying_shear as fs

    out = {}
    cases = [(f, "StartSync") for f in (0.9, 1.03, 1.06, 1.1, 1.2, 1.3, 1.5)] + [(1.1, "InSync")]
    for factor, at in cases:
        scene = _scene(ideal=True)
        demo = fs.Demo(scene, fs.CutJob(cuts=3))
        change = mcl.MC_MoveVelocity(
            Axis=scene.axes["L"], Velocity=1000.0 * factor, Acceleration=2000.0
        )
        started = [False]

        def program(
            demo: Any = demo, change: Any = change, started: list[bool] = started, at: str = at
        ) -> None:
            demo()
            started[0] = started[0] or (demo.cut == 2 and getattr(demo.gear, at))
            change(Execute=started[0])

        scene.run(program, until=lambda d=demo: d.done or bool(d.error), timeout=60.0)
        out[f"x{factor} at {at}"] = {
            **_cuts(demo),
            "slave_state": scene.axes["S"].state.name,
            "knife_output": scene.io("S").outputs[0],
        }
    return out


def unsynchronised_drag() -> dict[str, Any]:
    """The knife dropped on the strip at 60 m/min with the carriage standing (powered)."""
    import mcl
    from scenes.machines import flying_shear as fs

    scene = _scene()
    L, S = scene.axes["L"], scene.axes["S"]
    power = [mcl.MC_Power(Axis=L, Enable=True), mcl.MC_Power(Axis=S, Enable=True)]
    line = mcl.MC_MoveVelocity(Axis=L, Velocity=1000.0, Acceleration=1000.0)
    down = mcl.MC_WriteDigitalOutput(Axis=S, OutputNumber=0, Value=True)
    knife = scene.devices["knife"]
    assert isinstance(knife, fs.KnifeCylinder)
    state = {"drop": False, "drag": 0.0}

    def program() -> None:
        for p in power:
            p()
        line(Execute=power[0].Status)
        down(Execute=state["drop"])
        state["drag"] = max(state["drag"], abs(knife.drag))

    scene.run(program, until=lambda: line.InVelocity, timeout=5.0)
    scene.run(program, timeout=0.5)
    strip = scene.data.joint(scene.model_name("M")).qvel
    carriage = scene.data.joint(scene.model_name("S")).qpos
    before, q0 = float(strip[0]), float(carriage[0])
    state["drop"] = True
    scene.run(program, timeout=0.2)
    return {
        "drag_N_worst": round(state["drag"], 1),
        "grip_limit_N": round(knife.mu * (knife.force + knife.weight), 1),
        "carriage_dragged_mm": round(1000.0 * (float(carriage[0]) - q0), 2),
        "strip_speed_m_s_before_after": [round(before, 3), round(float(strip[0]), 3)],
    }


def mode_report() -> dict[str, Any]:
    """Every figure in this process' mode."""
    import mcl

    return {
        "mode": "compiled" if mcl.COMPILED else "pure Python",
        "length_60_m_min": real_time_factor(),
        "length_120_m_min": high_speed(),
        "wheel_errors": wheel_errors(),
        "line_ramp_at_in_sync": line_ramp(),
        "slip_length_mode": slip(),
        "cut_to_mark": marks(),
        "master_speed_change_after_start_sync": speed_change(),
        "unsynchronised_cut": unsynchronised_drag(),
    }


def main() -> None:
    """Print the benchmark as JSON, compiled (where built) and pure Python."""
    report_in_both_modes("tests.benchmarks.flying_shear", mode_report)


if __name__ == "__main__":
    main()

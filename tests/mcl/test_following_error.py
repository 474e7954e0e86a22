"""Accuracy of the closed loop on the default simulated axis, in simulated time only, judged on
the simulated carriage (the physics), not on the axis' own coordinate."""

from __future__ import annotations

import mcl
from tests.helpers import carriage_mm, scan

TARGET = 300.0
COUNT = 0.001
"""One encoder count [mm]: the carriage can stand anywhere within the count the loop holds."""


def test_fast_jerk_limited_move_keeps_the_following_error_small(machine, X):
    """300 mm at 400 mm/s, A = D = 4000 mm/s², J = 100000 mm/s³: the carriage never lags the
    set point by 50 µm or more, does not overshoot, and settles within one count of the target
    (plus the count it is read with) within 0.5 s of Done."""
    trace: list[tuple[float, float, float]] = []  # t, set point − carriage, carriage [mm]
    machine.runtime.observers.append(
        lambda t: trace.append((t, X.sp_pos - carriage_mm(machine), carriage_mm(machine)))
    )
    move = mcl.MC_MoveAbsolute()
    program = scan(
        lambda: move(
            Axis=X,
            Execute=True,
            Position=TARGET,
            Velocity=400.0,
            Acceleration=4000.0,
            Deceleration=4000.0,
            Jerk=100000.0,
        )
    )
    machine.run(program, until=lambda: move.Done, timeout=3.0)
    t_done = machine.time
    machine.run(program, timeout=1.0)
    assert move.Done
    assert X.state == mcl.AxisState.StandStill
    assert X.AxErrorID == 0

    peak = max(abs(e) for _, e, _ in trace)
    assert peak < 0.050, f"peak following error {peak * 1000:.1f} µm"
    assert max(p for _, _, p in trace) < TARGET + 0.050  # no visible overshoot either

    outside = [t for t, _, p in trace if abs(p - TARGET) > 2 * COUNT + 1e-9]
    settled_at = max(outside, default=0.0)
    assert settled_at <= t_done + 0.5, f"settled {settled_at - t_done:.3f} s after Done"
    assert abs(carriage_mm(machine) - TARGET) <= 2 * COUNT + 1e-9
    assert abs(X.actual - TARGET) <= COUNT + 1e-9

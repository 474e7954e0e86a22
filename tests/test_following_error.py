"""Accuracy of the closed loop on the default simulated axis, in simulated time only."""

from __future__ import annotations

import mcl
from tests.helpers import scan

TARGET = 300.0


def test_fast_jerk_limited_move_keeps_the_following_error_small(machine, X):
    """300 mm at 400 mm/s, A = D = 4000 mm/s², J = 100000 mm/s³: peak |following error| below
    50 µm, and the axis settles within 1 µm (one count) of the target within 0.5 s of Done."""
    trace: list[tuple[float, float, float]] = []
    machine.runtime.observers.append(lambda t: trace.append((t, X.following_error, X.actual)))
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

    outside = [t for t, _, p in trace if abs(p - TARGET) > 0.001 + 1e-9]
    settled_at = max(outside, default=0.0)
    assert settled_at <= t_done + 0.5, f"settled {settled_at - t_done:.3f} s after Done"
    assert abs(X.actual - TARGET) <= 0.001 + 1e-9

"""Example scenarios for sweeps (:mod:`scenes.tools.sweep`) that need no machine model: plain
functions of their parameters and a seed, each returning the metrics a user would study. The
machines' own scenarios are in their packages (``scenes.machines.gantry.scenarios``,
``scenes.machines.flying_shear.scenarios``).

- :func:`payload_following_error`: a jerk-limited move of a simulated axis against payload and
  friction (cheap: for trying out sweeps and clusters).
"""

from __future__ import annotations

__all__ = ["payload_following_error"]

import mcl


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

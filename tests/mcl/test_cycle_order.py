"""The servo cycle runs in phases over all axes: a follower reads its master's set point of the
same instant, whatever the order in which the axes were declared."""

from __future__ import annotations

import pytest

import mcl
from mcl.axis import Axis
from mcl.command import Command
from mcl.enums import AxisState
from tests.helpers import configure, power_on


class Follow(Command):
    """Test command: the follower's set point is its master's set point plus a fixed offset."""

    state = AxisState.SynchronizedMotion

    def __init__(self, master: Axis) -> None:
        super().__init__()
        self.master = master
        self.offset = 0.0

    def start(self, axis: Axis, p: float, v: float, a: float, v_end: float) -> None:
        self.offset = p - self.master.sp_pos

    def setpoint(self, axis: Axis, t: float) -> tuple[float, float, float]:
        master = self.master
        master.update_setpoint(axis.t_cycle)  # the master's value of this very instant
        return master.sp_pos + self.offset, master.sp_vel, master.sp_acc

    def finished(self) -> bool:
        return False


@pytest.mark.parametrize("order", ["MS", "SM"])
def test_a_follower_has_no_lag_in_either_declaration_order(order: str):
    machine = mcl.SimMachine({n: mcl.SimAxisParams(start=0.2) for n in order})
    M, S = machine.axes["M"], machine.axes["S"]
    for axis in (M, S):
        configure(axis)
        power_on(machine, axis)
    S.submit(Follow(M))
    move = mcl.MC_MoveVelocity()
    gaps: list[float] = []
    machine.runtime.observers.append(lambda t: gaps.append(S.sp_pos - M.sp_pos))
    machine.run(
        lambda: move(Axis=M, Execute=True, Velocity=200.0, Acceleration=2000.0), timeout=0.5
    )
    assert move.InVelocity and M.sp_vel == pytest.approx(200.0)
    assert max(gaps) - min(gaps) == pytest.approx(0.0, abs=1e-9)


def test_each_set_point_is_computed_once_per_instant():
    machine = mcl.SimMachine({"M": mcl.SimAxisParams(start=0.2)})
    M = machine.axes["M"]
    configure(M)
    power_on(machine, M)
    move = mcl.MC_MoveVelocity()
    machine.run(lambda: move(Axis=M, Execute=True, Velocity=100.0), timeout=0.1)
    before = (M.sp_pos, M.sp_vel, M.t_sp)
    M.update_setpoint(M.t_cycle)  # asked again within the same instant: nothing moves
    assert (M.sp_pos, M.sp_vel, M.t_sp) == before

"""The operator program of an axis on simulated axes (no physics engine): the Execute commands
run until their blocks end them and each outcome is reported once, a command started again gets
a fresh edge, parameters reach the blocks, MC_Power, the jog, the outputs, the constants, the
homing procedures, gearing by master number, the override; and the scene's program releasing a
group when a Stop is pressed on a member. Positions are measured on the simulated carriage."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pytest

import mcl
from plc.commissioning.axis import CommissioningRequests
from plc.operator.axis import (
    INDEX_FRACTION,
    REFUSED,
    AxisOperator,
    Orders,
    Parameters,
    no_parameters,
)
from plc.operator.program import GroupRelease, OperatorProgram
from plc.procedures import HomingRecipe
from tests.helpers import CONSTANTS, carriage_mm, make_machine

MOVE = {"velocity": 200.0, "acceleration": 2000.0, "deceleration": 2000.0}
"""A move's ramp [mm/s, mm/s²]."""


def given(**values: float) -> Parameters:
    """Parameters from keywords (the others 0.0)."""
    return lambda name: values.get(name, 0.0)


class Driver:
    """Gives an axis operator the same orders every scan, its starts in the first only."""

    def __init__(self, machine: mcl.SimMachine, operator: AxisOperator) -> None:
        self.machine, self.operator = machine, operator

    def run(
        self,
        seconds: float,
        execute: tuple[str, ...] = (),
        start: Mapping[str, Parameters] | None = None,
        **levels: Any,
    ) -> None:
        first = [start or {}]

        def program() -> None:
            starts = first.pop() if first else {}
            self.operator(Orders(execute=frozenset(execute), start=starts, **levels))

        self.machine.run(program, timeout=seconds)


@pytest.fixture
def rig() -> tuple[mcl.SimMachine, AxisOperator, list[tuple[str, str]], Driver]:
    """X powered and referenced at 0 mm, its operator (no recipe) and what on_error heard."""
    machine = make_machine("X")
    heard: list[tuple[str, str]] = []
    operator = AxisOperator(
        machine.axes["X"], None, (), lambda *e: heard.append(e), sim_time=lambda: machine.time
    )
    return machine, operator, heard, Driver(machine, operator)


Rig = tuple[mcl.SimMachine, AxisOperator, list[tuple[str, str]], Driver]


def test_a_move_runs_until_done_and_says_so(rig: Rig) -> None:
    machine, op, heard, drive = rig
    move = {"move_absolute": given(position=50.0, **MOVE)}
    drive.run(0.02, ("move_absolute",), move)
    assert op.executing("move_absolute") and op.message == ""
    drive.run(1.0, ("move_absolute",))
    assert carriage_mm(machine) == pytest.approx(50.0, abs=0.05)
    assert op.message == "Move to: done" and "move_absolute" in op.finished
    assert not op.executing("move_absolute") and not heard


def test_a_refused_command_is_reported_once_and_leaves_the_axis_alone(rig: Rig) -> None:
    machine, op, heard, drive = rig
    drive.run(0.2, ("move_relative",), {"move_relative": given(distance=10.0)})  # velocity 0
    text = f"Move by: error 5 ({mcl.error_text(5)}: Velocity 0 mm/s is not > 0)"  # and why
    assert op.message == op.last_error == text
    assert heard == [("X", text)]  # once, though its Execute stays set
    assert carriage_mm(machine) == pytest.approx(0.0, abs=0.01)


def test_a_command_started_again_gets_a_fresh_rising_edge(rig: Rig) -> None:
    machine, op, _, drive = rig
    by_20 = {"move_relative": given(distance=20.0, **MOVE)}
    drive.run(0.5, ("move_relative",), by_20)
    assert carriage_mm(machine) == pytest.approx(20.0, abs=0.05)
    drive.run(0.02, ("move_relative",), by_20)  # its Execute still set: started afresh
    assert op.message == "Move by: done" and op.executing("move_relative")
    drive.run(0.5, ("move_relative",))
    assert carriage_mm(machine) == pytest.approx(40.0, abs=0.05)


def test_a_halt_aborts_a_held_move_and_each_says_how_it_ended(rig: Rig) -> None:
    machine, op, _, drive = rig
    drive.run(0.2, ("move_absolute",), {"move_absolute": given(position=200.0, **MOVE)})
    both = ("move_absolute", "halt")
    drive.run(0.004, both, {"halt": given(deceleration=2000.0)})
    assert op.message == "Move to: aborted"
    drive.run(0.5, both)
    assert op.message == "Halt: done"
    assert 20.0 < carriage_mm(machine) < 200.0 - 20.0


def test_a_released_move_ends_unreported(rig: Rig) -> None:
    machine, op, _, drive = rig
    drive.run(0.1, ("move_relative",), {"move_relative": given(distance=30.0, **MOVE)})
    drive.run(0.5)  # its Execute falls: the move goes on, the block is still called
    assert carriage_mm(machine) == pytest.approx(30.0, abs=0.05)
    assert op.message == "" and not op.move_relative.Done  # shown for one scan, then reset


def test_a_velocity_move_takes_its_direction_from_the_sign(rig: Rig) -> None:
    machine, op, _, drive = rig
    backwards = {"move_velocity": given(velocity=-100.0, acceleration=2000.0)}
    drive.run(0.5, ("move_velocity",), backwards)
    assert op.move_velocity.InVelocity
    assert op.move_velocity.Direction == mcl.MC_Direction.MC_Negative
    velocity = machine.axes["X"].VEL
    assert velocity == pytest.approx(-100.0, abs=2.0)


def test_stop_ramps_with_its_deceleration_and_holds_while_execute_is_set(rig: Rig) -> None:
    machine, op, _, drive = rig
    ramp = {"velocity": 100.0, "acceleration": 2000.0}
    drive.run(0.3, ("move_velocity",), {"move_velocity": given(**ramp)})
    before = carriage_mm(machine)
    drive.run(1.0, ("stop",), {"stop": given(deceleration=200.0)})
    assert carriage_mm(machine) - before == pytest.approx(25.0, abs=2.0)  # v²/2a
    assert op.message == "Stop: done" and op.stopping is False
    assert machine.axes["X"].state == mcl.AxisState.Stopping  # Execute still set
    drive.run(0.01)
    assert machine.axes["X"].state == mcl.AxisState.StandStill


def test_power_none_leaves_mc_power_alone_and_false_switches_off(rig: Rig) -> None:
    machine, op, _, drive = rig
    drive.run(0.02, power=None)
    assert not op.power.Status and machine.axes["X"].state == mcl.AxisState.StandStill
    drive.run(0.02, power=False)
    assert machine.axes["X"].state == mcl.AxisState.Disabled


def test_the_jog_runs_while_its_level_is_set_and_a_refusal_names_it(rig: Rig) -> None:
    machine, op, heard, drive = rig
    drive.run(0.5, jog_pos=True, jog_velocity=50.0)
    velocity = machine.axes["X"].VEL
    assert op.jogging == 1 and velocity == pytest.approx(50.0, rel=0.05)
    drive.run(0.3)
    assert op.jogging == 0 and abs(machine.axes["X"].VEL) < 1.0
    drive.run(0.3, jog_neg=True, jog_velocity=50.0)
    assert op.jogging == -1 and machine.axes["X"].VEL < -40.0
    drive.run(0.3)
    drive.run(0.02, power=False)
    drive.run(0.02, jog_neg=True, jog_velocity=50.0)
    assert op.message == f"Jog−: error 10 ({mcl.error_text(10)})" and heard[-1][0] == "X"


def test_a_jog_too_slow_is_refused_and_says_why(rig: Rig) -> None:
    machine, op, heard, drive = rig
    drive.run(0.1, jog_pos=True, jog_velocity=2.0)  # Vmax 500 mm/s: at least 5 mm/s
    why = "Velocity 2 mm/s below 1 % of Vmax (5 mm/s)"
    assert op.message == f"Jog+: error 5 ({mcl.error_text(5)}: {why})"
    assert op.last_error_kind == REFUSED and heard == [("X", op.message)]
    assert machine.axes["X"].VEL == 0.0


def test_a_move_beyond_a_software_limit_names_it_and_another_error_says_no_more(
    rig: Rig,
) -> None:
    machine, op, heard, drive = rig
    limit = mcl.GT_SWLim(Axis=machine.axes["X"], LimPos=30.0, LimNeg=-40.0)
    machine.run(lambda: limit(Execute=True), timeout=0.01)
    drive.run(0.05, ("move_absolute",), {"move_absolute": given(position=35.0, **MOVE)})
    why = "target 35.000 mm beyond the positive SW limit 30.000 mm"
    assert op.message == f"Move to: error 8 ({mcl.error_text(8)}: {why})"
    drive.run(0.05)
    drive.run(0.05, ("move_relative",), {"move_relative": given(distance=-45.0, **MOVE)})
    why = "target -45.000 mm beyond the negative SW limit -40.000 mm"
    assert op.message == f"Move by: error 8 ({mcl.error_text(8)}: {why})"
    drive.run(0.05)
    drive.run(0.02, power=False)
    drive.run(0.05, ("move_absolute",), {"move_absolute": given(position=10.0, **MOVE)})
    assert op.message == f"Move to: error 10 ({mcl.error_text(10)})"
    assert heard[-1] == ("X", op.message) and len(heard) == 3
    assert carriage_mm(machine) == pytest.approx(0.0, abs=0.05)


def test_the_outputs_follow_their_bits() -> None:
    machine = make_machine({"X": mcl.SimAxisParams(start=0.2, digital_outputs=2)})
    op = AxisOperator(machine.axes["X"], None, sim_time=lambda: machine.time)
    Driver(machine, op).run(0.01, outputs=0b10)
    assert list(machine.axes["X"].io.outputs) == [False, True]
    Driver(machine, op).run(0.01, outputs=0b01)
    assert list(machine.axes["X"].io.outputs) == [True, False]


def test_constants_are_written_or_refused(rig: Rig) -> None:
    machine, op, heard, drive = rig
    good = mcl.ServoConstants(**{**CONSTANTS, "Kp": 2.5})
    drive.run(0.002, constants=good)
    assert op.message == "Write constants: done" and machine.axes["X"].constants == good
    drive.run(0.002, constants=mcl.ServoConstants(**{**CONSTANTS, "Vmax": -1.0}))
    assert op.message.startswith("Write constants: error 5") and len(heard) == 1
    assert machine.axes["X"].constants == good


def test_set_position_homes_without_moving_and_a_missing_recipe_is_said(rig: Rig) -> None:
    machine, op, _, drive = rig
    assert not op.select_homing("recipe")
    assert op.message == "Home: no homing recipe for this axis" and op.home is None
    assert op.select_homing("set position (no motion)", 123.0)
    drive.run(0.02, ("home",), {"home": no_parameters})
    assert op.message == "Home: done" and not op.homing
    position = machine.axes["X"].POS
    assert position == pytest.approx(123.0, abs=0.01)
    assert carriage_mm(machine) == pytest.approx(0.0, abs=0.01)


def test_the_index_pulse_procedures_search_at_their_velocity(rig: Rig) -> None:
    machine, op, _, drive = rig
    assert op.select_homing("set position (no motion)", 7.0)
    drive.run(0.01, ("home",), {"home": no_parameters})
    assert op.message == "Home: done" and op.set_position.Execute  # held
    assert op.select_homing("index pulse −", 5.0)  # the last procedure's Execute falls
    assert not op.set_position.Execute
    pulse = op.index_pulse
    assert pulse.Direction == mcl.MC_Direction.MC_Negative
    assert pulse.Velocity == pytest.approx(INDEX_FRACTION * CONSTANTS["Vmax"])
    drive.run(0.01, ("home",), {"home": no_parameters})
    assert op.homing and machine.axes["X"].VEL < 0.0
    drive.run(3.0, ("home",))
    assert op.message == "Home: done" and not op.homing
    position = machine.axes["X"].POS
    assert position == pytest.approx(5.0, abs=0.5)
    recipe = HomingRecipe(index_velocity=4.0)
    with_recipe = AxisOperator(machine.axes["X"], recipe, sim_time=lambda: machine.time)
    assert with_recipe.select_homing("index pulse +")
    assert with_recipe.index_pulse.Velocity == 4.0
    assert with_recipe.index_pulse.Direction == mcl.MC_Direction.MC_Positive
    assert with_recipe.select_homing("recipe") and with_recipe.home is with_recipe.recipe


def test_gearing_takes_its_master_by_number() -> None:
    machine = make_machine("MS")
    master, slave = machine.axes["M"], machine.axes["S"]
    op = AxisOperator(slave, None, [master, slave], sim_time=lambda: machine.time)
    ratio = {"ratio_numerator": 1.0, "ratio_denominator": 2.0, "acceleration": 2000.0}
    drive = Driver(machine, op)
    drive.run(0.01, ("gear_in",), {"gear_in": given(master=7.0, **ratio)})
    assert op.gear_in.Error and op.message.startswith("Gear in: error 5")  # no axis 7
    mover = mcl.MC_MoveRelative()
    drive.run(0.004)
    drive.run(0.01, ("gear_in",), {"gear_in": given(master=0.0, **ratio)})

    def program() -> None:
        mover(Axis=master, Execute=True, Distance=100.0, Velocity=100.0, Acceleration=1000.0)
        op(Orders(execute=frozenset({"gear_in"})))

    machine.run(program, timeout=2.0)
    assert op.gear_in.InGear and op.gear_in.Master is master
    assert carriage_mm(machine, "S") == pytest.approx(50.0, abs=0.5)


def test_the_override_is_passed_only_with_commissioning_controls(rig: Rig) -> None:
    machine, _, _, drive = rig
    drive.run(0.01, commissioning=None)
    assert machine.axes["X"].override_factor == 1.0
    drive.run(0.05, commissioning=CommissioningRequests(override=50.0))
    assert machine.axes["X"].override_factor == pytest.approx(0.5)


class Front:
    """A front end that presses Stop once (the panel's way on a group member)."""

    def __init__(self, operator: AxisOperator) -> None:
        self.operator = operator
        self.press = False

    def __call__(self) -> None:
        if self.press:
            self.press, self.operator.group_stop = False, True
        self.operator(Orders())


def test_a_stop_on_a_group_member_takes_the_group_apart() -> None:
    machine = make_machine("XY")
    group = mcl.AxesGroup("G")
    add = mcl.MC_AddAxisToGroup()
    for axis in machine.axes.values():
        add(AxesGroup=group, Axis=axis, Execute=True)
        add(Execute=False)
    heard: list[tuple[str, str]] = []
    fronts = [
        Front(AxisOperator(a, None, sim_time=lambda: machine.time)) for a in machine.axes.values()
    ]
    program = OperatorProgram(fronts, lambda *e: heard.append(e))
    assert program.groups() == [group] and set(program.axes) == {"X", "Y"}
    fronts[1].press = True
    machine.run(program, timeout=0.1)
    assert program.groups() == [] and not program.releasing
    assert all(a.group is None for a in machine.axes.values()) and not heard


def test_a_refused_group_release_is_heard_once() -> None:
    heard: list[tuple[str, str]] = []
    release = GroupRelease(mcl.AxesGroup("E"), lambda *e: heard.append(e))
    assert release._steps == [release.disable, release.ungroup]  # not in GroupErrorStop
    release()
    release()
    assert release.done and len(heard) == 1 and heard[0][0] == "group E"

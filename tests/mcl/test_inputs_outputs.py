"""Digital and analog I/O of an axis channel through the PLCopen blocks and the AXIS_REF fields,
and the encoder-only axis."""

from __future__ import annotations

import pytest

import mcl
from tests.helpers import configure, power_on


def machine_with(**params: object) -> tuple[mcl.SimMachine, mcl.Axis]:
    params = {"start": 0.2, **params}
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(**params)})  # type: ignore[arg-type]
    return machine, machine.axes["X"]


def test_a_program_sets_and_reads_back_a_digital_output():
    machine, X = machine_with(digital_outputs=2)
    write, read = mcl.MC_WriteDigitalOutput(), mcl.MC_ReadDigitalOutput()
    write(Axis=X, Execute=True, OutputNumber=1, Value=True)
    read(Axis=X, Enable=True, OutputNumber=1)
    assert write.Done and read.Valid and read.Value
    assert X.DO == (False, True) and machine.sims["X"].outputs == [False, True]
    write(Execute=False)
    write(Execute=True, Value=False)
    read()
    assert not read.Value and X.DO == (False, False)


@pytest.mark.parametrize("number", [2, -1, 0.5, float("nan"), "one"])
def test_an_output_the_axis_does_not_have_gives_eparam_and_changes_nothing(number: object):
    _, X = machine_with(digital_outputs=2)
    write = mcl.MC_WriteDigitalOutput()
    write(Axis=X, Execute=True, OutputNumber=number, Value=True)
    assert write.Error and write.ErrorID == mcl.ErrorID.EParam
    assert X.DO == (False, False)


def test_digital_inputs_are_the_switches_then_the_probe():
    _, X = machine_with(start=0.05, probe=mcl.Marks(first=0.05, width=0.001))
    read = mcl.MC_ReadDigitalInput()
    values = []
    for number in range(4):
        read(Axis=X, Enable=True, InputNumber=number)
        values.append(read.Value)
    assert values == [False, False, True, True]  # LIM+, LIM−, REF (below 100 mm), TP on a mark
    assert X.DI == (False, False, True, True)
    read(InputNumber=4)
    assert read.Error and read.ErrorID == mcl.ErrorID.EParam and not read.Valid


def test_analog_inputs_are_read_in_volts():
    _, X = machine_with(analog=(4.5,))
    read = mcl.MC_ReadAnalogInput()
    read(Axis=X, Enable=True, InputNumber=0)
    assert read.Valid and read.Value == 4.5 and X.AI == (4.5,)
    read(InputNumber=1)
    assert read.Error and read.ErrorID == mcl.ErrorID.EParam


def test_an_encoder_only_axis_measures_but_refuses_power_and_motion():
    machine, W = machine_with(has_drive=False, coulomb=0.0, viscous=0.0)
    configure(W)
    sim = machine.sims["X"]
    power, move, jog = mcl.MC_Power(), mcl.MC_MoveVelocity(), mcl.GT_Jog()
    power(Axis=W, Enable=True)
    move(Axis=W, Execute=True, Velocity=100.0)
    jog(Axis=W, Enable=True, JogPos=True, JogVelo=10.0)
    for fb in (power, move, jog):
        assert fb.Error and fb.ErrorID == mcl.ErrorID.ENoDrive
    assert W.state == mcl.AxisState.Disabled
    sim.v = 0.5  # the material drags the measuring wheel along
    machine.run(timeout=0.2)
    assert pytest.approx(500.0, rel=0.01) == W.VEL
    position = mcl.MC_ReadActualPosition()
    position(Axis=W, Enable=True)
    assert position.Valid and position.Position == pytest.approx(100.0, abs=1.0)
    sim.write(10.0, True)
    assert sim.volts == 0.0 and not sim.enabled  # nothing to drive


def test_a_driven_axis_still_powers_normally():
    machine, X = machine_with()
    configure(X)
    power_on(machine, X)
    assert X.has_drive and X.state == mcl.AxisState.StandStill

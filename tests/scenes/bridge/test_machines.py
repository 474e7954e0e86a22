"""The machines driven through the bridge's signal table by a PLC, in-process and over Modbus TCP
in lockstep (the server in its own process): the flying shear gears in to the measuring wheel and
cuts through its knife output, the press holds a force; both measured from the physics."""

from __future__ import annotations

import statistics
from pathlib import Path

import pytest

from tests.bridge_clients import (
    PRESS_FORCE,
    SHEAR_LENGTH,
    InProcess,
    ModbusLockstep,
    modbus_server,
    press_holds,
    shear_cuts,
)


def test_the_flying_shear_cuts_to_length_through_the_table() -> None:
    plc = InProcess("flying_shear")
    pieces = shear_cuts(plc, 4)
    assert len(pieces) == 4
    assert pieces[0] == pytest.approx(SHEAR_LENGTH, abs=5.0)  # the wheel's scale not yet known
    for piece in pieces[1:]:  # corrected by the pieces measured
        assert piece == pytest.approx(SHEAR_LENGTH, abs=0.5)


def test_the_press_holds_a_force_through_the_table() -> None:
    forces = press_holds(InProcess("press"), 0.5)
    assert statistics.fmean(forces) == pytest.approx(PRESS_FORCE, abs=0.5)  # the load cell
    assert max(abs(f - PRESS_FORCE) for f in forces) < 1.0


@pytest.mark.parametrize("machine", ["flying_shear", "press"])
def test_over_modbus_in_lockstep_as_in_process(machine: str, tmp_path: Path) -> None:
    """The same scenario over Modbus in lockstep: the same pieces and forces, to the bit."""

    def scenario(plc: InProcess | ModbusLockstep) -> list[float]:
        return shear_cuts(plc, 1) if machine == "flying_shear" else press_holds(plc, 0.1)

    reference = scenario(InProcess(machine))
    with modbus_server(machine, tmp_path / "stderr.txt", "--lockstep") as client:
        assert scenario(ModbusLockstep(machine, client)) == reference

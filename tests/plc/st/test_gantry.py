"""The MotionControlLib manual's ST example (Fig. 2.4) on the gantry, Pohon.Ax1 mapped to X,
unchanged but for a target inside the travel (examples/st/manual_move.st)."""

import pytest

import plc.st
from scenes.tools.testing import home, physical_position
from tests.helpers import ROOT

EXAMPLE = ROOT / "examples" / "st" / "manual_move.st"
TARGET = 300.0


@pytest.fixture
def gantry(scene):
    machine = scene("gantry")
    home(machine, "X")
    return machine


def test_a_rising_edge_on_start_moves_x_and_done_is_held_while_start_stays(gantry):
    prog = plc.st.load(EXAMPLE, gantry, mapping={"Pohon.Ax1": "X"})
    done = []

    def scan():
        prog()
        done.append(prog.Done2)

    gantry.run(scan, timeout=0.1)
    assert not any(done) and not prog.Busy2
    prog.Start = True
    gantry.run(scan, until=lambda: prog.Done2, timeout=20.0)
    held = len(done)
    gantry.run(scan, timeout=0.5)
    assert all(done[held - 1 :])  # Done stays while Execute (Start) is TRUE
    assert physical_position(gantry, "X") == pytest.approx(TARGET, abs=0.05)
    assert not (prog.Busy2 or prog.Error2 or prog.Aborted2) and prog.ErrorID2 == 0
    prog.Start = False
    gantry.run(scan, timeout=0.1)
    assert not prog.Done2  # reset by the falling edge


def test_done_is_true_for_exactly_one_scan_when_start_fell_before_the_end(gantry):
    prog = plc.st.load(EXAMPLE, gantry, mapping={"Pohon.Ax1": "X"})
    done = []

    def scan():
        prog()
        done.append(prog.Done2)

    prog.Start = True
    gantry.run(scan, timeout=0.2)
    assert prog.Busy2 and prog.Active2
    prog.Start = False
    gantry.run(scan, until=lambda: physical_position(gantry, "X") > TARGET - 0.05, timeout=20.0)
    gantry.run(scan, timeout=1.0)
    assert sum(done) == 1
    assert physical_position(gantry, "X") == pytest.approx(TARGET, abs=0.05)

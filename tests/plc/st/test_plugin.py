"""ST programs in scenario tests (the ``st_program`` fixture of scenes.tools.testing) and as a
sweep's scenario (``"gantry:file.st"``)."""

from pathlib import Path

import pytest

from scenes.tools.sweep import Sweep, check
from scenes.tools.testing import home, physical_position
from tests.helpers import ROOT

MANUAL = ROOT / "examples" / "st" / "manual_move.st"


def test_a_test_loads_an_st_program_writes_start_and_reads_the_blocks_done(scene, st_program):
    gantry = scene("gantry")
    home(gantry, "X")
    prog = st_program(MANUAL, gantry, mapping={"Pohon.Ax1": "X"})
    assert prog.step == "prgMain" and not prog.Head_X.Done
    prog.Start = True
    gantry.run(prog, until=lambda: prog.Head_X.Done, timeout=20.0)
    assert prog.Done2 and physical_position(gantry, "X") == pytest.approx(300.0, abs=0.05)


def test_a_relative_path_is_found_beside_the_test(scene, st_program):
    prog = st_program("sweep_move.st", scene("gantry", trace_every=0))
    assert prog.distance == 100.0 and prog.name == "SweepMove"


def test_a_sweep_runs_an_st_program_over_its_variables(monkeypatch):
    monkeypatch.chdir(Path(__file__).parent)
    sweep = Sweep("gantry:sweep_move.st", grid={"distance": [50.0, 120.0]}, seed=1)
    table = sweep.run(workers=0)
    assert "error" not in table
    assert list(table["distance"]) == [50.0, 120.0]
    assert list(table["travel"]) == pytest.approx([50.0, 120.0], abs=0.05)
    assert (table["time_s"] > 0.2).all()


def test_a_sweep_of_an_st_program_refuses_a_name_it_lacks(monkeypatch):
    monkeypatch.chdir(Path(__file__).parent)
    problems = check({"scenario": "gantry:sweep_move.st", "grid": {"distanse": [1.0]}})
    assert problems[0][:2] == ("grid.distanse", "not a parameter of gantry:sweep_move.st")
    assert "distance" in problems[0][2]
    missing = check({"scenario": "gantry:nothing.st"})
    assert missing[0][0] == "scenario" and "cannot read it" in missing[0][1]

"""The scenes package as a user meets it: load by name, the CLI, and clear wiring errors."""

from __future__ import annotations

import pytest

import mcl
import scenes
from scenes.definition import AxisDef, MachineDef
from scenes.machines import gantry
from scenes.plant.mujoco import WiringError
from scenes.scene import Scene
from scenes.tools.cli import main


def test_run_single_axis_demo_prints_the_report(capsys):
    assert main(["run", "single_axis"]) == 0
    out = capsys.readouterr().out
    assert "move.Done↑" in out
    assert "third.Done↑" in out
    assert "X: POS" in out and "StandStill" in out


def test_run_prints_the_machines_signals_and_the_demos_results(capsys):
    """The press' report ends with its signals (the chamber pressures, the force) and one
    line per step of its cycle, the pressing step at its 150 bar."""
    assert main(["run", "press"]) == 0
    out = capsys.readouterr().out
    assert "pressure A: " in out and " bar" in out and "load cell force: " in out
    lines = out.split("== results (")[1].splitlines()
    assert lines[1].split("  ")[:2] == ["step", "ended [s]"]
    pressing = next(line for line in lines if line.startswith("press to 150 bar"))
    assert 140.0 < float(pressing.split("  ")[4]) < 170.0  # p_A at the end of the step


def test_list_names_the_scenes(capsys):
    assert main(["list"]) == 0
    assert set(capsys.readouterr().out.split()) >= {"gantry", "single_axis"}


def test_unknown_scene_names_the_valid_ones():
    with pytest.raises(KeyError, match="gantry"):
        scenes.load("lathe")
    with pytest.raises(SystemExit):
        main(["run", "lathe"])


def test_load_gantry_by_name_with_overrides():
    scene = scenes.load("gantry", start={"X": 0.3}, trace_every=0)
    assert set(scene.axes) == {"X", "Y", "Z"}
    assert scene.joint_position("X") == pytest.approx(0.3)
    assert scene.axes["X"].POS == 0.0  # incremental encoder: counts from power-up
    assert scenes.homing(scene)["X"].set_position == 120.0


def test_missing_model_file_says_which_files_exist():
    spec = gantry.AXES["X"]
    with pytest.raises(FileNotFoundError, match=r"gantry\.xml"):
        Scene([MachineDef("m", "test", {"X": spec}, model="no_such_machine.xml")])


def test_model_without_an_amplifier_names_the_actuators(tmp_path):
    xml = tmp_path / "bare.xml"
    xml.write_text("""<mujoco><worldbody><body name="b"><joint name="X" type="slide"/>
      <geom size=".1"/></body></worldbody>
      <actuator><motor name="X_motor" joint="X"/></actuator></mujoco>""")
    spec = AxisDef(mcl.AxisConfig(), mcl.ServoConstants(Vmax=100.0))
    with pytest.raises(WiringError, match=r"X_amp.*X_motor"):
        Scene([MachineDef("bare", "test", {"X": spec}, model=str(xml))])


def test_wrong_encoder_resolution_is_refused():
    spec = gantry.AXES["X"]
    wrong = AxisDef(mcl.AxisConfig(resolution=0.01), spec.constants)
    with pytest.raises(WiringError, match="resolution"):
        Scene([MachineDef("gantry", "test", {**gantry.AXES, "X": wrong}, model="gantry.xml")])


def test_period_not_a_multiple_of_the_timestep_is_refused():
    with pytest.raises(ValueError, match="integer multiple"):
        scenes.load("gantry", servo_period=0.0012)


PROGRAM_WITHOUT_DONE = """PROGRAM Main
VAR
  n : INT;
END_VAR
n := n + 1;
END_PROGRAM
"""


def test_a_program_without_done_is_told_it_runs_for_the_timeout(tmp_path, capsys):
    path = tmp_path / "count.st"
    path.write_text(PROGRAM_WITHOUT_DONE)
    assert main(["run", "single_axis", "--program", str(path), "--timeout", "0.2"]) == 0
    err = capsys.readouterr().err
    assert "no variable 'done'" in err and "0.2 s" in err


def test_a_program_that_never_sets_done_fails_with_a_message_not_a_traceback(tmp_path, capsys):
    path = tmp_path / "never.st"
    path.write_text(PROGRAM_WITHOUT_DONE.replace("n : INT;", "n : INT;\n  done : BOOL;"))
    assert main(["run", "single_axis", "--program", str(path), "--timeout", "0.2"]) == 1
    err = capsys.readouterr().err
    assert f"{path} did not set done within the --timeout of 0.2 s" in err
    assert "Traceback" not in err

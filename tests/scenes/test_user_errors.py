"""A user's mistakes as the user meets them: ``python -m scenes`` run in a subprocess from a
folder outside the checkout, each mistake one line ``file:line: key: what is wrong; expected
...`` on standard error, exit status 2 and no traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

import mcl
import scenes

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

PAYLOAD = 'scenario = "scenes.tools.examples:payload_following_error"\n'


def assert_refused(result: subprocess.CompletedProcess[str], line: str) -> None:
    """The command stopped with exit status 2 and said ``line``, one line on stderr."""
    assert (result.returncode, result.stderr.splitlines()) == (2, [line])


def cli(folder: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """``python -m scenes ARGS`` run in ``folder`` (the same interpreter and build mode)."""
    env = {**os.environ, "MCL_PURE_PYTHON": os.environ.get("MCL_PURE_PYTHON", "")}
    return subprocess.run(
        [sys.executable, "-m", "scenes", *args],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


SWEEP_MISTAKES = {
    "a grid value that is a number": (
        PAYLOAD + "workers = 0\n[grid]\npayload_kg = 5\n",
        (),
        [
            "s.toml:4: grid.payload_kg: 5 is a single value, not a list; "
            "expected a list of values, e.g. payload_kg = [5]"
        ],
    ),
    "an unknown parameter": (
        PAYLOAD + "[grid]\npayload = [1, 2]\n",
        (),
        [
            "s.toml:3: grid.payload: not a parameter of "
            "scenes.tools.examples:payload_following_error; expected one of "
            "['friction_n', 'payload_kg'] (did you mean 'payload_kg'?)"
        ],
    ),
    "a TOML syntax error": (
        PAYLOAD + "seed = = 3\n",
        (),
        [
            "s.toml:2: TOML syntax: Invalid value, column 8; expected valid TOML (key = value, "
            "[table])"
        ],
    ),
    "an unclosed list": (
        PAYLOAD + "[grid]\npayload_kg = [1, 2\n",
        (),
        ["s.toml:3: TOML syntax: Unclosed array; expected valid TOML (key = value, [table])"],
    ),
    "an unknown key": (
        PAYLOAD + "sampels = 3\n",
        (),
        [
            "s.toml:2: sampels: unknown key; expected one of ['address', 'grid', 'out', 'random', "
            "'samples', 'scenario', 'seed', 'workers'] (did you mean 'samples'?)"
        ],
    ),
    "a scenario that does not exist": (
        'scenario = "scenes.machines.gantry.scenarios:homing"\n',
        (),
        [
            "s.toml:1: scenario: module scenes.machines.gantry.scenarios has no function "
            "'homing'; expected one of ['homing_repeatability']"
        ],
    ),
    "random bounds the wrong way round": (
        PAYLOAD + "samples = 2\n[random]\npayload_kg = [40, 0]\n",
        (),
        ["s.toml:4: random.payload_kg: low 40 is above high 0; expected [0, 40]"],
    ),
    "a value of the wrong type": (
        'scenario = "scenes.machines.flying_shear.scenarios:cut_length"\n'
        '[grid]\nspeed_m_min = [30, "fast"]\n',
        (),
        ["s.toml:3: grid.speed_m_min: 'fast' is not a number; expected values of type float"],
    ),
    "two mistakes at once": (
        PAYLOAD + "samples = 0\n[grid]\nfriction = [5]\n",
        (),
        [
            "s.toml:2: samples: 0; expected an integer >= 1",
            "s.toml:4: grid.friction: not a parameter of "
            "scenes.tools.examples:payload_following_error; expected one of "
            "['friction_n', 'payload_kg'] (did you mean 'friction_n'?)",
        ],
    ),
    "a bad value on the command line": (
        PAYLOAD + "[grid]\nfriction_n = [5]\n",
        ("--grid", "friction_n=5,x", "--set", "seed=-1"),
        [
            "command line: grid.friction_n: 'x' is not a number; expected values of type float",
            "command line: seed: -1; expected an integer >= 0",
        ],
    ),
}


@pytest.mark.parametrize("mistake", sorted(SWEEP_MISTAKES))
def test_a_sweep_file_mistake_is_one_line_and_exit_status_2(tmp_path, mistake):
    text, extra, lines = SWEEP_MISTAKES[mistake]
    (tmp_path / "s.toml").write_text(text)
    result = cli(tmp_path, "sweep", "s.toml", *extra)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    assert result.stderr.splitlines() == lines
    assert not list(tmp_path.glob("*.csv"))  # nothing ran


def test_a_missing_sweep_file_says_where_it_was_looked_for(tmp_path):
    result = cli(tmp_path, "sweep", "nosuch.toml")
    assert_refused(
        result,
        f"nosuch.toml: no such file; expected a sweep file (TOML), relative to {tmp_path}",
    )


@pytest.fixture(scope="module")
def trace_csv(tmp_path_factory) -> Path:
    machine = scenes.load("single_axis")
    power = mcl.MC_Power(Axis=machine.axes["X"])
    machine.run(lambda: power(Enable=True), timeout=0.02)
    return machine.trace.to_csv(tmp_path_factory.mktemp("trace") / "run.csv")


def test_plot_mistakes_are_one_line_each(tmp_path, trace_csv):
    lines = trace_csv.read_text().splitlines()
    (tmp_path / "ragged.csv").write_text("\n".join([*lines[:5], lines[5] + ",1", *lines[6:]]))
    row = lines[7].split(",")
    row[2] = "abc"
    (tmp_path / "text.csv").write_text("\n".join([*lines[:7], ",".join(row), *lines[8:]]))
    (tmp_path / "table.csv").write_text("run,seed\n0,1\n")
    expected = "a trace written by scene.trace.to_csv (.csv) or streamed (.csv, .npy)"
    cases = {
        "nosuch.csv": f"nosuch.csv: no such file; expected {expected}, relative to {tmp_path}",
        "ragged.csv": f"ragged.csv:6: Expected 12 fields in line 6, saw 13; expected {expected}",
        "text.csv": "text.csv:8: X.actual: 'abc' is not a number; expected numbers only",
        "table.csv": f"table.csv:1: no '<axis>.t' column (columns: ['run', 'seed']); expected "
        f"{expected}",
        "run.txt": f"run.txt: a .txt file; expected {expected}",
    }
    for file, line in cases.items():
        result = cli(tmp_path, "plot", file)
        assert_refused(result, line)


MODEL = Path(scenes.__file__).resolve().parent.parent / "models" / "gantry.xml"

RUN_WITH_MODEL = """
import sys
from dataclasses import replace
import scenes
from scenes.tools.cli import main
scenes.MACHINES["gantry"] = replace(scenes.MACHINES["gantry"], model=sys.argv[1])
sys.exit(main(["run", "gantry"]))
"""


def edited_model(tmp_path: Path, old: str, new: str) -> Path:
    text = MODEL.read_text()
    assert old in text
    path = tmp_path / "my_gantry.xml"
    path.write_text(text.replace(old, new, 1))
    return path


def run_gantry(tmp_path: Path, model: Path) -> subprocess.CompletedProcess[str]:
    (tmp_path / "run.py").write_text(RUN_WITH_MODEL)
    return subprocess.run(
        [sys.executable, "run.py", str(model)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )


def line_of(path: Path, text: str) -> int:
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_malformed_mjcf_names_the_users_file_and_line(tmp_path):
    model = edited_model(tmp_path, '<body name="bridge" pos="-0.5 0 1.0">', '<body name="bridge"')
    result = run_gantry(tmp_path, model)
    line = line_of(model, '<joint name="X"')  # where the parser finds the start tag broken
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.startswith(f"{model}:{line}: XML syntax: ")
    assert len(result.stderr.splitlines()) == 1


def test_a_renamed_joint_says_which_name_the_machine_expects(tmp_path):
    model = edited_model(tmp_path, '<joint name="X"', '<joint name="X_slide"')
    result = run_gantry(tmp_path, model)
    x, y, z = (line_of(model, f'<joint name="{name}"') for name in ("X_slide", "Y", "Z"))
    assert_refused(
        result,
        f"{model}: <joint name='X'>: not in the file, but machine 'gantry' needs it for axis X "
        f"(AxisDef.joint); expected one of the file's joints: 'X_slide' (line {x}), "
        f"'Y' (line {y}), 'Z' (line {z})",
    )


def test_a_compile_error_points_into_the_users_file_not_the_combined_model(tmp_path):
    model = edited_model(tmp_path, 'range="-0.050 1.050"', 'range="1.050 -0.050"')
    result = run_gantry(tmp_path, model)
    line = line_of(model, '<joint name="X"')
    assert_refused(
        result,
        f"{model}:{line}: <joint name='X'>: range[0] should be "
        "smaller than range[1] in joint; expected a model MuJoCo compiles "
        "(https://mujoco.readthedocs.io/en/stable/XMLreference.html)",
    )


def test_a_removed_amplifier_names_it_at_the_keyframe_that_no_longer_fits(tmp_path):
    import re

    text = MODEL.read_text()
    text, removed = re.subn(r"\n *<general name=\"Y_amp\".*?/>", "", text, flags=re.S)
    text = text.replace('<actuatorfrc name="Y_force" actuator="Y_amp"/>', "")
    assert removed == 1 and "Y_amp" not in text
    model = tmp_path / "my_gantry.xml"
    model.write_text(text)
    result = run_gantry(tmp_path, model)
    line = line_of(model, '<key name="home"')
    assert_refused(
        result,
        f"{model}:{line}: <key name='home'>: act has 3 values, the model has 2 actuator "
        "activations (one per actuator with dynamics, dyntype); expected the file to have "
        "actuator 'Y_amp' (machine 'gantry' needs it as the amplifier of axis Y), or act with "
        "2 values",
    )


FLAKY = '''
def flaky(seed, x: float = 0.0):
    """Fails above 1."""
    if x > 1:
        raise ValueError("x too big")
    return {"twice_x": 2.0 * x}
'''


def test_a_sweep_shows_progress_keeps_failed_rows_and_writes_where_told(tmp_path):
    (tmp_path / "flaky.py").write_text(FLAKY)
    (tmp_path / "s.toml").write_text('scenario = "flaky:flaky"\nworkers = 0\n[grid]\nx = [0]\n')
    result = cli(tmp_path, "sweep", "s.toml", "--grid", "x=0,1,2,3", "--out", "results")
    assert result.returncode == 1  # a scenario failed
    assert "Traceback" not in result.stderr
    progress = result.stderr.splitlines()
    assert progress[0] == "s.toml: 4 scenarios of flaky:flaky (serially)"
    assert progress[-1].startswith("s.toml: 4/4 done, 2 failed, ")
    assert len(progress) <= 12
    table = pd.read_csv(tmp_path / "results" / "s.csv", keep_default_na=False)
    assert list(table["x"]) == [0, 1, 2, 3]
    assert list(table["error"]) == ["", "", "ValueError: x too big", "ValueError: x too big"]
    assert (tmp_path / "results" / "s_x.png").stat().st_size > 10_000
    out = result.stdout
    assert "2 failed (column 'error'):\n  runs 2, 3: ValueError: x too big" in out
    whole = out[out.index("over the whole sweep:") :]
    assert "twice_x" in whole
    assert not any(line.split()[:1] in (["run"], ["seed"]) for line in whole.splitlines())


def test_the_sweep_api_takes_numpy_values_and_names_each_mistake():
    import numpy as np

    from scenes.errors import UserError
    from scenes.tools.sweep import Sweep

    sweep = Sweep(
        "scenes.tools.examples:payload_following_error",
        grid={"friction_n": np.array([5, 15])},
        random={"payload_kg": (np.float64(0.0), 40)},
        samples=2,
    )
    assert [r["friction_n"] for r in sweep.rows()] == [5, 5, 15, 15]
    with pytest.raises(UserError) as error:
        number_not_list: Any = 5
        Sweep(
            "scenes.tools.examples:payload_following_error",
            grid={"friction": number_not_list},
            samples=0,
        )
    assert error.value.lines == [
        "Sweep: grid.friction: not a parameter of scenes.tools.examples:payload_following_error; "
        "expected one of ['friction_n', 'payload_kg'] (did you mean 'friction_n'?)",
        "Sweep: grid.friction: 5 is a single value, not a list; expected a list of values, "
        "e.g. friction = [5]",
        "Sweep: samples: 0; expected an integer >= 1",
    ]


def test_a_renamed_amplifier_names_the_file_and_the_actuators_it_has(tmp_path):
    from dataclasses import replace

    from scenes.errors import ModelError
    from scenes.scene import Scene

    model = edited_model(tmp_path, '<general name="X_amp"', '<general name="X_drive"')
    model.write_text(model.read_text().replace('actuator="X_amp"', 'actuator="X_drive"'))
    gantry = replace(scenes.definition("gantry"), model=str(model))
    with pytest.raises(ModelError) as error:
        Scene([gantry], trace_every=0)
    assert error.value.lines == [
        f"{model}: model has no actuator 'gantry/X_amp'; actuators: "
        "['gantry/X_drive', 'gantry/Y_amp', 'gantry/Z_amp']"
    ]

"""docs/own-machine.md is true: its own files, written into an empty folder, make a machine that
registers, loads, runs its demo to done and moves the slide's joint where the demo says (from the
physics); its pyproject entry point registers it for the CLI; and its model keeps the
conventions the contract test checks for every machine."""

from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys
import tomllib
from collections.abc import Callable
from pathlib import Path

import pytest

import scenes
from tests.helpers import ROOT
from tests.scenes import test_machine_contract as contract

ROOT = ROOT
GUIDE = ROOT / "docs" / "own-machine.md"
BLOCK = re.compile(r"^<!-- file: (?P<path>\S+) -->\n```\w*\n(?P<text>.*?)^```$", re.S | re.M)
"""A file of the guide: the comment line naming it, then its fenced block."""
FINAL = 150.0
"""Where the guide's demo leaves the slide: 200 mm, then back by 50 mm [mm]."""


def files() -> dict[str, str]:
    """The guide's files: path → text."""
    found = {m["path"]: m["text"] for m in BLOCK.finditer(GUIDE.read_text(encoding="utf-8"))}
    assert {"my_machines/slide.xml", "my_machines/slide.py", "run_slide.py"} <= set(found)
    return found


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An empty folder holding the guide's files."""
    root = tmp_path_factory.mktemp("own_machine")
    for path, text in files().items():
        (root / path).parent.mkdir(parents=True, exist_ok=True)
        (root / path).write_text(text, encoding="utf-8")
    return root


def python(folder: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """Run Python in ``folder`` (this checkout's testbench importable), output captured."""
    paths = [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(paths))
    return subprocess.run(
        [sys.executable, *args], cwd=folder, env=env, capture_output=True, text=True, timeout=300
    )


def test_the_guides_machine_runs_its_demo_to_done_and_the_slide_ends_where_the_demo_says(
    folder: Path,
) -> None:
    result = python(folder, "run_slide.py")
    assert result.returncode == 0, result.stderr
    assert re.search(r"^done at t = ", result.stdout, re.M), result.stdout
    joint = re.search(r"^X joint: (-?\d+\.\d+) mm$", result.stdout, re.M)
    assert joint is not None, result.stdout
    assert float(joint.group(1)) == pytest.approx(FINAL, abs=0.02)  # mm, from the joint


def test_the_guides_entry_point_registers_the_machine_for_the_cli(folder: Path) -> None:
    """What ``pip install`` of the guide's pyproject.toml records (the package's metadata with
    its entry points) is found by the registry: ``python -m scenes run slide`` runs the demo."""
    project = tomllib.loads((folder / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    points = project["entry-points"]
    info = folder / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    info.mkdir(exist_ok=True)
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n"
    )
    (info / "entry_points.txt").write_text(
        "".join(
            f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items())
            for group, entries in points.items()
        )
    )
    listed = python(folder, "-m", "scenes", "list")
    assert listed.returncode == 0, listed.stderr
    assert re.search(r"^slide\s+a one-axis", listed.stdout, re.M), listed.stdout
    run = python(folder, "-m", "scenes", "run", "slide")
    assert run.returncode == 0, run.stderr
    assert f"X: POS {FINAL:.4f} mm, state StandStill, AxErrorID 0" in run.stdout, run.stdout


CONVENTIONS = [
    contract.test_each_axis_has_what_the_plant_needs,
    contract.test_the_home_keyframe_puts_every_joint_at_0_and_the_switches_as_their_trips_say,
    contract.test_drive_parameters_are_consistent,
    contract.test_switch_formula_at_joint_positions,
    contract.test_dog_geoms_match_switch_windows,
    contract.test_the_model_compiles_and_steps,
    contract.test_the_machines_scene_builds_and_steps,
    contract.test_the_demo_runs_without_error_and_moves_the_machine,
    contract.test_a_state_saved_at_power_up_repeats_the_demo_bit_for_bit_in_a_fresh_scene,
]
"""The contract tests that hold for a machine whose model is not in models/ (those that read
models/README.md skip it)."""


@pytest.mark.parametrize("check", CONVENTIONS, ids=lambda f: f.__name__.removeprefix("test_"))
def test_the_guides_model_keeps_the_machine_conventions(
    folder: Path, monkeypatch: pytest.MonkeyPatch, check: Callable[[str], None]
) -> None:
    monkeypatch.syspath_prepend(str(folder))
    try:
        machine = importlib.import_module("my_machines.slide").MACHINE
        monkeypatch.setitem(scenes.MACHINES, "slide", machine)
        check("slide")
    finally:
        for module in [m for m in sys.modules if m.split(".")[0] == "my_machines"]:
            del sys.modules[module]

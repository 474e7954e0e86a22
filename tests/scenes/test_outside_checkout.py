"""What a user sees outside the checkout: a script and a Dask sweep started from another folder,
in both import orders and both modes, and the packages installed as a copy (not editable)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from mcl import native
from tests.helpers import ROOT

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

ROOT = ROOT
FRESH = native.stale_sources() == [] and not native.forced_pure()
MODES = [
    pytest.param("compiled", marks=pytest.mark.skipif(not FRESH, reason="no fresh compiled build")),
    "pure",
]

SCRIPT = """
{imports}
import json, sys
scene = scenes.load("gantry", start={{"X": 0.3}})   # the first example of docs/first-scenario.md
X = scene.axes["X"]
power, move = mcl.MC_Power(), mcl.MC_MoveRelative()

def program():
    power(Axis=X, Enable=True)
    move(Axis=X, Execute=power.Status, Distance=100.0, Velocity=200.0,
         Acceleration=2000.0, Deceleration=2000.0, Jerk=50000.0)

scene.run(program, until=lambda: move.Done, timeout=5.0)
try:
    scene.run(program, until=lambda: X.AxErrorID, timeout=0.05)   # an int, as users write
except mcl.ConditionTimeout:
    pass
print(json.dumps({{"compiled": [mcl.COMPILED, scenes.COMPILED], "pos": X.POS,
                  "joint": scene.joint_position("X"), "scenes": scenes.__file__,
                  "plant": sys.modules["scenes.plant.mujoco"].__file__}}))
"""


def run(code: str, cwd: Path, mode: str, **env: str) -> dict[str, Any]:
    """Run ``code`` in a new interpreter in ``cwd``; its last line of output, parsed."""
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    environment.update(MCL_PURE_PYTHON="1" if mode == "pure" else "", **env)
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=cwd, env=environment, capture_output=True, text=True
    )
    assert result.returncode == 0, result.stderr[-3000:]
    out: dict[str, Any] = json.loads(result.stdout.strip().splitlines()[-1])
    return out


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("imports", ["import mcl, scenes", "import scenes, mcl", "import scenes"])
def test_a_script_in_another_folder_runs_the_readme_example(tmp_path: Path, mode: str, imports):
    imports += "\nimport mcl" if "mcl" not in imports else ""
    out = run(SCRIPT.format(imports=imports), tmp_path, mode)
    assert out["compiled"] == [mode == "compiled"] * 2
    assert out["pos"] == pytest.approx(100.0, abs=0.01)
    assert out["joint"] == pytest.approx(0.4, abs=20e-6)  # 300 mm + 100 mm, on the physics
    assert str(out["scenes"]).startswith(str(ROOT))
    assert str(out["plant"]).endswith(".so" if mode == "compiled" else ".py")


SWEEP = """
import json
from scenes.tools.sweep import Sweep
table = Sweep("scenes.machines.gantry.scenarios:homing_repeatability",
              grid={"hysteresis_um": [0.0, 50.0]}, samples=1, seed=3).run(workers=2)
print(json.dumps({"error_um": list(table["origin_error_um"]), "rows": len(table)}))
"""


@pytest.mark.parametrize("mode", MODES)
def test_a_dask_sweep_from_another_folder_runs_in_its_workers(tmp_path: Path, mode: str):
    out = run(SWEEP, tmp_path, mode)
    assert out["rows"] == 2
    assert all(abs(e) < 20.0 for e in out["error_um"])  # X homed onto its index, on the joint


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The packages installed as a copy into a folder of their own (no editable finder)."""
    target = tmp_path_factory.mktemp("site")
    source = tmp_path_factory.mktemp("src") / "checkout"
    tracked = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split()
    for name in tracked:  # a clean copy of the sources, as a user's clone has them
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        if (ROOT / name).is_symlink():
            (source / name).symlink_to(os.readlink(ROOT / name))
        elif (ROOT / name).is_file():
            shutil.copy2(ROOT / name, source / name)
    uv = [shutil.which("uv") or "python3", *([] if shutil.which("uv") else ["-m", "uv"])]
    subprocess.run(
        [*uv, "pip", "install", "--quiet", "--python", sys.executable, "--no-deps",
         "--target", str(target), str(source)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    return target


def test_an_installed_copy_runs_from_another_folder(installed: Path, tmp_path: Path):
    out = run(
        SCRIPT.format(imports="import mcl, scenes"), tmp_path, "pure", PYTHONPATH=str(installed)
    )
    assert str(out["scenes"]).startswith(str(installed))
    assert out["compiled"] == [False, False]  # nothing compiled in that copy yet
    assert out["joint"] == pytest.approx(0.4, abs=20e-6)


@pytest.mark.skipif(not FRESH, reason="no fresh compiled build")
def test_an_installed_copy_runs_compiled_beside_its_sources(installed: Path, tmp_path: Path):
    """The compiled files of the same sources, beside the copy's sources, are what it imports
    (``python -m mcl.build`` in the installed copy puts them there)."""
    for path in [*native.compiled_files(), native.MANIFEST]:
        shutil.copy2(path, installed / path.relative_to(native.ROOT))
    try:
        out = run(SCRIPT.format(imports="import scenes\nimport mcl"), tmp_path, "compiled",
                  PYTHONPATH=str(installed))  # fmt: skip
    finally:
        for path in [*native.compiled_files(), native.MANIFEST]:
            (installed / path.relative_to(native.ROOT)).unlink()
    assert out["compiled"] == [True, True]
    assert str(out["plant"]).startswith(str(installed)) and str(out["plant"]).endswith(".so")
    assert out["joint"] == pytest.approx(0.4, abs=20e-6)

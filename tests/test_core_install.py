"""An environment with the core alone (pyproject.toml's dependencies, no extra), made from this
interpreter's environment without the network: ``import mcl`` works and a simulated axis moves;
importing a part without its extra fails with the one line that names the extra to install."""

from __future__ import annotations

import importlib.metadata
import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from tests.helpers import CONSTANTS, ROOT

pytestmark = pytest.mark.once  # new interpreters, pure Python (see the marker in pyproject.toml)

PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
EXTRAS = [e for e in PROJECT["optional-dependencies"] if e not in ("all", "test", "docs")]
"""The extras (their names)."""
EXTRA_PACKAGES = sorted(
    {
        requirement.partition("==")[0]
        for extra in EXTRAS
        for requirement in PROJECT["optional-dependencies"][extra]
        if not requirement.startswith("mcl-testbench[")
    }
)
"""Every package an extra adds (their distribution names are their import names)."""


def core_environment(folder: Path) -> Path:
    """A new virtual environment in ``folder`` with only the core dependencies of pyproject.toml
    (linked from this interpreter's environment, no network) and this checkout's packages; its
    interpreter."""
    site = folder / "site"
    site.mkdir()
    for requirement in PROJECT["dependencies"]:
        distribution = importlib.metadata.distribution(requirement.partition("==")[0])
        tops = {Path(str(f)).parts[0] for f in distribution.files or ()}
        for top in tops - {"..", "__pycache__"}:
            (site / top).symlink_to(Path(str(distribution.locate_file(top))))
    for name in ("mcl", "plc", "scenes", "viewer", "pytest_mcl_testbench.py"):
        (site / name).symlink_to(ROOT / name)
    venv = folder / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", venv], check=True)
    python = venv / "bin" / "python"
    purelib = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
        capture_output=True, text=True, check=True,
    ).stdout.strip()  # fmt: skip
    Path(purelib, "core.pth").write_text(f"{site}\n")
    return python


CORE_RUN = """
import importlib.util, json, sys
import mcl, mcl.extras, pytest_mcl_testbench
machine = mcl.SimMachine({{"X": mcl.SimAxisParams(start=0.2)}})
X = machine.axes["X"]
constants, power, move = mcl.GT_SetConstant(), mcl.MC_Power(), mcl.MC_MoveRelative()
constants(Axis=X, Execute=True, **{constants})
start = X.POS

def program():
    power(Axis=X, Enable=True)
    move(Axis=X, Execute=power.Status, Distance=100.0, Velocity=200.0,
         Acceleration=2000.0, Deceleration=2000.0, Jerk=50000.0)

machine.run(program, until=lambda: move.Done, timeout=5.0)
print(json.dumps({{
    "moved": X.POS - start, "carriage_mm": (machine.sims["X"].x - 0.2) * 1000.0,
    "error": X.AxErrorID, "installed": [e for e in {extras} if mcl.extras.installed(e)],
    "found": [m for m in {packages} if importlib.util.find_spec(m)],
    "plugin_fixtures": hasattr(pytest_mcl_testbench, "scene"),
}}))
"""


@pytest.fixture(scope="module")
def core_python(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return core_environment(tmp_path_factory.mktemp("core"))


def run_core(python: Path, code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """``code`` run by the core environment's interpreter in ``cwd``, pure Python (an installed
    copy has no compiled build)."""
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    environment["MCL_PURE_PYTHON"] = "1"
    return subprocess.run(
        [python, "-c", code], cwd=cwd, env=environment, capture_output=True, text=True
    )


def test_with_the_core_alone_the_library_moves_a_simulated_axis(core_python: Path, tmp_path):
    code = CORE_RUN.format(constants=dict(CONSTANTS), extras=EXTRAS, packages=EXTRA_PACKAGES)
    result = run_core(core_python, code, tmp_path)
    assert result.returncode == 0, result.stderr[-3000:]
    out = json.loads(result.stdout.strip().splitlines()[-1])
    assert out["found"] == [] and out["installed"] == []  # none of the extras is there
    assert out["error"] == 0
    assert out["moved"] == pytest.approx(100.0, abs=0.05)
    assert out["carriage_mm"] == pytest.approx(100.0, abs=0.05)  # the simulated carriage moved
    assert out["plugin_fixtures"] is False  # pytest's plugin loads, empty, without [physics]


@pytest.mark.parametrize(
    "part, extra",
    [("plc.st", "st"), ("scenes", "physics"), ("viewer", "viewer"), ("mcl.st", "st")],
)
def test_a_part_without_its_extra_says_in_one_line_which_to_install(
    core_python: Path, tmp_path: Path, part: str, extra: str
):
    result = run_core(core_python, f"import {part}", tmp_path)
    hint = f"{'plc.st' if part == 'mcl.st' else part} needs the [{extra}] extra: "
    hint += f"pip install 'mcl-testbench[{extra}]'"
    assert result.returncode == 1
    assert result.stderr.splitlines()[-1] == f"mcl.extras.MissingExtra: {hint}"
    assert result.stderr.count(hint) == 1
    assert "During handling" not in result.stderr and "ModuleNotFoundError" not in result.stderr

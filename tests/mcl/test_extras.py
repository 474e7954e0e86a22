"""The extras: mcl.extras mirrors pyproject.toml's table, a part imported without its extra says
in one line which extra to install, and an environment with the core alone runs the library."""

from __future__ import annotations

import importlib.metadata
import json
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from mcl import extras
from tests.helpers import CONSTANTS, ROOT

PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
SELF = re.compile(rf"{extras.DISTRIBUTION}\[(?P<extras>[a-z,]+)\]")


def table() -> dict[str, tuple[set[str], set[str]]]:
    """pyproject.toml's extras but ``all`` and ``test``: extra → (its packages, the extras it
    builds on)."""
    out = {}
    for extra, requirements in PROJECT["optional-dependencies"].items():
        if extra in ("all", "test"):
            continue
        packages, included = set(), set()
        for requirement in requirements:
            if match := SELF.fullmatch(requirement):
                included |= set(match["extras"].split(","))
            else:
                packages.add(requirement.partition("==")[0])
        out[extra] = (packages, included)
    return out


def test_the_table_of_extras_is_pyprojects():
    assert {e: (set(extras.PACKAGES[e]), set(extras.INCLUDES[e])) for e in extras.PACKAGES} == (
        table()
    )
    everything = SELF.fullmatch(PROJECT["optional-dependencies"]["all"][0])
    assert everything is not None and set(everything["extras"].split(",")) == set(extras.PACKAGES)


def test_an_extra_brings_the_packages_of_the_extras_it_builds_on_each_once():
    assert extras.packages("st") == ["blark", "lark"]
    assert extras.packages("viewer") == [
        *("viser", "mujoco", "dm_control", "blark", "lark", "pymodbus", "asyncua"),
    ]
    assert extras.packages("sweep") == [
        *("pyarrow", "dask", "distributed", "matplotlib", "pandas", "mujoco", "dm_control"),
        *("blark", "lark"),
    ]


def test_every_extra_is_installed_here():
    assert [e for e in extras.PACKAGES if not extras.installed(e)] == []
    extras.require("viewer", "viewer")  # no error


def test_a_missing_package_names_the_extra_to_install(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setitem(extras.PACKAGES, "gauges", ("json", "no_such_gauge_driver"))
    monkeypatch.setitem(extras.INCLUDES, "gauges", ("st",))
    assert extras.missing("gauges") == ["no_such_gauge_driver"]
    assert not extras.installed("gauges")
    with pytest.raises(ImportError) as raised:
        extras.require("scenes.gauges", "gauges")
    assert str(raised.value) == (
        "scenes.gauges needs the [gauges] extra: pip install 'mcl-testbench[gauges]'"
    )
    assert raised.value.name == "no_such_gauge_driver"
    assert raised.value.__cause__ is None and raised.value.__suppress_context__


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
import mcl, pytest_mcl_testbench
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


@pytest.mark.once  # a new interpreter, pure Python (see the marker in pyproject.toml)
def test_with_the_core_alone_the_library_moves_a_simulated_axis(core_python: Path, tmp_path):
    all_packages = sorted({p for e in extras.PACKAGES for p in extras.packages(e)})
    code = CORE_RUN.format(
        constants=dict(CONSTANTS), extras=list(extras.PACKAGES), packages=all_packages
    )
    result = run_core(core_python, code, tmp_path)
    assert result.returncode == 0, result.stderr[-3000:]
    out = json.loads(result.stdout.strip().splitlines()[-1])
    assert out["found"] == [] and out["installed"] == []  # none of the extras is there
    assert out["error"] == 0
    assert out["moved"] == pytest.approx(100.0, abs=0.05)
    assert out["carriage_mm"] == pytest.approx(100.0, abs=0.05)  # the simulated carriage moved
    assert out["plugin_fixtures"] is False  # pytest's plugin loads, empty, without [physics]


@pytest.mark.once
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

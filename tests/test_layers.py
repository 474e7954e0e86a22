"""The import contracts of ``make lint`` (``lint-imports``, ``[tool.importlinter]`` in
pyproject.toml): the layers viewer → scenes → plc → mcl, and no package of an extra in mcl or
(but ST's) in plc. Tried on a copy of the packages, as they are and with wrong imports added."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import ROOT

pytestmark = pytest.mark.once  # a command line in a subprocess (see the marker in pyproject.toml)

LINT_IMPORTS = Path(sys.executable).parent / "lint-imports"


def lint_imports(folder: Path) -> subprocess.CompletedProcess[str]:
    """``lint-imports`` run on the packages in ``folder`` with their pyproject.toml."""
    return subprocess.run(
        [LINT_IMPORTS, "--no-cache"], cwd=folder, capture_output=True, text=True, check=False
    )


def add_import(module: Path, statement: str) -> None:
    module.write_text(module.read_text(encoding="utf-8") + f"\n{statement}\n", encoding="utf-8")


def test_lint_imports_fails_on_an_upward_import_and_on_an_extra_in_a_lower_layer(tmp_path):
    for package in ("mcl", "plc", "scenes", "viewer"):
        shutil.copytree(
            ROOT / package, tmp_path / package, ignore=shutil.ignore_patterns("__pycache__", "*.so")
        )
    shutil.copy2(ROOT / "pyproject.toml", tmp_path)
    kept = lint_imports(tmp_path)
    assert kept.returncode == 0, kept.stdout[-3000:] + kept.stderr[-3000:]
    assert "Contracts: 3 kept, 0 broken." in kept.stdout

    add_import(tmp_path / "mcl" / "trace.py", "import plc.sequence")  # a layer up
    add_import(tmp_path / "plc" / "commissioning" / "reversing.py", "import viser")  # an extra
    broken = lint_imports(tmp_path)
    assert broken.returncode == 1
    assert "Contracts: 1 kept, 2 broken." in broken.stdout
    assert "mcl is not allowed to import plc:\n\n- mcl.trace -> plc.sequence" in broken.stdout
    assert "plc is not allowed to import viser:\n\n-   plc.commissioning.reversing -> viser" in (
        broken.stdout
    )

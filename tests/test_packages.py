"""How the four packages fit together: the import contracts of ``make lint`` (``lint-imports``,
``[tool.importlinter]`` in pyproject.toml: the layers viewer → scenes → plc → mcl, no package of
an extra in mcl or (but ST's) in plc, mcl's internals kept inside it), tried on a copy of the
packages as they are and with wrong imports added; every module's public names (``__all__``);
every package in the layout table (docs/layout.md)."""

from __future__ import annotations

import ast
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import ROOT

pytestmark = pytest.mark.once  # the same in both modes (see the marker in pyproject.toml)

PACKAGES = ("mcl", "plc", "scenes", "viewer")
MODULES = sorted(p for package in PACKAGES for p in (ROOT / package).rglob("*.py"))

LINT_IMPORTS = Path(sys.executable).parent / "lint-imports"


def lint_imports(folder: Path) -> subprocess.CompletedProcess[str]:
    """``lint-imports`` run on the packages in ``folder`` with their pyproject.toml."""
    return subprocess.run(
        [LINT_IMPORTS, "--no-cache"], cwd=folder, capture_output=True, text=True, check=False
    )


def add_import(module: Path, statement: str) -> None:
    module.write_text(module.read_text(encoding="utf-8") + f"\n{statement}\n", encoding="utf-8")


def test_lint_imports_fails_on_an_upward_import_an_extra_low_down_and_an_internal(tmp_path):
    for package in PACKAGES:
        shutil.copytree(
            ROOT / package, tmp_path / package, ignore=shutil.ignore_patterns("__pycache__", "*.so")
        )
    shutil.copy2(ROOT / "pyproject.toml", tmp_path)
    kept = lint_imports(tmp_path)
    assert kept.returncode == 0, kept.stdout[-3000:] + kept.stderr[-3000:]
    assert "Contracts: 4 kept, 0 broken." in kept.stdout

    add_import(tmp_path / "mcl" / "trace.py", "import plc.sequence")  # a layer up
    add_import(tmp_path / "plc" / "commissioning" / "reversing.py", "import viser")  # an extra
    add_import(tmp_path / "viewer" / "sim" / "peaks.py", "import mcl.fb")  # an internal
    broken = lint_imports(tmp_path)
    assert broken.returncode == 1
    assert "Contracts: 1 kept, 3 broken." in broken.stdout
    assert "mcl is not allowed to import plc:\n\n- mcl.trace -> plc.sequence" in broken.stdout
    assert "plc is not allowed to import viser:\n\n-   plc.commissioning.reversing -> viser" in (
        broken.stdout
    )
    assert "viewer is not allowed to import mcl.fb:\n\n-   viewer.sim.peaks -> mcl.fb" in (
        broken.stdout
    )


def declares_all(module: Path) -> bool:
    """Whether the module assigns ``__all__`` (or takes it from the package it stands for)."""
    for node in ast.parse(module.read_text(encoding="utf-8")).body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        if any(isinstance(t, ast.Name) and t.id == "__all__" for t in targets):
            return True
        if isinstance(node, ast.ImportFrom) and any(a.name == "__all__" for a in node.names):
            return True
    return False


def test_every_module_declares_its_public_names():
    assert len(MODULES) > 150
    assert [str(m.relative_to(ROOT)) for m in MODULES if not declares_all(m)] == []


def test_the_layout_table_names_every_package():
    """Every package and sub-package (a machine's own package: under ``scenes/machines/``) in
    the table of docs/layout.md."""
    table = (ROOT / "docs" / "layout.md").read_text(encoding="utf-8")
    named = set(re.findall(r"`([a-z_0-9/]+/)`", table))
    packages = {
        f"{init.parent.relative_to(ROOT).as_posix()}/"
        for init in MODULES
        if init.name == "__init__.py" and init.parent.parent.name != "machines"
    }
    assert len(packages) > 20
    assert sorted(packages - named) == []

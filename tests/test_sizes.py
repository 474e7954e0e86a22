"""Sizes a reader can take in at once: no module of the four layers over 800 lines, no function
or method over 80 (its physical lines from ``def`` to its last line, docstring included)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("mcl", "plc", "scenes", "viewer")
MODULE_LINES = 800
FUNCTION_LINES = 80


def sources(root: Path = ROOT) -> list[Path]:
    """Every Python module of the four layers under ``root``."""
    return sorted(p for package in PACKAGES for p in (root / package).rglob("*.py"))


def long_modules(root: Path = ROOT) -> list[str]:
    """``path: lines`` of every module over :data:`MODULE_LINES` physical lines."""
    found = []
    for path in sources(root):
        lines = len(path.read_text(encoding="utf-8").splitlines())
        if lines > MODULE_LINES:
            found.append(f"{path.relative_to(root)}: {lines} lines")
    return found


def long_functions(root: Path = ROOT) -> list[str]:
    """``path:line name: lines`` of every function or method over :data:`FUNCTION_LINES`
    physical lines (``def`` to its last line: docstring, body and nested functions)."""
    found = []
    for path in sources(root):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                assert node.end_lineno is not None
                lines = node.end_lineno - node.lineno + 1
                if lines > FUNCTION_LINES:
                    where = f"{path.relative_to(root)}:{node.lineno}"
                    found.append(f"{where} {node.name}: {lines} lines")
    return found


def test_no_module_is_over_800_lines() -> None:
    assert len(sources()) > 100, "the four packages are where the tree is"
    found = long_modules()
    assert not found, "split by concept:\n" + "\n".join(found)


def test_no_function_is_over_80_lines() -> None:
    found = long_functions()
    assert not found, "split by concept:\n" + "\n".join(found)


def test_the_limits_name_what_exceeds_them(tmp_path: Path) -> None:
    """A module of 801 lines and a method of 81 lines (docstring included) are named with their
    size; 800 and 80 lines pass."""
    package = tmp_path / "mcl"
    package.mkdir()
    (package / "long.py").write_text("x = 0\n" * 801)
    (package / "fits.py").write_text("x = 0\n" * 800)
    body = "\n".join(f"        x = {i}" for i in range(78))
    method = f'class A:\n    def f(self) -> None:\n        """Doc."""\n{body}\n'
    (package / "method.py").write_text(method)  # def, docstring, 78 lines: 80
    (package / "longer.py").write_text(method + "        x = 78\n")
    assert long_modules(tmp_path) == ["mcl/long.py: 801 lines"]
    assert long_functions(tmp_path) == ["mcl/longer.py:2 f: 81 lines"]

"""The optional compiled build: chosen only while fresh, and bit for bit the same behaviour."""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from mcl import native

SCENARIO = """
import json, sys
import mcl, scenes
scene = scenes.load("gantry", start={"X": 0.43, "Y": 0.27, "Z": -0.12})
program = scenes.demo(scene)
scene.run(program, timeout=3.0)
rows = [[list(map(float, r)) for r in scene.trace.rows[a]] for a in scene.axes]
qpos = [float(q) for q in scene.data.qpos]
print(json.dumps({"compiled": mcl.COMPILED, "rows": rows, "qpos": qpos}))
"""


def run_scenario(pure: bool) -> dict[str, object]:
    env = {**os.environ, "MCL_PURE_PYTHON": "1" if pure else ""}
    out = subprocess.run(
        [sys.executable, "-c", SCENARIO], env=env, check=True, capture_output=True, text=True
    ).stdout
    result: dict[str, object] = json.loads(out)
    return result


@pytest.mark.skipif(native.stale_sources() != [], reason="no fresh compiled build (make setup)")
def test_compiled_and_pure_python_runs_are_identical_bit_for_bit():
    compiled, pure = run_scenario(pure=False), run_scenario(pure=True)
    assert compiled["compiled"] is True and pure["compiled"] is False
    assert compiled["rows"] == pure["rows"]  # every traced value of 3 s of the demo, exactly
    assert compiled["qpos"] == pure["qpos"]


COMPILED_SOURCES = native.compiled_sources
"""The real :func:`native.compiled_sources` (the fixture below replaces it)."""


@pytest.fixture
def checkout(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A folder of packages with one compiled source, its compiled module and the record."""
    (tmp_path / "mcl").mkdir()
    (tmp_path / "scenes").mkdir()
    source = tmp_path / "mcl" / "axis.py"
    source.write_text("x = 1\n")
    native.extension_of(source).write_bytes(b"")
    manifest = tmp_path / "mcl" / "compiled.json"
    digest = hashlib.sha256(source.read_bytes()).hexdigest()
    manifest.write_text(
        json.dumps({"python": sys.implementation.cache_tag, "sources": {"mcl/axis.py": digest}})
    )
    monkeypatch.setattr(native, "ROOT", tmp_path)
    monkeypatch.setattr(native, "MANIFEST", manifest)
    monkeypatch.setattr(native, "compiled_sources", lambda packages=None: [source])
    monkeypatch.setattr(native, "compiled_files", lambda: [native.extension_of(source)])
    monkeypatch.delenv("MCL_PURE_PYTHON", raising=False)
    native.reset()
    yield tmp_path
    native.reset()
    sys.path_importer_cache.pop(str(tmp_path / "mcl"), None)


def sources_only(folder: Path) -> bool:
    """The package folder imports its sources only (no extension modules)."""
    finder = sys.path_importer_cache.get(str(folder))
    loaders = getattr(finder, "_loaders", [])
    return bool(loaders) and all(suffix.endswith((".py", ".pyc")) for suffix, _ in loaders)


def test_a_fresh_build_is_imported_by_python_itself(checkout: Path):
    path = [str(checkout / "mcl")]
    assert native.activate("mcl", path)
    assert path == [str(checkout / "mcl")]  # nothing put on any path
    assert not sources_only(checkout / "mcl")
    assert native.mode().startswith("compiled")


def test_an_edited_source_is_never_shadowed_by_its_stale_build(checkout: Path):
    (checkout / "mcl" / "axis.py").write_text("x = 2\n")
    path = [str(checkout / "mcl")]
    with pytest.warns(RuntimeWarning, match=r"out of date \(mcl/axis\.py changed\)"):
        assert not native.activate("mcl", path)
    assert sources_only(checkout / "mcl")
    assert "out of date" in native.mode()


def test_a_stale_build_imports_the_edited_source(checkout: Path):
    """The finder really loads the source, although a compiled module stands beside it."""
    (checkout / "mcl" / "axis.py").write_text("x = 2\n")
    with pytest.warns(RuntimeWarning):
        native.activate("mcl", [str(checkout / "mcl")])
    finder = sys.path_importer_cache[str(checkout / "mcl")]
    assert finder is not None
    spec = finder.find_spec("mcl.axis")
    assert spec is not None and spec.origin == str(checkout / "mcl" / "axis.py")


def test_an_incomplete_build_is_not_used(checkout: Path):
    native.extension_of(checkout / "mcl" / "axis.py").unlink()
    with pytest.warns(RuntimeWarning, match=r"mcl/axis\.cpython.* missing"):
        assert not native.activate("mcl", [str(checkout / "mcl")])
    assert "missing" in native.mode()


def test_pure_python_can_be_forced(checkout: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setenv("MCL_PURE_PYTHON", "1")
    path = [str(checkout / "mcl")]
    assert not native.activate("mcl", path)
    assert sources_only(checkout / "mcl")
    assert "MCL_PURE_PYTHON" in native.mode()


def test_no_build_means_pure_python(checkout: Path):
    (checkout / "mcl" / "compiled.json").unlink()
    assert not native.activate("mcl", [str(checkout / "mcl")])
    assert sources_only(checkout / "mcl")
    assert "no compiled build" in native.mode()


def test_without_a_build_record_a_subpackage_never_loads_a_left_over_build(
    checkout: Path, monkeypatch: pytest.MonkeyPatch
):
    """While a build runs (no record yet) the compiled modules of an earlier build still stand
    beside scenes/plant's sources; they need the shared library pure Python hides, so the
    subpackage's folder must import its sources only, as the package's does."""
    (checkout / "mcl" / "compiled.json").unlink()
    plant = checkout / "scenes" / "plant"
    plant.mkdir()
    (checkout / "scenes" / "__init__.py").write_text("")
    (plant / "__init__.py").write_text('COMPILED_MODULES = ("mujoco",)\n')
    (plant / "mujoco.py").write_text("x = 1\n")
    native.extension_of(plant / "mujoco.py").write_bytes(b"")
    monkeypatch.setattr(native, "compiled_sources", COMPILED_SOURCES)
    try:
        assert not native.activate("scenes", [str(checkout / "scenes")])
        assert sources_only(plant) and sources_only(checkout / "scenes")
    finally:
        for folder in (plant, checkout / "scenes"):
            sys.path_importer_cache.pop(str(folder), None)

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


@pytest.fixture
def checkout(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A checkout with one compiled source and a build of it."""
    (tmp_path / "mcl").mkdir()
    (tmp_path / "scenes").mkdir()
    source = tmp_path / "mcl" / "axis.py"
    source.write_text("x = 1\n")
    build = tmp_path / ".build" / "compiled"
    build.mkdir(parents=True)
    manifest = build / "manifest.json"
    digest = hashlib.sha256(source.read_bytes()).hexdigest()
    manifest.write_text(
        json.dumps({"python": sys.implementation.cache_tag, "sources": {"mcl/axis.py": digest}})
    )
    monkeypatch.setattr(native, "ROOT", tmp_path)
    monkeypatch.setattr(native, "BUILD", build)
    monkeypatch.setattr(native, "MANIFEST", manifest)
    monkeypatch.setattr(native, "compiled_sources", lambda: [source])
    monkeypatch.delenv("MCL_PURE_PYTHON", raising=False)
    native.reset()
    yield tmp_path
    native.reset()


def test_a_fresh_build_is_put_in_front_of_the_sources(checkout: Path):
    path = [str(checkout / "mcl")]
    assert native.activate("mcl", path)
    assert path[0] == str(checkout / ".build" / "compiled" / "mcl")
    assert native.mode().startswith("compiled")


def test_an_edited_source_is_never_shadowed_by_its_stale_build(checkout: Path):
    (checkout / "mcl" / "axis.py").write_text("x = 2\n")
    path = [str(checkout / "mcl")]
    with pytest.warns(RuntimeWarning, match=r"older than mcl/axis\.py"):
        assert not native.activate("mcl", path)
    assert path == [str(checkout / "mcl")]
    assert "stale" in native.mode()


def test_pure_python_can_be_forced(checkout: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setenv("MCL_PURE_PYTHON", "1")
    path = [str(checkout / "mcl")]
    assert not native.activate("mcl", path)
    assert path == [str(checkout / "mcl")]
    assert "MCL_PURE_PYTHON" in native.mode()


def test_no_build_means_pure_python(checkout: Path):
    (checkout / ".build" / "compiled" / "manifest.json").unlink()
    assert not native.activate("mcl", [str(checkout / "mcl")])
    assert "no compiled build" in native.mode()

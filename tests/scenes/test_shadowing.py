"""A file named like one of the testbench's packages in the folder ``python -m scenes`` starts
from: one message naming the file and saying to rename it, no traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import ROOT


@pytest.mark.parametrize("name", ["plc", "mcl"])
def test_a_file_hiding_a_package_is_named_with_what_to_do(name: str, tmp_path: Path) -> None:
    (tmp_path / f"{name}.py").write_text("print('my own script')\n")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    command = [sys.executable, "-m", "scenes", "list"]
    result = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stderr.splitlines() == [
        f"error: {tmp_path / f'{name}.py'} hides the testbench's package {name!r} (Python "
        f"imports the file instead): rename the file, e.g. to my_{name}.py, or start from "
        "another folder"
    ]
    (tmp_path / f"{name}.py").rename(tmp_path / f"my_{name}.py")
    result = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True)
    assert result.returncode == 0 and "gantry" in result.stdout

"""``make mutate`` (tests/mutate.py) on a tiny project of its own: which modules and lines a change
touched, which test files exercise a module, and a real mutmut run over the changed lines."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

from tests import mutate

pytestmark = pytest.mark.once  # the tool under test, not the library, runs here

CALC = '''\
def clamp(x, low, high):
    """x limited to [low, high]."""
    if x < low:
        return low
    if x > high:
        return high
    return x


def double(x):
    return 2 * x
'''

TEST_CALC = """\
from pkg.calc import clamp, double


def test_clamp():
    assert clamp(5, 0, 10) == 5
    assert clamp(-1, 0, 10) == 0
    assert clamp(11, 0, 10) == 10


def test_double():
    assert double(3) == 6
"""


def write(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)


def git(root: Path, *args: str) -> str:
    command = ["git", "-c", "user.name=t", "-c", "user.email=t@t", *args]
    return subprocess.run(command, cwd=root, check=True, capture_output=True, text=True).stdout


@pytest.fixture
def project(tmp_path: Path) -> Path:
    """A committed project: package ``pkg`` (``calc`` and two more), its tests, a pyproject."""
    write(
        tmp_path,
        {
            "pkg/__init__.py": "",
            "pkg/calc.py": CALC,
            "pkg/gone.py": "X = 1\n",
            "pkg/shrunk.py": "A = 1\nB = 2\n",
            "tests/__init__.py": "",
            "tests/test_calc.py": TEST_CALC,
            "pyproject.toml": '[tool.pytest.ini_options]\nmarkers = ["browser: a page"]\n',
        },
    )
    git(tmp_path, "init", "-q")
    git(tmp_path, "add", ".")
    git(tmp_path, "commit", "-q", "-m", "base")
    return tmp_path


def test_a_change_names_its_modules_with_the_lines_it_changed_or_added(project):
    calc = project / "pkg/calc.py"
    calc.write_text(CALC.replace("return low\n", "return low  # the floor\n") + "\n\nY = 2\n")
    (project / "pkg/gone.py").unlink()
    write(project, {"pkg/shrunk.py": "A = 1\n", "pkg/new.py": "a = 1\nb = 2\n", "notes.txt": "x\n"})
    write(project, {"tests/test_new.py": "import pkg\n", "tests/test_helper.py": "import os\n"})

    changes = mutate.changed_lines(project, "HEAD")
    lines, touched = mutate.changed_modules(project, "HEAD", None, ["pkg"])

    assert changes["pkg/calc.py"] == {4, 12, 13, 14}
    assert changes["pkg/new.py"] == {1, 2}
    assert changes["pkg/shrunk.py"] == set()  # a line deleted: nothing to mutate
    assert "pkg/gone.py" not in changes
    assert lines == {"pkg/calc.py": {4, 12, 13, 14}, "pkg/new.py": {1, 2}}
    assert touched == ["tests/test_helper.py", "tests/test_new.py"]


def test_modules_named_with_a_base_are_mutated_on_their_changed_lines_only(project):
    calc = project / "pkg/calc.py"
    calc.write_text(CALC.replace("return low\n", "return low  # the floor\n"))
    write(project, {"pkg/new.py": "a = 1\n"})

    lines, _ = mutate.changed_modules(project, "HEAD", ["pkg/calc.py", "pkg/shrunk.py"], ["pkg"])
    whole, _ = mutate.changed_modules(project, None, ["pkg/calc.py"], ["pkg"])

    assert lines == {"pkg/calc.py": {4}, "pkg/shrunk.py": set()}  # shrunk.py: unchanged
    assert whole == {"pkg/calc.py": None}


def test_a_module_s_tests_import_it_or_name_what_it_defines_or_its_docstring_mentions(tmp_path):
    write(
        tmp_path,
        {
            "pkg/latch.py": '"""The latch MC_Probe arms (an app.Tool)."""\n'
            "class Latch: ...\nclass Common: ...\nclass Demo: ...\n",
            "pkg/blocks.py": "class MC_Probe: ...\nclass MC_Other: ...\nclass Demo: ...\n",
            "app/tools.py": "class Tool: ...\n",
            "tests/test_imports.py": "import pkg.latch\n",
            "tests/test_from.py": "from pkg import latch\n",
            "tests/test_name.py": "import pkg\npkg.Latch()\npkg.Common()\n",
            "tests/test_block.py": "from pkg import MC_Probe, Common\n",
            "tests/test_other.py": "import pkg\npkg.MC_Other()\npkg.Common()\n",
            "tests/test_local.py": "import pkg\nLatch = 1\npkg.Common()\n",
            "tests/test_demo.py": "from pkg import blocks\nblocks.Demo()\n",
            "tests/test_tool.py": "from app.tools import Tool\n",
            "tests/test_touched.py": "from pkg import blocks\n",
            "tests/test_touched_tool.py": "import pytest\n",
            "tests/benchmarks/test_speed.py": "import pkg.latch\n",
        },
    )
    candidates = mutate.find_test_files(tmp_path, ["tests"])
    touched = ["tests/test_touched.py", "tests/test_touched_tool.py"]

    selected = mutate.select_tests(tmp_path, ["pkg/latch.py"], candidates, ["pkg", "app"], touched)

    assert "tests/benchmarks/test_speed.py" not in candidates
    # Common: used by more than a quarter of the test files; Demo: defined twice; Tool: a class
    # of another package; a local name Latch: not the package's. Of the change's test files,
    # those that import from the packages
    assert selected == {
        "pkg/latch.py": [
            "tests/test_block.py",
            "tests/test_from.py",
            "tests/test_imports.py",
            "tests/test_name.py",
            "tests/test_touched.py",
        ]
    }


def test_make_mutate_reports_the_kill_rate_and_each_survivor_of_the_changed_lines(project, capsys):
    changed = CALC.replace("if x < low:", "if x < low:  # below").replace(
        "return 2 * x", "return 2 * x  # twice"
    )
    (project / "pkg/calc.py").write_text(changed)

    assert mutate.main(["--base", "HEAD", "--packages", "pkg"], root=project) == 0

    out = capsys.readouterr().out
    assert "pkg/calc.py: tests tests/test_calc.py" in out
    # mutmut's mutants of the changed lines 3 and 11 (not those of the unchanged line 5):
    # x < low → x <= low escapes (no test clamps x == low); 2 * x → 2 / x and → 3 * x are killed
    total = next(line.split() for line in out.splitlines() if line.startswith("total"))
    assert total[1:] == ["2", "1", "0", "0", "0", "66.7", "%"]
    listed = [line for line in out.splitlines() if re.match(r"  pkg/calc.py:\d", line)]
    assert len(listed) == 1
    assert listed[0].startswith("  pkg/calc.py:3: if x < low:  # below  →  if x <= low:  # below")
    assert "[survived: pkg.calc.x_clamp__mutmut_" in listed[0]
    assert (project / ".build/mutate/mutants/pkg/calc.py").is_file()
    assert (project / "pkg/calc.py").read_text() == changed  # never mutated in place


def test_functions_named_keep_only_their_mutants(project):
    scratch = project / mutate.SCRATCH
    mutate.prepare(project, scratch, ["pkg"], ["pkg/calc.py"], ["tests/test_calc.py"])
    everything = mutate.in_directory(scratch, lambda: mutate.mutations("pkg/calc.py", None))
    doubled = mutate.in_directory(
        scratch, lambda: mutate.mutations("pkg/calc.py", None, ["double"])
    )

    assert {m.line for m in everything} == {3, 5, 11}  # clamp's two comparisons, double
    assert doubled and {m.line for m in doubled} == {11}
    assert doubled == [m for m in everything if m.line == 11]
    assert mutate.in_functions("xǁCutterǁ_boundary", ["_boundary"])
    assert mutate.in_functions("xǁCutterǁ_boundary", ["Cutter._boundary"])
    assert not mutate.in_functions("xǁCutterǁ_boundary", ["Other._boundary", "boundary"])
    assert not mutate.in_functions("x_double", ["clamp"])


TEST_WIDE = """\
import time

import pytest

from pkg.calc import double


@pytest.fixture(scope="module")
def doubled():
    time.sleep(0.3)
    return double(3)


def test_the_fixture_gives_a_number(doubled):
    assert isinstance(doubled, int)


def test_three_doubled_is_six(doubled):
    assert doubled == 6
"""


def test_a_module_fixture_s_calls_go_to_every_test_that_uses_it(project, capsys):
    """The fixture calls ``double`` in the setup of the first test, which cannot tell a wrong
    double; the second test, which can, runs against its mutants too, and both are timed with
    the fixture's 0.3 s (mutmut times only a test's call)."""
    write(project, {"tests/test_calc.py": TEST_WIDE})

    args = ["--modules", "pkg/calc.py", "--functions", "double", "--packages", "pkg"]
    assert mutate.main(args, root=project) == 0

    out = capsys.readouterr().out
    total = next(line.split() for line in out.splitlines() if line.startswith("total"))
    assert total[1:] == ["2", "0", "0", "0", "0", "100.0", "%"]  # 2 / x and 3 * x
    stats = json.loads((project / mutate.SCRATCH / "mutants/mutmut-stats.json").read_text())
    tests = {
        f"tests/test_calc.py::test_{name}"
        for name in ("the_fixture_gives_a_number", "three_doubled_is_six")
    }
    assert set(stats["tests_by_mangled_function_name"]["pkg.calc.x_double"]) == tests
    assert all(stats["duration_by_test"][test] >= 0.3 for test in tests)

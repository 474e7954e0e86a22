"""``make mutate``: mutation testing (mutmut) of the Python modules a change touched.

It finds the modules of ``mcl``, ``scenes`` and ``viewer`` the change touched and their changed
lines (``git diff`` of the working tree against the merge base with ``main``, or against
``--base``), the test files that exercise each module (:func:`select_tests`) and lets mutmut
mutate the changed lines (``--modules`` names the modules: whole, or with ``--base`` only their
changed lines; ``--functions`` keeps the mutants of the named functions); mutmut runs the chosen
tests once to record which tests call which function, then each mutant against those that call
its function. A fixture wider than a test (``scope="module"``) runs only in the setup of the first
test that uses it, so mutmut alone would credit what it calls to that test only: the plugin
tests/mutate_fixtures.py credits it to every test that uses the fixture, and counts the fixture's
time in theirs (mutmut's timeout for a mutant, which counts as a kill, is a multiple of its tests'
times). Browser tests are left out.
The report gives, per module and in total, the killed / survived / no-test / timeout counts,
the kill rate and every mutant not caught, as ``file:line: before → after``.

    python -m tests.mutate [--base REV] [--modules FILE ...] [--functions NAME ...]
                           [--tests FILE ...] [--jobs N]

mutmut works in ``.build/mutate`` (a fresh copy each run): ``cd .build/mutate && mutmut show
NAME`` shows a mutant's diff; the sources are never mutated in place.
"""

from __future__ import annotations

import argparse
import ast
import difflib
import json
import os
import re
import shutil
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

PACKAGES = ("mcl", "plc", "scenes", "viewer")
"""The packages whose modules are mutated."""

TEST_DIRS = ("tests", "examples")
"""Where the test files (``test_*.py``) are; ``tests/benchmarks`` holds none."""

SCRATCH = Path(".build") / "mutate"
"""mutmut's working directory, below the project root."""

KILLED = ("killed", "timeout")
"""mutmut's verdicts that count as caught: the tests failed, or did not finish in time."""

ESCAPED = ("survived", "no tests")
"""Verdicts that count as escaped: the tests passed, or none of them runs the mutated code."""

PLUGIN = "mutate_fixtures.py"
"""The pytest plugin (beside this file) that credits a wide fixture's calls to all its tests;
copied to the top of mutmut's copy of the project, where pytest finds it."""

T = TypeVar("T")

HUNK = re.compile(r"^@@ -\d+(?:,\d+)? \+(\d+)(?:,(\d+))? @@", re.MULTILINE)


@dataclass(frozen=True)
class Mutation:
    """One mutant: mutmut's ``name``, the ``line`` of ``path`` it changes, and that code
    ``before`` and ``after`` the mutation."""

    name: str
    path: str
    line: int
    before: str
    after: str


def git(root: Path, *args: str) -> str:
    """Output of ``git args`` in ``root``."""
    return subprocess.run(
        ["git", *args], cwd=root, check=True, capture_output=True, text=True
    ).stdout


def changed_lines(root: Path, base: str) -> dict[str, set[int]]:
    """The Python files that differ between ``base`` and the working tree, each with its new or
    changed lines (all lines of a file git does not track yet); deleted files are left out."""
    changes: dict[str, set[int]] = {}
    diff = git(root, "diff", "-U0", "--no-color", "--no-ext-diff", base, "--", "*.py")
    for section in re.split(r"^diff --git ", diff, flags=re.MULTILINE)[1:]:
        target = re.search(r"^\+\+\+ b/(.+)$", section, re.MULTILINE)
        if target is None:  # deleted
            continue
        lines = changes.setdefault(target.group(1), set())
        for start, count in HUNK.findall(section):
            first = int(start)
            lines.update(range(first, first + (int(count) if count else 1)))
    for path in git(root, "ls-files", "--others", "--exclude-standard", "--", "*.py").split():
        changes[path] = set(range(1, len((root / path).read_text().splitlines()) + 1))
    return changes


def module_paths(paths: Iterable[str], packages: Sequence[str]) -> list[str]:
    """The paths of ``paths`` that are Python modules of ``packages``, sorted."""
    return sorted(p for p in paths if p.endswith(".py") and p.split("/", 1)[0] in packages)


def dotted(path: str) -> str:
    """The module name of a source path: ``mcl/axis.py`` → ``mcl.axis``."""
    name = path.removesuffix(".py").replace("/", ".")
    return name.removesuffix(".__init__")


def defined_names(source: str, classes_only: bool = False) -> set[str]:
    """The public names a module defines at its top level: classes, functions and assigned
    names, or only its classes."""
    kinds = (
        (ast.ClassDef,) if classes_only else (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
    )
    names: set[str] = set()
    for node in ast.parse(source).body:
        if isinstance(node, kinds):
            names.add(node.name)
        elif not classes_only and isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    return {name for name in names if not name.startswith("_")}


@dataclass(frozen=True)
class References:
    """What a test file refers to: the modules it imports and the names it reaches through the
    packages (``mcl.GT_SWLim``, ``from mcl import GT_SWLim``)."""

    modules: frozenset[str]
    names: frozenset[str]

    def uses(self, packages: Sequence[str]) -> bool:
        """Whether the file imports from one of ``packages``."""
        return any(module.split(".", 1)[0] in packages for module in self.modules)


def references(test_source: str, packages: Sequence[str]) -> References:
    """The modules a test file imports (``from a import b`` counts as ``a`` and ``a.b``) and the
    names it takes from ``packages`` or reaches as an attribute."""
    modules: set[str] = set()
    names: set[str] = set()
    for node in ast.walk(ast.parse(test_source)):
        if isinstance(node, ast.Import):
            modules.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            modules.add(node.module)
            modules.update(f"{node.module}.{alias.name}" for alias in node.names)
            if node.module.split(".", 1)[0] in packages:
                names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.Attribute):
            names.add(node.attr)
    return References(frozenset(modules), frozenset(names))


def find_test_files(root: Path, test_dirs: Sequence[str]) -> list[str]:
    """All test files below ``test_dirs`` (relative to ``root``), benchmarks excluded."""
    found = (p for d in test_dirs for p in (root / d).rglob("test_*.py"))
    return sorted(str(p.relative_to(root)) for p in found if "benchmarks" not in p.parts)


def select_tests(
    root: Path,
    modules: Iterable[str],
    candidates: Sequence[str],
    packages: Sequence[str],
    touched: Iterable[str] = (),
) -> dict[str, list[str]]:
    """The test files among ``candidates`` that exercise each module: they import it, or name
    one of its subject names: the names it defines and the classes of its own package its
    docstring mentions (like the blocks it serves). Names defined in more than one module
    (``Demo``) and names more than a quarter of the test files use (``Axis``) tell nothing
    about which tests are the module's and are left out. The ``touched`` test files (those of
    the change) that import from ``packages`` go with every module."""
    refs = {t: references((root / t).read_text(), packages) for t in candidates}
    use = Counter(name for r in refs.values() for name in r.names)
    definitions: Counter[str] = Counter()
    classes: dict[str, set[str]] = {pkg: set() for pkg in packages}
    for pkg in packages:
        for file in (root / pkg).rglob("*.py"):
            text = file.read_text()
            definitions.update(defined_names(text))
            classes[pkg] |= defined_names(text, classes_only=True)
    selected = {}
    for path in modules:
        source = (root / path).read_text()
        docstring = ast.get_docstring(ast.parse(source)) or ""
        mentioned = set(re.findall(r"[A-Za-z_]\w*", docstring)) & classes[path.split("/")[0]]
        subject = {
            name
            for name in defined_names(source) | mentioned
            if definitions[name] == 1 and use[name] <= len(candidates) / 4
        }
        module = dotted(path)
        selected[path] = [
            t
            for t, r in refs.items()
            if module in r.modules or r.names & subject or (t in touched and r.uses(packages))
        ]
    return selected


def mutations(
    path: str, lines: set[int] | None, functions: Sequence[str] | None = None
) -> list[Mutation]:
    """mutmut's mutants of the module at ``path`` (relative to the current directory, which
    holds the mutmut configuration), only those on ``lines`` unless None, and only those inside
    ``functions`` unless None (:func:`in_functions`)."""
    from mutmut.mutation.file_mutation import mutate_file_contents
    from mutmut.utils.format_utils import get_mutant_name

    source = Path(path).read_text()
    mutated = mutate_file_contents(path, source)
    code = mutated.code.splitlines()
    spans = mutated.line_span_by_function_name
    def_lines = function_def_lines(source)
    found = []
    for name in mutated.mutant_names:
        function = name.partition("__mutmut_")[0]
        if functions is not None and not in_functions(function, functions):
            continue
        orig, mutant = (spans[function + "__mutmut_orig"], spans[name])
        old = [
            text.replace(f"{function}__mutmut_orig", function)
            for text in code[orig.start - 1 : orig.end]
        ]
        new = [text.replace(name, function) for text in code[mutant.start - 1 : mutant.end]]
        opcodes = difflib.SequenceMatcher(a=old, b=new, autojunk=False).get_opcodes()
        _, i1, i2, j1, j2 = next(op for op in opcodes if op[0] != "equal")
        def_index = next(i for i, text in enumerate(old) if re.match(r"\s*(async\s+)?def ", text))
        line = def_lines[function] + i1 - def_index
        if lines is None or lines & set(range(line, line + max(i2 - i1, 1))):
            before, after = (" ".join(s.strip() for s in part) for part in (old[i1:i2], new[j1:j2]))
            found.append(Mutation(get_mutant_name(Path(path), name), path, line, before, after))
    return found


def in_functions(function: str, names: Sequence[str]) -> bool:
    """Whether mutmut's function ``function`` (``x_name``, ``xǁClassǁmethod``) is one of
    ``names``: a function's or a method's name, or ``Class.method``."""
    if function.startswith("x_"):
        return function[2:] in names
    _, cls, method = function.split("ǁ")
    return method in names or f"{cls}.{method}" in names


def function_def_lines(source: str) -> dict[str, int]:
    """The ``def`` line of each function and method, keyed by mutmut's names for them
    (``x_function``, ``xǁClassǁmethod``)."""
    found = {}
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            found[f"x_{node.name}"] = node.lineno
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef):
                    found[f"xǁ{node.name}ǁ{item.name}"] = item.lineno
    return found


def prepare(
    root: Path, scratch: Path, packages: Sequence[str], modules: Sequence[str], tests: Sequence[str]
) -> None:
    """A fresh mutmut working directory: the project's top-level entries linked in, its
    pyproject.toml copied with the ``[tool.mutmut]`` table of this run."""
    shutil.rmtree(scratch, ignore_errors=True)
    scratch.mkdir(parents=True)
    entries = [e for e in sorted(root.iterdir()) if not e.name.startswith(".")]
    for entry in entries:
        if entry.name != "pyproject.toml":
            (scratch / entry.name).symlink_to(entry.resolve())
    others = [e.name for e in entries if e.name not in packages and e.name != "pyproject.toml"]
    links = [str(p.relative_to(root)) for pkg in packages for p in (root / pkg).rglob("*")]
    links = [p for p in links if (root / p).is_symlink()]  # not copied by mutmut's own walk
    shutil.copy(Path(__file__).with_name(PLUGIN), scratch / PLUGIN)
    config = {
        "source_paths": list(packages),
        "only_mutate": list(modules),
        "also_copy": [*others, *links, PLUGIN],
        "pytest_add_cli_args_test_selection": ["-m", "not browser", *tests],
        "pytest_add_cli_args": ["-p", "no:xdist", "-p", PLUGIN.removesuffix(".py")],
    }
    table = "\n".join(f"{key} = {json.dumps(value)}" for key, value in config.items())
    text = (root / "pyproject.toml").read_text()
    (scratch / "pyproject.toml").write_text(f"{text}\n[tool.mutmut]\n{table}\n")


def run_mutmut(scratch: Path, names: Sequence[str], jobs: int | None) -> dict[str, str]:
    """Run the mutants ``names`` in ``scratch``; mutmut's verdict of each of them."""
    mutmut = str(Path(sys.executable).parent / "mutmut")
    env = {**os.environ, "MCL_PURE_PYTHON": "1"}
    command = [mutmut, "run", *(["--max-children", str(jobs)] if jobs else []), *names]
    log = scratch / "mutmut.log"
    with log.open("w") as out:  # mutmut's progress line on a terminal, else in the log
        shown = None if sys.stdout.isatty() else out
        done = subprocess.run(command, cwd=scratch, env=env, stdout=shown, stderr=subprocess.STDOUT)
    print()
    if done.returncode != 0:
        lines = re.split(r"[\r\n]+", log.read_text())
        said = [line for line in lines if line.strip() and not re.match(r"\W \S", line)]
        print("\n".join(said[-8:]))
        raise SystemExit(f"mutmut run failed (exit {done.returncode}); its output: {log}")
    listing = subprocess.run(
        [mutmut, "results", "--all", "true"],
        cwd=scratch,
        env=env,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return dict(re.findall(r"^\s+(\S+): (.+)$", listing, re.MULTILINE))


def report(found: dict[str, list[Mutation]], verdicts: dict[str, str]) -> str:
    """The table of verdicts per module and in total, with the kill rate (caught / (caught +
    escaped)), then every mutant that was not caught, as ``file:line: before → after``."""
    rows: list[tuple[str, ...]] = [
        ("module", "killed", "survived", "no tests", "timeout", "other", "kill rate")
    ]
    total: Counter[str] = Counter()
    for path, module_mutations in found.items():
        counts = Counter(verdicts.get(m.name, "not run") for m in module_mutations)
        total.update(counts)
        rows.append((path, *counts_row(counts)))
    rows.append(("total", *counts_row(total)))
    width = max(len(row[0]) for row in rows)
    lines = [f"{row[0]:<{width}}" + "".join(f"{cell:>10}" for cell in row[1:]) for row in rows]
    escaped = [
        (m, verdicts.get(m.name, "not run"))
        for module_mutations in found.values()
        for m in module_mutations
        if verdicts.get(m.name, "not run") not in KILLED
    ]
    if escaped:
        lines += ["", "not caught (each wants a test; `mutmut show NAME` in .build/mutate):"]
        for m, verdict in sorted(escaped, key=lambda e: (e[0].path, e[0].line)):
            lines.append(f"  {m.path}:{m.line}: {m.before}  →  {m.after}   [{verdict}: {m.name}]")
    return "\n".join(lines)


def counts_row(counts: Counter[str]) -> tuple[str, ...]:
    """killed, survived, no tests, timeout, other and the kill rate of a module's verdicts."""
    other = sum(n for verdict, n in counts.items() if verdict not in KILLED + ESCAPED)
    caught = sum(counts[v] for v in KILLED)
    judged = caught + sum(counts[v] for v in ESCAPED)
    rate = f"{100 * caught / judged:.1f} %" if judged else "–"
    cells = (counts["killed"], counts["survived"], counts["no tests"], counts["timeout"], other)
    return (*(str(n) for n in cells), rate)


def main(argv: Sequence[str] | None = None, root: Path | None = None) -> int:
    args = parse_args(argv)
    root = (root or Path.cwd()).resolve()
    packages = tuple(args.packages)
    lines, touched = changed_modules(root, args.base, args.modules, packages)
    if not lines:
        print("no module to mutate")
        return 0
    found_tests = select_tests(root, lines, find_test_files(root, TEST_DIRS), packages, touched)
    for module in lines:
        tests = args.tests or found_tests[module]
        print(f"  {module}: tests {' '.join(tests) or '(none names it: TESTS=... names some)'}")
    tests = args.tests or sorted({t for ts in found_tests.values() for t in ts})
    if not tests:
        raise SystemExit("no test exercises these modules; name the tests with TESTS=...")
    scratch = root / SCRATCH
    prepare(root, scratch, packages, list(lines), tests)
    start = time.monotonic()
    found = in_directory(
        scratch, lambda: {m: mutations(m, lines[m], args.functions) for m in lines}
    )
    names = [m.name for ms in found.values() for m in ms]
    print(f"{len(names)} mutants, {len(tests)} test file(s): mutmut at work in {SCRATCH}")
    if names:
        print(report(found, run_mutmut(scratch, names, args.jobs)))
        print(f"\n{len(names)} mutants in {time.monotonic() - start:.0f} s")
    return 0


def changed_modules(
    root: Path, base: str | None, modules: Sequence[str] | None, packages: Sequence[str]
) -> tuple[dict[str, set[int] | None], list[str]]:
    """The modules to mutate, each with its lines to mutate (None: all), and the test files the
    change touched: ``modules`` whole if given without ``base``, their lines the change against
    ``base`` added or changed if given with it, else every module of the change against ``base``
    (default: the merge base with main)."""
    if modules:
        missing = [m for m in modules if not (root / m).is_file()]
        if missing:
            raise SystemExit(f"no such module: {' '.join(missing)}")
        if base is None:
            return dict.fromkeys(modules), []
        changed = changed_lines(root, base)
        print(f"changes against {base[:12]} in {', '.join(modules)}")
        return {m: changed.get(m, set()) for m in modules}, []
    base = base or git(root, "merge-base", "main", "HEAD").strip()
    changes = changed_lines(root, base)
    print(f"changes against {base[:12]}: {', '.join(changes) or 'none'}")
    modules = [m for m in module_paths(changes, packages) if changes[m]]  # not deletions only
    lines: dict[str, set[int] | None] = {m: changes[m] for m in modules}
    return lines, [t for t in find_test_files(root, TEST_DIRS) if t in changes]


def in_directory(directory: Path, action: Callable[[], T]) -> T:
    """``action()`` run with ``directory`` as the current directory."""
    previous = Path.cwd()
    os.chdir(directory)
    try:
        return action()
    finally:
        os.chdir(previous)


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="make mutate", description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", help="compare with this commit (default: merge base with main)")
    parser.add_argument(
        "--modules", nargs="+", help="mutate these modules (whole; with --base their changes)"
    )
    parser.add_argument(
        "--functions",
        nargs="+",
        help="only the mutants inside these functions or methods (name or Class.method)",
    )
    parser.add_argument("--tests", nargs="+", help="run these test files instead of the found")
    parser.add_argument("--jobs", type=int, help="mutants run at once (default: all cores)")
    parser.add_argument("--packages", nargs="+", default=list(PACKAGES), help=argparse.SUPPRESS)
    return parser.parse_args(argv)


if __name__ == "__main__":
    sys.exit(main())

"""Parameter sweeps: a scenario run over a grid or a seeded random sample of parameters, on all
local cores or a Dask cluster, collected into one table.

A scenario is a plain function ``scenario(seed, **parameters) -> dict of metrics`` (importable,
so the workers find it), or an ST program on a machine, ``"gantry:move.st"`` (its variables the
parameters, its VAR_OUTPUTs the metrics: :mod:`scenes.tools.st_sweep`). Every row of the result
carries its parameters, its metrics, its seed and the project version; the rows come back in
the order of the sample whatever ran where, so a serial run and a cluster run give the same table.
A scenario that raises is a failed row (its ``error`` column says why); the others still run.

.. code-block:: python

    from scenes.tools.sweep import Sweep
    sweep = Sweep("scenes.machines.gantry.scenarios:homing_repeatability",
                  grid={"hysteresis_um": [0, 10, 50]}, random={"start_mm": (20, 300)},
                  samples=20, seed=1)
    table = sweep.run()                      # all local cores; address="tcp://..." for a cluster
    sweep.write(table, "homing.csv")         # or .parquet, plus homing_<parameter>.png

From the command line: ``python -m scenes sweep FILE.toml`` (see :func:`from_toml`). The whole
file is checked against the scenario's signature before anything runs; each mistake is one line
``file:line: key: what is wrong; expected ...`` (:class:`scenes.errors.UserError`).
"""

from __future__ import annotations

__all__ = [
    "BOOKKEEPING",
    "KEYS",
    "VERSION",
    "Problem",
    "Progress",
    "Sweep",
    "check",
    "from_toml",
    "scenario_of",
]

from mcl.extras import require

require("scenes.tools.sweep", "sweep")

import functools
import importlib
import importlib.metadata
import inspect
import itertools
import math
import numbers
import os
import random as random_module
import re
import sys
import time
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import numpy as np
import numpy.typing as npt
import pandas as pd

from scenes.errors import UserError, located, suggest
from scenes.tools.st_sweep import is_st_target

VERSION = importlib.metadata.version("mcl-testbench")
"""The project version every row carries."""

BOOKKEEPING = ("run", "seed", "version", "error")
"""Columns of a sweep table that are neither parameters nor metrics."""

KEYS = ("scenario", "grid", "random", "samples", "seed", "out", "workers", "address")
"""The keys of a sweep file."""

Problem = tuple[str, str, str]
"""A mistake: (key, what is wrong, what would be right)."""


def scenario_of(target: str) -> Callable[..., Mapping[str, float]]:
    """The function ``"module:function"`` names.

    Raises:
        UserError: not of that form, or no such function (the message says which).
    """
    function, problem = _resolve(target)
    if function is None:
        raise UserError.at("scenario", "", *problem)
    return function


def _resolve(target: object) -> tuple[Callable[..., Mapping[str, float]] | None, tuple[str, str]]:
    """The function ``target`` names, or None and (what is wrong, what would be right)."""
    form = "'module:function', e.g. 'scenes.machines.flying_shear.scenarios:cut_length'"
    if not isinstance(target, str):
        return None, (f"{target!r} is not a string", form)
    if is_st_target(target):  # an ST program: "machine:file.st"
        return _st_scenario(target)
    module_name, _, name = target.partition(":")
    if not module_name or not name:
        return None, (f"{target!r} is not 'module:function'", form)
    try:
        module = importlib.import_module(module_name)
    except ImportError as error:
        return None, (f"module {module_name!r} cannot be imported ({error})", form)
    function = getattr(module, name, None)
    if not callable(function):
        functions = sorted(
            n for n, f in vars(module).items() if inspect.isfunction(f) and not n.startswith("_")
        )
        what = "no function" if function is None else "not a function:"
        return None, (
            f"module {module_name} has {what} {name!r}",
            f"one of {functions}{suggest(name, functions)}",
        )
    return function, ("", "")


@functools.cache
def _st_scenario(target: str) -> tuple[Callable[..., Mapping[str, float]] | None, tuple[str, str]]:
    """The scenario of an ST program (:class:`scenes.tools.st_sweep.STScenario`), or None and
    why not."""
    import plc.st
    from scenes.tools.st_sweep import STScenario

    try:
        return STScenario(target), ("", "")
    except KeyError as error:
        return None, (str(error.args[0]), "'machine:file.st', e.g. 'gantry:examples/st/move.st'")
    except plc.st.STError as error:
        return None, (str(error), "an ST program that loads on the machine")


def _is_number(value: object) -> bool:
    """A real number (NumPy's too), not a bool."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def _is_list(value: object) -> bool:
    """A list of values (a tuple, a NumPy array), not a string or a single value."""
    return isinstance(value, Sequence | np.ndarray) and not isinstance(value, str | bytes)


def _parameters(function: Callable[..., Any]) -> tuple[dict[str, inspect.Parameter], bool]:
    """The scenario's keyword parameters but ``seed``, and whether it takes any (``**kw``)."""
    try:
        signature = inspect.signature(function, eval_str=True)
    except (NameError, TypeError, ValueError):
        signature = inspect.signature(function)
    named = {
        n: p
        for n, p in signature.parameters.items()
        if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and n != "seed"
    }
    anything = any(p.kind is p.VAR_KEYWORD for p in signature.parameters.values())
    return named, anything


def _value_problem(value: object, parameter: inspect.Parameter | None) -> str:
    """Why ``value`` does not fit the parameter's annotation ("" if it fits)."""
    kind = None if parameter is None else parameter.annotation
    if kind in (float, int) and not _is_number(value):
        return f"{value!r} is not a number"
    if kind is int and isinstance(value, float) and not value.is_integer():
        return f"{value!r} is not a whole number"
    if kind is str and not isinstance(value, str):
        return f"{value!r} is not a string"
    if kind is bool and not isinstance(value, bool):
        return f"{value!r} is not true or false"
    return ""


def check(spec: Mapping[str, Any]) -> list[Problem]:
    """Every mistake of a sweep described as in a sweep file (keys :data:`KEYS`), checked
    against the scenario's signature; empty when it can run."""
    problems: list[Problem] = [
        (key, "unknown key", f"one of {sorted(KEYS)}{suggest(key, KEYS)}")
        for key in spec
        if key not in KEYS
    ]
    if "scenario" not in spec:
        return [*problems, ("scenario", "missing", 'scenario = "module:function"')]
    function, problem = _resolve(spec["scenario"])
    if function is None:
        return [*problems, ("scenario", *problem)]
    named, anything = _parameters(function)
    if "seed" not in inspect.signature(function).parameters and not anything:
        problems.append(
            (
                "scenario",
                f"{spec['scenario']} has no 'seed' parameter",
                "a function f(seed, **parameters) -> dict of metrics",
            )
        )
    tables = _tables(spec, named, anything, problems)
    grid, drawn = tables.get("grid", {}), tables.get("random", {})
    problems += _grid_problems(grid, drawn, named)
    problems += _random_problems(drawn, named)
    problems += [
        (
            name,
            "the scenario needs it (no default)",
            f"it in [grid] ({name} = [...]) or [random] ({name} = [low, high])",
        )
        for name, parameter in named.items()
        if parameter.default is inspect.Parameter.empty and name not in {*grid, *drawn}
    ]
    return problems + _setting_problems(spec)


def _tables(
    spec: Mapping[str, Any],
    named: Mapping[str, inspect.Parameter],
    anything: bool,
    problems: list[Problem],
) -> dict[str, Mapping[str, Any]]:
    """The [grid] and [random] tables that are tables; the mistakes found go to ``problems``
    (not a table, a name the scenario does not take)."""
    tables: dict[str, Mapping[str, Any]] = {}
    for table in ("grid", "random"):
        value = spec.get(table, {})
        if not isinstance(value, Mapping):
            example = "x = [1, 2, 3]" if table == "grid" else "x = [0.0, 1.0]"
            problems.append((table, f"{value!r} is not a table", f"[{table}] with lines {example}"))
            continue
        tables[table] = value
        problems += [
            (
                f"{table}.{name}",
                f"not a parameter of {spec['scenario']}",
                f"one of {sorted(named)}{suggest(name, named)}",
            )
            for name in value
            if name not in named and not anything
        ]
    return tables


def _grid_problems(
    grid: Mapping[str, Any], drawn: Mapping[str, Any], named: Mapping[str, inspect.Parameter]
) -> list[Problem]:
    """The mistakes of the [grid] table: not a list, empty, a value of the wrong type, a name
    also in [random]."""
    problems: list[Problem] = []
    for name, values in grid.items():
        key, parameter = f"grid.{name}", named.get(name)
        if not _is_list(values):
            problems.append(
                (
                    key,
                    f"{values!r} is a single value, not a list",
                    f"a list of values, e.g. {name} = [{values!r}]",
                )
            )
        elif len(values) == 0:
            problems.append((key, "an empty list", "at least one value"))
        else:
            wrong = next((w for w in (_value_problem(v, parameter) for v in values) if w), "")
            if wrong:
                hint = getattr(parameter.annotation, "__name__", "") if parameter else ""
                problems.append((key, wrong, f"values of type {hint}"))
        if name in drawn:
            problems.append((key, "in both [grid] and [random]", "it in one of them"))
    return problems


def _random_problems(
    drawn: Mapping[str, Any], named: Mapping[str, inspect.Parameter]
) -> list[Problem]:
    """The mistakes of the [random] table: not [low, high], the wrong way round, a parameter
    that takes no real numbers."""
    problems: list[Problem] = []
    for name, bounds in drawn.items():
        key, parameter = f"random.{name}", named.get(name)
        if (
            not _is_list(bounds)
            or len(bounds) != 2
            or not all(_is_number(b) and math.isfinite(b) for b in bounds)
        ):
            problems.append(
                (key, f"{bounds!r} is not [low, high]", f"two numbers, e.g. {name} = [0.0, 1.0]")
            )
        elif bounds[0] > bounds[1]:
            problems.append(
                (
                    key,
                    f"low {bounds[0]!r} is above high {bounds[1]!r}",
                    f"[{bounds[1]!r}, {bounds[0]!r}]",
                )
            )
        elif parameter is not None and parameter.annotation in (int, str, bool):
            problems.append(
                (
                    key,
                    f"{name} takes {parameter.annotation.__name__} values; "
                    "random draws real numbers",
                    f"{name} in [grid] instead",
                )
            )
    return problems


def _setting_problems(spec: Mapping[str, Any]) -> list[Problem]:
    """The mistakes of the sweep's own settings: samples, seed, workers, out, address."""
    problems: list[Problem] = []
    for key, low in {"samples": 1, "seed": 0, "workers": 0}.items():
        if key in spec and not (
            isinstance(spec[key], int) and not isinstance(spec[key], bool) and spec[key] >= low
        ):
            problems.append((key, f"{spec[key]!r}", f"an integer >= {low}"))
    out = spec.get("out", "results.csv")
    if not isinstance(out, str) or Path(out).suffix not in (".csv", ".parquet"):
        problems.append(("out", f"{out!r}", "a file name ending in .csv or .parquet"))
    address = spec.get("address")
    if address is not None and not (isinstance(address, str) and "://" in address):
        problems.append(("address", f"{address!r}", "a Dask scheduler, e.g. 'tcp://host:8786'"))
    return problems


def _run_one(target: str, row: dict[str, Any]) -> dict[str, Any]:
    """One scenario of the sweep (runs on a worker): its row with the metrics, or with the
    reason it failed in ``error``."""
    parameters = {k: v for k, v in row.items() if k not in BOOKKEEPING}
    try:
        metrics = scenario_of(target)(seed=row["seed"], **parameters)
        if not isinstance(metrics, Mapping):
            raise TypeError(f"returned {type(metrics).__name__}, not a dict of metrics")
        return {**row, **metrics}
    except Exception as error:  # a failed scenario is a row of the table, not the sweep's end
        return {**row, "error": f"{type(error).__name__}: {error}".splitlines()[0]}


class Progress:
    """A sweep's progress on a stream: scenarios done and failed, time spent and left.

    On a terminal one line is rewritten in place (at most 5 times a second); otherwise a line is
    written at each tenth of the sweep, so a log gets at most 11 lines.

    Args:
        total: scenarios in the sweep.
        stream: where the lines go (standard error by default).
        label: what the lines start with (the sweep file's name).
    """

    def __init__(self, total: int, stream: TextIO | None = None, label: str = "sweep") -> None:
        self.total, self.label = total, label
        self.stream = sys.stderr if stream is None else stream
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.start = time.monotonic()
        self._shown = -1.0
        self._tenth = -1

    def line(self, done: int, failed: int) -> str:
        """The progress line after ``done`` scenarios (``failed`` of them failed)."""
        spent = time.monotonic() - self.start
        text = f"{self.label}: {done}/{self.total} done, {failed} failed, {spent:.1f} s"
        if 0 < done < self.total:
            left = spent / done * (self.total - done)
            text += f", about {left:.0f} s left" if left >= 10 else f", about {left:.1f} s left"
        return text

    def __call__(self, done: int, failed: int) -> None:
        """Show the progress after ``done`` scenarios."""
        final = done == self.total
        if self.tty:
            now = time.monotonic()
            if final or now - self._shown >= 0.2:
                self._shown = now
                end = "\n" if final else ""
                self.stream.write(f"\r{self.line(done, failed)}\x1b[K{end}")
                self.stream.flush()
            return
        tenth = 10 * done // max(self.total, 1)
        if tenth > self._tenth:
            self._tenth = tenth
            self.stream.write(self.line(done, failed) + "\n")
            self.stream.flush()


@dataclass
class Sweep:
    """A scenario over parameters.

    Attributes:
        scenario: ``"module:function"``; the function takes the parameters and ``seed`` as
            keyword arguments and returns a mapping of metric name to value.
        grid: parameter → values; every combination runs (the full factorial).
        random: parameter → ``(low, high)``; each grid point runs ``samples`` times with values
            drawn uniformly (seeded).
        samples: random draws per grid point (1 without ``random``).
        seed: the sweep's seed: the random draws and each scenario's own ``seed``.

    Raises:
        UserError: a parameter the scenario does not take, a grid value that is not a list, ...
            (one line per mistake).
    """

    scenario: str
    grid: Mapping[str, Sequence[Any] | npt.NDArray[Any]] = field(default_factory=dict)
    random: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    samples: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        spec = {
            "scenario": self.scenario,
            "grid": self.grid,
            "random": self.random,
            "samples": self.samples,
            "seed": self.seed,
        }
        problems = check(spec)
        if problems:
            raise UserError.of([located("Sweep", *p) for p in problems])

    def rows(self) -> list[dict[str, Any]]:
        """The scenarios to run, in order: run number, seed, version and parameters."""
        draw = random_module.Random(self.seed)
        rows: list[dict[str, Any]] = []
        names = list(self.grid)
        for point in itertools.product(*(self.grid[n] for n in names)):
            for _ in range(self.samples):
                drawn = {n: draw.uniform(lo, hi) for n, (lo, hi) in self.random.items()}
                rows.append(
                    {
                        "run": len(rows),
                        "seed": draw.randrange(2**31),
                        "version": VERSION,
                        **dict(zip(names, point, strict=True)),
                        **drawn,
                    }
                )
        return rows

    @property
    def parameters(self) -> list[str]:
        """The swept parameters: the grid's, then the random ones."""
        return [*self.grid, *self.random]

    def run(
        self,
        workers: int | None = None,
        address: str | None = None,
        progress: Callable[[int, int], None] | None = None,
        on_cluster: Callable[[str], None] | None = None,
    ) -> pd.DataFrame:
        """Run every scenario and return the table (one row each, in :meth:`rows` order; a
        failed scenario has its reason in the ``error`` column, present only then).

        Args:
            workers: local worker processes (default: one per core); 0 runs serially here.
            address: a Dask scheduler (``"tcp://host:8786"``): run on that cluster instead.
            progress: called with (scenarios done, of which failed) after each one, e.g. a
                :class:`Progress`.
            on_cluster: called with the Dask dashboard's address once the cluster is up.
        """
        rows = self.rows()
        report = progress or (lambda done, failed: None)
        results: list[dict[str, Any]] = []
        failed = 0
        if address is None and workers == 0:
            report(0, 0)
            for row in rows:
                results.append(_run_one(self.scenario, row))
                failed += "error" in results[-1]
                report(len(results), failed)
            return _table(results)
        from distributed import Client, LocalCluster, as_completed

        cluster = None
        if address is not None:
            client = Client(address)
        else:
            cluster = LocalCluster(
                n_workers=workers or os.cpu_count() or 1,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
            )
            client = Client(cluster)
        try:
            if on_cluster is not None and address is not None:
                on_cluster(client.dashboard_link)
            futures = client.map(_run_one, [self.scenario] * len(rows), rows, pure=False)
            report(0, 0)
            for future in as_completed(futures):
                if future.status == "error":  # the worker itself died
                    row = rows[futures.index(future)]
                    results.append({**row, "error": f"worker lost: {future.exception()}"})
                else:
                    results.append(future.result())
                failed += "error" in results[-1]
                report(len(results), failed)
            return _table(results)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()

    def write(self, table: pd.DataFrame, path: str | Path) -> list[Path]:
        """Write the table (``.csv`` or ``.parquet``) and, next to it, a PNG of every metric
        against every swept parameter (``<stem>_<parameter>.png``); returns the files written.

        Raises:
            UserError: ``path`` is neither ``.csv`` nor ``.parquet``.
        """
        from scenes.tools.plot import plot_table

        path = Path(path)
        if path.suffix not in (".csv", ".parquet"):
            raise UserError.at(str(path), "", "not a table file", "a .csv or .parquet file")
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".parquet":
            table.to_parquet(path, index=False)
        else:
            table.to_csv(path, index=False)
        metrics = self.metrics(table)
        written = [path]
        seeds = f"seed {self.seed}, {len(table)} scenarios"
        for name in self.parameters if metrics else ():
            others = [p for p in self.parameters if p != name and table[p].nunique() > 1]
            out = path.with_name(f"{path.stem}_{name}")
            title = f"{self.scenario} ({seeds})"
            written.append(plot_table(table, name, metrics, out, title=title, colour=others))
        return written

    def metrics(self, table: pd.DataFrame) -> list[str]:
        """The metric columns of a table of this sweep."""
        return [c for c in table.columns if c not in (*BOOKKEEPING, *self.parameters)]

    def summary(self, table: pd.DataFrame) -> str:
        """What a sweep found, for a reader: the failed scenarios, each metric's mean per grid
        point (over the random draws) and each metric's range over the whole sweep."""
        lines = [f"{len(table)} scenarios of {self.scenario}, seed {self.seed}"]
        failed = table[table["error"].astype(bool)] if "error" in table else table.iloc[:0]
        ok = table.drop(index=failed.index)
        if len(failed):
            lines.append(f"{len(failed)} failed (column 'error'):")
            for reason, group in failed.groupby("error", sort=False):
                runs = ", ".join(str(r) for r in group["run"][:5])
                more = ", ..." if len(group) > 5 else ""
                lines.append(f"  runs {runs}{more}: {reason}")
        metrics = [m for m in self.metrics(table) if pd.api.types.is_numeric_dtype(table[m])]
        if not metrics or ok.empty:
            return "\n".join(lines)
        if self.grid:
            draws = (
                f"mean of {self.samples} draws of {', '.join(self.random)}" if self.random else ""
            )
            lines.append(f"\nby grid point{f' ({draws})' if draws else ''}:")
            by_point = ok.groupby(list(self.grid), sort=False)[metrics].mean()
            lines.append(by_point.to_string(float_format=lambda v: f"{v:.4g}"))
        spread = ok[metrics].agg(["min", "mean", "max"]).T
        lines.append("\nover the whole sweep:")
        lines.append(spread.to_string(float_format=lambda v: f"{v:.4g}"))
        return "\n".join(lines)


def _table(results: list[dict[str, Any]]) -> pd.DataFrame:
    """The rows in run order as a table; ``error`` last, and only if a scenario failed."""
    results = sorted(results, key=lambda r: r["run"])
    table = pd.DataFrame(results)
    if "error" in table:
        table["error"] = table["error"].fillna("")
        table = table[[c for c in table.columns if c != "error"] + ["error"]]
    return table


class _Lines:
    """Where each key of a TOML text is defined (``"grid.x"`` → line number)."""

    HEADER = re.compile(r"^\s*\[\s*([^\[\]]+?)\s*\]")
    KEY = re.compile(r"^\s*(\"[^\"]*\"|'[^']*'|[A-Za-z0-9_.-]+)\s*=")

    def __init__(self, text: str) -> None:
        self.lines: dict[str, int] = {}
        table = ""
        for number, line in enumerate(text.splitlines(), start=1):
            header = self.HEADER.match(line)
            if header:
                table = header.group(1).strip("\"'")
                self.lines.setdefault(table, number)
                continue
            key = self.KEY.match(line)
            if key:
                name = key.group(1).strip("\"'")
                self.lines.setdefault(f"{table}.{name}" if table else name, number)

    def line(self, key: str) -> int | None:
        """The line of ``key`` or of the nearest table holding it (None: not in the text)."""
        while key:
            if key in self.lines:
                return self.lines[key]
            key = key.rpartition(".")[0]
        return None


def _toml_value(text: str) -> Any:
    """A command-line value read as TOML (``[1, 2]``, ``3``, ``"a"``); a list's items that are
    not TOML, and any other such text, as plain strings (``[30, fast]`` → ``[30, "fast"]``)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        if text.startswith("[") and text.endswith("]"):
            return [_toml_value(item.strip()) for item in text[1:-1].split(",") if item.strip()]
        return text


def _read_toml(path: Path) -> tuple[str, dict[str, Any]]:
    """A sweep file's text and its table.

    Raises:
        UserError: a missing or unreadable file, a TOML syntax error (``file:line``).
    """
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise UserError.at(
            str(path), "", "no such file", f"a sweep file (TOML), relative to {Path.cwd()}"
        ) from None
    except (OSError, UnicodeDecodeError) as error:
        raise UserError.at(str(path), "", f"cannot be read ({error})", "a TOML text file") from None
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        message = str(error)
        at = re.search(r"\(at line (\d+), column (\d+)\)", message)
        line = at.group(1) if at else str(len(text.splitlines()) or 1)
        column = f", column {at.group(2)}" if at else ""
        what = re.sub(r"\s*\(at [^)]*\)$", "", message)
        raise UserError.at(
            f"{path}:{line}",
            "",
            f"TOML syntax: {what}{column}",
            "valid TOML (key = value, [table])",
        ) from None


def _override(
    spec: dict[str, Any], overrides: Sequence[str], problems: list[tuple[str, Problem]]
) -> set[str]:
    """Apply the command line's ``key=value`` overrides to ``spec``; returns the keys set (a
    malformed one goes to ``problems``)."""
    overridden: set[str] = set()
    for item in overrides:
        key, equals, value = item.partition("=")
        key = key.strip()
        if not equals or not key:
            problems.append(
                (
                    "command line",
                    (item, "not KEY=VALUE", "e.g. --set samples=5 or --grid x=[1,2,3]"),
                )
            )
            continue
        table, _, name = key.rpartition(".")
        target = spec
        if table:
            target = spec.setdefault(table, {})
            if not isinstance(target, dict):
                continue  # check() reports the table itself
        target[name] = _toml_value(value.strip())
        overridden.add(key)
    return overridden


def from_toml(path: str | Path, overrides: Sequence[str] = ()) -> tuple[Sweep, dict[str, Any]]:
    """A sweep described in a TOML file, and its run options.

    .. code-block:: toml

        scenario = "scenes.machines.gantry.scenarios:homing_repeatability"
        samples = 20          # random draws per grid point
        seed = 1
        out = "homing.csv"    # or .parquet (relative to the TOML file)
        workers = 2           # optional; 0 = serial; default: one per core
        # address = "tcp://scheduler:8786"
        [grid]
        hysteresis_um = [0, 10, 50]
        [random]
        start_mm = [20, 300]

    Args:
        path: the TOML file.
        overrides: ``"key=value"`` (a TOML value; dotted keys reach into the tables:
            ``"grid.hysteresis_um=[0, 5]"``, ``"samples=3"``), applied over the file.

    Raises:
        UserError: a missing file, a TOML syntax error, or every mistake of the sweep (an
            unknown key or parameter, a grid value that is not a list, ...), one line each:
            ``file:line: key: what is wrong; expected ...``.
    """
    path = Path(path)
    text, spec = _read_toml(path)
    problems: list[tuple[str, Problem]] = []
    overridden = _override(spec, overrides, problems)
    lines = _Lines(text)

    def where(key: str) -> str:
        if any(key == o or key.startswith(f"{o}.") for o in overridden):
            return "command line"
        line = lines.line(key)
        return f"{path}:{line}" if line else str(path)

    found = [(where(p[0]), p) for p in check(spec)]
    problems += sorted(
        found, key=lambda f: 0 if f[0] == "command line" else lines.line(f[1][0]) or 0
    )
    if problems:
        raise UserError.of([located(w, *p) for w, p in problems])
    sweep = Sweep(
        spec["scenario"],
        grid=spec.get("grid", {}),
        random={k: (float(v[0]), float(v[1])) for k, v in spec.get("random", {}).items()},
        samples=int(spec.get("samples", 1)),
        seed=int(spec.get("seed", 0)),
    )
    options = {
        "out": path.parent / spec.get("out", f"{path.stem}.csv"),
        "workers": spec.get("workers"),
        "address": spec.get("address"),
    }
    return sweep, options

"""Parameter sweeps: a scenario run over a grid or a seeded random sample of parameters, on all
local cores or a Dask cluster, collected into one table.

A scenario is a plain function ``scenario(**parameters) -> dict of metrics`` (importable, so the
workers find it). Every row of the result carries its parameters, its metrics, its seed and the
project version; the rows come back in the order of the sample whatever ran where, so a serial run
and a cluster run give the same table.

.. code-block:: python

    from scenes.sweep import Sweep
    sweep = Sweep("scenes.examples:homing_repeatability",
                  grid={"hysteresis_um": [0, 10, 50]}, random={"start_mm": (20, 300)},
                  samples=20, seed=1)
    table = sweep.run()                      # all local cores; address="tcp://..." for a cluster
    sweep.write(table, "homing.csv")         # or .parquet, plus homing.png

From the command line: ``python -m scenes sweep FILE.toml`` (see :func:`from_toml`).
"""

from __future__ import annotations

import importlib
import importlib.metadata
import itertools
import os
import random as random_module
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

VERSION = importlib.metadata.version("mcl-testbench")
"""The project version every row carries."""


def scenario_of(target: str) -> Callable[..., Mapping[str, float]]:
    """The function ``"module:function"`` names.

    Raises:
        ValueError: not of that form, or no such function (the message says which).
    """
    module, _, name = target.partition(":")
    if not module or not name:
        raise ValueError(f"scenario must be 'module:function', got {target!r}")
    try:
        function = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as error:
        raise ValueError(f"scenario {target!r} not found: {error}") from None
    if not callable(function):
        raise ValueError(f"scenario {target!r} is not a function")
    return function


def _run_one(target: str, row: dict[str, Any]) -> dict[str, Any]:
    """One scenario of the sweep (runs on a worker): its row with the metrics."""
    parameters = {k: v for k, v in row.items() if k not in ("run", "seed", "version")}
    metrics = scenario_of(target)(seed=row["seed"], **parameters)
    return {**row, **metrics}


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
    """

    scenario: str
    grid: Mapping[str, Sequence[Any]] = field(default_factory=dict)
    random: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    samples: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        scenario_of(self.scenario)
        if self.samples < 1:
            raise ValueError(f"samples must be >= 1, got {self.samples}")
        for name, bounds in self.random.items():
            if len(bounds) != 2 or not bounds[0] <= bounds[1]:
                raise ValueError(f"random {name!r} must be (low, high), got {bounds!r}")
        for name, values in self.grid.items():
            if isinstance(values, str) or not len(values):
                raise ValueError(f"grid {name!r} must be a non-empty list, got {values!r}")

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

    def run(self, workers: int | None = None, address: str | None = None) -> pd.DataFrame:
        """Run every scenario and return the table (one row each, in :meth:`rows` order).

        Args:
            workers: local worker processes (default: one per core); 0 runs serially here.
            address: a Dask scheduler (``"tcp://host:8786"``): run on that cluster instead.
        """
        rows = self.rows()
        if address is None and workers == 0:
            return pd.DataFrame([_run_one(self.scenario, row) for row in rows])
        from distributed import Client, LocalCluster

        if address is not None:
            client = Client(address)
            cluster = None
        else:
            cluster = LocalCluster(
                n_workers=workers or os.cpu_count() or 1,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
            )
            client = Client(cluster)
        try:
            futures = client.map(_run_one, [self.scenario] * len(rows), rows, pure=False)
            return pd.DataFrame(client.gather(futures))
        finally:
            client.close()
            if cluster is not None:
                cluster.close()

    def write(self, table: pd.DataFrame, path: str | Path) -> list[Path]:
        """Write the table (``.csv`` or ``.parquet``) and, next to it, a PNG of every metric
        against every swept parameter; returns the files written."""
        from scenes.plot import plot_table

        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".parquet":
            table.to_parquet(path, index=False)
        elif path.suffix == ".csv":
            table.to_csv(path, index=False)
        else:
            raise ValueError(f"results go to a .csv or .parquet file, got {path.name!r}")
        parameters = [*self.grid, *self.random]
        metrics = [c for c in table.columns if c not in ("run", "seed", "version", *parameters)]
        written = [path]
        for name in parameters:
            if metrics:
                out = path.with_name(f"{path.stem}_{name}")
                written.append(plot_table(table, name, metrics, out))
        return written


def from_toml(path: str | Path) -> tuple[Sweep, dict[str, Any]]:
    """A sweep described in a TOML file, and its run options.

    .. code-block:: toml

        scenario = "scenes.examples:homing_repeatability"
        samples = 20          # random draws per grid point
        seed = 1
        out = "homing.csv"    # or .parquet (relative to the TOML file)
        workers = 2           # optional; 0 = serial; default: one per core
        # address = "tcp://scheduler:8786"
        [grid]
        hysteresis_um = [0, 10, 50]
        [random]
        start_mm = [20, 300]

    Raises:
        ValueError: a missing or unknown key (the message lists the valid ones).
    """
    path = Path(path)
    with path.open("rb") as f:
        spec = tomllib.load(f)
    known = {"scenario", "grid", "random", "samples", "seed", "out", "workers", "address"}
    unknown = set(spec) - known
    if unknown or "scenario" not in spec:
        raise ValueError(
            f"{path}: needs 'scenario'; unknown keys {sorted(unknown)}; valid: {sorted(known)}"
        )
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

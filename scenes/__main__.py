"""Command line: ``python -m scenes list`` lists the machines; ``python -m scenes run NAME`` runs
a machine's demo program headless and prints every FB edge, the positions and states;
``python -m scenes plot TRACE`` plots a recorded trace (.csv or .npy) as PNG and HTML;
``python -m scenes sweep FILE.toml`` runs a parameter sweep (see :mod:`scenes.sweep`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import scenes
from scenes.report import EdgeLog


def run(name: str, timeout: float = 300.0) -> int:
    """Run the demo of machine ``name`` from its demo start and print the report."""
    definition = scenes.definition(name)
    scene = scenes.load(name, start=definition.demo_start, trace_every=0)
    program = scenes.demo(scene)
    log = EdgeLog(scene)
    log.watch(**getattr(program, "blocks", {}))
    steps = [program.step]
    log.title(program.step)

    def scan() -> None:
        program()
        if program.step != steps[-1]:
            steps.append(program.step)
            log.title(f"t={scene.time:6.3f} s  {program.step}")

    scene.run(scan, until=lambda: program.done or bool(program.error), timeout=timeout)
    log.summary()
    if program.error:
        print(f"demo stopped: {program.error}", file=sys.stderr)
        return 1
    return 0


def sweep(file: str, workers: int | None, address: str | None) -> int:
    """Run the sweep described in ``file``; write its table and plots."""
    from scenes.sweep import from_toml

    spec, options = from_toml(file)
    workers = options["workers"] if workers is None else workers
    table = spec.run(workers=workers, address=address or options["address"])
    for path in spec.write(table, options["out"]):
        print(path)
    print(table.describe().to_string())
    return 0


def main(argv: list[str] | None = None) -> int:
    """Parse the command line and run the command."""
    parser = argparse.ArgumentParser(prog="python -m scenes", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    run_parser = sub.add_parser("run", help="run a machine's demo program headless")
    run_parser.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
    sub.add_parser("list", help="list the machines")
    plot_parser = sub.add_parser("plot", help="plot a trace file as PNG and HTML")
    plot_parser.add_argument("trace", help="a trace written by trace.to_csv or streamed (.npy)")
    plot_parser.add_argument("--out", help="output path without suffix (default: next to it)")
    sweep_parser = sub.add_parser("sweep", help="run a parameter sweep described in TOML")
    sweep_parser.add_argument("file", help="the sweep (scenario, grid, random, samples, seed)")
    sweep_parser.add_argument("--workers", type=int, help="local workers (0 = serial)")
    sweep_parser.add_argument("--address", help="a Dask scheduler to run on")
    args = parser.parse_args(argv)
    if args.command == "plot":
        from scenes.plot import plot

        trace = Path(args.trace)
        for path in plot(trace, Path(args.out) if args.out else trace.with_suffix("")):
            print(path)
        return 0
    if args.command == "sweep":
        return sweep(args.file, args.workers, args.address)
    if args.command == "list":
        width = max(len(n) for n in scenes.MACHINES)
        for name in sorted(scenes.MACHINES):
            print(f"{name:<{width}}  {scenes.MACHINES[name].description}")
        return 0
    return run(args.name)


if __name__ == "__main__":
    sys.exit(main())

"""Command line: ``python -m scenes list`` lists the machines; ``python -m scenes run NAME`` runs
a machine's demo program headless and prints every FB edge, the positions and states."""

from __future__ import annotations

import argparse
import sys

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


def main(argv: list[str] | None = None) -> int:
    """Parse the command line and run the command."""
    parser = argparse.ArgumentParser(prog="python -m scenes", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    run_parser = sub.add_parser("run", help="run a machine's demo program headless")
    run_parser.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
    sub.add_parser("list", help="list the machines")
    args = parser.parse_args(argv)
    if args.command == "list":
        width = max(len(n) for n in scenes.MACHINES)
        for name in sorted(scenes.MACHINES):
            print(f"{name:<{width}}  {scenes.MACHINES[name].description}")
        return 0
    return run(args.name)


if __name__ == "__main__":
    sys.exit(main())

"""Command line: ``python -m scenes run NAME`` runs a scene's demo program headless."""

from __future__ import annotations

import argparse
import importlib
import sys

DEMOS = {
    "gantry": "scenes.gantry",
    "single_axis": "scenes.single_axis",
}
"""Scene name → module whose ``main()`` runs its demo program."""


def main(argv: list[str] | None = None) -> int:
    """Parse the command line and run the demo."""
    parser = argparse.ArgumentParser(prog="python -m scenes", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scene's demo program headless and print a report")
    run.add_argument("name", choices=sorted(DEMOS), help="the scene")
    sub.add_parser("list", help="list the scenes")
    args = parser.parse_args(argv)
    if args.command == "list":
        print("\n".join(sorted(DEMOS)))
        return 0
    importlib.import_module(DEMOS[args.name]).main()
    return 0


if __name__ == "__main__":
    sys.exit(main())

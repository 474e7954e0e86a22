"""Command line: ``python -m scenes list`` lists the machines; ``python -m scenes run NAME`` runs
a machine's demo program headless and prints its steps, its blocks' output edges, the final
positions and states, the machine's signals and the demo's results; ``python -m scenes check
NAME PROGRAM...`` checks ST programs for the machine without running them (each item's first
error, then a summary; exit status 1 on errors);
``python -m scenes plot TRACE`` plots a recorded trace (.csv or .npy) as PNG and HTML;
``python -m scenes cam TABLE.csv`` (or ``--cut-length L --circumference C``, the rotary knife's
cam) plots a cam table's profile as PNG (see :mod:`scenes.tools.cam_plot`);
``python -m scenes sweep FILE.toml`` runs a parameter sweep (see :mod:`scenes.tools.sweep`);
``python -m scenes circle gantry --plane XY --radius 50 --feed 1000 --direction both [--plot
FILE]`` runs the circle test of ISO 230-4 and prints its figures (see :mod:`scenes.tools.circle`);
``python -m scenes bridge map NAME`` prints a machine's register map, ``python -m scenes bridge
modbus NAME`` runs it with its Modbus TCP server and ``python -m scenes bridge opcua NAME`` with
its OPC UA server (docs/bridge.md).

A mistake in a file or a value given here is one line on standard error, ``file:line: key: what
is wrong; expected ...``, and the exit status 2."""

from __future__ import annotations

__all__ = ["check", "machine_blocks", "main", "run", "st_task", "sweep"]

import argparse
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import mcl
import plc.st
import scenes
from scenes.errors import UserError
from scenes.tools.report import EdgeLog


def run(
    name: str,
    timeout: float = 300.0,
    st_program: str | None = None,
    maps: Sequence[str] = (),
    pou: str | None = None,
) -> int:
    """Run the demo of machine ``name`` (or the ST program ``st_program``, its PROGRAM ``pou``
    where it has several) from its demo start and print the report."""
    definition = scenes.definition(name)
    task = st_task(st_program) if st_program is not None else None
    try:
        scene = scenes.load(
            name,
            start=definition.demo_start,
            trace_every=0,
            **({"plc_period": task.interval} if task is not None else {}),
        )
    except ValueError as error:  # a TASK period the machine's servo cycle does not divide
        if task is None:
            raise
        raise plc.st.STError.at(task.where, f"TASK {task.name}: {error}", "") from None
    program: Any = (
        scenes.demo(scene)
        if st_program is None
        else plc.st.load(
            st_program,
            scene,
            mapping=_mapping(maps, scene.axes),
            program=pou,
            blocks=machine_blocks(scene),
        )
    )
    log = EdgeLog(scene)
    log.watch(**getattr(program, "blocks", {}))
    steps: list[str | None] = [program.step]
    log.step(scene.time, program.step)

    def scan() -> None:
        program()
        if program.error:  # a stop, not a step (the step reads the error then)
            if steps[-1] is not None:
                steps.append(None)
                fault = st_program is not None and plc.st.stopped(program)
                log.stopped(scene.time, "fault" if fault else "error", program.error)
        elif program.step != steps[-1]:
            steps.append(program.step)
            log.step(scene.time, program.step)

    timed_out = False
    if st_program is not None and "done" not in plc.st.variables(program):
        print(
            f"{st_program}: the program has no variable 'done': it runs for the whole --timeout "
            f"of {timeout:g} s of simulated time (declare done : BOOL and set it to end the run)",
            file=sys.stderr,
        )
        scene.run(scan, timeout=timeout)
    else:
        try:
            scene.run(scan, until=lambda: program.done or bool(program.error), timeout=timeout)
        except mcl.ConditionTimeout:
            timed_out = True
    stop = ""
    if st_program is not None and plc.st.stopped(program):
        stop = _ramped_down(scene)
    log.summary()
    log.results(getattr(program, "results", None) or [])
    if program.error:
        print(f"demo stopped: {program.error}{stop}", file=sys.stderr)
        return 1
    if timed_out:
        what = f"the demo (at {program.step})" if st_program is None else st_program
        print(
            f"{what} did not set done within the --timeout of {timeout:g} s of simulated "
            "time; give a longer --timeout or end the program with done",
            file=sys.stderr,
        )
        return 1
    return 0


RAMP_DOWN_TIMEOUT = 30.0
"""Simulated seconds the axes have to come to rest after a run-time fault stopped an ST
program (their stop ramps take well under a second)."""


def _ramped_down(scene: scenes.Scene) -> str:
    """Run the machine without the program (stopped by a run-time fault or the watchdog:
    every axis ramps down and is disabled) until every axis is at rest, so that the summary
    shows where they came to rest; what to add to the stop's message."""

    def moving() -> list[str]:
        return [p for p in (axis.rest_problem() for axis in scene.axes.values()) if p]

    start = scene.time
    if moving():
        try:
            scene.run(None, until=lambda: not moving(), timeout=RAMP_DOWN_TIMEOUT)
        except mcl.ConditionTimeout:
            return (
                f"; {RAMP_DOWN_TIMEOUT:g} s after the stop the axes were not at rest "
                f"({'; '.join(moving())}): the summary shows them then"
            )
    return (
        f"; the axes ramped down and were at rest at t={scene.time:.3f} s "
        f"({scene.time - start:.3f} s after the stop): the summary shows where"
    )


def machine_blocks(scene: scenes.Scene) -> dict[str, plc.st.External]:
    """The machine's own ST block types: ``blocks(scene)`` of its package's ``st_blocks``
    module (``scenes.machines.<name>.st_blocks``), if it has one."""
    import importlib

    name = f"scenes.machines.{scene.name}.st_blocks"
    try:
        module = importlib.import_module(name)
    except ModuleNotFoundError as error:
        if error.name not in (name, f"scenes.machines.{scene.name}"):
            raise
        return {}
    blocks: dict[str, plc.st.External] = module.blocks(scene)
    return blocks


def check(name: str, programs: Sequence[str], maps: Sequence[str] = ()) -> int:
    """Check the ST programs ``programs`` for machine ``name`` without running them
    (:mod:`plc.st.check`): each error on standard error, then the summary; 1 if one had an
    error. The machine is built for its axes, I/O and blocks, and not run."""
    from plc.st.check import Report, check

    for program in programs:
        if not Path(program).exists():
            raise UserError.at(program, "", "no such file or folder", _PROGRAMS)
    scene = scenes.load(name, trace_every=0)
    mapping = _mapping(maps, scene.axes)
    report = Report()
    for program in programs:
        report.add(check(program, scene.axes, mapping, machine_blocks(scene)))
    for error in report.errors:
        print(error, file=sys.stderr)
    print(report.summary())
    return 1 if report.errors else 0


_PROGRAMS = "an ST file, a TwinCAT folder or source file, a PLCopen .xml"
"""What a PROGRAM of ``check`` (and ``--program`` of ``run``) is."""


def _mapping(maps: Sequence[str], axes: dict[str, Any]) -> dict[str, str]:
    """The ``--map NAME=AXIS`` options as a mapping; one without its NAME, ``=`` or AXIS, or
    naming no axis of ``axes``, is a mistake on the command line (UserError: exit status 2)."""
    from plc.st.runtime.program import check_mapping

    mapping: dict[str, str] = {}
    for option in maps:
        key, equals, target = option.partition("=")
        if not (key and equals and target):
            raise UserError.at(
                f"--map {option}", "", "not NAME=AXIS", "Pohon.Ax1=X (an axis) or Knife=S.DO0 (I/O)"
            )
        mapping[key] = target
    try:
        check_mapping("--map", axes, mapping)
    except plc.st.STError as error:
        raise UserError(str(error)) from None
    return mapping


def st_task(path: str) -> plc.st.Task | None:
    """The TASK an ST file (or a TwinCAT project, a PLCopen XML file) declares (its INTERVAL
    is the PLC period of the scene built for it).

    Raises:
        STError: the file cannot be read, or has a syntax error.
    """
    return plc.st.task_of_file(path)


def sweep(
    file: str,
    workers: int | None,
    address: str | None,
    out: str | None = None,
    overrides: Sequence[str] = (),
) -> int:
    """Run the sweep described in ``file`` (with ``overrides``, ``"key=value"``) showing its
    progress on standard error; write its table and plots (to ``out``: a directory or a .csv /
    .parquet file) and print what it found. Returns 1 if a scenario failed."""
    from scenes.tools.sweep import Progress, from_toml

    spec, options = from_toml(file, overrides)
    table_path = Path(options["out"])
    if out is not None:
        table_path = Path(out) if Path(out).suffix else Path(out) / table_path.name
        if table_path.suffix not in (".csv", ".parquet"):
            raise UserError.at("--out", "", f"{out!r}", "a directory or a .csv/.parquet file")
    workers = options["workers"] if workers is None else workers
    given = "--address" if address else file
    address = address or options["address"]
    total = len(spec.rows())
    where = address or ("serially" if workers == 0 else f"{workers or os.cpu_count()} workers")
    print(f"{Path(file).name}: {total} scenarios of {spec.scenario} ({where})", file=sys.stderr)
    progress = Progress(total, label=Path(file).name)

    def dashboard(link: str) -> None:
        print(f"Dask dashboard (the cluster's own progress): {link}", file=sys.stderr)

    try:
        table = spec.run(workers, address, progress=progress, on_cluster=dashboard)
    except OSError as error:  # no scheduler at that address
        raise UserError.at(
            given, "address", f"cannot reach {address} ({error})", "a running Dask scheduler"
        ) from None
    for path in spec.write(table, table_path):
        print(path)
    print(spec.summary(table))
    failed = int(table["error"].astype(bool).sum()) if "error" in table else 0
    return 1 if failed else 0


def _program_parsers(sub: Any) -> None:
    """The commands ``run`` (a demo or an ST program, headless) and ``check`` (ST programs
    translated, not run)."""
    run_parser = sub.add_parser("run", help="run a machine's demo program headless")
    run_parser.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
    run_parser.add_argument(
        "--program",
        help=(
            "an IEC 61131-3 Structured Text file to run (.st; a TwinCAT folder or a PLCopen "
            ".xml) instead of the demo: the machine starts as for the demo (its joints at the "
            "demo's start, every axis Disabled, not homed, POS 0), the program scans from the "
            "first PLC cycle (t = 0); after a run-time fault the run goes on until the axes "
            "rest, then reports"
        ),
    )
    run_parser.add_argument(
        "--pou",
        metavar="PROGRAM",
        help="the PROGRAM to run where the file has several (default: its TASK's, or its only one)",
    )
    _map_option(run_parser)
    run_parser.add_argument(
        "--timeout",
        type=float,
        default=300.0,
        help="simulated seconds at most (default 300); a program's BOOL done ends the run",
    )
    check_parser = sub.add_parser(
        "check",
        help="check ST programs for a machine without running them (each item's first error)",
    )
    check_parser.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
    check_parser.add_argument(
        "programs",
        nargs="+",
        metavar="PROGRAM",
        help=_PROGRAMS,
    )
    _map_option(check_parser)


def _map_option(parser: argparse.ArgumentParser) -> None:
    """The ``--map`` option of a command that binds a program's names to the machine."""
    parser.add_argument(
        "--map",
        action="append",
        default=[],
        metavar="NAME=AXIS",
        help="bind Pohon.Ax1=X (an axis) or Knife=S.DO0 (I/O)",
    )


def main(argv: list[str] | None = None) -> int:
    """Parse the command line and run the command."""
    parser = argparse.ArgumentParser(prog="python -m scenes", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    _program_parsers(sub)
    sub.add_parser("list", help="list the machines")
    plot_parser = sub.add_parser("plot", help="plot a trace file as PNG and HTML")
    plot_parser.add_argument("trace", help="a trace written by trace.to_csv or streamed (.npy)")
    plot_parser.add_argument("--out", help="output path without suffix (default: next to it)")
    _cam_parser(sub)
    sweep_parser = sub.add_parser("sweep", help="run a parameter sweep described in TOML")
    sweep_parser.add_argument("file", help="the sweep (scenario, grid, random, samples, seed)")
    sweep_parser.add_argument("--workers", type=int, help="local workers (0 = serial)")
    sweep_parser.add_argument("--address", help="a Dask scheduler to run on")
    sweep_parser.add_argument(
        "--out", help="where the table and plots go: a directory, or a .csv/.parquet file"
    )
    sweep_parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a key of the file (a TOML value): samples=5, grid.x=[1,2], random.y=[0,1]",
    )
    sweep_parser.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="NAME=VALUES",
        help="override a grid parameter: x=[1,2,3] or x=1,2,3",
    )
    _circle_parser(sub)
    _bridge_parser(sub)
    args = parser.parse_args(argv)
    try:
        return _command(args)
    except (UserError, plc.st.STError) as error:
        for line in error.lines:
            print(line, file=sys.stderr)
        return 2


def _command(args: argparse.Namespace) -> int:
    """Run the parsed command."""
    if args.command == "plot":
        from scenes.tools.plot import plot

        trace = Path(args.trace)
        for path in plot(trace, Path(args.out) if args.out else trace.with_suffix("")):
            print(path)
        return 0
    if args.command == "cam":
        return _cam(args)
    if args.command == "sweep":
        grid = [_listed(g) for g in args.grid]
        return sweep(args.file, args.workers, args.address, args.out, [*args.set, *grid])
    if args.command == "bridge":
        return _bridge(args)
    if args.command == "circle":
        return _circle(args)
    if args.command == "check":
        return check(args.name, args.programs, args.map)
    if args.command == "list":
        width = max(len(n) for n in scenes.MACHINES)
        for name in sorted(scenes.MACHINES):
            print(f"{name:<{width}}  {scenes.MACHINES[name].description}")
        return 0
    return run(args.name, args.timeout, args.program, args.map, args.pou)


def _cam_parser(sub: Any) -> None:
    cam = sub.add_parser(
        "cam",
        help="plot a cam table's profile as PNG: a table file, or the rotary knife's arguments",
    )
    cam.add_argument("table", nargs="?", help="a CSV cam table (master,slave[,velocity,...])")
    cam.add_argument("--not-periodic", action="store_true", help="the table does not repeat")
    cam.add_argument("--cut-length", type=float, help="rotary knife: piece length [mm]")
    cam.add_argument("--circumference", type=float, help="rotary knife: blade circle [mm]")
    cam.add_argument("--blades", type=int, default=1, help="rotary knife: blades (default 1)")
    cam.add_argument(
        "--sync-angle", type=float, default=0.0, help="rotary knife: drum angle in sync [°]"
    )
    cam.add_argument("--law", default="ModifiedSine", help="rotary knife: the law between cuts")
    cam.add_argument("--out", help="output path without suffix (default: next to the table)")


def _cam(args: argparse.Namespace) -> int:
    """Plot a table file or the rotary knife's cam."""
    from scenes.tools.cam_plot import checked, knife_table, plot_cam, read_table

    knife = args.cut_length is not None or args.circumference is not None
    if (args.table is not None) == knife:
        raise UserError.at(
            "python -m scenes cam",
            "",
            "a table file and the rotary knife's arguments" if knife else "nothing to plot",
            "a table file, or --cut-length and --circumference (--blades, --sync-angle, --law)",
        )
    if args.table is not None:
        table, lines = read_table(args.table)
        cam = checked(table, not args.not_periodic, args.table, lines)
        out = Path(args.out) if args.out else Path(args.table).with_suffix("")
    else:
        if args.cut_length is None or args.circumference is None:
            raise UserError.at(
                "python -m scenes cam",
                "",
                "the rotary knife needs both",
                "--cut-length and --circumference",
            )
        table = knife_table(
            args.cut_length, args.circumference, args.blades, args.sync_angle, args.law
        )
        cam = checked(table, True, "rotary knife", [])
        out = Path(args.out) if args.out else Path("rotary_knife")
    print(plot_cam(table, cam, out))
    return 0


def _circle_parser(sub: Any) -> None:
    from scenes.tools.circle import DIRECTIONS, PLANES

    circle = sub.add_parser("circle", help="the circle test of ISO 230-4 on two axes")
    circle.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
    circle.add_argument("--plane", default="XY", choices=sorted(PLANES), help="the two axes")
    circle.add_argument("--radius", type=float, default=50.0, help="nominal radius [mm]")
    circle.add_argument("--feed", type=float, default=1000.0, help="path velocity [mm/min]")
    circle.add_argument("--direction", default="both", choices=list(DIRECTIONS))
    circle.add_argument("--plot", help="write the polar plot to this PNG file")


def _circle(args: argparse.Namespace) -> int:
    """Run the circle test about the middle of the plane's axes' travel (between their software
    limits; linear axes in mm) from the demo's start otherwise; print its figures."""
    from scenes.tools.circle import PLANES, circle_test

    definition = scenes.definition(args.name)
    start = dict(definition.demo_start)
    for axis in PLANES[args.plane]:
        c = definition.axes[axis].constants if axis in definition.axes else None
        if c is not None and c.sw_limits_active:
            start[axis] = 0.5 * (c.LimPos + c.LimNeg) / 1000.0  # mm → m
    scene = scenes.load(args.name, start=start, trace_every=0)
    result = circle_test(scene, args.plane, args.radius, args.feed, args.direction)
    print(result.summary())
    if args.plot:
        from scenes.tools.circle import plot

        print(plot(result, args.plot))
    return 0


def _bridge_parser(sub: Any) -> None:
    """``bridge map NAME [--csv]``, ``bridge modbus NAME [--host H] [--port P] …`` and
    ``bridge opcua NAME [--host H] [--port P] … [--secure] [--certs DIR]``."""
    bridge = sub.add_parser("bridge", help="an external PLC drives a machine (Modbus TCP, OPC UA)")
    what = bridge.add_subparsers(dest="bridge", required=True)
    map_parser = what.add_parser("map", help="print the machine's register map (Markdown)")
    map_parser.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
    map_parser.add_argument("--csv", action="store_true", help="print CSV instead")
    modbus = what.add_parser("modbus", help="run the machine with its Modbus TCP server")
    opcua = what.add_parser("opcua", help="run the machine with its OPC UA server")
    modbus_help = (
        "loopback address to bind (another one needs --allow)",
        "a PLC's IP address accepted when --host is beyond loopback (repeat for more)",
    )
    opcua_help = (
        "address to bind (beyond loopback: encrypted sessions of user plc only)",
        "serve only this client IP address beyond loopback (repeat for more)",
    )
    for server, port, (host_help, allow_help) in (
        (modbus, 5020, modbus_help),
        (opcua, 4840, opcua_help),
    ):
        server.add_argument("name", choices=sorted(scenes.MACHINES), help="the machine")
        server.add_argument("--host", default="127.0.0.1", help=host_help)
        server.add_argument("--port", type=int, default=port, help="TCP port")
        server.add_argument("--speed", type=float, default=1.0, help="free-running: × real time")
        server.add_argument("--lockstep", action="store_true", help="advance on sim.target only")
        server.add_argument(
            "--allow", action="append", default=[], metavar="ADDRESS", help=allow_help
        )
    opcua.add_argument(
        "--secure",
        action="store_true",
        help="encrypted sessions of user plc only, also on loopback (password: MCL_OPCUA_PASSWORD)",
    )
    opcua.add_argument(
        "--certs",
        metavar="DIR",
        help="where the server's self-signed certificate is made and kept, a directory of mode "
        "0700 (~/.mcl-testbench/opcua)",
    )
    opcua.add_argument(
        "--password-file",
        metavar="FILE",
        help="the password of user plc in a file of mode 0600 (else MCL_OPCUA_PASSWORD)",
    )


def _bridge(args: argparse.Namespace) -> int:
    """Run a ``bridge`` command."""
    if args.bridge == "map":
        from scenes.bridge.table import tables_of

        tables = tables_of(scenes.definition(args.name))
        print("\n\n".join(t.csv() if args.csv else t.markdown() for t in tables))
        return 0
    speed = None if args.lockstep else args.speed
    if args.bridge == "opcua":
        from scenes.bridge import opcua

        certs = Path(args.certs) if args.certs else opcua.CERTS
        password = Path(args.password_file) if args.password_file else None
        return opcua.main(
            args.name, args.host, args.port, speed, args.allow, args.secure, certs, password
        )
    from scenes.bridge.modbus import main as modbus

    return modbus(args.name, args.host, args.port, speed, args.allow)


def _listed(item: str) -> str:
    """``"x=1,2,3"`` or ``"x=[1,2,3]"`` as the override ``"grid.x=[1,2,3]"``."""
    name, equals, values = item.partition("=")
    if not equals:
        return item
    return f"grid.{name}={values if values.strip().startswith('[') else f'[{values}]'}"


if __name__ == "__main__":
    sys.exit(main())

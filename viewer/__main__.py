"""Command line: ``python -m viewer [--scene NAME] [--host H] [--port P] [--speed S] [--no-demo]
[--programs DIR] [--map NAME=AXIS]``.

Starts the browser viewer on a scene (the gantry with its demo program by default), prints the
address to open (with the secret token of this start) and runs until Ctrl-C. Binds 127.0.0.1
unless ``--host`` says otherwise; beyond loopback it warns and names the real address to open.
Exits with status 2 and a message when the port is taken or the address cannot be served.
"""

from __future__ import annotations

__all__ = [
    "EXIT_PORT_IN_USE",
    "external_plc",
    "main",
    "parse_directory",
    "parse_fps",
    "parse_mapping",
    "parse_port",
    "parse_speed",
    "parser",
    "serve",
]

import argparse
import math
import signal
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from types import FrameType

from viewer.serving.server import DEFAULT_HOST, DEFAULT_PORT, PortInUseError, Viewer
from viewer.sim.external_plc import ExternalPlc
from viewer.sim.programs import ProgramCatalog
from viewer.sim.session import Session, choices

EXIT_PORT_IN_USE = 2
"""Exit status when the port is taken or the address cannot be served (also argparse's status
for bad arguments)."""


def parse_speed(text: str) -> float:
    """A ``--speed`` value: a factor > 0 (``0.1`` … ``10``) or ``max`` (as fast as possible).

    Raises:
        argparse.ArgumentTypeError: If the text is neither.
    """
    if text.strip().lower() in ("max", "inf", "fast"):
        return math.inf
    try:
        speed = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number > 0 or 'max', got {text!r}") from None
    if not (speed > 0.0 and math.isfinite(speed)):
        raise argparse.ArgumentTypeError(f"expected a number > 0 or 'max', got {text!r}")
    return speed


def parse_fps(text: str) -> float:
    """A ``--fps`` value: 1 … 60.

    Raises:
        argparse.ArgumentTypeError: If the text is not a number in that range.
    """
    try:
        fps = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number 1 … 60, got {text!r}") from None
    if not 1.0 <= fps <= 60.0:
        raise argparse.ArgumentTypeError(f"fps must be 1 … 60, got {text!r}")
    return fps


def parse_port(text: str) -> int:
    """A ``--port`` value: 1 … 65535.

    Raises:
        argparse.ArgumentTypeError: If the text is not a port number.
    """
    try:
        port = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a port number, got {text!r}") from None
    if not 1 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"port must be 1 … 65535, got {port}")
    return port


def parse_directory(text: str) -> Path:
    """A ``--programs`` value: a directory that exists.

    Raises:
        argparse.ArgumentTypeError: If it is no directory.
    """
    path = Path(text)
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"expected a directory of ST programs, got {text!r}")
    return path


def parse_mapping(text: str) -> tuple[str, str]:
    """A ``--map`` value: ``NAME=AXIS`` (``Pohon.Ax1=X``).

    Raises:
        argparse.ArgumentTypeError: If it is not of that form.
    """
    name, _, axis = text.partition("=")
    if not (name.strip() and axis.strip()):
        raise argparse.ArgumentTypeError(f"expected NAME=AXIS (e.g. Pohon.Ax1=X), got {text!r}")
    return name.strip(), axis.strip()


def parser() -> argparse.ArgumentParser:
    """The command line parser."""
    p = argparse.ArgumentParser(
        prog="python -m viewer",
        description="Watch and operate a testbench scene live in the browser (3-D, per-axis "
        "panels, live plot).",
    )
    p.add_argument(
        "--scene",
        default="gantry",
        choices=choices(),
        help="machine to show first, one of `python -m scenes list` (default: gantry)",
    )
    p.add_argument(
        "--host",
        default=DEFAULT_HOST,
        help=f"interface to bind (default: {DEFAULT_HOST}, this machine only; "
        "0.0.0.0 exposes the viewer to the network)",
    )
    p.add_argument(
        "--port", type=parse_port, default=DEFAULT_PORT, help=f"TCP port (default {DEFAULT_PORT})"
    )
    p.add_argument(
        "--speed",
        type=parse_speed,
        default=1.0,
        help="simulated seconds per wall second, e.g. 0.1 … 10, or 'max' (default 1)",
    )
    p.add_argument("--no-demo", action="store_true", help="do not start the scene's demo program")
    p.add_argument(
        "--fps",
        type=parse_fps,
        default=30.0,
        help="3-D updates per second, 1 … 60 (default 30; at most 10 while a page has no GPU)",
    )
    p.add_argument(
        "--no-token",
        action="store_true",
        help="serve without the secret token (loopback only; beyond loopback it is mandatory)",
    )
    p.add_argument(
        "--allow-host",
        action="append",
        default=[],
        metavar="NAME",
        help="a further host name the viewer may be reached under (e.g. a DNS name); repeatable",
    )
    _add_programs(p)
    _add_external_plc(p)
    return p


def _add_programs(p: argparse.ArgumentParser) -> None:
    """The ST programs the Demo folder offers and their names' bindings."""
    p.add_argument(
        "--programs",
        type=parse_directory,
        action="append",
        default=[],
        metavar="DIR",
        help="a directory whose programs the Demo folder offers (read at start): *.st, PLCopen "
        "*.xml, TwinCAT project folders; repeatable",
    )
    p.add_argument(
        "--map",
        type=parse_mapping,
        action="append",
        default=[],
        metavar="NAME=AXIS",
        help="bind an ST program's AXIS_REF or I/O name to the machine's (Pohon.Ax1=X); repeatable",
    )


def _add_external_plc(p: argparse.ArgumentParser) -> None:
    """The Modbus TCP or OPC UA server an external PLC drives the machine through."""
    p.add_argument(
        "--modbus",
        type=parse_port,
        metavar="PORT",
        help="serve the machine to an external PLC over Modbus TCP on PORT (the bridge's register "
        "map, `python -m scenes bridge map SCENE`); it is in control while its Program entry runs",
    )
    p.add_argument(
        "--modbus-host",
        default=DEFAULT_HOST,
        metavar="HOST",
        help=f"interface of the Modbus server (default {DEFAULT_HOST}; beyond loopback it needs "
        "--modbus-allow)",
    )
    p.add_argument(
        "--modbus-allow",
        action="append",
        default=[],
        metavar="ADDR",
        help="a PLC's IP address the Modbus server accepts beyond loopback; repeatable",
    )
    p.add_argument(
        "--opcua",
        type=parse_port,
        metavar="PORT",
        help="serve the machine to an external PLC over OPC UA on PORT instead (the bridge's node "
        "tree, docs/bridge.md); it is in control while its Program entry runs",
    )
    p.add_argument(
        "--opcua-host",
        default=DEFAULT_HOST,
        metavar="HOST",
        help=f"interface of the OPC UA server (default {DEFAULT_HOST}; beyond loopback encrypted "
        "sessions of user plc only, the password from MCL_OPCUA_PASSWORD)",
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the viewer until Ctrl-C (or SIGTERM).

    Args:
        argv: Arguments without the program name (default: ``sys.argv[1:]``).

    Returns:
        Exit status: 0 after Ctrl-C, 2 if the port is taken.
    """
    args = parser().parse_args(argv)
    try:
        return serve(args)
    except KeyboardInterrupt:  # while starting or stopping; the viewer cleans up after itself
        print("viewer: interrupted", file=sys.stderr, flush=True)
        return 0


def serve(args: argparse.Namespace) -> int:
    """Start the viewer as ``args`` say and serve until Ctrl-C or SIGTERM.

    Args:
        args: Parsed command line (see :func:`parser`).

    Returns:
        Exit status: 0 when stopped, 2 if the port is taken or the address cannot be served.
    """
    try:
        plc = external_plc(args)
    except (ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_PORT_IN_USE
    programs = ProgramCatalog(args.programs, dict(args.map), external=plc)
    session = Session(args.scene, speed=args.speed, programs=programs)
    if plc is not None:
        session.programs.choose(plc.label)  # Run demo (and the start) hands it the machine
    try:
        viewer = Viewer(
            args.scene,
            session=session,
            host=args.host,
            port=args.port,
            speed=args.speed,
            demo=not args.no_demo,
            token=not args.no_token,
            fps=args.fps,
            allowed_hosts=args.allow_host,
        )
    except ValueError as exc:  # --no-token beyond loopback
        _close(plc)
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_PORT_IN_USE
    except PortInUseError as exc:
        _close(plc)
        print(f"error: {exc.strerror}", file=sys.stderr)
        return EXIT_PORT_IN_USE
    except OSError as exc:  # unknown host, another machine's address, privileged port
        _close(plc)
        print(f"error: cannot serve on {args.host}:{args.port}: {exc}", file=sys.stderr)
        return EXIT_PORT_IN_USE
    done = threading.Event()

    def on_terminate(signum: int, frame: FrameType | None) -> None:
        done.set()

    in_main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, on_terminate) if in_main_thread else None
    try:
        print(f"viewer: {args.scene} at {viewer.url}  (Ctrl-C to stop)", flush=True)
        if plc is not None:
            print(f"viewer: {plc.banner}", flush=True)
        if viewer.exposed:
            print(viewer.warning(), file=sys.stderr, flush=True)
        if not args.no_demo and not viewer.session.demo_available():
            print(f"viewer: scene {args.scene!r} has no demo program", flush=True)
        while not done.wait(0.5):
            pass
    except KeyboardInterrupt:
        pass
    finally:
        if in_main_thread:
            signal.signal(signal.SIGTERM, previous)
        print("viewer: stopping", flush=True)
        viewer.close()
        _close(plc)
    return 0


def external_plc(args: argparse.Namespace) -> ExternalPlc | None:
    """The external PLC's Modbus or OPC UA server that ``args`` ask for (None: neither
    ``--modbus`` nor ``--opcua``).

    Raises:
        ValueError: both asked for; a host beyond loopback without ``--modbus-allow`` or the
            OPC UA password; a bad address.
        OSError: the port cannot be served.
    """
    if args.modbus is not None and args.opcua is not None:
        raise ValueError("one external PLC at a time: give --modbus PORT or --opcua PORT")
    if args.opcua is not None:
        return ExternalPlc(args.scene, args.opcua_host, args.opcua, protocol="opcua")
    if args.modbus is None:
        return None
    return ExternalPlc(args.scene, args.modbus_host, args.modbus, args.modbus_allow)


def _close(plc: ExternalPlc | None) -> None:
    if plc is not None:
        plc.close()


if __name__ == "__main__":
    sys.exit(main())

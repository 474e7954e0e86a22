"""Build the compiled modules: ``python -m mcl.build`` (see :mod:`mcl.native`).

The modules are compiled beside their sources, wherever the packages are: in a checkout (``make
setup`` does it) or in an installed copy (``pip install .`` then ``python -m mcl.build``; it needs
mypy and a C compiler). Name the packages beside mcl whose declared modules compile too
(``python -m mcl.build mcl scenes``; by default those of the last build). ``--status`` prints
which mode a new process runs in; ``--clean`` removes the build; ``--verbose`` shows mypyc's and
the C compiler's own output.
"""

from __future__ import annotations

__all__ = ["build", "clean", "main"]

import argparse
import contextlib
import json
import os
import shutil
import sys
import tempfile
import threading
import time
from collections.abc import Iterator, Sequence
from pathlib import Path

from mcl.native import (
    GROUP,
    MANIFEST,
    ROOT,
    _recorded_packages,
    compiled_files,
    compiled_sources,
    digest,
    mode,
    reset,
    stale_sources,
)


def _fingerprint() -> str:
    """What else a compiled module depends on: the interpreter and the mypy release."""
    try:
        from mypy.version import __version__ as mypy_version
    except ImportError:  # pragma: no cover - mypy is installed with the test extras
        mypy_version = "?"
    return f"{sys.implementation.cache_tag} {sys.version.split()[0]} mypy {mypy_version}"


@contextlib.contextmanager
def _quiet(log: Path, verbose: bool) -> Iterator[None]:
    """Send what mypyc and the C compiler print (file descriptors 1 and 2) to ``log``."""
    if verbose:
        yield
        return
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with log.open("w") as sink:
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        try:
            yield
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


class _Progress:
    """One line on the terminal: the stage and the seconds since the build began."""

    def __init__(self, out: int) -> None:
        self.out, self.start, self.stage = out, time.monotonic(), ""
        self.tty = os.isatty(out)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._tick, daemon=True)

    def show(self, stage: str) -> None:
        self.stage = stage
        self._write(newline=not self.tty)
        if not self._thread.is_alive():
            self._thread.start()

    def _write(self, newline: bool) -> None:
        line = f"  {self.stage} … {time.monotonic() - self.start:.0f} s"
        os.write(self.out, (f"\r{line:<70}" if self.tty else f"{line}\n").encode())
        if newline and self.tty:
            os.write(self.out, b"\n")

    def _tick(self) -> None:
        while not self._stop.wait(1.0 if self.tty else 30.0):
            self._write(newline=False)

    def close(self) -> None:
        self._stop.set()
        if self.tty:
            os.write(self.out, b"\n")


def build(packages: Sequence[str], verbose: bool = False) -> str:
    """Compile mcl and the modules ``packages`` declare (:func:`compiled_sources`) beside their
    sources and record their hashes.

    The record is removed first and written last, and every compiled file replaces the old one
    in one rename, so a process started meanwhile runs pure Python and one already running keeps
    its modules.

    Returns:
        A one-line summary of what mypyc and the compiler remarked.

    Raises:
        SystemExit: mypyc or the C compiler failed (the message says why, with the end of their
            output); the build is then incomplete and not used.
    """
    from mypyc.build import mypycify
    from setuptools import setup

    others = [p for p in packages if p != "mcl"]
    sources = compiled_sources(others)
    digests = {p.relative_to(ROOT).as_posix(): digest(p) for p in sources}
    MANIFEST.unlink(missing_ok=True)
    out = os.dup(1)
    progress = _Progress(out)
    cwd = Path.cwd()
    os.chdir(ROOT)  # module names follow the paths relative to the packages' folder
    try:
        with tempfile.TemporaryDirectory() as temp:
            log = Path(temp) / "build.log"
            try:
                with _quiet(log, verbose):
                    progress.show(f"mypyc: type-checking and translating {len(sources)} modules")
                    extensions = mypycify(
                        [p.relative_to(ROOT).as_posix() for p in sources],
                        opt_level="3",
                        group_name=GROUP,
                        target_dir=str(Path(temp) / "c"),
                    )
                    progress.show("C compiler: one shared library and a module per source")
                    setup(
                        name=GROUP,
                        ext_modules=extensions,
                        script_args=["-q", "build_ext", "--build-lib", f"{temp}/lib"],
                        script_name="setup.py",
                    )
            except (Exception, SystemExit) as error:
                tail = log.read_text(errors="replace").splitlines()[-25:] if log.exists() else []
                raise SystemExit("\n".join([f"compiled build failed: {error}", *tail])) from None
            _install(Path(temp) / "lib", compiled_files(others))
            remarks = _remarks(log)
    finally:
        progress.close()
        os.close(out)
        os.chdir(cwd)
    MANIFEST.write_text(
        json.dumps(
            {
                "python": sys.implementation.cache_tag,
                "tool": _fingerprint(),
                "packages": others,
                "sources": digests,
            },
            indent=1,
        )
    )
    modules = {line.split(":", 1)[0] for line in remarks}
    return (
        f"built in {time.monotonic() - progress.start:.0f} s; mypyc made {len(remarks)} remarks "
        f"on {len(modules)} modules (defaults and comprehensions it handles in the interpreter's "
        "way; `python -m mcl.build --verbose` lists them)"
        if remarks
        else f"built in {time.monotonic() - progress.start:.0f} s"
    )


def _install(built: Path, targets: list[Path]) -> None:
    """Put each compiled file beside its source, each in one rename (a running process keeps
    the file it has open)."""
    for target in targets:
        shutil.copyfile(built / target.relative_to(ROOT), f"{target}.new")
        os.replace(f"{target}.new", target)


def _remarks(log: Path) -> list[str]:
    """The warnings mypyc and the C compiler wrote to ``log``."""
    if not log.exists():
        return []
    return [line for line in log.read_text(errors="replace").splitlines() if "warning:" in line]


def clean() -> None:
    """Remove the compiled modules, their shared library and the record."""
    for path in [*compiled_files(), MANIFEST]:
        path.unlink(missing_ok=True)


def main(argv: list[str] | None = None) -> int:
    """Build, or print the mode (``--status``)."""
    parser = argparse.ArgumentParser(prog="python -m mcl.build", description=__doc__)
    parser.add_argument("--status", action="store_true", help="print the active mode and exit")
    parser.add_argument("--clean", action="store_true", help="remove the compiled build")
    parser.add_argument(
        "--if-stale",
        action="store_true",
        help="build only when there is none or a compiled source changed, and a C compiler exists",
    )
    parser.add_argument(
        "--verbose", action="store_true", help="show what mypyc and the C compiler print"
    )
    parser.add_argument(
        "packages",
        nargs="*",
        help="the packages beside mcl whose declared modules compile too (default: those of the "
        "last build), e.g. `mcl scenes`",
    )
    args = parser.parse_args(argv)
    packages = [p for p in args.packages if p != "mcl"] if args.packages else _recorded_packages()
    same = sorted(packages) == sorted(_recorded_packages())
    if args.clean:
        clean()
    elif args.if_stale and same and stale_sources() == []:
        pass
    elif args.if_stale and not (shutil.which("cc") or shutil.which("gcc")):
        print("no C compiler found: no compiled build")
    elif not args.status:
        print(f"building the compiled modules (mypyc) in {ROOT} …", flush=True)
        try:
            print(build(packages, args.verbose))
        except SystemExit as failure:
            if not args.if_stale:
                raise
            print(f"{failure}\nrunning pure Python")  # setup goes on without the build
        reset()
    print(f"mcl runs {mode()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Build the compiled modules: ``python -m mcl.build`` (see :mod:`mcl.native`).

``--status`` prints which mode a new process runs in; ``--clean`` removes the build.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path

from mcl.native import (
    BUILD,
    GROUP,
    MANIFEST,
    ROOT,
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


def build() -> None:
    """Compile :func:`compiled_sources` into :data:`BUILD` and record their hashes.

    Raises:
        SystemExit: mypyc or the C compiler failed (the message says why); the previous build
            is removed, so nothing stale stays behind.
    """
    from mypyc.build import mypycify
    from setuptools import setup

    sources = compiled_sources()
    digests = {str(p.relative_to(ROOT)): digest(p) for p in sources}
    shutil.rmtree(BUILD, ignore_errors=True)
    BUILD.mkdir(parents=True)
    cwd = Path.cwd()
    os.chdir(ROOT)  # module names follow the paths relative to the checkout
    try:
        with tempfile.TemporaryDirectory() as temp:
            extensions = mypycify(
                [str(p.relative_to(ROOT)) for p in sources],
                opt_level="3",
                group_name=GROUP,
                target_dir=str(Path(temp) / "c"),
            )
            setup(
                name=GROUP,
                ext_modules=extensions,
                script_args=["-q", "build_ext", "--build-lib", str(BUILD), "--build-temp", temp],
            )
    except (Exception, SystemExit) as error:
        shutil.rmtree(BUILD, ignore_errors=True)
        raise SystemExit(f"compiled build failed: {error}") from None
    finally:
        os.chdir(cwd)
    MANIFEST.write_text(
        json.dumps(
            {"python": sys.implementation.cache_tag, "tool": _fingerprint(), "sources": digests},
            indent=1,
        )
    )


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
    args = parser.parse_args(argv)
    if args.clean:
        shutil.rmtree(BUILD.parent, ignore_errors=True)
    elif args.if_stale and stale_sources() == []:
        pass
    elif args.if_stale and not (shutil.which("cc") or shutil.which("gcc")):
        print("no C compiler found: no compiled build")
    elif not args.status:
        print("building the compiled modules (mypyc) …", flush=True)
        try:
            build()
        except SystemExit as failure:
            if not args.if_stale:
                raise
            print(f"{failure}; running pure Python")  # setup goes on without the build
        reset()
    print(f"mcl runs {mode()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

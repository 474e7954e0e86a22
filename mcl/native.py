"""Which modules run compiled: the optional mypyc build of mcl and of the per-step Python of scenes.

``python -m mcl.build`` compiles the modules of :func:`compiled_sources` from the same source into
extension modules beside their sources (``mcl/axis.cpython-311-x86_64-linux-gnu.so`` next to
``mcl/axis.py``, their shared library as ``mcl/native_lib__mypyc….so``), in a checkout and in an
installed copy of the packages alike, and records a hash of every source it compiled in
``mcl/compiled.json``. Python's import system prefers an extension module to a source of the same
name, so a fresh build is used wherever the packages are imported from, with nothing added to
``sys.path``. At import, :func:`activate` (called by the ``mcl`` and ``scenes`` packages) checks
the record: when a recorded source changed, when the build is incomplete or missing, or with
``MCL_PURE_PYTHON=1``, it gives the package's folders the interpreter's own file finder with the
source loaders only, so an edited source is never shadowed by a stale compiled module; the package
then runs in pure Python and says so once.
"""

from __future__ import annotations

__all__ = [
    "DECLARATION",
    "GROUP",
    "MANIFEST",
    "NOT_COMPILED",
    "ROOT",
    "activate",
    "compiled_files",
    "compiled_sources",
    "declared",
    "digest",
    "extension_of",
    "forced_pure",
    "mode",
    "reset",
    "stale_sources",
]

import ast
import hashlib
import json
import os
import sys
import warnings
from collections.abc import Sequence
from importlib.machinery import (
    BYTECODE_SUFFIXES,
    EXTENSION_SUFFIXES,
    SOURCE_SUFFIXES,
    FileFinder,
    SourceFileLoader,
    SourcelessFileLoader,
)
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
"""The folder holding the ``mcl`` and ``scenes`` packages (a checkout, or ``site-packages``)."""
MANIFEST = ROOT / "mcl" / "compiled.json"
"""The build's record: interpreter and a hash of every compiled source."""
GROUP = "mcl.native_lib"
"""Name of the shared library of the compiled modules (a module of the ``mcl`` package)."""

NOT_COMPILED = (
    "__init__.py",
    "__main__.py",
    "build.py",
    "extras.py",
    "native.py",
    "reference.py",
    "reference_intro.py",
    "errors.py",
    "io.py",
)
"""Modules of mcl that stay interpreted: package glue (and its check of the extras), tools, the
error texts (an exception class derived from a builtin cannot be a native class) and the I/O
protocol (runtime-checkable)."""


DECLARATION = "COMPILED_MODULES"
"""The name of the tuple in a package's ``__init__.py`` that lists which of its modules compile."""


def declared(package: Path) -> list[Path]:
    """The sources a package and its subpackages declare for the compiled build: the modules named
    by a literal ``COMPILED_MODULES = ("plant", ...)`` in each ``__init__.py`` (read, not
    imported)."""
    sources = []
    for init in sorted(package.rglob("__init__.py")):
        for node in ast.parse(init.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.Assign) and any(
                isinstance(target, ast.Name) and target.id == DECLARATION for target in node.targets
            ):
                names = ast.literal_eval(node.value)
                sources += [init.with_name(f"{name}.py") for name in names]
    return sources


def compiled_sources(packages: Sequence[str] | None = None) -> list[Path]:
    """The source files that the compiled build covers: every module of mcl but
    :data:`NOT_COMPILED`, and those the other ``packages`` declare (:func:`declared`); by
    default the packages of the last build.

    Raises:
        ValueError: a package is not beside ``mcl`` (the message lists what is).
    """
    names = _recorded_packages() if packages is None else [p for p in packages if p != "mcl"]
    mcl = sorted(p for p in (ROOT / "mcl").glob("*.py") if p.name not in NOT_COMPILED)
    others = []
    for name in names:
        if not (ROOT / name / "__init__.py").is_file():
            raise ValueError(f"no package {name!r} beside mcl in {ROOT}")
        others += declared(ROOT / name)
    return [*mcl, *others]


def _recorded_packages() -> list[str]:
    """The packages besides mcl that the last build compiled (none without a build)."""
    try:
        packages: list[str] = json.loads(MANIFEST.read_text()).get("packages", [])
    except (OSError, ValueError):
        return []
    return packages


def extension_of(source: Path) -> Path:
    """The compiled module that stands beside ``source`` (``axis.py`` → ``axis.cpython-….so``)."""
    return source.with_name(source.stem + EXTENSION_SUFFIXES[0])


def compiled_files(packages: Sequence[str] | None = None) -> list[Path]:
    """The compiled files a build (of ``packages``, by default those of the last build) puts
    beside the sources: a module each, their shared library."""
    package, name = GROUP.split(".")
    library = ROOT / package / f"{name}__mypyc{EXTENSION_SUFFIXES[0]}"
    return [*(extension_of(p) for p in compiled_sources(packages)), library]


def digest(path: Path) -> str:
    """SHA-256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


_state: dict[str, object] = {}


def stale_sources() -> list[str] | None:
    """What makes the build unusable, one phrase each (empty: fresh): compiled sources edited
    since the build, compiled modules missing, another interpreter; None when there is no build."""
    if "stale" in _state:
        return _state["stale"]  # type: ignore[return-value]
    stale: list[str] | None
    try:
        manifest = json.loads(MANIFEST.read_text())
    except (OSError, ValueError):
        stale = None
    else:
        recorded: dict[str, str] = manifest.get("sources", {})
        current = {p.relative_to(ROOT).as_posix(): p for p in compiled_sources()}
        stale = [f"{name} added or removed" for name in sorted(set(recorded) ^ set(current))]
        stale += [
            f"{name} changed"
            for name, path in current.items()
            if name in recorded and (not path.is_file() or digest(path) != recorded[name])
        ]
        stale += [
            f"{p.relative_to(ROOT).as_posix()} missing" for p in compiled_files() if not p.is_file()
        ]
        if manifest.get("python") != sys.implementation.cache_tag:
            stale.append(f"built for {manifest.get('python')}")
    _state["stale"] = stale
    return stale


def forced_pure() -> bool:
    """``MCL_PURE_PYTHON`` is set (to anything but 0)."""
    return os.environ.get("MCL_PURE_PYTHON", "") not in ("", "0")


def activate(package: str, path: list[str]) -> bool:
    """Decide whether ``package`` runs compiled; otherwise make it import its sources only.

    Args:
        package: ``"mcl"`` or ``"scenes"``.
        path: the package's ``__path__``.

    Returns:
        True when the package runs compiled.
    """
    stale = None if forced_pure() else stale_sources()
    if stale == []:
        return True
    if stale and not _state.get("warned"):
        _state["warned"] = True
        warnings.warn(
            f"the compiled build is out of date ({', '.join(stale[:3])}"
            f"{' …' if len(stale) > 3 else ''}): running pure Python; rebuild with "
            f"`python -m mcl.build` (or `make setup`)",
            RuntimeWarning,
            stacklevel=3,
        )
    base = Path(path[0]).resolve()
    inside = {  # the package's own declarations: without a build record (a build under way)
        # the modules an earlier build left must not load either
        p.parent.relative_to(base).parts
        for p in compiled_sources([package])
        if p.is_relative_to(base)
    }
    for folder in [*path, *(os.path.join(path[0], *parts) for parts in sorted(inside) if parts)]:
        sys.path_importer_cache[folder] = FileFinder(
            folder,
            (SourceFileLoader, SOURCE_SUFFIXES),
            (SourcelessFileLoader, BYTECODE_SUFFIXES),
        )
    return False


def mode() -> str:
    """The mode a new process runs in: ``"compiled"`` or ``"pure Python"``, with the reason."""
    if forced_pure():
        return "pure Python (MCL_PURE_PYTHON is set)"
    stale = stale_sources()
    if stale is None:
        return "pure Python (no compiled build; `make setup` builds one where a C compiler exists)"
    if stale:
        return f"pure Python (the compiled build is out of date: {', '.join(stale[:3])})"
    return f"compiled ({len(compiled_sources())} modules beside their sources in {ROOT})"


def reset() -> None:
    """Forget what was found out about the build (after building)."""
    _state.clear()

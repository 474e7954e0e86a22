"""Which modules run compiled: the optional mypyc build of mcl and of the per-step Python of scenes.

``python -m mcl.build`` compiles the modules of :func:`compiled_sources` from the same source into
``.build/compiled/`` (next to the checkout, never beside the sources) and records a hash of every
source it compiled. At import, :func:`activate` (called by the ``mcl`` and ``scenes`` packages)
puts the compiled modules in front of the sources only while every recorded source is unchanged:
an edited source is never shadowed by a stale compiled module; the package then runs in pure
Python and says so once. ``MCL_PURE_PYTHON=1`` forces pure Python.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
"""The checkout (the folder holding ``mcl/`` and ``scenes/``)."""
BUILD = ROOT / ".build" / "compiled"
"""Where the compiled modules go."""
MANIFEST = BUILD / "manifest.json"
GROUP = "mcl_native"
"""Name of the shared library of the compiled modules."""

NOT_COMPILED = (
    "__init__.py",
    "__main__.py",
    "build.py",
    "native.py",
    "reference.py",
    "errors.py",
    "io.py",
)
"""Modules of mcl that stay interpreted: package glue, tools, the error texts (an exception class
derived from a builtin cannot be a native class) and the I/O protocol (runtime-checkable)."""


def compiled_sources() -> list[Path]:
    """The source files that the compiled build covers: every module of mcl but
    :data:`NOT_COMPILED`, the per-physics-step modules of scenes (plant, drives, the devices of
    the flying shear and the hydraulics) and its PLC procedures (run every scan)."""
    mcl = sorted(p for p in (ROOT / "mcl").glob("*.py") if p.name not in NOT_COMPILED)
    scenes = ("plant.py", "drives.py", "procedures.py", "shear_devices.py", "hydraulics.py")
    return [*mcl, *(ROOT / "scenes" / name for name in scenes)]


def digest(path: Path) -> str:
    """SHA-256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


_state: dict[str, object] = {}


def stale_sources() -> list[str] | None:
    """The compiled sources edited since the build (empty: fresh); None when there is no build."""
    if "stale" in _state:
        return _state["stale"]  # type: ignore[return-value]
    stale: list[str] | None
    try:
        manifest = json.loads(MANIFEST.read_text())
    except (OSError, ValueError):
        stale = None
    else:
        recorded: dict[str, str] = manifest.get("sources", {})
        current = {str(p.relative_to(ROOT)): p for p in compiled_sources()}
        stale = sorted(set(recorded) ^ set(current))
        stale += [
            name
            for name, path in current.items()
            if name in recorded and (not path.is_file() or digest(path) != recorded[name])
        ]
        if manifest.get("python") != sys.implementation.cache_tag:
            stale.append(f"(built for {manifest.get('python')})")
    _state["stale"] = stale
    return stale


def activate(package: str, path: list[str]) -> bool:
    """Put the compiled modules of ``package`` first on its ``__path__`` when the build is fresh.

    Args:
        package: ``"mcl"`` or ``"scenes"``.
        path: the package's ``__path__`` (changed in place).

    Returns:
        True when the package runs compiled.
    """
    if os.environ.get("MCL_PURE_PYTHON", "") not in ("", "0"):
        return False
    stale = stale_sources()
    if stale is None:
        return False
    if stale:
        if not _state.get("warned"):
            _state["warned"] = True
            warnings.warn(
                f"the compiled build is older than {', '.join(stale[:3])}"
                f"{' …' if len(stale) > 3 else ''}: running pure Python; rebuild with "
                f"`python -m mcl.build` (or `make setup`)",
                RuntimeWarning,
                stacklevel=3,
            )
        return False
    folder = str(BUILD / package)
    if folder not in path:
        path.insert(0, folder)
    if str(BUILD) not in sys.path:
        sys.path.append(str(BUILD))  # the shared library of the compiled modules
    return True


def mode() -> str:
    """The mode a new process runs in: ``"compiled"`` or ``"pure Python"``, with the reason."""
    if os.environ.get("MCL_PURE_PYTHON", "") not in ("", "0"):
        return "pure Python (MCL_PURE_PYTHON is set)"
    stale = stale_sources()
    if stale is None:
        return "pure Python (no compiled build; `make setup` builds one where a C compiler exists)"
    if stale:
        return f"pure Python (the compiled build is stale: {', '.join(stale[:3])})"
    return f"compiled ({len(compiled_sources())} modules in {BUILD.relative_to(ROOT)})"


def reset() -> None:
    """Forget what was found out about the build (after building)."""
    _state.clear()

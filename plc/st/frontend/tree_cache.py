"""Parsed ST trees kept on disk, so a file parses once (blark's Earley parser takes seconds for
a program of a few hundred lines; loading the kept tree takes milliseconds).

A tree is kept under ``$MCL_ST_CACHE`` (default ``$XDG_CACHE_HOME/mcl/st``, else
``~/.cache/mcl/st``; ``MCL_ST_CACHE=`` switches the cache off), in a file named by the SHA-256 of
the source, its file name and the parser (blark's and lark's versions, this package's grammar
and transformer), like Python's own ``__pycache__``: the directory is the user's, created
private (0700). A file that does not load is parsed again and replaced.
"""

from __future__ import annotations

__all__ = ["cached", "directory", "keep", "key", "load", "store", "versions"]

import functools
import hashlib
import os
import pickle
import tempfile
from collections.abc import Callable
from importlib import metadata
from pathlib import Path
from typing import IO, Any


def directory() -> Path | None:
    """Where trees are kept (None: the cache is off)."""
    configured = os.environ.get("MCL_ST_CACHE")
    if configured is not None:
        return Path(configured).expanduser() if configured.strip() else None
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "mcl" / "st"


def key(source: str, filename: str, parser: bytes) -> str:
    """The name of the kept tree of ``source`` (from ``filename``) parsed by ``parser`` (bytes
    that change when the grammar or the transformer does)."""
    digest = hashlib.sha256()
    for part in (versions(), parser, filename.encode(), source.encode()):
        digest.update(len(part).to_bytes(8, "little") + part)
    return digest.hexdigest()


def load(name: str, kind: str = "pickle") -> Any:
    """The tree kept as ``name`` (of ``kind``: a tree, or ``cut`` a source's cut into items,
    ``lines`` a TwinCAT file's lines); None if there is none, or it does not load (truncated,
    corrupt, from another Python): it is parsed again and replaced."""
    folder = directory()
    if folder is None:
        return None
    try:
        with (folder / f"{name}.{kind}").open("rb") as file:
            return pickle.load(file)
    except Exception:  # missing, truncated, corrupt, or from another Python: parse again
        return None


def store(name: str, tree: Any, kind: str = "pickle") -> None:
    """Keep ``tree`` as ``name`` of ``kind`` (atomically: a reader sees the old file or the
    new one; on a read-only or full disk, nothing is kept)."""
    folder = directory()
    if folder is not None:
        keep(
            folder / f"{name}.{kind}",
            lambda file: pickle.dump(tree, file, protocol=pickle.HIGHEST_PROTOCOL),
        )


def keep(path: Path, write: Callable[[IO[bytes]], Any]) -> None:
    """Write a file of the cache with ``write`` (atomically; on a read-only or full disk, or
    if ``write`` cannot pickle, nothing is kept)."""
    temporary: str | None = None
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
        with os.fdopen(handle, "wb") as file:
            write(file)
        os.replace(temporary, path)
    except (OSError, pickle.PicklingError):  # a read-only or full disk: not kept
        if temporary is not None:
            Path(temporary).unlink(missing_ok=True)


@functools.cache
def versions() -> bytes:
    """blark's and lark's versions (read once: the package metadata is slow to read)."""
    return f"{metadata.version('blark')} {metadata.version('lark')}".encode()


def cached(name: str, make: Callable[[], Any], kind: str = "pickle") -> Any:
    """The tree kept as ``name`` of ``kind``, or ``make()`` (kept for the next time; an
    exception of ``make`` passes through and nothing is kept)."""
    tree = load(name, kind)
    if tree is None:
        tree = make()
        store(name, tree, kind)
    return tree

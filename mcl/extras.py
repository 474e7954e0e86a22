"""The optional parts of the distribution (its extras) and the one-line hint when one is missing.

``pip install mcl-testbench`` installs the core, what :mod:`mcl` and :mod:`plc` need; an extra
adds a part (``pip install 'mcl-testbench[physics]'``). A package of a part calls
:func:`require` before it imports its extra's packages, so importing it without them raises one
:class:`MissingExtra` line that says which extra to install::

    ImportError: plc.st needs the [st] extra: pip install 'mcl-testbench[st]'

:data:`PACKAGES` and :data:`INCLUDES` mirror ``[project.optional-dependencies]`` of
``pyproject.toml`` (a test keeps them equal).
"""

from __future__ import annotations

import importlib.util

__all__ = [
    "DISTRIBUTION",
    "INCLUDES",
    "PACKAGES",
    "MissingExtra",
    "installed",
    "missing",
    "packages",
    "require",
]

DISTRIBUTION = "mcl-testbench"
"""The name the project is installed by."""

PACKAGES: dict[str, tuple[str, ...]] = {
    "st": ("blark", "lark"),
    "physics": ("mujoco", "dm_control"),
    "bridge": ("pymodbus", "asyncua"),
    "plot": ("matplotlib", "pandas"),
    "sweep": ("pyarrow", "dask", "distributed"),
    "viewer": ("viser",),
}
"""The packages (import names) each extra adds."""

INCLUDES: dict[str, tuple[str, ...]] = {
    "st": (),
    "physics": ("st",),
    "bridge": ("physics",),
    "plot": ("physics",),
    "sweep": ("plot",),
    "viewer": ("physics", "bridge"),
}
"""The extras each extra builds on (installed with it)."""


class MissingExtra(ImportError):
    """A part was imported without its extra: the message says which extra to install."""


def packages(extra: str) -> list[str]:
    """The packages of ``extra`` and of the extras it builds on, each once.

    Raises:
        KeyError: ``extra`` is not one of :data:`PACKAGES`.
    """
    names = [*PACKAGES[extra]]
    for included in INCLUDES[extra]:
        names += packages(included)
    return list(dict.fromkeys(names))


def missing(extra: str) -> list[str]:
    """The packages of ``extra`` and of the extras it builds on that are not installed."""
    return [name for name in packages(extra) if importlib.util.find_spec(name) is None]


def installed(extra: str) -> bool:
    """Whether ``extra`` and every extra it builds on are installed."""
    return not missing(extra)


def require(part: str, extra: str) -> None:
    """Check that the part ``part`` (a package's dotted name) can be imported.

    Raises:
        MissingExtra: a package of ``extra`` is not installed, with the one line
            ``part needs the [extra] extra: pip install 'mcl-testbench[extra]'``.
    """
    absent = missing(extra)
    if absent:
        raise MissingExtra(
            f"{part} needs the [{extra}] extra: pip install '{DISTRIBUTION}[{extra}]'",
            name=absent[0],
        ) from None

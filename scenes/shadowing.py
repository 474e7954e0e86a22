"""The check that no file of the folder a program starts from hides one of the testbench's
packages: ``plc.py`` beside ``python -m scenes …`` would be imported as ``plc`` and fail with
"'plc' is not a package". Checked once when :mod:`scenes` is imported (a few ``stat`` calls)."""

from __future__ import annotations

__all__ = ["PACKAGES", "ShadowedPackage", "check"]

import os
import sys

PACKAGES = ("mcl", "plc")
"""The packages :mod:`scenes` imports (a ``scenes.py`` or ``viewer.py`` is run by ``python -m``
in place of the package: docs/getting-started.md)."""


class ShadowedPackage(ImportError):
    """A file of the start folder hides a package of the testbench."""


def check() -> None:
    """Refuse a ``mcl.py`` or ``plc.py`` in the first folder of the import path (the current
    folder of ``python -m``, a script's folder) that hides the package of that name: one
    message naming the file and saying to rename it — the exit message of ``python -m``, else
    an ImportError.

    Raises:
        SystemExit: under ``python -m``.
        ShadowedPackage: else.
    """
    folder = os.path.abspath(sys.path[0] if sys.path and sys.path[0] else os.curdir)
    for name in PACKAGES:
        module = sys.modules.get(name)
        if module is not None and hasattr(module, "__path__"):
            continue  # imported as the package already
        path = os.path.join(folder, f"{name}.py")
        if os.path.isfile(path) and not os.path.isdir(os.path.join(folder, name)):
            message = (
                f"{path} hides the testbench's package {name!r} (Python imports the file "
                f"instead): rename the file, e.g. to my_{name}.py, or start from another folder"
            )
            if sys.argv[:1] == ["-m"]:
                raise SystemExit(f"error: {message}")
            raise ShadowedPackage(message, name=name, path=path)

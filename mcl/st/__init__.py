"""Deprecated: Structured Text moved to :mod:`plc.st` (the PLC layer); ``mcl.st`` and its
modules stay importable for one release and warn once.

Importing ``mcl.st`` needs what :mod:`plc.st` needs (the ``[st]`` extra).
"""

import importlib
import sys
import warnings

warnings.warn(
    "mcl.st moved to plc.st: import plc.st (mcl.st goes away in the next release)",
    DeprecationWarning,
    stacklevel=2,
)

from plc.st import *  # noqa: F403
from plc.st import __all__  # noqa: F401

_MOVED = {
    "arithmetic": "plc.st.codegen.arithmetic",
    "blocks": "plc.st.runtime.blocks",
    "calls": "plc.st.codegen.calls",
    "catalog": "plc.st.semantics.catalog",
    "declarations": "plc.st.semantics.declarations",
    "errors": "plc.st.errors",
    "expressions": "plc.st.codegen.expressions",
    "external": "plc.st.runtime.external",
    "functions": "plc.st.runtime.functions",
    "hoist": "plc.st.codegen.hoist",
    "invoke": "plc.st.codegen.invoke",
    "io": "plc.st.runtime.io",
    "parse": "plc.st.frontend.parse",
    "program": "plc.st.runtime.program",
    "scope": "plc.st.semantics.scope",
    "standard": "plc.st.codegen.standard",
    "statements": "plc.st.codegen.statements",
    "task": "plc.st.runtime.task",
    "translate": "plc.st.codegen.translate",
    "tree_cache": "plc.st.frontend.tree_cache",
    "types": "plc.st.semantics.types",
}
"""The old modules of mcl.st and where they are now."""

for _old, _new in _MOVED.items():
    sys.modules.setdefault(f"{__name__}.{_old}", importlib.import_module(_new))

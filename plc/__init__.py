"""plc — what runs once per PLC scan and calls mcl's function blocks.

Step sequences (:mod:`plc.sequence`), homing procedures (:mod:`plc.procedures`), the operator
program the viewer's buttons and the bridge's command words drive (:mod:`plc.operator`), the
commissioning routines of an axis (:mod:`plc.commissioning`) and programs in IEC 61131-3
Structured Text (:mod:`plc.st`, which needs the ``[st]`` extra). ``plc`` imports ``mcl`` and
nothing of the machines, the physics or the viewer.

The public API is this namespace (``__all__``), its modules and :mod:`plc.st`'s namespace; the
sub-packages of :mod:`plc.st` (frontend, semantics, codegen, runtime) are the compiler's
internals, except the watch table of a running program (:mod:`plc.st.runtime.watch`).
"""

from mcl import native

COMPILED_MODULES = ("procedures", "sequence")
"""This package's modules that the compiled build covers (run every PLC scan); its subpackages
declare their own (see :mod:`mcl.native`)."""
COMPILED = native.activate("plc", __path__)
"""The per-scan modules run compiled (see :mod:`mcl.native`)."""

from plc.procedures import BlockHoming, HomeAxis, HomingRecipe, Recipe
from plc.sequence import Block, DemoProgram, Step, StepSequence, never

__all__ = [
    "Block",
    "BlockHoming",
    "DemoProgram",
    "HomeAxis",
    "HomingRecipe",
    "Recipe",
    "Step",
    "StepSequence",
    "never",
]

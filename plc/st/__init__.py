"""PLC programs in IEC 61131-3 Structured Text: parsed with blark, translated to Python that
calls mcl's function blocks, compiled with ``compile()`` (see docs/st.md).

``plc.st.load("prog.st", scene, mapping={"Pohon.Ax1": "X"})`` gives an :class:`STProgram`;
``scene.run(prog)`` scans it, ``prog.Start = True`` writes a variable.
"""

from mcl.extras import require

require("plc.st", "st")

from plc.st.errors import PLCFault, STError
from plc.st.runtime.external import External
from plc.st.runtime.program import (
    STProgram,
    compile_source,
    from_source,
    load,
    restart,
    stopped,
    variables,
)
from plc.st.runtime.task import Task, declared_task, task_of_file

__all__ = [
    "External",
    "PLCFault",
    "STError",
    "STProgram",
    "Task",
    "compile_source",
    "declared_task",
    "from_source",
    "load",
    "restart",
    "stopped",
    "task_of_file",
    "variables",
]

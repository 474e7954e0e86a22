"""PLC programs in IEC 61131-3 Structured Text: parsed with blark, translated to Python that
calls mcl's function blocks, compiled with ``compile()`` (see docs/st.md).

``mcl.st.load("prog.st", scene, mapping={"Pohon.Ax1": "X"})`` gives an :class:`STProgram`;
``scene.run(prog)`` scans it, ``prog.Start = True`` writes a variable.
"""

from mcl.st.errors import PLCFault, STError
from mcl.st.external import External
from mcl.st.program import STProgram, compile_source, from_source, load
from mcl.st.task import Task, declared_task

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
]

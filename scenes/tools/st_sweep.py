"""An ST program as a sweep's scenario (:class:`STScenario`): ``scenario = "gantry:move.st"``
(machine, then the Structured Text file, where a Python scenario names ``module:function``).

Its parameters are the PROGRAM's variables (elementary ones: BOOL, the integers, the reals),
their defaults the initial values; a run builds the machine's scene, writes the parameters into
the program, scans it until its ``done`` is TRUE (or a fault stops it, or ``timeout`` simulated
seconds pass) and returns its VAR_OUTPUT variables as the metrics, with ``time_s`` (how long it
ran [s]). A program that declares ``seed`` receives the row's seed; a fault stopping the program
is a failed row.
"""

from __future__ import annotations

__all__ = ["TIMEOUT", "STScenario", "is_st_target"]

import inspect
from pathlib import Path
from typing import Any

from plc.st.semantics.types import Elementary

TIMEOUT = 60.0
"""Simulated seconds a run may take by default [s] (the ``timeout`` parameter)."""


def is_st_target(target: str) -> bool:
    """``target`` names an ST program (``machine:file.st``, or a PLCopen XML
    ``machine:project.xml``)."""
    return target.rpartition(":")[2].lower().endswith((".st", ".xml"))


class STScenario:
    """The scenario of one ST file on one machine.

    Args:
        target: ``"machine:path/to/file.st"`` (the path relative to the working directory).

    Raises:
        STError: the file cannot be read, or has an error (``file:line:column``).
        KeyError: no such machine (the message lists them).
    """

    def __init__(self, target: str) -> None:
        import plc.st
        import scenes

        machine, _, path = target.partition(":")
        self.machine, self.path = machine, Path(path)
        scenes.definition(machine)  # an unknown machine: KeyError with the valid names
        probe = plc.st.load(self.path, scenes.load(machine, trace_every=0))
        self.kinds: dict[str, type] = {}
        parameters = [inspect.Parameter("seed", inspect.Parameter.KEYWORD_ONLY, annotation=int)]
        for name, value in plc.st.variables(probe).items():
            kind = _kind(probe._var(name).type)
            if kind is not None and name.lower() not in ("seed", "done", "timeout"):
                self.kinds[name] = kind
                parameters.append(
                    inspect.Parameter(
                        name, inspect.Parameter.KEYWORD_ONLY, default=value, annotation=kind
                    )
                )
        parameters.append(
            inspect.Parameter(
                "timeout", inspect.Parameter.KEYWORD_ONLY, default=TIMEOUT, annotation=float
            )
        )
        self.outputs = [v.name for v in probe._vars.values() if v.section == "output"]
        self.__signature__ = inspect.Signature(parameters)

    def __call__(self, seed: int, timeout: float = TIMEOUT, **parameters: Any) -> dict[str, Any]:
        """One run: the program's VAR_OUTPUT values and ``time_s``.

        Raises:
            RuntimeError: a run-time fault stopped the program (its ``file:line`` message).
        """
        import plc.st
        import scenes

        scene = scenes.load(self.machine, start=scenes.definition(self.machine).demo_start)
        program = plc.st.load(self.path, scene)
        if "seed" in {n.lower() for n in program._vars}:
            program.seed = seed
        for name, value in parameters.items():
            setattr(program, name, value)
        ends = "done" in {n.lower() for n in program._vars}
        took = scene.run(
            program,
            until=(lambda: program.done or plc.st.stopped(program)) if ends else None,
            timeout=timeout,
        )
        if plc.st.stopped(program):
            raise RuntimeError(program.error)
        return {**{n: getattr(program, n) for n in self.outputs}, "time_s": took}


def _kind(t: Any) -> type | None:
    """The Python type of a sweepable ST type (None: not a parameter)."""
    if not isinstance(t, Elementary):
        return None
    if t.kind == "bool":
        return bool
    if t.kind == "real":
        return float
    return int if t.integral else None

"""The three demos in Structured Text (examples/st/<machine>_demo.st) give traces bit-identical
to their Python versions: the same scans from the same start, every trace sample equal."""

from typing import Any

import numpy as np
import pytest

import plc.st
import scenes
from tests.helpers import ROOT

EXAMPLES = ROOT / "examples" / "st"


def run_to_done(machine: str, program_of) -> tuple[int, Any, scenes.Scene]:
    """Run a program from the demo start until it is done; the scans it took, it, the scene."""
    scene = scenes.load(machine, start=scenes.definition(machine).demo_start, trace_seconds=1e4)
    program = program_of(scene)
    scans = [0]

    def scan():
        program()
        scans[0] += 1

    scene.run(scan, until=lambda: program.done or program.error, timeout=120.0)
    return scans[0], program, scene


def st_demo(scene: scenes.Scene) -> plc.st.STProgram:
    """The machine's ST demo, with the machine's own blocks (the flying shear's gauge)."""
    from scenes.tools.cli import machine_blocks

    return plc.st.load(EXAMPLES / f"{scene.name}_demo.st", scene, blocks=machine_blocks(scene))


@pytest.mark.parametrize("machine", ["gantry", "press", "flying_shear"])
def test_the_st_demo_traces_bit_identical_to_the_python_demo(machine):
    python_scans, demo, python_scene = run_to_done(machine, scenes.demo)
    st_scans, prog, st_scene = run_to_done(machine, st_demo)
    assert demo.done and not demo.error
    assert prog.done and not prog.error, prog.error
    assert st_scans == python_scans
    if machine == "flying_shear":  # the correction ran: 19 pieces measured, the scale learned
        assert prog.cut == 21 and prog.scaleCount == 19
        assert prog.scale == demo.scale != 1.0
    python_rows, st_rows = python_scene.trace.rows, st_scene.trace.rows
    assert list(st_rows) == list(python_rows)
    for axis, rows in python_rows.items():
        assert len(st_rows[axis]) == len(rows) > 1000
        assert st_rows[axis] == rows, f"axis {axis} differs"
    for signal in python_scene.signals:  # NaN where a signal has no value yet, in both
        ours, theirs = st_scene.trace.signal(signal), python_scene.trace.signal(signal)
        assert np.array_equal(ours, theirs, equal_nan=True), signal

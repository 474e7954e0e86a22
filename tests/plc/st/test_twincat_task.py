"""A TwinCAT project's task (its ``.TcTTO``): the program runs at the task's cycle time, as at
a PLCopen task's interval or an ST CONFIGURATION's INTERVAL; a task file that cannot be one
is refused at its line. The ``.plcproj`` is not read (the folder's source files are)."""

from __future__ import annotations

import pytest

import plc.st
from scenes.tools import cli
from tests.plc.st.test_projects import OBJECT, _pou

TASK = """  <Task Name="PlcTask" Id="{02fe40af-27cf-412d-8873-439f5711722a}">
    <!--CycleTime in micro seconds.-->
    <CycleTime>20000</CycleTime>
    <Priority>20</Priority>
    <PouCall>
      <Name>MAIN</Name>
    </PouCall>
    <TaskFBGuid>{9a948d60-a1d1-483d-9d0f-6bc3375a6616}</TaskFBGuid>
  </Task>
"""
"""TwinCAT's task of 20 ms calling MAIN (CycleTime on line 5 of the file, MAIN on line 8)."""


def _project(folder, task: str = TASK) -> None:
    """A TwinCAT folder: MAIN.TcPOU counting its scans, PlcTask.TcTTO of ``task``, and the
    project file TwinCAT keeps beside them."""
    declaration = "PROGRAM MAIN\nVAR\n    nScans : INT;\n    done : BOOL;\nEND_VAR\n"
    (folder / "MAIN.TcPOU").write_text(
        _pou("MAIN", declaration, "nScans := nScans + 1;\ndone := nScans >= 3;\n")
    )
    (folder / "PlcTask.TcTTO").write_text(OBJECT.format(task))
    (folder / "Machine.plcproj").write_text("<Project>not ST</Project>\n")


def test_the_program_runs_at_the_cycle_time_of_its_task(tmp_path):
    """CycleTime 20000 µs on a 10 ms PLC: MAIN runs every second PLC scan, and the CLI builds
    the machine at the task's 20 ms, as for a PLCopen task."""
    _project(tmp_path)
    prog = plc.st.load(tmp_path, period=0.01)
    assert prog.name == "MAIN" and prog.every == 2
    for _ in range(4):
        prog()
    assert prog.nScans == 2
    task = cli.st_task(str(tmp_path))
    assert task is not None and (task.name, task.interval, task.program) == (
        "PlcTask",
        0.02,
        "MAIN",
    )
    assert task.where.startswith(f"{tmp_path / 'PlcTask.TcTTO'}:5:")


def test_the_cli_runs_a_twincat_project_at_its_task(tmp_path, capsys):
    """``python -m scenes run single_axis --program FOLDER`` with a 4 ms task: MAIN's scans
    are 4 ms apart."""
    _project(tmp_path, TASK.replace("20000", "4000"))
    (tmp_path / "MAIN.TcPOU").write_text(
        (tmp_path / "MAIN.TcPOU")
        .read_text()
        .replace("    done : BOOL;", "    done : BOOL;\n    step : STRING;")
        .replace("nScans := nScans + 1;", "nScans := nScans + 1; step := INT_TO_STRING(nScans);")
    )
    assert cli.run("single_axis", st_program=str(tmp_path)) == 0
    out = capsys.readouterr().out
    assert "== t= 0.000 s  1\n" in out and "== t= 0.004 s  2\n" in out
    assert "== t= 0.008 s  3\n" in out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "<CycleTime>20000</CycleTime>",
            "<CycleTime>30000</CycleTime>",
            "PlcTask.TcTTO:5:1: TASK PlcTask INTERVAL 30 ms cannot run on a PLC period of 20 ms",
        ),
        (
            "<CycleTime>20000</CycleTime>",
            "<CycleTime>fast</CycleTime>",
            "PlcTask.TcTTO:5: a task with <CycleTime>fast</CycleTime>; expected its cycle time "
            "in µs, <CycleTime>2000",
        ),
        (
            "<Name>MAIN</Name>",
            "<Name>Mian</Name>",
            "PlcTask.TcTTO:8:1: no PROGRAM Mian; expected MAIN",
        ),
    ],
)
def test_a_task_that_cannot_run_is_refused_at_its_line(tmp_path, old, new, message):
    """A cycle time the PLC period does not divide, one that is no number, a call of a
    program the project lacks: each at its line in the .TcTTO."""
    _project(tmp_path, TASK.replace(old, new))
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path, period=0.02)
    assert str(error.value).startswith(str(tmp_path / message))

"""A TwinCAT project's task (its ``.TcTTO``): the program runs at the task's cycle time, as at
a PLCopen task's interval or an ST CONFIGURATION's INTERVAL; a task file that cannot be one
is refused at its line. The ``.plcproj`` is not read (the folder's source files are)."""

from __future__ import annotations

import pytest

import plc.st
from plc.st.frontend.project import read_project
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


def test_the_task_becomes_the_configuration_of_the_project(tmp_path):
    """The task's cycle time, priority and program call are the project's CONFIGURATION, each
    line cited at the line of the .TcTTO it comes from (the TASK at its <CycleTime>, the
    PROGRAM at its <Name>)."""
    _project(tmp_path)
    project = read_project(tmp_path)
    source = project.source.splitlines()
    start = source.index("CONFIGURATION TwinCAT")
    assert source[start:] == [
        "CONFIGURATION TwinCAT",
        "RESOURCE PLC ON PLC",
        "TASK PlcTask (INTERVAL := T#20ms, PRIORITY := 20);",
        "PROGRAM MAIN WITH PlcTask : MAIN;",
        "END_RESOURCE",
        "END_CONFIGURATION",
    ]
    task_file = tmp_path / "PlcTask.TcTTO"
    cited = [project.where(start + 1 + n) for n in range(6)]
    assert cited == [f"{task_file}:{line}" for line in (5, 5, 5, 8, 5, 5)]


@pytest.mark.parametrize(("cycle", "interval", "every"), [("\n      4000\n    ", 0.004, 2)])
def test_a_cycle_time_written_over_lines(tmp_path, cycle, interval, every):
    """<CycleTime>4000</CycleTime> written over lines, as an editor may, is a 4 ms task: on a
    2 ms PLC MAIN runs every second scan."""
    _project(tmp_path, TASK.replace("20000", cycle))
    task = cli.st_task(str(tmp_path))
    assert task is not None and task.interval == pytest.approx(interval, rel=1e-12)
    prog = plc.st.load(tmp_path, period=0.002)
    assert prog.every == every
    for _ in range(every * 2):
        prog()
    assert prog.nScans == 2


def test_a_task_is_named_by_its_name_else_by_its_file(tmp_path):
    """``<Task Name="Motion">`` in PlcTask.TcTTO is the task Motion; ``<Task Name="">`` (or
    none) in FastTask.TcTTO the task FastTask."""
    _project(tmp_path, TASK.replace('Name="PlcTask" ', 'Name=" Motion " '))
    task = cli.st_task(str(tmp_path))
    assert task is not None and (task.name, task.program) == ("Motion", "MAIN")
    (tmp_path / "PlcTask.TcTTO").write_text(
        OBJECT.format(TASK.replace('Name="PlcTask" ', 'Name="  " '))
    )
    (tmp_path / "PlcTask.TcTTO").rename(tmp_path / "FastTask.TcTTO")
    task = cli.st_task(str(tmp_path))
    assert task is not None and (task.name, task.program) == ("FastTask", "MAIN")
    (tmp_path / "FastTask.TcTTO").write_text(OBJECT.format(TASK.replace('Name="PlcTask" ', "")))
    task = cli.st_task(str(tmp_path))
    assert task is not None and task.name == "FastTask"


@pytest.mark.parametrize(
    ("priority", "setting"),
    [("<Priority> 7 </Priority>", ", PRIORITY := 7"), ("<Priority>high</Priority>", ""), ("", "")],
)
def test_the_priority_of_the_task(tmp_path, priority, setting):
    """A task's <Priority> (a whole number) is its PRIORITY; one that is no number, or none,
    is left out (the task keeps its interval)."""
    _project(tmp_path, TASK.replace("<Priority>20</Priority>", priority))
    assert f"TASK PlcTask (INTERVAL := T#20ms{setting});\n" in read_project(tmp_path).source
    assert plc.st.load(tmp_path, period=0.01).every == 2


def test_tasks_of_two_files_each_cite_their_own_file(tmp_path):
    """A second task file whose call names a program the project lacks is refused at the line
    of that call in that file."""
    _project(tmp_path)
    slow = TASK.replace("PlcTask", "SlowTask").replace("<Name>MAIN", "<Name>Mian")
    (tmp_path / "SlowTask.TcTTO").write_text(OBJECT.format(slow))
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path, period=0.01)
    assert str(error.value).startswith(
        f"{tmp_path / 'SlowTask.TcTTO'}:8:1: no PROGRAM Mian; expected MAIN"
    )
    source = read_project(tmp_path).source
    assert "TASK PlcTask (INTERVAL := T#20ms, PRIORITY := 20);\n" in source
    assert "TASK SlowTask (INTERVAL := T#20ms, PRIORITY := 20);\n" in source


NOT_A_TASK = (
    "PlcTask.TcTTO:2: no <Task> in it; expected a TwinCAT task "
    "(<TcPlcObject><Task Name=...><CycleTime>)"
)
CYCLE = "; expected its cycle time in µs, <CycleTime>2000"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (OBJECT.format(TASK).replace("TcPlcObject", "TcProject"), NOT_A_TASK),
        (OBJECT.format(TASK.replace("<Task ", "<Job ").replace("</Task>", "</Job>")), NOT_A_TASK),
        (
            OBJECT.format(TASK.replace("<CycleTime>20000</CycleTime>", "")),
            "PlcTask.TcTTO:3: a task with no <CycleTime>" + CYCLE,
        ),
        (
            OBJECT.format(TASK.replace("20000", "0")),
            "PlcTask.TcTTO:5: a task with <CycleTime>0</CycleTime>" + CYCLE,
        ),
        (
            OBJECT.format(TASK.replace("20000", "")),
            "PlcTask.TcTTO:5: a task with <CycleTime></CycleTime>" + CYCLE,
        ),
        (
            OBJECT.format(TASK.replace("<Name>MAIN</Name>", "<Name> </Name>")),
            "PlcTask.TcTTO:8: a <PouCall> with no program; expected <Name>MAIN</Name>",
        ),
        (
            OBJECT.format(TASK.replace("<Name>MAIN</Name>", "<Name/>")),
            "PlcTask.TcTTO:8: a <PouCall> with no program; expected <Name>MAIN</Name>",
        ),
        (
            OBJECT.format(TASK.replace("</CycleTime>", "")),
            "PlcTask.TcTTO:11:5: not well-formed XML (mismatched tag); expected a TwinCAT task "
            "(<TcPlcObject><Task Name=...><CycleTime>)",
        ),
    ],
)
def test_a_task_file_that_is_no_task_is_refused_at_its_line(tmp_path, content, message):
    """A .TcTTO of another kind of object, a task with no cycle time, a zero one or an empty
    one, a program call without its program, a file that is no XML: one message at its line,
    saying what would be right."""
    _project(tmp_path)
    (tmp_path / "PlcTask.TcTTO").write_text(content)
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path, period=0.01)
    assert str(error.value) == str(tmp_path / message)

"""A task's cycle time is a whole number of ms: TIME is held in ms, and a PLC cycle is a
multiple of the machines' servo cycle of 1 ms. A cycle of a fraction of a ms (a TwinCAT
``<CycleTime>`` in µs, a PLCopen interval, an ST TASK's INTERVAL) is refused at its line,
saying why and what would do, never rounded to another period."""

from __future__ import annotations

from pathlib import Path

import pytest

import plc.st
from plc.st.frontend.tctask import WHOLE_MS
from tests.plc.st.test_twincat_task import TASK, _project

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "st"


@pytest.mark.parametrize(("micros", "ms"), [("500", "0.5"), ("1500", "1.5"), ("999", "0.999")])
def test_a_twincat_cycle_time_of_a_fraction_of_a_ms(tmp_path, micros, ms):
    _project(tmp_path, TASK.replace("20000", micros))
    with pytest.raises(plc.st.STError) as error:
        plc.st.task_of_file(tmp_path)
    assert str(error.value) == (
        f"{tmp_path / 'PlcTask.TcTTO'}:5: a task with <CycleTime>{micros}</CycleTime> ({ms} ms): "
        f"{WHOLE_MS}; expected a multiple of 1000 µs, <CycleTime>1000"
    )


@pytest.mark.parametrize("interval", ["T#0.5ms", "T#1.5ms", "T#2.25MS", "TIME#1s0.5ms"])
def test_an_st_task_interval_of_a_fraction_of_a_ms(tmp_path, interval):
    source = (
        f"CONFIGURATION c RESOURCE r ON PLC TASK t(INTERVAL := {interval}); PROGRAM main WITH t "
        ": P; END_RESOURCE END_CONFIGURATION\nPROGRAM P\nVAR n : INT; END_VAR\nn := n + 1;\n"
        "END_PROGRAM\n"
    )
    file = tmp_path / "fast.st"
    file.write_text(source)
    with pytest.raises(plc.st.STError) as error:
        plc.st.task_of_file(file)
    assert str(error.value).startswith(f"{file}:1:35: TASK t INTERVAL ")
    assert str(error.value).endswith(f": {WHOLE_MS}; expected T#1ms, T#2ms, ...")


def test_a_plcopen_task_of_a_fraction_of_a_ms(tmp_path):
    """CODESYS' PT0.0005S: 0.5 ms, at the task's line."""
    xml = (EXAMPLES / "plcopen" / "axis_cycle.xml").read_text()
    file = tmp_path / "fast.xml"
    file.write_text(xml.replace('interval="T#2ms"', 'interval="PT0.0005S"'))
    with pytest.raises(plc.st.STError) as error:
        plc.st.task_of_file(file)
    assert str(error.value).startswith(f"{file}:295:")
    assert WHOLE_MS in str(error.value)


@pytest.mark.parametrize(("micros", "interval"), [("1000", 0.001), ("3000", 0.003)])
def test_whole_ms_stay_as_they_were(tmp_path, micros, interval):
    _project(tmp_path, TASK.replace("20000", micros))
    task = plc.st.task_of_file(tmp_path)
    assert task is not None and task.interval == interval

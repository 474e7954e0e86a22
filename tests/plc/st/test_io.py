"""ST I/O binding: located variables (``AT %IX``, ``%QX``, ``%IW``) and named I/O read and
write the machine's switches, outputs and analog inputs; a TASK's INTERVAL sets the scan."""

import pytest

import plc.st

COUNTER = """
PROGRAM counter
VAR n : DINT; t : TON; late : BOOL; END_VAR
n := n + 1;
t(IN := TRUE, PT := T#100ms, Q => late);
END_PROGRAM
"""


def task(interval: str) -> str:
    return (
        COUNTER
        + "CONFIGURATION plc\n  RESOURCE cpu ON PLC\n"
        + f"    TASK cyclic(INTERVAL := {interval}, PRIORITY := 1);\n"
        + "    PROGRAM main WITH cyclic : counter;\n  END_RESOURCE\nEND_CONFIGURATION\n"
    )


def test_a_located_input_reads_the_ref_switch_of_the_axis_it_names(scene):
    gantry = scene("gantry", start={"X": 0.05, "Y": 0.3})  # X below its REF edge, Y above
    source = (
        "PROGRAM p\nVAR\n  x_ref AT %IX0.2 : BOOL;\n  y_ref AT %IX1.2 : BOOL;\nEND_VAR\n"
        "END_PROGRAM\n"
    )
    prog = plc.st.from_source(source, gantry)
    gantry.run(prog, timeout=0.01)
    assert prog.x_ref == gantry.axes["X"].DI[2] == gantry.io("X").ref
    assert prog.y_ref == gantry.axes["Y"].DI[2]
    assert prog.x_ref != prog.y_ref  # each reads its own axis' switch


def test_a_located_output_drives_the_flying_shears_knife_down(scene):
    shear = scene("flying_shear")
    source = (
        "PROGRAM p\nVAR down : BOOL; knife AT %QX2.0 : BOOL; END_VAR\nknife := down;\nEND_PROGRAM\n"
    )
    prog = plc.st.from_source(source, shear)
    shear.run(prog, timeout=0.2)
    top = shear.signal("knife")
    assert not shear.axes["S"].DO[0]
    prog.down = True
    shear.run(prog, timeout=0.2)
    assert shear.axes["S"].DO[0]
    assert shear.signal("knife") < top - 10.0  # the blade moved down [mm]


def test_named_io_from_a_mapping_reads_the_press_pressure_in_volts(scene):
    press = scene("press")
    source = "PROGRAM p\nVAR p_a : LREAL; bar : LREAL; END_VAR\nbar := p_a * 25.0;\nEND_PROGRAM\n"
    prog = plc.st.from_source(source, press, mapping={"p_a": "R.AI0"})
    press.run(prog, timeout=0.1)
    prog()  # one more scan, between servo cycles: the inputs as they are now
    assert prog.p_a == press.axes["R"].AI[0] != 0.0
    assert prog.bar == pytest.approx(press.signal("pressure_A"), abs=0.5)


@pytest.mark.parametrize(
    ("declaration", "message"),
    [
        ("k AT %QX0.0 : BOOL", "3:5: k AT %QX0.0: axis X has 0 digital outputs"),
        ("k AT %IX7.0 : BOOL", "axis index 7: the machine has 3 axes"),
        ("k AT %IX0.9 : BOOL", "axis X has 4 digital inputs"),
        ("k AT %IX0.2 : INT", "k on DI2 of axis X; expected a BOOL"),
        ("k AT %IW0.0 : LREAL", "axis X has 0 analog inputs"),
        ("k AT %QW0.0 : INT", "the machine has no analog outputs"),
    ],
)
def test_an_io_point_the_machine_lacks_names_file_line_column(scene, declaration, message):
    gantry = scene("gantry", trace_every=0)
    source = f"PROGRAM p\nVAR\n  {declaration};\nEND_VAR\nEND_PROGRAM\n"
    with pytest.raises(plc.st.STError, match=r"io\.st:") as raised:
        plc.st.from_source(source, gantry, filename="io.st")
    assert message in str(raised.value)


def test_a_task_of_4_ms_on_a_2_ms_plc_runs_every_second_scan_on_simulated_time(scene):
    gantry = scene("gantry", trace_every=0)
    prog = plc.st.from_source(task("T#4ms"), gantry)
    assert prog.every == 2
    gantry.run(prog, timeout=0.2)  # 100 PLC scans of 2 ms
    assert prog.n == 50
    assert prog.late and prog.t.ET == 100  # the timer on the simulated time


def test_a_task_the_scene_cannot_run_names_the_task_line(scene):
    gantry = scene("gantry", trace_every=0)
    with pytest.raises(plc.st.STError) as raised:
        plc.st.from_source(task("T#3ms"), gantry, filename="task.st")
    assert str(raised.value).startswith("task.st:9:5: TASK cyclic INTERVAL 3 ms cannot run")
    assert "an integer multiple of 2 ms" in str(raised.value)


@pytest.mark.parametrize(("interval", "every"), [("LTIME#2500us", 5), ("LTIME#2ms", 4)])
def test_an_interval_of_a_fraction_of_a_ms_is_an_ltime(interval, every):
    """A TIME is in whole ms (T#2.5ms is 2 ms): LTIME#2500us is a 2.5 ms task, every fifth
    scan of a 0.5 ms PLC."""
    prog = plc.st.from_source(task(interval), period=0.0005)
    assert prog.every == every


def test_a_task_without_interval_or_of_an_unknown_program_is_refused():
    no_interval = task("T#4ms").replace("INTERVAL := T#4ms, ", "")
    with pytest.raises(plc.st.STError, match=r"t\.st:9:5: TASK cyclic without INTERVAL"):
        plc.st.from_source(no_interval, filename="t.st")
    unknown = task("T#4ms").replace(": counter;", ": countr;")
    with pytest.raises(plc.st.STError, match=r"t\.st:10:5: no PROGRAM countr; expected counter"):
        plc.st.from_source(unknown, filename="t.st")


def test_the_cli_builds_the_scene_at_the_tasks_period(tmp_path, capsys):
    from scenes.tools.cli import main

    path = tmp_path / "counter.st"
    path.write_text(task("T#3ms"))  # a 2 ms scene cannot run it (see above); a 3 ms one can
    assert main(["run", "gantry", "--program", str(path), "--timeout", "0.3"]) == 0
    assert "cannot run" not in capsys.readouterr().err

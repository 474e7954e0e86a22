"""``python -m scenes check NAME PROGRAM...``: ST programs checked for a machine without
running them (:mod:`plc.st.check`): every error on standard error, one summary on standard
output, the exit status 1 on errors (for a CI job or a pre-commit hook)."""

from __future__ import annotations

from pathlib import Path

import pytest

from scenes.tools import cli
from tests.plc.st.test_check import SOURCE

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "st"


@pytest.mark.parametrize(
    ("machine", "program", "items"),
    [
        ("gantry", "gantry_demo.st", 4),
        ("flying_shear", "flying_shear_demo.st", 3),
        ("press", "press_twincat", 2),
    ],
)
def test_the_demos_check_clean(machine, program, items, capsys):
    """The machine's axes, I/O and own blocks (the flying shear's FS_CutGauge) bind."""
    assert cli.main(["check", machine, str(EXAMPLES / program)]) == 0
    captured = capsys.readouterr()
    assert (captured.out, captured.err) == (f"no errors in {items} items\n", "")


def test_the_command_reports_every_error_and_fails(tmp_path, capsys):
    """``python -m scenes check gantry a.st b.st``: the errors of both files on standard error,
    one summary, exit status 1 (for a CI job or a pre-commit hook)."""
    bad = tmp_path / "m.st"
    bad.write_text(SOURCE)
    good = tmp_path / "ok.st"
    good.write_text("PROGRAM Main\nVAR n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n")
    assert cli.main(["check", "gantry", str(bad), str(good)]) == 1
    captured = capsys.readouterr()
    assert captured.err.splitlines()[0] == f"{bad}:4:9: unexpected ';'; expected an expression"
    assert len(captured.err.splitlines()) == 4
    assert captured.out == "4 errors in 4 of 6 items\n"


@pytest.mark.parametrize(
    ("option", "message"),
    [
        ("Foo", "--map Foo: not NAME=AXIS; expected Pohon.Ax1=X (an axis) or Knife=S.DO0 (I/O)"),
        ("=X", "--map =X: not NAME=AXIS; expected Pohon.Ax1=X (an axis) or Knife=S.DO0 (I/O)"),
        (
            "Pohon.Ax1=Q",
            "--map: the mapping Pohon.Ax1 -> 'Q' names no axis; expected one of X, Y, Z",
        ),
    ],
)
@pytest.mark.parametrize("command", ["check", "run"])
def test_a_wrong_map_is_a_command_line_mistake(option, message, command, capsys):
    """Exit status 2 and the option named, not the program file."""
    program = str(EXAMPLES / "manual_move.st")
    args = (
        ["check", "gantry", program]
        if command == "check"
        else ["run", "gantry", "--program", program]
    )
    assert cli.main([*args, "--map", option]) == 2
    captured = capsys.readouterr()
    assert (captured.out, captured.err) == ("", f"{message}\n")


def test_a_missing_program_is_a_command_line_mistake(tmp_path, capsys):
    """Exit status 2 before any check: the file named."""
    missing = tmp_path / "gantry_ok.st"
    assert cli.main(["check", "gantry", str(EXAMPLES / "gantry_demo.st"), str(missing)]) == 2
    captured = capsys.readouterr()
    assert (captured.out, captured.err) == (
        "",
        f"{missing}: no such file or folder; expected an ST file, a TwinCAT folder or source "
        "file, a PLCopen .xml\n",
    )


def test_a_program_with_its_map_checks_clean(capsys):
    """``--map Pohon.Ax1=X``: ``examples/st/manual_move.st`` binds its axis."""
    program = str(EXAMPLES / "manual_move.st")
    assert cli.main(["check", "gantry", program, "--map", "Pohon.Ax1=X"]) == 0
    assert capsys.readouterr().out == "no errors in 1 item\n"

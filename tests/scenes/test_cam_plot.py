"""``python -m scenes cam``: a cam table's profile as PNG, from a table file or the rotary
knife's arguments; bad input is one line on standard error and exit status 2."""

from __future__ import annotations

from pathlib import Path

import matplotlib.image
import pytest

from scenes.tools.cli import main

LIFT = (
    "master,slave,velocity,acceleration,law\n# a lift\n"
    "0,0,0,0,Polynomial5\n10,5,0,0,ModifiedSine\n20,0,0,0,\n"
)


def test_a_table_file_and_the_rotary_knife_are_drawn_as_png(tmp_path: Path) -> None:
    table = tmp_path / "lift.csv"
    table.write_text(LIFT)
    assert main(["cam", str(table)]) == 0
    image = matplotlib.image.imread(tmp_path / "lift.png")
    assert image.shape[0] > 400 and image.shape[1] > 600
    assert image[..., :3].std() > 0.05, "something is drawn"
    knife = tmp_path / "knife"
    args = ["--cut-length", "600", "--circumference", "1000", "--sync-angle", "30"]
    assert main(["cam", *args, "--out", str(knife)]) == 0
    assert (tmp_path / "knife.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    ("content", "args", "message"),
    [
        ("master,slave\n0,0\n10,x\n", [], "bad.csv:3: slave: 'x' is not a number"),
        ("master,slave\n0,0\n10,5\n5,1\n", [], "bad.csv:4: point 2: Master 5.0 does not increase"),
        ("master,slave,law\n0,0,Cubic\n10,5\n", [], "bad.csv:2: law: 'Cubic' is not a cam law"),
        ("mast,slave\n0,0\n", [], "bad.csv:1: the header is"),
        (
            "",
            ["--cut-length", "3000", "--circumference", "1000", "--sync-angle", "30"],
            "the drum would turn backwards",
        ),
    ],
)
def test_bad_input_is_one_line_and_no_image(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], content: str, args: list[str], message: str
) -> None:
    table = tmp_path / "bad.csv"
    table.write_text(content)
    argv = ["cam", *args, "--out", str(tmp_path / "out")] if args else ["cam", str(table)]
    assert main(argv) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and message in lines[0]
    assert not list(tmp_path.glob("*.png"))

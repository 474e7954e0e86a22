"""The viewer's ``--programs DIR`` offers every program the ST loader takes: ``*.st`` files,
PLCopen XML exports and TwinCAT project folders; a project runs as its .st twin and its errors
name the project's own file and line."""

from __future__ import annotations

import shutil
from pathlib import Path

from tests.helpers import ROOT
from viewer.__main__ import parser
from viewer.sim.programs import ProgramCatalog, programs_in
from viewer.sim.session import Session

EXAMPLES = ROOT / "examples" / "st"
SCANS = 400
"""PLC scans the programs run before they are compared."""


def _programs(tmp_path: Path) -> Path:
    """A directory as an engineer keeps it: a .st file, a PLCopen export, a TwinCAT project
    folder, and a file of neither kind."""
    shutil.copy(EXAMPLES / "gantry_demo.st", tmp_path)
    shutil.copy(EXAMPLES / "plcopen" / "gantry_demo.xml", tmp_path / "gantry_export.xml")
    shutil.copytree(EXAMPLES / "gantry_twincat", tmp_path / "GantryProject" / "POUs")
    (tmp_path / "notes.txt").write_text("not a program\n")
    return tmp_path


def _run(catalog: ProgramCatalog, label: str) -> Session:
    session = Session("gantry", paused=True, programs=catalog)
    assert session.programs.choose(label), session.programs.chosen
    session.start_demo()
    session.advance(SCANS)
    return session


def test_the_directory_lists_st_files_plcopen_exports_and_twincat_projects(tmp_path: Path):
    folder = _programs(tmp_path)
    assert programs_in(folder) == [
        folder / "GantryProject",
        folder / "gantry_demo.st",
        folder / "gantry_export.xml",
    ]
    labels = Session("gantry", paused=True, programs=ProgramCatalog([folder])).programs.labels
    assert {"GantryProject", "gantry_export.xml"} <= set(labels)


def test_a_folder_of_loose_twincat_files_is_one_project(tmp_path: Path):
    shutil.copytree(EXAMPLES / "gantry_twincat", tmp_path, dirs_exist_ok=True)
    assert programs_in(tmp_path) == [tmp_path]


def test_a_twincat_project_and_a_plcopen_export_run_as_the_st_demo(tmp_path: Path):
    catalog = ProgramCatalog([_programs(tmp_path)])
    st = _run(catalog, "gantry_demo.st")
    start = Session("gantry", paused=True).snapshot.qpos
    assert abs(st.snapshot.qpos - start).max() > 1e-3  # the demo has moved the machine
    for label in ("GantryProject", "gantry_export.xml"):
        session = _run(catalog, label)
        assert session.snapshot.demo.running and not session.snapshot.demo.error
        assert (session.snapshot.qpos == st.snapshot.qpos).all(), label


def test_a_broken_project_is_listed_with_its_file_and_line(tmp_path: Path):
    project = tmp_path / "Broken"
    shutil.copytree(EXAMPLES / "gantry_twincat", project)
    pou = project / "GantryDemo.TcPOU"
    text = pou.read_text(encoding="utf-8")
    pou.write_text(text.replace("END_CASE", "END_CAS", 1), encoding="utf-8")
    session = Session("gantry", paused=True, programs=ProgramCatalog([tmp_path]))
    assert not session.programs.choose("Broken")
    chosen = session.programs.chosen
    assert chosen is not None and "GantryDemo.TcPOU:" in chosen.error
    assert "Broken.st" not in chosen.error


def test_the_command_line_takes_such_a_directory(tmp_path: Path):
    folder = _programs(tmp_path)
    assert parser().parse_args(["--programs", str(folder)]).programs == [folder]

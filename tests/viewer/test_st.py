"""Structured Text in the viewer's session: the Program choice runs an ST program as the demo,
its watch table shows the variables live, and a page forces them."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import pytest

from scenes.tools.testing import home, physical_position
from tests.helpers import ROOT, run_coroutine
from tests.viewer.test_browser import browser, take_control, wait_for
from tests.viewer.test_control import _drain, _encode, _page, _press, _until
from viewer.serving.server import Viewer
from viewer.sim.programs import PYTHON_DEMO, ProgramCatalog
from viewer.sim.session import Session
from viewer.sim.snapshot import Event

if TYPE_CHECKING:
    from playwright.sync_api import Browser

__all__ = ["browser"]  # the browser fixture, shared with the viewer's browser tests

EXAMPLES = ROOT / "examples" / "st"
SCANS = 400
"""PLC scans the demos run before they are compared."""


def _rows(session: Session) -> dict[str, tuple[str, str, bool]]:
    return {r.name: (r.type, r.value, r.forced) for r in session.watch}


def _run_demo(label: str, scans: int) -> Session:
    session = Session("gantry", paused=True)
    assert session.programs.choose(label)
    session.start_demo()  # published at once: the watch table of the fresh program
    if scans:
        session.advance(scans)
    return session


def test_the_gantry_st_demo_moves_the_joints_as_the_python_demo() -> None:
    python, st = _run_demo(PYTHON_DEMO, SCANS), _run_demo("gantry_demo.st", SCANS)
    assert "gantry_demo.st" in st.programs.labels and PYTHON_DEMO in st.programs.labels
    moved = python.snapshot.qpos
    start = Session("gantry", paused=True).snapshot.qpos
    assert abs(moved - start).max() > 1e-3  # the demo has moved the machine
    assert (st.snapshot.qpos == moved).all()
    assert st.snapshot.demo.running and not st.snapshot.demo.error
    assert python.watch == ()  # a Python demo has no watch table


def test_the_watch_table_shows_the_step_changing() -> None:
    session = _run_demo("gantry_demo.st", 0)
    first = _rows(session)["step"]
    assert first == ("GantryStep", "PowerOn", False)
    assert _rows(session)["powerX.Status"][0] == "BOOL"
    session.advance(SCANS)
    assert _rows(session)["step"][1] not in ("", "PowerOn")
    assert session.snapshot.demo.step == _rows(session)["step"][1]


@pytest.fixture
def manual() -> Session:
    """The gantry with X homed, running examples/st/manual_move.st (Pohon.Ax1 mapped to X)."""
    catalog = ProgramCatalog([EXAMPLES], mapping={"Pohon.Ax1": "X"})
    session = Session("gantry", paused=True, programs=catalog)
    home(session.scene, "X")
    assert session.programs.choose("manual_move.st")
    session.start_demo()
    session.advance(10)
    return session


def test_forcing_start_moves_x_until_unforced(manual: Session) -> None:
    x0 = physical_position(manual.scene, "X")
    assert _rows(manual)["Start"] == ("BOOL", "FALSE", False)
    assert manual.force("Start", True)
    manual.advance(1)
    assert _rows(manual)["Start"] == ("BOOL", "TRUE", True)
    manual.advance(300)
    assert physical_position(manual.scene, "X") > x0 + 1.0  # X moves towards 300 mm
    assert _rows(manual)["Head_X.Busy"][1] == "TRUE"
    assert manual.force("Start", None)
    manual.advance(1)
    assert _rows(manual)["Start"] == ("BOOL", "TRUE", False)  # unforced, keeps its value


def test_a_wrong_force_is_refused_and_logged(manual: Session) -> None:
    x0 = physical_position(manual.scene, "X")
    assert not manual.force("Nope", True)
    assert not manual.force("Head_X.Done", True)  # a block's output is the block's
    assert not manual.force("ErrorID2", float("nan"))
    manual.advance(5)
    assert physical_position(manual.scene, "X") == pytest.approx(x0, abs=1e-3)  # X stays
    assert _rows(manual)["Start"] == ("BOOL", "FALSE", False)
    refused = [e.text for e in manual.snapshot.events if "refused" in e.text]
    assert len(refused) == 3 and "'Nope'" in refused[0]


def test_a_file_that_does_not_translate_is_listed_with_its_error_and_not_run(
    tmp_path: Path,
) -> None:
    (tmp_path / "broken.st").write_text("PROGRAM p\nVAR x : NOSUCHTYPE; END_VAR\nEND_PROGRAM\n")
    session = Session("gantry", paused=True, programs=ProgramCatalog([tmp_path]))
    assert "broken.st" in session.programs.labels
    assert not session.programs.choose("broken.st")
    session.start_demo()
    session.advance(2)
    demo = session.snapshot.demo
    assert not demo.running and "broken.st:2:" in demo.error and "NOSUCHTYPE" in demo.error
    assert any("broken.st:2:" in e.text for e in demo_events(session))


def demo_events(session: Session) -> list[Event]:
    return [e for e in session.snapshot.events if e.source in ("demo", "program")]


def test_a_watcher_cannot_force_and_the_operator_can() -> None:
    session = Session("gantry", programs=ProgramCatalog())
    assert session.programs.choose("gantry_demo.st")
    session.start_demo()
    with Viewer("gantry", port=0, demo=False, session=session) as viewer:

        async def scenario() -> None:
            connection, client = await _page(viewer)
            reader = asyncio.create_task(_drain(connection))
            pages = viewer.app.pages
            await _until(lambda: pages.get(client) is not None, 10.0, "the page's panels")
            page = pages.get(client)
            assert page is not None
            watch = page.watch
            await _until(lambda: "done" in watch.variable.options, 5.0, "the watch table")
            cast(Any, watch.variable).value = "done"
            press = {"value": True}
            await connection.send(
                _encode("GuiUpdateMessage", uuid=watch.force._impl.uuid, updates=press)
            )
            await asyncio.sleep(0.5)
            assert not _rows(session)["done"][2]  # a watcher's Force is refused
            await _press(viewer, connection, client, "take")
            await _until(lambda: viewer.app.control.owner == client, 5.0, "control")
            await connection.send(
                _encode("GuiUpdateMessage", uuid=watch.force._impl.uuid, updates=press)
            )
            await _until(lambda: session.snapshot.demo.done, 5.0, "done forced TRUE")
            assert _rows(session)["done"] == ("BOOL", "TRUE", True)
            await connection.close()
            await reader

        run_coroutine(scenario())
    assert any("take control first" in e.text for e in session.snapshot.events)


def test_a_run_time_fault_stops_the_program_and_names_file_and_line(tmp_path: Path) -> None:
    (tmp_path / "faulty.st").write_text(
        "PROGRAM p\nVAR n : INT := 3; q : INT; END_VAR\nn := n - 1;\nq := 6 / n;\nEND_PROGRAM\n"
    )
    session = Session("gantry", paused=True, programs=ProgramCatalog([tmp_path]))
    assert session.programs.choose("faulty.st")
    session.start_demo()
    session.advance(2)
    assert _rows(session)["q"][1] == "6"  # two scans ran: 6 / 2, then 6 / 1
    session.advance(3)
    demo = session.snapshot.demo
    assert not demo.running and demo.error.startswith(f"{tmp_path / 'faulty.st'}:4: ")
    assert [e.text for e in demo_events(session)] == [demo.error]


def test_another_machine_offers_its_own_st_demo() -> None:
    session = Session("gantry", paused=True)
    assert session.programs.choose("gantry_demo.st")
    session.load("press")
    assert session.programs.labels == (PYTHON_DEMO, "press_demo.st")
    chosen = session.programs.chosen
    assert chosen is not None and chosen.label == PYTHON_DEMO  # gantry_demo.st is not offered


@pytest.mark.browser
def test_a_page_runs_the_st_demo_and_watches_its_step(
    browser: Browser, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("MCL_ST_CACHE", str(tmp_path / "st-cache"))  # a first translation
    with Viewer("gantry", port=0, demo=False) as viewer:
        context = browser.new_context(viewport={"width": 1280, "height": 1000})
        try:
            page = context.new_page()
            page.goto(viewer.url)
            page.get_by_role("button", name="Power", exact=True).wait_for(timeout=60_000)
            take_control(page, viewer)
            page.get_by_role("combobox", name="Program", exact=True).click()
            page.get_by_role("option", name="gantry_demo.st", exact=True).click()
            programs = viewer.session.programs
            # the first translation of a file takes seconds (blark's Earley parser); the page
            # says so meanwhile
            page.get_by_text("Translating gantry_demo.st").first.wait_for(timeout=10_000)
            wait_for(
                lambda: programs.chosen is not None and programs.chosen.path is not None,
                120.0,
                "the ST demo chosen",
            )
            page.get_by_text("Translating gantry_demo.st").wait_for(state="hidden", timeout=10_000)
            page.get_by_role("button", name="Run demo", exact=True).click()
            wait_for(lambda: viewer.session.snapshot.demo.running, 5.0, "the ST demo to run")
            page.get_by_role("tab", name="Watch").click()
            page.get_by_text("GantryStep").first.wait_for(timeout=5_000)
            step = viewer.session.snapshot.demo.step
            assert any(r.name == "step" and r.value == step for r in viewer.session.watch)
        finally:
            context.close()

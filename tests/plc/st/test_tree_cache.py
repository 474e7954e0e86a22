"""Parsed ST trees kept on disk: the second parse of a file loads its tree, a damaged file is
parsed again and replaced, errors are never kept, and the cache can be switched off; each
top-level item is kept on its own (a changed one alone parses again, a kept one moves to its
new lines) and parses in worker processes when there are several."""

from __future__ import annotations

import pickle
import stat
from pathlib import Path

import blark.transform as tf
import pytest

from plc.st.errors import STError
from plc.st.frontend import chunks, tree_cache
from plc.st.frontend import parse as st_parse

SOURCE = """PROGRAM Count
VAR n : INT; END_VAR
n := n + 1;
END_PROGRAM
"""


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "st-cache"
    monkeypatch.setenv("MCL_ST_CACHE", str(folder))
    return folder


def kept(folder: Path) -> list[Path]:
    return sorted(folder.glob("*.pickle")) if folder.exists() else []


def test_the_second_parse_loads_the_kept_tree(cache: Path, monkeypatch: pytest.MonkeyPatch):
    first = st_parse.parse(SOURCE, "count.st")
    assert len(kept(cache)) == 1
    assert stat.S_IMODE(cache.stat().st_mode) == 0o700
    monkeypatch.setattr(st_parse, "_parse", lambda *a: pytest.fail("parsed again"))
    assert st_parse.parse(SOURCE, "count.st") == first


def test_another_source_or_file_name_is_parsed_on_its_own(cache: Path):
    st_parse.parse(SOURCE, "count.st")
    st_parse.parse(SOURCE, "other.st")
    st_parse.parse(SOURCE.replace("1", "2"), "count.st")
    assert len(kept(cache)) == 3


def test_a_damaged_tree_is_parsed_again_and_replaced(cache: Path):
    first = st_parse.parse(SOURCE, "count.st")
    (file,) = kept(cache)
    file.write_bytes(b"\x80\x05not a pickle")
    assert st_parse.parse(SOURCE, "count.st") == first
    assert tree_cache.cached(file.stem, lambda: pytest.fail("parsed again")) == first


def test_a_syntax_error_is_not_kept(cache: Path):
    for _ in range(2):
        with pytest.raises(STError, match=r"bad\.st:3:"):
            st_parse.parse(SOURCE.replace("n + 1;", "n + ;"), "bad.st")
    assert kept(cache) == []


def test_an_empty_setting_switches_the_cache_off(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setenv("MCL_ST_CACHE", "")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert tree_cache.directory() is None
    st_parse.parse(SOURCE, "count.st")
    assert list(tmp_path.rglob("*.pickle")) == []


def test_an_unwritable_cache_still_parses(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("MCL_ST_CACHE", str(blocker / "st"))  # a directory under a file
    assert st_parse.parse(SOURCE, "count.st") is not None


TWO = """TYPE Mode : (Idle, Run); END_TYPE

(* the counter *)
FUNCTION_BLOCK Counter
VAR_OUTPUT n : INT; END_VAR
n := n + 1;
END_FUNCTION_BLOCK

PROGRAM Main
VAR c : Counter; m : Mode; k : INT; END_VAR
c();
k := c.n;
END_PROGRAM
"""


def _parsed_pieces(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The first lines of the pieces parsed from now on (not loaded from the cache)."""
    parsed: list[int] = []
    parse_piece = st_parse._parse

    def counting(text: str, filename: str, lines_before: int = 0, fast: bool = False):
        tree = parse_piece(text, filename, lines_before, fast)
        if tree is not None:  # read (by the fast parser alone it may not be)
            parsed.append(lines_before + 1)
        return tree

    monkeypatch.setattr(st_parse, "_parse", counting)
    return parsed


def test_each_item_is_kept_and_a_changed_one_alone_parses_again(
    cache: Path, monkeypatch: pytest.MonkeyPatch
):
    """A source of three items keeps three trees; changing the PROGRAM parses it alone."""
    first = st_parse.parse(TWO, "two.st")
    assert len(kept(cache)) == 3
    parsed = _parsed_pieces(monkeypatch)
    assert st_parse.parse(TWO, "two.st") == first and parsed == []
    changed = st_parse.parse(TWO.replace("k := c.n;", "k := c.n + 1;"), "two.st")
    assert parsed == [8] and changed.items[:2] == first.items[:2]
    assert changed.items[2] != first.items[2]


def test_a_kept_item_takes_its_new_lines_when_moved(cache: Path):
    """Lines added above an item: its kept tree is moved to where it now stands, as a fresh
    parse of the whole source places it."""
    st_parse.parse(TWO, "two.st")
    moved = TWO.replace("(* the counter *)", "(* the counter,\n   counting scans *)")
    loaded = st_parse.parse(moved, "two.st")
    whole = st_parse._parse(moved, "two.st")
    assert loaded.items == whole.items
    assert [i.meta.line for i in loaded.items] == [1, 5, 10]


def test_a_corrupt_item_is_parsed_again_the_others_loaded(
    cache: Path, monkeypatch: pytest.MonkeyPatch
):
    first = st_parse.parse(TWO, "two.st")
    for file in kept(cache):
        if isinstance(pickle.loads(file.read_bytes()).items[0], tf.Program):
            file.write_bytes(file.read_bytes()[:40])
    parsed = _parsed_pieces(monkeypatch)
    assert st_parse.parse(TWO, "two.st") == first and parsed == [8]


def test_a_syntax_error_in_a_later_item_names_its_line(cache: Path):
    with pytest.raises(STError, match=r"^two\.st:12:8: "):
        st_parse.parse(TWO.replace("k := c.n;", "k := c.;"), "two.st")


def test_items_parse_in_worker_processes_as_here(cache: Path, monkeypatch: pytest.MonkeyPatch):
    """With two jobs and enough lines the items the fast parser cannot read here (none, as if)
    parse in two worker processes: the same trees as one process gives, kept for the next
    load; the first syntax error in the file wins."""
    monkeypatch.setenv("MCL_ST_JOBS", "2")
    monkeypatch.setattr(st_parse, "_PARALLEL_LINES", 1)
    monkeypatch.setattr(st_parse.lalr, "parse", lambda text: None)
    parsed = _parsed_pieces(monkeypatch)
    trees = st_parse.parse(TWO, "two.st")
    assert parsed == [] and len(kept(cache)) == 3  # parsed in the workers, kept by them
    assert trees.items == st_parse._parse(TWO, "two.st").items
    broken = TWO.replace("n := n + 1;", "n := n + ;").replace("k := c.n;", "k := c.;")
    with pytest.raises(STError, match=r"^two\.st:6:10: "):
        st_parse.parse(broken, "two.st")


def test_a_source_that_cannot_be_cut_parses_whole(cache: Path):
    """Text between the items (here a stray ';' line of TwinCAT's) keeps the source one piece."""
    assert [c.line for c in chunks.chunks(TWO)] == [1, 2, 8]
    assert len(chunks.chunks(TWO.replace("\nPROGRAM Main", "\n42\nPROGRAM Main"))) == 1


def test_items_the_fast_parser_reads_parse_here_without_workers(
    cache: Path, monkeypatch: pytest.MonkeyPatch
):
    """A worker process starts slower than the fast parser reads an item: with two jobs and
    enough lines, items it reads parse in this process (each one once, kept)."""
    monkeypatch.setenv("MCL_ST_JOBS", "2")
    monkeypatch.setattr(st_parse, "_PARALLEL_LINES", 1)
    parsed = _parsed_pieces(monkeypatch)
    trees = st_parse.parse(TWO, "two.st")
    assert parsed == [1, 2, 8] and len(kept(cache)) == 3
    assert trees.items == st_parse._parse(TWO, "two.st").items


def test_a_project_loaded_from_the_cache_translates_as_a_fresh_load(
    cache: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    """A TwinCAT project (the load benchmark's, three stations) loaded with an empty cache, then
    from the cache (its files' lines, the cut into items, the trees at their places): the same
    Python as with the cache off; an edited file is read again and moved items take their new
    lines, and a message names the file's own line from the cache as when first read."""
    import mcl
    import plc.st
    from tests.benchmarks.st_twincat import write_project

    folder = tmp_path / "Plant"
    write_project(folder, count=3)
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})

    def source() -> str:
        return str(plc.st.load(folder, machine).module.source)

    first, cached = source(), source()
    monkeypatch.setenv("MCL_ST_CACHE", "")
    assert first == cached == source()
    monkeypatch.setenv("MCL_ST_CACHE", str(cache))
    station = folder / "FB_Station1.TcPOU"
    station.write_text(
        station.read_text().replace(
            "Velocity : LREAL := 100.0;", "Velocity : LREAL := 100.0;\n  Extra : INT;"
        )
    )
    edited = source()
    monkeypatch.setenv("MCL_ST_CACHE", "")
    assert edited == source() != first and "Extra" in edited
    monkeypatch.setenv("MCL_ST_CACHE", str(cache))
    station.write_text(station.read_text().replace("mean := mean / 8.0;", "mean := mean / ;"))
    for _ in range(2):
        with pytest.raises(STError, match=rf"^{station}:\d+:\d+: unexpected ';'"):
            plc.st.load(folder, machine)

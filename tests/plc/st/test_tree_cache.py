"""Parsed ST trees kept on disk: the second parse of a file loads its tree, a damaged file is
parsed again and replaced, errors are never kept, and the cache can be switched off."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from plc.st.errors import STError
from plc.st.frontend import parse as st_parse
from plc.st.frontend import tree_cache

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

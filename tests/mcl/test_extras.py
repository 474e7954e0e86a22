"""The extras (mcl.extras): its table mirrors pyproject.toml's, an extra brings the extras it
builds on, and a missing package names the extra to install (an environment with the core alone:
tests/test_core_install.py)."""

from __future__ import annotations

import re
import tomllib

import pytest

from mcl import extras
from tests.helpers import ROOT

PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
SELF = re.compile(rf"{extras.DISTRIBUTION}\[(?P<extras>[a-z,]+)\]")


def table() -> dict[str, tuple[set[str], set[str]]]:
    """pyproject.toml's extras but ``all`` and the tools' ``test`` and ``docs``: extra → (its
    packages, the extras it builds on)."""
    out = {}
    for extra, requirements in PROJECT["optional-dependencies"].items():
        if extra in ("all", "test", "docs"):
            continue
        packages, included = set(), set()
        for requirement in requirements:
            if match := SELF.fullmatch(requirement):
                included |= set(match["extras"].split(","))
            else:
                packages.add(requirement.partition("==")[0])
        out[extra] = (packages, included)
    return out


def test_the_table_of_extras_is_pyprojects():
    assert {e: (set(extras.PACKAGES[e]), set(extras.INCLUDES[e])) for e in extras.PACKAGES} == (
        table()
    )
    everything = SELF.fullmatch(PROJECT["optional-dependencies"]["all"][0])
    assert everything is not None and set(everything["extras"].split(",")) == set(extras.PACKAGES)


def test_an_extra_brings_the_packages_of_the_extras_it_builds_on_each_once():
    assert extras.packages("st") == ["blark", "lark"]
    assert extras.packages("viewer") == [
        *("viser", "mujoco", "dm_control", "blark", "lark", "pymodbus", "asyncua"),
    ]
    assert extras.packages("sweep") == [
        *("pyarrow", "dask", "distributed", "matplotlib", "pandas", "mujoco", "dm_control"),
        *("blark", "lark"),
    ]


def test_every_extra_is_installed_here():
    assert [e for e in extras.PACKAGES if not extras.installed(e)] == []
    extras.require("viewer", "viewer")  # no error


def test_a_missing_package_names_the_extra_to_install(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setitem(extras.PACKAGES, "gauges", ("json", "no_such_gauge_driver"))
    monkeypatch.setitem(extras.INCLUDES, "gauges", ("st",))
    assert extras.missing("gauges") == ["no_such_gauge_driver"]
    assert not extras.installed("gauges")
    with pytest.raises(ImportError) as raised:
        extras.require("scenes.gauges", "gauges")
    assert str(raised.value) == (
        "scenes.gauges needs the [gauges] extra: pip install 'mcl-testbench[gauges]'"
    )
    assert raised.value.name == "no_such_gauge_driver"
    assert raised.value.__cause__ is None and raised.value.__suppress_context__

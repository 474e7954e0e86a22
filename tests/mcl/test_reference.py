"""The Markdown reference (docs/reference.md) is the generator's output and covers the library;
the README is self-contained: it links and names nothing outside the repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import mcl
from mcl import reference
from mcl.fb import FunctionBlock, input_names
from tests.helpers import ROOT

ROOT = ROOT
README = ROOT / "README.md"
DOC = ROOT / "docs" / "reference.md"
REGENERATE = "run `python -m mcl.reference --write` and commit docs/reference.md"

OUTSIDE = re.compile(r"\.\./|(?<![\w.])~/")
"""A parent-directory or home path."""
ABSOLUTE = re.compile(r"(?<![\w.:/])/(?:work|home|tmp|root|usr|etc|opt|mnt|var)/")
"""An absolute path of the machine the text was written on."""


INTERPRETED = pytest.mark.skipif(
    mcl.COMPILED,
    reason="reads the interpreted classes in this process (their annotations and declared "
    "values); the pure-Python run of the suite checks it",
)


@pytest.fixture(scope="module")
def generated() -> str:
    return reference.generate()


@pytest.fixture(scope="module")
def doc() -> str:
    assert DOC.exists(), f"{DOC.relative_to(ROOT)} is missing: {REGENERATE}"
    return DOC.read_text(encoding="utf-8")


def test_doc_is_the_generators_output(doc, generated):
    assert doc == generated, f"docs/reference.md is out of date: {REGENERATE}"


def test_check_option_agrees(doc, generated, capsys):
    assert reference.main(["--check"]) == (0 if doc == generated else 1)
    capsys.readouterr()


@INTERPRETED
def test_every_exported_function_block_has_a_section(generated):
    exported = [
        getattr(mcl, name)
        for name in mcl.__all__
        if isinstance(getattr(mcl, name), type)
        and issubclass(getattr(mcl, name), FunctionBlock)
        and name != "MotionFB"  # the base class of the motion blocks, for typing a procedure
    ]
    assert len(exported) >= 30, "too few function blocks found in mcl.__all__"
    assert {cls.__name__ for cls in reference.function_blocks()} == {c.__name__ for c in exported}
    for cls in exported:
        assert f"\n### {cls.__name__}\n" in generated, f"no section for {cls.__name__}"
        section = generated.split(f"\n### {cls.__name__}\n", 1)[1].split("\n#", 1)[0]
        for name in input_names(cls):
            assert f"| `{name}` |" in section, f"{cls.__name__}: input {name} missing"


@INTERPRETED
def test_outputs_of_a_motion_block():
    names = [name for name, _, _ in reference.outputs(mcl.MC_MoveAbsolute)]
    for expected in ("Done", "Busy", "Active", "CommandAborted", "Error", "ErrorID", "Aborted"):
        assert expected in names
    assert "Position" not in names and "Axis" not in names
    assert [n for n, _, _ in reference.outputs(mcl.MC_Power)] == [
        "Valid",
        "Error",
        "ErrorID",
        "Status",
    ]


def test_every_error_code_appears_with_both_texts(generated):
    for code in mcl.ErrorID:
        en, cz = mcl.error_text(code, "en"), mcl.error_text(code, "cz")
        row = f"| {int(code)} | `{code.name}` | {en} | {cz} |"
        assert row in generated, f"error {int(code)} {code.name}: row missing"


def test_states_and_enums_appear_with_their_values(generated):
    for enum_cls in (
        mcl.AxisState,
        mcl.GroupState,
        mcl.MC_BufferMode,
        mcl.MC_Direction,
        mcl.MC_SwitchMode,
        mcl.MC_ExecutionMode,
    ):
        assert f"\n### {enum_cls.__name__}\n" in generated
        for member in enum_cls:
            assert f"| `{member.name}` | {int(member)} |" in generated


@pytest.mark.parametrize(
    "path", [README, DOC], ids=lambda p: str(p.relative_to(ROOT)) if isinstance(p, Path) else p
)
def test_texts_point_nowhere_outside_the_repository(path):
    text = path.read_text(encoding="utf-8")
    for pattern in (OUTSIDE, ABSOLUTE):
        match = pattern.search(text)
        assert match is None, f"{path.name} points outside the repository: {match.group(0)!r}"
    for name in set(re.findall(r"[\w./-]+\.md\b", text)):
        if "/" in name:
            assert (ROOT / name).exists(), f"{path.name} names {name}, which does not exist"
        else:
            found = [p for p in ROOT.rglob(name) if ".venv" not in p.parts]
            assert found, f"{path.name} names {name}: no such file in the repository"
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue  # a web address or an anchor
        local = (path.parent / target.split("#", 1)[0]).resolve()
        assert local.is_relative_to(ROOT), f"{path.name} links outside the repository: {target}"
        assert local.exists(), f"{path.name} links to {target}, which does not exist"


def test_readme_points_to_the_reference():
    assert "(docs/reference.md)" in README.read_text(encoding="utf-8")


def test_reference_names_no_internal_documents(generated):
    match = re.search(r"(?i:\bseed\b)|§|\b(?!README)[A-Z]+\.md\b", generated)
    assert match is None, f"the reference mentions {match.group(0)!r}"


def test_public_text_drops_citations_of_sources():
    text = reference.public_text(
        "Blocks (MotionControlLib §3.7). Beyond the Teco library: X (PLCopen Part 4). Y\n"
        "(MotionControlLib Fig. 2.2, note 4); ``Z`` (1 = on, as the MotionControlLib manual says;\n"
        "docs/reference.md, BufferMode). W (MotionControlLib §3.12, REXYGEN MC_MoveAdditive)."
    )
    assert text == "Blocks. Beyond the Teco library: X (PLCopen Part 4). Y; `Z` (1 = on). W."

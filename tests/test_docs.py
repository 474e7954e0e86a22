"""The documentation is true: the README reads in a minute (150 lines at most), every relative
link of the README and of the site's pages (docs/) reaches a file and a heading that exist, every
code block of the README and the tutorials runs as it is written, and the site (mkdocs.yml)
builds strictly.

A code block runs where the line before it is a marker (an HTML comment, invisible on the page):

- ``<!-- run -->``: a Python program, run in a new interpreter on this checkout's packages in an
  empty folder (``with NAME`` after ``run:`` first writes the page's Structured Text program
  above it into that folder as NAME);
- ``<!-- run: pytest -->``: a pytest file, run with the testbench's plugin;
- ``<!-- run: st MACHINE until=NAME.NAME -->``: a Structured Text program, loaded with
  ``plc.st`` on MACHINE and scanned until that variable is TRUE (at most 10 s simulated).
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
import unicodedata
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.helpers import ROOT

README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.rglob("*.md"))
"""The site's pages."""
TEXTS = [README, *PAGES]
"""Every text whose links are checked."""
TUTORIALS = [README] + [
    DOCS / name
    for name in ("getting-started.md", "first-scenario.md", "st.md", "sweep.md", "commissioning.md")
]
"""The pages whose every Python and Structured Text block runs in this file."""
TESTED_ELSEWHERE = {
    "own-machine.md": "tests/scenes/test_own_machine_guide.py writes the guide's files, runs them",
    "bridge.md": "tests/scenes/bridge/test_docs.py follows its settings; its Python block is a "
    "fragment of a client of a PLC's network, whose whole clients are examples/bridge_*_client.py",
}
"""Tutorials whose code another test runs."""

FENCE = re.compile(r"^(`{3,})([^\n`]*)\n(.*?)^\1[ \t]*$", re.M | re.S)
"""A fenced code block: its fence, its info string, its body."""
MARKER = re.compile(r"<!--\s*run(?::\s*(?P<args>[^>]*?))?\s*-->\s*\n$")
"""The run marker on the line before a block."""
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
"""A Markdown link or image: its target."""
SNIPPET = re.compile(r'^--8<--\s+"([^"]+)"\s*$', re.M)
"""A file the snippets extension includes (a path from the repository's root)."""
SUBPROCESS_TIMEOUT = 600.0
"""Seconds a snippet may take (a sweep of four homings on a loaded machine takes a minute)."""


@dataclass(frozen=True)
class Block:
    page: Path
    line: int
    info: str
    body: str
    marker: str | None
    """The marker's arguments ('' for a bare ``run``), None when unmarked."""

    @property
    def is_st(self) -> bool:
        return self.info in ("st", "iecst") or bool(
            re.match(r"\s*(PROGRAM|FUNCTION_BLOCK|CONFIGURATION|TYPE)\b", self.body)
        )

    @property
    def is_code(self) -> bool:
        return self.info == "python" or self.is_st

    def __str__(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"


def blocks(page: Path) -> list[Block]:
    """The fenced code blocks of a page, with their run markers."""
    text = page.read_text(encoding="utf-8")
    out = []
    for match in FENCE.finditer(text):
        before = text[: match.start()]
        marker = MARKER.search(before[before.rfind("\n", 0, len(before) - 1) + 1 :])
        out.append(
            Block(
                page,
                before.count("\n") + 1,
                match.group(2).strip(),
                match.group(3),
                None if marker is None else (marker["args"] or "").strip(),
            )
        )
    return out


def prose(text: str) -> str:
    """``text`` without its code blocks and inline code (whose brackets are not links)."""
    text = FENCE.sub("", text)
    return re.sub(r"(`+)[^`\n]*?\1", "", text)


def expanded(page: Path) -> str:
    """The page with the files it includes (snippets) in their place."""
    text = page.read_text(encoding="utf-8")
    return SNIPPET.sub(lambda m: (ROOT / m.group(1)).read_text(encoding="utf-8"), text)


def slug(heading: str) -> str:
    """A heading's anchor as the site (Python-Markdown's toc) and GitHub make it."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = re.sub(r"[`*]", "", text)
    text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode("ascii")
    text = re.sub(r"[^\w\s-]", "", text).strip().lower()
    return re.sub(r"[-\s]+", "-", text)


def anchors(page: Path) -> set[str]:
    """The anchors of a page's headings."""
    text = FENCE.sub("", expanded(page))
    return {slug(h) for h in re.findall(r"^#{1,6}\s+(.+?)\s*#*\s*$", text, re.M)}


def local_links(page: Path) -> list[str]:
    """The relative link targets of a page (not web addresses)."""
    targets = LINK.findall(prose(page.read_text(encoding="utf-8")))
    return [t for t in targets if not re.match(r"[a-z][a-z0-9+.-]*:", t)]


def test_the_readme_reads_in_a_minute():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 150, f"README.md has {len(lines)} lines; the rest belongs in docs/"


def test_the_readme_links_every_page_of_the_site():
    """A newcomer reaches every tutorial and how-to from the README."""
    linked = {t.split("#", 1)[0] for t in local_links(README)}
    pages = {f"docs/{p.relative_to(DOCS).as_posix()}" for p in PAGES if p.parent == DOCS}
    pages -= {"docs/index.md", "docs/models.md", "docs/examples.md"}  # the site's own front page
    # and the pages that include models/README.md and examples/README.md, which it links instead
    assert {"models/README.md", "examples/README.md"} <= linked
    assert sorted(pages - linked) == []


@pytest.mark.parametrize("page", TEXTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_reaches_a_file_and_a_heading(page: Path):
    broken = []
    for target in local_links(page):
        path, _, anchor = target.partition("#")
        file = (page.parent / path).resolve() if path else page
        if not file.is_relative_to(ROOT):
            broken.append(f"{target}: outside the repository")
        elif not file.exists():
            broken.append(f"{target}: no such file")
        elif anchor and file.suffix == ".md" and anchor not in anchors(file):
            broken.append(f"{target}: no heading #{anchor} in {file.relative_to(ROOT)}")
    assert broken == []


def test_the_links_are_checked_at_all():
    """The link and anchor checks see the links a page has (a pattern that found none would
    let every broken link pass)."""
    assert "docs/getting-started.md#the-first-five-minutes-in-the-browser" in local_links(README)
    assert "the-first-five-minutes-in-the-browser" in anchors(DOCS / "getting-started.md")
    assert "gantry-gantryxml" in anchors(
        DOCS / "models.md"
    )  # a heading of the included models/README.md
    assert slug("Free-running and lockstep") == "free-running-and-lockstep"
    assert slug("`scene.faults` — the *faults*") == "scenefaults-the-faults"


@pytest.mark.parametrize("page", TUTORIALS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_code_block_of_a_tutorial_runs(page: Path):
    """Every Python and ST block of the README and the tutorials carries a run marker (so the
    tests below run it), and each tutorial has at least one."""
    code = [b for b in blocks(page) if b.is_code]
    assert [str(b) for b in code if b.marker is None] == []
    if page.name != "getting-started.md":
        assert code, f"{page.name}: no runnable code block"


def test_the_tutorials_code_not_run_here_is_run_elsewhere():
    for name, reason in TESTED_ELSEWHERE.items():
        assert (DOCS / name).exists(), name
        test = ROOT / reason.split()[0]
        assert test.exists(), f"{name}: {reason}"


RUNNABLE = [b for page in TEXTS for b in blocks(page) if b.marker is not None]


def test_the_run_markers_are_found():
    kinds = {b.marker.split()[0] if b.marker else "python" for b in RUNNABLE}
    assert {"python", "pytest", "st", "with"} <= kinds
    assert len(RUNNABLE) >= 8


def snippet_environment() -> dict[str, str]:
    """This checkout's packages first on the path, pure Python unless a build is there."""
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    environment["PYTHONPATH"] = str(ROOT)
    environment["MPLBACKEND"] = "Agg"
    return environment


def run(command: list[str], folder: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        command,
        cwd=folder,
        env=snippet_environment(),
        capture_output=True,
        text=True,
        timeout=SUBPROCESS_TIMEOUT,
    )


def st_block_before(block: Block) -> Block:
    """The page's last Structured Text block above ``block``."""
    above = [b for b in blocks(block.page) if b.is_st and b.line < block.line]
    assert above, f"{block}: 'with' names a program, but no ST block precedes it"
    return above[-1]


@pytest.mark.once
@pytest.mark.parametrize(
    "block", [b for b in RUNNABLE if not b.is_st], ids=lambda b: f"{b}"
)  # fmt: skip
def test_a_python_block_runs(block: Block, tmp_path: Path):
    args = (block.marker or "").split()
    if args[:1] == ["with"]:
        (tmp_path / args[1]).write_text(st_block_before(block).body, encoding="utf-8")
    if args[:1] == ["pytest"]:
        (tmp_path / "test_snippet.py").write_text(block.body, encoding="utf-8")
        command = [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "test_snippet.py",
        ]
    else:
        command = [sys.executable, "-c", block.body]
    result = run(command, tmp_path)
    assert result.returncode == 0, (
        f"{block} failed:\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}"
    )
    if args[:1] == ["pytest"]:
        assert re.search(r"\b1 passed\b", result.stdout), result.stdout


@pytest.mark.parametrize("block", [b for b in RUNNABLE if b.is_st], ids=lambda b: f"{b}")
def test_an_st_block_runs_on_its_machine(block: Block, tmp_path: Path):
    pytest.importorskip("mujoco", reason="the ST blocks run on a MuJoCo machine: [physics] extra")
    import plc.st
    import scenes

    match = re.fullmatch(r"st\s+(\w+)\s+until=([\w.]+)", block.marker or "")
    assert match, f"{block}: the marker is `run: st MACHINE until=VARIABLE`"
    machine, until = match.groups()
    source = tmp_path / "program.st"
    source.write_text(block.body, encoding="utf-8")
    scene = scenes.load(machine)
    prog = plc.st.load(str(source), scene)

    def reached() -> bool:
        value: object = prog
        for name in until.split("."):
            value = getattr(value, name)
        return bool(value)

    scene.run(prog, until=reached, timeout=10.0)
    assert not prog.error, prog.error
    assert [a.AxErrorID for a in scene.axes.values()] == [0] * len(scene.axes)


@pytest.mark.once
def test_the_site_builds_strictly(tmp_path: Path):
    """``mkdocs build --strict`` (``make lint``): a broken link, a missing page or an API name
    that does not resolve fails."""
    if importlib.util.find_spec("mkdocs") is None:
        pytest.skip("mkdocs is not installed: pip install -e '.[docs]' (make installs it)")
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        capture_output=True,
        text=True,
        timeout=SUBPROCESS_TIMEOUT,
    )
    assert result.returncode == 0, result.stderr[-5000:]
    built = {p.relative_to(tmp_path / "site") for p in (tmp_path / "site").rglob("index.html")}
    assert len(built) >= len(PAGES), sorted(map(str, built))

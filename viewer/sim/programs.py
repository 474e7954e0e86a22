"""The programs the viewer's Demo folder offers for a machine: its Python demo and every
Structured Text program found for it, ``examples/st/<machine>_demo.st`` of the repository and,
in each directory the viewer is started with (``--programs DIR``, read once at start), every
program as :func:`plc.st.load` takes it: an ``*.st`` file, a PLCopen XML export (``*.xml``), and
a TwinCAT project (a sub-folder holding ``.TcPOU``/``.TcDUT``/``.TcGVL`` files; the directory
itself if it holds them). A program that fails to translate for the machine is listed with its
error, never run.

An external PLC the viewer serves (``--modbus PORT``, :mod:`viewer.sim.external_plc`) is the last
entry for its machine. Programs are chosen from this fixed list only: a page can neither type
nor upload one.
"""

from __future__ import annotations

__all__ = [
    "EXAMPLES",
    "PYTHON_DEMO",
    "ProgramCatalog",
    "ProgramChoice",
    "ProgramSelection",
    "programs_in",
]

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import plc.st
import scenes
from plc.st import STProgram
from plc.st.codegen.translate import Module
from plc.st.frontend.project import SUFFIXES, read_project
from plc.st.runtime.task import chosen_program
from plc.st.runtime.watch import WatchedProgram
from scenes import DemoProgram
from scenes.scene import Scene
from scenes.tools.cli import machine_blocks
from viewer.sim.external_plc import ExternalPlc

PYTHON_DEMO = "demo (Python)"
"""The label of a machine's own Python demo program."""

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "st"
"""The repository's ST examples (``<machine>_demo.st`` is offered for that machine)."""


@dataclass(frozen=True)
class ProgramChoice:
    """One entry of the Program dropdown.

    Attributes:
        label: as the dropdown shows it.
        path: the ST file (None: the machine's Python demo or the external PLC).
        error: why the file cannot run on this machine (its translation error), else empty.
        external: the external PLC (commanding through its Modbus server).
    """

    label: str
    path: Path | None = None
    error: str = ""
    external: bool = False


class ProgramCatalog:
    """The ST files the viewer offers, and for each machine what they translate to.

    Args:
        directories: where else to look for ``*.st`` files (read now, once).
        mapping: AXIS_REF and I/O names onto the machine's (``{"Pohon.Ax1": "X"}``); an entry
            naming an axis a machine lacks is left out for that machine.
        examples: the repository's ST examples.
        external: the external PLC the viewer serves (offered for its machine).
    """

    def __init__(
        self,
        directories: Iterable[Path | str] = (),
        mapping: Mapping[str, str] | None = None,
        examples: Path = EXAMPLES,
        external: ExternalPlc | None = None,
    ) -> None:
        self._examples = examples
        self.external = external
        self._found = tuple(p for d in directories for p in programs_in(Path(d)))
        self._mapping = dict(mapping or {})
        self._modules: dict[tuple[str, Path], Module | str] = {}
        """Each program translated for a machine (by machine name), or its error."""
        self._places: dict[Path, Callable[[int], str]] = {}
        """A project's file:line of each line of its source."""

    def choices(self, scene: Scene, python_demo: bool) -> tuple[ProgramChoice, ...]:
        """What the Program dropdown offers for ``scene`` (``python_demo``: it has one), with
        the translation error of each file translated so far (see :meth:`translate`)."""
        offered = [ProgramChoice(PYTHON_DEMO)] if python_demo else []
        example = self._examples / f"{scene.name}_demo.st"
        paths = ([example] if example.is_file() else []) + list(self._found)
        labels = {c.label for c in offered}
        for path in paths:
            label = path.name if path.name not in labels else str(path)
            labels.add(label)
            translated = self._modules.get((scene.name, path))
            error = translated if isinstance(translated, str) else ""
            offered.append(ProgramChoice(label, path, error))
        if self.external is not None and self.external.serves(scene):
            offered.append(ProgramChoice(self.external.label, external=True))
        return tuple(offered)

    def mapping_for(self, scene: Scene) -> dict[str, str]:
        """The mapping's entries that fit ``scene`` (onto its axes, or I/O addresses)."""
        return {
            k: v
            for k, v in self._mapping.items()
            if v in scene.axes or v.startswith("%") or "." in v
        }

    def translate(self, scene: Scene, path: Path) -> str:
        """Translate ``path`` for ``scene``'s machine, once (seconds: call it outside the
        simulation thread); its error (empty: it translates)."""
        key = (scene.name, path)
        if key not in self._modules:
            try:
                self._modules[key] = self._compiled(scene, path)
            except (OSError, UnicodeDecodeError) as error:
                self._modules[key] = f"{path}: cannot read it ({error})"
            except plc.st.STError as error:
                self._modules[key] = str(error)
        translated = self._modules[key]
        return translated if isinstance(translated, str) else ""

    def _compiled(self, scene: Scene, path: Path) -> Module:
        """``path`` (an ST file or a project) translated for ``scene``; a project's messages
        name its files' lines.

        Raises:
            plc.st.STError: it does not translate.
        """
        axes, mapping, blocks = scene.axes, self.mapping_for(scene), machine_blocks(scene)
        if path.suffix.lower() == ".st":
            source = path.read_text(encoding="utf-8")
            module = plc.st.compile_source(source, str(path), axes, mapping, blocks)
            chosen_program(module.places, module.task, str(path))  # one that runs
            return module
        project = read_project(path)
        generated = f"{path.name}.st"
        try:
            module = plc.st.compile_source(project.source, generated, axes, mapping, blocks)
            chosen_program(module.places, module.task, generated)
        except plc.st.STError as error:
            raise project.relocated(error, generated) from None
        self._places[path] = project.where
        return module

    def factory(
        self, choice: ProgramChoice, python: Callable[[Scene], DemoProgram] | None
    ) -> Callable[[Scene], DemoProgram]:
        """What makes the program ``choice`` for a scene (``python``: the Python demo's
        factory, default ``scenes.demo``).

        The factory raises :class:`plc.st.STError` for a file that does not translate."""
        path = choice.path
        if choice.external and self.external is not None:
            return self.external.program
        if path is None:
            return python or scenes.demo

        def make(scene: Scene) -> DemoProgram:
            error = self.translate(scene, path)
            module = self._modules[(scene.name, path)]
            if error or isinstance(module, str):
                raise plc.st.STError(error)
            blocks = {n: b.make for n, b in machine_blocks(scene).items()}
            clock = lambda: scene.time  # noqa: E731
            period = scene.runtime.plc_period
            program = STProgram(module, None, scene.axes, clock, period, str(path), blocks)
            if path in self._places:  # a run-time fault names the project's file and line
                program.__dict__["_place"] = self._places[path]
            return WatchedProgram(program)

        return make


def programs_in(directory: Path) -> list[Path]:
    """The programs of ``directory``, by name: its ``*.st`` and PLCopen ``*.xml`` files and its
    TwinCAT projects (each sub-folder holding TwinCAT sources, the directory itself if it
    holds some)."""
    found = [p for p in directory.iterdir() if p.is_file() and p.suffix.lower() in (".st", ".xml")]
    found += [p for p in directory.iterdir() if p.is_dir() and _holds_twincat(p)]
    if any(p.is_file() and p.suffix.lower() in SUFFIXES for p in directory.iterdir()):
        found.append(directory)
    return sorted(found)


def _holds_twincat(folder: Path) -> bool:
    """``folder`` (or a folder under it) holds TwinCAT source files."""
    return any(p.is_file() and p.suffix.lower() in SUFFIXES for p in folder.rglob("*"))


class ProgramSelection:
    """The Program dropdown's state for the current scene: what it offers, what is chosen.

    Args:
        catalog: the ST files found.
        on_error: hears a chosen file's translation error (source, text).
    """

    def __init__(self, catalog: ProgramCatalog, on_error: Callable[[str, str], None]) -> None:
        self.catalog = catalog
        self._on_error = on_error
        self._scene: Scene | None = None
        self.choices: tuple[ProgramChoice, ...] = ()
        """What the dropdown offers (the Python demo first, if the machine has one)."""
        self.chosen: ProgramChoice | None = None
        """The program Run demo runs (None: the machine has none)."""
        self.translating = ""
        """The file being translated now (empty: none); a first translation takes seconds."""

    @property
    def labels(self) -> tuple[str, ...]:
        """The dropdown's entries."""
        return tuple(c.label for c in self.choices)

    def install(self, scene: Scene, python_demo: bool) -> None:
        """A new scene: its choices; the chosen program stays if it is offered for it."""
        self._scene = scene
        self.choices = self.catalog.choices(scene, python_demo)
        label = self.chosen.label if self.chosen is not None else ""
        if label not in self.labels:
            label = self.choices[0].label if self.choices else ""
        self.chosen = None
        if label:
            self.choose(label)

    def choose(self, label: str) -> bool:
        """Choose the program ``label`` (translated now, in the calling thread, if it was not
        yet); whether it can run. An unknown label changes nothing.

        Raises:
            ValueError: no such program is offered.
        """
        scene = self._scene
        choice = next((c for c in self.choices if c.label == label), None)
        if choice is None or scene is None:
            raise ValueError(f"no program {label!r}; offered: {', '.join(self.labels)}")
        if choice.path is not None and not choice.error:
            self.translating = label
            try:
                error = self.catalog.translate(scene, choice.path)
            finally:
                self.translating = ""
            if error:
                choice = ProgramChoice(choice.label, choice.path, error)
                self.choices = tuple(choice if c.label == label else c for c in self.choices)
                self._on_error("program", error)
        self.chosen = choice
        return not choice.error

    def factory(
        self, python: Callable[[Scene], DemoProgram] | None
    ) -> Callable[[Scene], DemoProgram]:
        """What makes the chosen program for a scene (``python``: the Python demo's factory)."""
        chosen = self.chosen or ProgramChoice(PYTHON_DEMO)
        return self.catalog.factory(chosen, python)

    def prepare(self, scene: Scene) -> None:
        """Translate the chosen file for ``scene`` before it is installed (in the calling
        thread, so that the simulation thread never waits for a translation)."""
        path = self.chosen.path if self.chosen is not None else None
        if path is not None and any(c.path == path for c in self.catalog.choices(scene, False)):
            self.catalog.translate(scene, path)

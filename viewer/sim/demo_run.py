"""The demo program a viewer session runs (:class:`DemoRun`): the program, where it stands (step,
error, done, runs), its results table and Repeat demo. The session's simulation thread starts it,
scans it every PLC cycle and samples it for each snapshot; a program that raises or reports an
error ends, and the viewer lives on. A program that finishes with an axis not at rest (in
StandStill or Disabled, outside a group) is reported (its error, the history) and not repeated:
it could not run again.
"""

from __future__ import annotations

__all__ = ["REPEAT_PAUSE", "DemoRun", "Results"]

import logging
from collections.abc import Callable

import mcl
import plc.st
from plc.sequence import unrest
from scenes import DemoProgram
from scenes.scene import Scene
from viewer.sim.snapshot import DemoView, results_of

log = logging.getLogger(__name__)

REPEAT_PAUSE = 1.0
"""Simulated time [s] between the end of a demo and its repeat (with Repeat demo on)."""

Results = tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]
"""A results table: its header and its rows, as text."""


class DemoRun:
    """The demo program of the session's scene and how it stands.

    Args:
        record_event: Records an entry in the error history (source, text).
    """

    def __init__(self, record_event: Callable[[str, str], None]) -> None:
        self._record_event = record_event
        self.program: DemoProgram | None = None
        """The running program (None: none runs)."""
        self.repeat = False
        """Repeat demo: a demo that ends successfully starts again after :data:`REPEAT_PAUSE`
        (a fresh program); a failed demo does not repeat."""
        self.clear()

    def clear(self) -> None:
        """No demo has run (a scene was just installed)."""
        self.program = None
        self.step = ""
        """The program's step, as last sampled."""
        self.error = ""
        """Why the last program failed ("": it did not)."""
        self.done = False
        """The program finished, as last sampled."""
        self.runs = 0
        """Programs started since Run demo was pressed (repeats count)."""
        self.results: Results = ((), ())
        """The program's results table, as last sampled."""
        self._repeat_at: float | None = None
        self._axes: dict[str, mcl.Axis] = {}

    def begin(self, factory: Callable[[Scene], DemoProgram], scene: Scene, name: str) -> bool:
        """Make a fresh program with ``factory`` for ``scene`` (named ``name``) and run it;
        whether it started (a factory that raises is an error in the history)."""
        self.step = self.error = ""
        self.done = False
        self._repeat_at = None
        try:
            self.program = factory(scene)
        except Exception as exc:  # a bug in a user program must not kill the viewer
            log.exception("demo program of scene %r failed to start", name)
            self.program = None
            text = f"{type(exc).__name__}: {exc}"
            self.error = str(exc) if isinstance(exc, plc.st.STError) else text
            self._record_event("demo", self.error)
            return False
        self.runs += 1
        self._axes = dict(scene.axes)
        return True

    def scan(self, now: float, name: str) -> str:
        """One PLC scan of the program at simulated time ``now`` [s] (scene ``name``): "ended"
        when it failed or finished in this scan, "repeat" when its repeat is due, else ""."""
        program = self.program
        if program is not None and not program.done:
            try:
                program()
                error = str(getattr(program, "error", "") or "")
            except Exception as exc:  # a bug in a user program must not kill the viewer
                log.exception("demo program of scene %r failed", name)
                error = f"{type(exc).__name__}: {exc}"
            if error:  # it failed (or reported an error, like ``python -m scenes run``): it ends
                self.step = str(getattr(program, "step", self.step))
                self.program = None
                self.error = error
                self._record_event("demo", error)
                return "ended"
            if program.done:
                restless = self._restless()
                if restless:  # reported, and not repeated: it could not run again
                    self.error = restless
                    self._record_event("demo", restless)
                else:
                    self._repeat_at = now + REPEAT_PAUSE
                return "ended"
        elif program is not None and self._repeat_at is not None:
            if not self.repeat:
                self._repeat_at = None
            elif now >= self._repeat_at - 1e-9:
                return "repeat"
        return ""

    def _restless(self) -> str:
        """Why the finished program left the machine unable to run again ("": it did not)."""
        axes = [
            f"{name} {unrest(a)}" for name, a in self._axes.items() if a.has_drive and unrest(a)
        ]
        if not axes:
            return ""
        return (
            f"the demo finished with {', '.join(axes)}: it must leave every axis at rest "
            f"(StandStill or Disabled, outside any group) to run again"
        )

    def sample(self) -> None:
        """Take the program's step, done and results for a snapshot."""
        program = self.program
        if program is not None:
            self.step = str(program.step)
            self.done = bool(program.done)
            self.results = results_of(program)

    def view(self, available: bool) -> DemoView:
        """What the viewer shows of the demo (``available``: the scene has a demo)."""
        return DemoView(
            available=available,
            running=self.program is not None and not self.done,
            done=self.done,
            step=self.step,
            error=self.error,
            runs=self.runs,
            repeat=self.repeat,
        )

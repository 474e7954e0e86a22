"""The shape of a PLC program as the demos and the viewer see it: :class:`StepSequence`, the step
sequence the demos share, and :class:`DemoProgram`, what a demo reports while it runs."""

from __future__ import annotations

from typing import ClassVar, Protocol


class StepSequence:
    """The usual shape of a demo program: a PLC step sequence. ``STEPS`` names the steps in
    order (the last one means finished), ``index`` is the step now, a non-empty ``error`` stops
    it; a subclass is called once per PLC cycle and advances ``index``."""

    STEPS: ClassVar[tuple[str, ...]] = ("done",)
    index = 0
    error = ""

    @property
    def step(self) -> str:
        """What the program is doing (or why it stopped)."""
        return self.error or self.STEPS[self.index]

    @property
    def done(self) -> bool:
        """The sequence is complete."""
        return self.index == len(self.STEPS) - 1


class DemoProgram(Protocol):
    """A machine's demo: a PLC program (call once per PLC cycle) that reports its progress.

    A demo may also expose a results table (optional, not part of the protocol's required
    members): an attribute or property ``results``, a sequence of rows, oldest first, each a
    mapping column name → value (``float``, ``int``, ``str`` or ``None``), e.g. one row per cut
    ``{"cut": 3, "length [mm]": 1500.12, "error [mm]": 0.12}``. The columns are those of the last
    row, in its order (put units in the names); floats are shown with 3 decimals. The viewer
    shows the last rows in a table while the demo runs and after it ended.
    """

    @property
    def done(self) -> bool:
        """The demo has finished."""
        ...

    @property
    def step(self) -> str:
        """What it is doing (the error, once one stopped it)."""
        ...

    @property
    def error(self) -> str:
        """Why it stopped (empty: no error)."""
        ...

    def __call__(self) -> None:
        """One PLC scan."""
        ...

"""The shape of a PLC program as the demos and the viewer see it: :class:`StepSequence`, the step
sequence the demos share (its steps declared as a table of :class:`Step`), and
:class:`DemoProgram`, what a demo reports while it runs. A demo ends with its axes
:func:`at_rest`, so that it can run again."""

from __future__ import annotations

__all__ = ["REST", "Block", "DemoProgram", "Step", "StepSequence", "at_rest", "never", "unrest"]

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import ClassVar, Protocol

from mypy_extensions import mypyc_attr

import mcl


class Block(Protocol):
    """What a step watches of a function block: its error outputs."""

    @property
    def Error(self) -> bool:
        """The block failed."""
        ...

    @property
    def ErrorID(self) -> int:
        """Why it failed."""
        ...


def at_rest(axes: Iterable[mcl.Axis]) -> bool:
    """Every driven axis of ``axes`` stands ready for the next program: in StandStill (no
    motion, no coupling, no MC_Stop held by its Execute) or Disabled (not powered), in no axes
    group, its set velocity 0. An encoder-only axis has nothing to stand (it measures)."""
    return all(not a.has_drive or not unrest(a) for a in axes)


def unrest(axis: mcl.Axis) -> str:
    """Why a driven axis is not at rest ("" when it is): its state, its group."""
    if axis.state not in (mcl.AxisState.StandStill, mcl.AxisState.Disabled):
        return axis.state.name
    if axis.group is not None:
        return "in an axes group"
    if axis.sp_vel != 0.0:
        return f"set velocity {axis.sp_vel:g}"
    return ""


REST = "come to rest"
"""The step a demo's sequence ends with before its last: its Execute inputs fallen, couplings
and groups ended, it is complete once the axes are :func:`at_rest`."""


def never() -> bool:
    """A step that is never complete (the last one: finished)."""
    return False


@dataclass(frozen=True)
class Step:
    """One step of a :class:`StepSequence`.

    Attributes:
        name: what the program does in it (shown as ``step``).
        complete: the step is complete (checked once per scan, after the blocks ran).
        blocks: the blocks whose error stops the sequence in this step, by name.
        then: gives the name of the step that follows (None: the next in order); called once,
            when the step is complete, it may prepare that step (e.g. the next cut's inputs).
    """

    name: str
    complete: Callable[[], bool] = never
    blocks: Mapping[str, Block] = field(default_factory=dict)
    then: Callable[[], str] | None = None


@mypyc_attr(allow_interpreted_subclasses=True)
class StepSequence:
    """The usual shape of a demo program: a PLC step sequence. ``STEPS`` names the steps in
    order (the last one means finished), ``index`` is the step now, a non-empty ``error`` stops
    it; a subclass is called once per PLC cycle and advances ``index``.

    A subclass may declare its steps as a table (:meth:`declare`): then each scan runs its
    blocks and calls :meth:`advance`, which stops on an error of a block the step watches and
    otherwise goes on once the step is complete. A demo's sequence ends with :data:`REST`
    before its last step, so that it is done with its axes at rest.
    """

    STEPS: ClassVar[tuple[str, ...]] = ("done",)
    index = 0
    error = ""
    entered = 0.0
    """When the current step began [s] (the ``now`` of :meth:`advance`)."""
    table: tuple[Step, ...] = ()
    """The declared steps, in the order of ``STEPS``."""

    @property
    def step(self) -> str:
        """What the program is doing (or why it stopped)."""
        return self.error or self.STEPS[self.index]

    @property
    def done(self) -> bool:
        """The sequence is complete."""
        return self.index == len(self.STEPS) - 1

    def declare(self, *steps: Step) -> None:
        """Declare the steps, one :class:`Step` per name of ``STEPS`` in its order.

        Raises:
            ValueError: the names are not those of ``STEPS``.
        """
        names = tuple(s.name for s in steps)
        if names != self.STEPS:
            raise ValueError(f"the steps {names} are not STEPS {self.STEPS}")
        self.table = steps

    @staticmethod
    def watching(blocks: Mapping[str, Block]) -> Callable[..., Step]:
        """A maker of steps that all watch ``blocks``: ``step(name, complete, then=None)``
        gives ``Step(name, complete, blocks, then)``."""

        def step(
            name: str, complete: Callable[[], bool], then: Callable[[], str] | None = None
        ) -> Step:
            return Step(name, complete, blocks, then)

        return step

    def advance(self, now: float = 0.0) -> None:
        """After the scan's blocks: stop on an error of a block the step watches (``error``
        from :meth:`failure`), else go to the following step once this one is complete;
        ``now`` is the time [s] (it becomes ``entered``)."""
        step = self.table[self.index]
        for name, block in step.blocks.items():
            if block.Error:
                self.error = self.failure(step.name, name, block.ErrorID)
                return
        if step.complete():
            following = self.index + 1 if step.then is None else self.STEPS.index(step.then())
            self.enter(following, now)

    def enter(self, index: int, now: float) -> None:
        """Go to step number ``index`` at time ``now`` [s] (a subclass may record the step
        that ended)."""
        self.index, self.entered = index, now

    def failure(self, step: str, block: str, error_id: int) -> str:
        """The ``error`` text when ``block`` fails in ``step``."""
        return f"{step}: {block} error {error_id}"

    def __call__(self) -> None:
        """One PLC scan: a subclass runs its blocks, then :meth:`advance` (declared here so that
        the compiled build gives every sequence the same layout)."""
        raise NotImplementedError(f"{type(self).__name__} defines no PLC scan (__call__)")


class DemoProgram(Protocol):
    """A machine's demo: a PLC program (call once per PLC cycle) that reports its progress.
    It is ``done`` only once every axis it drove is :func:`at_rest` (its couplings and groups
    ended, the Execute of its MC_Stop fallen), so that the next program (or the same demo
    again) finds the machine ready; a :class:`StepSequence` ends with a step that waits for it.

    A demo may also expose a results table (optional, not part of the protocol's required
    members): an attribute or property ``results``, a sequence of rows, oldest first, each a
    mapping column name → value (``float``, ``int``, ``str`` or ``None``), e.g. one row per cut
    ``{"cut": 3, "length [mm]": 1500.12, "error [mm]": 0.12}``. The columns are those of the last
    row, in its order (put units in the names); floats are shown with 3 decimals. The viewer
    shows the last rows in a table while the demo runs and after it ended.
    """

    @property
    def done(self) -> bool:
        """The demo has finished, its axes at rest."""
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

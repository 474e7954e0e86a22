"""The operator program of a scene: one :class:`~plc.operator.axis.AxisOperator` per axis, each
driven by its front end — the viewer's panel (:mod:`plc.operator.hmi`) or a fieldbus master's
command words (:mod:`plc.operator.bus`) — and the release of axes groups: MC_GroupReset (from
GroupErrorStop), MC_GroupDisable (the group ramps to standstill), then MC_UngroupAllAxes, after
which the axes can be jogged, moved and homed one by one again.
"""

from __future__ import annotations

__all__ = ["FrontEnd", "GroupRelease", "OperatorProgram"]

import threading
from collections.abc import Iterable
from typing import Generic, Protocol, TypeVar

import mcl
from plc.operator.axis import AxisOperator, ErrorSink


class FrontEnd(Protocol):
    """What drives an axis' operator: called once per PLC scan, it gives its orders."""

    @property
    def operator(self) -> AxisOperator:
        """The axis' function blocks."""
        ...

    def __call__(self) -> None:
        """One PLC scan."""
        ...


F = TypeVar("F", bound=FrontEnd)


class GroupRelease:
    """Takes one axes group apart (one PLC scan per call): MC_GroupReset if it is in
    GroupErrorStop, MC_GroupDisable (its motion ramps to standstill), MC_UngroupAllAxes.

    Args:
        group: The group.
        on_error: Hears of a refusal: ("group <name>", text).
    """

    def __init__(self, group: mcl.AxesGroup, on_error: ErrorSink | None = None) -> None:
        self.group = group
        self.reset = mcl.MC_GroupReset(AxesGroup=group)
        self.disable = mcl.MC_GroupDisable(AxesGroup=group)
        self.ungroup = mcl.MC_UngroupAllAxes(AxesGroup=group)
        self._on_error = on_error
        self._steps: list[mcl.MC_GroupReset | mcl.MC_GroupDisable | mcl.MC_UngroupAllAxes] = []
        if group.state == mcl.GroupState.GroupErrorStop:
            self._steps.append(self.reset)
        self._steps += [self.disable, self.ungroup]
        self.done = False
        """The group is empty (or the release ended with an error)."""

    def __call__(self) -> None:
        """One scan: the current step until Done or Error, then the next."""
        if self.done:
            return
        block = self._steps[0]
        block(Execute=True)
        if block.Error:
            if self._on_error is not None:
                name = type(block).__name__
                self._on_error(
                    f"group {self.group.name}",
                    f"{name}: error {block.ErrorID} ({mcl.error_text(block.ErrorID)})",
                )
            block(Execute=False)
            self.done = True
        elif block.Done:
            block(Execute=False)
            self._steps.pop(0)
            self.done = not self._steps


class OperatorProgram(Generic[F]):
    """The operator PLC program of a scene (one PLC scan per call).

    Args:
        front_ends: One per axis, each with the axis' operator.
        on_error: Hears of a refused group release: (group, text).
    """

    def __init__(self, front_ends: Iterable[F], on_error: ErrorSink | None = None) -> None:
        self.front_ends: dict[str, F] = {f.operator.axis.name: f for f in front_ends}
        """The front ends by axis name."""
        self.axes = {name: f.operator for name, f in self.front_ends.items()}
        """The axes' function blocks by axis name."""
        self._scan = list(self.front_ends.values())
        self._on_error = on_error
        self._release = threading.Event()
        self.releasing: list[GroupRelease] = []
        """Groups being taken apart."""

    def groups(self) -> list[mcl.AxesGroup]:
        """The axes groups the scene's axes belong to now."""
        found: list[mcl.AxesGroup] = []
        for operator in self.axes.values():
            group = operator.axis.group
            if isinstance(group, mcl.AxesGroup) and group not in found:
                found.append(group)
        return found

    def release_groups(self) -> None:
        """Take every axes group apart at the next scan (thread-safe)."""
        self._release.set()

    def __call__(self) -> None:
        """One PLC scan: group releases first, then every axis as its front end orders."""
        if self._release.is_set():
            self._release.clear()
            busy = {r.group for r in self.releasing}
            self.releasing += [
                GroupRelease(g, self._on_error) for g in self.groups() if g not in busy
            ]
        if self.releasing:
            for release in self.releasing:
                release()
            self.releasing = [r for r in self.releasing if not r.done]
        for front_end in self._scan:
            front_end()
            operator = front_end.operator
            if operator.group_stop:
                operator.group_stop = False
                self._release.set()

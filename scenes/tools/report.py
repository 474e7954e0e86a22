"""Readable console reports of a running program: FB output edges, axis positions and states."""

from __future__ import annotations

__all__ = ["SIGNALS", "EdgeLog"]

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import mcl

SIGNALS = ("Status", "Done", "Busy", "Active", "InVelocity", "CommandAborted", "Error")


class EdgeLog:
    """Prints every edge of the watched FB outputs with the time and the axes' positions.

    Args:
        machine: a SimMachine or a scene.
        out: where lines go (``print`` by default).
    """

    def __init__(self, machine: mcl.Machine, out: Callable[[str], None] = print) -> None:
        self.machine = machine
        self.out = out
        self.blocks: dict[str, Any] = {}
        self._last: dict[tuple[str, str], Any] = {}
        self.peak_error = {name: 0.0 for name in machine.axes}
        machine.runtime.observers.append(self._observe)

    def watch(self, **blocks: Any) -> None:
        """Add FB instances to watch, by name."""
        self.blocks.update(blocks)

    def step(self, t: float, name: str) -> None:
        """The program entered the step ``name`` at ``t`` [s]: a new section (an empty step
        names none: no line)."""
        if name:
            self.out(f"\n== t={t:6.3f} s  {name}")

    def stopped(self, t: float, kind: str, message: str) -> None:
        """The program stopped at ``t`` [s]: a line of its own, ``kind`` (``fault``: a
        run-time fault; ``error``: the program's error) and the message."""
        self.out(f"\nt={t:7.3f} s  {kind}: {message}")

    def _axes(self) -> str:
        return "  ".join(
            f"{n}={a.POS:9.3f} {a.config.unit} {a.state.name}" for n, a in self.machine.axes.items()
        )

    def _observe(self, t: float) -> None:
        for name, axis in self.machine.axes.items():
            fe = abs(axis.following_error)
            if fe > self.peak_error[name]:
                self.peak_error[name] = fe
        for name, block in self.blocks.items():
            for signal in SIGNALS:
                value = getattr(block, signal, None)
                if value is None:
                    continue
                key = (name, signal)
                if self._last.get(key, False) != value:
                    self._last[key] = value
                    edge = "↑" if value else "↓"
                    extra = f" ErrorID={block.ErrorID}" if signal == "Error" and value else ""
                    self.out(f"t={t:7.3f} s  {name}.{signal}{edge}{extra}   {self._axes()}")

    def summary(self) -> None:
        """Final positions, states and peak following errors."""
        self.out("\n== summary")
        for name, axis in self.machine.axes.items():
            self.out(
                f"{name}: POS {axis.POS:.4f} {axis.config.unit}, state {axis.state.name}, "
                f"AxErrorID {axis.AxErrorID}, peak following error "
                f"{self.peak_error[name]:.4f} {axis.config.unit}"
            )
        signals = getattr(self.machine, "signals", {})
        for name, signal in signals.items():
            value = self.machine.signal(name)  # type: ignore[attr-defined]
            unit = f" {signal.unit}" if signal.unit not in ("", "0/1") else ""
            self.out(f"{signal.label or name}: {value:.4g}{unit}")

    def results(self, rows: Sequence[Mapping[str, Any]]) -> None:
        """The demo's results, one line per row (its columns those of the first row)."""
        if not rows:
            return
        columns = list(rows[0])
        self.out(f"\n== results ({len(rows)} rows)")
        self.out("  ".join(columns))
        for row in rows:
            self.out("  ".join(_cell(row.get(c)) for c in columns))


def _cell(value: Any) -> str:
    """A result's value as text: numbers to four significant digits, nothing as ``—``."""
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)

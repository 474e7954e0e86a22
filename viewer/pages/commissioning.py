"""The commissioning controls of one driven axis (a folder in its tab): the velocity
override, the jog speed, the reversing sequence A ↔ B with its progress, and the step test of
the position loop with its figures. Every element is made with
:class:`~viewer.pages.widgets.SceneGui` (the gate checks what a page sends); a press only sets a
request of :class:`~plc.operator.hmi.AxisRequests`, and the operator program does the rest in
the simulation thread."""

from __future__ import annotations

__all__ = ["JOG_SPEEDS", "Click", "CommissioningPanel", "step_html"]

import html
import math
from collections.abc import Callable
from typing import Any

import viser

from plc.commissioning.axis import MAX_OVERRIDE
from plc.commissioning.reversing import MAX_CYCLES, MAX_DWELL, Reversing
from plc.commissioning.step_test import StepResponse, amplitude_range
from plc.operator.hmi import SLOW_JOG_FRACTION, AxisRequests
from viewer.pages.widgets import SceneGui
from viewer.serving.security import number_in
from viewer.sim.session import Session
from viewer.sim.snapshot import AxisView

JOG_SPEEDS = ("fast (100 %)", f"slow ({SLOW_JOG_FRACTION * 100:g} %)")
"""Choices of the Jog speed switch: the jog velocity, or :data:`SLOW_JOG_FRACTION` of it."""

Click = Callable[[viser.GuiEvent[viser.GuiButtonHandle]], None]


def step_html(result: StepResponse | None, running: bool, unit: str) -> str:
    """The figures of the last step test (or that it records)."""
    if running:
        return _box("Step test: recording …")
    if result is None:
        return _box("Step test: none yet.")
    u = html.escape(unit)
    return _box(
        f"Step {result.amplitude:g} {u}: rise time {_ms(result.rise_time)}, "
        f"overshoot {result.overshoot:.1f} %, settling (±2 %) {_ms(result.settling_time)}, "
        f"steady-state error {result.steady_state_error:.4f} {u}"
    )


def _ms(seconds: float) -> str:
    return f"{seconds * 1e3:.1f} ms" if math.isfinite(seconds) else "—"


def _box(content: str) -> str:
    return f'<div style="font-size:0.85em;padding:0 0.75em">{content}</div>'


class CommissioningPanel:
    """The Commissioning folder of one driven axis (built inside its tab).

    Args:
        gui: Where the scene's elements go (:class:`~viewer.pages.widgets.SceneGui`).
        session: The session the controls operate.
        view: The axis in the snapshot the scene was built from.
        generation: The scene's generation (a press on a panel of a replaced scene is ignored).
    """

    def __init__(self, gui: SceneGui, session: Session, view: AxisView, generation: int) -> None:
        self._gui = gui
        self._session = session
        self.name = view.name
        self.unit = view.unit
        self.generation = generation
        self.buttons: list[str] = []
        """Labels of the folder's buttons."""
        self._shown = ("", "")
        vmax = view.vmax if math.isfinite(view.vmax) and view.vmax > 0.0 else 100.0
        axis = session.scene.axes[view.name]
        with gui.api.add_folder("Commissioning", expand_by_default=False):
            self._build_override(view.commissioning.override if view.commissioning else 100.0)
            self._build_jog_speed()
            self._build_reversing(vmax)
            self.progress = gui.api.add_html("")
            self._build_step(*amplitude_range(axis.config.resolution))
            self.figures = gui.api.add_html(step_html(None, False, self.unit))

    def show(self, view: AxisView) -> None:
        """Send the sequence's progress and the step test's figures of ``view`` (only
        changes)."""
        c = view.commissioning
        if c is None:
            return
        progress = _box(
            f"Override {c.override:.0f} %<br>Reversing: "
            + html.escape(c.reversing.text or "not started.")
        )
        figures = step_html(c.step, c.step_running, self.unit)
        if progress != self._shown[0]:
            self.progress.content = progress
        if figures != self._shown[1]:
            self.figures.content = figures
        self._shown = (progress, figures)

    def _requests(self) -> AxisRequests | None:
        """The axis' requests, None if the scene was replaced."""
        if self._session.snapshot.generation != self.generation:
            return None
        return self._session.requests(self.name)

    def _button(self, label: str, action: Click, **kwargs: Any) -> None:
        self.buttons.append(label)
        self._gui.button(label, **kwargs).on_click(action)

    def _build_override(self, percent: float) -> None:
        """The override slider, 0 … 150 % (MC_SetOverride), at the axis' override ``percent``."""
        gui = self._gui
        slider = gui.api.add_slider(
            "Override [%]",
            min=0.0,
            max=MAX_OVERRIDE,
            step=5.0,
            initial_value=min(max(round(percent), 0.0), MAX_OVERRIDE),
        )
        gui.gate.allow(slider, number_in(0.0, MAX_OVERRIDE))
        gui.inputs.append(slider)

        @slider.on_update
        def _(event: viser.GuiEvent[viser.GuiSliderHandle[float]]) -> None:
            requests = self._requests()
            value = float(slider.value)
            if requests is not None and math.isfinite(value) and 0.0 <= value <= MAX_OVERRIDE:
                requests.override = value

    def _build_jog_speed(self) -> None:
        """The Jog speed switch (fast or slow jog, buttons and hotkeys alike)."""
        speed = self._gui.dropdown("Jog speed", JOG_SPEEDS, JOG_SPEEDS[0])

        @speed.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            requests = self._requests()
            if requests is not None and speed.value in JOG_SPEEDS:
                requests.jog_slow = speed.value == JOG_SPEEDS[1]

    def _build_reversing(self, vmax: float) -> None:
        """Targets A and B, velocity, acceleration, dwell, cycles; Start and Stop sequence."""
        gui, u = self._gui, self.unit
        a = gui.number(f"A [{u}]", 0.0, -1e9, 1e9, 0.001)
        b = gui.number(f"B [{u}]", 10.0, -1e9, 1e9, 0.001)
        velocity = gui.number(f"Velocity A↔B [{u}/s]", round(0.1 * vmax, 3), 1e-6, vmax, 0.001)
        acceleration = gui.number(f"Accel. A↔B [{u}/s²]", round(vmax, 3), 1e-6, 1e9, 0.001)
        dwell = gui.number("Dwell [s]", 0.5, 0.0, MAX_DWELL, 0.01)
        cycles = gui.number("Cycles (0: until stopped)", 3.0, 0.0, float(MAX_CYCLES), 1.0)

        def start(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            requests = self._requests()
            count = float(cycles.value)
            if requests is None or count != round(count):
                return
            requests.reverse(
                Reversing(
                    float(a.value),
                    float(b.value),
                    float(velocity.value),
                    float(acceleration.value),
                    float(dwell.value),
                    int(count),
                )
            )

        def stop(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            requests = self._requests()
            if requests is not None:
                requests.end_reversing()

        self._button("Start sequence", start, icon=viser.Icon.REPEAT, hint="MC_MoveAbsolute A↔B")
        self._button("Stop sequence", stop, icon=viser.Icon.PLAYER_STOP, hint="MC_Halt")

    def _build_step(self, low: float, high: float) -> None:
        """The step amplitude and the Step test button."""
        amplitude = self._gui.number(
            f"Step amplitude [{self.unit}]", round(10 * low, 6), -high, high, low
        )

        def step(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            requests = self._requests()
            value = float(amplitude.value)
            if requests is not None and event.client_id is not None:
                requests.step_test(value, event.client_id)  # the PLC refuses a too small one

        self._button(
            "Step test",
            step,
            icon=viser.Icon.STAIRS_UP,
            hint="A set-point step from standstill; its response measured",
        )

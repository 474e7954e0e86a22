"""The panel of one axis: its read-outs and, as its definition says, the buttons that operate
it (power, reset, homing, jog, stop, moves, servo tuning); and the hotkeys that step and jog the
first three driven axes."""

from __future__ import annotations

__all__ = [
    "JOG_KEYS",
    "STEPS",
    "STEP_KEYS",
    "TUNING",
    "AxisPanel",
    "HomeField",
    "add_hotkeys",
    "home_position_field",
]

import dataclasses
import math
from collections.abc import Callable
from typing import Any, NamedTuple

import viser
from viser._messages import HotkeyKey

from plc.operator.hmi import HOMING_PROCEDURES, AxisRequests, Move
from viewer.pages.panels import axis_panel_html
from viewer.pages.widgets import SceneGui
from viewer.serving.control import JOG_HOLD_HZ, Operators
from viewer.serving.security import number_in
from viewer.sim.session import Session
from viewer.sim.snapshot import AxisView

STEPS = ("0.01", "0.1", "1", "10", "100")
"""Incremental jog steps [u]."""

TUNING = (
    ("Kp", "Kp [V/u]", 0.0, 1e6),
    ("Ki", "Ki [V/(u·s)]", 0.0, 1e6),
    ("Ff", "Ff [-]", 0.0, 10.0),
    ("Ka", "Ka [s]", 0.0, 10.0),
    ("LimPos", "LimPos [u]", -1e9, 1e9),
    ("LimNeg", "LimNeg [u]", -1e9, 1e9),
)
"""Servo constants of the tuning panel: (GT_SetConstant input, label, min, max)."""

STEP_KEYS: tuple[tuple[HotkeyKey, HotkeyKey], ...] = (
    ("arrowright", "arrowleft"),
    ("arrowup", "arrowdown"),
    ("pageup", "pagedown"),
)
"""Hotkeys (with Shift) of Step+ and Step− of the first three driven axes; each press (and each
key repeat while held) moves the axis by its Step."""

JOG_KEYS = STEP_KEYS
"""Hotkeys (with Alt) of Jog+ and Jog− of the first three driven axes: the axis jogs while the
key is held. The page sends a trigger on the press and on every auto-repeat of the key, no
release: each trigger renews a dead-man (:data:`~viewer.serving.control.KEY_JOG_FIRST`, then
:data:`~viewer.serving.control.KEY_JOG_REPEAT`)."""


class HomeField(NamedTuple):
    """What the Home position field shows for a homing procedure."""

    value: float
    """The position [u]."""
    disabled: bool
    """The recipe's own position: shown, not editable."""
    hint: str
    """What the position means."""


def home_position_field(
    procedure: str, recipe: float, chosen: float = 0.0, unit: str = "u"
) -> HomeField:
    """The Home position field for ``procedure``: the recipe's own position ``recipe`` [u]
    (NaN: no recipe) for the recipe, else the operator's ``chosen`` one."""
    if procedure == "recipe":
        return HomeField(
            recipe,
            True,
            f"The machine's homing recipe gives the axis {recipe:g} {unit} at its reference "
            "(the machine's coordinates, its limits and the 3-D model follow from it)",
        )
    where = (
        "where it stands (no motion)"
        if procedure == HOMING_PROCEDURES[3]
        else ("at the next index pulse")
    )
    return HomeField(chosen, False, f"The position [{unit}] the axis is given {where}")


class AxisPanel:
    """Read-outs and buttons of one axis (built inside its tab): an encoder-only axis gets no
    drive buttons, an axis without a homing recipe no Home.

    Args:
        gui: Where the scene's elements go.
        session: The session the buttons operate.
        operators: Who operates (the jog buttons' dead-man).
        view: The axis in the snapshot the scene was built from.
        generation: The scene's generation (a click on a panel of a replaced scene is ignored).
    """

    def __init__(
        self,
        gui: SceneGui,
        session: Session,
        operators: Operators,
        view: AxisView,
        generation: int,
    ) -> None:
        self._gui = gui
        self._session = session
        self._operators = operators
        self.name = view.name
        self.generation = generation
        self.unit = view.unit
        self.buttons: list[str] = []
        """Labels of the panel's buttons (what the operator can press)."""
        self.html = ""
        """The read-outs last sent."""
        self.powered: bool | None = None
        """The power state the Power button shows."""
        self.step: viser.GuiDropdownHandle[str] | None = None
        """The Step choice (None: the axis has no drive)."""
        self.panel = gui.api.add_html(axis_panel_html(view))
        self.power: viser.GuiButtonHandle | None = None
        if view.has_drive:
            self.power = self._button(
                "Power", color="gray", icon=viser.Icon.POWER, hint="MC_Power on/off"
            )
            self.power.on_click(self._on_click(lambda _: session.toggle_power(self.name)))
        reset = self._button(
            "Reset", icon=viser.Icon.REFRESH_ALERT, hint="MC_Reset: clear the error"
        )
        reset.on_click(self._on_click(AxisRequests.reset))
        if view.has_drive:
            self._build_drive(view)

    def _build_drive(self, view: AxisView) -> None:
        """Stop, jog, Move to and Home first (they fit the page's height), then the other
        moves, the homing position and tuning of a driven axis."""
        stop = self._button("Stop", color="red", icon=viser.Icon.HAND_STOP, hint="MC_Stop")
        stop.on_click(self._on_click(AxisRequests.stop))
        self._build_jog()
        vmax = view.vmax if math.isfinite(view.vmax) and view.vmax > 0.0 else 100.0
        self._build_moves(vmax, view)
        self._build_velocity(vmax)
        self._build_tuning(view)

    def show(self, view: AxisView) -> None:
        """Send the read-outs and the power colour of ``view`` (only changes)."""
        html = axis_panel_html(view)
        if html != self.html:
            self.html = self.panel.content = html
        if self.power is not None and view.powered != self.powered:
            self.powered = view.powered
            self.power.color = "green" if view.powered else "gray"

    def _current(self) -> bool:
        return self._session.snapshot.generation == self.generation

    def _requests(self) -> AxisRequests:
        return self._session.requests(self.name)

    def _on_click(
        self, action: Callable[[AxisRequests], None]
    ) -> Callable[[viser.GuiEvent[viser.GuiButtonHandle]], None]:
        def callback(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if self._current():  # a click on a panel of a replaced scene is ignored
                action(self._requests())

        return callback

    def _button(self, label: str, **kwargs: Any) -> viser.GuiButtonHandle:
        self.buttons.append(label)
        return self._gui.button(label, **kwargs)

    def _build_jog(self) -> None:
        """Jog+ and Jog−: the axis jogs while the page holds the button (a dead-man)."""
        jog_pos = self._button("Jog+", icon=viser.Icon.ARROW_RIGHT, hint="Hold to jog (GT_Jog)")
        jog_neg = self._button("Jog−", icon=viser.Icon.ARROW_LEFT, hint="Hold to jog (GT_Jog)")
        operators = self._operators
        for handle, direction in ((jog_pos, 1), (jog_neg, -1)):

            def hold(event: viser.GuiEvent[viser.GuiButtonHandle], d: int = direction) -> None:
                if self._current() and event.client_id is not None:
                    operators.hold(event.client_id, self.generation, self.name, d)

            def release(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
                if event.client_id is not None:
                    operators.let_go(event.client_id)
                if self._current():
                    self._requests().release_jog()

            handle.on_hold(hold, callback_hz=JOG_HOLD_HZ)
            handle.on_click(release)  # a click ends on release

    def _build_velocity(self, vmax: float) -> None:
        """The jog velocity slider."""
        velocity = self._gui.api.add_slider(
            f"Jog velocity [{self.unit}/s]",
            min=round(0.01 * vmax, 3),
            max=round(vmax, 3),
            step=round(0.01 * vmax, 3),
            initial_value=round(0.1 * vmax, 3),
        )
        self._gui.gate.allow(velocity, number_in(round(0.01 * vmax, 3), round(vmax, 3)))
        self._gui.inputs.append(velocity)

        @velocity.on_update
        def _(event: viser.GuiEvent[viser.GuiSliderHandle[float]]) -> None:
            value = float(velocity.value)
            if self._current() and math.isfinite(value) and 0.0 < value <= vmax:
                self._requests().jog_velocity = value

    def _build_moves(self, vmax: float, view: AxisView) -> None:
        """Move to a target, Home, Step± by the chosen step, Move by a distance."""
        gui, unit = self._gui, self.unit
        target = gui.number(f"Target [{unit}]", 0.0, -1e9, 1e9, 0.001)
        move_to = self._button("Move to", icon=viser.Icon.TARGET, hint="MC_MoveAbsolute to Target")
        self._build_homing(view)
        step = self.step = gui.dropdown(f"Step [{unit}]", STEPS, "1")
        step_pos = self._button("Step+", icon=viser.Icon.CHEVRON_RIGHT, hint="Move by one step")
        step_neg = self._button("Step−", icon=viser.Icon.CHEVRON_LEFT, hint="Move back one step")
        distance = gui.number(f"Distance [{unit}]", 10.0, -1e9, 1e9, 0.001)
        move_by = self._button("Move by", icon=viser.Icon.ARROWS_HORIZONTAL, hint="MC_MoveRelative")
        move_velocity = gui.number(f"Velocity [{unit}/s]", round(0.1 * vmax, 3), 1e-6, vmax, 0.001)
        acceleration = gui.number(f"Acceleration [{unit}/s²]", round(vmax, 3), 1e-6, 1e9, 0.001)

        def move(kind: str, value: Callable[[], float]) -> Callable[[Any], None]:
            def callback(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
                if self._current():
                    self._requests().move(
                        Move(
                            kind,
                            float(value()),
                            float(move_velocity.value),
                            float(acceleration.value),
                        )
                    )

            return callback

        move_to.on_click(move("absolute", lambda: target.value))
        move_by.on_click(move("relative", lambda: distance.value))
        step_pos.on_click(move("relative", lambda: float(step.value)))
        step_neg.on_click(move("relative", lambda: -float(step.value)))

    def _build_homing(self, view: AxisView) -> None:
        """The homing procedure, Home, and the position homing gives the axis: the recipe's
        own (shown, not editable: the machine's coordinates follow from it), the field's value
        for an index pulse or set position."""
        gui = self._gui
        procedures = [p for p in HOMING_PROCEDURES if p != "recipe" or view.homeable]
        procedure = gui.dropdown("Homing", procedures, procedures[0])
        home = self._button("Home", icon=viser.Icon.HOME, hint="Run the chosen homing procedure")
        recipe = view.home_position
        unit = view.unit
        field = home_position_field(procedure.value, recipe, unit=unit)
        position = gui.number(
            f"Home position [{view.unit}]",
            field.value,
            -1e9,
            1e9,
            0.001,
            disabled=field.disabled,
            hint=field.hint,
        )
        chosen = [0.0]  # the operator's own value, kept while the recipe's is shown

        @procedure.on_update
        def _(event: viser.GuiEvent[viser.GuiDropdownHandle[str]]) -> None:
            if not position.disabled:
                chosen[0] = float(position.value)
            shown = home_position_field(procedure.value, recipe, chosen[0], unit)
            position.value, position.disabled, position.hint = shown

        @home.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            if self._current():
                self._requests().home(procedure.value, float(position.value))

    def _build_tuning(self, view: AxisView) -> None:
        """The Tuning folder: the servo constants, written with GT_SetConstant."""
        constants, unit = view.constants, self.unit
        with self._gui.api.add_folder("Tuning", expand_by_default=False):
            fields = {
                field: self._gui.number(
                    label.replace("u", unit, 1) if "[" in label else label,
                    float(getattr(constants, field)) if constants is not None else 0.0,
                    low,
                    high,
                    0.001,
                )
                for field, label, low, high in TUNING
            }
            write = self._button(
                "Write constants", icon=viser.Icon.DEVICE_FLOPPY, hint="GT_SetConstant"
            )

        @write.on_click
        def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
            base = self._session.snapshot.axes[self.name].constants
            if not self._current() or base is None:
                return
            values = {field: float(handle.value) for field, handle in fields.items()}
            self._requests().write_constants(dataclasses.replace(base, **values))


def add_hotkeys(
    gui: SceneGui,
    session: Session,
    operators: Operators,
    steps: dict[str, viser.GuiDropdownHandle[str]],
    generation: int,
) -> None:
    """Shift+arrow keys (and PageUp/PageDown) step the first three driven axes (``steps``: their
    Step choices); Alt+ the same keys jog them while held (:meth:`Operators.key_jog`)."""
    for name, (plus, minus) in zip(steps, STEP_KEYS, strict=False):
        for key, sign in ((plus, 1.0), (minus, -1.0)):
            label = f"{name} step {'+' if sign > 0 else '−'}"
            command = gui.command(
                label, description=f"Move {name} by its Step", hotkey=key, modifier="shift"
            )

            def step(event: Any, axis: str = name, s: float = sign) -> None:
                if session.snapshot.generation != generation:
                    return
                view = session.snapshot.axes[axis]
                distance = s * float(steps[axis].value)
                velocity = 0.1 * (view.vmax if math.isfinite(view.vmax) else 100.0)
                session.requests(axis).move(Move("relative", distance, velocity, 10.0 * velocity))

            command.on_trigger(step)
    for name, (plus, minus) in zip(steps, JOG_KEYS, strict=False):
        for key, direction in ((plus, 1), (minus, -1)):
            label = f"{name} jog {'+' if direction > 0 else '−'}"
            command = gui.command(
                label,
                description=f"Jog {name} while the key is held",
                hotkey=key,
                modifier="alt",
            )

            def jog(event: Any, axis: str = name, d: int = direction) -> None:
                if event.client_id is not None:
                    operators.key_jog(event.client_id, generation, axis, d)

            command.on_trigger(jog)

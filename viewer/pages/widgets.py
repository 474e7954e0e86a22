"""The GUI elements of one scene: each made with the gate's rule for what pages may send, and
removed (with its rule) when the scene goes."""

from __future__ import annotations

__all__ = ["SceneGui", "gated_button"]

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import viser

from viewer.serving.retire import retire
from viewer.serving.security import GuiGate, button_value, choice_of, number_in


def gated_button(
    gate: GuiGate,
    label: str,
    *,
    control: bool = True,
    gui: viser.GuiApi | None = None,
    **kwargs: Any,
) -> viser.GuiButtonHandle:
    """A button the gate lets pages press (those in control unless ``control`` is False), in
    ``gui`` (default: the server's GUI, every page)."""
    button = (gui or gate.server.gui).add_button(label, **kwargs)
    gate.allow(button, button_value, control)
    return button


@dataclass
class SceneGui:
    """Where the panels of one scene are built (see :meth:`remove`)."""

    gate: GuiGate
    """Checks what pages send to the elements."""
    inputs: list[Any] = field(default_factory=list)
    """The scene's buttons, dropdowns, sliders and number boxes."""
    commands: list[Any] = field(default_factory=list)
    """The scene's hotkey commands."""
    folders: list[viser.GuiFolderHandle] = field(default_factory=list)
    """The scene's folders (removing one removes what is in it)."""
    gui: viser.GuiApi | None = None
    """Where the elements go: one page's ``client.gui`` (None: the server's GUI, every page)."""

    @property
    def api(self) -> viser.GuiApi:
        """The GUI the elements go to."""
        return self.gui or self.gate.server.gui

    def folder(self, label: str, **kwargs: Any) -> viser.GuiFolderHandle:
        """A folder of the scene."""
        folder = self.api.add_folder(label, **kwargs)
        self.folders.append(folder)
        return folder

    def button(self, label: str, *, control: bool = True, **kwargs: Any) -> viser.GuiButtonHandle:
        """A button of the scene (pressed by the page in control unless ``control`` is False)."""
        button = gated_button(self.gate, label, control=control, gui=self.gui, **kwargs)
        self.inputs.append(button)
        return button

    def dropdown(
        self,
        label: str,
        options: Sequence[str],
        initial: str,
        *,
        control: bool = True,
        **kwargs: Any,
    ) -> viser.GuiDropdownHandle[str]:
        """A dropdown of the scene that accepts only its ``options``."""
        handle = self.api.add_dropdown(label, options, initial_value=initial, **kwargs)
        self.gate.allow(handle, choice_of(options), control)
        self.inputs.append(handle)
        return handle

    def number(
        self,
        label: str,
        value: float,
        low: float,
        high: float,
        step: float,
        *,
        control: bool = True,
        **kwargs: Any,
    ) -> Any:
        """A number box of the scene that accepts finite numbers in [low, high]."""
        handle = self.api.add_number(
            label, initial_value=value, min=low, max=high, step=step, **kwargs
        )
        self.gate.allow(handle, number_in(low, high), control)
        self.inputs.append(handle)
        return handle

    def command(self, label: str, **kwargs: Any) -> Any:
        """A hotkey command of the scene, for the page in control."""
        command = self.api.add_command(label, **kwargs)
        self.gate.allow_command(command, label)
        self.commands.append(command)
        return command

    def remove(self) -> None:
        """Remove the folders (retired: :mod:`viewer.serving.retire`), the commands and the
        gate's rules of the scene's elements."""
        retire(self.folders)
        self.gate.forget(self.inputs + self.commands)
        for command in self.commands:
            command.remove()

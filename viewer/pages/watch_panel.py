"""The Watch tab of a page: the running ST program's variables live (name, type, value, forced
marked), and forcing one by the page in control: a variable chosen from a dropdown, a
TRUE/FALSE choice or a number, Force and Unforce. Nothing is typed but a number: a page
chooses from fixed lists, and the gate checks every value it sends."""

from __future__ import annotations

__all__ = ["BOOL_CHOICES", "FORCED_STYLE", "NONE", "NUMBER_LIMIT", "WatchPanel", "watch_html"]

import html

import viser

from plc.st.runtime.watch import WatchRow
from viewer.pages.widgets import gated_button
from viewer.serving.security import GuiGate, choice_of, number_in
from viewer.sim.session import Session

NONE = "(none)"
"""The variable dropdown's entry while no ST program runs."""

BOOL_CHOICES = ("TRUE", "FALSE")
"""What a BOOL variable is forced to."""

NUMBER_LIMIT = 1e12
"""The largest magnitude a forced number may have (the number box's range)."""


FORCED_STYLE = ' data-forced style="color:#c62828"'
"""A forced variable's line: red, as a PLC IDE marks it."""


def watch_html(rows: tuple[WatchRow, ...]) -> str:
    """The watch table: a line per variable, a forced one marked **F** in red."""
    if not rows:
        return '<div style="padding:0 0.75em;font-size:0.85em">No ST program runs.</div>'
    lines = "".join(
        f"<tr{FORCED_STYLE if r.forced else ''}>"
        f"<td>{html.escape(r.name)}</td><td>{html.escape(r.type)}</td>"
        f"<td style='text-align:right'>{html.escape(r.value)}</td>"
        f"<td>{'F' if r.forced else ''}</td></tr>"
        for r in rows
    )
    return (
        '<div style="padding:0 0.75em;font-size:0.8em;font-family:monospace;'
        'max-height:24em;overflow-y:auto"><table style="width:100%">'
        "<tr><th align=left>variable</th><th align=left>type</th><th>value</th><th></th></tr>"
        f"{lines}</table></div>"
    )


class WatchPanel:
    """The watch table and forcing controls of one page.

    Args:
        gui: The page's GUI (``client.gui``), inside the tab it goes in.
        gate: Checks what the page sends.
        session: The session whose ST program is watched.
    """

    def __init__(self, gui: viser.GuiApi, gate: GuiGate, session: Session) -> None:
        self._gate, self.session = gate, session
        self.table = gui.add_html(watch_html(()))
        self._names: tuple[str, ...] = (NONE,)
        self.variable = gui.add_dropdown("Variable", self._names, hint="The variable to force")
        gate.allow(self.variable, choice_of(self._names), control=False)
        self.state = gui.add_dropdown("BOOL value", BOOL_CHOICES, initial_value="TRUE")
        gate.allow(self.state, choice_of(BOOL_CHOICES), control=False)
        self.number = gui.add_number("Number", 0.0, min=-NUMBER_LIMIT, max=NUMBER_LIMIT, step=0.001)
        gate.allow(self.number, number_in(-NUMBER_LIMIT, NUMBER_LIMIT), control=False)
        self.force = gated_button(
            gate, "Force", gui=gui, hint="Write the value before every scan until unforced"
        )
        self.unforce = gated_button(gate, "Unforce", gui=gui, hint="The program writes it again")
        self._rows: tuple[WatchRow, ...] = ()
        self._shown = ""
        self.force.on_click(lambda event: self._force())
        self.unforce.on_click(lambda event: self._unforce())

    def _force(self) -> None:
        """Force the chosen variable: a BOOL to the TRUE/FALSE choice, a number to the box."""
        name = self.variable.value
        row = next((r for r in self._rows if r.name == name), None)
        is_bool = row is not None and row.type == "BOOL"
        value: bool | float = self.state.value == "TRUE" if is_bool else float(self.number.value)
        self.session.force(name, value)

    def _unforce(self) -> None:
        self.session.force(self.variable.value, None)

    def update(self, rows: tuple[WatchRow, ...]) -> None:
        """Show ``rows`` (the panel rate); the variable choice follows the program's."""
        self._rows = rows
        names = tuple(r.name for r in rows if r.forceable) or (NONE,)
        if names != self._names:
            self._names = names
            self._gate.allow(self.variable, choice_of(names), control=False)
            self.variable.options = names
        content = watch_html(rows)
        if content != self._shown:
            self._shown = self.table.content = content

    def forget(self) -> None:
        """The page closed: drop the rules of its elements."""
        self._gate.forget((self.variable, self.state, self.number, self.force, self.unforce))

"""The all-axes overview: one row per axis of the current scene (a table in an HTML element).

Interface used by the per-page layout (:mod:`viewer.page`): ``Overview(gui)`` adds its element
to the current container of ``gui`` (a page's ``client.gui``); :meth:`Overview.update` sends the
table when it changed.
"""

from __future__ import annotations

import html

import viser

from viewer.snapshot import Snapshot


def overview_html(snapshot: Snapshot) -> str:
    """The overview table of every axis of ``snapshot``."""
    rows = "".join(
        f"<tr><td>{html.escape(name)}</td><td>{view.position:.3f}</td>"
        f"<td>{view.velocity:.3f}</td><td>{view.following_error:.4f}</td>"
        f"<td>{html.escape(view.state)}</td></tr>"
        for name, view in snapshot.axes.items()
    )
    return (
        "<table><tr><th>axis</th><th>position</th><th>velocity</th><th>following error</th>"
        f"<th>state</th></tr>{rows}</table>"
    )


class Overview:
    """The overview table in a page's GUI (``gui``: the page's ``client.gui``)."""

    def __init__(self, gui: viser.GuiApi) -> None:
        self._html = gui.add_html("")
        self._shown = ""

    def update(self, snapshot: Snapshot) -> None:
        """Show ``snapshot``'s axes (sends only a changed table)."""
        content = overview_html(snapshot)
        if content != self._shown:
            self._shown = self._html.content = content

    def remove(self) -> None:
        """Remove the table from the page."""
        self._html.remove()

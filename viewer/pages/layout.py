"""The layout of each page (each browser tab): a panel of its own on the left (the all-axes
overview, the scope and the cam view while an axis is cammed, the watch table in a tab), the control
panel on the right and the 3-D canvas between them, at least half the page wide from 1280 to 1920
px (:data:`COLUMN_WIDTH` + :data:`CONTROL_WIDTH` ≤ 640 px). What a page does there (its scope's
settings) is its own."""

from __future__ import annotations

__all__ = ["COLUMN_WIDTH", "CONTROL_WIDTH", "Page", "Pages"]

import threading
from collections.abc import Callable

import viser

from viewer.pages.cam_panel import CamPanel
from viewer.pages.overview import Overview
from viewer.pages.watch_panel import WatchPanel
from viewer.pages.widgets import gated_button
from viewer.scope.panel import PageScope
from viewer.serving.retire import retire
from viewer.serving.security import GuiGate
from viewer.sim.session import Session
from viewer.sim.snapshot import Snapshot

COLUMN_WIDTH = 300
"""Width [CSS px] of a page's left column (scope and overview; a user may drag it wider)."""

CONTROL_WIDTH = 300
"""Width [CSS px] of the control panel on the right (the axes' tabs may widen it: the cell's
four ``gantry/X``… to 324 px)."""


class Page:
    """The panels of one page (client): overview and scope, rebuilt for a new scene.

    Args:
        client: The page.
        gate: Checks what the page sends (its own GUI's messages too).
        session: The session shown.
        redraw: Asks for the page's scope to be updated at the next frame.
    """

    def __init__(
        self,
        client: viser.ClientHandle,
        gate: GuiGate,
        session: Session,
        redraw: Callable[[], None] = lambda: None,
    ) -> None:
        self.client, self._gate, self.session, self._redraw = client, gate, session, redraw
        gui = client.gui
        # one panel: docked panels split a column in equal halves (viser 1.1.1 has no split
        # weights), which leaves the overview half empty and the scope cramped
        self._panel = gui.add_panel()
        self._panel.dock_left()
        self._panel.set_width(COLUMN_WIDTH)
        with self._panel.add_tab("Axes and scope", icon=viser.Icon.CHART_LINE):
            self._axes = gui.add_folder("All axes")
            self._scope = gui.add_folder("Scope")
            self._cam = gui.add_folder("Cam")
        with self._panel.add_tab("Watch", icon=viser.Icon.LIST_DETAILS):
            self.watch = WatchPanel(gui, gate, session)
            """The running ST program's variables, and forcing them."""
        self.overview: Overview | None = None
        self._reset_peaks: viser.GuiButtonHandle | None = None
        self.scope: PageScope | None = None
        """The page's scope (None until built)."""
        self.cam: CamPanel | None = None
        """The cam view (None until built; hidden while no axis is cammed)."""
        self.generation = -1
        """Generation of the scene the panels show."""
        self.build(session.snapshot)

    def build(self, snapshot: Snapshot) -> None:
        """The panels of ``snapshot``'s scene (the old ones removed)."""
        self.clear()
        gui = self.client.gui
        with self._axes:
            self.overview = Overview(gui)
            self._reset_peaks = gated_button(
                self._gate,
                "Reset peaks",
                gui=gui,
                icon=viser.Icon.REFRESH,
                hint="The peak following errors start again from now (for every page)",
            )
            self._reset_peaks.on_click(lambda event: self.session.reset_peaks())
        with self._scope:
            self.scope = PageScope(
                gui, self._gate, self.session, snapshot, self.client.atomic, self._redraw
            )
        self.cam = CamPanel(gui, self._cam, self.client.atomic)
        self.generation = snapshot.generation

    def clear(self) -> None:
        """Remove the scene's panels' content."""
        if self.overview is not None:
            self.overview.remove()
        if self._reset_peaks is not None:
            self._gate.forget([self._reset_peaks])
            retire([self._reset_peaks])
            self._reset_peaks = None
        if self.scope is not None:
            self.scope.remove()
        if self.cam is not None:
            self.cam.remove()
        self.overview = self.scope = self.cam = None


class Pages:
    """The pages open, by client id (thread-safe).

    Args:
        session: The session shown.
        gate: Checks what the pages send.
        redraw: Asks for the scopes to be updated at the next frame.
    """

    def __init__(
        self, session: Session, gate: GuiGate, redraw: Callable[[], None] = lambda: None
    ) -> None:
        self.session, self._gate, self._redraw = session, gate, redraw
        self._pages: dict[int, Page] = {}
        self._lock = threading.Lock()

    def connect(self, client: viser.ClientHandle) -> None:
        """A page opened: its panels."""
        page = Page(client, self._gate, self.session, self._redraw)
        with self._lock:
            self._pages[client.client_id] = page

    def disconnect(self, client: viser.ClientHandle) -> None:
        """A page closed: forget it."""
        with self._lock:
            page = self._pages.pop(client.client_id, None)
        if page is not None:
            page.clear()
            page.watch.forget()

    def show_step(self, client_id: int, axis: str, start: float, length: float) -> None:
        """A step test started from page ``client_id``: that page's scope records the axis'
        set point, position and following error from ``start`` [s] for ``length`` [s]."""
        page = self.get(client_id)
        if page is not None and page.scope is not None:
            channels = [f"{axis} set point", f"{axis} position", f"{axis} following error"]
            page.scope.capture(channels, start, length)

    def get(self, client_id: int) -> Page | None:
        """The page of ``client_id`` (None: not open)."""
        with self._lock:
            return self._pages.get(client_id)

    def all(self) -> list[Page]:
        """The pages open."""
        with self._lock:
            return list(self._pages.values())

    def rebuild(self, snapshot: Snapshot) -> None:
        """Every page's panels for a new scene."""
        for page in self.all():
            if page.generation != snapshot.generation:
                page.build(snapshot)

    def update_panels(self, snapshot: Snapshot) -> None:
        """Every page's overview and watch table (the update thread, at the panel rate)."""
        rows = self.session.watch
        for page in self.all():
            page.watch.update(rows)
            if page.overview is not None and page.generation == snapshot.generation:
                page.overview.update(snapshot)
            if page.cam is not None and page.generation == snapshot.generation:
                page.cam.update(snapshot)

    def update_plots(self) -> None:
        """Every page's scope (the update thread, at the plot rate)."""
        for page in self.all():
            if page.scope is not None:
                page.scope.update()

"""The pages: the GUI skeleton and its update loop (:mod:`~viewer.pages.app`), each page's layout,
the read-out panels, the panels of an axis, the overview, the cam view, the faults, the watch
table, the operator's controls and the widgets every element is made with."""

__all__: list[str] = []

"""Taking a page's elements away without errors on the page: hidden at once, removed a moment
later.

viser's page applies the updates of a batch of messages after its removals: an element updated
and removed within one batch (the page takes several of the server's sends at once while it
draws a 3-D frame in software) is updated after it is gone, and the page logs "Tried to update
non-existent component". A retired element is hidden at once (the page draws it no more) and
removed :data:`RETIRE_DELAY` later, long after its last update was applied.
"""

from __future__ import annotations

__all__ = ["RETIRE_DELAY", "Removable", "retire"]

import logging
import threading
from collections.abc import Iterable
from typing import Protocol

log = logging.getLogger(__name__)

RETIRE_DELAY = 5.0
"""Seconds between hiding an element and removing it: longer than a page busy drawing in
software goes without taking its messages (seconds, on a loaded machine); hidden, the element
costs nothing meanwhile."""


class Removable(Protocol):
    """A viser element: it can be hidden and removed."""

    @property
    def visible(self) -> bool: ...
    @visible.setter
    def visible(self, value: bool) -> None: ...
    def remove(self) -> None: ...


def retire(elements: Iterable[Removable], delay: float = RETIRE_DELAY) -> threading.Timer:
    """Hide ``elements`` now and remove them ``delay`` [s] later (a daemon timer, returned)."""
    retired = list(elements)
    for element in retired:
        element.visible = False
    timer = threading.Timer(delay, _remove, args=(retired,))
    timer.daemon = True
    timer.start()
    return timer


def _remove(elements: list[Removable]) -> None:
    for element in elements:
        try:
            element.remove()
        except Exception as exc:  # the server stopped meanwhile: nothing left to remove
            log.debug("retired element not removed: %s", exc)

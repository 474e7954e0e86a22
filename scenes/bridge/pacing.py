"""A scene running free in its own thread, paced to the wall clock (1 s simulated per second)."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

from scenes.scene import Scene

log = logging.getLogger(__name__)

CHUNK = 0.01
"""Simulated time run between two looks at the wall clock [s] (rounded to whole PLC cycles)."""


class PacedRun:
    """Runs ``program`` on ``scene`` in a daemon thread at ``speed`` × real time.

    Args:
        scene: the scene.
        program: one PLC scan.
        speed: simulated seconds per wall second (> 0).
        clock: monotonic wall clock [s].
    """

    def __init__(
        self,
        scene: Scene,
        program: Callable[[], None],
        speed: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        if not speed > 0.0:
            raise ValueError(f"speed must be > 0, got {speed}")
        self.scene = scene
        self.program = program
        self.speed = speed
        self._clock = clock
        plc = scene.runtime.plc_period
        self.chunk = max(1, round(CHUNK / plc)) * plc
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="bridge-sim", daemon=True)
        self.error = ""
        """Why the simulation stopped on its own (empty: it runs or was stopped)."""

    def start(self) -> None:
        """Start the thread."""
        self._thread.start()

    def stop(self, timeout: float = 2.0) -> None:
        """Stop the thread and wait for it [s]."""
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout)

    def _run(self) -> None:
        scene, start_wall, start_sim = self.scene, self._clock(), self.scene.time
        while not self._stop.is_set():
            try:
                scene.run(self.program, timeout=self.chunk)
            except Exception as error:  # the thread reports and ends; the server stays up
                self.error = f"{type(error).__name__}: {error}"
                log.exception("simulation stopped")
                return
            ahead = (scene.time - start_sim) / self.speed - (self._clock() - start_wall)
            if ahead > 0:
                self._stop.wait(ahead)

"""How the bridge's simulation advances, in its own thread: free-running, paced to the wall clock
at a speed (:class:`PacedRun`, with the testbench's pacing loop, :mod:`scenes.pacing`), or in
lockstep with the client (:class:`LockstepRun`)."""

from __future__ import annotations

__all__ = ["CHUNK", "IDLE_WAIT", "MAX_LAG", "LockstepRun", "PacedRun", "Run"]

import logging
import threading
import time
from collections.abc import Callable

from scenes.bridge.program import BridgeProgram
from scenes.pacing import Pacing

log = logging.getLogger(__name__)

CHUNK = 0.01
"""Simulated time a free run runs between two publishes [s] (whole PLC cycles)."""

MAX_LAG = 0.1
"""A free run that falls further behind the wall clock [s] gives the time up."""

IDLE_WAIT = 0.05
"""Longest wait of a lockstep run for a client write [s] (then it looks whether to stop)."""


class Run:
    """The simulation thread of ``program``'s scene (a daemon); subclasses advance it and
    publish the status after each run of scans (:meth:`_publish`)."""

    def __init__(self, program: BridgeProgram) -> None:
        self.program = program
        self.scene = program.scene
        self._stop = threading.Event()
        program.publish_every_scan = False  # the run publishes after each run of scans
        self._thread = threading.Thread(target=self._guarded, name="bridge-sim", daemon=True)
        self.error = ""
        """Why the simulation stopped on its own (empty: it runs or was stopped)."""
        self.on_publish: list[Callable[[int], None]] = []
        """Called in the simulation thread after each publish with the PLC cycle published (a
        server mirrors the tables there; keep them short: the scene waits)."""
        self._reached = threading.Condition()
        self._published = program.cycles
        """The cycle whose status the tables show (a client reads it once :meth:`wait` says so)."""
        self._waiters: list[tuple[int, Callable[[], None]]] = []

    def wait(self, cycle: int, timeout: float) -> bool:
        """Wait until the tables show PLC cycle ``cycle`` or a later one (or the run stops)
        [timeout: wall s]; whether they do."""
        with self._reached:
            return self._reached.wait_for(
                lambda: self._published >= cycle or self._stop.is_set(), timeout
            )

    def when_published(self, cycle: int, callback: Callable[[], None]) -> None:
        """Call ``callback()`` once the tables show PLC cycle ``cycle`` or a later one, or the
        run stops: at once if they do, else in the simulation thread after that publish."""
        with self._reached:
            if not (self._published >= cycle or self._stop.is_set()):
                self._waiters.append((cycle, callback))
                return
        callback()

    def forget(self, callback: Callable[[], None]) -> None:
        """No longer call ``callback`` (of :meth:`when_published`; one that timed out)."""
        with self._reached:
            self._waiters = [w for w in self._waiters if w[1] is not callback]

    @property
    def published(self) -> int:
        """The PLC cycle whose status the tables show."""
        with self._reached:
            return self._published

    def _publish(self) -> None:
        """Publish the status, then tell the hooks and whoever waits."""
        self.program.publish()
        cycle = self.program.cycles
        for hook in self.on_publish:
            hook(cycle)
        with self._reached:
            self._published = cycle
            self._reached.notify_all()
            due = [w for w in self._waiters if w[0] <= cycle]
            self._waiters = [w for w in self._waiters if w[0] > cycle]
        for _, callback in due:
            callback()

    def start(self) -> None:
        """Start the thread."""
        self._thread.start()

    def stop(self, timeout: float = 2.0) -> None:
        """Stop the thread and wait for it [s]."""
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout)
        self._release()

    def _guarded(self) -> None:
        try:
            self._run()
        except Exception as error:  # the thread reports and ends; the server stays up
            self.error = f"{type(error).__name__}: {error}"
            log.exception("simulation stopped")
        finally:
            self._release()

    def _release(self) -> None:
        """Wake whoever waits: the run stops."""
        with self._reached:
            self._reached.notify_all()
            due, self._waiters = self._waiters, []
        for _, callback in due:
            callback()

    def _run(self) -> None:
        raise NotImplementedError


class PacedRun(Run):
    """Free-running at ``speed`` × real time, publishing after each :data:`CHUNK` of simulated
    time.

    Args:
        program: the bridge program (its scene is run).
        speed: simulated seconds per wall second (> 0).
        clock: monotonic wall clock [s].
    """

    def __init__(
        self,
        program: BridgeProgram,
        speed: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.pacing = Pacing(speed, clock, max_lag=MAX_LAG, chunk=CHUNK, batch_wall=0.0)
        super().__init__(program)

    def _run(self) -> None:
        self.pacing.run(self, self._stop)

    def simulated(self) -> tuple[float, float]:
        """Simulated time and PLC period [s] (:class:`scenes.pacing.Paced`)."""
        return self.scene.time, self.scene.runtime.plc_period

    def held(self) -> bool:
        """Never held: the run has no commands of its own."""
        return False

    def run_cycles(self, cycles: int) -> None:
        """Run ``cycles`` PLC cycles of the program."""
        self.scene.run(self.program, timeout=cycles * self.scene.runtime.plc_period)

    def ran(self) -> None:
        """Publish after each run of cycles (also before a wait: nothing new then)."""
        if self.program.cycles != self._published:
            self._publish()

    def idle(self, seconds: float) -> None:
        """Wait for the next chunk, or until the run stops."""
        self._stop.wait(seconds)


class LockstepRun(Run):
    """Lockstep: the scene stands until the client writes ``sim.target``, then runs whole PLC
    cycles until ``sim.cycle`` equals it (the acknowledgement; a server may hold its answer to
    the write until then, :meth:`wait`). What the client wrote before is seen by the first of
    these scans, whatever the network timing."""

    def __init__(self, program: BridgeProgram) -> None:
        super().__init__(program)
        self.written = threading.Event()
        """Set by every client write to any table (the run waits on it)."""
        for table in program.tables:
            table.set("sim.mode", 1)
            table.written = self.written

    def _run(self) -> None:
        plc = self.scene.runtime.plc_period
        while not self._stop.is_set():
            self.written.clear()
            due = self.program.target - self.program.cycles
            if due > 0:
                self.scene.run(self.program, timeout=due * plc)
                self._publish()
            else:
                self.written.wait(IDLE_WAIT)

"""An axis' touch-probe latch (:class:`ProbeLatch`): armed by MC_TouchProbe or by MC_GearInPos'
zeroing, it takes the position of the next touch-probe edge the channel latched (within a window
of positions, when one is given) and then stays disarmed until armed again.
"""

from __future__ import annotations

__all__ = ["ProbeLatch"]


class ProbeLatch:
    """The touch-probe latch of one axis.

    ``generation`` counts the arm and abort requests: a block that armed the latch sees its own
    generation while it waits, and a newer arming, an abort or a restored machine state
    (``CommandAborted``) as another one.
    """

    def __init__(self) -> None:
        self.position: float | None = None
        """Position [u] the armed latch recorded (None: not yet, or not armed)."""
        self.generation = 0
        """Counts arm and abort requests."""
        self.armed = False
        """Waiting for an edge."""
        self.seq = 0
        """The channel's edge count the latch has seen."""
        self.window: tuple[float, float] | None = None
        """Positions [u] an edge must lie within (None: any)."""

    def arm(self, seq: int, window: tuple[float, float] | None = None) -> int:
        """Wait for the next edge after the channel's edge count ``seq`` (within ``window``
        [u], if given); returns the arming's generation."""
        self.generation += 1
        self.position = None
        self.armed = True
        self.seq = seq
        self.window = window
        return self.generation

    def abort(self) -> None:
        """Cancel a waiting arming (MC_AbortTrigger)."""
        self.generation += 1
        self.armed = False

    def latched(self, seq: int, position: float) -> None:
        """The channel latched edge number ``seq`` at ``position`` [u]: recorded when it lies
        in the window (the latch then disarms)."""
        self.seq = seq
        window = self.window
        if window is None or window[0] <= position <= window[1]:
            self.position = position
            self.armed = False

    def shift(self, delta: float) -> None:
        """The axis coordinate moved by ``delta`` [u]: the window moves with it."""
        window = self.window
        if window is not None:
            self.window = (window[0] + delta, window[1] + delta)

    def restore(self, position: float | None, seq: int) -> None:
        """Back to a saved machine state: a waiting arming ends (its block sees
        CommandAborted), the recorded ``position`` [u] is the saved one, edges up to the
        channel's count ``seq`` are seen."""
        self.generation += 1
        self.armed = False
        self.window = None
        self.position = position
        self.seq = seq

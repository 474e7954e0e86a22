"""The step test of an axis' position loop as PLC code, and the figures of its response.

The library moves an axis only along a limited set-point profile, so the step is the fastest
move it allows: ``MC_MoveRelative`` by the amplitude with the axis' velocity Vmax, its maximum
acceleration and deceleration (``AxisConfig.max_acceleration``; larger inputs are clamped to
it) and a jerk of :data:`STEP_JERK`, which the library clamps to the axis' maximum jerk where
it has one. A 1 mm step of an axis with 20 m/s² takes its set point 14 ms; the position loop
(feed-forward included) is then measured as the machine will run it. It starts only from
standstill, in position. The test records the actual position ``POS`` (MC_ReadActualPosition)
every PLC scan for :data:`STEP_WINDOW` and computes from it (:func:`step_response`): rise time
10–90 %, overshoot, settling time to ±2 % and the steady-state error.
"""

from __future__ import annotations

__all__ = [
    "SETTLING_BAND",
    "STEP_COUNTS",
    "STEP_JERK",
    "STEP_WINDOW",
    "StepListener",
    "StepResponse",
    "StepTest",
    "amplitude_range",
    "step_response",
]

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

import mcl

STEP_WINDOW = 0.5
"""Simulated time [s] the response is recorded after the step starts."""

STEP_JERK = 1e9
"""Jerk input of the step's move [u/s³]: practically unlimited (clamped to the axis' maximum)."""

STEP_COUNTS = (100, 5000)
"""Smallest and largest step amplitude in encoder counts (0.1 … 5 mm at 1 µm)."""

SETTLING_BAND = 0.02
"""Half width of the settling band, a fraction of the amplitude (±2 %)."""

StepListener = Callable[[int, str, float, float], None]
"""Hears that a step starts: (client id of the page that asked, axis, start [s], length [s] of
the recorded response, both simulated time)."""


def amplitude_range(resolution: float) -> tuple[float, float]:
    """Smallest and largest step amplitude [u] of an axis of encoder ``resolution`` [u/count]."""
    low, high = STEP_COUNTS
    return low * resolution, high * resolution


@dataclass(frozen=True, slots=True)
class StepResponse:
    """Figures of a recorded step response (times from the start of the step).

    Attributes:
        amplitude: Commanded step [u].
        rise_time: From 10 % to 90 % of the step [s] (NaN: never reached 90 %).
        overshoot: Peak beyond the target, in percent of the step (0: none).
        settling_time: Until the response stays within ±2 % of the target [s] (NaN: it never
            does in the window).
        steady_state_error: Target minus the mean actual position over the last tenth of the
            window [u].
    """

    amplitude: float
    rise_time: float
    overshoot: float
    settling_time: float
    steady_state_error: float


def step_response(
    times: npt.ArrayLike, positions: npt.ArrayLike, start: float, amplitude: float
) -> StepResponse:
    """The figures of a step response.

    Args:
        times: Sample times [s], increasing; the first sample is the position before the step.
        positions: Actual positions [u] at ``times``.
        start: Time the step was commanded [s].
        amplitude: The commanded step [u], not 0.

    Raises:
        ValueError: Fewer than two samples, lengths that differ, or an amplitude of 0.
    """
    t = np.asarray(times, dtype=np.float64)
    x = np.asarray(positions, dtype=np.float64)
    if t.shape != x.shape or t.size < 2:
        raise ValueError("a step response needs two or more samples of time and position")
    if not (math.isfinite(amplitude) and amplitude != 0.0):
        raise ValueError(f"the step amplitude must be finite and not 0, got {amplitude}")
    y = (x - x[0]) / amplitude  # 0 before, 1 at the target
    rise = _crossing(t, y, 0.9) - _crossing(t, y, 0.1)
    outside = np.flatnonzero(np.abs(y - 1.0) > SETTLING_BAND)
    if outside.size == 0:
        settling = 0.0
    elif outside[-1] == y.size - 1:
        settling = math.nan
    else:
        settling = float(t[outside[-1] + 1] - start)
    tail = x[-max(1, x.size // 10) :]
    return StepResponse(
        amplitude=amplitude,
        rise_time=float(rise),
        overshoot=max(0.0, float(np.max(y)) - 1.0) * 100.0,
        settling_time=settling,
        steady_state_error=float(x[0] + amplitude - np.mean(tail)),
    )


def _crossing(t: npt.NDArray[np.float64], y: npt.NDArray[np.float64], level: float) -> float:
    """First time [s] ``y`` reaches ``level`` (linear between samples); NaN if it never does."""
    above = np.flatnonzero(y >= level)
    if above.size == 0:
        return math.nan
    i = int(above[0])
    if i == 0:
        return float(t[0])
    fraction = (level - y[i - 1]) / (y[i] - y[i - 1])
    return float(t[i - 1] + fraction * (t[i] - t[i - 1]))


class StepTest:
    """The step test of one axis (one PLC scan per call).

    Args:
        axis: The axis.
        sim_time: Simulated time [s] of the recording.
    """

    def __init__(self, axis: mcl.Axis, sim_time: Callable[[], float]) -> None:
        self.axis = axis
        self._time = sim_time
        self.move = mcl.MC_MoveRelative(Axis=axis)
        self.read = mcl.MC_ReadActualPosition(Axis=axis)
        self.running = False
        self.amplitude = 0.0
        self.start_time = 0.0
        self.result: StepResponse | None = None
        """Figures of the last completed test (None: none yet)."""
        self._times: list[float] = []
        self._positions: list[float] = []

    def refusal(self, amplitude: float) -> str:
        """Why a step of ``amplitude`` [u] cannot start now (empty: it can)."""
        axis = self.axis
        low, high = amplitude_range(axis.config.resolution)
        if not (math.isfinite(amplitude) and low <= abs(amplitude) <= high):
            return f"amplitude must be {low:g} … {high:g} {axis.config.unit} (either sign)"
        if self.running:
            return "a step test runs"
        if axis.state != mcl.AxisState.StandStill:
            return f"the axis must stand still (it is {axis.state.name})"
        if abs(axis.following_error) > axis.config.in_position:
            return "the axis is not in position"
        return ""

    def begin(self, amplitude: float) -> int:
        """Command the step (call after :meth:`refusal` said it may); 0 or the ErrorID of the
        refused move."""
        axis = self.axis
        assert axis.constants is not None  # StandStill: the constants are set
        self.read(Axis=axis, Enable=True)
        self.start_time = self._time()
        self._times, self._positions = [self.start_time], [self.read.Position]
        self.move(Axis=axis, Execute=False)
        self.move(
            Axis=axis,
            Execute=True,
            Distance=amplitude,
            Velocity=axis.constants.Vmax,
            Acceleration=axis.config.max_acceleration,
            Deceleration=axis.config.max_deceleration,
            Jerk=STEP_JERK,
        )
        if self.move.Error:
            error = self.move.ErrorID
            self.move(Axis=axis, Execute=False)
            return error
        self.amplitude, self.running, self.result = amplitude, True, None
        return 0

    def __call__(self) -> tuple[str, int] | None:
        """One scan: record; how the test ended in this scan (text, ErrorID) or None."""
        if not self.running:
            return None
        axis = self.axis
        move = self.move
        move(Axis=axis, Execute=True)
        self.read(Axis=axis, Enable=True)
        now = self._time()
        self._times.append(now)
        self._positions.append(self.read.Position)
        if move.Error or axis.state == mcl.AxisState.ErrorStop:
            return self._stop("error", move.ErrorID or axis.AxErrorID)
        if move.CommandAborted:
            return self._stop("aborted", 0)
        if now - self.start_time < STEP_WINDOW - 1e-9:
            return None
        self.result = step_response(self._times, self._positions, self.start_time, self.amplitude)
        r = self.result
        return self._stop(f"rise {r.rise_time * 1e3:.1f} ms, overshoot {r.overshoot:.1f} %", 0)

    def cancel(self) -> tuple[str, int] | None:
        """End a running test (another command takes the axis over); how it ended (None: it
        did not run)."""
        return self._stop("aborted", 0) if self.running else None

    def _stop(self, text: str, error_id: int) -> tuple[str, int]:
        self.running = False
        self.move(Axis=self.axis, Execute=False)
        self.read(Axis=self.axis, Enable=False)
        return text, error_id

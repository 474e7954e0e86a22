"""The operator panel as PLC code: HMI request flags and the operator program that obeys them.

The browser never touches the simulation. A button only sets a request in :class:`AxisRequests`
(thread-safe, like an HMI variable); :class:`OperatorProgram` runs in the simulation thread once
per PLC cycle, reads the requests and passes them to the library's function blocks:

=============  ===================================================================================
Power          ``MC_Power``; a toggle: the request becomes "on" if the axis is Disabled, else "off".
               Until the operator first presses it the block is not called, so a running demo
               program keeps power in its own hands.
Reset          ``MC_Reset``: Execute from the request until Done or Error, then released.
Home           the scene's ``HomingRecipe`` through ``scenes.procedures.HomeAxis``: Execute until
               it is no longer Busy (Done, Error or aborted), then released.
Jog+ / Jog−    ``GT_Jog`` (levels JogPos / JogNeg): a request is a dead-man deadline
               (:data:`DEADMAN` [s] of wall time) that every hold message of the browser refreshes;
               when it runs out — button released, tab closed, network gone — the jog stops.
Stop           ``MC_Stop``: Execute from the request until Done (or Error), then released so that
               the axis leaves Stopping.
=============  ===================================================================================

Every scan also calls ``GT_AxStatusString`` and ``GT_AxErrStringEN`` for the panel's texts.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import mcl
from scenes.procedures import HomeAxis, HomingRecipe

DEADMAN = 0.2
"""Wall time [s] a jog request stays alive after the last hold message of the browser."""

DEFAULT_JOG_FRACTION = 0.1
"""Default jog velocity as a fraction of the axis' Vmax (velocity at 10 V)."""

Clock = Callable[[], float]
"""Monotonic wall clock [s]."""


@dataclass(frozen=True, slots=True)
class Requests:
    """What the operator wants from one axis in one PLC scan (taken from :class:`AxisRequests`).

    Attributes:
        power: ``True``/``False`` to switch the drive on/off, ``None``: no change of hands.
        toggle_power: a Power press to be resolved against the axis state.
        reset: a Reset press.
        home: a Home press.
        stop: a Stop press.
        jog_pos: Jog+ is held (its dead-man deadline has not run out).
        jog_neg: Jog− is held.
        jog_velocity: jog velocity [u/s]; 0 = the default (a tenth of Vmax).
    """

    power: bool | None
    toggle_power: bool
    reset: bool
    home: bool
    stop: bool
    jog_pos: bool
    jog_neg: bool
    jog_velocity: float


class AxisRequests:
    """Operator request flags of one axis, written by GUI threads, read by the PLC thread.

    Presses are latched until the operator program takes them; a jog request is a deadline on
    the wall clock ``clock`` that :meth:`jog` pushes :data:`DEADMAN` seconds ahead.

    Args:
        clock: Monotonic wall clock [s] (injectable for tests).
        deadman: Life time [s] of a jog request after the last :meth:`jog` call.
    """

    def __init__(self, clock: Clock = time.monotonic, deadman: float = DEADMAN) -> None:
        self._clock = clock
        self._deadman = deadman
        self._lock = threading.Lock()
        self._power: bool | None = None
        self._toggle = False
        self._reset = False
        self._home = False
        self._stop = False
        self._jog_until = {1: -math.inf, -1: -math.inf}
        self._jog_velocity = 0.0

    def set_power(self, on: bool) -> None:
        """Request the drive on (``True``) or off (``False``)."""
        with self._lock:
            self._power = bool(on)
            self._toggle = False

    def toggle_power(self) -> None:
        """The Power button: on if the axis is Disabled when the PLC sees it, else off."""
        with self._lock:
            self._toggle = True

    def release_power(self) -> None:
        """Stop calling the operator's MC_Power (e.g. while a demo program owns the drives)."""
        with self._lock:
            self._power = None
            self._toggle = False

    def reset(self) -> None:
        """The Reset button (MC_Reset)."""
        with self._lock:
            self._reset = True

    def home(self) -> None:
        """The Home button (the scene's homing recipe)."""
        with self._lock:
            self._home = True

    def stop(self) -> None:
        """The Stop button (MC_Stop)."""
        with self._lock:
            self._stop = True

    def jog(self, direction: int) -> None:
        """Hold Jog+ (``direction`` > 0) or Jog− (< 0) for another :data:`DEADMAN` seconds.

        Raises:
            ValueError: If ``direction`` is 0.
        """
        if direction == 0:
            raise ValueError("jog direction must be +1 (Jog+) or -1 (Jog−), got 0")
        key = 1 if direction > 0 else -1
        until = self._clock() + self._deadman
        with self._lock:
            self._jog_until[key] = until

    def release_jog(self) -> None:
        """Let go of both jog buttons at once (without waiting for the dead-man deadline)."""
        with self._lock:
            self._jog_until[1] = self._jog_until[-1] = -math.inf

    @property
    def jog_velocity(self) -> float:
        """Jog velocity [u/s]; 0 = a tenth of the axis' Vmax."""
        return self._jog_velocity

    @jog_velocity.setter
    def jog_velocity(self, velocity: float) -> None:
        if not (math.isfinite(velocity) and velocity >= 0.0):
            raise ValueError(f"jog velocity must be a finite number >= 0, got {velocity}")
        self._jog_velocity = float(velocity)

    def take(self) -> Requests:
        """The requests for this PLC scan; presses are consumed."""
        now = self._clock()
        with self._lock:
            requests = Requests(
                power=self._power,
                toggle_power=self._toggle,
                reset=self._reset,
                home=self._home,
                stop=self._stop,
                jog_pos=now < self._jog_until[1],
                jog_neg=now < self._jog_until[-1],
                jog_velocity=self._jog_velocity,
            )
            self._toggle = self._reset = self._home = self._stop = False
        return requests


class AxisOperator:
    """The operator's function blocks of one axis and their sequencing (one PLC scan per call).

    Args:
        axis: The axis.
        requests: Its request flags.
        recipe: Its homing recipe; ``None``: the Home button reports that there is none.
    """

    def __init__(self, axis: mcl.Axis, requests: AxisRequests, recipe: HomingRecipe | None) -> None:
        self.axis = axis
        self.requests = requests
        self.power = mcl.MC_Power()
        self.reset = mcl.MC_Reset()
        self.home = HomeAxis(axis, recipe) if recipe is not None else None
        self.jog = mcl.GT_Jog()
        self.stop = mcl.MC_Stop()
        self.status = mcl.GT_AxStatusString()
        self.error_text = mcl.GT_AxErrStringEN()
        self.power_request: bool | None = None
        """Level passed to MC_Power's Enable; ``None`` while the operator has not pressed Power."""
        self.resetting = False
        self.homing = False
        self.stopping = False
        self.message = ""
        """Outcome of the last operator command, e.g. ``"Home: done"``."""

    @property
    def jogging(self) -> int:
        """Direction of the jog request seen in the last scan: +1, −1 or 0."""
        return int(self.jog.JogPos) - int(self.jog.JogNeg) if self.jog.Enable else 0

    def release_power(self) -> None:
        """Hand the drive back: MC_Power is no longer called (called from the PLC thread)."""
        self.power_request = None

    def __call__(self) -> None:
        """One PLC scan: take the requests and call the function blocks."""
        axis = self.axis
        r = self.requests.take()
        if r.power is not None:
            self.power_request = r.power
        if r.toggle_power:
            self.power_request = axis.state == mcl.AxisState.Disabled
        if self.power_request is not None:
            self.power(Axis=axis, Enable=self.power_request)
            if self.power.Error:
                self._report("Power", self.power.ErrorID)

        if r.reset:
            self.resetting = True
        if self.resetting or self.reset.Execute:
            self.reset(Axis=axis, Execute=self.resetting)
            if self.resetting and (self.reset.Done or self.reset.Error):
                self.resetting = False
                self._report("Reset", self.reset.ErrorID)

        if r.home:
            if self.home is None:
                self.message = "Home: no homing recipe for this axis"
            else:
                self.homing = True
        home = self.home
        if home is not None and (self.homing or home.Busy or home.approach.Execute):
            home(Execute=self.homing)
            if self.homing and not home.Busy:
                self.homing = False
                if home.Done:
                    self.message = "Home: done"
                elif home.Error:
                    self._report("Home", home.ErrorID)
                else:
                    self.message = "Home: aborted"

        jog_pos, jog_neg = r.jog_pos, r.jog_neg
        if jog_pos or jog_neg or self.jog.Enable:
            velocity = r.jog_velocity or self._default_jog_velocity()
            self.jog(
                Axis=axis,
                Enable=jog_pos or jog_neg,
                JogPos=jog_pos,
                JogNeg=jog_neg,
                JogVelo=velocity,
            )
            if self.jog.Error:
                self._report("Jog+" if jog_pos else "Jog−", self.jog.ErrorID)

        if r.stop:
            self.stopping = True
        if self.stopping or self.stop.Execute:
            self.stop(Axis=axis, Execute=self.stopping)
            if self.stopping and (self.stop.Done or self.stop.Error):
                self.stopping = False
                self._report("Stop", self.stop.ErrorID)

        self.status(Axis=axis, Enable=True)
        self.error_text(Axis=axis, Enable=True)

    def _default_jog_velocity(self) -> float:
        constants = self.axis.constants
        vmax = constants.Vmax if constants is not None else 0.0
        return DEFAULT_JOG_FRACTION * vmax

    def _report(self, command: str, error_id: int) -> None:
        if error_id:
            self.message = f"{command}: error {error_id} ({mcl.error_text(error_id)})"
        else:
            self.message = f"{command}: done"


class OperatorProgram:
    """The operator PLC program of a scene: one :class:`AxisOperator` per axis.

    Args:
        axes: The scene's axes by name.
        recipes: Homing recipes by axis name (axes without one cannot be homed).
        clock: Monotonic wall clock [s] for the jog dead-man deadlines.
    """

    def __init__(
        self,
        axes: Mapping[str, mcl.Axis],
        recipes: Mapping[str, HomingRecipe],
        clock: Clock = time.monotonic,
    ) -> None:
        self.requests = {name: AxisRequests(clock) for name in axes}
        """Request flags by axis name (the only thing the GUI writes)."""
        self.axes = {
            name: AxisOperator(axis, self.requests[name], recipes.get(name))
            for name, axis in axes.items()
        }
        """Function blocks by axis name."""
        self._operators = list(self.axes.values())

    def __call__(self) -> None:
        """One PLC scan of every axis' operator blocks."""
        for operator in self._operators:
            operator()

    def release_power(self) -> None:
        """Hand every drive back to the other program (called from the PLC thread)."""
        for name, operator in self.axes.items():
            self.requests[name].release_power()
            operator.release_power()

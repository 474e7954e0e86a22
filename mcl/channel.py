"""One axis channel of the module: encoder, switches, touch probe, analog and digital I/O, faults.

:class:`AxisChannel` implements :class:`mcl.io.AxisIO` for every plant. A plant (the simulated
axes of :mod:`mcl.simaxis`, the MuJoCo plant of ``scenes``) only supplies the physics: once per
servo instant it calls :meth:`AxisChannel.sample` with the true position and switch levels, and it
gives each channel its :class:`Drive` (amplifier and brake) at construction. Everything
between the physics and the servo core happens here, once for every plant: quantizing the encoder
and latching its index, latching the touch probe after its sensor delay, and the injected faults
of :mod:`mcl.faults`.
"""

from __future__ import annotations

__all__ = [
    "IDEAL",
    "NO_SWITCHES",
    "AxisChannel",
    "ChannelSnapshot",
    "Drive",
    "Marks",
    "Normals",
    "NormalsState",
    "Sensors",
]

import copy
import math
import random
import zlib
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from mypy_extensions import mypyc_attr

from mcl import faults as flt
from mcl.encoder import AbsoluteEncoder, EncoderState, IncrementalEncoder
from mcl.errors import StateError, check_finite
from mcl.servo import DAC_FULL_SCALE

_SWITCH_INDEX = {"lim_pos": 0, "lim_neg": 1, "ref": 2, "tp": 3}
NO_SWITCHES: tuple[tuple[float, float], ...] = ((math.inf, -math.inf),) * 3
"""Switch windows of an axis without switches (LIM+, LIM−, REF never actuated)."""


@dataclass(frozen=True, slots=True)
class Marks:
    """Trigger marks along a coordinate (print marks on a strip, a cam on a shaft): the probe
    input is high while the coordinate lies within ``width`` above a mark.

    Attributes:
        first: coordinate of the first mark [m or rad of the trigger coordinate].
        pitch: distance between marks; 0 = a single mark.
        width: extent of a mark along the coordinate (> 0).
        errors: per-mark displacement added to ``first + k·pitch`` (cycled), e.g. print errors.
    """

    first: float
    pitch: float = 0.0
    width: float = 0.002
    errors: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        for name in ("first", "pitch", "width"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"Marks.{name} must be finite, got {getattr(self, name)!r}")
        if not self.width > 0.0 or self.pitch < 0.0 or (self.pitch and self.width >= self.pitch):
            raise ValueError(
                f"Marks need width > 0 and pitch 0 (one mark) or pitch > width; got width "
                f"{self.width}, pitch {self.pitch}"
            )

    def _start(self, k: int) -> float:
        e = self.errors[k % len(self.errors)] if self.errors else 0.0
        return self.first + k * self.pitch + e

    def _near(self, q: float) -> int:
        if not self.pitch:
            return 0
        return max(0, math.floor((q - self.first) / self.pitch))

    def level(self, q: float) -> bool:
        """The probe input at coordinate ``q`` (a mark displaced by its error below its place
        ``first + k·pitch`` is looked for too)."""
        near = self._near(q)
        for k in range(max(0, near - 1), near + 2):
            start = self._start(k)
            if start <= q <= start + self.width:
                return True
        return False

    def rising(self, q0: float, q1: float) -> float | None:
        """Where between two samples ``q0 → q1`` the input first rises: the fraction of the
        interval (0 < f ≤ 1), or None. Moving up it rises at a mark's start, moving down at its
        end."""
        if q1 == q0:
            return None
        lo, hi = (q0, q1) if q1 > q0 else (q1, q0)
        found: float | None = None
        for k in range(max(0, self._near(lo) - 1), self._near(hi) + 2):
            edge = self._start(k) if q1 > q0 else self._start(k) + self.width
            if lo < edge <= hi if q1 > q0 else lo <= edge < hi:
                f = (edge - q0) / (q1 - q0)
                if found is None or f < found:
                    found = f
            if not self.pitch:
                break
        return found


@dataclass(frozen=True, slots=True)
class Sensors:
    """What makes an axis' sensors and module real rather than ideal (all zero: ideal).

    The defaults are those of a precision machine axis: precision limit switches (mechanical
    plunger or inductive precision sensors: a few µm repeatability, some µm hysteresis), an
    optical encoder whose reading jitters by a fraction of a count, an index pulse that is not
    gated to one quadrature state, and a module that writes the command computed from one
    sample at the start of the next servo cycle.

    Attributes:
        switch_hysteresis: travel past its trip point before a switch releases [m or rad].
        switch_repeatability: standard deviation of a switch's trip point, drawn anew at each
            edge [m or rad].
        encoder_noise: standard deviation of the position the encoder counts (vibration,
            interpolation jitter) [counts].
        index_jitter: standard deviation of the counter value the index edge latches [counts];
            the latch rounds to a whole count.
        output_delay: servo cycles between sampling the inputs and the command reaching the
            drive (0 or 1).
        seed: seed of the noise; each axis draws its own sequence (from the seed and its name).
        absolute: the axis' absolute measuring system besides its incremental encoder (None:
            none; MC_StepAbsolute then refuses): a multi-turn absolute rotary encoder or an SSI
            linear transducer (:class:`mcl.encoder.AbsoluteEncoder`), read at the true position.
    """

    switch_hysteresis: float = 10.0e-6
    switch_repeatability: float = 2.0e-6
    encoder_noise: float = 0.2
    index_jitter: float = 0.3
    output_delay: int = 1
    seed: int = 0
    absolute: AbsoluteEncoder | None = None

    def __post_init__(self) -> None:
        names = ("switch_hysteresis", "switch_repeatability", "encoder_noise", "index_jitter")
        check_finite(self, names, False)
        if self.output_delay not in (0, 1):
            raise ValueError(
                f"Sensors.output_delay must be 0 or 1 servo cycles, got {self.output_delay!r}"
            )


@dataclass(frozen=True, slots=True)
class NormalsState:
    """Where a :class:`Normals` source is in its sequence.

    Attributes:
        generator: the bit generator's state (a private copy).
        block: the block of numbers drawn ahead.
        index: the next number's place in ``block``.
    """

    generator: dict[str, Any]
    block: tuple[float, ...]
    index: int


class Normals:
    """Standard normal numbers from a seeded generator, drawn in blocks (cheap per sample)."""

    __slots__ = ("_block", "_generator", "_i")

    def __init__(self, seed: int) -> None:
        self._generator = np.random.default_rng(seed)
        self._block: list[float] = []
        self._i = 0

    def next(self) -> float:
        """The next number (mean 0, standard deviation 1)."""
        i = self._i
        if i == len(self._block):
            self._block = self._generator.standard_normal(1024).tolist()
            i = 0
        self._i = i + 1
        return self._block[i]

    def snapshot(self) -> NormalsState:
        """Where the sequence is now (:meth:`restore` continues it from here)."""
        state: dict[str, Any] = copy.deepcopy(dict(self._generator.bit_generator.state))
        return NormalsState(state, tuple(self._block), self._i)

    def restore(self, state: NormalsState) -> None:
        """Continue the sequence from a state taken with :meth:`snapshot`."""
        self._generator.bit_generator.state = copy.deepcopy(state.generator)
        self._block = list(state.block)
        self._i = state.index


IDEAL = Sensors(0.0, 0.0, 0.0, 0.0, 0)
"""Ideal sensors: exact switches and encoder, the command applied in the cycle it is computed."""


def _same(a: object, b: object) -> bool:
    """Equal settings; numbers computed from a model's geometry may differ in rounding
    (1e-9 of their size)."""
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and isinstance(b, float) and math.isfinite(a):
        return abs(a - b) <= 1e-9 * max(1.0, abs(a))
    return a == b


@dataclass(frozen=True, slots=True)
class ChannelSnapshot:
    """Everything an :class:`AxisChannel` carries from one servo cycle to the next, at one
    instant (:meth:`AxisChannel.snapshot`): the encoder, the switch levels and trip points, the
    probe latch, the noise sequence, the injected faults and the outputs. Positions in the
    channel's SI unit [m or rad], times [s], volts [V].

    ``settings`` are the channel's fixed settings: a snapshot restores only into a channel built
    with the same ones.
    """

    settings: tuple[tuple[str, object], ...]
    encoder: EncoderState
    noise: NormalsState
    counts: int
    index_count: int
    index_seq: int
    index: bool
    lim_pos: bool
    lim_neg: bool
    ref: bool
    tp: bool
    tp_count: int
    tp_seq: int
    encoder_ok: bool
    analog: tuple[float, ...]
    inputs: tuple[bool, ...]
    outputs: tuple[bool, ...]
    volts: float
    enabled: bool
    brake: bool
    t: float
    x: float
    q: float
    history: tuple[tuple[float, float, float], ...]
    latches: tuple[float, ...]
    faults: tuple[flt.Fault, ...]
    fault_rngs: tuple[tuple[str, tuple[Any, ...]], ...]
    shift: float
    frozen_at: float | None
    edges: tuple[float, ...]
    true_levels: tuple[bool, ...]
    disabled_at: float
    enable_request: bool
    pending: tuple[float, bool] | None
    physical: tuple[bool, ...]
    trip: tuple[float, ...]


@mypyc_attr(allow_interpreted_subclasses=True)
class Drive:
    """What a channel's outputs drive in the plant: the amplifier and the holding brake (a base
    class: the compiled build calls it directly from :meth:`AxisChannel.write`)."""

    def apply(self, volts: float, enabled: bool, brake: bool) -> None:
        """Analog command [V] (0 when disabled), amplifier switched on, holding brake holds."""
        raise NotImplementedError


def _check_arguments(name: str, windows: Sequence[tuple[float, float]], probe_delay: float) -> None:
    """Raise ValueError unless the switch ``windows`` are three intervals (or empty) and
    ``probe_delay`` is a finite delay >= 0 [s] (the message names the axis ``name``)."""
    if len(windows) != 3 or any(not lo <= hi and lo != math.inf for lo, hi in windows):
        raise ValueError(
            f"axis {name}: windows must be three (lo, hi) intervals for LIM+, LIM- and REF "
            f"(lo <= hi, or (inf, -inf) for a missing switch), got {windows!r}"
        )
    if not (math.isfinite(probe_delay) and probe_delay >= 0.0):
        raise ValueError(f"axis {name}: probe_delay must be >= 0 s, got {probe_delay!r}")


@mypyc_attr(allow_interpreted_subclasses=True)
class AxisChannel:
    """The I/O of one axis as the module sees it; implements :class:`mcl.io.AxisIO`.

    Args:
        name: the axis' name (in messages).
        resolution: travel per encoder count [m or rad].
        counts_per_rev: counts per motor revolution (one index pulse each).
        origin: physical position where the counter reads 0 [m or rad].
        index_width: width of the index pulse [counts].
        probe: marks that trigger the touch probe TP (None: TP stays low).
        probe_delay: sensor delay between a mark and the latch [s].
        has_drive: False for an encoder-only axis (a measuring wheel): :meth:`write` is ignored.
        digital_outputs: number of digital outputs a program may set.
        windows: per switch (LIM+, LIM−, REF) the interval of the switch coordinate the plant
            passes to :meth:`sample` in which the switch is actuated [m or rad]; an empty
            interval (lo > hi) for a switch the axis does not have.
        sensors: the sensors' imperfections (default: a precision machine; :data:`IDEAL`).
        drive: what the outputs drive (None: the plant reads :attr:`volts`, :attr:`enabled`
            and :attr:`brake` itself, as the simulated axis does).
    """

    def __init__(
        self,
        name: str,
        resolution: float,
        counts_per_rev: int,
        origin: float = 0.0,
        index_width: int = 1,
        *,
        probe: Marks | None = None,
        probe_delay: float = 0.0,
        has_drive: bool | int = True,
        digital_outputs: int = 0,
        windows: Sequence[tuple[float, float]] = NO_SWITCHES,
        sensors: Sensors | None = None,
        drive: Drive | None = None,
    ) -> None:
        _check_arguments(name, windows, probe_delay)
        sensors = Sensors() if sensors is None else sensors
        self.sensors = sensors
        rng = Normals(sensors.seed * 1_000_003 + zlib.crc32(name.encode()))
        self.name = name
        self.resolution = resolution
        """Travel per encoder count [m or rad]."""
        self.encoder = IncrementalEncoder(
            resolution, counts_per_rev, origin, index_width, sensors.index_jitter, rng
        )
        self.has_drive = bool(has_drive)
        self._drive = drive
        self.probe = probe
        self.probe_delay = probe_delay
        self.counts = 0
        self.index_count = self.index_seq = 0
        self.index = self.lim_pos = self.lim_neg = self.ref = self.tp = False
        self.tp_count = self.tp_seq = 0
        self.encoder_ok = True
        self.absolute = sensors.absolute
        """The absolute measuring system (None: the axis has none)."""
        self.absolute_word = 0 if self.absolute is None else self.absolute.word(origin)
        """The last word the absolute sensor sent (known from power-on)."""
        self.absolute_ok = True
        """The last frame passed its check (False under :class:`mcl.faults.AbsoluteFrameError`:
        the word is discarded)."""
        self.analog: Sequence[float] = ()
        self.inputs: Sequence[bool] = ()
        self.outputs = [False] * digital_outputs
        self.volts = 0.0
        """Command applied to the drive [V] (after analog faults; 0 when disabled)."""
        self.enabled = False
        """The amplifier is switched on (enable, and no drive fault)."""
        self.brake = True
        """The holding brake holds (engaged and working)."""
        self.t = 0.0
        """Time of the last sample [s]."""
        self._x = origin
        self._q = origin
        self._history: list[tuple[float, float, float]] = []
        """The samples (t, x, q) back to one probe delay ago, oldest first (a few)."""
        self._latches: deque[float] = deque()
        self._faults: dict[str, flt.Fault] = {}
        self._shift = 0.0
        self._frozen_at: float | None = None
        self._edges = [-math.inf] * 4
        self._true = [False, False, False, False]
        self._rngs: dict[str, random.Random] = {}
        self._disabled_at = -math.inf
        self._enable_request = False
        self._rng = rng
        self._noise = sensors.encoder_noise * resolution
        self._hysteresis = sensors.switch_hysteresis
        self._spread = sensors.switch_repeatability
        self._delayed = sensors.output_delay == 1
        self._pending: tuple[float, bool] | None = None
        (self._plo, self._phi), (self._nlo, self._nhi), (self._rlo, self._rhi) = windows
        self._physical = [False, False, False]
        """Per switch, the level the switch itself has (before faults)."""
        self._trip = [0.0, 0.0, 0.0]
        """Per switch, this edge's deviation of the trip point (repeatability) [m or rad]."""

    # ------------------------------------------------------------------ state
    def settings(self) -> tuple[tuple[str, object], ...]:
        """The fixed settings a :class:`ChannelSnapshot` must match, as (name, value) pairs."""
        enc = self.encoder
        return (
            ("name", self.name),
            ("resolution", self.resolution),
            ("encoder", (enc._n, enc._width)),
            ("has_drive", self.has_drive),
            ("probe", (self.probe, self.probe_delay)),
            ("digital_outputs", len(self.outputs)),
            (
                "switch windows",
                ((self._plo, self._phi), (self._nlo, self._nhi), (self._rlo, self._rhi)),
            ),
            ("sensors", self.sensors),
        )

    def snapshot(self) -> ChannelSnapshot:
        """Everything the channel carries, now (an immutable value; see :meth:`restore`)."""
        return ChannelSnapshot(
            settings=self.settings(),
            encoder=self.encoder.snapshot(),
            noise=self._rng.snapshot(),
            counts=self.counts,
            index_count=self.index_count,
            index_seq=self.index_seq,
            index=self.index,
            lim_pos=self.lim_pos,
            lim_neg=self.lim_neg,
            ref=self.ref,
            tp=self.tp,
            tp_count=self.tp_count,
            tp_seq=self.tp_seq,
            encoder_ok=self.encoder_ok,
            analog=tuple(self.analog),
            inputs=tuple(self.inputs),
            outputs=tuple(self.outputs),
            volts=self.volts,
            enabled=self.enabled,
            brake=self.brake,
            t=self.t,
            x=self._x,
            q=self._q,
            history=tuple(self._history),
            latches=tuple(self._latches),
            faults=tuple(self._faults.values()),
            fault_rngs=tuple((key, rng.getstate()) for key, rng in self._rngs.items()),
            shift=self._shift,
            frozen_at=self._frozen_at,
            edges=tuple(self._edges),
            true_levels=tuple(self._true),
            disabled_at=self._disabled_at,
            enable_request=self._enable_request,
            pending=self._pending,
            physical=tuple(self._physical),
            trip=tuple(self._trip),
        )

    def check_snapshot(self, snapshot: ChannelSnapshot) -> None:
        """Raise :class:`~mcl.errors.StateError` unless ``snapshot`` was taken from a channel
        with this one's settings (the message names the settings that differ)."""
        mine = dict(self.settings())
        differ = [
            f"{name} {value!r} (this channel: {mine.get(name)!r})"
            for name, value in snapshot.settings
            if not _same(mine.get(name), value)
        ]
        if differ or len(mine) != len(snapshot.settings):
            raise StateError(
                f"axis {self.name}: the state was saved from a channel with other settings: "
                f"{'; '.join(differ) or 'other items'}; restore it into the machine it was "
                f"saved from (built with the same sensors and model)"
            )

    def restore(self, snapshot: ChannelSnapshot) -> None:
        """Return to the moment ``snapshot`` was taken (:meth:`snapshot`).

        The plant's amplifier and brake are not driven here: their state belongs to the plant
        and returns with the plant's own state.

        Raises:
            StateError: the snapshot is of a channel with other settings.
        """
        self.check_snapshot(snapshot)
        s = snapshot
        self.encoder.restore(s.encoder)
        self._rng.restore(s.noise)
        self.counts = s.counts
        self.index_count, self.index_seq, self.index = s.index_count, s.index_seq, s.index
        self.lim_pos, self.lim_neg, self.ref, self.tp = s.lim_pos, s.lim_neg, s.ref, s.tp
        self.tp_count, self.tp_seq = s.tp_count, s.tp_seq
        self.encoder_ok = s.encoder_ok
        self.analog = s.analog
        self.inputs = s.inputs
        self.outputs[:] = s.outputs  # in place: a device may hold the list
        self.volts, self.enabled, self.brake = s.volts, s.enabled, s.brake
        self.t, self._x, self._q = s.t, s.x, s.q
        self._history = list(s.history)
        self._latches = deque(s.latches)
        self._faults = {fault.key(): fault for fault in s.faults}
        rngs: dict[str, random.Random] = {}
        for key, state in s.fault_rngs:
            rng = random.Random()
            rng.setstate(state)
            rngs[key] = rng
        self._rngs = rngs
        self._shift, self._frozen_at = s.shift, s.frozen_at
        self._edges = list(s.edges)
        self._true = list(s.true_levels)
        self._disabled_at, self._enable_request = s.disabled_at, s.enable_request
        self._pending = s.pending
        self._physical = list(s.physical)
        self._trip = list(s.trip)
        self.absolute_ok = "absolute" not in self._faults
        if self.absolute is not None and self.absolute_ok:
            self.absolute_word = self.absolute.word(s.x)  # a function of the position

    # ------------------------------------------------------------------ faults
    @property
    def faults(self) -> list[flt.Fault]:
        """The faults set on this channel."""
        return list(self._faults.values())

    def set_fault(self, fault: flt.Fault) -> None:
        """Apply ``fault`` (it replaces a fault of the same slot)."""
        if (
            isinstance(fault, flt.SwitchStuck | flt.SwitchBounce)
            and fault.switch not in _SWITCH_INDEX
        ):
            raise ValueError(f"switch must be one of {flt.SWITCH_NAMES}, got {fault.switch!r}")
        key = fault.key()
        if isinstance(fault, flt.EncoderFreeze | flt.EncoderWireBreak):
            self._frozen_at = self._x - self._shift
        if isinstance(fault, flt.SwitchStuck | flt.SwitchBounce) and key not in self._faults:
            i = _SWITCH_INDEX[fault.switch]  # the level now is the true one: no edge yet
            self._true[i] = (self.lim_pos, self.lim_neg, self.ref, self.tp)[i]
            self._edges[i] = -math.inf
        if isinstance(fault, flt.BrakeSlow) and self.brake:
            self._disabled_at = -math.inf  # an engaged brake stays engaged
        seed = getattr(fault, "seed", None)
        if seed is not None:
            self._rngs[key] = random.Random(seed)
        self._faults[key] = fault
        if isinstance(fault, flt.AbsoluteFrameError):
            self.absolute_ok = False  # the module sees the bad frame at once

    def clear_fault(self, fault: flt.Fault) -> None:
        """Remove ``fault`` if it is set (a frozen counter resumes from where it stopped)."""
        if self._faults.get(fault.key()) == fault:
            del self._faults[fault.key()]
            if isinstance(fault, flt.EncoderFreeze | flt.EncoderWireBreak):
                self._frozen_at = None
                self.encoder_ok = True
            if isinstance(fault, flt.AbsoluteFrameError) and self.absolute is not None:
                self.absolute_ok = True  # the next frame is good: the position now
                self.absolute_word = self.absolute.word(self._x)

    # ------------------------------------------------------------------ inputs
    def sample(
        self,
        t: float,
        x: float,
        at_pos: float,
        at_neg: float,
        at_ref: float,
        probe_q: float | None = None,
        analog: Sequence[float] = (),
    ) -> None:
        """Sample the inputs at time ``t`` [s] from the physics.

        Args:
            t: the servo instant [s].
            x: true position of the axis [m or rad].
            at_pos, at_neg, at_ref: where LIM+, LIM− and REF see their cam, in the coordinate
                of their windows (the axis position on a slide; the angle from switch to cam on
                a hinge) [m or rad].
            probe_q: the coordinate the probe marks are on (default: ``x``).
            analog: true analog input voltages [V].
        """
        enc = self.encoder
        lim_pos = self._actuated(0, at_pos)
        lim_neg = self._actuated(1, at_neg)
        ref = self._actuated(2, at_ref)
        x_enc = x - self._shift  # the shift keeps what a cleared fault lost
        if self._noise:
            x_enc += self._noise * self._rng.next()
        if self._faults:
            lim_pos, lim_neg, ref, analog = self._faulty_inputs(
                t, x, x_enc, lim_pos, lim_neg, ref, analog
            )
        else:
            enc.update(x_enc)
            self.counts = enc.counts
        self.index = enc.index and self.encoder_ok
        self.index_count = enc.index_count
        self.index_seq = enc.index_seq
        self.lim_pos, self.lim_neg, self.ref = lim_pos, lim_neg, ref
        self.analog = analog
        if self.absolute is not None:
            self.absolute_ok = "absolute" not in self._faults
            if self.absolute_ok:
                self.absolute_word = self.absolute.word(x)
        if self.probe is not None:
            self._sample_probe(t, x, x if probe_q is None else probe_q)
        self.t, self._x = t, x
        if self._pending is not None:  # driven by hand: no runtime latched it at this instant
            self.latch(t)

    def absolute_position(self) -> float | None:
        """The position the absolute sensor's last word stands for [m or rad]; None without
        an absolute sensor or when the last frame failed its check."""
        absolute = self.absolute
        if absolute is None or not self.absolute_ok:
            return None
        return absolute.position(self.absolute_word)

    @property
    def position(self) -> float:
        """True position of the axis now [m or rad]: the physics' ground truth (a plant's
        channel reads its physics; by default the position of the last sample)."""
        return self._x

    def _actuated(self, i: int, at: float) -> bool:
        """Switch ``i`` at coordinate ``at``: on inside its window (shifted by this edge's
        repeatability), released only ``switch_hysteresis`` outside it."""
        if i == 0:
            lo, hi = self._plo, self._phi
        elif i == 1:
            lo, hi = self._nlo, self._nhi
        else:
            lo, hi = self._rlo, self._rhi
        j = self._trip[i]
        on = self._physical[i]
        if on:
            h = self._hysteresis
            now = lo - h + j <= at <= hi + h - j
        else:
            now = lo + j <= at <= hi - j
        if now != on:
            self._physical[i] = now
            if self._spread:
                # the next edge's trip point, within half the hysteresis of the nominal one
                limit = 0.5 * self._hysteresis if self._hysteresis else math.inf
                self._trip[i] = max(-limit, min(limit, self._spread * self._rng.next()))
        return now

    def _sample_probe(self, t: float, x: float, q: float) -> None:
        probe, delay = self.probe, self.probe_delay
        assert probe is not None
        history = self._history
        t0, q0 = self.t, self._q
        f = probe.rising(q0, q) if t > t0 else None
        if f is not None:
            self._latches.append(t0 + f * (t - t0) + delay)
        history.append((t, x, q))
        while len(history) > 2 and history[1][0] <= t - delay:
            del history[0]
        # the input as the module sees it: the sensor's level `delay` ago
        self.tp = probe.level(self._at(t - delay)[1]) if delay else probe.level(q)
        while self._latches and self._latches[0] <= t:
            x_latch = self._at(self._latches.popleft())[0] - self._shift
            self.tp_count = self.encoder.count_at(x_latch)
            self.tp_seq += 1
        self._q = q
        if self._faults and "switch:tp" in self._faults:
            self.tp = self._switch(3, self.tp, t)

    def _at(self, t: float) -> tuple[float, float]:
        """Axis position and probe coordinate at time ``t``, interpolated from the history."""
        history = self._history
        if t <= history[0][0]:
            return history[0][1], history[0][2]
        prev = history[0]
        for item in history:
            if item[0] >= t:
                s = (t - prev[0]) / (item[0] - prev[0]) if item[0] > prev[0] else 1.0
                return prev[1] + s * (item[1] - prev[1]), prev[2] + s * (item[2] - prev[2])
            prev = item
        return prev[1], prev[2]

    def _faulty_inputs(
        self,
        t: float,
        x: float,
        x_enc: float,
        lim_pos: bool,
        lim_neg: bool,
        ref: bool,
        analog: Sequence[float],
    ) -> tuple[bool, bool, bool, Sequence[float]]:
        faults, enc = self._faults, self.encoder
        encoder = faults.get("encoder")
        if isinstance(encoder, flt.EncoderLostCounts):
            self._shift += encoder.fraction * (x - self._x)
        if isinstance(encoder, flt.EncoderFreeze | flt.EncoderWireBreak):
            assert self._frozen_at is not None
            self._shift = x - self._frozen_at
            x_enc = self._frozen_at
        elif isinstance(encoder, flt.EncoderLostCounts):
            x_enc -= encoder.fraction * (x - self._x)
        enc.update(x_enc)
        self.counts = enc.counts
        if isinstance(encoder, flt.EncoderNoise):
            self.counts += self._rngs["encoder"].randint(-encoder.counts, encoder.counts)
        self.encoder_ok = not isinstance(encoder, flt.EncoderWireBreak)
        lim_pos = self._switch(0, lim_pos, t)
        lim_neg = self._switch(1, lim_neg, t)
        ref = self._switch(2, ref, t)
        if analog:
            analog = [self._analog_in(i, v) for i, v in enumerate(analog)]
        return lim_pos, lim_neg, ref, analog

    def _switch(self, i: int, level: bool, t: float) -> bool:
        if level != self._true[i]:
            self._true[i] = level
            self._edges[i] = t
        fault = self._faults.get(f"switch:{tuple(_SWITCH_INDEX)[i]}")
        if isinstance(fault, flt.SwitchStuck):
            return bool(fault.level)
        if isinstance(fault, flt.SwitchBounce):
            since = t - self._edges[i]
            if 0.0 <= since < fault.duration:
                return level != (math.floor(since / fault.period) % 2 == 0)
        return level

    def _analog_in(self, channel: int, volts: float) -> float:
        fault = self._faults.get(f"analog_in:{channel}")
        if not isinstance(fault, flt.AnalogInputFault):
            return volts
        noise = self._rngs[fault.key()].uniform(-fault.noise, fault.noise)
        return volts + fault.offset + noise

    # ------------------------------------------------------------------ outputs
    @property
    def delayed(self) -> bool:
        """The module latches the outputs for one servo cycle (``sensors.output_delay`` 1)."""
        return self._delayed

    def write(self, volts: float, enable: bool) -> None:
        """Set the analog command [V] and the drive enable (:class:`mcl.io.AxisIO`); with
        ``sensors.output_delay`` 1 they reach the drive at the next :meth:`latch`."""
        if not self.has_drive:
            return
        if self._delayed:
            self._pending = (volts, enable)
        else:
            self._output(volts, enable, self.t)

    def latch(self, t: float) -> None:
        """The module's output latch at the servo instant ``t`` [s]: the command written in the
        last servo cycle reaches the drive (with ``output_delay`` 1; nothing is pending else).

        :class:`mcl.runtime.Runtime` runs it as a phase of the servo cycle; a channel driven by
        hand, without a runtime, latches at its next :meth:`sample`.
        """
        pending = self._pending
        if pending is not None:
            self._pending = None
            self._output(pending[0], pending[1], t)

    def _output(self, volts: float, enable: bool, t: float) -> None:
        """The module's outputs reach the amplifier and the brake (through their faults) at
        time ``t`` [s]."""
        if self._faults:
            volts, on, brake = self._faulty_outputs(volts, enable, t)
        else:
            if enable != self._enable_request and not enable:
                self._disabled_at = t
            on, brake = enable, not enable
        self._enable_request = enable
        self.enabled = on
        self.brake = brake
        volts = volts if on else 0.0
        self.volts = volts
        drive = self._drive
        if drive is not None:
            drive.apply(volts, on, brake)

    def _faulty_outputs(self, volts: float, enable: bool, t: float) -> tuple[float, bool, bool]:
        faults = self._faults
        if enable != self._enable_request and not enable:
            self._disabled_at = t
        analog = faults.get("analog_out")
        if isinstance(analog, flt.AnalogOffset):
            volts += analog.volts
        elif isinstance(analog, flt.AnalogNoise):
            volts += self._rngs["analog_out"].uniform(-analog.volts, analog.volts)
        volts = max(-DAC_FULL_SCALE, min(DAC_FULL_SCALE, volts))
        on = enable and "drive" not in faults
        brake_fault = faults.get("brake")
        if isinstance(brake_fault, flt.BrakeFailure):
            brake = False
        elif isinstance(brake_fault, flt.BrakeSlow):
            brake = not on and (enable or t - self._disabled_at >= brake_fault.delay)
        else:
            brake = not on
        return volts, on, brake

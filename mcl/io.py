"""The I/O boundary: what a GT-x75x servo module sees of one axis.

:class:`AxisIO` is the contract; :class:`mcl.channel.AxisChannel` implements it once, and an
:class:`mcl.Axis` takes an ``AxisChannel``. A plant (the pure-Python simulated axes of
:mod:`mcl.simaxis`, the MuJoCo plant of ``scenes``, or a real module) subclasses it and supplies
the physics. Once per servo cycle the servo core reads the inputs (sampled at the same instant) and
then calls :meth:`AxisIO.write`.
"""

from __future__ import annotations

__all__ = ["AxisIO"]

from collections.abc import Sequence
from typing import Protocol, runtime_checkable


@runtime_checkable
class AxisIO(Protocol):
    """Inputs and outputs of one axis channel.

    Inputs (read by the servo core, sampled at the current servo instant):
        counts: incremental encoder counter [counts]; grows in the axis' positive direction.
        index_count: counter value latched by hardware at the last rising edge of the index
            pulse NI [counts].
        index_seq: number of index edges latched so far; a change means a new ``index_count``.
        index: level of the index pulse NI now.
        lim_pos, lim_neg: limit switches LIM+ / LIM− (True = actuated).
        ref: reference switch REF (True = actuated).
        tp: touch-probe input TP.
        tp_count, tp_seq: counter latched at the last rising edge of TP, and how many so far.
        encoder_ok: False when the encoder line monitor reports a fault (a broken wire).
        analog: analog inputs [V] (e.g. pressure transducers); may be empty.
        inputs: further digital inputs; may be empty.
        outputs: digital outputs the program sets (a knife valve, a clamp); may be empty.
        has_drive: False for an encoder-only axis; :meth:`write` then does nothing.
    """

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
    analog: Sequence[float]
    inputs: Sequence[bool]
    outputs: list[bool]
    has_drive: bool

    def write(self, volts: float, enable: bool) -> None:
        """Set the analog command [V] and the drive enable.

        ``enable`` False switches the amplifier off (no force) and engages the holding brake
        where the axis has one; True releases the brake.
        """
        ...

"""Digital and analog inputs and outputs of an axis channel.

PLCopen MC_ReadDigitalInput, MC_ReadDigitalOutput and MC_WriteDigitalOutput; MC_ReadAnalogInput
is beyond PLCopen.

Digital inputs are numbered per axis: 0 LIM+, 1 LIM−, 2 REF, 3 TP, then the channel's further
inputs. Digital outputs (a knife valve, a clamp) and analog inputs (pressure transducers [V]) are
numbered from 0 as the machine wires them. The same values are the AXIS_REF fields ``DI``, ``DO``
and ``AI`` of :class:`mcl.Axis`.
"""

from __future__ import annotations

__all__ = [
    "MC_ReadAnalogInput",
    "MC_ReadDigitalInput",
    "MC_ReadDigitalOutput",
    "MC_WriteDigitalOutput",
]

from typing import Any, ClassVar

from mcl.errors import ErrorID
from mcl.fb import EnableFB, ExecuteFB, number


def _index(value: object, count: int) -> int | None:
    """A channel number in 0 … count−1, or None."""
    n = number(value)
    if not (n == n and 0 <= n < count and n == int(n)):
        return None
    return int(n)


class MC_ReadDigitalInput(EnableFB):
    """Value of digital input InputNumber (0 LIM+, 1 LIM−, 2 REF, 3 TP, 4… further inputs).

    Outputs: Valid, Value, Error/ErrorID (EParam 5 for a number the axis does not have).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("InputNumber",)
    InputNumber: int = 0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Value = False

    def _evaluate(self) -> int:
        inputs = self.axis.DI
        i = _index(self.InputNumber, len(inputs))
        if i is None:
            self.Value = False
            return ErrorID.EParam
        self.Value = inputs[i]
        return 0

    def _disable(self) -> None:
        self.Value = False


class MC_ReadDigitalOutput(EnableFB):
    """Value of digital output OutputNumber. Outputs: Valid, Value, Error/ErrorID (EParam 5)."""

    INPUTS: ClassVar[tuple[str, ...]] = ("OutputNumber",)
    OutputNumber: int = 0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Value = False

    def _evaluate(self) -> int:
        outputs = self.axis.DO
        i = _index(self.OutputNumber, len(outputs))
        if i is None:
            self.Value = False
            return ErrorID.EParam
        self.Value = outputs[i]
        return 0

    def _disable(self) -> None:
        self.Value = False


class MC_WriteDigitalOutput(ExecuteFB):
    """Sets digital output OutputNumber to Value on the rising edge of Execute; Done at once.

    Error/ErrorID EParam 5 for an output the axis does not have (the outputs stay as they are).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("OutputNumber", "Value")
    OutputNumber: int = 0
    Value: bool = False

    def _begin(self) -> int:
        outputs = self.axis.io.outputs
        i = _index(self.OutputNumber, len(outputs))
        if i is None:
            return ErrorID.EParam
        outputs[i] = bool(self.Value)
        return 0


class MC_ReadAnalogInput(EnableFB):
    """Value [V] of analog input InputNumber (e.g. a pressure transducer, 0–10 V).

    Outputs: Valid, Value, Error/ErrorID (EParam 5 for an input the axis does not have).
    """

    INPUTS: ClassVar[tuple[str, ...]] = ("InputNumber",)
    InputNumber: int = 0

    def __init__(self, **inputs: Any) -> None:
        super().__init__(**inputs)
        self.Value = 0.0

    def _evaluate(self) -> int:
        analog = self.axis.AI
        i = _index(self.InputNumber, len(analog))
        if i is None:
            self.Value = 0.0
            return ErrorID.EParam
        self.Value = float(analog[i])
        return 0

    def _disable(self) -> None:
        self.Value = 0.0

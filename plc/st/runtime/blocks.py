"""The IEC 61131-3 standard function blocks: timers (TON, TOF, TP) on the program's clock (the
simulated time, TIME in ms), edges (R_TRIG, F_TRIG), counters (CTU, CTD, CTUD) and bistables
(SR, RS). Inputs and outputs are attributes with the IEC names; a call is one scan."""

from __future__ import annotations

__all__ = [
    "CTD",
    "CTU",
    "CTUD",
    "F_TRIG",
    "INT_MAX",
    "INT_MIN",
    "RS",
    "R_TRIG",
    "SR",
    "STANDARD",
    "TOF",
    "TON",
    "TP",
    "Clock",
    "Timer",
]

from collections.abc import Callable

Clock = Callable[[], int]
"""The program's time now [ms]."""

INT_MAX = 32767
INT_MIN = -32768


class Timer:
    """Common state of the timers: IN, PT [ms] → Q, ET [ms]."""

    def __init__(self, clock: Clock) -> None:
        self._clock = clock
        self.IN = False
        self.PT = 0
        self.Q = False
        self.ET = 0
        self._start = 0
        self._running = False
        self._last = False


class TON(Timer):
    """On-delay: Q rises once IN has been TRUE for PT; IN FALSE resets Q and ET."""

    def __call__(self) -> None:
        if not self.IN:
            self._running = self.Q = False
            self.ET = 0
            return
        now = self._clock()
        if not self._running:
            self._running, self._start = True, now
        elapsed = now - self._start
        self.Q = elapsed >= self.PT
        self.ET = min(elapsed, self.PT)


class TOF(Timer):
    """Off-delay: Q is TRUE with IN and falls once IN has been FALSE for PT."""

    def __call__(self) -> None:
        if self.IN:
            self.Q, self.ET, self._running = True, 0, False
        elif self._last:
            self._running, self._start = True, self._clock()
        if self._running:
            elapsed = self._clock() - self._start
            if elapsed >= self.PT:
                self.Q, self.ET, self._running = False, self.PT, False
            else:
                self.ET = elapsed
        self._last = self.IN


class TP(Timer):
    """Pulse: a rising edge of IN gives Q TRUE for PT, whatever IN does meanwhile; ET holds PT
    after the pulse while IN stays TRUE."""

    def __call__(self) -> None:
        if not self._running and self.IN and not self._last and not self.Q:
            self._running, self._start, self.Q = True, self._clock(), True
        if self._running:
            elapsed = self._clock() - self._start
            if elapsed >= self.PT:
                self.Q, self.ET, self._running = False, self.PT, False
            else:
                self.ET = elapsed
        if not self._running and not self.IN:
            self.ET = 0
        self._last = self.IN


class R_TRIG:
    """Rising edge: Q TRUE for the one call where CLK went TRUE (also at the first call)."""

    def __init__(self, clock: Clock | None = None) -> None:
        self.CLK = False
        self.Q = False
        self._m = False

    def __call__(self) -> None:
        self.Q = self.CLK and not self._m
        self._m = self.CLK


class F_TRIG:
    """Falling edge: Q TRUE for the one call where CLK went FALSE (IEC: memory initially TRUE,
    so no pulse at start-up)."""

    def __init__(self, clock: Clock | None = None) -> None:
        self.CLK = False
        self.Q = False
        self._m = True

    def __call__(self) -> None:
        self.Q = not self.CLK and not self._m
        self._m = not self.CLK


class CTU:
    """Up counter: a rising edge of CU counts CV up (to its type's largest value, 32767 for
    INT), R resets; Q = CV >= PV."""

    MAX = INT_MAX

    def __init__(self, clock: Clock | None = None) -> None:
        self.CU = self.R = self.Q = False
        self.PV = self.CV = 0
        self._cu = False

    def __call__(self) -> None:
        edge, self._cu = self.CU and not self._cu, self.CU
        if self.R:
            self.CV = 0
        elif edge and self.CV < self.MAX:
            self.CV += 1
        self.Q = self.CV >= self.PV


class CTD:
    """Down counter: a rising edge of CD counts CV down (to its type's smallest value, -32768
    for INT), LD loads PV; Q = CV <= 0."""

    MIN = INT_MIN

    def __init__(self, clock: Clock | None = None) -> None:
        self.CD = self.LD = self.Q = False
        self.PV = self.CV = 0
        self._cd = False

    def __call__(self) -> None:
        edge, self._cd = self.CD and not self._cd, self.CD
        if self.LD:
            self.CV = self.PV
        elif edge and self.CV > self.MIN:
            self.CV -= 1
        self.Q = self.CV <= 0


class CTUD:
    """Up/down counter: R resets, LD loads PV, else the edges of CU and CD count (both at once:
    no change); QU = CV >= PV, QD = CV <= 0."""

    MAX, MIN = INT_MAX, INT_MIN

    def __init__(self, clock: Clock | None = None) -> None:
        self.CU = self.CD = self.R = self.LD = self.QU = self.QD = False
        self.PV = self.CV = 0
        self._cu = self._cd = False

    def __call__(self) -> None:
        up, self._cu = self.CU and not self._cu, self.CU
        down, self._cd = self.CD and not self._cd, self.CD
        if self.R:
            self.CV = 0
        elif self.LD:
            self.CV = self.PV
        elif up and not down and self.CV < self.MAX:
            self.CV += 1
        elif down and not up and self.CV > self.MIN:
            self.CV -= 1
        self.QU = self.CV >= self.PV
        self.QD = self.CV <= 0


class SR:
    """Set-dominant bistable: Q1 := S1 OR (NOT R AND Q1)."""

    def __init__(self, clock: Clock | None = None) -> None:
        self.S1 = self.R = self.Q1 = False

    def __call__(self) -> None:
        self.Q1 = self.S1 or (not self.R and self.Q1)


class RS:
    """Reset-dominant bistable: Q1 := NOT R1 AND (S OR Q1)."""

    def __init__(self, clock: Clock | None = None) -> None:
        self.S = self.R1 = self.Q1 = False

    def __call__(self) -> None:
        self.Q1 = not self.R1 and (self.S or self.Q1)


_TIMER = {"IN": ("BOOL", "input"), "PT": ("TIME", "input"), "Q": ("BOOL", "output")}
STANDARD: dict[str, tuple[type, dict[str, tuple[str, str]]]] = {
    "TON": (TON, {**_TIMER, "ET": ("TIME", "output")}),
    "TOF": (TOF, {**_TIMER, "ET": ("TIME", "output")}),
    "TP": (TP, {**_TIMER, "ET": ("TIME", "output")}),
    "R_TRIG": (R_TRIG, {"CLK": ("BOOL", "input"), "Q": ("BOOL", "output")}),
    "F_TRIG": (F_TRIG, {"CLK": ("BOOL", "input"), "Q": ("BOOL", "output")}),
    "CTU": (
        CTU,
        {"CU": ("BOOL", "input"), "R": ("BOOL", "input"), "PV": ("INT", "input")}
        | {"Q": ("BOOL", "output"), "CV": ("INT", "output")},
    ),
    "CTD": (
        CTD,
        {"CD": ("BOOL", "input"), "LD": ("BOOL", "input"), "PV": ("INT", "input")}
        | {"Q": ("BOOL", "output"), "CV": ("INT", "output")},
    ),
    "CTUD": (
        CTUD,
        {"CU": ("BOOL", "input"), "CD": ("BOOL", "input"), "R": ("BOOL", "input")}
        | {"LD": ("BOOL", "input"), "PV": ("INT", "input")}
        | {"QU": ("BOOL", "output"), "QD": ("BOOL", "output"), "CV": ("INT", "output")},
    ),
    "SR": (SR, {"S1": ("BOOL", "input"), "R": ("BOOL", "input"), "Q1": ("BOOL", "output")}),
    "RS": (RS, {"S": ("BOOL", "input"), "R1": ("BOOL", "input"), "Q1": ("BOOL", "output")}),
}
"""Each standard block: its class and its members (name → (type, direction))."""


_COUNTED = {"INT": (16, True), "DINT": (32, True), "LINT": (64, True)}
_COUNTED |= {"UDINT": (32, False), "ULINT": (64, False)}
"""The types of the typed counters (IEC 61131-3 3rd ed. 6.6.3.5.4, Table 45): width, signed."""


def _typed_counters() -> None:
    """CTU_INT, CTU_DINT, ... CTUD_ULINT: the counters with PV and CV of another integer type."""
    for type_name, (bits, signed) in _COUNTED.items():
        low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
        for base in (CTU, CTD, CTUD):
            name = f"{base.__name__}_{type_name}"
            cls = type(name, (base,), {"MAX": high, "MIN": low, "__doc__": base.__doc__})
            globals()[name] = cls  # the generated code makes it as _std.CTU_DINT(_clock)
            members = dict(STANDARD[base.__name__][1])
            members |= {"PV": (type_name, "input"), "CV": (type_name, "output")}
            STANDARD[name] = (cls, members)


_typed_counters()

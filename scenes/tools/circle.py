"""The circular test of ISO 230-4 on two axes of a Cartesian machine's physics.

:func:`circle_test` groups two axes and runs one arc per direction: a 90° run-in on the test
circle, the full circle, a 90° run-out (one MC_MoveCircularRelative of 180° plus a full turn,
the way a ballbar's feed-in and feed-out arcs lie on the circle), counter-clockwise and then
clockwise back. Only the full circle between the run-in and the run-out is evaluated, each
servo cycle, from two sources: the encoders (``axis.POS``) and the physics' joints (where the
carriages really are). :func:`plot` draws the ballbar report's polar plot.

Figures (all lengths in mm, see :class:`Figures`): the circular deviation G (max − min radius
about the least-squares centre), the bi-directional circular deviation (both directions about
one centre), the mean radial deviation (mean radius − nominal radius, about the commanded
centre), the reversal spikes at the quadrant points, and a harmonic fit of the radius that
gives the ellipse: the centre offset, the scale mismatch of the two axes and the tilt at 45°
that a lag (gain) mismatch between them leaves.
"""

from __future__ import annotations

__all__ = [
    "DIRECTIONS",
    "PLANES",
    "CircleResult",
    "Ellipse",
    "Figures",
    "Spike",
    "circle_test",
    "evaluate",
    "plot",
]

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import mcl
from scenes.errors import UserError
from scenes.tools.grouping import PoweredGroup

PLANES = {"XY": ("X", "Y"), "YZ": ("Y", "Z"), "ZX": ("Z", "X")}
"""The test planes: the two axes, the first horizontal in the plot; counter-clockwise is seen
from the positive third axis."""
DIRECTIONS = {"ccw": ("CCW",), "cw": ("CW",), "both": ("CCW", "CW")}
"""What ``direction`` may be and the laps it runs, in order."""
SOURCES = ("encoders", "joints")
"""Where the path is measured: the axes' encoders (POS) and the physics' joints."""
RUN_ANGLE = 90.0
"""Run-in and run-out on the circle before and after the evaluated lap [deg]."""
QUADRANTS = (0.0, 90.0, 180.0, 270.0)
"""The quadrant points, where one of the axes reverses [deg]."""
SPIKE_WINDOW = 20.0
"""Half-width of the window about a quadrant point in which a spike is sought [deg]."""
_CCW = mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
_CW = mcl.MC_CIRC_PATHCHOICE.CLOCKWISE


@dataclass(frozen=True)
class Spike:
    """The reversal spike at a quadrant point: ``height`` the peak of the radius above (+) or
    below (−) the harmonic fit's residual around it [mm], ``width`` where it exceeds half of
    that [deg], ``at`` the quadrant point [deg]."""

    at: float
    height: float
    width: float


@dataclass(frozen=True)
class Ellipse:
    """The radius' harmonic fit ``a0 + a1·cos θ + b1·sin θ + a2·cos 2θ + b2·sin 2θ`` read as an
    ellipse: ``offset`` the centre's offset from the commanded one [mm] (a1, b1), ``scale``
    the first axis' scale minus the second's [1] (2·a2/R), ``tilt`` the radius' 45° term b2
    [mm], ``lag`` the first axis' lag behind the second that tilt means [s] (±2·b2/v), and the
    semi-axes [mm] and the angle of the major one [deg]."""

    offset: tuple[float, float]
    scale: float
    tilt: float
    lag: float
    major: float
    minor: float
    angle: float


@dataclass(frozen=True)
class Figures:
    """One lap measured by one source: ``G`` circular deviation [mm], ``mean_radial`` mean
    radius − nominal radius [mm], ``radial`` largest |radius − nominal| about the commanded
    centre [mm], ``spikes`` at the quadrant points and the ``ellipse``."""

    G: float
    mean_radial: float
    radial: float
    spikes: tuple[Spike, ...]
    ellipse: Ellipse

    @property
    def spike(self) -> float:
        """The largest spike height (magnitude) [mm]."""
        return max(abs(s.height) for s in self.spikes)


@dataclass
class CircleResult:
    """The circle test: its parameters, the laps measured (``laps[source][direction]`` (N, 2)
    points relative to the commanded centre [mm], in the plane's axes) and their figures."""

    plane: str
    radius: float
    feed: float
    laps: dict[str, dict[str, np.ndarray]]
    figures: dict[str, dict[str, Figures]] = field(default_factory=dict)
    bidirectional: dict[str, float] = field(default_factory=dict)
    """Bi-directional circular deviation per source [mm] (only with both directions)."""

    def as_dict(self) -> dict[str, Any]:
        """The figures as plain numbers (µm, deg, ms) for JSON."""
        out: dict[str, Any] = {"plane": self.plane, "radius_mm": self.radius, "feed": self.feed}
        for source, laps in self.figures.items():
            out[source] = {d: _plain(f) for d, f in laps.items()}
            if source in self.bidirectional:
                out[source]["G_bidirectional_um"] = round(self.bidirectional[source] * 1e3, 3)
        return out

    def summary(self) -> str:
        """The figures as a few lines of text (µm)."""
        lines = [f"circle {self.plane} R{self.radius:g} mm F{self.feed:g} mm/min"]
        for source, laps in self.figures.items():
            for direction, f in laps.items():
                e = f.ellipse
                spikes = " ".join(f"{s.height * 1e3:+.2f}/{s.width:.1f}°" for s in f.spikes)
                lines.append(
                    f"  {source:8} {direction:3}  G {f.G * 1e3:6.2f} µm  mean radial "
                    f"{f.mean_radial * 1e3:+6.2f} µm  radial {f.radial * 1e3:6.2f} µm  "
                    f"spikes 0/90/180/270° {spikes} µm  scale {e.scale * 1e6:+.1f} µm/m  "
                    f"45° tilt {e.tilt * 1e3:+.2f} µm (lag {e.lag * 1e3:+.3f} ms)"
                )
            if source in self.bidirectional:
                lines.append(
                    f"  {source:8} bi-directional G {self.bidirectional[source] * 1e3:.2f} µm"
                )
        return "\n".join(lines)


def _plain(f: Figures) -> dict[str, Any]:
    """A lap's figures in µm, deg and ms."""
    e = f.ellipse
    return {
        "G_um": round(f.G * 1e3, 3),
        "mean_radial_um": round(f.mean_radial * 1e3, 3),
        "radial_um": round(f.radial * 1e3, 3),
        "spike_um": round(f.spike * 1e3, 3),
        "spikes": [
            {k: round(v * (1e3 if k == "height" else 1.0), 3) for k, v in asdict(s).items()}
            for s in f.spikes
        ],
        "scale_um_per_m": round(e.scale * 1e6, 2),
        "tilt_um": round(e.tilt * 1e3, 3),
        "lag_ms": round(e.lag * 1e3, 4),
        "offset_um": [round(o * 1e3, 3) for o in e.offset],
    }


def circle_test(
    scene: Any,
    plane: str = "XY",
    radius: float = 50.0,
    feed: float = 1000.0,
    direction: str = "both",
    center: Sequence[float] | None = None,
    acceleration: float = 2000.0,
    jerk: float = 20000.0,
    timeout: float = 600.0,
) -> CircleResult:
    """Run the circle test on ``scene`` and evaluate it.

    Args:
        scene: a :class:`scenes.scene.Scene` of a Cartesian machine, the plane's axes still
            Disabled (they need no reference: every move is relative).
        plane: "XY", "YZ" or "ZX" (:data:`PLANES`).
        radius: nominal radius [mm].
        feed: path velocity [mm/min].
        direction: "ccw", "cw" or "both".
        center: the centre in the axes' coordinates [mm]; None: where they stand (a machine
            loaded at its start may stand on a limit switch: home it first or give a centre).
        acceleration, jerk: along the path [mm/s², mm/s³].
        timeout: simulated time for the whole test [s].

    Raises:
        UserError: a plane, direction, radius or feed that is not valid, an axis the scene lacks,
            or a move the group refuses (e.g. a circle beyond the software limits).
    """
    names = _checked(scene, plane, radius, feed, direction)
    axes = [scene.axes[n] for n in names]
    grouped = PoweredGroup(axes, f"circle{plane}", corner_tolerance=0.001)
    group, enable = grouped.group, grouped.enable
    moves: list[Any] = []
    go = [False]

    def program() -> None:
        grouped()
        for m in moves:
            m(Execute=go[0])
        for fb in (*grouped.blocks, *moves):
            if fb.Error:
                raise UserError.at("circle", type(fb).__name__, f"ErrorID {fb.ErrorID}", _WHAT_FITS)

    scene.run(program, until=lambda: enable.Done, timeout=2.0)
    scene.run(program, timeout=0.2)  # settle
    here = np.array(group.start_point(mcl.MC_BufferMode.Aborting))
    centre = here if center is None else np.asarray(center, dtype=float)
    laps = DIRECTIONS[direction]
    moves.extend(_moves(group, here, centre, radius, feed / 60.0, laps, acceleration, jerk))
    scales = np.array([scene.scales[n] for n in names])
    offset = np.array([scene.joint_position(n) for n in names]) * scales - here
    samples: list[tuple[int, float, float, float, float]] = []

    def observe(t: float) -> None:
        phase = next((k for k, m in enumerate(moves) if m.Active), -1)
        joints = [scene.joint_position(n) * s for n, s in zip(names, scales, strict=True)]
        samples.append((phase, axes[0].POS, axes[1].POS, *joints))

    go[0] = True
    scene.runtime.observers.append(observe)
    try:
        scene.run(program, until=lambda: moves[-1].Done, timeout=timeout)
    finally:
        scene.runtime.observers.remove(observe)
    result = CircleResult(plane, radius, feed, {s: {} for s in SOURCES})
    _split_laps(result, np.array(samples), laps, centre, offset)
    _evaluate(result, feed / 60.0)
    return result


def _split_laps(
    result: CircleResult,
    data: np.ndarray,
    laps: Sequence[str],
    centre: np.ndarray,
    offset: np.ndarray,
) -> None:
    """Each lap's points about the centre [mm], from the encoders and from the joints: the
    samples of its full circle (the run-in and run-out arcs left out)."""
    for k, lap in enumerate(laps):
        rows = data[data[:, 0] == k + 1]
        sign = 1.0 if lap == "CCW" else -1.0
        encoders, joints = rows[:, 1:3] - centre, rows[:, 3:5] - offset - centre
        mask = _lap_mask(encoders, sign)
        result.laps["encoders"][lap] = encoders[mask]
        result.laps["joints"][lap] = joints[mask]


def _evaluate(result: CircleResult, speed: float) -> None:
    """The figures of every source and lap at the path speed ``speed`` [mm/s], and the
    bi-directional deviation where both directions ran."""
    radius = result.radius
    for source in SOURCES:
        result.figures[source] = {
            lap: evaluate(points, radius, speed, lap == "CCW")
            for lap, points in result.laps[source].items()
        }
        if len(result.laps[source]) == 2:
            result.bidirectional[source] = circular_deviation(
                np.vstack(list(result.laps[source].values()))
            )


_WHAT_FITS = (
    "a circle within the axes' travel (software limits, limit switches: home first or give a"
    " centre clear of them) and velocity"
)


def _checked(scene: Any, plane: str, radius: float, feed: float, direction: str) -> tuple[str, str]:
    """The plane's two axis names once the arguments are valid."""
    if plane not in PLANES:
        raise UserError.at("circle", "plane", repr(plane), f"one of {sorted(PLANES)}")
    if direction not in DIRECTIONS:
        raise UserError.at("circle", "direction", repr(direction), f"one of {list(DIRECTIONS)}")
    for key, value in (("radius", radius), ("feed", feed)):
        if not (math.isfinite(value) and value > 0.0):
            raise UserError.at("circle", key, repr(value), "a positive number")
    names = PLANES[plane]
    missing = [n for n in names if n not in scene.axes]
    if missing:
        raise UserError.at(
            "circle", "plane", f"{plane}: no axis {missing}", f"axes of {sorted(scene.axes)}"
        )
    return names


def _moves(
    group: mcl.AxesGroup,
    here: np.ndarray,
    centre: np.ndarray,
    radius: float,
    speed: float,
    laps: Sequence[str],
    acceleration: float,
    jerk: float,
) -> list[Any]:
    """A line to the run-in's start (a quarter before the 0° point in the first lap's
    direction), then per lap one arc of 180° plus a full turn (run-in, circle, run-out)."""
    dynamics = dict(Velocity=speed, Acceleration=acceleration, Deceleration=acceleration, Jerk=jerk)
    first = 1.0 if laps[0] == "CCW" else -1.0
    start = centre + radius * np.array([0.0, -first])
    blocks: list[Any] = [
        mcl.MC_MoveLinearRelative(AxesGroup=group, Distance=list(start - here), **dynamics)
    ]
    point = start
    for lap in laps:
        end = 2.0 * centre - point
        blocks.append(
            mcl.MC_MoveCircularRelative(
                AxesGroup=group,
                CircMode=mcl.MC_CIRC_MODE.CENTER,
                AuxPoint=list(centre - point),
                EndPoint=list(end - point),
                PathChoice=_CCW if lap == "CCW" else _CW,
                Turns=1,
                BufferMode=mcl.MC_BufferMode.Buffered,
                **dynamics,
            )
        )
        point = end
    return blocks


def _lap_mask(points: np.ndarray, sign: float) -> np.ndarray:
    """The samples of the evaluated lap: past the run-in, before the run-out."""
    angle = np.unwrap(np.arctan2(points[:, 1], points[:, 0]))
    progress = np.degrees(sign * (angle - angle[0]))
    mask: np.ndarray = (progress >= RUN_ANGLE) & (progress < RUN_ANGLE + 360.0)
    return mask


def least_squares_centre(points: np.ndarray) -> np.ndarray:
    """The centre of the least-squares circle through ``points`` (N, 2) [mm]."""
    a = np.column_stack([2.0 * points, np.ones(len(points))])
    b = (points**2).sum(axis=1)
    solution = np.linalg.lstsq(a, b, rcond=None)[0]
    centre: np.ndarray = solution[:2]
    return centre


def circular_deviation(points: np.ndarray) -> float:
    """G: the radial distance between the two circles about the least-squares centre that
    enclose ``points`` [mm]."""
    r = np.linalg.norm(points - least_squares_centre(points), axis=1)
    return float(r.max() - r.min())


def evaluate(points: np.ndarray, radius: float, speed: float, ccw: bool) -> Figures:
    """The figures of one lap.

    Args:
        points: (N, 2) positions relative to the commanded centre [mm], one per servo cycle.
        radius: nominal radius [mm].
        speed: path velocity [mm/s] (for the lag that the 45° tilt means).
        ccw: the lap ran counter-clockwise.
    """
    r = np.linalg.norm(points, axis=1)
    theta = np.arctan2(points[:, 1], points[:, 0]) % (2.0 * math.pi)
    dr = r - radius
    basis = np.column_stack(
        [np.ones_like(theta)] + [f(k * theta) for k in (1, 2) for f in (np.cos, np.sin)]
    )
    coefficients = np.linalg.lstsq(basis, dr, rcond=None)[0]
    residual = dr - basis @ coefficients
    return Figures(
        G=circular_deviation(points),
        mean_radial=float(dr.mean()),
        radial=float(np.abs(dr).max()),
        spikes=tuple(_spike(np.degrees(theta), residual, q) for q in QUADRANTS),
        ellipse=_ellipse(coefficients, radius, speed, ccw),
    )


def _spike(angle: np.ndarray, residual: np.ndarray, at: float) -> Spike:
    """The spike of ``residual`` [mm] near the quadrant point ``at`` [deg] (angles in deg)."""
    off = (angle - at + 180.0) % 360.0 - 180.0
    window = np.abs(off) <= SPIKE_WINDOW
    if window.sum() < 3:
        return Spike(at, 0.0, 0.0)
    order = np.argsort(off[window])
    near, values = off[window][order], residual[window][order]
    values = values - np.median(values)
    peak = int(np.argmax(np.abs(values)))
    height = float(values[peak])
    above = np.abs(values) >= 0.5 * abs(height)
    lo = peak
    while lo > 0 and above[lo - 1]:
        lo -= 1
    hi = peak
    while hi < len(values) - 1 and above[hi + 1]:
        hi += 1
    half = 0.5 * abs(height)
    magnitude = np.abs(values)
    return Spike(
        at,
        height,
        _crossing(near, magnitude, hi, 1, half) - _crossing(near, magnitude, lo, -1, half),
    )


def _crossing(angle: np.ndarray, magnitude: np.ndarray, k: int, step: int, half: float) -> float:
    """Where ``magnitude`` falls to ``half`` between sample ``k`` (above it) and its neighbour
    ``k + step``, interpolated linearly [deg] (``angle[k]`` at the window's edge)."""
    j = k + step
    if not 0 <= j < len(angle):
        return float(angle[k])
    share = (magnitude[k] - half) / (magnitude[k] - magnitude[j])
    return float(angle[k] + share * (angle[j] - angle[k]))


def _ellipse(c: np.ndarray, radius: float, speed: float, ccw: bool) -> Ellipse:
    """The ellipse of the harmonic coefficients ``c`` = (a0, a1, b1, a2, b2) [mm]."""
    a0, a1, b1, a2, b2 = (float(x) for x in c)
    amplitude = math.hypot(a2, b2)
    return Ellipse(
        offset=(a1, b1),
        scale=2.0 * a2 / radius,
        tilt=b2,
        lag=(2.0 if ccw else -2.0) * b2 / speed,
        major=radius + a0 + amplitude,
        minor=radius + a0 - amplitude,
        angle=math.degrees(0.5 * math.atan2(b2, a2)),
    )


def plot(result: CircleResult, path: str | Path) -> Path:
    """Draw the polar plot of a ballbar report into ``path`` (PNG, needs the ``[plot]`` extra):
    per source the radial deviation of each direction against the angle, magnified (the radial
    scale in µm per division is written), the nominal circle dashed, G in the legend."""
    from mcl.extras import require

    require("scenes.tools.circle.plot", "plot")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(1, 2, subplot_kw={"projection": "polar"}, figsize=(12, 6.4))
    deviations = [
        (np.linalg.norm(p, axis=1) - result.radius) * 1e3
        for laps in result.laps.values()
        for p in laps.values()
    ]
    low = min(float(d.min()) for d in deviations)
    high = max(float(d.max()) for d in deviations)
    step = _division(high - low)
    low, high = step * math.floor(low / step), step * math.ceil(high / step)
    colours = {"CCW": "tab:blue", "CW": "tab:red"}
    for ax, source in zip(axes, SOURCES, strict=True):
        for lap, p in result.laps[source].items():
            theta = np.arctan2(p[:, 1], p[:, 0])
            deviation = (np.linalg.norm(p, axis=1) - result.radius) * 1e3
            g = result.figures[source][lap].G * 1e3
            ax.plot(theta, deviation, lw=1.0, color=colours[lap], label=f"{lap}  G {g:.2f} µm")
        ax.plot(np.linspace(0, 2 * math.pi, 361), np.zeros(361), "k--", lw=0.6)
        ax.set_rorigin(low - 2.0 * (high - low))
        ax.set_rlim(low, high)
        ax.set_rticks(np.arange(low, high + step / 2, step))
        ax.set_rlabel_position(22.5)
        bi = result.bidirectional.get(source)
        title = f"{source}: {step:g} µm/div" + (
            f", bi-directional G {bi * 1e3:.2f} µm" if bi else ""
        )
        ax.set_title(title, fontsize=10)
        ax.legend(loc="lower left", fontsize=8, bbox_to_anchor=(-0.1, -0.12))
    first, second = PLANES[result.plane]
    figure.suptitle(
        f"Circle test ISO 230-4, plane {result.plane} ({first} →, {second} ↑): R {result.radius:g} "
        f"mm, F {result.feed:g} mm/min; radial deviation [µm], 0 = nominal radius (dashed)"
    )
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(out, dpi=110)
    plt.close(figure)
    return out


def _division(span: float) -> float:
    """A round radial division [µm] giving about four divisions over ``span``."""
    raw = max(span, 0.1) / 4.0
    magnitude = 10.0 ** math.floor(math.log10(raw))
    return next(m * magnitude for m in (1.0, 2.0, 5.0, 10.0) if m * magnitude >= raw)

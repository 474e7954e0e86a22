"""The AxisIO contract (mcl/io.py), checked on both implementations with the same tests.

``mcl.SimAxis`` on an ``mcl.SimPlant`` and ``scenes.plant.MujocoAxisIO`` (X of the gantry) are
driven open loop with constant commands; what the channel reports (counts, index latch, switches)
is compared with the physical position of the plant. Both run with ideal sensors, so the contract
holds exactly; the sensors' imperfections have their own tests (tests/scenes/test_sensors.py).
"""

from __future__ import annotations

import itertools
import math
import random
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import pytest

import mcl
from scenes.machines import gantry


@dataclass(frozen=True)
class Sample:
    """The inputs after one plant step, with the physical state."""

    x: float
    v: float
    force: float
    counts: int
    index: bool
    index_count: int
    index_seq: int
    lim_pos: bool
    lim_neg: bool
    ref: bool


class Channel:
    """Adapter: one AxisIO with the plant that moves it and the physics behind it.

    Attributes:
        io: the AxisIO under test.
        resolution: travel per count [m]; lead: travel per index pulse [m].
        lim_neg, lim_pos, ref_edge: switch points [m] (REF actuated at or below ``ref_edge``).
        stops: hard stops [m]; vmax: speed at +10 V [m/s]; fmax: amplifier force limit [N].
        origin: physical position where the counter reads 0 [m].
    """

    def __init__(
        self,
        name: str,
        io: mcl.AxisIO,
        step: Callable[[], None],
        timestep: float,
        physics: Callable[[], tuple[float, float, float]],
        *,
        resolution: float,
        lead: float,
        lim_neg: float,
        lim_pos: float,
        ref_edge: float,
        stops: tuple[float, float],
        vmax: float,
        fmax: float,
    ) -> None:
        self.name, self.io, self._step, self.timestep = name, io, step, timestep
        self._physics = physics
        self.resolution, self.lead = resolution, lead
        self.counts_per_rev = round(lead / resolution)
        self.lim_neg, self.lim_pos, self.ref_edge = lim_neg, lim_pos, ref_edge
        self.stops, self.vmax, self.fmax = stops, vmax, fmax
        self.origin = self.position

    def sample(self) -> Sample:
        """The physical state and the inputs as they are now."""
        io = self.io
        return Sample(
            *self._physics(),
            io.counts,
            io.index,
            io.index_count,
            io.index_seq,
            io.lim_pos,
            io.lim_neg,
            io.ref,
        )

    @property
    def position(self) -> float:
        return self._physics()[0]

    @property
    def velocity(self) -> float:
        return self._physics()[1]

    @property
    def force(self) -> float:
        return self._physics()[2]

    def volts(self, speed: float) -> float:
        """The command for ``speed`` [m/s] (velocity-mode amplifier)."""
        return speed / self.vmax * 10.0

    def run(
        self,
        seconds: float,
        volts: float,
        enable: bool = True,
        until: Callable[[], bool] | None = None,
    ) -> list[Sample]:
        """Write the command once, then step the plant for ``seconds`` (or until ``until()``),
        sampling the inputs after every step."""
        self.io.write(volts, enable)
        samples = []
        for _ in range(round(seconds / self.timestep)):
            self._step()
            samples.append(self.sample())
            if until is not None and until():
                break
        return samples


def sim_channel() -> Channel:
    p = mcl.SimAxisParams(start=0.3, sensors=mcl.IDEAL_SENSORS)
    sim = mcl.SimAxis(p)
    plant = mcl.SimPlant([sim], 0.0005)

    def step() -> None:
        plant.step()
        plant.sense()

    return Channel(
        "SimAxis",
        sim,
        step,
        plant.timestep,
        lambda: (sim.x, sim.v, sim.force),
        resolution=p.resolution,
        lead=p.lead,
        lim_neg=p.lim_neg,
        lim_pos=p.lim_pos,
        ref_edge=p.ref_high,
        stops=(p.stop_neg, p.stop_pos),
        vmax=p.vmax,
        fmax=p.force_limit,
    )


def mujoco_channel() -> Channel:
    scene = gantry.build(
        start={"X": 0.3, "Y": 0.3, "Z": -0.1}, trace_every=0, sensors=mcl.IDEAL_SENSORS
    )
    model, data, plant = scene.model, scene.data, scene.plant
    io = scene.io("X")

    def step() -> None:
        plant.step()
        plant.sense()

    def numeric(name: str) -> float:
        return float(model.numeric(f"gantry/{name}").data[0])

    lo, hi = model.jnt_range[io.joint]
    return Channel(
        "MujocoAxisIO",
        io,
        step,
        plant.timestep,
        lambda: (
            float(data.qpos[io.qpos_adr]),
            float(data.qvel[io.dof]),
            float(data.actuator_force[io.actuator]),
        ),
        resolution=io.resolution,
        lead=numeric("X_lead"),
        lim_neg=numeric("X_lim_neg_trip"),
        lim_pos=numeric("X_lim_pos_trip"),
        ref_edge=numeric("X_ref_edge"),
        stops=(float(lo), float(hi)),
        vmax=numeric("X_vmax"),
        fmax=float(model.actuator_forcerange[io.actuator][1]),
    )


@pytest.fixture(params=["sim", "mujoco"])
def ch(request: pytest.FixtureRequest) -> Iterator[Channel]:
    yield sim_channel() if request.param == "sim" else mujoco_channel()


def counts_track_position(ch: Channel, samples: list[Sample]) -> None:
    for s in samples:
        travel = s.x - ch.origin
        assert abs(s.counts * ch.resolution - travel) <= ch.resolution * (1 + 1e-6), (
            f"{ch.name}: counts {s.counts} at travel {travel * 1e6:.3f} µm"
        )


# ----------------------------------------------------------------------------- tests


def test_is_an_axis_io(ch):
    io = ch.io
    assert isinstance(io, mcl.AxisIO)
    assert io.counts == 0, "the counter reads 0 at power-up"
    ch.run(0.05, ch.volts(0.1))
    assert io.counts > 0


def test_inputs_have_the_declared_types(ch):
    """mcl/io.py declares int counters and bool inputs (a numpy bool is not a bool: it fails
    ``is True`` and JSON serialisation)."""
    io = ch.io
    for name in ("counts", "index_count", "index_seq", "tp_count", "tp_seq"):
        assert isinstance(getattr(io, name), int), name
    for name in ("index", "lim_pos", "lim_neg", "ref", "tp"):
        assert isinstance(getattr(io, name), bool), f"{name} is {type(getattr(io, name))}"


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_counts_follow_the_volts_and_the_physical_position(ch, sign):
    samples = ch.run(0.4, ch.volts(sign * 0.2))
    assert sign * (ch.position - ch.origin) > 0.05, "the axis moved in the commanded direction"
    assert sign * samples[-1].counts > 0.05 / ch.resolution
    # and back the other way (the axis first has to turn round)
    back = ch.run(0.8, ch.volts(-sign * 0.2))
    assert sign * back[-1].counts < 0
    samples += back
    for a, b in itertools.pairwise(samples):
        if b.x - a.x > ch.resolution:
            assert b.counts > a.counts, "counting up while moving in the positive direction"
        elif a.x - b.x > ch.resolution:
            assert b.counts < a.counts, "counting down while moving in the negative direction"
    counts_track_position(ch, samples)


def test_zero_volts_with_the_drive_enabled_holds(ch):
    ch.run(0.3, 0.0)
    x0 = ch.position
    ch.run(1.0, 0.0)
    assert abs(ch.position - x0) < 20e-6, f"drift {(ch.position - x0) * 1e6:.2f} µm/s"
    # at speed, 0 V brakes actively: the axis stops much sooner than by friction alone
    ch.run(0.3, ch.volts(0.2))
    x1 = ch.position
    stop = ch.run(1.0, 0.0)
    held = ch.position - x1
    assert abs(stop[-1].v) < 1e-4
    assert 0.0 < held < 0.005, f"{ch.name}: stopped within {held * 1e3:.3f} mm"


def test_disabled_drive_gives_no_force_and_the_axis_coasts_to_rest(ch):
    ch.run(0.3, ch.volts(0.2))
    v0 = ch.velocity
    assert v0 > 0.15
    x1 = ch.position
    samples = ch.run(2.0, 5.0, enable=False)  # the volts must not matter while disabled
    lag = round(0.01 / ch.timestep)  # the current loop has decayed after 10 ms
    assert max(abs(s.force) for s in samples[lag:]) < 1e-3 * ch.fmax
    coast = ch.position - x1
    assert coast > 0.001, f"{ch.name}: coasted only {coast * 1e3:.3f} mm from {v0:.3f} m/s"
    assert all(b.v <= a.v + 1e-9 for a, b in itertools.pairwise(samples)), (
        "friction only slows it down"
    )
    assert abs(samples[-1].v) < 1e-4, "at rest"
    rest = ch.position
    ch.run(0.5, 0.0, enable=False)
    assert abs(ch.position - rest) < 5e-6
    # 0 V enabled from the same speed stops it in a shorter distance than coasting
    ch.run(0.3, ch.volts(0.2))
    x2 = ch.position
    ch.run(1.0, 0.0)
    assert ch.position - x2 < coast


def index_events(samples: list[Sample], before: Sample) -> list[tuple[Sample, Sample]]:
    """(sample before, sample after) of every step in which index_seq changed."""
    events = []
    prev = before
    for s in samples:
        if s.index_seq != prev.index_seq:
            events.append((prev, s))
        prev = s
    return events


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_index_pulse_once_per_lead_latched_where_the_axis_was(ch, sign):
    ch.run(0.1, ch.volts(sign * 0.033))  # leave the power-up position (it may be on a mark)
    ch.run(0.1, 0.0)
    before = ch.sample()
    travel = 5.5 * ch.lead
    speed = 0.1
    samples = ch.run(travel / speed, ch.volts(sign * speed))
    after = ch.position
    events = index_events(samples, before)
    crossed = abs(math.floor(after / ch.lead) - math.floor(before.x / ch.lead))
    assert len(events) == crossed, f"{len(events)} index events over {crossed} revolutions"
    assert all(b.index_seq - a.index_seq == 1 for a, b in events)
    latched = [b.index_count for _, b in events]
    for c0, c1 in itertools.pairwise(latched):
        assert c1 - c0 == sign * ch.counts_per_rev, "one index per lead"
    for a, b in events:
        place = b.index_count * ch.resolution + ch.origin
        lo, hi = sorted((a.x, b.x))
        assert lo - 2 * ch.resolution <= place <= hi + 2 * ch.resolution, (
            f"latched at {place * 1e3:.4f} mm, the axis moved {a.x * 1e3:.4f} → {b.x * 1e3:.4f}"
        )


def test_index_latched_at_the_same_place_on_every_pass(ch):
    """Back and forth three times over the same marks: the latch of each mark is the same on
    every pass in one direction."""
    speed = 0.1
    forward: dict[int, set[int]] = {}
    backward: dict[int, set[int]] = {}
    for _ in range(3):
        for sign in (1.0, -1.0):
            before = ch.sample()
            samples = ch.run(2.5 * ch.lead / speed, ch.volts(sign * speed))
            ch.run(0.1, 0.0)
            seen = forward if sign > 0 else backward
            for _, b in index_events(samples, before):
                mark = round(b.index_count / ch.counts_per_rev)
                seen.setdefault(mark, set()).add(b.index_count)
    assert len(forward) >= 2 and len(backward) >= 2
    assert all(len(v) == 1 for v in forward.values()), forward
    assert all(len(v) == 1 for v in backward.values()), backward
    for mark in forward.keys() & backward.keys():
        (c_f,) = forward[mark]
        (c_b,) = backward[mark]
        assert abs(c_f - c_b) < 10, "both directions latch the same pulse"


def test_limit_and_reference_switches_follow_the_trip_points(ch):
    speed = 0.25
    lo, hi = ch.stops
    down = ch.run((ch.position - lo) / speed + 0.3, ch.volts(-speed))
    assert ch.position == pytest.approx(lo, abs=1e-3), "reached the negative hard stop"
    up = ch.run((hi - lo) / speed + 0.3, ch.volts(speed))
    assert ch.position == pytest.approx(hi, abs=1e-3), "reached the positive hard stop"
    margin = 2 * ch.resolution
    samples = down + up
    checked: dict[str, set[bool]] = {"lim_neg": set(), "lim_pos": set(), "ref": set()}
    for s in samples:
        for name, level, trip, below in (
            ("lim_neg", s.lim_neg, ch.lim_neg, True),
            ("lim_pos", s.lim_pos, ch.lim_pos, False),
            ("ref", s.ref, ch.ref_edge, True),
        ):
            if abs(s.x - trip) <= margin:
                continue
            expected = s.x < trip if below else s.x > trip
            assert level == expected, f"{name} {level} at {s.x * 1e3:.4f} mm (trip {trip})"
            checked[name].add(level)
    assert all(levels == {True, False} for levels in checked.values()), checked


def test_any_command_up_to_ten_volts_keeps_the_plant_finite(ch):
    rng = random.Random(7)
    samples = ch.run(1.5, 10.0)  # full speed into the positive hard stop
    samples += ch.run(3.0, -10.0)  # and into the negative one
    for _ in range(60):
        volts = rng.choice([-10.0, 10.0, rng.uniform(-10.0, 10.0)])
        samples += ch.run(rng.uniform(0.005, 0.1), volts, enable=rng.random() > 0.2)
    lo, hi = ch.stops
    reach = 2.5e-3 * ch.vmax  # a stop takes at most 2.5 mm per m/s of impact (test_models)
    for s in samples:
        assert math.isfinite(s.x) and math.isfinite(s.v) and math.isfinite(s.force)
        assert lo - reach < s.x < hi + reach
        assert abs(s.force) <= ch.fmax * (1 + 1e-9)
    counts_track_position(ch, samples)

"""Incremental encoder with index latch."""

from __future__ import annotations

import pytest

from mcl.encoder import IncrementalEncoder

RES = 1e-6
"""1 µm per count."""
N = 10000
"""Counts per revolution (10 mm lead)."""


def encoder(origin: float = 0.0, width: int = 1) -> IncrementalEncoder:
    return IncrementalEncoder(RES, N, origin=origin, index_width=width)


def sweep(enc: IncrementalEncoder, start: float, end: float, step: float) -> list[int]:
    """Move from start to end in steps; return the latched counts seen (one per new edge)."""
    latched = []
    seq = enc.index_seq
    n = max(1, round(abs(end - start) / step))
    for i in range(1, n + 1):
        enc.update(start + (end - start) * i / n)
        if enc.index_seq != seq:
            assert enc.index_seq == seq + 1, "one edge per step at most"
            seq = enc.index_seq
            latched.append(enc.index_count)
    return latched


def test_counts_are_quantized_positions_relative_to_the_origin():
    enc = encoder(origin=0.2)
    assert enc.counts == 0
    enc.update(0.2005)
    assert enc.counts == 500
    enc.update(0.2000004)
    assert enc.counts == 0
    enc.update(0.2000016)
    assert enc.counts == 1
    enc.update(0.1995)
    assert enc.counts == -500
    enc.update(0.1999995)
    assert enc.counts == -1
    enc.update(0.0)
    assert enc.counts == -200000


def test_exact_multiples_of_the_resolution_keep_their_count():
    enc = encoder()
    for k in (1, 3, 7, 123, 9999, 123457):
        enc.update(k * RES)
        assert enc.counts == k
        enc.update(-k * RES)
        assert enc.counts == -k


def test_index_level_once_per_revolution():
    enc = encoder(origin=0.0, width=4)
    rising = 0
    high_counts = []
    prev = enc.index
    for i in range(1, 5 * N + 1):
        enc.update(i * RES + 0.3 * RES)
        if enc.index and not prev:
            rising += 1
        if enc.index:
            high_counts.append(enc.counts)
        prev = enc.index
    assert rising == 5
    assert len(high_counts) == 5 * 4
    assert all(c % N < 4 for c in high_counts)


@pytest.mark.parametrize("step_um", [0.3, 1.0, 7.0, 33.3, 250.0, 999.0, 4321.0])
def test_index_latch_forward_is_exact_for_any_step(step_um):
    """Going forward the index edge is latched at the first count of the pulse window."""
    enc = encoder(origin=0.2003, width=4)
    latched = sweep(enc, 0.2003, 0.2003 + 0.035, step_um * RES)
    # the index windows start at absolute counts k·N; relative to the origin: k·N − 200300
    assert latched == [-300 + N, -300 + 2 * N, -300 + 3 * N]
    assert enc.index_seq == 3


@pytest.mark.parametrize("step_um", [0.3, 1.0, 7.0, 33.3, 250.0, 999.0, 4321.0])
def test_index_latch_backward_is_exact_for_any_step(step_um):
    """Going backward the edge is latched at the last count of the window."""
    enc = encoder(origin=0.2003, width=4)
    enc.update(0.2003 + 0.035)
    seq = enc.index_seq
    latched = sweep(enc, 0.2003 + 0.035, 0.2003, step_um * RES)
    assert latched == [-300 + 3 * N + 3, -300 + 2 * N + 3, -300 + N + 3]
    assert enc.index_seq == seq + 3


def test_same_count_on_every_pass_from_the_same_direction():
    enc = encoder(origin=0.0, width=4)
    forward, backward = set(), set()
    for step_um in (0.7, 3.0, 11.0, 180.0):
        for _ in range(3):
            forward.update(sweep(enc, 0.0075, 0.0125, step_um * RES))
            backward.update(sweep(enc, 0.0125, 0.0075, step_um * RES))
    assert forward == {10000}
    assert backward == {10003}


def test_index_sequence_counts_every_edge():
    enc = encoder()
    assert enc.index_seq == 0
    sweep(enc, 0.0, 0.0455, 5 * RES)  # 4 windows passed going forward
    assert enc.index_seq == 4
    sweep(enc, 0.0455, 0.0205, 5 * RES)  # the windows at 40 and 30 mm
    assert enc.index_seq == 4 + 2
    # standing still or moving within one revolution without crossing a window: no new edge
    sweep(enc, 0.0205, 0.0295, 5 * RES)
    assert enc.index_seq == 6


def test_reversing_inside_the_window_does_not_relatch():
    enc = encoder(width=4)
    enc.update(0.0099995)
    seq = enc.index_seq
    enc.update(0.0100015)  # enters the window 10000..10003 from below
    assert (enc.index_seq, enc.index_count, enc.index) == (seq + 1, 10000, True)
    enc.update(0.0100005)  # back within the window: no edge
    enc.update(0.0100025)
    assert enc.index_seq == seq + 1


def test_invalid_construction():
    with pytest.raises(ValueError):
        IncrementalEncoder(0.0, N)
    with pytest.raises(ValueError):
        IncrementalEncoder(RES, N, index_width=N)

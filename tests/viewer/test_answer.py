"""A click is answered at once: the PLC scan after the request takes it, and the snapshot after
that scan is published without waiting for the next publishing time."""

from __future__ import annotations

from plc.operator.hmi import Move
from viewer.sim.session import Session, _Paced


class FrozenClock:
    """A wall clock that stands still: nothing is ever due by time alone [s]."""

    def __call__(self) -> float:
        return 100.0


def powered_gantry() -> Session:
    session = Session("gantry", clock=FrozenClock())
    session.requests("X").set_power(True)
    session.advance(50)
    assert session.snapshot.axes["X"].powered
    return session


def test_the_next_scan_takes_a_move_and_its_snapshot_is_published_at_once() -> None:
    session = powered_gantry()
    paced = _Paced(session)  # the simulation thread's view of the session
    paced.run_cycles(1)
    paced.ran()  # the power request's answer
    shown = session.snapshot
    paced.run_cycles(1)
    paced.ran()
    assert session.snapshot is shown  # nothing asked for, the clock stands: not published

    session.requests("X").move(Move("relative", 5.0, 100.0, 1000.0))
    paced.run_cycles(1)  # one PLC scan
    paced.ran()
    assert session.snapshot is not shown
    assert session.snapshot.axes["X"].state == "DiscreteMotion"
    assert session.scene.axes["X"].state.name == "DiscreteMotion"  # taken by that very scan
    shown = session.snapshot
    paced.run_cycles(1)
    paced.ran()
    assert session.snapshot is shown  # answered once, then the publishing rate again


def test_a_jog_renewal_is_no_request_to_answer() -> None:
    session = powered_gantry()
    paced = _Paced(session)
    paced.ran()
    shown = session.snapshot
    session.requests("X", answer=False).jog(1)
    paced.run_cycles(1)
    paced.ran()
    assert session.snapshot is shown

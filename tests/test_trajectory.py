"""Trajectory and Event (lcs_exact.phases.trajectory): immutable results with a status, x(t+) at event
times, certified samples, the computed extent of a partial run."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest

import lcs_exact as L
from lcs_exact.phases.trajectory import Status

OSC = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])  # x'' = -x + u, a stop at 0


def test_trajectory_is_immutable_with_a_status():
    tr = L.simulate(OSC, [1, 0], 4)
    assert tr.status is Status.COMPLETE and not tr.partial and tr.certified
    with pytest.raises(AttributeError, match="immutable"):
        tr.events = ()
    assert isinstance(tr.events, tuple) and isinstance(tr.assumptions, tuple)
    with pytest.raises(Exception):
        tr.events[0].time = 0  # frozen dataclass


def test_state_at_an_event_is_the_right_limit_and_samples_agree():
    """From (1, 0): x = (cos t, -sin t) until pi/2, where the stop takes the velocity (-1 -> 0)."""
    tr = L.simulate(OSC, [1, 0], 4)
    (e,) = tr.events
    x = tr.state(e.time)
    assert x[0].rational() == 0 and x[1].rational() == 0
    ts = [Fraction(k, 4) for k in range(17)]
    rows = tr.sample(ts, 25)
    with mp.workdps(50):
        for t, row in zip(ts, rows):
            tm = mp.mpf(t.numerator) / t.denominator
            want = [mp.cos(tm), -mp.sin(tm)] if tm < mp.pi / 2 else [0, 0]
            for b, w in zip(row, want):
                assert abs(mp.mpf(b.mid().str(40, radius=False)) - w) < mp.mpf(10) ** -25
                assert b.rad() < mp.mpf(10) ** -25


def test_partial_run_knows_how_far_it_got():
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]), [1, 0], 4, max_events=0)
    tr = err.value.trajectory
    assert tr.partial and tr.status is Status.EVENT_LIMIT and tr.events == ()
    assert tr.t_last.closed_form is not None and str(tr.t_last.closed_form) == "pi/2"
    assert "PARTIAL" in repr(tr)


def test_a_partial_runs_repr_says_where_it_is_known():
    """x1' = -x2, x2' = 0 from (1, 1), stop y = x1: x1 = 1 - t reaches the stop at t = 1.  With
    max_events = 0 the run stops there: it is known on [0, 1], not on the [0, 3] asked for (the
    repr said "on [0, 3]"); a complete run says its horizon only."""
    lcs = L.LCS([[0, -1], [0, 0]], [[1], [0]], [[1, 0]], [[0]])
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(lcs, [1, 1], 3, max_events=0)
    tr = err.value.trajectory
    assert tr.t_last.rational() == 1 and tr.t_end.rational() == 3
    for text in (repr(tr), str(tr)):
        assert text.startswith("<Trajectory known on [0, 1] of [0, 3] (PARTIAL, event limit): 0 events")
        assert "on [0, 3]" not in text and "max_events = 0 reached" in text
    done = L.simulate(lcs, [1, 1], 3)
    assert repr(done).startswith("<Trajectory on [0, 3]: 1 events, certified>") and "known" not in repr(done)
    # an accumulation stopped at once (zeno="stop"): known up to its last phase's end, the third impact
    ball = L.examples.bouncing_ball()
    with pytest.raises(L.ZenoDetected) as err:
        L.simulate(ball, ball.embed([1, 0]), 10, zeno="stop")
    tr = err.value.trajectory
    assert repr(tr).startswith(f"<Trajectory known on [0, {tr.events[-1].time.label()}] of [0, 10] (PARTIAL, "
                               "accumulation of events)")


def test_u_and_y_at_an_event_time_are_the_right_limits_as_the_state():
    """x1' = -x2 + u, x2' = 0 from (1, 1), stop y = x1: x1 = 1 - t, u = 0 until t = 1; then the
    stop holds x1 = 0 (mode {0}: y' = -x2 + u = 0, u = x2 = 1).  At t = 1 the state is x(1+) =
    (0, 1) and u, y are u(1+) = 1, y(1+) = 0, in one row of to_numpy (u was u(1-) = 0: a row
    mixed x(1+) with u(1-))."""
    lcs = L.LCS([[0, -1], [0, 0]], [[1], [0]], [[1, 0]], [[0]])
    tr = L.simulate(lcs, [1, 1], 3)
    assert len(tr.events) == 1 and tr.events[0].time.rational() == 1
    assert [str(c) for c in tr.state(1).rational().entries()] == ["0", "1"]
    assert [str(c) for c in tr.u(1).rational().entries()] == ["1"]
    assert [str(c) for c in tr.y(1).rational().entries()] == ["0"]
    assert [str(c) for c in tr.u(Fraction(999, 1000)).rational().entries()] == ["0"]  # before: free
    assert tr.to_numpy([Fraction(1, 2), 1, 2], u=True, y=True).tolist() == [[0.5, 1, 0, 0.5], [0, 1, 1, 0], [0, 1, 1, 0]]
    assert tr.undetermined(1) == frozenset()

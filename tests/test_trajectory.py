"""Trajectory and Event (lcs_exact.trajectory): immutable results with a status, x(t+) at event
times, certified samples, the computed extent of a partial run."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest

import lcs_exact as L
from lcs_exact.trajectory import Status

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

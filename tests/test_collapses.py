"""Inelastic collapse: two balls on a floor whose impacts ball-floor, ball-ball, ... accumulate
(lcs_exact.accumulations.collapses), crossed.  Each scene is checked against an event-driven run written
here in mpmath: both balls fall with g, so the floor gap is h0 + v t - g t^2 / 2 and the balls' gap
h1 + w t (w their relative speed); a floor impact sets v -> -e v, a ball-ball impact w -> -e w with
the impulse P = -(1 + e) w / (1/m1 + 1/m2) taken from ball 1's speed."""
from __future__ import annotations

import importlib
import json
from fractions import Fraction as F

import mpmath as mp
import pytest
from flint import fmpq, fmpq_mat

import lcs_exact as L
from lcs_exact.dynamics import bounces, collapsecycles, collapses

from helpers import num as mid


def two_balls(m2, g, e, radius, q1, q2, *, name=None):
    """Ball 1 (mass 1) above a floor y_0 = q1 >= 0, ball 2 (mass m2) above it, y_1 = q2 - q1 - 2 radius
    >= 0, gravity g, restitution e at both contacts (Siconos' TwoBouncingBalls: m2 = 2, g = 9.81,
    e = 0.95, radius 0.1, q = (0.1, 0.301))."""
    lcs = L.models.mechanical([[1, 0], [0, m2]], [[0, 0], [0, 0]], [[1, 0], [-1, 1]], force=[-g, -m2 * g],
                              gap=[0, -2 * radius], restitution=e, name=name)
    return lcs, lcs.embed([q1, q2, 0, 0])


def reference(m2, g, e, radius, q1, q2, tol=mp.mpf(10) ** -75):
    """The impacts of the two balls from rest, event by event (the module docstring), until a flight
    is shorter than tol: [(time, contact, (h0, v, h1, w) after)] and the accumulation time."""
    def q(x):
        x = F(x)
        return mp.mpf(x.numerator) / x.denominator

    g, e, m2 = q(g), q(e), q(m2)
    h0, v, h1, w = q(q1), mp.mpf(0), q(q2 - q1 - 2 * radius), mp.mpf(0)
    t, last, out = mp.mpf(0), None, []
    while True:
        s0 = 2 * v / g if last == 0 else (v + mp.sqrt(v * v + 2 * g * h0)) / g
        s1 = mp.inf if w >= 0 or last == 1 else -h1 / w
        s, c = (s0, 0) if s0 < s1 else (s1, 1)
        h0, v, h1, t = h0 + v * s - g * s * s / 2, v - g * s, h1 + w * s, t + s
        if c == 0:
            h0, dv = mp.mpf(0), -(1 + e) * v
            v, w = v + dv, w - dv
        else:
            P = -(1 + e) * w / (1 + 1 / m2)
            h1, v, w = mp.mpf(0), v - P, -e * w
        out.append((t, c, (h0, v, h1, w)))
        last = c
        if s < tol:
            return out, t


FAST = dict(m2=2, g=F(10), e=F(1, 2), radius=F(1, 2), q1=F(1, 2), q2=F(1, 2) + 1 + F(1, 10))


@pytest.fixture(scope="module")
def fast():
    lcs, x0 = two_balls(**FAST)
    with mp.workdps(80):
        ref = reference(**FAST)
    return lcs, L.simulate(lcs, x0, 3), ref


def test_two_balls_collapse_is_proven_and_crossed(fast):
    """Ball 1 lands at sqrt(1/10), then the impacts alternate floor, balls, floor, ... and accumulate;
    the run proves the collapse (a pattern of two contacts whose shape converges), crosses T* and
    rests: q1 = 0, q2 = 2 r exactly, the floor carrying (1 + 2) g and the balls' contact 2 g."""
    lcs, tr, (events, t_star) = fast
    assert tr.certified and not tr.partial and len(tr.accumulations) == 1
    acc = tr.accumulations[0]
    assert isinstance(acc.cycle, collapses.CollapseWindow) and acc.cycle.proof.cycle.P == (0, 1)
    assert acc.ratio is None and acc.first_event == len(tr.events) - 1
    with mp.workdps(80):
        for ev, (t, c, _) in zip(tr.events, events):
            assert ev.triggers == (f"y_{c}",) and abs(mid(ev.time, 35) - t) < mp.mpf(10) ** -33
        assert abs(mid(acc.time, 45) - t_star) < mp.mpf(10) ** -43
        k0 = len(tr.events)
        for k in (0, 1, 2, 25, 200):  # the impacts the window implies, one by one
            assert abs(mid(acc.event_time(k), 30) - events[k0 + k][0]) < mp.mpf(10) ** -28
    assert acc.state.known_rational() == fmpq_mat([[0], [1], [0], [0], [1]])
    assert tr.state(3).known_rational() == fmpq_mat([[0], [1], [0], [0], [1]])
    assert tr.u(3).known_rational() == fmpq_mat([[30], [20]]) and tr.phases[-1].mode == frozenset({0, 1})
    assert tr.events[0].time.closed_form is not None and abs(mid(tr.events[0].time, 30) - mp.sqrt(mp.mpf(1) / 10)) < 1e-29


def test_states_inside_the_collapse_window(fast):
    """Between implied impacts k and k + 1 the state is the flight of the reference: q1 = h0 + v s -
    g s^2 / 2, q2 = q1 + 2 r + h1 + w s (s the time since impact k)."""
    lcs, tr, (events, _) = fast
    k0 = len(tr.events)
    with mp.workdps(80):
        for k in (3, 40):
            (ta, _, (h0, v, h1, w)), (tb, _, _) = events[k0 + k - 1], events[k0 + k]
            t = F(mp.nstr((ta + tb) / 2, 60))
            s = mp.mpf(t.numerator) / t.denominator - ta
            q1 = h0 + v * s - 5 * s * s
            x = tr.state(t)
            assert abs(mid(x[0], 30) - q1) < mp.mpf(10) ** -30
            assert abs(mid(x[1], 30) - (q1 + 1 + h1 + w * s)) < mp.mpf(10) ** -30
            assert abs(mid(x[2], 30) - (v - 10 * s)) < mp.mpf(10) ** -28


def test_zeno_stop_encloses_the_collapse(fast):
    """zeno='stop' stops at the proven collapse with an enclosure narrower than the run's digits."""
    lcs, tr, (_, t_star) = fast
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, two_balls(**FAST)[1], 3, zeno="stop")
    lo, hi = info.value.lower, info.value.upper
    with mp.workdps(60):
        assert mp.mpf(int(lo.p)) / int(lo.q) <= t_star <= mp.mpf(int(hi.p)) / int(hi.q)
    assert hi - lo < fmpq(1, 10 ** 30) and "taking turns" in str(info.value)


def test_fixtures_list_the_collapse_impacts(fast, tmp_path):
    """A fixture of the run lists the implied impacts (certified balls of the window's iteration) up
    to float resolution of T*, and reads them back."""
    lcs, tr, (events, _) = fast
    path = tmp_path / "two.json"
    path.write_text(json.dumps(tr.to_fixture(digits=20)))
    implied = L.read_fixture(path).accumulations[0].implied
    assert implied["first_event"] == len(tr.events) - 1 and len(implied["times"]) > 20
    k0 = len(tr.events)
    assert all(abs(float(t) - float(events[k0 + k][0])) < 1e-15 for k, t in enumerate(implied["times"][:20]))


def test_the_proof_needs_constant_gap_accelerations(fast):
    """A spring between the balls makes the gaps' accelerations depend on the gaps: no exact scaling,
    so no collapse cycle (the run would go on event by event); a pattern the events do not repeat
    is none either."""
    lcs, tr, _ = fast
    assert collapsecycles.collapse_cycle(lcs, tr.events) is not None
    sprung = L.models.mechanical([[1, 0], [0, 2]], [[1, -1], [-1, 1]], [[1, 0], [-1, 1]], force=[-10, -20],
                                 gap=[0, -1], restitution="1/2")
    assert collapsecycles.collapse_cycle(sprung, tr.events) is None
    assert collapsecycles.collapse_cycle(lcs, tr.events[:2]) is None
    assert bounces.bounce_cycle(lcs, tr.events) is None


@pytest.mark.slow
def test_siconos_two_bouncing_balls_run_to_the_horizon():
    """Siconos' TwoBouncingBalls (m = 1 and 2, R = 0.1, e = 19/20, T = 3): hundreds of impacts
    alternate floor and balls, ever closer; the collapse is proven and crossed (it stopped with
    ZenoDetected at t = 2.5315 before), and the balls rest to t = 3.  Every listed impact, T*
    and implied impacts against the reference run from t = 0."""
    spec = dict(m2=2, g=F(981, 100), e=F(19, 20), radius=F(1, 10), q1=F(1, 10), q2=F(3, 10) + F(1, 1000))
    lcs, x0 = two_balls(**spec, name="TwoBouncingBalls")
    tr = L.simulate(lcs, x0, 3, closed_forms=False)
    assert tr.certified and not tr.partial and len(tr.accumulations) == 1
    acc = tr.accumulations[0]
    with mp.workdps(200):  # the early impacts amplify rounding: at 80 digits event 686 is off by 7e-29
        events, t_star = reference(**spec)
        assert len(events) > len(tr.events) > 300
        for ev, (t, c, _) in zip(tr.events, events):
            assert ev.triggers == (f"y_{c}",) and abs(mid(ev.time, 30) - t) < mp.mpf(10) ** -28
        assert abs(mid(acc.time, 45) - t_star) < mp.mpf(10) ** -43
        assert 2.5315096 < float(acc.time.ball(20)) < 2.5315097
        k0 = len(tr.events)
        for k in (0, 1, 1000):
            assert abs(mid(acc.event_time(k), 30) - events[k0 + k][0]) < mp.mpf(10) ** -28
    R = fmpq(1, 10)
    assert tr.state(3).known_rational() == fmpq_mat([[0], [2 * R], [0], [0], [1]])
    assert tr.u(3).known_rational() == fmpq_mat([[fmpq(2943, 100)], [fmpq(1962, 100)]])


@pytest.mark.slow
def test_without_a_proof_the_run_stops_as_a_suspected_accumulation(monkeypatch):
    """With the collapse proof out of the way (disabled here) TwoBouncingBalls shows the fallback:
    when the impacts are ~4e-21 apart a sign cannot be certified at max_prec; the run stops with
    ZenoDetected (suspected: the phases shrink pair by pair), not UnresolvedSign, its lower bound
    the last event time, keeping its 2316 certified events."""
    monkeypatch.setattr(importlib.import_module("lcs_exact.dynamics.simulate"), "collapse_cycle", lambda lcs, events: None)
    spec = dict(m2=2, g=F(981, 100), e=F(19, 20), radius=F(1, 10), q1=F(1, 10), q2=F(3, 10) + F(1, 1000))
    lcs, x0 = two_balls(**spec)
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, x0, 3, max_events=5000, closed_forms=False)
    events = info.value.trajectory.events
    assert {e.triggers for e in events[-4:]} == {("y_0",), ("y_1",)}
    with mp.workdps(40):
        lower, last = info.value.lower, mid(events[-1].time, 30)
        gap = last - mp.mpf(int(lower.p)) / int(lower.q)
        assert info.value.upper is None and -mp.mpf(10) ** -30 <= gap < mp.mpf(10) ** -24
    assert "suspected" in str(info.value) and 2.5315096 < float(lower) < 2.5315097


def test_a_collapse_beside_a_falling_ball(fast):
    """A third ball (mass 1) falls from 10 above ball 2: the background moves while balls 1 and 2
    collapse, and its gap is bounded over the whole window.  The collapse is the two-ball one (same
    impacts, same T*); at T* ball 3 is in free fall from rest (q3 = q3(0) - g T*^2 / 2, v3 = -g T*),
    and it lands on the stack (q3 = 2) at sqrt(2 (q3(0) - 2) / g) = sqrt(53/25)."""
    _, two, (events, t_star) = fast
    q = [FAST["q1"], FAST["q2"], FAST["q2"] + 1 + 10]
    three = L.models.mechanical([[1, 0, 0], [0, 2, 0], [0, 0, 1]], [[0] * 3] * 3, [[1, 0, 0], [-1, 1, 0], [0, -1, 1]],
                                force=[-10, -20, -10], gap=[0, -1, -1], restitution="1/2")
    tr = L.simulate(three, three.embed(q + [0, 0, 0]), 2)
    assert tr.certified and len(tr.accumulations) == 1
    acc = tr.accumulations[0]
    assert acc.cycle.proof.cycle.moving and acc.cycle.proof.cycle.P == (0, 1)
    assert [e.triggers for e in tr.events[:len(two.events)]] == [e.triggers for e in two.events]
    with mp.workdps(80):
        assert abs(mid(acc.time, 45) - t_star) < mp.mpf(10) ** -43
        q3 = mp.mpf(int(q[2].numerator)) / int(q[2].denominator)
        x = [mid(c, 35) for c in acc.state]
        assert abs(x[2] - (q3 - 5 * t_star ** 2)) < mp.mpf(10) ** -33 and abs(x[5] + 10 * t_star) < mp.mpf(10) ** -33
        assert abs(x[0]) < mp.mpf(10) ** -33 and abs(x[1] - 1) < mp.mpf(10) ** -33
    landing = tr.events[len(two.events)]  # after T*, a sum with T*: certified digits, no closed form
    with mp.workdps(60):
        assert landing.triggers == ("y_2",) and abs(mid(landing.time, 40) - mp.sqrt(mp.mpf(53) / 25)) < mp.mpf(10) ** -38


def test_a_collapse_forming_after_other_impacts_is_waited_for(fast):
    """turns_suspected: the last 24 events single impacts of two to four contacts in one mode (the
    run waits for their pattern instead of stopping at a suspected accumulation), whatever came
    before them - in Siconos' column of beads the upper beads collide among themselves first."""
    import dataclasses
    _, tr, _ = fast
    ev = tr.events[-1]

    def impact(b):
        return dataclasses.replace(ev, modes=(frozenset({b}),), triggers=(f"y_{b}",))

    before = [impact(b) for b in (5, 7, 6, 8, 9, 6, 7)] * 4
    turns = [impact(b) for b in (0, 1) * 12]
    assert collapsecycles.turns_suspected(before + turns) is True
    assert collapsecycles.turns_suspected(before + turns[:20]) is False  # the last 24 hold six contacts
    assert collapsecycles.turns_suspected(turns[1:]) is False  # too few
    assert collapsecycles.turns_suspected(before + [impact(b) for b in (0, 1, 2, 3, 4) * 5]) is False

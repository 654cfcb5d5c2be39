"""Accumulations of Newton impacts that no symmetry explains (lcs_exact.accumulations.bounces), crossed: each scene
is checked against a derivation written here (flights of a mass on a spring between impacts have
closed forms: the return speed equals the launch speed, so v' = e v and the flight lasts
(2/w) atan(v w / g))."""
from __future__ import annotations

import json
from fractions import Fraction as F

import mpmath as mp
import pytest
from flint import fmpq, fmpq_mat

import lcs_exact as L
from lcs_exact.dynamics import bounces
from lcs_exact.examples import ball_on_spring

from helpers import num as mid


def linear_oscillator_ed():
    """Siconos' LinearOscillatorED (examples/mechanics/BouncingBallEventDriven): a ball of mass 1e-3
    and radius 0.1 on springs k = 100 in x and y, gravity in x, a floor x >= 0 with e = 9/10,
    dropped from x = 1 with y = 0.001; its equilibrium 9.81e-5 below the floor."""
    m, R, g = F(1, 1000), F(1, 10), F(981, 100)
    M = [[m, 0, 0], [0, m, 0], [0, 0, F(3, 5) * m * R * R]]
    K = [[100, 0, 0], [0, 100, 0], [0, 0, 0]]
    lcs = L.models.mechanical(M, K, [[1, 0, 0]], force=[-m * g, 0, 0], restitution=F(9, 10),
                              name="LinearOscillatorED")
    return lcs, lcs.embed([1, F(1, 1000), 0, 0, 0, 0])


def spring_impacts(w, g, e, q0, count):
    """Impact times of x'' = -w^2 x - g from x = q0 at rest onto x >= 0 with restitution e, and T*:
    the first impact where cos(w t) = d / (1 + d), d = g / w^2, at speed v1 = w (1 + d) sin(w t1);
    then v_{m+1} = e v_m and each flight lasts (2/w) atan(v_m w / g)."""
    d = g / w ** 2
    t1 = mp.acos(d / (1 + d)) / w
    v1 = w * (1 + d) * mp.sin(w * t1)
    times, t, v = [t1], t1, v1
    for _ in range(count):
        v = e * v
        t = t + 2 / w * mp.atan(v * w / g)
        times.append(t)
    t_star = t1 + mp.nsum(lambda j: 2 / w * mp.atan(e ** j * v1 * w / g), [1, mp.inf])
    return times, t_star


@pytest.fixture(scope="module")
def oscillator():
    lcs, x0 = linear_oscillator_ed()
    return lcs, L.simulate(lcs, x0, F(17, 2))


def test_linear_oscillator_ed_runs_to_its_horizon_through_the_accumulation(oscillator):
    """Siconos' LinearOscillatorED stopped at t = 0.862 (ZenoDetected, 107 impacts, no law: the spring
    breaks the symmetry); now T* is proven, crossed, and the ball rests on the floor to t = 8.5 while
    it oscillates in y.  Impacts, T*, the implied impacts and the limit state against the derivation
    (x and y decouple: K is diagonal, the floor acts on x only)."""
    lcs, tr = oscillator
    assert tr.certified and not tr.partial and len(tr.accumulations) == 1
    w = mp.sqrt(100000)
    with mp.workdps(50):
        times, t_star = spring_impacts(w, mp.mpf(981) / 100, mp.mpf(9) / 10, 1, 2000)
        for i in (0, 1, 50, len(tr.events) - 1):
            assert abs(mid(tr.events[i].time, 30) - times[i]) < mp.mpf(10) ** -28
        acc = tr.accumulations[0]
        assert abs(mid(acc.time, 45) - t_star) < mp.mpf(10) ** -40
        k0 = len(tr.events)
        for k in (0, 1, 10, 100):
            assert abs(mid(acc.event_time(k), 30) - times[k0 + k]) < mp.mpf(10) ** -28
        # the limit: on the floor at rest (x = x' = 0 proven), the wheel never turned (exact zeros),
        # y = 0.001 cos(w T*), y' = -0.001 w sin(w T*)
        x = acc.state
        for i in (0, 2, 3, 5):
            assert x.sign_of_form(fmpq_mat([[int(j == i) for j in range(7)]])) == 0
        assert abs(mid(x[1], 30) - mp.mpf("0.001") * mp.cos(w * t_star)) < mp.mpf(10) ** -32
        assert abs(mid(x[4], 30) + mp.mpf("0.001") * w * mp.sin(w * t_star)) < mp.mpf(10) ** -28
        end = tr.state(F(17, 2))
        assert abs(mid(end[1], 30) - mp.mpf("0.001") * mp.cos(w * mp.mpf(17) / 2)) < mp.mpf(10) ** -32
        assert abs(mid(tr.u(F(17, 2))[0], 30) - mp.mpf(981) / 100000) < mp.mpf(10) ** -35  # it carries m g
    assert tr.phases[-1].mode == frozenset({0})


def test_inside_the_window_states_follow_the_flights(oscillator):
    """x(t) between two implied impacts: the flight x = -d (1 - cos w s) + (v/w) sin w s after the
    impact at t_m with speed e^(m+1) v1 (the derivation above)."""
    lcs, tr = oscillator
    acc = tr.accumulations[0]
    k0 = len(tr.events)
    w, g, e = mp.sqrt(100000), mp.mpf(981) / 100, mp.mpf(9) / 10
    with mp.workdps(50):
        times, _ = spring_impacts(w, g, e, 1, 400)
        d = g / w ** 2
        v1 = w * (1 + d) * mp.sin(w * times[0])
        m = k0 + 5  # the flight after implied impact 4, its midpoint as a rational
        t = F(str(mp.nstr((times[m - 1] + times[m]) / 2, 30)))
        s = mp.mpf(t.numerator) / t.denominator - times[m - 1]
        v = e ** m * v1  # launched by impact m - 1 (impact i sends the ball up at e^(i+1) v1)
        want = -d * (1 - mp.cos(w * s)) + v / w * mp.sin(w * s)
        assert abs(mid(tr.state(t)[0], 25) - want) < mp.mpf(10) ** -30
        X = tr.to_numpy([float(times[m - 1] + times[m]) / 2, float(acc.time) - 1e-6])
    assert X.shape == (2, 7) and abs(X[0, 0] - float(want)) < 1e-15 and X[1, 0] >= 0


def test_a_ball_on_a_soft_spring_and_zeno_stop():
    """x'' = -x - 10 from 1 onto x >= 0, e = 1/2 (examples.ball_on_spring(k=1, g=10, rest=0)): T* from
    the derivation; with zeno="stop" the run stops at T* with its certified enclosure."""
    lcs = ball_on_spring(k=1, mass=1, g=10, e="1/2", rest=0)
    with mp.workdps(50):
        times, t_star = spring_impacts(mp.mpf(1), mp.mpf(10), mp.mpf(1) / 2, 1, 10)
    tr = L.simulate(lcs, lcs.embed([1, 0]), 3)
    acc = tr.accumulations[0]
    with mp.workdps(50):
        assert abs(mid(acc.time) - t_star) < mp.mpf(10) ** -35
    assert acc.state.known_rational() == fmpq_mat([[0], [0], [1]])
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, lcs.embed([1, 0]), 3, zeno="stop")
    lo, hi = info.value.lower, info.value.upper
    with mp.workdps(50):
        assert mp.mpf(int(lo.p)) / int(lo.q) <= t_star <= mp.mpf(int(hi.p)) / int(hi.q)
        assert hi - lo < fmpq(1, 10 ** 30)


def test_the_proof_is_refused_where_it_does_not_hold():
    """No proof from a state whose flights are long beside the spring (the series of the blown-up
    flight would not converge fast): the run goes on event by event."""
    lcs = ball_on_spring(k=100, mass=1, g=1, e="9/10", rest=0)   # w = 10, flights of ~ 0.3 s
    tr = L.simulate(lcs, lcs.embed([1, 0]), F(3, 2))
    cyc = bounces.bounce_cycle(lcs, tr.events)
    assert cyc is not None and cyc.b == 0 and cyc.e == fmpq(9, 10)
    assert bounces.prove_bounces(cyc, tr.events) is None


def test_a_ball_on_a_spring_bouncing_on_a_resting_ball():
    """Ball 1 rests on the floor (its contact stays closed: the flights are in mode {0}); ball 2 on a
    spring, q2'' = -q2 - 10 + u_1, dropped from 1 onto it, e = 1/2.  Each impact closes both contacts
    and pushes both (W^-1 e_1 > 0): ball 1 stays at rest, ball 2 leaves at e times its speed, so the
    impacts are those of x'' = -x - 10 on a floor (spring_impacts) and accumulate at T*; then both
    rest, the floor carrying 20 and the balls' contact 10, exactly."""
    lcs = L.models.mechanical([[1, 0], [0, 1]], [[0, 0], [0, 1]], [[1, 0], [-1, 1]], force=[-10, -10],
                              restitution="1/2")
    tr = L.simulate(lcs, lcs.embed([0, 1, 0, 0]), 3)
    assert tr.certified and len(tr.accumulations) == 1
    assert all(e.mode_before == frozenset({0}) and e.modes == (frozenset({0, 1}),) for e in tr.events[1:])
    acc = tr.accumulations[0]
    with mp.workdps(50):
        times, t_star = spring_impacts(mp.mpf(1), mp.mpf(10), mp.mpf(1) / 2, 1, 40)
        assert abs(mid(acc.time) - t_star) < mp.mpf(10) ** -38
        assert abs(mid(acc.event_time(0), 30) - times[len(tr.events)]) < mp.mpf(10) ** -28
    assert acc.state.known_rational() == fmpq_mat([[0], [0], [0], [0], [1]])
    assert tr.u(3).known_rational() == fmpq_mat([[20], [10]]) and tr.phases[-1].mode == frozenset({0, 1})
    # inside the window, between implied impacts 2 and 3: ball 2 flies (q2 = -10 (1 - cos s) +
    # v sin s, launched at v = e^(k+1) v1), ball 1 rests: the floor carries its weight 10, u_1 = 0
    with mp.workdps(50):
        k = len(tr.events) + 2
        t = F(str(mp.nstr((times[k] + times[k + 1]) / 2, 30)))
        s_ = mp.mpf(t.numerator) / t.denominator - times[k]
        v = mp.mpf(1) / 2 ** (k + 1) * mp.sqrt(21)
        u, y = tr.u(t), tr.y(t)
        assert abs(mid(u[0], 25) - 10) < mp.mpf(10) ** -25 and abs(mid(u[1], 25)) < mp.mpf(10) ** -25
        assert abs(mid(y[1], 25) - (-10 * (1 - mp.cos(s_)) + v * mp.sin(s_))) < mp.mpf(10) ** -25


def test_two_masses_on_a_spring_hitting_their_stops_together():
    """Two unit masses joined by a spring (K = [[1, -1], [-1, 1]]), stops q_i >= 0, force -2 on
    each, e = 1/2, from q = (1, 1), v = (-1, -1): by symmetry the spring never acts and both are
    a ball with g = 2 thrown down from 1 at speed 1: 1 - t - t^2 = 0 gives the first impact at
    t1 = (sqrt 5 - 1)/2, at speed sqrt 5; the k-th flight after it lasts 2 (sqrt 5 / 2^k) / 2 =
    sqrt 5 / 2^k, so impact k is at t1 + sqrt 5 (1 - 2^-k) and T* = t1 + sqrt 5 = (3 sqrt 5 - 1)/2;
    then both rest, each stop carrying 2.  Every event closes both contacts at once; the accumulation is
    proven on the subspace where the two gaps agree.  An asymmetric start (q = (1, 11/10)) is not
    such a cycle: its events are not simultaneous."""
    lcs = L.models.mechanical([[1, 0], [0, 1]], [[1, -1], [-1, 1]], [[1, 0], [0, 1]], force=[-2, -2],
                              restitution=F(1, 2))
    tr = L.simulate(lcs, lcs.embed([1, 1, -1, -1]), 4)
    assert tr.certified and len(tr.accumulations) == 1
    assert all(e.modes == (frozenset({0, 1}),) and sorted(e.triggers) == ["y_0", "y_1"] for e in tr.events)
    acc = tr.accumulations[0]
    with mp.workdps(50):
        t1 = (mp.sqrt(5) - 1) / 2
        assert abs(mid(tr.events[0].time, 40) - t1) < mp.mpf(10) ** -38
        for k, e in enumerate(tr.events[1:], start=1):
            assert abs(mid(e.time, 40) - (t1 + mp.sqrt(5) * (1 - mp.mpf(1) / 2 ** k))) < mp.mpf(10) ** -38
        assert abs(mid(acc.time) - (3 * mp.sqrt(5) - 1) / 2) < mp.mpf(10) ** -35
    assert acc.state.known_rational() == fmpq_mat([[0], [0], [0], [0], [1]])
    assert tr.u(4).known_rational() == fmpq_mat([[2], [2]])
    cyc = bounces.bounce_cycle(lcs, L.simulate(lcs, lcs.embed([1, F(11, 10), -1, -1]), 2).events)
    assert cyc is None


def test_fixtures_carry_the_implied_impacts_and_compare_windows_them(tmp_path):
    """A fixture of a law-less accumulation lists its implied impacts (up to float resolution of T*,
    each the certified ball of the live run) and reads them back; compare() leaves a window around
    each, so the exact solution sampled on a float grid passes."""
    import numpy as np
    lcs = ball_on_spring(k=100, mass="1/1000", g="981/100", e="9/10", rest=0)
    tr = L.simulate(lcs, lcs.embed(["1/100", 0]), F(1, 2))
    acc = tr.accumulations[0]
    path = tmp_path / "spring.json"
    path.write_text(json.dumps(tr.to_fixture(digits=20)))
    fx = L.read_fixture(path)
    implied = fx.accumulations[0].implied
    assert implied["first_event"] == len(tr.events) - 1
    times = implied["times"]
    with mp.workdps(40):
        for k in (0, 1, len(times) - 1):
            assert times[k].overlaps(acc.event_time(k).ball(25))
        t_star = mid(acc.time)
        last = mp.mpf(times[-1].mid().str(30, radius=False))
        assert 0 < t_star - last <= t_star * mp.mpf(2) ** -52  # the last one a float grid can tell apart
        assert t_star - mp.mpf(times[-2].mid().str(30, radius=False)) > t_star * mp.mpf(2) ** -52
    with pytest.raises(L.InvalidArgument, match="implied events"):
        fx.accumulations[0].event_time(len(times))
    t = np.linspace(0, 0.5, 5001)
    X = tr.to_numpy(t)
    report = L.compare(fx, t, X, atol=1e-12)
    assert report.passed and report.n_compared > 4000
    t_k = float(tr.events[-1].time)
    inside = [w for w in report.windows if w[0] > t_k]  # windows of the implied impacts, merged near T*
    assert inside and inside[-1][1] >= float(acc.time)


def test_plots_evaluate_u_y_w_inside_windows_from_balls():
    """Inside an accumulation window a plot's u, y and w come from the sampled state balls and the
    flight's mode (Trajectory.window_rows: the exact values cost a Calcium evaluation each); they
    equal the exact traj.u, traj.y, traj.outputs at the same times - on Filippov's spiral (4.12),
    whose cycles switch modes and carry nonzero u, and on a law-less window (a ball on a spring)."""
    from lcs_exact.interfaces import AccumulationWindow
    spiral = L.examples.filippov_spiral()
    lcs = ball_on_spring(k=100, mass="1/1000", g="981/100", e="9/10", rest=0)
    for tr in (L.simulate(spiral, spiral.embed([1, 2]), 2), L.simulate(lcs, lcs.embed(["1/100", 0]), F(1, 2))):
        rec = next(r for r in tr.phases if isinstance(r.phase, AccumulationWindow))
        a, b = float(rec.t0), float(tr.accumulations[0].time)
        ts = [F(round((a + (b - a) * x) * 10 ** 12), 10 ** 12) for x in (0.013, 0.21, 0.5, 0.77, 0.9)]
        kinds = {"u": tr.u, "y": tr.y}
        if tr.output_names:
            kinds["w"] = tr.outputs
        for kind, exact in kinds.items():
            fast = tr.window_rows(rec.phase, ts, kind)
            want = [[float(c) for c in exact(t)] for t in ts]
            assert fast is not None and len(fast) == len(ts)
            assert all(abs(p - q) <= 1e-12 * max(1, abs(q)) for r, e in zip(fast, want) for p, q in zip(r, e)), kind
        if tr.output_names:  # the spiral: its relays' multipliers are nonzero inside the window
            assert any(abs(v) > 1e-3 for r in tr.window_rows(rec.phase, ts, "u") for v in r)

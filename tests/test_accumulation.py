"""Right-accumulations proven by a scaling symmetry (lcs_exact.accumulations.accumulation): the symmetry of the
LCS data, the geometric law of the relay spiral (4.12) derived by hand, the scaled cycles."""
from __future__ import annotations

from fractions import Fraction

from flint import fmpq, fmpq_mat

import mpmath as mp
import pytest

import lcs_exact as L
from lcs_exact.accumulations.accumulation import ScaledCycle, geometric_law, symmetry_exponents
from lcs_exact.numbers.reals import RationalReal
from lcs_exact.numbers.vectors import RationalVector
from lcs_exact.phases.trajectory import Event


def relay_lcs(B, C):
    """x' = B w, w in Sgn(C x) (A = 0) with a constant state c = 1: per relay j, inputs
    (u1, u2) >= 0, w_j = u1 - c, y1 = -C_j x + u2, y2 = 2c - u1 (written out by hand here)."""
    m, r = len(B), len(C)
    n, k = m + 1, 2 * r
    A = [[0] * n for _ in range(n)]
    Bt = [[0] * k for _ in range(n)]
    for i in range(m):
        A[i][m] = -sum(B[i][j] for j in range(r))
        for j in range(r):
            Bt[i][2 * j] = B[i][j]
    Ct = [[0] * n for _ in range(k)]
    Dt = [[0] * k for _ in range(k)]
    for j in range(r):
        for i in range(m):
            Ct[2 * j][i] = -C[j][i]
        Dt[2 * j][2 * j + 1] = 1
        Ct[2 * j + 1][m] = 2
        Dt[2 * j + 1][2 * j] = -1
    return L.LCS(A, Bt, Ct, Dt)


SPIRAL = relay_lcs([[-1, 2], [-2, -1]], [[1, 0], [0, 1]])  # (4.12)


def test_symmetry_of_the_relay_spiral():
    """States x scale like t (exponent 1), the constant state not at all (0); u1 (1 + w) does not
    scale, u2 (the positive part of z) scales like x; y1 like x, y2 not."""
    s = symmetry_exponents(SPIRAL)
    shift = -s["x"][2]  # one component: normalise the constant state's exponent to 0
    assert [e + shift for e in s["x"]] == [1, 1, 0]
    assert [e + shift for e in s["u"]] == [0, 1, 0, 1] and [e + shift for e in s["y"]] == [1, 0, 1, 0]


def test_no_symmetry_for_springs():
    """q' = v, v' = -q forces e_v = e_q - 1 and e_q = e_v - 1: no scaling symmetry."""
    assert symmetry_exponents(L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])) is None


def spiral_events():
    """(4.12) from (1, 2), by hand: the field is (1, -3), (-3, -1), (-1, 3), (3, 1) in quadrants
    I, IV, III, II; each switch lands on an axis at 1/3 of the previous distance:
    t_k = 3/2 - (5/2) 3^-k, states (5/3, 0), (0, -5/9), (-5/27, 0), (0, 5/81), ..."""
    events, x = [], [Fraction(1), Fraction(2)]
    fields = [(1, -3), (-3, -1), (-1, 3), (3, 1)]
    t = Fraction(0)
    for k in range(1, 10):
        f = fields[(k - 1) % 4]
        dt = -x[1] / f[1] if (k - 1) % 2 == 0 else -x[0] / f[0]
        t += dt
        x = [x[0] + f[0] * dt, x[1] + f[1] * dt]
        assert t == Fraction(3, 2) - Fraction(5, 2) / 3 ** k
        state = RationalVector(fmpq_mat([[fmpq(x[0].numerator, x[0].denominator)],
                                         [fmpq(x[1].numerator, x[1].denominator)], [1]]))
        q = (k - 1) % 4
        events.append(Event(RationalReal(fmpq(t.numerator, t.denominator)), frozenset({q}), (),
                            frozenset({(q + 1) % 4}), state, state, 0, {}, (f"y_{q}",)))
    return events


def test_geometric_law_of_the_spiral():
    events = spiral_events()
    assert geometric_law(SPIRAL, events[:7], symmetry_exponents(SPIRAL)) is None  # < 2 cycles
    law = geometric_law(SPIRAL, events, symmetry_exponents(SPIRAL))
    assert law is not None and law.period == 4 and law.ratio == fmpq(1, 81)
    assert law.time.known_rational() == fmpq(3, 2)  # sum of the geometric series, exactly
    assert list(law.limit.known_rational().entries()) == [0, 0, 1] and law.exponents == (1, 1, 0)


def test_scaled_cycle_reproduces_the_hand_derived_motion():
    """Inside the window after the last event, the state at t is the reference cycle's scaled:
    check against the hand-derived spiral (the switch at t_10 = 3/2 - (5/2) 3^-10 lands on
    (0, -5/3^10))."""
    events = spiral_events()
    law = geometric_law(SPIRAL, events, symmetry_exponents(SPIRAL))

    def reference(t, kind="x"):  # the spiral between the events, by hand (linear in each phase)
        ts = [Fraction(0)] + [Fraction(3, 2) - Fraction(5, 2) / 3 ** k for k in range(1, 10)]
        xs = [(Fraction(1), Fraction(2))] + [(Fraction(int(e.state_after.q[0, 0].p), int(e.state_after.q[0, 0].q)),
                                              Fraction(int(e.state_after.q[1, 0].p), int(e.state_after.q[1, 0].q)))
                                             for e in events]
        t = t.known_rational()  # an exact real (rational here)
        tf = Fraction(int(t.p), int(t.q))
        i = max(j for j in range(len(ts)) if ts[j] <= tf)
        a, b = xs[i], xs[min(i + 1, len(xs) - 1)]
        s = (tf - ts[i]) / (ts[i + 1] - ts[i]) if i + 1 < len(ts) else Fraction(0)
        x = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
        return RationalVector(fmpq_mat([[fmpq(x[0].numerator, x[0].denominator)],
                                        [fmpq(x[1].numerator, x[1].denominator)], [1]]))

    t9 = events[-1].time.known_rational()
    cyc = ScaledCycle(law, reference, events[-1].time, None, events[-1].state_after)
    t10 = fmpq(3, 2) - fmpq(5, 2) / 3 ** 10
    x = cyc.state(t10 - t9).rational()
    # event 10 is the second of a cycle (quadrant IV lands on x1 = 0) at 5/3^10 from the origin
    assert list(x.entries()) == [0, -fmpq(5, 3 ** 10), 1]


def test_inputs_at_a_crossed_accumulation_time_are_right_limits():
    """u and y at the accumulation time T* itself, as the state there: right limits, from the
    phase after the scaled cycles (they raised "internal inconsistency" at T*).  Bouncing ball
    (g = 10, e = 1/2) dropped from 5 at rest: impacts at 1, 2, 5/2, ..., T* = 3; after it the
    ball rests: x = (0, 0, 1), the contact force u = m g = 10, the gap y = 0.  Filippov's spiral
    from (1, 2): T* = 3/2, at rest at the origin after it, u = (1, 0, 1, 0) and y = (0, 1, 0, 1)
    as at t = 7/4."""
    ball = L.examples.bouncing_ball(g=10, e="1/2")
    tr = L.simulate(ball, ball.embed([5, 0]), 4)
    assert tr.accumulations[0].time.known_rational() == 3
    assert list(tr.u(3).known_rational().entries()) == [10]
    assert list(tr.y(3).known_rational().entries()) == [0]
    assert tr.to_numpy([0, 3, 4], u=True)[1].tolist() == [0.0, 0.0, 1.0, 10.0]
    spiral = L.examples.filippov_spiral()
    tr = L.simulate(spiral, [1, 2, 1], 2)
    assert tr.accumulations[0].time.known_rational() == fmpq(3, 2)
    assert list(tr.u("3/2").known_rational().entries()) == [1, 0, 1, 0] == list(tr.u("7/4").known_rational().entries())
    assert list(tr.y("3/2").known_rational().entries()) == [0, 1, 0, 1]


def _damped_ball_t_star(g, c, e, q0):
    """T* of a damped ball (q'' = -g - c q' + u, restitution e) dropped from q0, derived by hand:
    flights q(t) = q0 + (v0 + g/c)(1 - e^{-ct})/c - g t/c between impacts, summed with mpmath until
    they are shorter than 1e-45."""
    def flight(q0, v0):
        return (lambda t: q0 + (v0 + g / c) * (1 - mp.exp(-c * t)) / c - g * t / c,
                lambda t: (v0 + g / c) * mp.exp(-c * t) - g / c)
    q, v = flight(q0, mp.mpf(0))
    T = mp.findroot(q, mp.sqrt(2 * q0 / g))
    t_star, vv, impacts = T, v(T), [T]
    while T > mp.mpf(10) ** -45:
        q, v = flight(mp.mpf(0), -e * vv)
        T = mp.findroot(q, -2 * e * vv / g * mp.mpf("0.99"))
        t_star, vv = t_star + T, v(T)
        impacts.append(t_star)
    return t_star, impacts


def test_a_damped_ball_crosses_its_accumulation_without_a_law():
    """A damped ball (q'' = -10 - q'/10 + u, e = 1/2) dropped from 1: damping breaks the symmetry, so
    no exact law; the impacts are proven to accumulate by the contraction of the impact map
    (lcs_exact.accumulations.bounces) and the ball rests on the floor after T*, which agrees to 40 digits with the
    hand derivation, as do the implied impacts (traj.accumulations[0].event_time(k))."""
    from lcs_exact import models, sources
    lcs = models.mechanical([[1]], [[0]], [[1]], damping=[["1/10"]], force=[sources.constant(-10)], restitution="1/2")
    with mp.workdps(100):  # the flight formula cancels badly for short flights: 100 digits for 40
        t_star, impacts = _damped_ball_t_star(mp.mpf(10), mp.mpf(1) / 10, mp.mpf(1) / 2, mp.mpf(1))
    tr = L.simulate(lcs, lcs.embed([1, 0]), 5, digits=20)
    assert tr.certified and not tr.partial and len(tr.accumulations) == 1
    acc = tr.accumulations[0]
    assert acc.ratio is None and acc.start is tr.events[-1].time
    with mp.workdps(60):
        b = acc.time.ball(45)
        assert abs(mp.mpf(b.mid().str(50, radius=False)) - t_star) < mp.mpf(10) ** -40
        lo, hi = acc.lower, acc.upper  # rational bounds, as narrow as the run's 20 digits
        assert mp.mpf(int(lo.p)) / int(lo.q) <= t_star <= mp.mpf(int(hi.p)) / int(hi.q)
        assert (hi - lo) / lo < fmpq(1, 10**20)
        k0 = len(tr.events)  # the implied impacts continue the listed ones
        for k in range(5):
            tk = acc.event_time(k).ball(40)
            assert abs(mp.mpf(tk.mid().str(45, radius=False)) - impacts[k0 + k]) < mp.mpf(10) ** -35
    assert acc.state.known_rational() == fmpq_mat([[0], [0], [1]])  # at rest on the floor, exactly
    assert tr.events[-1].triggers == ("y_0",) and tr.phases[-1].mode == frozenset({0})
    assert tr.state(5).known_rational() == fmpq_mat([[0], [0], [1]])
    assert tr.u(5).known_rational() == fmpq_mat([[10]])  # the floor carries the ball's weight


def test_one_map_of_a_window_time_to_its_reference_cycle():
    """A time of a geometric law's window is mapped into the reference cycle by one search
    (exact for states, on balls for samples, in floats for a plot's flight modes): the float map
    agrees with the exact one, the flight's mode is that of the reference phase holding the exact
    reference time, and the flights' float times a plot cuts its lines at are the exact event
    times.  A window without a law (a ball on a spring) has one mode for all its flights."""
    from lcs_exact.display.plotting import _flight_times
    from lcs_exact.interfaces import AccumulationWindow

    spiral = L.examples.filippov_spiral()
    tr = L.simulate(spiral, spiral.embed([1, 2]), 2)
    rec = next(r for r in tr.phases if isinstance(r.phase, ScaledCycle))
    w, t_k, T_star = rec.phase, rec.t0, tr.accumulations[0].time
    a, b = float(t_k), float(T_star)
    ts = [Fraction(round((a + (b - a) * (1 - Fraction(9, 10) ** j)) * 10 ** 15), 10 ** 15) for j in range(1, 40)]
    phases = [r for r in tr.phases if not isinstance(r.phase, AccumulationWindow)]
    for t in ts:
        t_ref, _ = w._map(fmpq(t.numerator, t.denominator) - t_k)   # the exact map (a state's)
        exact_ref = float(t_ref)
        assert abs(w.reference_time(float(t)) - exact_ref) <= 1e-9 * max(1.0, abs(exact_ref))
        holder = next(r for r in phases if (t_ref - r.t0).sign() >= 0 and (t_ref - r.t1).sign() < 0)
        assert w.flight_mode(float(t)) is holder.phase.mode
    flights = list(_flight_times(w, 30))
    assert all(abs(f - float(w.event_time(k))) <= 1e-14 * abs(f) for k, f in enumerate(flights))
    ball = L.examples.ball_on_spring(k=100, mass="1/1000", g="981/100", e="9/10", rest=0)
    tb = L.simulate(ball, ball.embed(["1/100", 0]), Fraction(1, 2))
    bw = next(r.phase for r in tb.phases if isinstance(r.phase, AccumulationWindow))
    assert not isinstance(bw, ScaledCycle) and bw.flight_mode(float(bw.t_k) + 1e-9) is bw.mode

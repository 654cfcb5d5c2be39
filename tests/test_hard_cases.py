"""Hard cases, each derived by hand in the test: stiff systems whose A has a repeated eigenvalue
(free masses: 0 is a double eigenvalue; e^{At} goes through the Jordan-Chevalley split A = S + N,
so the error bounds do not grow like e^{||A|| t}), simultaneous impacts, and an exact graze.
"""
import mpmath as mp
import pytest
from flint import fmpq, fmpq_mat

import lcs_exact as L
from lcs_exact.numbers.expm import jordan_chevalley

from helpers import close, num
from reference.flows import first_fall

mp.mp.dps = 50


def free_pair(k):
    """Two unit masses joined by a spring k, no wall spring; stop on mass 1 (q1 >= 0)."""
    A = [[0, 0, 1, 0], [0, 0, 0, 1], [-k, k, 0, 0], [k, -k, 0, 0]]
    return L.LCS(A, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])


@pytest.mark.parametrize("k", [10 ** 4, 10 ** 6])
def test_stiff_free_pair_first_impact(k):
    """From q = (1, 1), v = (-1, 0): centre c = 1 - t/2, difference d = -sin(ωt)/ω with ω = √(2k),
    so q1 = 1 - t/2 - sin(ωt)/(2ω). The impact is at its first root (near t = 2); v1 jumps to 0."""
    tr = L.simulate(free_pair(k), [1, 1, -1, 0], "21/10")
    assert tr.certified and len(tr.events) >= 1
    w = mp.sqrt(2 * k)
    f = lambda t: 1 - t / 2 - mp.sin(w * t) / (2 * w)
    # the oscillation is 1/(2ω) small: start scanning where 1 - t/2 < 1/(2ω), step << period
    start = 2 - 1 / w
    tau = first_fall(f, start, mp.mpf(2) + 1 / w, 2 * mp.pi / w / 50)
    e = tr.events[0]
    assert close(num(e.time), tau)
    assert e.modes == (frozenset({0}),)
    q2 = 1 - tau / 2 + mp.sin(w * tau) / (2 * w)
    v2 = -mp.mpf(1) / 2 + mp.cos(w * tau) / 2
    after = [num(c) for c in e.state_after]
    assert after[0] == 0 and after[2] == 0
    assert close(after[1], q2) and close(after[3], v2)


def test_jordan_chevalley_split():
    """A = S + N with SN = NS, N nilpotent, S diagonalizable (minimal polynomial squarefree):
    for the free pair with k = 3, S = A - N with N = [[0, 0, 1/2, 1/2]]-type rank-one nilpotent."""
    A = fmpq_mat(4, 4, [0, 0, 1, 0, 0, 0, 0, 1, -3, 3, 0, 0, 3, -3, 0, 0])
    S, N, m = jordan_chevalley(A)
    assert S + N == A and S * N == N * S
    assert m == 2 and N * N == fmpq_mat(4, 4) and N != fmpq_mat(4, 4)
    # S annihilated by the squarefree part s(s^2 + 6) of χ = s^2 (s^2 + 6)
    I = fmpq_mat(4, 4, [int(i == j) for i in range(4) for j in range(4)])
    assert S * (S * S + 6 * I) == fmpq_mat(4, 4)
    # N is the centre-of-mass drift: q_i gains t (v1 + v2)/2, i.e. N = [[0, 0, 1/2, 1/2]] twice
    h = fmpq(1, 2)
    assert N == fmpq_mat(4, 4, [0, 0, h, h, 0, 0, h, h] + [0] * 8)


# --- a symmetric three-mass chain with stops on the outer masses --------------------------------
A3 = [[0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1],
      [-1, 1, 0, 0, 0, 0], [1, -2, 1, 0, 0, 0], [0, 1, -1, 0, 0, 0]]


def outer_stops():
    """Three unit masses, unit springs 1-2 and 2-3; stops q1 >= 0 and q3 >= 0."""
    return L.LCS(A3, [[0, 0], [0, 0], [0, 0], [1, 0], [0, 0], [0, 1]],
                 [[1, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0]], [[0, 0], [0, 0]])


def test_symmetric_simultaneous_impact():
    """q1 ≡ q3 by symmetry, so both stops are hit at the same instant: one event, mode {0, 1}
    (the equality of the two roots is proven structurally, not by closeness of balls).

    With a = q1 = q3, b = q2: the centre (2a + b)/3 = 4/3 - 2t/3 and e = b - a = cos √3t + sin √3t/√3,
    so a = 4/3 - 2t/3 - e/3. After the impact q1 = q3 = 0 and b'' = -2b; u_0 = u_1 = -b >= 0 until
    b returns to 0, where both stops release together."""
    tr = L.simulate(outer_stops(), [1, 2, 1, -1, 0, -1], 6)
    assert tr.certified and len(tr.events) == 2
    r3, r2 = mp.sqrt(3), mp.sqrt(2)
    a = lambda t: mp.mpf(4) / 3 - 2 * t / 3 - (mp.cos(r3 * t) + mp.sin(r3 * t) / r3) / 3
    tau = first_fall(a, mp.mpf(1) / 2, 4, mp.mpf(1) / 100)
    e0, e1 = tr.events
    assert close(num(e0.time), tau)
    assert e0.modes == (frozenset({0, 1}),) and e0.mode_after == frozenset({0, 1})
    assert set(e0.triggers) == {"y_0", "y_1"}
    ee = mp.cos(r3 * tau) + mp.sin(r3 * tau) / r3
    de = -r3 * mp.sin(r3 * tau) + mp.cos(r3 * tau)
    b, db = a(tau) + ee, -mp.mpf(2) / 3 + (2 * de) / 3  # b = a + e, b' = a' + e'
    after = [num(c) for c in e0.state_after]
    assert after[0] == after[2] == after[3] == after[5] == 0
    assert close(after[1], b) and close(after[4], db)
    # release when b = B cos √2 s + B'/√2 sin √2 s returns to 0 (b < 0, so u = -b > 0 before)
    s = mp.findroot(lambda s: b * mp.cos(r2 * s) + db / r2 * mp.sin(r2 * s), 1)
    assert 0 < s < mp.pi / r2
    assert close(num(e1.time), tau + s)
    assert e1.mode_before == frozenset({0, 1}) and e1.mode_after == frozenset() and e1.modes == ()
    assert close(num(e1.state_before[4]), -b * r2 * mp.sin(r2 * s) + db * mp.cos(r2 * s))


@pytest.mark.slow
def test_tangential_touch_from_a_transcendental_start_is_no_event():
    """x0 = e^{-A}(0, 1, 0, 0, 1, 0): at t = 1 both outer masses touch their stops with zero
    velocity and positive acceleration (q1'' = q2 - q1 = 1): a graze, proven exact (the state at
    the critical point t* = 1 collapses to a rational vector), so no event in [0, 6]; q1 > 0 on
    (0, 1) ∪ (1, 6] (checked on a grid in mpmath below)."""
    x0 = L.expm_action(A3, -1, [0, 1, 0, 0, 1, 0])
    tr = L.simulate(outer_stops(), x0, 6)
    assert tr.certified and tr.events == ()
    A = mp.matrix(A3)
    v = mp.matrix([0, 1, 0, 0, 1, 0])
    assert min((mp.expm(A * (mp.mpf(t) / 50 - 1)) * v)[0] for t in range(0, 301) if t != 50) > 0
    got = [num(c) for c in tr.state(3)]
    want = mp.expm(A * 2) * v
    assert all(close(g, want[i]) for i, g in enumerate(got))


def test_structural_zero_of_an_exact_start():
    """x0 = e^{-R}(0, -1, 1, 0) with R rotating only (c, s): q(0) = 0 exactly (a form vanishing on
    the whole orbit of R), so the impact at t = 0 is decided without refining balls. With
    q'' = -c + u, c = cos(t - 1): the stop holds while u = cos(t - 1) >= 0, release at 1 + π/2,
    then free flight: x(3) = (cos 2 + 2 - π/2, 1 - sin 2, cos 2, -sin 2) (by hand)."""
    A = [[0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1], [0, 0, -1, 0]]
    R = [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]]
    lcs = L.LCS(A, [[0], [1], [0], [0]], [[1, 0, 0, 0]], [[0]])
    tr = L.simulate(lcs, L.expm_action(R, -1, [0, -1, 1, 0]), 3)
    assert tr.certified and len(tr.events) == 2
    e0, e1 = tr.events
    assert e0.time.closed_form == 0 and e0.modes == (frozenset({0}),)
    assert close(num(e1.time), 1 + mp.pi / 2) and e1.mode_after == frozenset()
    want = [mp.cos(2) + 2 - mp.pi / 2, 1 - mp.sin(2), mp.cos(2), -mp.sin(2)]
    assert all(close(num(c), w) for c, w in zip(tr.state(3), want))


def test_exact_tangential_touches_of_one_frequency_phases():
    """Issue 15's reproducers: y = 5 + 3 cos 2t + 4 sin 2t = 5 + 5 cos(2t - phi) from the rational
    state (q, q') = (3, 8) of q'' = -4q touches 0 (a double root) without going below: no event;
    y = 1 - sin t (q'' = -q from (0, -1)) grazes 0 at t = pi/2: no event.  The states at t_end
    are the free oscillations, by hand."""
    import mpmath
    from lcs_exact.builders.mechanics import mechanical
    osc = mechanical([[1]], [[4]], [[1]], gap=[5])
    tr = L.simulate(osc, osc.embed([3, 8]), 3)
    assert tr.certified and tr.events == ()
    with mpmath.workdps(40):
        q = 3 * mpmath.cos(6) + 4 * mpmath.sin(6)
        v = -6 * mpmath.sin(6) + 8 * mpmath.cos(6)
        x = tr.state(3)
        assert abs(mpmath.mpf(x[0].ball(30).mid().str(40, radius=False)) - q) < mpmath.mpf(10) ** -28
        assert abs(mpmath.mpf(x[1].ball(30).mid().str(40, radius=False)) - v) < mpmath.mpf(10) ** -28
    graze = mechanical([[1]], [[1]], [[1]], gap=[1])
    tr = L.simulate(graze, graze.embed([0, -1]), 3)
    assert tr.certified and tr.events == ()
    with mpmath.workdps(40):
        x = tr.state(3)
        assert abs(mpmath.mpf(x[0].ball(30).mid().str(40, radius=False)) + mpmath.sin(3)) < mpmath.mpf(10) ** -28


def test_two_stops_hit_1e30_apart():
    """Two uncoupled unit oscillators with stops (q_i >= 0), from q = (1, 1), v = (0, -10^-30):
    q1 = cos t - 10^-30 sin t hits first, at t1 = pi/2 - atan(10^-30) (plastic: q1 = v1 = 0
    after), and q0 = cos t at pi/2 exactly, 10^-30 later.  After the first event the state is
    cos(t1) (1, 0, -10^30, 0): a rational direction with an entry beyond 53 bits, whose ball
    used to be rounded at 53 bits and kept as exact (the start of q0 was then refused)."""
    from lcs_exact.models import mechanical
    lcs = mechanical([[1, 0], [0, 1]], [[1, 0], [0, 1]], [[1, 0], [0, 1]])
    tr = L.simulate(lcs, [1, 1, 0, fmpq(-1, 10 ** 30)], 3)
    assert tr.certified and not tr.partial and [e.triggers for e in tr.events] == [("y_1",), ("y_0",)]
    with mp.workdps(80):
        t1 = mp.pi / 2 - mp.atan(mp.mpf(10) ** -30)
        got = [mp.mpf(e.time.ball(60).mid().str(70, radius=False)) for e in tr.events]
        assert abs(got[0] - t1) < mp.mpf(10) ** -60 and abs(got[1] - mp.pi / 2) < mp.mpf(10) ** -60
        assert mp.mpf(10) ** -30 * 0.999 < got[1] - got[0] < mp.mpf(10) ** -30 * 1.001
    x = tr.state(3)  # both masses at rest on their stops
    assert [c.rational() for c in x] == [0, 0, 0, 0]


def test_integers_beyond_the_working_precision_are_not_rounded():
    """An integer entry that needs more than 53 bits is not an exact 53-bit ball."""
    from lcs_exact.numbers.reals import RationalReal
    from lcs_exact.numbers.vectors import RationalVector
    big = 10 ** 30 + 1
    assert RationalReal(big).arb(200).is_exact() and RationalReal(big).arb(200) == big
    v = RationalVector(fmpq_mat([[big], [-big]]))
    assert v.arb(200)[0, 0] == big and v.arb(200)[1, 0] == -big


def test_an_impact_exactly_at_a_transcendental_horizon_is_proven_there():
    """q'' + q' + 5/4 q = 0 from (1, -2) against a stop q >= 0 with e = 1/2: q = e^{-t/2}(cos t -
    3/2 sin t) reaches 0 at t* = atan(2/3) exactly (tan t* = 2/3), with q'(t*-) = -(√13/2)
    e^{-t*/2}.  With t_end = t* no ball separates the impact from the horizon: it is proven at
    t_end (was UnresolvedSign), and x(t_end) is the state after it."""
    import sympy as sp
    lcs = L.models.mechanical([[1]], [["5/4"]], [[1]], damping=[[1]], restitution="1/2")
    T = sp.atan(sp.Rational(2, 3))
    tr = L.simulate(lcs, lcs.embed([1, -2]), T, digits=30)
    assert tr.certified and len(tr.events) == 1
    assert sp.simplify(tr.events[0].time.closed_form - T) == 0
    with mp.workdps(40):
        ts = mp.atan(mp.mpf(2) / 3)
        v_minus = -mp.sqrt(13) / 2 * mp.exp(-ts / 2)
        q, v = tr.state(T)
        assert q.rational() == 0
        assert close(num(v), -v_minus / 2)
        assert close(num(tr.events[0].state_before[1]), v_minus)


def test_a_forced_impact_oscillator_grazing_on_a_nested_radical_critical_point_ends():
    """q'' + q = sin 2t from rest, stop q >= -1/2, inelastic: q = 2/3 sin t - 1/3 sin 2t hits
    the stop at t1 ~ 3.5428 and leaves it at once; the free motion q = A cos(t - t1) + B sin(t -
    t1) - 1/3 sin 2t returns tangentially to the stop at t1 + 2 pi, a graze whose critical point
    SymPy writes as acos of a root of 16a^4 - 32a^3 + 32a - 7 in nested radicals.  The proof of
    the touch used to run SymPy's simplify for minutes, past ``time_limit``; Calcium now decides it
    with the root re-expressed by its minimal polynomial."""
    lcs = L.models.mechanical([[1]], [[1]], [[1]], force=[L.sources.sine(2, 1)], gap=["1/2"])
    tr = L.simulate(lcs, lcs.embed([0, 0]), 12, digits=30, time_limit=60)
    with mp.workdps(50):
        t1 = mp.findroot(lambda t: 2 * mp.sin(t) / 3 - mp.sin(2 * t) / 3 + mp.mpf(1) / 2, 3.54)
        A, B = -mp.mpf(1) / 2 + mp.sin(2 * t1) / 3, 2 * mp.cos(2 * t1) / 3
        q12 = A * mp.cos(12 - t1) + B * mp.sin(12 - t1) - mp.sin(24) / 3
        v12 = -A * mp.sin(12 - t1) + B * mp.cos(12 - t1) - 2 * mp.cos(24) / 3
        assert tr.certified and len(tr.events) == 1
        assert close(num(tr.events[0].time), t1)
        q, v = tr.state(12)[:2]  # (then the source's states)
        assert close(num(q), q12) and close(num(v), v12)


def test_an_accumulation_without_a_law_is_proven_and_crossed():
    """A damped ball q'' = -q' - 10 dropped from q = 1 onto q >= 0 with e = 1/2: damping breaks
    the scaling symmetry, so no geometric law; the impacts are proven to accumulate by the
    contraction of the impact map (lcs_exact.accumulations.bounces) and the ball rests after T*.  Per phase
    q = (v+ + 10)(1 - e^{-s}) - 10 s from q = 0 (the first from q = 1 - 10 t + 10 (1 - e^{-t})),
    v- = (v+ + 10) e^{-s} - 10, v+ = -v-/2 (derived here), summed until the flights are below
    1e-40: the impacts, T* (was an unproven estimate 1.16656 and a stop) and the implied impacts."""
    lcs = L.models.mechanical([[1]], [[0]], [[1]], damping=[[1]], force=[-10], restitution="1/2")
    tr = L.simulate(lcs, lcs.embed([1, 0]), 3, digits=30, time_limit=60)
    assert tr.certified and not tr.partial and len(tr.accumulations) == 1
    events, acc = tr.events, tr.accumulations[0]
    with mp.workdps(90):  # short flights cancel in the formula: 90 digits for 35
        t = mp.findroot(lambda t: 1 - 10 * t + 10 * (1 - mp.exp(-t)), 0.45)
        vm, times, s = -10 * (1 - mp.exp(-t)), [t], 1
        while s > mp.mpf(10) ** -42:
            vp = -vm / 2
            s = mp.findroot(lambda s: (vp + 10) * (1 - mp.exp(-s)) - 10 * s, 2 * vp / 10)
            vm, t = (vp + 10) * mp.exp(-s) - 10, t + s
            times.append(t)
        assert all(close(num(ev.time), r) for ev, r in zip(events, times))
        assert close(num(acc.time), t)
        assert all(close(num(acc.event_time(k)), times[len(events) + k]) for k in range(5))
        lo, hi = acc.lower, acc.upper
        assert mp.mpf(int(lo.p)) / int(lo.q) <= t <= mp.mpf(int(hi.p)) / int(hi.q)
    assert acc.state.known_rational() == fmpq_mat([[0], [0], [1]]) and tr.phases[-1].mode == frozenset({0})


def _copies(lcs, m):
    """m uncoupled copies of lcs (block-diagonal A, B, C, D)."""
    def blocks(M):
        r, c = M.nrows(), M.ncols()
        out = fmpq_mat(r * m, c * m)
        for b in range(m):
            for i in range(r):
                for j in range(c):
                    out[b * r + i, b * c + j] = M[i, j]
        return out
    return L.LCS(*(blocks(M) for M in (lcs.A, lcs.B, lcs.C, lcs.D)))


def test_relations_among_the_components_of_a_start_are_zero_forms():
    """x0 = (a, 0, 2a, b) with a, b components of e^{-A} v: 2 x_0 - x_2 = 0 and x_1 = 0 are
    proven by the definitions (and nothing else: a and b are independent reals); the components
    of a vector carry that vector's relations (3 w_0 - w_1 = 0 for w = (a, 3a))."""
    from lcs_exact.numbers.relations import component_relations
    from lcs_exact.numbers.vectors import as_exact_vector
    carts = L.models.two_carts()
    x = L.expm_action(carts.A, -1, [0, -1, -1, 0])
    a, b = x[1], x[3]
    zf = as_exact_vector([a, 0, 2 * a, b]).zero_forms
    assert zf == fmpq_mat([[1, 0, fmpq(-1, 2), 0], [0, 1, 0, 0]])
    w = as_exact_vector([a, 3 * a])
    assert w.zero_forms == fmpq_mat([[1, fmpq(-1, 3)]])  # the canonical row basis of 3 w_0 - w_1
    assert component_relations([w[0], w[1]]) == fmpq_mat([[1, fmpq(-1, 3)]])
    assert component_relations([a, b]).nrows() == 0
    # e^{-A} v built twice is one definition: its components relate across the two copies
    y = L.expm_action(carts.A, -1, [0, -1, -1, 0])
    assert component_relations([x[1], y[1], x[3], y[3]]) == fmpq_mat([[1, -1, 0, 0], [0, 0, 1, -1]])
    assert component_relations([x[1], L.expm_action(carts.A, -2, [0, -1, -1, 0])[1]]).nrows() == 0


@pytest.mark.parametrize("m", [2, 8])
def test_copies_of_the_two_carts_from_an_exact_start_hit_together(m):
    """m uncoupled copies of section 7's two carts, each from x0 = e^{-A}(0, -1, -1, 0) (the
    same exact reals repeated): every event of one copy is an event of all at the same instant
    (x_i = x_{i+4} on every phase: the copies' roots are proven equal, never compared by balls),
    at section 7's times 1 and 1 + pi/2 (closed forms) and then at the single system's two later
    events; m = 8 (n = 32) runs on Taylor steps, m = 2 on spectral data."""
    carts = L.models.two_carts()
    x1 = L.expm_action(carts.A, -1, [0, -1, -1, 0])
    single = L.simulate(carts, x1, 10, digits=30)
    tr = L.simulate(_copies(carts, m), list(x1) * m, 10, digits=30)
    assert tr.certified and len(tr.events) == len(single.events) == 4
    assert [str(e.time.closed_form) for e in tr.events[:2]] == ["1", "1 + pi/2"]
    for e, s in zip(tr.events, single.events):
        assert e.time.ball(30).overlaps(s.time.ball(30)) and e.time.ball(30).rad() < 1e-30
        (trigger,) = s.triggers  # y_0 or u_0: constraint 0 of every copy (copy b's is b)
        assert set(e.triggers) == {f"{trigger[0]}_{b}" for b in range(m)}
        assert e.mode_after == frozenset(b for b in range(m) if 0 in s.mode_after)
        assert e.modes == tuple(frozenset(range(m)) for _ in s.modes)
    xs, xt = single.state(10).ball(25), tr.state(10).ball(25)
    assert all(xt[4 * b + i].overlaps(xs[i]) for b in range(m) for i in range(4))


def _stop_and_touch():
    """x = (p, v, w, a, b): p = cos t hits its stop (y_0 = p) at pi/2; y_1 = w - a with a = sin t,
    w constant: from w = 1 it touches 0 exactly at pi/2 (1 - sin t), from w = 2 it stays > 0."""
    A = [[0, 1, 0, 0, 0], [-1, 0, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 1], [0, 0, 0, -1, 0]]
    B = [[0, 0], [1, 0], [0, 0], [0, 0], [0, -1]]
    C = [[1, 0, 0, 0, 0], [0, 0, 1, -1, 0]]
    return L.LCS(A, B, C, [[0, 0], [0, 0]])


@pytest.mark.parametrize("w, positive", [(2, True), (1, False)])
def test_a_constraint_is_known_positive_at_an_event_only_when_its_search_proved_it(w, positive):
    """The event state at pi/2 knows y_1 > 0 from the root search (2 - sin(pi/2) = 1) without a
    ball, but not when y_1 touches 0 there (1 - sin(pi/2) = 0: the search proved a touch, so it
    claims nothing); the impact is the same in both."""
    tr = L.simulate(_stop_and_touch(), [1, 0, w, 0, 1], 2)
    (e,) = tr.events
    assert str(e.time.closed_form) == "pi/2" and e.triggers == ("y_0",)
    known = [[g[0, j] for j in range(5)] for g in e.state_before.positive_forms]
    assert known == ([[0, 0, 1, -1, 0]] if positive else [])
    assert all(close(num(c), v) for c, v in zip(e.state_after, [0, 0, w, 1, 0]))


def test_the_signs_event_states_know_are_positive_on_a_chain():
    """Sixteen carts (n = 32, Taylor steps), 12 events among clusters 1e-20 apart: every row an event
    state knows positive from the search is > 0 there, shown by its ball at 2000 bits."""
    from fractions import Fraction
    N = 16
    tr = L.simulate(L.examples.cart_chain(N), [Fraction((-1) ** i, 2) for i in range(N)] + [0] * N, 10)
    known = 0
    for e in tr.events:
        x = e.state_before
        for g in getattr(x, "positive_forms", ()):
            v = sum((x.arb(2000)[j, 0] * g[0, j] for j in range(g.ncols()) if g[0, j] != 0), 0)
            assert v > 0
            known += 1
    assert len(tr.events) == 12 and known >= 60


def test_a_near_graze_beside_a_chain_is_proven_in_the_dimension_of_its_block():
    """A unit oscillator with a stop at 1 - 10^-60 (y = 1 - 10^-60 - sin t from q = 0, v = -1)
    beside fifteen uncoupled carts (n = 33): the touch test near pi/2 runs on the 3 states the
    constraint sees (its left Krylov space), not on 33 (minutes in Calcium, past time_limit,
    before).  The impact is at asin(1 - 10^-60) = pi/2 - 1.41e-30, written out here."""
    from fractions import Fraction
    from lcs_exact.builders.mechanics import mechanical
    from lcs_exact.numbers.closedforms import observed
    graze = mechanical([[1]], [[1]], [[1]], gap=[1 - fmpq(1, 10 ** 60)])
    chain = L.examples.cart_chain(15)
    blocks = [(graze, 0, 0), (chain, graze.n, graze.B.ncols())]
    n, k = graze.n + chain.n, graze.B.ncols() + chain.B.ncols()
    A, B, C, D = fmpq_mat(n, n), fmpq_mat(n, k), fmpq_mat(k, n), fmpq_mat(k, k)
    for s, r, c in blocks:
        for i in range(s.n):
            for j in range(s.n):
                A[r + i, r + j] = s.A[i, j]
            for j in range(s.B.ncols()):
                B[r + i, c + j] = s.B[i, j]
        for i in range(s.B.ncols()):
            for j in range(s.n):
                C[c + i, r + j] = s.C[i, j]
    lcs = L.LCS(A, B, C, D)
    x0 = [0, -1, 1] + [Fraction(1 + i, 5) for i in range(15)] + [0] * 15
    tr = L.simulate(lcs, x0, 2, time_limit=60)
    assert tr.certified and len(tr.events) == 1
    with mp.workdps(80):
        want = mp.asin(1 - mp.mpf(10) ** -60)
        assert abs(mp.mpf(tr.events[0].time.ball(50).mid().str(60, radius=False)) - want) < mp.mpf(10) ** -48
    # the reduction itself: y_0 sees 3 of the 33 states, with the same function
    sp = L.numbers.spectrum_of(A)
    g = fmpq_mat(1, n, [C[0, j] for j in range(n)])
    x = L.numbers.vectors.as_exact_vector(x0)
    spr, c, w = observed(sp, g, x)
    assert spr.n == 3 and (c.nrows(), c.ncols()) == (1, 3)
    from flint import arb, arb_mat, ctx
    with ctx.workprec(128):
        full = (arb_mat(g) * sp.apply(arb(fmpq(3, 7)), x.arb(128), 128))[0, 0]
        small = (arb_mat(c) * spr.apply(arb(fmpq(3, 7)), w.arb(128), 128))[0, 0]
    assert full.overlaps(small) and full.rad() < 1e-30


def test_a_crossing_through_a_triple_root_at_an_exact_time_is_proven():
    """Free pair (k = 1), stop q1 >= 0, from e^{-A}(0, 0, 0, -1): at t = 1 the state is (0, 0, 0, -1),
    so q1 = q1' = q1'' (= -q1 + q2) = 0 and q1''' = -q1' + q2' = -1 < 0: q1 crosses through a triple
    root.  Its bracket is not simple; t = 1 is proven its only zero there (f, f', f'' vanish at 1,
    f''' < 0 on the bracket), so the state there is exact and the mode {0} is selected without a
    jump.  Then q1 = 0, q2 = -sin(t - 1), u = sin(t - 1) >= 0 up to t = 2."""
    tr = L.simulate(free_pair(1), L.expm_action(free_pair(1).A, -1, [0, 0, 0, -1]), 2)
    assert tr.certified and len(tr.events) == 1
    (e,) = tr.events
    assert str(e.time.closed_form) == "1" and e.triggers == ("y_0",)
    assert e.modes == () and e.mode_after == frozenset({0})
    assert [num(c) for c in e.state_after] == [0, 0, 0, -1]
    x2 = [num(c) for c in tr.state(2)]
    assert x2[0] == 0 and x2[2] == 0
    assert close(x2[1], -mp.sin(1)) and close(x2[3], -mp.cos(1))


def _side_by_side(*systems):
    """The uncoupled system of several LCSs (block-diagonal A, B, C, D)."""
    n, k = sum(s.n for s in systems), sum(s.B.ncols() for s in systems)
    A, B, C, D = fmpq_mat(n, n), fmpq_mat(n, k), fmpq_mat(k, n), fmpq_mat(k, k)
    r = c = 0
    for s in systems:
        m = s.B.ncols()
        for i in range(s.n):
            for j in range(s.n):
                A[r + i, r + j] = s.A[i, j]
            for j in range(m):
                B[r + i, c + j] = s.B[i, j]
        for i in range(m):
            for j in range(s.n):
                C[c + i, r + j] = s.C[i, j]
            for j in range(m):
                D[c + i, c + j] = s.D[i, j]
        r, c = r + s.n, c + m
    return L.LCS(A, B, C, D)


def test_two_bridges_switch_together_at_a_closed_form_of_absolute_time():
    """Full-wave bridges driven by sin t and sin(4t/3), side by side (n = 6): each alone switches at
    t = 3 pi/4 (the second where sin(4t/3) = 0), after events at times without closed forms.  Side by
    side the two roots are proven one instant through the sources' clock (3 pi/4 in absolute time
    for both; no ball can order them): one event with both bridges' triggers, and every other
    event of the pair is an event of one bridge alone, at the same time."""
    from fractions import Fraction
    rs = [L.examples.sine_rectifier(omega=Fraction(k, 3), full_wave=True) for k in (3, 4)]
    x0s = [list(s.embed([Fraction(k + 1, 9)])) for k, s in enumerate(rs)]
    tr = L.simulate(_side_by_side(*rs), sum(x0s, []), 8)
    assert tr.certified
    alone = [[e.time.ball(25) for e in L.simulate(s, x0, 8).events] for s, x0 in zip(rs, x0s)]
    both = [e.time.ball(25) for e in tr.events]
    assert len(both) == len(alone[0]) + len(alone[1]) - 1  # one instant shared
    for t in alone[0] + alone[1]:
        assert sum(b.overlaps(t) for b in both) == 1
    (shared,) = [e for e in tr.events if all(any(e.time.ball(25).overlaps(t) for t in a) for a in alone)]
    assert str(shared.time.closed_form) == "3*pi/4"
    assert set(shared.triggers) == {"u_3", "y_0", "y_5"}  # bridge 0's u_3, y_0 and bridge 1's y_1 (y_5 here)
    assert abs(mp.sin(mp.mpf(4) / 3 * 3 * mp.pi / 4)) < mp.mpf(10) ** -40


@pytest.mark.parametrize("k", [4, 6])
def test_a_touch_of_even_order_four_or_six_is_no_event(k):
    """An integrator chain q^(k+1) = d feeding from a rotation d' = -s, s' = d that is not excited
    (d = s = 0): from q^(i)(0) = (-1)^i k!/(k-i)! the stop's function is y = (1 - t)^k exactly,
    which touches 0 at t = 1 without crossing for k even.  There f'' = k(k-1)(1 - t)^(k-2) vanishes
    too (no convexity to show): the touch is proven of order k at the closed form 1 (f^(j)(1) = 0,
    j < k, f^(k) = k! > 0), so there is no event, and x(2) = (1, -k(-1)^(k-1), ...) by the formula."""
    from math import comb, factorial
    m, n = k + 1, k + 3
    A = [[0] * n for _ in range(n)]
    for i in range(m - 1):
        A[i][i + 1] = 1
    A[m - 1][m], A[m][m + 1], A[m + 1][m] = 1, -1, 1
    lcs = L.LCS(A, [[int(i == 1)] for i in range(n)], [[int(j == 0) for j in range(n)]], [[0]])
    x0 = [comb(k, i) * (-1) ** i * factorial(i) for i in range(m)] + [0, 0]
    tr = L.simulate(lcs, x0, 2)
    assert tr.certified and len(tr.events) == 0
    x2 = [num(c) for c in tr.state(2)]
    want = [factorial(k) // factorial(k - i) * (-1) ** i * (1 - 2) ** (k - i) for i in range(m)]  # d^i/dt^i (1-t)^k at 2
    assert all(close(a, b) for a, b in zip(x2, want + [0, 0]))

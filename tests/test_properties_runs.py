"""Properties of whole runs (issue 8), on random small well-posed mechanical systems (section 8):

    M q'' + K q = E^T u,   y = E q,   0 <= y ⊥ u >= 0,

M diagonal positive, K symmetric positive definite and tridiagonal (a chain of springs), often no
damping and sometimes a passive one (C = c I, c > 0: then M q'' + C q' + K q = E^T u), one or two
stops (E of full row rank: well-posed by Theorem 8.2), rational data and random feasible rational
initial states (E q0 >= 0).  Hypothesis, bounded and derandomized.

(a) complementarity at certified sample points strictly inside each phase: u >= 0, y >= 0 and
    u_i y_i = 0, each sign certified by the library's exact sign decisions; y and u are also
    recomputed independently from the state (y = E q; on a contact phase in mode I,
    u_I = (E_I M^-1 E_I^T)^-1 E_I M^-1 K q, from y_I'' = 0, reference.mechanics) and must overlap
    the library's balls;
(b) the semigroup property: 0 -> T equals 0 -> t1 -> T, restarting from the exact state
    traj.state(t1) at a rational t1 strictly inside a phase: same events (times as overlapping
    25-digit balls, same modes) and the same final state (25 digits);
(c) energy 1/2 v^T M v + 1/2 q^T K q is constant on every phase of an undamped system (the
    contact force does no work: u^T E q' = u^T y' = 0), decreases along a damped one, and drops at
    each impact by exactly 1/2 (v- - v+)^T M (v- - v+) (Carnot: Moreau's rule projects v- onto
    the tangent cone in the M-metric), so it never increases; compared by balls.

Each property is checked to be non-vacuous over the examples (runs with events, contact phases with
u > 0 certified, strict energy losses), and its comparison to be sharp: a deliberately wrong
variant (a wrong energy, a shifted restart time, a doubled stiffness) must fail it.
"""
from __future__ import annotations

from collections import Counter
from fractions import Fraction as Fr

import pytest
from flint import arb, fmpq, fmpq_mat
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from lcs_exact import simulate
from lcs_exact.numbers.balls import workprec
from lcs_exact.models import mechanical

from reference.mechanics import contact_force_matrix

SETTINGS = dict(derandomize=True, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                       HealthCheck.data_too_large])
PREC = 256      # bits for the test's own ball arithmetic
DIGITS = 25     # digits of the comparisons

# ---------------------------------------------------------------------------------------------
# random systems and states
# ---------------------------------------------------------------------------------------------

POSITIVE = [Fr(1), Fr(2), Fr(3), Fr(1, 2), Fr(3, 2), Fr(5, 4)]
STOPS_2 = [((1, 0),), ((0, 1),), ((1, 0), (0, 1)), ((1, -1),), ((1, 0), (1, -1))]
GRID = [Fr(n, d) for d in (1, 2, 3, 4) for n in range(-4 * d, 4 * d + 1) if abs(Fr(n, d)) <= 1]


@st.composite
def cases(draw):
    """(M, K, E, x0, T): a chain of m in {1, 2} masses with springs k0 (wall - mass 0), k1
    (mass 0 - mass 1), k2 (mass 1 - wall, may be 0); stops E q >= 0; a feasible x0 = (q, v)."""
    m = draw(st.sampled_from([1, 2, 2, 2]))  # one mass soon rests at its stop: mostly two
    masses = [draw(st.sampled_from(POSITIVE)) for _ in range(m)]
    k0 = draw(st.sampled_from(POSITIVE))
    if m == 1:
        K, E = [[k0]], [[Fr(1)]]
    else:
        k1 = draw(st.sampled_from(POSITIVE))
        k2 = draw(st.sampled_from([Fr(0), Fr(1), Fr(2)]))
        K = [[k0 + k1, -k1], [-k1, k1 + k2]]
        E = [[Fr(v) for v in r] for r in draw(st.sampled_from(STOPS_2))]
    M = [[masses[i] if i == j else Fr(0) for j in range(m)] for i in range(m)]
    q = [draw(st.sampled_from(GRID)) for _ in range(m)]
    assume(all(sum(e * x for e, x in zip(r, q)) >= 0 for r in E))  # feasible: E q0 >= 0
    v = [2 * draw(st.sampled_from(GRID)) for _ in range(m)]
    T = draw(st.sampled_from([Fr(4), Fr(6), Fr(15, 2)]))
    c = draw(st.sampled_from([Fr(0), Fr(0), Fr(0), Fr(1, 10), Fr(1, 2)]))  # passive damping c I, often 0
    C = [[c if i == j else Fr(0) for j in range(m)] for i in range(m)]
    return M, K, E, C, q + v, T


def build(M, K, E, C):
    s = lambda a: [[str(x) for x in r] for r in a]  # noqa: E731
    return mechanical(s(M), s(K), s(E), damping=s(C))


def Q(x: Fr) -> fmpq:
    return fmpq(x.numerator, x.denominator)


# ---------------------------------------------------------------------------------------------
# ball helpers (the exact contact forces: reference.mechanics.contact_force_matrix)
# ---------------------------------------------------------------------------------------------

def lin(row, xs):
    """sum row_j x_j for rational row and arb xs."""
    out = arb(0)
    for c, x in zip(row, xs):
        if c:
            out += arb(Q(c)) * x
    return out


def quad(A, xs):
    """xs^T A xs / 2 for a rational symmetric A and arb xs."""
    return sum((arb(Q(A[i][j])) * xs[i] * xs[j] for i in range(len(xs)) for j in range(len(xs)) if A[i][j]),
               arb(0)) / 2


def energy(x, M, K):
    m = len(M)
    return quad(M, x[m:]) + quad(K, x[:m])


def balls(vec, digits=DIGITS + 5):
    return vec.ball(digits)


def interior_times(phase, fracs=(Fr(1, 5), Fr(1, 2), Fr(4, 5))):
    """Rational (dyadic) times strictly inside a phase, certified by balls."""
    out = []
    with workprec(PREC):
        a, b = phase.t0.arb(PREC), phase.t1.arb(PREC)
        for f in fracs:
            m = (a + (b - a) * arb(Q(f))).mid()
            t = fmpq(int((m * 2**48).floor().unique_fmpz()), 2**48)
            if a < arb(t) < b:
                out.append(t)
    return out


def unit(k, i):
    return fmpq_mat(1, k, [int(j == i) for j in range(k)])


# ---------------------------------------------------------------------------------------------
# (a) complementarity at sample points
# ---------------------------------------------------------------------------------------------

def check_complementarity(case, stats):
    M, K, E, C, x0, T = case
    lcs = build(M, K, E, C)
    k, m = len(E), len(M)
    traj = simulate(lcs, [str(v) for v in x0], str(T))
    assert traj.certified and not traj.partial
    stats["runs"] += 1
    stats["events"] += len(traj.events)
    for ph in traj.phases:
        I = ph.mode
        G = contact_force_matrix(M, K, E, C, I) if I else None
        for t in interior_times(ph):
            u, y = traj.u(t), traj.y(t)
            su = [u.sign_of_form(unit(k, i)) for i in range(k)]
            sy = [y.sign_of_form(unit(k, i)) for i in range(k)]
            # certified signs: u >= 0, y >= 0, u_i y_i = 0, and the mode says which one is zero
            assert all(s >= 0 for s in su + sy), (t, su, sy)
            assert all(a * b == 0 for a, b in zip(su, sy))
            assert all(sy[i] == 0 for i in I) and all(su[i] == 0 for i in range(k) if i not in I)
            # independent values from the state: y = E q; u_I = G q on a contact phase
            with workprec(PREC):
                x = balls(traj.state(t))
                yb, ub = balls(y), balls(u)
                for i in range(k):
                    assert lin(E[i], x[:m]).overlaps(yb[i]), (t, i, "y")
                for r, i in enumerate(sorted(I)):
                    mine = lin(G[r], x)
                    assert mine.overlaps(ub[i]), (t, i, "u")
                    if su[i] > 0:
                        stats["contact samples, u > 0"] += 1
                        # sharpness: a doubled stiffness gives another force, and it is seen
                        if not lin([2 * g for g in G[r]], x).overlaps(ub[i]):
                            stats["doubled stiffness caught"] += 1
                stats["samples"] += 1


@pytest.mark.slow
def test_complementarity_at_certified_sample_points():
    stats = Counter()

    @settings(max_examples=100, **SETTINGS)
    @given(cases())
    def run(case):
        check_complementarity(case, stats)

    run()
    assert stats["runs"] >= 90 and stats["events"] >= 150 and stats["samples"] >= 600, stats
    assert stats["contact samples, u > 0"] >= 100, stats
    assert stats["doubled stiffness caught"] >= stats["contact samples, u > 0"] - 2, stats


# ---------------------------------------------------------------------------------------------
# (b) the semigroup property
# ---------------------------------------------------------------------------------------------

def same_real(a, b) -> bool:
    return a.ball(DIGITS).overlaps(b.ball(DIGITS))


def check_semigroup(case, which, stats):
    M, K, E, C, x0, T = case
    lcs = build(M, K, E, C)
    Tq = Q(T)
    full = simulate(lcs, [str(v) for v in x0], Tq)
    ph = full.phases[which % len(full.phases)]
    times = interior_times(ph, (Fr(1, 3),))
    assume(times)
    t1 = times[0]
    rest = simulate(lcs, full.state(t1), Tq - t1)
    assert rest.certified and not rest.partial
    later = [e for e in full.events if e.time.ball(DIGITS) > arb(t1)]
    assert len(rest.events) == len(later), (t1, len(rest.events), len(later))
    with workprec(PREC):
        for e1, e2 in zip(later, rest.events):
            assert e1.time.ball(DIGITS).overlaps(e2.time.ball(DIGITS) + arb(t1))
            assert (e1.mode_before, e1.modes, e1.mode_after) == (e2.mode_before, e2.modes, e2.mode_after)
            assert all(a.overlaps(b) for a, b in zip(balls(e1.state_after, DIGITS), balls(e2.state_after, DIGITS)))
    end_full, end_rest = balls(full.state(Tq), DIGITS), balls(rest.state(Tq - t1), DIGITS)
    assert all(a.overlaps(b) for a, b in zip(end_full, end_rest)), (end_full, end_rest)
    stats["restarts"] += 1
    stats["events after t1"] += len(later)
    # sharpness: the same comparison against the state 1/1000 earlier fails when the state moves
    if Tq - t1 > fmpq(1, 1000):
        shifted = balls(rest.state(Tq - t1 - fmpq(1, 1000)), DIGITS)
        if not all(a.overlaps(b) for a, b in zip(end_full, shifted)):
            stats["shift caught"] += 1


@pytest.mark.slow
def test_semigroup_0_t1_T():
    stats = Counter()

    @settings(max_examples=80, **SETTINGS)
    @given(cases(), st.integers(0, 3))
    def run(case, which):
        check_semigroup(case, which, stats)

    run()
    assert stats["restarts"] >= 60 and stats["events after t1"] >= 50, stats
    assert stats["shift caught"] >= stats["restarts"] // 2, stats


# ---------------------------------------------------------------------------------------------
# (c) energy never increases
# ---------------------------------------------------------------------------------------------

def check_energy(case, stats):
    M, K, E, C, x0, T = case
    lcs = build(M, K, E, C)
    damped = any(C[i][i] for i in range(len(C)))
    m = len(M)
    traj = simulate(lcs, [str(v) for v in x0], str(T))
    wrong_M = [[Fr(int(i == j)) for j in range(m)] for i in range(m)]  # forgets the masses
    off = 1 if traj.events and traj.events[0].mode_before is None else 0  # a jump at t = 0 comes first
    with workprec(PREC):
        timeline = [energy([arb(Q(v)) for v in x0], M, K)]  # energies in time order
        if off:
            e = traj.events[0]
            assert energy(balls(e.state_before), M, K).overlaps(timeline[0])
        for i, ph in enumerate(traj.phases):
            if i == 0 and off or i > 0:
                e = traj.events[i - 1 + off]
                before, after = balls(e.state_before), balls(e.state_after)
                Eb, Ea = energy(before, M, K), energy(after, M, K)
                # Carnot: the loss is 1/2 (v- - v+)^T M (v- - v+) exactly; positions do not jump
                dv = [b - a for a, b in zip(after[m:], before[m:])]
                assert (Eb - Ea).overlaps(quad(M, dv)), (e, Eb - Ea, quad(M, dv))
                assert all(a.overlaps(b) for a, b in zip(before[:m], after[:m]))
                if Eb - Ea > 0:
                    stats["strict losses"] += 1
                timeline += [Eb, Ea]
            start = energy(balls(traj.state(ph.t0)), M, K)
            wrong_start = energy(balls(traj.state(ph.t0)), wrong_M, K)
            for t in interior_times(ph):
                x = balls(traj.state(t))
                now = energy(x, M, K)
                if damped:  # dE/dt = -v^T C v <= 0: no certified increase (checked on the timeline)
                    stats["damped samples, strict loss"] += bool(now < timeline[-1])
                else:       # conservative along the phase (the contact force does no work)
                    assert now.overlaps(start), (t, now, start)
                    stats["samples"] += 1
                    if not energy(x, wrong_M, K).overlaps(wrong_start):
                        stats["wrong energy caught"] += 1
                timeline.append(now)
            end = traj.events[i + off].state_before if i + off < len(traj.events) else traj.state(ph.t1)
            Eend = energy(balls(end), M, K)
            assert damped or Eend.overlaps(start)
            timeline.append(Eend)
        # never increases: no certified increase between any two consecutive points in time
        assert not any(b > a for a, b in zip(timeline, timeline[1:])), timeline
    stats["events"] += len(traj.events)


@pytest.mark.slow
def test_energy_never_increases():
    stats = Counter()

    @settings(max_examples=100, **SETTINGS)
    @given(cases())
    def run(case):
        check_energy(case, stats)

    run()
    assert stats["events"] >= 150 and stats["strict losses"] >= 100 and stats["samples"] >= 200, stats
    assert stats["wrong energy caught"] >= 150 and stats["damped samples, strict loss"] >= 100, stats

"""Scenes the exact core must survive (issue "the exact core, version 2"): long runs, decidable
signs of tiny values, exact zeros that are not structural, near-coincident impacts, stiff
circuits.  Every expected value is derived in the test (by hand or with mpmath)."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest
import sympy as sp

from flint import fmpq

import lcs_exact as L
from lcs_exact.numbers.balls import dyadic_lower
from lcs_exact.models import mechanical, two_carts_with_hook

mp.mp.dps = 60


def num(r, digits=40):
    return mp.mpf(r.ball(digits).mid().str(digits + 5, radius=False))


def close(a, b, tol=mp.mpf(10) ** -28):
    return abs(a - b) <= tol * max(1, abs(b))


# --------------------------------------------------------------------------------------------
# a long run: two masses (m = 1, 2), wall springs 3 and 1, coupling 2, a stop on q1
# --------------------------------------------------------------------------------------------
LONG = ([[0, 0, 1, 0], [0, 0, 0, 1], [-5, 2, 0, 0], [1, "-3/2", 0, 0]], [[0], [0], [1], [0]],
        [[1, 0, 0, 0]], [[0]])
LONG_X0 = [1, Fraction(1, 3), 0, Fraction(1, 2)]


def _first_impact_mpmath():
    """The first time q1 reaches the stop from LONG_X0 (free flight, mpmath's expm + findroot)."""
    A = mp.matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-5, 2, 0, 0], [1, mp.mpf(-3) / 2, 0, 0]])
    x0 = mp.matrix([1, mp.mpf(1) / 3, 0, mp.mpf(1) / 2])
    q1 = lambda t: (mp.expm(A * t) * x0)[0]  # noqa: E731
    ts = [k / 100 for k in range(1, 400)]
    a = next(t for t, u in zip(ts, ts[1:]) if q1(t) > 0 > q1(u))
    return mp.findroot(q1, (a, a + mp.mpf(1) / 100), solver="anderson")


@pytest.mark.slow
def test_thousand_events_run_flat_and_certified():
    """1000 events end in LimitExceeded (max_events) with the partial trajectory - never a
    RecursionError; times increase, the first one is mpmath's, every impact zeroes v1 (Moreau),
    and the 1000th event time can be refined to 30 digits afterwards."""
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(L.LCS(*LONG), LONG_X0, 10**6, max_events=1000)
    tr = err.value.trajectory
    assert tr.partial and tr.status is L.trajectory.Status.EVENT_LIMIT and len(tr.events) == 1000
    assert tr.certified
    assert close(num(tr.events[0].time), _first_impact_mpmath())
    times = [e.time.ball(20) for e in tr.events]
    assert all(a < b for a, b in zip(times, times[1:]))
    impacts = [e for e in tr.events if e.modes]
    assert len(impacts) >= 300
    assert all(e.state_after[2].ball(20).contains(0) and e.state_after[0].rational() == 0 for e in impacts[-5:])
    last = tr.events[-1].time.ball(30)
    assert last.rel_accuracy_bits() >= 100


# --------------------------------------------------------------------------------------------
# decidable signs of tiny values
# --------------------------------------------------------------------------------------------

def test_hook_gap_of_minus_5e_21_selects_the_hook():
    """x0 = e^{A 10^-10}(1, 1, 0, 0) in Example 8.3: q1 - q2 = -t^2/2 + O(t^4) = -5e-21 < 0 (from
    A(1,1,0,0) = (0,0,-1,0) and A^2 (1,1,0,0) = (-1,0,0,0) computed by hand): the hook must act."""
    h = two_carts_with_hook()
    x0 = L.expm_action(h.A, "1/10000000000", [1, 1, 0, 0])
    gap = num(x0[0], 40) - num(x0[1], 40)
    assert abs(gap + mp.mpf("5e-21")) < mp.mpf("1e-40")
    assert h.select_modes(x0) == {frozenset({1})}


# --------------------------------------------------------------------------------------------
# exact zeros beyond structure: a return after exactly pi (free-mode frequencies 1 and 2)
# --------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_period_pi_return_from_an_irrational_release():
    """M = diag(1, 1/2), K = [[2, -1], [-1, 3/2]]: M^-1 K = [[2, -1], [-2, 3]], eigenvalues 1 and
    4 (eigenvectors (1, 1), (1, -2)).  From q = 0, v = (0, w), w = sqrt 2:
    q(t) = (w/3) sin t (1, 1) - (w/6) sin 2t (1, -2), so q1 = (w/3) sin t (1 - cos t) >= 0 returns
    to the stop at exactly pi with q2 = (w/3)(sin t + sin 2t) = 0, v = (-2w/3, w/3).  The impact
    leaves (0, 0, 0, w/3) = (1/3) x0 (lift-off: q1''' = v2 > 0), so the events are k pi with
    x(k pi+) = (0, 0, 0, w / 3^k); the returning coordinates are exactly 0 and the run is
    certified."""
    lcs = mechanical([[1, 0], [0, "1/2"]], [[2, -1], [-1, "3/2"]], [[1, 0]])
    w = sp.sqrt(2)
    tr = L.simulate(lcs, [0, 0, 0, w], 10)
    assert tr.certified and len(tr.events) == 3
    for k, e in enumerate(tr.events, 1):
        assert sp.simplify(e.time.closed_form - k * sp.pi) == 0
        assert e.modes == (frozenset({0}),) and e.mode_after == frozenset()
        assert e.state_before[0].rational() == 0 and e.state_before[1].rational() == 0
        assert e.state_after[1].rational() == 0 and e.state_after[2].rational() == 0
        v = mp.sqrt(2) / 3 ** k
        assert close(num(e.state_before[2]), -2 * v) and close(num(e.state_after[3]), v)


# --------------------------------------------------------------------------------------------
# near-coincident impacts: the chain of 16 carts
# --------------------------------------------------------------------------------------------

def chain16_stiffness():
    """K of the chain, written out here for the independent mpmath derivation."""
    N = 16
    K = [[2 if i == j else -1 if abs(i - j) == 1 else 0 for j in range(N)] for i in range(N)]
    K[N - 1][N - 1] = 1
    return K


@pytest.mark.slow
def test_chain_of_16_carts_to_t_10():
    """q0 = (1, -1, 1, ...)/2, v0 = 0, stops on carts 0, 2, ..., 14: eight impacts (each stop
    once), all but one within 2e-4 of pi/4 and some 1e-16 apart, certified (its time per event
    is measured in benchmarks/scale.py, not here).  The first impact (cart 14) is checked against mpmath: q(t) = cos(sqrt(K) t)
    q0 through the eigendecomposition of the symmetric K."""
    lcs, K = L.examples.cart_chain(16), chain16_stiffness()
    assert all(lcs.A[16 + i, j] == -K[i][j] for i in range(16) for j in range(16))
    q0 = [Fraction((-1) ** i, 2) for i in range(16)]
    tr = L.simulate(lcs, q0 + [0] * 16, 10)
    assert tr.certified and not tr.partial
    impacts = [e for e in tr.events if any(t.startswith("y_") for t in e.triggers)]
    assert sorted(t for e in impacts for t in e.triggers) == sorted(f"y_{i}" for i in range(8))
    Km = mp.matrix(K)
    ev, V = mp.eigsy(Km)
    c = V.T * mp.matrix([mp.mpf(q.numerator) / q.denominator for q in q0])
    q14 = lambda t: sum(V[14, j] * mp.cos(mp.sqrt(ev[j]) * t) * c[j] for j in range(16))  # noqa: E731
    want = mp.findroot(q14, mp.mpf("0.7725"))
    assert close(num(tr.events[0].time), want, mp.mpf(10) ** -25)
    assert tr.events[0].triggers == ("y_7",)
    close_pairs = [b.time.ball(30) - a.time.ball(30) for a, b in zip(tr.events, tr.events[1:])]
    assert any(d < mp.mpf("1e-15") for d in close_pairs)


# --------------------------------------------------------------------------------------------
# a stiff RC-diode circuit: time constants from 5e-7 to 0.5
# --------------------------------------------------------------------------------------------

def test_stiff_rc_diode_circuit_against_mpmath():
    """Three nodes, capacitances 1, 1e-3, 1e-6, each with 1 ohm to ground and 1 ohm between
    neighbours (v' = -C^-1 G v; eigenvalues ~ -2e6, -3e3, -2); an ideal diode from ground to node
    2 (y = v2 >= 0, u its current).  From v = (-1, 1, 1) node 2 is pulled below 0 at mpmath's
    root of v2(t) = (e^{At} v0)_2; the diode then conducts for good (u > 0: v1 < 0 decays)."""
    A = [[-2, 1, 0], [1000, -3000, 1000], [0, 10**6, -2 * 10**6]]
    lcs = L.LCS(A, [[0], [1000], [0]], [[0, 1, 0]], [[0]])
    tr = L.simulate(lcs, [-1, 1, 1], 5)
    assert tr.certified and len(tr.events) == 1 and tr.events[0].mode_after == frozenset({0})
    Am, x0 = mp.matrix(A), mp.matrix([-1, 1, 1])
    want = mp.findroot(lambda t: (mp.expm(Am * t) * x0)[1], (mp.mpf("0.0004"), mp.mpf("0.0006")),
                       solver="anderson")
    assert close(num(tr.events[0].time), want)
    x5 = tr.state(5)
    assert x5[1].rational() == 0  # clamped by the diode: structural


# --------------------------------------------------------------------------------------------
# an impact cascade near a corner (three contacts): a right-accumulation proven without a law
# --------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_impact_cascade_stops_with_a_certified_enclosure():
    """M = diag(2, 3, 2), springs 2 between neighbours and 4 to the walls, contacts q0 >= 0,
    q1 - q0 >= 0, q2 - q1 >= 0, from q = (1/4, 3/4, 7/8), v = (-3/4, -1/4, 0): impacts on the
    first two contacts alternate with gaps shrinking like g^3 near t ~ 1.3654.  No law exists;
    the cascade is proven on a family of states, so the run stops with ZenoDetected carrying a
    certified enclosure lower <= T* <= upper after the last event computed (the accumulation
    time itself is checked against an independent run in tests/test_cascades.py), the partial
    trajectory kept.  The first impact (mass 0 at the wall, free flight) is checked against
    mpmath."""
    lcs = mechanical([[2, 0, 0], [0, 3, 0], [0, 0, 2]], [[6, -2, 0], [-2, 4, -2], [0, -2, 6]],
                     [[1, 0, 0], [-1, 1, 0], [0, -1, 1]])
    x0 = [Fraction(1, 4), Fraction(3, 4), Fraction(7, 8), Fraction(-3, 4), Fraction(-1, 4), 0]
    with pytest.raises(L.ZenoDetected) as err:
        L.simulate(lcs, x0, 12)
    e = err.value
    tr = e.trajectory
    assert tr.partial and tr.status is L.trajectory.Status.ZENO and len(tr.events) >= 6
    A = mp.matrix([[0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1],
                   [-3, 1, 0, 0, 0, 0], [mp.mpf(2) / 3, -mp.mpf(4) / 3, mp.mpf(2) / 3, 0, 0, 0],
                   [0, 1, -3, 0, 0, 0]])  # -M^-1 K by hand
    xm = mp.matrix([mp.mpf(1) / 4, mp.mpf(3) / 4, mp.mpf(7) / 8, -mp.mpf(3) / 4, -mp.mpf(1) / 4, 0])
    t1 = mp.findroot(lambda t: (mp.expm(A * t) * xm)[0], (mp.mpf("0.3"), mp.mpf("0.4")), solver="anderson")
    assert close(num(tr.events[0].time), t1) and tr.events[0].triggers == ("y_0",)
    last = tr.events[-1].time.ball(40)
    assert e.lower is not None and e.upper is not None and e.time is None
    assert e.lower >= dyadic_lower(last) and e.lower < e.upper and e.upper - e.lower < fmpq(1, 10 ** 30)
    assert 1.3654 < float(e.lower) < 1.3655
    gaps = [b.time.ball(30) - a.time.ball(30) for a, b in zip(tr.events[-4:], tr.events[-3:])]
    assert all(b < a / 2 for a, b in zip(gaps, gaps[1:]))


def test_eleven_independent_blocks_above_the_p_test_limit():
    """Eleven uncoupled 2-state systems x' = [[0, 1], [-(i + 1), 0]] x + u, y = x + D u with the
    nonsymmetric P-matrix D = [[1, 2], [0, 1]] (its symmetric part is not positive definite): k =
    22, above the enumeration limit of the P-matrix test, which now goes block by block.  The
    run is certified and its events are the union of the eleven systems' own runs: as many, at
    the same times (30-digit balls overlap), the block's constraint 2i + l at copy i's l."""
    from fractions import Fraction as Fr
    from flint import fmpq_mat as M
    from lcs_exact import LCS, simulate
    c = 11
    bases = [LCS([[0, 1], [-(i + 1), 0]], [[1, 0], [0, 1]], [[1, 0], [0, 1]], [[1, 2], [0, 1]]) for i in range(c)]
    A, B, C, D = (M(2 * c, 2 * c, [0] * (4 * c * c)) for _ in range(4))
    for i, s in enumerate(bases):
        for r in range(2):
            for q in range(2):
                A[2 * i + r, 2 * i + q], B[2 * i + r, 2 * i + q] = s.A[r, q], s.B[r, q]
                C[2 * i + r, 2 * i + q], D[2 * i + r, 2 * i + q] = s.C[r, q], s.D[r, q]
    x0 = [v for i in range(c) for v in (Fr(1, i + 2), Fr(-1, 3))]
    tr = simulate(LCS(A, B, C, D), x0, 2)
    assert tr.certified and tr.status.name == "COMPLETE"
    single = []
    for i, s in enumerate(bases):
        for e in simulate(s, x0[2 * i:2 * i + 2], 2).events:
            single.append((e.time.ball(30), {f"{t[0]}_{2 * i + int(t[2:])}" for t in e.triggers}))
    single.sort(key=lambda p: p[0].mid())
    assert len(tr.events) == len(single) == 33
    for e, (t, trig) in zip(tr.events, single):
        assert e.time.ball(30).overlaps(t) and set(e.triggers) == trig

"""Algorithm 7.1 against answers derived independently of the library.

Every expected value here comes from a hand analysis (closed forms, written out in the comments)
or from mpmath at 60 digits applied to formulas written in this file (mpmath.expm of the
closed-loop matrices derived by hand, mpmath.findroot on analytic modal solutions) or in
``reference.flows`` (root location on a grid, a relative-degree-0 simulator); nothing is
taken from the library.  Event times and states are compared at a relative tolerance of 1e-25
(absolute 1e-25 for values that are exactly zero) after a run at digits=30, and the true value
must lie inside the library's certified 30-digit ball.  Where the library claims a closed form,
it must be right.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest
import sympy as sp

import lcs_exact as L
from lcs_exact.models import mechanical, two_carts, two_carts_with_hook

from helpers import mpmath_digits
from reference.flows import first_root, mpvec, rd0_closed_loop, rd0_reference

mp.mp.dps = 60
TOL = mp.mpf(10) ** -25
DIGITS = 30


_mpmath_60_digits = mpmath_digits(60)  # every expected value is computed at 60 digits


# -------------------------------------------------------------------------------------------------
# comparison helpers
# -------------------------------------------------------------------------------------------------
def num(r) -> mp.mpf:
    """The library's exact real as an mpf (midpoint of a 40-digit ball)."""
    return mp.mpf(r.ball(40).mid().str(45, radius=False))


def check(r, want, cf=None, what: str = "") -> None:
    """r (an exact real of the library) equals want (mpmath, 60 digits) to 25 digits; the true value
    lies in r's certified 30-digit ball; if r claims a closed form it is right (== cf when given)."""
    want = mp.mpf(want)
    got = num(r)
    if abs(want) < mp.mpf(10) ** -45:  # an exact zero (a 60-digit computation of 0 leaves ~1e-60)
        want = mp.mpf(0)
    if want == 0:
        assert abs(got) <= TOL, f"{what}: got {got}, want 0"
    else:
        assert abs(got - want) <= TOL * abs(want), f"{what}: got {got}, want {want}"
    b = r.ball(DIGITS)
    mid = mp.mpf(b.mid().str(80, radius=False))
    rad = mp.mpf(b.rad().str(10, radius=False)) if not b.is_exact() else mp.mpf(0)
    assert abs(want - mid) <= rad + mp.mpf(10) ** -50 * max(1, abs(want)), \
        f"{what}: {want} not in the certified ball {b}"
    if r.closed_form is not None:
        if cf is not None:
            assert sp.simplify(r.closed_form - cf) == 0, f"{what}: closed form {r.closed_form} != {cf}"
        else:
            v = mp.mpf(str(sp.N(r.closed_form, 55)))
            assert abs(v - want) <= mp.mpf(10) ** -45 * max(1, abs(want)), \
                f"{what}: claimed closed form {r.closed_form} = {v} != {want}"


def check_vec(v, want, cfs=None, what: str = "") -> None:
    v = list(v)
    assert len(v) == len(want)
    for i, (r, w) in enumerate(zip(v, want)):
        check(r, w, None if cfs is None else cfs[i], f"{what}[{i}]")


def is_exact_zero(r) -> bool:
    q = r.rational()
    return q is not None and q == 0


# -------------------------------------------------------------------------------------------------
# 1. a 2-dof mechanical chain with a unilateral stop on the first mass
# -------------------------------------------------------------------------------------------------
# Wall -- k1 = 2 -- mass m1 = 1 -- k2 = 2 -- mass m2 = 2.  Stop y = q1 >= 0, inelastic.
#   M = diag(1, 2), K = [[k1 + k2, -k2], [-k2, k2]] = [[4, -2], [-2, 2]], x = (q1, q2, q1', q2').
# Free motion: q'' = -W q, W = M^-1 K = [[4, -2], [-1, 1]], eigenvalues l = (5 -+ sqrt(17))/2,
# eigenvectors (2, 4 - l); from rest q(t) = sum_i c_i phi_i cos(w_i t), w_i = sqrt(l_i).
# Impact at the first zero t1 of q1 (q1' < 0 there).  Moreau (M diagonal, E = [1, 0]):
# v+ = v- + M^-1 E^T lam with E v+ = 0: q1' -> 0, q2' unchanged.
# Constrained mode {0}: q1 = 0, m2 q2'' = -k2 q2 -> q2'' = -q2; contact force from
# m1 q1'' = -(4 q1 - 2 q2) + u = 0: u = -2 q2, positive while q2 < 0.  Lift-off when q2 = 0:
# s* = atan(-q2(t1) / q2'(t1)) (both q2(t1) < 0 and q2'(t1) > 0 here), state (0, 0, 0, V),
# V = sqrt(q2(t1)^2 + q2'(t1)^2).
CHAIN_M = [[1, 0], [0, 2]]
CHAIN_K = [[4, -2], [-2, 2]]
CHAIN_A = [[0, 0, 1, 0], [0, 0, 0, 1], [-4, 2, 0, 0], [1, -1, 0, 0]]  # written by hand: -M^-1 K


def chain_expected():
    s17 = mp.sqrt(17)
    lam = [(5 - s17) / 2, (5 + s17) / 2]
    w = [mp.sqrt(x) for x in lam]
    phi = [(mp.mpf(2), 4 - x) for x in lam]
    c = mp.lu_solve(mp.matrix([[phi[0][0], phi[1][0]], [phi[0][1], phi[1][1]]]), mp.matrix([1, -1]))

    def q(t, j):
        return sum(c[i] * phi[i][j] * mp.cos(w[i] * t) for i in range(2))

    def v(t, j):
        return sum(-c[i] * phi[i][j] * w[i] * mp.sin(w[i] * t) for i in range(2))

    t1 = first_root(lambda t: q(t, 0), 0, 5, mp.mpf(1) / 100)
    before = [mp.mpf(0), q(t1, 1), v(t1, 0), v(t1, 1)]
    after = [mp.mpf(0), before[1], mp.mpf(0), before[3]]
    assert before[2] < 0 and before[1] < 0 and before[3] > 0  # impact, u = -2 q2 > 0, then release
    s = mp.atan(-before[1] / before[3])
    t2 = t1 + s
    V = mp.sqrt(before[1] ** 2 + before[3] ** 2)
    return dict(t1=t1, before=before, after=after, t2=t2, V=V, q2=before[1], v2=before[3])


@pytest.fixture(scope="module")
def chain():
    lcs = mechanical(CHAIN_M, [[0, 0], [0, 0]], CHAIN_K, [[1, 0]])
    return L.simulate(lcs, [1, -1, 0, 0], Fraction(3, 2), digits=DIGITS)


def test_chain_data_matches_hand_derivation(chain):
    lcs = chain.lcs
    got_A = [[Fraction(int(lcs.A[i, j].p), int(lcs.A[i, j].q)) for j in range(4)] for i in range(4)]
    assert got_A == CHAIN_A
    # CB = 0, CAB = 1/m1 = 1: relative degree 2, D = 0
    assert lcs.D[0, 0] == 0 and lcs.B[2, 0] == 1 and lcs.B[3, 0] == 0


def test_chain_impact_and_liftoff(chain):
    ex = chain_expected()
    tr = chain
    assert tr.certified and not tr.partial
    assert len(tr.events) == 2
    e1, e2 = tr.events
    check(e1.time, ex["t1"], what="impact time")
    assert e1.mode_before == frozenset() and e1.mode_after == frozenset({0})
    assert e1.modes == (frozenset({0}),) and e1.multiplicity == 1
    check_vec(e1.state_before, ex["before"], what="x(t1-)")
    check_vec(e1.state_after, ex["after"], what="x(t1+)")
    assert is_exact_zero(e1.state_after[0]) and is_exact_zero(e1.state_after[2])
    # impulse of the inelastic impact: lam = -m1 q1'(t1-) (u = lam * delta)
    check(e1.impulse[0][0], -ex["before"][2], what="impulse")

    check(e2.time, ex["t2"], what="lift-off time")
    assert e2.mode_before == frozenset({0}) and e2.mode_after == frozenset() and e2.modes == ()
    check_vec(e2.state_before, [0, 0, 0, ex["V"]], what="x(t2-)")
    check_vec(e2.state_after, [0, 0, 0, ex["V"]], what="x(t2+)")


def test_chain_states_between_and_after(chain):
    ex = chain_expected()
    tr = chain
    # in the constrained phase: q2 = q2(t1) cos s + v2(t1) sin s, u = -2 q2
    t = Fraction(1)
    s = mp.mpf(1) - ex["t1"]
    q2 = ex["q2"] * mp.cos(s) + ex["v2"] * mp.sin(s)
    v2 = -ex["q2"] * mp.sin(s) + ex["v2"] * mp.cos(s)
    check_vec(tr.state(t), [0, q2, 0, v2], what="x(1)")
    check(tr.u(t)[0], -2 * q2, what="u(1)")
    # after the lift-off: free motion from (0, 0, 0, V), by mpmath.expm of the hand-written A
    A = mp.matrix(CHAIN_A)
    free = lambda tt: mp.expm(A * (tt - ex["t2"])) * mp.matrix([0, 0, 0, ex["V"]])  # noqa: E731
    # no further impact before t_end (q1 > 0 on the grid)
    assert all(free(ex["t2"] + k * (mp.mpf(3) / 2 - ex["t2"]) / 20)[0] > 0 for k in range(1, 21))
    check_vec(tr.state(Fraction(3, 2)), mpvec(free(mp.mpf(3) / 2)), what="x(3/2)")


# -------------------------------------------------------------------------------------------------
# 2. circuits with an ideal diode: D = 0, CB != 0 (relative degree 1)
# -------------------------------------------------------------------------------------------------
# 2a. LC circuit.  Node 1: capacitor C1 = 1 (voltage v1) to ground and an ideal diode from ground
# (anode) to node 1 (cathode), diode current u >= 0, y = v1 (cathode - anode voltage) >= 0;
# an inductor L = 1 (current i, from node 1) to node 2, capacitor C2 = 1 (voltage v2) to ground.
#   v1' = -i + u,  i' = v1 - v2,  v2' = i.   x = (v1, i, v2),  CB = 1, D = 0.
# Mode {} from x0 = (1, 0, -1): v1 + v2 = 0 is conserved, w = v1 - v2 satisfies w'' = -2w,
# w(0) = 2, w'(0) = 0: v1 = cos(sqrt2 t), i = sqrt2 sin(sqrt2 t), v2 = -cos(sqrt2 t).
# v1 = 0 first at t1 = pi/(2 sqrt2) = sqrt2 pi/4 with v1' = -i = -sqrt2 < 0: state (0, sqrt2, 0).
# Mode {0}: v1 = 0, i' = -v2, v2' = i, u = i: i = sqrt2 cos s, v2 = sqrt2 sin s; u = 0 at
# s = pi/2 (then negative): t2 = sqrt2 pi/4 + pi/2, state (0, 0, sqrt2).
# Mode {} again: v1 + v2 = sqrt2, w(0) = -sqrt2, w'(0) = 0: w = -sqrt2 cos(sqrt2 s),
# v1 = (sqrt2 - sqrt2 cos(sqrt2 s))/2 >= 0 (no event before s = sqrt2 pi > 3 - t2),
# i = -w'/2 = -sin(sqrt2 s), v2 = sqrt2 - v1.
LC_A = [[0, -1, 0], [1, 0, -1], [0, 1, 0]]


@pytest.fixture(scope="module")
def lc():
    lcs = L.LCS(LC_A, [[1], [0], [0]], [[1, 0, 0]], [[0]])
    return L.simulate(lcs, [1, 0, -1], 3, digits=DIGITS)


def test_lc_diode_is_relative_degree_one(lc):
    lcs = lc.lcs
    assert lcs.D[0, 0] == 0
    assert (lcs.C * lcs.B)[0, 0] == 1
    # leading row index (Markov parameter H_1 = CB is the first nonzero one): relative degree 1
    assert tuple(lcs.leading_row_indices()) == (1,)


def test_lc_diode_events(lc):
    tr = lc
    assert tr.certified and not tr.partial
    assert len(tr.events) == 2
    e1, e2 = tr.events
    r2 = mp.sqrt(2)
    t1 = r2 * mp.pi / 4
    check(e1.time, t1, sp.sqrt(2) * sp.pi / 4, "diode on")
    assert e1.mode_before == frozenset() and e1.mode_after == frozenset({0})
    assert e1.modes == () and e1.multiplicity == 0  # no jump: the state is consistent
    check_vec(e1.state_before, [0, r2, 0], [0, sp.sqrt(2), 0], "x(t1-)")
    check_vec(e1.state_after, [0, r2, 0], [0, sp.sqrt(2), 0], "x(t1+)")
    t2 = t1 + mp.pi / 2
    check(e2.time, t2, sp.sqrt(2) * sp.pi / 4 + sp.pi / 2, "diode off")
    assert e2.mode_before == frozenset({0}) and e2.mode_after == frozenset() and e2.modes == ()
    check_vec(e2.state_after, [0, 0, r2], [0, 0, sp.sqrt(2)], "x(t2+)")


def test_lc_diode_states(lc):
    tr = lc
    r2 = mp.sqrt(2)
    # t = 1/2 in mode {}
    t = mp.mpf(1) / 2
    check_vec(tr.state(Fraction(1, 2)), [mp.cos(r2 * t), r2 * mp.sin(r2 * t), -mp.cos(r2 * t)], what="x(1/2)")
    # t = 2 in mode {0}: diode current u = i
    s = 2 - r2 * mp.pi / 4
    check_vec(tr.state(2), [0, r2 * mp.cos(s), r2 * mp.sin(s)], what="x(2)")
    check(tr.u(2)[0], r2 * mp.cos(s), what="u(2)")
    # t = 3 in mode {}
    s = 3 - r2 * mp.pi / 4 - mp.pi / 2
    v1 = (r2 - r2 * mp.cos(r2 * s)) / 2
    check_vec(tr.state(3), [v1, -mp.sin(r2 * s), r2 - v1], what="x(3)")


# 2b. RC circuit.  Node 1: capacitor C1 = 1 (v1) and the diode as above (y = v1); a resistor R = 1
# between nodes 1 and 2; node 2: capacitor C2 = 1 (v2) and a resistor 2/3 to ground:
#   v1' = -(v1 - v2) + u,  v2' = (v1 - v2) - (3/2) v2.   A = [[-1, 1], [1, -5/2]], CB = 1.
# Eigenvalues -1/2 (eigenvector (2, 1)) and -3 (eigenvector (1, -2)); x0 = (1, -7) =
# -(2, 1) + 3 (1, -2): v1 = -2 e^{-t/2} + 3 e^{-3t} = 0 at e^{5t/2} = 3/2, t1 = (2/5) log(3/2).
# v2(t1) = -e^{-t1/2} - 6 e^{-3 t1} = -5 (2/3)^{1/5}.  Mode {0}: v1 = 0, u = -v2 > 0,
# v2' = -(5/2) v2, so v2 = -5 (2/3)^{1/5} e^{-5(t - t1)/2} and u stays positive: one event.
@pytest.fixture(scope="module")
def rc():
    lcs = L.LCS([[-1, 1], [1, "-5/2"]], [[1], [0]], [[1, 0]], [[0]])
    return L.simulate(lcs, [1, -7], 2, digits=DIGITS)


def test_rc_diode(rc):
    tr = rc
    assert tr.certified and not tr.partial
    assert (tr.lcs.C * tr.lcs.B)[0, 0] == 1 and tr.lcs.D[0, 0] == 0
    assert len(tr.events) == 1
    (e,) = tr.events
    t1 = mp.mpf(2) / 5 * mp.log(mp.mpf(3) / 2)
    check(e.time, t1, sp.Rational(2, 5) * sp.log(sp.Rational(3, 2)), "diode on")
    assert e.mode_before == frozenset() and e.mode_after == frozenset({0}) and e.modes == ()
    v2 = -5 * (mp.mpf(2) / 3) ** (mp.mpf(1) / 5)
    check_vec(e.state_after, [0, v2], [0, -5 * sp.Rational(2, 3) ** sp.Rational(1, 5)], "x(t1)")
    # before the event (mode {})
    t = mp.mpf(1) / 10
    check_vec(tr.state(Fraction(1, 10)), [-2 * mp.exp(-t / 2) + 3 * mp.exp(-3 * t),
                                          -mp.exp(-t / 2) - 6 * mp.exp(-3 * t)], what="x(1/10)")
    # after the event (mode {0})
    v2_at_2 = v2 * mp.exp(-mp.mpf(5) / 2 * (2 - t1))
    check_vec(tr.state(2), [0, v2_at_2], what="x(2)")
    check(tr.u(2)[0], -v2_at_2, what="u(2)")


# -------------------------------------------------------------------------------------------------
# 3. relative degree 0: D a P-matrix
# -------------------------------------------------------------------------------------------------
# 3a. A = diag(1, -2), B = (1, 0)^T, C = (1, 1), D = (1).  Mode {}: x = (-e^t, 4 e^{-2t}),
# y = Cx = -e^t + 4 e^{-2t} = 0 at e^{3t} = 4: t1 = log(4)/3, state (-a, a), a = 4^{1/3}.
# Mode {0}: u = -(x1 + x2), x1' = -x2, x2' = -2 x2: x2 = a e^{-2s},
# x1 = -a - (a/2)(1 - e^{-2s}), u = (3a/2)(1 - e^{-2s}) > 0: one event.
@pytest.fixture(scope="module")
def rd0():
    lcs = L.LCS([[1, 0], [0, -2]], [[1], [0]], [[1, 1]], [[1]])
    return L.simulate(lcs, [-1, 4], 2, digits=DIGITS)


def test_relative_degree_zero_scalar(rd0):
    tr = rd0
    assert tr.certified and not tr.partial
    assert len(tr.events) == 1
    (e,) = tr.events
    t1 = mp.log(4) / 3
    check(e.time, t1, sp.log(4) / 3, "theta")
    assert e.mode_before == frozenset() and e.mode_after == frozenset({0})
    assert e.modes == () and e.multiplicity == 0
    a = mp.mpf(4) ** (mp.mpf(1) / 3)
    cbrt4 = sp.Integer(4) ** sp.Rational(1, 3)
    check_vec(e.state_before, [-a, a], [-cbrt4, cbrt4], "x(t1)")
    check_vec(e.state_after, [-a, a], [-cbrt4, cbrt4], "x(t1)")
    s = 2 - t1
    check_vec(tr.state(2), [-a - a / 2 * (1 - mp.exp(-2 * s)), a * mp.exp(-2 * s)], what="x(2)")
    check(tr.u(2)[0], 3 * a / 2 * (1 - mp.exp(-2 * s)), what="u(2)")
    check(tr.y(2)[0], 0, what="y(2)")


# 3b. D = [[2, 1], [1, 2]] (positive definite), A = [[0, 1], [-1, 0]], B = C = I, x0 = (1, 1).
# Independent derivation: a small relative-degree-0 simulator in mpmath only (reference.flows.
# rd0_reference).  In a
# mode I, u_I = -D_II^-1 C_I x and x' = (A - B_I D_II^-1 C_I) x (solved with mpmath.expm); the
# phase ends at the first zero crossing of u_i (i in I) or y_j = C_j x + D_jI u_I (j not in I),
# found on a grid and refined with findroot; the next mode is the (smallest) solution of the
# 2x2 LCP (enumerated) at q = C x(t) + delta q'(t), delta = 1e-25 (q' = C(Ax + Bu), u continuous).
RD2 = dict(A=[[0, 1], [-1, 0]], B=[[1, 0], [0, 1]], C=[[1, 0], [0, 1]], D=[[2, 1], [1, 2]])


@pytest.mark.slow
def test_relative_degree_zero_two_by_two():
    lcs = L.LCS(RD2["A"], RD2["B"], RD2["C"], RD2["D"])
    assert lcs.well_posedness()
    T = 6
    tr = L.simulate(lcs, [1, 1], T, digits=DIGITS)
    assert tr.certified and not tr.partial
    ref, final_mode = rd0_reference(RD2["A"], RD2["B"], RD2["C"], RD2["D"], [1, 1], T)
    assert len(ref) >= 3  # the example is nontrivial
    assert len(tr.events) == len(ref)
    # first event by hand: mode {}: x = (cos t + sin t, cos t - sin t), y_1 = x2 = 0 at pi/4
    check(tr.events[0].time, mp.pi / 4, sp.pi / 4, "first event")
    check_vec(tr.events[0].state_after, [mp.sqrt(2), 0], [sp.sqrt(2), 0], "x(pi/4)")
    prev = frozenset()
    for n, (ev, want) in enumerate(zip(tr.events, ref)):
        check(ev.time, want["time"], what=f"event {n} time")
        assert ev.mode_before == want["before"] == prev, f"event {n}"
        assert ev.mode_after == want["after"], f"event {n}: {ev.mode_after} != {want['after']}"
        assert ev.modes == () and ev.multiplicity == 0  # relative degree 0: no jumps
        check_vec(ev.state_before, mpvec(want["state"]), what=f"event {n} x-")
        check_vec(ev.state_after, mpvec(want["state"]), what=f"event {n} x+")
        prev = want["after"]
    # final state by the reference's closed loop in the last mode
    AI, _ = rd0_closed_loop(*(mp.matrix(RD2[m]) for m in "ABCD"), final_mode)
    xT = mp.expm(AI * (T - ref[-1]["time"])) * ref[-1]["state"]
    check_vec(tr.state(T), mpvec(xT), what="x(T)")


# -------------------------------------------------------------------------------------------------
# 4. Section 8: the hook system, x0(eps) = (eps, eps, -2, 1)
# -------------------------------------------------------------------------------------------------
# y0 = q1 (stop), y1 = q1 - q2 (hook); M = I, K = [[2, -1], [-1, 1]].
# t = 0: y1 = 0, y1' = v1 - v2 = -3 < 0: the hook engages; Moreau along M^-1 E1^T = (1, -1):
#   v+ = (-2, 1) + (3/2)(1, -1) = (-1/2, -1/2): x(0+) = (eps, eps, -1/2, -1/2), mode {1}.
# Mode {1}: q1 = q2 = p, the pair (mass 2) on the wall spring (force -(2q1 - q2) - (q2 - q1) = -p):
#   2p'' = -p, p = eps cos(t/sqrt2) - (sqrt2/2) sin(t/sqrt2); hook force u1 = -q2'' = p/2 >= 0.
# Both p and u1 vanish at tan(t/sqrt2) = sqrt2 eps: t* = sqrt2 atan(sqrt2 eps), where
#   p'(t*) = -(1/2) sqrt(1 + 2 eps^2) =: w.   x(t*-) = (0, 0, w, w).
# Impact on the stop with both constraints closed: Moreau min |v - (w, w)| s.t. v1 >= 0,
# v1 - v2 >= 0 gives v+ = (0, w) (lam0 = -w > 0, lam1 = 0): x(t*+) = (0, 0, 0, w), mode {0}
# (hook opening: y1' = -w > 0).  x4 + 1/2 = -(sqrt(1 + 2 eps^2) - 1)/2, |x4 + 1/2| <= eps^2/2 -> 0.
# Mode {0}: q1 = 0, q2'' = -q2: q2 = w sin s, v2 = w cos s; u0 = 2q1 - q2 = -q2 >= 0, and the
# hook gap y1 = -q2 is the same function: both vanish at s = pi, x = (0, 0, 0, -w).
# There y1' = -v2 = w < 0: the hook engages again: jump along (1, -1) onto v1 = v2:
# x = (0, 0, -w/2, -w/2), mode {1} (u1 = p/2 starts at 0 and grows).  Then mode {1}:
# p = (-w/2) sqrt2 sin(s/sqrt2) > 0 until s = sqrt2 pi.
EPSILONS = [Fraction(1, 10), Fraction(1, 100), Fraction(1, 1000)]


def hook_expected(eps):
    e = mp.mpf(eps.numerator) / eps.denominator
    r2 = mp.sqrt(2)
    tstar = r2 * mp.atan(r2 * e)
    w = -mp.sqrt(1 + 2 * e * e) / 2
    es = sp.Rational(eps.numerator, eps.denominator)
    return dict(e=e, tstar=tstar, w=w, tstar_cf=sp.sqrt(2) * sp.atan(sp.sqrt(2) * es),
                w_cf=-sp.sqrt(1 + 2 * es ** 2) / 2)


@pytest.fixture(scope="module")
def hook_runs():
    return {eps: L.simulate(two_carts_with_hook(), [eps, eps, -2, 1], 1, digits=DIGITS) for eps in EPSILONS}


@pytest.mark.slow
@pytest.mark.parametrize("eps", EPSILONS, ids=str)
def test_hook_two_impacts(hook_runs, eps):
    tr = hook_runs[eps]
    ex = hook_expected(eps)
    e = ex["e"]
    assert tr.certified and not tr.partial
    assert len(tr.events) == 2
    e0, e1 = tr.events
    # t = 0: the hook jump
    check(e0.time, 0, 0, "t0")
    assert e0.mode_before is None and e0.modes == (frozenset({1}),) and e0.mode_after == frozenset({1})
    assert e0.multiplicity == 1
    half = sp.Rational(-1, 2)
    check_vec(e0.state_after, [e, e, -mp.mpf(1) / 2, -mp.mpf(1) / 2],
              [sp.Rational(eps.numerator, eps.denominator)] * 2 + [half, half], "x(0+)")
    # continuous phase in the hook mode, at t = eps (0 < eps < t* = sqrt2 atan(sqrt2 eps) < 2 eps)
    r2 = mp.sqrt(2)
    p = e * mp.cos(e / r2) - r2 / 2 * mp.sin(e / r2)
    dp = -e / r2 * mp.sin(e / r2) - mp.cos(e / r2) / 2
    x_mid = tr.state(eps)
    check_vec(x_mid, [p, p, dp, dp], what="x(eps)")
    u_mid = tr.u(eps)
    check(u_mid[1], p / 2, what="hook force")
    check(u_mid[0], 0, what="stop force")
    # t*: the stop is hit; the hook force vanishes at the same instant
    check(e1.time, ex["tstar"], ex["tstar_cf"], "t*")
    assert e1.mode_before == frozenset({1}) and e1.modes == (frozenset({0}),)
    assert e1.mode_after == frozenset({0}) and e1.multiplicity == 1
    w = ex["w"]
    check_vec(e1.state_before, [0, 0, w, w], [0, 0, ex["w_cf"], ex["w_cf"]], "x(t*-)")
    check_vec(e1.state_after, [0, 0, 0, w], [0, 0, 0, ex["w_cf"]], "x(t*+)")
    # the first three components are exactly 0 (proven rational)
    assert all(is_exact_zero(c) for c in list(e1.state_after)[:3])
    # x4 -> -1/2: |x4 + 1/2| = (sqrt(1 + 2 eps^2) - 1)/2 <= eps^2/2
    # mode {0} after t*: q2 = w sin(t - t*), v2 = w cos(t - t*), u0 = -q2 > 0, u1 = 0
    s = 1 - ex["tstar"]
    check_vec(tr.state(1), [0, w * mp.sin(s), 0, w * mp.cos(s)], what="x(1)")
    check_vec(tr.u(1), [-w * mp.sin(s), 0], what="u(1)")
    gap = abs(num(e1.state_after[3]) + mp.mpf(1) / 2)
    assert gap <= e * e / 2
    assert gap >= e * e / 2 * (1 - e * e)  # and it is really of order eps^2 (not smaller)


def test_hook_x4_tends_to_minus_half(hook_runs):
    gaps = [abs(num(hook_runs[eps].events[1].state_after[3]) + mp.mpf(1) / 2) for eps in EPSILONS]
    assert gaps[0] > gaps[1] > gaps[2] > 0
    assert gaps[2] < mp.mpf(10) ** -6


def test_hook_eps_zero_single_jump_to_origin():
    tr = L.simulate(two_carts_with_hook(), [0, 0, -2, 1], 1, digits=DIGITS)
    assert tr.certified and not tr.partial
    assert len(tr.events) == 1
    (e,) = tr.events
    assert e.time.rational() == 0
    # Moreau with both constraints closed: v - (-2, 1) = (l0 + l1, -l1), v = 0: l1 = 1, l0 = 1 >= 0
    assert all(is_exact_zero(c) for c in e.state_after)
    assert e.mode_after == frozenset()  # the origin is an equilibrium: u = 0
    x1 = tr.state(1)
    assert all(is_exact_zero(c) for c in x1)
    assert [c.rational() for c in x1] == [0, 0, 0, 0]


@pytest.mark.slow
def test_hook_through_liftoff_and_rehook():
    """eps = 1/10 up to t = 4: the third event at t* + pi (u0 and the hook gap y1 vanish together,
    the hook engages again: x = (0, 0, -w/2, -w/2), mode {1})."""
    eps = Fraction(1, 10)
    ex = hook_expected(eps)
    w = ex["w"]
    tr = L.simulate(two_carts_with_hook(), [eps, eps, -2, 1], 4, digits=DIGITS)
    assert tr.certified and not tr.partial
    assert len(tr.events) == 3
    e2 = tr.events[2]
    t3 = ex["tstar"] + mp.pi
    check(e2.time, t3, ex["tstar_cf"] + sp.pi, "t* + pi")
    assert e2.mode_before == frozenset({0}) and e2.modes == (frozenset({1}),)
    assert e2.mode_after == frozenset({1})
    wc = ex["w_cf"]
    check_vec(e2.state_before, [0, 0, 0, -w], [0, 0, 0, -wc], what="x(t*+pi-)")
    check_vec(e2.state_after, [0, 0, -w / 2, -w / 2], [0, 0, -wc / 2, -wc / 2], what="x(t*+pi+)")
    # closed forms are carried through the flow and the projection P_{1}
    assert e2.time.closed_form is not None
    assert e2.state_after.closed_form() is not None
    s = 4 - t3
    r2 = mp.sqrt(2)
    p = (-w / 2) * r2 * mp.sin(s / r2)
    dp = (-w / 2) * mp.cos(s / r2)
    check_vec(tr.state(4), [p, p, dp, dp], what="x(4)")


# -------------------------------------------------------------------------------------------------
# 5. Examples 4.4 / 4.5: the two carts
# -------------------------------------------------------------------------------------------------
# Mode {0} from (0, -1, 0, 0): x1 = x3 = 0, x2'' = x1 - x2 = -x2: x2 = -cos t, x4 = sin t;
# u = 2x1 - x2 = cos t = 0 at pi/2: x = (0, 0, 0, 1).
def test_example_4_4_release_at_pi_half():
    tr = L.simulate(two_carts(), [0, -1, 0, 0], 2, digits=DIGITS)
    assert tr.certified and not tr.partial
    assert len(tr.events) == 1
    (e,) = tr.events
    check(e.time, mp.pi / 2, sp.pi / 2, "release")
    assert e.time.closed_form is not None and sp.simplify(e.time.closed_form - sp.pi / 2) == 0
    assert e.mode_before == frozenset({0}) and e.mode_after == frozenset() and e.modes == ()
    assert [c.rational() for c in e.state_after] == [0, 0, 0, 1]
    t = mp.mpf(1)
    check_vec(tr.state(1), [0, -mp.cos(t), 0, mp.sin(t)], what="x(1)")
    check(tr.u(1)[0], mp.cos(t), what="u(1)")


# From (0, 1, -1, 0): x1 = 0 and x3 < 0: a jump at t = 0 to (0, 1, 0, 0) (Moreau: x3 -> 0), and
# since x1'' = x2 = 1 > 0 the cart leaves at once: mode {}.
# Free motion from (0, 1, 0, 0), by hand: K = [[2, -1], [-1, 1]] has w1 = (sqrt5 - 1)/2,
# w2 = (sqrt5 + 1)/2 = 1/w1; with orthonormal eigenvectors phi_i,
#   x1 = c (cos w1 t - cos w2 t), x4 = -(phi_12^2 w1 sin w1 t + phi_22^2 w2 sin w2 t).
# x1 = 0 first at (w1 + w2) t = 2 pi: t1 = 2 pi / sqrt5, where sin w1 t1 = -sin w2 t1 and
# phi_12^2 w1 = phi_22^2 w2, so x4(t1) = 0 exactly, and x2(t1) = cos(w1 t1) = -cos(pi/sqrt5) < 0.
# Impact x3 -> 0, mode {0}: x2 = x2(t1) cos s, u = -x2 > 0 until s = pi/2:
# t2 = 2 pi/sqrt5 + pi/2, x = (0, 0, 0, cos(pi/sqrt5)).
A_CARTS = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]


@pytest.mark.slow
def test_example_4_5_jump_at_zero_then_impact_and_release():
    tr = L.simulate(two_carts(), [0, 1, -1, 0], 5, digits=DIGITS)
    assert tr.certified and not tr.partial
    assert len(tr.events) == 3
    e0, e1, e2 = tr.events
    assert e0.time.rational() == 0
    assert e0.mode_before is None and e0.modes == (frozenset({0}),) and e0.mode_after == frozenset()
    assert [c.rational() for c in e0.state_after] == [0, 1, 0, 0]
    assert [c.rational() for c in e0.state_before] == [0, 1, -1, 0]
    # the impact: findroot on mpmath.expm of the hand-written A, and the closed form 2 pi / sqrt5
    A = mp.matrix(A_CARTS)
    free = lambda t: mp.expm(A * t) * mp.matrix([0, 1, 0, 0])  # noqa: E731
    t1 = first_root(lambda t: free(t)[0], mp.mpf(1) / 100, 5, mp.mpf(1) / 20)
    assert abs(t1 - 2 * mp.pi / mp.sqrt(5)) < mp.mpf(10) ** -50
    x1m = free(t1)
    check(e1.time, t1, 2 * sp.pi / sp.sqrt(5), "impact")
    assert e1.mode_before == frozenset() and e1.modes == (frozenset({0}),)
    assert e1.mode_after == frozenset({0})
    q2 = -mp.cos(mp.pi / mp.sqrt(5))
    assert abs(x1m[1] - q2) < mp.mpf(10) ** -50
    check_vec(e1.state_before, [0, q2, x1m[2], 0], what="x(t1-)")
    check_vec(e1.state_after, [0, q2, 0, 0], what="x(t1+)")
    check(e2.time, t1 + mp.pi / 2, 2 * sp.pi / sp.sqrt(5) + sp.pi / 2, "release")
    assert e2.mode_before == frozenset({0}) and e2.mode_after == frozenset() and e2.modes == ()
    check_vec(e2.state_after, [0, 0, 0, -q2], [0, 0, 0, sp.cos(sp.pi / sp.sqrt(5))], "x(t2)")
    xT = mp.expm(A * (5 - t1 - mp.pi / 2)) * mp.matrix([0, 0, 0, -q2])
    assert xT[0] > 0
    check_vec(tr.state(5), mpvec(xT), what="x(5)")

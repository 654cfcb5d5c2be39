"""Exact reals and vectors (lcs_exact.numbers.reals): anchored evaluation in a loop, structural signs,
homogeneity, composition, closed forms derived on demand."""
from __future__ import annotations

import sys

import mpmath as mp
import pytest
import sympy as sp
from flint import arb, fmpq, fmpq_mat

import lcs_exact as L
from lcs_exact.numbers.reals import RationalReal, SumReal, as_real, linear_terms
from lcs_exact.numbers.expvectors import expm_action
from lcs_exact.numbers.vectors import RationalVector, ScaledVector, homogenized

A_CARTS = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]


@pytest.mark.slow
def test_deep_definitions_evaluate_without_recursion():
    """A sum of 20,000 terms (an event time after 20,000 events has this shape) evaluates, gives
    its closed form and its rationality without exhausting the Python stack."""
    assert sys.getrecursionlimit() < 20_000
    t = RationalReal(0)
    for k in range(1, 20_001):
        t = t + as_real(sp.pi / k**2) if k % 5000 == 0 else t + RationalReal(fmpq(1, k * (k + 1)))
    # sum 1/(k(k+1)) over k not divisible by 5000, plus pi (1/5000^2 + ... + 1/20000^2)
    b = t.ball(30)
    with mp.workdps(60):
        want = sum(mp.mpf(1) / (k * (k + 1)) for k in range(1, 20_001) if k % 5000) + \
            mp.pi * sum(mp.mpf(1) / k**2 for k in (5000, 10000, 15000, 20000))
        assert abs(mp.mpf(b.mid().str(50, radius=False)) - want) < mp.mpf(10) ** -28
    const, terms = linear_terms(t)
    assert len(terms) == 4 and const == sum(fmpq(1, k * (k + 1)) for k in range(1, 20_001) if k % 5000)
    assert t.closed_form is not None and t.rational() is None


def test_expm_action_composes_and_collapses():
    x0 = expm_action(A_CARTS, -1, [0, -1, -1, 0])
    x1 = expm_action(A_CARTS, 1, x0)
    assert isinstance(x1, RationalVector) and list(x1.known_rational().entries()) == [0, -1, -1, 0]


def test_sign_of_form_structural_and_by_ball():
    x0 = expm_action(A_CARTS, -1, [0, -1, -1, 0])   # approx (0.3202, -0.4335, 0.3716, -1.0915)
    assert x0.sign_of_form(fmpq_mat([[1, 0, 0, 0]])) == 1
    assert x0.sign_of_form(fmpq_mat([[0, 0, 0, 1]])) == -1
    # the orbit of (1, 0, 0) under a rotation (+) growth block keeps x3 = 0 at every time, also
    # at pi/7 where no ball could show it: a structural zero (Krylov left kernel)
    x = expm_action([[0, 1, 0], [-1, 0, 0], [0, 0, 2]], sp.pi / 7, [1, 0, 0])
    assert x.sign_of_form(fmpq_mat([[0, 0, 1]])) == 0 and x[2].rational() == 0
    assert x.sign_of_form(fmpq_mat([[1, 0, 0]])) == 1 and x.sign_of_form(fmpq_mat([[0, 1, 0]])) == -1


def test_homogeneity_decides_signs_exactly():
    """P v with v = (sqrt 2, 0) and P = [[3, 0], [-1, 0]]: the relation x1 + 3 x2 = 0 is proven
    (pulled back through P), so x = c q with q = (3, -1) and c = sqrt 2 > 0 certified; every sign
    at x is then the sign at q: exact, even for forms that no single relation decides."""
    v = L.vectors.ComponentsVector([as_real(sp.sqrt(2)), as_real(0)])
    x = L.vectors.ProjectedVector(fmpq_mat([[3, 0], [-1, 0]]), v)
    h = homogenized(x)
    assert isinstance(h, ScaledVector) and h.v.known_rational() is not None
    q = h.v.known_rational()
    assert q[0, 0] * 1 + q[1, 0] * 3 == 0 and q[0, 0] > 0
    assert h.sign_of_form(fmpq_mat([[1, 2]])) == 1      # 3 sqrt2 - 2 sqrt2 > 0
    assert h.sign_of_form(fmpq_mat([[-1, -4]])) == 1    # -3 sqrt2 + 4 sqrt2 > 0
    assert h.sign_of_form(fmpq_mat([[2, 6]])) == 0


def test_rational_is_derived_through_closed_forms():
    """x(1-) of section 7 is e^{A theta} e^{-A} v with theta the proven root 1: exactly v."""
    tr = L.simulate(L.LCS(A_CARTS, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]]),
                    expm_action(A_CARTS, -1, [0, -1, -1, 0]), 2)
    x = tr.events[0].state_before
    assert x.known_rational() is None  # lazy: nothing derived during the run
    assert list(x.rational().entries()) == [0, -1, -1, 0]


def test_decimal_strings():
    assert RationalReal(fmpq(1, 3)).decimal(5) == "0.33333 +/- 3.37e-6"
    assert RationalReal(5).decimal(3) == "5"
    assert as_real(sp.pi).decimal(10).startswith("3.141592654 +/- ")


def test_sum_of_roots_is_cheap_to_test_for_rationality():
    s = SumReal(RationalReal(1), RationalReal(fmpq(1, 2)))
    assert s.known_rational() == fmpq(3, 2) and s.sign() == 1 and (s - fmpq(3, 2)).sign() == 0
    with pytest.raises(ZeroDivisionError):
        s / 0


def test_a_label_of_a_ball_around_zero_shows_only_its_bound():
    """sin²(π/7) + cos²(π/7) − 1 is 0 but not known to be: its ball straddles 0, and a label
    that printed the ball's midpoint would show digits of noise. A nonzero number as small
    relative to its parts, e^(π√163) − 640320³ − 744 ≈ −7.5e−13, keeps its digits."""
    from lcs_exact.numbers.reals import ClosedFormReal
    s, c = sp.sin(sp.pi / 7), sp.cos(sp.pi / 7)
    z = ClosedFormReal(s**2) + ClosedFormReal(c**2) - 1
    lab = z.label()
    assert lab.startswith("[+/- ") and lab.endswith("]")
    assert 0 < mp.mpf(lab[5:-1]) < mp.mpf("1e-15")
    r = ClosedFormReal(sp.exp(sp.pi * sp.sqrt(163))) - (640320**3 + 744)
    with mp.workdps(60):
        want = mp.exp(mp.pi * mp.sqrt(163)) - 640320**3 - 744
    assert mp.almosteq(mp.mpf(r.label()), want, rel_eps=mp.mpf("1e-13"))


def test_projected_vector_reads_its_values_from_the_inner_ball():
    """x = P v with v = e^{A} (0, -1, -1, 0) (the carts' matrix): before x has a ball of its own,
    the balls of F x come from v's ball as (F P) v; each holds F P e^{A} v0 computed here by
    mpmath at 60 digits (an independent evaluation), and is as tight as v's ball allows."""
    v = expm_action(A_CARTS, 1, [0, -1, -1, 0])
    P = fmpq_mat([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, fmpq(1, 2), fmpq(1, 2)], [0, 0, fmpq(1, 2), fmpq(1, 2)]])
    x = L.vectors.ProjectedVector(P, v)
    F = fmpq_mat([[1, 0, 0, 0], [0, 0, 1, -1], [2, -3, 1, 5]])
    assert x.form_balls(F) is None  # no ball anywhere yet: decided by structure, not evaluated
    v.arb(200)
    balls, prec = x.form_balls(F)
    with mp.workdps(60):
        E = mp.expm(mp.matrix(A_CARTS)) * mp.matrix([0, -1, -1, 0])
        Pm = mp.matrix([[float(P[i, j]) for j in range(4)] for i in range(4)])  # entries 0, 1, 1/2: exact
        ref = mp.matrix([[int(F[i, j]) for j in range(4)] for i in range(3)]) * (Pm * E)
        for i in range(3):
            b = balls[i, 0]
            assert b.rad() < 1e-50
            assert abs(mp.mpf(b.mid().str(60, radius=False)) - ref[i]) < 1e-50
    assert balls[1, 0].is_zero()  # (F P)_1 = 0: the exact product shows it


def test_signs_of_rows_agree_with_sign_of_form_row_by_row():
    """signs_of_rows (one product of balls, exact forms only where a ball holds 0) gives the
    signs sign_of_form gives row by row: on e^{A} v0 of the carts (before and after it has a
    ball), on P v (P the projection onto x1 = 0 along e1, rows that vanish by the pull-back), and
    on a rational vector; rows listed out of order come back in that order."""
    v = expm_action(A_CARTS, 1, [0, -1, -1, 0])
    P = fmpq_mat([[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    F = fmpq_mat([[1, 0, 0, 0], [0, 0, 1, -1], [2, -3, 1, 5], [0, 0, 0, 0], [-1, 0, 0, 0]])
    for x in (v, L.vectors.ProjectedVector(P, v), RationalVector(fmpq_mat([[1], [0], [-2], [3]]))):
        want = [x.sign_of_form(fmpq_mat(1, 4, [F[r, j] for j in range(4)])) for r in range(5)]
        assert list(x.signs_of_rows(F)) == want
        assert list(x.signs_of_rows(F, [4, 0, 2])) == [want[4], want[0], want[2]]
        x.arb(128)
        assert list(x.signs_of_rows(F)) == want
    assert list(L.vectors.ProjectedVector(P, v).signs_of_rows(F))[0] == 0  # x1 = 0 on P v: exact


def test_projected_vector_applies_a_split_projection_in_low_rank():
    """times_P(F) = F P exactly, where P = I - T (W T)^{-1} W is given as its split (W, T): on
    the carts' projection onto x3 = x4 along (0, 0, 1, -1) (P written out here), on random
    splits of Q^6 (d = 1, 2, 3; P built here from the definition), and with W of dependent rows
    (no low rank: the plain product).  The balls read through the split equal those read
    through P."""
    import random
    v = expm_action(A_CARTS, 1, [0, -1, -1, 0])
    P = fmpq_mat([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, fmpq(1, 2), fmpq(1, 2)], [0, 0, fmpq(1, 2), fmpq(1, 2)]])
    W, T = fmpq_mat([[0, 0, 1, -1]]), fmpq_mat([[0], [0], [1], [-1]])
    F = fmpq_mat([[1, 0, 0, 0], [0, 0, 1, -1], [2, -3, 1, 5]])
    x = L.vectors.ProjectedVector(P, v, split=(W, T))
    assert x.times_P(F) == F * P
    v.arb(200)
    a, b = x.form_balls(F)[0], L.vectors.ProjectedVector(P, v).form_balls(F)[0]
    assert all(a[i, 0].mid() == b[i, 0].mid() and a[i, 0].rad() == b[i, 0].rad() for i in range(3))
    rng = random.Random(3)
    for d in (1, 2, 3):
        while True:
            W = fmpq_mat(d, 6, [rng.randint(-3, 3) for _ in range(6 * d)])
            T = fmpq_mat(6, d, [rng.randint(-3, 3) for _ in range(6 * d)])
            if (W * T).det() != 0:
                break
        P6 = fmpq_mat(6, 6, [int(i == j) for i in range(6) for j in range(6)]) - T * (W * T).inv() * W
        assert P6 * P6 == P6 and W * P6 == fmpq_mat(d, 6, [0] * (6 * d))  # the projection onto Ker W
        F6 = fmpq_mat(4, 6, [fmpq(rng.randint(-9, 9), rng.randint(1, 4)) for _ in range(24)])
        z = L.vectors.ProjectedVector(P6, RationalVector(fmpq_mat(6, 1, [1, 2, 3, 4, 5, 6])), split=(W, T))
        assert z.times_P(F6) == F6 * P6
    Wdep = fmpq_mat([[0, 0, 1, -1], [0, 0, 2, -2]])  # dependent rows: W T is not square
    assert L.vectors.ProjectedVector(P, v, split=(Wdep, fmpq_mat([[0], [0], [1], [-1]]))).times_P(F) == F * P

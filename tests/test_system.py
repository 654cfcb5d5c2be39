"""LCS data: Markov parameters (5.8), G(s), R(s) (5.3), leading indices (Def. 6.2), Thm 6.3."""
from __future__ import annotations

import math
from fractions import Fraction

import pytest
from helpers import carts, hook, mat

from lcs_exact import LCS, IllPosed, RationalFunction

s = RationalFunction.s()
CHI = s**4 + 3 * s**2 + 1  # det(sI - A) of the two carts, section 7 (7.1)


def test_markov_parameters_two_carts():
    c = carts()
    assert [mat(c.markov(i)) for i in range(3)] == [[[0]], [[0]], [[1]]]  # section 7: H0 = H1 = 0, H2 = 1
    # G(s) = (s^2+1)/(s^4+3s^2+1) = s^-2 - 2 s^-4 + 5 s^-6 - ...: H3 = 0, H4 = -2, H5 = 0, H6 = 5
    assert [mat(c.markov(i))[0][0] for i in range(3, 7)] == [0, -2, 0, 5]


def test_transfer_matrices_match_7_1():
    # (7.1): (s^4 + 3 s^2 + 1) y = (s(s^2+1), s, s^2+1, 1) x0 + (s^2 + 1) u
    c = carts()
    assert c.G()[0, 0] == (s**2 + 1) / CHI
    assert [c.R()[0, j] for j in range(4)] == [s * (s**2 + 1) / CHI, s / CHI, (s**2 + 1) / CHI, 1 / CHI]
    assert c.charpoly().coeffs() == [1, 0, 3, 0, 1]


def test_transfer_matrices_hook_section_8():
    # section 8: (s^4+3s^2+1) y1 = (s^2+1) x30 + x40 + (s^2+1) u1 + s^2 u2,
    #            (s^4+3s^2+1) y2 = s^2 x30 - (s^2+1) x40 + s^2 u1 + (2 s^2 + 1) u2
    h = hook()
    G, R = h.G(), h.R()
    assert [[G[i, j] for j in range(2)] for i in range(2)] == [[(s**2 + 1) / CHI, s**2 / CHI],
                                                              [s**2 / CHI, (2 * s**2 + 1) / CHI]]
    assert R[0, 2] == (s**2 + 1) / CHI and R[0, 3] == 1 / CHI
    assert R[1, 2] == s**2 / CHI and R[1, 3] == -(s**2 + 1) / CHI


def test_leading_indices_and_matrices():
    c = carts()
    assert c.leading_row_indices() == (2,) and c.leading_column_indices() == (2,)
    assert mat(c.leading_row_matrix()) == [[1]] and mat(c.leading_column_matrix()) == [[1]]
    h = hook()
    # rho = eta = (2, 2) and M = N = E M^-1 E^T = [[1, 1], [1, 2]] (section 8)
    assert h.leading_row_indices() == (2, 2) == h.leading_column_indices()
    assert mat(h.leading_row_matrix()) == [[1, 1], [1, 2]] == mat(h.leading_column_matrix())


def test_mixed_leading_indices():
    # y1 = x1 (relative degree 2), y2 = x2 + u2 (degree 0): rows of H differ
    lcs = LCS([[0, 1, 0], [0, 0, 0], [0, 0, 0]], [[0, 0], [1, 0], [0, 1]], [[1, 0, 0], [0, 0, 1]],
              [[0, 0], [0, 1]])
    assert lcs.leading_row_indices() == (2, 0)
    assert lcs.leading_column_indices() == (2, 0)
    assert mat(lcs.leading_row_matrix()) == [[1, 0], [0, 1]]
    assert bool(lcs.well_posedness())


def test_well_posedness_report():
    wp = carts().well_posedness()
    assert wp and wp.M_is_P and wp.N_is_P and wp.reasons == ()
    assert "WELL-POSED" in str(wp)
    bad = LCS([[1]], [[1]], [[1]], [[-1]]).well_posedness()
    assert not bad and not bad.M_is_P and not bad.N_is_P
    assert bad.M_violation == (0,)
    assert any("principal minor on {0} is -1" in r for r in bad.reasons)


def test_well_posedness_reports_zero_row():
    lcs = LCS([[0, 0], [0, 0]], [[1, 0], [0, 1]], [[1, 0], [0, 0]], [[0, 0], [0, 0]])
    assert lcs.leading_row_indices() == (1, math.inf)
    with pytest.raises(IllPosed, match="row 1 of G"):
        lcs.leading_row_matrix()
    wp = lcs.well_posedness()
    assert not wp and any("identically zero" in r for r in wp.reasons)


def test_float_and_string_inputs_are_exact():
    lcs = LCS([[0.1]], [["1/3"]], [[Fraction(2, 7)]], [[0]])
    assert mat(lcs.A) == [[Fraction(1, 10)]] and mat(lcs.B) == [[Fraction(1, 3)]]
    assert mat(lcs.markov(1)) == [[Fraction(2, 21)]]


def test_numpy_scalars_where_a_scalar_is_accepted():
    """D for k = 1, a restitution coefficient and a mechanical force may be NumPy scalars or 0-d
    arrays (a NumPy scalar has ``tolist`` too: it was taken for a matrix or a list, and refused
    with "D must be a matrix" or a bare TypeError); each is read as its own type's shortest
    decimal: np.float32(-0.1) is -1/10, as typed."""
    import numpy as np
    from lcs_exact import models
    for D in (np.float32(-0.1), np.array(np.float16(-0.1)), np.float64(-0.1)):
        assert mat(LCS([[1]], [[1]], [[1]], D).D) == [[Fraction(-1, 10)]]
    ball = models.mechanical([[1]], [[0]], [[1]], force=np.float32(-9.81))
    assert mat(ball.A)[1][2] == Fraction(-981, 100)  # q'' = -9.81 (the force on the appended state)
    for e in (np.float32(0.9), np.array(np.float16(0.9)), np.array([np.float32(0.9)]), [np.float64(0.9)]):
        assert [Fraction(int(v.p), int(v.q)) for v in LCS(ball.A, ball.B, ball.C, ball.D, restitution=e).restitution] \
            == [Fraction(9, 10)]


def test_flat_inputs_for_single_constraint():
    lcs = LCS([[0, 1], [0, 0]], [0, 1], [1, 0], 0)
    assert (lcs.n, lcs.k) == (2, 1)
    assert mat(lcs.markov(2)) == [[1]]

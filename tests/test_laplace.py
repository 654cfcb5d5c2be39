"""Symbolic inverse Laplace transforms (laplace.laplace_closed_form, laplace.symbolic_expm) against
mpmath's matrix exponential: these expressions are used in closed-form proofs, so they must be
right for every factor shape (non-monic linear factors, repeated roots, complex pairs,
biquadratic quartics over Q(√d))."""
import mpmath as mp
import pytest
import sympy as sp
from flint import fmpq, fmpq_mat, fmpq_poly
from hypothesis import given, settings, strategies as st

from lcs_exact.numbers.expm import Spectrum
from lcs_exact.numbers.laplace import laplace_closed_form, symbolic_expm, t_symbol

_t = t_symbol()

mp.mp.dps = 40
TIMES = [mp.mpf(3) / 10, mp.mpf(17) / 7]


def _mp(m: fmpq_mat):
    return mp.matrix([[mp.mpf(int(m[i, j].p)) / int(m[i, j].q) for j in range(m.ncols())]
                      for i in range(m.nrows())])


def _check(M: fmpq_mat, row: fmpq_mat, z: fmpq_mat):
    f = laplace_closed_form(M, row, z)
    if f is None:
        return False
    for t in TIMES:
        want = (_mp(row) * mp.expm(_mp(M) * t) * _mp(z))[0]
        got = mp.mpf(str(sp.N(f.subs(_t, sp.Float(str(t), 50)), 45)))
        assert abs(got - want) <= mp.mpf(10) ** -30 * max(1, abs(want)), (M, row, z, f)
    return True


small = st.integers(-4, 4)


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(st.lists(small, min_size=4, max_size=4), st.lists(small, min_size=2, max_size=2),
       st.lists(small, min_size=2, max_size=2), st.integers(1, 3))
def test_laplace_2x2(entries, row, z, den):
    """Every 2x2 case has factors of degree <= 2, so a closed form must exist and be right."""
    M = fmpq_mat(2, 2, [fmpq(e, den) for e in entries])
    assert _check(M, fmpq_mat(1, 2, row), fmpq_mat(2, 1, z))


@pytest.mark.slow
@settings(max_examples=25, deadline=None)
@given(st.lists(small, min_size=9, max_size=9), st.lists(small, min_size=3, max_size=3),
       st.lists(small, min_size=3, max_size=3))
def test_laplace_3x3(entries, row, z):
    """3x3: a closed form when χ has a rational root; when one is claimed, it is right."""
    M = fmpq_mat(3, 3, entries)
    _check(M, fmpq_mat(1, 3, row), fmpq_mat(3, 1, z))


def test_non_monic_linear_factor():
    """A = [[-1, 1], [1, -5/2]]: e^{At}(1, -7) = -(2, 1) e^{-t/2} + 3 (1, -2) e^{-3t} (eigenvectors
    (2, 1) for -1/2 and (1, -2) for -3); the denominator has the factor 2s + 1."""
    M = fmpq_mat(2, 2, [-1, 1, 1, fmpq(-5, 2)])
    f = laplace_closed_form(M, fmpq_mat(1, 2, [1, 0]), fmpq_mat(2, 1, [1, -7]))
    assert sp.simplify(f - (-2 * sp.exp(-_t / 2) + 3 * sp.exp(-3 * _t))) == 0


@pytest.mark.slow
def test_two_carts_free_mode_biquadratic():
    """χ = s^4 + 3s^2 + 1 is irreducible over Q but splits over Q(√5) as (s^2 + φ^2)(s^2 + φ^-2),
    φ = (1 + √5)/2: e^{At} is symbolic and equals mpmath's expm."""
    A = fmpq_mat(4, 4, [0, 0, 1, 0, 0, 0, 0, 1, -2, 1, 0, 0, 1, -1, 0, 0])
    E = symbolic_expm(Spectrum(A))
    assert E is not None
    for t in TIMES:
        want = mp.expm(_mp(A) * t)
        got = E.subs(_t, sp.Float(str(t), 50))
        for i in range(4):
            for j in range(4):
                assert abs(mp.mpf(str(sp.N(got[i, j], 45))) - want[i, j]) <= mp.mpf(10) ** -30


def _block_diag(*blocks: fmpq_mat) -> fmpq_mat:
    n = sum(b.nrows() for b in blocks)
    M = fmpq_mat(n, n)
    at = 0
    for b in blocks:
        for i in range(b.nrows()):
            for j in range(b.ncols()):
                M[at + i, at + j] = b[i, j]
        at += b.nrows()
    return M


CARTS = fmpq_mat(4, 4, [0, 0, 1, 0, 0, 0, 0, 1, -2, 1, 0, 0, 1, -1, 0, 0])  # s^4 + 3s^2 + 1: Q(√5)


@pytest.mark.slow
def test_two_biquadratics_over_one_field():
    """s^4 + 3s^2 + 1 (d = 5) and s^4 + 12s^2 + 16 (the carts at twice the rate, d = 80 = 16 * 5)
    split over the same Q(√5): the transform of a row and a state touching both blocks is
    inverted, and equals mpmath's expm."""
    M = _block_diag(CARTS, CARTS * 2)
    assert Spectrum(M).chi == fmpq_poly([1, 0, 3, 0, 1]) * fmpq_poly([16, 0, 12, 0, 1])
    assert _check(M, fmpq_mat(1, 8, [1, 0, 0, 0, 1, 0, 0, 0]), fmpq_mat(8, 1, [1, 0, 0, 0, 0, 1, 0, 0]))


def test_two_biquadratics_over_different_fields():
    """s^4 + 3s^2 + 1 (Q(√5)) and s^4 + 4s^2 + 2 (d = 8: Q(√2)) have no common quadratic field:
    no closed form (decided from d_1 d_2 = 40, not a rational square)."""
    other = fmpq_mat(4, 4, [0, 0, 1, 0, 0, 0, 0, 1, -3, 1, 0, 0, 1, -1, 0, 0])
    assert Spectrum(other).chi == fmpq_poly([2, 0, 4, 0, 1])
    M = _block_diag(CARTS, other)
    assert laplace_closed_form(M, fmpq_mat(1, 8, [1, 0, 0, 0, 1, 0, 0, 0]),
                               fmpq_mat(8, 1, [1, 0, 0, 0, 1, 0, 0, 0])) is None
    # each block alone has its closed form
    assert _check(CARTS, fmpq_mat(1, 4, [1, 0, 0, 0]), fmpq_mat(4, 1, [1, 0, 0, 0]))
    assert _check(other, fmpq_mat(1, 4, [1, 0, 0, 0]), fmpq_mat(4, 1, [1, 0, 0, 0]))

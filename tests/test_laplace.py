"""Symbolic inverse Laplace transforms (expm.laplace_closed_form, expm.symbolic_expm) against
mpmath's matrix exponential: these expressions are used in closed-form proofs, so they must be
right for every factor shape (non-monic linear factors, repeated roots, complex pairs,
biquadratic quartics over Q(√d))."""
import mpmath as mp
import pytest
import sympy as sp
from flint import fmpq, fmpq_mat
from hypothesis import given, settings, strategies as st

from lcs_exact.expm import Spectrum, laplace_closed_form, symbolic_expm, t_symbol

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

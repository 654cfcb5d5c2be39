"""e^{Mt} (lcs_exact.numbers.expm): spectral balls against mpmath, no blow-up for stiff matrices, the exact
Jordan-Chevalley split, and exact values at closed-form times with Calcium."""
from __future__ import annotations

import mpmath as mp
import pytest
from flint import arb, arb_mat, ctx, fmpq, fmpq_mat
from hypothesis import given, settings
from hypothesis import strategies as st

from lcs_exact.numbers import calcium
from lcs_exact.numbers.expm import Spectrum, jordan_chevalley


def _check(M, t, z, digits=40):
    sp = Spectrum(fmpq_mat(M))
    with ctx.workprec(200):
        x = sp.apply(arb(t), arb_mat([[v] for v in z]), 200)
    with mp.workdps(80):
        tq = fmpq(t) if not isinstance(t, fmpq) else t
        want = mp.expm(mp.matrix(M) * (mp.mpf(int(tq.p)) / int(tq.q))) * mp.matrix(z)
        with ctx.workprec(300):
            for i in range(len(z)):
                ref = arb(mp.nstr(want[i], 75), mp.nstr(mp.mpf(10) ** -72 * (1 + abs(want[i])), 5))
                # the true value is in ref; ours must hold it (when ours is the tighter ball, as an
                # exact result is, it must at least meet ref)
                assert x[i, 0].contains(ref) or (x[i, 0].rad() < ref.rad() and x[i, 0].overlaps(ref))
                assert x[i, 0].rad() < mp.mpf(10) ** -digits * (1 + abs(want[i]))


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(-4, 4), min_size=9, max_size=9), st.integers(1, 30))
def test_spectral_ball_against_mpmath(entries, tq):
    M = [entries[0:3], entries[3:6], entries[6:9]]
    _check(M, fmpq(tq, 10), [1, -2, 3], digits=35)


def test_repeated_eigenvalues_through_jordan_chevalley():
    """A Jordan block plus a rotation: chi = s^2 (s^2 + 1)."""
    M = [[0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]]
    S, N, m = jordan_chevalley(fmpq_mat(M))
    assert m == 2 and N * N == fmpq_mat(4, 4) and S * N == N * S and S + N == fmpq_mat(M)
    _check(M, fmpq(7, 3), [1, 1, 1, 1])


def test_modal_vectors_stop_at_the_multiplicity():
    """chi = s^3 (s^2 + 1)(s + 2): the triple eigenvalue 0 (a 3 x 3 Jordan block) has three modal
    vectors w_0, w_1, w_2 (t^2 / 2 appears), the simple ones only w_0 (K_lambda N = 0 exactly),
    and e^{Mt} z stays right (against mpmath)."""
    M = [[0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 0, 0],
         [0, 0, 0, 0, 1, 0], [0, 0, 0, -1, 0, 0], [1, 0, 0, 0, 0, -2]]
    sp = Spectrum(fmpq_mat(M))
    assert not sp.semisimple
    with ctx.workprec(128):
        modal = sp.modal(arb_mat([[1], [2], [3], [1], [1], [1]]), 128)
        lengths = sorted((len(ws), lam.real.contains(0) and lam.imag.contains(0)) for lam, _, ws in modal)
        assert lengths == [(1, False), (1, False), (3, True)]
        (w2,) = [ws[2] for lam, _, ws in modal if len(ws) == 3]
        assert w2[0, 0].overlaps(arb(fmpq(3, 2)))  # q_0 = 1 + 2t + 3 t^2 / 2: w_2 = N^2 z / 2
    _check(M, fmpq(5, 3), [1, 2, 3, 1, 1, 1])


def test_eigenvectors_vanishing_on_the_sampled_rows():
    """The 10-cart chain in mode {1, 3}: chi = r14 (s^2 + 2)^3, and eigenvectors of the symmetric
    chain vanish on the rows the accuracy check samples.  The factors were refused after 64
    attempts (the sample's balls hold only noise around 0); now they are certified, and e^{Mt} z
    agrees with mpmath."""
    import lcs_exact
    M = lcs_exact.examples.cart_chain(10).mode(frozenset({1, 3})).closed_loop()
    assert [(p.degree(), k) for p, k in M.charpoly().factor_squarefree()[1]] == [(14, 1), (2, 3)]
    rows = [[int(M[i, j]) for j in range(20)] for i in range(20)]  # integer entries
    _check(rows, fmpq(7, 5), [(-1) ** i * (i % 3) for i in range(20)], digits=30)


def test_stiff_matrix_has_a_tight_ball():
    """Eigenvalues -10^6 and -1: at t = 1 the ball is tight (arb_mat.exp's bound would be ~e^(10^6))."""
    _check([[-10**6, 10**6 - 1], [0, -1]], 1, [1, 1], digits=40)


def test_e_to_the_a_pi_is_rational():
    """A with eigenvalues +-i, +-2i: P1 = (A^2 + 4I)/3 and P2 = -(A^2 + I)/3 are the spectral
    projectors, e^{A pi} = -P1 + P2 = -(2A^2 + 5I)/3 (derived by hand); Calcium proves it."""
    A = fmpq_mat([[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [-4, 0, -5, 0]])
    I4 = fmpq_mat([[int(i == j) for j in range(4)] for i in range(4)])
    want = (A * A * 2 + I4 * 5) * fmpq(-1, 3)
    assert Spectrum(A).exact_at(calcium.Ca.pi(), calcium) == want


def test_e_to_the_a_at_one_is_not_rational():
    A = fmpq_mat([[0, 1], [-1, 0]])
    assert Spectrum(A).exact_at(calcium.Ca(1), calcium) is None


@settings(max_examples=60, deadline=None)
@given(st.lists(st.fractions(-50, 50, max_denominator=7), min_size=16, max_size=16), st.integers(0, 3))
def test_modulus_bounds_hold_the_eigenvalues(entries, zero_rows):
    """Spectrum.modulus_bounds (the horizon limits' test without roots) bounds max |lambda| and
    the smallest nonzero |lambda| from above: checked against numpy's eigenvalues of the same
    rational matrix (rows set to 0 give zero eigenvalues beside the others; how many of the
    eigenvalues are 0 is read exactly off chi)."""
    import numpy as np
    M = [[fmpq(v.numerator, v.denominator) for v in entries[4 * i:4 * i + 4]] for i in range(4)]
    for i in range(zero_rows):
        M[i] = [fmpq(0)] * 4
    sp = Spectrum(fmpq_mat(M))
    ev = np.linalg.eigvals(np.array([[float(v) for v in row] for row in M]))
    mods = sorted(abs(complex(e)) for e in ev)
    zeros = next(j for j, c in enumerate(sp.chi.coeffs()) if c != 0)  # exact multiplicity of 0
    nonzero = mods[zeros:]
    b = sp.modulus_bounds()
    if b is None:  # chi = s^n: every eigenvalue 0
        assert sp.chi.coeffs()[:-1] == [0] * 4 and not nonzero
        return
    fast, slow = b
    assert mods[-1] <= float(fast) * (1 + 1e-9)
    if nonzero:
        assert nonzero[0] <= float(slow) * (1 + 1e-9)


def test_modulus_bounds_of_a_rotation_beside_a_free_mass():
    """chi = s^2 (s^2 + 4): Cauchy 1 + 4 = 5 >= |2i|, and the nonzero product 4 >= |2i|; a
    nilpotent matrix has no nonzero eigenvalue (None)."""
    sp = Spectrum(fmpq_mat([[0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, -4, 0]]))
    assert sp.modulus_bounds() == (5, 4)
    assert Spectrum(fmpq_mat([[0, 1], [0, 0]])).modulus_bounds() is None


def test_spectral_factors_of_a_large_matrix_call_the_deadline_check_between_steps():
    """The Krylov columns of a 40 x 40 matrix take 39 products of 40 x 40 balls: ``check`` (a
    run's deadline check) is called between them, and a check that stops the work leaves no
    factors cached (the next call computes them whole; e^{M t} of the chain's tridiagonal M
    then agrees with its value at t = 0, the identity)."""
    n = 40
    M = fmpq_mat(n, n, [(-2 if i == j else 1 if abs(i - j) == 1 else 0) for i in range(n) for j in range(n)])
    sp = Spectrum(M)
    calls = []

    class Stop(Exception):
        pass

    def check():
        calls.append(1)
        raise Stop

    with pytest.raises(Stop):
        sp.factors(64, check)
    assert calls == [1]
    E = sp.matrix(arb(0), 64)
    assert all(E[i, j].contains(int(i == j)) and E[i, j].rad() < 1e-15 for i in range(n) for j in range(n))

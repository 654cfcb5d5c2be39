"""Modes: V_I (3.2), T_I (3.5), autonomy (Lemma 3.3), P_I (4.2), feedback F_I (4.1)."""
from __future__ import annotations

from fractions import Fraction

import pytest
from helpers import carts, columns, hook, mat

from reference.linalg import mv, rank, same_span

from lcs_exact import LCS, NotAutonomous
from lcs_exact.examples import cart_chain


def test_two_carts_mode_1_section_7():
    m = carts().mode({0})
    assert same_span(columns(m.consistent_subspace()), [[0, 1, 0, 0], [0, 0, 0, 1]])  # V_{1} = Im[e2 e4]
    assert same_span(columns(m.jump_space()), [[1, 0, 0, 0], [0, 0, 1, 0]])  # T_{1} = Im[e1 e3]
    assert m.is_autonomous is True
    P = mat(m.projection())
    assert mv(P, [0, -1, -1, 0]) == [0, -1, 0, 0]
    assert mv(P, [0, 1, -1, 0]) == [0, 1, 0, 0]
    # on V_{1}: u = -2 x1 - x2 (section 7) = -x2 since x1 = 0; F T = 0
    F = mat(m.feedback())
    assert mv(F, [0, 1, 0, 0]) == [-1] and mv(F, [0, 0, 0, 1]) == [0]
    assert mv(F, [1, 0, 0, 0]) == [0] and mv(F, [0, 0, 1, 0]) == [0]
    # closed loop on V: x2'' = -x2, x1 = x3 = 0
    AI = mat(m.closed_loop())
    assert mv(AI, [0, 1, 0, 0]) == [0, 0, 0, -1] and mv(AI, [0, 0, 0, 1]) == [0, 1, 0, 0]


def test_empty_mode_is_identity():
    m = carts().mode(set())
    assert mat(m.projection()) == [[int(i == j) for j in range(4)] for i in range(4)]
    assert m.jump_space().ncols() == 0 and m.consistent_subspace().ncols() == 4


def test_hook_modes_reinitialize_as_in_section_8():
    h = hook()
    # hook mode {2} (0-based {1}): (eps, eps, -2, 1) jumps to (eps, eps, -1/2, -1/2)
    eps = Fraction(1, 1000)
    assert mv(mat(h.mode({1}).projection()), [eps, eps, -2, 1]) == [eps, eps, Fraction(-1, 2), Fraction(-1, 2)]
    # both constraints: V = {0}
    assert h.mode({0, 1}).consistent_subspace().ncols() == 0
    assert mat(h.mode({0, 1}).projection()) == [[0] * 4 for _ in range(4)]


def test_modes_are_built_lazily_and_cached():
    h = hook()
    assert h.built_modes() == frozenset()
    m = h.mode([1])
    assert h.mode({1}) is m and h.built_modes() == {frozenset({1})}


def test_non_autonomous_mode_reason():
    # G_{11}(s) = 0: y = x2 has no dependence on u (B e1 only drives x1)
    lcs = LCS([[0, 0], [0, 0]], [[1], [0]], [[0, 1]], [[0]])
    m = lcs.mode({0})
    assert m.is_autonomous is False
    assert "G_II(s) is singular" in m.autonomy_reason


def test_a_modes_data_are_computed_once_in_typed_attributes(monkeypatch):
    """V_I, T_I, P_I, F_I, A_I and the spectrum are computed on first use and kept (cached
    properties of the mode, no string-keyed memo): a second call returns the same object and
    does not compute again; a mode whose state is not determined raises at every call."""
    import lcs_exact.modes.mode as mode_module

    h = hook()
    m = h.mode({1})
    calls = []
    real, along = mode_module.projection, mode_module.projection_along  # P_I by either route
    monkeypatch.setattr(mode_module, "projection", lambda V, T: calls.append(1) or real(V, T))
    monkeypatch.setattr(mode_module, "projection_along", lambda W, T: calls.append(1) or along(W, T))
    first = [m.annihilator(), m.consistent_subspace(), m.jump_space(), m.projection(), m.feedback(),
             m.closed_loop(), m.spectrum(), m.free_inputs()]
    again = [m.annihilator(), m.consistent_subspace(), m.jump_space(), m.projection(), m.feedback(),
             m.closed_loop(), m.spectrum(), m.free_inputs()]
    assert all(a is b for a, b in zip(first, again)) and calls == [1]
    assert not hasattr(m, "_cache") and m.derived.family is None  # the data of the modules above: still lazy
    lcs = LCS([[0, 0], [0, 0]], [[1], [0]], [[0, 1]], [[0]])   # not autonomous, V + T != Q^2
    bad = lcs.mode({0})
    for _ in range(2):
        with pytest.raises(NotAutonomous, match="not determined"):
            bad.projection()
        with pytest.raises(NotAutonomous, match="not determined"):
            bad.feedback()


def test_projection_is_idempotent_and_splits():
    h = hook()
    for I in ({0}, {1}, {0, 1}, set()):
        P = mat(h.mode(I).projection())
        PP = [[sum(P[i][l] * P[l][j] for l in range(4)) for j in range(4)] for i in range(4)]
        assert PP == P
        V = h.mode(I).consistent_subspace()
        for j in range(V.ncols()):
            v = [V[i, j] for i in range(4)]
            assert mv(P, v) == [Fraction(int(x.p), int(x.q)) for x in v]


@pytest.mark.parametrize("mask", [0b1, 0b101, 0b11, 0b1110, 0b11111, 0b10010])
def test_feedback_of_chain_modes_keeps_the_state_in_V_and_y_I_at_zero(mask):
    """F_I on modes of six coupled carts (n = 12): F T_I = 0, and for each basis vector x of V_I
    the input u = F x keeps y_I = C_I x + D_II u = 0 along the motion (C_I (A x + B_I u) = 0) and
    (A + B_I F) x lies in V_I (checked here with the reference's exact rank)."""
    lcs = cart_chain(6)
    I = [i for i in range(lcs.k) if mask >> i & 1]
    m = lcs.mode(I)
    A, B, C = mat(lcs.A), mat(lcs.B), mat(lcs.C)
    F, V, T = mat(m.feedback()), columns(m.consistent_subspace()), columns(m.jump_space())
    for t in T:
        assert mv(F, t) == [0] * len(I)
    for x in V:
        u = mv(F, x)
        dx = [a + sum(B[r][i] * u[j] for j, i in enumerate(I)) for r, a in enumerate(mv(A, x))]
        assert all(mv([C[i] for i in I], dx)[j] == 0 for j in range(len(I)))
        assert rank(V + [dx]) == len(V)


@pytest.mark.parametrize("A, nilpotent", [
    ([[0, 1], [0, 0]], True),                                   # the double integrator: A^2 = 0
    ([[0, 1, 0], [0, 0, 1], [0, 0, 0]], True),                  # a chain of integrators: A^3 = 0
    ([[Fraction(1, 2), Fraction(1, 4)], [-1, Fraction(-1, 2)]], True),  # A^2 = 0, rational entries
    ([[0, 1], [-1, 0]], False),                                 # a rotation
    ([[0, 2 ** 61 - 1], [1, 0]], False),  # det(sI - A) = s^2 - (2^61 - 1): s^2 modulo that prime
    ([[0, 0, 2 ** 61 - 1], [1, 0, 0], [0, 1, 0]], False),  # s^3 - (2^61 - 1): tr A = tr A^2 = 0 too
])
def test_closed_loop_nilpotent_against_the_powers(A, nilpotent):
    """Mode.closed_loop_nilpotent (tr A and tr A^2 first, then the characteristic polynomial
    modulo a prime) against A^n = 0 computed here with Fractions; the last matrix has
    tr A = tr A^2 = 0 and is nilpotent modulo the prime the test reads next, so its answer comes
    from the polynomial over Q."""
    n = len(A)
    P = [[Fraction(int(i == j)) for j in range(n)] for i in range(n)]
    for _ in range(n):
        P = [[sum(Fraction(P[i][k]) * Fraction(A[k][j]) for k in range(n)) for j in range(n)] for i in range(n)]
    assert all(x == 0 for row in P for x in row) == nilpotent
    lcs = LCS(A, [[1]] + [[0]] * (n - 1), [[1] + [0] * (n - 1)], [[1]])
    assert lcs.mode(set()).closed_loop_nilpotent == nilpotent


@pytest.mark.parametrize("seed", range(12))
def test_closed_loop_norm_and_nilpotency_of_every_mode(seed):
    """||A_I||_inf and the nilpotency of A_I (Mode.closed_loop_norm from the rows A_I shares with
    A and the others; closed_loop_nilpotent from traces, then the characteristic polynomial)
    against the definitions computed here with Fractions from A_I: max_i sum_j |a_ij| and
    A_I^n = 0.  Systems with a strictly upper triangular A (nilpotent; some modes stay so) and
    random ones, every mode of k = 2 or 3."""
    import random
    from itertools import combinations
    rnd = random.Random(seed)
    n, k = rnd.randint(2, 5), rnd.randint(2, 3)
    upper = seed % 2 == 0
    A = [[Fraction(rnd.randint(-2, 2)) if (j > i or not upper) else Fraction(0) for j in range(n)] for i in range(n)]
    B = [[Fraction(rnd.randint(-1, 1)) for _ in range(k)] for _ in range(n)]
    C = [[Fraction(rnd.randint(-1, 1)) for _ in range(n)] for _ in range(k)]
    D = [[Fraction(int(i == j) * rnd.randint(1, 2)) for j in range(k)] for i in range(k)]
    lcs = LCS(A, B, C, D)
    seen = 0
    for r in range(k + 1):
        for I in combinations(range(k), r):
            mode = lcs.mode(set(I))
            if not mode.is_autonomous:
                continue
            seen += 1
            AI = [[Fraction(int(x.p), int(x.q)) for x in row] for row in mode.closed_loop().tolist()]
            norm = mode.closed_loop_norm
            assert Fraction(int(norm.p), int(norm.q)) == max(sum(abs(x) for x in row) for row in AI)
            P = [[Fraction(int(i == j)) for j in range(n)] for i in range(n)]
            for _ in range(n):
                P = [[sum(P[i][m] * AI[m][j] for m in range(n)) for j in range(n)] for i in range(n)]
            assert mode.closed_loop_nilpotent == all(x == 0 for row in P for x in row)
    assert seen >= 1


def test_closed_loop_norm_and_nilpotency_by_hand():
    """Two systems x' = A x + (0, 1) u, y = x_1 + u (so u = -x_1 in mode {0}: F = (-1, 0)).
    A = [[0, 1], [5, 0]]: A_I = [[0, 1], [4, 0]], ||A_I||_inf = 4 while A's row is 5 (the row the
    feedback changes).  A = [[0, 1], [1, 0]]: A_I = [[0, 1], [0, 0]] is nilpotent although
    tr A^2 = 2 (tr A_I^2 = tr A^2 + 2 tr F A L + tr (F L)^2 = 2 - 2 + 0), and A is not (its
    eigenvalues are 1 and -1)."""
    B, C, D = [[0], [1]], [[1, 0]], [[1]]
    lcs = LCS([[0, 1], [5, 0]], B, C, D)
    assert lcs.mode({0}).closed_loop().tolist() == [[0, 1], [4, 0]]
    assert lcs.mode({0}).closed_loop_norm == 4 and lcs.mode(set()).closed_loop_norm == 5
    lcs = LCS([[0, 1], [1, 0]], B, C, D)
    assert lcs.mode({0}).closed_loop().tolist() == [[0, 1], [0, 0]]
    assert lcs.mode({0}).closed_loop_nilpotent is True and lcs.mode(set()).closed_loop_nilpotent is False

"""Theorem 5.2 (S_RCP = S_LDCP^n) and Theorem 8.2 (re-initialization = Moreau's rule) as properties."""
from __future__ import annotations

from fractions import Fraction
from itertools import combinations

from helpers import rank, vec
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from lcs_exact import LCS
from lcs_exact.models import mechanical

small = st.integers(-2, 2)
SETTINGS = settings(derandomize=True, deadline=None, max_examples=60,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def matrix(rows, cols, elems=small):
    return st.lists(st.lists(elems, min_size=cols, max_size=cols), min_size=rows, max_size=rows)


def matmul(a, b):
    return [[sum(Fraction(a[i][l]) * b[l][j] for l in range(len(b))) for j in range(len(b[0]))]
            for i in range(len(a))]


def transpose(a):
    return [list(r) for r in zip(*a)]


def spd(L):
    """L L^T + I: symmetric positive definite."""
    m = len(L)
    return [[sum(Fraction(L[i][l]) * L[j][l] for l in range(m)) + (i == j) for j in range(m)] for i in range(m)]


@st.composite
def relative_degree_systems(draw):
    """D = 0, C B = L L^T + I (a P-matrix), or D = L L^T + I: well-posed by Theorem 6.3."""
    n, k = draw(st.integers(1, 4)), draw(st.integers(1, 3))
    A = draw(matrix(n, n))
    L = draw(matrix(k, k))
    if draw(st.booleans()):  # relative degree 0
        B, C, D = draw(matrix(n, k)), draw(matrix(k, n)), spd(L)
    else:  # relative degree 1: choose B with C B = P; C = [I 0] when n >= k
        assume(n >= k)
        C = [[int(i == j) for j in range(n)] for i in range(k)]
        P = spd(L)
        B = [P[i] if i < k else draw(st.lists(small, min_size=k, max_size=k)) for i in range(n)]
        D = [[0] * k for _ in range(k)]
    lcs = LCS(A, B, C, D)
    assume(bool(lcs.well_posedness()))
    # x0 often in special position: 0, in Ker C, or generic
    kind = draw(st.sampled_from(["zero", "kerC", "generic", "generic"]))
    if kind == "zero":
        x0 = [0] * n
    else:
        x0 = draw(st.lists(small, min_size=n, max_size=n))
        if kind == "kerC":
            # project onto Ker C when C = [I 0] (zero the first k coordinates)
            if all(C[i][j] == int(i == j) for i in range(k) for j in range(n)):
                x0 = [0] * k + x0[k:]
    return lcs, x0


@st.composite
def mechanical_systems(draw, feasible=False):
    m = draw(st.integers(1, 3))
    k = draw(st.integers(1, m))
    Mm = spd(draw(matrix(m, m, st.integers(-1, 1))))
    K = spd(draw(matrix(m, m, st.integers(-1, 1))))
    Dm = [[Fraction(draw(st.integers(0, 1))) * (i == j) for j in range(m)] for i in range(m)]
    E = draw(matrix(k, m))
    assume(rank([[Fraction(v) for v in r] for r in E]) == k)
    J = draw(st.sets(st.integers(0, k - 1), min_size=1))
    # q0: E_J q0 = 0, other constraints anything (feasible: E q0 >= 0); v0 random
    q0 = draw(st.lists(small, min_size=m, max_size=m))
    if feasible:
        q0 = _in_kernel_of_rows(E, sorted(J), q0)
        assume(all(sum(Fraction(E[i][j]) * q0[j] for j in range(m)) >= 0 for i in range(k)))
    v0 = draw(st.lists(small, min_size=m, max_size=m))
    return mechanical(Mm, Dm, K, E), Mm, E, [Fraction(v) for v in q0], [Fraction(v) for v in v0]


def _in_kernel_of_rows(E, rows, q):
    """Project q onto {w : E_rows w = 0} (a point of the kernel, exact)."""
    q = [Fraction(v) for v in q]
    if not rows:
        return q
    Er = [[Fraction(v) for v in E[i]] for i in rows]
    # q - Er^T (Er Er^T)^{-1} Er q
    G = matmul(Er, transpose(Er))
    rhs = [sum(a * b for a, b in zip(r, q)) for r in Er]
    lam = solve(G, rhs)
    return [q[j] - sum(Er[i][j] * lam[i] for i in range(len(rows))) for j in range(len(q))]


def solve(K, rhs):
    """Gauss-Jordan over Fractions; None if singular."""
    n = len(K)
    a = [list(map(Fraction, K[i])) + [Fraction(rhs[i])] for i in range(n)]
    for c in range(n):
        p = next((i for i in range(c, n) if a[i][c] != 0), None)
        if p is None:
            return None
        a[c], a[p] = a[p], a[c]
        for i in range(n):
            if i != c and a[i][c] != 0:
                f = a[i][c] / a[c][c]
                a[i] = [x - f * y for x, y in zip(a[i], a[c])]
    return [a[i][n] / a[i][i] for i in range(n)]


def moreau(Mm, E, J, v0):
    """argmin_{E_J w >= 0} (w - v0)^T M (w - v0) / 2 by its KKT system (active-set enumeration).

    M w - E_S^T lam = M v0, E_S w = 0, lam >= 0, E_J w >= 0; unique (Minimization problem 8.1).
    """
    m = len(v0)
    Mv = [sum(Fraction(Mm[i][j]) * v0[j] for j in range(m)) for i in range(m)]
    for r in range(len(J) + 1):
        for S in combinations(J, r):
            size = m + len(S)
            K = [[Fraction(0)] * size for _ in range(size)]
            rhs = [Fraction(0)] * size
            for i in range(m):
                for j in range(m):
                    K[i][j] = Fraction(Mm[i][j])
                for a, s in enumerate(S):
                    K[i][m + a] = -Fraction(E[s][i])
                    K[m + a][i] = Fraction(E[s][i])
                rhs[i] = Mv[i]
            sol = solve(K, rhs)
            if sol is None:
                continue
            w, lam = sol[:m], dict(zip(S, sol[m:]))
            if any(v < 0 for v in lam.values()):
                continue
            if any(sum(Fraction(E[i][j]) * w[j] for j in range(m)) < 0 for i in J):
                continue
            return w, {i: lam.get(i, Fraction(0)) for i in J}
    raise AssertionError("no KKT point")


@SETTINGS
@given(relative_degree_systems())
def test_theorem_5_2_rcp_equals_ldcp_relative_degree(data):
    lcs, x0 = data
    s_rcp = lcs.select_modes(x0, "rcp")
    s_ldcp = lcs.select_modes(x0, "ldcp")
    assert s_rcp == s_ldcp and s_rcp
    # well-posed: every selected mode re-initializes to the same state (Theorem 6.3)
    jumps = {tuple(vec(lcs.mode(I).projection() * _col(x0))) for I in s_rcp}
    assert len(jumps) == 1
    assert list(jumps)[0] == tuple(vec(lcs.initial_solution(x0).state_after))


@SETTINGS
@given(mechanical_systems())
def test_theorem_5_2_rcp_equals_ldcp_mechanical(data):
    lcs, _, _, q0, v0 = data
    x0 = q0 + v0
    s_rcp = lcs.select_modes(x0, "rcp")
    assert s_rcp == lcs.select_modes(x0, "ldcp") and s_rcp
    after = {tuple(vec(lcs.mode(I).projection() * _col(x0))) for I in s_rcp}
    assert after == {tuple(vec(lcs.initial_solution(x0).state_after))}


@SETTINGS
@given(mechanical_systems(feasible=True))
def test_theorem_8_2_moreau(data):
    lcs, Mm, E, q0, v0 = data
    m, k = len(q0), len(E)
    J = [i for i in range(k) if sum(Fraction(E[i][j]) * q0[j] for j in range(m)) == 0]
    w, lam = moreau(Mm, E, J, v0)
    lo = {i for i in J if lam[i] > 0}
    hi = {i for i in J if sum(Fraction(E[i][j]) * w[j] for j in range(m)) == 0}
    S = lcs.select_modes(q0 + v0)
    assert S
    for I in S:
        assert vec(lcs.mode(I).projection() * _col(q0 + v0)) == q0 + w
        assert lo <= I <= hi


def _col(x):
    from lcs_exact.rational import to_vector
    return to_vector(x, len(x))


def test_theorem_8_2_hook_grid():
    """Figure 8.2: on x0 = (0, 0, x3, x4) the jump is Moreau's projection of (x3, x4) onto the
    cone {w1 >= 0, w1 - w2 >= 0} (M = I, J = {stop, hook})."""
    from lcs_exact.models import two_carts_with_hook
    h = two_carts_with_hook()
    E = [[1, 0], [1, -1]]
    I2 = [[1, 0], [0, 1]]
    grid = [Fraction(i, 2) for i in range(-6, 7)]
    for x3 in grid:
        for x4 in grid:
            w, lam = moreau(I2, E, [0, 1], [x3, x4])
            S = h.select_modes([0, 0, x3, x4])
            assert S
            lo = {i for i in (0, 1) if lam[i] > 0}
            hi = {i for i in (0, 1) if (w[0] if i == 0 else w[0] - w[1]) == 0}
            # every selected mode lies between {lam > 0} and {E_i w = 0} (Theorem 8.2); inside a
            # region of Figure 8.2 (the two sets agree) the mode is determined by Moreau's rule
            assert all(lo <= I <= hi for I in S), (x3, x4)
            if lo == hi:
                assert S == {frozenset(lo)}, (x3, x4)
            for I in S:
                assert vec(h.mode(I).projection() * _col([0, 0, x3, x4])) == [0, 0] + w

"""lcp.py: LCP(q, M) (3.9)-(3.10) exactly: P-matrix test, Murty (on linear forms), Lemke, enumeration.

    y = q + M u,   0 <= y ⊥ u >= 0.

Independent references, in Fractions (tests/reference): principal minors by Gaussian elimination
(reference.linalg), and every solution of a small LCP by enumerating supports (reference.lcp).
"""
from __future__ import annotations

from fractions import Fraction

import pytest
from flint import fmpq, fmpq_mat
from helpers import F, vec
from hypothesis import given, settings
from hypothesis import strategies as st

from lcs_exact.errors import LCSError, ShapeError
from lcs_exact.algebra.lcp import (LCPSolution, all_solutions, basis_inputs, is_p_matrix, lemke, murty, murty_signs,
                                   p_matrix_violation,
                           solve_lcp)

from reference.lcp import lcp_solutions
from reference.linalg import det, is_P, principal_minors

PROP = settings(derandomize=True, deadline=None, max_examples=50)


# ---------------------------------------------------------------------------------------------
# checks
# ---------------------------------------------------------------------------------------------

def check_solution(sol: LCPSolution, q, m) -> tuple:
    """(u, y) of sol is a true solution of LCP(q, M): y = q + M u, u, y >= 0, u . y = 0 (exact)."""
    k = len(m)
    u, y = vec(sol.u), vec(sol.y)
    assert len(u) == len(y) == k
    assert y == [Fraction(q[i]) + sum(Fraction(m[i][j]) * u[j] for j in range(k)) for i in range(k)]
    assert all(v >= 0 for v in u) and all(v >= 0 for v in y)
    assert sum(a * b for a, b in zip(u, y)) == 0
    return tuple(u)


# ---------------------------------------------------------------------------------------------
# strategies
# ---------------------------------------------------------------------------------------------

def int_matrix(k, lo=-3, hi=3):
    return st.lists(st.lists(st.integers(lo, hi), min_size=k, max_size=k), min_size=k, max_size=k)


any_matrix = st.integers(1, 5).flatmap(int_matrix)


@st.composite
def p_matrix(draw, kmax=5):
    """A P-matrix by one of three constructions (each P by a classical argument)."""
    k = draw(st.integers(1, kmax))
    kind = draw(st.sampled_from(["pd", "dominant", "triangular"]))
    if kind == "pd":  # L L^T + I + (S - S^T): positive definite (not symmetric) => P
        L = draw(int_matrix(k, -2, 2))
        Sk = draw(int_matrix(k, -3, 3))
        return [[sum(L[i][l] * L[j][l] for l in range(k)) + (i == j) + Sk[i][j] - Sk[j][i]
                 for j in range(k)] for i in range(k)]
    if kind == "dominant":  # strictly row diagonally dominant with positive diagonal => P
        off = draw(int_matrix(k, -3, 3))
        extra = draw(st.lists(st.integers(1, 3), min_size=k, max_size=k))
        return [[off[i][j] if i != j else sum(abs(off[i][l]) for l in range(k) if l != i) + extra[i]
                 for j in range(k)] for i in range(k)]
    # triangular with positive diagonal: every principal minor is a product of diagonal entries
    low = draw(int_matrix(k, -4, 4))
    diag = draw(st.lists(st.integers(1, 4), min_size=k, max_size=k))
    return [[low[i][j] if j < i else diag[i] if i == j else 0 for j in range(k)] for i in range(k)]


def vector(k, lo=-4, hi=4):
    return st.lists(st.integers(lo, hi), min_size=k, max_size=k)


def fmat(m) -> fmpq_mat:
    return fmpq_mat([[fmpq(Fraction(v).numerator, Fraction(v).denominator) for v in r] for r in m])


# ---------------------------------------------------------------------------------------------
# P-matrices
# ---------------------------------------------------------------------------------------------

def test_p_matrix_by_hand():
    assert is_p_matrix([[1, 2], [0, 1]])                  # minors 1, 1, 1
    assert p_matrix_violation([[1, 2], [1, 1]]) == (0, 1)  # det = 1 - 2 = -1
    assert p_matrix_violation([[1, 0], [0, 0]]) == (1,)    # m22 = 0
    assert p_matrix_violation([[0]]) == (0,)
    assert not is_p_matrix([[2, 1, 0], [1, 2, 0], [0, 0, -1]])
    assert is_p_matrix([[1, -1], [1, 1]])                  # nonsymmetric PD: minors 1, 1, 2
    assert not is_p_matrix([[1, 2], [2, 1]])               # det = -3 (three LCP solutions below)
    assert is_p_matrix([["1/2", "1/3"], [0, "1/5"]])
    with pytest.raises(ShapeError):
        p_matrix_violation([[1, 2, 3], [4, 5, 6]])


@given(any_matrix)
@PROP
def test_p_matrix_test_against_principal_minors_random(m):
    mins = principal_minors(m)
    viol = p_matrix_violation(m)
    assert is_p_matrix(m) == all(v > 0 for v in mins.values())
    if viol is None:
        assert all(v > 0 for v in mins.values())
    else:
        assert viol == tuple(sorted(set(viol)))
        assert mins[viol] <= 0                             # the named minor really is not positive


@given(p_matrix())
@PROP
def test_p_matrix_test_on_p_matrices(m):
    assert is_P(m)
    assert is_p_matrix(m) and p_matrix_violation(m) is None


@given(p_matrix(), st.data())
@PROP
def test_p_matrix_violation_on_perturbed_p_matrices(m, data):
    """Make one diagonal entry very negative: no longer P; the named index set is a witness."""
    i = data.draw(st.integers(0, len(m) - 1))
    m = [list(r) for r in m]
    m[i][i] -= data.draw(st.integers(1, 40))
    mins = principal_minors(m)
    viol = p_matrix_violation(m)
    assert (viol is None) == all(v > 0 for v in mins.values())
    if viol is not None:
        assert mins[viol] <= 0


def test_p_matrix_violation_only_in_the_full_minor():
    # M = I + c C with C the cyclic shift 0 -> 1 -> 2 -> 0, c = -2: every proper principal
    # submatrix is triangular after reordering (a path, not a cycle) with unit diagonal, so all
    # 1x1 and 2x2 minors are 1; det M = 1 - (-c)^3 = 1 - 8 = -7.  Only (0, 1, 2) is a witness.
    m = [[1, -2, 0], [0, 1, -2], [-2, 0, 1]]
    assert det(m) == -7 and all(v == 1 for idx, v in principal_minors(m).items() if len(idx) < 3)
    assert p_matrix_violation(m) == (0, 1, 2)
    assert not is_p_matrix(m)
    # c = 1/2: det = 1 - (-1/2)^3 = 9/8 > 0, a P-matrix
    assert is_p_matrix([[1, "1/2", 0], [0, 1, "1/2"], ["1/2", 0, 1]])


@given(st.integers(3, 5), st.integers(-3, 3), st.permutations(range(5)),
       st.lists(st.integers(1, 3), min_size=5, max_size=5), st.lists(st.integers(1, 3), min_size=5, max_size=5))
@PROP
def test_p_matrix_violation_hidden_cycles(k, c, perm, d1, d2):
    """Pi D1 (I + c C_k) D2 Pi^T (C_k a k-cycle, D1, D2 positive diagonal, Pi a permutation): all
    proper principal minors are positive, det = d1 d2 (1 - (-c)^k); a violation can only be the
    whole index set, and it exists iff 1 - (-c)^k <= 0."""
    perm = [p for p in perm if p < k]
    base = [[Fraction(int(i == j) + (c if j == (i + 1) % k else 0)) for j in range(k)] for i in range(k)]
    scaled = [[d1[i] * base[i][j] * d2[j] for j in range(k)] for i in range(k)]
    m = [[scaled[perm[i]][perm[j]] for j in range(k)] for i in range(k)]
    mins = principal_minors(m)
    assert all(v > 0 for idx, v in mins.items() if len(idx) < k)
    full_ok = 1 - (-c) ** k > 0
    assert (mins[tuple(range(k))] > 0) == full_ok
    assert p_matrix_violation(m) == (None if full_ok else tuple(range(k)))
    assert is_p_matrix(m) == full_ok


# ---------------------------------------------------------------------------------------------
# solve_lcp, all_solutions
# ---------------------------------------------------------------------------------------------

def test_solve_lcp_by_hand():
    # M = [[2, 1], [1, 2]] (P), q = (-1, 1): u = (1/2, 0) gives y = (-1 + 1, 1 + 1/2) = (0, 3/2)
    sol = solve_lcp([-1, 1], [[2, 1], [1, 2]])
    assert vec(sol.u) == [Fraction(1, 2), 0] and vec(sol.y) == [0, Fraction(3, 2)]
    assert sol.basis == frozenset({0})
    # q >= 0: u = 0, y = q
    sol = solve_lcp(["1/2", 0], [[2, 1], [1, 2]])
    assert vec(sol.u) == [0, 0] and vec(sol.y) == [Fraction(1, 2), 0]


def test_all_solutions_three_solutions():
    # M = [[1, 2], [2, 1]], q = (-1, -1):
    #   u = (1, 0):     y = (-1 + 1, -1 + 2)       = (0, 1)
    #   u = (0, 1):     y = (-1 + 2, -1 + 1)       = (1, 0)
    #   u = (1/3, 1/3): y = (-1 + 1/3 + 2/3, same) = (0, 0)
    #   u = 0 fails (y = (-1, -1)).
    m, q = [[1, 2], [2, 1]], [-1, -1]
    sols = all_solutions(q, m)
    us = {tuple(vec(s.u)) for s in sols}
    assert len(sols) == 3
    assert us == {(1, 0), (0, 1), (Fraction(1, 3), Fraction(1, 3))}
    assert us == lcp_solutions(q, m)
    for s in sols:
        check_solution(s, q, m)
    # M is not P, so solve_lcp uses Lemke; its answer is one of the three
    assert check_solution(solve_lcp(q, m), q, m) in us


@given(p_matrix(), st.data())
@PROP
def test_p_matrix_lcp_unique_solution(m, data):
    k = len(m)
    q = data.draw(vector(k))
    ref = lcp_solutions(q, m)
    assert len(ref) == 1                                  # Theorem 3.4 (unique for a P-matrix)
    sol = solve_lcp(q, m)
    assert check_solution(sol, q, m) in ref
    sols = all_solutions(q, m)
    assert len(sols) == 1 and vec(sols[0].u) == vec(sol.u) and vec(sols[0].y) == vec(sol.y)


@given(any_matrix, st.data())
@PROP
def test_all_solutions_equals_enumeration(m, data):
    k = len(m)
    q = data.draw(vector(k))
    sols = all_solutions(q, m)
    us = [check_solution(s, q, m) for s in sols]
    assert len(us) == len(set(us))                         # no duplicates
    assert set(us) == lcp_solutions(q, m)


@given(any_matrix, st.data())
@PROP
def test_solve_lcp_result_is_a_solution_or_an_honest_failure(m, data):
    k = len(m)
    q = data.draw(vector(k))
    try:
        sol = solve_lcp(q, m)
    except LCSError as e:
        # only Lemke may fail (ray termination), never for a P-matrix
        assert not is_P(m)
        assert "ray" in str(e)
        return
    check_solution(sol, q, m)


def test_solve_lcp_shape_errors():
    with pytest.raises(ShapeError):
        solve_lcp([1, 2], [[1, 2, 3], [4, 5, 6]])
    with pytest.raises(ShapeError):
        solve_lcp([1, 2, 3], [[1, 0], [0, 1]])


# ---------------------------------------------------------------------------------------------
# Lemke
# ---------------------------------------------------------------------------------------------

def test_lemke_skew_symmetric_copositive_plus():
    # M = [[0, 1], [-1, 0]] (PSD, copositive-plus, not P), q = (-1, 1):
    # y1 = u2 - 1 >= 0 forces u2 >= 1 > 0, so y2 = 1 - u1 = 0, u1 = 1 > 0, so y1 = 0, u2 = 1.
    m, q = [[0, 1], [-1, 0]], [-1, 1]
    assert not is_p_matrix(m)
    sol = lemke(q, m)
    assert sol is not None
    assert check_solution(sol, q, m) == (1, 1) and vec(sol.y) == [0, 0]
    assert check_solution(solve_lcp(q, m), q, m) == (1, 1)


def test_lemke_psd_singular_infinitely_many_solutions():
    # M = [[1, 1], [1, 1]], q = (-1, -1): every u >= 0 with u1 + u2 = 1 is a solution
    m, q = [[1, 1], [1, 1]], [-1, -1]
    sol = lemke(q, m)
    u = check_solution(sol, q, m)
    assert sum(u) == 1


def test_lemke_ray_on_infeasible_copositive_plus():
    # M = [[1, -1], [-1, 1]] PSD; q = (-1, -1): y1 + y2 = -2 < 0 for every u, infeasible.
    # For copositive-plus M, Lemke ends on a secondary ray exactly when the LCP is infeasible.
    assert lemke([-1, -1], [[1, -1], [-1, 1]]) is None
    assert lemke([-1, 0], [[0, 0], [0, 0]]) is None      # y1 = -1 always
    with pytest.raises(LCSError, match="ray"):
        solve_lcp([-1, -1], [[1, -1], [-1, 1]])


def test_lemke_degenerate_ties_and_zeros():
    # ties: q = (-1, -1, -1), M = I + ones: y = -1 + u_i + (u1+u2+u3) = 0 -> u = (1/4, 1/4, 1/4)
    m3 = [[2, 1, 1], [1, 2, 1], [1, 1, 2]]
    sol = lemke([-1, -1, -1], m3)
    assert check_solution(sol, [-1, -1, -1], m3) == (Fraction(1, 4),) * 3
    # zeros in q: q = (0, -1, 0), M = I -> u = (0, 1, 0), y = 0 (doubly degenerate)
    eye = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    sol = lemke([0, -1, 0], eye)
    assert check_solution(sol, [0, -1, 0], eye) == (0, 1, 0) and vec(sol.y) == [0, 0, 0]
    # q = 0: u = 0 immediately
    sol = lemke([0, 0], [[1, 2], [3, 4]])
    assert vec(sol.u) == [0, 0] and vec(sol.y) == [0, 0]
    # a tie between two rows and a zero: q = (-2, -2, 0), M = [[1, 0, 1], [0, 1, 1], [1, 1, 1]]
    # (not P: det M = -1).  u = (2, 2, 0) gives y = (-2 + 2, -2 + 2, 0 + 2 + 2) = (0, 0, 4).
    m = [[1, 0, 1], [0, 1, 1], [1, 1, 1]]
    assert not is_p_matrix(m)
    sol = lemke([-2, -2, 0], m)
    assert sol is not None
    assert check_solution(sol, [-2, -2, 0], m) == (2, 2, 0) and vec(sol.y) == [0, 0, 4]
    assert lcp_solutions([-2, -2, 0], m) == {(2, 2, 0)}


@given(p_matrix(kmax=4), st.data())
@PROP
def test_lemke_on_p_matrices_with_degenerate_q(m, data):
    """q with entries in {-1, 0, 1} (many ties and zeros): Lemke with the lexicographic rule
    terminates with the unique solution."""
    k = len(m)
    q = data.draw(vector(k, -1, 1))
    sol = lemke(q, m)
    assert sol is not None
    assert {check_solution(sol, q, m)} == lcp_solutions(q, m)


@given(st.integers(1, 4).flatmap(lambda k: st.tuples(int_matrix(k, -2, 2), int_matrix(k, -2, 2),
                                                     vector(k, 0, 2), vector(k, 0, 2))))
@PROP
def test_lemke_psd_feasible_always_solves(data):
    """M = L L^T + (S - S^T) is PSD hence copositive-plus; q = y0 - M u0 with u0, y0 >= 0 is
    feasible.  Lemke's theorem: then it ends with a solution, not on a ray."""
    L, Sk, u0, y0 = data
    k = len(L)
    m = [[sum(L[i][l] * L[j][l] for l in range(k)) + Sk[i][j] - Sk[j][i] for j in range(k)] for i in range(k)]
    q = [y0[i] - sum(m[i][j] * u0[j] for j in range(k)) for i in range(k)]
    sol = lemke(q, m)
    assert sol is not None
    check_solution(sol, q, m)


# ---------------------------------------------------------------------------------------------
# Murty on linear forms
# ---------------------------------------------------------------------------------------------

def test_murty_forms_by_hand():
    # M = [[2, 1], [1, 2]], Q = [[1, -1], [-2, 1]], x = (1, 3): q = Q x = (-2, 1).
    # Basis {0}: u1 = -q1/2 = 1 -> y = (0, 1 + 1) = (0, 2) >= 0.  As forms: U = [[-1/2, 1/2], [0, 0]],
    # Y = Q + M U = [[0, 0], [-5/2, 3/2]].
    M = fmat([[2, 1], [1, 2]])
    Q = fmat([[1, -1], [-2, 1]])
    x = fmat([[1], [3]])
    basis, U, Y = murty(M, Q, x)
    assert basis == frozenset({0})
    assert [[F(U[i, j]) for j in range(2)] for i in range(2)] == [[Fraction(-1, 2), Fraction(1, 2)], [0, 0]]
    assert [[F(Y[i, j]) for j in range(2)] for i in range(2)] == [[0, 0], [Fraction(-5, 2), Fraction(3, 2)]]
    assert vec(U * x) == [1, 0] and vec(Y * x) == [0, 2]
    # x = None: q itself
    basis, u, y = murty(M, Q * x)
    assert vec(u) == [1, 0] and vec(y) == [0, 2]
    with pytest.raises(ShapeError):
        murty(fmat([[1, 0], [0, 1]]), fmat([[1], [2], [3]]))


def test_murty_not_p_matrix_stops():
    # M = [[-1, 0], [0, 1]] is not P (m11 = -1) and LCP((-1, 1), M) is infeasible (y1 = -1 - u1 < 0).
    # Least-index pivoting alternates between bases {} (y1 = -1 < 0) and {0} (u1 = -1 < 0):
    # it must stop with an error that names the missing P-matrix property, not loop forever.
    with pytest.raises(LCSError, match="P-matrix"):
        murty(fmat([[-1, 0], [0, 1]]), fmat([[-1], [1]]), max_pivots=20)


def _forms_and_point(m, data):
    """(n, Q, x, M, Qm, xm): k x n forms Q with entries in [-2, 2], n in 1..3, and a rational
    point x, as lists and as fmpq matrices."""
    k = len(m)
    n = data.draw(st.integers(1, 3))
    Q = [data.draw(vector(n, -2, 2)) for _ in range(k)]
    x = [Fraction(data.draw(st.integers(-3, 3)), data.draw(st.integers(1, 3))) for _ in range(n)]
    return n, Q, x, fmat(m), fmat(Q), fmat([[v] for v in x])


@given(p_matrix(kmax=4), st.data())
@PROP
def test_murty_with_linear_forms(m, data):
    k = len(m)
    n, Q, x, M, Qm, xm = _forms_and_point(m, data)
    basis, U, Y = murty(M, Qm, xm)
    assert (U.nrows(), U.ncols(), Y.nrows(), Y.ncols()) == (k, n, k, n)
    # Y = Q + M U as forms (exactly, for every x), and U x, Y x solve LCP(Q x, M)
    assert Y == Qm + M * U
    q = [sum(Fraction(Q[i][j]) * x[j] for j in range(n)) for i in range(k)]
    u = check_solution(LCPSolution(U * xm, Y * xm, basis), q, m)
    assert {u} == lcp_solutions(q, m)
    # u_i = 0 off the basis, as forms
    assert all(U[i, j] == 0 for i in range(k) if i not in basis for j in range(n))


class _FormsOnly:
    """A point that answers only sign_of_form: Murty decides every sign on the k x n forms."""

    def __init__(self, x):
        self.x = x

    def sign_of_form(self, form):
        return self.x.sign_of_form(form)


@given(p_matrix(kmax=4), st.data())
@PROP
def test_murty_on_the_balls_of_an_exact_point_agrees_with_the_forms(m, data):
    """At an exact-real point x = (a, a, b, 0, 1) (a = sqrt 2, b = sqrt 3; x_0 - x_1 = 0 and x_3 = 0
    are exact relations no ball shows), Murty's pivoting on the balls of Q x (a ball holding 0 asks
    the exact form) gives the basis and forms of the pivoting on the forms alone, and U x, Y x
    solve the LCP: u, y >= 0 and u_i y_i = 0, certified at 200 bits where nonzero."""
    import sympy
    from lcs_exact.algebra import submatrix
    from lcs_exact.numbers.reals import as_real
    from lcs_exact.numbers.vectors import as_exact_vector
    a, b = as_real(sympy.sqrt(2)), as_real(sympy.sqrt(3))
    x = as_exact_vector([a, a, b, 0, 1])
    x.arb(128)  # the ball Murty reads
    k, n = len(m), 5
    Q = [data.draw(vector(n, -2, 2)) for _ in range(k)]
    M, Qm = fmat(m), fmat(Q)
    got = murty(M, Qm, x)
    assert got == murty(M, Qm, _FormsOnly(x))
    basis, U, Y = got
    assert Y == Qm + M * U
    u, y = U * x.arb(200), Y * x.arb(200)  # arb_mat products: balls of u and y
    for i in range(k):
        su, sy = x.sign_of_form(submatrix(U, [i], None)), x.sign_of_form(submatrix(Y, [i], None))
        assert su >= 0 and sy >= 0 and su * sy == 0
        assert (i in basis) or su == 0
        assert not u[i, 0] < 0 and not y[i, 0] < 0


def test_p_matrix_test_of_interleaved_blocks_above_the_enumeration_limit():
    """k = 24 (above MAX_P_TEST_K = 20), nonsymmetric, symmetric part not positive definite: twelve
    2 x 2 blocks [[1, 2], [0, 1]] (P: minors 1, 1, 1) on interleaved indices (block b on {b, b +
    12}).  Tested block by block (det M[S] is the product of the blocks' minors): P.  One block
    replaced by [[1, 2], [1, 1]] (det -1): the violation is that block's index pair, and its
    minor, computed here with Fractions, is <= 0."""
    k = 24

    def build(bad_block=None):
        rows = [[Fraction(0)] * k for _ in range(k)]
        for b in range(12):
            i, j = b, b + 12
            blk = [[1, 2], [1, 1]] if b == bad_block else [[1, 2], [0, 1]]
            rows[i][i], rows[i][j], rows[j][i], rows[j][j] = map(Fraction, (blk[0][0], blk[0][1], blk[1][0], blk[1][1]))
        return rows

    assert p_matrix_violation(build()) is None
    rows = build(bad_block=5)
    bad = p_matrix_violation(rows)
    assert bad == (5, 17)
    assert det([[rows[i][j] for j in bad] for i in bad]) <= 0


@given(p_matrix(kmax=4), st.data())
@PROP
def test_murty_signs_are_the_signs_of_the_solution(m, data):
    """murty_signs: the basis of murty and, per row, the sign of u_i (in the basis) or y_i (off
    it) at x, from the solution's exact values U x, Y x computed here; basis_inputs is murty's U."""
    k = len(m)
    _, _, _, M, Qm, xm = _forms_and_point(m, data)
    basis, U, Y = murty(M, Qm, xm)
    got_basis, signs = murty_signs(M, Qm, xm)
    assert got_basis == basis
    u, y = vec(U * xm), vec(Y * xm)
    assert signs == [int((u[i] if i in basis else y[i]) > 0) for i in range(k)]
    assert basis_inputs(M, Qm, sorted(basis)) == U

"""The linear complementarity problem LCP(q, M) (3.9)-(3.10), exactly over Q.

    y = q + M u,   0 <= y ⊥ u >= 0.

* :func:`p_matrix_violation` / :func:`is_p_matrix`: P-matrix test (all principal minors > 0) by
  the recursive Schur-complement test (Tsatsomeros-Li): M is P iff m11 > 0 and both M(1)
  (row/column 1 deleted) and the Schur complement M/m11 are P.  A failure names the principal
  minor that is not positive.
* :func:`murty`: Murty's least-index principal pivoting for a P-matrix (finite for every q,
  degenerate or not).  It works on *linear forms*: q = Q x with Q a k x n rational matrix and x a
  point; every sign is decided by :func:`~lcs_exact.rational.sign_of_form`, so the same code
  serves rational q and the exact-real states of a simulation.
* :func:`lemke`: Lemke's complementary pivoting with lexicographic degeneracy resolution (for
  any M; may end on a ray, then it says so).
* :func:`all_solutions`: every solution, by enumeration of complementary index sets (small k).
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any

from flint import arb_mat, ctx, fmpq, fmpq_mat

from ..errors import LCSError, ShapeError
from .rational import MAX_P_TEST_K, check_enumerable, pivot_tableau, selection_matrix, sign_of_form, submatrix, to_matrix, to_vector, zeros

__all__ = ["LCPSolution", "p_matrix_violation", "is_p_matrix", "murty", "murty_signs", "basis_inputs", "lemke", "solve_lcp",
           "all_solutions"]


@dataclass(frozen=True)
class LCPSolution:
    """A solution (u, y) of LCP(q, M); ``basis`` is the set {i : u_i basic}."""

    u: fmpq_mat
    y: fmpq_mat
    basis: frozenset

    def __repr__(self):
        us = ", ".join(str(self.u[i, 0]) for i in range(self.u.nrows()))
        ys = ", ".join(str(self.y[i, 0]) for i in range(self.y.nrows()))
        return f"LCPSolution(u=({us}), y=({ys}))"


# ---------------------------------------------------------------------------------------------
# P-matrices
# ---------------------------------------------------------------------------------------------


def _schur(m: fmpq_mat) -> fmpq_mat:
    """M / m11: the Schur complement of the (0, 0) entry."""
    k = m.nrows()
    a = m[0, 0]
    out = fmpq_mat(k - 1, k - 1)
    for i in range(1, k):
        f = m[i, 0] / a
        for j in range(1, k):
            out[i - 1, j - 1] = m[i, j] - f * m[0, j]
    return out


def _leading_violation(m: fmpq_mat) -> tuple[int, ...] | None:
    """None when every leading principal minor of m is > 0, else the first index set 0..j whose
    minor is <= 0: the pivots of the successive Schur complements are the ratios of the leading
    minors (k steps)."""
    a, k = m, m.nrows()
    for j in range(k):
        if a[0, 0] <= 0:
            return tuple(range(j + 1))
        if j + 1 < k:
            a = _schur(a)
    return None


def p_matrix_violation(m: Any) -> tuple[int, ...] | None:
    """None if M is a P-matrix, else a (0-based) index set whose principal minor is <= 0.

    det M[pre ∪ S] = det M[pre] * det (M/M[pre])[S], so a nonpositive leading entry found in a
    Schur complement names the principal minor on pre ∪ {i}.  The test visits 2^k Schur
    complements, so it runs only when quicker tests say nothing: a symmetric M is P iff its
    leading minors are positive (positive definite), and M is P when its symmetric part is
    positive definite (Theorem 3.5) - mechanical systems (N = E M^{-1} E^T) and most circuits
    never enumerate.  A matrix of uncoupled diagonal blocks (up to a symmetric permutation) is
    tested block by block: det M[S] is the product of the blocks' minors.  A nonsymmetric block
    above ``MAX_P_TEST_K`` = 20 that fails the second test is refused
    (:class:`~lcs_exact.errors.Unsupported`).

    Parameters
    ----------
    m : k x k matrix of rationals
        The matrix M.

    >>> p_matrix_violation([[1, 2], [0, 1]]) is None
    True
    >>> p_matrix_violation([[1, 2], [1, 1]])
    (0, 1)
    """
    m = to_matrix(m, "M")
    if m.nrows() != m.ncols():
        raise ShapeError(f"a P-matrix must be square, got {m.nrows()}x{m.ncols()}")
    k = m.nrows()
    if m == m.transpose():
        # symmetric: P iff positive definite iff every leading minor is > 0 (Sylvester); a
        # nonpositive diagonal entry is reported first (the smallest violation, the clearest)
        bad = next((i for i in range(k) if m[i, i] <= 0), None)
        return (bad,) if bad is not None else _leading_violation(m)
    if k and _leading_violation((m + m.transpose()) / 2) is None:
        return None  # x^T M x > 0 for x != 0: positive definite, so P (Theorem 3.5)
    blocks = _blocks(m)
    if len(blocks) > 1:
        # M is block diagonal up to a symmetric permutation: det M[S] is the product of the
        # blocks' det M[S ∩ B], so M is P iff every block is, and a block's violation is M's
        # (eleven full-wave bridges side by side: k = 44, eleven tests of 2^4 index sets)
        for b in blocks:
            bad = p_matrix_violation(submatrix(m, b, b))
            if bad is not None:
                return tuple(sorted(b[i] for i in bad))
        return None
    check_enumerable(k, "the P-matrix test of a nonsymmetric matrix", MAX_P_TEST_K)

    def rec(a: fmpq_mat, labels: tuple[int, ...], pre: tuple[int, ...]):
        if not labels:
            return None
        if a[0, 0] <= 0:
            return tuple(sorted(pre + (labels[0],)))
        rest = labels[1:]
        if rest:
            bad = rec(submatrix(a, range(1, len(labels)), range(1, len(labels))), rest, pre)
            if bad is not None:
                return bad
            return rec(_schur(a), rest, pre + (labels[0],))
        return None

    return rec(m, tuple(range(m.nrows())), ())


def _blocks(m: fmpq_mat) -> list[list[int]]:
    """The index sets of M's diagonal blocks: the connected components of the graph with an edge
    i - j where M_ij or M_ji is nonzero (each sorted; in the order of their least index)."""
    k = m.nrows()
    e = m.entries()
    seen = [False] * k
    out = []
    for s0 in range(k):
        if seen[s0]:
            continue
        seen[s0], stack, comp = True, [s0], []
        while stack:
            i = stack.pop()
            comp.append(i)
            for j in range(k):
                if not seen[j] and (e[i * k + j] != 0 or e[j * k + i] != 0):
                    seen[j] = True
                    stack.append(j)
        out.append(sorted(comp))
    return out


def is_p_matrix(m: Any) -> bool:
    """All principal minors positive (section 3).

    Parameters
    ----------
    m : k x k matrix of rationals
        The matrix M (Theorem 3.4: LCP(q, M) has a unique solution for every q iff M is a P-matrix).
    """
    return p_matrix_violation(m) is None


# ---------------------------------------------------------------------------------------------
# Murty (P-matrix), on linear forms
# ---------------------------------------------------------------------------------------------


def murty(m: fmpq_mat, q_forms: fmpq_mat, x: Any = None, *, max_pivots: int | None = None):
    """Solve LCP(Q x, M) for a P-matrix M by Murty's least-index principal pivoting.

    ``q_forms`` is k x n (q = Q x); with ``x=None`` it is the k x 1 vector q itself.
    Returns (basis, U, Y): u = U x, y = Y x as k x n forms (exact), with u_i = 0 off the basis.

    The pivoting reads values, not forms: q = Q x exactly for a rational x, else the balls of
    Q x that x gives (``x.form_balls``); a sign a ball does not show is decided on the exact
    form of that one row by :func:`~lcs_exact.rational.sign_of_form` (exact, or raises).  The
    forms of u and y are solved once, for the final basis (k x 1 work per pivot instead of
    k x n: the LDCP stages of a 128-state system pivot on 32 x 128 forms).

    Parameters
    ----------
    m : fmpq_mat
        The k x k P-matrix M.
    q_forms : fmpq_mat
        Q (k x n), with q = Q x; with ``x=None`` the k x 1 vector q itself.
    x : state, optional
        The point at which the signs of the forms are decided (None: Q is q).
    max_pivots : int, optional
        A bound on the pivots (LimitExceeded beyond it); None: no bound but Murty's finiteness.
    """
    basis, _ = murty_signs(m, q_forms, x, max_pivots=max_pivots)
    return basis, *_solution(m, q_forms, sorted(basis))


def murty_signs(m: fmpq_mat, q_forms: fmpq_mat, x: Any = None, *,
                max_pivots: int | None = None) -> tuple[frozenset, list[int]]:
    """The basis of :func:`murty`'s solution and the certified sign at x of each row's unknown
    in it: u_i (i in the basis) or y_i (off it), each 0 or 1 (none is negative at the solution).
    The signs are those the last pivoting pass read, so a caller that needs only which u and y
    are positive (the LDCP stages of mode selection) reads no form again.

    Parameters
    ----------
    m, q_forms, x, max_pivots
        As in :func:`murty`: the k x k P-matrix M, Q with q = Q x, the point, a pivot bound.
    """
    k = q_forms.nrows()
    if m.nrows() != k or m.ncols() != k:
        raise ShapeError(f"LCP: M is {m.nrows()}x{m.ncols()} but q has {k} rows")
    if max_pivots is None:
        max_pivots = 2 ** k + 1
    values = _values(q_forms, x)
    basis: set[int] = set()
    signs: list[int] = [0] * k
    for _ in range(max_pivots + 1):
        a = sorted(basis)
        bad = _first_negative(m, q_forms, x, values, a, signs)
        if bad is None:
            return frozenset(basis), signs
        basis ^= {bad}
    raise LCSError(f"Murty's method did not terminate in {max_pivots} pivots: M is not a P-matrix")


def _values(q_forms: fmpq_mat, x: Any):
    """(q, prec): q = Q x exactly (prec None) for x None or rational, else the balls of Q x and
    their precision, or None when x gives none (every sign then asked of the forms)."""
    if x is None:
        return q_forms, None
    if isinstance(x, fmpq_mat):
        return q_forms * x, None
    balls = getattr(x, "form_balls", None)
    return balls(q_forms) if balls is not None else None


def _first_negative(m: fmpq_mat, q_forms: fmpq_mat, x: Any, values, a: list[int],
                    signs: list[int] | None = None) -> int | None:
    """The least index whose u (in the basis a) or y (off it) is negative at x, None if none
    (then ``signs``, when given, holds every row's sign: the pass read them all)."""
    if values is None:  # no values: the forms themselves (k x n)
        U, Y = _solution(m, q_forms, a)
        for i in range(m.nrows()):
            s = sign_of_form(submatrix(U if i in a else Y, [i], None), x)
            if s < 0:
                return i
            if signs is not None:
                signs[i] = s
        return None
    q, prec = values
    k = m.nrows()
    with ctx.workprec(prec if prec is not None else ctx.prec):
        M = m if prec is None else arb_mat(m)
        u = [0] * k
        if a:
            try:
                ua = (submatrix(m, a, a) if prec is None else arb_mat(submatrix(m, a, a))).solve(
                    type(q)(len(a), 1, [q[i, 0] for i in a]))
            except ZeroDivisionError:  # a ball solve not certified: the forms decide
                return _first_negative(m, q_forms, x, None, a, signs)
            for r, i in enumerate(a):
                u[i] = -ua[r, 0]
        X: list = []  # M_aa^{-1} Q_a, solved once for the rows whose ball holds 0
        for i in range(k):
            v = u[i] if i in a else q[i, 0] + sum((M[i, j] * u[j] for j in a), 0 * q[i, 0])
            s = (v > 0) - (v < 0)
            if s == 0 and prec is not None and not v.is_zero():  # a ball holding 0: the exact form
                s = sign_of_form(_row(m, q_forms, a, i, X), x)
            if s < 0:
                return i
            if signs is not None:
                signs[i] = s
    return None


def _row(m: fmpq_mat, q_forms: fmpq_mat, a: list[int], i: int, X: list) -> fmpq_mat:
    """The form of u_i (i in the basis a) or of y_i (off it): one row, 1 x n (``X``: a cache of
    M_aa^{-1} Q_a, u_a = -X, filled on first use)."""
    if not a:
        return submatrix(q_forms, [i], None)
    if not X:
        X.append(submatrix(m, a, a).solve(submatrix(q_forms, a, None)))
    if i in a:
        return -submatrix(X[0], [a.index(i)], None)
    return submatrix(q_forms, [i], None) - submatrix(m, [i], a) * X[0]


def _solution(m: fmpq_mat, q_forms: fmpq_mat, a: list[int]) -> tuple[fmpq_mat, fmpq_mat]:
    """(U, Y) in the basis a: U_a = -M_aa^{-1} Q_a, U = 0 off it, Y = Q + M U (exact forms)."""
    u = basis_inputs(m, q_forms, a)
    if not a:  # u = 0, y = q (no k x k by k x n product)
        return u, fmpq_mat(q_forms)
    return u, q_forms + m * u


def basis_inputs(m: fmpq_mat, q_forms: fmpq_mat, a) -> fmpq_mat:
    """U of LCP(Q x, M) in the basis a (sorted indices): U_a = -M_aa^{-1} Q_a and U = 0 off a,
    as k x n forms (the u of :func:`murty` once :func:`murty_signs` gave the basis).

    Parameters
    ----------
    m : fmpq_mat
        k x k.
    q_forms : fmpq_mat
        k x n.
    a : sequence of int
        The basis, sorted.

    >>> basis_inputs(fmpq_mat([[2, 1], [1, 2]]), fmpq_mat([[-2], [1]]), [0]).tolist()
    [[1], [0]]
    """
    k, n = q_forms.nrows(), q_forms.ncols()
    if not a:
        return zeros(k, n)
    ua = -submatrix(m, a, a).solve(submatrix(q_forms, a, None))
    return selection_matrix(a, k).transpose() * ua  # rows a of u: a product, not k x n Python entries


# ---------------------------------------------------------------------------------------------
# Lemke with lexicographic pivoting
# ---------------------------------------------------------------------------------------------


def lemke(q: Any, m: Any, *, max_pivots: int = 10_000) -> LCPSolution | None:
    """Lemke's method with the lexicographic minimum-ratio rule; None on ray termination.

    Tableau rows: w - M z - e z0 = q, columns [w (k) | z (k) | z0 | rhs].  The w-columns of the
    current tableau are B^{-1}, which gives the lexicographic tie-break (rhs_i, B^{-1}_i) / d_i.
    """
    m = to_matrix(m, "M")
    k = m.nrows()
    q = to_vector(q, k, "q")
    if all(q[i, 0] >= 0 for i in range(k)):
        return LCPSolution(zeros(k, 1), q, frozenset())
    width = 2 * k + 2
    t = [[fmpq(0)] * width for _ in range(k)]
    for i in range(k):
        t[i][i] = fmpq(1)
        for j in range(k):
            t[i][k + j] = -m[i, j]
        t[i][2 * k] = fmpq(-1)
        t[i][2 * k + 1] = q[i, 0]
    basic = list(range(k))  # variable ids: w_i = i, z_i = k + i, z0 = 2k
    rhs = 2 * k + 1

    def key(i, c):
        d = t[i][c]
        return [t[i][rhs] / d] + [t[i][j] / d for j in range(k)]

    def pivot(r, c):
        pivot_tableau(t, r, c)
        leaving = basic[r]
        basic[r] = c
        return leaving

    # z0 enters where q is lexicographically most negative
    r = min(range(k), key=lambda i: [t[i][rhs]] + [t[i][j] for j in range(k)])
    leaving = pivot(r, 2 * k)
    for _ in range(max_pivots):
        entering = leaving + k if leaving < k else leaving - k
        rows = [i for i in range(k) if t[i][entering] > 0]
        if not rows:
            return None  # secondary ray
        r = min(rows, key=lambda i: key(i, entering))
        leaving = pivot(r, entering)
        if leaving == 2 * k:
            break
    else:
        raise LCSError(f"Lemke's method exceeded {max_pivots} pivots")
    u = zeros(k, 1)
    for i, v in enumerate(basic):
        if k <= v < 2 * k:
            u[v - k, 0] = t[i][rhs]
    y = q + m * u
    return LCPSolution(u, y, frozenset(v - k for v in basic if k <= v < 2 * k))


def solve_lcp(q: Any, m: Any) -> LCPSolution:
    """One solution of LCP(q, M): Murty when M is a P-matrix (unique, Theorem 3.4), else Lemke.

    Parameters
    ----------
    q : k-vector of rationals
        The vector q of LCP(q, M) (section 3): find u >= 0 with y = q + M u >= 0, u ⊥ y.
    m : k x k matrix of rationals
        The matrix M.

    >>> solve_lcp([-1, 1], [[2, 1], [1, 2]])
    LCPSolution(u=(1/2, 0), y=(0, 3/2))
    """
    m = to_matrix(m, "M")
    if m.nrows() != m.ncols():
        raise ShapeError(f"LCP: M must be square, got {m.nrows()}x{m.ncols()}")
    q = to_vector(q, m.nrows(), "q")
    if is_p_matrix(m):
        basis, u, y = murty(m, q)
        return LCPSolution(u, y, basis)
    sol = lemke(q, m)
    if sol is None:
        raise LCSError("LCP(q, M): Lemke's method ended on a secondary ray; for this M that "
                       "does not prove there is no solution (use all_solutions for small k)")
    return sol


def all_solutions(q: Any, m: Any) -> list[LCPSolution]:
    """Every solution of LCP(q, M) with a nonsingular complementary basis, by enumeration.

    When all principal minors of M are nonzero (e.g. a P-matrix) these are all solutions.
    Cost 2^k linear solves: for small k.

    Parameters
    ----------
    q : k-vector of rationals
        The vector q of LCP(q, M) (section 3).
    m : k x k matrix of rationals
        The matrix M.
    """
    m = to_matrix(m, "M")
    k = m.nrows()
    if m.ncols() != k:
        raise ShapeError(f"LCP: M must be square, got {k}x{m.ncols()}")
    q = to_vector(q, k, "q")
    check_enumerable(k, "all_solutions")
    found: list[LCPSolution] = []
    seen = set()
    for r in range(k + 1):
        for a in combinations(range(k), r):
            u = zeros(k, 1)
            if a:
                maa = submatrix(m, a, a)
                if maa.det() == 0:
                    continue
                ua = -maa.solve(submatrix(q, a, None))
                if any(ua[i, 0] < 0 for i in range(r)):
                    continue
                for i, j in enumerate(a):
                    u[j, 0] = ua[i, 0]
            y = q + m * u
            if any(y[i, 0] < 0 for i in range(k)):
                continue
            key = tuple(str(u[i, 0]) for i in range(k))
            if key not in seen:
                seen.add(key)
                found.append(LCPSolution(u, y, frozenset(i for i in a)))
    return found

"""subspaces.py: exact subspace arithmetic over Q (used for V_I, T_I, P_I in sections 3-4).

Expected values are checked with independent Fraction arithmetic (``reference.linalg``: rank,
spans, matrix products), and the two-carts values of section 7 are derived by hand.
"""
from __future__ import annotations

import random
from fractions import Fraction

import pytest
from flint import fmpq, fmpq_mat
from helpers import A_CARTS, carts, columns, mat, vec
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from lcs_exact.errors import ShapeError
from lcs_exact.algebra.subspaces import (complement, contains, image, intersection, kernel, left_kernel,
                                 projection, projection_along, rref, RowSpan, same_subspace, solve_any,
                                 subspace_sum)
from lcs_exact.algebra.subspaces import rank as lib_rank
from lcs_exact.algebra import invariant_forms, projected_forms, pulled_back_forms, row_basis, submatrix, vstack
from lcs_exact.examples import cart_chain

from reference.linalg import eye, mm, nullspace, rank, same_span
from reference.linalg import span_le as ref_span_le

PROP = settings(derandomize=True, deadline=None, max_examples=50)


# ---------------------------------------------------------------------------------------------
# the Fraction references (reference.linalg) on flint matrices
# ---------------------------------------------------------------------------------------------

def frank(m: fmpq_mat) -> int:
    """Rank in Fractions (rank of the column list = rank of m)."""
    return rank(columns(m))


def span_le(a: fmpq_mat, b: fmpq_mat) -> bool:
    """Im a ⊆ Im b (Fractions)."""
    return ref_span_le(columns(a), columns(b))


def is_zero_rows(rows) -> bool:
    return all(v == 0 for r in rows for v in r)


def fm(rows: list[list]) -> fmpq_mat:
    r = len(rows)
    c = len(rows[0]) if rows else 0
    return fmpq_mat(r, c, [fmpq(Fraction(v).numerator, Fraction(v).denominator) for row in rows for v in row])


# ---------------------------------------------------------------------------------------------
# strategies: small rational matrices, often rank deficient (products L R through a thin middle)
# ---------------------------------------------------------------------------------------------

entries = st.builds(Fraction, st.integers(-3, 3), st.sampled_from([1, 1, 1, 2, 3]))


@st.composite
def rat_matrix(draw, rows=None, cols_=None):
    r = draw(st.integers(1, 4)) if rows is None else rows
    c = draw(st.integers(1, 4)) if cols_ is None else cols_
    if draw(st.booleans()):
        k = draw(st.integers(1, 3))
        L = [[draw(entries) for _ in range(k)] for _ in range(r)]
        R = [[draw(entries) for _ in range(c)] for _ in range(k)]
        return fm(mm(L, R))
    return fm([[draw(entries) for _ in range(c)] for _ in range(r)])


@st.composite
def basis_split(draw):
    """An invertible n x n S (columns) and a split d: V = S[:, :d], T = S[:, d:]."""
    n = draw(st.integers(1, 4))
    S = [[draw(entries) for _ in range(n)] for _ in range(n)]
    assume(rank(S) == n)
    d = draw(st.integers(0, n))
    return n, S, d


def sub_cols(m: list[list[Fraction]], idx) -> fmpq_mat:
    idx = list(idx)
    return fmpq_mat(len(m), len(idx), [fmpq(m[i][j].numerator, m[i][j].denominator) for i in range(len(m)) for j in idx])


# ---------------------------------------------------------------------------------------------
# kernel, image, left kernel
# ---------------------------------------------------------------------------------------------

def test_kernel_by_hand():
    # x1 = 0, x3 = 0 leaves Im[e2 e4]
    K = kernel(fm([[1, 0, 0, 0], [0, 0, 1, 0]]))
    assert mat(K.transpose()) == [[0, 1, 0, 0], [0, 0, 0, 1]]
    # x + 2y + 3z = 0: kernel of dimension 2, e.g. (-2, 1, 0), (-3, 0, 1)
    K = kernel(fm([[1, 2, 3]]))
    assert K.ncols() == 2 and span_le(fm([[-2, -3], [1, 0], [0, 1]]), K) and span_le(K, fm([[-2, -3], [1, 0], [0, 1]]))
    # invertible: trivial kernel, an n x 0 matrix
    K = kernel(fm([[1, 2], [3, 4]]))
    assert (K.nrows(), K.ncols()) == (2, 0)
    # a 0 x n matrix has all of Q^n as kernel
    assert mat(kernel(fmpq_mat(0, 3))) == [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    # zero matrix: all of Q^2
    assert kernel(fmpq_mat(2, 2)).ncols() == 2


@given(rat_matrix())
@PROP
def test_kernel_properties(M):
    K = kernel(M)
    n = M.ncols()
    r = frank(M)
    assert K.nrows() == n
    assert K.ncols() == n - r                             # rank-nullity
    assert frank(K) == K.ncols()                          # a basis (independent columns)
    assert is_zero_rows(mm(mat(M), mat(K)))              # M * kernel(M) == 0
    assert lib_rank(M) == r


@pytest.mark.slow
@given(rat_matrix())
@PROP
def test_image_properties(M):
    Im = image(M)
    r = frank(M)
    assert Im.nrows() == M.nrows() and Im.ncols() == r == frank(Im)
    assert span_le(Im, M) and span_le(M, Im)
    # canonical: the same subspace from another spanning set gives the same basis
    doubled = fm([row + [2 * v for v in row] for row in mat(M)])  # [M, 2M]
    assert mat(image(doubled)) == mat(Im)


@given(rat_matrix())
@PROP
def test_left_kernel_properties(M):
    W = left_kernel(M)
    r = frank(M)
    assert W.ncols() == M.nrows()
    assert W.nrows() == M.nrows() - r
    assert is_zero_rows(mm(mat(W), mat(M)))              # W M = 0
    assert (rank(mat(W)) if W.nrows() else 0) == W.nrows()


def test_left_kernel_of_empty_column_block():
    assert mat(left_kernel(fmpq_mat(2, 0))) == [[1, 0], [0, 1]]


def test_rref_pivots():
    R, piv = rref(fm([[0, 2, 4], [0, 1, 3]]))
    # rows: (0, 1, 2), (0, 1, 3) -> (0, 1, 0), (0, 0, 1): pivots at columns 1, 2
    assert piv == [1, 2]
    assert mat(R) == [[0, 1, 0], [0, 0, 1]]


# ---------------------------------------------------------------------------------------------
# sums, intersections, complements, containment
# ---------------------------------------------------------------------------------------------

def test_sum_and_intersection_by_hand():
    V = fm([[1, 0], [0, 1], [0, 0]])       # the plane x3 = 0
    W = fm([[0, 0], [1, 0], [0, 1]])       # the plane x1 = 0
    X = intersection(V, W)
    assert mat(X.transpose()) == [[0, 1, 0]]     # the x2 axis
    assert subspace_sum(V, W).ncols() == 3
    line = fm([[1], [1], [1]])
    assert intersection(V, line).ncols() == 0
    assert (intersection(V, line).nrows(), intersection(fmpq_mat(3, 0), V).ncols()) == (3, 0)
    assert mat(subspace_sum(line, fm([[2], [2], [2]]))) == [[1], [1], [1]]


@given(rat_matrix(rows=4), rat_matrix(rows=4))
@PROP
def test_intersection_dimension_formula(A, B):
    V, W = image(A), image(B)
    X = intersection(V, W)
    S = subspace_sum(V, W)
    assert S.ncols() == rank(columns(A) + columns(B))            # dim(V + W), in Fractions
    assert X.ncols() == V.ncols() + W.ncols() - S.ncols()  # dim V∩W = dim V + dim W - dim(V+W)
    assert span_le(X, V) and span_le(X, W)
    assert frank(X) == X.ncols()
    assert span_le(V, S) and span_le(W, S)


@given(rat_matrix(rows=4), rat_matrix(rows=4))
@PROP
def test_contains_and_same_subspace(A, B):
    V = image(A)
    assert contains(V, A) and contains(A, V)
    assert same_subspace(V, image(A))
    assert contains(V, B) == span_le(B, A)
    both = subspace_sum(V, image(B))
    assert same_subspace(both, image(B)) == (span_le(A, B))
    # each column of B separately
    for j in range(B.ncols()):
        c = fmpq_mat(4, 1, [B[i, j] for i in range(4)])
        assert contains(V, c) == span_le(c, A)


def test_same_subspace_needs_equal_dimension():
    assert not same_subspace(fm([[1], [0]]), fm([[1, 0], [0, 1]]))
    assert same_subspace(fm([[1, 1], [0, 1]]), fm([[1, 0], [0, 1]]))
    assert not contains(fm([[1], [0]]), fm([[1], [1]]))


@given(rat_matrix(rows=4))
@PROP
def test_complement_properties(A):
    V = image(A)
    C = complement(V)
    assert C.ncols() == 4 - V.ncols()
    assert subspace_sum(V, C).ncols() == 4                 # V + C = Q^4
    assert intersection(V, C).ncols() == 0
    # spanned by coordinate vectors
    for j in range(C.ncols()):
        column = [C[i, j] for i in range(4)]
        assert sorted(column) == [0, 0, 0, 1]


def test_complement_of_zero_space():
    assert mat(complement(fmpq_mat(3, 0))) == [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


# ---------------------------------------------------------------------------------------------
# solve_any
# ---------------------------------------------------------------------------------------------

@given(rat_matrix(), st.data())
@PROP
def test_solve_any(M, data):
    r, c = M.nrows(), M.ncols()
    X0 = fm([[data.draw(entries) for _ in range(2)] for _ in range(c)])
    rhs = M * X0                                        # consistent
    X = solve_any(M, rhs)
    assert X is not None and (X.nrows(), X.ncols()) == (c, 2)
    assert mat(M * X) == mat(rhs)
    b = fm([[data.draw(entries)] for _ in range(r)])
    consistent = span_le(b, M)
    Y = solve_any(M, b)
    assert (Y is not None) == consistent
    if Y is not None:
        assert mat(M * Y) == mat(b)


def test_solve_any_by_hand_and_shape_error():
    # x + y = 1, x + y = 2: inconsistent
    assert solve_any(fm([[1, 1], [1, 1]]), fm([[1], [2]])) is None
    # x + y = 2 (free y = 0) -> (2, 0)
    assert mat(solve_any(fm([[1, 1]]), fm([[2]]))) == [[2], [0]]
    with pytest.raises(ShapeError):
        solve_any(fm([[1, 1]]), fm([[1], [2]]))


# ---------------------------------------------------------------------------------------------
# projection onto V along T
# ---------------------------------------------------------------------------------------------

@given(basis_split())
@PROP
def test_projection_properties(split):
    n, S, d = split
    V, T = sub_cols(S, range(d)), sub_cols(S, range(d, n))
    P = projection(V, T)
    Pm = mat(P)
    assert (P.nrows(), P.ncols()) == (n, n)
    assert mm(Pm, Pm) == Pm                                  # idempotent
    if d:
        assert mm(Pm, mat(V)) == mat(V)                      # P V = V
    if d < n:
        assert is_zero_rows(mm(Pm, mat(T)))                  # P T = 0
    # P S = [V 0] (independent characterization), and I - P projects onto T along V
    expected = [[S[i][j] if j < d else Fraction(0) for j in range(n)] for i in range(n)]
    assert mm(Pm, S) == expected
    Q = [[eye(n)[i][j] - Pm[i][j] for j in range(n)] for i in range(n)]
    assert mat(projection(T, V)) == Q
    assert frank(P) == d                                      # rank P = dim V


def test_projection_errors():
    with pytest.raises(ShapeError):
        projection(fm([[1], [0], [0]]), fm([[0], [1], [0]]))           # dims 1 + 1 != 3
    with pytest.raises(ShapeError):
        projection(fm([[1], [0]]), fm([[2], [0]]))                     # V = T: they intersect
    with pytest.raises(ShapeError):  # a "basis" of Q^2 with a dependency, T = 0: no solve sees it
        projection(fm([[1, 2], [1, 2]]), fmpq_mat(2, 0))
    with pytest.raises(ShapeError):
        projection(fmpq_mat(2, 0), fm([[1, 2], [1, 2]]))


# ---------------------------------------------------------------------------------------------
# the paper's two carts (sections 2, 7): mode {1} (0-based {0})
# ---------------------------------------------------------------------------------------------

def test_two_carts_V_T_P_by_hand():
    # y = x1 (C = e1^T).  In mode {0}: y = x1 = 0 and y' = x3 = 0 for all t (u enters y''), so
    # V_{1} = {x1 = x3 = 0} = Im[e2 e4] = Ker [C; CA].  The jump space is spanned by B = e3 and
    # A B = e1 (an impulse in u moves x3, its derivative x1): T_{1} = Im[e1 e3].
    A = fm(A_CARTS)
    C = fm([[1, 0, 0, 0]])
    B = fm([[0], [0], [1], [0]])
    V = kernel(fm([[1, 0, 0, 0], [0, 0, 1, 0]]))
    assert mat(C * A) == [[0, 0, 1, 0]]
    T = image(fm([[0, 1], [0, 0], [1, 0], [0, 0]]))
    assert mat(A * B) == [[1], [0], [0], [0]]
    assert mat(V.transpose()) == [[0, 1, 0, 0], [0, 0, 0, 1]]
    assert mat(T.transpose()) == [[1, 0, 0, 0], [0, 0, 1, 0]]
    P = projection(V, T)
    # P_{1} = diag(0, 1, 0, 1):  P_{1} (0, -1, -1, 0) = (0, -1, 0, 0)  (section 7's first jump)
    assert mat(P) == [[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]
    assert vec(P * fm([[0], [-1], [-1], [0]])) == [0, -1, 0, 0]
    # the mode object computes the same subspaces (canonical bases are equal)
    m = carts().mode({0})
    assert mat(m.consistent_subspace()) == mat(V)
    assert mat(m.jump_space()) == mat(T)
    assert mat(m.projection()) == mat(P)


def test_units_of_a_row_span_are_the_coordinates_it_holds():
    """e_i in rowspan(R) exactly for the unit rows of rref(R): R = [[1, 1, 0, 0], [1, -1, 0, 0],
    [0, 0, 1, 1]] holds e_0 and e_1 (sums and differences of its first two rows), not e_2 or e_3
    (only e_2 + e_3); checked against membership of each e_i."""
    Z = RowSpan(fmpq_mat([[1, 1, 0, 0], [1, -1, 0, 0], [0, 0, 1, 1]]))
    assert Z.units() == {0, 1}
    for i in range(4):
        e = fmpq_mat(1, 4, [int(j == i) for j in range(4)])
        assert (e in Z) == (i in Z.units()) == Z.has_unit(i)
    assert RowSpan(fmpq_mat(0, 4, [])).units() == frozenset()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 6 - 1), st.integers(0, 8), st.integers(0, 10 ** 6))
def test_projected_forms_are_the_forms_pulled_back_through_P_I(mask, z, seed):
    """For P_I of a mode of six coupled carts (n = 12) and random forms Z vanishing on v, the
    forms r with r P_I in rowspan(Z), computed from the small matrix Z T_I, span the same space as
    the kernel of [P^T, -Z^T] gives (the general pulled-back forms), and each vanishes on P_I v
    for a v with Z v = 0 (a rational v from the kernel of Z)."""
    rnd = random.Random(seed)
    lcs = cart_chain(6)
    mode = lcs.mode({i for i in range(lcs.k) if mask >> i & 1})
    n = lcs.n
    Z = fmpq_mat(z, n, [rnd.randint(-2, 2) for _ in range(z * n)])
    P = mode.projection()
    got = projected_forms(mode.annihilator(), mode.jump_space(), Z)
    assert got == row_basis(pulled_back_forms(P, Z))
    K = kernel(Z) if z else fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])
    if K.ncols():
        v = K * fmpq_mat(K.ncols(), 1, [rnd.randint(-3, 3) for _ in range(K.ncols())])
        assert all(e == 0 for e in (got * (P * v)).entries())


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 6), st.integers(0, 5), st.integers(0, 10 ** 6))
def test_invariant_forms_are_the_largest_invariant_part(n, r, seed):
    """invariant_forms(R, M) = {u : u M^j in rowspan(R) for every j}, computed here as the forms
    vanishing on the Krylov space K + M K + ... + M^(n-1) K of K = Ker R (reference rational
    arithmetic); M with small entries, R random rows, sometimes an invariant part planted (R
    holds e, e M, ..., e M^(n-1) for its first row e; then also with those rows passed as the
    ``known`` invariant forms and the rest as R: the same span)."""
    rnd = random.Random(seed)
    planted = False
    Mr = [[Fraction(rnd.randint(-2, 2)) if rnd.random() < 0.6 else Fraction(0) for _ in range(n)] for _ in range(n)]
    Rr = [[Fraction(rnd.randint(-2, 2)) for _ in range(n)] for _ in range(r)]
    if r and rnd.random() < 0.5:  # plant an M-invariant row span: e and e M, ..., e M^(n-1)
        e, planted = Rr[0], True
        for _ in range(n - 1):
            e = [sum(e[i] * Mr[i][j] for i in range(n)) for j in range(n)]
            Rr.append(e)
    M = fmpq_mat(n, n, [fmpq(int(x)) for row in Mr for x in row])
    R = fmpq_mat(len(Rr), n, [fmpq(x.numerator, x.denominator) for row in Rr for x in row]) if Rr else fmpq_mat(0, n)
    got = [[Fraction(int(U[i, j].p), int(U[i, j].q)) for j in range(n)] for U in [invariant_forms(R, M)]
           for i in range(U.nrows())]
    K = nullspace(Rr, n)
    krylov, layer = list(K), list(K)
    for _ in range(n - 1):
        layer = [[sum(Mr[i][j] * v[j] for j in range(n)) for i in range(n)] for v in layer]
        krylov += layer
    want = nullspace(krylov, n) if krylov else [[Fraction(int(i == j)) for j in range(n)] for i in range(n)]
    assert same_span(got, want)
    if planted:
        known, rest = [Rr[0]] + Rr[r:], Rr[1:r]
        as_mat = lambda rows: fmpq_mat(len(rows), n, [fmpq(x.numerator, x.denominator) for row in rows for x in row])
        U = invariant_forms(as_mat(rest) if rest else fmpq_mat(0, n), M, as_mat(known))
        assert same_span([[Fraction(int(U[i, j].p), int(U[i, j].q)) for j in range(n)] for i in range(U.nrows())], want)


@pytest.mark.parametrize("mask", [0, 0b1, 0b11, 0b101, 0b11111, 0b111111])
def test_projection_along_the_annihilator_is_P_I(mask):
    """I - T (W T)^{-1} W with W a row basis of V_I's annihilator and T a basis of T_I, on modes
    of six carts (n = 12), is the projection built from bases of V_I and T_I: idempotent, the
    identity on V_I, zero on T_I (reference arithmetic); W with a dependent row, or a T that does
    not split with Ker W, gives None."""
    lcs = cart_chain(6)
    m = lcs.mode({i for i in range(lcs.k) if mask >> i & 1})
    W, T = row_basis(m.annihilator()), m.jump_space()
    P = projection_along(W, T)
    assert P == projection(m.consistent_subspace(), T)
    Pr = [[Fraction(int(P[i, j].p), int(P[i, j].q)) for j in range(12)] for i in range(12)]
    assert mm(Pr, Pr) == Pr
    for v in columns(m.consistent_subspace()):
        assert [sum(Pr[i][j] * v[j] for j in range(12)) for i in range(12)] == v
    for t in columns(T):
        assert all(sum(Pr[i][j] * t[j] for j in range(12)) == 0 for i in range(12))
    if W.nrows():
        assert projection_along(vstack(W, submatrix(W, [0], None)), T) is None  # dependent rows
        assert projection_along(W, fmpq_mat(12, T.ncols())) is None  # W T singular


@pytest.mark.parametrize("seed", range(6))
def test_kernel_basis_has_unit_rows_and_spans_the_kernel(seed):
    """kernel_basis(m) = (K, free): m K = 0, K[free, :] = I, and K spans the kernel the
    reference's nullspace (Fractions) spans; kernel(m) is its canonical form."""
    from lcs_exact.algebra import kernel_basis
    rng = random.Random(seed)
    r, c = rng.randint(1, 6), rng.randint(2, 9)
    rows = [[Fraction(rng.choice([0, 0, 1, -2, 3]), rng.randint(1, 4)) for _ in range(c)] for _ in range(r)]
    if seed == 0:
        rows[-1] = rows[0][:]  # a dependent row
    m = fmpq_mat(r, c, [fmpq(x.numerator, x.denominator) for row in rows for x in row])
    K, free = kernel_basis(m)
    Kl = mat(K)
    assert all(x == 0 for row in mm(rows, Kl) for x in row)
    assert [[Kl[f][j] for j in range(len(free))] for f in free] == eye(len(free))
    ref = nullspace(rows, c)
    assert len(free) == len(ref) == c - rank(rows)
    assert same_span(columns(K), ref)
    assert kernel(m) == image(K)


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6), st.integers(0, 4), st.integers(0, 10 ** 6))
def test_rows_inside_a_span_at_once(n, r, seed):
    """RowSpan.rows_inside(F): the rows of F in span(R), against the reference rank test
    rank([R; f]) == rank(R) row by row; F mixes combinations of R's rows (inside), random rows
    (mostly outside), zero rows and rows whose product with the probe column vanishes."""
    from lcs_exact.algebra import RowSpan
    rnd = random.Random(seed)
    Rr = [[Fraction(rnd.randint(-2, 2)) for _ in range(n)] for _ in range(r)]
    Fr = []
    for _ in range(6):
        kind = rnd.randrange(4)
        if kind == 0 and Rr:
            cs = [Fraction(rnd.randint(-3, 3), rnd.randint(1, 3)) for _ in Rr]
            Fr.append([sum(c * row[j] for c, row in zip(cs, Rr)) for j in range(n)])
        elif kind == 1:
            Fr.append([Fraction(0)] * n)
        elif kind == 2 and n >= 2:  # f p = 0 for the probe p (p_0 f_0 + p_1 f_1 = 0), f != 0
            p0, p1 = 7919 % 65521 + 1, (7919 * 2) % 65521 + 1
            Fr.append([Fraction(p1), Fraction(-p0)] + [Fraction(0)] * (n - 2))
        else:
            Fr.append([Fraction(rnd.randint(-2, 2)) for _ in range(n)])
    R = fmpq_mat(len(Rr), n, [fmpq(x.numerator, x.denominator) for row in Rr for x in row]) if Rr else fmpq_mat(0, n)
    F = fmpq_mat(len(Fr), n, [fmpq(x.numerator, x.denominator) for row in Fr for x in row])
    want = [i for i, f in enumerate(Fr) if rank(Rr + [f]) == rank(Rr)] if Rr else \
        [i for i, f in enumerate(Fr) if not any(f)]
    assert RowSpan(R).rows_inside(F) == want

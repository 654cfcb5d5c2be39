"""Exact subspace arithmetic over Q on ``fmpq_mat`` (sections 3-4 use it for V_I, T_I, P_I).

Representation: a subspace of Q^n is an n x d ``fmpq_mat`` whose d columns are a basis (d = 0
is the zero subspace, an n x 0 matrix).  Every function returns such a basis, reduced
(columns of a reduced row echelon form of the transpose), so equal subspaces have equal bases.
"""
from __future__ import annotations

from flint import fmpq_mat

from .errors import ShapeError
from .rational import hstack, identity, submatrix, zeros

__all__ = [
    "rref", "rank", "kernel", "image", "left_kernel", "subspace_sum", "intersection",
    "complement", "contains", "same_subspace", "solve_any", "projection",
]


def rref(m: fmpq_mat) -> tuple[fmpq_mat, list[int]]:
    """Reduced row echelon form and the pivot columns."""
    if m.nrows() == 0 or m.ncols() == 0:
        return m, []
    r, rk = m.rref()
    pivots = []
    for i in range(rk):
        j = next(j for j in range(m.ncols()) if r[i, j] != 0)
        pivots.append(j)
    return r, pivots


def rank(m: fmpq_mat) -> int:
    return 0 if m.nrows() == 0 or m.ncols() == 0 else m.rank()


def kernel(m: fmpq_mat) -> fmpq_mat:
    """Basis (columns) of Ker m.

    >>> kernel(fmpq_mat([[1, 0, 0, 0], [0, 0, 1, 0]])).transpose()
    [0, 1, 0, 0]
    [0, 0, 0, 1]
    """
    n = m.ncols()
    if m.nrows() == 0:
        return identity(n)
    r, piv = rref(m)
    free = [j for j in range(n) if j not in piv]
    out = fmpq_mat(n, len(free))
    for c, f in enumerate(free):
        out[f, c] = 1
        for i, p in enumerate(piv):
            out[p, c] = -r[i, f]
    return image(out)


def image(m: fmpq_mat) -> fmpq_mat:
    """Canonical basis (columns) of Im m: the nonzero rows of rref(m^T), transposed."""
    n = m.nrows()
    if m.ncols() == 0:
        return zeros(n, 0)
    r, piv = rref(m.transpose())
    return submatrix(r, range(len(piv)), None).transpose() if piv else zeros(n, 0)


def left_kernel(m: fmpq_mat) -> fmpq_mat:
    """Rows spanning {w : w m = 0} (returned as a d x nrows matrix)."""
    if m.ncols() == 0:
        return identity(m.nrows())
    return kernel(m.transpose()).transpose()


def subspace_sum(*spaces: fmpq_mat) -> fmpq_mat:
    """V1 + V2 + ..."""
    return image(hstack(*spaces))


def intersection(v: fmpq_mat, w: fmpq_mat) -> fmpq_mat:
    """V ∩ W from bases: the kernel of [V, -W] mapped through V."""
    n = v.nrows()
    if v.ncols() == 0 or w.ncols() == 0:
        return zeros(n, 0)
    k = kernel(hstack(v, -w))
    if k.ncols() == 0:
        return zeros(n, 0)
    return image(v * submatrix(k, range(v.ncols()), None))


def complement(v: fmpq_mat) -> fmpq_mat:
    """A complement of V in Q^n spanned by coordinate vectors (the non-pivot coordinates)."""
    n = v.nrows()
    _, piv = rref(v.transpose()) if v.ncols() else (None, [])
    free = [j for j in range(n) if j not in piv]
    return submatrix(identity(n), None, free)


def contains(v: fmpq_mat, x: fmpq_mat) -> bool:
    """x (columns) lies in Im v."""
    return rank(hstack(v, x)) == rank(v)


def same_subspace(v: fmpq_mat, w: fmpq_mat) -> bool:
    return v.ncols() == w.ncols() and contains(v, w) and contains(w, v)


def solve_any(m: fmpq_mat, rhs: fmpq_mat) -> fmpq_mat | None:
    """One solution X of m X = rhs (free variables set to 0), or None when inconsistent."""
    r, c = m.nrows(), m.ncols()
    if rhs.nrows() != r:
        raise ShapeError(f"solve_any: rhs has {rhs.nrows()} rows, matrix has {r}")
    k = rhs.ncols()
    if r == 0:
        return zeros(c, k)
    aug, piv = rref(hstack(m, rhs))
    if any(p >= c for p in piv):
        return None
    x = zeros(c, k)
    for i, p in enumerate(piv):
        for j in range(k):
            x[p, j] = aug[i, c + j]
    return x


def projection(v: fmpq_mat, t: fmpq_mat) -> fmpq_mat:
    """The projection P onto V along T (requires V ⊕ T = Q^n): P = [V 0] [V T]^{-1}.

    >>> v = fmpq_mat([[0, 0], [1, 0], [0, 0], [0, 1]]); t = fmpq_mat([[0, 1], [0, 0], [1, 0], [0, 0]])
    >>> projection(v, t) * fmpq_mat([[0], [-1], [-1], [0]])
    [ 0]
    [-1]
    [ 0]
    [ 0]
    """
    n = v.nrows()
    if v.ncols() + t.ncols() != n:
        raise ShapeError(f"V (dim {v.ncols()}) and T (dim {t.ncols()}) do not split Q^{n}")
    s = hstack(v, t) if n else zeros(0, 0)
    if n == 0:
        return s
    if s.det() == 0:
        raise ShapeError("V and T intersect: no projection onto V along T")
    # coordinates of e_j in the basis [V T]: S^{-1}; keep the V block
    coords = s.solve(identity(n))
    return v * submatrix(coords, range(v.ncols()), None) if v.ncols() else zeros(n, n)


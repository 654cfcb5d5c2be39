"""Exact linear algebra over Q in ``fractions.Fraction``: matrices are lists of rows, vectors
lists; entries may be int, str, Fraction or anything with integer ``p`` and ``q`` (flint's fmpq)
and are converted by :func:`F` where it matters.  An independent reference for the library's
flint computations (Gauss-Jordan elimination written out here)."""
from __future__ import annotations

from fractions import Fraction
from itertools import combinations


def F(x) -> Fraction:
    """int / str / Fraction / flint fmpq (anything with integer ``p`` and ``q``) -> Fraction."""
    if hasattr(x, "p") and hasattr(x, "q"):
        return Fraction(int(x.p), int(x.q))
    return Fraction(x)


def fmat(a) -> list[list[Fraction]]:
    """A matrix (rows of numbers) with Fraction entries."""
    return [[F(v) for v in r] for r in a]


# ---------------------------------------------------------------------------------------------
# construction and arithmetic
# ---------------------------------------------------------------------------------------------

def zeros(r, c):
    return [[Fraction(0)] * c for _ in range(r)]


def eye(n):
    return [[Fraction(int(i == j)) for j in range(n)] for i in range(n)]


def mm(a, b):
    """Matrix product (b may have zero columns only if a has columns)."""
    cols = len(b[0]) if b else 0
    return [[sum((a[i][l] * b[l][j] for l in range(len(b))), Fraction(0)) for j in range(cols)]
            for i in range(len(a))]


def mv(a, v):
    """Matrix times vector (entries converted by F)."""
    return [sum((F(x) * F(y) for x, y in zip(r, v)), Fraction(0)) for r in a]


def madd(a, b):
    return [[x + y for x, y in zip(r, s)] for r, s in zip(a, b)]


def mscale(c, a):
    return [[c * x for x in r] for r in a]


def tr(a):
    return [list(r) for r in zip(*a)] if a else []


def rows(a, idx):
    return [a[i] for i in idx]


def sub(a, ri, ci):
    return [[a[i][j] for j in ci] for i in ri]


def subsets(s):
    """Every subset of s, as frozensets, by size."""
    s = sorted(s)
    return [frozenset(c) for r in range(len(s) + 1) for c in combinations(s, r)]


# ---------------------------------------------------------------------------------------------
# elimination
# ---------------------------------------------------------------------------------------------

def rref(a):
    """Reduced row echelon form (Fractions) and pivot columns (Gauss-Jordan over Q)."""
    a = [[F(x) for x in r] for r in a]
    piv, r = [], 0
    ncols = len(a[0]) if a else 0
    for c in range(ncols):
        p = next((i for i in range(r, len(a)) if a[i][c] != 0), None)
        if p is None:
            continue
        a[r], a[p] = a[p], a[r]
        a[r] = [x / a[r][c] for x in a[r]]
        for i in range(len(a)):
            if i != r and a[i][c] != 0:
                f = a[i][c]
                a[i] = [x - f * y for x, y in zip(a[i], a[r])]
        piv.append(c)
        r += 1
    return a, piv


def rank(a) -> int:
    """Rank of a list of rows (0 for no rows or rows of length 0)."""
    return len(rref(a)[1]) if a else 0


def det(a) -> Fraction:
    """Determinant by Fraction elimination (row swaps counted)."""
    a = [[F(x) for x in r] for r in a]
    n = len(a)
    d = Fraction(1)
    for c in range(n):
        p = next((i for i in range(c, n) if a[i][c] != 0), None)
        if p is None:
            return Fraction(0)
        if p != c:
            a[c], a[p] = a[p], a[c]
            d = -d
        d *= a[c][c]
        for i in range(c + 1, n):
            f = a[i][c] / a[c][c]
            a[i] = [x - f * y for x, y in zip(a[i], a[c])]
    return d


def solve(a, b):
    """x with a x = b for square a (b a vector); None if a is singular."""
    n = len(a)
    red, piv = rref([list(a[i]) + [F(b[i])] for i in range(n)])
    if piv != list(range(n)):
        return None
    return [red[i][n] for i in range(n)]


def inverse(a):
    n = len(a)
    red, piv = rref([list(a[i]) + eye(n)[i] for i in range(n)])
    assert piv == list(range(n)), "singular matrix"
    return [r[n:] for r in red]


def nullspace(a, n):
    """A basis (list of vectors) of {x in Q^n : a x = 0}; a may have no rows."""
    if not a:
        return eye(n)
    red, piv = rref(a)
    basis = []
    for f in (c for c in range(n) if c not in piv):
        x = [Fraction(0)] * n
        x[f] = Fraction(1)
        for r, p in enumerate(piv):
            x[p] = -red[r][f]
        basis.append(x)
    return basis


def pinv_rows(E):
    """E^T (E E^T)^{-1} for E of full row rank."""
    return mm(tr(E), inverse(mm(E, tr(E))))


# ---------------------------------------------------------------------------------------------
# spans (subspaces given by spanning vectors)
# ---------------------------------------------------------------------------------------------

def span_le(a: list, b: list) -> bool:
    """span(a) ⊆ span(b), for lists of vectors."""
    if not a:
        return True
    if not b:
        return all(all(v == 0 for v in c) for c in a)
    return rank(b) == rank(b + a)


def same_span(a: list, b: list) -> bool:
    """span(a) = span(b), for lists of vectors."""
    return rank(a) == rank(b) == rank(a + b) if (a or b) else True


# ---------------------------------------------------------------------------------------------
# principal minors and P-matrices (section 3)
# ---------------------------------------------------------------------------------------------

def principal_minors(a) -> dict[tuple, Fraction]:
    """Every principal minor det a[idx, idx] (idx a nonempty increasing tuple)."""
    k = len(a)
    return {idx: det(sub(a, idx, idx)) for r in range(1, k + 1) for idx in combinations(range(k), r)}


def is_P(a) -> bool:
    """All principal minors positive."""
    return all(v > 0 for v in principal_minors(a).values())

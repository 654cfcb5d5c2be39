"""Shared helpers for the tests: exact conversions and the paper's systems."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest
from flint import fmpq, fmpq_mat

from lcs_exact import LCS

A_CARTS = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]


def carts() -> LCS:
    """Two carts (2.1) with ẋ4 = x1 - x2."""
    return LCS(A_CARTS, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])


def hook() -> LCS:
    """Two carts with stop and hook (Example 8.3), written out by hand from (8.12)."""
    return LCS(A_CARTS, [[0, 0], [0, 0], [1, 1], [0, -1]], [[1, 0, 0, 0], [1, -1, 0, 0]], [[0, 0], [0, 0]])


def F(x) -> Fraction:
    if isinstance(x, fmpq):
        return Fraction(int(x.p), int(x.q))
    return Fraction(x)


def vec(x: fmpq_mat) -> list[Fraction]:
    """An n x 1 (or 1 x n) fmpq_mat as a list of Fractions."""
    if x.ncols() == 1:
        return [F(x[i, 0]) for i in range(x.nrows())]
    return [F(x[0, j]) for j in range(x.ncols())]


def mat(m: fmpq_mat) -> list[list[Fraction]]:
    return [[F(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())]


def matvec(m, v) -> list[Fraction]:
    m = mat(m) if isinstance(m, fmpq_mat) else m
    return [sum((F(a) * F(b) for a, b in zip(r, v)), Fraction(0)) for r in m]


def rank(rows: list[list[Fraction]]) -> int:
    a = [list(map(Fraction, r)) for r in rows]
    r = 0
    for c in range(len(a[0]) if a else 0):
        p = next((i for i in range(r, len(a)) if a[i][c] != 0), None)
        if p is None:
            continue
        a[r], a[p] = a[p], a[r]
        for i in range(len(a)):
            if i != r and a[i][c] != 0:
                f = a[i][c] / a[r][c]
                a[i] = [x - f * y for x, y in zip(a[i], a[r])]
        r += 1
    return r


def fdet(a: list[list[Fraction]]) -> Fraction:
    """Determinant by Fraction elimination (an independent reference for the flint results)."""
    a = [list(map(Fraction, r)) for r in a]
    n = len(a)
    det = Fraction(1)
    for c in range(n):
        p = next((i for i in range(c, n) if a[i][c] != 0), None)
        if p is None:
            return Fraction(0)
        if p != c:
            a[c], a[p] = a[p], a[c]
            det = -det
        det *= a[c][c]
        for i in range(c + 1, n):
            f = a[i][c] / a[c][c]
            a[i] = [x - f * y for x, y in zip(a[i], a[c])]
    return det


def same_span(basis: fmpq_mat, cols: list[list[int]]) -> bool:
    """Im(basis) (columns) equals span(cols)."""
    b = [[F(basis[i, j]) for i in range(basis.nrows())] for j in range(basis.ncols())]
    c = [[Fraction(v) for v in col] for col in cols]
    return rank(b) == rank(c) == rank(b + c) if (b or c) else True


def modes(*sets) -> set:
    return {frozenset(s) for s in sets}


TOL = mp.mpf(10) ** -28


def num(r, digits: int = 40):
    """An exact real from the library as an mpf (the midpoint of its certified ball)."""
    return mp.mpf(r.ball(digits).mid().str(digits + 5, radius=False))


def close(a, b, tol=TOL) -> bool:
    """|a - b| <= tol * max(1, |b|) (28 digits by default)."""
    return abs(a - b) <= tol * max(1, abs(b))


def mpmath_digits(dps: int):
    """An autouse fixture running every test of a module with mpmath at ``dps`` digits (whatever
    other modules set); assign it to a module-level name: ``_mp = mpmath_digits(60)``."""
    @pytest.fixture(autouse=True)
    def _fixture():
        old = mp.mp.dps
        mp.mp.dps = dps
        yield
        mp.mp.dps = old
    return _fixture

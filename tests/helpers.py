"""Shared helpers for the tests: exact conversions of the library's objects, the paper's systems,
tolerances.  The independent reference implementations (oracles) live in ``tests/reference``."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest
from flint import fmpq_mat

from lcs_exact import LCS
from reference.linalg import F

A_CARTS = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]


def carts() -> LCS:
    """Two carts (2.1) with ẋ4 = x1 - x2."""
    return LCS(A_CARTS, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])


def hook() -> LCS:
    """Two carts with stop and hook (Example 8.3), written out by hand from (8.12)."""
    return LCS(A_CARTS, [[0, 0], [0, 0], [1, 1], [0, -1]], [[1, 0, 0, 0], [1, -1, 0, 0]], [[0, 0], [0, 0]])


def vec(x: fmpq_mat) -> list[Fraction]:
    """An n x 1 (or 1 x n) fmpq_mat as a list of Fractions."""
    if x.ncols() == 1:
        return [F(x[i, 0]) for i in range(x.nrows())]
    return [F(x[0, j]) for j in range(x.ncols())]


def column(x: fmpq_mat) -> tuple[Fraction, ...]:
    """An n x 1 fmpq_mat (and nothing else) as a tuple of Fractions."""
    assert x.ncols() == 1
    return tuple(F(x[i, 0]) for i in range(x.nrows()))


def mat(m: fmpq_mat) -> list[list[Fraction]]:
    """An fmpq_mat as a list of rows of Fractions."""
    return [[F(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())]


def columns(m: fmpq_mat) -> list[list[Fraction]]:
    """The columns of an fmpq_mat as lists of Fractions (the spanning vectors of its image)."""
    return [[F(m[i, j]) for i in range(m.nrows())] for j in range(m.ncols())]


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

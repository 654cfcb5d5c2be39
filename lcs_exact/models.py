"""Builders for common linear complementarity systems.

* :func:`mechanical`: M q'' + D q' + K q = E^T u, y = E q (8.1)-(8.3), state x = (q, q').
* :func:`two_carts`, :func:`two_carts_with_hook`: the paper's examples (section 2, Example 8.3).
"""
from __future__ import annotations

from typing import Any

from .errors import ShapeError
from .rational import hstack, identity, to_matrix, vstack, zeros
from .system import LCS

__all__ = ["mechanical", "two_carts", "two_carts_with_hook"]


def mechanical(M: Any, D: Any, K: Any, E: Any, *, name: str | None = None) -> LCS:
    """The LCS (8.3) of a linear mechanical system with unilateral constraints E q >= 0.

    A = [[0, I], [-M^{-1} K, -M^{-1} D]], B = [[0], [M^{-1} E^T]], C = [E, 0], D = 0.
    M must be invertible (positive definite for Theorem 8.2); E is k x m.

    >>> two = mechanical([[1, 0], [0, 1]], [[0, 0], [0, 0]], [[2, -1], [-1, 1]], [[1, 0]])
    >>> two.A == two_carts().A
    True
    """
    Mm = to_matrix(M, "M")
    m = Mm.nrows()
    if Mm.ncols() != m:
        raise ShapeError(f"mass matrix M must be square, got {m}x{Mm.ncols()}")
    Dm, Km = to_matrix(D, "D", (m, m)), to_matrix(K, "K", (m, m))
    Em = to_matrix(E, "E", (None, m))
    k = Em.nrows()
    if Mm.det() == 0:
        raise ShapeError("mass matrix M is singular")
    Minv = Mm.solve(identity(m))
    A = vstack(hstack(zeros(m, m), identity(m)), hstack(-(Minv * Km), -(Minv * Dm)))
    B = vstack(zeros(m, k), Minv * Em.transpose())
    C = hstack(Em, zeros(k, m))
    return LCS(A, B, C, zeros(k, k), name=name)


def two_carts() -> LCS:
    """Two carts, a spring to the wall and an inelastic stop at x1 = 0 (section 2, (2.1))."""
    return LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]],
               [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]], name="two carts (section 2)")


def two_carts_with_hook() -> LCS:
    """The two carts with a stop (y1 = x1) and a hook (y2 = x1 - x2) (Example 8.3, (8.12))."""
    return mechanical([[1, 0], [0, 1]], [[0, 0], [0, 0]], [[2, -1], [-1, 1]], [[1, 0], [1, -1]],
                      name="two carts with hook (Example 8.3)")

"""Linear mechanical systems with unilateral constraints as LCSs (section 8, (8.1)-(8.3)).

    M q'' + D q' + K q = E^T u,   y = E q,   0 <= y ⊥ u >= 0

with state x = (q, q') becomes (8.3): A = [[0, I], [-M^{-1} K, -M^{-1} D]], B = [[0], [M^{-1} E^T]],
C = [E, 0], D = 0.  u are the contact forces (Lagrange multipliers of the constraints E q >= 0).
With M positive definite and E of full row rank the system is well-posed (Theorem 8.2: M = N =
E M^{-1} E^T), and its re-initializations are Moreau's rule (Minimization problem 8.1).
"""
from __future__ import annotations

from typing import Any

from .errors import InvalidArgument, ShapeError
from .rational import hstack, identity, to_matrix, vstack, zeros
from .system import LCS

__all__ = ["mechanical"]


def mechanical(M: Any, K: Any, E: Any, *legacy: Any, damping: Any = None, name: str | None = None,
               q_names: Any = None, constraint_names: Any = None, D: Any = None) -> LCS:
    """The LCS (8.3) of M q'' + damping q' + K q = E^T u, y = E q, 0 <= y ⊥ u >= 0.

    Parameters
    ----------
    M : m x m matrix
        Mass matrix, invertible (positive definite for Theorem 8.2).
    K : m x m matrix
        Stiffness matrix.
    E : k x m matrix
        Constraint matrix: the constraints are E q >= 0 (a flat list is one constraint).
    damping : m x m matrix, optional
        Damping matrix (the paper's D); zero by default.  ``D=`` is accepted as its old name.
    name : str, optional
    q_names : sequence of m str, optional
        Names of the coordinates q; default ``q_0, ..., q_{m-1}``.  The state names are the
        q names followed by the same names primed (the velocities): ``q_0, q_1, q_0', q_1'``.
    constraint_names : sequence of k str, optional

    Notes
    -----
    The old call ``mechanical(M, D, K, E)`` (four positional arguments, damping second) keeps
    working: a fourth positional argument always means that order.  New code passes damping by
    keyword: ``mechanical(M, K, E, damping=D)``.

    Examples
    --------
    The two carts of section 2 (unit masses, springs 1 and 1, a stop at q_0 >= 0):

    >>> carts = mechanical([[1, 0], [0, 1]], [[2, -1], [-1, 1]], [[1, 0]], constraint_names=["stop"])
    >>> carts.A
    [ 0,  0, 1, 0]
    [ 0,  0, 0, 1]
    [-2,  1, 0, 0]
    [ 1, -1, 0, 0]
    >>> carts.state_names
    ('q_0', 'q_1', "q_0'", "q_1'")
    >>> mechanical([[1, 0], [0, 1]], [[0, 0], [0, 0]], [[2, -1], [-1, 1]], [[1, 0]]).A == carts.A  # old order
    True
    """
    if legacy:
        if len(legacy) > 1:
            raise InvalidArgument(f"mechanical() takes M, K, E (and damping=...), or the old M, D, K, E; "
                            f"got {3 + len(legacy)} positional arguments")
        if damping is not None or D is not None:
            raise InvalidArgument("mechanical(M, D, K, E) with damping= or D= as well: give the damping once")
        M, damping, K, E = M, K, E, legacy[0]  # the old order (M, D, K, E)
    if D is not None:
        if damping is not None:
            raise InvalidArgument("give the damping once: damping= or its old name D=, not both")
        damping = D
    Mm = to_matrix(M, "M")
    m = Mm.nrows()
    if m == 0 or Mm.ncols() != m:
        raise ShapeError(f"mass matrix M must be square and nonempty, got {m}x{Mm.ncols()}")
    Km = to_matrix(K, "K", (m, m))
    Dm = zeros(m, m) if damping is None else to_matrix(damping, "damping", (m, m))
    if isinstance(E, (list, tuple)) and E and not isinstance(E[0], (list, tuple)) and not hasattr(E[0], "tolist"):
        E = [list(E)]  # a flat list is one constraint row
    Em = to_matrix(E, "E", (None, m))
    k = Em.nrows()
    if k == 0:
        raise ShapeError("E has no rows: give at least one constraint E q >= 0")
    if Mm.det() == 0:
        raise ShapeError("mass matrix M is singular")
    if q_names is None:
        q_names = tuple(f"q_{i}" for i in range(m))
    elif isinstance(q_names, str) or not hasattr(q_names, "__iter__") or len(tuple(q_names)) != m:
        raise ShapeError(f"q_names must be {m} names (one per coordinate), got {q_names!r}")
    q_names = tuple(q_names)
    if not all(isinstance(q, str) and q for q in q_names):
        raise InvalidArgument(f"q_names must be nonempty strings, got {q_names!r}")
    Minv = Mm.solve(identity(m))
    A = vstack(hstack(zeros(m, m), identity(m)), hstack(-(Minv * Km), -(Minv * Dm)))
    B = vstack(zeros(m, k), Minv * Em.transpose())
    C = hstack(Em, zeros(k, m))
    return LCS(A, B, C, zeros(k, k), name=name, state_names=q_names + tuple(f"{q}'" for q in q_names),
               constraint_names=constraint_names)

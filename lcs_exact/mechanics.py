"""Linear mechanical systems with unilateral constraints as LCSs (section 8, (8.1)-(8.3)).

    M q'' + D q' + K q = f(t) + E^T u,   y = E q + g(t),   0 <= y ⊥ u >= 0

with state x = (q, q') becomes (8.3): A = [[0, I], [-M^{-1} K, -M^{-1} D]], B = [[0], [M^{-1} E^T]],
C = [E, 0], D = 0.  u are the contact forces (Lagrange multipliers of the constraints E q >= 0).
With M positive definite and E of full row rank the system is well-posed (Theorem 8.2: M = N =
E M^{-1} E^T), and its re-initializations are Moreau's rule (Minimization problem 8.1).

Beyond the paper (docs/extensions.md): a force f (gravity -m g, a constant push, a sinusoidal
excitation) and gaps g (constant offsets of the constraints: a floor at height -r) are sources
(:mod:`lcs_exact.sources`) carried by appended exosystem states (:mod:`lcs_exact.exosystems`:
the state is (q, q', z), ``lcs.embed([q..., q'...])`` appends z(0)); ``restitution`` replaces the
inelastic impacts by Newton's law with Moreau's generalisation (:mod:`lcs_exact.impacts`).
"""
from __future__ import annotations

from typing import Any

from .errors import InvalidArgument, ShapeError
from .exosystems import extend
from .rational import as_list, hstack, identity, submatrix, to_matrix, vstack, zeros
from .sources import as_source, exosystem
from .system import LCS

__all__ = ["mechanical"]


def mechanical(M: Any, K: Any, E: Any, *legacy: Any, damping: Any = None, force: Any = None, gap: Any = None,
               restitution: Any = None, name: str | None = None, q_names: Any = None,
               constraint_names: Any = None, D: Any = None) -> LCS:
    """The LCS (8.3) of M q'' + damping q' + K q = force + E^T u, y = E q + gap, 0 <= y ⊥ u >= 0.

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
    force : sequence of m rationals or Source objects, optional
        External force on each coordinate: a constant (gravity: ``-m g``) or a source of
        :mod:`lcs_exact.sources` (``sine(omega, F0)``); one entry per coordinate (a single entry
        for m = 1).  Carried by appended exosystem states.
    gap : sequence of k rationals or Source objects, optional
        Offsets of the constraints, y = E q + gap >= 0 (a floor at q_0 = -1/10 is gap 1/10).
    restitution : rational or sequence of k rationals in [0, 1], optional
        Newton's impact law (Moreau's generalisation for simultaneous impacts), see
        :mod:`lcs_exact.impacts`; the default None is the paper's inelastic impact (e = 0 gives
        the same jumps).
    name : str, optional
    q_names : sequence of m str, optional
        Names of the coordinates q; default ``q_0, ..., q_{m-1}``.  The state names are the
        q names followed by the same names primed (the velocities): ``q_0, q_1, q_0', q_1'``,
        then the exosystem's states (``'1'`` for constant forces and gaps, ``'sin(2t)'``, ...).
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

    A ball of unit mass dropped under gravity g = 10 onto a floor, bouncing with e = 1/2 (the
    constant force -10 is carried by the state '1'):

    >>> ball = mechanical([[1]], [[0]], [[1]], force=[-10], restitution="1/2", q_names=["h"])
    >>> ball.A, ball.state_names, ball.embed([5, 0]).transpose()
    ([0, 1,   0]
    [0, 0, -10]
    [0, 0,   0], ('h', "h'", '1'), [5, 0, 1])
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
    names = q_names + tuple(f"{q}'" for q in q_names)
    cn = tuple(constraint_names) if constraint_names is not None else tuple(str(i) for i in range(k))
    roles = tuple((f"force ({c})", f"gap ({c})", "contact", "open") for c in cn)
    forces = _sources(force, m, "force", "coordinate")
    gaps = _sources(gap, k, "gap", "constraint")
    if forces is None and gaps is None:
        return LCS(A, B, C, zeros(k, k), name=name, state_names=names, constraint_names=constraint_names,
                   restitution=restitution, roles=roles)
    forces = forces or [0] * m
    gaps = gaps or [0] * k
    ex = exosystem(forces + gaps)
    Wf = submatrix(ex.W, range(m), None)
    Wg = submatrix(ex.W, range(m, m + k), None)
    EW = vstack(zeros(m, ex.size), Minv * Wf)  # q'' gets M^{-1} f
    return extend(A, B, C, zeros(k, k), EW, Wg, ex, name=name, state_names=names,
                  constraint_names=constraint_names, restitution=restitution, roles=roles)


def _sources(values: Any, count: int, what: str, per: str) -> list | None:
    """``force`` / ``gap`` as a list of ``count`` sources (a single value when count = 1), or None."""
    if values is None:
        return None
    if isinstance(values, (str, bytes)) or getattr(values, "ndim", None) == 0 or \
            not isinstance(values, (list, tuple)) and not hasattr(values, "tolist"):  # one value (a numpy scalar too)
        if count != 1:
            raise ShapeError(f"{what} must have one entry per {per} ({count}), got a single value {values!r}")
        values = [values]
    values = list(as_list(values) if hasattr(values, "tolist") else values)
    if len(values) == count and all(isinstance(v, (list, tuple)) and len(v) == 1 for v in values):
        values = [v[0] for v in values]  # a column
    if len(values) != count:
        raise ShapeError(f"{what} has {len(values)} entries, expected one per {per} ({count})")
    out = [as_source(v, f"{what}[{i}]") for i, v in enumerate(values)]
    return None if all(not s.terms for s in out) else out

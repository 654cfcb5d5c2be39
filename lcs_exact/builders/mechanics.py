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

Compliant contacts (``compliance``): y = E q + g(t) + C_c u with a compliance C_c (the LCS's
D = C_c): a constraint with c_i > 0 is a one-sided spring of stiffness 1/c_i, u_i = max(0,
-(E_i q + g_i)/c_i) when C_c is diagonal.  Its row has relative degree 0 (H_0 = D), so with C_c a
P-matrix on the compliant constraints the leading matrices are P-matrices (Theorem 6.3) and no
compliant constraint ever takes an impulse: every state is consistent for it, and the force is a
continuous function of the state.  A zero compliance keeps a constraint rigid (its row and column
of C_c must then be zero).  Newton's law (``restitution``) acts on the velocity jump of an
impact, which a compliant contact never has (its spring is elastic: the energy it stores during
contact is given back at lift-off): with a compliance, ``restitution`` is one entry per
constraint, None for each compliant one, and acts on the rigid contacts alone (a compliant floor
under a rigid ceiling with e = 1, as Siconos' BouncingBallTS-CompliantContact).
"""
from __future__ import annotations

from typing import Any

from ..errors import InvalidArgument, ShapeError
from .exosystems import extend
from ..algebra import p_matrix_violation
from ..algebra import as_list, hstack, identity, submatrix, to_fmpq, to_matrix, vstack, zeros
from ..system import as_source, exosystem
from ..system import LCS

__all__ = ["mechanical"]


def mechanical(M: Any, K: Any, E: Any, *legacy: Any, damping: Any = None, force: Any = None, gap: Any = None,
               restitution: Any = None, compliance: Any = None, name: str | None = None, q_names: Any = None,
               constraint_names: Any = None, D: Any = None) -> LCS:
    """The LCS (8.3) of M q'' + damping q' + K q = force + E^T u, y = E q + gap + compliance u,
    0 <= y ⊥ u >= 0.

    Parameters
    ----------
    M : m x m matrix
        Mass matrix, invertible (positive definite for Theorem 8.2).
    K : m x m matrix
        Stiffness matrix.
    E : k x m matrix
        Constraint matrix: the constraints are E q >= 0 (a flat list is one constraint).
    damping, D : m x m matrix, optional
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
        the same jumps).  With ``compliance``: one entry per constraint, None for each
        compliant one (a compliant contact takes no impulse; the law acts on the rigid ones).
    compliance : rational, sequence of k rationals, or k x k matrix, optional
        Compliant contacts: y = E q + gap + compliance u (the LCS's D).  A rational is the
        compliance of every constraint, a sequence one per constraint (the diagonal), a matrix
        the whole coupling.  Diagonal entries are >= 0; a zero one keeps its constraint rigid
        (its row and column must then be zero) and the compliant constraints' block must be a
        P-matrix (a symmetric positive definite compliance is one).  A constraint with
        compliance c > 0 is a one-sided spring of stiffness 1/c (u = max(0, -(E q + gap)/c)):
        no impulses, no jumps.  Default: rigid contacts (D = 0, the paper's (8.3)).
    name : str, optional
    q_names : sequence of m str, optional
        Names of the coordinates q; default ``q_0, ..., q_{m-1}``.  The state names are the
        q names followed by the same names primed (the velocities): ``q_0, q_1, q_0', q_1'``,
        then the exosystem's states (``'1'`` for constant forces and gaps, ``'sin(2t)'``, ...).
    constraint_names : sequence of k str, optional
    *legacy
        The old call's damping, ``mechanical(M, D, K, E)`` (see Notes).

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

    The same ball on a compliant floor (compliance 1/100: a one-sided spring of stiffness 100),
    y = h + u/100; the contact force is u = max(0, -100 h):

    >>> soft = mechanical([[1]], [[0]], [[1]], force=[-10], compliance="1/100", q_names=["h"])
    >>> soft.D, soft.markov(0) == soft.D
    ([1/100], True)
    """
    M, K, E, damping = _damping_in_either_order(M, K, E, legacy, damping, D)
    Mm, Km, Dm, Em = _mechanical_matrices(M, K, damping, E)
    m, k = Mm.nrows(), Em.nrows()
    q_names = _coordinate_names(q_names, m)
    A, B, C, Minv = _first_order_form(Mm, Km, Dm, Em)
    names = q_names + tuple(f"{q}'" for q in q_names)
    cn = tuple(constraint_names) if constraint_names is not None else tuple(str(i) for i in range(k))
    roles = tuple((f"force ({c})", f"gap ({c})", "contact", "open") for c in cn)
    forces = _sources(force, m, "force", "coordinate")
    gaps = _sources(gap, k, "gap", "constraint")
    Dc = _compliance(compliance, k, cn)
    _check_restitution(restitution, Dc, cn)
    options = dict(name=name, state_names=names, constraint_names=constraint_names, restitution=restitution,
                   roles=roles)
    if forces is None and gaps is None:
        return LCS(A, B, C, Dc, **options)
    return _with_forces_and_gaps(A, B, C, Dc, Minv, forces or [0] * m, gaps or [0] * k, options)


def _damping_in_either_order(M: Any, K: Any, E: Any, legacy: tuple, damping: Any, D: Any) -> tuple:
    """(M, K, E, damping) from the call ``mechanical(M, K, E, damping=...)``, the old order
    ``mechanical(M, D, K, E)`` (a fourth positional argument) or the old keyword ``D=``."""
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
    return M, K, E, damping


def _mechanical_matrices(M: Any, K: Any, damping: Any, E: Any) -> tuple:
    """M, K, the damping and E of M q'' + D q' + K q = E^T u as rational matrices, checked: M square,
    nonempty and invertible, K and the damping m x m, E with m columns and at least one row (a flat
    list is one constraint)."""
    Mm = to_matrix(M, "M")
    m = Mm.nrows()
    if m == 0 or Mm.ncols() != m:
        raise ShapeError(f"mass matrix M must be square and nonempty, got {m}x{Mm.ncols()}")
    Km = to_matrix(K, "K", (m, m))
    Dm = zeros(m, m) if damping is None else to_matrix(damping, "damping", (m, m))
    if isinstance(E, (list, tuple)) and E and not isinstance(E[0], (list, tuple)) and not hasattr(E[0], "tolist"):
        E = [list(E)]  # a flat list is one constraint row
    Em = to_matrix(E, "E", (None, m))
    if Em.nrows() == 0:
        raise ShapeError("E has no rows: give at least one constraint E q >= 0")
    if Mm.det() == 0:
        raise ShapeError("mass matrix M is singular")
    return Mm, Km, Dm, Em


def _coordinate_names(q_names: Any, m: int) -> tuple:
    """The names of the m coordinates q: ``q_0, ..., q_{m-1}`` by default, else m nonempty strings."""
    if q_names is None:
        return tuple(f"q_{i}" for i in range(m))
    if isinstance(q_names, str) or not hasattr(q_names, "__iter__") or len(tuple(q_names)) != m:
        raise ShapeError(f"q_names must be {m} names (one per coordinate), got {q_names!r}")
    q_names = tuple(q_names)
    if not all(isinstance(q, str) and q for q in q_names):
        raise InvalidArgument(f"q_names must be nonempty strings, got {q_names!r}")
    return q_names


def _first_order_form(Mm, Km, Dm, Em) -> tuple:
    """(A, B, C, M^{-1}) of (8.3): x = (q, q'), A = [[0, I], [-M^{-1} K, -M^{-1} D]],
    B = [[0], [M^{-1} E^T]], C = [E, 0]."""
    m, k = Mm.nrows(), Em.nrows()
    Minv = Mm.solve(identity(m))
    A = vstack(hstack(zeros(m, m), identity(m)), hstack(-(Minv * Km), -(Minv * Dm)))
    B = vstack(zeros(m, k), Minv * Em.transpose())
    C = hstack(Em, zeros(k, m))
    return A, B, C, Minv


def _with_forces_and_gaps(A, B, C, Dc, Minv, forces: list, gaps: list, options: dict) -> LCS:
    """The LCS (8.3) driven by the forces f (q'' gets M^{-1} f) and the gaps g (y gets g), both
    carried by one exosystem whose states are appended to x."""
    m, k = len(forces), len(gaps)
    ex = exosystem(forces + gaps)
    Wf = submatrix(ex.W, range(m), None)
    Wg = submatrix(ex.W, range(m, m + k), None)
    EW = vstack(zeros(m, ex.size), Minv * Wf)  # q'' gets M^{-1} f
    return extend(A, B, C, Dc, EW, Wg, ex, **options)


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


def _compliance(value: Any, k: int, names: tuple) -> Any:
    """``compliance`` as the k x k matrix D of the LCS (zero when None), checked: entries of a
    rational or a sequence >= 0, zero rows and columns for rigid constraints (zero diagonal), a
    P-matrix on the compliant ones."""
    if value is None:
        return zeros(k, k)
    is_seq = isinstance(value, (list, tuple)) or hasattr(value, "tolist") and getattr(value, "ndim", None) != 0
    if not is_seq:
        c = to_fmpq(value, "compliance")
        if c < 0:
            raise InvalidArgument(f"compliance must be >= 0 (a one-sided spring of stiffness 1/c), got {c}")
        return identity(k) * c
    rows = list(as_list(value) if hasattr(value, "tolist") else value)
    if rows and all(isinstance(r, (list, tuple)) or hasattr(r, "tolist") and getattr(r, "ndim", 0) != 0
                    for r in rows):
        Dc = to_matrix(rows, "compliance", (k, k))
    else:
        if len(rows) != k:
            raise ShapeError(f"compliance has {len(rows)} entries, expected one per constraint (k = {k}) or a "
                             f"{k}x{k} matrix")
        Dc = zeros(k, k)
        for i, c in enumerate(rows):
            Dc[i, i] = to_fmpq(c, f"compliance[{i}]")
    for i in range(k):
        if Dc[i, i] < 0:
            raise InvalidArgument(f"compliance of constraint {names[i]!r} must be >= 0, got {Dc[i, i]}")
        if Dc[i, i] == 0 and any(Dc[i, j] != 0 or Dc[j, i] != 0 for j in range(k)):
            raise InvalidArgument(f"compliance: constraint {names[i]!r} is rigid (zero compliance on the diagonal) "
                                  f"but its row or column of the compliance matrix is not zero")
    soft = [i for i in range(k) if Dc[i, i] != 0]
    bad = p_matrix_violation(submatrix(Dc, soft, soft)) if soft else None
    if bad is not None:
        which = ", ".join(repr(names[soft[i]]) for i in bad)
        raise InvalidArgument(f"compliance must be a P-matrix on the compliant constraints (Theorem 6.3: one force "
                              f"for every state); its principal minor on {which} is <= 0")
    return Dc


def _check_restitution(restitution: Any, Dc: Any, names: tuple) -> None:
    """Restitution with compliant contacts: one coefficient per constraint, None for each compliant
    one (it never takes an impulse, so Newton's law has nothing to act on there)."""
    soft = [i for i in range(Dc.nrows()) if Dc[i, i] != 0]
    if restitution is None or not soft:
        return
    listed = isinstance(restitution, (list, tuple)) or hasattr(restitution, "tolist") and \
        getattr(restitution, "ndim", None) != 0
    values = list(as_list(restitution) if hasattr(restitution, "tolist") else restitution) if listed else None
    if values is None or len(values) != Dc.nrows():
        raise InvalidArgument(f"restitution with compliance: give one coefficient per constraint, None for each "
                              f"compliant one ({', '.join(repr(names[i]) for i in soft)}): a compliant contact "
                              f"never takes an impulse (its force u = max(0, -y/c) is continuous in the state), "
                              f"so Newton's impact law has no velocity jump to act on there")
    for i in soft:
        if values[i] is not None:
            raise InvalidArgument(f"restitution[{i}] must be None: constraint {names[i]!r} is compliant "
                                  f"(compliance {Dc[i, i]}), it never takes an impulse for Newton's law to act on "
                                  f"(its spring is elastic)")

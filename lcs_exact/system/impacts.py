"""Newton's impact law, generalised by Moreau to simultaneous impacts (docs/extensions.md).

The paper's impacts are inelastic: at an impact the state is re-initialized by P_I, which for a
mechanical system (8.3) is Moreau's rule, Minimization problem 8.1 (Theorem 8.2).  With
restitution coefficients e_i in [0, 1] (``LCS(..., restitution=e)``, every constraint of relative
degree 2: y = C x, y' = C A x, and an impulse lambda jumps x by B lambda), the jump at a feasible
state z (y = C z >= 0) whose closed constraints J = {i : y_i = 0} approach (some y_i' < 0) is

    x+ = z + B_J lambda,   y'_J(+) = y'_J(-) + W_JJ lambda,   W = C A B  (= E M^-1 E^T),
    0 <= y'_J(+) + e_J y'_J(-)  ⊥  lambda >= 0,

an LCP in lambda with the P-matrix W_JJ: LCP((1 + e_J) y'_J(-), W_JJ), unique (Theorem 3.4);
contacts that cannot close together (a floor and a ceiling) may have dependent rows, so W_JJ is
checked on each closed set J (IllPosed when it is not a P-matrix).
With e = 0 it is (8.7)-(8.8), so it gives exactly the paper's jump P_I z (Theorem 8.2).  It is
solved by Murty's method on linear forms in z (:func:`~lcs_exact.lcp.murty`): every sign is exact
for a rational z and certified (or refused) for an exact-real one, and the jump is the rational
matrix I + B_J U (lambda = U z), so exact states stay exact.

Energy: the kinetic energy changes by (1/2) lambda^T (y'(+) + y'(-)); when the closed contacts
share one coefficient e it is (1 - e)/2 lambda^T y'(-) <= 0, zero for e = 1 (an elastic impact
keeps the energy) and Carnot's loss for e = 0.

Compliant contacts (D_ii > 0: relative degree 0, :func:`lcs_exact.models.mechanical`'s
``compliance``) take no impulse: their force is a continuous function of the state, so the law
leaves them out (their coefficient is 0) and acts on the rigid contacts alone; W_JJ and y'_J
involve rigid rows only (C B = 0 there, so y'_J = C_J A z whatever the compliant forces).

What the law does not cover, and the paper's rule then does: an infeasible state (some y_i < 0:
the paper jumps the positions too, u^{-1} != 0), and the rare closed constraint that separates
(y_i' > 0) yet is pushed back below zero velocity by a neighbour's impulse (Newton's law allows
y'_i(+) = -e y'_i(-) < 0 there; mode selection then re-initializes it inelastically).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from flint import fmpq_mat

from ..errors import IllPosed
from ..interfaces import SystemLike
from ..algebra import murty, p_matrix_violation
from ..algebra import identity, sign_of_form, submatrix, zeros

__all__ = ["Impact", "newton_impact", "delassus"]


@dataclass(frozen=True)
class Impact:
    """One impact: the closed constraints ``closed`` (y_i = 0), those that receive an impulse
    (``active``, lambda_i > 0), the impulse as forms (k x n: lambda = ``impulse_forms`` z; zero
    rows off the closed set) and the jump (n x n: x+ = ``jump`` z)."""

    closed: frozenset
    active: frozenset
    impulse_forms: fmpq_mat
    jump: fmpq_mat


def delassus(lcs: SystemLike) -> fmpq_mat:
    """W = C A B (k x k): y' jumps by W lambda under an impulse lambda (E M^-1 E^T for (8.3))."""
    return lcs.C * lcs.A * lcs.B


def newton_impact(lcs: SystemLike, z: Any) -> Impact | None:
    """The impact at z by Newton's law with Moreau's generalisation (module docstring), or None
    when the law does not apply: no restitution set, z infeasible (some y_i < 0), or no closed
    constraint approaching (then there is no impact).

    ``z`` is a rational column (``fmpq_mat``) or an exact vector (signs certified).

    Parameters
    ----------
    lcs : LCS
        With ``restitution`` set (Newton's law).
    z : fmpq_mat or ExactVector
        The state at the impact (above).

    >>> from lcs_exact import LCS
    >>> ball = LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]], restitution="1/2")   # q'' = u
    >>> imp = newton_impact(ball, fmpq_mat([[0], [-4]]))     # at the floor, falling at 4
    >>> imp.active, (imp.jump * fmpq_mat([[0], [-4]])).transpose()
    (frozenset({0}), [0, 2])
    """
    e = lcs.restitution
    if e is None:
        return None
    k, n = lcs.k, lcs.n
    C, CA = lcs.C, lcs.C * lcs.A
    closed = []
    for i in range(k):
        if lcs.D[i, i] > 0:
            continue  # a compliant contact (relative degree 0): no impulse, y_i = C_i z + D_i u may be < 0
        s = sign_of_form(submatrix(C, [i], None), z)
        if s < 0:
            return None  # infeasible: the paper's re-initialization (positions jump too)
        if s == 0:
            closed.append(i)
    if not closed or all(sign_of_form(submatrix(CA, [i], None), z) >= 0 for i in closed):
        return None
    # LCP((1 + e_J) y'_J(-), W_JJ) on the forms of z
    q = fmpq_mat(len(closed), n)
    for r, i in enumerate(closed):
        for c in range(n):
            q[r, c] = (1 + e[i]) * CA[i, c]
    W = submatrix(delassus(lcs), closed, closed)
    bad = p_matrix_violation(W)
    if bad is not None:
        names = [lcs.constraint_names[closed[i]] for i in bad]
        raise IllPosed(f"contacts {names} close together but their Delassus matrix E M^-1 E^T is not a P-matrix "
                       f"(principal minor {submatrix(W, bad, bad).det()} <= 0): the impact LCP (8.7) has no unique "
                       "solution (dependent constraints)")
    _, U, _ = murty(W, q, z)
    forms = zeros(k, n)
    for r, i in enumerate(closed):
        for c in range(n):
            forms[i, c] = U[r, c]
    active = frozenset(i for r, i in enumerate(closed) if sign_of_form(submatrix(U, [r], None), z) > 0)
    return Impact(frozenset(closed), active, forms, identity(n) + lcs.B * forms)


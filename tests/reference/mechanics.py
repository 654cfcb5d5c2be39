"""Mechanical systems M q'' + D q' + K q = E^T u, y = E q, 0 <= y ⊥ u >= 0 (section 8), x = (q, v):

* exactly, in Fractions: Moreau's impact rule (Minimization problem 8.1) by enumerating the active
  sets of its KKT system, and the contact forces u_I = G x of a constrained mode;
* in mpmath: the closed loop of a constrained mode, inelastic impacts, and an event-driven
  simulator with impacts, sticking and releases.

Conventions (the library's, DESIGN.md section 4): an impact on the contact set J gives the
inelastic (Moreau) jump  v+ = v- - M^-1 E_J^T (E_J M^-1 E_J^T)^-1 E_J v-, with J chosen so that
the impulses are >= 0 and E v+ >= 0 on the closed contacts; in the constrained mode I
(E_I q == 0) the contact forces are u_I = (E_I M^-1 E_I^T)^-1 E_I M^-1 (K q + D v); a phase ends
when some u_i (i in I) or some y_j (j not in I) turns negative."""
from __future__ import annotations

import itertools
from fractions import Fraction

import mpmath as mp

from .flows import first_crossing, mpm, row
from .linalg import inverse, mm, mv, rows, solve, subsets, tr, zeros

# ---------------------------------------------------------------------------------------------
# exact (Fractions)
# ---------------------------------------------------------------------------------------------


def moreau(M, E, J, v0):
    """w = argmin_{E_J w >= 0} 1/2 (w - v0)^T M (w - v0) and its multiplier lam (dict on J), by
    enumerating the active sets S ⊆ J of the KKT system M (w - v0) = E_S^T lam, E_S w = 0,
    lam >= 0, E_J w >= 0.  All KKT points found are checked to agree (uniqueness)."""
    m = len(v0)
    Mv = mv(M, v0)
    found = []
    for S in subsets(J):
        S = sorted(S)
        size = m + len(S)
        K = zeros(size, size)
        rhs = [Fraction(0)] * size
        for i in range(m):
            K[i][:m] = list(M[i])
            for a, s in enumerate(S):
                K[i][m + a] = -E[s][i]
                K[m + a][i] = E[s][i]
            rhs[i] = Mv[i]
        sol = solve(K, rhs)
        assert sol is not None  # M > 0 and E_S of full row rank
        w, lam = sol[:m], dict(zip(S, sol[m:]))
        if all(v >= 0 for v in lam.values()) and all(e >= 0 for e in mv(rows(E, J), w)):
            found.append((tuple(w), tuple(lam.get(i, Fraction(0)) for i in J)))
    assert found and len(set(found)) == 1, found
    w, lam = found[0]
    return list(w), dict(zip(J, lam))


def contact_force_matrix(M, K, E, C, I):
    """G with u_I = G x on a contact phase in mode I, x = (q, v), of M q'' + C q' + K q = E^T u:
    y_I'' = E_I q'' = 0 gives u_I = (E_I M^-1 E_I^T)^-1 E_I M^-1 [K C] x."""
    EI = [E[i] for i in sorted(I)]
    Mi = inverse(M)
    KC = [list(rk) + list(rc) for rk, rc in zip(K, C)]
    return mm(inverse(mm(mm(EI, Mi), tr(EI))), mm(mm(EI, Mi), KC))


# ---------------------------------------------------------------------------------------------
# mpmath
# ---------------------------------------------------------------------------------------------

def mech_matrices(Mm, Dm, Km, E, I=()):
    """Closed-loop A_I and the contact-force rows F (u = F x) of the constrained mode I of
    M q'' + D q' + K q = E^T u (module docstring)."""
    M_, D_, K_, E_ = mpm(Mm), mpm(Dm), mpm(Km), mpm(E)
    m, k = M_.rows, E_.rows
    Mi = M_ ** -1
    KD = mp.zeros(m, 2 * m)
    for i in range(m):
        for j in range(m):
            KD[i, j], KD[i, m + j] = K_[i, j], D_[i, j]
    F = mp.zeros(k, 2 * m)
    if I:
        I = sorted(I)
        EI = mp.matrix([[E_[i, j] for j in range(m)] for i in I])
        FI = (EI * Mi * EI.T) ** -1 * EI * Mi * KD
        for a, i in enumerate(I):
            for j in range(2 * m):
                F[i, j] = FI[a, j]
    acc = -Mi * KD + Mi * E_.T * F
    A = mp.zeros(2 * m)
    for i in range(m):
        A[i, m + i] = 1
        for j in range(2 * m):
            A[m + i, j] = acc[i, j]
    return A, F


def impact(Mm, E, x, J):
    """Inelastic impact on the contacts J: (state after, impulses)."""
    M_, E_ = mpm(Mm), mpm(E)
    m = M_.rows
    Mi = M_ ** -1
    EJ = mp.matrix([[E_[i, j] for j in range(m)] for i in sorted(J)])
    v = mp.matrix([x[m + j] for j in range(m)])
    lam = -(EJ * Mi * EJ.T) ** -1 * (EJ * v)
    vp = v + Mi * EJ.T * lam
    return mp.matrix([x[j] for j in range(m)] + [vp[j] for j in range(m)]), lam


def _subsets(Z):
    Z = sorted(Z)
    for r in range(len(Z) + 1):
        yield from (list(c) for c in itertools.combinations(Z, r))


def mech_reference(Mm, Dm, Km, E, x, T, step=0.01):
    """Event-driven reference for M q'' + D q' + K q = E^T u, 0 <= u _|_ E q >= 0 with inelastic
    impacts (module docstring).  At an event with closed contacts Z (y = 0): the impact set J is
    the subset of Z with impulses >= 0 and E v+ >= 0 on Z (the impact LCP); then the contacts
    with y = y' = 0 pick the mode by the force/acceleration LCP (forces >= 0 in the mode,
    accelerations >= 0 off it; the smallest solution is taken, as in Remark 4.8).
    Returns [(t, mode_before, J, mode_after, x-, x+)] and x(T).  Starts in mode {} (x0 with
    y > 0, or y = 0 with an impact at t = 0)."""
    Em = mpm(E)
    m, k = Em.cols, Em.rows
    small = mp.mpf(10) ** -35
    y = lambda z: [sum(Em[i, j] * z[j] for j in range(m)) for i in range(k)]  # noqa: E731
    yd = lambda z: [sum(Em[i, j] * z[m + j] for j in range(m)) for i in range(k)]  # noqa: E731

    def reinit(xm):
        Z = [i for i in range(k) if abs(y(xm)[i]) < small]
        J, xp = [], xm
        if any(yd(xm)[i] < -small for i in Z):
            for J in _subsets(Z):
                if not J:
                    continue
                xp, lam = impact(Mm, E, xm, J)
                if all(l >= -small for l in lam) and all(yd(xp)[i] >= -small for i in Z):
                    break
            else:
                raise AssertionError("no impact solution")
        Z2 = [i for i in Z if abs(yd(xp)[i]) < small]
        sols = []
        for I in _subsets(Z2):
            AI, F = mech_matrices(Mm, Dm, Km, E, I)
            u, dx = F * xp, AI * xp
            acc = [sum(Em[i, j] * dx[m + j] for j in range(m)) for i in range(k)]
            if all(u[i] >= -small for i in I) and all(acc[i] >= -small for i in Z2 if i not in I):
                sols.append(frozenset(I))
        # the smallest admissible mode (a contact that carries no force is not in it)
        return J, xp, min(sols, key=len)

    t, I, out = mp.mpf(0), frozenset(), []
    if any(abs(v) < small for v in y(x)):
        J, xp, I = reinit(x)
        if J:
            out.append((t, None, frozenset(J), I, x, xp))
        x = xp
    while True:
        AI, F = mech_matrices(Mm, Dm, Km, E, I)
        forms = [row(F, i) for i in sorted(I)] + \
            [[Em[i, j] for j in range(m)] + [0] * m for i in range(k) if i not in I]
        hits = []
        for g in forms:
            val = sum(a * b for a, b in zip(g, x))
            h = first_crossing(g, AI, x, t, T, step, start_eps=1e-6 if abs(val) < small else 0.0)
            if h is not None:
                hits.append(h)
        if not hits:
            return out, mp.expm(AI * (T - t)) * x
        t1 = min(hits)
        xm = mp.expm(AI * (t1 - t)) * x
        J, xp, Inew = reinit(xm)
        if J:  # the jump's mode: the impacting contacts and the closed ones that stay closed
            J = frozenset(J) | (I & Inew)
        out.append((t1, I, frozenset(J), Inew, xm, xp))
        t, I, x = t1, Inew, xp

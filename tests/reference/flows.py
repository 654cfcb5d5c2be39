"""Event location on linear flows and event-driven references for index-one systems, in mpmath
(the working precision is the caller's ``mp.mp.dps``) with float64 scans (NumPy / SciPy) to
bracket roots.  Matrices are ``mp.matrix``; ``mpm`` / ``mpv`` build them from rationals."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import numpy as np
from scipy.linalg import expm as fexpm

from .lcp import strict_lcp_mode

# ---------------------------------------------------------------------------------------------
# conversions
# ---------------------------------------------------------------------------------------------


def Q(x) -> mp.mpf:
    """A rational (int, str, Fraction) as an mpf at the current precision."""
    return mp.mpf(Fraction(x).numerator) / Fraction(x).denominator


def mpm(rows) -> mp.matrix:
    return mp.matrix([[Q(x) for x in r] for r in rows])


def mpv(xs) -> mp.matrix:
    return mp.matrix([Q(x) if not isinstance(x, mp.mpf) else x for x in xs])


def npm(m: mp.matrix) -> np.ndarray:
    return np.array([[float(m[i, j]) for j in range(m.cols)] for i in range(m.rows)])


def row(m: mp.matrix, i: int) -> list:
    return [m[i, j] for j in range(m.cols)]


def mpvec(m) -> list:
    """An mp column vector as a list."""
    return [m[i] for i in range(m.rows)]


# ---------------------------------------------------------------------------------------------
# roots
# ---------------------------------------------------------------------------------------------

def first_crossing(g, A, x, a, b, step, start_eps=0.0):
    """First t in (a, b] where g . e^{A (t - a)} x turns negative (a + to - sign change), located
    by a float64 scan of step `step` (from a + start_eps) and refined by mpmath's findroot.
    Returns None if there is none.  g: mp row (list), A: mp.matrix, x: mp vector at time a."""
    An, xn, gn = npm(A), np.array([float(c) for c in x]), np.array([float(c) for c in g])
    f_float = lambda s: float(gn @ (fexpm(An * s) @ xn))  # noqa: E731
    s0 = start_eps
    f0 = f_float(s0) if s0 > 0 else 1.0
    n = int(float(b - a) / step) + 1
    for i in range(1, n + 1):
        s1 = min(start_eps + i * step, float(b - a))
        f1 = f_float(s1)
        if f1 < 0 <= f0 or (f0 > 0 and f1 < 0):
            f = lambda s: sum(gi * vi for gi, vi in zip(g, mp.expm(A * s) * x))  # noqa: E731
            return a + mp.findroot(f, (mp.mpf(s0), mp.mpf(s1)), solver="illinois")
        s0, f0 = s1, f1
        if s1 >= float(b - a):
            break
    return None


def first_root(f, a, b, h):
    """The first sign change of f on (a, b], located on a grid of step h and refined by findroot
    on the bracketing grid cell.  A constraint that starts at zero (|f(a)| < 1e-40, e.g. the one
    that has just become active) is tracked from a + h on, where it must be positive."""
    x, f0 = mp.mpf(a), f(mp.mpf(a))
    if abs(f0) < mp.mpf(10) ** -40:
        x = x + h
        f0 = f(x)
        assert f0 > 0, "a constraint starting at zero must become positive"
    while x < b:
        x1 = min(x + h, mp.mpf(b))
        f1 = f(x1)
        if f1 == 0 or (f0 > 0) != (f1 > 0):
            return mp.findroot(f, (x, x1), solver="anderson")
        x, f0 = x1, f1
    return None


def first_fall(f, a, b, h):
    """The first t in (a, b) where f goes from > 0 to < 0 between grid points of step h, refined
    by findroot; an AssertionError if there is none."""
    x, fx = mp.mpf(a), f(mp.mpf(a))
    while x < b:
        y = x + h
        fy = f(y)
        if fy < 0 < fx:
            return mp.findroot(f, (x, y), solver="anderson")
        x, fx = y, fy
    raise AssertionError("no crossing")


# ---------------------------------------------------------------------------------------------
# index-one systems (D a P-matrix, or D = 0 with C B invertible): events are mode changes
# ---------------------------------------------------------------------------------------------

def pl_closed(A, B, C, D, I):
    """Mode I: u_I = -D_II^-1 C_I x (D_II != 0) or u_I = -(C_I B_I)^-1 C_I A x (D_II = 0, y_I
    kept at 0 with C_I B_I invertible); returns (A_I, F) with u = F x."""
    n, k = A.rows, C.rows
    I = sorted(I)
    F = mp.zeros(k, n)
    if I:
        CI = mp.matrix([[C[i, j] for j in range(n)] for i in I])
        DII = mp.matrix([[D[i, j] for j in I] for i in I])
        if mp.norm(DII) != 0:
            FI = -(DII ** -1) * CI
        else:
            BI = mp.matrix([[B[r, j] for j in I] for r in range(n)])
            FI = -((CI * BI) ** -1) * CI * A
        for a, i in enumerate(I):
            for j in range(n):
                F[i, j] = FI[a, j]
    return A + B * F, F


def pl_reference(A, B, C, D, x, T, I, step=0.01):
    """Events of the index-one LCS from x in mode I on (0, T]: each phase ends at the first
    crossing of some u_i (i in I) or y_j (j not in I); the next mode is the one (unique for these
    systems) whose own constraints are all >= 0 just after the event (checked at 1e-12, 1e-10).
    Returns [(t, mode before, mode after, x(t))] and x(T)."""
    k = C.rows
    t, out = mp.mpf(0), []
    while True:
        AI, F = pl_closed(A, B, C, D, I)
        G = C + D * F
        forms = [row(F, i) for i in sorted(I)] + [row(G, j) for j in range(k) if j not in I]
        hits = [first_crossing(g, AI, x, t, T, step, start_eps=1e-9) for g in forms]
        hits = [h for h in hits if h is not None]
        if not hits:
            return out, mp.expm(AI * (T - t)) * x
        t1 = min(hits)
        x = mp.expm(AI * (t1 - t)) * x
        ok = []
        for r in range(1 << k):
            J = frozenset(i for i in range(k) if r >> i & 1)
            try:
                AJ, FJ = pl_closed(A, B, C, D, J)
            except ZeroDivisionError:
                continue
            yx = C * x
            if any(D[i, i] == 0 and abs(yx[i]) > mp.mpf(10) ** -40 for i in J):
                continue  # a relative-degree-one constraint can only be active where y_i = 0
            good = True
            for d in (mp.mpf(10) ** -12, mp.mpf(10) ** -10):
                z = mp.expm(AJ * d) * x
                u, y = FJ * z, C * z + D * (FJ * z)
                good &= all(u[i] > -mp.mpf(10) ** -40 for i in J)
                good &= all(y[j] > -mp.mpf(10) ** -40 for j in range(k) if j not in J)
            if good:
                ok.append(J)
        assert len(ok) == 1, ok
        out.append((t1, I, ok[0], x))
        t, I = t1, ok[0]


def _sub(Mx, rows, cols):
    return mp.matrix([[Mx[i, j] for j in cols] for i in rows]) if rows and cols else None


def rd0_closed_loop(A, B, C, D, I):
    """Relative degree 0 (D a P-matrix), mode I: u_I = -D_II^-1 C_I x; returns (A_I, u(x))."""
    k = C.rows
    idx = sorted(I)
    if not idx:
        return A, (lambda xx: [mp.mpf(0)] * k)
    DinvC = mp.inverse(_sub(D, idx, idx)) * _sub(C, idx, range(C.cols))

    def u_of(xx):
        uI = -(DinvC * xx)
        u = [mp.mpf(0)] * k
        for n, i in enumerate(idx):
            u[i] = uI[n]
        return u
    BI = mp.matrix([[B[r, i] for i in idx] for r in range(B.rows)])
    return A - BI * DinvC, u_of


def rd0_reference(A, B, C, D, x0, T, h=None):
    """Events of a relative-degree-0 LCS (D a P-matrix) from x0 with C x0 > 0 on (0, T]: each phase
    ends at the first sign change of some u_i (i in I) or y_j (j not in I), found on a grid of
    step h (default 1/100) and refined with findroot; the next mode is the smallest strictly
    complementary solution of the LCP at q = C x + delta C x' (delta = 1e-25, u continuous).
    Returns ([dict(time, before, after, state)], the final mode)."""
    h = mp.mpf(1) / 100 if h is None else h
    A, B, C, D = (mp.matrix(m) for m in (A, B, C, D))
    k = C.rows
    x = mp.matrix(x0)
    t = mp.mpf(0)

    def next_mode(xx, u_prev):
        xd = A * xx + B * mp.matrix(u_prev)
        q = [(C * xx)[j] + mp.mpf(10) ** -25 * (C * xd)[j] for j in range(k)]
        return strict_lcp_mode(D, q)

    # initial mode: q = C x0 > 0, so u(0) = 0 and the perturbed LCP decides
    assert all((C * x)[j] > 0 for j in range(k))
    mode = next_mode(x, [mp.mpf(0)] * k)
    events = []
    while True:
        AI, u_of = rd0_closed_loop(A, B, C, D, mode)

        def cons(s, AI=AI, u_of=u_of, mode=mode, x=x):
            xs = mp.expm(AI * s) * x
            u = u_of(xs)
            y = [(C * xs)[j] + sum(D[j, i] * u[i] for i in range(k)) for j in range(k)]
            return [u[i] if i in mode else y[i] for i in range(k)]
        roots = []
        for i in range(k):
            r = first_root(lambda s, i=i: cons(s)[i], 0, T - t, h)
            if r is not None:
                roots.append(r)
        if not roots:
            return events, mode
        s = min(roots)
        x_new = mp.expm(AI * s) * x
        u_new = u_of(x_new)
        t = t + s
        new_mode = next_mode(x_new, u_new)
        events.append(dict(time=t, before=mode, after=new_mode, state=x_new))
        x, mode = x_new, new_mode

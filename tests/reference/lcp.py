"""LCP(q, M) (3.9)-(3.10), y = q + M u, 0 <= y ⊥ u >= 0, by enumerating supports: exactly in
Fractions (every solution of a small LCP) and in mpmath (the smallest strictly complementary
solution's support)."""
from __future__ import annotations

from fractions import Fraction
from itertools import combinations

import mpmath as mp

from .linalg import det, solve, sub


def lcp_solutions(q, m) -> set[tuple]:
    """All u solving LCP(q, M) whose support has a nonsingular principal submatrix (Fractions)."""
    k = len(m)
    out = set()
    for r in range(k + 1):
        for a in combinations(range(k), r):
            u = [Fraction(0)] * k
            if a:
                maa = sub(m, a, a)
                if det(maa) == 0:
                    continue
                ua = solve(maa, [-Fraction(q[i]) for i in a])
                if any(v < 0 for v in ua):
                    continue
                for i, v in zip(a, ua):
                    u[i] = v
            y = [Fraction(q[i]) + sum(Fraction(m[i][j]) * u[j] for j in range(k)) for i in range(k)]
            if any(v < 0 for v in y):
                continue
            out.add(tuple(u))
    return out


def strict_lcp_mode(D, q):
    """The smallest I with u_I = -D_II^-1 q_I > 0 and w = q + D u > 0 off I (2^k enumeration,
    mpmath; margins 1e-45); D an mp.matrix, q a list."""
    k = len(q)
    eps = mp.mpf(10) ** -45
    for r in range(k + 1):
        for I in combinations(range(k), r):
            u = [mp.mpf(0)] * k
            if I:
                DII = mp.matrix([[D[i, j] for j in I] for i in I])
                uI = -mp.lu_solve(DII, mp.matrix([q[i] for i in I]))
                for n, i in enumerate(I):
                    u[i] = uI[n]
            w = [q[j] + sum(D[j, i] * u[i] for i in range(k)) for j in range(k)]
            if all(u[i] > eps for i in I) and all(w[j] > eps for j in range(k) if j not in I):
                return frozenset(I)
    raise AssertionError(f"no strictly complementary LCP solution at q = {q}")

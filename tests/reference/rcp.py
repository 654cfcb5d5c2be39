"""RCP(x0) (5.3)-(5.5) of Heemels-Schumacher-Weiland (2000) from scratch, exactly over Q:
chi(s) = det(sI - A) and adj(sI - A) by Faddeev-LeVerrier, y(s) = [r(s) + Gn(s) u(s)] / chi(s),
mode by mode by Cramer's rule over Q[s], admissibility by the signs of leading coefficients; the
impulse u^{-i} and x(0+) = x0 + sum A^i B u^{-i} (3.8).  Also the Markov parameters and the
leading row / column matrices (M, N) of (6.1)."""
from __future__ import annotations

from fractions import Fraction
from functools import reduce

from .linalg import F, eye, fmat, madd, mm, mscale, mv, subsets, tr, zeros
from .polynomials import padd, pdet, pdivmod, pmul, pneg, pscale, ptrim, sign_at_infinity


def faddeev_leverrier(A):
    """chi(s) = det(sI - A) and adj(sI - A) = sum_k Mk s^(n-k) (k = 1..n), exactly."""
    n = len(A)
    c = [Fraction(0)] * (n + 1)
    c[n] = Fraction(1)
    Mk = zeros(n, n)
    Ms = []
    for k in range(1, n + 1):
        Mk = madd(mm(A, Mk), mscale(c[n - k + 1], eye(n)))
        Ms.append(Mk)
        AM = mm(A, Mk)
        c[n - k] = -sum(AM[i][i] for i in range(n)) / k
    adj = [[ptrim([Ms[n - 1 - p][i][j] for p in range(n)]) for j in range(n)] for i in range(n)]
    return c, adj


class RCP:
    """RCP(x0) of (A, B, C, D) from scratch: y(s) = [r(s) + Gn(s) u(s)] / chi(s) with
    Gn = C adj(sI-A) B + D chi and r = C adj(sI-A) x0; in mode I, Gn_II u_I = -r_I (Cramer)."""

    def __init__(self, A, B, C, D):
        self.A, self.B, self.C, self.D = fmat(A), fmat(B), fmat(C), fmat(D)
        self.n, self.k = len(self.A), len(self.C)
        self.chi, adj = faddeev_leverrier(self.A)
        n, k = self.n, self.k
        # C adj (k x n polynomials)
        self.Cadj = [[reduce(padd, (pscale(self.C[i][l], adj[l][j]) for l in range(n)), [])
                      for j in range(n)] for i in range(k)]
        self.Gn = [[padd(reduce(padd, (pscale(self.B[l][j], self.Cadj[i][l]) for l in range(n)), []),
                         pscale(self.D[i][j], self.chi)) for j in range(k)] for i in range(k)]

    def solution(self, x0, I):
        """(u, y) for mode I: dicts index -> (num, den) polynomials; y_I = 0 and u_Ic = 0."""
        x0 = [F(v) for v in x0]
        I = sorted(I)
        r = [reduce(padd, (pscale(x0[j], self.Cadj[i][j]) for j in range(self.n)), []) for i in range(self.k)]
        GII = [[self.Gn[i][j] for j in I] for i in I]
        d = pdet(GII)
        assert d, f"Assumption 4.1 fails: det G_II(s) = 0 for I = {I}"
        nums = {}
        for c, j in enumerate(I):
            Mj = [[(r[i] if cc == c else GII[ri][cc]) for cc in range(len(I))] for ri, i in enumerate(I)]
            nums[j] = pneg(pdet(Mj))
        u = {j: (nums.get(j, []), d) for j in range(self.k)}
        y = {}
        for i in range(self.k):
            num = reduce(padd, (pmul(self.Gn[i][j], nums[j]) for j in I), pmul(r[i], d))
            if i in I:
                assert not num, "Cramer's rule failed: y_I != 0"
            y[i] = (num, pmul(self.chi, d))
        return u, y

    def admissible(self, x0, I) -> bool:
        u, y = self.solution(x0, I)
        return all(sign_at_infinity(*u[j]) >= 0 for j in I) and \
            all(sign_at_infinity(*y[i]) >= 0 for i in range(self.k) if i not in I)

    def select(self, x0) -> set:
        return {I for I in subsets(range(self.k)) if self.admissible(x0, I)}

    def impulse(self, x0, I):
        """u^{-p} (coefficient of s^p in u(s), i.e. of delta^(p)) for p = 0..n-1."""
        u, _ = self.solution(x0, I)
        out = [[Fraction(0)] * self.k for _ in range(self.n)]
        for j, (num, den) in u.items():
            q, _ = pdivmod(num, den) if num else ([], [])
            assert len(q) <= self.n, "impulse of order >= n"
            for p, c in enumerate(q):
                out[p][j] = c
        return out

    def state_after(self, x0, I):
        """x(0+) = x0 + sum_p A^p B u^{-p} (3.8)."""
        x = [F(v) for v in x0]
        AB = self.B
        for up in self.impulse(x0, I):
            x = [a + b for a, b in zip(x, mv(AB, up))]
            AB = mm(self.A, AB)
        return tuple(x)


def markov(A, B, C, D, i):
    """The Markov parameter H^i: D for i = 0, C A^(i-1) B for i >= 1."""
    if i == 0:
        return fmat(D)
    M = fmat(B)
    for _ in range(i - 1):
        M = mm(fmat(A), M)
    return mm(fmat(C), M)


def leading_matrices(A, B, C, D):
    """(M, N) of (6.1), None for a matrix with an identically zero row / column (up to H^n)."""
    n, k = len(A), len(C)
    H = [markov(A, B, C, D, i) for i in range(n + 1)]
    Mrows, Ncols = [], []
    for j in range(k):
        rho = next((i for i in range(n + 1) if any(H[i][j])), None)
        eta = next((i for i in range(n + 1) if any(H[i][l][j] for l in range(k))), None)
        Mrows.append(None if rho is None else H[rho][j])
        Ncols.append(None if eta is None else [H[eta][l][j] for l in range(k)])
    M = None if None in Mrows else Mrows
    N = None if None in Ncols else tr(Ncols)
    return M, N

"""RCP(x0) (5.3)-(5.5) in a mode that is not autonomous: an affine family over Q(s), decided exactly.

In an autonomous mode I (Lemma 3.3), G_II(s) is invertible and u_I(s) = -G_II(s)^{-1} R_I.(s) x0
is the only candidate (section 5.2).  Without Assumption 4.1, G_II(s) may be singular, and RCP(x0)
restricted to mode I (u_Ic = 0, y_I = 0) still makes sense:

    G_II(s) u_I(s) = -R_I.(s) x0,   u_I(s) >= 0,   y_Ic(s) = R_Ic.(s) x0 + G_IcI(s) u_I(s) >= 0

with ">= 0" meaning "for all large real s" (5.4).  This module decides whether that system has a
solution, exactly, for every x0:

1. **Pivots.**  Gaussian elimination over Q(s) gives the rank r of G_II(s), rows P and columns Q
   (constraint indices in I) with G_PQ(s) invertible; F = I minus Q are the free inputs, v = u_F.
2. **Consistency** (R_I x0 in Im G_II(s)).  With a = -G_PQ^{-1} R_P, the equations are solvable iff
   the rows E_x = R_Pc + G_PcQ a vanish at x0 identically in s; the numerator coefficients of those
   rows are linear forms in x0 that must all be 0 (:meth:`RCPFamily.consistent`).
3. **The family.**  u_Q = a x0 + E v with E = -G_PQ^{-1} G_PF, u_F = v, and
   y_Ic = (R_Ic + G_IcQ a) x0 + (G_IcQ E + G_IcF) v, for v in Q(s)^d arbitrary (d = |I| - r).
4. **Signs.**  "f(s) >= 0 for all large real s" is the order of the ordered field Q(s) at s = +oo
   (Lemma 5.1): f > 0 iff its leading Laurent coefficient is positive.  The sign conditions are
   rows alpha_i(s) x0 + beta_i(s) v >= 0 with beta_i independent of x0.  Fourier-Motzkin
   elimination of v_1, ..., v_d is exact over *any* ordered field (a positive combination of valid
   inequalities is valid; conversely, if the eliminated system holds, every lower bound of v_1 is
   below every upper bound, and v_1 = the largest lower bound, or the smallest upper bound, or 0,
   is a solution in the field), and the signs of its multipliers beta_ij(s) are exact because
   they do not depend on x0.  It leaves finitely many rows alpha(s) x0 >= 0, each decided by its
   Laurent coefficients at s = oo (linear forms) lexicographically, as for autonomous modes.

Hence I in S_RCP(x0) (5.5) iff every consistency form vanishes at x0 and every eliminated row is
lexicographically nonnegative at x0 (:meth:`RCPFamily.admissible`): a mode that is never admissible
is proven so (the relay LCS of :mod:`lcs_exact.relays`: its non-autonomous modes need the relay
level c to be 0).  For a rational x0, back-substitution gives one member of the family
(:meth:`RCPFamily.solution`).  What is *not* decided here is uniqueness: an admissible
non-autonomous mode has, in general, many initial solutions (Definition 3.2), and the paper's
continuation (Definitions 4.2, 4.10) needs F_I and P_I, which exist only for autonomous modes;
:func:`lcs_exact.selection.select_modes` therefore refuses such a state by default.

Signs at an exact-real x0 go through :func:`~lcs_exact.rational.sign_of_form` only; a condition
that is certified violated decides "not admissible" even when another condition's sign cannot be
certified (that UnresolvedSign is raised only when nothing else decides).
"""
from __future__ import annotations

from dataclasses import dataclass
from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import LCSError, UnresolvedSign, Unsupported
from ..algebra import RationalFunction, RationalMatrix, laurent_coefficients
from ..algebra import is_zero, lex_sign, sign_of_form

__all__ = ["RowSeries", "row_series", "RCPFamily", "family", "MAX_ELIMINATION_ROWS"]

#: Fourier-Motzkin may grow the number of rows; above this many the elimination stops with
#: :class:`~lcs_exact.errors.Unsupported` (never a hang)
MAX_ELIMINATION_ROWS = 4000


@dataclass(frozen=True)
class RowSeries:
    """Laurent coefficients at s = oo (forms) of one row of a rational matrix: f_start, f_start+1, ...

    The row's value at x0 is >= 0 for all large s iff ``sign(x0) >= 0`` (5.7, Lemma 5.1).
    """

    start: int
    forms: tuple

    def sign(self, x) -> int:
        return lex_sign(self.forms, x)


def row_series(m: RationalMatrix, i: int) -> RowSeries:
    """The Laurent forms of row i of m(s) (as many as decide it: a numerator of degree <= a
    vanishes iff its a + 1 leading Laurent coefficients do, since N = f d).

    >>> s = RationalFunction.s()
    >>> r = row_series(RationalMatrix([[1 / s, 1 / s**2]]), 0)   # x0 . (1/s, 1/s^2) = x_0/s + x_1/s^2
    >>> r.start, [str(f) for f in r.forms], r.sign(fmpq_mat([[0], [-1]]))
    (1, ['[1, 0]', '[0, 1]'], -1)
    """
    coeffs, d = m.row_forms(i)
    a, b = len(coeffs) - 1, d.degree()
    forms = laurent_coefficients(coeffs, d.coeffs(), a + 1)
    return RowSeries(b - a, tuple(forms))


# ---------------------------------------------------------------------------------------------
# small linear algebra over Q(s) (rows as lists of RationalFunction)
# ---------------------------------------------------------------------------------------------

_ZERO = RationalFunction(0)


def _sign(f: RationalFunction) -> int:
    return f.sign_at_infinity()


def _pivots(G: RationalMatrix, rows: list[int], cols: list[int]) -> tuple[list[int], list[int]]:
    """Rows P and columns Q (labels from ``rows``/``cols``) with G_PQ invertible, |P| = rank G."""
    a = [list(r) for r in G.rows]
    label = list(rows)
    P, Q = [], []
    top = 0
    for c in range(len(cols)):
        cand = [i for i in range(top, len(a)) if not a[i][c].is_zero()]
        if not cand:
            continue
        p = cand[0]
        a[top], a[p] = a[p], a[top]
        label[top], label[p] = label[p], label[top]
        inv = 1 / a[top][c]
        for i in range(top + 1, len(a)):
            if not a[i][c].is_zero():
                f = a[i][c] * inv
                a[i] = [e - f * g for e, g in zip(a[i], a[top])]
        P.append(label[top])
        Q.append(cols[c])
        top += 1
    return P, Q


def _normalize(alpha: list, beta: list) -> tuple[list, list] | None:
    """The row (alpha, beta) times a positive element of Q(s), with polynomial entries of gcd 1
    and a leading rational of absolute value 1; None for the zero row (0 >= 0 holds)."""
    entries = alpha + beta
    if all(e.is_zero() for e in entries):
        return None
    den = fmpq_poly([1])
    for e in entries:
        den = fmpq_poly(den * e.den / den.gcd(e.den))  # lcm; monic, so positive at s = +oo
    nums = [fmpq_poly(e.num * fmpq_poly(den / e.den)) for e in entries]
    g = fmpq_poly([0])
    for p in nums:
        g = p.gcd(g) if not g.is_zero() else p
    g = fmpq_poly(g / g.leading_coefficient())  # monic: positive at s = +oo
    nums = [fmpq_poly(p / g) for p in nums]
    lead = next(p for p in nums if not p.is_zero()).leading_coefficient()
    scale = fmpq(1) / abs(lead)
    out = [RationalFunction(p * scale) for p in nums]
    return out[:len(alpha)], out[len(alpha):]


def _key(row: tuple[list, list]) -> tuple:
    return tuple(str(e.num) for e in row[0] + row[1])


def _eliminate(rows: list[tuple[list, list]], j: int) -> list[tuple[list, list]]:
    """One Fourier-Motzkin step over the ordered field Q(s): remove variable j."""
    pos = [r for r in rows if _sign(r[1][j]) > 0]
    neg = [r for r in rows if _sign(r[1][j]) < 0]
    out = [r for r in rows if r[1][j].is_zero()]
    if len(out) + len(pos) * len(neg) > MAX_ELIMINATION_ROWS:
        raise Unsupported(f"Fourier-Motzkin elimination over Q(s) would need more than "
                          f"{MAX_ELIMINATION_ROWS} rows (MAX_ELIMINATION_ROWS)")
    for ap, bp in pos:
        for an, bn in neg:
            lp, ln = -bn[j], bp[j]  # both positive at s = +oo
            alpha = [lp * x + ln * y for x, y in zip(ap, an)]
            beta = [lp * x + ln * y for x, y in zip(bp, bn)]
            beta[j] = _ZERO  # exactly cancelled
            r = _normalize(alpha, beta)
            if r is not None:
                out.append(r)
    seen, uniq = set(), []
    for r in out:
        k = _key(r)
        if k not in seen:
            seen.add(k)
            uniq.append(r)
    return uniq


def _max(values: list[RationalFunction]) -> RationalFunction:
    best = values[0]
    for v in values[1:]:
        if _sign(v - best) > 0:
            best = v
    return best


def _min(values: list[RationalFunction]) -> RationalFunction:
    return -_max([-v for v in values])


# ---------------------------------------------------------------------------------------------
# the family of one mode
# ---------------------------------------------------------------------------------------------


class RCPFamily:
    """The solutions of RCP(x0) in mode I (u_Ic = 0, y_I = 0) as an affine family over Q(s).

    Built by :func:`family` (cached on the mode).  Attributes: ``rank`` of G_II(s), ``pivot_rows``
    P, ``pivot_cols`` Q, ``free`` F (constraint indices, 0-based); ``consistency``: the rows
    (rational, forms in x0) that must vanish at x0 for G_II u_I = -R_I x0 to be solvable.

    >>> from lcs_exact import LCS
    >>> lazy = LCS([[0]], [[1]], [[0]], [[0]])      # x' = u, y = 0: G(s) = 0
    >>> fam = family(lazy.mode({0}))
    >>> fam.rank, fam.free, fam.admissible(fmpq_mat([[1]]))
    (0, (0,), True)
    """

    def __init__(self, mode):
        lcs = mode.lcs
        self.mode = mode.index_set
        self.n = lcs.n
        G, R = lcs.G(), lcs.R()
        I, Ic, n = mode.I, mode.Ic, lcs.n
        allx = list(range(n))
        P, Q = _pivots(G.sub(I, I), I, I)
        self.rank = len(P)
        self.pivot_rows, self.pivot_cols = tuple(P), tuple(Q)
        self.free = tuple(i for i in I if i not in Q)
        Pc = [i for i in I if i not in P]
        F = list(self.free)
        if P:
            GPQ = G.sub(P, Q)
            self._a = -(GPQ.solve(R.sub(P, allx)))
            self._E = -(GPQ.solve(G.sub(P, F))) if F else RationalMatrix([[] for _ in Q])
        else:
            self._a, self._E = RationalMatrix([]), RationalMatrix([])
        # rows P^c of G_II are combinations of rows P: solvable iff R_Pc x0 + G_PcQ a x0 = 0
        if Pc:
            ex = R.sub(Pc, allx) + (G.sub(Pc, Q) * self._a if Q else RationalMatrix([[_ZERO] * n for _ in Pc]))
            if F and Q:
                ev = G.sub(Pc, F) + G.sub(Pc, Q) * self._E
            else:
                ev = G.sub(Pc, F) if F else None
            if ev is not None and any(not e.is_zero() for r in ev.rows for e in r):
                raise LCSError(f"internal inconsistency: the rows of G_II(s) outside the pivots are not "
                               f"combinations of the pivot rows in mode {sorted(self.mode)}")
            self.consistency = ex
        else:
            self.consistency = RationalMatrix([])
        rows = (self.consistency.row_forms(r)[0] for r in range(len(Pc)))
        nonzero = (tuple(f for f in forms if not is_zero(f)) for forms in rows)
        self._consistency_forms = tuple(forms for forms in nonzero if forms)  # 0 = 0 rows dropped
        self._rows: list | None = None
        self._stages: list | None = None
        self._conditions: tuple | None = None
        self._lcs_R, self._lcs_G, self._Ic, self._Q = R, G, Ic, Q

    @property
    def particular(self) -> RationalMatrix:
        """a(s) (|Q| x n): u_Q = a(s) x0 + E(s) v, u_F = v (the pivot inputs of the family)."""
        return self._a

    @property
    def directions(self) -> RationalMatrix:
        """E(s) (|Q| x |F|): how the pivot inputs move with the free inputs v."""
        return self._E

    # --- the sign rows alpha x0 + beta v >= 0 and their elimination -----------------------------
    def _sign_rows(self) -> list[tuple[list, list]]:
        """u_F = v >= 0, u_Q = a x0 + E v >= 0, y_Ic = (R_Ic + G_IcQ a) x0 + (G_IcQ E + G_IcF) v >= 0."""
        n, d, F, Q, Ic = self.n, len(self.free), list(self.free), self._Q, self._Ic
        R, G = self._lcs_R, self._lcs_G
        rows = []
        for j in range(d):
            rows.append(([_ZERO] * n, [RationalFunction(int(i == j)) for i in range(d)]))
        for r in range(len(Q)):
            rows.append((list(self._a.rows[r]), list(self._E.rows[r]) if d else []))
        if Ic:
            yx = R.sub(Ic, list(range(n)))
            if Q:
                yx = yx + G.sub(Ic, Q) * self._a
            yv = None
            if d:
                yv = G.sub(Ic, F)
                if Q:
                    yv = yv + G.sub(Ic, Q) * self._E
            for r in range(len(Ic)):
                rows.append((list(yx.rows[r]), list(yv.rows[r]) if d else []))
        out = []
        for a, b in rows:
            nr = _normalize(a, b)
            if nr is not None:
                out.append(nr)
        return out

    def _eliminated(self):
        if self._conditions is None:
            stages = [self._sign_rows()]
            for j in range(len(self.free)):
                stages.append(_eliminate(stages[-1], j))
            final = RationalMatrix([a for a, _ in stages[-1]]) if stages[-1] else RationalMatrix([])
            self._stages = stages
            self._conditions = tuple(row_series(final, r) for r in range(len(stages[-1])))
        return self._conditions

    def conditions(self) -> tuple[tuple, tuple]:
        """(equalities, inequalities) in x0: each equality a tuple of 1 x n forms that must all
        vanish; each inequality a tuple of Laurent forms (f_1, f_2, ...) that must be
        lexicographically nonnegative.  I in S_RCP(x0) iff both hold."""
        return self._consistency_forms, tuple(r.forms for r in self._eliminated())

    # --- decisions ------------------------------------------------------------------------------
    def consistent(self, x) -> bool:
        """R_I x0 in Im G_II(s): every consistency form vanishes at x0 (exact; an exact-real x0 may
        raise UnresolvedSign only when no form is certified nonzero)."""
        return _all_hold(((f, 0) for row in self._consistency_forms for f in row), x)

    def admissible(self, x) -> bool:
        """I in S_RCP(x0) (5.5): consistent, and the eliminated rows are lexicographically >= 0."""
        if not self.consistent(x):
            return False
        return _all_hold(((r, 1) for r in self._eliminated()), x)

    def solution(self, x: fmpq_mat) -> tuple[list, list]:
        """One member (u_I(s), y_Ic(s)) of the family at a rational, admissible x0, by
        back-substitution through the Fourier-Motzkin stages (each free input v_j is 0 when 0 is
        feasible, else the largest lower bound, else the smallest upper bound)."""
        if not self.admissible(x):
            raise LCSError(f"mode {sorted(self.mode)} is not admissible at this x0")
        d = len(self.free)
        xv = [RationalFunction(x[i, 0]) for i in range(self.n)]
        v = [_ZERO] * d
        for j in reversed(range(d)):
            lower, upper = [], []
            for alpha, beta in self._stages[j]:
                const = sum((a * c for a, c in zip(alpha, xv)), _ZERO)
                const = const + sum((beta[l] * v[l] for l in range(j + 1, d)), _ZERO)
                b = beta[j]
                if _sign(b) > 0:
                    lower.append(-const / b)
                elif _sign(b) < 0:
                    upper.append(const / (-b))
            lo = _max(lower) if lower else None
            hi = _min(upper) if upper else None
            if (lo is None or _sign(lo) <= 0) and (hi is None or _sign(hi) >= 0):
                v[j] = _ZERO
            else:
                v[j] = lo if lo is not None else hi
        values = []
        for alpha, beta in self._stages[0]:
            val = sum((a * c for a, c in zip(alpha, xv)), _ZERO) + sum((b * w for b, w in zip(beta, v)), _ZERO)
            values.append(val)
        if any(_sign(val) < 0 for val in values):
            raise LCSError(f"internal inconsistency: back-substitution left a negative row in mode {sorted(self.mode)}")
        uQ = [sum((a * c for a, c in zip(self._a.rows[r], xv)), _ZERO)
              + sum((e * w for e, w in zip(self._E.rows[r], v)), _ZERO) for r in range(len(self._Q))]
        u = {i: f for i, f in zip(self._Q, uQ)}
        u.update({i: w for i, w in zip(self.free, v)})
        uI = [u[i] for i in sorted(self.mode)]
        R, G, n = self._lcs_R, self._lcs_G, self.n
        yIc = []
        for i in self._Ic:
            f = sum((R[i, c] * xv[c] for c in range(n)), _ZERO)
            f = f + sum((G[i, j] * u[j] for j in sorted(self.mode)), _ZERO)
            yIc.append(f)
        return uI, yIc

    def __repr__(self):
        return (f"<RCPFamily mode={sorted(self.mode)} rank G_II = {self.rank}, free inputs {list(self.free)}, "
                f"{len(self._consistency_forms)} consistency rows>")


def _all_hold(conditions, x) -> bool:
    """Every (item, kind) holds at x: kind 0, a form that must vanish; kind 1, a RowSeries that
    must be lexicographically >= 0.  A certified violation wins over an unresolved sign."""
    pending: UnresolvedSign | None = None
    for item, kind in conditions:
        try:
            ok = sign_of_form(item, x) == 0 if kind == 0 else item.sign(x) >= 0
        except UnresolvedSign as e:
            pending = pending or e
            continue
        if not ok:
            return False
    if pending is not None:
        raise pending
    return True


def family(mode) -> RCPFamily:
    """The :class:`RCPFamily` of mode I (any mode; for an autonomous one it has no free input),
    computed once and cached on the mode.

    >>> from lcs_exact import LCS
    >>> twins = LCS([[0]], [[1, 1]], [[1], [1]], [[0, 0], [0, 0]])   # y0 = y1 = x, x' = u0 + u1
    >>> fam = family(twins.mode({0, 1}))       # u0 + u1 = -x0: one free input, u1 = v >= 0
    >>> fam.rank, fam.free, fam.conditions()   # Fourier-Motzkin leaves -x0 >= 0
    (1, (1,), ((), (([-1],),)))
    >>> fam.solution(fmpq_mat([[-2]]))
    ([RationalFunction('2'), RationalFunction('0')], [])
    """
    if mode.derived.family is None:
        mode.derived.family = RCPFamily(mode)
    return mode.derived.family

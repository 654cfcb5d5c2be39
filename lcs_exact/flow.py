"""The continuous phase in mode I (section 4.1) and the time to the next event θ(z, I) (Def. 4.3).

From a consistent state z in V_I the phase is x(t) = e^{A_I t} z with A_I = A + B_.I F_I;
the monitored functions are u_i = (F_I)_i x (i in I) and y_i = (C_i + D_{i,I} F_I) x (i not in I),
each of the form f(t) = g e^{A_I t} z with a rational row g.

θ is found by certified root isolation:

* at t = 0 the lexicographic sign of (g z, g A_I z, ..., g A_I^{n-1} z) (Lemma 5.1) decides
  the start; all zero means f ≡ 0 (Cayley-Hamilton) and f is never an event;
* on an interval X = [m - r, m + r] a Taylor enclosure f(X) ⊆ sum_{j<K} f^{(j)}(m) [-r, r]^j / j!
  + f^{(K)}(X) [-r, r]^K / K! with f^{(K)}(X) from the spectral form of e^{A_I t} at the ball t = X;
* an interval is discarded when f(X) > 0, isolates exactly one simple root when f'(X) excludes
  0 and f changes sign (certified), and is bisected otherwise; a possible tangential touch that
  cannot be resolved is an unresolved sign (never guessed);
* the root is refined by Newton steps inside a certified bracket (:class:`RootReal`), and a
  closed form (small rational, rational multiple of π/ω, log(q)/λ) is accepted only when it lies
  in the isolating interval and f vanishes there exactly (structurally, or symbolically in SymPy).
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy
from flint import arb, arb_mat, fmpq, fmpq_mat

from .errors import LCSError
from .rational import matrix_to_sympy, submatrix, zeros
from .subspaces import left_kernel
from .reals import (ExactVector, ExpVector, orbit_zero_forms, Real, RationalVector, _max_prec, _sympy_to_arb, ball_sign,
                    check_deadline, expm_action, expm_apply, invariant_forms, unresolved, workprec)
from .modes import format_mode

__all__ = ["Phase", "Constraint", "RootReal", "next_event", "theta", "laplace_closed_form"]

_K = 4  # Taylor order of the enclosures
_MAX_DEPTH = 60


@dataclass(frozen=True)
class Constraint:
    """One monitored function of a phase: ``kind`` 'u' or 'y', constraint ``index``, row ``g``."""

    kind: str
    index: int
    g: fmpq_mat

    @property
    def name(self) -> str:
        return f"{self.kind}_{self.index}"


class Phase:
    """The continuous phase in mode I from the consistent state z (x(t) = e^{A_I t} z)."""

    def __init__(self, mode, z: ExactVector):
        self.mode = mode
        self.lcs = mode.lcs
        self.M = mode.closed_loop()
        W = mode._annihilator()
        self.z = z
        q = z.rational()
        if q is not None:
            # every form vanishing on the whole phase: the left kernel of the Krylov matrix
            # [z, A_I z, ..., A_I^{n-1} z] (it contains the annihilator of V_I)
            self.zero_forms = orbit_zero_forms(self.M, q)
        else:
            # z in V_I: the annihilator of V_I (A_I-invariant) vanishes on the whole phase, and so
            # do the A_I-invariant relations already known on z
            zf = z.zero_forms
            self.zero_forms = W if not zf.nrows() else _stack(W, invariant_forms(zf, self.M))
            if W.nrows():
                z.zero_forms = _stack(z.zero_forms, W)
        F = mode.feedback()
        C, D = self.lcs.C, self.lcs.D
        cons = []
        for r, i in enumerate(mode.I):
            cons.append(Constraint("u", i, submatrix(F, [r], None)))
        for i in mode.Ic:
            g = submatrix(C, [i], None)
            if mode.I:
                g = g + submatrix(D, [i], mode.I) * F
            cons.append(Constraint("y", i, g))
        self.constraints = cons
        self._powers = {}

    def gM(self, c: Constraint, j: int) -> fmpq_mat:
        """g A_I^j (cached)."""
        key = (c.kind, c.index, j)
        if key not in self._powers:
            self._powers[key] = c.g if j == 0 else self.gM(c, j - 1) * self.M
        return self._powers[key]

    def state(self, t: Any) -> ExactVector:
        """x(t) = e^{A_I t} z (t relative to the phase start)."""
        x = expm_action(self.M, t, self.z)
        if isinstance(x, ExpVector):
            x.zero_forms = _stack(x.zero_forms, self.zero_forms)
        return x

    # --- start of the phase: Lemma 5.1 -------------------------------------------------------
    def start_order(self, c: Constraint) -> tuple[int, int]:
        """(sign, order) of f at t = 0+: the first nonzero f^{(j)}(0); (0, -1) if f ≡ 0."""
        for j in range(self.lcs.n):
            s = self.z.sign_of_form(self.gM(c, j)) if not isinstance(self.z, RationalVector) else \
                _rsign((self.gM(c, j) * self.z.q)[0, 0])
            if s:
                return s, j
        # f ≡ 0 (Cayley-Hamilton): g A_I^j vanishes on the whole phase, for every j
        self.zero_forms = _stack(self.zero_forms, _stack(*[self.gM(c, j) for j in range(self.lcs.n)]))
        return 0, -1

    # --- enclosures ---------------------------------------------------------------------------
    def _enclose(self, c: Constraint, d: int, a: fmpq, b: fmpq, prec: int) -> arb:
        """Enclosure of f^{(d)} on [a, b] (Taylor form around the midpoint)."""
        with workprec(prec):
            m = (a + b) / 2
            r = (b - a) / 2
            z = self.z.arb(prec)
            wm = expm_apply(self.M, arb(m), z, prec)
            wx = expm_apply(self.M, arb(m, r), z, prec) if r else wm
            rr = arb(r)
            out = arb(0)
            fact = 1
            for j in range(_K):
                if j:
                    fact *= j
                val = (arb_mat(self.gM(c, d + j)) * wm)[0, 0]
                out += val if j == 0 else val * arb(0, rr ** j) / fact
            fact *= _K
            out += (arb_mat(self.gM(c, d + _K)) * wx)[0, 0] * arb(0, rr ** _K) / fact
            return out

    def value(self, c: Constraint, t: Any, prec: int, d: int = 0) -> arb:
        """f^{(d)}(t) as a ball (t rational or arb)."""
        with workprec(prec):
            tb = t if isinstance(t, arb) else arb(t)
            return (arb_mat(self.gM(c, d)) * expm_apply(self.M, tb, self.z.arb(prec), prec))[0, 0]

    # --- root isolation -----------------------------------------------------------------------
    def first_root(self, c: Constraint, horizon: fmpq, prec: int = 64):
        """The first t in (0, horizon] where f = g x(t) turns negative.

        Returns None (no event in (0, horizon]), ``fmpq(0)`` (immediately negative) or an
        isolating interval (lo, hi) with f(lo) > 0 > f(hi) and f' != 0 on it.
        """
        sign, order = self.start_order(c)
        if sign == 0:
            return None  # f ≡ 0
        if sign < 0:
            return fmpq(0)
        if order == 0:  # f(0) > 0 is certified: search from 0
            return self._search(c, fmpq(0), horizon, prec, 0)
        # f(0) = ... = f^{(order-1)}(0) = 0 < f^{(order)}(0): f^{(order)} > 0 on [0, eps] => f > 0 on (0, eps]
        p = prec
        while True:
            eps = horizon
            for _ in range(_MAX_DEPTH):
                if self._enclose(c, order, fmpq(0), eps, p) > 0:
                    break
                eps = eps / 2
            else:
                if p < _max_prec():
                    p *= 4
                    continue
                raise LCSError(f"could not certify the start of {c.name} (sign {sign}, order {order})")
            break
        if eps == horizon:
            return None
        return self._search(c, eps, horizon, p, 0)

    def _search(self, c: Constraint, a: fmpq, b: fmpq, prec: int, depth: int):
        """DFS over [a, b], f(a) > 0 known; returns the first isolating interval or None."""
        check_deadline(f" while isolating the roots of {c.name} near t = {float(a):.6g} (phase time)")
        F = self._enclose(c, 0, a, b, prec)
        if F > 0:
            return None
        D = self._enclose(c, 1, a, b, prec)
        if D > 0 or D < 0:
            fb = self.value(c, b, prec)
            if fb > 0:
                return None
            if fb < 0:
                return (a, b)
            # f(b) ≈ 0 with f monotone on [a, b]: the root is at b or beyond; decide at b exactly
            s = ball_sign(lambda p: self.value(c, b, p), lambda: f"{c.name} at t = {b} (root at an interval end)", prec)
            if s > 0:
                return None
            if s < 0:
                return (a, b)
            return (a, b)  # assumed zero at b: keep it as the root's bracket
        res = self._tangency(c, a, b, prec)
        if res is not _UNDECIDED:
            return res
        if depth >= _MAX_DEPTH:
            if prec < _max_prec():  # the enclosures may be limited by rounding: more bits
                return self._search(c, a, b, min(4 * prec, _max_prec()), _MAX_DEPTH // 2)
            s = unresolved(f"possible tangential touch (grazing) of {c.name} near t = {float(a):.17g}")
            return None if s == 0 else (a, b)
        m = (a + b) / 2
        left = self._search(c, a, m, prec, depth + 1)
        if left is not None:
            return left
        fm = self.value(c, m, prec)
        if fm < 0:
            return (a, m)  # pragma: no cover - left search would have found it
        return self._search(c, m, b, prec, depth + 1)


    def _tangency(self, c: Constraint, a: fmpq, b: fmpq, prec: int):
        """Decide [a, b] (f(a) > 0) when f'' has a sign there: the grazing test.

        Concave: the minimum is at b.  Convex with f'(a) < 0 < f'(b): the minimum is at the
        unique critical point t* (a root of f'); f(t*) > 0 means no event, f(t*) < 0 an event in
        (a, t*), and f(t*) = 0 - proven with closed forms of t* and f - a tangential touch, which
        is not an event.  Returns None, an isolating interval, or _UNDECIDED.
        """
        D2 = self._enclose(c, 2, a, b, prec)
        if not (D2 > 0 or D2 < 0):
            return _UNDECIDED
        fb = self.value(c, b, prec)
        da, db = self.value(c, a, prec, 1), self.value(c, b, prec, 1)
        if D2 < 0 or db < 0:  # the minimum of f on [a, b] is at b
            return None if fb > 0 else (a, b) if fb < 0 else _UNDECIDED
        if da > 0:
            return None  # convex and nondecreasing from f(a) > 0
        if not (da < 0 and db > 0):
            return _UNDECIDED
        tstar = RootReal(self, Constraint("d" + c.kind, c.index, -self.gM(c, 1)), a, b)
        for p in (prec, 2 * prec, 4 * prec):
            v = self.value(c, tstar.arb(p + 20), p)
            if v > 0:
                return None
            if v < 0:
                for q in (p, 2 * p, 4 * p, 8 * p):
                    tstar.arb(q + 20)
                    if self.value(c, tstar.lo, q) < 0:
                        return (a, tstar.lo)
                return _UNDECIDED
        # f(t*) may be exactly 0: a tangential touch if proven
        if prove_closed_form(tstar) is not None and vanishes_at(self, c.g, tstar.closed_form):
            return None  # f >= 0 on [a, b]: convex with f(t*) = f'(t*) = 0
        s = ball_sign(lambda p: self.value(c, tstar.arb(p + 20), p),
                      lambda: f"{c.name} at its critical point t ≈ {float(tstar.arb(64).mid()):.17g} "
                              "(phase time; tangential touch?)", prec)
        if s > 0 or s == 0:
            return None
        return _UNDECIDED


_UNDECIDED = object()


def _stack(*ms: fmpq_mat) -> fmpq_mat:
    """Rows of all the matrices, reduced to a basis of their span."""
    from .subspaces import image
    from .rational import vstack
    m = vstack(*ms)
    return image(m.transpose()).transpose() if m.nrows() else m


def _rsign(v) -> int:
    return (v > 0) - (v < 0)


# ---------------------------------------------------------------------------------------------
# the root as an exact real
# ---------------------------------------------------------------------------------------------


class RootReal(Real):
    """The unique root of f = g e^{Mt} z in the isolating interval [lo, hi] (f(lo) > 0 > f(hi))."""

    def __init__(self, phase: Phase, c: Constraint, lo: fmpq, hi: fmpq):
        super().__init__()
        self.phase, self.c = phase, c
        self.lo, self.hi = lo, hi

    def _try_sign(self, t: fmpq, prec: int) -> int:
        """Sign of f(t) at this precision; 0 when the ball contains 0 (undecided, not a zero)."""
        v = self.phase.value(self.c, t, prec)
        return 1 if v > 0 else -1 if v < 0 else 0

    def _eval(self, prec: int) -> arb:
        if self.closed_form is not None:
            return _sympy_to_arb(self.closed_form)
        target = fmpq(1, 2 ** (prec + 2))
        work = prec + 16
        while self.hi - self.lo > target * max(1, abs(self.hi)):
            check_deadline(f" while refining the root of {self.c.name}")
            lo, hi = self.lo, self.hi
            # Newton from the midpoint; certify a small bracket around the candidate
            m = (lo + hi) / 2
            with workprec(work):
                fm = self.phase.value(self.c, m, work)
                dfm = self.phase.value(self.c, m, work, 1)
            if not dfm.contains(0):
                step = _arb_to_fmpq((fm / dfm).mid())
                cand = m - step
                if lo < cand < hi:
                    # quadratic convergence: the error after the step is about C * step^2
                    delta = max(min((hi - lo) / 4, 64 * step * step + (hi - lo) / 2 ** 64), target / 4)
                    a, b = max(lo, cand - delta), min(hi, cand + delta)
                    if a > lo and b < hi and self._try_sign(a, work) > 0 and self._try_sign(b, work) < 0:
                        self.lo, self.hi = a, b
                        continue
            # bisection at a point where the sign is decidable (an exact dyadic root, or a ball
            # too wide at this precision, makes the midpoint undecidable: try nearby points)
            for t in (m, lo + (hi - lo) * 3 / 8, lo + (hi - lo) * 5 / 8):
                sg = self._try_sign(t, work)
                if sg > 0:
                    self.lo = t
                    break
                if sg < 0:
                    self.hi = t
                    break
            else:
                if work >= _max_prec():
                    unresolved(lambda: f"the sign of {self.c.name} near its root t = {float(m):.17g}")
                    self.lo = self.hi = m  # assumed: m is the root
                    break
                work = min(2 * work, _max_prec())
        return arb(self.lo).union(arb(self.hi))  # rigorous: both ends are exact rationals

    def interval(self) -> tuple[fmpq, fmpq]:
        return self.lo, self.hi


def _arb_to_fmpq(x: arb) -> fmpq:
    """The exact (dyadic) midpoint of a ball as fmpq."""
    m, e = x.mid().man_exp()
    m, e = int(m), int(e)
    return fmpq(m * 2 ** e) if e >= 0 else fmpq(m, 2 ** (-e))


def _horizon_bound(H) -> fmpq:
    """A rational upper bound of H (slightly above it)."""
    b = H.arb(64)
    up = b.mid() + b.rad() + arb(2) ** -40
    return _arb_to_fmpq(up)


def next_event(phase: Phase, H, closed_forms: bool):
    """(θ, constraints reaching zero at θ) for the first event in (0, H), or None (Def. 4.3).

    Constraints whose roots cannot be separated from the first one are simultaneous only when
    proven (equal closed forms); otherwise the order is an unresolved sign.
    """
    hb = _horizon_bound(H)
    found = []  # (constraint, lo, hi)
    limit = hb
    for c in phase.constraints:
        r = phase.first_root(c, limit)
        if r is None:
            continue
        if isinstance(r, fmpq):
            raise LCSError(f"internal inconsistency: {c.name} of the selected mode "
                           f"{format_mode(phase.mode.I)} is negative at the start of the phase")
        lo, hi = r
        found.append((c, lo, hi))
        limit = min(limit, hi)
    if not found:
        return None
    roots = [(c, RootReal(phase, c, lo, hi)) for c, lo, hi in found]
    # the first root; others that cannot be separated from it are simultaneous (or unresolved)
    first_c, first = roots[0]
    for c, r in roots[1:]:
        s = compare_roots(r, first, closed_forms)
        if s < 0:
            first_c, first = c, r
    if closed_forms and first.closed_form is None:
        prove_closed_form(first)
    # beyond the horizon? (an event exactly at t_end is reported: the state there is x(t_end+))
    if (first - H).sign() > 0:
        return None
    simultaneous = [first_c]
    for c, r in roots:
        if r is first:
            continue
        if compare_roots(r, first, closed_forms) == 0:
            simultaneous.append(c)
    return first, simultaneous


def proportional_on_phase(phase: Phase, ga: fmpq_mat, gb: fmpq_mat) -> bool:
    """True when g_a x(t) = c g_b x(t) on the whole phase with c != 0, proven exactly.

    That holds when g_a lies in span(g_b, forms vanishing on the phase) but not in the span of
    the vanishing forms alone (e.g. u_0 = 2q_1 - q_2 and y_1 = q_1 - q_2 while q_1 ≡ 0).
    """
    from .rational import vstack
    from .subspaces import rank
    Z = [phase.zero_forms] if phase.zero_forms.nrows() else []
    base = rank(Z[0]) if Z else 0
    with_b = rank(vstack(*Z, gb))
    return rank(vstack(*Z, gb, ga)) == with_b > base and rank(vstack(*Z, ga)) > base


def compare_roots(a: RootReal, b: RootReal, closed_forms: bool) -> int:
    """Certified order of two roots; equal only when proven (identical functions up to a factor
    on the phase, or equal closed forms) or assumed."""
    if a.phase is b.phase and proportional_on_phase(a.phase, a.c.g, b.c.g):
        return 0
    if a.closed_form is not None and b.closed_form is not None:
        import sympy
        d = sympy.simplify(a.closed_form - b.closed_form)
        if d == 0:
            return 0
    prec = 64
    while prec <= 4096:
        x, y = a.arb(prec), b.arb(prec)
        if x < y:
            return -1
        if x > y:
            return 1
        if prec == 128 and closed_forms:
            for r in (a, b):
                if r.closed_form is None:
                    prove_closed_form(r)
            if a.closed_form is not None and b.closed_form is not None:
                import sympy
                if sympy.simplify(a.closed_form - b.closed_form) == 0:
                    return 0
        prec *= 2
    return unresolved(f"the order of the roots of {a.c.name} and {b.c.name} (simultaneous events?)")


def theta(lcs, x0: Any, I, horizon: Any) -> Real | None:
    """θ(x0, I) of Def. 4.3 on (0, horizon]: the length of the phase in mode I from x0.

    x0 outside V_I is first re-initialized to P_I x0 (the regular part of the solution of (4.2)).
    Returns an exact real (0 when u or y is immediately negative, Example 4.5), or None when
    no event occurs in (0, horizon).

    >>> from lcs_exact.models import two_carts
    >>> theta(two_carts(), [0, -1, 0, 0], {0}, 10).closed_form   # Example 4.4
    pi/2
    >>> theta(two_carts(), [0, 1, -1, 0], {0}, 10).closed_form   # Example 4.5
    0
    """
    from .reals import ProjectedVector, RationalReal, as_exact_vector, as_real
    mode = lcs.mode(I)
    z = as_exact_vector(x0, lcs.n)
    q = z.rational()
    if q is not None:
        z = RationalVector(mode.projection() * q)
    else:
        z = ProjectedVector(mode.projection(), z)
    phase = Phase(mode, z)
    for c in phase.constraints:
        if phase.start_order(c)[0] < 0:
            return RationalReal(0)
    hit = next_event(phase, as_real(horizon), True)
    return None if hit is None else hit[0]

# ---------------------------------------------------------------------------------------------
# closed forms
# ---------------------------------------------------------------------------------------------

_t = sympy.Symbol("t", real=True)
_s = sympy.Symbol("s")


def laplace_closed_form(M: fmpq_mat, row: fmpq_mat, z: fmpq_mat):
    """A SymPy closed form of row . e^{Mt} z (z rational), or None.

    The Laplace transform row (sI - M)^{-1} z = N(s)/d(s) is reduced; when every irreducible
    factor of d over Q has degree <= 2 the partial fractions are inverted term by term
    (t^l e^{rt}, e^{at} cos/sin, cosh/sinh); otherwise None.
    """
    from .rational import RationalFunction
    from .system import LCS
    n = M.nrows()
    aux = LCS(M, zeros(n, 1) + z, row, [[0]])  # G(s) = row (sI - M)^{-1} z
    f: RationalFunction = aux.G()[0, 0]
    if f.is_zero():
        return sympy.Integer(0)
    ext = _quadratic_extension(f.den)
    if ext is False:
        return None
    expr = f.to_sympy().subs(sympy.Symbol("s"), _s)
    total = sympy.Integer(0)
    parts = sympy.apart(expr, _s) if ext is None else sympy.apart(expr, _s, extension=ext)
    for term in sympy.Add.make_args(parts):
        inv = _inverse_laplace_term(term)
        if inv is None:
            return None
        total += inv
    return total  # each term is already in lowest terms; simplify() here costs ~0.1 s a call


def _quadratic_extension(den):
    """None when every irreducible factor of den over Q has degree <= 2; sqrt(d) when the others
    are biquadratic a s^4 + b s^2 + c splitting over one Q(sqrt(d)), d = b^2 - 4ac (the two carts'
    free mode: s^4 + 3s^2 + 1 over Q(sqrt 5)); False otherwise."""
    ext = None
    for p, _ in den.factor()[1]:
        if p.degree() <= 2:
            continue
        c = p.coeffs()
        if p.degree() != 4 or c[1] != 0 or c[3] != 0:
            return False
        d = c[2] * c[2] - 4 * c[4] * c[0]
        root = sympy.sqrt(sympy.Rational(int(d.p), int(d.q)))
        if ext is not None and sympy.simplify(sympy.sqrt(root ** 2 / ext ** 2)).is_Rational is not True:
            return False  # two different quadratic fields
        ext = ext if ext is not None else root
    return ext


def _inverse_laplace_term(term):
    num, den = sympy.fraction(sympy.factor(term))
    dp = sympy.Poly(den, _s)
    np_ = sympy.Poly(num, _s)
    if dp.degree() == 0:
        return None  # a polynomial part: impossible for a strictly proper transform
    lc = dp.LC()
    fl = sympy.factor_list(dp.as_expr() / lc, _s)
    if len(fl[1]) != 1:
        return sympy.inverse_laplace_transform(term, _s, _t)
    base, mult = fl[1][0]
    bp = sympy.Poly(base, _s)
    c0 = fl[0] * lc
    if bp.degree() == 1:
        a1, a0 = bp.all_coeffs()
        r = -a0 / a1
        if np_.degree() > 0:
            return sympy.inverse_laplace_transform(term, _s, _t)
        # term = k / (s - r)^mult with k = num / (c0 a1^mult): the base may be non-monic (2s + 1)
        k = np_.as_expr() / (c0 * a1 ** mult)
        return k * _t ** (mult - 1) * sympy.exp(r * _t) / sympy.factorial(mult - 1)
    if bp.degree() == 2 and mult == 1:
        a2, p, q = bp.all_coeffs()
        p, q = p / a2, q / a2
        c0 = c0 * a2
        coeffs = np_.all_coeffs()
        alpha, beta = (coeffs if len(coeffs) == 2 else [0] + coeffs)
        alpha, beta = alpha / c0, beta / c0
        disc = q - p ** 2 / 4
        a = -p / 2
        if disc > 0:
            w = sympy.sqrtdenest(sympy.sqrt(disc))
            return sympy.exp(a * _t) * (alpha * sympy.cos(w * _t) + (beta + alpha * a) / w * sympy.sin(w * _t))
        w = sympy.sqrtdenest(sympy.sqrt(-disc))
        return sympy.exp(a * _t) * (alpha * sympy.cosh(w * _t) + (beta + alpha * a) / w * sympy.sinh(w * _t))
    return sympy.inverse_laplace_transform(term, _s, _t)


def frequencies(M: fmpq_mat) -> tuple[list, list]:
    """(ω's of complex-pair quadratic factors, real rational eigenvalues) of the charpoly of M."""
    chi = M.charpoly()
    omegas, lambdas = [], []
    for p, _ in chi.factor()[1]:
        c = [sympy.Rational(int(x.p), int(x.q)) for x in p.coeffs()]
        if p.degree() == 1:
            lambdas.append(-c[0] / c[1])
        elif p.degree() == 2:
            q, pp, a2 = c
            disc = q / a2 - (pp / a2) ** 2 / 4
            if disc > 0:
                omegas.append(sympy.sqrt(disc))
    return omegas, lambdas


def closed_form_candidates(theta_ball: arb, M: fmpq_mat) -> list:
    """Small-height candidates for a root: rationals, (p/q) π / ω, log(p/q) / λ."""
    from mpmath import mp, mpf
    out = []
    with mp.workdps(40):
        x = mpf(theta_ball.mid().str(40, radius=False))
        def approx(v):
            f = Fraction(str(v))
            return {f.limit_denominator(d) for d in (1, 2, 3, 4, 6, 8, 12, 16, 24, 100, 1000)}
        for f in approx(x):
            out.append(sympy.Rational(f.numerator, f.denominator))
        omegas, lambdas = frequencies(M)
        for w in [sympy.Integer(1)] + omegas:
            wv = mpf(str(sympy.N(w, 40)))
            for f in approx(x * wv / mp.pi):
                if f:
                    out.append(sympy.Rational(f.numerator, f.denominator) * sympy.pi / w)
        for lam in lambdas:
            if lam != 0:
                v = mp.exp(mpf(lam.p) / lam.q * x)
                for f in approx(v):
                    if f > 0 and f != 1:
                        out.append(sympy.log(sympy.Rational(f.numerator, f.denominator)) / lam)
    seen, uniq = set(), []
    for c in out:
        if c not in seen and c.is_positive:
            seen.add(c)
            uniq.append(c)
    return uniq


def function_closed_form(phase: Phase, g: fmpq_mat):
    """f(t) = g e^{A_I t} z as a SymPy expression in t (phase time), or None.

    The expression is cross-checked against the certified ball of f at two rational times (a
    defect in the symbolic inversion must never turn into a false proof)."""
    z = phase.z.rational()
    if z is not None:
        sym = laplace_closed_form(phase.M, g, z)
    else:
        x = phase_closed_form(phase)
        sym = None if x is None else sympy.expand((matrix_to_sympy(g) * x)[0, 0])
    if sym is not None:
        for tq in (fmpq(1, 7), fmpq(5, 3)):
            with workprec(128):
                want = (arb_mat(g) * expm_apply(phase.M, arb(tq), phase.z.arb(128), 128))[0, 0]
                got = _sympy_to_arb(sym.subs(_t, sympy.Rational(int(tq.p), int(tq.q))))
            if not want.overlaps(got):
                raise LCSError(f"internal error: the symbolic form {sym} of {_fmt_row(g)} e^(A_I t) z "
                               f"disagrees with its certified value at t = {tq}")
    return sym


def _fmt_row(g: fmpq_mat) -> str:
    return "(" + ", ".join(str(g[0, j]) for j in range(g.ncols())) + ")"


def vanishes_at(phase: Phase, g: fmpq_mat, t_cf, sym=None) -> bool:
    """True when f = g x(t) is proven exactly 0 at the closed-form time t_cf: (a) structurally
    (the state at t_cf collapses to a rational vector) or (b) symbolically (SymPy simplifies
    f(t_cf) to literal 0). False means "not proven", not "nonzero"."""
    x = expm_action(phase.M, t_cf, phase.z)
    q = x.rational()
    if q is not None:
        return (g * q)[0, 0] == 0
    if sym is None:
        sym = function_closed_form(phase, g)
    if sym is None:
        return False
    expr = sympy.expand_trig(sym.subs(_t, t_cf))
    if sympy.count_ops(expr) > _MAX_SIMPLIFY_OPS:
        return False  # SymPy's simplify can take minutes on large expressions: not proven
    check_deadline(" while proving a closed form")
    return sympy.simplify(expr) == 0


_MAX_SIMPLIFY_OPS = 400


def prove_closed_form(root: RootReal) -> Any:
    """Try the candidates; return the proven closed form (and set it on the root) or None.

    Structural proofs (the state at the candidate collapses to a rational vector) are tried
    first: they need no SymPy expression of the phase, which costs ~0.5 s for a new mode."""
    phase, c = root.phase, root.c
    structural = isinstance(phase.z, ExpVector) and phase.z.M == phase.M and phase.z.v.rational() is not None
    b = root.arb(200)

    def inside(cand) -> bool:
        with workprec(512):  # the bracket is ~2^-200 wide: compare well above that
            cb = _sympy_to_arb(cand)
            return cb > arb(root.lo) and cb < arb(root.hi)

    cands = [x for x in closed_form_candidates(b, phase.M) if inside(x)]
    if structural:
        for cand in cands:
            q = expm_action(phase.M, cand, phase.z).rational()
            if q is not None and (c.g * q)[0, 0] == 0:
                root.closed_form = cand
                return cand
    sym = function_closed_form(phase, c.g)
    if sym is None:
        return None  # no symbolic f: no proof is possible
    for more in (lambda: cands, lambda: _exp_candidates(sym), lambda: _solve_candidates(sym, b)):
        for cand in more():  # cheap candidates first: SymPy's solve can take 0.2 s
            if inside(cand) and vanishes_at(phase, c.g, cand, sym):
                root.closed_form = cand
                return cand
    return None


def _exp_candidates(sym) -> list:
    """Roots of an exponential sum f = Σ c_k e^{μ_k t} whose exponents are integer multiples of
    one g (rational ratios): f is a polynomial in u = e^{g t}; each positive real root r in
    radicals gives t = log(r) / g. (Candidates only: they are proven by the caller.)"""
    if sym.has(sympy.sin, sympy.cos):
        return []
    f = sympy.powsimp(sympy.expand(sym.rewrite(sympy.exp)))
    terms = {}
    for term in sympy.Add.make_args(f):
        coeff, mu = term, sympy.Integer(0)
        for e in term.atoms(sympy.exp):
            mu += sympy.diff(e.args[0], _t)
            coeff = coeff.subs(e, 1)
        if coeff.has(_t) or mu.has(_t):
            return []  # t^m e^{μt} terms or non-linear exponents: no polynomial in e^{gt}
        terms[mu] = terms.get(mu, 0) + coeff
    mus = [m for m in terms if m != 0]
    if not mus:
        return []
    ratios = [sympy.nsimplify(sympy.simplify(m / mus[0])) for m in mus]
    if not all(r.is_Rational for r in ratios):
        return []
    num = sympy.gcd([r.p for r in ratios])
    den = sympy.lcm([r.q for r in ratios])
    g = sympy.simplify(mus[0] * num / den)
    u = sympy.Symbol("u", positive=True)
    powers = {m: int(sympy.nsimplify(sympy.simplify(m / g))) for m in terms}
    low = min(powers.values())
    poly = sympy.Poly(sum(terms[m] * u ** (powers[m] - low) for m in terms), u)
    if poly.degree() < 1 or poly.degree() > 12:
        return []
    out = []
    for factor, _ in poly.factor_list()[1]:
        if factor.degree() > 2:
            continue  # cubic/quartic radicals: unreadable and slow to prove (minutes in SymPy)
        for r in sympy.roots(factor, filter=None):
            if r.is_real and r.is_positive and r != 1:
                out.append(sympy.log(r) / g)
    return out


def _solve_candidates(sym, b: arb) -> list:
    """Exact solutions of a one-frequency f = a cos(ωt) + b sin(ωt) + c (SymPy solve), shifted by
    multiples of 2π/ω towards the root ball b."""
    trig = sym.atoms(sympy.sin, sympy.cos)
    if sym.has(sympy.exp, sympy.cosh, sympy.sinh) or not trig or len(sympy.Add.make_args(sym)) > 3:
        return []
    if sym.xreplace({f: sympy.Dummy() for f in trig}).has(_t):
        return []  # t also outside the trigonometric terms (e.g. 1 - t/2 - sin t): not one-frequency
    freqs = {sympy.simplify(sympy.diff(f.args[0], _t)) for f in trig}
    if len(freqs) != 1:
        return []
    (w,) = freqs
    if w.has(_t) or not all(sympy.diff(f.args[0], _t, 2) == 0 for f in trig):
        return []  # arguments not linear in t
    try:
        sols = sympy.solve(sym, _t)
    except Exception:  # SymPy could not solve: no candidates
        return []
    from mpmath import mp, mpf
    out = []
    with mp.workdps(30):
        target = mpf(b.mid().str(30, radius=False))
        period = 2 * mp.pi / mpf(str(sympy.N(w, 30)))
        for sol in sols:
            val = sympy.N(sol, 30) if not isinstance(sol, dict) else None
            if val is None or not val.is_Number or not val.is_real:
                continue
            v = mpf(str(val))
            k = int(mp.nint((target - v) / period))
            out.append(sympy.simplify(sol + k * 2 * sympy.pi / w))
    return out


_EXPM_CACHE: dict = {}


def expm_symbolic(M: fmpq_mat):
    """e^{Mt} as a SymPy matrix in t (column j by :func:`laplace_closed_form` of e_j), or None
    when some denominator has an irreducible factor of degree > 2. Cached per M."""
    key = (M.nrows(), tuple(M.entries()))
    if key not in _EXPM_CACHE:
        n = M.nrows()
        unit = [fmpq_mat(n, 1, [int(i == j) for i in range(n)]) for j in range(n)]
        cols = []
        for j in range(n):
            col = [laplace_closed_form(M, unit[i].transpose(), unit[j]) for i in range(n)]
            if any(c is None for c in col):
                cols = None
                break
            cols.append(col)
        E = None if cols is None else sympy.Matrix(n, n, lambda i, j: cols[j][i])
        if E is not None:  # cross-check against the certified e^{M/7} (never a false closed form)
            with workprec(128):
                ball = expm_apply(M, arb(fmpq(1, 7)), arb_mat(fmpq_mat(n, n, [int(i == j) for i in range(n)
                                                                               for j in range(n)])), 128)
                for i in range(n):
                    for j in range(n):
                        if not ball[i, j].overlaps(_sympy_to_arb(E[i, j].subs(_t, sympy.Rational(1, 7)))):
                            raise LCSError(f"internal error: symbolic e^(Mt) disagrees with its "
                                           f"certified value at t = 1/7 (entry {i}, {j})")
        _EXPM_CACHE[key] = E
    return _EXPM_CACHE[key]


def phase_closed_form(phase: Phase):
    """x(t) = e^{A_I t} z as a SymPy vector in t, when z has a closed form (None otherwise)."""
    if not hasattr(phase, "_closed"):
        phase._closed = None
        zc = phase.z.closed_form()
        if zc is not None:
            E = expm_symbolic(phase.M)
            if E is not None:
                phase._closed = E * zc
    return phase._closed


def state_closed_form(phase: Phase, theta: Real):
    """x(θ) as a SymPy vector when z and θ have closed forms (None otherwise)."""
    if theta.closed_form is None:
        return None
    x = phase_closed_form(phase)
    if x is None:
        return None
    return x.subs(_t, theta.closed_form).applyfunc(lambda e: sympy.simplify(sympy.expand_trig(e)))

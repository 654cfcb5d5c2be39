"""Certified real roots of exponential sums (the events of Def. 4.3).

A constraint of a continuous phase is f(t) = g e^{A_I t} z, an exponential sum

    f(t) = sum_k w_k Re( e^{lambda_k t} P_k(t) ),   P_k(t) = sum_j c_{k,j} t^j       (:class:`ExpSum`)

with certified complex-ball coefficients (from the modal vectors of z, :mod:`lcs_exact.expm`).
Enclosures are built from the terms: f^{(d)} on X = [m - r, m + r] is enclosed by its Taylor form
sum_{j<K} f^{(d+j)}(m) [-r, r]^j / j! + f^{(d+K)}(X) [-r, r]^K / K!, where each derivative is a
sum over the eigenvalues (lambda^d e^{lambda X}: a stiff term with Re(lambda) = -10^6 contributes
nothing once it has decayed, however large lambda^d is).

:func:`first_crossing` finds the first point where f turns negative, theta = inf{t > a : f(t) < 0}
(Def. 4.3), by a depth-first search over intervals with the invariant "no crossing before the
interval" (an explicit stack, never recursion).  An interval is discarded when f > 0 on it, when f
is increasing on it, when it is decreasing and f(hi) > 0, or by the convexity argument (the
minimum is at the critical point t*, a root of f'; f(t*) > 0, or f(t*) = 0 proven - a tangential
touch, not an event).  The search returns a :class:`Bracket` (lo, hi] that contains theta: f has
no crossing before lo and f(hi) < 0 is certified.  A bracket on which f' < 0 holds one simple root
(refined by interval Newton); otherwise (a multiple root, a cluster) theta is refined by bisection
with the same invariant, so a triple root is handled like a simple one.  Split points are chosen
where the sign of f is certified; a search that cannot decide at the policy's ceiling reports an
unresolved sign.  The work is bounded: interval widths are limited by the precision, precision by
the ceiling, and the wall clock by the policy's deadline.

:class:`RootReal` is the root as an exact real: its ball at any precision comes from the bracket
and the phase start's ball at that precision (it is anchored like every node of
:mod:`lcs_exact.reals`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Protocol

from flint import acb, arb, fmpq

from ..numbers import calcium
from ..numbers import Policy, ball_sign, dyadic, dyadic_lower, dyadic_upper, workprec
from ..errors import LCSError
from ..numbers import Closed
from .guesses import float_root
from ..numbers import Real

__all__ = ["ExpSum", "Bracket", "RootFunction", "first_crossing", "RootReal", "dyadic", "newton_ball",
           "positive_step", "taylor_form", "TAYLOR_ORDER"]

TAYLOR_ORDER = 4
#: extra bits for the exponential sum when a root is refined to a given precision
ROOT_GUARD = 32
_SPLITS = (fmpq(1, 2), fmpq(7, 16), fmpq(9, 16), fmpq(3, 8), fmpq(5, 8), fmpq(13, 32), fmpq(19, 32))


class ExpSum:
    """f(t) = sum_k w_k Re(e^{lambda_k t} P_k(t)) at a fixed precision (see the module docstring).

    ``terms``: [(lambda, weight, [c_0, c_1, ...])] with complex balls; weight 2 stands for a
    conjugate pair.

    >>> f = ExpSum([(acb(0, 1), 2, [acb(0.5)])], 64)      # cos t
    >>> f.value(0), f.value(0, 1)
    (1.00000000000000, 0)
    """

    def __init__(self, terms: list, prec: int):
        self.terms = terms
        self.prec = prec
        self._d: dict[int, list] = {0: terms}
        self._shifted: dict[int, "ExpSum"] = {}
        # the semisimple eigenvalues (one coefficient: all of them, usually) take their values
        # by the powers of lambda, {d: [(lambda, w lambda^d c)]} (w = 2 exact in a ball); the
        # others (a rigid-body mode of a chain of carts: 0 twice) by their derivative terms
        self._powers: dict[int, list] = {}
        self._poly: dict[int, list] = {0: [t for t in terms if len(t[2]) > 1]}

    def _deriv_terms(self, d: int, cache: dict | None = None) -> list:
        """Terms of f^{(d)}: (e^{lambda t} P)' = e^{lambda t} (lambda P + P') (``cache``: the
        derivatives of a subset of the terms, {0: subset})."""
        cache = self._d if cache is None else cache
        if d not in cache:
            prev = self._deriv_terms(d - 1, cache)
            with workprec(self.prec):
                out = []
                for lam, w, cs in prev:
                    new = [lam * c for c in cs]
                    for j in range(1, len(cs)):
                        new[j - 1] += cs[j] * j
                    out.append((lam, w, new))
            cache[d] = out
        return cache[d]

    def values(self, t: arb | fmpq, orders: range) -> list[arb]:
        """[f^{(d)}(t) for d in orders] (t a rational point, or a ball: an interval), sharing
        e^{lambda t}; rationals are converted at the sum's precision, never at flint's ambient
        53 bits."""
        with workprec(self.prec):
            tc = acb(arb(t) if isinstance(t, fmpq) else t)
            out = self._semisimple_values(tc, orders)
            if not self._poly[0]:
                return out
            exps = [(lam * tc).exp() for lam, _, _ in self._poly[0]]
            for j, d in enumerate(orders):
                for (_, w, cs), e in zip(self._deriv_terms(d, self._poly), exps):
                    p = cs[-1]
                    for c in reversed(cs[:-1]):
                        p = p * tc + c
                    v = (e * p).real
                    out[j] += v * w if w != 1 else v
            return out

    def _semisimple_values(self, tc: acb, orders: range) -> list[arb]:
        """The part of values() of the terms w Re(c e^{lambda t}): f^{(d)}(t) = sum w Re(lambda^d
        c e^{lambda t}), one exponential and one product a term and order (the caller holds the
        precision)."""
        d0, k = orders.start, len(orders)
        if d0 not in self._powers:  # w lambda^d0 c directly (no chain of derivative terms)
            self._powers[d0] = [(lam, cs[0] * (lam ** d0 * w) if d0 else cs[0] * w)
                                for lam, w, cs in self.terms if len(cs) == 1]
        out = [arb(0)] * k
        for lam, c in self._powers[d0]:
            p = (lam * tc).exp() * c
            out[0] += p.real
            for j in range(1, k):
                p *= lam
                out[j] += p.real
        return out

    def value(self, t: arb | fmpq, d: int = 0) -> arb:
        """f^{(d)}(t)."""
        return self.values(t, range(d, d + 1))[0]

    def floats(self) -> tuple:
        """(lambda, weight, coefficients) as numpy arrays of the balls' midpoints: for float
        estimates that only guide the certified search (see :mod:`lcs_exact.guesses`)."""
        if "_floats" not in self.__dict__:
            import numpy as np  # only for guesses; `import lcs_exact` stays without numpy
            lam = np.array([complex(l) for l, _, _ in self.terms], dtype=complex)
            w = np.array([float(w) for _, w, _ in self.terms])
            deg = max((len(cs) for _, _, cs in self.terms), default=1)
            cs = np.array([[complex(c) for c in cs] + [0] * (deg - len(cs)) for _, _, cs in self.terms],
                          dtype=complex).reshape(len(lam), deg)
            self._floats = (lam, w, cs)
        return self._floats

    def float_values(self, t, d: int = 0):
        """f^{(d)} at the float points t (midpoints of the terms; overflow gives inf/nan)."""
        import numpy as np
        lam, w, cs = self.floats()
        deg = cs.shape[1]
        for _ in range(d):  # (e^{lambda t} P)' = e^{lambda t} (lambda P + P')
            cs = cs * lam[:, None] + np.hstack([cs[:, 1:] * np.arange(1, deg), np.zeros((len(lam), 1))])
        with np.errstate(all="ignore"):
            E = np.exp(np.outer(t, lam))
            P = np.zeros_like(E)
            for j in range(deg - 1, -1, -1):
                P = P * t[:, None] + cs[:, j][None, :]
            return (E * P).real @ w

    def sign_enclose(self, lo: fmpq, hi: fmpq, d: int = 0) -> arb:
        """An enclosure of e^{-mu t} f^{(d)}(t) on [lo, hi], mu a dyadic near the largest real
        part of the exponents: the same sign as f^{(d)} everywhere (e^{-mu t} > 0), but a ball
        can show it.  e^{-10^6 t} on [0, 1] spans 10^-434294 .. 1 - no midpoint-radius ball of it
        excludes 0 - while its shifted form is the constant 1: stiff decaying terms cost nothing
        once the slowest term is factored out."""
        if d not in self._shifted:
            terms = [t for t in self._deriv_terms(d) if any(not c.is_zero() for c in t[2])]
            if not terms:
                self._shifted[d] = ExpSum([(acb(0), 1, [acb(0)])], self.prec)
            else:
                with workprec(self.prec):
                    mu = dyadic(max((lam.real for lam, _, _ in terms), key=lambda r: r.mid()))
                    self._shifted[d] = ExpSum([(lam - mu, w, cs) for lam, w, cs in terms], self.prec)
        return self._shifted[d].enclose(lo, hi, 0, sign_only=True)

    def enclose(self, lo: fmpq, hi: fmpq, d: int = 0, sign_only: bool = False) -> arb:
        """An enclosure of f^{(d)} on [lo, hi] (:func:`taylor_form`)."""
        return taylor_form(self, lo, hi, d, sign_only)

    def guess_root(self, lo: float, hi: float) -> float | None:
        """A float root in (lo, hi) where f decreases (:func:`~lcs_exact.guesses.float_root`)."""
        return float_root(self, lo, hi)


def taylor_form(f, lo: fmpq, hi: fmpq, d: int = 0, sign_only: bool = False) -> arb:
    """An enclosure of f^{(d)} on [lo, hi] for a function with ``values(t, orders)`` at points and
    balls and a ``prec``: the Taylor form of order TAYLOR_ORDER at the midpoint, intersected with
    the natural interval evaluation.  ``sign_only``: the caller wants the sign only, so a Taylor
    form that already excludes 0 is returned as it is."""
    with workprec(f.prec):
        X = arb(lo).union(arb(hi))  # contains [lo, hi] whatever the rounding
        m, r = X.mid(), X.rad()  # exact: X = [m - r, m + r]
        at_m = f.values(m, range(d, d + TAYLOR_ORDER))
        rem = f.value(X, d + TAYLOR_ORDER)
        out = at_m[0]
        rp, fact = arb(1), 1
        for j in range(1, TAYLOR_ORDER + 1):
            rp, fact = rp * r, fact * j
            coef = at_m[j] if j < TAYLOR_ORDER else rem
            # [-r, r]^j / j!: [0, r^j] for even j, [-r^j, r^j] for odd j
            box = arb(rp / 2, rp / 2) if j % 2 == 0 else arb(0, rp)
            out += coef * box / fact
        if sign_only and ball_sign(out):
            return out
        # the natural interval evaluation is rigorous too and far tighter on wide intervals
        # where one exponential dominates (e^{-10^6 t} on [0, 1]): keep the intersection
        direct = f.values(X, range(d, d + 1))[0]
        return out.intersection(direct) if out.overlaps(direct) else direct


class RootFunction(Protocol):
    """What a root needs of its function: balls of the exponential sum at any precision, the nodes
    those balls depend on, and a name for messages."""

    policy: Policy

    def at(self, prec: int) -> ExpSum: ...

    def deps(self) -> tuple: ...

    def describe(self) -> str: ...


@dataclass(frozen=True)
class Bracket:
    """theta in (lo, hi]: no crossing before lo (f > 0 on (start, lo]), f(hi) < 0 certified.
    ``simple``: f' < 0 on [lo, hi] is certified (one simple root)."""

    lo: fmpq
    hi: fmpq
    simple: bool


def _split_point(f: ExpSum, lo: fmpq, hi: fmpq) -> tuple[fmpq, int] | None:
    """A point of (lo, hi) near the middle where the sign of f is certified, with that sign."""
    w = hi - lo
    for s in _SPLITS:
        m = lo + w * s
        sg = ball_sign(f.value(m))
        if sg:
            return m, sg
    return None


TouchProver = Callable[[fmpq, fmpq, fmpq, fmpq], "bool | None"]


def first_crossing(fn: RootFunction, a: fmpq, b: fmpq, prec: int, *, touch: TouchProver | None = None
                   ) -> Bracket | None:
    """The first crossing theta = inf{t in (a, b] : f(t) < 0} as a :class:`Bracket`, or None when
    f >= 0 on (a, b].  Precondition: no crossing in (start, a] (f > 0 just after a).

    ``touch(clo, chi, lo, hi)``, called when the minimum of f at the critical point t* in
    [clo, chi] cannot be separated from 0 (f convex on [lo, hi], which holds [clo, chi]: t* is the
    only critical point there), proves a tangential touch (True), refutes it (False) or cannot
    tell (None).
    """
    policy = fn.policy
    stack: list = [(a, b, False)]
    while stack:
        lo, hi, neg = stack.pop()
        flat_tried = False
        policy.check_deadline(lambda: f" while isolating the roots of {fn.describe()} near t = "
                              f"{float(lo):.6g} (phase time)")
        while True:
            f = fn.at(prec)
            verdict = _decide_interval(fn, f, lo, hi, neg, prec, touch)
            if verdict == "split" and neg:
                # no crossing before lo, f(hi) < 0: theta is in (lo, hi] (a multiple root or a
                # cluster: refined by bisection with the same invariant)
                verdict = Bracket(lo, hi, False)
            if verdict not in ("split", "escalate"):
                break
            sp = None
            if verdict == "split" and (hi - lo) > fmpq(1, 2 ** max(8, prec // 2)) * max(1, abs(hi)):
                sp = _split_point(f, lo, hi)
            if sp is not None:
                verdict = "split"
                break
            if touch is not None and not neg and not flat_tried and hasattr(touch, "flat") and \
                    (hi - lo) <= fmpq(1, 2 ** max(8, prec // 16)) * max(1, abs(hi)):
                # no point of the interval has a sign: a touch of even order (4, 6, ...) at a
                # closed form, where not even f'' has one, is proven once, before more bits.  Only
                # on a narrow interval: around a touch of order m no ball shows a sign within
                # about 2^(-prec/m) of it (order 4 at 181 bits: 2^-45; up to m = 16 the interval
                # is below the bound 2^(-prec/16)), while a function below
                # the balls' resolution over a wide interval (a current decayed to 10^-60) needs
                # bits, not a proof over a dozen candidates (20 s of exact e^{At} at n = 34)
                flat_tried = True
                if touch.flat(lo, hi, f):
                    verdict = "none"
                    break
            policy.check_deadline(lambda: f" while isolating the roots of {fn.describe()} at {2 * prec} bits")
            if prec >= policy.max_prec:  # undecidable: raise, or assume f >= 0 here (recorded)
                policy.unresolved(lambda: f"{fn.describe()} on [{float(lo):.17g}, {float(hi):.17g}] "
                                  "(phase time; a tangential touch?)")
                verdict = "none"
                break
            prec = min(2 * prec, policy.max_prec)
        if verdict == "none":
            continue
        if isinstance(verdict, Advance):  # f > 0 on (lo, p]: the rest of the interval remains
            stack.append((verdict.p, hi, neg))
            continue
        if isinstance(verdict, Bracket):
            return verdict
        if isinstance(verdict, tuple):  # a crossing bracketed on a smaller interval
            if verdict[:2] == (lo, hi):
                return Bracket(lo, hi, False)
            stack.append(verdict)
            continue
        m, sg = sp
        if sg < 0:
            stack.append((lo, m, True))
        else:
            stack.append((m, hi, neg))
            stack.append((lo, m, False))
    return None


def _decide_interval(fn, f: ExpSum, lo: fmpq, hi: fmpq, neg: bool, prec: int, touch):
    """One interval of the search: "none" (no crossing in it), a Bracket, a smaller interval
    (lo, p, True) known to hold the crossing, an :class:`Advance` (f > 0 on a first part of the
    interval, at least an eighth of it), or "split"."""
    verdict = _decide_by_enclosures(fn, f, lo, hi, neg, prec, touch)
    if verdict == "split" and not neg:
        p = positive_step(f, lo, hi)
        if p is not None and (p - lo) * 8 >= hi - lo:
            return "none" if p >= hi else Advance(p)
    return verdict


def _decide_by_enclosures(fn, f: ExpSum, lo: fmpq, hi: fmpq, neg: bool, prec: int, touch):
    F = f.sign_enclose(lo, hi, 0)
    if not neg and F > 0:
        return "none"
    D = f.sign_enclose(lo, hi, 1)
    if D > 0 and not neg:
        return "none"  # increasing from f(lo) > 0
    if D < 0:
        if neg:
            return Bracket(lo, hi, True)
        s = ball_sign(f.value(hi))
        if s > 0:
            return "none"
        if s < 0:
            return Bracket(lo, hi, True)
        return "split"
    D2 = f.sign_enclose(lo, hi, 2)
    if D2 < 0:  # concave with f(lo) > 0: at most one root in [lo, hi], a crossing
        s = -1 if neg else ball_sign(f.value(hi))
        if s > 0:
            return "none"
        if s < 0:
            return Bracket(lo, hi, False)
        return "split"
    if D2 > 0:  # convex: f' increasing
        da, db = f.value(lo, 1), f.value(hi, 1)
        if da >= 0 and not neg:
            return "none"
        if not (da < 0 and db > 0):
            return "split"
        return _convex_minimum(fn, f, lo, hi, neg, prec, touch)
    return "split"


@dataclass(frozen=True)
class Advance:
    """A verdict of the search: f > 0 on (lo, p] is certified; (p, hi] remains."""

    p: fmpq


def positive_step(f: ExpSum, lo: fmpq, hi: fmpq, *, zero_below: int = 0,
                  orders: int = TAYLOR_ORDER) -> fmpq | None:
    """p in (lo, hi] with f > 0 on (lo, p], from the Taylor coefficients c_j = f^{(j)}(lo) / j!
    and bounds M_K of |f^{(K)}| / K! on [lo, b]: when c_0, ..., c_{K-1} >= 0 and c_J > 0 for some
    J < K, f(lo + s) >= c_J s^J - M_K s^K > 0 for 0 < s < (c_J / M_K)^{1/(K - J)}.

    ``zero_below``: c_j = 0 exactly for j < zero_below (a phase start where f and its first
    derivatives vanish, Lemma 5.1); otherwise c_0 >= 0 is the caller's invariant (f > 0 just
    before lo).  This is a step of the right size where f is tiny at lo and grows (a constraint
    just released, f = 10^-65 t + t^3 / 3): bisection from the right would halve the interval a
    hundred times to reach it.  None when no such J, K exist."""
    with workprec(f.prec):
        cs = f.values(lo, range(zero_below, zero_below + orders))
        lows = [arb(0)] * zero_below
        fact = math.factorial(zero_below)
        for j, c in enumerate(cs, start=zero_below):
            fact = fact * max(j, 1)
            low = c.lower() / fact
            if j == 0:
                low = max(low, arb(0))
            elif low < 0:
                break
            lows.append(low)
        if not any(l > 0 for l in lows):
            return None
        best = None
        b = hi
        tiny = arb(2) ** -(1 << 20)  # below any step a precision can resolve (MAX_PREC_BITS)
        rounds, shrinks = 0, 0
        while rounds < 3 and shrinks < 64:  # a bound on a shorter interval gives a longer step
            X = arb(lo).union(arb(b))
            bounds = f.values(X, range(1, len(lows) + 1))
            w = None
            fact = 1
            for K in range(1, len(lows) + 1):
                fact *= K
                M = abs(bounds[K - 1]).upper() / fact
                for J in range(K):
                    if lows[J] > 0:
                        s = arb(b - lo) if M == 0 else (lows[J] / M).root(K - J).lower()
                        w = s if w is None or s > w else w
            if w is None:
                return best
            if best is None and w < tiny:
                # the bounds over [lo, b] are useless (a rate of 10^200 over its horizon gives
                # e^(10^6)): shrink b before taking a step, never a dyadic of e^-(10^6)
                b, shrinks = lo + (b - lo) * fmpq(1, 2 ** 64), shrinks + 1
                continue
            rounds += 1
            step = dyadic_lower(w * arb(fmpq(15, 16)))
            if step <= 0:
                return best
            p = min(b, lo + step)
            if p > lo and (best is None or p > best):
                best = p
            if best >= b or step * 8 >= (b - lo):
                break
            b = lo + step * 8
        return best


def _convex_minimum(fn, f: ExpSum, lo: fmpq, hi: fmpq, neg: bool, prec: int, touch):
    """f convex on [lo, hi] with f'(lo) < 0 < f'(hi): decide by the value at the critical point."""
    clo, chi = lo, hi
    for k in range(3 * prec):  # bisection of f' (increasing) down to the precision's resolution
        if k % 64 == 63:
            fn.policy.check_deadline(lambda: f" at the minimum of {fn.describe()} (a tangential touch?)")
        m = (clo + chi) / 2
        s = ball_sign(f.value(m, 1))
        if s == 0:
            break
        if s < 0:
            clo = m
        else:
            chi = m
        v = f.sign_enclose(clo, chi, 0)
        if v > 0:
            return "none" if not neg else "split"
        if f.value(clo) < 0:
            return (lo, clo, True)
        if f.value(chi) < 0:
            return (lo, chi, True)
        if chi - clo < fmpq(1, 2 ** (prec // 2)) * max(1, abs(chi)):
            break
    if touch is not None and not neg:
        proven = touch(clo, chi, lo, hi)
        if proven is True:
            return "none"  # f >= 0: convex with f(t*) = f'(t*) = 0
    # f(t*) cannot be separated from 0 at this precision: splitting cannot help, more bits can
    return "escalate"


class RootReal(Real):
    """theta = inf{t in (lo, hi] : f(t) < 0} for a :class:`Bracket` of ``function``: an exact real.

    Refined by interval Newton when the bracket is simple (f' < 0 on it), else by bisection with
    the crossing invariant; the best rational bracket found is kept (a cache, not a change of
    value).  ``closed_form_finder(root)``, when given, proves a closed form on first access
    (:mod:`lcs_exact.closedforms`, set by the phase that owns the function).
    """

    def __init__(self, function: RootFunction, bracket: Bracket,
                 closed_form_finder: Callable | None = None):
        super().__init__(function.policy)
        self.function = function
        self.lo, self.hi, self.simple = bracket.lo, bracket.hi, bracket.simple
        self._finder = closed_form_finder
        self._proven = None  # (Closed form, Calcium number) once proven
        self._q = None  # the root as an exact rational, when proven so

    def _deps(self):
        return self.function.deps()

    def interval(self) -> tuple[fmpq, fmpq]:
        """The current rational bracket (lo, hi] of the root."""
        return self.lo, self.hi

    def _compute(self, prec: int) -> arb:
        if self._q is not None:
            return arb(self._q)
        # relative to the root's size, read off the end of the bracket nearer to 0 (a bracket
        # (0, 10^98] must be refined to the root near 1.57, not to 10^98 * 2^-prec)
        target = fmpq(1, 2 ** (prec + 2)) * max(1, min(abs(self.lo), abs(self.hi)))
        # the function's ball loses bits to cancellation, and a small f' at the root costs
        # more: evaluated with a margin learnt from this root's earlier calls, the bracket
        # reaches the target here instead of exhausting the precision and being asked again
        # at twice the precision
        f = self.function.at(prec + ROOT_GUARD)
        if self.simple:
            if not self._polish(f, prec, target):
                self._newton(f, prec, target)
        else:
            self._bisect(f, prec, target)
        return arb(self.lo).union(arb(self.hi))

    def _polish(self, f: ExpSum, prec: int, target: fmpq) -> bool:
        """Refine a simple bracket (f' < 0 on it is certified: a fact of the function, whatever
        the precision that showed it) by Newton's method on points, then certify: from the float
        root, or from the midpoint of a bracket already narrow, x <- x - f(x)/f'(x) doubles the
        correct bits at each step; f(x - d) > 0 > f(x + d) with d = target/2 then brackets the
        one root (f decreases).  Three or four evaluations instead of the interval Newton's
        ten to twenty from a wide bracket.  False when the point iteration leaves the bracket or
        the signs at x -+ d are not certified: the interval Newton takes over."""
        lo, hi = self.lo, self.hi
        scale = max(1, abs(hi))
        if hi - lo < scale * fmpq(1, 2 ** 40):
            x = (lo + hi) / 2
            ratio = scale / (hi - lo) if hi > lo else fmpq(2) ** prec  # (no float: it can be 2^3000)
            good = max(1, ratio.p.bit_length() - ratio.q.bit_length() - 1)
        else:
            t = f.guess_root(float(lo), float(hi))
            if t is None:
                return False
            with workprec(64):
                x = dyadic(arb(t))
            good = 40
        with workprec(f.prec):
            while True:
                v, dv = f.values(x, range(2))
                if not dv < 0:
                    return False
                if good >= prec + 8:
                    break
                x = dyadic(arb(x) - v / dv)
                if not lo < x < hi:
                    return False
                good = 2 * good - 4
            # the signs at x -+ d are certified only beyond the resolution of f: the radius of
            # its ball (the start state's accuracy) over |f'|, where the interval Newton stops too
            d = max(target / 2, dyadic_upper(2 * v.rad() / abs(dv).lower()))
        for _ in range(3):
            a, b = x - d, x + d
            if not (lo <= a and b <= hi):
                return False
            fa, fb = f.value(a), f.value(b)
            if fa > 0 and fb < 0:
                self.lo, self.hi = a, b
                return True
            if not (fa.contains(0) or fb.contains(0)):
                return False  # a sign against the guess: the point iteration did not settle
            d = 4 * d
        return False

    def _newton(self, f: ExpSum, prec: int, target: fmpq) -> None:
        """Interval Newton N(X) = m - f(m)/f'(X) on the bracket, kept as rational ends; a
        bisection step where Newton does not contract (a wide bracket), a stop where the
        precision is exhausted."""
        certified = False  # f' < 0 on the bracket; it stays so on every sub-bracket
        for _ in range(64 + 4 * prec.bit_length()):
            if self.hi - self.lo <= target:
                return
            scale = max(1, abs(self.hi))
            narrow = (self.hi - self.lo) < scale * fmpq(1, 2 ** 20)
            X = arb(self.lo).union(arb(self.hi))
            # on a narrow bracket the direct interval value of f' is tight (one evaluation,
            # not a Taylor form's three)
            dX = f.value(X, 1) if narrow else f.enclose(self.lo, self.hi, 1)
            certified = certified or dX < 0
            if not certified:
                if not f.sign_enclose(self.lo, self.hi, 1) < 0:
                    self.simple = False
                    return self._bisect(f, prec, target)
                certified = True
            m = dyadic(X)
            fm = f.value(m)
            if not dX < 0:  # f' < 0 is certified, but this enclosure is too loose: bisect once
                sp = _split_point(f, self.lo, self.hi)
                if sp is None:
                    return
                if sp[1] < 0:
                    self.hi = sp[0]
                else:
                    self.lo = sp[0]
                continue
            N = arb(m) - fm / dX
            lo2, hi2 = max(self.lo, dyadic_lower(N)), min(self.hi, dyadic_upper(N))
            if lo2 > hi2:
                return  # impossible for a valid bracket: keep it
            if hi2 - lo2 <= (self.hi - self.lo) * 3 / 4:
                self.lo, self.hi = lo2, hi2
                continue
            if fm.contains(0):
                # f(m) is below the resolution of f at this precision and N(X) did not contract:
                # the points a split would try lie closer to the root than that resolution
                self.lo, self.hi = lo2, hi2
                return  # the precision is exhausted: the caller raises it
            sp = _split_point(f, lo2, hi2)
            if sp is None:
                self.lo, self.hi = lo2, hi2
                return  # the precision is exhausted: the caller raises it
            if sp[1] < 0:
                self.lo, self.hi = lo2, sp[0]
            else:
                self.lo, self.hi = sp[0], hi2

    def _bisect(self, f: ExpSum, prec: int, target: fmpq) -> None:
        """Bisection keeping "no crossing before lo" (a search on the left part at each step)."""
        while self.hi - self.lo > target:
            self.policy.check_deadline(lambda: f" while refining the root of {self.function.describe()}")
            if f.sign_enclose(self.lo, self.hi, 1) < 0:  # one simple root left: Newton from here
                self.simple = True
                return self._newton(f, prec, target)
            sp = _split_point(f, self.lo, self.hi)
            if sp is None:
                return  # undecidable at this precision: the caller raises the precision
            m, s = sp
            if s < 0:
                self.hi = m
                continue
            br = first_crossing(self.function, self.lo, m, prec)
            if br is None:
                self.lo = m
            else:
                self.lo, self.hi = br.lo, br.hi
                if br.simple:
                    self.simple = True
                    return self._newton(f, prec, target)

    # --- closed forms -------------------------------------------------------------------------
    def _closed(self):
        if self._q is not None:
            return Closed.rational(self._q)
        if self._proven is None and self._finder is not None:
            self._proven = self._finder(self) or False
        return self._proven[0] if self._proven else None

    def to_ca(self):
        if self._q is not None:
            return calcium.Ca(self._q) if calcium.available() else None
        self.closed
        if self._proven and self._proven[1] is None:
            self._proven = (self._proven[0], self._proven[0].to_ca())
        return self._proven[1] if self._proven else None

    def known_rational(self):
        if self._q is not None:
            return self._q
        if self._proven:
            return self._proven[0].to_fmpq()
        return None

    def __getstate__(self):
        state = super().__getstate__()
        if state.get("_proven"):
            state["_proven"] = (state["_proven"][0], None)  # the Calcium number is rebuilt on demand
        return state

    def set_rational(self, q: fmpq) -> None:
        """Record that the root is exactly the rational q (proven by the caller, e.g. as the
        root of an exact polynomial inside the bracket); no SymPy involved."""
        if not self.lo <= q <= self.hi:
            raise LCSError(f"internal inconsistency: the rational root {q} is outside its bracket")
        self._q = q
        self.lo = self.hi = q
        self._ball, self._prec = None, 0  # recomputed as arb(q) at the precision asked

    def set_proven(self, form, ca) -> None:
        """Record a closed form (a :class:`~lcs_exact.forms.Closed`, or a SymPy expression)
        proven by the caller (an exact zero of f in the bracket)."""
        form = form if isinstance(form, Closed) else Closed.of_sympy(form)
        self._proven = (form, ca)
        self._cf, self._cf_done = form, True


def newton_ball(f: ExpSum, X: arb, steps: int = 60) -> arb:
    """Interval Newton X := X n (m - f(m)/f'(X)) on a ball holding one simple root of f (f' != 0
    on X), until it stops contracting: an enclosure of the root (X itself if f' may vanish)."""
    with workprec(f.prec):
        for _ in range(steps):
            d = f.value(X, 1)
            if d.contains(0):
                return X
            m = X.mid()
            N = m - f.value(m) / d
            if not N.overlaps(X):
                return X  # cannot happen when X holds the root; keep the valid enclosure
            Y = N.intersection(X)
            if not Y.rad() < X.rad() * 3 / 4:
                return Y
            X = Y
        return X

"""Exact first crossings of polynomial phases: the events of a piecewise-polynomial motion.

When the closed-loop matrix A_I of a mode is nilpotent (a free fall under gravity, a relay's
piecewise-constant field, a chain of integrators) and the phase starts from an exactly known
state z (rational, or algebraic: a previous event of such a phase), every constraint of the
phase is an exact polynomial f(t) = sum_j g N^j z t^j / j! (:mod:`lcs_exact.phase`).  Its first
crossing theta = inf{t > 0 : f(t) < 0} (Def. 4.3) is then found exactly, never from balls:

* rational coefficients: f is factored over Q; a root of odd multiplicity is a crossing, one of
  even multiplicity a touch (f keeps its sign: no event, proven); the real roots of each
  irreducible factor are exact algebraic numbers (FLINT's ``qqbar``, :func:`calcium.real_roots`),
  compared exactly;
* algebraic coefficients (Calcium numbers) of degree <= 2 after removing the roots at t = 0:
  the linear root, or the quadratic formula with the sign of the discriminant decided exactly
  (zero: a double root, a touch).

So two relays reaching zero together are simultaneous exactly (the roots are equal numbers),
t = 1 is the root of (1 - t)^3 with x(1) exact, and a ball dropped from height h lands at
sqrt(2 h / g), an exact algebraic number from which the next flights stay exact.  Anything else
(algebraic coefficients of degree >= 3 or past :data:`MAX_EXACT_SIZE`, a sign Calcium cannot
decide) returns ``None`` for the
caller's certified numerical search (:mod:`lcs_exact.roots`).
"""
from __future__ import annotations

from typing import Any

from flint import fmpq, fmpq_poly

from ..numbers import calcium
from ..numbers import AlgebraicReal

__all__ = ["ExactCrossing", "exact_first_crossing"]


class ExactCrossing:
    """The answer of :func:`exact_first_crossing`: ``root`` (an :class:`AlgebraicReal`) or None
    when f >= 0 on the whole of (0, horizon] (touches only)."""

    __slots__ = ("root",)

    def __init__(self, root: AlgebraicReal | None):
        self.root = root


def _strip(cs: list, is_zero) -> list | None:
    """Coefficients without the roots at t = 0 (leading zeros of the low end) and without zero
    high-degree terms; None when a zero test is undecided."""
    lo, hi = 0, len(cs)
    while lo < hi:
        z = is_zero(cs[lo])
        if z is None:
            return None
        if not z:
            break
        lo += 1
    while hi > lo:
        z = is_zero(cs[hi - 1])
        if z is None:
            return None
        if not z:
            break
        hi -= 1
    return cs[lo:hi]


def _in_window(r, horizon: fmpq) -> bool | None:
    """0 < r <= horizon, exactly (None: undecided)."""
    s = r.sign(real=True)
    if s is None:
        return None
    if s <= 0:
        return False
    d = (r - calcium.Ca(horizon)).sign(real=True)
    return None if d is None else d <= 0


def _smallest(roots: list):
    """The smallest of exact real Calcium numbers (None if a comparison is undecided)."""
    best = None
    for r in roots:
        if best is None:
            best = r
            continue
        d = (r - best).sign(real=True)
        if d is None:
            return None
        if d < 0:
            best = r
    return best


def _window(roots: list, horizon: fmpq) -> list | None:
    """The roots in (0, horizon] (None when a comparison is undecided)."""
    out = []
    for r in roots:
        inside = _in_window(r, horizon)
        if inside is None:
            return None
        if inside:
            out.append(r)
    return out


def _rational_crossing(p: fmpq_poly, horizon: fmpq) -> list | None:
    """Crossings (odd-multiplicity real roots in (0, horizon]) of a rational polynomial."""
    out = []
    for factor, mult in p.factor()[1]:
        if mult % 2 == 0 or factor.degree() < 1:
            continue  # an even root is a touch: f keeps its sign there
        cs = factor.coeffs()
        if factor.degree() == 1:
            r = -cs[0] / cs[1]
            if 0 < r <= horizon:
                out.append(calcium.Ca(r))
            continue
        inside = _window(calcium.real_roots(cs), horizon)
        if inside is None:
            return None
        out += inside
    return out


#: Largest printed size (characters) of a Calcium coefficient the exact path takes on.  Each exact
#: event of a piecewise-quadratic motion adjoins a square root, so the field of a long run's
#: times is a growing tower; past this size a sign test in it costs seconds (a column of three
#: beads: 0.1 s at 400 characters, 7 s at 1000), and the certified numerical search is faster.
MAX_EXACT_SIZE = 600


def _algebraic_crossing(cs: list, horizon: fmpq) -> list | None:
    """Crossings of a polynomial with Calcium coefficients of degree <= 2 (else None: the
    degree is higher, or a coefficient is past :data:`MAX_EXACT_SIZE`)."""
    cs = [c.compact() for c in cs]
    if any(len(str(c)) > MAX_EXACT_SIZE for c in cs):
        return None
    if len(cs) == 2:
        roots = [-cs[0] / cs[1]]
    elif len(cs) == 3:
        # each step compacted: an expression in the generators of c0, c1, c2 and sqrt(disc) at
        # once is past the degree Calcium's minimal polynomials reach, two at a time is not
        c0, c1, c2 = cs
        disc = ((c1 * c1).compact() - (4 * c2 * c0).compact()).compact()
        s = disc.sign(real=True)
        if s is None:
            return None
        if s <= 0:
            return []  # no real root, or a double root (a touch)
        sq = disc.sqrt().compact()
        den = 2 * c2
        roots = [((-c1 - sq).compact() / den).compact(), ((-c1 + sq).compact() / den).compact()]
    else:
        return None
    return _window(roots, horizon)


def exact_first_crossing(coeffs: list[Any], horizon: fmpq, policy=None) -> ExactCrossing | None:
    """theta = inf{t in (0, horizon] : f(t) < 0} for f = sum coeffs[j] t^j, exactly.

    ``coeffs`` are ``fmpq`` or Calcium numbers, f not identically zero, and f > 0 just after
    t = 0 (the caller's Lemma 5.1 test).  Returns an :class:`ExactCrossing` (its ``root`` None
    when f >= 0 on (0, horizon]), or None when the exact path cannot decide (the caller then
    isolates the root numerically).

    >>> exact_first_crossing([fmpq(1), fmpq(-2)], fmpq(10)).root.closed_form        # 1 - 2t
    1/2
    >>> exact_first_crossing([fmpq(5), fmpq(0), fmpq(-1)], fmpq(10)).root.closed_form  # 5 - t^2
    sqrt(5)
    >>> exact_first_crossing([fmpq(1), fmpq(-2), fmpq(1)], fmpq(10)).root is None     # (1 - t)^2: a touch
    True
    """
    if all(isinstance(c, fmpq) for c in coeffs):
        p = fmpq_poly(list(coeffs))
        while p.degree() > 0 and p[0] == 0:
            p = fmpq_poly(p.coeffs()[1:])
        if p.degree() < 1:
            return ExactCrossing(None)
        roots = _rational_crossing(p, horizon)
    else:
        if not calcium.available():
            return None
        cas = [c if isinstance(c, calcium.Ca) else calcium.Ca(c) for c in coeffs]
        cs = _strip(cas, lambda c: c.is_zero())
        if cs is None:
            return None
        if len(cs) < 2:
            return ExactCrossing(None)
        qs = [c.to_fmpq() for c in cs]
        if all(q is not None for q in qs):
            roots = _rational_crossing(fmpq_poly(qs), horizon)
        else:
            roots = _algebraic_crossing(cs, horizon)
    if roots is None:
        return None
    if not roots:
        return ExactCrossing(None)
    first = _smallest(roots)
    return None if first is None else ExactCrossing(AlgebraicReal(first, policy))

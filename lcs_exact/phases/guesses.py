"""Float guesses that guide the certified root search of :mod:`lcs_exact.roots`: where the first
crossing of an exponential sum probably is (the order and windows of the searches), and a float
root that the certified refinement starts from.  Midpoints of the terms, scalar complex arithmetic
(numpy only for a large grid): heuristics only, never a decision - every result here is checked by
a certified evaluation before it is used, and a wrong guess costs time, not a digit.

The sums are :class:`~lcs_exact.roots.ExpSum` objects (their ``terms``, ``floats()`` and
``float_values``); this module does not import it (imports point down).
"""
from __future__ import annotations

import cmath
import math
from typing import Any

__all__ = ["float_crossing", "float_root", "newton_in_bracket", "MAX_FLOAT_POINTS"]

#: how many float points an estimate of a crossing looks at, at most
MAX_FLOAT_POINTS = 1 << 14


#: a chunk of at most this many (term, point) pairs is evaluated with Python's complex arithmetic
#: (no numpy: a small system's first ``simulate`` does not pay numpy's 50-100 ms import; about
#: 0.25 us a pair, numpy 25 us a call + 10-40 ns a pair), a larger one with numpy.  Same grid,
#: same formula; the values may differ in the last bits (numpy's SIMD complex product can fuse a
#: multiply-add), so the estimate - a grid point - differs only where a value is within rounding
#: of 0: on the fast tests and the chains of up to 32 carts, every estimate is the same
SCALAR_TERM_POINTS = 2048


def float_crossing(f: Any, a: float, b: float, points: int = 64) -> float | None:
    """A float estimate of the first t in (a, b] where f turns negative (None: none seen), from
    the midpoints of the terms on a grid fine enough for the fastest oscillation (8 points a
    radian), scanned in chunks from a so that an early crossing costs one chunk however long
    the horizon.  A heuristic for the order and windows of the certified searches only: never a
    decision."""
    lam, w, cs = _scalar_floats(f)
    if not lam or not b > a:
        return None
    omega = max(abs(l.imag) for l in lam)
    step = (b - a) / points if omega * (b - a) < points / 8 else 1 / (8 * omega)
    chunk = 256
    lo, b = a, min(b, a + MAX_FLOAT_POINTS * step)  # a long horizon: the estimate looks ahead only so far
    while lo < b:
        hi = min(b, lo + chunk * step)
        n = max(1, int(round((hi - lo) / step)))
        found = _scalar_chunk(lam, w, cs, lo, hi, n) if len(lam) * n <= SCALAR_TERM_POINTS else None
        if found is None:  # a large chunk, or a float overflow: numpy (inf and nan as before)
            found = _numpy_chunk(f, lo, hi, n)
        if found != "none":
            return found
        lo = hi
    return None


def _scalar_floats(f: Any) -> tuple[list, list, list]:
    """The midpoints of f's terms as Python numbers, (lambda, weight, coefficients padded with
    zeros to one length), cached on f: the values of ``f.floats()`` without numpy."""
    d = f.__dict__
    if "_scalar_floats" not in d:
        deg = max((len(cs) for _, _, cs in f.terms), default=1)
        d["_scalar_floats"] = ([complex(l) for l, _, _ in f.terms], [float(wt) for _, wt, _ in f.terms],
                               [[complex(c) for c in cs] + [0j] * (deg - len(cs)) for _, _, cs in f.terms])
    return d["_scalar_floats"]


def _scalar_chunk(lam: list, w: list, cs: list, lo: float, hi: float, n: int) -> float | str | None:
    """The first of the points ``numpy.linspace(lo, hi, n + 1)[1:]`` where f < 0 ("none": f >= 0
    at all of them; None: a value overflowed, the caller asks numpy), with the float operations
    of ``ExpSum.float_values`` in its order: e^{lambda t} (P(t) by Horner from zero), the real
    parts times the weights summed from 0.0 term by term; it stops at the first negative value."""
    delta = hi - lo
    step = delta / n
    rows = list(zip(lam, w, [row[::-1] for row in cs]))
    exp = cmath.exp
    for i in range(1, n + 1):
        # numpy.linspace: i * step + lo, i * (delta / n) when step underflows; the last point is hi
        t = hi if i == n else (i * step + lo if step != 0 else i / n * delta + lo)
        v = 0.0
        try:
            for l, wt, row in rows:
                p = 0j
                for c in row:
                    p = p * t + c
                v += (exp(l * t) * p).real * wt
        except OverflowError:
            return None
        if not math.isfinite(v):
            return None
        if v < 0:
            return t
    return "none"


def _numpy_chunk(f: Any, lo: float, hi: float, n: int) -> float | str | None:
    """As :func:`_scalar_chunk` with numpy arrays (any size, inf and nan included): the first
    point where f < 0 (None when that value is not finite), else "none", or None when some value
    is not finite."""
    import numpy as np
    t = np.linspace(lo, hi, n + 1)[1:]
    vals = f.float_values(t)
    neg = np.nonzero(vals < 0)[0]
    if len(neg):
        return float(t[neg[0]]) if np.isfinite(vals[neg[0]]) else None
    if not np.all(np.isfinite(vals)):
        return None
    return "none"


def float_root(f: Any, lo: float, hi: float) -> float | None:
    """A float root of f in (lo, hi), where f decreases (a simple bracket), by Newton's method
    safeguarded by bisection (a step leaving the bracket of float signs bisects it): a guess
    that the certified refinement then checks (None when the floats overflow)."""
    terms = [(complex(l), float(wt), [complex(c) for c in cs]) for l, wt, cs in f.terms]

    def f_df(t: float) -> tuple[float, float]:
        v = dv = 0.0
        for l, wt, row in terms:  # scalar complex arithmetic: cheaper than numpy on one point
            p = dp = 0j
            for c in reversed(row):
                dp = dp * t + p
                p = p * t + c
            e = cmath.exp(l * t)
            v += wt * (e * p).real
            dv += wt * (e * (l * p + dp)).real
        return v, dv

    return newton_in_bracket(f_df, lo, hi)


def newton_in_bracket(f_df: Any, lo: float, hi: float, iterations: int = 200) -> float | None:
    """A float root in (lo, hi) of a function that decreases there, given as ``f_df(t) -> (f,
    f')``: Newton's method, a step leaving the bracket of float signs bisecting it instead (None
    when the floats overflow or are not finite).  A guess only: checked before use."""
    a, b = lo, hi
    t = (a + b) / 2
    for _ in range(iterations):
        try:
            v, dv = f_df(t)
        except OverflowError:
            return None
        if not (math.isfinite(v) and math.isfinite(dv)):
            return None
        if v > 0:
            a = t
        elif v < 0:
            b = t
        else:
            return t
        step = v / dv if dv < 0 else math.inf
        if abs(step) <= 4e-16 * max(1.0, abs(t)):
            return t - step  # settled (the float sign of f here is noise: checked before use)
        nt = t - step
        if not a < nt < b:  # outside the float bracket: bisect
            nt = (a + b) / 2
            if not a < nt < b:
                return t
        t = nt
    return t

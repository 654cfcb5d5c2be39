"""Float guesses that guide the certified root search of :mod:`lcs_exact.roots`: where the first
crossing of an exponential sum probably is (the order and windows of the searches), and a float
root that the certified refinement starts from.  Midpoints of the terms, numpy or scalar complex
arithmetic: heuristics only, never a decision - every result here is checked by a certified
evaluation before it is used, and a wrong guess costs time, not a digit.

The sums are :class:`~lcs_exact.roots.ExpSum` objects (their ``terms``, ``floats()`` and
``float_values``); this module does not import it (imports point down).
"""
from __future__ import annotations

import cmath
import math
from typing import Any

__all__ = ["float_crossing", "float_root", "MAX_FLOAT_POINTS"]

#: how many float points an estimate of a crossing looks at, at most
MAX_FLOAT_POINTS = 1 << 14


def float_crossing(f: Any, a: float, b: float, points: int = 64) -> float | None:
    """A float estimate of the first t in (a, b] where f turns negative (None: none seen), from
    the midpoints of the terms on a grid fine enough for the fastest oscillation (8 points a
    radian), scanned in chunks from a so that an early crossing costs one chunk however long
    the horizon.  A heuristic for the order and windows of the certified searches only: never a
    decision."""
    import numpy as np
    lam, _, _ = f.floats()
    if not len(lam) or not b > a:
        return None
    omega = float(np.max(np.abs(lam.imag)))
    step = (b - a) / points if omega * (b - a) < points / 8 else 1 / (8 * omega)
    chunk = 256
    lo, b = a, min(b, a + MAX_FLOAT_POINTS * step)  # a long horizon: the estimate looks ahead only so far
    while lo < b:
        hi = min(b, lo + chunk * step)
        n = max(1, int(round((hi - lo) / step)))
        t = np.linspace(lo, hi, n + 1)[1:]
        vals = f.float_values(t)
        neg = np.nonzero(vals < 0)[0]
        if len(neg):
            return float(t[neg[0]]) if np.isfinite(vals[neg[0]]) else None
        if not np.all(np.isfinite(vals)):
            return None
        lo = hi
    return None


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

    a, b = lo, hi
    t = (a + b) / 2
    for _ in range(200):
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

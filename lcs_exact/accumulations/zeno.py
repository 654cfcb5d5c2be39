"""Suspected right-accumulations (Remark 4.11) that nothing proves: the last phases shrink
geometrically with the limit of their sum before t_end.  Neither a law (:mod:`lcs_exact.accumulation`)
nor a cascade proof (:mod:`lcs_exact.cascade`) applies, so the run stops with
:class:`~lcs_exact.errors.ZenoDetected`: a certified lower bound (the last event) and an estimate,
printed with the digits its window's ratios agree on (it is no bound)."""
from __future__ import annotations

import math

from flint import arb

from ..numbers import dyadic_lower
from ..errors import ZenoDetected

__all__ = ["ZENO_WINDOW", "check_accumulation", "shrinking_cycles"]

#: phases in the window of a suspected accumulation (:func:`check_accumulation`)
ZENO_WINDOW = 24


def check_accumulation(durations: list, t_now, t_end) -> None:
    """Right-Zeno (Remark 4.11): raise :class:`ZenoDetected` when the last phases shrink
    geometrically (ratio < 0.95 over a window of 24) with the limit of their sum before t_end."""
    if len(durations) < ZENO_WINDOW:
        return
    balls = [d.arb(64) for d in durations[-ZENO_WINDOW:]]
    ratios = []
    for a, b in zip(balls, balls[1:]):
        if not (a > 0 and b > 0):
            return
        ratios.append(b / a)
    rho = max(ratios, key=lambda r: r.mid())
    if not all(r < arb("0.95") for r in ratios):
        return
    tail = balls[-1] * rho / (1 - rho)
    limit = t_now.arb(64) + tail
    if limit < t_end.arb(64):  # suspected, not proven: lower = the last event (certified), upper None
        # the geometric tails with the smallest and the largest ratio of the window: their spread
        # says how many digits of the estimate mean anything (it is no bound: nothing is proven)
        low = min(ratios, key=lambda r: r.mid())
        spread = abs(float((tail - balls[-1] * low / (1 - low)).mid()))
        raise ZenoDetected(f"event times accumulate: {ZENO_WINDOW} phases shrinking geometrically (ratio <= "
                           f"{float(rho.mid()):.3g}); accumulation point near t = {_estimate(float(limit.mid()), spread)} "
                           "< t_end (Remark 4.11; an estimate, not a bound)", lower=dyadic_lower(t_now.arb(64)),
                           upper=None, estimate=float(limit.mid()))


def shrinking_cycles(durations: list) -> bool:
    """The last phases shrink cycle by cycle (a suspected accumulation, for a decision that failed
    right after them): for some period p <= 8, the last p phases are each less than half the one p
    before, or the last ZENO_WINDOW phases are each less than 0.95 times the one p before (two
    contacts taking turns shrink by pairs, not phase by phase)."""
    d = [x.arb(64) for x in durations[-(ZENO_WINDOW + 8):]]
    if any(not x > 0 for x in d):
        return False
    half = any(len(d) >= 2 * p and all(d[-j] * 2 < d[-j - p] for j in range(1, p + 1)) for p in range(2, 9))
    return half or any(len(d) >= ZENO_WINDOW + p and all(d[-j] < arb("0.95") * d[-j - p] for j in range(1, ZENO_WINDOW + 1))
                       for p in range(1, 9))


def _estimate(x: float, spread: float) -> str:
    """x with the digits its spread leaves meaningful (two more than the spread's leading digit,
    at least 2 and at most 15 significant digits).

    >>> _estimate(0.87791234567, 7.6e-3), _estimate(0.87791234567, 0.0)
    ('0.878', '0.87791234567')
    """
    if spread <= 0 or x == 0:
        return f"{x:.15g}"
    digits = max(2, min(15, int(math.floor(math.log10(abs(x)))) - int(math.floor(math.log10(spread))) + 1))
    return f"{x:.{digits}g}"

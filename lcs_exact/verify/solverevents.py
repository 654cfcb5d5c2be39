"""Events in a numerical solver's data: the windows a comparison leaves out, and the solver's
switch times (:func:`lcs_exact.compare`).

At an event τ the exact solution has a first discontinuous derivative of some order j: j = 0 at
a jump (an impact), j = 1 when x' jumps (u jumps), higher at a smooth lift-off.  It is computed
exactly from the reference: d_j = A_{I+}^j x(τ+) - A_{I-}^j x(τ-) with A_I the closed-loop matrix
of mode I (x' = A_I x on a phase of mode I, section 4.1), the first j with d_j != 0 certified
(:func:`derivative_jump`).  In the solver's data the switch is where the j-th divided difference of
the signal d_j . x changes most (:func:`switch_time`); its time is the middle of that stencil.

A time-stepper resolves an event within a step or so, and its event times drift by a few steps
over a run of impacts: between the exact and the solver's event time the state error is O(1)
and says nothing about the method's order.  So :func:`event_windows` leaves out [τ - w, τ + w]
around every event, those an accumulation implies included (Remark 4.11: the k-th implied event
repeats the reference cycle's event k mod p, scaled), widened to cover the solver's own switch for
it; the event's time error is reported instead.  The windows only choose which of the solver's
points are compared: they decide no sign of an exact quantity, so floats are enough here.
"""
from __future__ import annotations

import bisect
import math
from typing import Any, Sequence

from flint import arb, arb_mat, ctx, fmpq_mat

from ..errors import LCSError
from ..system import LCS

__all__ = ["SEARCH_STEPS", "implied_events", "event_windows", "reference_cycle", "in_windows", "derivative_jump",
           "closed_loop", "signature", "switch_time"]

_PREC = 128  # bits for the jump of the derivatives at an event

#: a solver's switch for an event is searched up to this many of its largest steps from the exact
#: time (and no farther than halfway to the neighbouring events): a first-order method's event
#: times drift by a few steps over a run of impacts
SEARCH_STEPS = 25


def implied_events(acc: Any, w: float) -> tuple[list, float] | None:
    """The event times (floats) an accumulation implies before its time T*, as many as fit
    apart from one another: up to the first one within max(2w, float resolution) of T*, after
    which every window touches the next and together they cover [that event - w, T* + w]; and
    T* as a float.  None when the accumulation carries no law."""
    if getattr(acc, "cycle", None) is None and getattr(acc, "law", None) is None and getattr(acc, "implied", None) is None:
        return None  # a live Accumulation carries its law as ``cycle``, a fixture's as ``law``
    t_star = float(_mid(acc.time))
    resolution = max(2 * w, 2.0 ** -50 * max(1.0, abs(t_star)))
    at = getattr(acc, "event_time_ball", acc.event_time)  # a live law's balls: its exact times cost more
    out = []
    for k in range(100_000):
        tk = float(_mid(at(k)))
        out.append(tk)
        if t_star - tk <= resolution:
            break
    return out, t_star


def _mid(x: Any) -> arb:
    return x.ball(20).mid() if hasattr(x, "ball") else x.mid()


def event_windows(events: list, signatures: list, accumulations: Sequence, tf: list, Xf: list, w: float,
                   reach: float) -> tuple[list, list]:
    """(windows, switches): the merged intervals left out of the comparison and, per listed
    event, the solver's switch time (or None).

    Every event is windowed by [τ - w, τ + w], those an accumulation implies included (its law:
    the k-th implied event repeats the reference cycle's event k mod p, whose order and jump
    direction are used to find the solver's switch; from the first one that no longer fits, the
    window is [that event - w, T* + w]).  The window of an event also covers the solver's own
    switch, searched within ``reach`` of τ and halfway to the neighbouring events: a solver whose
    event time is off by more than w is measured by its time error, not by an O(1) state error
    between the two times."""
    todo = [(float(ev[0].mid()), sig, j) for j, (ev, sig) in enumerate(zip(events, signatures))]
    spans = []
    for acc in accumulations:
        implied = implied_events(acc, w)
        if implied is None:  # no law: the accumulation time itself
            t_star = float(_mid(acc.time))
            spans.append((t_star - w, t_star + w))
            continue
        times, t_star = implied
        first, period = reference_cycle(acc)
        for k, tk in enumerate(times[:-1]):
            r = None if first is None else first + k % period
            sig = signatures[r] if r is not None and r < len(signatures) else None
            # the implied event's jump is the reference event's, scaled down by the law: no floor
            todo.append((tk, None if sig is None else (sig[0], sig[1], 0.0), None))
        spans.append((times[-1] - w, t_star + w))
    todo.sort(key=lambda e: e[0])
    switches = [None] * len(events)
    for i, (tau, sig, j) in enumerate(todo):
        lo = max(tau - reach, (todo[i - 1][0] + tau) / 2 if i else -math.inf)
        hi = min(tau + reach, (tau + todo[i + 1][0]) / 2 if i + 1 < len(todo) else math.inf)
        covered = bool(tf) and tf[0] <= tau <= tf[-1]  # the solver's data holds the event
        found = None if sig is None or not covered else switch_time(tf, Xf, sig, min(lo, tau - w), max(hi, tau + w))
        if j is not None:
            switches[j] = found
        at = tau if found is None else found
        spans.append((min(tau, at) - w, max(tau, at) + w))
    spans.sort()
    merged: list = []
    for lo, hi in spans:
        if merged and lo <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], hi))
        else:
            merged.append((lo, hi))
    return merged, switches


def reference_cycle(acc: Any) -> tuple[int | None, int]:
    """(index of the reference cycle's first event in the events, its length p)."""
    law, implied = getattr(acc, "law", None), getattr(acc, "implied", None)
    if isinstance(law, dict):
        return law.get("first_event"), len(law["offsets"])
    if isinstance(implied, dict):  # a fixture's law-less accumulation: each implied event repeats one
        return implied.get("first_event"), 1
    return acc.first_event, len(acc.offsets) or 1


def in_windows(tf: list, windows: list) -> list:
    """Whether each time lies in one of the (sorted, disjoint) windows."""
    starts = [lo for lo, _ in windows]
    out = []
    for t in tf:
        j = bisect.bisect_right(starts, t) - 1
        out.append(j >= 0 and t <= windows[j][1])
    return out


def derivative_jump(lcs: LCS, mb, ma, xb: tuple, xa: tuple, after: LCS | None = None) -> tuple:
    """(j, d_j): the first order whose derivative jumps at the event, certified, and its jump
    d_j = A_{I+}^j x+ - A_{I-}^j x-; (None, None) when no jump up to order n is certified.
    ``lcs`` is the system in force before the event, ``after`` the one after it (a schedule's
    switch changes it; default the same)."""
    try:
        Ab, Aa = arb_mat(closed_loop(lcs, mb)), arb_mat(closed_loop(after or lcs, ma))
    except LCSError:  # a mode that is not autonomous has no flow to compare with
        return None, None
    with ctx.workprec(_PREC):
        vb = arb_mat([[c] for c in xb])
        va = arb_mat([[c] for c in xa])
        for j in range(lcs.n + 1):
            d = [va[i, 0] - vb[i, 0] for i in range(lcs.n)]
            if any(not c.contains(0) for c in d):
                return j, d
            vb, va = Ab * vb, Aa * va
    return None, None


def closed_loop(lcs: LCS, I: frozenset) -> fmpq_mat:
    """A_I = A + B_{.I} F_I: x' = A_I x on a phase of mode I (section 4.1); F_I's rows follow
    the indices of I in increasing order."""
    A = fmpq_mat(lcs.A)
    if not I:
        return A
    F = lcs.mode(I).feedback()
    for r, i in enumerate(sorted(I)):
        for a in range(lcs.n):
            if lcs.B[a, i] != 0:
                for b in range(lcs.n):
                    A[a, b] += lcs.B[a, i] * F[r, b]
    return A


def signature(ev: tuple, lcs: LCS, comps: tuple) -> tuple | None:
    """(order, direction) of an event in the solver's data: the order j of the first derivative
    that jumps and the jump d_j normalised on the compared components (zero elsewhere), or None
    (the start, no certified jump, or a jump only in components the solver did not give)."""
    tau_b, mb, ma, xb, xa, cf = ev
    if mb is None:
        return None
    before, after = lcs, lcs
    schedule = getattr(lcs, "schedule", None)
    if schedule is not None:  # the systems in force on either side (a switch changes them)
        tau, eps = float(tau_b.mid()), 1e-9 * (1 + abs(float(tau_b.mid())))
        before, after = schedule.system_at(tau - eps), schedule.system_at(tau + eps)
    order, d = derivative_jump(before, mb, ma, xb, xa, after)
    if order is None:
        return None
    scale = max(abs(float(d[c].mid())) for c in comps)
    if scale == 0:
        return None
    dirv = [float(c.mid()) / scale if i in comps else 0.0 for i, c in enumerate(d)]
    return order, dirv, sum(v * float(c.mid()) for v, c in zip(dirv, d))  # the jump of dirv . x^(order)


def switch_time(tf: list, Xf: list, sig: tuple, a: float, b: float) -> float | None:
    """The middle of the stencil where the order-th divided difference of dirv . x changes most,
    among stencils centred within [a, b]; None when that change is below a quarter of the exact
    jump (the solver shows no such event there)."""
    order, dirv, size = sig
    i0, i1 = bisect.bisect_left(tf, a), bisect.bisect_right(tf, b)
    if i0 >= i1:
        return None
    lo, hi = max(0, i0 - order - 1), min(len(tf), i1 + order + 1)
    ts = tf[lo:hi]
    ss = [sum(x * y for x, y in zip(dirv, r)) for r in Xf[lo:hi]]
    if order >= 1:  # divided differences need distinct times: keep the last row of a repeated time
        keep = [i for i in range(len(ts)) if i + 1 == len(ts) or ts[i + 1] != ts[i]]
        ts, ss = [ts[i] for i in keep], [ss[i] for i in keep]
    D = ss
    for k in range(1, order + 1):
        D = [(D[i + 1] - D[i]) / (ts[i + k] - ts[i]) for i in range(len(D) - 1)]
    best = None
    for i in range(1, len(D)):
        loc = (ts[i - 1] + ts[i + order]) / 2
        if not a <= loc <= b:
            continue
        change = abs(D[i] - D[i - 1])
        if best is None or change > best[0]:
            best = (change, loc)
    return None if best is None or best[0] < abs(size) / 4 else best[1]

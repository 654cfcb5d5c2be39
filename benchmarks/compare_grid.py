"""Minimal comparison of another solver's sampled solution with a certified trajectory, on a
common uniform grid. (A full `lcs_exact.compare` is being built for issue 9; this file only
needs the public `traj.state(t)` and `Event.time`, and can be swapped for it when it lands.)

The reference values are the midpoints of `traj.state(t)` balls at 20 digits, so the
reference's own error (< 1e-19 relative) is far below any float solver's.
"""
from __future__ import annotations

import math
from fractions import Fraction


def grid_step(T: Fraction) -> Fraction:
    """About 200 grid intervals, the step a multiple of 1/100 (so of every Siconos step h)."""
    return Fraction(math.ceil(Fraction(T) / 2), 100)


def reference(traj, T, dt) -> dict:
    """Certified states on the grid 0, dt, 2 dt, ... <= T and the event times, as floats."""
    ts = [i * dt for i in range(int(Fraction(T) / dt) + 1)]
    xs = []
    for t in ts:
        xs.append([float(c.ball(20).mid()) for c in traj.state(t)])
    return {"t": [float(t) for t in ts], "dt": float(dt), "x": xs,
            "events": [float(e.time.ball(20).mid()) for e in traj.events]}


def errors(ref: dict, ts, xs, switch_times, window: float) -> dict:
    """state_err: max |x - x_exact| over grid points farther than `window` from every exact
    event; event_err: max over exact events of the distance to the nearest switch time
    (inf when the method reports none, NaN when the run has no event)."""
    ev = ref["events"]
    dt = ref["dt"]
    worst, used = 0.0, 0
    for t, x in zip(ts, xs):
        i = round(t / dt)
        if i >= len(ref["t"]) or abs(ref["t"][i] - t) > 1e-9 * max(1.0, t):
            continue
        if any(abs(t - e) <= window for e in ev):
            continue
        d = max(abs(a - b) for a, b in zip(x, ref["x"][i]))
        if math.isnan(d):
            d = math.inf
        worst = max(worst, d)
        used += 1
    if not ev:
        event_err = math.nan
    elif not switch_times:
        event_err = math.inf
    else:
        s = sorted(switch_times)
        event_err = max(min(abs(e - x) for x in s) for e in ev)
    return {"state_err": worst if used else math.nan, "event_err": event_err, "grid_points": used}

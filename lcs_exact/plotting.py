"""Figures: a trajectory (states, u, y against t) and a 2-D mode map (Figure 8.2 style).

matplotlib and numpy are imported inside the functions, so ``import lcs_exact`` stays light.
This module sits below :mod:`lcs_exact.trajectory` and never imports it: a trajectory is used
through its public interface only (``lcs``, ``x0``, ``t_end``, ``events``, ``partial``,
``state(t)``, ``u(t)``, ``y(t)``; an event's ``time``, ``mode_before``, ``mode_after``,
``state_before``, ``state_after``, ``impulse``), and a mode map through ``faces``,
``hyperplanes``, ``regions``, ``locate`` and ``slice_jump``.

What a reader needs to see, and how it is drawn:

* jumps are discontinuities: each continuous phase is its own line (no segment joins x(τ-) to
  x(τ+)); at a jump an open circle marks x(τ-) and a filled one x(τ+) (the trajectory is
  right-continuous); a component is drawn as jumping only when its two values are certainly
  different (disjoint balls); the same for u and y, which jump where the mode changes (their
  values at the phase ends are exact: u = F_I x, y = C x + D u with the phase's F_I);
* an impulse u^0 δ (3.6) is a dotted arrow whose height grows with its weight (written next to
  it when there are few), never a segment that reads as part of u;
* events are dashed vertical lines labelled with the mode change (``∅→{0}``, ``start→{1}`` at
  t = 0, ``∅→∅ via {0}`` for an impact with immediate lift-off), on up to four lines so that
  close events do not overwrite each other; each phase is shaded with the colour of its mode
  (read from the events: the ``mode_before`` of the event that ends it, else the last
  ``mode_after``);
* names come from ``lcs.state_names`` / ``lcs.constraint_names``; legends sit outside the data
  (in columns when long); a partial run is drawn up to where it stopped, marked;
* sampling is cheap (``traj.sample``: one exponential sum per point), so 800 points by default.

Numbers are evaluated exactly (certified balls) and only then rounded to floats for drawing.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

from flint import fmpq

from .errors import InvalidArgument, LCSError
from .modes import format_mode

__all__ = ["plot_trajectory", "plot_mode_map", "phase_intervals", "PhaseInterval"]

_MODE_COLORS = ["#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860", "#da8bc3",
                "#8c8c8c", "#ccb974", "#64b5cd"]


def _is_default(names: Sequence[str], prefix: str) -> bool:
    return tuple(names) == tuple(f"{prefix}{i}" for i in range(len(names)))


def _pair_label(lcs, which: str, i: int) -> str:
    roles = getattr(lcs, "roles", None)
    if roles is not None:  # the builder's words: "force (floor)", "i(D1)"
        return roles[i][0 if which == "u" else 1]
    names = getattr(lcs, "constraint_names", None) or tuple(str(j) for j in range(lcs.k))
    if _is_default(names, ""):
        return f"${which}_{{{i}}}$"
    return f"{which} ({names[i]})"


def _mode_label(lcs, m, free=frozenset()) -> str:
    """The legend text of a mode: the builder's words when it gave roles (a long text is cut);
    ``free``: inputs left undetermined on its phases."""
    if m is None:
        return "mode ?"
    if getattr(lcs, "roles", None) is None or not hasattr(lcs, "describe_mode"):
        return f"mode {format_mode(m)}" + (f" ({format_mode(free)} undetermined)" if free else "")
    text = lcs.describe_mode(m, free)
    return text if len(text) <= 48 else f"mode {format_mode(m)}: " + text[:40] + "…"


def _state_label(lcs, i: int) -> str:
    names = getattr(lcs, "state_names", None) or tuple(f"x_{j}" for j in range(lcs.n))
    nm = names[i]
    if _is_default(names, "x_"):
        return f"$x_{{{i}}}$"
    return nm


def _certainly_different(a, b, digits: int = 20) -> bool:
    """True iff the two exact reals are proven different (their balls are disjoint)."""
    try:
        return not a.ball(digits).overlaps(b.ball(digits))
    except AttributeError:  # anything without balls: compare floats (display only)
        return float(a) != float(b)


def _frac(x: float) -> Fraction:
    return Fraction(x)


@dataclass(frozen=True)
class PhaseInterval:
    """A continuous phase read from the events: [start, end] in ``mode``; the events (or None)
    at its two ends give the exact states x(start+) and x(end-)."""

    start: Any
    end: Any
    mode: frozenset | None
    start_event: Any
    end_event: Any
    window: Any = None  # an accumulation window (accumulation.ScaledCycle): infinitely many events


def _positive(t) -> bool:
    if hasattr(t, "ball"):
        return bool(t.ball(30) > 0)
    return t > 0


def phase_intervals(traj) -> list[PhaseInterval]:
    """The continuous phases of a trajectory, derived from its events alone.

    A phase ending at an event (time > 0) runs in that event's ``mode_before``; the last phase
    runs in the last event's ``mode_after``; with no event at all, in the smallest mode of
    S(x0) (Remark 4.8).  Phases of zero length are dropped; a partial trajectory ends at its
    ``t_last``, the last time it covers (the phase after its last event was computed too, up to
    where the run stopped).

    >>> from lcs_exact import simulate
    >>> from lcs_exact.examples import two_carts
    >>> tr = simulate(two_carts(), [0, -1, 0, 0], 2)   # Example 4.4: the stop releases at t = pi/2
    >>> [(float(p.start), float(p.end), sorted(p.mode)) for p in phase_intervals(tr)]
    [(0.0, 1.5707963267948966, [0]), (1.5707963267948966, 2.0, [])]
    """
    evs = sorted(traj.events, key=lambda e: float(e.time))
    at_zero = [e for e in evs if not _positive(e.time)]
    inner = [e for e in evs if _positive(e.time)]
    end: Any = traj.t_end
    end_event = None
    if getattr(traj, "partial", False):
        if getattr(traj, "t_last", None) is not None:
            end = traj.t_last
        elif not inner:
            return []
        else:  # a trajectory-like object without t_last: up to its last event
            end, end_event = inner[-1].time, inner[-1]
            inner = inner[:-1]
    out = []
    start, start_event = 0, (at_zero[-1] if at_zero else None)
    for e in inner:
        if float(e.time) > float(start):
            out.append(PhaseInterval(start, e.time, e.mode_before, start_event, e))
        start, start_event = e.time, e
    if end_event is not None:
        mode = end_event.mode_before
    elif evs:
        mode = evs[-1].mode_after
    else:
        S = traj.lcs.select_modes(traj.x0)
        mode = min(S, key=lambda m: (len(m), sorted(m))) if S else None
    if float(end) > float(start):
        out.append(PhaseInterval(start, end, mode, start_event, end_event))
    return _split_at_accumulations(traj, out)


def _split_at_accumulations(traj, intervals: list) -> list:
    """Each accumulation point T* crossed (``traj.accumulations``) splits its interval: the window
    [t_k, T*) of infinitely many events, then the phase after T* in its own mode (read from the
    trajectory's phases when it has them)."""
    accs = [a for a in (getattr(traj, "accumulations", ()) or ()) if hasattr(a, "time")]
    if not accs:
        return intervals
    windows = {}
    for rec in getattr(traj, "phases", ()) or ():
        if hasattr(rec.phase, "offsets"):
            windows[float(rec.t1)] = rec
    out = []
    for ph in intervals:
        inside = [a for a in accs if float(ph.start) < float(a.time) < float(ph.end) or
                  (float(a.time) == float(ph.end) and float(a.time) > float(ph.start))]
        if not inside:
            out.append(ph)
            continue
        a = inside[0]
        rec = windows.get(float(a.time))
        out.append(PhaseInterval(ph.start, a.time, ph.mode, ph.start_event, None,
                                 rec.phase if rec is not None else None))
        if float(ph.end) > float(a.time):
            after = _mode_after(traj, a)
            out.append(PhaseInterval(a.time, ph.end, after, None, ph.end_event))
    return out


def _mode_after(traj, acc):
    """The mode of the phase that starts at the accumulation time (S(x(T*)) otherwise)."""
    for rec in getattr(traj, "phases", ()) or ():
        if not hasattr(rec.phase, "offsets") and abs(float(rec.t0) - float(acc.time)) == 0:
            return rec.mode
    S = traj.lcs.select_modes(acc.state)
    return min(S, key=lambda m: (len(m), sorted(m))) if S else None


def _component(v, i: int) -> tuple[float, bool]:
    """(float value, certainly nonzero) of entry i of an exact vector or an n x 1 fmpq_mat."""
    if hasattr(v, "nrows"):
        q = v[i, 0]
        return float(Fraction(int(q.p), int(q.q))), q != 0
    c = v[i]
    return float(c), not c.ball(20).contains(0)


def _pair_maps(lcs, mode):
    """(F_u, F_y) with u = F_u x, y = F_y x on a phase of ``mode``: u_I = F_I x, zero off I
    (section 4.1), y = C x + D u.  None for an unknown mode (a deadlock at the start)."""
    from flint import fmpq_mat
    if mode is None:
        return None
    Fu = fmpq_mat(lcs.k, lcs.n)
    if mode:
        F = lcs.mode(mode).feedback()  # rows follow the indices of I in increasing order
        for r, i in enumerate(sorted(mode)):
            for j in range(lcs.n):
                Fu[i, j] = F[r, j]
    return Fu, lcs.C + lcs.D * Fu


def _draw_window(traj, ph, ax_of, sidx, cidx, cyc, sty, npts: int) -> None:
    """An accumulation window [t_k, T*): the scaled cycles of the proven law, each flight its own
    line (no segment across an event), until the flights are shorter than the plot resolves;
    states, u and y are the exact values of the law (``traj.state``, ``traj.u``, ``traj.y``)."""
    fa, fb = float(ph.start), float(ph.end)
    width = fb - fa
    cuts = [fa]
    for t in ph.window.event_times(400):
        ft = float(t)
        if ft >= fb or ft - cuts[-1] < width * 5e-3:
            break
        cuts.append(ft)
    cuts.append(fb)
    for a, b in zip(cuts, cuts[1:]):
        m = max(3, int(npts * (b - a) / width))
        ts = [_frac(a + (b - a) * (j + 0.5) / m) for j in range(m)]
        tt = [float(t) for t in ts]
        if "x" in ax_of:
            rows = [[float(v.mid()) for v in row] for row in traj.sample(ts, 10)]
            for pos, i in enumerate(sidx):
                ax_of["x"].plot(tt, [r[i] for r in rows], color=cyc[pos], ls=sty[pos], lw=1.6)
        for which in ("u", "y"):
            if which in ax_of:
                vals = [[float(c) for c in getattr(traj, which)(t)] for t in ts]
                for pos, i in enumerate(cidx):
                    ax_of[which].plot(tt, [v[i] for v in vals], color=cyc[pos], ls=sty[pos], lw=1.6)


def _undetermined(traj, ph) -> frozenset:
    """The inputs left free by the state on the phase interval ``ph`` (a floating network)."""
    if not hasattr(traj, "undetermined"):
        return frozenset()
    try:
        return traj.undetermined(_frac((float(ph.start) + float(ph.end)) / 2))
    except LCSError:
        return frozenset()


def _apply(F, rows: list, zero: Sequence[int] = ()) -> list[list[float]]:
    """F x for every sampled state x (a row of balls), in ball arithmetic, as floats to draw;
    the entries in ``zero`` are exactly 0 (y_i for i in the phase's mode: y_I = 0 there, (4.2))."""
    from flint import arb, ctx
    m, n = F.nrows(), F.ncols()
    coef = [[(j, arb(F[i, j])) for j in range(n) if F[i, j] != 0] if i not in zero else [] for i in range(m)]
    out = []
    with ctx.workprec(128):
        for x in rows:
            out.append([float(sum((c * x[j] for j, c in coef[i]), arb(0)).mid()) if coef[i] else 0.0
                        for i in range(m)])
    return out


#: line styles after the 10 colours of the default cycle are used up (q_0 and q_10 must differ)
_STYLES = ("-", "--", ":", "-.")


def _event_text(e) -> str:
    """``∅→{0}``; ``start→{1}`` at t = 0; ``∅→∅ via {0}`` when the state jumped through modes
    other than the one entered (an impact followed by lift-off, a chain (4.9))."""
    before = "start" if e.mode_before is None else format_mode(e.mode_before)
    text = f"{before}→{format_mode(e.mode_after)}"
    chain = tuple(getattr(e, "modes", ()) or ())
    if chain and (len(chain) > 1 or chain[-1] != e.mode_after):
        text += " via " + ", ".join(format_mode(m) for m in chain)
    return text


def _label_levels(xs: list[float], widths: list[float], max_levels: int = 4) -> list[int | None]:
    """Stack labels (left ends ``xs``, estimated ``widths``, both in axes fractions, sorted by
    x) on lines above the axes, greedily in the lowest line where they do not overlap the label
    before them; None when all ``max_levels`` lines are taken there (the event stays marked)."""
    ends: list[float] = []
    out: list[int | None] = []
    for x, w in zip(xs, widths):
        level = next((i for i, e in enumerate(ends) if e < x), None)
        if level is None and len(ends) < max_levels:
            level = len(ends)
            ends.append(-1.0)
        if level is not None:
            ends[level] = x + w
        out.append(level)
    return out


def plot_trajectory(traj, *, states: Sequence[Any] | None = None, constraints: Sequence[Any] | None = None,
                    panels: Sequence[str] = ("x", "u", "y"), points: int = 800, label_events: int = 24,
                    figsize: tuple | None = None, title: str | None = None, components=None):
    """Plot a trajectory: states, u and y on separate axes sharing t.  Returns the Figure.

    Parameters
    ----------
    traj : Trajectory
        The result of :func:`lcs_exact.simulate` (or anything with its public interface).
    states : sequence of int or str, optional
        Which states to draw (indices or names); all by default.  ``components`` is an alias.
    constraints : sequence of int or str, optional
        Which complementarity pairs to draw in the u and y panels; all by default.
    panels : subset of ("x", "u", "y")
    points : int
        Approximate number of sample times in total (spread over the phases by length, at least
        six per phase); each is a certified evaluation (``traj.sample``: 800 points take a
        fraction of a second).
    label_events : int
        Events beyond this number are marked but not labelled.
    figsize, title : optional

    What is drawn: each continuous phase is its own line (no segment joins x(τ-) to x(τ+));
    where a state, u or y jumps, an open circle marks the left limit and a filled one the right
    limit (drawn only when the two are certainly different); an impulse u^0 δ (3.6) is a dotted
    arrow labelled with its weight; events are dashed lines labelled with the mode change
    (``∅→{0}``; ``start→{1}`` for a jump at t = 0; ``∅→∅ via {0}`` for an impact followed by
    lift-off: the re-initialization chain when it differs from the mode entered); each phase is
    shaded with its mode's colour.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from lcs_exact import simulate
    >>> from lcs_exact.examples import two_carts
    >>> fig = plot_trajectory(simulate(two_carts(), [0, 1, -1, 0], 2), points=40)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['state', 'u', 'y']
    """
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from .reals import ProjectedVector

    lcs = traj.lcs
    if components is not None and states is None:
        states = components
    sidx = _indices(states, getattr(lcs, "state_names", ()), lcs.n, "state")
    cidx = _indices(constraints, getattr(lcs, "constraint_names", ()), lcs.k, "constraint")
    panels = [p for p in ("x", "u", "y") if p in panels]
    if not panels:
        raise InvalidArgument("panels must contain at least one of 'x', 'u', 'y'")
    if isinstance(points, bool) or not isinstance(points, int) or points < 1:
        raise InvalidArgument(f"points must be a positive integer, got {points!r}")
    phases = phase_intervals(traj)
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=figsize or (9, 2.4 * len(panels) + 0.8), layout="constrained")
    axes = list(axes[:, 0])
    ax_of = dict(zip(panels, axes))
    total = sum(float(p.end) - float(p.start) for p in phases) or 1.0
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    cyc = [palette[i % len(palette)] for i in range(max(lcs.n, lcs.k))]
    sty = [_STYLES[(i // len(palette)) % len(_STYLES)] for i in range(max(lcs.n, lcs.k))]

    # one colour per mode, the same whatever the order of the phases: the free mode grey
    ordered = sorted({ph.mode for ph in phases if ph.mode}, key=lambda m: (len(m), sorted(m)))
    colors = {m: _MODE_COLORS[i % len(_MODE_COLORS)] for i, m in enumerate(ordered)}
    colors.update({m: "#9a9a9a" for ph in phases for m in (ph.mode,) if not m})
    pair_ends = []  # per phase: (u, y) at its start and at its end, exact, for the jump markers
    any_free = False
    free_of: dict = {}  # mode -> inputs undetermined on its phases (legend)
    for ph in phases:
        fa, fb = float(ph.start), float(ph.end)
        for ax in axes:
            ax.axvspan(fa, fb, color=colors[ph.mode], alpha=0.10, lw=0)
        npts = max(6, int(points * (fb - fa) / total))
        if ph.window is not None:  # infinitely many events: a line per scaled flight, exact values
            _draw_window(traj, ph, ax_of, sidx, cidx, cyc, sty, npts)
            pair_ends.append((None, None))
            continue
        ts = [_frac(fa + (fb - fa) * (j + 0.5) / npts) for j in range(npts)]  # inside the phase
        tt = [fa] + [float(t) for t in ts] + [fb]
        first = ph.start_event.state_after if ph.start_event is not None else \
            (traj.state(ph.start) if float(ph.start) > 0 else traj.x0)  # after an accumulation: x(T*)
        last = ph.end_event.state_before if ph.end_event is not None else traj.state(ph.end)
        balls = traj.sample(ts, 10)  # certified, one exponential sum per point
        if "x" in ax_of:
            rows = [[float(b.mid()) for b in row] for row in balls]
            for pos, i in enumerate(sidx):
                vals = [float(first[i])] + [r[i] for r in rows] + [float(last[i])]
                ax_of["x"].plot(tt, vals, color=cyc[pos], ls=sty[pos], lw=1.6)
        maps = _pair_maps(lcs, ph.mode)
        if maps is None:  # no mode: u and y are not defined there
            pair_ends.append((None, None))
            continue
        # u and y are linear in x on the phase: from the same balls, and exactly at the two ends
        # (u(τ+) at the start, u(τ-) at the end: the values the jump markers compare)
        ends = tuple((ProjectedVector(maps[0], z), ProjectedVector(maps[1], z)) for z in (first, last))
        pair_ends.append(ends)
        free = _undetermined(traj, ph)  # inputs the state leaves free here: not drawn (no value)
        free_of[ph.mode] = free_of.get(ph.mode, frozenset()) | free
        free_y = {i for i in range(lcs.k) if any(lcs.D[i, j] != 0 for j in free)}
        for w, which in enumerate(("u", "y")):
            if which in ax_of:
                vals = ([[float(c) for c in ends[0][w]]] + _apply(maps[w], balls, ph.mode if w else ())
                        + [[float(c) for c in ends[1][w]]])
                for pos, i in enumerate(cidx):
                    if i in (free if w == 0 else free_y):
                        any_free = True
                        continue
                    ax_of[which].plot(tt, [v[i] for v in vals], color=cyc[pos], ls=sty[pos], lw=1.6)

    evs = sorted(traj.events, key=lambda e: float(e.time))
    any_jump = False
    any_impulse = False
    t_hi = float(phases[-1].end) if phases else float(traj.t_end)
    t_hi = t_hi if t_hi > 0 else 1.0
    # event labels: horizontal, on up to four lines above the first panel, never on top of
    # each other (widths estimated from the text: ~4.7 pt per character at 8 pt)
    texts = [_event_text(e) for e in evs[:label_events]]
    axes_pt = fig.get_figwidth() * 72 * 0.78
    x_lo, x_span = -0.015 * t_hi, 1.03 * t_hi
    levels = _label_levels([(float(e.time) - x_lo) / x_span for e in evs[:label_events]],
                           [(4.7 * len(tx) + 6) / axes_pt for tx in texts])
    many = len(evs) > 2 * label_events  # a dense run: thin light event lines, not a hatching
    impulses: dict = {}  # event number -> [(position, pair, weight of u^0)]
    for num, e in enumerate(evs):
        u0 = (getattr(e, "impulse", None) or {}).get(0)
        if u0 is not None:
            for pos, i in enumerate(cidx):
                v, nonzero = _component(u0, i)
                if nonzero:
                    impulses.setdefault(num, []).append((pos, i, v))
    w_max = max((abs(v) for lst in impulses.values() for _, _, v in lst), default=1.0) or 1.0
    # weights are written next to their arrows when there are few (else the arrows' heights and
    # the event table tell them)
    label_weights = sum(len(lst) for lst in impulses.values()) <= 12
    for num, e in enumerate(evs):
        te = float(e.time)
        for ax in axes:
            ax.axvline(te, color="0.35", lw=0.4 if many else 0.8, ls="--", alpha=0.35 if many else 1.0, zorder=1)
        if num < label_events and levels[num] is not None:
            axes[0].annotate(texts[num], xy=(te, 1.0), xycoords=("data", "axes fraction"),
                             xytext=(1, 2 + 10 * levels[num]), textcoords="offset points", fontsize=8,
                             ha="left", va="bottom", color="0.2")
        if "x" in ax_of:
            for pos, i in enumerate(sidx):
                xb, xa = e.state_before[i], e.state_after[i]
                if _certainly_different(xb, xa):
                    any_jump = True
                    ax_of["x"].plot([te], [float(xb)], "o", mfc="white", mec=cyc[pos], ms=6, zorder=5)
                    ax_of["x"].plot([te], [float(xa)], "o", color=cyc[pos], ms=5, zorder=6)
        if "u" in ax_of:
            shown = 0
            for pos, i, v in impulses.get(num, ()):
                # an impulse u^0 δ at the event (3.6): a dotted arrow whose height grows with the
                # weight (the largest reaches the top), not a value of u
                any_impulse = True
                dx = 0.004 * t_hi * shown  # side by side when several constraints act at once
                top = 0.03 + 0.94 * (0.15 + 0.85 * abs(v) / w_max)
                ax_of["u"].annotate("", xy=(te + dx, top), xycoords=("data", "axes fraction"),
                                    xytext=(te + dx, 0.03), textcoords=("data", "axes fraction"),
                                    arrowprops=dict(arrowstyle="-|>", color=cyc[pos], lw=1.2, ls=":", alpha=0.8),
                                    zorder=4)
                if label_weights:
                    ax_of["u"].annotate(f"{v:.4g}·δ", xy=(te + dx, min(0.6, top - 0.05) - 0.1 * (shown + (levels[num] or 0))),
                                        xycoords=("data", "axes fraction"), xytext=(4, 0),
                                        textcoords="offset points", fontsize=8, color=cyc[pos])
                shown += 1
    # u and y jump wherever the mode changes: open/closed markers as for the state
    for (prev, ends), ph in zip(zip(pair_ends, pair_ends[1:]), phases[1:]):
        if prev[1] is None or ends[0] is None:
            continue
        te = float(ph.start)
        for w, which in enumerate(("u", "y")):
            if which not in ax_of:
                continue
            for pos, i in enumerate(cidx):
                left, right = prev[1][w][i], ends[0][w][i]
                if _certainly_different(left, right):
                    any_jump = True
                    ax_of[which].plot([te], [float(left)], "o", mfc="white", mec=cyc[pos], ms=5, zorder=5)
                    ax_of[which].plot([te], [float(right)], "o", color=cyc[pos], ms=4, zorder=6)

    for ax in axes:
        ax.set_xlim(-0.015 * t_hi, 1.015 * t_hi)
        ax.grid(True, lw=0.3, alpha=0.5)
    axes[-1].set_xlabel("t")
    for p, ax in ax_of.items():
        ax.set_ylabel({"x": "state"}.get(p, p))
        if p == "x":
            handles = [Line2D([], [], color=cyc[pos], ls=sty[pos], lw=1.6, label=_state_label(lcs, i))
                       for pos, i in enumerate(sidx)]
        else:
            handles = [Line2D([], [], color=cyc[pos], ls=sty[pos], lw=1.6, label=_pair_label(lcs, p, i))
                       for pos, i in enumerate(cidx)]
            if p == "u" and any_impulse:
                handles.append(Line2D([], [], color="0.3", ls=":", marker="^", ms=5, label="impulse (weight·δ)"))
            if any_free:
                handles.append(Line2D([], [], color="none", label="(gaps: not determined by the state)"))
        if ax is axes[0]:
            if any_jump:
                handles += [Line2D([], [], ls="", marker="o", mfc="white", mec="0.3", label="left limit (τ−)"),
                            Line2D([], [], ls="", marker="o", color="0.3", label="right limit (τ+)")]
            handles += [Patch(color=colors[m], alpha=0.3, label=_mode_label(lcs, m, free_of.get(m, frozenset())))
                        for m in sorted(colors, key=lambda m: (m is None, len(m or ()), sorted(m or ())))]
        # a long legend in columns: it must not be taller than its panel
        ncol = 1 + (len(handles) - 1) // 12
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False,
                  ncol=ncol)
    name = title if title is not None else (getattr(lcs, "name", None) or "LCS trajectory")
    if getattr(traj, "partial", False):
        status = getattr(getattr(traj, "status", None), "value", None)
        name += f" (partial: {status})" if status else " (partial)"
        if phases:  # where the run stopped
            for ax in axes:
                ax.axvline(float(phases[-1].end), color="#c44e52", lw=1.2, ls=":", zorder=2)
            axes[0].annotate("run stopped", xy=(float(phases[-1].end), 1.0), xycoords=("data", "axes fraction"),
                             xytext=(-2, 2), textcoords="offset points", ha="right", va="bottom", fontsize=8,
                             color="#c44e52")
    fig.suptitle(name, fontsize=11)
    return fig


def _indices(sel, names, count: int, what: str) -> list[int]:
    if sel is None:
        return list(range(count))
    out = []
    for v in sel:
        if isinstance(v, str):
            if v not in names:
                raise InvalidArgument(f"unknown {what} name {v!r}; the names are {tuple(names)}")
            out.append(tuple(names).index(v))
        else:
            i = int(v)
            if not 0 <= i < count:
                raise InvalidArgument(f"{what} index {i} outside 0..{count - 1} (indices are 0-based)")
            out.append(i)
    return out


# ---------------------------------------------------------------------------------------------
# mode maps
# ---------------------------------------------------------------------------------------------


def _clip(poly: list[tuple[fmpq, fmpq]], a, b, sign: int) -> list[tuple[fmpq, fmpq]]:
    """Sutherland-Hodgman: keep the part of the polygon with sign * (a . p + b) >= 0 (exact)."""
    def val(p):
        return sign * (a[0] * p[0] + a[1] * p[1] + b)
    out = []
    for i in range(len(poly)):
        p, q = poly[i], poly[(i + 1) % len(poly)]
        vp, vq = val(p), val(q)
        if vp >= 0:
            out.append(p)
        if (vp > 0 and vq < 0) or (vp < 0 and vq > 0):
            t = vp / (vp - vq)
            out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    return out


def _segment(face, hyperplanes, window) -> tuple | None:
    """The closure of a 1-D face inside the window: two endpoints (exact) or None."""
    j0 = face.signs.index(0)
    a, b = hyperplanes[j0]
    p = face.point
    d = (-a[1], a[0])
    lo, hi = None, None
    cons = [(hyperplanes[j], face.signs[j]) for j in range(len(face.signs)) if j != j0]
    x0, x1, y0, y1 = window
    cons += [(((fmpq(1), fmpq(0)), -x0), 1), (((fmpq(1), fmpq(0)), -x1), -1),
             (((fmpq(0), fmpq(1)), -y0), 1), (((fmpq(0), fmpq(1)), -y1), -1)]
    for (c, e), s in cons:
        g0 = s * (c[0] * p[0] + c[1] * p[1] + e)  # >= 0 on the closure
        g1 = s * (c[0] * d[0] + c[1] * d[1])
        if g1 == 0:
            if g0 < 0:
                return None
            continue
        t = -g0 / g1
        if g1 > 0:
            lo = t if lo is None or t > lo else lo
        else:
            hi = t if hi is None or t < hi else hi
    if lo is None or hi is None or lo > hi:
        return None
    return ((p[0] + lo * d[0], p[1] + lo * d[1]), (p[0] + hi * d[0], p[1] + hi * d[1]))


def _default_window(mm) -> tuple:
    verts = [f.point for f in mm.faces if f.dimension == 0]
    if not verts:
        verts = [f.point for f in mm.faces if f.dimension <= 1][:1] or [(fmpq(0), fmpq(0))]
    cx = sum((v[0] for v in verts), fmpq(0)) / len(verts)
    cy = sum((v[1] for v in verts), fmpq(0)) / len(verts)
    spread = max([abs(v[0] - cx) for v in verts] + [abs(v[1] - cy) for v in verts] + [fmpq(0)])
    h = max(fmpq(1), fmpq(3, 2) * spread)
    return (cx - h, cx + h, cy - h, cy + h)


def _region_legend(lcs, r) -> str:
    """``S = {0}: stop`` (constraint names of the single admissible mode), ``(ray)``/``(point)``."""
    text = f"S = {r.label}"
    names = getattr(lcs, "constraint_names", None)
    if len(r.modes) == 1 and names and not _is_default(names, ""):
        (m,) = r.modes
        text += ": " + ("+".join(names[i] for i in sorted(m)) if m else "free")
    if r.dimension < 2:
        text += " (ray)" if r.dimension == 1 else " (point)"
    return text


def plot_mode_map(mm, ax=None, *, window: Sequence[Any] | None = None, arrows: bool = True,
                  grid: int = 9, title: str | None = None):
    """Draw a 2-D mode map: regions filled and labelled with S(x0), jumps as arrows.

    Faces are clipped to the window exactly (rational polygon clipping) before they are drawn;
    1-D regions are thick lines and 0-D regions dots, in the colour of their S(x0).  An arrow
    goes from a grid point s to the point where the re-initialization takes it (P_I x0 - x0 in
    slice coordinates, exact, then rounded for drawing; its projection onto the slice when the
    jump leaves the slice, as the title then says).  Grid points are rational and located
    exactly, so points on boundaries get their own region.  Returns the Figure.

    Parameters
    ----------
    mm : ModeMap
        A map with two coordinates (``slice=(base, [d_0, d_1])``, or an LCS with n = 2).
    window : (xmin, xmax, ymin, ymax), optional
        Rationals; by default a square around the vertices of the arrangement.
    arrows : bool
    grid : int
        Arrows on a grid x grid lattice (offset by half a step).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from lcs_exact.examples import two_carts_with_hook
    >>> fig = two_carts_with_hook().mode_map(slice=([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]])).plot()
    >>> fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel()
    ("q_0'", "q_1'")
    """
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Polygon

    from .rational import to_fmpq

    if mm.dimension != 2:
        raise InvalidArgument(f"plot draws a 2-D map; this map has {mm.dimension} coordinates "
                         "(give slice=(base, [d_0, d_1]))")
    if window is None:
        window = _default_window(mm)
    window = tuple(to_fmpq(w, "window") for w in window)
    x0, x1, y0, y1 = window
    if not (x0 < x1 and y0 < y1):
        raise InvalidArgument("window must be (xmin, xmax, ymin, ymax) with xmin < xmax and ymin < ymax")
    own_figure = ax is None
    if own_figure:
        fig, ax = plt.subplots(figsize=(8.2, 5.0), layout="constrained")
    else:
        fig = ax.figure
    from matplotlib.colors import to_rgb
    color = {r.modes: _MODE_COLORS[i % len(_MODE_COLORS)] for i, r in enumerate(mm.regions)}
    pastel = {m: tuple(0.62 + 0.38 * v for v in to_rgb(c)) for m, c in color.items()}
    rect = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    region_of = {f.signs: r.modes for r in mm.regions for f in r.faces}
    best_poly: dict = {}
    for r in mm.regions:
        for f in r.faces:
            if f.dimension == 2:
                poly = rect
                for (a, b), s in zip(mm.hyperplanes, f.signs):
                    poly = _clip(poly, a, b, s)
                    if not poly:
                        break
                if len(poly) >= 3:
                    pts = [(float(p[0]), float(p[1])) for p in poly]
                    # opaque pastel with an edge of the same colour: no seams between faces
                    ax.add_patch(Polygon(pts, closed=True, facecolor=pastel[r.modes], edgecolor=pastel[r.modes],
                                         lw=0.8, zorder=1))
                    area = abs(sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
                                   for i in range(len(pts)))) / 2
                    if area > best_poly.get(r.modes, (0, None))[0]:
                        cx = sum(p[0] for p in pts) / len(pts)
                        cy = sum(p[1] for p in pts) / len(pts)
                        best_poly[r.modes] = (area, (cx, cy))
            elif f.dimension == 1:
                # a ray of its own S is drawn thick; a boundary ray of a 2-D region thin, in the
                # colour of the region that owns it; a ray inside one region not at all
                j0 = f.signs.index(0)
                sides = {region_of.get(f.signs[:j0] + (s,) + f.signs[j0 + 1:]) for s in (-1, 1)}
                if r.dimension == 1:
                    lw = 4.0
                elif len(sides) > 1:
                    lw = 1.8
                else:
                    continue
                seg = _segment(f, mm.hyperplanes, window)
                if seg is not None:
                    ax.plot([float(seg[0][0]), float(seg[1][0])], [float(seg[0][1]), float(seg[1][1])],
                            color=color[r.modes], lw=lw, solid_capstyle="butt", zorder=3)
            elif f.dimension == 0 and r.dimension == 0:  # a vertex inside a larger region is not special
                p = f.point
                if x0 <= p[0] <= x1 and y0 <= p[1] <= y1:
                    ax.plot([float(p[0])], [float(p[1])], "o", color=color[r.modes], mec="black", ms=8, zorder=4)
    for r in mm.regions:
        if r.modes in best_poly:
            cx, cy = best_poly[r.modes][1]
            ax.text(cx, cy, r.label, ha="center", va="center", fontsize=11, weight="bold",
                    bbox=dict(boxstyle="round,pad=0.25", fc="white", ec=color[r.modes], alpha=0.85), zorder=6)
    leaves = False
    if arrows and grid > 0:
        us, vs, xs, ys = [], [], [], []
        for i in range(grid):
            for j in range(grid):
                s = (x0 + (x1 - x0) * fmpq(2 * i + 1, 2 * grid), y0 + (y1 - y0) * fmpq(2 * j + 1, 2 * grid))
                reg = mm.locate(s)
                jm = mm.slice_jump(reg)
                if jm is None:
                    continue
                c0, C1, exact = jm
                dx = c0[0, 0] + C1[0, 0] * s[0] + C1[0, 1] * s[1]
                dy = c0[1, 0] + C1[1, 0] * s[0] + C1[1, 1] * s[1]
                if dx == 0 and dy == 0:
                    continue
                leaves = leaves or not exact
                xs.append(float(s[0]))
                ys.append(float(s[1]))
                us.append(float(dx))
                vs.append(float(dy))
        if xs:
            ax.quiver(xs, ys, us, vs, angles="xy", scale_units="xy", scale=1, width=0.004, color="0.15",
                      zorder=5, alpha=0.8)
    ax.set_xlim(float(x0), float(x1))
    ax.set_ylim(float(y0), float(y1))
    ax.set_xlabel(mm.variables[0])
    ax.set_ylabel(mm.variables[1])
    ax.set_aspect("equal", adjustable="box")
    handles = [Patch(facecolor=pastel[r.modes] if r.dimension == 2 else color[r.modes], label=_region_legend(mm.lcs, r))
               for r in mm.regions]
    if arrows:
        handles.append(Line2D([], [], color="0.15", marker=r"$\rightarrow$", ls="", ms=12, label="jump x0 → x(0+)"))
    if own_figure:
        fig.legend(handles=handles, loc="outside right upper", fontsize=9, frameon=False)
    else:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=9, frameon=False)
    name = title if title is not None else f"{getattr(mm.lcs, 'name', None) or 'LCS'}: mode map (exact)"
    if leaves:
        name += "\n(jumps leave the slice: arrows show their projection)"
    ax.set_title(name, fontsize=11)
    return fig

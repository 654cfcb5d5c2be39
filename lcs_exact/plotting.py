"""Figures: a trajectory (states, u, y against t); the 2-D mode map (Figure 8.2 style) is drawn by
:mod:`lcs_exact.mapplot` (:func:`plot_mode_map`, importable from here too).

matplotlib is imported inside the functions, so ``import lcs_exact`` stays light.  This module
sits below :mod:`lcs_exact.trajectory` and never imports it: a trajectory is used through its
public interface only (``lcs``, ``x0``, ``t_end``, ``events``, ``partial``, ``state(t)``,
``u(t)``, ``y(t)``; an event's ``time``, ``mode_before``, ``mode_after``, ``state_before``,
``state_after``, ``impulse``).  :func:`plot_trajectory` draws in steps named after what they draw
(each phase with its states panel and u/y panels, accumulation windows, events with the jumps and
impulses at them, u/y jumps, legends, the title), sharing one ``_Canvas``.

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

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Sequence

from flint import arb, ctx, fmpq_mat

from .errors import InvalidArgument, LCSError
from .interfaces import SystemLike
from .mapplot import MODE_COLORS, default_names, plot_mode_map
from .modes import format_mode, mode_order
from .vectors import ProjectedVector

__all__ = ["plot_trajectory", "plot_mode_map", "phase_intervals", "PhaseInterval"]


def _pair_label(lcs: SystemLike, which: str, i: int) -> str:
    roles = getattr(lcs, "roles", None)
    if roles is not None:  # the builder's words: "force (floor)", "i(D1)"
        return roles[i][0 if which == "u" else 1]
    names = getattr(lcs, "constraint_names", None) or tuple(str(j) for j in range(lcs.k))
    if default_names(names, ""):
        return f"${which}_{{{i}}}$"
    return f"{which} ({names[i]})"


def _mode_label(lcs: SystemLike, m, free=frozenset()) -> str:
    """The legend text of a mode: the builder's words when it gave roles (a long text is cut);
    ``free``: inputs left undetermined on its phases."""
    if m is None:
        return "mode ?"
    if getattr(lcs, "roles", None) is None or not hasattr(lcs, "describe_mode"):
        return f"mode {format_mode(m)}" + (f" ({format_mode(free)} undetermined)" if free else "")
    text = lcs.describe_mode(m, free)
    return text if len(text) <= 48 else f"mode {format_mode(m)}: " + text[:40] + "…"


def _state_label(lcs: SystemLike, i: int) -> str:
    names = getattr(lcs, "state_names", None) or tuple(f"x_{j}" for j in range(lcs.n))
    nm = names[i]
    if default_names(names, "x_"):
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
        mode = min(S, key=mode_order) if S else None
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
    return min(S, key=mode_order) if S else None


def _component(v, i: int) -> tuple[float, bool]:
    """(float value, certainly nonzero) of entry i of an exact vector or an n x 1 fmpq_mat."""
    if hasattr(v, "nrows"):
        q = v[i, 0]
        return float(Fraction(int(q.p), int(q.q))), q != 0
    c = v[i]
    return float(c), not c.ball(20).contains(0)


def _pair_maps(lcs: SystemLike, mode):
    """(F_u, F_y) with u = F_u x, y = F_y x on a phase of ``mode``: u_I = F_I x, zero off I
    (section 4.1), y = C x + D u.  None for an unknown mode (a deadlock at the start)."""
    if mode is None:
        return None
    Fu = fmpq_mat(lcs.k, lcs.n)
    if mode:
        F = lcs.mode(mode).feedback()  # rows follow the indices of I in increasing order
        for r, i in enumerate(sorted(mode)):
            for j in range(lcs.n):
                Fu[i, j] = F[r, j]
    return Fu, lcs.C + lcs.D * Fu


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
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    cv = _Canvas(traj, lcs, fig, axes, dict(zip(panels, axes)), sidx, cidx,
                 pens=[(palette[i % len(palette)], _STYLES[(i // len(palette)) % len(_STYLES)])
                       for i in range(max(lcs.n, lcs.k))],
                 colors=_mode_colors(phases))
    total = sum(float(p.end) - float(p.start) for p in phases) or 1.0
    # per phase: (u, y) at its start and at its end, exact, for the jump markers
    pair_ends = [_draw_phase(cv, ph, max(6, int(points * (float(ph.end) - float(ph.start)) / total)))
                 for ph in phases]
    t_hi = float(phases[-1].end) if phases else float(traj.t_end)
    t_hi = t_hi if t_hi > 0 else 1.0
    _draw_events(cv, sorted(traj.events, key=lambda e: float(e.time)), t_hi, label_events)
    _draw_pair_jumps(cv, phases, pair_ends)
    for ax in axes:
        ax.set_xlim(-0.015 * t_hi, 1.015 * t_hi)
        ax.grid(True, lw=0.3, alpha=0.5)
    axes[-1].set_xlabel("t")
    _draw_legends(cv)
    _draw_title(cv, phases, title)
    return fig


@dataclass
class _Canvas:
    """What the parts of a trajectory figure share: the trajectory, the panels (``ax_of``: "x",
    "u", "y" to their axes), the states and pairs drawn and their pens (colour, line style of
    the pos-th line), the shade of each mode, and what was drawn (for the legends)."""

    traj: Any
    lcs: Any
    fig: Any
    axes: list
    ax_of: dict
    sidx: list
    cidx: list
    pens: list
    colors: dict
    any_jump: bool = False
    any_impulse: bool = False
    any_free: bool = False
    free_of: dict = field(default_factory=dict)  # mode -> inputs undetermined on its phases

    def line(self, which: str, pos: int, tt, vals) -> None:
        """The pos-th line of a panel (a state, or a pair's u or y) over the times tt."""
        color, ls = self.pens[pos]
        self.ax_of[which].plot(tt, vals, color=color, ls=ls, lw=1.6)

    def jump(self, which: str, pos: int, t: float, left, right, sizes: tuple) -> None:
        """A jump of the pos-th line of a panel at t: an open circle at the left limit, a filled
        one at the right limit (the trajectory is right-continuous)."""
        color = self.pens[pos][0]
        self.ax_of[which].plot([t], [float(left)], "o", mfc="white", mec=color, ms=sizes[0], zorder=5)
        self.ax_of[which].plot([t], [float(right)], "o", color=color, ms=sizes[1], zorder=6)


def _mode_colors(phases: list) -> dict:
    """One colour per mode, the same whatever the order of the phases: the free mode grey."""
    ordered = sorted({ph.mode for ph in phases if ph.mode}, key=mode_order)
    colors = {m: MODE_COLORS[i % len(MODE_COLORS)] for i, m in enumerate(ordered)}
    colors.update({m: "#9a9a9a" for ph in phases for m in (ph.mode,) if not m})
    return colors


def _draw_phase(cv: _Canvas, ph: PhaseInterval, npts: int) -> tuple:
    """A continuous phase: shaded with its mode's colour in every panel, its ``npts`` certified
    samples drawn in the states panel and the u/y panels (an accumulation window: its flights).
    Returns the exact (u, y) at its start and its end ((None, None) when it has none)."""
    fa, fb = float(ph.start), float(ph.end)
    for ax in cv.axes:
        ax.axvspan(fa, fb, color=cv.colors[ph.mode], alpha=0.10, lw=0)
    if ph.window is not None:  # infinitely many events: a line per scaled flight, exact values
        _draw_window(cv, ph, npts)
        return (None, None)
    traj = cv.traj
    ts = [_frac(fa + (fb - fa) * (j + 0.5) / npts) for j in range(npts)]  # inside the phase
    tt = [fa] + [float(t) for t in ts] + [fb]
    first = ph.start_event.state_after if ph.start_event is not None else \
        (traj.state(ph.start) if float(ph.start) > 0 else traj.x0)  # after an accumulation: x(T*)
    last = ph.end_event.state_before if ph.end_event is not None else traj.state(ph.end)
    balls = traj.sample(ts, 10)  # certified, one exponential sum per point
    _draw_states_panel(cv, tt, first, last, balls)
    return _draw_pair_panels(cv, ph, tt, first, last, balls)


def _draw_states_panel(cv: _Canvas, tt: list, first, last, balls: list) -> None:
    """The states on one phase: the exact x(start+), the sampled balls, the exact x(end-)."""
    if "x" not in cv.ax_of:
        return
    rows = [[float(b.mid()) for b in row] for row in balls]
    for pos, i in enumerate(cv.sidx):
        cv.line("x", pos, tt, [float(first[i])] + [r[i] for r in rows] + [float(last[i])])


def _draw_pair_panels(cv: _Canvas, ph: PhaseInterval, tt: list, first, last, balls: list) -> tuple:
    """u and y on one phase: linear in x there (u = F_u x, y = F_y x), from the same balls and
    exactly at the two ends (u(τ+) at the start, u(τ-) at the end: the values the jump markers
    compare); inputs the state leaves free are not drawn (no value).  Returns those ends."""
    maps = _pair_maps(cv.lcs, ph.mode)
    if maps is None:  # no mode: u and y are not defined there
        return (None, None)
    ends = tuple((ProjectedVector(maps[0], z), ProjectedVector(maps[1], z)) for z in (first, last))
    free = _undetermined(cv.traj, ph)  # inputs the state leaves free here
    cv.free_of[ph.mode] = cv.free_of.get(ph.mode, frozenset()) | free
    free_y = {i for i in range(cv.lcs.k) if any(cv.lcs.D[i, j] != 0 for j in free)}
    for w, which in enumerate(("u", "y")):
        if which in cv.ax_of:
            vals = ([[float(c) for c in ends[0][w]]] + _apply(maps[w], balls, ph.mode if w else ())
                    + [[float(c) for c in ends[1][w]]])
            for pos, i in enumerate(cv.cidx):
                if i in (free if w == 0 else free_y):
                    cv.any_free = True
                    continue
                cv.line(which, pos, tt, [v[i] for v in vals])
    return ends


def _draw_window(cv: _Canvas, ph: PhaseInterval, npts: int) -> None:
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
        if "x" in cv.ax_of:
            rows = [[float(v.mid()) for v in row] for row in cv.traj.sample(ts, 10)]
            for pos, i in enumerate(cv.sidx):
                cv.line("x", pos, tt, [r[i] for r in rows])
        for which in ("u", "y"):
            if which in cv.ax_of:
                vals = [[float(c) for c in getattr(cv.traj, which)(t)] for t in ts]
                for pos, i in enumerate(cv.cidx):
                    cv.line(which, pos, tt, [v[i] for v in vals])


def _draw_events(cv: _Canvas, evs: list, t_hi: float, label_events: int) -> None:
    """Every event: its dashed line, its label, the jumps of the states and the impulses."""
    # event labels: horizontal, on up to four lines above the first panel, never on top of
    # each other (widths estimated from the text: ~4.7 pt per character at 8 pt)
    texts = [_event_text(e) for e in evs[:label_events]]
    axes_pt = cv.fig.get_figwidth() * 72 * 0.78
    x_lo, x_span = -0.015 * t_hi, 1.03 * t_hi
    levels = _label_levels([(float(e.time) - x_lo) / x_span for e in evs[:label_events]],
                           [(4.7 * len(tx) + 6) / axes_pt for tx in texts])
    levels += [None] * (len(evs) - len(levels))  # the events beyond label_events have no label line
    many = len(evs) > 2 * label_events  # a dense run: thin light event lines, not a hatching
    impulses = _impulses(cv, evs)
    w_max = max((abs(v) for lst in impulses.values() for _, _, v in lst), default=1.0) or 1.0
    # weights are written next to their arrows when there are few (else the arrows' heights and
    # the event table tell them)
    label_weights = sum(len(lst) for lst in impulses.values()) <= 12
    for num, e in enumerate(evs):
        te = float(e.time)
        for ax in cv.axes:
            ax.axvline(te, color="0.35", lw=0.4 if many else 0.8, ls="--", alpha=0.35 if many else 1.0, zorder=1)
        if num < label_events and levels[num] is not None:
            cv.axes[0].annotate(texts[num], xy=(te, 1.0), xycoords=("data", "axes fraction"),
                                xytext=(1, 2 + 10 * levels[num]), textcoords="offset points", fontsize=8,
                                ha="left", va="bottom", color="0.2")
        _draw_state_jumps(cv, e, te)
        _draw_impulses(cv, impulses.get(num, ()), te, t_hi, w_max, (levels[num] or 0) if label_weights else None)


def _draw_state_jumps(cv: _Canvas, e, te: float) -> None:
    """The states that certainly jump at the event: x(τ-) open, x(τ+) filled."""
    if "x" not in cv.ax_of:
        return
    for pos, i in enumerate(cv.sidx):
        xb, xa = e.state_before[i], e.state_after[i]
        if _certainly_different(xb, xa):
            cv.any_jump = True
            cv.jump("x", pos, te, xb, xa, (6, 5))


def _impulses(cv: _Canvas, evs: list) -> dict:
    """Event number -> [(position, pair, weight of u^0)] for the drawn pairs with an impulse."""
    out: dict = {}
    for num, e in enumerate(evs):
        u0 = (getattr(e, "impulse", None) or {}).get(0)
        if u0 is not None:
            for pos, i in enumerate(cv.cidx):
                v, nonzero = _component(u0, i)
                if nonzero:
                    out.setdefault(num, []).append((pos, i, v))
    return out


def _draw_impulses(cv: _Canvas, arrows, te: float, t_hi: float, w_max: float, level: int | None) -> None:
    """The impulses u^0 δ at an event (3.6): dotted arrows whose height grows with the weight
    (the largest reaches the top), not values of u; their weights written beside them unless
    ``level`` is None (the event label's line, which the text steps below)."""
    if "u" not in cv.ax_of:
        return
    for shown, (pos, i, v) in enumerate(arrows):
        cv.any_impulse = True
        color = cv.pens[pos][0]
        dx = 0.004 * t_hi * shown  # side by side when several constraints act at once
        top = 0.03 + 0.94 * (0.15 + 0.85 * abs(v) / w_max)
        cv.ax_of["u"].annotate("", xy=(te + dx, top), xycoords=("data", "axes fraction"),
                               xytext=(te + dx, 0.03), textcoords=("data", "axes fraction"),
                               arrowprops=dict(arrowstyle="-|>", color=color, lw=1.2, ls=":", alpha=0.8), zorder=4)
        if level is not None:
            cv.ax_of["u"].annotate(f"{v:.4g}·δ", xy=(te + dx, min(0.6, top - 0.05) - 0.1 * (shown + level)),
                                   xycoords=("data", "axes fraction"), xytext=(4, 0),
                                   textcoords="offset points", fontsize=8, color=color)


def _draw_pair_jumps(cv: _Canvas, phases: list, pair_ends: list) -> None:
    """u and y jump wherever the mode changes: open/closed markers as for the state."""
    for (prev, ends), ph in zip(zip(pair_ends, pair_ends[1:]), phases[1:]):
        if prev[1] is None or ends[0] is None:
            continue
        te = float(ph.start)
        for w, which in enumerate(("u", "y")):
            if which not in cv.ax_of:
                continue
            for pos, i in enumerate(cv.cidx):
                left, right = prev[1][w][i], ends[0][w][i]
                if _certainly_different(left, right):
                    cv.any_jump = True
                    cv.jump(which, pos, te, left, right, (5, 4))


def _draw_legends(cv: _Canvas) -> None:
    """Each panel's label and legend outside the data: its lines (names), the impulses and the
    gaps where they occur; in the first panel the jump markers and the modes' shades."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    lcs = cv.lcs
    for p, ax in cv.ax_of.items():
        ax.set_ylabel({"x": "state"}.get(p, p))
        if p == "x":
            handles = [Line2D([], [], color=cv.pens[pos][0], ls=cv.pens[pos][1], lw=1.6, label=_state_label(lcs, i))
                       for pos, i in enumerate(cv.sidx)]
        else:
            handles = [Line2D([], [], color=cv.pens[pos][0], ls=cv.pens[pos][1], lw=1.6,
                              label=_pair_label(lcs, p, i)) for pos, i in enumerate(cv.cidx)]
            if p == "u" and cv.any_impulse:
                handles.append(Line2D([], [], color="0.3", ls=":", marker="^", ms=5, label="impulse (weight·δ)"))
            if cv.any_free:
                handles.append(Line2D([], [], color="none", label="(gaps: not determined by the state)"))
        if ax is cv.axes[0]:
            if cv.any_jump:
                handles += [Line2D([], [], ls="", marker="o", mfc="white", mec="0.3", label="left limit (τ−)"),
                            Line2D([], [], ls="", marker="o", color="0.3", label="right limit (τ+)")]
            handles += [Patch(color=cv.colors[m], alpha=0.3, label=_mode_label(lcs, m, cv.free_of.get(m, frozenset())))
                        for m in sorted(cv.colors, key=lambda m: (m is None, mode_order(m or ())))]
        # a long legend in columns: it must not be taller than its panel
        ncol = 1 + (len(handles) - 1) // 12
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False,
                  ncol=ncol)


def _draw_title(cv: _Canvas, phases: list, title: str | None) -> None:
    """The title (the system's name); a partial run says so and is marked where it stopped."""
    traj = cv.traj
    name = title if title is not None else (getattr(cv.lcs, "name", None) or "LCS trajectory")
    if getattr(traj, "partial", False):
        status = getattr(getattr(traj, "status", None), "value", None)
        name += f" (partial: {status})" if status else " (partial)"
        if phases:  # where the run stopped
            for ax in cv.axes:
                ax.axvline(float(phases[-1].end), color="#c44e52", lw=1.2, ls=":", zorder=2)
            cv.axes[0].annotate("run stopped", xy=(float(phases[-1].end), 1.0), xycoords=("data", "axes fraction"),
                                xytext=(-2, 2), textcoords="offset points", ha="right", va="bottom", fontsize=8,
                                color="#c44e52")
    cv.fig.suptitle(name, fontsize=11)


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

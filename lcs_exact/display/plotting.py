"""Figures: a trajectory (states, the declared outputs w, u, y against t); the 2-D mode map
(Figure 8.2 style) is drawn by :mod:`lcs_exact.mapplot` (:func:`plot_mode_map`), the order of
convergence of other solvers by :mod:`lcs_exact.convergence` (:func:`plot_convergence`); both are
importable from here too.

matplotlib is imported inside the functions, so ``import lcs_exact`` stays light.  This module
sits below :mod:`lcs_exact.trajectory` and never imports it: a trajectory is used through its
public interface only (``lcs``, ``x0``, ``t_end``, ``events``, ``partial``, ``state(t)``,
``u(t)``, ``y(t)``, ``outputs(t)``; an event's ``time``, ``mode_before``, ``mode_after``,
``state_before``, ``state_after``, ``impulse``).  :func:`plot_trajectory` draws in steps named
after what they draw (each phase with its states panel and linear panels, accumulation windows,
events with the jumps and impulses at them, jumps of u, y, w, legends, the title, then the texts
placed where there is room), sharing one ``Canvas``.

What a reader needs to see, and how it is drawn:

* jumps are discontinuities: each continuous phase is its own line (no segment joins x(τ-) to
  x(τ+)); at a jump an open circle marks x(τ-) and a filled one x(τ+) (the trajectory is
  right-continuous); a component is drawn as jumping only when its two values are certainly
  different (disjoint balls); the same for u, y and w, which jump where the mode changes (their
  values at the phase ends are exact: u = F_I x, y = C x + D u, w = W_x x + W_u u with the
  phase's F_I); an input the state leaves undetermined is not drawn (a gap), nor its jumps;
* the system's own states are drawn; the states a builder appended for its sources (``1``,
  ``sin(t)``, ``cos(t)``, a relay's level ``c``: ``lcs.sources``) only when asked
  (``sources=True``); the outputs a builder declared (a relay's w_j in Sgn(C_j x)) are drawn
  instead of its internal pairs' u and y;
* an impulse u^0 δ (3.6) is a dashed dark arrow through the whole u panel (not on the scale of
  u: a Dirac has no value there; not in a pair's colour: it is not a line of u) labelled
  ``impulse (stop) = 1.5`` where there is room;
* events are dashed vertical lines labelled with the mode change (``∅→{0}``, ``start→{1}`` at
  t = 0, ``∅→∅ via {0}`` for an impact with immediate lift-off) above the first panel, on up to
  four rows, where the measured text has room (the others stay marked by their line; the
  axis label says how many are labelled); each phase is shaded with its mode's colour (read
  from the events: the ``mode_before`` of the event that ends it, else the last ``mode_after``),
  one colour and one legend text per mode (:mod:`lcs_exact.figlabels`);
* names come from ``lcs.state_names`` / ``lcs.constraint_names`` / the outputs' names; legends
  sit outside the data (in columns when long); a partial run is drawn up to where it stopped,
  marked;
* sampling is cheap (``traj.sample``: one exponential sum per point), so 800 points by default.

Numbers are evaluated exactly (certified balls) and only then rounded to floats for drawing.
"""
from __future__ import annotations


from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

from flint import arb, ctx, fmpq_mat

from .canvas import Canvas
from .convergence import plot_convergence
from ..errors import InvalidArgument, LCSError
from ..interfaces import AccumulationWindow
from .figlabels import (Rows, derived_outputs, draw_schedule, event_text, impulse_label, mode_colors, mode_texts, pair_label,
                        selected_indices, state_label, text_width)
from .mapplot import plot_mode_map
from ..modes import format_mode, mode_order
from ..numbers import ProjectedVector

__all__ = ["plot_trajectory", "plot_mode_map", "plot_convergence", "phase_intervals", "PhaseInterval"]

#: the panels a trajectory figure can have, top to bottom, and their axis labels
PANELS = ("x", "w", "u", "y")
_LINEAR = ("w", "u", "y")


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
        if isinstance(rec.phase, AccumulationWindow):
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
        if not isinstance(rec.phase, AccumulationWindow) and abs(float(rec.t0) - float(acc.time)) == 0:
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


def _linear_maps(cv: "Canvas", mode, lcs) -> dict | None:
    """{panel: M} with panel(t) = M x(t) on a phase of ``mode`` of ``lcs`` (the system in force:
    a schedule's phase): u_I = F_I x, zero off I (section 4.1), y = C x + D u, w = W_x x + W_u u.
    None for an unknown mode (a deadlock at the start)."""
    if mode is None:
        return None
    Fu = fmpq_mat(lcs.k, lcs.n)
    if mode:
        F = lcs.mode(mode).feedback()  # rows follow the indices of I in increasing order
        for r, i in enumerate(sorted(mode)):
            for j in range(lcs.n):
                Fu[i, j] = F[r, j]
    maps = {"u": Fu, "y": lcs.C + lcs.D * Fu}
    if cv.outputs is not None:
        maps["w"] = cv.outputs.Wx + cv.outputs.Wu * Fu
    return maps


def _system_in_force(lcs, ph: PhaseInterval):
    """The LCS whose data hold on the phase: ``lcs``, or its schedule's at the phase's middle."""
    schedule = getattr(lcs, "schedule", None)
    return lcs if schedule is None else schedule.system_at((float(ph.start) + float(ph.end)) / 2)


def _free_rows(cv: "Canvas", free: frozenset) -> dict:
    """{panel: components that depend on the undetermined inputs ``free``}."""
    lcs = cv.lcs
    out = {"u": set(free), "y": {i for i in range(lcs.k) if any(lcs.D[i, j] != 0 for j in free)}}
    if cv.outputs is not None:
        Wu = cv.outputs.Wu
        out["w"] = {r for r in range(Wu.nrows()) if any(Wu[r, j] != 0 for j in free)}
    return out


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


#: the colour of impulse arrows and their texts (not a pair's colour: they are not lines of u)
_IMPULSE = "0.2"

#: line styles after the 10 colours of the default cycle are used up (q_0 and q_10 must differ)
_STYLES = ("-", "--", ":", "-.")


def plot_trajectory(traj, *, states: Sequence[Any] | None = None, constraints: Sequence[Any] | None = None,
                    panels: Sequence[str] | None = None, points: int = 800, label_events: int = 60,
                    figsize: tuple | None = None, title: str | None = None, components=None,
                    sources: bool = False):
    """Plot a trajectory: states, outputs, u and y on separate axes sharing t.  Returns the Figure.

    Parameters
    ----------
    traj : Trajectory
        The result of :func:`lcs_exact.simulate` (or anything with its public interface).
    states, components : sequence of int or str, optional
        Which states to draw (indices or names); by default the system's own states (the
        sources' states appended by a builder are left out unless ``sources``).
        ``components`` is an alias.
    constraints : sequence of int or str, optional
        Which complementarity pairs to draw in the u and y panels; all by default.
    panels : subset of ("x", "w", "u", "y"), optional
        ``"w"`` is the outputs the builder declared (a relay's w_j: ``traj.outputs``).  Default
        ``("x", "w")`` for a system with declared outputs, ``("x", "u", "y")`` otherwise.
    points : int
        Approximate number of sample times in total (spread over the phases by length, at least
        six per phase); each is a certified evaluation (``traj.sample``: 800 points take a
        fraction of a second).
    label_events : int
        At most this many events are labelled (where their labels have room); every event is
        marked by its line.
    figsize, title : optional
    sources : bool
        Draw the states of the sources too (``lcs.sources``: ``1``, ``sin(t)``, a relay's level).

    What is drawn: each continuous phase is its own line (no segment joins x(τ-) to x(τ+));
    where a state, u, y or w jumps, an open circle marks the left limit and a filled one the
    right limit (drawn only when the two are certainly different); an impulse u^0 δ (3.6) is an
    arrow through the u panel labelled ``impulse (name) = weight``; events are dashed lines labelled
    with the mode change where there is room (``∅→{0}``; ``start→{1}`` for a jump at t = 0;
    ``∅→∅ via {0}`` for an impact followed by lift-off: the re-initialization chain when it
    differs from the mode entered); each phase is shaded with its mode's colour, one legend
    entry per mode (``{0}: stop contact``).

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
    outputs = derived_outputs(lcs)
    sidx, hidden = _drawn_states(lcs, components if components is not None and states is None else states, sources)
    cidx = selected_indices(constraints, getattr(lcs, "constraint_names", ()), lcs.k, "constraint")
    panels = _drawn_panels(panels, outputs)
    if isinstance(points, bool) or not isinstance(points, int) or points < 1:
        raise InvalidArgument(f"points must be a positive integer, got {points!r}")
    phases = phase_intervals(traj)
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=figsize or (9, 2.4 * len(panels) + 0.8), layout="constrained")
    axes = list(axes[:, 0])
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    m = len(outputs.names) if outputs is not None else 0
    cv = Canvas(traj, lcs, fig, axes, dict(zip(panels, axes)),
                 {"x": sidx, "u": cidx, "y": cidx, "w": list(range(m))},
                 pens=[(palette[i % len(palette)], _STYLES[(i // len(palette)) % len(_STYLES)])
                       for i in range(max(lcs.n, lcs.k, m))],
                 colors=mode_colors(lcs, [ph.mode for ph in phases]), outputs=outputs,
                 hidden=[lcs.state_names[i] for i in hidden], batch=len(phases) > 48)
    total = sum(float(p.end) - float(p.start) for p in phases) or 1.0
    # per phase: u, y, w at its start and at its end, exact, for the jump markers
    ends = [_draw_phase(cv, ph, max(6, int(points * (float(ph.end) - float(ph.start)) / total)))
            for ph in phases]
    t_hi = float(phases[-1].end) if phases else float(traj.t_end)
    cv.t_hi = t_hi if t_hi > 0 else 1.0
    evs = sorted(traj.events, key=lambda e: float(e.time))
    _draw_events(cv, evs)
    _draw_linear_jumps(cv, phases, ends)
    cv.flush()
    for ax in axes:
        ax.set_xlim(-0.015 * cv.t_hi, 1.015 * cv.t_hi)
        ax.grid(True, lw=0.3, alpha=0.5)
    if getattr(lcs, "schedule", None) is not None:  # the schedule's phases as a band over the first axes
        draw_schedule(axes[0], lcs.schedule, cv.t_hi)
    _draw_legends(cv)
    _draw_title(cv, phases, title)
    _place_texts(cv, evs, label_events)
    return fig


def _drawn_states(lcs, states, sources: bool) -> tuple[list[int], list[int]]:
    """The states drawn (indices) and the sources' states left out (unless ``sources``)."""
    hidden: list[int] = []
    if states is None and not sources and getattr(lcs, "sources", None) is not None:
        hidden = sorted(lcs.sources.states)
        states = [i for i in range(lcs.n) if i not in hidden]
    return selected_indices(states, getattr(lcs, "state_names", ()), lcs.n, "state"), hidden


def _drawn_panels(panels, outputs) -> list[str]:
    """The panels drawn, in the order of PANELS; ("x", "w") with declared outputs by default."""
    if panels is None:
        panels = ("x", "w") if outputs is not None else ("x", "u", "y")
    if isinstance(panels, str) or any(p not in PANELS for p in panels):
        raise InvalidArgument(f"panels must be a subset of {PANELS}, got {panels!r}")
    panels = [p for p in PANELS if p in panels]
    if not panels:
        raise InvalidArgument(f"panels must contain at least one of {PANELS}")
    if "w" in panels and outputs is None:
        raise InvalidArgument("panel 'w' draws the outputs a builder declared (models.relay does); "
                              "this system declares none")
    return panels


def _draw_phase(cv: Canvas, ph: PhaseInterval, npts: int) -> dict | None:
    """A continuous phase: shaded with its mode's colour in every panel, its ``npts`` certified
    samples drawn in the states panel and the linear panels (an accumulation window: its
    flights).  Returns {panel: (value at its start, value at its end, undetermined components)},
    exact, or None when it has none."""
    fa, fb = float(ph.start), float(ph.end)
    cv.span(fa, fb, ph.mode)
    if ph.window is not None:  # infinitely many events: a line per scaled flight, exact values
        _draw_window(cv, ph, npts)
        return None
    traj = cv.traj
    ts = [_frac(fa + (fb - fa) * (j + 0.5) / npts) for j in range(npts)]  # inside the phase
    tt = [fa] + [float(t) for t in ts] + [fb]
    first = ph.start_event.state_after if ph.start_event is not None else \
        (traj.state(ph.start) if float(ph.start) > 0 else traj.x0)  # after an accumulation: x(T*)
    last = ph.end_event.state_before if ph.end_event is not None else traj.state(ph.end)
    balls = traj.sample(ts, 10)  # certified, one exponential sum per point
    if "x" in cv.ax_of:
        rows = [[float(b.mid()) for b in row] for row in balls]
        for pos, i in enumerate(cv.comps["x"]):
            cv.line("x", pos, tt, [float(first[i])] + [r[i] for r in rows] + [float(last[i])])
    return _draw_linear_panels(cv, ph, tt, first, last, balls)


def _draw_linear_panels(cv: Canvas, ph: PhaseInterval, tt: list, first, last, balls: list) -> dict | None:
    """w, u and y on one phase: linear in x there (:func:`_linear_maps`), from the same balls and
    exactly at the two ends (the values after the event that starts it and before the one that
    ends it: the values the jump markers compare); components that depend on inputs the state
    leaves free are not drawn (they have no value).  Returns those ends."""
    maps = _linear_maps(cv, ph.mode, _system_in_force(cv.lcs, ph))
    if maps is None:  # no mode: u and y are not defined there
        return None
    free = _undetermined(cv.traj, ph)  # inputs the state leaves free here
    cv.free_of[ph.mode] = cv.free_of.get(ph.mode, frozenset()) | free
    frees = _free_rows(cv, free)
    ends = {}
    for p in _LINEAR:
        if p not in cv.ax_of:
            continue
        M = maps[p]
        a, b = ProjectedVector(M, first), ProjectedVector(M, last)
        ends[p] = (a, b, frees[p])
        vals = [[float(c) for c in a]] + _apply(M, balls, ph.mode if p == "y" else ()) + [[float(c) for c in b]]
        for pos, i in enumerate(cv.comps[p]):
            if i in frees[p]:
                cv.any_free = True
                continue
            cv.line(p, pos, tt, [v[i] for v in vals])
            row = [M[i, j] for j in range(M.ncols())]
            for before, h in enumerate(cv.comps[p][:pos]):  # equal on the whole phase (rows of M), not 0
                if h not in frees[p] and any(row) and row == [M[h, j] for j in range(M.ncols())]:
                    cv.equal.setdefault((p, before, pos), set()).add(ph.mode)
    return ends


def _draw_window(cv: Canvas, ph: PhaseInterval, npts: int) -> None:
    """An accumulation window [t_k, T*): the scaled cycles of the proven law, each flight its own
    line (no segment across an event), until the flights are shorter than the plot resolves;
    states are certified balls (``traj.sample``), u, y and w the flight's mode applied to them."""
    fa, fb = float(ph.start), float(ph.end)
    width = fb - fa
    cuts = [fa]
    for ft in _flight_times(ph.window, 400):
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
            for pos, i in enumerate(cv.comps["x"]):
                cv.line("x", pos, tt, [r[i] for r in rows])
        for p in _LINEAR:
            if p in cv.ax_of:
                fast = getattr(cv.traj, "window_rows", None)  # balls and the flight's mode, else exact values
                vals = fast(ph.window, ts, p) if fast is not None else None
                if vals is None:
                    get = cv.traj.outputs if p == "w" else getattr(cv.traj, p)
                    vals = [[float(c) for c in get(t)] for t in ts]
                for pos, i in enumerate(cv.comps[p]):
                    cv.line(p, pos, tt, [v[i] for v in vals])


def _flight_times(window, count: int):
    """The first ``count`` event times of an accumulation window as floats, for cutting its lines:
    a geometric law's from the window's balls of them (``event_time_ball``: one closed expression
    each, where the exact sums of ``event_times`` grow with every cycle: 400 of a bouncing ball's
    took a minute), a window without a reference cycle's from ``event_times``; the samples inside
    each flight are exact."""
    if not getattr(window, "offsets", ()):
        yield from (float(t) for t in window.event_times(count))
        return
    for k in range(count):
        yield float(window.event_time_ball(k, 64).mid())


def _draw_events(cv: Canvas, evs: list) -> None:
    """Every event: its dashed line, the jumps of the states and the impulses (their texts and
    the events' labels are placed last, when the axes have their size)."""
    many = len(evs) > 48  # a dense run: thin light event lines, not a hatching
    times = [float(e.time) for e in evs]
    for ax in cv.axes:
        if many:  # one collection an axis (an axvline each autoscales the axes: 13 s for 700 events)
            ax.vlines(times, 0, 1, transform=ax.get_xaxis_transform(), colors="0.35", lw=0.4, linestyles="--",
                      alpha=0.35, zorder=1)
        else:
            for te in times:
                ax.axvline(te, color="0.35", lw=0.8, ls="--", zorder=1)
    for e, te in zip(evs, times):
        if "x" in cv.ax_of:  # the states that certainly jump: x(τ-) open, x(τ+) filled
            for pos, i in enumerate(cv.comps["x"]):
                xb, xa = e.state_before[i], e.state_after[i]
                if _certainly_different(xb, xa):
                    cv.any_jump = True
                    cv.jump("x", pos, te, xb, xa, (6, 5))
        _draw_impulses(cv, e, te)


def _draw_impulses(cv: Canvas, e, te: float) -> None:
    """The impulses u^0 δ at an event (3.6): dashed dark arrows through the whole u panel (a Dirac
    has no value on the scale of u, and the arrows are not lines of u), their texts
    ``impulse (stop) = 1.5`` placed last."""
    u0 = (getattr(e, "impulse", None) or {}).get(0)
    if u0 is None or "u" not in cv.ax_of:
        return
    shown = 0
    for i in cv.comps["u"]:
        v, nonzero = _component(u0, i)
        if not nonzero:
            continue
        x = te + 0.004 * cv.t_hi * shown  # side by side when several constraints act at once
        cv.ax_of["u"].annotate("", xy=(x, 0.97), xycoords=("data", "axes fraction"), xytext=(x, 0.0),
                               textcoords=("data", "axes fraction"),
                               arrowprops=dict(arrowstyle="-|>,head_length=0.6,head_width=0.3", color=_IMPULSE,
                                               lw=1.4, ls=(0, (4, 2)), shrinkA=0, shrinkB=0), zorder=4)
        cv.impulses.append((x, f"{impulse_label(cv.lcs, i)} = {v:.3g}"))
        shown += 1


def _draw_linear_jumps(cv: Canvas, phases: list, ends: list) -> None:
    """u, y and w jump wherever the mode changes: open/closed markers as for the state, for the
    components determined on both sides."""
    for prev, cur, ph in zip(ends, ends[1:], phases[1:]):
        if prev is None or cur is None:
            continue
        te = float(ph.start)
        for p, (start, _, free_here) in cur.items():
            end_before, free_before = prev[p][1], prev[p][2]
            for pos, i in enumerate(cv.comps[p]):
                if i in free_here or i in free_before:
                    continue
                left, right = end_before[i], start[i]
                if _certainly_different(left, right):
                    cv.any_jump = True
                    cv.jump(p, pos, te, left, right, (5, 4))


def _draw_legends(cv: Canvas) -> None:
    """Each panel's label and legend outside the data: its lines (names), the impulses and the
    gaps where they occur, the states not drawn; in the first panel the jump markers and the
    modes' shades, one entry per mode."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    lcs = cv.lcs
    for p, ax in cv.ax_of.items():
        ax.set_ylabel({"x": "state", "w": getattr(cv.outputs, "symbol", "w")}.get(p, p))
        if p == "x":
            labels = [state_label(lcs, i) for i in cv.comps["x"]]
        elif p == "w":
            labels = list(cv.outputs.names)
        else:
            labels = [pair_label(lcs, p, i) for i in cv.comps[p]]
        handles = [Line2D([], [], color=cv.pens[pos][0], ls=cv.pens[pos][1], lw=cv.width(p, pos), label=text)
                   for pos, text in enumerate(labels)]
        if p == "x" and cv.hidden:
            handles.append(Line2D([], [], color="none", label=f"(not drawn: {', '.join(cv.hidden)};\n"
                                                              " sources=True draws them)"))
        if p == "u" and cv.impulses:
            handles.append(Line2D([], [], color=_IMPULSE, ls=(0, (4, 2)), marker="^", ms=5,
                                  label="impulse δ (arrow not to scale)"))
        for (panel, a, b), modes in sorted(cv.equal.items()):
            if panel == p:  # the later line hides the earlier: say so
                handles.append(Line2D([], [], color="none", label=f"({labels[b]} = {labels[a]} in "
                                      + ", ".join(format_mode(m) for m in sorted(modes, key=mode_order)) + ")"))
        if p != "x" and cv.any_free:
            handles.append(Line2D([], [], color="none", label="(gaps: not determined by the state)"))
        if ax is cv.axes[0]:
            if cv.any_jump:
                handles += [Line2D([], [], ls="", marker="o", mfc="white", mec="0.3", label="left limit (τ−)"),
                            Line2D([], [], ls="", marker="o", color="0.3", label="right limit (τ+)")]
            modes = sorted(cv.colors, key=lambda m: (m is None, mode_order(m or ())))
            texts, notes = mode_texts(lcs, modes, cv.free_of)
            handles += [Patch(color=cv.colors[m], alpha=0.3, label=texts[m]) for m in modes]
            handles += [Line2D([], [], color="none", label=f"({note})") for note in notes]
        # a long legend in columns: it must not be taller than its panel
        lines = sum(h.get_label().count("\n") + 1 for h in handles)
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False,
                  ncol=1 + (lines - 1) // 14)


def _draw_title(cv: Canvas, phases: list, title: str | None) -> None:
    """The title (the system's name); a partial run says so and is marked where it stopped."""
    traj = cv.traj
    name = title if title is not None else (getattr(cv.lcs, "name", None) or "LCS trajectory")
    if getattr(traj, "partial", False):
        status = getattr(getattr(traj, "status", None), "value", None)
        name += f" (partial: {status})" if status else " (partial)"
        if phases:  # where the run stopped
            cv.stopped = float(phases[-1].end)
            for ax in cv.axes:
                ax.axvline(cv.stopped, color="#c44e52", lw=1.2, ls=":", zorder=2)
    cv.fig.suptitle(name, fontsize=11)


def _place_texts(cv: Canvas, evs: list, label_events: int) -> None:
    """The texts placed last, measured against the axes' final width: the events' labels above
    the first panel (four rows), the impulses' texts beside their arrows (three rows from the
    arrows' tips down); a text with no room is left out (its event or arrow stays drawn), and the
    axis label says how many events are labelled (:class:`~lcs_exact.figlabels.Rows`)."""
    fig, top = cv.fig, cv.axes[0]
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)  # the layout with legends and titles: the axes' width is final

    def width_pt(ax) -> float:
        return ax.get_position().width * fig.get_figwidth() * 72

    x_lo, x_hi = top.get_xlim()

    def place(ax, rows: Rows, x: float, text: str, off: float = 3, avoid=(), left=False, beyond: float = 0.0):
        """:meth:`Rows.place_text` of a text at the data coordinate x of the axes ax."""
        W = width_pt(ax)
        return rows.place_text((x - x_lo) / (x_hi - x_lo) * W, text_width(text, 8), W, off,
                               [(a - x_lo) / (x_hi - x_lo) * W for a in avoid], left, beyond)

    rows = Rows(4, gap=8)
    if cv.stopped is not None:  # "run stopped", right-aligned at the stop, in the lowest row
        stop = place(top, rows, cv.stopped, "run stopped", left=True)
        if stop is not None:
            top.annotate("run stopped", xy=(cv.stopped, 1.0), xycoords=("data", "axes fraction"),
                         xytext=(3 if stop[1] == "left" else -3, 2 + 10 * stop[0]), textcoords="offset points",
                         ha=stop[1], va="bottom", fontsize=8, color="#c44e52")
    # a label starts at its event's line; near the right end it reaches over the legends' column
    # (above the first legend), kept out of the layout so that the axes keep their width
    room = (1 - top.get_position().x1) * fig.get_figwidth() * 72 - 6
    labelled, in_layout_rows, outside_rows = 0, {-1}, set()
    for e in evs:
        if labelled == label_events:
            break
        text = event_text(e)
        spot = place(top, rows, float(e.time), text, beyond=room)
        if spot is None:
            continue
        labelled += 1
        label = top.annotate(text, xy=(float(e.time), 1.0), xycoords=("data", "axes fraction"),
                             xytext=(3 if spot[1] == "left" else -3, 2 + 10 * spot[0]), textcoords="offset points",
                             fontsize=8, ha=spot[1], va="bottom", color="0.2")
        label.set_in_layout(not spot[2])
        (outside_rows if spot[2] else in_layout_rows).add(spot[0])
    if max(outside_rows, default=-1) > max(in_layout_rows):  # the layout still makes room for that row
        top.annotate(" ", xy=(x_lo, 1.0), xycoords=("data", "axes fraction"), xytext=(0, 2 + 10 * max(outside_rows)),
                     textcoords="offset points", fontsize=8, va="bottom", alpha=0)
    if "u" in cv.ax_of and cv.impulses:
        ax_u, rows_u = cv.ax_of["u"], Rows(3)
        for x, text in sorted(cv.impulses):
            spot = place(ax_u, rows_u, x, text, 4, [a for a, _ in cv.impulses if a != x])
            if spot is not None:
                ax_u.annotate(text, xy=(x, 0.86), xycoords=("data", "axes fraction"),
                              xytext=(4 if spot[1] == "left" else -4, -11 * spot[0]), textcoords="offset points",
                              fontsize=8, ha=spot[1], va="center", color=_IMPULSE, zorder=7,
                              bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.85))
    notes = [f"{len(evs)} events (dashed), {labelled} labelled above"] if labelled < len(evs) else []
    accs = [a for a in getattr(cv.traj, "accumulations", ()) or () if hasattr(a, "time")]
    notes += [f"infinitely many events before t = {float(a.time):.4g}" for a in accs]
    cv.axes[-1].set_xlabel("t" + (f"    ({'; '.join(notes)})" if notes else ""))

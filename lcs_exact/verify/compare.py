"""Other solvers' solutions compared against certified trajectories.

* :func:`compare` measures a numerical solution (times t, rows of states X) against a certified
  trajectory (a fixture read back by :func:`lcs_exact.read_fixture`, or a live
  :class:`~lcs_exact.Trajectory`): the largest state error away from the events, and for each
  event the time at which the solver's data switches against the certified event time.
  :func:`convergence_order` is the least-squares slope of log error against log step over several
  solutions; :func:`read_solution_csv` reads a solver's solution (t, x_0..x_{n-1}).

Windows.  Every event of the reference is windowed, and so are the events an accumulation
implies (``accumulations[i].event_time(k)``: a bouncing ball's impacts after the last one listed,
up to its accumulation time T*), each widened to the solver's own switch for it
(:mod:`lcs_exact.solverevents`), so a time-stepper that is right away from events passes.

This module sits above the fixture reader and the engine (a fixture with rational x0 is
recomputed exactly between its samples); nothing imports it but :mod:`lcs_exact.testing`, the
package front and the CLI.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any, Sequence

from flint import arb, ctx, fmpq

from ..display import convergence_slope
from ..errors import FormatError, InvalidArgument, ShapeError
from ..dynamics import ball_number, number_rational, short_text, to_fraction
from ..io import read_fixture
from ..algebra import to_fmpq
from ..numbers import check_digits
from .solverevents import SEARCH_STEPS, event_windows, in_windows, signature

__all__ = ["read_solution_csv", "compare", "ComparisonReport", "EventComparison", "Violation", "convergence_order",
           "OVERSHOOT"]

_PREC = 128  # bits for the arithmetic on solver data (doubles) against references


# ---------------------------------------------------------------------------------------------
# solutions of other solvers
# ---------------------------------------------------------------------------------------------

def read_solution_csv(path: Any) -> tuple[list[str], list[list[str]]]:
    """Read a solver's solution: one row per time, columns t, x_0..x_{n-1} (comma- or whitespace-
    separated), an optional header line, ``#`` comments.  Returns (t, X) as decimal strings
    (read exactly later).

    Parameters
    ----------
    path : str or path
        The CSV file.

    >>> import tempfile, os
    >>> with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
    ...     _ = f.write("t,x1,x2\\n0,1,0\\n0.5,0.87,-0.47\\n")
    >>> read_solution_csv(f.name); os.unlink(f.name)
    (['0', '0.5'], [['1', '0'], ['0.87', '-0.47']])
    """
    p = Path(path)
    t, X, width = [], [], None
    with p.open(encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            fields = [f.strip() for f in (line.split(",") if "," in line else line.split())]
            if not t and width is None and not all(_is_number(f) for f in fields):
                width = len(fields)  # a header line
                continue
            if width is not None and len(fields) != width:
                raise ShapeError(f"{p}: line {lineno} has {len(fields)} columns, expected {width}")
            width = len(fields)
            if width < 2:
                raise ShapeError(f"{p}: line {lineno} has {width} column; expected t, x_0, ..., x_{{n-1}}")
            bad = next((f for f in fields if not _is_number(f)), None)
            if bad is not None:
                raise FormatError(f"{p}: line {lineno}: {bad[:30]!r} is not a number")
            huge = next((f for f in fields if not math.isfinite(float(f))), None)
            if huge is not None:  # a solver writes doubles: beyond their range is a broken file
                raise FormatError(f"{p}: line {lineno}: {huge[:30]!r} is beyond the range of a double")
            t.append(fields[0])
            X.append(fields[1:])
    if len(t) < 2:
        raise FormatError(f"{p}: a solution needs at least 2 rows (t, x_0, ..., x_{{n-1}}), found {len(t)}")
    return t, X


_NUMBER = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]{1,4})?")


def _is_number(text: str) -> bool:
    return _NUMBER.fullmatch(text) is not None


@dataclass(frozen=True)
class EventComparison:
    """One event against the solver's data: the certified time, the order j of the first
    discontinuous derivative (0: x jumps), the solver's switch time and the difference."""

    index: int
    time: arb
    order: int | None
    kind: str
    solver_time: float | None
    time_error: float | None  # solver_time - certified time
    time_exact: str | None = None

    def to_dict(self) -> dict:
        return {"index": self.index, "time": {**ball_number(self.time, 17), "exact": self.time_exact},
                "order": self.order,
                "kind": self.kind, "solver_time": self.solver_time, "time_error": self.time_error}


@dataclass(frozen=True)
class Violation:
    """The worst point outside the tolerance ``|X - x| <= atol + rtol |x|``: its time, component
    (index and name), the solver's value, the certified exact value and the error."""

    time: float
    component: int
    name: str
    solver: float
    exact: arb
    error: float
    tolerance: float

    def message(self, digits: int = 20) -> str:
        """The sentence an :class:`AssertionError` carries, the exact value to ``digits`` digits.

        Parameters
        ----------
        digits : int, optional
        """
        digits = check_digits(digits)
        exact = f"{self.exact.mid().str(digits, radius=False)} (+/- {float(self.exact.rad()):.3g})"
        return (f"the solution differs from the fixture by {self.error:.3g} > tolerance {self.tolerance:.3g} at "
                f"t = {self.time:.17g}, component {self.name}: solver {self.solver!r}, exact {exact}")


@dataclass(frozen=True)
class ComparisonReport:
    """The error of a solution against a fixture (:func:`compare`).

    ``max_error`` is a certified ball of ``max |x_i(t) - X_i|`` over the compared components and
    points (those outside the event windows), ``component_errors`` the same per compared
    component (``components``: their indices, ``names``: the fixture's state names of all n);
    ``events`` compares each event time with the solver's switch.  With tolerances (``atol``,
    ``rtol``) ``violation`` is the worst point outside them (None when every point is inside) and
    ``n_violations`` their number.

    Attributes
    ----------
    label : str
        The solution's name (``compare``'s ``label``).
    reference : str
        ``"samples"`` (the fixture's samples) or ``"exact"`` (an exact recomputation, or a Trajectory).
    n_points : int
        The solution's times.
    n_compared : int
        The points compared (outside the event windows, with a reference).
    n_in_windows : int
        The points left out inside event windows.
    n_unmatched : int
        The points left out without a reference (off the sample grid, x0 not rational).
    step : float
        The solution's largest step.
    window : float
        The half-width of the window left out around each event.
    window_rule : str
        Where ``window`` comes from (``event_tol``, or ``"2 x the largest step"``).
    max_error : arb
        Certified ball of ``max |x_i(t) - X_i|`` over the compared points and components.
    max_error_time : float or None
        Where the largest error is (None when nothing was compared).
    max_error_component : int or None
        Its component.
    component_errors : tuple of arb
        The largest error of each of ``components``.
    events : tuple of EventComparison
        Each event time against the solver's switch.
    certified : bool
        The reference is certified (no assumed sign).
    time_mismatch : float
        The largest distance of a solution time from the sample grid time it was matched to.
    names : tuple of str
        The names of all n states.
    n_beyond : int
        The points after ``last_time``, left out.
    last_time : arb or None
        The last time the reference covers (t_end, or where a partial run stopped).
    components : tuple of int
        The compared components' indices (the plant's states when X omits the sources).
    windows : tuple of (float, float)
        The merged intervals left out.
    atol : float or None
        The absolute tolerance (None: no tolerance given).
    rtol : float
        The relative tolerance.
    violation : Violation or None
        The worst point outside ``|X - x| <= atol + rtol |x|``.
    n_violations : int
        The points outside it.
    solver_end : float or None
        The solution's last time (against ``last_time``: coverage).
    """

    label: str
    reference: str
    n_points: int
    n_compared: int
    n_in_windows: int
    n_unmatched: int
    step: float
    window: float
    window_rule: str
    max_error: arb
    max_error_time: float | None
    max_error_component: int | None
    component_errors: tuple
    events: tuple
    certified: bool
    time_mismatch: float = 0.0
    names: tuple = field(default=())
    n_beyond: int = 0  # solver times after the last time the reference knows (t_end, or a partial run's end)
    last_time: arb | None = None
    components: tuple = field(default=())
    windows: tuple = field(default=())  # the merged intervals left out, (lo, hi) floats
    atol: float | None = None
    rtol: float = 0.0
    violation: Violation | None = None
    n_violations: int = 0
    solver_end: float | None = None  # the solver's last time (compared with last_time: coverage)

    def _name(self, i: int) -> str:
        return self.names[i] if i < len(self.names) else f"x_{i}"

    @property
    def passed(self) -> bool:
        """True when tolerances were given, some point was compared and none is outside them."""
        return self.atol is not None and self.n_compared > 0 and self.violation is None

    def to_dict(self) -> dict:
        """A JSON-ready dict (errors and event times as fixture numbers: value and bound)."""
        return {"label": self.label, "reference": self.reference, "points": self.n_points,
                "compared": self.n_compared, "in_event_windows": self.n_in_windows,
                "unmatched": self.n_unmatched, "step": self.step, "window": self.window,
                "window_rule": self.window_rule, "max_error": ball_number(self.max_error, 6),
                "max_error_time": self.max_error_time,
                "max_error_component": None if self.max_error_component is None else self._name(self.max_error_component),
                "component_errors": {self._name(i): ball_number(b, 6) for i, b in zip(self.components, self.component_errors)},
                "events": [e.to_dict() for e in self.events], "certified": self.certified,
                "time_mismatch": self.time_mismatch, "beyond_last_time": self.n_beyond,
                "last_time": None if self.last_time is None else ball_number(self.last_time, 17),
                "atol": self.atol, "rtol": self.rtol, "violations": self.n_violations,
                "solver_end": self.solver_end,
                "violation": None if self.violation is None else self.violation.message(17)}

    def to_pandas(self, what: str = "components"):
        """A pandas DataFrame: ``"components"`` (default) one row per compared component, indexed
        by its name, with the largest error (``max_error``, its certified upper bound
        ``max_error_bound``); ``"events"`` one row per event (certified time, kind, the solver's
        switch time and the difference).

        Parameters
        ----------
        what : {"components", "events"}, optional
            The table (above).

        >>> import lcs_exact as L
        >>> osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
        >>> tr = L.simulate(osc, [1, 0], 1)
        >>> ts = [k / 4 for k in range(5)]
        >>> r = compare(tr, ts, [[float(c) + 1e-3, float(v)] for c, v in tr.sample(ts)])
        >>> r.to_pandas().round(9)  # doctest: +NORMALIZE_WHITESPACE
                   max_error  max_error_bound
        component
        x_0            0.001            0.001
        x_1            0.000            0.000
        """
        try:
            import pandas as pd
        except ImportError:
            raise InvalidArgument("to_pandas needs pandas: pip install pandas (or lcs_exact[data])") from None
        if what == "components":
            rows = [(float(b.mid()), float(b.upper())) for b in self.component_errors]
            return pd.DataFrame(rows, columns=["max_error", "max_error_bound"],
                                index=pd.Index([self._name(i) for i in self.components], name="component"))
        if what == "events":
            return pd.DataFrame([{"time": float(e.time.mid()), "exact": e.time_exact, "kind": e.kind,
                                  "solver_time": e.solver_time, "time_error": e.time_error} for e in self.events],
                                index=pd.Index([e.index for e in self.events], name="event"))
        raise InvalidArgument(f"to_pandas: what must be 'components' or 'events', got {what!r}")

    def __repr__(self):
        return (f"<ComparisonReport {self.label!r}: max error {_sci(self.max_error)} over "
                f"{self.n_compared} points away from {len(self.events)} events, step {self.step:.3g}>")

    def __str__(self):
        ref = "the fixture's samples" if self.reference == "samples" else "the exact trajectory"
        lines = [f"{self.label}: against {ref}" + ("" if self.certified else " (fixture NOT certified)"),
                 f"  {self.n_points} points, largest step {self.step:.6g}; {self.n_compared} compared, "
                 f"{self.n_in_windows} in event windows |t - τ| <= {self.window:.3g} ({self.window_rule})"
                 + (f", {self.n_unmatched} not on the sample grid" if self.n_unmatched else "")
                 + (f", {self.n_beyond} after the reference's last time {short_text(self.last_time)} (left out)"
                    if self.n_beyond else "")]
        if self.max_error_time is not None:
            lines.append(f"  max state error {_sci(self.max_error)} at t = {self.max_error_time:.6g} "
                         f"in {self._name(self.max_error_component)}")
            lines.append("  per component: " + ", ".join(f"{self._name(i)} {_sci(b)}"
                                                         for i, b in zip(self.components, self.component_errors)))
        else:
            lines.append("  no point outside the event windows: no state error measured")
        if self.atol is not None:
            lines.append(f"  tolerance atol = {self.atol:.3g}, rtol = {self.rtol:.3g}: " +
                         ("every compared point inside" if self.violation is None else
                          f"{self.n_violations} point(s) outside; worst: {self.violation.message(12)}"))
        if self.events:
            lines.append(f"  {'event':>5}  {'certified time':<18}  {'kind':<16}  {'solver switch':>14}  "
                         f"{'time error':>11}  closed form")
            for e in self.events:
                st = "-" if e.solver_time is None else f"{e.solver_time:.10g}"
                te = "-" if e.time_error is None else f"{e.time_error:+.3e}"
                lines.append(f"  {e.index:>5}  {short_text(e.time):<18}  {e.kind:<16}  {st:>14}  {te:>11}  "
                             f"{e.time_exact or '-'}")
        return "\n".join(lines)


def _sci(b: arb) -> str:
    v = float(b.mid())
    return f"{v:.4g}" if v == 0 else f"{v:.4e}"


def _as_rows(X: Any, widths: Sequence[int], what: str) -> list:
    """The solver's rows, each of one of the accepted widths (all n states, or the plant's)."""
    rows = X.tolist() if hasattr(X, "tolist") else list(X)
    want = " or ".join(str(w) for w in dict.fromkeys(widths))
    width = None
    for i, r in enumerate(rows):
        if not hasattr(r, "__len__") or isinstance(r, str) or len(r) not in widths or (width is not None and len(r) != width):
            got = len(r) if hasattr(r, "__len__") and not isinstance(r, str) else "not a row"
            raise ShapeError(f"{what}: row {i} has {got} values, expected {want if width is None else width} "
                             f"(all n states, or the plant's states only)")
        width = len(r)
    return rows


def _reference_of(fixture: Any):
    """Normalise the reference: a FixtureTrajectory (path/dict/object) or a live Trajectory."""
    if hasattr(fixture, "to_fixture") and hasattr(fixture, "lcs"):  # a Trajectory from simulate
        return fixture, True
    return read_fixture(fixture), False


#: a solver's time beyond the reference's last time by at most this fraction of its largest step
#: is that last time (float grids such as ``np.arange(N + 1) * h`` overshoot t_end by rounding)
OVERSHOOT = Fraction(1, 10 ** 9)


def compare(fixture: Any, t: Any, X: Any, *, event_tol: Any = None, label: str = "solution",
            names: Sequence[str] = (), atol: Any = None, rtol: Any = 0.0) -> ComparisonReport:
    """Compare a numerical solution (times ``t``, states ``X``) against a certified trajectory.

    Parameters
    ----------
    fixture : path, dict, FixtureTrajectory or Trajectory
    t : 1-D sequence (numbers or decimal strings; floats by their shortest repr), nondecreasing
        (a repeated time is a jump: the rows before and after it).
    X : rows of state values, one row per time: all n states, or the plant's states only
        (``lcs.plant``: the sources appended by a builder left out).
    event_tol : the half-width w of the window excluded around each event (default: twice the
        solution's largest step), the events an accumulation implies included; each window also
        reaches the solver's own switch for its event (searched within 25 of its steps), so even
        ``event_tol=0`` leaves out the span between the exact event and the solver's.
    names : the components' names (default: the fixture's state names, ``x_0, x_1, ...``).
    atol, rtol : optional tolerances: the report's ``violation`` is the worst point with
        ``|X - x| > atol + rtol |x|`` (what :func:`lcs_exact.testing.assert_matches_fixture` raises).

    The reference at each time is the fixture's sample when the time is on the sample grid (to
    within 1e-9 of the grid step: solvers accumulate t in floating point), else the exact
    recomputation when x0 is rational (or the Trajectory itself); other times are left out and
    counted as ``n_unmatched``.  Times after the last time the reference covers (``t_end``, or
    where a partial run stopped) are left out and counted as ``n_beyond``, except those within
    1e-9 of a step of it (a float grid's rounding), which are compared there.  Error balls are
    certified against the solver's numbers as given.
    label : str, optional
        The solution's name in the report.

    Examples
    --------
    >>> import lcs_exact as L
    >>> osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])   # x'' = -x + u, 0 <= x _|_ u >= 0
    >>> tr = L.simulate(osc, [1, 0], 2)
    >>> ts = [k / 8 for k in range(17)]
    >>> X = [[float(c) + 1e-6, float(v)] for c, v in tr.sample(ts)]   # x_0 off by 1e-6
    >>> r = compare(tr, ts, X)
    >>> round(float(r.max_error.mid()), 12), r.events[0].kind, r.names
    (1e-06, 'jump', ('x_0', 'x_1'))
    """
    ref, live = _reference_of(fixture)
    lcs = ref.lcs
    n = lcs.n
    names = tuple(names) or tuple(lcs.state_names)
    tq, rows, comps = _solution(t, X, n, tuple(lcs.plant), label)
    tol = _tolerances(atol, rtol)
    with ctx.workprec(_PREC):
        Xb = [[arb(to_fmpq(v, f"{label} X[{i}][{c}]")) for c, v in enumerate(r)] for i, r in enumerate(rows)]
    tf = [float(v) for v in tq]
    step = max((b - a for a, b in zip(tq, tq[1:])), default=Fraction(0))
    window, rule = _event_window_width(event_tol, step)

    events = [_event_data(e, live) for e in ref.events]
    signatures = [signature(ev, lcs, comps) for ev in events]
    Xf = [_full_row([float(b.mid()) for b in r], comps, n) for r in Xb]
    windows, switches = event_windows(events, signatures, ref.accumulations, tf, Xf, window,
                                       max(window, SEARCH_STEPS * float(step)))
    inside = in_windows(tf, windows)
    last, known = _known_times(ref, live, tq, step)

    todo = [i for i in range(len(tq)) if not inside[i] and known[i]]
    refs, kind, mismatch, unmatched = _references(ref, live, [tq[i] for i in todo])
    err = _Errors(len(comps))
    with ctx.workprec(_PREC):
        for i, r in zip(todo, refs):
            if r is not None:
                err.add(i, Xb[i], r, comps, tol, tf[i], names)
        overall = arb(0)
        for e in err.components:
            overall = overall.max(e)
    best = err.best
    ev_cmp = tuple(_compare_event(j, ev, sig, sw) for j, (ev, sig, sw) in enumerate(zip(events, signatures, switches)))
    return ComparisonReport(
        label=label, reference=kind, n_points=len(tq), n_compared=err.compared,
        n_in_windows=sum(1 for i, w in enumerate(inside) if w and known[i]), n_unmatched=unmatched,
        step=float(step), window=window, window_rule=rule,
        max_error=overall, max_error_time=None if best[0] is None else tf[best[0]],
        max_error_component=best[1], component_errors=tuple(err.components), events=ev_cmp,
        certified=bool(ref.certified), time_mismatch=mismatch, names=names,
        n_beyond=len(tq) - sum(known), last_time=last, components=comps, windows=tuple(windows),
        atol=None if tol is None else tol[0], rtol=0.0 if tol is None else tol[1],
        violation=None if err.worst is None else err.worst[1], n_violations=err.violations,
        solver_end=float(tq[-1]))


def _solution(t: Any, X: Any, n: int, plant: tuple, label: str) -> tuple[list, list, tuple]:
    """The solver's times (exact fractions, checked nondecreasing), its rows of states, and the
    components they hold (all n states, or the plant's)."""
    ts = t.tolist() if hasattr(t, "tolist") else list(t)
    rows = _as_rows(X, (n, len(plant)), label)
    comps = tuple(range(n)) if not rows or len(rows[0]) == n else plant
    if len(ts) != len(rows):
        raise ShapeError(f"{label}: {len(ts)} times but {len(rows)} rows of states")
    if not ts:
        raise FormatError(f"{label}: a solution needs at least 1 point")
    tq = [to_fraction(v, f"{label} t[{i}]") for i, v in enumerate(ts)]
    if any(b < a for a, b in zip(tq, tq[1:])):
        i = next(i for i, (a, b) in enumerate(zip(tq, tq[1:])) if b < a)
        raise FormatError(f"{label}: times decrease at row {i + 1} ({float(tq[i])} then {float(tq[i + 1])})")
    return tq, rows, comps


def _event_window_width(event_tol: Any, step: Fraction) -> tuple[float, str]:
    """The half-width of the window left out around each event, and the rule that gave it."""
    if event_tol is None:
        return 2 * float(step), "2 x the largest step"
    window = float(to_fraction(event_tol, "event_tol"))
    if window < 0:
        raise FormatError(f"event_tol must be >= 0, got {event_tol}")
    return window, "event_tol"


def _known_times(ref: Any, live: bool, tq: list, step: Fraction) -> tuple[Any, list[bool]]:
    """The reference's last time and, per solver time, whether the reference covers it.  The
    reference is known on [0, last] only (t_end, or the end of a partial run): later times are
    left out and counted, but a float grid's rounding past a rational last time is forgiven (such
    a time in ``tq`` is moved to the last time, in place)."""
    last = ref.t_last.ball(30) if live else ref.final_time
    last_q = _rational_last(ref, live)
    with ctx.workprec(_PREC):
        for i, q in enumerate(tq):
            if last_q is not None and last_q < q <= last_q + OVERSHOOT * step:
                tq[i] = last_q
        known = [q <= last_q if last_q is not None else bool(arb(fmpq(q.numerator, q.denominator)) <= last)
                 for q in tq]
    return last, known


class _Errors:
    """The solver's errors against the reference, gathered point by point: per component the
    largest error ball, the largest error (its point, component, midpoint and ball), and with
    tolerances the worst violation and the number of points that violate them."""

    def __init__(self, m: int):
        self.components = [arb(0)] * m
        self.best: tuple = (None, None, None, arb(0))  # (index, component, mid, ball)
        self.worst: tuple | None = None                # (excess, Violation)
        self.violations = 0
        self.compared = 0

    def add(self, i: int, row: list, r: Any, comps: tuple, tol: tuple | None, time: float, names: tuple) -> None:
        """The errors of the solver's row i (balls) against the reference state r at ``time``."""
        self.compared += 1
        bad = None
        for c, comp in enumerate(comps):
            e = abs(row[c] - r[comp])
            self.components[c] = self.components[c].max(e)
            mid = float(e.mid())
            if self.best[2] is None or mid > self.best[2]:
                self.best = (i, comp, mid, e)
            if tol is not None:
                limit = tol[0] + tol[1] * abs(float(r[comp].mid()))
                excess = float(e.upper()) - limit
                if excess > 0:
                    bad = True
                    if self.worst is None or excess > self.worst[0]:
                        self.worst = (excess, Violation(time, comp, names[comp] if comp < len(names) else f"x_{comp}",
                                                        float(row[c].mid()), r[comp], mid, limit))
        self.violations += bool(bad)


def _tolerances(atol: Any, rtol: Any) -> tuple[float, float] | None:
    if atol is None:
        return None
    out = []
    for name, v in (("atol", atol), ("rtol", rtol)):
        try:
            f = float(v)
        except (TypeError, ValueError):
            raise InvalidArgument(f"{name} must be a number >= 0, got {v!r}") from None
        if isinstance(v, bool) or not math.isfinite(f) or f < 0:
            raise InvalidArgument(f"{name} must be a finite number >= 0, got {v!r}")
        out.append(f)
    return out[0], out[1]


def _full_row(vals: list, comps: tuple, n: int) -> list:
    """A solver row on all n components (0 where the solver gave none: the sources, which are
    continuous and take no part in the switch detection)."""
    if len(comps) == n:
        return vals
    row = [0.0] * n
    for c, v in zip(comps, vals):
        row[c] = v
    return row


def _rational_last(ref: Any, live: bool) -> Fraction | None:
    """The reference's last time as a Fraction when it is rational (t_end of a complete run)."""
    if live:
        q = ref.t_last.known_rational()
        return None if q is None else Fraction(int(q.p), int(q.q))
    return number_rational(ref.data["final_time"])


def _event_data(e: Any, live: bool) -> tuple:
    """(time, mode_before, mode_after, x-, x+, closed form of the time) with balls, from a live
    Event or a FixtureEvent."""
    if live:
        cf = e.time.closed_form
        return (e.time.ball(20), e.mode_before, e.mode_after, tuple(c.ball(20) for c in e.state_before),
                tuple(c.ball(20) for c in e.state_after), None if cf is None else str(cf))
    return e.time, e.mode_before, e.mode_after, e.state_before, e.state_after, e.time_exact


def _references(ref: Any, live: bool, times: list) -> tuple:
    """Certified reference states at ``times``: (list of ball rows or None, kind, max |Δt| of
    the grid matching, number of times without a reference)."""
    if live:
        return ref.sample(times, 20), "exact", 0.0, 0
    if not ref.digested and ref.can_recompute:
        ref.verify()  # no digest vouches for the samples: the recomputed run checks them
    step = ref.sample_step
    matched: list = []
    mismatch = 0.0
    if step is not None and ref.samples:
        tol = step * Fraction(1, 10 ** 9)
        by_time = {s.t: s for s in ref.samples}
        for t in times:
            k = round(t / step)
            s = by_time.get(k * step)
            if s is not None and abs(t - k * step) <= tol:
                matched.append(s.x)
                mismatch = max(mismatch, float(abs(t - k * step)))
            else:
                matched.append(None)
    else:
        matched = [None] * len(times)
    missing = [i for i, m in enumerate(matched) if m is None]
    if not missing:
        return matched, "samples", mismatch, 0
    if ref.can_recompute:
        exact = ref.exact.sample([times[i] for i in missing], 20)
        for i, row in zip(missing, exact):
            matched[i] = row
        return matched, "exact", mismatch, 0
    if len(missing) == len(times) and times:
        grid = "no samples" if step is None else f"samples every {step}"
        raise FormatError(f"{ref.source}: none of the solution's times is on the fixture's grid ({grid}) "
                          f"and x0 is not rational (no exact recomputation): write the fixture with "
                          f"a sample step that divides the solver's times")
    return matched, "samples", mismatch, len(missing)


def _compare_event(j: int, ev: tuple, sig: tuple | None, found: float | None) -> EventComparison:
    tau_b, mb, ma, xb, xa, cf = ev
    tau = float(tau_b.mid())
    if mb is None:
        return EventComparison(j, tau_b, 0, "initial jump", None, None, cf)
    if sig is None:
        return EventComparison(j, tau_b, None, "no visible jump", None, None, cf)
    order = sig[0]
    kind = {0: "jump", 1: "kink (x' jumps)"}.get(order, f"x^({order}) jumps")
    return EventComparison(j, tau_b, order, kind, found, None if found is None else found - tau, cf)


def convergence_order(reports: Sequence[ComparisonReport], steps: Sequence[Any] | None = None) -> float:
    """The least-squares slope p of log(max error) against log(step): error ~ C h^p.

    ``steps`` defaults to each report's largest step.

    Parameters
    ----------
    reports : sequence of ComparisonReport
        One report per step size.
    steps : sequence of numbers, optional
        The step sizes h.

    >>> class R:  # anything with max_error; the errors of a second-order method
    ...     def __init__(self, e): self.max_error = arb(e)
    >>> round(convergence_order([R(4e-4), R(1e-4), R(2.5e-5)], [0.02, 0.01, 0.005]), 9)
    2.0
    """
    reports = list(reports)
    hs = [r.step for r in reports] if steps is None else [float(to_fraction(h, "step")) for h in steps]
    if len(hs) != len(reports):
        raise ShapeError(f"{len(reports)} reports but {len(hs)} steps")
    return convergence_slope(hs, [float(r.max_error.mid()) for r in reports])

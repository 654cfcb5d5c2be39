"""Scheduled switching: LCS data that change at known times (a PWM switch, sampled-data control).

A *schedule* is a sequence of phases (duration d_k, LCS_k, reset R_k) that run one after the other
from t = 0, repeated every period P = d_0 + ... + d_{p-1} when the schedule is periodic.  On
[s_k, s_k + d_k) the state follows the LCS (4.1) of phase k, with every part of the paper in
force (mode selection, re-initialization, events); at a switch time s_k (an exact rational) the
state is carried over continuously, optionally mapped by the phase's reset x := R_k x (a held
input w := K x(t_k) of sampled-data control), and Algorithm 7.1 goes on in LCS_k from there:
where the state is not consistent with LCS_k's modes, the jump P_I of section 4.2 happens at the
switch time.  Every switch is an event (the dynamics change there), recorded with the trigger
``"schedule"``.

All phases share the state x (the same n and state names) and the same number k of
complementarity pairs (each phase's C and D are its own rows: a diode whose circuit changes
around it).  :class:`ScheduledLCS` is an :class:`~lcs_exact.LCS` (the first phase's data, for
names and shapes) that carries the :class:`Schedule`; :func:`lcs_exact.simulate` runs it.

* :func:`scheduled` builds one from phases;
* :func:`sampled` builds sampled-data control: x' = A x + B u + Bh w with w(t) = K x(t_k) held on
  [t_k, t_k + T), t_k = k T, as an appended state w (w' = 0) reset to K x at every t_k.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any, Iterator, Sequence

from flint import fmpq, fmpq_mat

from ..phases import autonomous_block
from ..errors import InvalidArgument, ShapeError, Unsupported
from ..algebra import hstack, identity, to_fmpq, to_matrix, vstack, zeros
from ..system import LCS, WellPosedness

__all__ = ["SchedulePhase", "Schedule", "ScheduledLCS", "scheduled", "sampled", "HeldInputs", "shares_clock"]


@dataclass(frozen=True)
class SchedulePhase:
    """One phase of a schedule: its ``duration`` (a positive rational; None for the last phase of
    a schedule that is not periodic: it lasts to t_end), its ``lcs`` and the ``reset`` applied to
    the state when it starts (an n x n rational matrix, or None: the state carries over)."""

    duration: fmpq | None
    lcs: LCS
    reset: fmpq_mat | None = None


@dataclass(frozen=True)
class Schedule:
    """The phases, and the period (their total duration) when they repeat, else None."""

    phases: tuple
    period: fmpq | None = None

    def segments(self) -> Iterator[tuple[fmpq, fmpq | None, SchedulePhase]]:
        """(start, end, phase) of every segment from t = 0 on, in order (end None: to t_end).

        >>> two = scheduled([(1, LCS([[0]], [[1]], [[1]], [[0]])), ("1/2", LCS([[-1]], [[1]], [[1]], [[0]]))], period="3/2")
        >>> [(str(s), str(e)) for s, e, _ in __import__("itertools").islice(two.schedule.segments(), 4)]
        [('0', '1'), ('1', '3/2'), ('3/2', '5/2'), ('5/2', '3')]
        """
        start = fmpq(0)
        while True:
            for ph in self.phases:
                end = None if ph.duration is None else start + ph.duration
                yield start, end, ph
                if end is None:
                    return
                start = end
            if self.period is None:
                return

    def system_at(self, t: float) -> LCS:
        """The LCS in force at a time strictly inside a segment (a float: for drawing, where a
        phase's middle never lies on a switch)."""
        for _, end, ph in self.segments():
            if end is None or t < float(end):
                return ph.lcs
        return self.phases[-1].lcs

    def switch_times(self, t_end: Any) -> list[fmpq]:
        """The switch times s with 0 < s < t_end (rational t_end, or an exact real's upper bound)."""
        T = to_fmpq(t_end, "t_end")
        out = []
        for start, _, _ in self.segments():
            if start >= T:
                break
            if start > 0:
                out.append(start)
        return out


def shares_clock(schedule: Schedule) -> bool:
    """The sources' clock (:mod:`lcs_exact.clock`: z(t) = e^{S t} z(0) in absolute time) holds
    across the schedule: every phase has the same autonomous block with the same S, and no reset."""
    phases = schedule.phases
    if any(p.reset is not None for p in phases):
        return False
    J = autonomous_block(phases[0].lcs.A, phases[0].lcs.B)
    return all(autonomous_block(p.lcs.A, p.lcs.B) == J and
               all(p.lcs.A[i, j] == phases[0].lcs.A[i, j] for i in J for j in J) for p in phases)


class HeldInputs:
    """x -> (embed(x), K embed(x)): the full initial state of a sampled-data system (the held
    input w starts at K x(0)); ``n`` is the size of the plant's state (what ``embed`` takes)."""

    def __init__(self, lcs: LCS, K: fmpq_mat):
        self.lcs, self.K = lcs, K
        self.n = len(lcs.plant)

    def __call__(self, x: Any) -> fmpq_mat:
        full = self.lcs.embed(x)
        return vstack(full, self.K * full)

    def __repr__(self):
        return f"HeldInputs({self.lcs.name or 'lcs'}, K)"


class ScheduledLCS(LCS):
    """An LCS whose data switch at scheduled times (module docstring): the first phase's A, B, C,
    D, names and embedding, and ``schedule`` (:class:`Schedule`), which
    :func:`lcs_exact.simulate` follows."""

    def __init__(self, schedule: Schedule, *, name: str | None = None):
        first = schedule.phases[0].lcs
        super().__init__(first.A, first.B, first.C, first.D, name=name,
                         state_names=first.state_names, constraint_names=first.constraint_names,
                         embedding=first.embedding, restitution=first.restitution, roles=first.roles)
        self.schedule = schedule

    def well_posedness(self):
        """Theorem 6.3 for every phase: the report of the first phase whose leading matrices are
        not both P-matrices (its reasons prefixed with the phase), else phase 0's (every phase is
        well-posed: each event inside a phase has multiplicity <= 1)."""
        return self._schedule_report

    @cached_property
    def _schedule_report(self) -> WellPosedness:
        reports = [p.lcs.well_posedness() for p in self.schedule.phases]
        bad = next(((k, r) for k, r in enumerate(reports) if not r), None)
        return reports[0] if bad is None else \
            replace(bad[1], reasons=tuple(f"phase {bad[0]} of the schedule: {x}" for x in bad[1].reasons)
                    or (f"phase {bad[0]} of the schedule is not well-posed",))

    def to_statespace(self):
        """Refused: python-control's StateSpace holds one linear system, a schedule several."""
        raise Unsupported("a ScheduledLCS switches between several linear systems: take one phase's, "
                          "lcs.schedule.phases[k].lcs.to_statespace()")

    def __repr__(self):
        parts = ", ".join(f"({'None' if p.duration is None else str(p.duration)!s}, <LCS n={p.lcs.n} k={p.lcs.k}>"
                          + (", reset)" if p.reset is not None else ")") for p in self.schedule.phases)
        period = "" if self.schedule.period is None else f", period={str(self.schedule.period)!r}"
        return f"<ScheduledLCS [{parts}]{period}>"

    def __str__(self):
        return repr(self)


def _duration(d: Any, i: int, last: bool) -> fmpq | None:
    if d is None:
        if not last:
            raise InvalidArgument(f"phase {i}: only the last phase of a schedule that does not repeat may have "
                                  "duration None (it lasts to t_end)")
        return None
    q = to_fmpq(d, f"the duration of phase {i}")
    if q <= 0:
        raise InvalidArgument(f"phase {i}: a duration must be > 0, got {q}")
    return q


def scheduled(phases: Sequence, period: Any = None, *, name: str | None = None) -> ScheduledLCS:
    """An LCS whose data switch at scheduled rational times (module docstring).

    Parameters
    ----------
    phases : sequence of (duration, lcs) or (duration, lcs, reset)
        The phases in order from t = 0: a positive rational duration, an :class:`~lcs_exact.LCS`
        (all with the same n and k), and optionally a reset, an n x n rational matrix applied to
        the state when the phase starts.  Without ``period`` the last phase lasts to t_end (its
        duration may be None; a duration given to it is its time before it goes on anyway).
    period : rational or True, optional
        When given, the phases repeat with this period, which must be the sum of the durations
        (``True``: the sum itself).
    name : str, optional

    Returns
    -------
    ScheduledLCS

    Examples
    --------
    A capacitor charged through a resistor while a switch is on (v' = 1 - v for 1/2 of each
    period 1), discharging otherwise (v' = -v), clamped at 0 by a diode (never active here):

    >>> import lcs_exact as L
    >>> on = L.LCS([[-1, 1], [0, 0]], [[1], [0]], [[1, 0]], [[0]])    # state (v, 1): a constant source
    >>> off = L.LCS([[-1, 0], [0, 0]], [[1], [0]], [[1, 0]], [[0]])
    >>> pwm = scheduled([("1/2", on), ("1/2", off)], period=1)
    >>> tr = L.simulate(pwm, [0, 1], 2)
    >>> [e.time.label() for e in tr.events], tr.events[0].triggers
    (['1/2', '1', '3/2'], ('schedule',))
    >>> tr.state("1/2")[0].closed_form     # 1 - e^{-1/2}
    1 - exp(-1/2)
    """
    if isinstance(phases, (str, bytes)) or not hasattr(phases, "__iter__"):
        raise InvalidArgument(f"phases must be a sequence of (duration, lcs) pairs, got {type(phases).__name__}")
    items = list(phases)
    if not items:
        raise InvalidArgument("a schedule needs at least one phase")
    out = []
    for i, item in enumerate(items):
        if not isinstance(item, (tuple, list)) or len(item) not in (2, 3):
            raise InvalidArgument(f"phase {i} must be (duration, lcs) or (duration, lcs, reset), got {item!r}")
        lcs = item[1]
        if not isinstance(lcs, LCS) or isinstance(lcs, ScheduledLCS):
            raise InvalidArgument(f"phase {i}: the second entry must be an LCS, got {type(lcs).__name__}")
        first = out[0].lcs if out else lcs
        if (lcs.n, lcs.k) != (first.n, first.k):
            raise ShapeError(f"phase {i}: n = {lcs.n}, k = {lcs.k}, but phase 0 has n = {first.n}, k = {first.k} "
                             "(every phase shares the state and the number of complementarity pairs)")
        if lcs.state_names != first.state_names:
            raise InvalidArgument(f"phase {i}: states {lcs.state_names} differ from phase 0's {first.state_names} "
                                  "(every phase shares the state: give the phases the same state_names)")
        reset = None if len(item) == 2 or item[2] is None else to_matrix(item[2], f"the reset of phase {i}", (lcs.n, lcs.n))
        out.append(SchedulePhase(_duration(item[0], i, i == len(items) - 1 and period is None), lcs, reset))
    P = None
    if period is not None:
        total = sum((p.duration for p in out), fmpq(0))
        P = total if period is True else to_fmpq(period, "period")
        if P != total:
            raise InvalidArgument(f"period = {P} is not the sum of the phases' durations ({total}): the phases "
                                  "repeat with their own total length")
    return ScheduledLCS(Schedule(tuple(out), P), name=name)


def _spread(M: fmpq_mat, plant: list, n: int, rows: bool) -> fmpq_mat:
    """M given on the plant's states only, as rows (Bh) or columns (K) of the full state (zeros
    for the sources' states)."""
    out = fmpq_mat(n, M.ncols()) if rows else fmpq_mat(M.nrows(), n)
    for r in range(M.nrows()):
        for c in range(M.ncols()):
            if rows:
                out[plant[r], c] = M[r, c]
            else:
                out[r, plant[c]] = M[r, c]
    return out


def sampled(lcs: LCS, Bh: Any, K: Any, period: Any, *, name: str | None = None,
            held_names: Sequence[str] | None = None) -> ScheduledLCS:
    """Sampled-data control of an LCS: x' = A x + B u + Bh w with w(t) = K x(t_k) held on
    [t_k, t_k + period), t_k = k period.

    The held input is an appended state w (w' = 0: nothing moves it between samples) reset to
    K x at every sampling time t_k, t_0 = 0 included, exactly (a schedule of one phase, repeated,
    with the reset x := [[I, 0], [K, 0]] x).  ``lcs.embed`` of the result takes the plant's state
    and appends the sources' states and w(0) = K x(0).

    Parameters
    ----------
    lcs : LCS
        The plant (with its sources, if a builder appended any: K reads the full state).
    Bh : n x m matrix
        How the held input enters x' (or len(plant) x m: rows for the plant's states only).
    K : m x n matrix
        The control law, read on the full state x of ``lcs`` (or m x len(plant): on the plant's
        states only, the sources' states not read).
    period : positive rational
        The sampling period.
    name : str, optional
    held_names : sequence of m str, optional
        Names of the held inputs (default ``w_0, ..., w_{m-1}``).

    Examples
    --------
    A mass pushed back to 0 by a sampled proportional force, against a stop at -1 (x' = v,
    v' = u + w, w = -x(t_k) held for 1/2):

    >>> import lcs_exact as L
    >>> plant = L.LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]], state_names=["x", "v"])
    >>> loop = sampled(plant, [[0], [1]], [[-1, 0]], "1/2")
    >>> loop.state_names, loop.embed([1, 0]).transpose()
    (('x', 'v', 'w_0'), [1, 0, -1])
    >>> tr = L.simulate(loop, loop.embed([1, 0]), 1)
    >>> [e.time.label() for e in tr.events], tr.state("1/2")[2].rational()     # w(1/2) = -x(1/2) = -7/8
    (['1/2'], -7/8)
    """
    if not isinstance(lcs, LCS) or isinstance(lcs, ScheduledLCS):
        raise InvalidArgument(f"lcs must be an LCS, got {type(lcs).__name__}")
    n, plant = lcs.n, list(lcs.plant)
    Bh = to_matrix(Bh, "Bh")
    if Bh.nrows() == len(plant) < n:  # rows for the plant's states only: none for the sources'
        Bh = _spread(Bh, plant, n, rows=True)
    Bh = to_matrix(Bh, "Bh", (n, None))
    m = Bh.ncols()
    if m == 0:
        raise ShapeError("Bh has no columns: sampled-data control needs at least one held input")
    K = to_matrix(K, "K")
    if K.ncols() == len(plant) < n:  # the law on the plant's states only
        K = _spread(K, plant, n, rows=False)
    K = to_matrix(K, "K", (m, n))
    T = to_fmpq(period, "period")
    if T <= 0:
        raise InvalidArgument(f"period must be > 0, got {T}")
    names = tuple(f"w_{j}" for j in range(m)) if held_names is None else tuple(held_names)
    if len(names) != m:
        raise ShapeError(f"held_names has {len(names)} names, expected {m}")
    A = vstack(hstack(lcs.A, Bh), zeros(m, n + m))
    B = vstack(lcs.B, zeros(m, lcs.k))
    C = hstack(lcs.C, zeros(lcs.k, m))
    reset = vstack(hstack(identity(n), zeros(n, m)), hstack(K, zeros(m, m)))
    plant = LCS(A, B, C, lcs.D, name=name if name is not None else lcs.name, state_names=lcs.state_names + names,
                constraint_names=lcs.constraint_names, embedding=HeldInputs(lcs, K), restitution=lcs.restitution,
                roles=lcs.roles)
    return ScheduledLCS(Schedule((SchedulePhase(T, plant, reset),), T), name=plant.name)

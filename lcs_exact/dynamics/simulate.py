"""Algorithm 7.1: mode selection, re-initialization, continuous phases and events, exactly.

    Initialization  z := x0, t := 0
    Step one        select I in S(z) (the smallest admissible mode, Remark 4.8)
    Step two        z in V_I ?  yes: step four;  no: step three
    Step three      z := P_I z, go to step one          (the re-initialization chain (4.9))
    Step four       x(t) = e^{A_I t} z, u_I = F_I x      (:mod:`lcs_exact.phase`)
    Step five       theta(z, I) by certified root isolation; t := t + theta, z := x(theta-); repeat

Each event state is anchored: its ball is computed at the run's working precision when the event
is found (:meth:`~lcs_exact.balls.Policy.working_prec`), which grows by the accuracy the run
measures as lost, so the cost of an event does not grow with its index and refinement walks
forward from the nearest anchor (:func:`lcs_exact.nodes.evaluate`).

Stops: deadlock (S(z) = empty) -> :class:`Deadlock`; a re-initialization chain that does not end
-> :class:`ZenoDetected`; event times accumulating (geometrically shrinking phases with the limit
before t_end, Remark 4.11) -> :class:`ZenoDetected`; ``max_events`` / ``time_limit`` ->
:class:`LimitExceeded`; an undecidable sign -> :class:`UnresolvedSign`.  Each such error carries
the partial :class:`~lcs_exact.trajectory.Trajectory` in ``.trajectory``.
"""
from __future__ import annotations

import decimal
import time as _time
from typing import Any, Literal, overload

from flint import arb, fmpq, fmpq_mat

from ..numbers import (ACCURACY_HEADROOM, Policy, accuracy_bits, digits_to_bits, dyadic_lower, dyadic_upper, workprec)
from ..errors import (Deadlock, HorizonExceeded, IllPosed, LCSError, LimitExceeded, TimeLimitExceeded,
                     UnresolvedSign, ZenoDetected)
from ..accumulations import (BOUNCE_PATIENCE, Accumulation, BounceWindow, CollapseWindow, ReferenceStates, ScaledCycle,
                             bounce_cycle, bounce_window, cascade_bound, check_accumulation, collapse_cycle,
                             geometric_law, prove_collapse, shrinking_cycles, symmetry_exponents, turns_suspected)
from ..phases import (Branches, Event, ExactStates, Phase, PhaseFunction, PhaseRecord, SourceClock, Status, Trajectory,
                      apply_forms, event_step, next_event, phase_horizon)
from .schedule import shares_clock
from ..algebra import vstack
from ..numbers import RationalReal
from ..numbers import ExactVector, as_exact_vector, homogenized
from ..modes import (format_mode, initial_solution, initial_solution_groups, mode_order, state_groups,
                     undetermined_inputs)
from ..interfaces import AccumulationWindow
from .options import progress_bar, run_options

__all__ = ["simulate", "simulate_branches"]


@overload
def simulate(lcs, x0: Any, t_end: Any, digits: int = 30, *, max_events: int = 1000, time_limit: float | None = None,
             allow_unresolved: bool = False, closed_forms: Any = "lazy", zeno: str = "cross",
             branches: Literal["unique"] = "unique", max_prec: int | None = None, progress: bool = False) -> Trajectory: ...


@overload
def simulate(lcs, x0: Any, t_end: Any, digits: int = 30, *, max_events: int = 1000, time_limit: float | None = None,
             allow_unresolved: bool = False, closed_forms: Any = "lazy", zeno: str = "cross",
             branches: Literal["all"], max_prec: int | None = None, progress: bool = False) -> Branches: ...


@overload
def simulate(lcs, x0: Any, t_end: Any, digits: int = 30, *, max_events: int = 1000, time_limit: float | None = None,
             allow_unresolved: bool = False, closed_forms: Any = "lazy", zeno: str = "cross", branches: str = "unique",
             max_prec: int | None = None, progress: bool = False) -> Trajectory | Branches: ...


def simulate(lcs, x0: Any, t_end: Any, digits: int = 30, *, max_events: int = 1000,
             time_limit: float | None = None, allow_unresolved: bool = False,
             closed_forms: Any = "lazy", zeno: str = "cross", branches: str = "unique",
             max_prec: int | None = None, progress: bool = False) -> Trajectory | Branches:
    """Run Algorithm 7.1 from x0 on [0, t_end] and return the exact :class:`Trajectory`
    (:class:`~lcs_exact.trajectory.Branches` with ``branches="all"``: :func:`simulate_branches`).

    Parameters
    ----------
    lcs : LCS
    x0 : vector
        Rational (any input LCS accepts: a flat list or a column, not a string, dict or set) or
        an exact vector such as ``expm_action(A, -1, v)``.
    t_end : rational or exact real, >= 0
        Any horizon (a rational has at most 65,536 bits, ``MAX_RATIONAL_BITS``).  Each phase is
        searched for its next event within the horizon limits of docs/limits.md for its own
        rates (10^6 of its slowest, 10^12 of its fastest time constants); a phase without an
        event within them stops the run with :class:`HorizonExceeded` (a LimitExceeded), its
        trajectory computed up to there.
    digits : int
        Correct significant digits promised for every reported number (1..10000,
        ``balls.MAX_DIGITS``).  Evaluation is on demand; sign decisions refine up to
        ``max_prec`` bits (default max(4096, 8 * bits(digits)); at most 2^20).
    max_events, time_limit : limits (an int >= 0; seconds >= 0 or None); reaching one raises
        :class:`LimitExceeded` with the partial trajectory in ``.trajectory``.
    allow_unresolved : if True, an undecidable sign is assumed zero, recorded in
        ``traj.assumptions``, and the result is not ``certified``; otherwise UnresolvedSign.
    closed_forms : ``"lazy"`` (default): a closed form is proven on the first access of
        ``.closed_form`` (event times, states); True or ``"eager"`` (the same): as lazy, and the
        closed form of every phase's duration is proven at its event, as the run goes (its cost
        paid by the run); False or ``"off"`` (the same): none is looked for (``closed_form`` is
        None, ``closed_form_status`` "off").  Any other value is an InvalidArgument.
    zeno : ``"cross"`` (default): a right-accumulation of events (Remark 4.11) whose geometric law
        is proven exactly (:mod:`lcs_exact.accumulation`) is crossed: recorded in
        ``traj.accumulations``, and the run continues from the limit state; an accumulation
        without a proven law stops with :class:`ZenoDetected` (a certified lower bound of its
        time).  ``"stop"``: every accumulation stops with ZenoDetected.
    branches : ``"unique"`` (default): where S(z) holds several initial solutions that give
        different trajectories (outside Theorem 6.3), raise :class:`IllPosed` with
        ``.alternatives`` (each mode with its initial solution) and the partial trajectory.
        ``"all"``: follow every branch and return :class:`~lcs_exact.trajectory.Branches`, as
        :func:`simulate_branches` (the same call, typed as such).
    progress : if True, a progress bar (tqdm) over [0, t_end], advanced at every event (needs
        tqdm: ``pip install tqdm``, or ``lcs_exact[sweep]``).
    max_prec : int, optional
        The ceiling of sign refinement in bits (see ``digits``); 64..2^20, None: the default.

    Raises
    ------
    InvalidArgument, ShapeError, NotRational
        Before anything is computed, for a bad option, x0 or t_end (the message names it).

    Examples
    --------
    >>> from lcs_exact.models import two_carts
    >>> tr = simulate(two_carts(), [0, 1, -1, 0], 1)
    >>> tr.events[0].state_after
    (0, 1, 0, 0)
    """
    opts = run_options(lcs, x0, t_end, digits, max_events=max_events, time_limit=time_limit,
                       allow_unresolved=allow_unresolved, closed_forms=closed_forms, zeno=zeno, branches=branches,
                       max_prec=max_prec, progress=progress)
    T, policy = opts.t_end, opts.policy
    z0 = as_exact_vector(x0, lcs.n)
    bar = progress_bar(T) if opts.progress else None
    if opts.branches == "all":
        if bar is not None:
            bar.close()  # a bar over [0, t_end] says nothing of branches re-run from the start
        return _all_branches(lcs, z0, T, digits, max_events, policy, zeno)
    try:
        return _run(lcs, z0, T, digits, max_events, policy, zeno, "unique", [], bar)
    finally:
        policy.deadline.disarm()
        if bar is not None:
            bar.close()


def simulate_branches(lcs, x0: Any, t_end: Any, digits: int = 30, *, max_events: int = 1000,
                      time_limit: float | None = None, allow_unresolved: bool = False, closed_forms: Any = "lazy",
                      zeno: str = "cross", max_prec: int | None = None, progress: bool = False) -> Branches:
    """Every solution from x0 on [0, t_end]: ``simulate(..., branches="all")``, typed as such.
    Where S(z) holds initial solutions that give different trajectories (outside Theorem 6.3),
    every branch is followed (at most MAX_BRANCHES, each within ``max_events``, all within
    ``time_limit``), each with its ``.choices``: one solution, exactly, none *the* solution
    (:class:`~lcs_exact.trajectory.Branches`).

    Parameters
    ----------
    lcs, x0, t_end, digits, max_events, time_limit, allow_unresolved, closed_forms, zeno, max_prec, progress
        As for :func:`simulate` (checked the same way).

    Examples
    --------
    >>> import lcs_exact as L
    >>> b = simulate_branches(L.LCS([[-1]], [[1]], [[1]], [[-1]]), [1], 2)   # x = e^-t, or x = 1
    >>> len(b), b.unique, b.certified, [tr.state(2)[0].rational() for tr in b]
    (2, False, True, [None, 1])
    """
    return simulate(lcs, x0, t_end, digits, max_events=max_events, time_limit=time_limit,
                    allow_unresolved=allow_unresolved, closed_forms=closed_forms, zeno=zeno, branches="all",
                    max_prec=max_prec, progress=progress)


class _Fork(Exception):
    """A branch reached a choice it has no instruction for (``branches="all"``)."""

    def __init__(self, count: int):
        super().__init__(count)
        self.count = count


def _run(lcs, z0, T, digits, max_events, policy, zeno, branches, forced, bar=None) -> Trajectory:
    run = _Run(lcs, policy, T, max_events)
    run.zeno, run.branches, run.forced, run.bar = zeno, branches, list(forced), bar
    started = _time.monotonic()
    try:
        with policy.deadline.in_force():  # Calcium's long exact steps look at it too
            run.execute(z0)
    except LCSError as e:
        status = _STATUS.get(type(e), Status.FAILED)
        e.trajectory = run.result(z0, digits, status, f"{type(e).__name__}: {e}", _time.monotonic() - started)
        raise
    except KeyboardInterrupt as e:  # Ctrl-C: still an interrupt, carrying what was computed
        e.trajectory = run.result(z0, digits, Status.INTERRUPTED, "interrupted (KeyboardInterrupt)",
                                  _time.monotonic() - started)
        raise
    if bar is not None:
        bar.update(float(T) - bar.n)  # the whole horizon covered
    return run.result(z0, digits, Status.COMPLETE, None, _time.monotonic() - started)


MAX_BRANCHES = 64


def _all_branches(lcs, z0, T, digits, max_events, policy, zeno) -> Branches:
    """Every solution: a depth-first enumeration of the choices (each branch re-run from the
    start with its list of choices), at most MAX_BRANCHES of them, under the run's deadline.  A
    branch stopped by an error keeps its partial trajectory (with its status)."""
    done: list = []
    pending: list = [[]]
    try:
        while pending:
            forced = pending.pop()
            if len(done) + len(pending) >= MAX_BRANCHES:
                raise LimitExceeded(f"more than {MAX_BRANCHES} branches: the solution set is too large "
                                    "to enumerate", trajectory=done[0] if done else None)
            try:
                done.append(_run(lcs, z0, T, digits, max_events, policy, zeno, "all", forced))
            except _Fork as f:
                pending.extend(forced + [c] for c in reversed(range(f.count)))
            except LCSError as e:
                if isinstance(e, TimeLimitExceeded):
                    raise
                done.append(e.trajectory)
    finally:
        policy.deadline.disarm()
    return Branches(done)


_STATUS = {LimitExceeded: Status.EVENT_LIMIT, TimeLimitExceeded: Status.TIME_LIMIT, HorizonExceeded: Status.HORIZON_LIMIT, Deadlock: Status.DEADLOCK,
           ZenoDetected: Status.ZENO,
           UnresolvedSign: Status.UNRESOLVED, IllPosed: Status.ILL_POSED}


class _Run:
    """The state of one run of Algorithm 7.1 (events and phases found so far)."""

    def __init__(self, lcs, policy: Policy, T, max_events: int):
        self.lcs, self.policy, self.T, self.max_events = lcs, policy, T, max_events
        self.events: list[Event] = []
        self.phases: list[PhaseRecord] = []
        self.durations: list = []
        self.lost = 0  # accuracy (bits) measured as lost by the anchors so far
        self.accuracy: int | None = None  # accuracy (bits) of the last anchored event state
        self.boost = 0  # extra precision added when the anchors ran out of accuracy
        self.accumulations: list = []
        self.symmetry = False  # the LCS's scaling symmetry, computed when first needed
        self.zeno = "cross"
        self.branches = "unique"
        self.forced: list = []  # the choices this branch must take (indices into the groups)
        self.choices: list = []  # (time, mode) of the choices taken
        self.unique_by_theorem = bool(lcs.well_posedness())  # Theorem 6.3: one initial solution
        self.undetermined: frozenset = frozenset()  # inputs the state leaves free on the next phase
        self.bar = None  # a progress bar (simulate(..., progress=True))
        self.cascade_tried: set = set()  # starts of cascade proofs tried (cascade.cascade_bound)
        self.collapse_next = 0  # the event count before which no collapse proof is tried again
        self.clock = None  # the sources' clock (absolute time of a driven LCS), set by execute
        self.system = lcs  # the system asked for (a ScheduledLCS: self.lcs is the phase in force)
        self.schedule = getattr(lcs, "schedule", None)
        self.segments = self.schedule.segments() if self.schedule is not None else None
        self.segment_end = None  # the end of the schedule's segment in force (None: t_end)
        self.pending_reset = None  # a schedule's reset, applied to the state at its switch time

    def result(self, z0, digits, status, reason, elapsed) -> Trajectory:
        return Trajectory(self.system, z0, self.T, digits, events=self.events, phases=self.phases,
                          status=status, stop_reason=reason, assumptions=self.policy.assumptions,
                          accumulations=self.accumulations, elapsed=elapsed, policy=self.policy,
                          choices=self.choices)

    def execute(self, z: ExactVector) -> None:
        policy, self.origin = self.policy, z
        t = RationalReal(0, policy)
        mode_before = None
        triggers: tuple = ()
        if self.schedule is not None:
            self.next_segment()
            triggers = ("schedule",) if self.pending_reset is not None else ()
        self.clock = SourceClock.of(self.lcs, z) if self.schedule is None or shares_clock(self.schedule) else None
        while True:
            state_before = z
            reset, self.pending_reset = self.pending_reset, None
            if reset is not None:  # the schedule's reset at its switch time: x := R x
                z = apply_forms(reset, z)
            try:
                mode, chain, z, impulse = self.select_and_reinitialize(z, t)
            except UnresolvedSign as e:
                self.cascade_or_raise(e, t)
            if chain or mode_before is not None or (reset is not None and not _same(reset, state_before)):
                if len(self.events) >= self.max_events:
                    raise LimitExceeded(f"max_events = {self.max_events} reached: the next event is "
                                        f"at t = {t.label()}")
                self.events.append(Event(t, mode_before, tuple(chain), mode.index_set, state_before, z,
                                         len(chain), impulse, triggers))
                law = (self.geometric_law(t, mode) or self.bounce_law(t, mode)) if self.schedule is None else None
                if law is not None:  # a proven right-accumulation at law.time <= t_end
                    t, z = self.cross(law, t, mode)
                    mode_before, triggers = None, ("accumulation",)
                    continue
                if chain and self.schedule is None and self.cascade_suspected():  # an impact cascade: prove it first
                    self.stop_at_cascade(None)
            policy.check_deadline(lambda: f" at t = {t.label()}")
            prec = self.event_prec()
            phase = Phase(mode, homogenized(z), policy, self.lost)
            stop = self.stop()  # t_end, or the schedule's next switch before it
            H = stop - t
            if H.sign() == 0:
                self.phases.append(PhaseRecord(t, self.T, mode.index_set, phase, self.undetermined))
                return
            H_search, cap = phase_horizon(phase, H)
            try:
                hit = next_event(phase, H_search, prec, self.clock.started(t, stop if cap is None else None) if self.clock else None)
            except (UnresolvedSign, LCSError) as e:
                self.cascade_or_raise(e, t)
            if stop is not self.T and cap is None and (hit is None or hit.at_horizon):  # the schedule switches
                # at `stop`: x carried over, then its reset and the next LCS; constraints at 0 trigger too
                z = phase.state(H) if hit is None else phase.event_state(hit.theta, vstack(*[c.g for c in hit.constraints]))
                self.anchor(H, z, prec)
                self.phases.append(PhaseRecord(t, stop, mode.index_set, phase, self.undetermined))
                self.durations.clear()  # the dynamics change: no accumulation runs across a switch
                cons = () if hit is None else tuple(c.name for c in hit.constraints)
                mode_before, triggers, t = mode.index_set, cons + ("schedule",), stop
                self.next_segment()
                continue
            if hit is None:
                if cap is not None:  # no event within the horizon limit of this phase: stop there
                    end = t + H_search
                    self.phases.append(PhaseRecord(t, end, mode.index_set, phase, self.undetermined))
                    raise HorizonExceeded(f"t_end = {_short(self.T)} is beyond the horizon limit of mode "
                                          f"{format_mode(mode.I)} from t = {t.label()}: no event until t = "
                                          f"{end.label()} ({cap}, docs/limits.md); the trajectory is computed "
                                          f"up to there: simulate on from traj.state({end.label()})")
                self.phases.append(PhaseRecord(t, self.T, mode.index_set, phase, self.undetermined))
                return
            theta, cons = hit.theta, hit.constraints  # t + theta: in absolute time when the sources' clock proves it
            t_new = self.T if hit.at_horizon else self.clock.event_time(phase, t, theta) if self.clock else t + theta
            z = phase.event_state(theta, vstack(*[c.g for c in cons]), tuple(c.g for c in hit.positive))
            self.anchor(theta, z, prec)
            self.phases.append(PhaseRecord(t, t_new, mode.index_set, phase, self.undetermined))
            self.durations.append(theta)
            if self.bar is not None:
                self.bar.update(float(t_new) - self.bar.n)
            self.check_accumulation(t_new)
            mode_before, triggers, t = mode.index_set, tuple(c.name for c in cons), t_new
            if stop is not self.T and (t - stop).sign() == 0:  # the event falls on the schedule's switch
                triggers += ("schedule",)
                self.durations.clear()
                self.next_segment()

    # --- scheduled switching (lcs_exact.schedule) ------------------------------------------------
    def next_segment(self) -> None:
        """Enter the schedule's next segment: its LCS in force, its end, its reset pending."""
        start, end, ph = next(self.segments)
        self.lcs = ph.lcs
        self.unique_by_theorem = bool(ph.lcs.well_posedness())
        self.segment_end = end
        self.pending_reset = ph.reset

    def stop(self):
        """Where the phase search stops: t_end, or the schedule's next switch when it is before."""
        end = self.segment_end
        return self.T if end is None or (self.T - end).sign() <= 0 else RationalReal(end, self.policy)

    def geometric_law(self, t, mode):
        """The proven geometric law of the last events when it accumulates before t_end
        (:mod:`lcs_exact.accumulation`), else None; with ``zeno="stop"`` a proven law stops the
        run with ZenoDetected at its exact time."""
        if len(self.events) < 3 or not t.known_exactly():
            return None
        if self.symmetry is False:
            self.symmetry = symmetry_exponents(self.lcs)
        law = geometric_law(self.lcs, self.events, self.symmetry, enclose=self.enclose, horizon=self.T)
        if law is None or (self.T - law.time).sign() < 0:
            return None
        if self.zeno == "stop":
            q = law.time.known_rational()
            with workprec(128):  # a certified rational enclosure (the time itself is exact: .time)
                lo, hi = (q, q) if q is not None else (dyadic_lower(law.time.arb(128)), dyadic_upper(law.time.arb(128)))
            raise ZenoDetected(f"event times accumulate at exactly t = {law.time.label()} (a proven geometric law: "
                               f"cycles of {law.period} events, each {law.ratio} times the previous; "
                               f"Remark 4.11); zeno='stop'", lower=lo, upper=hi, time=law.time)
        return law

    def bounce_law(self, t, mode):
        """The window of a proven accumulation of Newton impacts that no symmetry explains - one
        contact bouncing (:mod:`lcs_exact.accumulations.bounces`) or several taking turns
        (:mod:`lcs_exact.accumulations.collapses`) - when it ends before t_end, else None; tried every
        third event (a proof costs milliseconds, a failed one less)."""
        d = self.durations
        if len(d) < 6 or len(d) % 3:
            return None
        window = None
        if all(b.arb(64) < a.arb(64) for a, b in zip(d[-4:], d[-3:])):
            window = bounce_window(self.lcs, self.events, t, mode, self.event_prec(), self.origin)
        if window is None:
            window = self.collapse(t, mode)
        if window is None or (self.T - window.time).sign() < 0:
            return None
        if self.zeno == "stop":
            digits = self.policy.digits + 2  # an enclosure as narrow as the run's digits
            with workprec(digits_to_bits(digits) + 16):
                b = window.time.ball(digits)
                lo, hi = dyadic_lower(b), dyadic_upper(b)
            raise ZenoDetected(f"event times accumulate at t = {window.time.label()} (Newton impacts proven to "
                               f"accumulate: {window.proof!r}; Remark 4.11); zeno='stop'", lower=lo, upper=hi,
                               time=window.time)
        return window

    def collapse(self, t, mode):
        """The window of a proven collapse of contacts taking turns, or None; after a failed proof
        the next waits for 1/16 more events (a proof iterates up to thousands of periods)."""
        cyc = collapse_cycle(self.lcs, self.events) if len(self.events) >= self.collapse_next else None
        if cyc is None:
            return None
        proof = prove_collapse(cyc, self.events, max(128, self.event_prec()))
        if proof is None:
            self.collapse_next = len(self.events) + max(6, len(self.events) // 16)
            return None
        return CollapseWindow(proof, t, mode, self.events[-1].state_after, self.origin)

    def enclose(self, form, t0, t1):
        """An arb enclosure of form . x(t) over [t0, t1] (exact reals inside the computed run),
        from the phases' exponential sums over their (outer, rational) time intervals."""
        prec = 128
        out = None
        with workprec(prec):
            a, b = dyadic_lower(t0.arb(prec)), dyadic_upper(t1.arb(prec))
            for rec in self.phases:
                if isinstance(rec.phase, AccumulationWindow):
                    continue
                r0, r1 = dyadic_lower(rec.t0.arb(prec)), dyadic_upper(rec.t1.arb(prec))
                lo, hi = max(a, r0), min(b, r1)
                if lo > hi:
                    continue
                f = PhaseFunction(rec.phase, form, "bound").at(prec)
                base = dyadic_lower(rec.t0.arb(prec))
                e = f.enclose(max(lo - base, fmpq(0)), hi - base)
                if rec.phase.scale is not None:
                    e = e * rec.phase.scale.arb(prec)
                out = e if out is None else out.union(e)
        return out if out is not None else arb(0, "inf")

    def cross(self, law, t, mode):
        """Cross a proven accumulation point: the motion on [t_k, T*) is the law's scaled cycles
        (:class:`~lcs_exact.accumulation.ScaledCycle`), x(T*-) its exact limit; the run goes on
        from there as Definition 4.10 prescribes (item 2: the limit state, then selection)."""
        if isinstance(law, BounceWindow):  # no law: the window iterates the proven impact map on balls
            self.phases.append(PhaseRecord(t, law.time, mode.index_set, law))
            period = len(law.proof.cycle.pattern) if isinstance(law, CollapseWindow) else 1  # impacts a cycle
            self.accumulations.append(Accumulation(law.time, law.limit_state, period, None, len(self.events) - 1, law))
            self.durations.clear()
            return law.time, law.limit_state
        T_star, limit = law.time, law.limit
        offsets = [self.events[law.start + j].time - law.cycle_start for j in range(law.period)]
        cycle = ScaledCycle(law, ReferenceStates(self), t, mode, self.events[-1].state_after, offsets)
        self.phases.append(PhaseRecord(t, T_star, mode.index_set, cycle))
        self.accumulations.append(Accumulation(T_star, limit, law.period, law.ratio, law.start, cycle))
        self.durations.clear()
        return T_star, limit

    def anchor(self, theta, z: ExactVector, prec: int) -> None:
        """Anchor the event: its time and state get balls at the working precision.  The bits of
        accuracy the state lost against the previous event's state (re-initialization,
        homogenization and the phase together: ~1.4 bits an event on the two carts, the
        wrapping of ball arithmetic) are added to the working precision of the next events, so
        the anchors keep the accuracy they started with."""
        theta.arb(prec)
        acc = min(prec, _accuracy(z.arb(prec)))
        if self.accuracy is not None and acc < self.accuracy:
            self.lost += self.accuracy - acc
        if acc < self.policy.target_bits + 8 and self.events:
            # the anchors ran out of accuracy: re-anchor this state from the start at a higher
            # precision (one walk over the history; the boost doubles, so walks are rare)
            self.boost += max(64, self.lost)
            prec = self.working_prec()
            theta.arb(prec)
            acc = min(prec, _accuracy(z.arb(prec)))
        self.accuracy = acc

    def working_prec(self) -> int:
        """The working precision of the next event (policy target, measured loss, boost)."""
        return self.policy.working_prec(self.lost) + self.boost

    def event_prec(self) -> int:
        """The working precision capped ACCURACY_HEADROOM bits above the accuracy of the state the
        next event starts from: bits beyond the ball it is computed from give nothing (a long run's
        working precision grows with its measured loss, 149 to 469 bits in 1000 events, while its
        states keep ~130 bits); re-anchoring (:meth:`anchor`'s boost) uses the full precision."""
        prec = self.working_prec()
        if self.accuracy is not None and self.accuracy >= self.policy.target_bits + 8:  # else: boosting
            prec = min(prec, max(self.accuracy + ACCURACY_HEADROOM, self.policy.working_prec(0)))
        return prec

    def select_and_reinitialize(self, z: ExactVector, t):
        """Steps one to three (:func:`~lcs_exact.phases.eventstep.event_step` on exact states,
        step one's choice by :meth:`choose`); returns (mode, chain of jump modes, state after,
        impulse)."""
        arith = ExactStates(self.lcs, lambda S, x: self.choose(S, x, t), t)
        step = event_step(arith, z)
        return step.mode, list(step.chain), step.state, arith.impulse

    def choose(self, S: set, z: ExactVector, t) -> frozenset:
        """The mode to continue in: the smallest of S(z) (Remark 4.8) when all of S(z) carries one
        initial solution; otherwise a choice that changes the trajectory (outside Theorem 6.3):
        ``branches="unique"`` raises IllPosed with the alternatives, ``"all"`` takes the forced
        choice of this branch or forks.  When S(z) holds modes that are not autonomous (a
        floating network), the modes are grouped by the state they give: one group means the
        state is unique, and the inputs that differ or are free are recorded as undetermined
        on the phase (``self.undetermined``)."""
        smallest = min(S, key=mode_order)
        self.undetermined = frozenset()
        nonautonomous = not self.unique_by_theorem and any(not self.lcs.mode(I).is_autonomous for I in S)
        if not nonautonomous and (len(S) == 1 or self.unique_by_theorem):
            return smallest
        q = z.known_rational()
        x = q if q is not None else z
        groups = state_groups(self.lcs, x, S) if nonautonomous else initial_solution_groups(self.lcs, x, S)
        if len(groups) == 1:
            if nonautonomous:
                self.undetermined = undetermined_inputs(self.lcs, x, groups[0])
            return smallest
        i = len(self.choices)
        if i < len(self.forced):
            mode = groups[self.forced[i]][0]
            self.choices.append((t, mode))
            return mode
        if self.branches == "all":
            raise _Fork(len(groups))
        alternatives = [(g[0], initial_solution(self.lcs, q if q is not None else z, g[0])) for g in groups]
        raise IllPosed(f"non-unique continuation at t = {t.label()}: S(z) = "
                       f"{{{', '.join(format_mode(m) for m in sorted(S, key=mode_order))}}} "
                       f"holds {len(groups)} different initial solutions (modes "
                       f"{', '.join(format_mode(g[0]) for g in groups)}); Theorem 6.3 does not hold, so the "
                       "solution is not unique: see .alternatives, or simulate(..., branches='all')",
                       alternatives=alternatives)

    def check_accumulation(self, t_now) -> None:
        """Stop at a suspected accumulation (:mod:`lcs_exact.zeno`), unless the run repeats Newton
        impacts of one contact or of a few taking turns: their proofs (:meth:`bounce_law`) wait for
        flights short beside the background's motion, or for the pattern to repeat, up to
        BOUNCE_PATIENCE shrinking phases."""
        try:
            check_accumulation(self.durations, t_now, self.T)
        except ZenoDetected:
            if len(self.durations) >= BOUNCE_PATIENCE or (bounce_cycle(self.lcs, self.events) is None
                                                          and not turns_suspected(self.events)):
                raise

    def cascade_suspected(self) -> bool:
        """A cheap guess that the run is inside an impact cascade (the last phase more than 10^9
        times shorter than one of the six before it): worth trying :meth:`stop_at_cascade`."""
        if len(self.durations) < 3 or len(self.events) < 3:
            return False
        with workprec(64):
            d = [x.arb(64) for x in self.durations[-7:]]
            return bool(d[-1] * 10**9 < max(d[:-1], key=lambda b: b.mid()))

    def stop_at_cascade(self, err: LCSError | None) -> None:
        """Prove the accumulation of an impact cascade (:func:`~lcs_exact.cascade.cascade_bound`:
        a cycle of events repeating forever from a one-parameter family of states, its times
        summed by a certified contraction) and stop with :class:`ZenoDetected` carrying the
        certified enclosure lower <= T* <= upper; return (nothing proven) otherwise."""
        policy = self.policy
        bound = cascade_bound(self.lcs, self.events, prec=max(128, policy.target_bits + 32),
                              max_prec=policy.max_prec, tried=self.cascade_tried,
                              check=lambda: policy.check_deadline(lambda: " while proving an impact cascade"),
                              background_order=7 if err is None else 12,  # cheap while more events can come
                              budget=CASCADE_BUDGET[err is not None])
        if bound is None:
            return
        if err is None and bound.lower > self.T.arb(64).upper():
            return  # the accumulation is after t_end: the events before it are still to be computed
        lo, hi = bound.lower, bound.upper
        first = self.events[bound.first_event]
        kind = "two contacts taking turns over a moving background" if bound.background else "a corner"
        message = (f"event times accumulate at T* in [{_num(lo, down=True)}, {_num(hi)}] (width {_num(hi - lo, 2)}): an "
                   f"impact cascade ({kind}) whose cycle of {bound.period} events repeats forever from event "
                   f"{bound.first_event} (t = {_short(first.time)}), its small parameter shrinking by a factor "
                   f"<= {_num(bound.contraction, 3)} a cycle (proven on a family of states, Remark 4.11, "
                   "docs/numerics.md); no exact law is known, so the solution is not continued past T*")
        if err is not None:
            message += f" (the decision that stopped the run: {err})"
        raise ZenoDetected(message, lower=lo, upper=hi, estimate=float((lo + hi) / 2)) from err  # estimate: display only

    def cascade_or_raise(self, err: LCSError, t) -> None:
        """A decision that fails inside an impact cascade: stop with :class:`ZenoDetected` and a
        certified enclosure of the accumulation time when the cascade is proven
        (:meth:`stop_at_cascade`); otherwise, when the decision fails right after events closer
        and closer together (each gap less than half the previous over the last three, or cycles
        of events shrinking: :func:`~lcs_exact.accumulations.zeno.shrinking_cycles`), stop with
        ZenoDetected whose ``lower`` is the last event time (certified) and ``upper`` None
        (nothing proven bounds it but t_end); any other failure is raised as it is."""
        if isinstance(err, (ZenoDetected, LimitExceeded, Deadlock)) or len(self.durations) < 3:
            raise err
        self.stop_at_cascade(err)
        with workprec(64):
            d = [x.arb(64) for x in self.durations]
            if not ((all(b < a / 2 for a, b in zip(d[-3:], d[-2:])) and d[-1] >= 0) or shrinking_cycles(self.durations)):
                raise err
            with workprec(128):  # the last event time to 25 digits (an anchor may be far coarser)
                lower = dyadic_lower(t.ball(25))
            estimate = float(t.arb(64).mid()) + float((d[-1] * d[-1] / (d[-2] - d[-1])).mid()) \
                if (d[-2] - d[-1]) > 0 else float(t.arb(64).mid())
        raise ZenoDetected(f"events closer and closer after t = {_num(lower, 17, down=True)} (gaps "
                           f"{', '.join(f'{float(x.mid()):.2g}' for x in d[-3:])}): a right-accumulation of events "
                           "(Remark 4.11) is suspected, not proven (no law and no cascade proof applies), and the "
                           f"solution cannot be computed past this point; certified: the trajectory up to "
                           f"t >= {_num(lower, 17, down=True)}, and any accumulation time is after it "
                           f"(the decision that failed: {err})",
                           lower=lower, upper=None, estimate=estimate) from err


#: the work a cascade proof may do, in coefficient products of its Taylor models (while the run can go
#: on, when a decision failed and it cannot): about 2 s and 20 s on a 2-core machine of 2026, but counted
#: as work so that a run ends the same way on every machine and under any load
CASCADE_BUDGET = (8_000_000, 80_000_000)


def _num(q, digits: int = 20, *, down: bool = False) -> str:
    """A rational for a message, to ``digits`` significant digits, rounded up (a bound from
    above stays one), or down with ``down=True``."""
    with decimal.localcontext() as ctx:
        ctx.prec, ctx.rounding = digits, (decimal.ROUND_FLOOR if down else decimal.ROUND_CEILING)
        return str(decimal.Decimal(int(q.p)) / decimal.Decimal(int(q.q)))


def _short(r) -> str:
    """A number for a message: its label, or 6 significant digits when that is long."""
    text = r.label()
    return text if len(text) <= 24 else f"{float(r.ball(6).mid()):.6g}"


def _accuracy(ball) -> int:
    """Relative accuracy (bits) of a state ball, measured on its largest component."""
    comps = [ball[i, 0] for i in range(ball.nrows()) if not ball[i, 0].contains(0)]
    if not comps:
        return 0
    return accuracy_bits(max(comps, key=lambda b: abs(b.mid())))


def _same(R: fmpq_mat, z: ExactVector) -> bool:
    """R z = z, proven (a rational state: exactly; else only when R is the identity)."""
    q = z.known_rational()
    if q is not None:
        return R * q == q
    n = R.nrows()
    return all(R[i, j] == (1 if i == j else 0) for i in range(n) for j in range(n))

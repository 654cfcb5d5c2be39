"""Results of a simulation: :class:`Trajectory` (and :class:`Branches`, the solutions of a
non-unique problem), which holds the run's records (:class:`Event`, :class:`PhaseRecord`,
:class:`Status`: :mod:`lcs_exact.phases.events`).

Every number is an exact real (:mod:`lcs_exact.reals`): ``.closed_form`` where proven (derived on
first access), ``.ball(digits)`` / ``.decimal(digits)`` certified to any number of digits, under
the run's precision policy.  Results are immutable values with a :class:`Status`; a trajectory
stopped early (a limit, an accumulation of events, a deadlock, an unresolved sign) is ``partial``
and says why in ``stop_reason``.  Indices are 0-based.
"""
from __future__ import annotations

from typing import Any, Sequence

from flint import arb, fmpq, fmpq_mat

from ..numbers import DEFAULT_POLICY, Policy, accuracy_bits, check_digits, digits_to_bits, workprec
from ..errors import InvalidArgument, LCSError
from ..interfaces import AccumulationWindow
from .fixture import fixture_dict
from .events import Event, PhaseRecord, Status
from .timeline import Timeline
from .undetermined import PartlyUndetermined
from .exports import array, data_frame, write_csv, write_npz
from ..modes import format_mode, latex_mode
from ..display import derived_outputs
from ..display import plot_trajectory
from ..algebra import to_fmpq
from ..numbers import Real, as_real
from ..system import source_block
from ..system import time_response
from ..numbers import ComponentsVector, ExactVector, ProjectedVector

__all__ = ["Event", "PhaseRecord", "Trajectory", "Status", "SCHEMA", "Branches"]

SCHEMA = "lcs-exact/trajectory/1"


class Trajectory:
    """The solution of an LCS on [0, t_end] produced by Algorithm 7.1 (immutable), made by
    :func:`~lcs_exact.simulate`: each parameter below is the attribute of the same name (sequences
    as tuples).  ``partial`` is True unless the run covered [0, t_end].  A trajectory with
    ``choices`` (``simulate(..., branches="all")``) is *a* solution, not *the* solution (``unique``
    is False), and it is ``certified`` like any other when no sign was assumed: every digit it
    reports is right for the solution it follows.

    Parameters
    ----------
    lcs : LCS
        The system (or the scheduled system, :mod:`lcs_exact.dynamics.schedule`).
    x0 : ExactVector
        The initial state.
    t_end : Real
        The horizon asked for.
    digits : int
        The run's certified digits (the default of :meth:`to_fixture`).
    events : sequence of Event, optional
    phases : sequence of PhaseRecord, optional
        The continuous phases in order (a proven accumulation's window of implied events is one).
    status : Status, optional
        How the run ended (default ``Status.COMPLETE``).
    stop_reason : str, optional
        Why a partial run stopped.
    assumptions : sequence of str, optional
        The unresolved zeros decided as 0 (``allow_unresolved=True``).
    accumulations : sequence of Accumulation, optional
        The right-accumulation points crossed.
    elapsed : float, optional
        Seconds the run took.
    policy : Policy, optional
        The run's precision policy, which later queries follow (its ``time_limit`` too).
    choices : sequence of (Real, frozenset), optional
        (time, mode) for each point where S(z) left a choice between different initial solutions.
    """

    __slots__ = ("lcs", "x0", "t_end", "digits", "events", "phases", "status", "stop_reason", "choices",
                 "assumptions", "accumulations", "elapsed", "policy", "_ends", "_frozen")  # _ends: a Timeline

    def __init__(self, lcs, x0: ExactVector, t_end: Real, digits: int, *, events: Sequence = (),
                 phases: Sequence = (), status: Status = Status.COMPLETE, stop_reason: str | None = None,
                 assumptions: Sequence = (), accumulations: Sequence = (), elapsed: float = 0.0,
                 policy: Policy | None = None, choices: Sequence = ()):
        self.lcs, self.x0, self.t_end, self.digits = lcs, x0, t_end, digits
        self.events = tuple(events)
        self.phases = tuple(phases)
        self.status = Status(status)
        self.stop_reason = stop_reason
        self.assumptions = tuple(assumptions)
        self.accumulations = tuple(accumulations)
        self.choices = tuple(choices)
        self.elapsed = elapsed
        self.policy = policy or DEFAULT_POLICY
        self._frozen = True

    def __setattr__(self, name, value):
        if getattr(self, "_frozen", False):
            raise AttributeError(f"Trajectory is immutable (cannot set {name})")
        object.__setattr__(self, name, value)

    @property
    def partial(self) -> bool:
        """True when the run stopped before t_end (see ``status`` and ``stop_reason``)."""
        return self.status is not Status.COMPLETE

    @property
    def certified(self) -> bool:
        """True iff every sign decision is proven (no unresolved zero assumed) and the run was not
        stopped by a non-unique continuation (IllPosed).  A branch of a non-unique problem
        (``simulate(..., branches="all")``) is certified when its signs are: it is one solution,
        exactly; ``unique`` says whether it is the only one."""
        return not self.assumptions and self.status is not Status.ILL_POSED

    @property
    def unique(self) -> bool:
        """False when a choice between different initial solutions was made on the way (``choices``):
        the trajectory is then one of several solutions of the problem (see :class:`Branches`)."""
        return not self.choices

    @property
    def t_last(self) -> Real:
        """The last time the trajectory covers (t_end unless partial)."""
        return self.phases[-1].t1 if self.phases else (self.events[-1].time if self.events else as_real(0))

    @property
    def sources(self):
        """The exosystem of the run (:class:`~lcs_exact.sources.SourceBlock`): the LCS's
        (:attr:`LCS.sources <lcs_exact.LCS.sources>`) with z0 read from this run's x0 (a user may
        start the sources elsewhere than ``embed`` does); None when the system has none.

        >>> import lcs_exact as L
        >>> rect = L.examples.sine_rectifier()
        >>> L.simulate(rect, [0, 0, 2], 1).sources.expressions      # x0 gives 2 cos t
        ('2*sin(t)', '2*cos(t)')
        """
        sb = self.lcs.sources
        if sb is None:
            return None
        z0 = [self.x0[i].known_rational() for i in sb.states]
        if any(q is None for q in z0) or all(q == sb.z0[r, 0] for r, q in enumerate(z0)):
            return sb
        return source_block(sb.states, sb.S, fmpq_mat(len(z0), 1, z0), sb.names)

    # --- evaluation ---------------------------------------------------------------------------
    def _locate(self, t: Real, start: int = 0) -> tuple[int, bool]:
        """(index of the phase holding t, True at its end exactly): :meth:`Timeline.locate`."""
        if not self.phases:
            raise LCSError("the trajectory has no continuous phase")
        if start == 0 and (t - self.phases[0].t0).sign() < 0:
            raise InvalidArgument(f"t = {t.label()} is before the start of the trajectory")
        if getattr(self, "_ends", None) is None:  # a cache of immutable data: set past the freeze
            object.__setattr__(self, "_ends", Timeline(self.phases))
        found = self._ends.locate(t, start)
        if found is None:
            raise InvalidArgument(f"t = {t.label()} is after the last computed time {self.phases[-1].t1.label()}"
                                  + (" (the trajectory is partial)" if self.partial else ""))
        return found

    def _phase_at(self, t: Real) -> PhaseRecord:
        """The phase holding t, for u and y; at the end of a phase, the phase after it: u and y
        at an event time are the right limits u(t+), y(t+), as the state is x(t+) (the scaled
        cycles of an accumulation window have no value at its end T* itself)."""
        i, at_end = self._locate(t)
        if at_end and i + 1 < len(self.phases):
            return self.phases[i + 1]
        if at_end and isinstance(self.phases[i].phase, AccumulationWindow):
            raise InvalidArgument(f"u and y at the accumulation time {t.label()} itself: the trajectory "
                                  "ends there, and the inputs have no limit from the left (the state does)")
        return self.phases[i]

    def state(self, t: Any) -> ExactVector:
        """x(t), exact (t rational or an exact real); at an event time, the state after it.

        Parameters
        ----------
        t : rational-like or Real
            A time in [0, ``t_last``]: a rational (int, ``"p/q"``, Fraction, a float read as its
            shortest decimal) or an exact real (an event's ``time``)."""
        t = as_real(t, self.policy)
        if not self.phases and (t - self.t_last).sign() == 0:  # stopped before its first phase
            return self.events[-1].state_after if self.events else self.x0
        i, at_end = self._locate(t)
        if at_end and i + 1 < len(self.phases):
            return self.phases[i + 1].phase.z  # x(t+): the start of the next phase
        rec = self.phases[i]
        if at_end and self.events and self.events[-1].time is rec.t1:  # a last event, no phase after it
            return self.events[-1].state_after
        return rec.phase.state(t - rec.t0)

    def u(self, t: Any) -> ExactVector:
        """u(t) on a continuous phase (u_I = F_I x, zero off I); at an event time the value after
        it, u(t+), as :meth:`state` gives x(t+) (the impulse at the event is in ``Event.impulse``).
        An input that the state does not determine there (:meth:`undetermined`) is reported as
        such: its component is an :class:`~lcs_exact.phases.undetermined.UndeterminedReal`
        (printed ``undetermined``; asking it for digits raises
        :class:`~lcs_exact.errors.Undetermined`).

        Parameters
        ----------
        t : rational-like or Real
            A time in [0, ``t_last``]: a rational (int, ``"p/q"``, Fraction, a float read as its
            shortest decimal) or an exact real (an event's ``time``)."""
        t = as_real(t, self.policy)
        rec = self._phase_at(t)
        if isinstance(rec.phase, AccumulationWindow):
            return rec.phase.output(t - rec.t0, "u")
        v = ProjectedVector(full_feedback(rec.phase.mode), rec.phase.state(t - rec.t0))
        return PartlyUndetermined(v, rec.undetermined, "u") if rec.undetermined else v

    def y(self, t: Any) -> ExactVector:
        """y(t) = C x + D u on a continuous phase, y(t+) at an event time (components that depend
        on an undetermined input are undetermined, as for :meth:`u`).

        Parameters
        ----------
        t : rational-like or Real
            As for :meth:`state`."""
        t = as_real(t, self.policy)
        rec = self._phase_at(t)
        if isinstance(rec.phase, AccumulationWindow):
            return rec.phase.output(t - rec.t0, "y")
        lcs = rec.phase.mode.lcs  # the phase's own system (a scheduled LCS switches between several)
        v = ProjectedVector(lcs.C + lcs.D * full_feedback(rec.phase.mode), rec.phase.state(t - rec.t0))
        free = frozenset(i for i in range(lcs.k) if any(lcs.D[i, j] != 0 for j in rec.undetermined))
        return PartlyUndetermined(v, free, "y") if free else v

    @property
    def output_names(self) -> tuple:
        """The names of the outputs the builder declared (a relay's ``w_0, w_1, ...``), or ()."""
        out = derived_outputs(self.lcs)
        return () if out is None else tuple(out.names)

    def outputs(self, t: Any) -> ExactVector:
        """The outputs the builder declared, exact at t: w = W_x x + W_u u on the phase holding t
        (at an event time, the right limit: the values on the phase after it, as for :meth:`state`).  A relay system
        (:func:`lcs_exact.models.relay`) declares its relays' outputs w_j in Sgn(C_j x); their
        names are :attr:`output_names`.  An output that depends on an undetermined input is
        undetermined.

        Parameters
        ----------
        t : rational-like or Real
            As for :meth:`state`.

        Examples
        --------
        >>> from lcs_exact.models import relay
        >>> from lcs_exact import simulate
        >>> lcs = relay([[0]], [[-1]], [[1]])        # x' = -w, w in Sgn(x)
        >>> tr = simulate(lcs, lcs.embed([1]), 2)    # x = 1 - t, then x = 0 sliding
        >>> tr.output_names, tr.outputs("1/2"), tr.outputs(1), tr.outputs(2)   # w = sgn(x), 0 sliding
        (('w_0',), (1), (0), (0))
        """
        out = derived_outputs(self.lcs)
        if out is None:
            raise InvalidArgument("this system declares no outputs (models.relay declares its relays' w); "
                                  "use u(t), y(t) or state(t)")
        t = as_real(t, self.policy)
        i, at_end = self._locate(t)
        rec = self.phases[i + 1] if at_end and i + 1 < len(self.phases) else self.phases[i]
        if at_end and isinstance(rec.phase, AccumulationWindow) and rec is self.phases[i]:
            raise InvalidArgument(f"the outputs at the accumulation time {t.label()} itself: the trajectory "
                                  "ends there, and the inputs have no limit from the left (the state does)")
        W = fmpq_mat(out.Wx.nrows(), self.lcs.n + self.lcs.k)
        for r in range(W.nrows()):
            for j in range(self.lcs.n):
                W[r, j] = out.Wx[r, j]
            for j in range(self.lcs.k):
                W[r, self.lcs.n + j] = out.Wu[r, j]
        if isinstance(rec.phase, AccumulationWindow):  # its exact x and u
            u = rec.phase.output(t - rec.t0, "u")
            v = ProjectedVector(W, ComponentsVector(list(self.state(t)) + list(u)))
            free = frozenset()
        else:
            v = ProjectedVector(out.Wx + out.Wu * full_feedback(rec.phase.mode), rec.phase.state(t - rec.t0))
            free = frozenset(r for r in range(W.nrows()) if any(out.Wu[r, j] != 0 for j in rec.undetermined))
        return PartlyUndetermined(v, free, "w") if free else v

    def undetermined(self, t: Any) -> frozenset:
        """The inputs u_j that the state does not determine at t (empty unless the mode there
        is not autonomous but the state is unique: a floating diode bridge).

        Parameters
        ----------
        t : rational-like or Real
            As for :meth:`state` (at an event time, the phase after it).

        Examples
        --------
        >>> from lcs_exact.models import two_carts
        >>> from lcs_exact import simulate
        >>> simulate(two_carts(), [0, 1, -1, 0], 1).undetermined(1)
        frozenset()
        """
        return self._phase_at(as_real(t, self.policy)).undetermined

    def window_rows(self, window: AccumulationWindow, ts: Sequence[Any], kind: str) -> list | None:
        """Float rows of u, y or w inside an accumulation window, for plots: u = F_I x from the
        sampled state balls and the mode of the flight holding each time (exact values cost a
        Calcium evaluation each); None when a time's mode cannot be placed.

        Parameters
        ----------
        window : AccumulationWindow
            The window (``traj.phases[i].phase``).
        ts : sequence of rationals
            Times inside its flights.
        kind : {"u", "y", "w"}
        """
        modes = [window.flight_mode(float(t)) for t in ts]
        if not ts or any(m is None for m in modes):
            return None
        rows = []
        for mode, x in zip(modes, self.sample(ts, 10)):
            F, lcs, xf = full_feedback(mode), mode.lcs, [float(v.mid()) for v in x]
            out = derived_outputs(lcs) if kind == "w" else None
            M = F if kind == "u" else lcs.C + lcs.D * F if kind == "y" else out.Wx + out.Wu * F
            rows.append([sum(float(M[i, j]) * xf[j] for j in range(len(xf))) for i in range(M.nrows())])
        return rows

    def sample(self, ts: Sequence[Any], digits: int = 17) -> list[list[arb]]:
        """Certified balls of x(t) for every t in ``ts`` (rationals), each component to ``digits``
        digits (absolute 10^-digits for components below that).  One exponential per eigenvalue
        and point, from the phase's modal data: thousands of points in well under a second.

        Parameters
        ----------
        ts : sequence of rational-like
            Times in [0, ``t_last``] (floats read as their shortest decimal); increasing is fastest.
        digits : int, optional
            Significant digits, 1 to ``MAX_DIGITS`` (default 17: the digits of a float64)."""
        digits = check_digits(digits)
        with self.policy.deadline.query():  # bounded by the run's time_limit, as the run was
            return self._sample(ts, digits)

    def _sample(self, ts: Sequence[Any], digits: int) -> list[list[arb]]:
        if isinstance(ts, (str, bytes)) or not hasattr(ts, "__iter__"):
            raise InvalidArgument(f"ts must be a sequence of rational times, got {type(ts).__name__}")
        need = digits_to_bits(digits) + 4
        out: list = []
        prec = need + 32
        cursor, last = 0, None
        for t in ts:
            tq = to_fmpq(t, "t")
            if not self.phases:  # stopped before its first phase: the state at t_last only
                x, _ = self._refined(_components(self.state(tq)), tq, need, digits, need + 32)
                out.append(x)
                continue
            if last is None or tq < last:
                cursor = 0
            i, at_end = self._locate(as_real(tq, self.policy), cursor)
            cursor, last = i, tq
            after = at_end and i + 1 < len(self.phases)  # x(t+) at an event time
            rec = self.phases[i + 1] if after else self.phases[i]
            if at_end and not after and self.events and self.events[-1].time is rec.t1:
                # a last event with no phase after it: x(t+) is its state after
                x, _ = self._refined(_components(self.events[-1].state_after), tq, need, digits, need + 32)
            else:
                x, prec = self._refined(lambda p: self._point(rec, tq, p, after), tq, need, digits, prec)
            out.append(x)
        return out

    def _refined(self, compute, tq: fmpq, need: int, digits: int, prec: int) -> tuple[list[arb], int]:
        """(compute(p), p): balls accurate to ``need`` bits, p doubled from ``prec`` until they are."""
        while True:
            self.policy.check_deadline(lambda: f" while sampling x({tq})")
            x = compute(prec)
            if all(_accurate(b, need) for b in x):
                return x, prec
            prec *= 2
            if prec > 64 * (need + 32):
                raise LCSError(f"could not evaluate x({tq}) to {digits} digits")

    @staticmethod
    def _point(rec: PhaseRecord, tq: fmpq, prec: int, at_start: bool = False) -> list[arb]:
        phase = rec.phase
        with workprec(prec):
            if at_start or rec.t0.known_rational() == tq or getattr(phase, "equilibrium", False):
                # the phase's start itself, exactly, or any time of a phase at an equilibrium
                x = phase.z.arb(prec)
                return [x[i, 0] for i in range(x.nrows())]
            dt = arb(tq) - rec.t0.arb(prec)
            if isinstance(phase, AccumulationWindow):  # balls, else exact states
                x = phase.ball_state(dt, prec)
                if x is None:
                    x = phase.state(as_real(tq) - rec.t0).arb(prec)
                return [x[i, 0] for i in range(x.nrows())]
            x = phase.ball_state(dt, prec)
            return [x[i, 0] for i in range(x.nrows())]

    # --- export -------------------------------------------------------------------------------
    def to_fixture(self, digits: int | None = None, sample=None, closed_forms: bool = True,
                   provenance: dict | None = None) -> dict:
        """A dict in the fixture schema ``lcs-exact/trajectory/1`` (docs/fixtures.md;
        :func:`~lcs_exact.phases.fixture.build_fixture`).

        Parameters
        ----------
        digits : int, optional
            Significant digits of every number (default: the run's ``digits``).
        sample : rational-like, optional
            A step h: adds the states at t = 0, h, 2h, ... (``samples``).
        closed_forms : bool, optional
            False writes only the closed forms already derived (a quick write); default True.
        provenance : dict, optional
            JSON-ready (builder, parameters, version, ...): the fixture's ``provenance``, covered
            by its digest."""
        return fixture_dict(self, digits, sample, closed_forms, provenance)

    def plot(self, **kw):
        """States and u/y (or the declared outputs w) against t, events and jumps marked.
        Returns the matplotlib Figure.

        Parameters
        ----------
        **kw
            The keywords of :func:`lcs_exact.plotting.plot_trajectory`: ``states`` and
            ``constraints`` (indices or names to draw), ``panels`` (a subset of ``("x", "w", "u",
            "y")``; ``"w"``: the outputs a builder declared, :meth:`outputs`, drawn instead of u
            and y by default), ``points`` (about 800 certified sample times in total),
            ``label_events`` (at most how many events get a label), ``figsize``, ``title``,
            ``sources`` (draw the states the builder appended for its sources, hidden by default)."""
        return plot_trajectory(self, **kw)

    # --- arrays, data frames and files (lcs_exact.phases.exports) -----------------------------
    def to_numpy(self, t: Any, *, u: bool = False, y: bool = False):
        """A float64 array of shape (len(t), n) (plus k columns for u and k for y when asked):
        the certified states at the times t (at an event time the state after it), rounded to
        float.

        Parameters
        ----------
        t : rational-like or sequence of rational-like
            The times, in [0, ``t_last``]: rationals, or floats read as their shortest decimal.
        u, y : bool, optional
            Add the k columns of u(t), then the k of y(t) (an undetermined input is NaN); default
            False.

        Examples
        --------
        >>> from lcs_exact.examples import two_carts
        >>> from lcs_exact import simulate
        >>> simulate(two_carts(), [0, 1, -1, 0], 1).to_numpy([0, 0.5]).round(6).tolist()
        [[0.0, 1.0, 0.0, 0.0], [0.117359, 0.880101, 0.439551, -0.459615]]
        """
        return array(self, t, u, y)

    def to_pandas(self, t: Any, *, u: bool = False, y: bool = False, outputs: bool | None = None):
        """A pandas DataFrame indexed by t (name ``t``) with the state names as columns (then u
        and y when asked, named as in plots: the builder's words, ``u_0``, or ``u (stop)``;
        :func:`~lcs_exact.statespace.signal_names`), then the outputs the builder declared, e.g. a
        relay's ``w_0``: :meth:`to_numpy` with labels.

        Parameters
        ----------
        t, u, y
            As for :meth:`to_numpy`.
        outputs : bool, optional
            Add the columns of the declared outputs (:meth:`outputs`); default: when there are any.

        Examples
        --------
        >>> from lcs_exact.models import relay
        >>> from lcs_exact import simulate
        >>> lcs = relay([[0]], [[-1]], [[1]])        # x' = -w, w in Sgn(x)
        >>> df = simulate(lcs, lcs.embed([1]), 2).to_pandas([0, "1/2", "3/2"])
        >>> list(df.columns), df["w_0"].tolist(), df["x_0"].tolist()
        (['x_0', 'c', 'w_0'], [1.0, 1.0, 0.0], [1.0, 0.5, 0.0])
        """
        return data_frame(self, t, u, y, outputs)

    def to_control(self, t: Any):
        """The run at the times ``t`` as a python-control ``TimeResponseData`` (needs the extra
        ``control``): ``time``, ``states`` x(t), ``inputs`` u(t), ``outputs`` y(t), each at an
        event time the value after it (as :meth:`to_numpy`), certified then rounded to float64,
        named as :meth:`LCS.to_statespace <lcs_exact.LCS.to_statespace>` names them; ``success``
        is False for a partial run.  See :func:`lcs_exact.statespace.time_response`.

        Parameters
        ----------
        t : sequence of rational-like
            The times, as for :meth:`to_numpy`.

        Examples
        --------
        >>> from lcs_exact.examples import two_carts
        >>> from lcs_exact import simulate
        >>> r = simulate(two_carts(), [0, 1, -1, 0], 1).to_control([0, 0.5, 1])
        >>> r.state_labels, r.input_labels, r.states.shape, r.inputs.shape
        (['q_0', 'q_1', "q_0'", "q_1'"], ['force (stop)'], (4, 3), (3,))
        """
        return time_response(self, t)

    def to_csv(self, path: Any, t: Any, *, u: bool = False, y: bool = False) -> None:
        """Write t and the states (u, y) at the times t as CSV (the format ``lcs-exact compare``
        reads: a header line, then t, x1, ..., xn); floats written to 17 significant digits.

        Parameters
        ----------
        path : str or path-like
            The file (overwritten).
        t, u, y
            As for :meth:`to_numpy`."""
        write_csv(self, path, t, u, y)

    def to_npz(self, path: Any, t: Any, *, u: bool = False, y: bool = False) -> None:
        """Write ``t`` (float64), ``x`` (len(t) x columns) and ``names`` to a NumPy .npz file.

        Parameters
        ----------
        path : str or path-like
            The file (``numpy.savez`` adds ``.npz`` when the name lacks it).
        t, u, y
            As for :meth:`to_numpy`."""
        write_npz(self, path, t, u, y)

    # --- display ------------------------------------------------------------------------------
    def __str__(self):
        evs = [f"  {e!r}" for e in self.events] if len(self.events) <= 40 else \
            [f"  {e!r}" for e in self.events[:20]] + [f"  ... {len(self.events) - 30} more events (traj.events) ..."] + \
            [f"  {e!r}" for e in self.events[-10:]]
        return "\n".join([repr(self)] + evs)

    def __repr__(self):
        if self.certified:
            status = "certified"
        elif self.assumptions:
            status = f"NOT certified ({len(self.assumptions)} assumptions)"
        else:
            status = "NOT certified"
        if self.choices:
            status += f", one of several solutions ({len(self.choices)} choices)"
        if not self.partial:
            return f"<Trajectory on [0, {self.t_end.label()}]: {len(self.events)} events, {status}>"
        # a partial run is known up to t_last only: say so first, then the horizon asked for
        return (f"<Trajectory known on [0, {self.t_last.label()}] of [0, {self.t_end.label()}] (PARTIAL, "
                f"{self.status.value}): {len(self.events)} events, {status}; {self.stop_reason}>")

    def _repr_latex_(self):
        rows = []
        derive = len(self.events) <= 10  # closed forms are proven on demand: only for short tables
        for e in self.events[:50]:
            cf = e.time.closed_form if derive else e.time.known_closed_form
            if cf is not None:
                import sympy
                t = sympy.latex(cf)
            else:
                t = e.time.decimal(12).replace(" +/- ", r" \pm ")
            mb = "-" if e.mode_before is None else latex_mode(e.mode_before)
            rows.append(rf"{t} & {mb} & {latex_mode(e.mode_after)} & {e.multiplicity} \\")
        body = "\n".join(rows)
        if len(self.events) > 50:
            body += "\n" + rf"\multicolumn{{4}}{{l}}{{\text{{... {len(self.events) - 50} more events}}}} \\"
        return r"$\begin{array}{llll} t & I^- & I^+ & m \\ \hline " + body + r"\end{array}$"


def _components(v: ExactVector):
    """p -> the components of v as balls at p bits."""
    def at(prec: int) -> list[arb]:
        xb = v.arb(prec)
        return [xb[i, 0] for i in range(xb.nrows())]
    return at


def _accurate(b: arb, need: int) -> bool:
    return b.is_exact() or accuracy_bits(b) >= need or (b.rad() < arb(2) ** (-need))


def full_feedback(mode) -> fmpq_mat:
    """k x n matrix with rows F_I on I and zero rows elsewhere."""
    lcs = mode.lcs
    F = mode.feedback()
    out = fmpq_mat(lcs.k, lcs.n)
    for r, i in enumerate(mode.I):
        for j in range(lcs.n):
            out[i, j] = F[r, j]
    return out



class Branches:
    """The solutions of a non-unique problem (:func:`~lcs_exact.simulate_branches`, or
    ``simulate(..., branches="all")``): one
    :class:`Trajectory` per sequence of choices between different initial solutions, each
    recording its ``choices``.

    ``unique`` is False when the solution is not unique (some branch made a choice: Theorem 6.3
    does not hold and S(z) held different initial solutions somewhere); then every trajectory is
    *a* solution, and each is ``certified`` when no sign was assumed on it: its digits are right
    for that solution.  ``certified`` is True when every branch is.  A branch stopped early (a
    limit, an unresolved sign) keeps its partial trajectory and status.

    Parameters
    ----------
    trajectories : sequence of Trajectory
        One per branch (the attribute ``trajectories``, a tuple; also the items of the Branches).
    """

    __slots__ = ("trajectories",)

    def __init__(self, trajectories: Sequence[Trajectory]):
        object.__setattr__(self, "trajectories", tuple(trajectories))

    def __setattr__(self, name, value):
        raise AttributeError("Branches is immutable")

    def __len__(self):
        return len(self.trajectories)

    def __iter__(self):
        return iter(self.trajectories)

    def __getitem__(self, i):
        return self.trajectories[i]

    @property
    def unique(self) -> bool:
        """True iff no branch made a choice (the problem had one solution after all)."""
        return not any(tr.choices for tr in self.trajectories)

    @property
    def certified(self) -> bool:
        """True iff every branch is certified (each one solution, every digit proven)."""
        return all(tr.certified for tr in self.trajectories)

    def __repr__(self):
        n = len(self.trajectories)
        kind = "unique" if self.unique else "NOT unique"
        cert = ("each certified" if self.certified else
                f"{sum(tr.certified for tr in self.trajectories)} of {n} certified")
        lines = [f"<Branches: {n} solution{'s' if n != 1 else ''}, {kind}, {cert}>"]
        for tr in self.trajectories:
            picks = ", ".join(f"t = {t.label()}: {format_mode(m)}" for t, m in tr.choices)
            lines.append(f"  [{picks}] {tr!r}")
        return "\n".join(lines)

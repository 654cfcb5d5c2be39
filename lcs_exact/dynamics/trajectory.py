"""Results of a simulation: :class:`Event`, :class:`PhaseRecord` and :class:`Trajectory`.

Every number is an exact real (:mod:`lcs_exact.reals`): ``.closed_form`` where proven (derived on
first access), ``.ball(digits)`` / ``.decimal(digits)`` certified to any number of digits, under
the run's precision policy.  Results are immutable values with a :class:`Status`; a trajectory
stopped early (a limit, an accumulation of events, a deadlock, an unresolved sign) is ``partial``
and says why in ``stop_reason``.  Indices are 0-based.
"""
from __future__ import annotations


import enum
from dataclasses import dataclass, field
from typing import Any, Sequence

from flint import arb, fmpq, fmpq_mat

from ..numbers import DEFAULT_POLICY, Policy, accuracy_bits, check_digits, digits_to_bits, workprec
from ..errors import InvalidArgument, LCSError, Undetermined
from ..interfaces import AccumulationWindow
from .fixture import fixture_dict
from .timeline import Timeline
from ..modes import format_mode, latex_mode
from ..display import derived_outputs
from ..display import plot_trajectory
from ..algebra import as_list, to_fmpq
from ..numbers import Real, as_real
from ..system import source_block
from ..system import signal_names, time_response
from ..numbers import ComponentsVector, ExactVector, ProjectedVector

__all__ = ["Event", "PhaseRecord", "Trajectory", "Status", "SCHEMA", "Branches"]

SCHEMA = "lcs-exact/trajectory/1"


class Status(str, enum.Enum):
    """How a run ended (diffrax's ``RESULTS``): only ``COMPLETE`` covers [0, t_end]."""

    COMPLETE = "complete"
    EVENT_LIMIT = "event limit"
    TIME_LIMIT = "time limit"
    HORIZON_LIMIT = "horizon limit"
    DEADLOCK = "deadlock"
    ZENO = "accumulation of events"
    UNRESOLVED = "unresolved sign"
    ILL_POSED = "ill-posed"
    INTERRUPTED = "interrupted"
    FAILED = "failed"


@dataclass(frozen=True)
class Event:
    """An event (section 4.5): a phase ends or the state jumps.

    ``modes`` is the re-initialization chain (4.9): the modes I_1, I_2, ... whose projections
    were applied, ``multiplicity`` their number m(tau); ``mode_after`` is the mode of the next
    continuous phase (the smallest admissible mode, Remark 4.8); ``mode_before`` is None at
    t = 0.  ``impulse`` maps i to u^{-i} (the coefficient of delta^{(i)}) of the first jump.
    ``triggers`` names the constraints whose sign change ended the phase (``"y_0"``, ``"u_1"``).
    """

    time: Real
    mode_before: frozenset | None
    modes: tuple
    mode_after: frozenset
    state_before: ExactVector
    state_after: ExactVector
    multiplicity: int
    impulse: dict = field(default_factory=dict)
    triggers: tuple = ()

    def __repr__(self):
        mb = "—" if self.mode_before is None else format_mode(self.mode_before)
        chain = " -> ".join(format_mode(m) for m in self.modes) or \
            ("reset (schedule)" if "schedule" in self.triggers and self.state_before is not self.state_after else "no jump")
        return (f"Event(t={self.time.label()}, {mb} => {format_mode(self.mode_after)}, jumps: {chain}, "
                f"x- = {self.state_before!r}, x+ = {self.state_after!r})")

    def _repr_latex_(self):
        cf = self.time.closed_form
        if cf is not None:
            import sympy
            t = sympy.latex(cf)
        else:
            t = self.time.decimal(15).replace(" +/- ", r" \pm ")
        return rf"$t = {t}:\ {latex_mode(self.mode_before or frozenset())} \to {latex_mode(self.mode_after)}$"


@dataclass(frozen=True)
class PhaseRecord:
    """A continuous phase on [t0, t1] in ``mode`` (``phase`` evaluates x(t - t0)).
    ``undetermined``: the inputs u_j that the state does not determine on it (a floating
    network, docs/extensions.md); they are reported as undetermined, never chosen."""

    t0: Real
    t1: Real
    mode: frozenset
    phase: Any
    undetermined: frozenset = frozenset()


class Trajectory:
    """The solution of an LCS on [0, t_end] produced by Algorithm 7.1 (immutable).

    ``events``, ``phases``, ``accumulations``, ``assumptions`` are tuples; ``status`` a
    :class:`Status`; ``partial`` is True unless the run covered [0, t_end].  ``choices`` lists
    (time, mode) for every point where S(z) left a choice between different initial solutions
    (``simulate(..., branches="all")``): such a trajectory is *a* solution, not *the* solution
    (``unique`` is False), and it is ``certified`` like any other when no sign was assumed: every
    digit it reports is right for the solution it follows.
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
        """x(t), exact (t rational or an exact real); at an event time, the state after it."""
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
        it, u(t+), as :meth:`state` gives x(t+) (the impulse at the event is in
        ``Event.impulse``).  An input that the state does
        not determine there (:meth:`undetermined`) is reported as such: its component is an
        :class:`UndeterminedReal` (printed ``undetermined``; asking it for digits raises
        :class:`~lcs_exact.errors.Undetermined`)."""
        t = as_real(t, self.policy)
        rec = self._phase_at(t)
        if isinstance(rec.phase, AccumulationWindow):
            return rec.phase.output(t - rec.t0, "u")
        v = ProjectedVector(full_feedback(rec.phase.mode), rec.phase.state(t - rec.t0))
        return PartlyUndetermined(v, rec.undetermined, "u") if rec.undetermined else v

    def y(self, t: Any) -> ExactVector:
        """y(t) = C x + D u on a continuous phase, y(t+) at an event time (components that depend
        on an undetermined input are undetermined, as for :meth:`u`)."""
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
        and point, from the phase's modal data: thousands of points in well under a second."""
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
        """A dict in the fixture schema ``lcs-exact/trajectory/1`` (see lcs_exact.fixture);
        ``closed_forms=False`` writes only the closed forms already derived (a quick write);
        ``provenance`` (a JSON-ready dict: builder, parameters, version, ...) is written as the
        fixture's ``provenance`` and covered by its digest."""
        return fixture_dict(self, digits, sample, closed_forms, provenance)

    def plot(self, **kw):
        """States and u/y (or the declared outputs w) against t, events and jumps marked.

        Keywords (:func:`lcs_exact.plotting.plot_trajectory`): ``states`` and ``constraints``
        (indices or names to draw), ``panels`` (a subset of ``("x", "w", "u", "y")``; ``"w"``:
        the outputs a builder declared, :meth:`outputs`, drawn instead of u and y by default),
        ``points`` (about 800 certified sample times in total), ``label_events`` (at most how
        many events get a label), ``figsize``, ``title``, ``sources`` (draw the states the
        builder appended for its sources, hidden by default).  Returns the matplotlib Figure."""
        return plot_trajectory(self, **kw)

    # --- arrays and data frames ---------------------------------------------------------------
    def _columns(self, t: Any, u: bool, y: bool, w: bool = False) -> tuple[list, list[str], list[list[float]]]:
        """(times as fmpq, column names, rows of floats): the states at t (right limits), then
        u and y when asked (an undetermined input is NaN), then the declared outputs (``w``)."""
        if hasattr(t, "tolist"):
            t = as_list(t)
        if isinstance(t, (str, bytes)) or not hasattr(t, "__iter__"):
            t = [t]
        ts = [to_fmpq(v, "t") for v in t]
        names = list(self.lcs.state_names)
        rows = [[float(b.mid()) for b in row] for row in self.sample(ts, 17)]
        for kind, wanted in (("u", u), ("y", y)):
            if not wanted:
                continue
            names += signal_names(self.lcs)[1 if kind == "u" else 2]
            for row, tq in zip(rows, ts):
                vec = getattr(self, kind)(tq)
                row += [float(c) for c in vec]
        if w:
            names += list(self.output_names)
            for row, tq in zip(rows, ts):
                row += [float(c) for c in self.outputs(tq)]
        return ts, names, rows

    def to_numpy(self, t: Any, *, u: bool = False, y: bool = False):
        """A float64 array of shape (len(t), n) (plus k columns for u and k for y when asked):
        the certified states at the times t (rationals, or floats read as their shortest decimal;
        at an event time the state after it), rounded to float.

        >>> from lcs_exact.examples import two_carts
        >>> from lcs_exact import simulate
        >>> simulate(two_carts(), [0, 1, -1, 0], 1).to_numpy([0, 0.5]).round(6).tolist()
        [[0.0, 1.0, 0.0, 0.0], [0.117359, 0.880101, 0.439551, -0.459615]]
        """
        import numpy as np
        _, _, rows = self._columns(t, u, y)
        return np.array(rows, dtype=np.float64)

    def to_pandas(self, t: Any, *, u: bool = False, y: bool = False, outputs: bool | None = None):
        """A pandas DataFrame indexed by t (name ``t``) with the state names as columns (then u
        and y when asked, named as in plots: the builder's words, ``u_0``, or ``u (stop)``;
        :func:`~lcs_exact.statespace.signal_names`), then the outputs the builder declared, e.g. a
        relay's ``w_0`` (by default when there are any): :meth:`to_numpy` with labels.

        >>> from lcs_exact.models import relay
        >>> from lcs_exact import simulate
        >>> lcs = relay([[0]], [[-1]], [[1]])        # x' = -w, w in Sgn(x)
        >>> df = simulate(lcs, lcs.embed([1]), 2).to_pandas([0, "1/2", "3/2"])
        >>> list(df.columns), df["w_0"].tolist(), df["x_0"].tolist()
        (['x_0', 'c', 'w_0'], [1.0, 1.0, 0.0], [1.0, 0.5, 0.0])
        """
        try:
            import pandas as pd
        except ImportError:
            raise InvalidArgument("to_pandas needs pandas: pip install pandas (or lcs_exact[data])") from None
        if outputs is None:
            outputs = bool(self.output_names)
        ts, names, rows = self._columns(t, u, y, outputs)
        return pd.DataFrame(rows, index=pd.Index([float(v) for v in ts], name="t"), columns=names)

    def to_control(self, t: Any):
        """The run at the times ``t`` as a python-control ``TimeResponseData`` (needs the extra
        ``control``): ``time``, ``states`` x(t), ``inputs`` u(t), ``outputs`` y(t), each at an
        event time the value after it (as :meth:`to_numpy`), certified then rounded to float64,
        named as :meth:`LCS.to_statespace <lcs_exact.LCS.to_statespace>` names them; ``success``
        is False for a partial run.  See :func:`lcs_exact.statespace.time_response`.

        >>> from lcs_exact.examples import two_carts
        >>> from lcs_exact import simulate
        >>> r = simulate(two_carts(), [0, 1, -1, 0], 1).to_control([0, 0.5, 1])
        >>> r.state_labels, r.input_labels, r.states.shape, r.inputs.shape
        (['q_0', 'q_1', "q_0'", "q_1'"], ['force (stop)'], (4, 3), (3,))
        """
        return time_response(self, t)

    def to_csv(self, path: Any, t: Any, *, u: bool = False, y: bool = False) -> None:
        """Write t and the states (u, y) at the times t as CSV (the format ``lcs-exact compare``
        reads: a header line, then t, x1, ..., xn); floats written to 17 significant digits."""
        import csv
        ts, names, rows = self._columns(t, u, y)
        with open(path, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["t"] + names)
            for tq, row in zip(ts, rows):
                w.writerow([repr(float(tq))] + [repr(v) for v in row])

    def to_npz(self, path: Any, t: Any, *, u: bool = False, y: bool = False) -> None:
        """Write ``t`` (float64), ``x`` (len(t) x columns) and ``names`` to a NumPy .npz file."""
        import numpy as np
        ts, names, rows = self._columns(t, u, y)
        np.savez(path, t=np.array([float(v) for v in ts]), x=np.array(rows, dtype=np.float64),
                 names=np.array(names))

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


class UndeterminedReal(Real):
    """A component the solution does not determine (an input left free by the state, or an
    output depending on one): it has no value to give.  Its ball is the whole real line (it
    contains every admissible value); digits, signs and closed forms raise
    :class:`~lcs_exact.errors.Undetermined`."""

    def __init__(self, name: str, policy: Policy | None = None):
        super().__init__(policy)
        self.name = name

    def _compute(self, prec):
        return arb(0, "inf")

    def _refuse(self, *args, **kw):
        raise Undetermined(f"{self.name} is not determined by the state here: any value that keeps the "
                           "complementarity conditions solves the LCS (a free input of a mode that is not "
                           "autonomous, e.g. the potential of a floating node)")

    ball = decimal = sign = _refuse

    def __float__(self):
        return float("nan")

    def label(self) -> str:
        return "undetermined"

    def __repr__(self):
        return "undetermined"

    def _closed_form(self):
        return None


class PartlyUndetermined(ExactVector):
    """u(t) or y(t) with some components undetermined (:class:`UndeterminedReal`); the others
    are those of ``v``.  Its ball has infinite radius in the undetermined components."""

    def __init__(self, v: ExactVector, undetermined: frozenset, kind: str):
        super().__init__(v.n, None, v.policy)
        self.v, self.free, self.kind = v, frozenset(undetermined), kind

    def _deps(self):
        return (self.v,)

    def _compute(self, prec):
        from flint import arb_mat
        b = self.v.arb(prec)
        return arb_mat([[arb(0, "inf") if i in self.free else b[i, 0]] for i in range(self.n)])

    def _structural_sign(self, form):
        if any(form[0, j] != 0 for j in self.free):
            UndeterminedReal(f"a form in {self.kind}").sign()
        return self.v.sign_of_form(form)

    def known_rational(self):
        return None

    def __getitem__(self, i: int) -> Real:
        if not -self.n <= i < self.n:
            raise IndexError(f"component {i} of a vector of length {self.n}")
        i %= self.n
        return UndeterminedReal(f"{self.kind}_{i}", self.policy) if i in self.free else self.v[i]

    def __iter__(self):
        return (self[i] for i in range(self.n))

    def __repr__(self):
        return "(" + ", ".join(c.label() for c in self) + ")"


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

"""The continuous phase in mode I (section 4.1): x(t) = e^{A_I t} z and its constraint functions.

From a consistent state z in V_I the phase is x(t) = e^{A_I t} z with A_I = A + B_.I F_I; the
monitored functions (4.5) are u_i = (F_I)_i x (i in I) and y_i = (C_i + D_{i,I} F_I) x (i not
in I), each f(t) = g e^{A_I t} z with a rational row g (:class:`Constraint`).

Representation.  The spectral data of A_I live on the mode (computed once per mode); the phase
computes the modal vectors K_lambda N^j z / j! of its start once per precision, and every
constraint is then an exponential sum (:class:`PhaseFunction`, :class:`~lcs_exact.roots.ExpSum`).
Homogeneity: when z = c v with c > 0 proven (:class:`~lcs_exact.vectors.ScaledVector`), the
functions are those of v - the same roots, exactly, with no dependence on c.

Forms vanishing on the whole phase (``zero_forms``): for a rational start q, the left kernel of
the Krylov matrix [q, A_I q, ..., A_I^{n-1} q]; otherwise the annihilator of V_I and the
A_I-invariant part of the relations known on z.
"""
from __future__ import annotations

import decimal
from dataclasses import dataclass
from typing import Any

from flint import acb_mat, arb, arb_mat, fmpq, fmpq_mat

from ..numbers import calcium
from ..numbers import Policy, dyadic_lower, dyadic_upper, workprec
from ..errors import LCSError
from ..modes import format_mode
from ..numbers import RationalReal, as_real, ca_from_state, ca_state
from ..numbers import ExactVector, ExpVector, RationalVector, ScaledVector, TaylorSteps, algebraic_vector, ca_matvec, first_step, orbit_start
from ..algebra import eliminate
from ..algebra import MAX_HORIZON_FAST, MAX_HORIZON_SLOW, is_zero, row_norms, submatrix, to_fmpq, vstack, zeros
from .roots import ExpSum, RootReal, newton_ball
from .taylorsum import TaylorRows, TaylorSum
from ..algebra import RowSpan, invariant_forms, orbit_zero_forms, row_basis

__all__ = ["Constraint", "Phase", "PhaseFunction", "EventState", "phase_horizon", "TAYLOR_MIN_N"]

#: a mode's phases are evaluated by Taylor steps (:mod:`lcs_exact.numbers.taylorsteps`) from this
#: state dimension on; below it the spectral data are cheap and kept (one computation per mode).
#: Measured on the chains of carts to t = 10 (a few events, short phases) and t = 300 (190
#: events): n = 16 runs 30 % faster on spectral data; n = 24 15-25 % faster on Taylor steps to
#: t = 10 but 10 % slower to t = 300; n = 32 10 % faster and 6 % slower; n = 64 twice as fast
TAYLOR_MIN_N = 32
#: ... and only for ||A_I||_inf up to this (a stiff mode keeps the spectral path)
TAYLOR_MAX_NORM = 2 ** 12
#: ... and for runs of at most this many bits (about 300 digits: a step's order grows with the
#: precision, J = 98 at 300 bits, and the spectral path's cost much less)
TAYLOR_MAX_BITS = 1024
#: the most units of ||A_I|| t a phase's search steps over (4 units a step; 128 steps cost about
#: what the spectral data of a mode of n = 128 cost: a longer quiet horizon takes that path)
TAYLOR_MAX_SPAN = 4 * 128
#: the precision of a phase's screen for events (:meth:`Phase.screen_rows`): every constraint
#: proven > 0 up to the horizon on Taylor steps of this many bits means no event, and the steps at
#: the search's precision are never built (a quiet phase to t_end was a quarter of a 32-state chain)
SCREEN_PREC = 64
#: bits of accuracy a run may lose before its event states on Taylor steps take the centered form
#: (from the mode's spectral data): plain balls lose ~2.2 bits an event against ~1.2, which a long
#: run pays in re-anchoring at a growing precision; a short run does not pay for the spectral data
CENTERED_AFTER_LOST = 64


@dataclass(frozen=True)
class Constraint:
    """One monitored function of a phase: ``kind`` 'u' or 'y', constraint ``index``, row ``g``.
    In a mode that is not autonomous, ``kind`` 'c' is a condition on the state left by
    eliminating the free inputs (``label`` names the rows it combines, e.g. ``"u_1 & y_0"``)."""

    kind: str
    index: int
    g: fmpq_mat
    label: str = ""

    @property
    def name(self) -> str:
        return self.label or f"{self.kind}_{self.index}"


class PhaseFunction:
    """f(t) = g e^{A_I t} v on a phase (v its start, or the base of a scaled start) as a
    :class:`~lcs_exact.roots.RootFunction`: exponential sums at any precision."""

    def __init__(self, phase: "Phase", g: fmpq_mat, name: str):
        self.phase, self.g, self.name = phase, g, name
        self.policy = phase.policy
        self._sum: ExpSum | None = None

    def at(self, prec: int) -> ExpSum | TaylorSum:
        if self._sum is None or self._sum.prec < prec:
            if self.phase.taylor:
                self._sum = self.phase.taylor_sum(self.g, prec)
                return self._sum
            modal = self.phase.modal(prec)
            with workprec(prec):
                gc = acb_mat(self.g)
                terms = [(lam, w, [(gc * v)[0, 0] for v in ws]) for lam, w, ws in modal]
            self._sum = ExpSum(terms, prec)
        return self._sum

    def deps(self) -> tuple:
        return (self.phase.base,)

    def __getstate__(self):
        # the exponential sum is a ball cache of the exact data (rebuilt on demand): a pickled
        # trajectory (sweeps) carries its exact definitions and computed digits, not its caches
        return {**self.__dict__, "_sum": None}

    def exact_coefficients(self) -> list | None:
        """f as an exact polynomial in t, sum_j c_j t^j with c_j = g N^j z / j!, when A_I is
        nilpotent (a free fall, a relay's constant field, a chain of integrators) and the start
        z is known exactly: ``fmpq`` coefficients for a rational z, Calcium numbers for an
        algebraic one; None otherwise."""
        z = self.phase.exact_start
        if z is None:
            return None
        rows = [self.g * P for P in self.phase.spectrum.nilpotent]
        if isinstance(z, fmpq_mat):
            return [(r * z)[0, 0] for r in rows]
        return [ca_matvec(r, z)[0] for r in rows]

    def describe(self) -> str:
        return self.name

    def derivative(self) -> "PhaseFunction":
        """f' = g A_I e^{A_I t} v."""
        return PhaseFunction(self.phase, self.g * self.phase.M, f"{self.name}'")


class Phase:
    """The continuous phase in mode I from the consistent state z (x(t) = e^{A_I t} z)."""

    def __init__(self, mode, z: ExactVector, policy: Policy, lost: int = 0):
        self.mode = mode
        # event states on Taylor steps in the centered form once the run lost that many bits
        self.centered = lost > CENTERED_AFTER_LOST
        self.lcs = mode.lcs
        self.policy = policy
        self.M = mode.closed_loop()
        # Taylor steps (no spectral data) for a mode of a large system that is neither nilpotent
        # (its phases are polynomials, exactly) nor too fast for steps of ||A_I h|| <= 4
        # and a run's precision at which a step's order (J ~ bits / 3) stays moderate
        self.taylor = (self.M.nrows() >= TAYLOR_MIN_N and policy.target_bits <= TAYLOR_MAX_BITS
                       and not mode.closed_loop_nilpotent and 0 < mode.closed_loop_norm <= TAYLOR_MAX_NORM)
        self.z = z
        if isinstance(z, ScaledVector):
            self.base, self.scale = z.v, z.c
        else:
            self.base, self.scale = z, None
        inner, _ = orbit_start(self.base, self.M)
        q = inner.known_rational()
        if q is not None:
            self.zero_forms = orbit_zero_forms(self.M, q)
        else:
            W = mode.annihilator()
            # W (V_I = Ker W) vanishes on the phase and is invariant under A_I (section 3): the
            # forms of the start are iterated modulo it
            inv = invariant_forms(self.base.zero_forms, self.M, W) if self.base.zero_forms.nrows() else W
            self.zero_forms = row_basis(inv) if inv.nrows() else zeros(0, self.M.nrows())
        if mode.derived.constraints is None:  # the same for every phase of the mode
            cons, G = self._constraints()
            n = self.M.ncols()
            G = vstack(*[c.g for c in cons], ncols=n) if G is None else G
            mode.derived.constraints = (tuple(cons), row_norms(G), G)
        self.constraints = list(mode.derived.constraints[0])
        q0 = self.base.known_rational()
        # A_I z = 0, proven: x(t) = z throughout, so every monitored function is constant (no
        # event ever, at any horizon).  Exact for a rational start; for another, when every row
        # of A_I is among the forms proven to vanish on the phase
        self.equilibrium = is_zero(self.M * q0) if q0 is not None else \
            all(submatrix(self.M, [i], None) in self.zero_span for i in range(self.M.nrows()))
        # a polynomial phase (A_I nilpotent) from an exactly known start: exact roots and states
        self.exact_start = None
        if not self.taylor and self.spectrum.nilpotent_only:
            q = self.base.known_rational()
            self.exact_start = q if q is not None else self.base.known_ca()
        self._powers: dict = {}
        self._orders: dict = {}
        self._rows: TaylorRows | None = None
        self._screen: TaylorRows | None = None
        self._first: fmpq | None | bool = False  # the Taylor steps' first step (False: not guessed yet)
        self._end: fmpq | None = None  # an upper bound of the times the phase is evaluated at later
        self._modal = None
        self._modal_prec = 0
        self._functions: dict = {}

    def _constraints(self) -> tuple[list[Constraint], fmpq_mat | None]:
        """(the monitored functions, their rows stacked or None): u_I = F_I x and
        y_Ic = (C_Ic + D_Ic,I F_I) x (section 4.1), computed as two blocks and cut into rows
        (a row at a time cost 4 ms a mode at n = 128); None when free inputs were eliminated."""
        mode, C, D = self.mode, self.lcs.C, self.lcs.D
        F = mode.feedback()
        n = C.ncols()
        Gy = submatrix(C, mode.Ic, None)
        if mode.I and mode.Ic:
            Gy = Gy + submatrix(D, mode.Ic, mode.I) * F
        G = vstack(F, Gy, ncols=n)  # the u rows, then the y rows: the order of the constraints
        e = G.entries()
        rows = [fmpq_mat(1, n, e[r * n:(r + 1) * n]) for r in range(G.nrows())]
        m = len(mode.I)
        cons = [Constraint("u", i, rows[r]) for r, i in enumerate(mode.I)] + \
            [Constraint("y", i, rows[m + r]) for r, i in enumerate(mode.Ic)]
        W = mode.free_inputs() if mode.I else None
        if W is None or W.ncols() == 0:
            return cons, G
        # a state-determined mode with free inputs b (u_I = F x + W b): the phase lasts while
        # some b keeps u_I >= 0 and y_Ic >= 0, i.e. while the rows left by Fourier-Motzkin hold
        d = W.ncols()
        rows = []
        for r, c in enumerate(cons):
            if c.kind == "u":
                h = [W[r, j] for j in range(d)]
            else:
                DW = submatrix(D, [c.index], mode.I) * W
                h = [DW[0, j] for j in range(d)]
            rows.append(([c.g[0, j] for j in range(c.g.ncols())], h, frozenset({c.name})))
        out = []
        for k, (g, label) in enumerate(eliminate(rows, d)):
            names = sorted(label)
            kind, _, idx = names[0].partition("_")
            row = fmpq_mat(1, len(g), g)
            out.append(Constraint(kind, int(idx), row) if len(names) == 1 else
                       Constraint("c", k, row, " & ".join(names)))
        return out, None

    def __getstate__(self):
        state = {**self.__dict__, "_modal": None, "_modal_prec": 0, "_rows": None, "_screen": None}  # ball caches, as above
        if isinstance(self.exact_start, list):  # Calcium numbers travel as exact descriptions (sweeps)
            state["exact_start"] = ("ca", [ca_state(c) for c in self.exact_start])
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.__dict__.setdefault("_orders", {})
        if isinstance(self.exact_start, tuple):
            self.exact_start = [ca_from_state(c) for c in self.exact_start[1]]

    @property
    def spectrum(self):
        """The spectral data of A_I (:class:`~lcs_exact.expm.Spectrum`; computed by the mode once,
        on first use: a phase on Taylor steps may never need it)."""
        return self.mode.spectrum()

    def use_spectral(self, horizon: fmpq) -> None:
        """Leave Taylor steps for the spectral path when the search would span more than
        TAYLOR_MAX_SPAN units of ||A_I|| t (a long horizon without events: steps cost per unit
        of time, the spectral data once per mode).  Called before any function is evaluated."""
        if self.taylor and self._rows is None and horizon * self.mode.closed_loop_norm > TAYLOR_MAX_SPAN:
            self.taylor = False
            for f in self._functions.values():
                f._sum = None

    # --- data per precision -------------------------------------------------------------------
    def propagate(self, dt: arb, prec: int) -> arb_mat:
        """e^{A_I dt} v at a ball dt (v the phase's start, or the base of a scaled start), at
        ``prec`` bits: Taylor steps, or one exponential per eigenvalue from the modal data."""
        if self.taylor:  # dt >= 0: a root's ball may reach below 0 by rounding
            return self.taylor_rows(prec).steps.state(dt, nonnegative=True)
        with workprec(prec):
            return self.spectrum.apply(dt, self.base.arb(prec), prec, self.modal(prec))

    def ball_state(self, dt: arb, prec: int) -> arb_mat:
        """x(t) at a ball dt = t - t_s (relative to the phase start), at ``prec`` bits (sampling,
        plots)."""
        x = self.propagate(dt, prec)
        with workprec(prec):
            return x * self.scale.arb(prec) if self.scale is not None else x

    def taylor_rows(self, prec: int) -> TaylorRows:
        """The constraints' polynomials on Taylor steps from the start's ball at ``prec`` bits (or
        more: cached at the highest precision asked; a higher one restarts from the exact start)."""
        if self._rows is None or self._rows.prec < prec:
            self.policy.check_deadline(lambda: f" while isolating events: Taylor steps of mode "
                                       f"{format_mode(self.mode.I)} at {prec} bits")
            x0, norm = self.base.arb(prec), self.mode.closed_loop_norm
            G = self.mode.derived.constraints[2]  # the constraints' rows, stacked once a mode
            Ma, Ga = self._mode_balls(prec, G)
            if self._first is False:  # once a phase: the grid of the search
                self._first = first_step(self.M, G, x0, prec, norm, (Ma, Ga))
            first = self._first
            if self._end is not None:  # steps built once the phase's end is bounded reach only so far
                first = self._end if first is None else min(first, self._end)
            steps = TaylorSteps(self.M, norm, x0, prec, self.zero_coordinates(), first, balls=Ma)
            self._rows = TaylorRows(steps, [c.g for c in self.constraints], self.row_norms, G, balls=Ga)
        return self._rows

    def ends_by(self, t: fmpq) -> None:
        """Every later evaluation of the phase is at times <= t (its event is bracketed below t):
        steps built from now on, at higher precisions (the event's refinement, the history of a
        later start), take a first step longer than t, so that one step of low order holds the
        whole phase (an event at 0.0129 of a step of length 1: 130 terms at 1224 bits, not 268).
        Only the cost depends on it: the grid covers every t >= 0 whatever its first step.

        Parameters
        ----------
        t : fmpq
            A positive bound."""
        if t > 0:
            end = 2 * t  # TaylorSteps rounds a first step down to a power of two: still > t
            self._end = end if self._end is None else min(self._end, end)

    def starts_near(self, t: float) -> None:
        """A float guess t of the phase's first crossing (the screen's, :meth:`screen_rows`): when
        the search's steps take the uniform grid and none is computed yet, they are built again
        with a first step of about 2 t (a crossing at 0.0129 of a step of length 1: one step of
        ~30 terms at 181 bits, not 71).  Only the cost depends on the guess: the grid covers
        every t >= 0 whatever its first step.

        Parameters
        ----------
        t : float
            A positive guess."""
        rows = self._rows
        if self._first is not None or rows is None or rows.steps.computed or not t > 0:
            return
        with workprec(64):
            first = dyadic_upper(2 * arb(t))
        if first < rows.steps.h:
            self._first = first
            self._rows = None  # rebuilt (lazy: no step computed) at the precision it had
            self.taylor_rows(rows.prec)

    @property
    def first_step(self) -> fmpq | None:
        """The length of the Taylor steps' first step (:func:`~lcs_exact.numbers.first_step`: a
        constraint foreseen to cross 0 long before a regular step), None for the uniform grid;
        guessed when the first steps are built (:meth:`taylor_rows`)."""
        if self._first is False:
            raise LCSError("internal inconsistency: the first step is read before the Taylor steps are built")
        return self._first

    def screen_rows(self) -> TaylorRows:
        """The constraints' polynomials on Taylor steps of SCREEN_PREC bits on the uniform grid (no
        first-step guess): a cheap first look at a phase, whose proofs of f > 0 are as rigorous as
        those at any precision (balls), and whose midpoints are good enough for guesses where the
        constraints are not near a cancellation.  Built once a phase."""
        if self._screen is None:
            self.policy.check_deadline(lambda: f" while screening mode {format_mode(self.mode.I)} for events")
            G = self.mode.derived.constraints[2]
            kept = self.mode.derived.screen_balls
            if kept is None:
                with workprec(SCREEN_PREC):
                    kept = self.mode.derived.screen_balls = (arb_mat(self.M), arb_mat(G))
            x0 = self.base.arb(SCREEN_PREC)  # the anchor, whatever its precision
            steps = TaylorSteps(self.M, self.mode.closed_loop_norm, x0, SCREEN_PREC, self.zero_coordinates(),
                                balls=kept[0])
            self._screen = TaylorRows(steps, [c.g for c in self.constraints], self.row_norms, G, balls=kept[1])
        return self._screen

    def _mode_balls(self, prec: int, G: fmpq_mat) -> tuple[arb_mat, arb_mat]:
        """A_I and the constraints' rows as balls of ``prec`` bits or more, kept on the mode (a
        conversion of n^2 rationals a phase and precision, ~5 % of a 128-state run, otherwise)."""
        kept = self.mode.derived.balls
        if kept is None or kept[0] < prec:
            with workprec(prec):
                kept = (prec, arb_mat(self.M), arb_mat(G))
            self.mode.derived.balls = kept
        return kept[1], kept[2]

    @property
    def row_norms(self) -> list[fmpq]:
        """||g||_1 of each constraint's row (the tails of Taylor steps; once per mode)."""
        return self.mode.derived.constraints[1]

    def taylor_sum(self, g: fmpq_mat, prec: int) -> TaylorSum:
        """f = g x(t) on Taylor steps: a constraint's row from the phase's rows, another (a
        derivative, a bound) on the same steps."""
        rows = self.taylor_rows(prec)
        for i, c in enumerate(self.constraints):
            if c.g is g or c.g == g:
                return rows.function(i)
        return TaylorRows(rows.steps, [g]).function(0)

    def modal(self, prec: int) -> list:
        """Modal vectors of the phase's base start at ``prec`` bits (cached at the highest)."""
        if self._modal_prec < prec:
            modal = self.spectrum.modal(self.base.arb, prec, lambda: self.policy.check_deadline(
                f" while computing the spectral data of mode {format_mode(self.mode.I)} at {prec} bits"))
            zero = self.zero_coordinates()
            if zero:  # x_i = 0 on the whole phase: every modal coefficient of x_i is 0 exactly
                for _, _, ws in modal:
                    for w in ws:
                        for i in zero:
                            w[i, 0] = 0
            self._modal, self._modal_prec = modal, prec
        return self._modal

    def zero_coordinates(self) -> list[int]:
        """The coordinates i with x_i(t) = 0 on the whole phase (e_i in the span of the forms
        that vanish on it).  The exponentials e^{lambda t} t^j are independent, so each modal
        coefficient of such an x_i is exactly 0: balls computed through the spectral factors
        are replaced by exact zeros (a constrained cart's position samples as exactly 0)."""
        if "_zero_coords" not in self.__dict__:
            span = self.zero_span
            self._zero_coords = sorted(span.units())
        return self._zero_coords

    @property
    def zero_span(self) -> RowSpan:
        """The span of the forms vanishing on the phase, for membership tests (built once)."""
        if "_zero_span" not in self.__dict__:
            self._zero_span = RowSpan(self.zero_forms)
        return self._zero_span

    def function(self, c: Constraint) -> PhaseFunction:
        key = (c.kind, c.index)
        if key not in self._functions:
            self._functions[key] = PhaseFunction(self, c.g, c.name)
        return self._functions[key]

    def gM(self, c: Constraint, j: int) -> fmpq_mat:
        """g A_I^j (cached)."""
        key = (c.kind, c.index, j)
        if key not in self._powers:
            self._powers[key] = c.g if j == 0 else self.gM(c, j - 1) * self.M
        return self._powers[key]

    # --- the start of the phase (Lemma 5.1) ----------------------------------------------------
    def start_order(self, c: Constraint) -> tuple[int, int]:
        """(sign, order) of f at t = 0+: the first nonzero f^{(j)}(0) = g A_I^j z; (0, -1) if f = 0
        identically (Cayley-Hamilton: n zeros suffice).  Kept per constraint."""
        key = (c.kind, c.index, c.label)
        if key not in self._orders:
            self._orders[key] = self._start_order(c)
        return self._orders[key]

    def _start_order(self, c: Constraint) -> tuple[int, int]:
        if "_vanishing_rows" not in self.__dict__:  # the constraints' rows tested at once
            G = self.mode.derived.constraints[2]
            inside = set(self.zero_span.rows_inside(G)) if self.zero_forms.nrows() else set()
            self._vanishing_rows = {(d.kind, d.index, d.label): r in inside for r, d in enumerate(self.constraints)}
        vanishes = self._vanishing_rows.get((c.kind, c.index, c.label))
        if vanishes:
            # the forms vanishing on the phase span an A_I-invariant space (the largest invariant
            # one in those known at the start): g A_I^j vanishes with g, f = 0 on the whole phase
            return 0, -1
        for j in range(self.lcs.n):
            form = self.gM(c, j)
            if (j or vanishes is None) and form in self.zero_span:
                continue
            s = self.base.sign_of_form(form)
            if s:
                return s, j
        return 0, -1

    def vanishing(self, c: Constraint) -> bool:
        """f = 0 on the whole phase (proven)."""
        return self.start_order(c)[0] == 0

    # --- states -------------------------------------------------------------------------------
    def state(self, t: Any, extra_zero_forms: fmpq_mat | None = None) -> ExactVector:
        """x(t) = e^{A_I t} z (t relative to the phase start), with the phase's vanishing forms and
        ``extra_zero_forms`` (the constraints proven zero at t) as its known relations."""
        t = as_real(t, self.policy)
        zf = self.zero_forms
        if extra_zero_forms is not None and extra_zero_forms.nrows():
            zf = row_basis(zf, extra_zero_forms) if zf.nrows() else row_basis(extra_zero_forms)
        if t.known_rational() == 0 or self.equilibrium:
            return self.z
        x = self._exact_state(t, zf)
        if x is None:
            x = ExpVector(self.mode.spectrum, t, self.base, zf, self.policy, modal=self.modal, M=self.M,
                          propagate=self.propagate if self.taylor else None)
        return ScaledVector(self.scale, x, self.policy) if self.scale is not None else x

    def _exact_state(self, t, zero_forms) -> ExactVector | None:
        """e^{N t} z = sum_j N^j z t^j / j! exactly, on a polynomial phase from an exact start at
        an exactly known time t (rational or algebraic); None otherwise."""
        z = self.exact_start
        if z is None:
            return None
        tq = t.known_rational()
        nil = self.spectrum.nilpotent
        if tq is not None and isinstance(z, fmpq_mat):
            out, tp = nil[0] * z, fmpq(1)
            for P in nil[1:]:
                tp *= tq
                out = out + P * z * tp
            return RationalVector(out, self.policy)
        tc = t.known_ca()
        if tc is None:
            return None
        zc = z if not isinstance(z, fmpq_mat) else [calcium.Ca(z[i, 0]) for i in range(z.nrows())]
        acc = None
        for P in reversed(nil):  # Horner in t: ((N^2/2 z) t + N z) t + z
            term = ca_matvec(P, zc)
            acc = term if acc is None else [((a * tc).compact() + b).compact() for a, b in zip(acc, term)]
        return algebraic_vector(acc, zero_forms, self.policy)

    def event_state(self, theta: RootReal, zero_forms: fmpq_mat | None = None, positive: tuple = ()) -> ExactVector:
        """x(theta-) at the end of the phase (theta a root of a constraint of this phase), with
        the phase's vanishing forms and ``zero_forms`` (the triggers) as known relations, and the
        rows ``positive`` (constraints the search proved > 0 at theta) as known signs."""
        zf = self.zero_forms
        if zero_forms is not None and zero_forms.nrows():
            zf = row_basis(zf, zero_forms) if zf.nrows() else row_basis(zero_forms)
        x = self._exact_state(theta, zf)
        if x is None:
            x = EventState(self, theta, zf, positive)
        return ScaledVector(self.scale, x, self.policy) if self.scale is not None else x

    def proportional(self, ga: fmpq_mat, gb: fmpq_mat) -> bool:
        """g_a x(t) = c g_b x(t) on the whole phase with c != 0, proven exactly: g_a lies in
        span(g_b, forms vanishing on the phase) but not in the span of the vanishing forms alone
        (e.g. u_0 = 2 q_1 - q_2 and y_1 = q_1 - q_2 while q_1 = 0)."""
        return self.zero_span.proportional(ga, gb)

    def describe_state(self) -> str:
        return repr(self.z)

    def __repr__(self):
        return f"<Phase in mode {format_mode(self.mode.I)} from {self.z!r}>"


#: precision of the Jacobian in an event state's centered form (it bounds a radius only)
RADIUS_PREC = 64


class EventState(ExpVector):
    """x(theta-) = e^{A_I theta} z where theta = theta(z) is the root of a constraint g e^{A_I t} z
    that ends the phase: an :class:`~lcs_exact.numbers.expvectors.ExpVector` whose ball is computed by the
    mean-value (centered) form

        x(z) in x(z_c) + J(Z) (Z - z_c),   J = (I - A_I x g / (g A_I x)) e^{A_I theta},

    J the Jacobian of z -> x(theta(z)) (implicit function theorem; g A_I x != 0 at a simple
    root) enclosed over the ball Z of the phase start, z_c its exact center.  Plain ball
    arithmetic treats theta and z as independent and loses ~1.4 bits an event on the two carts
    (the wrapping effect); the centered form keeps their correlation, so a long run's anchors
    keep their accuracy.  The plain enclosure is intersected in (both are rigorous)."""

    def __init__(self, phase: "Phase", theta: RootReal, zero_forms: fmpq_mat | None, positive: tuple = ()):
        super().__init__(phase.mode.spectrum, theta, phase.base, zero_forms, phase.policy, modal=phase.modal,
                         M=phase.M, propagate=phase.propagate if phase.taylor else None)
        self.g = theta.function.g
        self.positive_forms = tuple(positive)
        self.centered = not phase.taylor or phase.centered

    def _compute(self, prec):
        plain = super()._compute(prec)
        if not self.centered:
            # Taylor steps in a run that has kept its accuracy: plain balls.  The centered form
            # needs the mode's spectral data (or FLINT's arb_mat.exp: 20 ms at n = 64, 120 ms at
            # n = 128) and cost more than it saved on the chains: 4.9 s against 3.6 s on 191 events
            # of twelve carts, N = 32 and 64 10-20 % slower (CENTERED_AFTER_LOST)
            return plain
        Z = self.v.arb(prec)
        n = self.n
        if all(Z[i, 0].rad() == 0 for i in range(n)):
            return plain  # an exact start: no correlation to keep
        sp = self.spectrum
        zc = arb_mat([[Z[i, 0].mid()] for i in range(n)])
        old = self.__dict__.get("_jacobian")  # (Z', Theta', J') of an earlier precision
        if old is not None and all(old[0][i, 0].contains(Z[i, 0]) for i in range(n)):
            # Z inside Z': Theta' holds theta(z) and J' the Jacobian for every z in Z (both were
            # certified over Z'); the 64-bit propagator and its check are not redone
            _, Theta, J = old
        else:
            got = self._jacobian_over(Z, prec)
            if got is None:
                return plain
            Theta, J = got
            self._jacobian = (Z, Theta, J)
        # the root for the center z_c, inside Theta (which holds theta(z) for every z in Z)
        fc = ExpSum([(lam, w, [(acb_mat(self.g) * v)[0, 0] for v in ws])
                     for lam, w, ws in sp.modal(zc, prec)], prec)
        tc = newton_ball(fc, Theta)
        xc = sp.apply(tc, zc, prec)
        with workprec(RADIUS_PREC):
            # J (Z - z_c) with Z - z_c = [0 +- rad Z_j]: each product is [0 +- |J_ij| rad Z_j]
            # or wider, so the radii of this one product bound sum_j |J_ij| rad Z_j
            JD = J * arb_mat([[arb(0, Z[j, 0].rad())] for j in range(n)])
        out = []
        for i in range(n):
            c = xc[i, 0] + arb(0, JD[i, 0].rad() + abs(JD[i, 0].mid()))
            p = plain[i, 0]
            out.append([c.intersection(p) if c.overlaps(p) else p])
        return arb_mat(out)

    def __getstate__(self):
        state = super().__getstate__()
        state.pop("_jacobian", None)  # a cache of the centered form (n x n): rebuilt on demand
        return state

    def _jacobian_over(self, Z: arb_mat, prec: int) -> tuple[arb, arb_mat] | None:
        """(Theta, J): a ball Theta that holds theta(z) for EVERY z in Z (the mean value form
        integrates J over the segment from z_c to z), certified on the root's rational bracket
        with the function's ball over Z (f(lo) > 0 > f(hi), f' < 0 on [lo, hi]), and the
        Jacobian enclosed over Theta and Z at RADIUS_PREC; None when either cannot be shown."""
        self.t.arb(prec)
        lo, hi = self.t.interval() if hasattr(self.t, "interval") else (None, None)
        if lo is None or lo == hi:  # lo == hi: an exact rational root (polynomial phase)
            return None
        fZ = self.t.function.at(prec)
        if not (fZ.value(lo) > 0 and fZ.value(hi) < 0 and fZ.sign_enclose(lo, hi, 1) < 0):
            return None
        Theta = arb(lo).union(arb(hi))
        sp = self.spectrum
        with workprec(RADIUS_PREC):  # J only bounds the radius: 64-bit balls suffice
            E = sp.matrix(Theta, RADIUS_PREC)
            v = arb_mat(sp.M) * (E * Z)
            s = (arb_mat(self.g) * v)[0, 0]
            if s.contains(0):
                return None
            return Theta, E - v * ((arb_mat(self.g) * E) * (1 / s))


def phase_horizon(phase: Phase, H):
    """(horizon to search, None) when H is within the limits of docs/limits.md for this phase's
    rates, else (the largest horizon they allow, a reason): H max|lambda(A_I)| <= MAX_HORIZON_FAST
    and H min{|lambda(A_I)| != 0} <= MAX_HORIZON_SLOW.  Applied to the phases evaluated (a mode
    can be faster than A: x' = u, y = x + u has A = 0 but A_I = -1 in mode {0}); a nilpotent A_I
    has no limit (its constraints are polynomials), nor has an equilibrium (x constant: no event)."""
    if phase.taylor:  # |lambda| <= ||A_I||_inf: within both limits without the spectral data
        with workprec(64):
            if H.arb(64) * arb(phase.mode.closed_loop_norm) <= min(MAX_HORIZON_FAST, MAX_HORIZON_SLOW):
                return H, None
    quick = phase.spectrum.modulus_bounds()  # bounds from chi's coefficients: no roots
    if quick is None or phase.equilibrium:
        return H, None
    with workprec(64):
        if H.arb(64) * quick[0] <= MAX_HORIZON_FAST and H.arb(64) * quick[1] <= MAX_HORIZON_SLOW:
            return H, None
    eig = phase.spectrum.eigenvalues(64)
    with workprec(64):
        mods = [abs(lam) for lam, _ in eig]
        nonzero = [m for m in mods if m > 0]
        if not nonzero:
            return H, None
        fast = max(nonzero, key=lambda b: b.upper()).upper()
        slow = min(nonzero, key=lambda b: b.lower()).upper()
        allowed = min(arb(MAX_HORIZON_FAST) / fast, arb(MAX_HORIZON_SLOW) / slow)
        if H.arb(64) <= allowed:
            return H, None
        q = dyadic_lower(allowed)
        with decimal.localcontext() as dc:  # a short decimal below it: readable, and exact to resume from
            dc.prec, dc.rounding = 3, decimal.ROUND_FLOOR
            cap = to_fmpq(str(decimal.Decimal(int(q.p)) / decimal.Decimal(int(q.q))))
        which = "fast" if arb(MAX_HORIZON_FAST) / fast <= arb(MAX_HORIZON_SLOW) / slow else "slow"
        reason = ("t * max|eigenvalue| <= 10^12, MAX_HORIZON_FAST" if which == "fast" else
                  "t * min nonzero |eigenvalue| <= 10^6, MAX_HORIZON_SLOW")
    return RationalReal(cap, phase.policy), reason

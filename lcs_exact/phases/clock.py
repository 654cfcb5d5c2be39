"""The sources' clock: event times in absolute time, proven through the exosystem's states.

A driven LCS (docs/extensions.md) carries its sources as states z with z' = S z in every mode:
the rows J of A have no entries outside J and B has none in J, so no mode changes them and no
re-initialization moves them (a jump x+ - x- lies in the span of B, AB, A^2 B, ..., which has no
component in J).  Hence z(t) = e^{S t} z(0) in
*absolute* time, whatever happened before.  A monitored function f(tau) = g e^{A_I tau} x_s of a
phase that starts at t_s with no closed form (an event at 3.9407..., a root of a transcendental
equation) may still vanish at a closed-form absolute time T* (the source crossing 0 at 2 pi):

    when g - (0, h) vanishes on the whole phase (it lies in the span of the phase's zero forms,
    which are invariant under A_I), f(tau) = h e^{S tau} z(t_s) = h e^{S (t_s + tau)} z(0),

so f(T* - t_s) = h e^{S T*} z(0), a closed form decided exactly by Calcium.  With f' < 0
certified on an interval holding both T* - t_s and the root's bracket, the root *is* T* - t_s:
the event is at T* exactly (Definition 4.3: theta(x_s, I) = T* - t_s), and a run to t_end = T*
ends on it.
"""
from __future__ import annotations

from typing import Any

from flint import arb, fmpq, fmpq_mat

from ..numbers import dyadic_lower, dyadic_upper, workprec
from ..numbers import spectrum_of
from ..numbers import Closed
from ..numbers import candidates, prove_zero_at, symbolic_candidates
from ..algebra import is_zero, mat_equal, submatrix
from ..numbers import Real
from .roots import RootReal
from ..algebra import RowSpan, solve_any
from ..numbers import RationalVector

__all__ = ["EventTime", "SourceClock", "autonomous_block"]


def autonomous_block(A: fmpq_mat, B: fmpq_mat) -> list[int]:
    """The largest set J of states with B[J, :] = 0 and A[J, not J] = 0: states that evolve by
    z' = A[J, J] z alone in every mode (the sources' exosystem, a constant 1)."""
    n = A.nrows()
    J = {i for i in range(n) if all(B[i, j] == 0 for j in range(B.ncols()))}
    changed = True
    while changed:
        changed = False
        for i in sorted(J):
            if any(A[i, j] != 0 for j in range(n) if j not in J):
                J.discard(i)
                changed = True
    return sorted(J)


class SourceClock:
    """z(t) = e^{S t} z(0) for the autonomous block J of a run's n states (z(0) rational).

    >>> from flint import fmpq_mat
    >>> from lcs_exact import LCS
    >>> lcs = LCS([[-1, 1, 0], [0, 0, 1], [0, -1, 0]], [[1], [0], [0]], [[1, 0, 0]], [[1]])
    >>> SourceClock.of(lcs, fmpq_mat([[0], [0], [1]])).J
    [1, 2]
    """

    def __init__(self, J: list[int], S: fmpq_mat, z0: fmpq_mat, n: int):
        self.J, self.S, self.z0, self.n = J, S, z0, n
        self.spectrum = spectrum_of(S)

    @classmethod
    def of(cls, lcs: Any, x0: Any) -> "SourceClock | None":
        """The clock of a run of ``lcs`` from x0 (an exact vector or a rational matrix), or None
        when the states have no autonomous block or its start is not rational."""
        A, B = getattr(lcs, "A", None), getattr(lcs, "B", None)
        if not isinstance(A, fmpq_mat) or not isinstance(B, fmpq_mat):
            return None
        J = autonomous_block(A, B)
        if not J:
            return None
        if isinstance(x0, fmpq_mat):
            z0 = [x0[j, 0] for j in J]
        else:
            z0 = [x0[j].known_rational() for j in J]
            if any(q is None for q in z0):
                return None
        return cls(J, submatrix(A, J, J), fmpq_mat(len(J), 1, z0), A.nrows())

    def source_form(self, span: RowSpan, g: fmpq_mat) -> fmpq_mat | None:
        """h (a row over J) with g - (0, h) in ``span`` (the forms vanishing on a whole phase:
        ``phase.zero_span``), or None: then g e^{A_I tau} x_s = h e^{S tau} z(t_s) there."""
        n = g.ncols()
        units = [span.reduce(fmpq_mat(1, n, [int(i == j) for i in range(n)])) for j in self.J]
        R = fmpq_mat(n, len(self.J), [units[k][i] for i in range(n) for k in range(len(self.J))])
        h = solve_any(R, fmpq_mat(n, 1, span.reduce(g)))
        return None if h is None else h.transpose()

    def value_is_zero(self, h: fmpq_mat, t: Closed, deadline=None) -> bool | None:
        """h e^{S t} z(0) == 0 at the closed-form absolute time t: True, False, or None
        (:func:`~lcs_exact.closedforms.prove_zero_at` on the sources' own system)."""
        return prove_zero_at(self.spectrum, h, RationalVector(self.z0), t, deadline=deadline)

    def event_time(self, phase: Any, t_s: Any, theta: Any) -> Real:
        """The event time t_s + theta (theta a root on ``phase``): an :class:`EventTime`, whose
        closed form is also sought in absolute time, when theta's function may be a source's;
        else the plain sum."""
        if is_zero(self.S) or not isinstance(theta, RootReal) or theta.known_rational() is not None:
            return t_s + theta
        return EventTime(t_s, theta, phase, self)

    def proven_time(self, phase: Any, t_s: Any, theta: Any, b: arb) -> Closed | None:
        """The closed form of the absolute time t_s + theta (its ball ``b``), proven, or None:
        candidates from S's frequencies and rationals near b, each proven by
        :meth:`PhaseClock.proves_root_at` (theta's function must be a source's h z)."""
        h = self.source_form(phase.zero_span, theta.function.g)
        if h is None:
            return None
        seen = self.started(t_s, None)
        for stream in (candidates(b, self.S), self._zeros_near(h, b, theta.policy.deadline)):  # cheap ones first
            for cand in stream:
                with workprec(128):
                    if not abs(cand.arb() - b) < arb(2) ** -60 * max(arb(1), abs(b)):
                        continue
                if seen.proves_root_at(phase, theta, cand):
                    return cand
        return None

    def _zeros_near(self, h: fmpq_mat, b: arb, deadline):
        """Closed-form zeros near b of the source's function h e^{St} z(0) of absolute time (its
        symbolic form: atan 2 + 2 pi, sqrt 2 ...), as candidates; SymPy, on first access of a
        closed form only, under the run's deadline."""
        return symbolic_candidates(self.spectrum, h, RationalVector(self.z0), b, deadline)

    def started(self, t_s: Any, t_end: Any) -> "PhaseClock":
        """The clock seen from a phase that runs from the absolute time t_s towards t_end (exact
        reals)."""
        return PhaseClock(self, t_s, t_end)


class EventTime(Real):
    """t_s + theta, an event time of a run whose sources keep absolute time: its closed form
    (derived on first access, like every exact real's) is sought in absolute time first (2 pi
    after a phase started at 3.9407...: :meth:`SourceClock.proven_time`), then as the sum of the
    parts' forms."""

    def __init__(self, t_s: Real, theta: Any, phase: Any, clock: SourceClock):
        super().__init__(theta.policy)
        self.t_s, self.theta, self.phase, self.clock = t_s, theta, phase, clock

    def _deps(self):
        return (self.t_s, self.theta)

    def _compute(self, prec):
        return self.t_s.arb(prec) + self.theta.arb(prec)

    def _closed(self) -> Closed | None:
        # a ball to 40 digits (the candidates are sifted at 2^-60: a fresh event time's ball
        # from its anchors can be wider than that)
        form = self.clock.proven_time(self.phase, self.t_s, self.theta, self.ball(40))
        if form is not None:
            return form
        down, x = [], self.t_s  # the earlier event times first, in a loop (a long run: no recursion)
        while isinstance(x, EventTime) and not x._cf_done:
            down.append(x)
            x = x.t_s
        for x in reversed(down):
            self.policy.check_deadline(" while deriving the closed forms of the earlier event times")
            x.closed
        a = self.t_s.closed
        b = self.theta.closed if a is not None else None
        return a + b if a is not None and b is not None else None

    def to_ca(self):
        form = self.closed
        return None if form is None else form.to_ca()


class PhaseClock:
    """A :class:`SourceClock` seen from a phase running from absolute time ``t_s`` towards
    ``t_end``."""

    def __init__(self, clock: SourceClock, t_s: Any, t_end: Any):
        self.clock, self.t_s, self.t_end = clock, t_s, t_end

    def proves_root_at(self, phase: Any, root: Any, t_abs: Closed) -> bool:
        """True when the root (a :class:`~lcs_exact.roots.RootReal` of f = g e^{A_I tau} x_s on
        ``phase``) is proven to be t_abs - t_s: the phase keeps the sources' block (A_I[J, not J]
        = 0, A_I[J, J] = S), f is a source's h z, h e^{S t_abs} z(0) = 0, and f has no other zero
        between t_abs - t_s and the root's bracket."""
        c = self.clock
        h = self._source_form(phase, root.function.g)
        if h is None or not root.simple or not self._alone_with(root, t_abs):
            return False
        return c.value_is_zero(h, t_abs, phase.policy.deadline) is True

    def proves_touch(self, phase: Any, g: fmpq_mat, clo: fmpq, chi: fmpq, lo: fmpq, hi: fmpq) -> bool:
        """True when f = g e^{A_I tau} x_s, convex on [lo, hi] with its critical point in
        [clo, chi], touches 0 there: f is a source's h z, and a closed-form absolute time t*
        with t* - t_s in [lo, hi] has f'(t*) = h S e^{S t*} z(0) = 0 (so t* - t_s is the critical
        point: f' increases on [lo, hi]) and f(t*) = h e^{S t*} z(0) = 0 (Calcium)."""
        c = self.clock
        h = self._source_form(phase, g)
        if h is None:
            return False
        hd = h * c.S
        with workprec(128):
            b = self.t_s.arb(128) + arb(clo).union(arb(chi))
        deadline = phase.policy.deadline
        for stream in (candidates(b, c.S), symbolic_candidates(c.spectrum, hd, RationalVector(c.z0), b, deadline)):
            for cand in stream:
                if self._within(cand, lo, hi) and c.value_is_zero(hd, cand, deadline) is True and \
                        c.value_is_zero(h, cand, deadline) is True:
                    return True
        return False

    def _source_form(self, phase: Any, g: fmpq_mat) -> fmpq_mat | None:
        """h with g e^{A_I tau} x_s = h e^{S tau} z(t_s) on the phase (h != 0), when the phase
        keeps the sources' block (A_I[J, not J] = 0, A_I[J, J] = S); else None."""
        c = self.clock
        J, M = c.J, phase.M
        if M.nrows() != c.n:
            return None
        out = [j for j in range(M.nrows()) if j not in set(J)]
        if out and any(e != 0 for e in submatrix(M, J, out).entries()):
            return None
        if not mat_equal(submatrix(M, J, J), c.S):
            return None
        h = c.source_form(phase.zero_span, g)
        return None if h is None or all(h[0, k] == 0 for k in range(h.ncols())) else h

    def _within(self, t_abs: Closed, lo: fmpq, hi: fmpq) -> bool:
        """t_abs - t_s in [lo, hi], certified at a precision well above the interval's width."""
        w = hi - lo
        bits = max(128, int(w.q.bit_length() - w.p.bit_length()) + 64) if w > 0 else 128
        with workprec(bits):
            d = t_abs.arb() - self.t_s.arb(bits)
            return bool(d >= arb(lo) and d <= arb(hi))

    def _alone_with(self, root: Any, t_abs: Closed) -> bool:
        """t_abs - t_s and the root lie in one interval where f' < 0 (certified): f has one zero
        there, so once f(t_abs - t_s) = 0 is proven the two are equal.  (t_s is known only as
        well as the phase start, the root's bracket no better: containment in the bracket itself
        cannot be shown, monotonicity on a slightly wider interval can.)"""
        lo, hi = root.interval()
        w = hi - lo
        bits = max(64, int(w.q.bit_length() - w.p.bit_length()) + 64) if w > 0 else 64
        bits = min(bits, root.policy.max_prec)
        with workprec(bits):
            d = t_abs.arb() - self.t_s.arb(bits)
            a, b = min(lo, dyadic_lower(d)), max(hi, dyadic_upper(d))
            if a <= 0:
                return False
            return root.function.at(bits).sign_enclose(a, b, 1) < 0

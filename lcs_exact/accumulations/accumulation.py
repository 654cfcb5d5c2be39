"""Right-accumulation points of event times (Remark 4.11, Definition 4.10), proven by a symmetry.

Definition 4.10 admits solutions whose event times accumulate from the left at a time T* (the
relay spiral (4.12): infinitely many switches before the state reaches the origin at a finite
time, after which it stays there).  Algorithm 7.1 cannot run through infinitely many events; this
module proves such an accumulation *exactly* when it is forced by a scaling symmetry:

* **The symmetry.** An LCS is invariant under t -> rho t, x_i -> rho^{e_i} x_i, u_j -> rho^{a_j}
  u_j, y_i -> rho^{b_i} y_i (rho > 0) when every nonzero entry of A, B, C, D is balanced:
  A_ij != 0 => e_j = e_i - 1, B_ij != 0 => a_j = e_i - 1, C_ij != 0 => b_i = e_j,
  D_ij != 0 => b_i = a_j (:func:`symmetry_exponents`: difference constraints on a graph, solved
  exactly, one free shift per connected component).  Positive scalings keep 0 <= y ⊥ u >= 0, so
  the map sends solutions (impulsive-smooth ones included) to solutions and initial solutions to
  initial solutions in the same modes: S(S_rho z) = S(z), theta(S_rho z, I) = rho theta(z, I),
  and Algorithm 7.1 run from S_rho z is the time-scaled image of its run from z.  The relay
  systems x' = Bw, w in Sgn(Cx) (with a constant state for the relay levels) have it: the vector
  field is piecewise constant.
* **The law.** If the last p events repeat the p before them (same modes, chains, triggers),
  every duration of the cycle is rho times the previous cycle's (exact rationals, 0 < rho < 1)
  and the state after the cycle is S_rho of the state after the previous one, with exponents of
  the symmetry (exact check), then by induction every later cycle is the previous one scaled:
  the event times accumulate at T* = t_k + rho T / (1 - rho) (T the last cycle's length), and
  x(T*-) = lim S_{rho^m} z: components with e_i > 0 go to 0, those with e_i = 0 stay.

Nothing here guesses: a cycle that does not satisfy every exact check is not a law.  Impact
cascades, which have no symmetry, are proven on a family of states by :mod:`lcs_exact.cascade`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

from flint import arb, arb_mat, fmpq, fmpq_mat

from ..numbers import calcium
from ..numbers import digits_to_bits, dyadic_lower, dyadic_upper, workprec
from ..errors import InvalidArgument, LCSError
from ..algebra import submatrix
from ..interfaces import AccumulationWindow
from ..numbers import Real, as_real
from ..phases import full_feedback
from .symmetry import symmetry_exponents
from ..numbers import ExactVector, ProjectedVector, RationalVector, algebraic_vector, ca_matvec

__all__ = ["Accumulation", "geometric_law", "ScaledCycle", "ReferenceStates", "event_signature"]


def _power(rho: fmpq, e: int) -> fmpq:
    return rho ** e if e >= 0 else 1 / rho ** (-e)


def _exponent(r: fmpq, rho: fmpq, limit: int = 16) -> int | None:
    """The integer e with rho^e = r exactly (|e| <= limit), or None."""
    return next((e for e in range(-limit, limit + 1) if _power(rho, e) == r), None)


def event_signature(e) -> tuple:
    """What must repeat for events to form a cycle: (mode before, chain, mode after, triggers)."""
    return (e.mode_before, e.modes, e.mode_after, e.triggers)


def _exact_number(x: Real):
    """An event time as fmpq, or as a Calcium number when it is a known algebraic irrational
    (a free fall's sqrt(2 h / g)); None when it is not known exactly."""
    q = x.known_rational()
    return q if q is not None else x.known_ca()


def _exact_state(v: ExactVector):
    """A state as an fmpq_mat column, or a list of Calcium numbers (algebraic), or None."""
    q = v.known_rational()
    return q if q is not None else v.known_ca()


def _as_ca(x):
    return x if isinstance(x, calcium.Ca) else calcium.Ca(x)


def _zero(x) -> bool | None:
    return x == 0 if isinstance(x, fmpq) else x.is_zero()


def _ratio(b, a) -> fmpq | None:
    """b / a as a rational when it is one, proven (a != 0)."""
    if isinstance(a, fmpq) and isinstance(b, fmpq):
        return b / a
    return (_as_ca(b) / _as_ca(a)).to_fmpq()


@dataclass(frozen=True)
class GeometricLaw:
    """A proven geometric law: cycles of ``period`` events, each ``ratio`` times shorter and with
    states scaled by rho^{exponents} (see the module docstring).  Times are exact reals
    (rational, or algebraic: a bouncing ball's t1 (1 + e) / (1 - e) with t1 = sqrt(2 h / g))."""

    period: int
    ratio: fmpq
    exponents: tuple
    start: int  # index of the first event of the reference cycle (events start..start+period-1)
    cycle_start: Real  # time of the event before the reference cycle
    cycle_length: Real  # duration of the reference cycle
    time: Real  # the accumulation time T*
    limit: ExactVector  # the limit state x(T*-)
    input_exponents: tuple = ()  # a_j of u_j (u scales by rho^a_j)
    output_exponents: tuple = ()  # b_i of y_i
    transform: fmpq_mat | None = None  # x~ = T x, the coordinates of the symmetry (None: x itself)


def _transform(T: fmpq_mat, z):
    """T z for a rational column or a list of Calcium numbers."""
    if isinstance(z, fmpq_mat):
        return T * z
    return ca_matvec(T, z)


def _transform_vector(T: fmpq_mat, v: ExactVector) -> ExactVector:
    q = v.known_rational()
    if q is not None:
        return RationalVector(T * q)
    return algebraic_vector(ca_matvec(T, v.known_ca()))


def _acting(events: Sequence, k: int) -> frozenset:
    """The constraints that act in these events: in a mode before, in the chain or after, or a
    trigger (``y_0``, ``u_1``, ``u_1 & y_0``)."""
    out: set = set()
    for e in events:
        out |= set(e.mode_before or ()) | set(e.mode_after)
        for m in e.modes:
            out |= set(m)
        for name in e.triggers:
            for part in str(name).split("&"):
                idx = part.strip().rpartition("_")[2]
                if idx.isdigit():
                    out.add(int(idx))
    return frozenset(i for i in out if 0 <= i < k)


def geometric_law(lcs, events: Sequence, symmetry: dict | None, max_period: int = 8,
                  enclose=None, horizon: Real | None = None) -> GeometricLaw | None:
    """The geometric law that the last events satisfy, proven exactly, or None.

    ``events`` are :class:`~lcs_exact.trajectory.Event` objects; their times and states must be
    known exactly (rational, or algebraic numbers) for a law to be proven.  When the system has
    no symmetry but the constraints acting in the cycle do (a ball bouncing on a floor below a
    ceiling it no longer reaches), the law is proven for those, provided every other constraint
    is certified positive on all the scaled cycles: ``enclose(form, t0, t1)``, an arb enclosure of
    form . x(t) over [t0, t1] of the computed run, bounds it over the reference cycle.
    ``horizon``: a law whose accumulation time would certainly come after it is not proven
    (balls of the times say so first: the exact check forms a Calcium number of every time)."""
    K = len(events) - 1
    for p in range(1, max_period + 1):
        if K - 2 * p < 0:
            break
        if any(event_signature(events[K - j]) != event_signature(events[K - p - j]) for j in range(p)):
            continue
        sym = symmetry
        active = _acting(events[K - 2 * p:], lcs.k)
        if (sym is None or lcs.k > len(active)) and enclose is not None and active:
            sym = symmetry_exponents(lcs, active) if sym is None or len(active) < lcs.k else sym
        if sym is None or _ratios_differ(events[K - 2 * p:], p, horizon):
            continue
        times = [_exact_number(events[K - 2 * p + j].time) for j in range(2 * p + 1)]
        if any(t is None for t in times):
            continue
        if not all(isinstance(t, fmpq) for t in times):
            if not calcium.available():
                continue
            times = [_as_ca(t) for t in times]
        durs = [b - a for a, b in zip(times, times[1:])]
        T1, T2 = sum(durs[1:p], durs[0]), sum(durs[p + 1:], durs[p])
        rho = _ratio(T2, T1)
        if rho is None or not 0 < rho < 1 or _sign(T1) != 1:
            continue
        if not all(_zero(durs[p + j] - durs[j] * rho) is True for j in range(p)):
            continue
        z1, z2 = _exact_state(events[K - p].state_after), _exact_state(events[K].state_after)
        if z1 is None or z2 is None:
            continue
        T = sym.get("T")
        if T is not None:  # the symmetry holds in x~ = T x (constant offsets moved)
            z1, z2 = _transform(T, z1), _transform(T, z2)
        law = _exponents_of(lcs, sym, rho, z1, z2)
        if law is None:
            continue
        exps, limit, ua, yb = law
        if "active" in sym and not _inactive_stay_positive(lcs, sym["active"], exps, T, rho, enclose,
                                                           events[K - p].time, events[K].time):
            continue
        if T is not None:
            limit = _transform_vector(T.inv(), limit)
        # the law's times as exact reals built from the events' own (closed forms derive from them)
        t_ref, t_end = events[K - p].time, events[K].time
        length = t_end - t_ref
        T_star = t_end + length * (rho / (1 - rho))
        return GeometricLaw(p, rho, tuple(exps), K - p + 1, t_ref, length, T_star, limit, tuple(ua), tuple(yb), T)
    return None


def _ratios_differ(events: Sequence, p: int, horizon: Real | None = None, prec: int = 256) -> bool:
    """Balls of the event times prove that no law of period p can hold, or that its accumulation
    would come after ``horizon``: the durations of the second cycle are not one ratio rho in
    (0, 1) times those of the first (disjoint balls), or t_K + T2 rho / (1 - rho) > horizon.
    Then the exact check (a Calcium number of every time) is skipped; False when balls cannot
    tell."""
    with workprec(prec):
        t = [e.time.arb(prec) for e in events]
        d = [b - a for a, b in zip(t, t[1:])]
        if any(x.contains(0) for x in d):
            return False
        r = [d[p + j] / d[j] for j in range(p)]
        if any(x <= 0 or x >= 1 for x in r):
            return True
        if any(not r[0].overlaps(x) for x in r[1:]):
            return True
        if horizon is None:
            return False
        T2 = sum(d[p:], arb(0))
        return bool(t[-1] + T2 * r[0] / (1 - r[0]) > horizon.arb(prec))


def _sign(x) -> int | None:
    return (x > 0) - (x < 0) if isinstance(x, fmpq) else x.sign()


def _inactive_stay_positive(lcs, active, exps, T, rho: fmpq, enclose, t0: Real, t1: Real) -> bool:
    """Every constraint j outside ``active`` stays positive on all later (scaled) cycles: with
    L = C_j T^{-1} in the symmetry's coordinates, y_j = sum_i L_i rho^{m e_i} x~_i(t') over the
    reference cycle t' in [t0, t1], so for m >= 1
        y_j >= inf (sum_{e_i = 0} L_i x~_i) - sum_{e_i > 0} |L_i| rho^{e_i} sup |x~_i| > 0
    is certified from enclosures of the computed reference cycle.  D_jJ must vanish (y_j reads
    the state only) and no component with e_i < 0 may enter."""
    if enclose is None:
        return False
    n = lcs.n
    Tinv = T.inv() if T is not None else None
    for j in range(lcs.k):
        if j in active:
            continue
        if any(lcs.D[j, a] != 0 for a in active):
            return False
        Cj = submatrix(lcs.C, [j], None)
        L = Cj * Tinv if Tinv is not None else Cj
        base = fmpq_mat(1, n)
        for i in range(n):
            if exps[i] < 0 and L[0, i] != 0:
                return False
            if exps[i] == 0:
                base[0, i] = L[0, i]
        Tm = T if T is not None else None
        with workprec(128):
            low = enclose(base * Tm if Tm is not None else base, t0, t1)
            slack = arb(0)
            for i in range(n):
                if exps[i] > 0 and L[0, i] != 0:
                    row = fmpq_mat(1, n, [int(c == i) for c in range(n)])
                    xi = enclose(row * Tm if Tm is not None else row, t0, t1)
                    slack += abs(arb(L[0, i])) * arb(rho) ** exps[i] * abs(xi).upper()
            if not (low - slack).lower() > 0:
                return False
    return True


def _entries(z) -> list:
    return [z[i, 0] for i in range(z.nrows())] if isinstance(z, fmpq_mat) else list(z)


def _exponents_of(lcs, symmetry: dict, rho: fmpq, z1, z2):
    """Exponents e (one shift per component of the symmetry) with z2 = S_rho z1, and the limit of
    S_{rho^m} z2 (m -> oo); None when there are none or the limit does not exist."""
    n = lcs.n
    comp = symmetry["component"]
    shift: dict = {}
    a_s, b_s = _entries(z1), _entries(z2)
    zeros_b = []
    for i in range(n):
        a, b = a_s[i], b_s[i]
        za, zb = _zero(a), _zero(b)
        if za is None or zb is None:
            return None
        zeros_b.append(zb)
        if za or zb:
            if za != zb:
                return None
            continue
        r = _ratio(b, a)
        e = None if r is None else _exponent(r, rho)
        if e is None:
            return None
        c = comp[("x", i)]
        s = e - symmetry["x"][i]
        if shift.setdefault(c, s) != s:
            return None
    exps, limit = [], []
    for i in range(n):
        c = comp[("x", i)]
        e = symmetry["x"][i] + shift.get(c, 0) if c in shift else None
        if zeros_b[i]:
            exps.append(e if e is not None else 0)
            limit.append(fmpq(0))
            continue
        if e is None or e < 0:
            return None  # a component that grows without bound: no limit state
        exps.append(e)
        limit.append(b_s[i] if e == 0 else fmpq(0))
    ua = [symmetry["u"][j] + shift.get(comp[("u", j)], 0) for j in range(lcs.k)]
    yb = [symmetry["y"][i] + shift.get(comp[("y", i)], 0) for i in range(lcs.k)]
    if all(isinstance(x, fmpq) for x in limit):
        lim = RationalVector(fmpq_mat(n, 1, limit))
    else:
        lim = algebraic_vector([_as_ca(x) for x in limit])
    return exps, lim, ua, yb


@dataclass(frozen=True)
class Accumulation:
    """A right-accumulation point crossed (Remark 4.11), made by the run (``traj.accumulations``).
    Without a law (:mod:`lcs_exact.accumulations.bounces`) ``ratio`` is None and ``time``, ``state``,
    the implied events are certified balls of any precision.

    The infinitely many events before ``time`` are not in ``traj.events`` (which ends with the
    last event computed one by one, at :attr:`start`); :meth:`event_time` gives the k-th of them
    exactly, from the law: cycle m repeats the reference cycle's events scaled by rho^(m+1).

    Attributes
    ----------
    time : Real
        T*, where the event times accumulate.
    state : ExactVector
        x(T*-), the limit of the state.
    events : int
        The number of events in a cycle of the proven law (1 without a geometric law).
    ratio : fmpq or None
        rho, the scale factor of one cycle (0 < rho < 1); None without a geometric law.
    first_event : int
        The index in ``traj.events`` of the first event of the law's reference cycle.
    cycle : ScaledCycle, BounceWindow or None
        The window of implied events (the phase of the run on [:attr:`start`, T*)), or None.
    """

    time: Real
    state: ExactVector
    events: int
    ratio: fmpq | None
    first_event: int
    cycle: Any = field(default=None, repr=False, compare=False)  # the window: ScaledCycle or BounceWindow

    @property
    def start(self) -> Real | None:
        """The time of the last event before the window of implied events (``traj.events[-1]``
        when the accumulation was crossed)."""
        return None if self.cycle is None else self.cycle.t_k

    @property
    def cycle_length(self) -> Real | None:
        """T, the reference cycle's length (cycle m after :attr:`start` lasts T rho^(m+1)), or None."""
        return None if self.cycle is None or self.ratio is None else self.cycle.law.cycle_length

    @property
    def lower(self) -> fmpq:
        """A rational lower bound of T*, within the run's digits of it (relative)."""
        return self._bounds()[0]

    upper = property(lambda self: self._bounds()[1], doc="A rational upper bound of T*, within the run's digits.")

    def _bounds(self) -> tuple:
        with workprec(digits_to_bits(self.time.policy.digits + 2) + 16):
            b = self.time.ball(self.time.policy.digits + 2)
            return dyadic_lower(b), dyadic_upper(b)

    @property
    def offsets(self) -> tuple:
        """The reference cycle's event times after its start (exact): event j of cycle m is at
        start + T rho (1 - rho^m) / (1 - rho) + offsets[j] rho^(m+1)."""
        return () if self.cycle is None else tuple(self.cycle.offsets)

    def event_time(self, k: int) -> Real:
        """The k-th event (k = 0, 1, ...) implied by the law after :attr:`start`, exactly.

        Parameters
        ----------
        k : int
            0, 1, ...: the events after :attr:`start`, in order.

        Examples
        --------
        >>> import lcs_exact as L
        >>> ball = L.examples.bouncing_ball(g=10, e="1/2")     # dropped from 5: impacts 1, 2, 2.5, ...
        >>> acc = L.simulate(ball, ball.embed([5, 0]), 4).accumulations[0]
        >>> acc.time.known_rational(), [acc.event_time(k).known_rational() for k in range(3)]
        (3, [11/4, 23/8, 47/16])
        """
        return self._implied(k).event_time(k)

    def event_time_ball(self, k: int, prec: int = 128) -> arb:
        """:meth:`event_time` as a certified ball at ``prec`` bits, cheaply (balls only).

        Parameters
        ----------
        k : int
            As for :meth:`event_time`.
        prec : int, optional
            The working precision in bits (default 128)."""
        return self._implied(k).event_time_ball(k, prec)

    def _implied(self, k: int):
        if self.cycle is None:
            raise InvalidArgument("this accumulation carries no law for its implied events")
        if isinstance(k, bool) or not isinstance(k, int) or k < 0:
            raise InvalidArgument(f"k must be an int >= 0, got {k!r}")
        return self.cycle

    def __repr__(self):
        return (f"Accumulation(time={self.time.label()}, state={self.state!r}, cycle of {self.events} events, "
                f"{'no geometric law' if self.ratio is None else f'ratio {self.ratio}'})")


def _cycle_start(j: int, T: Any, rho: Any) -> Any:
    """s_j = T rho (1 - rho^j) / (1 - rho): where cycle j of a geometric law starts after t_k (cycle
    j covers [s_j, s_{j+1}): the reference cycle, of length T, scaled by rho^(j+1)), in the
    arithmetic of T and rho: exact (a Real and a rational), balls or floats."""
    return T * (rho * (1 - rho ** j) / (1 - rho))


def _locate_cycle(m: int, side: Callable[[int], int | None]) -> int | None:
    """The cycle holding a time, from a guess m (:func:`_cycle_guess`): moved by one cycle while
    ``side(m)`` says the time lies before cycle m (-1, for m > 0 only) or after it (+1), at most 64
    moves; None when ``side`` cannot tell (None: a ball on a cycle's boundary) or the moves run out.
    The one search of :class:`ScaledCycle`'s maps, exact, on balls and in floats."""
    for _ in range(64):
        s = side(m)
        if s is None or s == 0:
            return m if s == 0 else None
        m += s
    return None


def _cycle_guess(dt: float, T: Any, rho: fmpq) -> int:
    """A float guess of the cycle m holding t_k + dt (cycle m covers [s_m, s_m + T rho^(m+1)),
    s_m = T rho (1 - rho^m) / (1 - rho)); the callers check it exactly and move it."""
    frac = dt / max(float(T) * float(rho) / (1 - float(rho)), 1e-300)
    return max(0, int(math.log(max(1e-300, 1 - min(frac, 1 - 1e-16))) / math.log(float(rho)))) if frac > 0 else 0


class ScaledCycle(AccumulationWindow):
    """The continuous motion on [t_k, T*) of a proven geometric law, as a phase-like object: a time
    in cycle m (the reference cycle scaled by rho^(m+1)) is mapped back into the reference cycle
    and the reference trajectory is scaled there (x by rho^e, u by rho^a, y by rho^b).  Times and
    states are exact (rational or algebraic)."""

    def __init__(self, law: GeometricLaw, reference, t_k: Real, mode, z: ExactVector, offsets: Sequence = ()):
        self.law, self.reference, self.t_k = law, reference, t_k
        self.mode = mode  # the mode of the first phase after t_k (reprs only)
        self.z = z  # the state at t_k (after the last computed event)
        self.offsets = tuple(offsets)  # the reference cycle's event times after its start

    def event_times(self, count: int) -> list:
        """The first ``count`` event times inside the window (exact reals, increasing): cycle m
        starts at t_k + T (rho + ... + rho^m) and repeats the reference cycle's events scaled by
        rho^(m+1).  Needs the reference cycle's ``offsets``.  Each is :meth:`event_time` (one
        closed expression each: a running sum of cycle starts grew with every cycle, and 400 of
        a bouncing ball's took a minute)."""
        return [self.event_time(k) for k in range(count)] if self.offsets else []

    def event_time(self, k: int) -> Real:
        """The k-th event time inside the window (k = 0, 1, ...): event j = k mod p of cycle
        m = k div p, at t_k + T rho (1 - rho^m) / (1 - rho) + offsets[j] rho^(m+1)."""
        rho, T, p = self.law.ratio, self.law.cycle_length, len(self.offsets)
        m, j = divmod(k, p)
        return self.t_k + T * (rho * (1 - rho ** m) / (1 - rho)) + self.offsets[j] * rho ** (m + 1)

    def _map(self, dt: Any) -> tuple[Real, fmpq]:
        """(t_ref, scale) for a time t_k + dt of the window."""
        d = as_real(dt)
        if d.known_rational() is None and d.known_ca() is None:
            raise InvalidArgument("inside an accumulation window states are evaluated at exact (rational or "
                                  "algebraic) times only")
        law = self.law
        rho, T = law.ratio, law.cycle_length

        def side(j):  # the two bounds of cycle j checked exactly
            if j > 0 and (d - _cycle_start(j, T, rho)).sign() < 0:
                return -1
            return 1 if (d - _cycle_start(j + 1, T, rho)).sign() >= 0 else 0

        m = _locate_cycle(_cycle_guess(float(d), T, rho), side)
        if m is None:
            raise LCSError("internal inconsistency: a time inside an accumulation window beyond its end")
        scale = rho ** (m + 1)
        return law.cycle_start + (d - _cycle_start(m, T, rho)) / scale, scale

    def reference_time(self, t: float) -> float | None:
        """A time t of the window (absolute, a float: a plot's sample) mapped into the reference
        cycle as :meth:`_map` maps an exact time, in floats: it places a sample and certifies
        nothing; None when its cycle cannot be placed (t at T*, to a float's precision).

        Parameters
        ----------
        t : float
        """
        law = self.law
        rho, T, d = float(law.ratio), float(law.cycle_length), t - float(self.t_k)

        def side(j):
            if j > 0 and d < _cycle_start(j, T, rho):
                return -1
            return 1 if d >= _cycle_start(j + 1, T, rho) else 0

        m = _locate_cycle(_cycle_guess(d, law.cycle_length, law.ratio), side)
        return None if m is None else float(law.cycle_start) + (d - _cycle_start(m, T, rho)) / rho ** (m + 1)

    def flight_mode(self, t: float) -> Any:
        """The mode of the flight holding the time t (a float: a plot's sample): that of the
        reference cycle's phase where :meth:`reference_time` puts it, or None.

        Parameters
        ----------
        t : float
        """
        t_ref = self.reference_time(t)
        return None if t_ref is None else self.reference.mode_at(t_ref)

    def event_time_ball(self, k: int, prec: int = 128) -> arb:
        """:meth:`event_time` as a certified ball at ``prec`` bits, from balls of t_k, T and the
        offsets (no exact arithmetic: deep cycles' exact times cost a Calcium compaction each)."""
        rho, p = self.law.ratio, len(self.offsets)
        m, j = divmod(k, p)
        with workprec(prec):
            r = arb(rho)
            return (self.t_k.arb(prec) + self.law.cycle_length.arb(prec) * (r * (1 - r ** m) / (1 - r))
                    + self.offsets[j].arb(prec) * r ** (m + 1))

    def ball_state(self, d: arb, prec: int) -> arb_mat | None:
        """x(t_k + d) for a ball d at ``prec`` bits, without exact arithmetic: the cycle m and the
        reference time decided on balls, the reference phase evaluated from its modal data and
        scaled (what sampling and plots need: ~100 times cheaper than :meth:`state`).  None when
        a ball cannot decide (d within its width of a cycle's or an event's boundary)."""
        law = self.law
        rho, T = law.ratio, law.cycle_length
        with workprec(prec):
            Tb, r = T.arb(prec), arb(rho)

            def side(j):  # None: on a cycle's boundary, to the ball's width
                lo, hi = d - _cycle_start(j, Tb, r), d - _cycle_start(j + 1, Tb, r)
                if j > 0 and lo < 0:
                    return -1
                if hi >= 0:
                    return 1
                return 0 if lo > 0 and hi < 0 else None

            m = _locate_cycle(_cycle_guess(float(d.mid()), T, rho), side)
            if m is None:
                return None
            lo = d - _cycle_start(m, Tb, r)
            scale = rho ** (m + 1)
            x = self.reference.ball(law.cycle_start.arb(prec) + lo / arb(scale), prec)
            if x is None:
                return None
            factors = arb_mat(len(law.exponents), 1, [arb(_power(scale, e)) for e in law.exponents])
            if law.transform is None:
                return arb_mat(x.nrows(), 1, [x[i, 0] * factors[i, 0] for i in range(x.nrows())])
            y = arb_mat(law.transform) * x
            y = arb_mat(y.nrows(), 1, [y[i, 0] * factors[i, 0] for i in range(y.nrows())])
            return arb_mat(law.transform.inv()) * y

    @staticmethod
    def _scaled(v, scale: fmpq, exps: Sequence[int]) -> ExactVector:
        if isinstance(v, fmpq_mat):
            return RationalVector(fmpq_mat(v.nrows(), 1, [v[i, 0] * _power(scale, exps[i]) for i in range(v.nrows())]))
        return algebraic_vector([x * _power(scale, e) for x, e in zip(v, exps)])

    def state(self, dt: Any) -> ExactVector:
        t_ref, scale = self._map(dt)
        T = self.law.transform
        x = _exact(self.reference(t_ref, "x"))
        if T is None:
            return self._scaled(x, scale, self.law.exponents)
        return _transform_vector(T.inv(), self._scaled(_transform(T, x), scale, self.law.exponents))

    def output(self, dt: Any, kind: str) -> ExactVector:
        """u (``kind`` "u") or y ("y") at t_k + dt: u scaled from the reference cycle (rho^a_j),
        y = C x + D u from the scaled state and input."""
        t_ref, scale = self._map(dt)
        u = self._scaled(_exact(self.reference(t_ref, "u")), scale, self.law.input_exponents)
        if kind == "u":
            return u
        x = self.state(dt)
        lcs = self.reference.lcs
        xq, uq = x.known_rational(), u.known_rational()
        if xq is not None and uq is not None:
            return RationalVector(lcs.C * xq + lcs.D * uq)
        cx, cu = ca_matvec(lcs.C, x.known_ca()), ca_matvec(lcs.D, u.known_ca())
        return algebraic_vector([a + b for a, b in zip(cx, cu)])


def _exact(v: ExactVector):
    q = _exact_state(v)
    if q is None:
        raise LCSError("internal inconsistency: a reference value of a proven law is not exact")
    return q


class ReferenceStates:
    """x(t) on the part of a run computed so far (the reference cycle of a geometric law)."""

    def __init__(self, run: Any):
        self.run = run

    @property
    def lcs(self):
        return self.run.lcs

    def __call__(self, t_ref, kind: str = "x"):
        t = as_real(t_ref)
        phases = self.run.phases
        for i, rec in enumerate(phases):
            s = (t - rec.t1).sign()
            if s > 0 and i + 1 < len(phases):
                continue
            if s == 0 and i + 1 < len(phases):  # x(t+) at an event time: the next phase's start
                rec, t0 = phases[i + 1], phases[i + 1].t0
            else:
                t0 = rec.t0
            x = rec.phase.state(t - t0)
            if kind == "x":
                return x
            F = full_feedback(rec.phase.mode)
            M = F if kind == "u" else self.run.lcs.C + self.run.lcs.D * F
            return ProjectedVector(M, x)
        raise LCSError("internal inconsistency: a reference time outside the computed run")

    def mode_at(self, t_ref: float) -> Any:
        """The mode of the computed phase holding the time t_ref (a float: a plot's sample), or None.

        Parameters
        ----------
        t_ref : float
        """
        rec = next((r for r in self.run.phases if not isinstance(r.phase, AccumulationWindow)
                    and float(r.t0) <= t_ref < float(r.t1)), None)
        return None if rec is None else rec.phase.mode

    def ball(self, t_ref: arb, prec: int):
        """x(t_ref) for a ball t_ref inside the computed part, from the phase holding it (balls
        only), or None when t_ref's ball touches an event time."""
        for rec in self.run.phases:  # a Phase or a window: both give ball_state
            if t_ref < rec.t1.arb(prec):
                dt = t_ref - rec.t0.arb(prec)
                return rec.phase.ball_state(dt, prec) if dt > 0 else None
            if not t_ref > rec.t1.arb(prec):
                return None
        return None

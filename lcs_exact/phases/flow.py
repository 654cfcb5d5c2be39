"""theta(z, I): the time to the next event (Def. 4.3), the order of simultaneous roots, grazing.

For a phase (:mod:`lcs_exact.phase`) every monitored function f = g e^{A_I t} z is examined:

* at t = 0 the lexicographic sign of (g z, g A_I z, ..., g A_I^{n-1} z) (Lemma 5.1) decides the
  start; all zero means f = 0 on the phase (Cayley-Hamilton) and f never ends it;
* f^{(j)} > 0 on [0, eps] for the first nonzero order j gives f > 0 on (0, eps];
* :func:`lcs_exact.roots.first_crossing` brackets the first crossing in (eps, horizon];
* the first event is the smallest root; roots that cannot be separated from it are equal only when
  proven (f_a = c f_b on the phase, or equal proven closed forms); otherwise their order is an
  unresolved sign.  A tangential touch (grazing: f = f' = 0, f'' > 0) is not an event when proven.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

from flint import arb, fmpq

from ..numbers import Deadline, Policy, ball_sign, dyadic_lower, dyadic_upper, workprec
from .clock import PhaseClock
from ..numbers import prove_flat_touch, prove_root, prove_root_is, prove_touch
from ..numbers import sympy_proves_zero
from ..errors import LCSError, UnresolvedSign
from ..interfaces import SystemLike
from ..modes import format_mode
from .phase import Constraint, Phase
from ..numbers import RationalReal, Real, as_real
from ..numbers import ExactVector, ProjectedVector, RationalVector, as_exact_vector
from .polyroots import exact_first_crossing
from .guesses import float_crossing
from .roots import ROOT_GUARD, RootReal, first_crossing, positive_step

__all__ = ["Hit", "first_root", "next_event", "compare_roots", "theta", "horizon_bound", "IMMEDIATE", "Immediate"]

#: precision at which roots are searched for (escalated when a decision needs more); the
#: bracket found is then refined to the run's working precision by interval Newton alone
SEARCH_PREC = 192
#: the most Taylor steps a phase's screen for events looks over (:func:`_quiet`; a longer horizon
#: is searched at the search's precision directly)
SCREEN_MAX_STEPS = 128


class _Finder:
    """The closed-form finder of a root of constraint c on a phase (lazy; see closedforms).
    A class rather than a closure so that trajectories pickle (sweeps send them between
    processes)."""

    def __init__(self, phase: Phase, c: Constraint):
        self.phase, self.c = phase, c

    def __call__(self, root: RootReal):
        ph = self.phase
        return prove_root(root, ph.spectrum, self.c.g, ph.base, ph.policy.deadline)


class _Toucher(_Finder):
    """Proves a tangential touch of constraint c at a critical point in [lo, hi]: a closed form
    of the phase's time, or through the sources' clock one of absolute time (the contact force
    1 - sin t of a forced mass held at a stop touches 0 at pi/2, after an impact at a time with
    no closed form)."""

    def __init__(self, phase: Phase, c: Constraint, clock: PhaseClock | None = None):
        super().__init__(phase, c)
        self.clock = clock
        self.touched = False  # a touch was proven: f = 0 somewhere in the search, not f > 0

    def __call__(self, lo: fmpq, hi: fmpq, convex_lo: fmpq, convex_hi: fmpq):
        ph = self.phase
        if ph.policy.closed_forms == "off":
            return None
        if prove_touch(ph.spectrum, self.c.g, ph.base, lo, hi, ph.policy.deadline) or (
                self.clock is not None and self.clock.proves_touch(ph, self.c.g, lo, hi, convex_lo, convex_hi)):
            self.touched = True
            return True
        return None

    def flat(self, lo: fmpq, hi: fmpq, f) -> bool:
        """f >= 0 on [lo, hi] with its one zero a touch of even order at a proven closed form
        (:func:`~lcs_exact.closedforms.prove_flat_touch`): where f'' vanishes at the touch too,
        (1 - t)^4, and no convexity can be shown."""
        ph = self.phase
        if ph.policy.closed_forms == "off":
            return False
        if prove_flat_touch(ph.spectrum, self.c.g, ph.base, f, lo, hi, ph.policy.deadline):
            self.touched = True
            return True
        return False


class Immediate:
    """The answer of :func:`first_root` when f is negative right after t = 0 (Example 4.5:
    theta = 0; the selected mode cannot continue smoothly)."""

    __slots__ = ()

    def __repr__(self):
        return "IMMEDIATE"


#: the single :class:`Immediate` value
IMMEDIATE = Immediate()


def first_root(phase: Phase, c: Constraint, horizon: fmpq, prec: int, estimate: float | None = None,
               clock: PhaseClock | None = None) -> Real | Immediate | None:
    """The first t in (0, horizon] where f = g x(t) turns negative: a :class:`RootReal` (or an
    exact :class:`~lcs_exact.reals.AlgebraicReal` on a polynomial phase from an exact start,
    :mod:`lcs_exact.polyroots`), None (no event in (0, horizon]) or :data:`IMMEDIATE` (f is
    negative right after t = 0).

    ``estimate``: a float guess of the crossing (:func:`~lcs_exact.guesses.float_crossing`).  The
    certified search covers (0, estimate] first and, only when it finds no crossing there, the
    rest of the horizon: a guess can cost time, never the result."""
    return _search(phase, c, horizon, prec, estimate, clock)[0]


def _search(phase: Phase, c: Constraint, horizon: fmpq, prec: int, estimate: float | None = None,
            clock: PhaseClock | None = None) -> tuple:
    """(:func:`first_root`'s answer, strict): ``strict`` True when the search proved f > 0 at
    every point of (0, end] it passed, end the horizon (no root) or the root's bracket's lower end
    (every verdict of the search is strict positivity, except a proven touch or a zero assumed
    under ``allow_unresolved``, and an exact polynomial's roots, which are not looked at)."""
    sign, order = phase.start_order(c)
    if sign == 0:
        return None, False  # f = 0 on the whole phase
    if sign < 0:
        return IMMEDIATE, False
    fn = phase.function(c)
    exact = fn.exact_coefficients()
    if exact is not None:  # a polynomial phase from an exact start: its roots exactly
        hit = exact_first_crossing(exact, horizon, phase.policy)
        if hit is not None:
            return hit.root, False
    a, prec = _start(phase, c, fn, order, horizon, prec)
    strict = exact is None and not phase.policy.allow_unresolved
    if a >= horizon:
        return None, strict
    touch = _Toucher(phase, c, clock)
    br = None
    if estimate is not None:
        with workprec(64):
            b1 = min(horizon, dyadic_upper(arb(estimate)))
        # a window cannot end where f's ball holds 0 (a guess on an event at an exact time, t = 1):
        # no sign there would ever close it; the whole horizon is searched instead
        if a < b1 < horizon and ball_sign(fn.at(prec).value(b1)) != 0:
            br = first_crossing(fn, a, b1, prec, touch=touch)
            # go on from b1 only where f(b1) > 0 is certified (the search's precondition); an
            # estimate that lands on a root (an exact time such as 1) is searched again whole
            if br is None and ball_sign(fn.at(prec).value(b1)) > 0:
                a = b1
    if br is None and a < horizon:
        br = first_crossing(fn, a, horizon, prec, touch=touch)
    strict = strict and not touch.touched
    if br is None:
        return None, strict
    return RootReal(fn, br, _Finder(phase, c)), strict


def _start(phase: Phase, c: Constraint, fn, order: int, horizon: fmpq, prec: int) -> tuple[fmpq, int]:
    """(eps, prec) with f > 0 on (0, eps], when f(0) = ... = f^{(order-1)}(0) = 0 < f^{(order)}(0)
    (Lemma 5.1): the Taylor coefficients at 0 from ``order`` on, with bounds of the higher
    derivatives (:func:`~lcs_exact.roots.positive_step`), give eps in one step - a near graze
    with f'(0) = 10^-65 and f = t^3 / 3 beyond costs no more than a plain start.  More bits are
    taken only when no step is certified at all: the step the certified coefficients give is
    taken as it is (raising the precision of every constraint for a longer first step cost a
    long run and the chain of carts 6-7 % of their instructions; the search goes on from eps)."""
    policy = phase.policy
    while True:
        policy.check_deadline(lambda: f" while isolating the roots of {c.name} (at the phase start)")
        f = fn.at(prec)
        # f^{(order)}(0) > 0 is proven (exactly, by start_order); its ball may not show it yet.
        # On Taylor steps the bounds are taken over the first step (not up to the horizon)
        reach = min(horizon, f.steps.length(0)) if phase.taylor else horizon
        eps = positive_step(f, fmpq(0), reach, zero_below=order)
        if eps is not None:
            break
        if prec >= policy.max_prec:  # the sign was certified exactly: this needs more bits only
            raise UnresolvedSign(f"could not certify the start of {c.name} (sign 1, order {order}) in mode "
                                 f"{format_mode(phase.mode.I)} at {prec} bits: no step (0, eps] with {c.name} > 0 "
                                 f"is proven at this precision (max_prec)")
        prec = min(2 * prec, policy.max_prec)
    with workprec(64):
        eps = min(eps, dyadic_lower(arb(eps)))  # a short dyadic
    return eps, prec


def horizon_bound(H: Real) -> fmpq:
    """A rational upper bound of H (above it by a relative 2^-40: a horizon of 10^-188, the
    limit of a rate of 10^200, stays 10^-188, not 2^-40)."""
    with workprec(64):
        b = H.arb(64)
        return dyadic_upper(b + abs(b) * arb(2) ** -40)


def compare_roots(phase: Phase, a: RootReal, ca: Constraint, b: RootReal, cb: Constraint,
                  clock: PhaseClock | None = None) -> int:
    """Certified order of two roots of the same phase: -1, 0 (equal: proven, or assumed under
    ``allow_unresolved``), +1.  Equality is proven by closed forms of the roots, or through the
    sources' ``clock`` by one closed form of absolute time for both (two rectifiers driven by
    sin t and sin 4t/3 switch together at t = 3 pi, after phases that start at times without a
    closed form)."""
    if isinstance(a, RootReal) and isinstance(b, RootReal):  # disjoint brackets (lo, hi]: no refinement
        if a.hi <= b.lo:  # (and no exact test: proportional functions, positive at the start,
            return -1  # share their first root, which both brackets hold)
        if b.hi <= a.lo:
            return 1
    if phase.proportional(ca.g, cb.g):
        return 0
    xa, xb = a.known_ca(), b.known_ca()
    if xa is not None and xb is not None:  # exact roots (polynomial phases): decided exactly
        s = (xa - xb).sign(real=True)
        if s is not None:
            return s
    policy: Policy = phase.policy
    prec = start = max(64, a.anchor_prec, b.anchor_prec)
    tried = False
    gap = None  # |mid x - mid y| at the previous precision
    while True:
        x, y = a.arb(prec), b.arb(prec)
        if x < y:
            return -1
        if x > y:
            return 1
        # closed forms after two doublings: roots that are distinct but close (a cluster of
        # impacts running down a chain, 10^-27 .. 10^-100 apart) separate at 2-8x the start,
        # and a closed-form attempt costs more than a refinement.  Equal roots' midpoints close
        # in as fast as the balls shrink; while the midpoints' gap stays (it kept more than
        # 1/16 of its size over the last doubling) the roots are refined further first, up to
        # 16x the start (a root whose ball stops shrinking, a touch, keeps its midpoint too)
        was, gap = gap, abs(x.mid() - y.mid())
        apart = was is not None and gap > was / 16 and gap > 0
        if not tried and ((prec >= 4 * start and not apart) or prec >= 16 * start or prec >= policy.max_prec):
            tried = True
            if policy.closed_forms != "off":
                fa, fb = a.closed, b.closed
                if fa is not None and fb is not None:
                    d = _equal_closed(a, b)
                    if d is True:
                        return 0
                if clock is not None and _same_absolute_time(phase, clock, a, b):
                    return 0
        if prec >= policy.max_prec:
            return policy.unresolved(f"the order of the roots of {ca.name} and {cb.name} "
                                     "(simultaneous events?)")
        prec = min(2 * prec, policy.max_prec)


def _same_absolute_time(phase: Phase, clock: PhaseClock, a: RootReal, b: RootReal) -> bool:
    """t_s + a and t_s + b are proven one closed form of absolute time (each root a source's
    zero, :meth:`~lcs_exact.clock.SourceClock.proven_time`)."""
    times = []
    for r in (a, b):
        with workprec(200):
            ball = clock.t_s.arb(200) + r.arb(200)
        t = clock.clock.proven_time(phase, clock.t_s, r, ball)
        if t is None:
            return False
        times.append(t)
    ta, tb = times
    if ta == tb:
        return True
    xa, xb = ta.to_ca(), tb.to_ca()
    return xa is not None and xb is not None and (xa - xb).is_zero() is True


def _equal_closed(a: RootReal, b: RootReal) -> bool | None:
    if a.closed == b.closed:  # the same form: the same number
        return True
    xa, xb = a.to_ca(), b.to_ca()
    if xa is not None and xb is not None:
        return (xa - xb).is_zero()
    return sympy_proves_zero(a.closed_form - b.closed_form, a.policy.deadline)


class Hit(NamedTuple):
    """The next event of a phase: ``theta`` its time from the phase start, ``constraints`` those
    reaching zero there, ``at_horizon`` True when theta is proven equal to the horizon H,
    ``positive`` constraints proven > 0 at theta by their searches (strictly positive up to a
    later root or the search's end: a gap 10^-200 wide at the event, which no ball of the event
    state at the working precision shows, is known positive without refining the state)."""

    theta: Real
    constraints: list
    at_horizon: bool = False
    positive: tuple = ()


def next_event(phase: Phase, H: Real, prec: int, clock: PhaseClock | None = None) -> Hit | None:
    """The first event in (0, H] (:class:`Hit`), or None.

    Roots are searched for at SEARCH_PREC bits (or less, when ``prec`` is less), escalating only
    where a decision needs it.  An event exactly at H is reported (the state there is x(H+));
    ``clock`` (the sources' clock of a driven LCS seen from the phase, :mod:`lcs_exact.clock`)
    proves touches in absolute time and, when H = clock.t_end - clock.t_s (t_end not None), an
    event at t_end when t_s has no closed form.  A phase at an equilibrium (A_I z = 0, proven:
    ``phase.equilibrium``) has none at any horizon: its functions are constant, and none is
    negative at the start (the mode was selected there)."""
    if phase.equilibrium and all(phase.start_order(c)[0] >= 0 for c in phase.constraints):
        return None
    hb = horizon_bound(H)
    phase.use_spectral(hb)
    found: list = []
    strict: list = []  # constraints whose search proved them > 0 up to the first event (see Hit)
    limit = hb
    search = min(prec, SEARCH_PREC)
    if phase.taylor:  # the steps at the bits the event's root is refined to as well (one set, not two)
        phase.taylor_rows(search + ROOT_GUARD)  # (lazy: its steps are computed when read)
        # the screen, where no early crossing is foreseen (a phase of 10^-50 in a cluster of
        # impacts ends long before a screen's first step)
        if phase.first_step is None:
            quiet, guess = _quiet(phase, hb)
            if quiet:
                return None
            if guess is not None:  # the screen foresees a crossing early in a regular step
                phase.starts_near(guess)
    index = {id(c): i for i, c in enumerate(phase.constraints)}
    for est, c in _by_estimate(phase, hb, search):
        if est is None and _positive_until(phase, index[id(c)], c, limit, search):
            strict.append(c)  # proven > 0 up to the first event on the steps, no search
            continue
        r, positive = _search(phase, c, limit, search, est, clock)
        if r is None:
            if positive:  # > 0 on (0, limit], and the first event is before limit
                strict.append(c)
            continue
        if r is IMMEDIATE:
            raise LCSError(f"internal inconsistency: {c.name} of the selected mode "
                           f"{format_mode(phase.mode.I)} is negative at the start of the phase")
        found.append((c, r))
        if positive and r.simple:  # > 0 before its root (f decreases through it), later than the event's
            strict.append(c)
        limit = min(limit, r.hi)
        if phase.taylor and len(found) == 1:  # later searches, comparisons and refinements of the
            phase.ends_by(limit)  # roots found (each below the limit when found) stay below it
    if not found:
        return None
    first_c, first = found[0]
    order: dict = {}  # id(r) -> the order of r against the first root found so far

    def against_first(c, r) -> int:
        if order.get(id(r), (None,))[0] is not first:
            order[id(r)] = (first, compare_roots(phase, r, c, first, first_c, clock))
        return order[id(r)][1]

    for c, r in found[1:]:
        if against_first(c, r) < 0:
            first_c, first = c, r
    if phase.policy.closed_forms == "eager":
        first.closed
    at = False
    if not _before(first, H):  # the bracket settles the usual case without a sign decision
        at = _at_horizon(phase, first, first_c, H, clock)
        if not at and (first - H).sign() > 0:
            return None
    simultaneous = [first_c] + [c for c, r in found if r is not first and against_first(c, r) == 0]
    return Hit(first, simultaneous, at, tuple(c for c in strict if c not in simultaneous))


def _positive_until(phase: Phase, i: int, c: Constraint, end: fmpq, prec: int) -> bool:
    """c's function proven > 0 on (0, end] by enclosures on the Taylor steps' polynomials
    (:meth:`~lcs_exact.phases.taylorsum.TaylorRows.positive_until`): a constraint far from 0 up
    to the first event needs no search of its own.  False: not proven (or not on Taylor steps)."""
    if not phase.taylor or phase.policy.allow_unresolved:
        return False
    sign, order = phase.start_order(c)
    return sign > 0 and phase.taylor_rows(prec).positive_until(i, order, end)


def _quiet(phase: Phase, end: fmpq) -> tuple[bool, float | None]:
    """(quiet, guess): quiet when no event in (0, end] is proven on the phase's screen (Taylor
    steps of SCREEN_PREC bits, :meth:`~lcs_exact.phases.phase.Phase.screen_rows`): no
    constraint's guess crosses 0 there, and every constraint not identically 0 is proven > 0 on
    (0, end] (Lemma 5.1's start, then the steps' enclosures).  Not quiet: not proven (a guess
    crosses, a sign needs more bits, or the search's tie rules apply), and the search runs at its
    own precision; a guess that crosses costs the screen one step, and the earliest guess is
    returned (a float, for the search's grid only: no decision rests on it)."""
    if phase.policy.allow_unresolved:  # the search's assumed zeros must see every constraint
        return False, None
    live = []
    for i, c in enumerate(phase.constraints):
        sign, order = phase.start_order(c)
        if sign < 0:
            return False, None  # the search reports it
        if sign > 0:
            live.append((i, order))
    rows = phase.screen_rows()
    if rows.steps.locate(end) >= SCREEN_MAX_STEPS:
        return False, None
    guesses = [g for g in rows.guess_crossings(0.0, _float(end), [i for i, _ in live]) if g is not None]
    if guesses:
        return False, min(guesses)
    return all(rows.positive_until(i, order, end, SCREEN_MAX_STEPS) for i, order in live), None


def _before(first: Real, H: Real) -> bool:
    """first < H, shown by the root's bracket alone (False: not shown)."""
    if not isinstance(first, RootReal):
        return False
    with workprec(64):
        return first.hi < dyadic_lower(H.arb(64))


def _at_horizon(phase: Phase, first: Real, c: Constraint, H: Real, clock: PhaseClock | None) -> bool:
    """first == H, proven (False: not proven; the caller compares them).  A root that balls cannot
    tell from H is proven equal to it when H has a closed form that is a zero of c's function
    inside the root's bracket (a run to t_end = atan(2/3) or 2 pi that ends on an impact or a
    switch: no ball separates them, and none ever will), or, through the sources' clock, when
    t_end is a closed-form zero of a source's function (a phase started at an event with no
    closed form)."""
    if not isinstance(first, RootReal) or first.known_rational() is not None or \
            phase.policy.closed_forms == "off":
        return False
    with workprec(256):
        if not first.arb(256).overlaps(H.arb(256)):
            return False
    hc = H.closed
    if hc is not None and prove_root_is(first, phase.spectrum, c.g, phase.base, hc, phase.policy.deadline):
        first.set_proven(hc, None)
        return True
    ec = clock.t_end.closed if clock is not None and clock.t_end is not None else None  # H = t_end - t_s
    return ec is not None and clock.proves_root_at(phase, first, ec)


def _by_estimate(phase: Phase, horizon: fmpq, prec: int) -> list[tuple[float | None, Constraint]]:
    """[(estimate, constraint)], those whose float estimate crosses zero first in front: the
    certified search of the first one then bounds the others' (a constraint that never crosses is
    certified only up to the event, not over the whole horizon), and each search looks up to its
    estimate first.  Only the order and the windows depend on floats; every decision stays
    certified.  The sums are those the search uses next (same precision)."""
    keyed = []
    live = [i for i, c in enumerate(phase.constraints) if phase.start_order(c)[0] > 0]
    taylor = phase.taylor_rows(prec).guess_crossings(0.0, _float(horizon), live) if phase.taylor else None
    for i, c in enumerate(phase.constraints):
        est = None
        if i in live:
            est = taylor[i] if taylor is not None else \
                float_crossing(phase.function(c).at(prec), 0.0, _float(horizon))
        keyed.append((math.inf if est is None else est, i, est, c))
    keyed.sort(key=lambda e: (e[0], e[1]))
    return [(est, c) for _, _, est, c in keyed]


def _float(q: fmpq) -> float:
    """q as a float, capped at 1e300 (a horizon of 10^400 is only looked into so far)."""
    return float(min(q, fmpq(10) ** 300))


def theta(lcs: SystemLike, x0: Any, I, horizon: Any, *, time_limit: float | None = None) -> Real | None:
    """theta(x0, I) of Def. 4.3 on (0, horizon]: the length of the phase in mode I from x0.

    x0 outside V_I is first re-initialized to P_I x0 (the regular part of the solution of (4.2)).
    Returns an exact real (0 when u or y is immediately negative, Example 4.5), or None when
    no event occurs in (0, horizon].

    >>> from lcs_exact.models import two_carts
    >>> theta(two_carts(), [0, -1, 0, 0], {0}, 10).closed_form   # Example 4.4
    pi/2
    >>> theta(two_carts(), [0, 1, -1, 0], {0}, 10).closed_form   # Example 4.5
    0
    """
    mode = lcs.mode(I)
    policy = Policy(deadline=Deadline(time_limit))
    z: ExactVector = as_exact_vector(x0, lcs.n, policy=policy)
    q = z.known_rational()
    z = RationalVector(mode.projection() * q, policy) if q is not None else ProjectedVector(mode.projection(), z, policy)
    phase = Phase(mode, z, policy)
    if any(phase.start_order(c)[0] < 0 for c in phase.constraints):
        return RationalReal(0)
    H = as_real(horizon, policy)
    hit = next_event(phase, H, phase.policy.working_prec())
    return None if hit is None else hit.theta

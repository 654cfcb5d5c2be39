"""Impact cascades without a symmetry: the accumulation proven on a family of states (Remark 4.11).

A cascade of impacts (three carts closing on a wall one after the other, 1e-20, 1e-59, 1e-176,
...; two contacts taking turns between moving carts, 1e-11, 1e-21, 1e-42, ...) has no scaling
symmetry, so no geometric law.  It is proven here by induction over a family of states:

* The family.  After an event whose re-initialization ends in mode I, the state lies in V_I.
  With g the monitored row whose root ends the next phase (a gap y_b, or a force u_b) and A the
  next mode's A_J, V_I = V_bg + span(p, r), V_bg = {z in V_I : g z = 0, g A z = 0} (the
  "background": zero gap, zero speed), p and r in the sum of the cycle's jump spaces (so the
  jumps leave the background alone) with (g, gA) = (1, 0) on p and (0, 1) on r.  The LCS is
  linear, so states are taken up to a positive factor (the run from c z is the run from z with
  the states scaled by c):
    - no background (dim V_I = 2, the carts closing on the wall):  z = -r + eps p;
    - a background:  z = beta(delta) - sigma r + eps sigma^2 p, beta(delta) = beta_0 + sum_i
      delta_i b_i on the hyperplane l = 1 of V_bg (l, beta_0 rational, near the run's state).
  eps is small (super-geometrically so along the cascade), sigma in (0, Sigma] (the speed
  over the background), delta_i in [-Delta, Delta] (the background's drift).
* One cycle for the whole family at once.  Every quantity of the next p events is a Taylor
  model (:class:`~lcs_exact.taylormodels.Model`): an exact polynomial in eps and the parameters (python-flint's
  fmpq_mpoly) plus eps^(n+1) sigma^k times a certified interval, valid on the whole box.  A phase
  in mode J from x: f(t) = sum_j f A_J^j x t^j / j! with a certified tail; the trigger's root is
  t* = eps^mu sigma^nu tau(eps), tau a power series (Newton's method on series, exact; its
  speed's leading coefficient must be a rational constant), its remainder certified by the
  monotonicity of the blown-up function (d/dtau < 0 on the whole box).  Every other monitored
  function is t^r eps^m sigma^k (P(tau) + O(eps)) with P > 0 on the box, certified by interval
  evaluation (or P > 0 up to tau_a, f' < 0 after it and f(t*) > 0: a force that vanishes with
  the gaps).  The re-initialization is Algorithm 7.1's own event step
  (:func:`~lcs_exact.phases.eventstep.event_step`) in the arithmetic of families
  (:class:`~lcs_exact.phases.eventstep.FamilyStates`): each mode of the run's chain certified
  selected (the RCP admissibility rows lexicographically nonnegative, the rows of u_I strictly
  positive: by Theorem 6.3 the smallest admissible mode), the state outside V_I before each
  jump, inside V of the mode after at the end.  Exact zeros are structural only: a form
  vanishing on an exact subspace that contains the state for every parameter.
* The induction.  After the cycle the state is in the family again, with eps' <= kappa eps
  (kappa < 1), sigma' <= sigma and |delta' - delta| <= D eps, all certified on the box; with
  |delta_0| + D eps_0 / (1 - kappa) <= Delta every later cycle stays in the box: the run has
  infinitely many events and their times accumulate at T* = t_k + sum_m dur(m), enclosed by
  t_k + dur(0) <= T* <= t_k + dur(0) + beta eps_1 / (1 - kappa), beta = sup dur / eps.

Every decision is a certified sign of an exact rational or of an interval; a check that does
not hold (or that the models cannot decide) makes the proof fail, never guess.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from math import factorial
from typing import Sequence

from flint import arb, arb_mat, fmpq, fmpq_mat

from ..phases import FamilyState, FamilyStates, event_step, vanishes
from .accumulation import event_signature
from ..numbers import dyadic_lower, dyadic_upper, workprec
from ..algebra import hstack, submatrix, vstack
from ..algebra import image, intersection, kernel, rank
from ..numbers import (Box, Model, NoProof, Space, WorkBudget, interval, ipow, positive_on, series_root, shift, terms,
                           truncate)

def _row(M: fmpq_mat, i: int) -> list:
    return [M[i, j] for j in range(M.ncols())]


def _monitored(lcs, mode) -> list:
    """[(name, row)] of the functions a phase in ``mode`` monitors (u_i, i in I; y_i, i not in I),
    as :mod:`lcs_exact.phase` builds them for an autonomous mode."""
    F = mode.feedback()
    out = [(f"u_{i}", submatrix(F, [r], None)) for r, i in enumerate(mode.I)]
    for i in mode.Ic:
        g = submatrix(lcs.C, [i], None)
        if mode.I:
            g = g + submatrix(lcs.D, [i], mode.I) * F
        out.append((f"y_{i}", g))
    return out


def _krylov(A: fmpq_mat, U: fmpq_mat) -> fmpq_mat:
    """The smallest A-invariant subspace containing span(U) (a basis)."""
    n = A.nrows()
    cols, block = [U], U
    for _ in range(n):
        block = A * block
        cols.append(block)
    return image(hstack(*cols, nrows=n))


def _positive_multiple(a: fmpq_mat, b: fmpq_mat) -> bool:
    """a = lambda b for some rational lambda > 0 (rows, exactly); False when b = 0."""
    ae, be = a.entries(), b.entries()
    lam = next((x / y for x, y in zip(ae, be) if y != 0), None)
    return lam is not None and lam > 0 and all(x == lam * y for x, y in zip(ae, be))


def _norm_inf(M: fmpq_mat) -> arb:
    return arb(max((sum(abs(M[i, j]) for j in range(M.ncols())) for i in range(M.nrows())), default=fmpq(0)))


def _vanishing_orders(cons: list, triggers: tuple, K: fmpq_mat, A: fmpq_mat, U: fmpq_mat) -> dict:
    """The order of vanishing at t = 0 of each monitored function other than the triggers, on the
    whole family (structural: f A^r vanishes on U for r below it); those that vanish on the orbit
    K are left out."""
    orders = {}
    for name, f in cons:
        if name in triggers or vanishes(f, K):
            continue
        r = 0
        while vanishes(f * A ** r, U):
            r += 1
        orders[name] = r
    return orders


@dataclass
class _Phase:
    """One phase of the cycle on the family, on its trigger's time scale (module docstring):
    t = eps^mu sigma^nu tau, the trigger g's gap g x = eps^m0 sigma^a0 (gamma + ...) closing at a
    speed with the rational leading coefficient omega < 0; tau0 = gamma / -omega, tau in
    [0, tau_max].  ``X`` = [x, A x, ..., A^Jmax x] are the Taylor coefficients of x(t) (filled by
    :meth:`_Cascade.expand`), with |x| <= xbound, |A| <= alpha and e^(alpha t) <= growth on the
    phase (for the series' tails)."""

    A: fmpq_mat
    alpha: arb
    g: fmpq_mat
    m0: int
    a0: int
    omega: fmpq
    mu: int
    nu: int
    tau0: object
    tau_max: fmpq
    X: list = field(default_factory=list)
    Jmax: int = 0
    xbound: arb = None
    growth: arb = None


class _Cascade:
    """One cycle of a cascade run on the family (module docstring)."""

    def __init__(self, lcs, box: Box, order: int):
        self.lcs, self.box, self.N = lcs, box, order

    def event(self, x: list, U: fmpq_mat, mode_now, sig: tuple) -> tuple[list, fmpq_mat, Model]:
        """The next event from x (in the exact subspace U, a consistent state of ``mode_now``) with
        signature ``sig`` (mode before, chain, mode after, triggers): (state after, its subspace,
        the phase's duration t*)."""
        box = self.box
        J, chain, after, triggers = sig
        if J != mode_now:
            raise NoProof("the cycle's modes do not follow one another")
        mode = self.lcs.mode(J)
        if not mode.is_autonomous:
            raise NoProof(f"mode {sorted(J)} is not autonomous")
        cons = _monitored(self.lcs, mode)
        ph, K = self.trigger(x, U, mode, cons, triggers)
        orders = _vanishing_orders(cons, triggers, K, ph.A, U)
        self.expand(ph, x, orders)
        tau_m, rt = self.trigger_root(ph)
        tstar = box.up_s(box.up(tau_m, ph.mu), ph.nu)
        top = dyadic_upper(rt)
        # every other monitored function stays positive on (0, t*]
        at_end = []
        for name, f in cons:
            if name in orders and self.positive(name, f, ph.A, orders[name], ph.X, ph.mu, ph.nu, top, ph.alpha,
                                                ph.xbound, ph.growth):
                at_end.append((name, f))
        xm = FamilyState(box, self.state_at(ph, tstar), intersection(K, kernel(ph.g)))
        for name, f in at_end:
            if xm.sign(f) != 1:
                raise NoProof(f"{name} is not certified positive at the event", order=True)
        # the jumps, as Algorithm 7.1 makes them (the event step), certified on the whole family
        arith = FamilyStates(self.lcs, (*chain, after))
        step = event_step(arith, xm)
        arith.follows(step, chain, after)
        return step.state.x, step.state.U, tstar

    def cycle(self, x: list, V: fmpq_mat, mode_now, pattern: list) -> tuple[list, Model]:
        """The cycle ``pattern`` of events (signatures) from x, a family in V = V_I of ``mode_now``:
        (the state after it, back in V, and its duration, the sum of the phases' t*)."""
        U, D = V, None
        for sig in pattern:
            if self.box.check is not None:
                self.box.check()
            x, U, tstar = self.event(x, U, mode_now, sig)
            D, mode_now = (tstar if D is None else self.box.add(D, tstar)), sig[2]
        if rank(hstack(V, U, nrows=V.nrows())) != V.ncols():
            raise NoProof("the cycle does not return to V_I")
        return x, D

    def trigger(self, x: list, U: fmpq_mat, mode, cons: list, triggers: tuple) -> tuple["_Phase", fmpq_mat]:
        """The phase in ``mode`` from x on its trigger's time scale (:class:`_Phase`), and K, the
        smallest A_J-invariant subspace holding the family (the orbit): the triggers are
        monitored, simultaneous ones positive multiples of the first on the orbit, and the first
        a positive gap eps^m0 sigma^a0 gamma closing at the speed eps^m1 sigma^a1 omega < 0, omega
        rational, on a small time scale t = eps^mu sigma^nu tau."""
        box, sp = self.box, self.box.sp
        named = dict(cons)
        if not triggers or any(name not in named for name in triggers):
            raise NoProof(f"triggers {triggers} are not monitored in mode {sorted(mode.I)}")
        g = named[triggers[0]]
        A = mode.closed_loop()
        alpha = _norm_inf(A)
        K = _krylov(A, U)
        for name in triggers[1:]:  # simultaneous triggers: positive multiples of the first on the orbit
            if not _positive_multiple(named[name] * K, g * K):
                raise NoProof(f"{name} and {triggers[0]} are not proven to reach 0 together")
        # the trigger: gap eps^m0 sigma^a0 gamma > 0, speed eps^m1 sigma^a1 omega < 0 (omega rational)
        d0, d1 = box.lin(_row(g, 0), x), box.lin(_row(g, 0), box.matvec(A, x))
        if box.sign(d0) != 1 or box.sign(d1) != -1:
            raise NoProof(f"{triggers[0]} is not a positive gap closing at a certified speed", order=True)
        m0, a0, gamma = box.lead(d0)
        m1, a1, omega = box.lead(d1)
        if not omega.is_constant():
            raise NoProof("the trigger's speed is not a rational multiple of the family's speed")
        omega = terms(omega)[(0,) * sp.nv]
        mu, nu = m0 - m1, a0 - a1
        if mu < 1 or nu < 0:
            raise NoProof("the trigger's time scale is not small")
        tau0 = gamma * (-1 / omega)
        tau_max = 2 * dyadic_upper(box.param_range(tau0))
        return _Phase(A, alpha, g, m0, a0, omega, mu, nu, tau0, tau_max), K

    def expand(self, ph: "_Phase", x: list, orders: dict) -> None:
        """The phase's Taylor coefficients X_j = A^j x, j <= Jmax (enough for models of order N
        after the slowest monitored function's vanishing order), and the bounds of their tails."""
        box = self.box
        ph.Jmax = -(-(self.N + 1) // ph.mu) + max(orders.values(), default=0) + 1
        ph.X = [x]
        for _ in range(ph.Jmax):
            ph.X.append(box.matvec(ph.A, ph.X[-1]))
        ph.xbound = max((abs(box.range(c)).upper() for c in x), default=arb(0))
        Tmax = box.pw(ph.mu).upper() * box.ps(ph.nu).upper() * arb(ph.tau_max)  # t <= S^mu Sigma^nu tau_max
        ph.growth = (ph.alpha * Tmax).exp()

    def blown_up_trigger(self, ph: "_Phase") -> tuple[list, int, arb, int, int]:
        """H(tau) = g x(eps^mu sigma^nu tau) / (eps^m0 sigma^a0) = sum_j H_j tau^j, the series'
        tail in H_0: (H, the models' order nH, |g|, and the orders eps^lost sigma^lost_s of the
        tail)."""
        box, g, mu, nu, m0, a0 = self.box, ph.g, ph.mu, ph.nu, ph.m0, ph.a0
        phi = arb(sum(abs(c) for c in g.entries()))
        H = []
        for j, Xj in enumerate(ph.X):
            dj = box.lin(_row(g, 0), Xj)
            if j >= 2 and box.val(dj) + mu * j <= m0:
                raise NoProof("the trigger is not ruled by its gap and speed", order=box.val(dj) > dj.n)
            hj = box.up(dj, mu * j - m0) if mu * j >= m0 else box.down(dj, m0 - mu * j)
            hj = box.up_s(hj, nu * j - a0) if nu * j >= a0 else box.down_s(hj, a0 - nu * j)
            H.append(box.scale(hj, fmpq(1, factorial(j))))
        lost, lost_s = mu * (ph.Jmax + 1) - m0, nu * (ph.Jmax + 1) - a0
        if lost < 1 or lost_s < 0:
            raise NoProof("series too short", order=True)
        eH = (phi * ph.xbound * ipow(ph.alpha * arb(ph.tau_max), ph.Jmax + 1) / factorial(ph.Jmax + 1)
              * ph.growth)
        H[0] = box.add(H[0], box.error(lost, lost_s, eH))
        nH = min(h.n for h in H)
        if nH < 0:
            raise NoProof("the trigger's model is too short", order=True)
        return H, nH, phi, lost, lost_s

    def trigger_root(self, ph: "_Phase") -> tuple[Model, arb]:
        """The trigger's root tau* of H (a power series in the parameters by Newton's method,
        exact) as a Taylor model whose remainder is certified by the monotonicity of H on
        [0, tau_max] (dH/dtau < 0 on the whole box, H(tau_max) < 0); and its range, inside
        (0, tau_max)."""
        box, sp = self.box, self.box.sp
        H, nH, phi, lost, lost_s = self.blown_up_trigger(ph)
        tau = series_root(sp, [truncate(sp, h.p, nH) for h in H], ph.tau0, ph.omega, nH)
        tau_m = Model(tau, nH, 0, arb(0))
        resid, power = box.const(0, nH), box.const(1, nH)
        for hj in H:
            resid = box.add(resid, box.mul(hj, power))
            power = box.mul(power, tau_m)
        resid = box.trunc(resid, nH)
        if box.val(resid) <= nH:
            raise NoProof("internal: the series root does not solve the truncated equation")
        tau_max = ph.tau_max
        tI = interval(fmpq(0), tau_max)
        dH = arb(0)
        for j in range(1, len(H)):
            dH += j * box.range(H[j]) * ipow(tI, j - 1)
        edH = phi * ph.xbound * ph.alpha * ipow(ph.alpha * arb(tau_max), ph.Jmax) / factorial(ph.Jmax) * ph.growth
        dH += arb(0, (edH * box.pw(lost) * box.ps(lost_s)).upper())
        if not dH < 0:
            raise NoProof("the trigger is not certified monotone on the phase")
        H_end = arb(0)
        for j, hj in enumerate(H):
            H_end += box.range(hj) * ipow(arb(tau_max), j)
        if not H_end < 0:
            raise NoProof("the trigger's root is not bracketed")
        tau_m = Model(tau, nH, resid.k, arb(0, (abs(resid.r).upper() / (-dH.upper())).upper()))
        rt = box.range(tau_m)
        if not (rt > 0 and rt < arb(tau_max)):
            raise NoProof("the trigger's root leaves the box")
        return tau_m, rt

    def state_at(self, ph: "_Phase", tstar: Model) -> list:
        """The state at t*: sum_j A^j x t*^j / j! plus the tail."""
        box = self.box
        xm = None
        power = box.const(1, self.N)
        for j, Xj in enumerate(ph.X):
            term = [box.scale(box.mul(c, power), fmpq(1, factorial(j))) for c in Xj]
            xm = term if xm is None else [box.add(a, b) for a, b in zip(xm, term)]
            power = box.mul(power, tstar)
        ex = box.error(ph.mu * (ph.Jmax + 1), ph.nu * (ph.Jmax + 1),
                       ph.xbound * ipow(ph.alpha * arb(ph.tau_max), ph.Jmax + 1) / factorial(ph.Jmax + 1) * ph.growth)
        return [box.add(c, ex) for c in xm]

    def profile(self, name, f, phi, X, mu, nu, r, top, alpha, xbound, growth):
        """F(t) = sum_j f X_j t^j / j! (+ its series' tail) on t = eps^mu sigma^nu tau, tau in
        [0, top]: F = t^r eps^m sigma^k (P(tau) + e), |e| <= bound.  Returns (P, bound)."""
        box = self.box
        J = len(X) - 1
        G = []
        for i, Xj in enumerate(X[r:]):
            dj = box.lin(_row(f, 0), Xj)
            G.append(box.scale(box.up_s(box.up(dj, mu * i), nu * i), fmpq(1, factorial(r + i))))
        m = min(box.val(gi) for gi in G)
        if any(gi.n < m for gi in G):
            raise NoProof(f"{name}: a model of too low an order", order=True)
        coefs = [box.coef(gi, m) for gi in G]
        ks = min((box.vs(c) for c in coefs if not c.is_zero()), default=0)
        P = [shift(box.sp, c, box.sig, -ks) if ks else c for c in coefs]
        bound = arb(0)
        tm = arb(top)
        for i, gi in enumerate(G):
            bound += abs(box.range(box.down_s(box.rest(gi, m), ks))) * box.Sa * ipow(tm, i)
        k = J + 1 - r
        if mu * k - m < 1 or nu * k - ks < 0:
            raise NoProof(f"{name}: series too short", order=True)
        # the series' tail: |E(t)| / (t^r eps^m sigma^ks) <= phi X alpha^(J+1) t^(J+1-r) / (J+1)! e^(alpha t) / ...
        bound += (phi * xbound * ipow(alpha, J + 1) * ipow(tm, k) / factorial(J + 1) * box.pw(mu * k - m)
                  * box.ps(nu * k - ks) * growth)
        return P, bound.upper()

    def positive(self, name, f, A, r, X, mu, nu, top, alpha, xbound, growth) -> bool:
        """f(t) > 0 for t in (0, eps^mu sigma^nu top], on the whole box (top >= tau*): f = t^r
        eps^m sigma^k (P(tau) + O(eps)) with P > 0 on [0, top].  When P reaches 0 near the trigger
        (a force that vanishes with the gaps at a corner), P > 0 on [0, tau_a] and f' < 0 on
        [tau_a, top]: then True is returned and f(t*) > 0 must still be certified by the caller.
        ``r``: f vanishes to order r at t = 0 on the whole family (structurally)."""
        phi = arb(sum(abs(c) for c in f.entries()))
        P, bound = self.profile(name, f, phi, X, mu, nu, r, top, alpha, xbound, growth)
        if positive_on(self.box, P, fmpq(0), top, bound):
            return False
        fA = f * A
        phi1 = arb(sum(abs(c) for c in fA.entries()))
        P1, bound1 = self.profile(name + "'", f, phi1, X[1:], mu, nu, 0, top, alpha, xbound, growth)
        negP1 = [-c for c in P1]
        for k in range(1, 24):
            tau_a = top * (1 - fmpq(1, 2 ** k))
            if not positive_on(self.box, P, fmpq(0), tau_a, bound):
                break
            if positive_on(self.box, negP1, tau_a, top, bound1):
                return True
        raise NoProof(f"{name} is not certified positive before the trigger", order=True)


#: the highest order of the models tried on a family with a background (their polynomials in
#: the parameters grow with it: order 12 costs ~10 s a cycle)
MAX_BACKGROUND_ORDER = 12


@dataclass(frozen=True)
class CascadeBound:
    """A right-accumulation of events proven without a geometric law (an impact cascade): the
    run from event ``first_event`` repeats a cycle of ``period`` events forever, each cycle's
    small parameter at most ``contraction`` times the previous one, so the event times
    accumulate at a time T* with ``lower <= T* <= upper`` (exact rationals, certified).
    ``order`` is the order of the Taylor models that proved it, ``background`` whether the family
    had one (two contacts taking turns between moving carts) or not (a corner)."""

    lower: fmpq
    upper: fmpq
    period: int
    first_event: int
    contraction: fmpq
    order: int
    background: bool = False

    def __repr__(self):
        return (f"CascadeBound({float(self.lower):.17g} <= T* <= {float(self.upper):.17g}, cycle of "
                f"{self.period} events from event {self.first_event}, contraction <= {float(self.contraction):.3g})")


def cascade_bound(lcs, events: Sequence, *, prec: int = 128, max_prec: int = 4096,
                  orders: Sequence[int] = (7, 12, 40), check=None, tried: set | None = None,
                  background_order: int = 12, budget: int | None = None) -> CascadeBound | None:
    """A certified enclosure of the accumulation time of the cascade the last events start, or
    None when no proof is found (the module docstring).

    ``events`` are the run's :class:`~lcs_exact.trajectory.Event` objects (exact states and times);
    the cycle is read from the last events (signatures repeating with a period p <= 8) and proven
    from a state after one of them; ``prec`` is the precision of the enclosure's arithmetic,
    ``max_prec`` the most spent on the start state's coordinates; ``check()`` (a deadline) is
    called between the steps; ``tried`` (a set kept by the caller) skips the starts a previous
    call tried already; ``background_order`` caps the order of the models for a family with a
    background (they grow fast: a caller that can wait for more events tries 7 first);
    ``budget`` (coefficient products of the Taylor models, :class:`~lcs_exact.taylormodels.WorkBudget`:
    work, not seconds, so that the outcome is the same on every machine) ends the attempt with None
    when spent.  Requires Theorem 6.3 (unique initial solutions) and the paper's
    re-initialization (no restitution)."""
    if getattr(lcs, "restitution", None) is not None or not lcs.well_posedness():
        return None
    K = len(events) - 1
    tried = set() if tried is None else tried
    guard = WorkBudget(budget, check)

    for p in range(1, 9):
        if K - 2 * p + 1 < 0:
            break
        if any(event_signature(events[K - j]) != event_signature(events[K - p - j]) for j in range(p)):
            continue
        for k0 in range(K, max(K - 2 * p, p - 2), -1):
            if (p, k0, background_order) in tried:
                continue
            tried.add((p, k0, background_order))
            ev = events[k0]
            if not ev.modes:
                continue
            pattern = [event_signature(events[k0 + 1 - p + j]) for j in range(p)]
            if pattern[0][0] != ev.mode_after or pattern[-1] != event_signature(ev):
                continue
            for N in orders:
                try:
                    guard()
                    return _certify_cycle(lcs, ev, k0, pattern, N, prec, max_prec, check=guard,
                                          background_order=background_order)
                except NoProof as e:
                    if guard.exhausted:
                        return None
                    if not e.order:
                        break
    return None


def _certify_cycle(lcs, ev, k0: int, pattern: list, N: int, prec: int, max_prec: int, cusp: int = 2,
                   check=None, background_order: int = 12) -> CascadeBound:
    """The proof from the state after event ``ev`` (index k0) through one cycle ``pattern``; with a
    background the small variable is eta = eps / sigma^cusp (the family is the cusp eps <= S sigma^cusp,
    which the cycle keeps: eps shrinks far faster than sigma)."""
    n = lcs.n
    dec = _decomposition(lcs, ev, pattern)
    nb = dec.Vbg.ncols()
    if nb and N > min(background_order, MAX_BACKGROUND_ORDER):
        raise NoProof("models of this order are too costly with a background")
    zb, co, pbits = _start_coordinates(ev.state_after, dec.Ldec, nb, n, prec, max_prec)
    with workprec(max(prec, pbits)):
        fam = _corner_family(dec, co, n) if nb == 0 else _background_family(dec, zb, co, n, cusp)
        box = Box(fam.sp, check)
        x, D = _Cascade(lcs, box, N).cycle([box.model(xi, N) for xi in fam.x_of], dec.V, ev.mode_after, pattern)
        kappa, eps1 = _contraction(box, dec, x, fam, cusp)
        beta = box.bounds(D, 1).upper()
        D0 = box.at(D, fam.point)
        t0 = ev.time.ball(max(1, int(prec * 0.30103)))
        lower = t0 + D0
        upper = t0 + D0 + beta * eps1 / (1 - kappa)
        return CascadeBound(dyadic_lower(lower), dyadic_upper(upper), len(pattern), k0, dyadic_upper(kappa), N,
                            nb > 0)


def _contraction(box: Box, dec: "_Decomposition", x: list, fam: "_Family", cusp: int) -> tuple[arb, arb]:
    """The state x after the cycle back in the family (a positive gap closing), its small
    parameter contracted (kappa < 1) and, with a background, its drift kept inside the box:
    (kappa, the small parameter after the cycle at the run's point)."""
    gx, gAx = box.lin(_row(dec.g, 0), x), box.lin(_row(dec.gA, 0), x)
    if box.sign(gx) != 1 or box.sign(gAx) != -1:
        raise NoProof("the state after the cycle is not certified in the family", order=True)
    if dec.Vbg.ncols() == 0:
        kappa, eps1, drift = _corner_contraction(box, gx, gAx, fam.point)
    else:
        kappa, eps1, drift = _background_contraction(box, gx, gAx, x, fam, cusp)
    if not kappa < 1:
        raise NoProof("the cycle is not certified to contract")
    if drift is not None and not (arb(fam.dmax) + drift * arb(fam.S) / (1 - kappa)) <= arb(fam.sp.Delta):
        raise NoProof("the background's drift is not certified inside the box")
    return kappa, eps1


@dataclass(frozen=True)
class _Decomposition:
    """V_I = V_bg + span(p, r) (module docstring): V, the consistent subspace after the event;
    ``Vbg`` the background (zero gap and speed); p and r in the cycle's jump spaces with
    (g, gA) = (1, 0) on p and (0, 1) on r, g the first phase's trigger and A its mode's A_J;
    ``Ldec`` the coordinates on V in the basis [Vbg, p, r]."""

    V: fmpq_mat
    g: fmpq_mat
    gA: fmpq_mat
    Vbg: fmpq_mat
    p_vec: fmpq_mat
    r_vec: fmpq_mat
    Ldec: fmpq_mat


def _decomposition(lcs, ev, pattern: list) -> _Decomposition:
    """The decomposition of V_I after event ``ev`` for the cycle ``pattern``, checked: V_I inside
    the first mode's consistent subspace, its trigger monitored, the cycle's jump spaces meeting
    V_I in a plane on which the trigger's gap and speed are coordinates."""
    n = lcs.n
    V = lcs.mode(ev.modes[-1]).consistent_subspace()
    d = V.ncols()
    J0, _, _, triggers = pattern[0]
    mode0 = lcs.mode(J0)
    if not vanishes(mode0.annihilator(), V):
        raise NoProof("V_I is not inside the consistent subspace of the next mode")
    named = dict(_monitored(lcs, mode0))
    if not triggers or triggers[0] not in named:
        raise NoProof("the trigger is not monitored")
    g = named[triggers[0]]
    gA = g * mode0.closed_loop()
    # V = V_bg + span(p, r): the background has zero gap and speed; p, r in the cycle's jump spaces
    Vbg = intersection(V, kernel(vstack(g, gA)))
    jumps = hstack(*[lcs.mode(I).jump_space() for sig in pattern for I in sig[1]], nrows=n)
    Wc = intersection(V, image(jumps)) if jumps.ncols() else fmpq_mat(n, 0)
    if Wc.ncols() != 2 or Vbg.ncols() != d - 2 or rank(hstack(Vbg, Wc, nrows=n)) != d:
        raise NoProof("no decomposition of V_I into a background and the trigger's gap and speed")
    GW = vstack(g, gA) * Wc
    if GW.det() == 0:
        raise NoProof("the trigger's gap and speed do not span the jump directions")
    PR = Wc * GW.inv()  # columns p, r: (g, gA) = (1, 0) and (0, 1)
    p_vec, r_vec = submatrix(PR, None, [0]), submatrix(PR, None, [1])
    basis = hstack(Vbg, p_vec, r_vec, nrows=n)
    Ldec = (basis.transpose() * basis).inv() * basis.transpose()  # coordinates on V
    return _Decomposition(V, g, gA, Vbg, p_vec, r_vec, Ldec)


def _start_coordinates(z, Ldec: fmpq_mat, nb: int, n: int, prec: int, max_prec: int) -> tuple[arb_mat, list, int]:
    """The start state z (balls) and its coordinates [background, gap, speed] on V, to ``prec``
    bits of relative accuracy (the precision doubled up to ``max_prec`` until the gap is positive,
    the speed negative and some background coordinate nonzero); and the precision used."""
    pbits = prec
    while True:
        with workprec(pbits):
            zb = z.arb(pbits)
            co = [sum((arb(Ldec[i, j]) * zb[j, 0] for j in range(n)), arb(0)) for i in range(nb + 2)]
            gap, speed = co[nb], co[nb + 1]
            ok = gap > 0 and speed < 0 and min(gap.rel_accuracy_bits(), speed.rel_accuracy_bits()) >= prec - 8
            if ok and nb:
                ok = all(c.rel_accuracy_bits() >= prec - 8 or c.rad() == 0 for c in co[:nb]) and \
                    any(not c.contains(0) for c in co[:nb])
            if ok:
                return zb, co, pbits
        if pbits >= max_prec:
            raise NoProof("the start state's gap is not resolved")
        pbits = min(2 * pbits, max_prec)


@dataclass(frozen=True)
class _Family:
    """The family of states the cycle is proven on (module docstring): its parameter space ``sp``
    (eps, and with a background sigma and delta), the run's own point in it, the state x(params)
    (``x_of``, polynomials), the bound S on eps, and with a background the forms l and delta_i on
    R^n and the start's largest |delta|."""

    sp: Space
    point: list
    x_of: list
    S: fmpq
    l_row: fmpq_mat | None = None
    d_rows: tuple = ()
    dmax: fmpq = fmpq(0)


def _corner_family(dec: _Decomposition, co: list, n: int) -> _Family:
    """No background (the carts closing on the wall): z = c (-r + eps p), c = -speed."""
    gap, speed = co[0], co[1]
    eps0 = gap / -speed
    S = dyadic_upper(eps0)
    sp = Space(S)
    e_g = sp.gens[0]
    x_of = [-sp.const(dec.r_vec[i, 0]) + e_g * dec.p_vec[i, 0] for i in range(n)]
    return _Family(sp, [eps0], x_of, S)


def _background_family(dec: _Decomposition, zb: arb_mat, co: list, n: int, cusp: int) -> _Family:
    """A background: z = l(beta) (beta_0 + sum delta_i b_i - sigma r + eps sigma^(cusp + 2) p),
    beta_0 a few-bit rounding of the start's background, l = 1 on it, the b_i completing it to a
    basis of V_bg; sigma the speed over the background, eta = eps / sigma^cusp the small variable."""
    Vbg, Ldec = dec.Vbg, dec.Ldec
    nb = Vbg.ncols()
    gap, speed = co[nb], co[nb + 1]
    cb = [_round_bits(dyadic_lower(c.mid()), 24) for c in co[:nb]]  # few bits: small polynomials
    cvec = fmpq_mat(nb, 1, cb)
    beta0 = Vbg * cvec
    norm2 = (cvec.transpose() * cvec)[0, 0]
    if norm2 == 0:
        raise NoProof("no background")
    # coordinates of the background in the basis [beta_0's direction, e_1, ..., e_{nb-1}]
    comp = kernel(cvec.transpose())  # nb x (nb - 1)
    Q = hstack(cvec, comp, nrows=nb).inv()  # rows: l, delta_1..delta_{nb-1} on background coordinates
    Lbg = submatrix(Ldec, range(nb), None)
    rows = Q * Lbg  # forms on R^n (exact on V)
    l_row = submatrix(rows, [0], None)
    d_rows = tuple(submatrix(rows, [i], None) for i in range(1, nb))
    lz = sum((arb(l_row[0, j]) * zb[j, 0] for j in range(n)), arb(0))
    if not lz > 0:
        raise NoProof("the background is not certified positive along l")
    sigma0 = -speed / lz
    eps0 = gap * lz / (speed * speed) / ipow(sigma0, cusp)  # eta = eps / sigma^cusp
    deltas0 = [sum((arb(r[0, j]) * zb[j, 0] for j in range(n)), arb(0)) / lz for r in d_rows]
    S, Sigma = dyadic_upper(eps0), dyadic_upper(sigma0)
    dmax = max((dyadic_upper(abs(c)) for c in deltas0), default=fmpq(0))
    Delta = max(4 * dmax, S * 2 ** 10)
    sp = Space(S, Sigma, nb - 1, Delta)
    e_g, s_g = sp.gens[0], sp.gens[1]
    bcols = [Vbg * submatrix(comp, None, [i]) for i in range(nb - 1)]
    x_of = []
    for i in range(n):
        xi = sp.const(beta0[i, 0]) - s_g * dec.r_vec[i, 0] + e_g * s_g ** (cusp + 2) * dec.p_vec[i, 0]
        for t, bc in enumerate(bcols):
            xi = xi + sp.gens[2 + t] * bc[i, 0]
        x_of.append(xi)
    return _Family(sp, [eps0, sigma0] + deltas0, x_of, S, l_row, d_rows, dmax)


def _corner_contraction(box: Box, gx: Model, gAx: Model, point: list) -> tuple[arb, arb, None]:
    """No background: eps' = g x / (-gA x); (kappa, the sup of eps' / eps on the box; eps' at the
    run's point; no drift)."""
    if not box.range(gAx) < 0:
        raise NoProof("the cycle's speed is not certified")
    kappa = box.bounds(gx, 1).upper() / (-box.range(gAx)).lower()
    eps1 = box.at(gx, point) / -box.at(gAx, point)
    return kappa, eps1, None


def _background_contraction(box: Box, gx: Model, gAx: Model, x: list, fam: _Family, cusp: int) -> tuple:
    """A background: sigma' = -gA x / l', eta' = g x l'^(q+1) / (-gA x)^(q+2), delta' - delta =
    (d x - delta l') / l'; (kappa, the sup of eta' / eta; eta' at the run's point; the drift's
    bound per unit of eps), with the speed over the background certified not to grow."""
    sp = fam.sp
    lx = box.lin(_row(fam.l_row, 0), x)
    lr = box.range(lx)
    if not lr > 0:
        raise NoProof("the background after the cycle is not certified positive", order=True)
    speed1 = box.range(box.down_s(gAx, 1))  # gA x / sigma < 0
    if not speed1 < 0:
        raise NoProof("the cycle's speed is not certified", order=True)
    if not (-speed1).upper() / lr.lower() <= 1:
        raise NoProof("the speed over the background is not certified not to grow")
    kappa = (box.bounds(box.down_s(gx, cusp + 2), 1).upper() * ipow(lr.upper(), cusp + 1)
             / ipow((-speed1).lower(), cusp + 2))
    drift = arb(0)
    for i, dr in enumerate(fam.d_rows):
        num = box.add(box.lin(_row(dr, 0), x), box.scale(box.mulp(lx, sp.gens[2 + i]), -1))
        drift = max(drift, abs(box.bounds(num, 1)).upper() / lr.lower(), key=lambda b: b.upper())
    lpt, gpt, gApt = box.at(lx, fam.point), box.at(gx, fam.point), box.at(gAx, fam.point)
    eps1 = gpt * ipow(lpt, cusp + 1) / ipow(-gApt, cusp + 2)
    return kappa, eps1, drift


def _round_bits(q: fmpq, bits: int) -> fmpq:
    """q rounded to a dyadic with about ``bits`` significant bits (0 stays 0)."""
    if q == 0:
        return q
    num, den = int(q.p), int(q.q)
    e = bits - (abs(num).bit_length() - den.bit_length())
    if e >= 0:
        return fmpq((num << e) // den, 1 << e)
    return fmpq(num // (den << -e) << -e, 1)

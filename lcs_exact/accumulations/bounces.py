"""Accumulations of Newton impacts without a symmetry: a contraction of the impact map (Remark 4.11).

A ball bouncing to rest on a floor has a geometric law when nothing but gravity acts
(:mod:`lcs_exact.accumulation`).  A spring, a second mass or a drag breaks the scaling symmetry:
the impacts still accumulate (Siconos' LinearOscillatorED: a mass on a spring whose equilibrium is
below the floor), each flight about e times the previous, but no law holds exactly.  Such an
accumulation is proven here by induction over a family of states, with certified balls only.

* The cycle.  One contact b (or several hitting together where their gaps agree, :func:`bounce_cycle`),
  one mode J of resting contacts between impacts (J = {}: every contact open), Newton's law with restitution 0 < e_b < 1 at each impact, pushing the resting contacts
  too (x+ = R x-, R = I - (1 + e_b) r (C A)_b, r = B_C W_CC^-1 e_b, C = J + {b}, W_CC^-1 e_b > 0);
  the last events of the run repeat it; A below is the flights' closed loop A_J.
* The family.  After an impact the gap c x = 0 (c = C_b) and its speed c A x = sigma > 0.  With
  the background V_bg = {c x = 0, c A x = 0} inside V_J (basis V, coordinates w = L x), every such state is
  x = V w + sigma r; R leaves V w alone (c A V = 0).
* One cycle in blown-up time.  The flight from x lasts tau = sigma s*, s* the root of
  F(s) = g(sigma s) / (sigma^2 s) = sum_j c A^(j+1) r t^j / (j+1)! + s sum_j c A^(j+2) V w t^j / (j+2)!
  (t = sigma s; F(0) = 1, F'(s) ~ a / 2 with a = c A^2 V w < 0: the force pushing onto the contact).
  The impact gives sigma' = -e sigma V(s*), V the normalized speed before it, and
  w' = w + sigma L R Delta(s*), Delta the flight's displacement over sigma.  Every series is
  summed with a certified tail (|rho A^j v| <= |rho| C nu^j |v|, nu from ||A^p||^(1/p)).
* The induction.  On a box (sigma in [0, Sigma], w within Delta of the start) certified balls show:
  F' < 0 on [0, s_hi], F(s_lo) > 0 > F(s_hi) (one root, the gap positive before it), the other
  contacts' gaps positive, V < 0 on [s_lo, s_hi], kappa = e sup(-V) < 1 and |w' - w| <= D sigma;
  with |w_0 - centre| + D Sigma / (1 - kappa) inside the box every later cycle stays in it.  So
  there are infinitely many impacts, sigma_m <= kappa^m sigma_0, and their times accumulate at
  T* = t_k + sum_m sigma_m s*_m.
* Digits.  T*, the event times t_k + tau_0 + ... + tau_m, the states inside the window and the
  limit x(T*-) = V w* are balls of any precision: the cycle map iterated on balls (interval
  Newton for each s*) until the tail s_hi sigma_M / (1 - kappa) is below the precision asked.
  Coordinates that every cycle keeps exactly (forms q with q A = 0 and q r = 0: a constant
  source) make the limit exact where they determine it (a ball at rest on the floor: x* = (0, 0, 1)).

Every decision is a certified sign of a ball; a check that fails makes the proof fail, never guess.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

from flint import arb, arb_mat, fmpq, fmpq_mat

from ..algebra import hstack, kernel, norm_inf, rank, submatrix, vstack, zeros
from ..errors import LimitExceeded, UnresolvedSign
from ..interfaces import AccumulationWindow
from ..numbers import ExactVector, ProjectedVector, RationalVector, Real, as_real, dyadic_lower, dyadic_upper, workprec
from .bouncecycles import BounceCycle, bounce_cycle

__all__ = ["BOUNCE_PATIENCE", "flight_holding", "BounceCycle", "BounceProof", "BounceWindow", "bounce_cycle", "prove_bounces", "bounce_window"]

#: shrinking phases a run of Newton impacts of one contact may go on before a suspected accumulation
#: stops it unproven (the proof needs flights short beside the background's motion: a spring of
#: period 0.02 s beside the flights, 40 more impacts at e = 0.9)
BOUNCE_PATIENCE = 400

#: cycles of the ball iteration before it gives up (a contraction this slow is not an accumulation
#: this method serves: kappa = 0.999 needs ~90,000 cycles for 128 bits)
MAX_CYCLES = 200_000


def _tail(u: arb, J: int) -> arb:
    """u^J / J! e^u: the tail sum_{j>=J} u^j / j! (u >= 0)."""
    return u ** J / arb(math.factorial(J)) * u.exp()


def _terms(u_up: float, bits: int) -> int:
    """The number of series terms whose tail is below 2^-bits for nu t <= u_up (a choice only:
    the tail is bounded rigorously where it is used)."""
    J, term = 4, 1.0
    for j in range(1, 400):
        term *= max(u_up, 1e-300) / j
        if j >= 4 and term * math.exp(min(u_up, 700)) < 2.0 ** -bits:
            return max(J, j + 1)
    return 400


class _Eval:
    """The cycle's series at (s, sigma, w) balls, J terms and certified tails."""

    def __init__(self, cyc: BounceCycle, J: int, prec: int):
        self.cyc, self.J, self.prec = cyc, J, prec
        self.k = cyc.coefficients(J, prec)
        with workprec(prec):
            self.nu, self.C = arb(cyc.nu), arb(cyc.C)
            self.cn = arb(sum((abs(cyc.c[0, j]) for j in range(cyc.c.ncols())), fmpq(0)))
            self.rn = arb(norm_inf(cyc.r))
            self.Vn = arb(norm_inf(cyc.V))
            self.LRn = arb(norm_inf(cyc.L * cyc.R))
            self.fn = [arb(sum((abs(f[0, j]) for j in range(f.ncols())), fmpq(0))) for f in cyc.others]
            self.fV = [arb_mat(f * cyc.V) for f in cyc.others]
            self.fAr = [[arb_mat(f) * a for a in self.k["Ar"]] for f in cyc.others]
            self.fAV = [[arb_mat(f) * a for a in self.k["AV"]] for f in cyc.others]

    def _wn(self, w: arb_mat) -> arb:
        return self.Vn * max((abs(w[i, 0]).upper() for i in range(w.nrows())), default=arb(0))

    def _pm(self, x: arb) -> arb:
        return arb(0, x.upper()) if x.upper() > 0 else arb(0)

    def F(self, s: arb, sig: arb, w: arb_mat) -> arb:
        k, J, f = self.k, self.J, self.k["f"]
        t = sig * s
        out = sum((k["cr"][j] * t ** j / f[j + 1] for j in range(J)), arb(0))
        out += s * sum(((k["cw"][j] * w)[0, 0] * t ** j / f[j + 2] for j in range(J)), arb(0))
        u = abs(self.nu * t).upper()
        return out + self._pm(self.cn * self.C * (self.nu * self.rn + abs(s).upper() * self.nu ** 2 * self._wn(w)) * _tail(u, J))

    def dF(self, s: arb, sig: arb, w: arb_mat) -> arb:
        k, J, f = self.k, self.J, self.k["f"]
        t = sig * s
        out = sum((k["cr"][j] * sig * j * t ** (j - 1) / f[j + 1] for j in range(1, J)), arb(0))
        out += sum(((k["cw"][j] * w)[0, 0] * (j + 1) * t ** j / f[j + 2] for j in range(J)), arb(0))
        u = abs(self.nu * t).upper()
        tail = self.cn * self.C * (self.rn * self.nu ** 2 * abs(sig).upper() * _tail(u, J - 1)
                                   + self.nu ** 2 * self._wn(w) * _tail(u, J))
        return out + self._pm(tail)

    def V(self, s: arb, sig: arb, w: arb_mat) -> arb:
        """The speed of the gap before the impact over sigma: c A x(sigma s) / sigma."""
        k, J, f = self.k, self.J, self.k["f"]
        t = sig * s
        out = sum((k["cr"][j] * t ** j / f[j] for j in range(J)), arb(0))
        out += s * sum(((k["cw"][j] * w)[0, 0] * t ** j / f[j + 1] for j in range(J)), arb(0))
        u = abs(self.nu * t).upper()
        return out + self._pm(self.cn * self.C * (self.nu * self.rn + abs(s).upper() * self.nu ** 2 * self._wn(w)) * _tail(u, J))

    def _delta(self, Ar: list, AV: list, norm: arb, s: arb, sig: arb, w: arb_mat) -> arb_mat:
        """sum_j M A^j r t^j / j! + s sum_j M A^(j+1) V w t^j / (j+1)! (rows of M: Ar, AV given)."""
        J, f = self.J, self.k["f"]
        t = sig * s
        rows = Ar[0].nrows()
        out = arb_mat(rows, 1)
        for j in range(J):
            tj = t ** j
            out += Ar[j] * (tj / f[j]) + (AV[j] * w) * (s * tj / f[j + 1])
        u = abs(self.nu * t).upper()
        e = self._pm(norm * self.C * (self.rn + abs(s).upper() * self.nu * self._wn(w)) * _tail(u, J))
        return arb_mat(rows, 1, [out[i, 0] + e for i in range(rows)])

    def drift(self, s: arb, sig: arb, w: arb_mat) -> arb_mat:
        """(w' - w) / sigma = L R Delta(s)."""
        return self._delta(self.k["LRr"], self.k["LRV"], self.LRn, s, sig, w)

    def state(self, s: arb, sig: arb, w: arb_mat) -> arb_mat:
        """x(sigma s) = V w + sigma Delta(s) on a flight from V w + sigma r."""
        d = self._delta(self.k["Ar"], self.k["AV"], arb(1), s, sig, w)
        return arb_mat(self.cyc.V) * w + d * sig

    def gaps(self, s: arb, sig: arb, w: arb_mat) -> list:
        """The other contacts' gaps f x(sigma s) = f V w + sigma f Delta(s)."""
        out = []
        for fn, fV, fAr, fAV in zip(self.fn, self.fV, self.fAr, self.fAV):
            d = self._delta(fAr, fAV, fn, s, sig, w)
            out.append((fV * w)[0, 0] + sig * d[0, 0])
        return out


def _hull(lo: arb, hi: arb) -> arb:
    return lo.union(hi)


@dataclass(frozen=True)
class BounceProof:
    """A proven accumulation of the cycle's impacts from event ``first_event`` on: for every state
    of the family box, one root s* in [s_lo, s_hi], sigma' <= kappa sigma, |w' - w| <= D sigma."""

    cycle: BounceCycle
    first_event: int
    s_lo: fmpq
    s_hi: fmpq
    kappa: fmpq
    Sigma: fmpq
    centre: tuple
    radius: tuple
    J: int

    def __repr__(self):
        return (f"BounceProof(contact {self.cycle.b}, e = {self.cycle.e}, from event {self.first_event}: "
                f"sigma' <= {float(self.kappa):.6g} sigma, flight in [{float(self.s_lo):.6g}, {float(self.s_hi):.6g}] sigma)")


def _start(cyc: BounceCycle, x: ExactVector, prec: int) -> tuple[arb_mat, arb] | None:
    """(w, sigma) of a state after an impact (balls at ``prec`` bits), or None when its gap is not
    proven 0 or its speed not certified positive."""
    if x.sign_of_form(cyc.c) != 0:
        return None
    try:
        if cyc.same is not None and any(s != 0 for s in x.signs_of_rows(cyc.same)):
            return None  # not on the subspace where the contacts' gaps agree (exactly)
    except UnresolvedSign:
        return None  # agreement not proven: no proof (the run goes on event by event)
    with workprec(prec):
        xb = x.arb(prec)
        w = arb_mat(cyc.L) * xb
        sig = (arb_mat(cyc.c * cyc.A) * xb)[0, 0]
    return (w, sig) if sig > 0 else None


def prove_bounces(cyc: BounceCycle, events: Sequence, prec: int = 128) -> BounceProof | None:
    """The induction of the module docstring from the state after the last event, or None when a
    check fails (the run is not yet close enough to its accumulation, or it is not one)."""
    start = _start(cyc, events[-1].state_after, prec)
    if start is None:
        return None
    w0, sig0 = start
    m = cyc.m
    with workprec(prec):
        a = (cyc.coefficients(1, prec)["cw"][0] * w0)[0, 0]  # the acceleration pressing on the contact
        if not a < 0:
            return None
        s_mid = -2 / a
        grow = [fmpq(0)] * m
        for _ in range(4):
            proof = _try_box(cyc, w0, sig0, s_mid, grow, len(events) - 1, prec)
            if isinstance(proof, BounceProof):
                return proof
            if proof is None:
                return None
            grow = proof  # the box was too small: the drift it needs
    return None


def _try_box(cyc, w0, sig0, s_mid, grow, k0, prec):
    """One attempt on the box w0 +/- (radius + grow), sigma in [0, Sigma]: a BounceProof, a list of
    the radii the drift needs (retry), or None."""
    m = cyc.m
    Sigma = dyadic_upper(sig0)
    centre = [dyadic_lower(w0[i, 0].mid()) for i in range(m)]
    rad = [dyadic_upper(abs(w0[i, 0] - arb(centre[i]))) + grow[i] for i in range(m)]
    sig_box = arb(0).union(arb(Sigma))
    w_box = arb_mat(m, 1, [arb(centre[i]).union(arb(centre[i]) + arb(rad[i])).union(arb(centre[i]) - arb(rad[i]))
                           for i in range(m)])
    u_up = float(cyc.nu) * float(Sigma) * float(s_mid.upper()) * 2
    if u_up > 4:
        return None  # flights too long for the blown-up series: later, nearer the accumulation
    J = _terms(u_up, prec + 16)
    ev = _Eval(cyc, J, prec)
    # the root's enclosure on the whole box: interval Newton from s_mid (1 +/- 1/8)
    X = (s_mid * arb("0.875")).union(s_mid * arb("1.125"))
    for _ in range(30):
        d = ev.dF(X, sig_box, w_box)
        if not d < 0:
            return None
        mid = arb(X.mid())
        N = mid - ev.F(mid, sig_box, w_box) / d
        lo, hi = max(N.lower(), X.lower(), key=lambda b: b.mid()), min(N.upper(), X.upper(), key=lambda b: b.mid())
        if not lo < hi:
            return None
        Y = _hull(lo, hi)
        if Y.rad() >= X.rad() * arb("0.99"):
            X = Y
            break
        X = Y
    width = X.rad() * 2
    s_lo = dyadic_lower(X.lower() - width / 64)
    s_hi = dyadic_upper(X.upper() + width / 64)
    if s_lo <= 0:
        return None
    S_lo, S_hi = arb(s_lo), arb(s_hi)
    if not ev.dF(arb(0).union(S_hi), sig_box, w_box) < 0:
        return None
    if not (ev.F(S_lo, sig_box, w_box) > 0 and ev.F(S_hi, sig_box, w_box) < 0):
        return None
    Srange = S_lo.union(S_hi)
    V = ev.V(Srange, sig_box, w_box)
    if not V < 0:
        return None
    kappa = arb(cyc.e) * (-V).upper()
    if not kappa < 1:
        return None
    if any(not g > 0 for g in ev.gaps(arb(0).union(S_hi), sig_box, w_box)):
        return None
    D = ev.drift(Srange, sig_box, w_box)
    need = [abs(w0[i, 0] - arb(centre[i])).upper() + abs(D[i, 0]).upper() * arb(Sigma) / (1 - kappa) for i in range(m)]
    if all(need[i] <= arb(rad[i]) for i in range(m)):
        return BounceProof(cyc, k0, s_lo, s_hi, dyadic_upper(kappa), Sigma, tuple(centre), tuple(rad), J)
    return [dyadic_upper(need[i] * 2) for i in range(m)]


class _Iteration:
    """The cycle map iterated on balls at one precision from the window's start: for each impact m
    after t_k, sigma_m, w_m (the state V w_m + sigma_m r after it), and the impact times."""

    def __init__(self, proof: BounceProof, t0: arb, z: arb_mat, prec: int):
        cyc = proof.cycle
        self.proof, self.prec = proof, prec
        with workprec(prec):
            self.ev = _Eval(cyc, max(proof.J, 8), prec)
            self.sig = [(arb_mat(cyc.c * cyc.A) * z)[0, 0]]
            self.w = [arb_mat(cyc.L) * z]
            self.t = [t0]  # t[m]: the time of impact m (t[0] = t_k, the run's last event)
            self.X = arb(proof.s_lo).union(arb(proof.s_hi))
            self.kappa, self.s_hi = arb(proof.kappa), arb(proof.s_hi)

    def _root(self, sig: arb, w: arb_mat) -> arb:
        """s* of the flight from (sigma, w): interval Newton inside [s_lo, s_hi] (proven to hold it)."""
        ev, X = self.ev, self.X
        for _ in range(200):
            mid = arb(X.mid())
            N = mid - ev.F(mid, sig, w) / ev.dF(X, sig, w)
            lo, hi = max(N.lower(), X.lower(), key=lambda b: b.mid()), min(N.upper(), X.upper(), key=lambda b: b.mid())
            if not lo <= hi:  # N(X) and X overlap only within rounding: keep X (it holds the root)
                return X
            Y = lo.union(hi)
            if not Y.rad() < X.rad() * arb("0.9"):
                return Y if Y.rad() < X.rad() else X
            X = Y
        return X

    def step(self) -> None:
        """One more flight and impact."""
        cyc, ev = self.proof.cycle, self.ev
        with workprec(self.prec):
            sig, w = self.sig[-1], self.w[-1]
            u = float(cyc.nu) * float(abs(sig).upper()) * float(self.proof.s_hi)
            ev.J = min(_terms(u, self.prec + 8), len(ev.k["cr"]) - 1) if u > 0 else 4
            s = self._root(sig, w)
            self.sig.append(-arb(cyc.e) * sig * ev.V(s, sig, w))
            self.w.append(w + ev.drift(s, sig, w) * sig)
            self.t.append(self.t[-1] + sig * s)

    def tail(self, m: int) -> arb:
        """sum of every flight after impact m: in [0, s_hi sigma_m / (1 - kappa)]."""
        with workprec(self.prec):
            return arb(0).union(self.s_hi * abs(self.sig[m]).upper() / (1 - self.kappa))

    def until_tail(self, bits: int) -> int:
        """Iterate until the tail after the last impact is below 2^-bits; its index."""
        with workprec(self.prec):
            eps = arb(2) ** -bits
            while not self.tail(len(self.sig) - 1).upper() < eps:
                if len(self.sig) > MAX_CYCLES:
                    raise LimitExceeded(f"the accumulation's impacts summed for {MAX_CYCLES} cycles without reaching "
                                        f"{bits} bits (sigma' <= {float(self.proof.kappa):.6g} sigma): ask fewer digits")
                self.step()
        return len(self.sig) - 1

    def until_time(self, t: arb) -> int | None:
        """The m with t in (t_m, t_m+1) (:func:`flight_holding`)."""
        return flight_holding(self, t)


def flight_holding(it, t: arb) -> int | None:
    """The m with t in (t_m, t_m+1) (the flight after impact m) of an iteration ``it`` of a window
    (its impact times ``t``, ``step()``, ``tail(m)``: None where no bound is known yet), iterating as
    needed; None when t's ball touches an impact time or lies beyond T* - or cannot be told from it.

    Parameters
    ----------
    it : _Iteration
        The ball iteration of a bounce or collapse window.
    t : arb
    """
    with workprec(it.prec):
        m = 0
        while True:
            while m + 1 >= len(it.t):
                tail = it.tail(len(it.t) - 1)
                if len(it.t) > MAX_CYCLES or (tail is not None and not tail.upper() > arb(2) ** -(it.prec - 8)):
                    return None
                it.step()
            if t > it.t[m] and t < it.t[m + 1]:
                return m
            if not t > it.t[m + 1]:
                return None
            m += 1


class BounceWindow(AccumulationWindow):
    """The motion on [t_k, T*) of a proven bounce accumulation (:class:`BounceProof`), as a
    phase-like object: impact times, states inside the window and the limit, as balls of any
    precision from the cycle map iterated on balls (see the module docstring)."""

    offsets = ()  # no reference cycle: the implied events come from the iteration, not from a law
    equilibrium = False

    def __init__(self, proof: BounceProof, t_k: Real, mode, z: ExactVector, origin: ExactVector | None = None):
        self.proof, self.t_k, self.mode, self.z, self.origin = proof, t_k, mode, z, origin
        self._runs: dict = {}
        self.time = BounceTime(self)  # T*
        self.limit_state = self.limit()  # x(T*-)

    def iteration(self, prec: int) -> _Iteration:
        """The ball iteration at >= prec bits (cached: the best one kept)."""
        best = max((p for p in self._runs if p >= prec), default=None)
        if best is None:
            wp = prec + 32
            with workprec(wp):
                it = _Iteration(self.proof, self.t_k.arb(wp), self.z.arb(wp), wp)
            self._runs = {wp: it}
            return it
        return self._runs[best]

    def time_ball(self, prec: int) -> arb:
        """T* to about ``prec`` bits: the impacts summed until their tail is below 2^-prec."""
        it = self.iteration(prec)
        M = it.until_tail(prec + 4)
        with workprec(it.prec):
            return it.t[M] + it.tail(M)

    def limit_ball(self, prec: int) -> arb_mat:
        """x(T*-) = V w*, w* within D sigma_M / (1 - kappa) of w_M."""
        it = self.iteration(prec)
        M = it.until_tail(prec + 4)
        cyc = self.proof.cycle
        with workprec(it.prec):  # the drift over the proof's box: it holds every later w
            box = arb_mat(cyc.m, 1, [arb(c).union(arb(c) - arb(r)).union(arb(c) + arb(r))
                                      for c, r in zip(self.proof.centre, self.proof.radius)])
            D = it.ev.drift(arb(self.proof.s_lo).union(arb(self.proof.s_hi)), arb(0).union(abs(it.sig[M]).upper()), box)
            spread = abs(it.sig[M]).upper() / (1 - it.kappa)
            w = arb_mat(cyc.m, 1, [it.w[M][i, 0] + arb(0, (abs(D[i, 0]).upper() * spread).upper()) for i in range(cyc.m)])
            return arb_mat(cyc.V) * w

    def event_time_ball(self, k: int, prec: int = 128) -> arb:
        """The k-th impact after t_k (k = 0, 1, ...), a certified ball."""
        it = self.iteration(prec)
        while len(it.t) <= k + 1:
            if len(it.t) > MAX_CYCLES:
                raise LimitExceeded(f"implied event {k} of the accumulation is beyond {MAX_CYCLES} cycles of its window")
            it.step()
        return it.t[k + 1]

    def event_time(self, k: int) -> Real:
        return BounceEventTime(self, k)

    def event_times(self, count: int) -> list:
        return [self.event_time(k) for k in range(count)]

    def ball_state(self, d: arb, prec: int) -> arb_mat | None:
        """x(t_k + d) for a ball d: the flight holding it found on balls, None when d touches an
        impact time (to its width) or cannot be told from T*."""
        it = self.iteration(prec)
        with workprec(it.prec):
            t = self.t_k.arb(it.prec) + d
            m = it.until_time(t)
            if m is None:
                return None
            sig = it.sig[m]
            return it.ev.state((t - it.t[m]) / sig, sig, it.w[m])

    def state(self, dt: Any) -> ExactVector:
        return BounceState(self, dt)

    def output(self, dt: Any, kind: str) -> ExactVector:
        """u on the flights (the resting contacts' forces u_J = F_J x, 0 elsewhere), y = C x + D u."""
        lcs = self.proof.cycle.lcs
        Fk = zeros(lcs.k, lcs.n)
        if self.mode is not None and self.mode.I:
            F = self.mode.feedback()
            for r, i in enumerate(self.mode.I):
                for j in range(lcs.n):
                    Fk[i, j] = F[r, j]
        return ProjectedVector(Fk if kind == "u" else lcs.C + lcs.D * Fk, self.state(dt))

    def limit(self) -> ExactVector:
        """x(T*-): exact where the forms that vanish in the limit (c x = 0, c A x = 0) and the forms
        that keep their value fix it - those of the whole run (q A = 0, q B = 0: a constant source,
        its value from the initial state) first, then those of the cycle (q A = 0, q r = 0, their
        value from the window's start); else :class:`BounceLimitState` (balls)."""
        cyc = self.proof.cycle
        lcs, n = cyc.lcs, cyc.lcs.n
        vanish = kernel(cyc.V.transpose()).transpose()  # x* = V w*: gaps and speeds of b and J are 0
        rows, sources = [submatrix(vanish, [i], None) for i in range(vanish.nrows())], []
        zero = self.zero_forms()
        for keep, z in ((hstack(lcs.A, lcs.B, nrows=n), self.origin), (hstack(cyc.A, cyc.r, nrows=n), self.z)):
            if z is None:
                continue
            Q = kernel(keep.transpose()).transpose()
            if z is self.origin and zero.nrows():
                Q = vstack(zero, Q) if Q.nrows() else zero
            for i in range(Q.nrows()):
                if rank(vstack(*rows, submatrix(Q, [i], None))) > len(rows):
                    rows.append(submatrix(Q, [i], None))
                    sources.append((len(rows) - 1, z))
        if len(rows) < n:
            return BounceLimitState(self, vstack(vanish, zero, ncols=n))
        Ginv = vstack(*rows).inv()
        parts = {}
        for i, z in sources:  # x* = G^-1 (0, 0, q z, ...): one projection per state it reads
            sel = parts.setdefault(id(z), (z, fmpq_mat(n, n)))[1]
            for j in range(n):
                sel[i, j] = rows[i][0, j]
        vecs = [(z, Ginv * sel) for z, sel in parts.values()]
        if all(z.known_rational() is not None for z, _ in vecs):
            return RationalVector(sum((P * z.known_rational() for z, P in vecs), zeros(n, 1)))
        if len(vecs) == 1:
            return ProjectedVector(vecs[0][1], vecs[0][0])
        return BounceLimitState(self, vstack(vanish, zero, ncols=n))

    def zero_forms(self) -> fmpq_mat:
        """Forms that vanish on every state of the run (so in the window and at its limit): the
        largest N with N x0 = 0, N B = 0 and N A inside N, for a rational initial state x0 (a
        wheel that never turns: its angle and rate stay exactly 0)."""
        lcs = self.proof.cycle.lcs
        x0 = None if self.origin is None else self.origin.known_rational()
        if x0 is None:
            return zeros(0, lcs.n)
        N = kernel(hstack(lcs.B, x0, nrows=lcs.n).transpose()).transpose()
        while N.nrows():
            K = kernel(N)  # rowspan(N) = {v : v K = 0}
            if K.ncols() == 0:
                break
            a = kernel((N * lcs.A * K).transpose()).transpose()
            if a.nrows() == N.nrows():
                break
            N = a * N if a.nrows() else zeros(0, lcs.n)
        return N


class BounceEventTime(Real):
    """The k-th impact of a bounce accumulation's window (k = 0 is the first after t_k)."""

    def __init__(self, window: BounceWindow, k: int):
        super().__init__(window.t_k.policy)
        self.window, self.k = window, k

    def _deps(self):
        return (self.window.t_k, self.window.z)

    def _compute(self, prec: int):
        return self.window.event_time_ball(self.k, prec)


class BounceTime(Real):
    """T*, the accumulation time of a bounce window."""

    def __init__(self, window: BounceWindow):
        super().__init__(window.t_k.policy)
        self.window = window

    def _deps(self):
        return (self.window.t_k, self.window.z)

    def _compute(self, prec: int):
        return self.window.time_ball(prec)


class BounceState(ExactVector):
    """x(t_k + dt) inside a bounce window (balls from the iteration)."""

    def __init__(self, window: BounceWindow, dt: Any):
        super().__init__(window.proof.cycle.lcs.n, window.zero_forms(), policy=window.t_k.policy)
        self.window, self.dt = window, as_real(dt, window.t_k.policy)

    def _deps(self):
        return (self.window.t_k, self.window.z, self.dt)

    def _compute(self, prec: int):
        for p in (prec, 2 * prec, 4 * prec):
            with workprec(p):
                x = self.window.ball_state(self.dt.arb(p), p)
            if x is not None:
                return x
        raise UnresolvedSign(f"x(t) inside the accumulation window at t = t_k + {self.dt.label()}: t cannot be "
                             "told apart from an impact time (or from T*) at 4x the precision asked")


class BounceLimitState(ExactVector):
    """x(T*-) of a bounce window where no exact invariant fixes it: balls of any precision, with
    the gap and its speed proven 0 (``zero_forms``)."""

    def __init__(self, window: BounceWindow, zero_forms: fmpq_mat):
        super().__init__(window.proof.cycle.lcs.n, zero_forms, policy=window.t_k.policy)
        self.window = window

    def _deps(self):
        return (self.window.t_k, self.window.z)

    def _compute(self, prec: int):
        return self.window.limit_ball(prec)


def bounce_window(lcs, events: Sequence, t_k: Real, mode, prec: int = 128,
                  origin: ExactVector | None = None) -> BounceWindow | None:
    """The window [t_k, T*) of a proven accumulation of Newton impacts from the run's last event
    (:func:`bounce_cycle`, :func:`prove_bounces`), or None when none is proven; ``origin`` is the
    run's initial state (the constant sources' values, for an exact limit)."""
    cyc = bounce_cycle(lcs, events)
    if cyc is None:
        return None
    proof = prove_bounces(cyc, events, max(prec, 128))
    return None if proof is None else BounceWindow(proof, t_k, mode, events[-1].state_after, origin)

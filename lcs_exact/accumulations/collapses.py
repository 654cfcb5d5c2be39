"""Inelastic collapse: Newton impacts at several contacts taking turns, accumulating (Remark 4.11).

Two balls dropped on a floor (Siconos' TwoBouncingBalls) end in impacts ball-floor, ball-ball,
ball-floor, ... ever closer in time, converging to rest.  No single contact bounces
(:mod:`lcs_exact.accumulations.bounces`) and the cycles are not similar to one another (no geometric law,
:mod:`lcs_exact.accumulations.accumulation`): their shape converges to one.  Such an accumulation is
proven here, with certified balls only, when the flights have constant gap accelerations (gravity,
with or without contacts resting under the bouncing ones).

* The cycle.  Contacts P take turns in a pattern b_1, ..., b_p that the last events repeat; each
  event is a Newton impact of one contact b (restitution 0 < e_b < 1) that also pushes the contacts
  J resting between impacts (the jump -(1 + e_b) (c_b A x) r_b, r_b = B_C W_CC^-1 e_b, C = J + {b},
  W_CC^-1 e_b > 0, as in :mod:`~lcs_exact.accumulations.bounces`); the flights are in mode J, A its
  closed loop, V_J its consistent subspace.
* The family.  G stacks the gaps c_i and speeds c_i A of P.  When S = A V_J + span{r_b} has
  dimension 2|P| and G is invertible on it, every state of the run is x = x_bg + E xi with
  xi = G x, E the basis of S with G E = I, and x_bg = (I - E G) x the same on every flight
  (A V_J in S) and across every impact (r_b in S).  When moreover c_i A^2 E = 0 the gaps'
  accelerations are constants a_i = c_i A^2 x_bg: a flight is g_i(t) = g_i + v_i t + a_i t^2 / 2,
  an impact of b sets v_i -= (1 + e_b) W_ib v_b (W_ib = c_i A r_b, W_bb = 1).
* Scaling.  After an impact of b at speed sigma, the shape p = (g_i / sigma^2, v_i / sigma) fixes
  the rest: the next impact after sigma s*(p) (the first positive root of a quadratic), at the next
  speed rho(p) sigma, with the next shape f(p) - all free of sigma.  The period's shape map is F.
* The proof.  F is iterated on balls from the state after the last event (each step certifies its
  impact: the root simple, every other gap, resting force and far gap positive) until it is near
  a fixed point p^ (Newton's method).  In coordinates z = T^-1 (p - p^), in which DF(p^) is nearly
  normal (its real eigenbasis), the disc B = {|z|_2 <= r} is invariant: |T^-1 (F(p^) - p^)|_2 +
  L r <= r, L >= |T^-1 DF T|_2 on B (forward differentiation on balls over sub-boxes of B; the
  mean value theorem).  On B every step's checks hold (sigma at most its value on entry) and the
  period's speed ratio is at most kappa < 1.  So the pattern goes on forever, sigma shrinking by
  kappa a period, and the impacts accumulate at T* <= t_N + sigma_N D / (1 - kappa) (D bounds a
  period's duration over sigma).
* Digits.  T*, the impact times and the states inside the window are balls of any precision: the
  steps iterated on balls until the tail is below the precision asked.  The limit state is
  x_bg = (I - E G) x_k, exact.

Every decision is a certified sign of a ball; a check that fails makes the proof fail, never guess.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import mpmath
from flint import arb, arb_mat, fmpq, fmpq_mat

from ..algebra import RowSpan, hstack, identity, is_zero, kernel, norm_inf
from ..errors import LimitExceeded, UnresolvedSign
from ..numbers import (Dual, ExactVector, ProjectedVector, RationalVector, Real, dyadic_upper, expm_action, norm2_bound,
                       spectrum_of, vector_norm2_bound, workprec)
from .bounces import MAX_CYCLES, BounceWindow, flight_holding
from .collapsecycles import CollapseCycle, collapse_cycle, row

__all__ = ["CollapseProof", "CollapseWindow", "prove_collapse", "collapse_window"]

#: periods a proof may track the shape map before it gives up (work, not time: the same on every machine;
#: about 2 s; TwoBouncingBalls needs 1024 from its 713th impact)
MAX_PERIODS = 4096


def _val(x) -> arb:  # the value of a ball or of a Dual
    return x.v if isinstance(x, Dual) else x


class _Fail(Exception):
    """A step's check failed: ``undecided`` when a ball held 0 (more precision may decide it),
    else it is false (the pattern does not go on)."""

    def __init__(self, undecided: bool):
        self.undecided = undecided


def _positive(x) -> None:
    v = _val(x)
    if not v > 0:
        raise _Fail(not v <= 0)


@dataclass
class _Shape:
    """Gaps over sigma^2 and speeds over sigma of the contacts P after an impact of P[last]."""

    Y: list
    V: list
    last: int


class _Steps:
    """The scaled flights and impacts of a cycle at one precision: a (the accelerations, balls, with
    their exact signs), the background's monitored values, and one step of the map."""

    def __init__(self, cyc: CollapseCycle, x: ExactVector, prec: int, theta: fmpq | None = None):
        self.cyc, self.prec = cyc, prec
        signs = [x.sign_of_form(row(cyc.acc, i)) for i in range(len(cyc.P))]
        xb = x.arb(prec)
        with workprec(prec):
            a = arb_mat(cyc.acc) * xb
            self.a = [a[i, 0] if s else arb(0) for i, s in enumerate(signs)]
            self.sign = signs
            self.W = [[arb(cyc.W[i, j]) for j in range(len(cyc.P))] for i in range(len(cyc.P))]
            self.e = [arb(e) for e in cyc.e]
            bg = arb_mat(cyc.background) * xb
            # lower bounds of the monitored rows on the background (over the window when it moves;
            # the ball iteration of a proven window checks none: no theta)
            self.mon = [(arb_mat(m) * bg)[0, 0] if not cyc.moving else None if theta is None else
                        _lowest(m, cyc.Abg, bg, theta) for m in cyc.monitors]
            self.monE = [[abs(arb((m * cyc.E)[0, j])) for j in range(cyc.E.ncols())] for m in cyc.monitors]

    def step(self, sh: _Shape, b: int, sigma: arb | None):
        """The flight from shape ``sh`` to the impact of P[b] and the impact: (s*, rho, next shape);
        ``sigma`` bounds the scale for the monitored rows (None: no monitored row)."""
        Y, V, a, last = sh.Y, sh.V, self.a, sh.last
        if b == last:
            _positive(V[b])
            _positive(-a[b])
            s = -2 * V[b] / a[b]
            vb = -V[b]
        else:
            _positive(Y[b])
            if self.sign[b]:
                disc = V[b] * V[b] - 2 * a[b] * Y[b]
                _positive(disc)
                root = disc.sqrt()
            else:  # a_b = 0: the gap closes at a constant speed
                _positive(-V[b])
                root = -V[b]
            _positive(root - V[b])
            s = 2 * Y[b] / (root - V[b])
            vb = -root
        n = len(Y)
        for j in range(n):
            if j != b:
                self._stays_open(Y[j], V[j], a[j], self.sign[j], s, j == last)
        if sigma is not None:
            self._monitors(Y, V, s, sigma)
        e = self.e[b]
        Vp = [V[j] + a[j] * s - (1 + e) * self.W[j][b] * vb for j in range(n)]
        rho = -e * vb
        rho2 = rho * rho
        Yn = [arb(0) if j == b else (Y[j] + V[j] * s + a[j] * s * s / 2) / rho2 for j in range(n)]
        Vn = [Vp[j] / rho for j in range(n)]
        return s, rho, _Shape(Yn, Vn, b)

    @staticmethod
    def _stays_open(Y, V, a, sign: int, s, closed: bool) -> None:
        """g(s') = Y + V s' + a s'^2 / 2 > 0 on (0, s] (``closed``: Y = 0 structurally, the
        contact just hit: g / s' = V + a s' / 2 > 0 there)."""
        if closed:
            _positive(V)
            _positive(V + a * s / 2)
            return
        _positive(Y)
        _positive(Y + V * s + a * s * s / 2)
        if sign > 0 and not _val(V) >= 0:  # convex: the minimum may be inside
            _positive(Y - V * V / (2 * a))

    def _monitors(self, Y, V, s, sigma: arb) -> None:
        """Every monitored row m x_bg + m E xi(t) stays positive over the flight: |xi| bounded by
        sigma^2 (|Y| + |V| s + |a| s^2 / 2) for the gaps and sigma (|V| + |a| s) for the speeds."""
        if not self.mon:
            return
        S = abs(_val(s))
        gaps = [abs(_val(y)) + abs(_val(v)) * S + abs(a) * S * S / 2 for y, v, a in zip(Y, V, self.a)]
        speeds = [abs(_val(v)) + abs(a) * S for v, a in zip(V, self.a)]
        n = len(Y)
        for m, weights in zip(self.mon, self.monE):
            if m is None:
                continue  # a moving background on a first pass (prove_collapse): the window's length not yet known
            bound = sum((weights[j] * gaps[j] * sigma * sigma + weights[n + j] * speeds[j] * sigma for j in range(n)), arb(0))
            _positive(m - bound)


def _lowest(m: fmpq_mat, Abg: fmpq_mat, bg: arb_mat, theta: fmpq) -> arb:
    """A lower bound of m e^{Abg s} x_bg over 0 <= s <= theta: the Taylor terms m Abg^j x_bg s^j / j!
    bounded one by one (exact when m Abg^j = 0 from some j < 8 on: a body falling freely), then
    the tail |m Abg^8|_1 theta^8 / 8! e^{|Abg| theta} |x_bg| (infinity norms)."""
    th, out, row, term = arb(theta), (arb_mat(m) * bg)[0, 0], m, arb(1)
    for j in range(1, 9):
        row = row * Abg
        if is_zero(row):
            return out
        term = term * th / j
        if j < 8:
            out -= abs((arb_mat(row) * bg)[0, 0]) * term
    xn = max((abs(bg[i, 0]).upper() for i in range(bg.nrows())), key=lambda b: b.mid())
    return out - arb(norm_inf(row)) * term * (arb(norm_inf(Abg)) * th).exp() * xn


def _period(steps: _Steps, sh: _Shape, pattern: tuple, sigma: arb | None):
    """One period of impacts from ``sh``: (shape after, speed ratio rho_1 ... rho_p, duration over
    the starting sigma, [(s*, rho, shape after) for each impact])."""
    scale, dur, out = arb(1), arb(0), []
    for b in pattern:
        s, rho, sh = steps.step(sh, b, None if sigma is None else sigma * _val(scale))
        out.append((s, rho, sh))
        dur = dur + scale * s
        scale = scale * rho
    return sh, scale, dur, out


def _pack(sh: _Shape) -> list:
    """The free coordinates of a shape: (Y_j, V_j) for j != last (Y_last = 0, V_last = 1)."""
    others = [j for j in range(len(sh.Y)) if j != sh.last]
    return [sh.Y[j] for j in others] + [sh.V[j] for j in others]


def _unpack(p: list, last: int, n: int) -> _Shape:
    others = [j for j in range(n) if j != last]
    Y, V = [arb(0)] * n, [arb(1)] * n
    for i, j in enumerate(others):
        Y[j], V[j] = p[i], p[len(others) + i]
    return _Shape(Y, V, last)


def _normal_basis(J: arb_mat) -> fmpq_mat | None:
    """T (rational) whose columns are the real eigenbasis of DF's midpoint (Re u, Im u for a complex
    pair), so that T^-1 DF T is nearly normal; a choice only, every bound is computed with it."""
    d = J.nrows()
    M = mpmath.matrix([[float(J[i, j].mid()) for j in range(d)] for i in range(d)])
    try:
        lam, U = mpmath.eig(M)
    except (ZeroDivisionError, ValueError):
        return None
    cols, done = [], set()
    for i in sorted(range(d), key=lambda i: (-abs(lam[i]), -mpmath.im(lam[i]))):
        if i in done:
            continue
        done.add(i)
        u = [U[r, i] for r in range(d)]
        if abs(mpmath.im(lam[i])) > 1e-12 * max(1, abs(lam[i])):
            j = min((j for j in range(d) if j not in done), key=lambda j: abs(lam[j] - mpmath.conj(lam[i])), default=None)
            if j is None:
                return None
            done.add(j)
            cols += [[mpmath.re(x) for x in u], [mpmath.im(x) for x in u]]
        else:
            cols.append([mpmath.re(x) for x in u])
    T = fmpq_mat(d, d, [fmpq(round(float(cols[j][i]) * 2 ** 40), 2 ** 40) for i in range(d) for j in range(d)])
    return T if T.det() != 0 else None


@dataclass(frozen=True)
class CollapseProof:
    """A proven collapse from event ``first_event``: after ``transient`` periods tracked on balls the
    shape lies in the invariant disc |T^-1 (p - p^)|_2 <= radius, where the period's speed ratio
    is at most ``kappa`` and its duration at most ``D`` sigma."""

    cycle: CollapseCycle
    first_event: int
    transient: int
    kappa: fmpq
    D: fmpq
    lipschitz: fmpq
    radius: fmpq
    T: fmpq_mat
    length: fmpq  # T* - t_k is at most this

    def __repr__(self):
        pat = " ".join(f"y_{self.cycle.P[b]}" for b in self.cycle.pattern)
        return (f"CollapseProof(contacts {list(self.cycle.P)} taking turns ({pat}) from event {self.first_event}: "
                f"after {self.transient} periods, sigma' <= {float(self.kappa):.6g} sigma a period, "
                f"shape map Lipschitz {float(self.lipschitz):.4g} on a disc of radius {float(self.radius):.3g})")


def _start(cyc: CollapseCycle, x: ExactVector, prec: int) -> tuple[_Shape, arb]:
    """The shape and sigma after the last event (an impact of P[pattern[-1]])."""
    b, n = cyc.pattern[-1], len(cyc.P)
    with workprec(prec):
        xi = arb_mat(cyc.G) * x.arb(prec)
        sigma = xi[n + b, 0]
        _positive(sigma)
        sh = _Shape([arb(0) if j == b else xi[j, 0] / (sigma * sigma) for j in range(n)],
                    [arb(1) if j == b else xi[n + j, 0] / sigma for j in range(n)], b)
    return sh, sigma


class _Tracker:
    """The shape after each period as a centre c and a radius e in T-coordinates, p in c + T {|z|_2
    <= e} (a mean-value form: balls iterated directly widen ~4 bits a period by cancellation, here
    e contracts with the map), and the scale sigma."""

    def __init__(self, steps: _Steps, cyc: CollapseCycle, T: fmpq_mat, sh: _Shape, sigma: arb, monitored: bool = True):
        self.steps, self.cyc, self.last, self.sigma, self.monitored = steps, cyc, sh.last, sigma, monitored
        self.Ta, self.Ti = arb_mat(T), arb_mat(T.inv())
        p = _pack(sh)
        self.c = [arb(v.mid()) for v in p]
        self.e = self.dist(p, self.c)

    def dist(self, p: list, c: list) -> arb:
        """An upper bound of |T^-1 (p - c)|_2 over the balls p."""
        z = self.Ti * arb_mat(len(c), 1, [a - b for a, b in zip(p, c)])
        return vector_norm2_bound([z[i, 0] for i in range(len(c))])

    def period(self) -> list:
        """One period: every impact's (s*, rho, shape after) as balls holding the true values, and
        the next centre, radius and sigma."""
        n, d, Ta = len(self.cyc.P), len(self.c), self.Ta
        zb = (-self.e).union(self.e)
        box = [Dual(self.c[i] + sum((Ta[i, j] * zb for j in range(d)), arb(0)), [Ta[i, j] for j in range(d)])
               for i in range(d)]
        out, ratio, _, recs = _period(self.steps, _unpack(box, self.last, n), self.cyc.pattern,
                                      self.sigma if self.monitored else None)
        q = _pack(out)
        L = norm2_bound(self.Ti * arb_mat(d, d, [q[i].d[j] for i in range(d) for j in range(d)]))
        centre = _pack(_period(self.steps, _unpack(self.c, self.last, n), self.cyc.pattern, None)[0])
        c = [arb(v.mid()) for v in centre]
        self.e = arb((self.dist(centre, c) + L * self.e).upper())
        self.c, self.sigma = c, self.sigma * _val(ratio)
        return [(_val(s), _val(rho), _Shape([_val(y) for y in sh.Y], [_val(v) for v in sh.V], sh.last))
                for s, rho, sh in recs]


def prove_collapse(cyc: CollapseCycle, events: Sequence, prec: int = 128) -> CollapseProof | None:
    """The proof of the module docstring from the state after the last event, or None when a check
    fails (the pattern breaks, or no invariant disc is found within MAX_PERIODS periods).

    Parameters
    ----------
    cyc : CollapseCycle
        The pattern's exact data (:func:`collapse_cycle`).
    events : sequence of Event
        The run's events; the proof starts after the last.
    prec : int
        Bits of the balls (raised when a ball is too wide to decide a check).
    """
    x = events[-1].state_after
    if x.sign_of_form(row(cyc.lcs.C, cyc.P[cyc.pattern[-1]])) != 0:
        return None
    first = _attempts(cyc, x, len(events) - 1, prec, None)
    if first is None or not cyc.moving:
        return first
    # a moving background: its monitored rows bounded over twice the window the first pass found
    return _attempts(cyc, x, len(events) - 1, prec, 2 * first.length)


def _attempts(cyc: CollapseCycle, x: ExactVector, k0: int, prec: int, theta: fmpq | None) -> CollapseProof | None:
    """:func:`_attempt` at rising precisions while a ball is too wide to decide a check."""
    for wp in (prec + 64, 2 * prec + 256, 4 * prec + 1024):
        try:
            return _attempt(cyc, x, k0, wp, theta)
        except _Fail as f:
            if not f.undecided:
                return None
    return None


def _attempt(cyc: CollapseCycle, x: ExactVector, k0: int, wp: int, theta: fmpq | None) -> CollapseProof | None:
    """Track the shape from x period by period, and at periods 0, 1, 2, 4, ... try an invariant disc;
    with a moving background (``theta`` given) the window's length must come out below ``theta``."""
    steps = _Steps(cyc, x, wp, theta)
    sh, sigma = _start(cyc, x, wp)
    with workprec(wp):
        fp = _fixed_point(steps, cyc, _pack(sh), sh.last)
        T = None if fp is None else _normal_basis(fp[1])
        if T is None:
            return None
        tracker = _Tracker(steps, cyc, T, sh, sigma)
        check, elapsed = 0, arb(0)
        for periods in range(MAX_PERIODS + 1):
            if periods == check:
                check = max(1, 2 * check)
                found = _invariant_disc(steps, cyc, fp[0], fp[1], T, tracker)
                if found is not None:
                    length = elapsed + tracker.sigma * arb(found[1]) / (1 - arb(found[0]))
                    if theta is not None and not length < arb(theta):
                        return None  # the window is longer than the monitored rows were bounded over
                    return CollapseProof(cyc, k0, periods, *found, T, dyadic_upper(length))
            sig = tracker.sigma
            for s, rho, _ in tracker.period():
                elapsed, sig = elapsed + sig * s, sig * rho
    return None


def _fixed_point(steps: _Steps, cyc: CollapseCycle, p: list, last: int) -> tuple[list, arb_mat] | None:
    """Newton's method for F(p) = p from the midpoints of p: (p^, DF(p^))."""
    d, n = len(p), len(cyc.P)
    ph, done = [arb(v.mid()) for v in p], False
    for it in range(13):
        duals = [Dual(v, [arb(int(i == j)) for j in range(d)]) for i, v in enumerate(ph)]
        q = _pack(_period(steps, _unpack(duals, last, n), cyc.pattern, None)[0])
        J = arb_mat(d, d, [q[i].d[j] for i in range(d) for j in range(d)])
        if done or it == 12:
            return ph, J
        try:
            delta = (J - arb_mat(identity(d))).solve(arb_mat(d, 1, [q[i].v - ph[i] for i in range(d)]))
        except (ZeroDivisionError, ValueError):
            return None
        ph = [arb((ph[i] - delta[i, 0]).mid()) for i in range(d)]
        done = all(abs(delta[i, 0]).upper() < arb(2) ** (-steps.prec // 2) * (1 + abs(ph[i]).upper()) for i in range(d))
    return None


def _invariant_disc(steps: _Steps, cyc: CollapseCycle, ph: list, J: arb_mat, T: fmpq_mat,
                    tracker: _Tracker) -> tuple | None:
    """(kappa, D, L, r) of an invariant disc around the fixed point p^ that holds the tracked shapes
    (the module docstring), or None."""
    n, Ta, Ti = len(cyc.P), tracker.Ta, tracker.Ti
    try:
        out = _pack(_period(steps, _unpack(ph, tracker.last, n), cyc.pattern, None)[0])
        delta = tracker.dist(out, ph)
        L0 = norm2_bound(Ti * J * Ta)
        if not L0 < 1:
            return None
        d0 = tracker.dist(tracker.c, ph) + tracker.e
        r = dyadic_upper(max((2 * d0).upper(), (4 * delta / (1 - L0)).upper(), arb(2) ** -(steps.prec // 2),
                             key=lambda b: b.mid()))
        L, kappa, D = _over_disc(steps, cyc, ph, Ta, Ti, r, tracker.last, tracker.sigma)
    except _Fail:
        return None
    if L < 1 and kappa < 1 and (delta + L * arb(r)) <= arb(r):
        return dyadic_upper(kappa), dyadic_upper(D), dyadic_upper(L), r
    return None


def _over_disc(steps: _Steps, cyc: CollapseCycle, ph: list, Ta: arb_mat, Ti: arb_mat, r: fmpq, last: int,
               sigma: arb) -> tuple[arb, arb, arb]:
    """Upper bounds over the box |z_j| <= r (sub-boxes of it) of |T^-1 DF T|_2, the period's speed
    ratio and its duration over sigma; every step's checks hold there (else _Fail)."""
    d, n = len(ph), len(cyc.P)
    k = 4 if d <= 2 else 2 if d <= 4 else 1
    w = 2 * r / k
    sig = arb(0).union(arb(sigma.upper()))
    L = kappa = D = arb(0)
    for cell in range(k ** d):
        zb = []
        for _ in range(d):
            i, cell = cell % k, cell // k
            zb.append(arb(-r + i * w).union(arb(-r + (i + 1) * w)))
        duals = [Dual(ph[i] + sum((Ta[i, j] * zb[j] for j in range(d)), arb(0)), [Ta[i, j] for j in range(d)])
                 for i in range(d)]
        out, ratio, dur, _ = _period(steps, _unpack(duals, last, n), cyc.pattern, sig)
        q = _pack(out)
        DT = arb_mat(d, d, [q[i].d[j] for i in range(d) for j in range(d)])
        L = max(L, norm2_bound(Ti * DT).upper(), key=lambda b: b.mid())
        kappa = max(kappa, _val(ratio).upper(), key=lambda b: b.mid())
        D = max(D, _val(dur).upper(), key=lambda b: b.mid())
    return L, kappa, D


class _Iteration:
    """The impacts iterated on balls at one precision from the window's start: for impact m after
    t_k, its time t[m + 1], sigma[m + 1] and the shape after it (index 0: the last event)."""

    def __init__(self, proof: CollapseProof, t0: arb, x: ExactVector, prec: int):
        cyc = proof.cycle
        self.proof, self.prec = proof, prec
        self.steps = _Steps(cyc, x, prec)
        sh, sigma = _start(cyc, x, prec)
        self.shapes, self.sig, self.t = [sh], [sigma], [t0]
        self.moving = spectrum_of(cyc.Abg) if cyc.moving else None  # x_bg(t) = e^{Abg (t - t_k)} x_bg
        with workprec(prec):
            self.tracker = _Tracker(self.steps, cyc, proof.T, sh, sigma, monitored=False)  # proven: no re-check
            self.bg = arb_mat(cyc.background) * x.arb(prec)
            self.kappa, self.D = arb(proof.kappa), arb(proof.D)

    def step(self) -> None:
        """One more period of impacts."""
        with workprec(self.prec):
            try:
                recs = self.tracker.period()
            except _Fail as f:  # proven to hold: only a ball too wide at this precision
                raise UnresolvedSign(f"an impact of the collapse ({self.proof!r}) cannot be decided at "
                                     f"{self.prec} bits: ask fewer digits") from f
            for s, rho, sh in recs:
                self.t.append(self.t[-1] + self.sig[-1] * s)
                self.sig.append(self.sig[-1] * rho)
                self.shapes.append(sh)

    def tail(self, m: int) -> arb | None:
        """The time after impact m until T*, when m ends a period after the transient: in
        [0, sigma_m D / (1 - kappa)]; else None."""
        p = len(self.proof.cycle.pattern)
        if m % p or m // p < self.proof.transient:
            return None
        with workprec(self.prec):
            return arb(0).union(self.D * abs(self.sig[m]).upper() / (1 - self.kappa))

    def until_tail(self, bits: int) -> int:
        """Iterate until the tail after the last impact is below 2^-bits; that impact's index."""
        with workprec(self.prec):
            eps = arb(2) ** -bits
            while True:
                m = len(self.t) - 1
                tail = self.tail(m)
                if tail is not None and tail.upper() < eps:
                    return m
                if m > MAX_CYCLES:
                    raise LimitExceeded(f"the collapse's impacts iterated for {m} impacts without reaching "
                                        f"{bits} bits: ask fewer digits")
                self.step()

    def until_time(self, t: arb) -> int | None:
        """The m with t in (t_m, t_m+1) (:func:`~lcs_exact.accumulations.bounces.flight_holding`)."""
        return flight_holding(self, t)

    def state(self, m: int, t: arb) -> arb_mat:
        """x at time t in the flight after impact m: x_bg + E xi, xi the gaps sigma^2 g(s) and speeds
        sigma g'(s), s = (t - t_m) / sigma_m."""
        cyc, sh, sig = self.proof.cycle, self.shapes[m], self.sig[m]
        a, n = self.steps.a, len(cyc.P)
        with workprec(self.prec):
            s = (t - self.t[m]) / sig
            xi = [sig * sig * (sh.Y[j] + sh.V[j] * s + a[j] * s * s / 2) for j in range(n)]
            xi += [sig * (sh.V[j] + a[j] * s) for j in range(n)]
            bg = self.bg if self.moving is None else self.moving.apply(t - self.t[0], self.bg, self.prec)
            return bg + arb_mat(cyc.E) * arb_mat(2 * n, 1, xi)


class CollapseWindow(BounceWindow):
    """The motion on [t_k, T*) of a proven collapse (:class:`CollapseProof`): impact times, states
    inside the window as balls of any precision (the impacts iterated on balls), and the exact
    limit x_bg = (I - E G) x_k."""

    def iteration(self, prec: int) -> _Iteration:
        """The ball iteration at >= prec bits (cached: the best one kept)."""
        best = max((p for p in self._runs if p >= prec), default=None)
        if best is None:
            wp = prec + 64
            with workprec(wp):
                it = _Iteration(self.proof, self.t_k.arb(wp), self.z, wp)
            self._runs = {wp: it}
            return it
        return self._runs[best]

    def ball_state(self, d: arb, prec: int) -> arb_mat | None:
        """x(t_k + d) for a ball d, or None when d touches an impact time or cannot be told from T*."""
        it = self.iteration(prec)
        with workprec(it.prec):
            t = self.t_k.arb(it.prec) + d
            m = it.until_time(t)
            return None if m is None else it.state(m, t)

    def limit(self) -> ExactVector:
        """x(T*-) = x_bg = (I - E G) x_k: the gaps and speeds of the contacts taking turns are 0, the
        rest is what every flight and impact kept; read from the initial state when the rows of
        I - E G are forms the whole run keeps (q A = 0, q B = 0: gravity's constant source), so a
        rational start gives an exact rational limit."""
        bg, lcs = self.proof.cycle.background, self.proof.cycle.lcs
        if self.proof.cycle.moving:  # x_bg moved on alone: e^{Abg (T* - t_k)} x_bg(t_k)
            return expm_action(spectrum_of(self.proof.cycle.Abg), self.time - self.t_k, ProjectedVector(bg, self.z))
        if self.origin is not None:
            keep = kernel(hstack(lcs.A, lcs.B, nrows=lcs.n).transpose()).transpose()
            span = RowSpan(keep) if keep.nrows() else None
            if span is not None and all(row(bg, i) in span for i in range(lcs.n)):
                q = self.origin.known_rational()
                return RationalVector(bg * q) if q is not None else ProjectedVector(bg, self.origin)
        return ProjectedVector(bg, self.z)


def collapse_window(lcs, events: Sequence, t_k: Real, mode, prec: int = 128,
                    origin: ExactVector | None = None) -> CollapseWindow | None:
    """The window [t_k, T*) of a proven collapse from the run's last event (:func:`collapse_cycle`,
    :func:`prove_collapse`), or None when none is proven.

    Parameters
    ----------
    lcs : LCS
        The system, with Newton's restitution.
    events : sequence of Event
        The run's events so far; the last ones repeat the pattern.
    t_k : Real
        The time of the last event.
    mode : Mode
        The mode of the flights (the resting contacts J).
    prec : int
        Bits of the proof's balls (at least 128).
    origin : ExactVector, optional
        The run's initial state (forms that vanish on the whole run).
    """
    cyc = collapse_cycle(lcs, events)
    if cyc is None:
        return None
    proof = prove_collapse(cyc, events, max(prec, 128))
    return None if proof is None else CollapseWindow(proof, t_k, mode, events[-1].state_after, origin)

"""Taylor models in a small parameter over a box of parameters: the arithmetic that proves an impact cascade
(:mod:`lcs_exact.cascade`) for a whole family of states at once.

A model of f on the box is ``p + eps^(n+1) sigma^k r``: p an exact polynomial (``fmpq_mpoly``) of eps-degree
<= n in eps (the small parameter, variable 0), sigma (the speed over a background, variable 1, when there is
one) and the drift parameters delta_i; r a certified ``arb`` ball that bounds the rest on the whole box eps in
[0, S], sigma in [0, Sigma], delta_i in [-Delta, Delta].  Sums, products, shifts by powers of eps and sigma,
truncation and certified signs (from a leading coefficient whose range over the box excludes 0 and dominates
the rest) are exact on p and certified on r; a power series root of a polynomial equation in tau is exact
(fixed-point iteration, one order of eps a step).  Any check that cannot be certified raises :class:`NoProof`.
"""
from __future__ import annotations

from flint import arb, fmpq, fmpq_mat, fmpq_mpoly_ctx

class NoProof(Exception):
    """The cascade certificate does not apply or a check could not be certified (``order``: a higher order
    of the models might decide it).

    Parameters
    ----------
    reason : str
    order : bool, optional"""

    def __init__(self, reason: str, order: bool = False):
        super().__init__(reason)
        self.order = order  # True when a higher order of the models might decide it


class WorkBudget:
    """The work a proof may do, in coefficient products of its Taylor models, and the run's deadline: calling
    it checks the deadline, :meth:`charge` counts work and raises :class:`NoProof` when ``units`` (None: no
    limit) are spent.  Work, not seconds: a proof ends at the same point on any machine under any load.

    Parameters
    ----------
    units : int or None
    deadline : callable, optional
        It raises when the run's ``time_limit`` is up (which only cuts a run short)."""

    def __init__(self, units: int | None, deadline=None):
        self.units, self.deadline, self.spent = units, deadline, 0

    def __call__(self) -> None:
        if self.deadline is not None:
            self.deadline()

    @property
    def exhausted(self) -> bool:
        return self.units is not None and self.spent > self.units

    def charge(self, units: int) -> None:
        """Count ``units`` coefficient products; :class:`NoProof` once the budget is spent.

        Parameters
        ----------
        units : int"""
        self.spent += units
        if self.exhausted:
            raise NoProof(f"the proof's work budget ({self.units} coefficient products) is spent")


def ipow(x: arb, k: int) -> arb:
    """x^k for an integer k >= 0 by multiplication (python-flint 0.9's ``arb ** k`` is nan for a
    ball centred at 0); :class:`NoProof` for k < 0.

    Parameters
    ----------
    x : arb
    k : int"""
    if k < 0:
        raise NoProof("internal: a negative power")
    out, base = arb(1), x
    while k:
        if k & 1:
            out = out * base
        k >>= 1
        if k:
            base = base * base
    return out


def interval(lo, hi) -> arb:
    """An arb ball containing [lo, hi].

    Parameters
    ----------
    lo, hi : fmpq"""
    return arb((lo + hi) / 2, (hi - lo) / 2)


class Space:
    """The variables of the models: eps (index 0), then sigma (index 1, with a background: Sigma not None)
    and delta_1..delta_k, with their ranges [0, S], [0, Sigma], [-Delta, Delta].

    Parameters
    ----------
    S, Sigma, Delta : fmpq
        Sigma (default None) and Delta (default 0) optional.
    k : int, optional"""

    def __init__(self, S: fmpq, Sigma: fmpq | None = None, k: int = 0, Delta: fmpq = fmpq(0)):
        names = ("e",) + (("s",) if Sigma is not None else ()) + tuple(f"d{i}" for i in range(k))
        self.ctx = fmpq_mpoly_ctx.get(names, "lex")
        self.nv = len(names)
        self.sig = 1 if Sigma is not None else None
        self.S, self.Sigma, self.Delta, self.k = S, Sigma, Delta, k
        self.gens = self.ctx.gens()
        self.ranges = [(fmpq(0), S)] + ([(fmpq(0), Sigma)] if Sigma is not None else []) + [(-Delta, Delta)] * k
        self.box = [interval(lo, hi) for lo, hi in self.ranges]

    def zero(self):
        return self.ctx.from_dict({})

    def const(self, c):
        """The constant polynomial c.

        Parameters
        ----------
        c : fmpq"""
        return self.ctx.from_dict({(0,) * self.nv: c} if c != 0 else {})

    def mono(self, i: int, e: int):
        """The monomial var_i^e (i = 0: eps; then sigma, when there is one, and the delta_i).

        Parameters
        ----------
        i, e : int"""
        exps = [0] * self.nv
        exps[i] = e
        return self.ctx.from_dict({tuple(exps): 1})


def terms(p) -> dict:
    """p's terms as a dict {exponents: coefficient}.

    Parameters
    ----------
    p : fmpq_mpoly"""
    return p.to_dict()


def valuation(p, i: int | None) -> int | None:
    """The least exponent of variable i in p (None for p = 0; 0 when i is None)."""
    ms = p.monoms()
    if not ms:
        return None
    return 0 if i is None else min(e[i] for e in ms)


def shift(sp: Space, p, i: int | None, k: int):
    """p times var_i^k (k < 0: an exact division, or NoProof; i = None, a missing sigma: p for k >= 0).

    Parameters
    ----------
    sp : Space
    p : fmpq_mpoly
    i : int or None
    k : int"""
    if k == 0 or i is None:
        if k < 0 and i is None:
            raise NoProof("a division by a missing variable")
        return p
    out = {}
    for e, c in terms(p).items():
        if e[i] + k < 0:
            raise NoProof("a model is not divisible by the scale of its phase")
        e2 = list(e)
        e2[i] += k
        out[tuple(e2)] = c
    return sp.ctx.from_dict(out)


def select_degrees(sp: Space, p, lo: int, hi: int | None):
    """The terms of p whose eps-degree is in [lo, hi]."""
    return sp.ctx.from_dict({e: c for e, c in terms(p).items() if e[0] >= lo and (hi is None or e[0] <= hi)})


def evaluate(sp: Space, p, box: list | None = None) -> arb:
    """p over the box (interval arithmetic, term by term)."""
    return evaluate_terms(sp, terms(p).items(), box)


def evaluate_terms(sp: Space, items, box: list | None = None) -> arb:
    """sum of c x^e over the box for the (exponents, coefficient) pairs ``items``."""
    box = box or sp.box
    out = arb(0)
    powers: dict = {}
    for e, c in items:
        t = arb(c)
        for i, k in enumerate(e):
            if k:
                key = (i, k)
                pw = powers.get(key)
                if pw is None:
                    pw = powers[key] = ipow(box[i], k)
                t *= pw
        out += t
    return out


class Model:
    """f in p + eps^(n+1) sigma^k r on the box: p an exact polynomial of eps-degree <= n (the order), r an
    interval (k = 0 without sigma).

    Parameters
    ----------
    p : fmpq_mpoly
    n, k : int
    r : arb"""

    __slots__ = ("p", "n", "k", "r")

    def __init__(self, p, n: int, k: int, r: arb):
        self.p, self.n, self.k, self.r = p, n, k, r


class Box:
    """Taylor-model arithmetic on a :class:`Space` (module docstring).  ``check()``, when given, is called
    before every product (the costly operation): a deadline or a budget (charged the product's size) raises.

    Parameters
    ----------
    sp : Space
    check : callable or WorkBudget, optional"""

    def __init__(self, sp: Space, check=None):
        self.sp = sp
        self.check = check
        self.E = sp.box[0]
        self.Sa = arb(sp.S)
        self.sig = sp.sig

    def pw(self, e: int) -> arb:
        """eps^e over [0, S] (e >= 0).

        Parameters
        ----------
        e : int"""
        if e < 0:
            raise NoProof("internal: a negative power of eps")
        return ipow(self.E, e)

    def ps(self, k: int) -> arb:
        """sigma^k over [0, Sigma] (k >= 0; 1 without sigma).

        Parameters
        ----------
        k : int"""
        if k < 0:
            raise NoProof("internal: a negative power of sigma")
        return arb(1) if self.sig is None else ipow(self.sp.box[self.sig], k)

    def vs(self, p) -> int:
        """The sigma-valuation of p (0 without sigma; large for p = 0).

        Parameters
        ----------
        p : fmpq_mpoly"""
        if self.sig is None:
            return 0
        v = valuation(p, self.sig)
        return 1 << 20 if v is None else v

    def combine(self, parts: list) -> tuple[int, arb]:
        """eps^(n+1) sum_j eps^e_j sigma^k_j R_j as eps^(n+1) sigma^k R: (k, R).

        Parameters
        ----------
        parts : list of (int, int, arb)"""
        parts = [(e, k, R) for e, k, R in parts if not R.is_zero()]
        if not parts:
            return 0, arb(0)
        k = min(kk for _, kk, _ in parts) if self.sig is not None else 0
        R = arb(0)
        for e, kk, RR in parts:
            R += self.pw(e) * self.ps(kk - k) * RR
        return k, R

    def tail(self, p, n: int) -> tuple:
        """(p's terms of eps-degree <= n, (k, R): the rest as eps^(n+1) sigma^k R).

        Parameters
        ----------
        p : fmpq_mpoly
        n : int"""
        # one pass over p's terms (the products are large: no intermediate polynomials)
        low, high = {}, []
        for e, c in terms(p).items():
            if e[0] <= n:
                low[e] = c
            else:
                high.append((e, c))
        lowp = self.sp.ctx.from_dict(low)
        if not high:
            return lowp, (0, arb(0))
        k = 0 if self.sig is None else min(e[self.sig] for e, _ in high)
        shifted = []  # the rest divided by eps^(n+1) sigma^k: a translation of the exponents
        for e, c in high:
            e2 = list(e)
            e2[0] -= n + 1
            if k:
                e2[self.sig] -= k
            shifted.append((tuple(e2), c))
        return lowp, (k, evaluate_terms(self.sp, shifted))

    def model(self, p, n: int) -> Model:
        """p as a model of order n (its terms above eps^n enclosed in the rest).

        Parameters
        ----------
        p : fmpq_mpoly
        n : int"""
        low, (k, R) = self.tail(p, n)
        return Model(low, n, k, R)

    def const(self, c, n: int) -> Model:
        """The constant c as a model of order n.

        Parameters
        ----------
        c : fmpq
        n : int"""
        return Model(self.sp.const(c), n, 0, arb(0))

    def error(self, order: int, sig: int, bound: arb) -> Model:
        """eps^order sigma^sig times [-|bound|, |bound|] (sig ignored without sigma).

        Parameters
        ----------
        order, sig : int
        bound : arb"""
        return Model(self.sp.zero(), order - 1, sig if self.sig is not None else 0, arb(0, abs(bound).upper()))

    def trunc(self, a: Model, n: int) -> Model:
        """a at order n (its terms above eps^n moved into the rest); a itself when n >= a.n.

        Parameters
        ----------
        a : Model
        n : int"""
        if n >= a.n:
            return a
        low, (k, R) = self.tail(a.p, n)
        k2, R2 = self.combine([(0, k, R), (a.n - n, a.k, a.r)])
        return Model(low, n, k2, R2)

    def add(self, a: Model, b: Model) -> Model:
        """a + b, of order min(a.n, b.n).

        Parameters
        ----------
        a, b : Model"""
        n = min(a.n, b.n)
        low, (k, R) = self.tail(a.p + b.p, n)
        k2, R2 = self.combine([(0, k, R), (a.n - n, a.k, a.r), (b.n - n, b.k, b.r)])
        return Model(low, n, k2, R2)

    def scale(self, a: Model, q) -> Model:
        """q a.

        Parameters
        ----------
        a : Model
        q : fmpq"""
        return Model(a.p * q, a.n, a.k, a.r * arb(q))

    def mulp(self, a: Model, c) -> Model:
        """a times an exact polynomial c in the parameters (no eps).

        Parameters
        ----------
        a : Model
        c : fmpq_mpoly"""
        if c.is_zero():
            return Model(self.sp.zero(), a.n, 0, arb(0))
        kc = self.vs(c)
        rc = evaluate(self.sp, shift(self.sp, c, self.sig, -kc) if kc else c)
        return Model(a.p * c, a.n, a.k + kc, a.r * rc)

    def val(self, a: Model) -> int:
        """The eps-valuation of a's polynomial (a.n + 1 when it has no term of eps-degree <= a.n).

        Parameters
        ----------
        a : Model"""
        v = valuation(a.p, 0)
        return a.n + 1 if v is None or v > a.n else v

    def mul(self, a: Model, b: Model) -> Model:
        """a b, of order min(a.n + val(b), b.n + val(a)), after ``check``.

        Parameters
        ----------
        a, b : Model"""
        if self.check is not None:
            self.check()
            if isinstance(self.check, WorkBudget):
                self.check.charge(max(1, len(a.p)) * max(1, len(b.p)))
        va, vb = self.val(a), self.val(b)
        n = min(a.n + vb, b.n + va)
        low, (k, R) = self.tail(a.p * b.p, n)
        parts = [(0, k, R)]
        if not a.r.is_zero():  # eps^(a.n+1) sigma^a.k r_a b, b = eps^vb b'
            bp = shift(self.sp, b.p, 0, -vb) if vb <= b.n else self.sp.zero()
            kb = min(self.vs(bp), b.k if not b.r.is_zero() else 1 << 20) if self.sig is not None else 0
            kb = 0 if kb >= 1 << 20 else kb
            rb = evaluate(self.sp, shift(self.sp, bp, self.sig, -kb) if kb else bp)
            if not b.r.is_zero():
                rb += self.pw(b.n + 1 - vb) * self.ps(b.k - kb) * b.r
            parts.append((a.n + vb - n, a.k + kb, a.r * rb))
        if not b.r.is_zero() and va <= a.n:  # eps^(b.n+1) sigma^b.k r_b A, A = eps^va A'
            ap = shift(self.sp, a.p, 0, -va)
            ka = self.vs(ap)
            parts.append((b.n + va - n, b.k + ka, b.r * evaluate(self.sp, shift(self.sp, ap, self.sig, -ka) if ka else ap)))
        k2, R2 = self.combine(parts)
        return Model(low, n, k2, R2)

    def up(self, a: Model, k: int) -> Model:
        """a times eps^k (k >= 0; order a.n + k).

        Parameters
        ----------
        a : Model
        k : int"""
        return Model(shift(self.sp, a.p, 0, k), a.n + k, a.k, a.r)

    def down(self, a: Model, k: int) -> Model:
        """a / eps^k (order a.n - k); :class:`NoProof` when a is not O(eps^k).

        Parameters
        ----------
        a : Model
        k : int"""
        if k == 0:
            return a
        if self.val(a) < k or k > a.n + 1:
            raise NoProof("a division by eps^k of a model that is not O(eps^k)", order=k > a.n + 1)
        return Model(shift(self.sp, a.p, 0, -k), a.n - k, a.k, a.r)

    def up_s(self, a: Model, k: int) -> Model:
        """a times sigma^k (a without sigma).

        Parameters
        ----------
        a : Model
        k : int"""
        if self.sig is None or k == 0:
            return a
        return Model(shift(self.sp, a.p, self.sig, k), a.n, a.k + k, a.r)

    def down_s(self, a: Model, k: int) -> Model:
        """a / sigma^k (a without sigma); :class:`NoProof` when the rest is not divisible by it.

        Parameters
        ----------
        a : Model
        k : int"""
        if self.sig is None or k == 0:
            return a
        if not a.r.is_zero() and a.k < k:
            raise NoProof("a model is not divisible by the speed")
        return Model(shift(self.sp, a.p, self.sig, -k), a.n, a.k - k if not a.r.is_zero() else 0, a.r)

    def lin(self, row, xs: list) -> Model:
        """sum_j row[j] xs[j] (the constant 0 of order min_j xs[j].n when every weight is 0).

        Parameters
        ----------
        row : sequence of fmpq
        xs : list of Model"""
        out = None
        for j, w in enumerate(row):
            if w == 0:
                continue
            term = self.scale(xs[j], w)
            out = term if out is None else self.add(out, term)
        return out if out is not None else self.const(0, min(x.n for x in xs))

    def matvec(self, M: fmpq_mat, xs: list) -> list:
        """M xs, a list of models (:meth:`lin` of each row).

        Parameters
        ----------
        M : fmpq_mat
        xs : list of Model"""
        return [self.lin([M[i, j] for j in range(M.ncols())], xs) for i in range(M.nrows())]

    def range(self, a: Model) -> arb:
        """An enclosure of a over the whole box.

        Parameters
        ----------
        a : Model"""
        return evaluate(self.sp, a.p) + self.pw(a.n + 1) * self.ps(a.k) * a.r

    def at(self, a: Model, point: list) -> arb:
        """a at a point (a ball for every variable, inside the box).

        Parameters
        ----------
        a : Model
        point : list of arb"""
        rem = ipow(point[0], a.n + 1) * a.r
        if self.sig is not None and a.k:
            rem *= ipow(point[self.sig], a.k)
        return evaluate(self.sp, a.p, point) + rem

    def coef(self, a: Model, i: int):
        """The eps^i coefficient (a polynomial in the parameters).

        Parameters
        ----------
        a : Model
        i : int"""
        return shift(self.sp, select_degrees(self.sp, a.p, i, i), 0, -i)

    def rest(self, a: Model, m: int) -> Model:
        """(a - a_m eps^m) / eps^(m+1) (a of eps-valuation >= m).

        Parameters
        ----------
        a : Model
        m : int"""
        if a.n < m:
            raise NoProof("a model of too low an order", order=True)
        return self.down(Model(a.p - select_degrees(self.sp, a.p, m, m), a.n, a.k, a.r), m + 1)

    def param_range(self, c, pieces: int = 64) -> arb:
        """The range of a parameter polynomial over the box, refined on ``pieces`` pieces of [0, Sigma].

        Parameters
        ----------
        c : fmpq_mpoly
        pieces : int, optional"""
        if self.sig is None or self.sp.Sigma == 0:
            return evaluate(self.sp, c)
        lo_b, hi_b = None, None
        Sg = self.sp.Sigma
        items = list(terms(c).items())  # once, not once a piece
        for j in range(pieces):
            box = list(self.sp.box)
            box[self.sig] = interval(Sg * j / pieces, Sg * (j + 1) / pieces)
            v = evaluate_terms(self.sp, items, box)
            lo_b = v.lower() if lo_b is None else min(lo_b, v.lower())
            hi_b = v.upper() if hi_b is None else max(hi_b, v.upper())
        return arb((lo_b + hi_b) / 2, (hi_b - lo_b) / 2)

    def lead(self, a: Model) -> tuple:
        """(v, kappa, c'): a = eps^v sigma^kappa (c' + eps rest / sigma^kappa), c' the leading coefficient over
        its sigma-valuation; NoProof if the rest is not divisible by it (the sign is not uniform in sigma).

        Parameters
        ----------
        a : Model"""
        v = self.val(a)
        if v > a.n:
            raise NoProof("a leading coefficient lies beyond the models' order", order=True)
        c = self.coef(a, v)
        kc = self.vs(c)
        return v, kc, shift(self.sp, c, self.sig, -kc) if kc else c

    def sign(self, a: Model) -> int | None:
        """The sign of a on the whole box from its leading coefficient, or None.

        Parameters
        ----------
        a : Model"""
        try:
            v, kc, c = self.lead(a)
            rest = self.down_s(self.rest(a, v), kc)
        except NoProof:
            return None
        cr = self.param_range(c)
        if cr.contains(0):
            return None
        if (abs(cr).lower() - abs(self.range(rest)) * self.Sa) > 0:
            return 1 if cr > 0 else -1
        return None

    def bounds(self, a: Model, m: int, ks: int = 0) -> arb:
        """The range of a / (eps^m sigma^ks) over the box.

        Parameters
        ----------
        a : Model
        m : int
        ks : int, optional"""
        return self.range(self.down_s(self.down(a, m), ks))


def positive_on(box: Box, P: list, lo: fmpq, hi: fmpq, margin: arb, pieces: int = 4096) -> bool:
    """sum_i P[i] tau^i > margin for all tau in [lo, hi] and all parameters in the box, certified by interval
    evaluation on pieces of tau (and sigma); False if not (a midpoint not above margin, or > ``pieces`` pieces).

    Parameters
    ----------
    box : Box
    P : list of fmpq_mpoly
    lo, hi : fmpq
    margin : arb
    pieces : int, optional"""
    sp = box.sp
    Sg = sp.Sigma if sp.sig is not None else None
    items = [(i, list(terms(c).items())) for i, c in enumerate(P) if not c.is_zero()]  # once, not once a piece
    stack = [(lo, hi, fmpq(0), Sg)]
    count = 0
    while stack:
        a, b, s0, s1 = stack.pop()
        count += 1
        if count > pieces:
            return False
        bx = list(sp.box)
        if sp.sig is not None:
            bx[sp.sig] = interval(s0, s1)
        tau = interval(a, b)
        val = arb(0)
        for i, its in items:
            val += evaluate_terms(sp, its, bx) * ipow(tau, i)
        if val > margin:
            continue
        bx_mid = list(bx)
        if sp.sig is not None:
            bx_mid[sp.sig] = interval((s0 + s1) / 2, (s0 + s1) / 2)
        midval = sum((evaluate_terms(sp, its, bx_mid) * ipow(arb((a + b) / 2), i) for i, its in items), arb(0))
        if not midval > margin:
            return False  # P <= margin somewhere (up to rounding): not certified
        if Sg and (s1 - s0) * (hi - lo) > (b - a) * Sg:
            stack += [(a, b, s0, (s0 + s1) / 2), (a, b, (s0 + s1) / 2, s1)]
        else:
            stack += [(a, (a + b) / 2, s0, s1), ((a + b) / 2, b, s0, s1)]
    return True


def truncate(sp: Space, p, n: int):
    """The terms of p of eps-degree <= n.

    Parameters
    ----------
    sp : Space
    p : fmpq_mpoly
    n : int"""
    return select_degrees(sp, p, 0, n)


def coefficients(sp: Space, p, n: int) -> list:
    """The eps^0..eps^n coefficients of p (parameter polynomials)."""
    out = [{} for _ in range(n + 1)]
    for e, c in terms(p).items():
        if e[0] <= n:
            out[e[0]][(0,) + tuple(e[1:])] = c
    return [sp.ctx.from_dict(d) for d in out]


def series_mul(a: list, b: list, n: int, zero) -> list:
    """The product of two series (lists of coefficients) mod eps^(n+1)."""
    out = [zero] * (n + 1)
    for i, x in enumerate(a):
        if x.is_zero():
            continue
        for j, y in enumerate(b[: n + 1 - i]):
            if not y.is_zero():
                out[i + j] = out[i + j] + x * y
    return out


def series_root(sp: Space, H: list, tau0, omega: fmpq, n: int):
    """tau(eps) mod eps^(n+1) with sum_j H_j tau^j = 0, tau(0) = tau0, d/dtau at eps = 0 the rational constant
    omega != 0: fixed-point iteration tau <- tau - F(tau) / omega, one order of eps a step (exact).

    Parameters
    ----------
    sp : Space
    H : list of fmpq_mpoly
    tau0 : fmpq_mpoly
    omega : fmpq
    n : int"""
    zero = sp.zero()
    Hs = [coefficients(sp, h, n) for h in H]
    Hs = [h for h in Hs]
    tau = [tau0] + [zero] * n
    for _ in range(n + 2):
        F = [zero] * (n + 1)
        power = [sp.const(1)] + [zero] * n
        for j, h in enumerate(Hs):
            if j:
                power = series_mul(power, tau, n, zero)
            if all(c.is_zero() for c in h):
                continue
            term = series_mul(h, power, n, zero)
            F = [a + b for a, b in zip(F, term)]
        if all(c.is_zero() for c in F):
            break
        tau = [t - f * (1 / omega) for t, f in zip(tau, F)]
    out = zero
    eps = sp.gens[0]
    for i, c in enumerate(tau):
        if not c.is_zero():
            out = out + c * eps ** i
    return out

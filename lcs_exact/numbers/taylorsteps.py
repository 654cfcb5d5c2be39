"""x(t) = e^{Mt} x_0 as Taylor steps on balls (Taylor-Krylov): no eigenvalues, no eigenvectors.

Over a step [t_k, t_k + h_k] of a grid (h_k a power of two, ``||M h_k||_inf <= STEP_NORM``):

    x(t_k + theta h_k) in sum_{j<J_k} w_j theta^j + [-rho, rho],   w_j = (M h_k)^j x_k / j!,

for |theta| <= 1, where x_k is a ball of x(t_k) (the next one is the sum at theta = 1) and, with
s = ||M h_k||_inf, the tail of the series is bounded by ||x_k||_inf s^J e^s / J! (the Lagrange form
of sum_{j>=J} (M h theta)^j / j!, each term of norm at most s^j / j!).  Its d-th theta-derivative
has the truncated sum's derivative and the tail ||x_k||_inf s^J e^s / (J - d)! (d < J; for d >= J
every term is tail: ||x_k|| s^d e^s).  J products of a ball matrix with a ball vector a step, and
a monitored row g gives its polynomial in theta from the products g w_j: every constraint of a
phase (section 4.1) at once.  The products are kept unscaled, u_j = M^j x_k (w_j = u_j h^j / j!):
the factors h^j / j! go to the rows' coefficients (m scalars a term, not n) and to the Horner
sums of a state (a scalar h theta / j a level), and x_{k+1} is summed only when step k + 1 is
asked for (a phase whose event falls in its first step never sums it).

The grid is t_k = k h (h the largest power of two with ||M h|| <= STEP_NORM), or, given a first
step h_0 = h / 2^m, the geometric start 0, h_0, 2 h_0, 4 h_0, ..., h followed by h, 2 h, ...: a
phase whose event comes after 10^-50 (an impact running down a chain of carts) takes a step of
about that length, whose order J (about bits / log2(1 / ||M h_0||)) is 2 or 3 instead of ~60,
and a wrong guess of h_0 costs at most m short steps.

The cost grows with ||M|| t (stiff modes need ||M|| t / STEP_NORM steps): the spectral path of
:mod:`.expm` stays for them, and for small systems whose spectral data is cheap.  Balls only: the
ball x_0 comes from an exact start at a precision, and a precision asked later restarts from it
(the exact anchor), never from a step's ball.
"""
from __future__ import annotations

import math
from functools import lru_cache

from flint import arb, arb_mat, fmpq, fmpq_mat

from .balls import dyadic_lower, dyadic_upper, workprec
from ..errors import LCSError

__all__ = ["TaylorSteps", "STEP_NORM", "taylor_order", "first_step"]

#: ||M h||_inf of a step, at most: a larger step costs fewer products a unit of time (measured
#: at n = 64, 192 bits: 0.82 ms a unit of ||M|| t at 4, 1.4 ms at 2), its polynomials are of
#: higher degree (about 70 at 192 bits)
STEP_NORM = 4
#: how far past its end a step's series is evaluated for a ball's rounding (:meth:`TaylorSteps.pieces`)
SPILL_BITS = 16


@lru_cache(maxsize=1024)
def taylor_order(s: float, prec: int) -> int:
    """The order J with s^J e^s / J! below 2^-(prec + 8) (s = ||M h||): the tail of a step at the
    precision's resolution.  Any J is rigorous (the tail is bounded whatever it is); this one
    makes the tail negligible."""
    J = 1
    lg2 = math.log2(s) if s > 0 else -1e9
    while J * lg2 + s / math.log(2) - math.lgamma(J + 1) / math.log(2) > -(prec + 8):
        J += 1
    return max(J, 2)


class TaylorSteps:
    """e^{Mt} x_0 for t >= 0 on a grid of steps (see the module docstring), computed as far as
    asked.

    Parameters
    ----------
    M : fmpq_mat
        The n x n rational matrix.
    norm : fmpq
        ||M||_inf, exactly (or an upper bound).
    x0 : arb_mat
        A ball of the start (n x 1).
    prec : int
        The working precision of the balls.
    zero : list of int, optional
        Coordinates i with x_i(t) = 0 for all t (proven by the caller): kept exactly 0.
    first : fmpq, optional
        A length for the first step (rounded down to a power of two h / 2^m, at most h): the grid
        starts 0, h_0, 2 h_0, ..., h, then goes on by h.
    balls : arb_mat, optional
        M as balls of ``prec`` bits or more (a caller's kept conversion); computed when not given.

    >>> from flint import fmpq_mat, arb_mat, fmpq
    >>> st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 64)
    >>> x = st.state(arb(3))              # (cos 3, -sin 3)
    >>> abs(x[0, 0] - arb(3).cos()) < 1e-15, abs(x[1, 0] + arb(3).sin()) < 1e-15
    (True, True)
    >>> st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 64, first=fmpq(1, 100))
    >>> st.length(0), [st.start(k) for k in range(12)][-5:], st.order(0) < st.order(10) == st.J
    (1/128, [1/2, 1, 2, 4, 8], True)
    """

    def __init__(self, M: fmpq_mat, norm: fmpq, x0: arb_mat, prec: int, zero: list[int] | tuple = (),
                 first: fmpq | None = None, balls: arb_mat | None = None):
        self.n, self.prec, self.zero, self.norm = M.nrows(), prec, tuple(zero), norm
        e = 0
        if norm > 0:  # h = 2^e, the largest with ||M|| h <= STEP_NORM
            e = _log2_floor(fmpq(STEP_NORM) / norm)
        self.h = fmpq(2) ** e
        self._e = e
        self._lengths: dict[int, fmpq] = {}  # k -> h_k (a step's length is read at every evaluation)
        # m doublings from h_0 = h / 2^m up to h (m = 0: the uniform grid)
        self.m = 0 if first is None or first >= self.h or first <= 0 else e - _log2_floor(first)
        if balls is None:
            with workprec(prec):
                balls = arb_mat(M)
        self._M = balls
        self._level: dict[int, tuple] = {}  # step length's exponent -> (J, s, h, e^s, [h/j])
        self._factors: dict[int, tuple] = {}  # step length's exponent -> (h^j / j! for j < J)
        # x_k, the ball at t_k (x0 copied before its zero coordinates are set: it is the caller's)
        self._x = [self._clean(arb_mat(self.n, 1, x0.entries()) if self.zero else x0)]
        self._u: list[list[arb_mat]] = []  # the unscaled columns u_j = M^j x_k, j < J, of step k
        self._norms: list[arb] = []  # ||x_k||_inf bounds
        self._tails: dict = {}

    @property
    def computed(self) -> int:
        """How many steps' columns are computed so far."""
        return len(self._u)

    @property
    def J(self) -> int:
        """The order of a step of the regular length h."""
        return self.order(self.m + 1)

    @property
    def s(self) -> fmpq:
        """||M h||_inf for the regular step h."""
        return self.norm * self.h

    def _data(self, k: int) -> tuple:
        """(J, s, h_k, e^s, [h_k / j for 0 < j < J]) of step k (per step length, as balls: h_k is
        a power of two, so M w h_k / j is M h_k w / j exactly, without an n x n scaling of M a
        step length - 10 % of a 128-state run's steps at its highest precisions)."""
        e = self._exponent(k)
        if e not in self._level:
            hk = fmpq(2) ** e
            s = self.norm * hk
            if e > -1000:
                J = taylor_order(float(s), self.prec)
            else:  # s below float range: s^J / J! <= 2^(J log2 s), log2 s = e + log2 ||M||
                J = max(2, -(-(self.prec + 8) // max(1, -(e + math.ceil(math.log2(max(float(self.norm), 1e-300)))))))
            with workprec(self.prec):
                hb = arb(hk)
                self._level[e] = (J, s, hb, arb(s).exp(), tuple(hb * inv for inv in _inverses(J, self.prec)))
        return self._level[e]

    def _exponent(self, k: int) -> int:
        """log2 of the length of step k."""
        if k > self.m:
            return self._e
        return self._e - self.m + max(k - 1, 0)

    def length(self, k: int) -> fmpq:
        """h_k, the length of step k.

        Parameters
        ----------
        k : int
            The step.
        """
        h = self._lengths.get(k)
        if h is None:
            h = self._lengths[k] = self.h if k > self.m else fmpq(2) ** self._exponent(k)
        return h

    def order(self, k: int) -> int:
        """J_k, the number of terms of step k's series.

        Parameters
        ----------
        k : int
            The step.
        """
        return self._data(k)[0]

    def _clean(self, x: arb_mat) -> arb_mat:
        for i in self.zero:
            x[i, 0] = 0
        return x

    def columns(self, k: int) -> list[arb_mat]:
        """[w_0, ..., w_{J_k - 1}] of step k, w_j = (M h_k)^j x_k / j! (computing the steps before
        it; the engine reads :meth:`unscaled` and :meth:`factors`).

        Parameters
        ----------
        k : int
            The step.
        """
        with workprec(self.prec):
            return [self._clean(u * f) for u, f in zip(self.unscaled(k), self.factors(k))]

    def unscaled(self, k: int) -> list[arb_mat]:
        """[u_0, ..., u_{J_k - 1}] of step k, u_j = M^j x_k (computing the steps before it).

        Parameters
        ----------
        k : int
            The step.
        """
        while len(self._u) <= k:
            self._advance()
        return self._u[k]

    def factors(self, k: int) -> tuple:
        """(h_k^j / j! for j < J_k) as balls: w_j = u_j h_k^j / j!.

        Parameters
        ----------
        k : int
            The step.
        """
        e = self._exponent(k)
        if e not in self._factors:
            f, out = arb(1), [arb(1)]
            with workprec(self.prec):
                for hj in self._data(k)[4]:
                    f = f * hj
                    out.append(f)
            self._factors[e] = tuple(out)
        return self._factors[e]

    def _advance(self) -> None:
        k = len(self._u)
        u = self.state_at(k)
        M = self._M
        with workprec(self.prec):
            us = [u]
            for _ in range(1, self.order(k)):
                u = self._clean(M * u)
                us.append(u)
        self._u.append(us)

    def state_at(self, k: int) -> arb_mat:
        """x_k, the ball at t_k: the sum of step k - 1 at theta = 1 with its tail (summed when
        first asked for).

        Parameters
        ----------
        k : int
            The step.
        """
        while len(self._x) <= k:
            j = len(self._x) - 1
            self.unscaled(j)
            x = self._horner(j, self._data(j)[4])
            with workprec(self.prec):
                x = x + self._radius(self.tail(j, 0))
            self._x.append(self._clean(x))
        return self._x[k]

    def _horner(self, k: int, scales) -> arb_mat:
        """sum_j u_j (h theta)^j / j! = u_0 + s_1 (u_1 + s_2 (u_2 + ...)) on step k, ``scales``
        the balls s_j = h theta / j, j = 1 .. J - 1."""
        us = self._u[k]
        with workprec(self.prec):
            acc = us[-1]
            for j in range(len(us) - 1, 0, -1):
                acc = us[j - 1] + acc * scales[j - 1]
            return acc

    def _radius(self, rho: arb) -> arb_mat:
        """The column [-rho, rho]^n (a product of an exact column of ones with one ball: no n
        entries built in Python)."""
        return _ones(self.n) * arb(0, rho)

    def start(self, k: int) -> fmpq:
        """t_k: k h on the uniform grid; 0, h_0, 2 h_0, ..., h = 2^m h_0, h + h, ... after a first
        step h_0.

        Parameters
        ----------
        k : int
            The step.
        """
        if k <= self.m:
            return fmpq(0) if k == 0 else self.length(k)  # t_k = 2^(k-1) h_0 = h_k
        return self.h * (k - self.m)

    def norm_at(self, k: int) -> arb:
        """An upper bound of ||x_k||_inf over its ball.

        Parameters
        ----------
        k : int
            The step.
        """
        while len(self._norms) <= k:
            x = self.state_at(len(self._norms))
            self._norms.append(max((abs(e).upper() for e in x.entries()), default=arb(0)))
        return self._norms[k]

    def tail(self, k: int, d: int) -> arb:
        """A bound of the d-th theta-derivative of the series' tail on step k, |theta| <= 1 (see
        the module docstring).

        Parameters
        ----------
        k : int
            The step.
        d : int
            The order of the derivative.
        """
        key = (k, d)
        if key not in self._tails:
            J, s, _, es, _ = self._data(k)
            top = max(J, d)
            with workprec(self.prec):
                self._tails[key] = self.norm_at(k) * arb(s) ** top * es / math.factorial(top - d)
        return self._tails[key]

    def tail_at(self, k: int, d: int, theta: arb) -> arb:
        """:meth:`tail` for the theta of a ball, which may pass |theta| = 1 by a rounding (a time
        at a step's end): for |theta| <= m with m > 1 the tail's terms grow by m^(j - d), so the
        bound takes the factor m^J e^{s (m - 1)} (J >= the order's top power).

        Parameters
        ----------
        k : int
            The step.
        d : int
            The order of the derivative.
        theta : arb
        """
        rho = self.tail(k, d)
        with workprec(self.prec):
            m = abs(theta).upper()
            if m <= 1:
                return rho
            if m > 2:
                raise LCSError(f"internal inconsistency: theta = {theta} is outside step {k} of the Taylor steps")
            J, s = self._data(k)[:2]
            return rho * m ** max(J, d) * (arb(s) * (m - 1)).exp()

    def locate(self, t: fmpq) -> int:
        """The step k with t_k <= t < t_{k+1} (t >= 0; t < 0 gives step 0, whose series holds
        for theta >= -1 too).

        Parameters
        ----------
        t : fmpq
        """
        if t <= 0:
            return 0
        if self.m and t < self.h:  # the geometric start: t in [2^(k-1) h_0, 2^k h_0)
            return max(0, _log2_floor(t * 2 ** self.m / self.h) + 1)
        q = t / self.h
        return int(q.p // q.q) + self.m

    def pieces(self, lo: fmpq, hi: fmpq, spill: bool = False) -> list[tuple[int, fmpq, fmpq]]:
        """[(k, a, b)]: [lo, hi] cut at the grid, a piece [a, b] in step k.

        Parameters
        ----------
        lo : fmpq
            At least -h_0 (step 0's series holds back to -h_0).
        hi : fmpq
        spill : bool, optional
            The last piece may pass its step's end by up to 2^-SPILL_BITS of the step's length
            (theta <= 1 + 2^-SPILL_BITS, bounded by :meth:`tail_at`) rather than open the next
            step: a ball's radius, rounded up, passes the end of the interval it encloses
            ([0, 1] as a ball reaches 1 + 2^-30), and the next step's series (its J products)
            would be computed for that rounding alone.
        """
        if lo < -self.length(0):
            raise LCSError(f"internal inconsistency: Taylor steps asked at t = {lo} < -h_0 = {-self.length(0)}")
        out = []
        k = self.locate(lo)
        a = lo
        while True:
            end = self.start(k + 1)
            if hi <= end or (spill and (hi - end) * 2 ** SPILL_BITS <= self.length(k)):
                out.append((k, a, hi))
                return out
            out.append((k, a, end))
            a, k = end, k + 1

    def theta(self, k: int, t: arb) -> arb:
        """(t - t_k) / h_k, a ball.

        Parameters
        ----------
        k : int
            The step.
        t : arb
        """
        with workprec(self.prec):
            return (t - arb(self.start(k))) / arb(self.length(k))

    def state(self, t: arb, nonnegative: bool = False) -> arb_mat:
        """A ball of x(t) for a ball t >= 0 (an enclosure over it when wide).

        Parameters
        ----------
        t : arb
        nonnegative : bool, optional
            The time t is >= 0 (the caller's fact: a phase's time): a ball reaching below 0 (a
            root's bracket (10^-185, 10^-89] as a ball, its lower end rounded below 0) is taken
            from 0.
        """
        lo, hi = _bounds(t)
        if nonnegative and lo < 0 <= hi:
            lo = fmpq(0)
        out = None
        for k, a, b in self.pieces(lo, hi, spill=True):
            th = self.theta(k, arb(a).union(arb(b)) if (a, b) != (lo, hi) else t)
            x = self._at(k, th)
            out = x if out is None else arb_mat([[out[i, 0].union(x[i, 0])] for i in range(self.n)])
        return out

    def _at(self, k: int, th: arb) -> arb_mat:
        self.unscaled(k)
        rho = self.tail_at(k, 0, th)
        with workprec(self.prec):
            ht = self._data(k)[2] * th
            x = self._horner(k, [ht * inv for inv in _inverses(self.order(k), self.prec)])
            return self._clean(x + self._radius(rho))


def first_step(M: fmpq_mat, G: fmpq_mat, x0: arb_mat, prec: int, norm: fmpq,
               balls: tuple[arb_mat, arb_mat] | None = None) -> fmpq | None:
    """A first step for :class:`TaylorSteps` when a row of G x(t) turns negative long before
    STEP_NORM / ||M|| (a gap of 10^-50 closing at unit speed: an impact running down a chain of
    carts), else None.

    For each row with g x0 > 0 (its ball), the cubic c_0 + c_1 t + c_2 t^2 + c_3 t^3 of the first
    Taylor coefficients c_j = g M^j x0 / j! (at ``prec`` bits: c_0 may be a 10^-50 difference of
    O(1) entries) is looked at on t = tau 2^i (tau the scale where a negative term can match c_0),
    i < 16, from the midpoints; the first point where it is negative, doubled, is that row's step.
    A guess only: the steps are rigorous whatever their lengths, and a guess too short costs at
    most log2(h / h_0) short steps of low order.

    Parameters
    ----------
    M : fmpq_mat
        The n x n matrix.
    G : fmpq_mat
        The monitored rows (m x n).
    x0 : arb_mat
        A ball of the start.
    prec : int
    norm : fmpq
        ||M||_inf: only roots t with ||M|| t < 2^-6 give a step (the cubic is then accurate).
    balls : (arb_mat, arb_mat), optional
        M and G as balls of ``prec`` bits or more (a caller's kept conversion).
    """
    if G.nrows() == 0 or norm <= 0:
        return None
    with workprec(prec):
        Ma, Ga = balls if balls is not None else (arb_mat(M), arb_mat(G))
        v, cs = x0, []
        for j in range(4):
            cs.append((Ga * v).entries())
            if j < 3:  # (M^4 x0 is not read)
                v = Ma * v * arb(fmpq(1, j + 1))
    limit = arb(2) ** -6 / arb(norm)
    best = None
    with workprec(64):
        for i in range(G.nrows()):
            c = [arb(cs[j][i].mid()) for j in range(4)]
            if not c[0] > 0:
                continue
            tau = min(((c[0] / -c[j]) ** arb(fmpq(1, j)) for j in (1, 2, 3) if c[j] < 0), default=None)
            if tau is None or not tau < limit:
                continue
            t = tau
            for _ in range(16):
                if t > limit or (best is not None and t >= best):
                    break
                if ((c[3] * t + c[2]) * t + c[1]) * t + c[0] < 0:
                    best = t
                    break
                t = 2 * t
    return None if best is None else dyadic_upper(2 * best)


@lru_cache(maxsize=16)
def _ones(n: int) -> arb_mat:
    """The n x 1 column of ones (exact)."""
    return arb_mat(n, 1, [1] * n)


@lru_cache(maxsize=64)
def _inverses(J: int, prec: int) -> tuple[arb, ...]:
    """(1/j for 0 < j < J) as balls of ``prec`` bits (shared by the steps of every phase)."""
    with workprec(prec):
        return tuple(arb(fmpq(1, j)) for j in range(1, J))


def _log2_floor(q: fmpq) -> int:
    """floor(log2 q) for a rational q = a / b > 0: with e = bitlen(a) - bitlen(b),
    2^(e-1) < q < 2^(e+1), so it is e when a >= b 2^e (shifts of integers), else e - 1.

    >>> [_log2_floor(fmpq(x)) for x in (1, 2, 3, fmpq(1, 3), fmpq(3, 8), fmpq(1, 2 ** 300))]
    [0, 1, 1, -2, -2, -300]
    """
    a, b = q.p, q.q
    e = a.bit_length() - b.bit_length()
    return e if (a >= b << e if e >= 0 else a << -e >= b) else e - 1


def _bounds(t: arb) -> tuple[fmpq, fmpq]:
    """Rational ends of a ball, outward."""
    return dyadic_lower(t), dyadic_upper(t)

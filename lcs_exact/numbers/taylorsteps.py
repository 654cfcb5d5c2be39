"""x(t) = e^{Mt} x_0 as Taylor steps on balls (Taylor-Krylov): no eigenvalues, no eigenvectors.

Over a step [t_k, t_k + h] of a grid t_k = k h (h a power of two, ``||M h||_inf <= STEP_NORM``):

    x(t_k + theta h) in sum_{j<J} w_j theta^j + [-rho, rho],   w_j = (M h)^j x_k / j!,

for |theta| <= 1, where x_k is a ball of x(t_k) (the next one is the sum at theta = 1) and, with
s = ||M h||_inf, the tail of the series is bounded by ||x_k||_inf s^J e^s / J! (the Lagrange form
of sum_{j>=J} (M h theta)^j / j!, each term of norm at most s^j / j!).  Its d-th theta-derivative
has the truncated sum's derivative and the tail ||x_k||_inf s^J e^s / (J - d)! (d < J; for d >= J
every term is tail: ||x_k|| s^d e^s).  J products of a ball matrix with a ball vector a step, and
a monitored row g gives its polynomial in theta from the products g w_j: every constraint of a
phase (section 4.1) at once.

The cost grows with ||M|| t (stiff modes need ||M|| t / STEP_NORM steps): the spectral path of
:mod:`.expm` stays for them, and for small systems whose spectral data is cheap.  Balls only: the
ball x_0 comes from an exact start at a precision, and a precision asked later restarts from it
(the exact anchor), never from a step's ball.
"""
from __future__ import annotations

import math

from flint import arb, arb_mat, fmpq, fmpq_mat

from .balls import dyadic_lower, dyadic_upper, workprec
from ..errors import LCSError

__all__ = ["TaylorSteps", "STEP_NORM", "taylor_order"]

#: ||M h||_inf of a step, at most: a larger step costs fewer products a unit of time (measured
#: at n = 64, 192 bits: 0.82 ms a unit of ||M|| t at 4, 1.4 ms at 2), its polynomials are of
#: higher degree (about 70 at 192 bits)
STEP_NORM = 4


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
    """e^{Mt} x_0 for t >= 0 on the grid of steps t_k = k h, computed as far as asked.

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

    >>> from flint import fmpq_mat, arb_mat, fmpq
    >>> st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 64)
    >>> x = st.state(arb(3))              # (cos 3, -sin 3)
    >>> abs(x[0, 0] - arb(3).cos()) < 1e-15, abs(x[1, 0] + arb(3).sin()) < 1e-15
    (True, True)
    """

    def __init__(self, M: fmpq_mat, norm: fmpq, x0: arb_mat, prec: int, zero: list[int] | tuple = ()):
        self.n, self.prec, self.zero = M.nrows(), prec, tuple(zero)
        e = 0
        if norm > 0:  # h = 2^e, the largest with ||M|| h <= STEP_NORM
            q = fmpq(STEP_NORM) / norm
            e = q.p.bit_length() - q.q.bit_length()
            while fmpq(2) ** e > q:
                e -= 1
            while fmpq(2) ** (e + 1) <= q:
                e += 1
        self.h = fmpq(2) ** e
        self.s = norm * self.h
        self.J = taylor_order(float(self.s), prec)
        with workprec(prec):
            self._Mh = arb_mat(M * self.h)
            self._es = arb(self.s).exp()
            self._inv = [arb(fmpq(1, j)) for j in range(1, self.J)]
        # x_k, the ball at t_k (x0 copied before its zero coordinates are set: it is the caller's)
        self._x = [self._clean(arb_mat(self.n, 1, x0.entries()) if self.zero else x0)]
        self._w: list[list[arb_mat]] = []  # the columns w_0 .. w_{J-1} of step k
        self._norms: list[arb] = []  # ||x_k||_inf bounds
        self._tails: dict = {}

    def _clean(self, x: arb_mat) -> arb_mat:
        for i in self.zero:
            x[i, 0] = 0
        return x

    def columns(self, k: int) -> list[arb_mat]:
        """[w_0, ..., w_{J-1}] of step k (computing the steps before it).

        Parameters
        ----------
        k : int
            The step.
        """
        while len(self._w) <= k:
            self._advance()
        return self._w[k]

    def _advance(self) -> None:
        k = len(self._w)
        x = self._x[k]
        with workprec(self.prec):
            ws = [x]
            w = x
            for inv in self._inv:
                w = self._clean((self._Mh * w) * inv)
                ws.append(w)
            nxt = ws[0]
            for w in ws[1:]:
                nxt = nxt + w
            rho = arb(0, self.tail(k, 0))
            nxt = arb_mat(self.n, 1, [e + rho for e in nxt.entries()])
        self._w.append(ws)
        self._x.append(self._clean(nxt))

    def start(self, k: int) -> fmpq:
        """t_k = k h.

        Parameters
        ----------
        k : int
            The step.
        """
        return self.h * k

    def norm_at(self, k: int) -> arb:
        """An upper bound of ||x_k||_inf over its ball.

        Parameters
        ----------
        k : int
            The step.
        """
        while len(self._norms) <= k:
            if len(self._norms) >= len(self._x):
                self._advance()
            x = self._x[len(self._norms)]
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
            top = max(self.J, d)
            with workprec(self.prec):
                self._tails[key] = self.norm_at(k) * arb(self.s) ** top * self._es / math.factorial(top - d)
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
            return rho * m ** max(self.J, d) * (arb(self.s) * (m - 1)).exp()

    def locate(self, t: fmpq) -> int:
        """The step k with t_k <= t < t_{k+1} (t >= 0; t < 0 gives step 0, whose series holds
        for theta >= -1 too).

        Parameters
        ----------
        t : fmpq
        """
        if t <= 0:
            return 0
        q = t / self.h
        return int(q.p // q.q)

    def pieces(self, lo: fmpq, hi: fmpq) -> list[tuple[int, fmpq, fmpq]]:
        """[(k, a, b)]: [lo, hi] cut at the grid, a piece [a, b] in step k.

        Parameters
        ----------
        lo : fmpq
            At least -h (step 0's series holds back to -h).
        hi : fmpq
        """
        if lo < -self.h:
            raise LCSError(f"internal inconsistency: Taylor steps asked at t = {lo} < -h = {-self.h}")
        out = []
        k = self.locate(lo)
        a = lo
        while True:
            end = self.start(k + 1)
            if hi <= end:
                out.append((k, a, hi))
                return out
            out.append((k, a, end))
            a, k = end, k + 1

    def theta(self, k: int, t: arb) -> arb:
        """(t - t_k) / h, a ball.

        Parameters
        ----------
        k : int
            The step.
        t : arb
        """
        with workprec(self.prec):
            return (t - arb(self.start(k))) / arb(self.h)

    def state(self, t: arb) -> arb_mat:
        """A ball of x(t) for a ball t >= 0 (an enclosure over it when wide).

        Parameters
        ----------
        t : arb
        """
        lo, hi = _bounds(t)
        out = None
        for k, a, b in self.pieces(lo, hi):
            th = self.theta(k, arb(a).union(arb(b)) if (a, b) != (lo, hi) else t)
            x = self._at(k, th)
            out = x if out is None else arb_mat([[out[i, 0].union(x[i, 0])] for i in range(self.n)])
        return out

    def _at(self, k: int, th: arb) -> arb_mat:
        ws = self.columns(k)
        rho = self.tail_at(k, 0, th)
        with workprec(self.prec):
            acc = ws[-1]
            for w in reversed(ws[:-1]):  # Horner in theta
                acc = acc * th + w
            return self._clean(arb_mat([[acc[i, 0] + arb(0, rho)] for i in range(self.n)]))


def _bounds(t: arb) -> tuple[fmpq, fmpq]:
    """Rational ends of a ball, outward."""
    return dyadic_lower(t), dyadic_upper(t)

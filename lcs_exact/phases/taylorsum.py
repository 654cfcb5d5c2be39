"""The constraint functions of a phase on Taylor steps: f(t) = g e^{A_I t} z without spectral data.

On step k (of length h_k) of :class:`~lcs_exact.numbers.taylorsteps.TaylorSteps` a row g has the
polynomial p_k(theta) = sum_j (g w_j) theta^j, and

    f^{(d)}(t_k + theta h_k) in p_k^{(d)}(theta) / h_k^d + [-1, 1] ||g||_1 tail_k(d) / h_k^d,   |theta| <= 1

(the tail bound of the steps times ||g||_1 >= |g v| / ||v||_inf).  :class:`TaylorRows` holds the
polynomials of all the monitored rows of a phase (one product of the rows with each column w_j
gives them all), :class:`TaylorSum` one row with the interface the certified root search uses
(:class:`~lcs_exact.roots.ExpSum`'s: ``values``, ``value``, ``enclose``, ``sign_enclose``, float
guesses).  Enclosures over an interval are taken piece by piece on the grid of steps.  Float
guesses (the midpoints of the coefficients on a grid of theta) only order and window the searches
(:mod:`lcs_exact.guesses`): no decision is taken on them.
"""
from __future__ import annotations


from flint import arb, arb_mat, arb_poly, fmpq, fmpq_mat

from ..numbers import TaylorSteps, dyadic_lower, dyadic_upper, workprec
from ..algebra import norm_inf, vstack
from .guesses import newton_in_bracket
from .roots import taylor_form

__all__ = ["TaylorRows", "TaylorSum"]

#: float points a step at which a crossing is looked for (guesses only)
GUESS_POINTS = 64
#: where in its 1/GUESS_POINTS of the step each point lies: not at a simple rational, so that a
#: guess does not land exactly on an event at a rational time (t = 1 in section 7), where no ball
#: can show the sign the search's window needs at its end
GUESS_OFFSET = 0.6180339887498949


class TaylorRows:
    """The polynomials of rows g_0, ..., g_{m-1} on the steps of a phase (see the module docstring).

    Parameters
    ----------
    steps : TaylorSteps
    rows : list of fmpq_mat
        1 x n rational rows.
    norms : list of fmpq, optional
        ||g||_1 of each row, exactly or an upper bound (computed when not given).
    stacked : fmpq_mat, optional
        The rows stacked (m x n), when the caller keeps them (computed when not given).
    balls : arb_mat, optional
        The stacked rows as balls of the steps' precision or more (a caller's kept conversion).
    """

    def __init__(self, steps: TaylorSteps, rows: list[fmpq_mat], norms: list | None = None,
                 stacked: fmpq_mat | None = None, balls: arb_mat | None = None):
        self.steps, self.rows = steps, list(rows)
        self.prec = steps.prec
        if norms is None:
            norms = [norm_inf(g.transpose()) for g in self.rows]
        with workprec(self.prec):
            if balls is None and self.rows:
                balls = arb_mat(stacked if stacked is not None else vstack(*self.rows))
            self._G = balls if self.rows else None
            self._g1 = [arb(q) for q in norms]  # ||g||_1
        self._coeffs: list[list[list[arb]]] = []  # step -> row -> [c_0 .. c_{J-1}]
        self._polys: dict = {}
        self._floats: dict = {}

    def function(self, i: int) -> "TaylorSum":
        """Row i as a :class:`TaylorSum`."""
        return TaylorSum(self, i)

    def coefficients(self, k: int) -> list[list[arb]]:
        """[[g_i w_j for j < J] for each row i] on step k."""
        while len(self._coeffs) <= k:
            j = len(self._coeffs)
            us, fs = self.steps.unscaled(j), self.steps.factors(j)
            with workprec(self.prec):  # g w_j = (g u_j) h^j / j!: m scalings, not n
                cols = [((self._G * u) * f).entries() for u, f in zip(us, fs)]
            self._coeffs.append(list(map(list, zip(*cols))) if cols else [])  # rows of the columns' table
        return self._coeffs[k]

    def poly(self, i: int, k: int, d: int) -> arb_poly:
        """p_k^{(d)} of row i (in theta)."""
        key = (i, k, d)
        if key not in self._polys:
            with workprec(self.prec):
                self._polys[key] = arb_poly(self.coefficients(k)[i]) if d == 0 else \
                    self.poly(i, k, d - 1).derivative()
        return self._polys[key]

    def value(self, i: int, k: int, theta: arb, d: int) -> arb:
        """f_i^{(d)}(t_k + theta h), |theta| <= 1."""
        return self.values(i, k, theta, (d,))[0]

    def values(self, i: int, k: int, theta: arb, orders) -> list[arb]:
        """[f_i^{(d)}(t_k + theta h) for d in orders], |theta| <= 1 (one precision context and
        one step length for all the orders: the root search asks 2-5 at a point)."""
        st = self.steps
        g1 = self._g1[i]
        out = []
        with workprec(self.prec):
            h = None
            for d in orders:
                v = self.poly(i, k, d)(theta) + arb(0, (g1 * st.tail_at(k, d, theta)).upper())
                if d:
                    h = arb(st.length(k)) if h is None else h
                    v = v / h ** d
                out.append(v)
        return out

    def positive_until(self, i: int, order: int, end: fmpq, max_steps: int = 16) -> bool:
        """f_i > 0 on (0, end], proven on the steps' polynomials (False: not proven), where
        f_i^{(j)}(0) = 0 exactly for j < ``order`` and f_i > 0 just after 0 (Lemma 5.1, the
        caller's).  On a piece [theta_a, theta_b] of step k, f_i lies in p_k(Theta) plus the tail
        bound; on step 0 with order o > 0, f_i / theta^o lies in sum_{j >= o} c_j Theta^(j - o) plus the
        same bound (the tail is O(theta^J), J > o).  A piece the bound of :func:`_positive_on` does
        not show positive is halved, three times at most; more than ``max_steps`` steps: not tried
        (the search's)."""
        st = self.steps
        pieces = st.pieces(fmpq(0), end)
        if len(pieces) > max_steps:
            return False
        for k, a, b in pieces:
            cs = self.coefficients(k)[i]
            o = order if k == 0 else 0
            if o >= len(cs):
                return False
            h, t0 = st.length(k), st.start(k)
            with workprec(self.prec):
                p = arb_poly(cs[o:])
                rho = arb(0, (self._g1[i] * st.tail(k, 0)).upper())
                if not _positive_on(p, (a - t0) / h, (b - t0) / h, rho, 3):
                    return False
        return True

    def float_coefficients(self, i: int, k: int) -> list[float]:
        """The midpoints of row i's coefficients on step k (guesses only; per row: a root's
        Newton guess reads one row, and converting the whole step was 9 % of a 64-state run)."""
        key = (i, k)
        if key not in self._floats:
            self._floats[key] = [float(c.mid()) for c in self.coefficients(k)[i]]
        return self._floats[key]

    def _grid_values(self, k: int, rows: list[int], points: tuple) -> list:
        """Step k's ``rows`` at the grid ``points`` (indices into the GUESS_POINTS thetas), as
        53-bit balls, row after row: one product of the coefficients with a Vandermonde matrix (no
        float underflow for a row of 10^-400, and no numpy import).  Every term is kept: a row
        near 0 (10^-20 where the state is O(1)) needs all of them."""
        coeffs = self.coefficients(k)
        with workprec(53):
            C = arb_mat([coeffs[i] for i in rows])
            return (C * _vandermonde(len(coeffs[0]), points)).entries()

    def guess_crossings(self, a: float, b: float, only: list[int] | None = None) -> list[float | None]:
        """Float guesses of the first t in (a, b] where each row (of ``only``, default all) turns
        negative (None: not seen), step by step from a; the scan stops at the end of the first step
        where a row crosses (a later crossing of another row can only be an event if it is
        certified before the first, which the certified search of the others up to that root
        decides).  Every fourth point of the grid is looked at first; the three before the first
        such point where a row is negative, for that row only."""
        st = self.steps
        out: list[float | None] = [None] * len(self.rows)
        scan = set(range(len(self.rows)) if only is None else only)
        k = st.locate(fmpq(a) if isinstance(a, int) else _fmpq_of_float(a))
        while float(st.start(k)) < b:
            t0, h = float(st.start(k)), float(st.length(k))
            todo = sorted(i for i in scan if out[i] is None)
            vals = self._grid_values(k, todo, _COARSE) if todo else []
            Q = len(_COARSE)
            for r, i in enumerate(todo):
                for c, p in enumerate(_COARSE):
                    if vals[r * Q + c] < 0 and a < t0 + h * _GUESS_THETAS[p]:
                        fine = tuple(range(p - _STRIDE + 1, p))
                        before = [q for q, v in zip(fine, self._grid_values(k, [i], fine))
                                  if v < 0 and a < t0 + h * _GUESS_THETAS[q]]
                        t = t0 + h * _GUESS_THETAS[before[0] if before else p]
                        if t <= b:
                            out[i] = t
                        break
            if any(o is not None for o in out):
                return out
            k += 1
        return out


class TaylorSum:
    """One monitored row of a phase on Taylor steps, with the interface of
    :class:`~lcs_exact.roots.ExpSum` (see the module docstring)."""

    def __init__(self, rows: TaylorRows, i: int):
        self.rows, self.i = rows, i
        self.prec = rows.prec
        self.steps = rows.steps

    def values(self, t, orders: range) -> list[arb]:
        """[f^{(d)}(t) for d in orders], t a rational, a point or a ball (an enclosure over it)."""
        st = self.steps
        if isinstance(t, fmpq):
            k = st.locate(t)
            with workprec(self.prec):
                th = arb(t - st.start(k)) / arb(st.length(k))
            return self.rows.values(self.i, k, th, orders)
        lo, hi = dyadic_lower(t), dyadic_upper(t)
        out = None
        for k, a, b in st.pieces(lo, hi, spill=True):
            th = st.theta(k, arb(a).union(arb(b)) if (a, b) != (lo, hi) else t)
            vs = self.rows.values(self.i, k, th, orders)
            out = vs if out is None else [x.union(y) for x, y in zip(out, vs)]
        return out

    def value(self, t, d: int = 0) -> arb:
        """f^{(d)}(t)."""
        return self.values(t, range(d, d + 1))[0]

    def enclose(self, lo: fmpq, hi: fmpq, d: int = 0, sign_only: bool = False) -> arb:
        """An enclosure of f^{(d)} on [lo, hi]: the union of the Taylor forms
        (:func:`~lcs_exact.roots.taylor_form`) of its pieces on the grid of steps."""
        out = None
        for _, a, b in self.steps.pieces(lo, hi):
            v = taylor_form(self, a, b, d, sign_only)
            out = v if out is None else out.union(v)
            if sign_only and out.contains(0):
                return out  # its sign is undecided already: more pieces cannot decide it
        return out

    def sign_enclose(self, lo: fmpq, hi: fmpq, d: int = 0) -> arb:
        """An enclosure of f^{(d)} on [lo, hi], for its sign (no stiff terms to factor out: a
        stiff mode keeps the spectral path)."""
        return self.enclose(lo, hi, d, sign_only=True)

    def guess_root(self, lo: float, hi: float) -> float | None:
        """A float root in (lo, hi) where f decreases: Newton's method on the midpoints of the
        step's polynomial, safeguarded by bisection (a guess, checked before use)."""
        st = self.steps

        def f_df(t: float) -> tuple[float, float]:
            k = st.locate(_fmpq_of_float(t))
            row = self.rows.float_coefficients(self.i, k)
            h = float(st.length(k))
            th = (t - float(st.start(k))) / h
            return _horner(row, th), _horner_derivative(row, th) / h

        return newton_in_bracket(f_df, lo, hi, 100)


#: the points of a step the guesses look at (theta in (0, 1))
_GUESS_THETAS = [(p + GUESS_OFFSET) / GUESS_POINTS for p in range(GUESS_POINTS)]
#: the coarse points looked at first (every fourth), the fine ones only before a negative one
_STRIDE = 4
_COARSE = tuple(range(_STRIDE - 1, GUESS_POINTS, _STRIDE))
_VANDERMONDE: dict[tuple, arb_mat] = {}


def _vandermonde(J: int, points: tuple) -> arb_mat:
    """[theta_p^j] (J x len(points), 53-bit balls), kept per (J, points)."""
    key = (J, points)
    if key not in _VANDERMONDE:
        with workprec(53):
            _VANDERMONDE[key] = arb_mat([[arb(_GUESS_THETAS[p]) ** j for p in points] for j in range(J)])
    return _VANDERMONDE[key]


def _positive_on(p: arb_poly, lo: fmpq, hi: fmpq, rho: arb, depth: int) -> bool:
    """p + rho > 0 on [lo, hi] (rho a ball around 0): with q(u) = p(lo + (hi - lo) u), u in [0, 1],
    q >= q_0 + sum_{j >= 1} min(0, q_j) (a ball's product with a wide ball of theta would lose the
    signs: c_0 + c_3 theta^3 with every c_j > 0 is not shown positive by Horner on [0, 0.34]);
    the interval is halved ``depth`` times at most where that bound does not show it.  Horner on
    the ball of [lo, hi] is tried first: it encloses p over a superset, and far from 0 it shows the
    sign without the composition."""
    if p(arb(lo).union(arb(hi))) + rho > 0:
        return True
    q = p(arb_poly([arb(lo), arb(hi - lo)])).coeffs()
    if not q:  # p = 0 exactly: nothing shows p + rho > 0
        return False
    low = q[0] + rho
    for c in q[1:]:
        if not c > 0:
            low += arb(c.lower())
    if low > 0:
        return True
    if depth == 0:
        return False
    m = (lo + hi) / 2
    return _positive_on(p, lo, m, rho, depth - 1) and _positive_on(p, m, hi, rho, depth - 1)


def _horner(row: list[float], x: float) -> float:
    v = 0.0
    for c in reversed(row):
        v = v * x + c
    return v


def _horner_derivative(row: list[float], x: float) -> float:
    v = 0.0
    for j in range(len(row) - 1, 0, -1):
        v = v * x + j * row[j]
    return v


def _fmpq_of_float(x: float) -> fmpq:
    n, d = float(x).as_integer_ratio()
    return fmpq(n, d)

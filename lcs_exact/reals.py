"""Exact reals and exact vectors (DESIGN.md section 2, layer 2).

An exact real is an exact *definition* (rational, closed form, sum, component of e^{Mt} v,
isolated root of c . e^{Mt} z) that evaluates to an ``arb`` ball of any requested precision with
the true value inside.  Balls are cached (the most accurate one is kept) and refined on demand.

Composition is structural: e^{Ma}(e^{Mb} v) = e^{M(a+b)} v, and when a + b is proven 0 the
vector is v again; a rational matrix on a rational vector stays rational; a vector whose
components are proven rational collapses to ``fmpq_mat``.

Sign decisions on a state x (``ExactVector.sign_of_form``) go in this order:
1. x proven rational: exact;
2. the form lies in the rational span of the relations known to vanish on x (``zero_forms``:
   the annihilator of V_I along a phase of mode I, the left kernel of a projection, the
   constraint whose root defines an event time): exact zero by structure;
3. a ball that excludes 0, refined up to ``max_prec`` bits;
4. otherwise an *unresolved zero*: :class:`~lcs_exact.errors.UnresolvedSign`, or - inside
   :func:`assumption_policy` with ``allow=True`` - decided as zero and recorded.
"""
from __future__ import annotations

import abc
import contextlib
import contextvars
from typing import Any, Iterator

import sympy
from flint import arb, arb_mat, ctx, fmpq, fmpq_mat

from .errors import UnresolvedSign
from .rational import identity, is_zero, matrix_to_sympy, submatrix, to_fmpq, to_matrix, vstack, zeros

__all__ = ["Real", "RationalReal", "ClosedFormReal", "SumReal", "ExactVector", "RationalVector",
           "ExpVector", "ProjectedVector", "expm_action", "as_real", "as_exact_vector",
           "assumption_policy", "DEFAULT_MAX_PREC", "digits_to_bits"]

DEFAULT_MAX_PREC = 4096


def digits_to_bits(digits: int) -> int:
    return int(digits * 3.3219280948873626) + 1


@contextlib.contextmanager
def workprec(prec: int):
    """Scoped flint precision (ctx.prec is global): restored in ``finally``."""
    old = ctx.prec
    ctx.prec = prec
    try:
        yield
    finally:
        ctx.prec = old


# ---------------------------------------------------------------------------------------------
# the policy for unresolved zeros (scoped, not global)
# ---------------------------------------------------------------------------------------------

_policy: contextvars.ContextVar = contextvars.ContextVar("lcs_exact_sign_policy", default=None)


@contextlib.contextmanager
def assumption_policy(allow: bool, max_prec: int = DEFAULT_MAX_PREC):
    """Within the block, unresolved zeros raise (allow=False) or are assumed and recorded.

    Yields the list that collects the recorded assumptions (strings).
    """
    record: list[str] = []
    token = _policy.set({"allow": allow, "record": record, "max_prec": max_prec})
    try:
        yield record
    finally:
        _policy.reset(token)


_deadline: contextvars.ContextVar = contextvars.ContextVar("lcs_exact_deadline", default=None)


@contextlib.contextmanager
def deadline(seconds: float | None):
    """Within the block, :func:`check_deadline` raises LimitExceeded after ``seconds`` (wall clock)."""
    import time
    token = _deadline.set(None if seconds is None else (time.monotonic() + seconds, seconds))
    try:
        yield
    finally:
        _deadline.reset(token)


def check_deadline(where: str = "") -> None:
    """Raise LimitExceeded when the current :func:`deadline` has passed (called inside long
    searches, so a time limit also interrupts one hard phase, not only between events)."""
    d = _deadline.get()
    if d is not None:
        import time
        if time.monotonic() > d[0]:
            from .errors import LimitExceeded
            raise LimitExceeded(f"time_limit = {d[1]} s reached{where}")


def _max_prec() -> int:
    p = _policy.get()
    return p["max_prec"] if p else DEFAULT_MAX_PREC


def unresolved(what) -> int:
    """An unresolved zero: raise, or record the assumption that it is 0 and return 0.

    ``what`` is the description, or a callable making it (built only when needed).
    """
    what = what() if callable(what) else what
    p = _policy.get()
    if p and p["allow"]:
        if what not in p["record"]:
            p["record"].append(what)
        return 0
    raise UnresolvedSign(f"cannot decide the sign of {what}: the ball contains 0 at "
                         f"{_max_prec()} bits and no structural proof of zero is known")


def ball_sign(compute, what, start: int = 64) -> int:
    """Sign of a quantity given by ``compute(prec) -> arb``, certified by refinement; 0 if unresolved-and-allowed."""
    prec = start
    while True:
        check_deadline()
        b = compute(prec)
        if b > 0:
            return 1
        if b < 0:
            return -1
        if prec >= _max_prec():
            return unresolved(what)
        prec = min(2 * prec, _max_prec())


# ---------------------------------------------------------------------------------------------
# exact reals
# ---------------------------------------------------------------------------------------------


class Real(abc.ABC):
    """An exact real number: evaluates to an arb ball of any precision (true value inside)."""

    closed_form: Any = None  # SymPy expression when proven

    def __init__(self):
        self._ball: arb | None = None
        self._ball_prec = 0

    # evaluation ------------------------------------------------------------------------------
    @abc.abstractmethod
    def _eval(self, prec: int) -> arb:
        """A ball of the value computed at ``prec`` bits (subclasses)."""

    def arb(self, prec: int) -> arb:
        """A ball computed with working precision ``prec`` bits (cached)."""
        if self._ball is None or self._ball_prec < prec:
            with workprec(prec):
                b = self._eval(prec)
            if self._ball is None or b.rad() <= self._ball.rad():
                self._ball, self._ball_prec = b, prec
            else:
                self._ball_prec = prec
        return self._ball

    def ball(self, digits: int = 30) -> arb:
        """An arb ball containing the value with relative radius < 10^-digits (0 is exact)."""
        need = digits_to_bits(digits) + 4
        prec = max(64, need + 16)
        for _ in range(12):
            b = self.arb(prec)
            if b.is_exact() or (b.rel_accuracy_bits() >= need):
                return b
            if b.contains(0) and b.rad() < arb(2) ** (-need):
                return b  # a number that is (nearly) zero: absolute accuracy is what counts
            prec *= 2
        raise UnresolvedSign(f"could not evaluate {self!r} to {digits} digits")

    def decimal(self, digits: int = 30) -> str:
        """The value to ``digits`` significant digits, followed by an error bound ``+/- e``."""
        b = self.ball(digits + 2)
        q = self.rational()
        if q is not None:
            return _decimal_of_fmpq(q, digits)
        return _decimal_of_ball(b, digits)

    def __float__(self) -> float:
        return float(self.ball(20).mid())

    # structure -------------------------------------------------------------------------------
    def rational(self) -> fmpq | None:
        """The value as fmpq when it is proven rational, else None."""
        cf = self.closed_form
        if cf is not None and getattr(cf, "is_Rational", False):
            return fmpq(int(cf.p), int(cf.q))
        return None

    def sign(self) -> int:
        """Certified sign (-1, 0, +1); a zero must be proven (rational or closed form)."""
        q = self.rational()
        if q is not None:
            return (q > 0) - (q < 0)
        if self.closed_form is not None and self.closed_form == 0:
            return 0
        return ball_sign(self.arb, lambda: f"the real {self!r}")

    def __add__(self, o):
        return SumReal(self, as_real(o))

    def __radd__(self, o):
        return SumReal(as_real(o), self)

    def __sub__(self, o):
        return SumReal(self, as_real(o), -1)

    def __rsub__(self, o):
        return SumReal(as_real(o), self, -1)

    def __lt__(self, o):
        return (self - o).sign() < 0

    def __le__(self, o):
        return (self - o).sign() <= 0

    def __gt__(self, o):
        return (self - o).sign() > 0

    def __ge__(self, o):
        return (self - o).sign() >= 0

    def __repr__(self):
        if self.closed_form is not None:
            return f"Real({self.closed_form})"
        return f"Real({self.decimal(20)})"

    def _repr_latex_(self):
        if self.closed_form is not None:
            return f"${sympy.latex(self.closed_form)}$"
        return f"${self.decimal(20)}$"


class RationalReal(Real):
    """A rational number."""

    def __init__(self, q: Any):
        super().__init__()
        self.q = to_fmpq(q)
        self.closed_form = sympy.Rational(int(self.q.p), int(self.q.q))

    def _eval(self, prec):
        return arb(self.q)

    def rational(self):
        return self.q


class ClosedFormReal(Real):
    """A real given by a SymPy expression built from rationals, pi, E, +, *, rational powers,
    exp, log, sin, cos, tan, atan, asin, acos, sqrt (evaluated rigorously with arb)."""

    def __init__(self, expr: Any):
        super().__init__()
        self.closed_form = sympy.nsimplify(expr) if isinstance(expr, float) else sympy.sympify(expr)
        _sympy_to_arb(self.closed_form)  # validate now: raises for unsupported expressions

    def _eval(self, prec):
        return _sympy_to_arb(self.closed_form)


class SumReal(Real):
    """a + sign * b."""

    def __init__(self, a: Real, b: Real, sign: int = 1):
        super().__init__()
        self.a, self.b, self.s = a, b, sign
        if a.closed_form is not None and b.closed_form is not None:
            self.closed_form = sympy.simplify(a.closed_form + sign * b.closed_form)

    def _eval(self, prec):
        if self.closed_form is not None:
            return _sympy_to_arb(self.closed_form)
        a, b = self.a.arb(prec), self.b.arb(prec)
        return a + b if self.s == 1 else a - b


def as_real(x: Any) -> Real:
    """An exact real from a Real, a rational-like value or a SymPy expression."""
    if isinstance(x, Real):
        return x
    if isinstance(x, sympy.Basic):
        if x.is_Rational:
            return RationalReal(fmpq(int(x.p), int(x.q)))
        return ClosedFormReal(x)
    return RationalReal(x)


_ARB_FUNCS = {
    sympy.exp: lambda a: a.exp(), sympy.log: lambda a: a.log(), sympy.sin: lambda a: a.sin(),
    sympy.cos: lambda a: a.cos(), sympy.tan: lambda a: a.tan(), sympy.atan: lambda a: a.atan(),
    sympy.asin: lambda a: a.asin(), sympy.acos: lambda a: a.acos(),
    sympy.sinh: lambda a: a.sinh(), sympy.cosh: lambda a: a.cosh(), sympy.tanh: lambda a: a.tanh(),
    sympy.atanh: lambda a: a.atanh(), sympy.asinh: lambda a: a.asinh(),
}


def _sympy_to_arb(e) -> arb:
    """Rigorous arb value of a SymPy expression at the current precision."""
    if e.is_Rational:
        return arb(fmpq(int(e.p), int(e.q)))
    if e is sympy.pi:
        return arb.pi()
    if e is sympy.E:
        return arb(1).exp()
    if e.is_Add:
        out = arb(0)
        for a in e.args:
            out += _sympy_to_arb(a)
        return out
    if e.is_Mul:
        out = arb(1)
        for a in e.args:
            out *= _sympy_to_arb(a)
        return out
    if e.is_Pow:
        base, ex = e.args
        b = _sympy_to_arb(base)
        if ex.is_Integer:
            return b ** int(ex)
        if ex.is_Rational:
            return b ** arb(fmpq(int(ex.p), int(ex.q)))
        return (b.log() * _sympy_to_arb(ex)).exp()
    f = _ARB_FUNCS.get(e.func)
    if f is not None and len(e.args) == 1:
        return f(_sympy_to_arb(e.args[0]))
    raise ValueError(f"closed form {e} is outside the supported set (rationals, pi, E, +, *, powers, "
                     f"exp, log, trigonometric functions)")


def _bound_up(err) -> str:
    """A 3-digit decimal >= err (nstr rounds to nearest, within 0.5%: scale by 1.01 first)."""
    from mpmath import mpf, nstr
    return nstr(err * mpf("1.01"), 3) if err else "0"


def _decimal_of_fmpq(q: fmpq, digits: int) -> str:
    """q to ``digits`` significant digits; exact strings stand alone, rounded ones carry a bound."""
    from fractions import Fraction
    from mpmath import mp, mpf, nstr
    if q.q == 1 and len(str(abs(int(q.p)))) <= digits:
        return str(int(q.p))  # an integer is exact as it stands ("0", not "0.0")
    with mp.workdps(digits + 10):
        text = nstr(mpf(int(q.p)) / int(q.q), digits, strip_zeros=True)
        err = abs(Fraction(text) - Fraction(int(q.p), int(q.q)))
        return text if err == 0 else f"{text} +/- {_bound_up(mpf(err.numerator) / err.denominator)}"


def _decimal_of_ball(b: arb, digits: int) -> str:
    """mid rounded to ``digits`` significant digits, with an upper bound on the total error."""
    from mpmath import mp, mpf, nstr
    mid = b.mid()
    with mp.workdps(digits + 20):
        m = mpf(mid.str(digits + 15, radius=False)) if not mid.is_zero() else mpf(0)
        s = nstr(m, digits, strip_zeros=False, min_fixed=-5, max_fixed=digits + 1)
        err = abs(mpf(s) - m) + mpf(b.rad().str(5, radius=False)) * 2 + abs(m) * mpf(10) ** (-(digits + 12))
        return f"{s} +/- {_bound_up(err)}"


# ---------------------------------------------------------------------------------------------
# exact vectors
# ---------------------------------------------------------------------------------------------


class ExactVector(abc.ABC):
    """An exact vector in R^n: evaluates to an arb_mat (n x 1) ball of any precision.

    ``zero_forms`` (an m x n fmpq_mat) are linear forms proven to vanish on the vector.
    """

    n: int

    def __init__(self, n: int, zero_forms: fmpq_mat | None = None):
        self.n = n
        self.zero_forms = zero_forms if zero_forms is not None else zeros(0, n)
        self._ball: arb_mat | None = None
        self._ball_prec = 0

    @abc.abstractmethod
    def _eval(self, prec: int) -> arb_mat:
        """A ball vector computed at ``prec`` bits (subclasses)."""

    def arb(self, prec: int) -> arb_mat:
        if self._ball is None or self._ball_prec < prec:
            with workprec(prec):
                self._ball = self._eval(prec)
            self._ball_prec = prec
        return self._ball

    def rational(self) -> fmpq_mat | None:
        """The vector as n x 1 fmpq_mat when proven rational."""
        return None

    def closed_form(self, derive: bool = True):
        """A SymPy column vector when every component has a proven closed form, else None.

        ``derive=False`` returns only what is already known (cheap); True may derive it with
        SymPy (e^{Mt} symbolically: up to a second for a new matrix)."""
        return None

    def __len__(self):
        return self.n

    def __getitem__(self, i: int) -> Real:
        return ComponentReal(self, i)

    def __iter__(self) -> Iterator[Real]:
        return (ComponentReal(self, i) for i in range(self.n))

    def tolist(self) -> list[Real]:
        return list(self)

    def ball(self, digits: int = 30) -> list[arb]:
        return [c.ball(digits) for c in self]

    def sign_of_form(self, form: fmpq_mat) -> int:
        """Certified sign of form . x (see the module docstring for the order of the tests)."""
        q = self.rational()
        if q is not None:
            v = (form * q)[0, 0]
            return (v > 0) - (v < 0)
        if is_zero(form):
            return 0
        if self.zero_forms.nrows() and _in_row_span(form, self.zero_forms):
            return 0
        return ball_sign(lambda p: (arb_mat(form) * self.arb(p))[0, 0],
                         lambda: f"the form {_fmt_form(form)} at {self!r}")

    def __repr__(self):
        q = self.rational()
        if q is not None:
            return "(" + ", ".join(str(q[i, 0]) for i in range(self.n)) + ")"
        return "(" + ", ".join(str(c.closed_form) if c.closed_form is not None and c.closed_form.is_Rational
                               else c.decimal(12).split(" +/-")[0] for c in self) + ")"


class ComponentReal(Real):
    """Component i of an exact vector."""

    def __init__(self, vec: ExactVector, i: int):
        super().__init__()
        self.vec, self.i = vec, i
        q = vec.rational()
        if q is not None:
            self.closed_form = sympy.Rational(int(q[i, 0].p), int(q[i, 0].q))
        else:
            cf = vec.closed_form(derive=False)
            if cf is not None:
                self.closed_form = cf[i]
            elif vec.zero_forms.nrows():
                e = fmpq_mat(1, vec.n, [int(j == i) for j in range(vec.n)])
                if _in_row_span(e, vec.zero_forms):  # x_i = 0 is a proven relation
                    self.closed_form = sympy.Integer(0)

    def _eval(self, prec):
        if self.closed_form is not None and self.closed_form == 0:
            return arb(0)
        return self.vec.arb(prec)[self.i, 0]


class RationalVector(ExactVector):
    """A rational vector (n x 1 fmpq_mat)."""

    def __init__(self, q: fmpq_mat):
        super().__init__(q.nrows())
        self.q = q

    def _eval(self, prec):
        return arb_mat(self.q)

    def rational(self):
        return self.q

    def closed_form(self, derive: bool = True):
        return sympy.Matrix([sympy.Rational(int(self.q[i, 0].p), int(self.q[i, 0].q)) for i in range(self.n)])


class ProjectedVector(ExactVector):
    """P v for a rational matrix P (a projection P_I); r P = 0 rows are zero forms."""

    def __init__(self, P: fmpq_mat, v: ExactVector):
        super().__init__(P.nrows(), pulled_back_forms(P, v.zero_forms))
        self.P, self.v = P, v

    def _eval(self, prec):
        return arb_mat(self.P) * self.v.arb(prec + 4)

    def closed_form(self, derive: bool = True):
        """P times the closed form of v (exact: P is rational), when v has one."""
        cache = self.__dict__.setdefault("_closed", {})
        if False not in cache:  # the known form: a simplified state (simplify detects rationals)
            cf = self.v.closed_form(derive=False)
            cache[False] = None if cf is None else \
                (matrix_to_sympy(self.P) * cf).applyfunc(sympy.simplify)
        if not derive or cache[False] is not None:
            return cache[False]
        if True not in cache:  # derived forms are large and exact as they stand: no simplify
            cf = self.v.closed_form(derive=True)
            cache[True] = None if cf is None else matrix_to_sympy(self.P) * cf
        return cache[True]

    def rational(self):
        c = self.closed_form(derive=False)
        if c is not None and all(e.is_Rational for e in c):
            return fmpq_mat(self.n, 1, [fmpq(int(e.p), int(e.q)) for e in c])
        return None


class ExpVector(ExactVector):
    """e^{M t} v: M rational, t an exact real, v an exact vector (or rational)."""

    def __init__(self, M: fmpq_mat, t: Real, v: ExactVector, zero_forms: fmpq_mat | None = None,
                 closed: Any = None):
        super().__init__(M.nrows(), zero_forms)
        self.M, self.t, self.v = M, t, v
        self._closed = closed

    def _eval(self, prec):
        # same precision below: arb tracks the loss; callers escalate when a ball is too wide
        t = self.t.arb(prec + 4)
        return expm_apply(self.M, t, self.v.arb(prec + 4), prec)

    def closed_form(self, derive: bool = True):
        """e^{Mt} v in closed form when t and v have one and e^{Mt} is symbolic (flow.expm_symbolic);
        exact by construction (not simplified: SymPy's simplify costs seconds here)."""
        if derive and self._closed is None and not getattr(self, "_tried", False):
            self._tried = True
            vc = self.v.closed_form() if self.t.closed_form is not None else None
            if vc is not None:
                from .flow import _t, expm_symbolic
                E = expm_symbolic(self.M)
                if E is not None:
                    self._closed = E.subs(_t, self.t.closed_form) * vc
        return self._closed

    def rational(self):
        c = self._closed
        if c is not None and all(e.is_Rational for e in c):
            return fmpq_mat(self.n, 1, [fmpq(int(e.p), int(e.q)) for e in c])
        return None


# e^{Mt} v by the spectral sum: no norm blow-up for stiff or oscillatory M, where the error
# bounds of arb_mat.exp grow like e^{||M|| t}
_SPECTRAL: dict = {}


def _poly_at_matrix(p, S: fmpq_mat) -> fmpq_mat:
    """p(S) for p in Q[s] (Horner), exactly."""
    n = S.nrows()
    out = zeros(n, n)
    for c in reversed(p.coeffs()):
        out = out * S + identity(n) * c
    return out


def jordan_chevalley(M: fmpq_mat, r=None) -> tuple[fmpq_mat, fmpq_mat, int]:
    """(S, N, m): M = S + N with S semisimple, N nilpotent (N^m = 0), SN = NS, both exact.

    S is a polynomial in M found by Newton's iteration S <- S - r(S) r'(S)^{-1} on the squarefree
    part r of χ (exact in Q[M]; quadratic convergence, so about log2(max multiplicity) steps)."""
    chi = M.charpoly()
    if r is None:
        r = chi.gcd(chi.derivative())
        r = chi / r
    r = r / r.coeffs()[-1]
    dr = r.derivative()
    S = M
    for _ in range(M.nrows() + 1):
        rS = _poly_at_matrix(r, S)
        if is_zero(rS):
            break
        S = S - rS * _poly_at_matrix(dr, S).inv()
    N = M - S
    m, P = 1, N
    while not is_zero(P):
        P, m = P * N, m + 1
    return S, N, m


def _spectral_data(M: fmpq_mat, prec: int):
    """[(λ, K_λ)], the nilpotent powers [N^j / j!] with e^{Mt} = Σ_λ e^{λt} K_λ Σ_j t^j N^j / j!.

    M = S + N (Jordan-Chevalley); r = the squarefree part of χ, the minimal polynomial of S;
    K_λ = q_λ(S) / r'(λ) with q_λ(s) = r(s) / (s - λ) (the spectral projector of S onto the
    eigenvalue λ; adj(λI - M)/χ'(λ) when χ is squarefree)."""
    from flint import acb, acb_mat
    from .system import adjugate_coefficients
    key = (M.nrows(), tuple(str(e) for e in M.entries()))
    entry = _SPECTRAL.get(key)
    if entry is None:
        chi = M.charpoly()
        g = chi.gcd(chi.derivative())
        if g.degree() == 0:
            S, N, m, r = M, zeros(M.nrows(), M.nrows()), 1, chi
        else:
            r = chi / g
            r = r / r.coeffs()[-1]
            S, N, m = jordan_chevalley(M, r)
        nil, P, fact = [], identity(M.nrows()), 1
        for j in range(m):
            if j:
                P, fact = P * N, fact * j
            nil.append(P * fmpq(1, fact))
        entry = _SPECTRAL[key] = {"r": r, "dr": r.derivative(), "B": adjugate_coefficients(S, r),
                                  "nil": nil}
    cached = entry.get("prec", 0)
    if cached < prec:
        with workprec(prec + 20):
            n = M.nrows()
            out = []
            for lam, _ in entry["r"].complex_roots():
                q = acb_mat(n, n)
                for B in entry["B"]:  # Horner in λ
                    q = q * lam + acb_mat(B)
                d = acb(0)
                for c in reversed(entry["dr"].coeffs()):
                    d = d * lam + acb(c)
                out.append((lam, q * (1 / d)))
        entry["terms"], entry["nil_arb"], entry["prec"] = out, [arb_mat(P) for P in entry["nil"]], prec
    return entry["terms"], entry["nil_arb"]


def expm_apply(M: fmpq_mat, t: arb, z: arb_mat, prec: int) -> arb_mat:
    """A ball of e^{M t} z (z: n x m; t a ball, possibly wide: an enclosure over an interval)."""
    if M.nrows() == 0:
        return z
    from flint import acb, acb_mat
    terms, nil = _spectral_data(M, prec)
    w = nil[0] * z if len(nil) == 1 else sum((P * z * t ** j for j, P in enumerate(nil[1:], 1)), nil[0] * z)
    zc = acb_mat(w)
    acc = acb_mat(M.nrows(), z.ncols())
    tc = acb(t)
    for lam, K in terms:
        acc += (K * zc) * (lam * tc).exp()
    return arb_mat([[acc[i, j].real for j in range(z.ncols())] for i in range(M.nrows())])


def as_exact_vector(x: Any, n: int | None = None) -> ExactVector:
    """An ExactVector from an ExactVector, an fmpq_mat column or any vector input."""
    if isinstance(x, ExactVector):
        q = x.rational()
        return RationalVector(q) if q is not None and not isinstance(x, RationalVector) else x
    if isinstance(x, fmpq_mat):
        return RationalVector(x if x.ncols() == 1 else x.transpose())
    from .rational import to_vector
    flat = list(x.tolist() if hasattr(x, "tolist") else x)
    return RationalVector(to_vector(flat, len(flat) if n is None else n))


def pulled_back_forms(P: fmpq_mat, Z: fmpq_mat) -> fmpq_mat:
    """Rows r with r P in rowspan(Z): the forms that vanish on P v whenever Z v = 0."""
    from .rational import hstack
    from .subspaces import image, kernel, left_kernel
    m = P.nrows()
    if not Z.nrows():
        return left_kernel(P)
    k = kernel(hstack(P.transpose(), -Z.transpose()))  # (r, s) with P^T r = Z^T s
    if not k.ncols():
        return zeros(0, m)
    r = submatrix(k, range(m), None)
    return image(r).transpose()


def invariant_forms(R: fmpq_mat, M: fmpq_mat) -> fmpq_mat:
    """The largest subspace U of rowspan(R) with U M ⊆ U (rows): R x = 0 => U e^{Mt} x = 0."""
    from .rational import hstack
    from .subspaces import image, kernel
    n = M.nrows()
    U = image(R.transpose()).transpose() if R.nrows() else zeros(0, n)
    while U.nrows():
        # a U M in span(U): kernel of [ (U M)^T, -U^T ] in (a, b)
        d = U.nrows()
        k = kernel(hstack((U * M).transpose(), -U.transpose()))
        a = submatrix(k, range(d), None) if k.ncols() else zeros(d, 0)
        newU = image((a.transpose() * U).transpose()).transpose() if a.ncols() else zeros(0, n)
        if newU.nrows() == U.nrows():
            return U
        U = newU
    return U


def orbit_zero_forms(M: fmpq_mat, q: fmpq_mat) -> fmpq_mat:
    """Every form g with g e^{Mt} q ≡ 0: the left kernel of the Krylov matrix [q, Mq, ...,
    M^{n-1} q] (Cayley-Hamilton), exact."""
    from .rational import hstack
    from .subspaces import left_kernel
    cols, v = [], q
    for _ in range(M.nrows()):
        cols.append(v)
        v = M * v
    return left_kernel(hstack(*cols))


def expm_action(M: Any, t: Any, v: Any) -> ExactVector:
    """e^{M t} v as an exact vector (M, v: any matrix/vector input LCS accepts; t exact).

    Composes structurally: expm_action(M, a, expm_action(M, b, v)) = e^{M(a+b)} v, and is v
    itself (rational again) when a + b is proven 0.

    >>> x0 = expm_action([[0, 1], [-1, 0]], -1, [1, 0])
    >>> expm_action([[0, 1], [-1, 0]], 1, x0).rational().transpose()
    [1, 0]
    """
    M = to_matrix(M, "M")
    if M.nrows() != M.ncols():
        from .errors import ShapeError
        raise ShapeError(f"M must be square, got {M.nrows()}x{M.ncols()}")
    t = as_real(t)
    v = as_exact_vector(v, M.nrows())
    if isinstance(v, ExpVector) and v.M == M:
        t, v = t + v.t, v.v
    if t.closed_form is not None and t.closed_form == 0:
        return v
    q = v.rational()
    if q is not None and is_zero(M * q):  # an equilibrium: e^{Mt} v = v
        return v
    if q is not None:  # forms vanishing on the whole orbit e^{Ms} q (e.g. coordinates M leaves at 0)
        zf = orbit_zero_forms(M, q)
    else:
        zf = invariant_forms(v.zero_forms, M) if v.zero_forms.nrows() else None
    return ExpVector(M, t, v, zf)


def _in_row_span(form: fmpq_mat, R: fmpq_mat) -> bool:
    from .subspaces import rank
    return rank(vstack(R, form)) == rank(R)


def _fmt_form(form: fmpq_mat) -> str:
    return "(" + ", ".join(str(form[0, j]) for j in range(form.ncols())) + ")"


"""Exact reals and exact vectors (docs/numerics.md).

An exact real (:class:`Real`) or vector (:class:`ExactVector`) is an immutable exact
*definition* - a rational, a sum, a component, e^{Mt} v, P v, a positive multiple c q, or a root
of an exponential sum (:mod:`lcs_exact.roots`) - that evaluates to an ``arb`` ball of any
requested precision with the true value inside.

Anchors and evaluation.  Every node caches its best ball and the precision it was computed at (an
*anchor*).  ``node.arb(prec)`` evaluates the definitions it depends on in a loop over an explicit
stack, walking forward from the nearest anchors at >= prec bits (or exact leaves), never by
recursion: a state after 10,000 events is evaluated in O(10,000) steps and cannot exhaust the
Python stack, and a state whose anchor is good enough costs nothing.  The simulation anchors each
event at its working precision (:meth:`lcs_exact.balls.Policy.working_prec`).

Signs.  ``x.sign_of_form(g)`` decides the sign of g . x, in this order (docs/numerics.md):
exact when x is proven rational; 0 when g lies in the rational span of the forms proven to vanish
on x (``zero_forms``: the annihilator of V_I along a phase, forms vanishing on the orbit of a
rational phase start, the constraint whose root ended the phase, all pulled back through
projections); by homogeneity (x = c q with c > 0 certified and q structured: the sign of g q);
then a ball that excludes 0, an exact zero test of the closed form (``prove_zero``: Calcium) and
refinement up to the policy's ceiling; otherwise an *unresolved zero*
(:meth:`~lcs_exact.balls.Policy.unresolved`).

Closed forms are lazy: ``r.closed_form`` (a SymPy expression, for display) is derived on first
access; nothing on the evaluation path imports SymPy.
"""
from __future__ import annotations

import abc
from typing import Any, Callable, Iterator

from flint import arb, arb_mat, fmpq, fmpq_mat

from . import calcium
from .balls import (DEFAULT_POLICY, MAX_DIGITS, Policy, accuracy_bits, closed_form_arb, decide_sign,
                    digits_to_bits, dyadic_lower, dyadic_upper, long_int_strings, workprec)
from .errors import LCSError, NotRational, ShapeError, UnresolvedSign
from .expm import Spectrum, spectrum_of, symbolic_expm, t_symbol
from .forms import Closed, ca_of_sympy
from .rational import is_zero, matrix_to_sympy, to_fmpq, to_int, to_matrix, to_vector, vector_entries, zeros
from .subspaces import RowSpan, invariant_forms, kernel, orbit_zero_forms, pulled_back_forms, row_basis

__all__ = ["Real", "RationalReal", "SumReal", "ScaledReal", "ClosedFormReal", "ComponentReal",
           "AlgebraicReal", "ExactVector", "RationalVector", "ScaledVector", "ExpVector", "ProjectedVector",
           "ComponentsVector", "AlgebraicVector", "algebraic_vector", "ca_matvec", "radical_form", "as_real", "as_exact_vector", "expm_action", "evaluate",
           "homogenized", "orbit_start", "format_form", "decimal_of_fmpq", "decimal_of_ball"]


# ---------------------------------------------------------------------------------------------
# nodes and their iterative evaluation
# ---------------------------------------------------------------------------------------------

#: an anchor computed at >= prec - ANCHOR_SLACK bits serves a request for prec bits
ANCHOR_SLACK = 64


class _Node:
    """A definition with a cached ball (the anchor) and the definitions it depends on."""

    def __init__(self, policy: Policy | None = None):
        self._ball = None
        self._prec = 0
        self.policy = policy or DEFAULT_POLICY

    def _deps(self) -> tuple:
        """The nodes whose balls at the same precision :meth:`_compute` reads."""
        return ()

    def __getstate__(self):
        # Calcium numbers do not pickle: drop the caches that hold them (rebuilt on demand)
        state = dict(self.__dict__)
        if "_ca" in state:
            state["_ca"], state["_ca_done"] = None, False
        return state

    @abc.abstractmethod
    def _compute(self, prec: int):
        """The ball at ``prec`` bits, assuming every dependency has a ball at >= prec bits."""

    def _store(self, ball, prec: int) -> None:
        if self._ball is None or _radius_le(ball, self._ball):
            self._ball = ball
        self._prec = max(self._prec, prec)

    @property
    def anchor_prec(self) -> int:
        """The working precision of the cached ball (0 when none is cached)."""
        return self._prec

    def arb(self, prec: int):
        """A ball computed at working precision >= ``prec - ANCHOR_SLACK`` bits (cached; the true
        value inside).  The slack lets a run whose working precision grows by a bit or two per
        event reuse the anchors of earlier events instead of re-evaluating the whole history;
        callers that need more accuracy double ``prec``, which forces a real refinement."""
        if self._prec < prec - ANCHOR_SLACK or self._ball is None:
            evaluate(self, prec)
        return self._ball


def _radius_le(a, b) -> bool:
    if isinstance(a, arb):
        return a.rad() <= b.rad()
    ra = max((a[i, j].rad() for i in range(a.nrows()) for j in range(a.ncols())), default=arb(0))
    rb = max((b[i, j].rad() for i in range(b.nrows()) for j in range(b.ncols())), default=arb(0))
    return ra <= rb


def evaluate(node: _Node, prec: int) -> None:
    """Give ``node`` a ball at ``prec`` bits, and every definition it needs one at >= prec -
    ANCHOR_SLACK bits, in a loop: post-order over an explicit stack, stopping at the anchors
    that are good enough (walking forward from the nearest anchor, never by recursion).  The
    policy's deadline is checked every 64 nodes (a walk over a long history stops in time)."""
    stack: list = [(node, False)]
    steps = 0
    while stack:
        steps += 1
        if steps % 64 == 0:
            node.policy.check_deadline(" while evaluating a long definition")
        cur, ready = stack.pop()
        if cur is not node and cur._prec >= prec - ANCHOR_SLACK and cur._ball is not None:
            continue
        if ready:
            with workprec(prec):
                cur._store(cur._compute(prec), prec)
            continue
        stack.append((cur, True))
        for d in cur._deps():
            if d._prec < prec - ANCHOR_SLACK or d._ball is None:
                stack.append((d, False))


# ---------------------------------------------------------------------------------------------
# exact reals
# ---------------------------------------------------------------------------------------------


class Real(_Node):
    """An exact real number: evaluates to an arb ball of any precision (true value inside)."""

    _cf_done = False
    _cf = None

    # --- structure ----------------------------------------------------------------------------
    def known_rational(self) -> fmpq | None:
        """The value as fmpq when it is already known to be rational (cheap: never derives a
        closed form; the engine's fast paths use this)."""
        return None

    def rational(self) -> fmpq | None:
        """The value as fmpq when it is proven rational, deriving the closed form if needed
        (lazy, like ``closed_form``); None when it is not proven rational."""
        q = self.known_rational()
        if q is None and self.policy.closed_forms != "off":
            cf = self.closed
            if cf is not None and cf.is_rational:
                q = cf.to_fmpq()
        return q

    @property
    def closed(self) -> Closed | None:
        """The proven closed form as a light :class:`~lcs_exact.forms.Closed` (derived on first
        access, without SymPy for the common forms), else None."""
        if not self._cf_done:
            self._cf = None if self.policy.closed_forms == "off" else self._closed()
            self._cf_done = True
        return self._cf

    def _closed(self) -> Closed | None:
        expr = self._closed_form()  # subclasses that build SymPy expressions
        return None if expr is None else Closed.of_sympy(expr)

    @property
    def closed_form(self):
        """A SymPy expression of the value when proven (derived on first access), else None."""
        cf = self.closed
        return None if cf is None else cf.to_sympy()

    def _closed_form(self):
        return None

    @property
    def known_closed_form(self):
        """The closed form (SymPy) if it has already been derived (never derives one), else None."""
        return self._cf.to_sympy() if self._cf_done and self._cf is not None else None

    def to_ca(self):
        """The value as a Calcium number (exact), or None when no closed form is known."""
        return None

    def known_ca(self):
        """The value as a Calcium number when it is already known exactly as a rational or an
        algebraic number (cheap: never derives a closed form), else None."""
        q = self.known_rational()
        if q is not None:
            return calcium.Ca(q) if calcium.available() else None
        return None

    # --- evaluation ---------------------------------------------------------------------------
    def ball(self, digits: int = 30) -> arb:
        """An arb ball containing the value with relative radius < 10^-digits (absolute for a
        value that is zero or below 10^-digits).  Bounded by the run's ``time_limit`` (a
        :class:`~lcs_exact.errors.LimitExceeded` instead of a hang)."""
        digits = to_int(digits, "digits", 1, MAX_DIGITS)
        with self.policy.deadline.query():
            return self._refined(digits)

    def _refined(self, digits: int) -> arb:
        need = digits_to_bits(digits) + 4
        q = self.known_rational()
        if q is not None:  # exact (or rounded to far more than the digits asked)
            with workprec(need + 64):
                return arb(q)
        prec = max(self._prec, need + 16)
        for _ in range(16):
            self.policy.check_deadline(lambda: f" while evaluating a number to {digits} digits")
            b = self.arb(prec)
            if b.is_exact() or accuracy_bits(b) >= need:
                return b
            if b.contains(0) and b.rad() < arb(2) ** (-need):
                return b
            prec *= 2
        raise UnresolvedSign(f"could not evaluate {self!r} to {digits} digits")

    def decimal(self, digits: int = 30) -> str:
        """The value to ``digits`` significant digits, followed by an error bound ``+/- e``
        unless it is exact."""
        digits = to_int(digits, "digits", 1, MAX_DIGITS)
        q = self.known_rational()
        if q is None and self._cf_done and self._cf is not None and self._cf.is_rational:
            q = self._cf.to_fmpq()  # a closed form already proven rational
        if q is not None:
            return decimal_of_fmpq(q, digits)
        return decimal_of_ball(self.ball(min(digits + 2, MAX_DIGITS)), digits)  # the bound covers the rest

    def __float__(self) -> float:
        return float(self.ball(20).mid())

    def sign(self) -> int:
        """Certified sign (-1, 0, +1); a zero must be proven (rational or closed form)."""
        q = self.known_rational()
        if q is not None:
            return (q > 0) - (q < 0)
        c = self.known_ca()
        if c is not None:  # an algebraic number: Calcium decides its sign exactly
            s = c.sign()
            if s is not None:
                return s
        with self.policy.deadline.query():
            return decide_sign(self.arb, policy=self.policy, what=lambda: f"the real {self!r}",
                               start=max(64, self._prec), prove_zero=self._prove_zero)

    def _prove_zero(self) -> bool | None:
        c = self.to_ca()
        return None if c is None else c.is_zero()

    # --- arithmetic ---------------------------------------------------------------------------
    def __add__(self, o):
        return SumReal(self, as_real(o))

    def __radd__(self, o):
        return SumReal(as_real(o), self)

    def __sub__(self, o):
        return SumReal(self, as_real(o), -1)

    def __rsub__(self, o):
        return SumReal(as_real(o), self, -1)

    def __neg__(self):
        return ScaledReal(self, fmpq(-1))

    def __mul__(self, o):
        return ScaledReal(self, to_fmpq(o, "factor"))

    __rmul__ = __mul__

    def __truediv__(self, o):
        q = to_fmpq(o, "divisor")
        if q == 0:
            raise ZeroDivisionError("division of an exact real by 0")
        return ScaledReal(self, 1 / q)

    def __lt__(self, o):
        return (self - o).sign() < 0

    def __le__(self, o):
        return (self - o).sign() <= 0

    def __gt__(self, o):
        return (self - o).sign() > 0

    def __ge__(self, o):
        return (self - o).sign() >= 0

    # --- display ------------------------------------------------------------------------------
    def label(self) -> str:
        """Short text: the known closed form or rational, else 15 digits (never derives one)."""
        q = self.known_rational()
        if q is not None:
            return str(q)
        if self._cf_done and self._cf is not None:
            return str(self._cf)
        return self.decimal(15).split(" +/-")[0]

    def __repr__(self):
        # a repr never derives a closed form (that may run a proof): a known one, else digits
        cf = self._cf if self._cf_done else None
        if cf is not None:
            return f"Real({cf})"
        q = self.known_rational()
        if q is not None:
            return f"Real({q})"
        return f"Real({self.decimal(20)})"

    def _repr_latex_(self):
        cf = self.closed_form
        if cf is not None:
            import sympy
            return f"${sympy.latex(cf)}$"
        return "$" + self.decimal(20).replace(" +/- ", r" \pm ") + "$"


class RationalReal(Real):
    """A rational number."""

    def __init__(self, q: Any, policy: Policy | None = None):
        super().__init__(policy)
        self.q = to_fmpq(q)
        if self.q.q == 1:  # an integer is an exact ball at every precision
            self._ball, self._prec = arb(self.q), 1 << 30

    def _compute(self, prec):
        return arb(self.q)

    def known_rational(self):
        return self.q

    def _closed(self):
        return Closed.rational(self.q)

    def to_ca(self):
        return calcium.Ca(self.q) if calcium.available() else None


def linear_terms(r: Real) -> tuple[fmpq, list[tuple[fmpq, Real]]]:
    """r = c + sum q_j r_j with rationals c, q_j and reals r_j that are neither sums, multiples
    nor known rationals, found in a loop (an event time after 10,000 events is a sum of 10,000
    roots: no recursion)."""
    const, out = fmpq(0), []
    stack: list = [(fmpq(1), r)]
    while stack:
        q, x = stack.pop()
        if isinstance(x, SumReal):
            stack.append((q, x.a))
            stack.append((q * x.s, x.b))
        elif isinstance(x, ScaledReal):
            stack.append((q * x.q, x.a))
        else:
            v = x.known_rational()
            if v is not None:
                const += q * v
            else:
                out.append((q, x))
    return const, out


class _Linear(Real):
    """A rational linear combination of reals (sums and multiples): closed forms, Calcium numbers
    and rationality are derived from :func:`linear_terms`, never by recursion.  When the parts
    are exact algebraic numbers, so is the combination: its Calcium number is formed at
    construction from theirs (``_kca``, O(1) per node, so a sum of 10,000 event times costs no
    recursion)."""

    _q = None
    _kca = None

    def known_rational(self):
        return self._q

    def known_ca(self):
        if self._kca is not None:
            return self._kca
        return super().known_ca()

    def _set_known_ca(self, parts: list, combine) -> None:
        """Set ``_kca`` from the known Calcium numbers of ``parts`` when one of them is an
        algebraic irrational (rational-only combinations stay rational and need none)."""
        if self._q is not None or all(getattr(x, "_kca", None) is None and not isinstance(x, AlgebraicReal)
                                      for x in parts):
            return
        cas = [x.known_ca() for x in parts]
        if all(c is not None for c in cas):
            self._kca = combine(*cas)

    def rational(self):
        if self._q is None and self.policy.closed_forms != "off":
            const, terms = linear_terms(self)
            qs = [x.rational() for _, x in terms]
            if all(q is not None for q in qs):
                self._q = const + sum((c * q for (c, _), q in zip(terms, qs)), fmpq(0))
        return self._q

    def _closed(self):
        const, terms = linear_terms(self)
        out = Closed.rational(const)
        for c, x in terms:
            cf = x.closed
            if cf is None:
                return None
            out = out + cf * c
        return out

    def to_ca(self):
        if not calcium.available():
            return None
        const, terms = linear_terms(self)
        out = calcium.Ca(const)
        for c, x in terms:
            cx = x.to_ca()
            if cx is None:
                return None
            out = out + cx * calcium.Ca(c)
        return out


class SumReal(_Linear):
    """a + sign * b."""

    def __init__(self, a: Real, b: Real, sign: int = 1, policy: Policy | None = None):
        super().__init__(policy or (a.policy if a.policy is not DEFAULT_POLICY else b.policy))
        self.a, self.b, self.s = a, b, sign
        qa, qb = a.known_rational(), b.known_rational()  # O(1): cached in the parts
        if qa is not None and qb is not None:
            self._q = qa + qb if sign == 1 else qa - qb
        self._set_known_ca([a, b], (lambda x, y: x + y) if sign == 1 else (lambda x, y: x - y))

    def _deps(self):
        return (self.a, self.b)

    def _compute(self, prec):
        a, b = self.a.arb(prec), self.b.arb(prec)
        return a + b if self.s == 1 else a - b


class ScaledReal(_Linear):
    """q * a for a rational q."""

    def __init__(self, a: Real, q: fmpq, policy: Policy | None = None):
        super().__init__(policy or a.policy)
        self.a, self.q = a, q
        qa = a.known_rational()
        if qa is not None or q == 0:
            self._q = fmpq(0) if q == 0 else qa * q
        self._set_known_ca([a], lambda x: x * q)

    def _deps(self):
        return (self.a,)

    def _compute(self, prec):
        return self.a.arb(prec) * arb(self.q)

    def sign(self):
        if self.q == 0:
            return 0
        return self.a.sign() * ((self.q > 0) - (self.q < 0))


class ClosedFormReal(Real):
    """A real given by a SymPy expression built from rationals, pi, E, +, *, rational powers,
    exp, log and (inverse, hyperbolic) trigonometric functions, evaluated rigorously with arb."""

    def __init__(self, expr: Any, policy: Policy | None = None):
        super().__init__(policy)
        import sympy
        self.expr = sympy.sympify(expr)
        with workprec(64):
            closed_form_arb(self.expr)  # validate now: raises for unsupported expressions
        self._cf, self._cf_done = Closed.of_sympy(self.expr), True

    def _compute(self, prec):
        return closed_form_arb(self.expr)

    def known_rational(self):
        if self.expr.is_Rational:
            return fmpq(int(self.expr.p), int(self.expr.q))
        return None

    def to_ca(self):
        return ca_of_sympy(self.expr)


class ComponentReal(Real):
    """Component i of an exact vector."""

    def __init__(self, vec: "ExactVector", i: int):
        super().__init__(vec.policy)
        self.vec, self.i = vec, i

    def _deps(self):
        return (self.vec,)

    def _compute(self, prec):
        return self.vec.arb(prec)[self.i, 0]

    def known_rational(self):
        q = self.vec.known_rational()
        if q is not None:
            return q[self.i, 0]
        if self.vec.proven_zero(self.i):
            return fmpq(0)
        return None

    def sign(self):
        q = self.known_rational()
        if q is not None:
            return (q > 0) - (q < 0)
        e = fmpq_mat(1, self.vec.n, [int(j == self.i) for j in range(self.vec.n)])
        return self.vec.sign_of_form(e)

    def _closed(self):
        q = self.known_rational()
        if q is not None:
            return Closed.rational(q)
        q = self.vec.rational()  # rational when proven so (no SymPy)
        if q is not None:
            return Closed.rational(q[self.i, 0])
        cf = self.vec.closed_form()
        return None if cf is None else Closed.of_sympy(cf[self.i])

    def to_ca(self):
        v = self.vec.to_ca()
        return None if v is None else v[self.i]

    def known_ca(self):
        v = self.vec.known_ca()
        return None if v is None else v[self.i]


def _ca_state(c) -> tuple:
    """A picklable exact description of an algebraic Calcium number: (minimal polynomial, an
    isolating rational interval as ((p, q), (p, q))), rebuilt by :func:`_ca_from_state`."""
    coeffs = c.minimal_polynomial()
    if coeffs is None:
        raise LCSError("internal inconsistency: an algebraic number without a minimal polynomial")
    with workprec(256):
        r = c.enclosure(256).real
        a, b = dyadic_lower(r), dyadic_upper(r)
    return (tuple(coeffs), ((int(a.p), int(a.q)), (int(b.p), int(b.q))))


def _ca_from_state(state: tuple):
    coeffs, ((ap, aq), (bp, bq)) = state
    with workprec(256):
        ball = arb(fmpq(ap, aq)).union(arb(fmpq(bp, bq)))
    return calcium.Ca.algebraic(list(coeffs), ball)


def radical_form(c):
    """A SymPy closed form of the real algebraic number c (a Calcium number), proven equal to it
    by Calcium: the rational itself, or a root of its minimal polynomial in radicals (degree <= 4)
    selected by c's enclosure; None otherwise."""
    import sympy
    q = c.to_fmpq()
    if q is not None:
        return sympy.Rational(int(q.p), int(q.q))
    coeffs = c.minimal_polynomial()
    if coeffs is None or len(coeffs) - 1 > 4:
        return None
    x = sympy.Symbol("x")
    poly = sympy.Poly(list(reversed(coeffs)), x)
    with workprec(128):
        target = c.enclosure(128).real
        for r in sympy.roots(poly, multiple=True):
            if not r.is_real:
                continue
            try:
                if not closed_form_arb(r).overlaps(target):
                    continue
            except Exception:  # noqa: BLE001 - an expression the ball evaluator cannot read
                continue
            rc = ca_of_sympy(r)
            if rc is not None and (rc - c).is_zero() is True:
                return sympy.radsimp(r) if len(str(r)) > 40 else r
    return None


class AlgebraicReal(Real):
    """An exact real algebraic number, held as a Calcium number (a root of a polynomial phase,
    the event time of a free fall, sqrt(2 h / g)): signs and equalities are decided exactly,
    balls come from Calcium's enclosures at any precision, and ``closed_form`` gives radicals
    where the degree allows (proven).  ``lo`` / ``hi`` are dyadic bounds (rational brackets, as
    for a root found by isolation).

    >>> from lcs_exact.calcium import Ca
    >>> r = AlgebraicReal(Ca(2).sqrt())
    >>> r.sign(), r.closed_form, r.decimal(20)
    (1, sqrt(2), '1.4142135623730950488 +/- 1.71e-21')
    """

    def __init__(self, ca: Any, policy: Policy | None = None):
        super().__init__(policy)
        self.ca = ca
        self._q = ca.to_fmpq()
        self._bounds = None
        if self._q is not None and self._q.q == 1:
            self._ball, self._prec = arb(self._q), 1 << 30

    def _compute(self, prec):
        if self._q is not None:
            return arb(self._q)
        return self.ca.enclosure(prec + 8).real

    def known_rational(self):
        return self._q

    def known_ca(self):
        return self.ca

    def to_ca(self):
        return self.ca

    def sign(self) -> int:
        if self._q is not None:
            return (self._q > 0) - (self._q < 0)
        s = self.ca.sign()
        return s if s is not None else super().sign()

    def interval(self) -> tuple[fmpq, fmpq]:
        """Dyadic rationals lo <= value <= hi (exactly the value when it is rational)."""
        if self._q is not None:
            return self._q, self._q
        if self._bounds is None:
            with workprec(128):
                b = self.ca.enclosure(128).real
                self._bounds = (dyadic_lower(b), dyadic_upper(b))
        return self._bounds

    @property
    def lo(self) -> fmpq:
        return self.interval()[0]

    @property
    def hi(self) -> fmpq:
        return self.interval()[1]

    def _closed_form(self):
        return radical_form(self.ca)

    def __getstate__(self):
        state = super().__getstate__()
        state["ca"] = _ca_state(self.ca) if self._q is None else None
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.ca = _ca_from_state(state["ca"]) if state["ca"] is not None else _rational_ca(self._q)


def _rational_ca(q):
    return calcium.Ca(q)


# ---------------------------------------------------------------------------------------------
# exact vectors
# ---------------------------------------------------------------------------------------------


class ExactVector(_Node):
    """An exact vector in R^n: evaluates to an n x 1 ``arb_mat`` ball of any precision.

    ``zero_forms`` (an m x n ``fmpq_mat``, a row basis) are linear forms proven to vanish on the
    vector; they are fixed at construction (vectors are immutable).
    """

    n: int

    def __init__(self, n: int, zero_forms: fmpq_mat | None = None, policy: Policy | None = None):
        super().__init__(policy)
        self.n = n
        zf = zero_forms if zero_forms is not None and zero_forms.nrows() else zeros(0, n)
        self.zero_forms = row_basis(zf) if zf.nrows() > 1 else zf
        self._twin: ExactVector | None = None  # an exact equal found by a proof (see prove_zero)
        self._ca = None
        self._ca_done = False

    # --- structure ----------------------------------------------------------------------------
    @property
    def zero_span(self) -> RowSpan:
        """The span of ``zero_forms``, for membership tests (built once; a cache)."""
        span = self.__dict__.get("_zero_span")
        if span is None:
            span = self._zero_span = RowSpan(self.zero_forms)
        return span

    def known_rational(self) -> fmpq_mat | None:
        """The vector as an n x 1 ``fmpq_mat`` when already known to be rational (cheap)."""
        return self._twin.known_rational() if self._twin is not None else None

    def rational(self) -> fmpq_mat | None:
        """The vector as an n x 1 ``fmpq_mat`` when proven rational, deriving the closed forms
        of the times in its definition if needed (lazy); None when not proven."""
        q = self.known_rational()
        if q is None and self.policy.closed_forms != "off":
            q = self.exact_rational()
        return q

    def exact_rational(self, depth: int = 40) -> fmpq_mat | None:
        """The vector as a rational vector when closed forms prove it (may derive the closed forms
        of the times in its definition, e.g. e^{A(theta - 1)} q with theta = 1 proven is q);
        None when not proven.  ``depth`` bounds how far back the definition is followed."""
        q = self.known_rational()
        if q is not None or depth <= 0:
            return q
        q = self._exact_rational(depth - 1)
        if q is not None and self._twin is None:
            self._twin = RationalVector(q, policy=self.policy)
        return q

    def _exact_rational(self, depth: int) -> fmpq_mat | None:
        return None

    def proven_zero(self, i: int) -> bool:
        """Component i is 0 by a proven relation (or by an exact twin found by a proof)."""
        if self._twin is not None:
            return self._twin.q[i, 0] == 0
        if not self.zero_forms.nrows():
            return False
        return self.zero_span.has_unit(i)

    def closed_form(self, derive: bool = True):
        """A SymPy column vector when every component has a proven closed form, else None.

        ``derive=False`` returns only what is cheaply known; True may derive it with SymPy (the
        symbolic e^{Mt}: up to a second for a new matrix)."""
        if self._twin is not None:
            return self._twin.closed_form(derive)
        return None

    def known_ca(self) -> list | None:
        """The components as Calcium numbers when the vector is already known exactly (rational,
        or algebraic: :class:`AlgebraicVector`); cheap, never derives a closed form."""
        q = self.known_rational()
        if q is None:
            return None
        return [calcium.Ca(q[i, 0]) for i in range(self.n)] if calcium.available() else None

    def to_ca(self) -> list | None:
        """The components as Calcium numbers (exact), or None (cached)."""
        if not self._ca_done:
            self._ca_done = True
            try:
                self._ca = self._to_ca()
            except (ZeroDivisionError, ValueError, UnresolvedSign):
                self._ca = None  # Calcium could not build it (an undecided divisor): no closed form
        return self._ca

    def _to_ca(self):
        return None

    # --- signs --------------------------------------------------------------------------------
    def sign_of_form(self, form: fmpq_mat) -> int:
        """Certified sign of form . x (see the module docstring for the order of the tests)."""
        q = self.known_rational()
        if q is not None:
            v = (form * q)[0, 0]
            return (v > 0) - (v < 0)
        if is_zero(form):
            return 0
        if self.zero_forms.nrows() and form in self.zero_span:
            return 0
        s = self._structural_sign(form)
        if s is not None:
            return s
        return decide_sign(lambda p: (arb_mat(form) * self.arb(p))[0, 0], policy=self.policy,
                           what=lambda: f"the form {format_form(form)} at {self!r}",
                           start=max(64, self._prec), prove_zero=lambda: self.prove_zero(form))

    def _structural_sign(self, form: fmpq_mat) -> int | None:
        return None

    def prove_zero(self, form: fmpq_mat) -> bool | None:
        """form . x == 0 by an exact proof: True, False (proven nonzero), None (unknown).

        Tries the Calcium closed form of the vector; when every component is rational there,
        the vector gets an exact twin (a rational vector) used from then on.  Never with
        ``closed_forms=False``."""
        if self.policy.closed_forms == "off":
            return None
        xs = self.to_ca()
        if xs is None:
            return None
        qs = [c.to_fmpq() for c in xs]
        if all(q is not None for q in qs):
            self._twin = RationalVector(fmpq_mat(self.n, 1, qs), policy=self.policy)
            v = (form * self._twin.q)[0, 0]
            return v == 0
        acc = calcium.Ca(0)
        for j, c in enumerate(xs):
            if form[0, j] != 0:
                acc = acc + c * calcium.Ca(form[0, j])
        return acc.is_zero()

    # --- access -------------------------------------------------------------------------------
    def __len__(self):
        return self.n

    def __getitem__(self, i: int) -> Real:
        if not -self.n <= i < self.n:
            raise IndexError(f"component {i} of a vector of length {self.n}")
        return ComponentReal(self, i % self.n)

    def __iter__(self) -> Iterator[Real]:
        return (ComponentReal(self, i) for i in range(self.n))

    def tolist(self) -> list[Real]:
        return list(self)

    def ball(self, digits: int = 30) -> list[arb]:
        """Certified balls of the components, each to ``digits`` digits (one query: bounded by
        the run's ``time_limit`` as a whole)."""
        with self.policy.deadline.query():
            return [c.ball(digits) for c in self]

    def __repr__(self):
        q = self.known_rational()
        if q is not None:
            return "(" + ", ".join(str(q[i, 0]) for i in range(self.n)) + ")"
        return "(" + ", ".join(c.label() for c in self) + ")"


class RationalVector(ExactVector):
    """A rational vector (n x 1 ``fmpq_mat``)."""

    def __init__(self, q: fmpq_mat, policy: Policy | None = None):
        super().__init__(q.nrows(), None, policy)
        self.q = q
        if all(q[i, 0].q == 1 for i in range(q.nrows())):  # integer entries: exact balls
            self._ball, self._prec = arb_mat(q), 1 << 30

    def _compute(self, prec):
        return arb_mat(self.q)

    def known_rational(self):
        return self.q

    def closed_form(self, derive: bool = True):
        import sympy
        return sympy.Matrix([sympy.Rational(int(self.q[i, 0].p), int(self.q[i, 0].q)) for i in range(self.n)])

    def _to_ca(self):
        return [calcium.Ca(self.q[i, 0]) for i in range(self.n)] if calcium.available() else None


class ScaledVector(ExactVector):
    """c v with c an exact real proven positive and v an exact vector (homogeneity: the LCS is
    linear, so phases from c v have the event times of v and c times its states)."""

    def __init__(self, c: Real, v: ExactVector, policy: Policy | None = None):
        super().__init__(v.n, v.zero_forms, policy or v.policy)
        self.c, self.v = c, v

    def _deps(self):
        return (self.c, self.v)

    def _compute(self, prec):
        return self.v.arb(prec) * self.c.arb(prec)

    def known_rational(self):
        qc = self.c.known_rational()
        qv = self.v.known_rational()
        if qc is not None and qv is not None:
            return qv * qc
        return super().known_rational()

    def _structural_sign(self, form):
        return self.v.sign_of_form(form)  # c > 0

    def known_ca(self):
        if "_kca" not in self.__dict__:
            cc, cv = self.c.known_ca(), self.v.known_ca()
            self._kca = None if cc is None or cv is None else [x * cc for x in cv]
        return self._kca

    def proven_zero(self, i: int) -> bool:
        return self.v.proven_zero(i)

    def _exact_rational(self, depth):
        qv = self.v.exact_rational(depth)
        cf = self.c.closed if qv is not None else None
        if cf is not None and cf.is_rational:
            return qv * cf.to_fmpq()
        return None

    def closed_form(self, derive: bool = True):
        cv = self.v.closed_form(derive)
        cc = (self.c.closed_form if derive else self.c.known_closed_form) if cv is not None else None
        return None if cc is None or cv is None else cv * cc

    def _to_ca(self):
        cc, cv = self.c.to_ca(), self.v.to_ca()
        return None if cc is None or cv is None else [x * cc for x in cv]


class ProjectedVector(ExactVector):
    """P v for a rational matrix P (a projection P_I, an impulse map, a feedback); the forms r
    with r P in the span of v's zero forms vanish on it."""

    def __init__(self, P: fmpq_mat, v: ExactVector, policy: Policy | None = None,
                 zero_forms: fmpq_mat | None = None):
        zf = pulled_back_forms(P, v.zero_forms)
        if zero_forms is not None and zero_forms.nrows():
            zf = row_basis(zf, zero_forms) if zf.nrows() else zero_forms
        super().__init__(P.nrows(), zf, policy or v.policy)
        self.P, self.v = P, v

    def _deps(self):
        return (self.v,)

    def _compute(self, prec):
        return arb_mat(self.P) * self.v.arb(prec)

    def known_rational(self):
        q = self.v.known_rational()
        if q is not None:
            return self.P * q
        return super().known_rational()

    def _structural_sign(self, form):
        return self.v.sign_of_form(form * self.P)

    def known_ca(self):
        if "_kca" not in self.__dict__:
            if self.known_rational() is not None:
                return super().known_ca()
            self._kca = ca_matvec(self.P, self.v.known_ca())
        return self._kca

    def _exact_rational(self, depth):
        q = self.v.exact_rational(depth)
        return None if q is None else self.P * q

    def closed_form(self, derive: bool = True):
        if self._twin is not None:
            return self._twin.closed_form(derive)
        cf = self.v.closed_form(derive)
        if cf is None:
            return None
        return (matrix_to_sympy(self.P) * cf).applyfunc(_tidy)

    def _to_ca(self):
        xs = self.v.to_ca()
        if xs is None:
            return None
        out = []
        for i in range(self.n):
            acc = calcium.Ca(0)
            for j in range(self.v.n):
                if self.P[i, j] != 0:
                    acc = acc + xs[j] * calcium.Ca(self.P[i, j])
            out.append(acc)
        return out


class ExpVector(ExactVector):
    """e^{M t} v: M rational (through its :class:`~lcs_exact.expm.Spectrum`), t an exact real, v
    an exact vector.  ``modal(prec)``, when given, supplies the per-eigenvalue vectors of v at
    ``prec`` (a phase computes them once for all its functions)."""

    def __init__(self, spectrum: Spectrum, t: Real, v: ExactVector, zero_forms: fmpq_mat | None = None,
                 policy: Policy | None = None, modal: Callable[[int], list] | None = None):
        super().__init__(spectrum.n, zero_forms, policy or v.policy)
        self.spectrum, self.t, self.v = spectrum, t, v
        self._modal = modal

    @property
    def M(self) -> fmpq_mat:
        return self.spectrum.M

    def _deps(self):
        return (self.t, self.v)

    def _compute(self, prec):
        t = self.t.arb(prec)
        modal = self._modal(prec) if self._modal is not None else None
        return self.spectrum.apply(t, self.v.arb(prec), prec, modal)

    def known_rational(self):
        if self._twin is not None:
            return self._twin.known_rational()
        tq = self.t.known_rational()
        if tq == 0:
            return self.v.known_rational()
        if tq is not None and self.spectrum.nilpotent_only:
            q = self.v.known_rational()
            if q is not None:  # e^{Nt} q = sum_j t^j N^j q / j!: exact for a nilpotent M
                out, tp = self.spectrum.nilpotent[0] * q, fmpq(1)
                for P in self.spectrum.nilpotent[1:]:
                    tp *= tq
                    out = out + P * q * tp
                self._twin = RationalVector(out, policy=self.policy)
                return out
        return None

    def _exact_rational(self, depth):
        inner, s = orbit_start(self.v, self.spectrum.M)  # e^{Mt} e^{Ms} w = e^{M(t+s)} w
        q = inner.exact_rational(depth)
        if q is None:
            return None
        tc = self.t.closed
        if tc is not None and s is not None:
            sc = s.closed
            tc = None if sc is None else tc + sc
        if tc is None:
            return None
        if tc.is_zero:
            return q
        if all(q[i, 0] == 0 for i in range(self.n)):
            return q
        if not calcium.available():
            return None
        try:  # e^{M t*} q exactly (Calcium), rational when every component is
            tca = tc.to_ca()
            if tca is None:
                return None
            xs = self.spectrum.ca_apply(tca, [calcium.Ca(q[i, 0]) for i in range(self.n)], calcium)
            qs = None if xs is None else [x.to_fmpq() for x in xs]
        except (ValueError, ZeroDivisionError, UnresolvedSign):
            return None
        return None if qs is None or any(x is None for x in qs) else fmpq_mat(self.n, 1, qs)

    def closed_form(self, derive: bool = True):
        if self._twin is not None:
            return self._twin.closed_form(derive)
        if not derive:
            return None
        q = self.exact_rational()
        if q is not None:
            return self._twin.closed_form()
        if "_sym" not in self.__dict__:
            self._sym = None
            tc = self.t.closed_form
            vc = self.v.closed_form(derive) if tc is not None else None
            if vc is not None:
                E = symbolic_expm(self.spectrum)
                if E is not None:
                    self._sym = (E.subs(t_symbol(), tc) * vc).applyfunc(_tidy)
        return self._sym

    def _to_ca(self):
        tc = self.t.to_ca()
        if tc is None:
            return None
        xs = self.v.to_ca()
        if xs is None:
            return None
        return self.spectrum.ca_apply(tc, xs, calcium)


class ComponentsVector(ExactVector):
    """A vector of exact reals (e.g. an initial state with closed-form entries)."""

    def __init__(self, comps: list[Real], policy: Policy | None = None):
        zf = [j for j, c in enumerate(comps) if c.known_rational() == 0]
        Z = fmpq_mat(len(zf), len(comps), [int(j == z) for z in zf for j in range(len(comps))])
        super().__init__(len(comps), Z, policy)
        self.comps = comps

    def _deps(self):
        return tuple(self.comps)

    def _compute(self, prec):
        return arb_mat([[c.arb(prec)] for c in self.comps])

    def known_rational(self):
        qs = [c.known_rational() for c in self.comps]
        if all(q is not None for q in qs):
            return fmpq_mat(self.n, 1, qs)
        return super().known_rational()

    def closed_form(self, derive: bool = True):
        cs = [c.closed_form for c in self.comps]
        if any(c is None for c in cs):
            return None
        import sympy
        return sympy.Matrix(cs)

    def _to_ca(self):
        cs = [c.to_ca() for c in self.comps]
        return None if any(c is None for c in cs) else cs

    def known_ca(self):
        cs = [c.known_ca() for c in self.comps]
        return None if any(c is None for c in cs) else cs


def ca_matvec(P: fmpq_mat, xs: list | None) -> list | None:
    """P x for a rational matrix P and a vector of Calcium numbers (None stays None)."""
    if xs is None:
        return None
    out = []
    for i in range(P.nrows()):
        acc = calcium.Ca(0)
        for j in range(P.ncols()):
            if P[i, j] != 0:
                acc = acc + xs[j] * calcium.Ca(P[i, j])
        out.append(acc)
    return out


class AlgebraicVector(ExactVector):
    """A vector of exact real algebraic numbers (Calcium numbers): the state at an event of a
    polynomial phase (a free fall, a relay's constant field) whose time is algebraic.  Every sign
    of a rational form is decided exactly (Calcium decides algebraic numbers); balls come from
    Calcium's enclosures at any precision.  Rational components stay rational
    (``known_rational`` when all are).

    >>> from lcs_exact.calcium import Ca
    >>> x = AlgebraicVector([Ca(2).sqrt(), Ca(1)])
    >>> x.sign_of_form(fmpq_mat([[1, -2]])), x[0].closed_form
    (-1, sqrt(2))
    """

    def __init__(self, comps: list, zero_forms: fmpq_mat | None = None, policy: Policy | None = None):
        super().__init__(len(comps), zero_forms, policy)
        self.comps = list(comps)
        qs = [c.to_fmpq() for c in self.comps]
        self._q = fmpq_mat(self.n, 1, qs) if all(q is not None for q in qs) else None

    def _compute(self, prec):
        if self._q is not None:
            return arb_mat(self._q)
        return arb_mat([[c.enclosure(prec + 8).real] for c in self.comps])

    def known_rational(self):
        return self._q if self._q is not None else super().known_rational()

    def known_ca(self):
        return self.comps

    def _to_ca(self):
        return self.comps

    def _structural_sign(self, form):
        acc = calcium.Ca(0)
        for j in range(self.n):
            if form[0, j] != 0:
                acc = acc + self.comps[j] * calcium.Ca(form[0, j])
        return acc.sign()

    def proven_zero(self, i: int) -> bool:
        return self.comps[i].is_zero() is True or super().proven_zero(i)

    def closed_form(self, derive: bool = True):
        if self._q is not None:
            return RationalVector(self._q).closed_form()
        if not derive:
            return None
        cs = [radical_form(c) for c in self.comps]
        if any(c is None for c in cs):
            return None
        import sympy
        return sympy.Matrix(cs)

    def __getstate__(self):
        state = super().__getstate__()
        state["comps"] = None if self._q is not None else [_ca_state(c) for c in self.comps]
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        if state["comps"] is None:
            self.comps = [_rational_ca(self._q[i, 0]) for i in range(self.n)]
        else:
            self.comps = [_ca_from_state(c) for c in state["comps"]]


def algebraic_vector(xs: list, zero_forms: fmpq_mat | None = None, policy: Policy | None = None) -> ExactVector:
    """A RationalVector when every Calcium number of xs is rational, else an AlgebraicVector."""
    qs = [c.to_fmpq() for c in xs]
    if all(q is not None for q in qs):
        return RationalVector(fmpq_mat(len(xs), 1, qs), policy)
    return AlgebraicVector(xs, zero_forms, policy)


def _tidy(e):
    """Light SymPy clean-up of a closed-form entry (no simplify: it costs seconds)."""
    import sympy
    return sympy.nsimplify(e, rational=False) if e.is_number and e.is_Float else sympy.expand(e)


# ---------------------------------------------------------------------------------------------
# constructors
# ---------------------------------------------------------------------------------------------


def _is_sympy(x: Any) -> bool:
    return type(x).__module__.startswith("sympy")


def as_real(x: Any, policy: Policy | None = None) -> Real:
    """An exact real from a Real, a rational-like value or a SymPy expression."""
    if isinstance(x, Real):
        return x
    if _is_sympy(x):
        if getattr(x, "is_Rational", False):
            return RationalReal(fmpq(int(x.p), int(x.q)), policy)
        try:
            return ClosedFormReal(x, policy)
        except (TypeError, ValueError, AttributeError) as e:
            raise NotRational(f"{x} is not a supported exact real: {e}") from None
    return RationalReal(x, policy)


def as_exact_vector(x: Any, n: int | None = None, name: str = "x0", policy: Policy | None = None) -> ExactVector:
    """An ExactVector from an ExactVector, an ``fmpq_mat`` column or any vector input (entries
    rational-like, or SymPy closed forms)."""
    if isinstance(x, ExactVector):
        if n is not None and x.n != n:
            raise ShapeError(f"{name} has length {x.n}, expected {n}")
        return x
    if isinstance(x, fmpq_mat):
        return RationalVector(to_vector(x, x.nrows() if n is None and x.ncols() == 1 else
                                        (n if n is not None else x.ncols()), name), policy)
    if hasattr(x, "tolist") and not _is_sympy(x):
        x = x.tolist()
    flat = vector_entries(x, n, name)
    if any(isinstance(e, Real) or (_is_sympy(e) and not getattr(e, "is_Rational", False)) for e in flat):
        # the library's own exact reals (a component of traj.state(t)) and SymPy closed forms
        return ComponentsVector([as_real(e, policy) for e in flat], policy)
    return RationalVector(to_vector(flat, len(flat), name), policy)


def orbit_start(v: ExactVector, M: fmpq_mat) -> tuple[ExactVector, Real | None]:
    """(w, s) with v = e^{M s} w and w not itself of that form (s None when v is not e^{M s} w):
    a phase from v follows the orbit of w, so forms vanishing on the orbit of w vanish on it."""
    s = None
    while isinstance(v, ExpVector) and (v.spectrum.M is M or v.spectrum.M == M):
        s = v.t if s is None else s + v.t
        v = v.v
    return v, s


def homogenized(x: ExactVector) -> ExactVector:
    """x itself, or c q (c > 0 certified, q rational) when the forms proven to vanish on x leave
    a single direction q (rank n - 1): then every sign at x is the sign at q, exactly."""
    if x.known_rational() is not None or isinstance(x, (ScaledVector, AlgebraicVector)) or \
            x.zero_forms.nrows() != x.n - 1:
        return x
    q = kernel(x.zero_forms)
    i = next(i for i in range(x.n) if q[i, 0] != 0)
    c = ScaledReal(ComponentReal(x, i), 1 / q[i, 0])
    s = c.sign()
    if s == 0:
        return RationalVector(zeros(x.n, 1), x.policy)
    if s < 0:
        c, q = -c, -q
    return ScaledVector(c, RationalVector(q, x.policy), x.policy)


def expm_action(M: Any, t: Any, v: Any, *, policy: Policy | None = None) -> ExactVector:
    """e^{M t} v as an exact vector (M, v: any matrix/vector input LCS accepts; t exact).

    Composes structurally: expm_action(M, a, expm_action(M, b, v)) = e^{M(a+b)} v, and is v
    itself (rational again) when a + b is proven 0.

    >>> x0 = expm_action([[0, 1], [-1, 0]], -1, [1, 0])
    >>> expm_action([[0, 1], [-1, 0]], 1, x0).known_rational().transpose()
    [1, 0]
    """
    if isinstance(M, Spectrum):
        sp = M
    else:
        Mq = to_matrix(M, "M")
        if Mq.nrows() != Mq.ncols():
            raise ShapeError(f"M must be square, got {Mq.nrows()}x{Mq.ncols()}")
        sp = spectrum_of(Mq)
    t = as_real(t, policy)
    v = as_exact_vector(v, sp.n, "v", policy)
    if isinstance(v, ExpVector) and v.spectrum.M == sp.M:
        t, v = t + v.t, v.v
    if t.known_rational() == 0:
        return v
    q = v.known_rational()
    if q is not None and is_zero(sp.M * q):  # an equilibrium: e^{Mt} v = v
        return v
    if q is not None:  # forms vanishing on the whole orbit e^{Ms} q (e.g. coordinates M leaves at 0)
        zf = orbit_zero_forms(sp.M, q)
    else:
        zf = invariant_forms(v.zero_forms, sp.M) if v.zero_forms.nrows() else None
    return ExpVector(sp, t, v, zf, policy)


# ---------------------------------------------------------------------------------------------
# text
# ---------------------------------------------------------------------------------------------

def format_form(form: fmpq_mat) -> str:
    """A row as text: (1, 0, -1/2)."""
    return "(" + ", ".join(str(form[0, j]) for j in range(form.ncols())) + ")"


def _bound_up(err) -> str:
    """A 3-digit decimal >= err (nstr rounds to nearest, within 0.5%: scale by 1.01 first)."""
    from mpmath import mpf, nstr
    return nstr(err * mpf("1.01"), 3) if err else "0"


def decimal_of_fmpq(q: fmpq, digits: int) -> str:
    """q to ``digits`` significant digits; exact strings stand alone, rounded ones carry a bound."""
    with long_int_strings():
        return _decimal_of_fmpq(q, digits)


def _decimal_of_fmpq(q: fmpq, digits: int) -> str:
    from fractions import Fraction
    from mpmath import mp, mpf, nstr
    if q.q == 1 and len(str(abs(int(q.p)))) <= digits:
        return str(int(q.p))  # an integer is exact as it stands ("0", not "0.0")
    with mp.workdps(digits + 10):
        text = nstr(mpf(int(q.p)) / int(q.q), digits, strip_zeros=True)
        err = abs(Fraction(text) - Fraction(int(q.p), int(q.q)))
        return text if err == 0 else f"{text} +/- {_bound_up(mpf(err.numerator) / err.denominator)}"


def decimal_of_ball(b: arb, digits: int) -> str:
    """mid rounded to ``digits`` significant digits, with an upper bound on the total error."""
    with long_int_strings():
        return _decimal_of_ball(b, digits)


def _decimal_of_ball(b: arb, digits: int) -> str:
    from mpmath import mp, mpf, nstr
    mid = b.mid()
    with mp.workdps(digits + 20):
        m = mpf(mid.str(digits + 15, radius=False)) if not mid.is_zero() else mpf(0)
        s = nstr(m, digits, strip_zeros=False, min_fixed=-5, max_fixed=digits + 1)
        err = abs(mpf(s) - m) + mpf(b.rad().str(5, radius=False)) * 2 + abs(m) * mpf(10) ** (-(digits + 12))
        return f"{s} +/- {_bound_up(err)}"


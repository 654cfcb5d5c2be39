"""Exact reals (docs/numerics.md); exact vectors are in :mod:`lcs_exact.vectors`.

An exact real (:class:`Real`) is an immutable exact *definition* - a rational, a sum, a positive
multiple, a component of an exact vector, a closed form, an algebraic number, or a root of an
exponential sum (:mod:`lcs_exact.roots`) - that evaluates to an ``arb`` ball of any requested
precision with the true value inside, from its anchors (:mod:`lcs_exact.nodes`).

Signs.  ``x.sign()`` is exact when x is proven rational (or algebraic: Calcium), 0 when a
component is proven to vanish (forms vanishing on its vector), then a ball that excludes 0, an
exact zero test of the closed form (``prove_zero``: Calcium) and refinement up to the policy's
ceiling; otherwise an *unresolved zero* (:meth:`~lcs_exact.balls.Policy.unresolved`).

Closed forms are lazy: ``r.closed_form`` (a SymPy expression, for display) is derived on first
access; nothing on the evaluation path imports SymPy.
"""
from __future__ import annotations

import operator
from typing import Any

from flint import arb, fmpq, fmpq_mat

from . import calcium
from .balls import (DEFAULT_POLICY, MAX_DIGITS, Policy, check_digits, accuracy_bits, closed_form_arb, decide_sign, decimal_of_ball,
                    decimal_of_fmpq, digits_to_bits, dyadic_lower, dyadic_upper, workprec)
from ..errors import NotRational, UnresolvedSign
from .algebraics import ca_from_state, ca_state, radical_form, rational_ca
from .forms import Closed, ca_of_sympy
from .nodes import Node, closed_ready, in_dependency_order
from ..algebra import to_fmpq

__all__ = ["Real", "RationalReal", "SumReal", "ScaledReal", "ClosedFormReal", "ComponentReal",
           "AlgebraicReal", "as_real", "is_sympy"]


class Real(Node):
    """An exact real number: evaluates to an arb ball of any precision (true value inside).

    The base of the exact reals (the classes below say what the number is; made by
    :func:`as_real`, by arithmetic on reals and by the engine).

    Parameters
    ----------
    policy : Policy, optional
        The precision policy of its evaluations and sign decisions (default ``DEFAULT_POLICY``).
    """

    _cf_done = False
    _cf = None
    _cf_cut = False

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
            if self.policy.closed_forms == "off":
                self._cf = None
            else:
                cuts = len(self.policy.deadline.safety_cuts)
                with self.policy.deadline.query():  # a query after the run: its time_limit holds
                    # the light closed forms of the reals it is derived from first, in a loop (no deep
                    # recursion); the states' SymPy forms only when a derivation asks for them
                    in_dependency_order(self, _derive_real_closed, closed_ready)
                    self._cf = self._closed()
                if self._cf is None and (len(self.policy.deadline.safety_cuts) > cuts or
                                         any(getattr(d, "_cf_cut", False) for d in self._deps())):
                    self._cf_cut = True  # derived from a form that was not searched: not searched
            self._cf_done = True
        return self._cf

    @property
    def closed_form_status(self) -> str:
        """"proven" (``closed_form`` is a proven closed form), "none" (the search ended without
        one), "not searched" (a SymPy step of the search was stopped by its wall-clock safety
        net, :data:`~lcs_exact.forms.SYMPY_SAFETY_NET`: the only search a clock ends) or "off"
        (``closed_forms=False``); derives the closed form when not yet done.

        >>> from lcs_exact.reals import as_real
        >>> as_real(1).closed_form_status
        'proven'
        """
        if self.policy.closed_forms == "off" and self.known_rational() is None:
            return "off"
        if self.closed is not None:
            return "proven"
        return "not searched" if self._cf_cut else "none"

    def _closed_ready(self) -> bool:
        return self._cf_done

    def _derive_closed(self) -> None:
        self.closed  # noqa: B018 -- derived and cached on access

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

    def known_exactly(self) -> bool:
        """True when :meth:`known_ca` gives the value (a rational, or an algebraic number known
        or pending as a combination of such), without forming any Calcium number."""
        return self.known_rational() is not None or _algebraic(self) or self.known_ca() is not None

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
        :class:`~lcs_exact.errors.LimitExceeded` instead of a hang).

        Parameters
        ----------
        digits : int, optional
            Significant decimal digits, 1 to ``MAX_DIGITS`` (default 30)."""
        digits = check_digits(digits)
        with self.policy.deadline.query():
            return self._refined(digits)

    def _refined(self, digits: int) -> arb:
        need = digits_to_bits(digits) + 4
        q = self.known_rational()
        if q is not None:  # exact (or rounded to far more than the digits asked)
            with workprec(need + 64):
                return arb(q)
        prec = max(self._prec, need + 16)
        # at most 16 x max_prec bits (a cancellation of e^(10^12)-sized terms would take the
        # doublings to millions of bits, seconds each: refused at the cap instead)
        cap = max(16 * self.policy.max_prec, 4 * need)
        while True:
            self.policy.check_deadline(lambda: f" while evaluating a number to {digits} digits")
            b = self.arb(prec)
            if b.is_exact() or accuracy_bits(b) >= need:
                return b
            if b.contains(0) and b.rad() < arb(2) ** (-need):
                return b
            if prec >= cap:
                break
            prec = min(2 * prec, cap)
        with workprec(64):  # the message names the ball (a repr would evaluate the number again)
            raise UnresolvedSign(f"could not evaluate a number to {digits} digits: at {prec} bits (16 x max_prec) "
                                 f"its ball is still {b.str(5, radius=True)}")

    def decimal(self, digits: int = 30) -> str:
        """The value to ``digits`` significant digits, followed by an error bound ``+/- e``
        unless it is exact.

        Parameters
        ----------
        digits : int, optional
            Significant decimal digits, 1 to ``MAX_DIGITS`` (default 30)."""
        digits = check_digits(digits)
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
        if getattr(self, "_kca_parts", None) is not None:  # Calcium could decide, but a ball is cheaper
            b = self.arb(max(64, self._prec))
            if not b.contains(0):
                return 1 if b > 0 else -1
        c = self.known_ca()
        if c is not None:  # an algebraic number: Calcium decides its sign exactly
            s = c.sign(real=True)
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
        """Short text: the known closed form or rational, else 15 digits (never derives one), or
        ``[+/- e]`` when the ball contains 0 (a number that may be 0: its digits would mean
        nothing)."""
        q = self.known_rational()
        if q is not None:
            return str(q)
        if self._cf_done and self._cf is not None:
            return str(self._cf)
        mid, _, err = self.decimal(15).partition(" +/- ")
        if err and self.ball(17).contains(0):  # the ball decimal(15) printed
            return f"[+/- {err}]"
        return mid

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
    """A rational number.

    Parameters
    ----------
    q : rational-like
        The value: int, ``"p/q"``, Fraction, fmpq, a float read as its shortest decimal.
    policy : Policy, optional
        The precision policy (default ``DEFAULT_POLICY``).
    """

    def __init__(self, q: Any, policy: Policy | None = None):
        super().__init__(policy)
        self.q = to_fmpq(q)
        if self.q.q == 1:  # an integer is an exact ball at every precision (when it fits this one)
            ball = arb(self.q)
            if ball.is_exact():
                self._ball, self._prec = ball, 1 << 30

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
    are exact algebraic numbers, so is the combination: its Calcium number is formed from theirs
    on first use (``known_ca``), the pending combinations it needs deepest first in a loop (a sum
    of 10,000 event times costs no recursion).  On first use, not at construction: compacting
    sums of square roots of growing degree cost a ball between a floor and a ceiling 7 s for 16
    events, and a sign that a ball decides needs none of it."""

    _q = None
    _kca = None
    _kca_parts = None  # (parts, combine) while the Calcium number is not formed

    def known_rational(self):
        return self._q

    def known_ca(self):
        if self._kca is None and self._kca_parts is not None:
            self._form_known_ca()
        if self._kca is not None:
            return self._kca
        return super().known_ca()

    def __getstate__(self):  # a formed Calcium number travels as its exact description (sweeps)
        state = super().__getstate__()
        return {**state, "_kca": ca_state(state["_kca"])} if state.get("_kca") is not None else state

    def __setstate__(self, state):
        self.__dict__.update(state, _kca=ca_from_state(state["_kca"]) if state.get("_kca") is not None else None)

    def _set_known_ca(self, parts: list, combine) -> None:
        """Record that the combination of ``parts`` is an exact algebraic number when one of them
        is (rational-only combinations stay rational and need none); formed on first use."""
        if self._q is not None or not any(_algebraic(x) for x in parts):
            return
        self._kca_parts = (tuple(parts), combine)

    def _form_known_ca(self) -> None:
        """Form the Calcium numbers of this combination and of the pending ones it is made of,
        deepest first, in a loop over an explicit stack."""
        order, stack, seen = [], [(self, False)], set()
        while stack:
            cur, ready = stack.pop()
            if ready:
                order.append(cur)
                continue
            if id(cur) in seen:
                continue
            seen.add(id(cur))
            stack.append((cur, True))
            for x in cur._kca_parts[0]:
                if isinstance(x, _Linear) and x._kca_parts is not None and id(x) not in seen:
                    stack.append((x, False))
        for node in order:
            if node._kca_parts is None:
                continue
            parts, combine = node._kca_parts
            node._kca_parts = None
            cas = [x.known_ca() for x in parts]
            if all(c is not None for c in cas):
                node._kca = combine(*cas).compact()

    def rational(self):
        if self._q is None and self._kca is not None:
            self._q = self._kca.to_fmpq()
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
        if self._kca is not None:
            return self._kca
        if not calcium.available():
            return None
        const, terms = linear_terms(self)
        out = calcium.Ca(const)
        for c, x in terms:
            cx = x.to_ca()
            if cx is None:
                return None
            out = out + cx * calcium.Ca(c)
        return out.compact()


def _derive_real_closed(x) -> None:
    """The light closed form of an exact real (:attr:`Real.closed`), for
    :func:`~lcs_exact.nodes.in_dependency_order`; vectors are passed over (their closed forms are
    SymPy matrices, derived when a derivation needs them)."""
    if isinstance(x, Real):
        x.closed  # noqa: B018 -- derived and cached on access


def _algebraic(x: Real) -> bool:
    """x is known to be an exact algebraic number (formed, or pending in a combination)."""
    return isinstance(x, AlgebraicReal) or getattr(x, "_kca", None) is not None or \
        getattr(x, "_kca_parts", None) is not None


class SumReal(_Linear):
    """a + sign * b."""

    def __init__(self, a: Real, b: Real, sign: int = 1, policy: Policy | None = None):
        super().__init__(policy or (a.policy if a.policy is not DEFAULT_POLICY else b.policy))
        self.a, self.b, self.s = a, b, sign
        qa, qb = a.known_rational(), b.known_rational()  # O(1): cached in the parts
        if qa is not None and qb is not None:
            self._q = qa + qb if sign == 1 else qa - qb
        self._set_known_ca([a, b], operator.add if sign == 1 else operator.sub)  # picklable (sweeps)

    def _deps(self):
        return (self.a, self.b)

    def _compute(self, prec):
        a, b = self.a.arb(prec), self.b.arb(prec)
        return a + b if self.s == 1 else a - b

    def _closed(self):
        a, b = self.a, self.b
        if a._cf_done and b._cf_done:  # derived in dependency order: the parts', not a walk of the sum
            return None if a._cf is None or b._cf is None else a._cf + b._cf * self.s
        return super()._closed()


class ScaledReal(_Linear):
    """q * a for a rational q."""

    def __init__(self, a: Real, q: fmpq, policy: Policy | None = None):
        super().__init__(policy or a.policy)
        self.a, self.q = a, q
        qa = a.known_rational()
        if qa is not None or q == 0:
            self._q = fmpq(0) if q == 0 else qa * q
        self._set_known_ca([a, RationalReal(q)], operator.mul)

    def _deps(self):
        return (self.a,)

    def _compute(self, prec):
        return self.a.arb(prec) * arb(self.q)

    def _closed(self):
        if self.a._cf_done:  # derived in dependency order (see SumReal._closed)
            return None if self.a._cf is None else self.a._cf * self.q
        return super()._closed()

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

    def __init__(self, vec: Node, i: int):
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


class AlgebraicReal(Real):
    """An exact real algebraic number, held as a Calcium number (a root of a polynomial phase,
    the event time of a free fall, sqrt(2 h / g)): signs and equalities are decided exactly,
    balls come from Calcium's enclosures at any precision, and ``closed_form`` gives radicals
    where the degree allows (proven).  ``lo`` / ``hi`` are dyadic bounds (rational brackets, as
    for a root found by isolation).

    Parameters
    ----------
    ca : Ca
        The number (:class:`~lcs_exact.numbers.calcium.Ca`), real algebraic; kept compacted.
    policy : Policy, optional
        The precision policy (default ``DEFAULT_POLICY``).

    Examples
    --------
    >>> from lcs_exact.calcium import Ca
    >>> r = AlgebraicReal(Ca(2).sqrt())
    >>> r.sign(), r.closed_form, r.decimal(20)
    (1, sqrt(2), '1.4142135623730950488 +/- 1.71e-21')
    """

    def __init__(self, ca: Any, policy: Policy | None = None):
        super().__init__(policy)
        self.ca = ca.compact()  # a long run's times would otherwise grow in Calcium's field form
        self._q = self.ca.to_fmpq()
        self._bounds = None
        if self._q is not None and self._q.q == 1:
            ball = arb(self._q)
            if ball.is_exact():  # an integer that fits the precision: exact at every precision
                self._ball, self._prec = ball, 1 << 30

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
        s = self.ca.sign(real=True)
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
        state["ca"] = ca_state(self.ca) if self._q is None else None
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.ca = ca_from_state(state["ca"]) if state["ca"] is not None else rational_ca(self._q)


def is_sympy(x: Any) -> bool:
    return type(x).__module__.startswith("sympy")


def as_real(x: Any, policy: Policy | None = None) -> Real:
    """An exact real from a Real, a rational-like value or a SymPy expression.

    Parameters
    ----------
    x : Real, rational-like or SymPy expression
        A Real is returned as it is; a rational (int, ``"p/q"``, Fraction, fmpq, a float read as
        its shortest decimal, a SymPy Rational) gives a :class:`RationalReal`; another SymPy
        expression a :class:`ClosedFormReal` (rationals, pi, E, +, *, rational powers, exp, log,
        trigonometric and hyperbolic functions and their inverses; else
        :class:`~lcs_exact.errors.NotRational`).
    policy : Policy, optional
        The precision policy of a number made here (default ``DEFAULT_POLICY``).
    """
    if isinstance(x, Real):
        return x
    if is_sympy(x):
        if getattr(x, "is_Rational", False):
            return RationalReal(fmpq(int(x.p), int(x.q)), policy)
        try:
            return ClosedFormReal(x, policy)
        except (TypeError, ValueError, AttributeError) as e:
            raise NotRational(f"{x} is not a supported exact real: {e}") from None
    return RationalReal(x, policy)

"""The precision policy: scoped ball precision, certified sign decisions, unresolved zeros.

Exact reals (:mod:`lcs_exact.reals`) are evaluated to ``arb`` balls that contain the true value.
Every decision made on a ball goes through this module, under one :class:`Policy`:

* ``digits``: correct significant digits promised for every reported number; the working
  precision of a run starts at ``target_bits = bits(digits) + guard`` and grows with the number
  of events (each event costs a run ~1.4 bits of accuracy on the two carts; the simulation adds
  what it measures, see :meth:`Policy.working_prec`).
* ``max_prec``: the ceiling of refinement for sign decisions (default max(4096, 8 bits(digits))).
* ``allow_unresolved``: what to do with a sign that is neither certified by a ball nor proven
  zero - raise :class:`~lcs_exact.errors.UnresolvedSign` (default) or decide it as zero and
  record the assumption (the result is then not ``certified``).
* a :class:`Deadline` (``time_limit``) checked inside long searches.

A policy is an immutable value carried by the objects a run creates (states, event times), so a
refinement made after :func:`~lcs_exact.simulate.simulate` returns obeys the same ceiling; the
assumptions a run records are appended to the policy's ``assumptions`` list (the only mutable
part, with the deadline).  Ball arithmetic always runs inside :func:`workprec` (flint's ``ctx.prec``
is global state: a product of two 4096-bit balls at the ambient 53 bits loses everything).
"""
from __future__ import annotations

import contextlib
import contextvars
import math
import sys
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator

from flint import arb, ctx, fmpq

from ..algebra import to_short
from ..errors import InvalidArgument, TimeLimitExceeded, UnresolvedSign, Unsupported

__all__ = ["Policy", "Deadline", "check_in_force", "DEFAULT_POLICY", "workprec", "long_int_strings", "check_digits",
           "digits_to_bits", "decide_sign",
           "ball_sign", "MAX_DIGITS", "accuracy_bits", "closed_form_arb", "dyadic", "dyadic_lower",
           "dyadic_upper", "decimal_of_fmpq", "decimal_of_ball"]

#: largest ``digits`` accepted (10^4 digits = 33,220 bits: e^{Mt} at that precision takes seconds)
MAX_DIGITS = 10_000
#: guard bits added to the bits of the promised digits
GUARD_BITS = 16


def check_digits(digits: Any, what: str = "digits") -> int:
    """``digits`` checked, the one rule of every entry point that takes it: a Python ``int`` (not a
    bool, a float, a string or a numpy integer: ``int(...)`` converts one) in 1..``MAX_DIGITS``;
    :class:`~lcs_exact.errors.InvalidArgument` naming ``what`` otherwise.

    Where ``digits`` is taken and its default: a run and its exact numbers, 30
    (``simulate``, ``simulate_branches``, ``Real.ball``, ``Real.decimal``, ``ExactVector.ball``,
    ``lcs-exact simulate --digits``); float-sized samples, 17 (the digits that round-trip a
    float64: ``Trajectory.sample``, ``FixtureTrajectory.sample``); the zoo and the exact values an
    assertion prints, 20 (``write_zoo``, the zoo's ``Problem.run``, ``assert_matches_fixture``,
    ``Violation.message``, ``lcs-exact zoo --digits``); a fixture, its run's ``digits``
    (``Trajectory.to_fixture``).

    Parameters
    ----------
    digits : int
        Correct significant digits asked for.
    what : str, optional
        Its name in the message.

    >>> check_digits(30)
    30
    >>> check_digits(0)
    Traceback (most recent call last):
    ...
    lcs_exact.errors.InvalidArgument: digits must be an integer in 1..10000, got 0
    """
    if isinstance(digits, bool) or not isinstance(digits, int):
        if hasattr(digits, "__index__") and not isinstance(digits, bool):  # numpy, flint, SymPy integers
            raise InvalidArgument(f"{what} must be a Python int in 1..{MAX_DIGITS}, got {to_short(digits)} "
                                  f"({type(digits).__name__}; use int(...))")
        raise InvalidArgument(f"{what} must be an integer, got {to_short(digits)} ({type(digits).__name__})")
    if not 1 <= digits <= MAX_DIGITS:
        raise InvalidArgument(f"{what} must be an integer in 1..{MAX_DIGITS}, got {to_short(digits)}")
    return int(digits)


def digits_to_bits(digits: int) -> int:
    """Bits needed for ``digits`` decimal digits (ceil(digits log2 10)).

    Parameters
    ----------
    digits : int
    """
    return int(math.ceil(digits * 3.3219280948873626)) + 1


@contextlib.contextmanager
def long_int_strings() -> Iterator[None]:
    """Python's int <-> str conversions without the 4300-digit limit (CPython >= 3.11) inside the
    block: 10,000 promised digits are longer than that.  Restored in ``finally``.

    >>> import sys
    >>> with long_int_strings():
    ...     n = len(str(10 ** 5000))
    >>> n
    5001
    """
    get = getattr(sys, "get_int_max_str_digits", None)
    if get is None:
        yield
        return
    old = get()
    sys.set_int_max_str_digits(0)
    try:
        yield
    finally:
        sys.set_int_max_str_digits(old)


class workprec:
    """Scoped flint precision (``ctx.prec`` is process-global): restored on exit, also on an
    exception.  A plain class, not a generator context manager: the evaluation loops enter it
    hundreds of thousands of times in a long run.

    Parameters
    ----------
    prec : int
        Bits.

    Examples
    --------
    >>> from flint import arb, ctx, fmpq
    >>> with workprec(200):
    ...     third = arb(1) / 3
    >>> third.rel_accuracy_bits() >= 198, ctx.prec
    (True, 53)
    """

    __slots__ = ("prec", "old")

    def __init__(self, prec: int):
        self.prec = prec

    def __enter__(self) -> None:
        self.old = ctx.prec
        ctx.prec = self.prec

    def __exit__(self, *exc) -> None:
        ctx.prec = self.old


def accuracy_bits(b: arb) -> int:
    """Relative accuracy of a ball in bits (large for exact balls; 0 for balls containing 0).

    Parameters
    ----------
    b : arb
    """
    if b.is_exact():
        return 1 << 30
    return max(0, b.rel_accuracy_bits())


class Deadline:
    """A wall-clock limit (``time_limit`` seconds from its creation); mutable: a run disarms it
    when it returns, and every later query of its results (``ball``, ``decimal``, ``sample``)
    re-arms it for its own duration (:meth:`query`), so no query runs longer than the run's
    ``time_limit`` either: it ends in :class:`TimeLimitExceeded`, never in a hang.

    ``safety_cuts`` lists the SymPy steps of the run (and of its queries) stopped by their
    wall-clock safety net (:data:`~lcs_exact.forms.SYMPY_SAFETY_NET`): the only outcomes a clock
    decided (a closed form not searched to the end of its work budget), named, never silent.

    Parameters
    ----------
    limit : float or None, optional
        Seconds; None for no limit.
    """

    __slots__ = ("limit", "_end", "safety_cuts")

    def __init__(self, limit: float | None = None):
        self.limit = limit
        self._end = None if limit is None else time.monotonic() + limit
        self.safety_cuts: list[str] = []

    def expired(self) -> bool:
        """True when an armed limit has passed."""
        return self._end is not None and time.monotonic() > self._end

    def check(self, where: str | Callable[[], str] = "") -> None:
        """Raise :class:`TimeLimitExceeded` when the limit has passed (``where``: text, or a callable
        making it - built only when the limit is reached).

        Parameters
        ----------
        where : str or callable, optional
            Appended to the message.
        """
        if self._end is not None and time.monotonic() > self._end:
            if callable(where):
                end, self._end = self._end, None  # the message itself may evaluate numbers
                try:
                    where = where()
                finally:
                    self._end = end
            raise TimeLimitExceeded(f"time_limit = {self.limit} s reached{where}")

    def disarm(self) -> None:
        self._end = None

    def remaining(self) -> float | None:
        """Seconds left (None: no limit armed)."""
        return None if self._end is None else max(0.0, self._end - time.monotonic())

    @contextlib.contextmanager
    def in_force(self) -> Iterator[None]:
        """Inside the block this deadline is the one :func:`check_in_force` looks at: exact
        computations far below the run, holding no policy (Calcium's compactions and zero tests,
        each bounded but together seconds long), stop at it."""
        token = _IN_FORCE.set(self)
        try:
            yield
        finally:
            _IN_FORCE.reset(token)

    @contextlib.contextmanager
    def query(self) -> Iterator[None]:
        """Inside the block, the limit counts from its start (when no run or outer query has
        armed it already); restored on exit.

        >>> d = Deadline(0.0)
        >>> d.disarm()
        >>> with d.query():
        ...     d.check(" in a query")
        Traceback (most recent call last):
        ...
        lcs_exact.errors.TimeLimitExceeded: time_limit = 0.0 s reached in a query
        """
        if self.limit is None or self._end is not None:
            yield
            return
        self._end = time.monotonic() + self.limit
        try:
            with self.in_force():
                yield
        finally:
            self._end = None


#: the deadline of the run or query in progress (:meth:`Deadline.in_force`)
_IN_FORCE: contextvars.ContextVar = contextvars.ContextVar("lcs_exact_deadline", default=None)


def check_in_force(where: str = "") -> None:
    """Check the deadline of the run or query in progress, if any (:meth:`Deadline.in_force`):
    raise :class:`TimeLimitExceeded` when it has passed.

    >>> d = Deadline(0.0)
    >>> check_in_force()                      # no run in progress: nothing to check
    >>> with d.in_force():
    ...     check_in_force(" in a test")
    Traceback (most recent call last):
    ...
    lcs_exact.errors.TimeLimitExceeded: time_limit = 0.0 s reached in a test
    """
    d = _IN_FORCE.get()
    if d is not None:
        d.check(where)


#: bits above a state's accuracy that a run computes the next event with (a state computed from
#: a ball gains nothing from more bits than that ball carries)
ACCURACY_HEADROOM = 64


@dataclass(frozen=True, eq=False)
class Policy:
    """The precision policy of a run (see the module docstring).

    Attributes
    ----------
    digits : int
        Correct significant digits promised for every reported number.
    max_prec : int
        The refinement ceiling in bits; 0 for max(4096, 8 bits(digits)).
    allow_unresolved : bool
        Decide an unresolved zero as zero and record it (True), or raise UnresolvedSign.
    closed_forms : {"lazy", "eager", "off"}
        Closed forms proven on first access, at every event, or never.
    deadline : Deadline
        The run's wall-clock limit.
    assumptions : list of str
        The zeros assumed so far (appended to: a run's ``assumptions``).

    Examples
    --------
    >>> p = Policy(digits=30)
    >>> p.target_bits, p.max_prec
    (117, 4096)
    """

    digits: int = 30
    max_prec: int = 0
    allow_unresolved: bool = False
    closed_forms: str = "lazy"
    deadline: Deadline = field(default_factory=Deadline)
    assumptions: list = field(default_factory=list)

    def __post_init__(self):
        if self.max_prec <= 0:
            object.__setattr__(self, "max_prec", max(4096, 8 * digits_to_bits(self.digits)))

    @property
    def target_bits(self) -> int:
        """Bits that every reported number is refined to (the promised digits + guard bits)."""
        return digits_to_bits(self.digits) + GUARD_BITS

    def working_prec(self, lost_bits: int = 0) -> int:
        """Working precision of anchors: the target, 32 bits of headroom, and the accuracy the run
        has measured as lost so far (``lost_bits``).

        Parameters
        ----------
        lost_bits : int, optional
            The accuracy lost so far, measured.
        """
        return min(self.target_bits + 32 + max(0, lost_bits), 16 * max(self.max_prec, self.target_bits + 64))

    def check_deadline(self, where: str | Callable[[], str] = "") -> None:
        """Raise TimeLimitExceeded when the deadline has passed (:meth:`Deadline.check`).

        Parameters
        ----------
        where : str or callable
            As :meth:`Deadline.check`.
        """
        self.deadline.check(where)

    def unresolved(self, what: str | Callable[[], str]) -> int:
        """An unresolved zero: raise :class:`UnresolvedSign`, or record it as an assumption and
        decide it as zero (``allow_unresolved``).

        Parameters
        ----------
        what : str or callable
            The quantity, for the message (a callable: built only when needed).
        """
        text = what() if callable(what) else what
        if self.deadline.safety_cuts:  # a proof of zero may have been cut short by a clock: say so
            text += (f" (not searched to the end: {len(self.deadline.safety_cuts)} SymPy step(s) of this run "
                     f"stopped by their wall-clock safety net, the first {self.deadline.safety_cuts[0]})")
        if self.allow_unresolved:
            if text not in self.assumptions:
                self.assumptions.append(text)
            return 0
        raise UnresolvedSign(f"cannot decide the sign of {text}: the ball contains 0 at "
                             f"{self.max_prec} bits and no proof of zero is known")


DEFAULT_POLICY = Policy()


def ball_sign(b: arb) -> int:
    """Sign of a ball when certain: +1, -1; 0 when the ball contains 0 (undecided, not zero).

    Parameters
    ----------
    b : arb
    """
    if b > 0:
        return 1
    if b < 0:
        return -1
    return 0


#: dyadics of magnitude beyond 2^(+-MAX_DYADIC_EXPONENT) are not built (a rational of millions
#: of bits: a sign of a runaway bound, not of a value the engine needs)
MAX_DYADIC_EXPONENT = 1 << 24


def dyadic(x: arb) -> fmpq:
    """The exact midpoint of a ball as fmpq (:class:`Unsupported` beyond 2^(+-2^24)).

    Parameters
    ----------
    x : arb
    """
    m, e = x.mid().man_exp()
    m, e = int(m), int(e)
    if abs(e) > MAX_DYADIC_EXPONENT:
        raise Unsupported(f"a number of magnitude 2^{e} arose (beyond 2^(+-{MAX_DYADIC_EXPONENT}), "
                          "docs/limits.md): the system's rates or entries are too far apart")
    return fmpq(m << e) if e >= 0 else fmpq(m, 1 << -e)


def dyadic_lower(x: arb) -> fmpq:
    """A dyadic rational <= every point of the ball.

    Parameters
    ----------
    x : arb
    """
    return dyadic(x.lower())


def dyadic_upper(x: arb) -> fmpq:
    """A dyadic rational >= every point of the ball.

    Parameters
    ----------
    x : arb
    """
    return dyadic(x.upper())


def decide_sign(compute: Callable[[int], arb], *, policy: Policy, what: str | Callable[[], str],
                start: int = 64, prove_zero: Callable[[], bool | None] | None = None) -> int:
    """Certified sign of a quantity whose ball at ``prec`` bits is ``compute(prec)``.

    Order (docs/numerics.md): a ball that excludes 0 at ``start`` bits; then, if given,
    ``prove_zero()`` (structure, homogeneity, closed forms: True = proven 0, False = proven
    nonzero, None = unknown) is tried once, because an exact zero never shows in a ball;
    then refinement by doubling up to ``policy.max_prec`` (beyond it only for a quantity proven
    nonzero); then :meth:`Policy.unresolved`.
    """
    prec = max(start, 32)
    proof: bool | None = None
    tried = prove_zero is None
    while True:
        policy.check_deadline()
        with workprec(prec):
            s = ball_sign(compute(prec))
        if s:
            return s
        if not tried:
            tried = True
            proof = prove_zero()
            if proof is True:
                return 0
        if prec >= policy.max_prec and not (proof is False and prec < 16 * policy.max_prec):
            return policy.unresolved(what)
        prec *= 2


_ARB_FUNCS = {
    "exp": lambda a: a.exp(), "log": lambda a: a.log(), "sin": lambda a: a.sin(),
    "cos": lambda a: a.cos(), "tan": lambda a: a.tan(), "atan": lambda a: a.atan(),
    "asin": lambda a: a.asin(), "acos": lambda a: a.acos(), "sinh": lambda a: a.sinh(),
    "cosh": lambda a: a.cosh(), "tanh": lambda a: a.tanh(), "atanh": lambda a: a.atanh(),
    "asinh": lambda a: a.asinh(),
}


def closed_form_arb(e) -> arb:
    """Rigorous arb value of a SymPy closed form at the current precision (no SymPy numerics;
    the expression tree is walked and every operation is a ball operation)."""
    if e.is_Rational:
        return arb(fmpq(int(e.p), int(e.q)))
    name = type(e).__name__
    if name == "Pi":
        return arb.pi()
    if name == "Exp1":
        return arb(1).exp()
    if e.is_Add:
        out = arb(0)
        for a in e.args:
            out += closed_form_arb(a)
        return out
    if e.is_Mul:
        out = arb(1)
        for a in e.args:
            out *= closed_form_arb(a)
        return out
    if e.is_Pow:
        base, ex = e.args
        b = closed_form_arb(base)
        if ex.is_Integer:
            return b ** int(ex)
        if ex.is_Rational:
            return b ** arb(fmpq(int(ex.p), int(ex.q)))
        return (b.log() * closed_form_arb(ex)).exp()
    f = _ARB_FUNCS.get(type(e).__name__)
    if f is not None and len(e.args) == 1:
        return f(closed_form_arb(e.args[0]))
    raise InvalidArgument(f"closed form {e} is outside the supported set (rationals, pi, E, +, *, powers, "
                     f"exp, log, trigonometric functions)")


# ---------------------------------------------------------------------------------------------
# text: decimals with an error bound
# ---------------------------------------------------------------------------------------------

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
    if mid.is_zero() and b.rad() == 0:
        return "0"  # an exact zero (a component proven to vanish): no digits to bound
    with mp.workdps(digits + 20):
        m = mpf(mid.str(digits + 15, radius=False)) if not mid.is_zero() else mpf(0)
        s = nstr(m, digits, strip_zeros=False, min_fixed=-5, max_fixed=digits + 1)
        err = abs(mpf(s) - m) + mpf(b.rad().str(5, radius=False)) * 2 + abs(m) * mpf(10) ** (-(digits + 12))
        return f"{s} +/- {_bound_up(err)}"

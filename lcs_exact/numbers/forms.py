"""Closed forms of real numbers, kept light: SymPy is built from them only when asked.

A :class:`Closed` is c_0 + sum_j c_j a_j with rational coefficients and *atoms* a_j:

* ``("pi", r)``: pi / sqrt(r) for a positive rational r - the times (p/q) pi / omega of an
  oscillation of frequency omega = sqrt(r) (section 7's 1 + pi/2 is 1 + 1/2 ("pi", 1));
* ``("log", r)``: log r for a positive rational r != 1 - the times of real exponentials;
* ``("sym", e)``: a SymPy expression - whatever the symbolic last resort of
  :mod:`lcs_exact.closedforms` proves (an arctangent, a radical).

Candidates of event times are built as forms, proven by Calcium (:meth:`Closed.to_ca`: an exact
number whose zero test never answers wrongly) and placed in their bracket by arb balls
(:meth:`Closed.arb`); sums of event times stay forms.  A run and its printout (``str`` matches
SymPy's for rationals and rational multiples of pi / sqrt(r)) therefore never import SymPy;
``Real.closed_form`` converts with :meth:`Closed.to_sympy` on first access.  Forms are immutable
and compare structurally (equal forms are equal numbers; the converse needs a proof).
"""
from __future__ import annotations

import contextlib
import signal
import sys
import threading
from typing import Any

from flint import arb, fmpq

from . import calcium
from .balls import closed_form_arb, workprec
from ..errors import InvalidArgument

__all__ = ["Closed", "ca_of_sympy", "sympy_proves_zero", "sympy_budget", "SympyOutOfTime", "SYMPY_WORK",
           "SYMPY_SAFETY_NET"]

#: the work one SymPy step may do (a simplification, a symbolic inversion, a family of candidates),
#: counted in Python function calls: SymPy's ``simplify`` has no limit of its own (on a
#: trigonometric expression of nested radicals it ran for minutes), and a limit in seconds would
#: make a closed form, or a decision that needs one, depend on the machine and its load.  About
#: 5 s of SymPy on a 2-core machine of 2026 (0.8 million calls a second; the longest step of the
#: test suite made 0.6 million); the same step ends at the same point anywhere.
SYMPY_WORK = 4_000_000

#: seconds: the safety net under :data:`SYMPY_WORK` for work the count cannot see (a long call
#: into C: a product of huge integers, a factorization in FLINT).  A step it stops is *not
#: searched* (recorded on the run's deadline, :attr:`~lcs_exact.balls.Deadline.safety_cuts`, and
#: named in the message of a decision that then fails), never reported as having no closed form.
SYMPY_SAFETY_NET = 120.0

#: calls between two looks at the run's deadline inside a SymPy step
_DEADLINE_STRIDE = 20_000


def _squarefree(m: int) -> tuple[int, int]:
    """(s, f) with m = s^2 f, f squarefree (m > 0, small: trial division)."""
    s, f, p = 1, 1, 2
    while p * p <= m:
        while m % (p * p) == 0:
            m //= p * p
            s *= p
        if m % p == 0:
            m //= p
            f *= p
        p += 1
    return s, f * m


class Closed:
    """c_0 + sum c_j a_j (see the module docstring).

    Parameters
    ----------
    const : int, fmpz or fmpq, optional
        c_0 (default 0).
    terms : tuple of (atom, fmpq), optional
        The pairs (a_j, c_j), atoms ``("pi", r)``, ``("log", r)`` or ``("sym", expr)``: equal atoms
        are merged, zero coefficients dropped, pi atoms normalized (r a squarefree integer, unless huge).

    >>> half_pi = Closed.pi_over_sqrt(1) * fmpq(1, 2)
    >>> str(Closed.rational(1) + half_pi), str(Closed.pi_over_sqrt(2)), str(-half_pi * 3)
    ('1 + pi/2', 'sqrt(2)*pi/2', '-3*pi/2')
    >>> (half_pi + half_pi) == Closed.pi_over_sqrt(1), Closed.rational(fmpq(3, 4)).to_fmpq()
    (True, 3/4)
    """

    __slots__ = ("const", "terms", "_sym")

    def __init__(self, const: Any = 0, terms: tuple = ()):
        acc: dict = {}
        for atom, c in terms:
            if atom[0] == "pi":
                c, atom = _pi_normal(atom[1], c)
            acc[atom] = acc.get(atom, fmpq(0)) + c
        self.const = fmpq(const)
        self.terms = tuple(sorted(((a, c) for a, c in acc.items() if c != 0), key=_atom_key))
        self._sym = None

    # --- construction -------------------------------------------------------------------------
    @classmethod
    def rational(cls, q: Any) -> "Closed":
        """The rational q as a form.

        Parameters
        ----------
        q : int, fmpz or fmpq
        """
        return cls(fmpq(q))

    @classmethod
    def pi_over_sqrt(cls, r: Any) -> "Closed":
        """pi / sqrt(r).

        Parameters
        ----------
        r : int, fmpz or fmpq
            Positive (:class:`~lcs_exact.errors.InvalidArgument` otherwise).
        """
        r = fmpq(r)
        if not r > 0:
            raise InvalidArgument(f"pi / sqrt(r) needs r > 0, got {r}")
        return cls(0, ((("pi", r), fmpq(1)),))

    @classmethod
    def log(cls, r: Any) -> "Closed":
        """log r (log 1 = 0, the form 0).

        Parameters
        ----------
        r : int, fmpz or fmpq
            Positive (:class:`~lcs_exact.errors.InvalidArgument` otherwise).
        """
        r = fmpq(r)
        if not r > 0:
            raise InvalidArgument(f"log r needs r > 0, got {r}")
        return cls() if r == 1 else cls(0, ((("log", r), fmpq(1)),))

    @classmethod
    def of_sympy(cls, expr: Any) -> "Closed":
        """A SymPy expression as a form (a rational stays a rational; anything else is one ``sym`` atom).

        Parameters
        ----------
        expr : sympy.Expr
        """
        if getattr(expr, "is_Rational", False):
            return cls(fmpq(int(expr.p), int(expr.q)))
        out = cls(0, ((("sym", expr), fmpq(1)),))
        out._sym = expr
        return out

    # --- arithmetic ---------------------------------------------------------------------------
    def __add__(self, other: Any) -> "Closed":
        o = other if isinstance(other, Closed) else Closed(fmpq(other))
        return Closed(self.const + o.const, self.terms + o.terms)

    __radd__ = __add__

    def __neg__(self) -> "Closed":
        return self * -1

    def __sub__(self, other: Any) -> "Closed":
        o = other if isinstance(other, Closed) else Closed(fmpq(other))
        return self + (-o)

    def __rsub__(self, other: Any) -> "Closed":
        return Closed(fmpq(other)) - self

    def __mul__(self, q: Any) -> "Closed":
        if isinstance(q, Closed):
            if q.is_rational:
                q = q.const
            elif self.is_rational:
                return q * self.const
            else:
                return Closed.of_sympy(self.to_sympy() * q.to_sympy())
        q = fmpq(q)
        return Closed(self.const * q, tuple((a, c * q) for a, c in self.terms))

    __rmul__ = __mul__

    def __eq__(self, other: Any) -> bool:
        if not isinstance(other, Closed):
            try:
                other = Closed(fmpq(other))
            except (TypeError, ValueError):
                return NotImplemented
        return self.const == other.const and self.terms == other.terms

    def __hash__(self) -> int:
        return hash((str(self.const), tuple((_atom_key((a, c)), str(c)) for a, c in self.terms)))

    # --- queries ------------------------------------------------------------------------------
    @property
    def is_rational(self) -> bool:
        return not self.terms

    def to_fmpq(self) -> fmpq | None:
        return self.const if not self.terms else None

    @property
    def is_zero(self) -> bool:
        """Structurally zero (a form with atoms may still equal 0: that needs a proof)."""
        return not self.terms and self.const == 0

    @property
    def has_pi(self) -> bool:
        """pi occurs (a light atom, or inside a SymPy atom)."""
        for (kind, x), _ in self.terms:
            if kind == "pi":
                return True
            if kind == "sym":
                import sympy
                if x.has(sympy.pi):
                    return True
        return False

    # --- conversions --------------------------------------------------------------------------
    def arb(self) -> arb:
        """A ball of the value at the ambient precision (callers scope it with workprec)."""
        out = arb(self.const)
        for (kind, x), c in self.terms:
            if kind == "pi":
                v = arb.pi() / arb(x).sqrt()
            elif kind == "log":
                v = arb(x).log()
            else:
                v = closed_form_arb(x)
            out += v * arb(c)
        return out

    def to_ca(self):
        """The exact Calcium number of the form (None when Calcium is unavailable)."""
        if not calcium.available():
            return None
        out = calcium.Ca(self.const)
        for (kind, x), c in self.terms:
            if kind == "pi":
                v = calcium.Ca.pi() / calcium.Ca(x).sqrt()
            elif kind == "log":
                v = calcium.Ca(x).log()
            else:
                v = ca_of_sympy(x)
                if v is None:
                    return None
            out = out + v * calcium.Ca(c)
        return out

    def to_sympy(self):
        """The form as a SymPy expression (built once)."""
        if self._sym is None:
            import sympy
            out = _sympy_q(sympy, self.const)
            for (kind, x), c in self.terms:
                if kind == "pi":
                    v = sympy.pi / sympy.sqrt(_sympy_q(sympy, x))
                elif kind == "log":
                    v = sympy.log(_sympy_q(sympy, x))
                else:
                    v = x
                out += _sympy_q(sympy, c) * v
            self._sym = out
        return self._sym

    def __str__(self) -> str:
        """SymPy's text for rationals and rational multiples of pi / sqrt(r) (built here, without
        SymPy); SymPy's own for anything else, and for pi / sqrt(r) with a huge r (whose square
        factors a trial division would take hours to find: SymPy's search of them is bounded)."""
        if any(kind != "pi" or not _small(r) for (kind, r), _ in self.terms):
            return str(self.to_sympy())
        parts = [str(self.const)] if self.const != 0 or not self.terms else []
        for (_, r), c in self.terms:
            parts.append(_pi_text(r, c))
        out = parts[0]
        for p in parts[1:]:
            out += f" - {p[1:]}" if p.startswith("-") else f" + {p}"
        return out

    def __repr__(self) -> str:
        return f"Closed({self})"


def _small(r) -> bool:
    """r = a/b with ab <= 10^12: its square factors are found by trial division at once."""
    return int(r.p) * int(r.q) <= 10 ** 12


def _pi_normal(r: fmpq, c: fmpq) -> tuple[fmpq, tuple]:
    """c pi / sqrt(r) as c' pi / sqrt(f), f a squarefree integer: pi / sqrt(a/b) = sqrt(ab) pi / a
    = s sqrt(f) pi / a = (s f / a) pi / sqrt(f) with ab = s^2 f (equal values, equal atoms; a
    huge r is left as it is)."""
    a, b = int(r.p), int(r.q)
    if not _small(r):
        return c, ("pi", r)
    s, f = _squarefree(a * b)
    return c * fmpq(s * f, a), ("pi", fmpq(f))


def _atom_key(item: tuple) -> tuple:
    (kind, x), _ = item
    return (kind, str(x))


def _sympy_q(sympy: Any, q: fmpq):
    return sympy.Rational(int(q.p), int(q.q))


def _pi_text(r: fmpq, c: fmpq) -> str:
    """c pi / sqrt(r) as SymPy prints it: pi / sqrt(a/b) = sqrt(ab) pi / a = s sqrt(f) pi / a."""
    a, b = int(r.p), int(r.q)
    s, f = _squarefree(a * b)
    k = c * fmpq(s, a)
    body = "pi" if f == 1 else f"sqrt({f})*pi"
    p, q = abs(int(k.p)), int(k.q)
    if p != 1:
        body = f"{p}*{body}"
    if q != 1:
        body = f"{body}/{q}"
    return f"-{body}" if k < 0 else body


# ---------------------------------------------------------------------------------------------
# closed forms written as SymPy expressions
# ---------------------------------------------------------------------------------------------

def _sympy_node(e: Any, rec) -> Any:
    """One node of a SymPy expression tree as a Ca (children through ``rec``); dispatch by class
    name, so this module never imports SymPy."""
    name = type(e).__name__
    if getattr(e, "is_Rational", False):
        return calcium.Ca(fmpq(int(e.p), int(e.q)))
    if name == "Pi":
        return calcium.Ca.pi()
    if name == "Exp1":
        return calcium.Ca(1).exp()
    if name == "ImaginaryUnit":
        return calcium.Ca.i()
    args = [rec(a) for a in e.args]
    if any(a is None for a in args):
        return None
    if name == "Add":
        out = args[0]
        for a in args[1:]:
            out = out + a
        return out
    if name == "Mul":
        out = args[0]
        for a in args[1:]:
            out = out * a
        return out
    if name == "Pow":
        ex = e.args[1]
        if getattr(ex, "is_Integer", False):
            return args[0] ** int(ex)
        if getattr(ex, "is_Rational", False) and int(ex.q) == 2:
            return args[0].compact().sqrt() ** int(ex.p)  # (compact: see below)
        return (args[0].log() * args[1]).exp()
    unary = {"exp": calcium.Ca.exp, "log": calcium.Ca.log, "sin": calcium.Ca.sin, "cos": calcium.Ca.cos, "atan": calcium.Ca.atan,
             "acos": calcium.Ca.acos, "asin": calcium.Ca.asin}
    if name in unary and len(args) == 1:
        # an algebraic argument by its minimal polynomial (Ca.compact): acos of a root of a
        # quartic written in nested radicals leaves a field of 8 generators where zero tests fail
        return unary[name](args[0].compact())
    if name == "tan" and len(args) == 1:
        return args[0].sin() / args[0].cos()
    if name in ("sinh", "cosh") and len(args) == 1:
        p, m = args[0].exp(), (-args[0]).exp()
        return (p - m) / 2 if name == "sinh" else (p + m) / 2
    return None


def ca_of_sympy(expr: Any) -> Any:
    """The Calcium number of a SymPy closed form (rationals, pi, E, I, +, *, integer and
    half-integer powers, exp, log, sin, cos, tan, atan, asin, acos, sinh, cosh); None when the
    expression uses anything else or Calcium is unavailable.  The tree is walked with an
    explicit stack (deep sums cannot exhaust the Python stack).

    >>> import sympy
    >>> ca_of_sympy(sympy.exp(sympy.I * sympy.pi) + 1).is_zero()
    True
    """
    if not calcium.available():
        return None
    done: dict = {}
    stack = [(expr, False)]
    while stack:
        node, ready = stack.pop()
        if id(node) in done:
            continue
        if ready:
            done[id(node)] = _sympy_node(node, lambda a: done[id(a)])
            continue
        stack.append((node, True))
        stack.extend((a, False) for a in node.args if id(a) not in done)
    return done[id(expr)]


class SympyOutOfTime(BaseException):
    """A SymPy step stopped by :func:`sympy_budget` (its work spent, or its safety net): raised
    inside SymPy as a BaseException (SymPy's own ``except Exception`` clauses must not swallow
    it); ``cut`` is True when the wall-clock safety net stopped it (the step was not searched to
    the end of its work)."""

    def __init__(self, cut: bool = False):
        super().__init__(cut)
        self.cut = cut


class _Stop(BaseException):
    """Raised inside SymPy by the counter or the alarm of :func:`sympy_budget`; ``why`` is
    "work", "deadline" or "safety" (translated when the step is left)."""

    def __init__(self, why: str):
        super().__init__(why)
        self.why = why


class _Counter:
    """The global trace function of a SymPy step: counts Python calls (``call`` events), raises
    :class:`_Stop` when ``left`` reaches 0 and, every ``_DEADLINE_STRIDE`` calls, when the run's
    deadline has passed; chains to the trace function that was installed before (a debugger, a
    coverage tracer), whose answer it returns."""

    __slots__ = ("left", "deadline", "old", "tick")

    def __init__(self, left: int, deadline, old):
        self.left, self.deadline, self.old, self.tick = left, deadline, old, 0

    def __call__(self, frame, event, arg):
        self.left -= 1
        if self.left < 0:
            raise _Stop("work")
        self.tick += 1
        if self.tick >= _DEADLINE_STRIDE:
            self.tick = 0
            if self.deadline is not None and self.deadline.expired():
                raise _Stop("deadline")
        return self.old(frame, event, arg) if self.old is not None else None


@contextlib.contextmanager
def _alarm(seconds: float):
    """SIGALRM after ``seconds`` raises :class:`_Stop` ("safety") in the block; a no-op off the main
    thread, where signals are unavailable, or when a timer of the caller is already running."""
    usable = (hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
              and signal.getitimer(signal.ITIMER_REAL)[0] == 0)
    if not usable:
        yield
        return

    def on_alarm(signum, frame):
        raise _Stop("safety")

    old = signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3))
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def sympy_proves_zero(expr: Any, deadline=None) -> bool | None:
    """True when SymPy simplifies the real closed form ``expr`` to 0, False when its certified
    ball excludes 0, None when neither is shown within the work of :func:`sympy_budget`
    (``deadline``: the run's :class:`~lcs_exact.balls.Deadline`; past it,
    :class:`~lcs_exact.errors.TimeLimitExceeded`).

    Parameters
    ----------
    expr : sympy.Expr
        A real closed form.
    deadline : Deadline, optional
        The run's ``time_limit``; None (default): the work bound alone.

    >>> import sympy
    >>> sympy_proves_zero(sympy.sin(sympy.pi / 7)**2 + sympy.cos(sympy.pi / 7)**2 - 1)
    True
    >>> sympy_proves_zero(sympy.sqrt(2) - sympy.Rational(140, 99))
    False
    """
    import sympy
    try:
        with workprec(128):
            b = closed_form_arb(expr)
        if not b.contains(0):
            return False
    except InvalidArgument:
        pass  # no ball for this form: only SymPy can say
    try:
        with sympy_budget(deadline, "SymPy's simplification of a candidate zero"):
            return True if sympy.simplify(expr) == 0 else None
    except SympyOutOfTime:
        return None


@contextlib.contextmanager
def sympy_budget(deadline=None, what: str = "a SymPy step"):
    """Bound the SymPy work of the block (pure SymPy: a simplification, a symbolic inversion, a
    search for candidates) by :data:`SYMPY_WORK` Python calls: past it, :class:`SympyOutOfTime`
    is raised out of the block, at the same point on every machine and under any load.  A
    wall-clock safety net of :data:`SYMPY_SAFETY_NET` seconds catches work the count cannot
    see (one long call into C); a step it stops raises :class:`SympyOutOfTime` with ``cut``
    True and is recorded on ``deadline`` (``deadline.safety_cuts``: the closed form was not
    searched, which is not "none").  ``deadline`` (a :class:`~lcs_exact.balls.Deadline`, the
    run's ``time_limit``) is looked at during the step: past it,
    :class:`~lcs_exact.errors.TimeLimitExceeded` (the run is cut short, never given another
    outcome).  A block inside another runs under the outer one's count.

    >>> def depth(n):
    ...     return 0 if n == 0 else 1 + depth(n - 1)
    >>> with sympy_budget():
    ...     depth(100)
    100
    """
    outer = sys.gettrace()
    if isinstance(outer, _Counter):  # nested: the outer step's count and net govern
        yield
        return
    left = None if deadline is None else deadline.remaining()
    counter = _Counter(SYMPY_WORK, deadline, outer)
    try:
        with _alarm(SYMPY_SAFETY_NET if left is None else min(SYMPY_SAFETY_NET, left + 0.05)):
            sys.settrace(counter)
            try:
                yield
            finally:
                sys.settrace(outer)
    except _Stop as stop:
        why = stop.why
        if why != "work" and deadline is not None and deadline.expired():
            deadline.check(f" in {what}")  # raises TimeLimitExceeded
        if why == "safety":
            if deadline is not None:
                deadline.safety_cuts.append(f"{what} (stopped after {SYMPY_SAFETY_NET:g} s)")
            raise SympyOutOfTime(cut=True) from None
        if why == "deadline":  # (expired() said so; the check above raised)
            raise SympyOutOfTime(cut=True) from None
        raise SympyOutOfTime from None

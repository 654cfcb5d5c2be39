"""Exact real and complex numbers with a safe zero test: a small ctypes binding to FLINT's Calcium.

Calcium (``ca_*``, ``qqbar_*``, part of FLINT 3) represents a number exactly, as an element of a field
Q(a_1, ..., a_n) whose generators are algebraic numbers or closed forms (pi, exp, log, ...).  Its predicates
never answer wrongly: they answer true, false or *unknown*.  python-flint has no Python binding for Calcium,
but the FLINT library it ships (``python_flint.libs/``) exports it: this module loads it with :mod:`ctypes`.

Representation
--------------
* :class:`Ca` wraps one ``ca_t``: a private ctypes buffer (twice ``sizeof(ca_struct)``), initialized with
  ``ca_init`` and freed with ``ca_clear`` when the wrapper is collected.  The buffer never leaves the wrapper, so
  no two wrappers share a ``ca_t``.
* All numbers live in one module-level ``ca_ctx_t``, created on first use and cleared at interpreter exit
  (``atexit``); after that no ``ca_clear`` is called any more.
* Every call into FLINT holds one module-level re-entrant lock: the context is mutated even by queries (caches),
  so the lock makes the module safe to use from several threads (they are serialized).  A running Calcium call
  cannot be interrupted (Ctrl-C waits for it).

Invariants
----------
* A :class:`Ca` is immutable and always holds a *number*: never one of Calcium's special values (Unknown,
  Undefined, infinities).  An operation whose result would be special raises instead: ``ZeroDivisionError``
  (divisor proven zero), ``ValueError`` (undefined or infinite, e.g. ``log(0)``),
  :class:`~lcs_exact.errors.UnresolvedSign` (Calcium could not decide, e.g. whether a divisor is zero).
* A FLINT abort would kill the process, so no call gets an input Calcium documents as invalid: divisions go
  through ``ca_inv`` (which answers Unknown or infinity for a zero divisor, never aborts) and are checked before
  the product is formed; negative powers go through that inverse; every result is checked for special values
  before it is used.  (The aborts left in Calcium's sources are internal-consistency checks.)
* Enclosures are rigorous: the true value lies in the returned ``flint.acb`` (see :meth:`Ca.enclosure`).
* ``str(x)`` is Calcium's ``ca_get_str``: a 6-digit value, then the exact form in braces
  (``1.41421 {a where a = 1.41421 [a^2-2=0]}``); an integer prints alone (``3``).

What ``None`` means
-------------------
:meth:`Ca.is_zero`, :meth:`Ca.is_rational`, :meth:`Ca.is_real` and :meth:`Ca.sign` return ``None`` when Calcium
could not decide.  ``None`` is never a guess and never means "probably": callers must treat it as "undecided"
(for a sign, fall back to a ball, or raise :class:`~lcs_exact.errors.UnresolvedSign`).  :meth:`Ca.to_fmpq`
returns ``None`` whenever the value is not *proven* rational (undecided, or proven irrational).

Pitfalls
--------
* Calcium caches every generator (``exp(1)``, ``log(2)``, fields built from them) in the context for the life of
  the process: memory per *number* is returned on collection, but memory per distinct *generator* is not
  (measured: 20,000 distinct ``log(k)`` keep 9 MB).
* A zero test can be slow (it may compute to 4096 bits, factor, or run Groebner bases) and cannot be interrupted;
  the examples in ``tests/test_calcium.py`` take milliseconds.
* ``Ca`` objects cannot be pickled; ``copy.copy`` returns the same (immutable) object.

The ctypes layer (struct layouts checked against the library, signatures, context, lock): :mod:`lcs_exact.flintlib`.

>>> from lcs_exact import calcium
>>> calcium.available()
True
>>> x = (calcium.Ca.i() * calcium.Ca.pi()).exp() + 1     # e^{i pi} + 1
>>> x.is_zero()
True
"""
from __future__ import annotations

import ctypes
from fractions import Fraction  # noqa: F401 -- used by the doctests
from numbers import Integral
from typing import Any, Sequence

import flint  # noqa: F401 -- used by the doctests
from flint import acb, arb, fmpq, fmpz

from .balls import check_in_force
from ..errors import NotRational, UnresolvedSign
from .flintlib import (CA_UNDEFINED, CA_UNKNOWN, CA_WORDS, AcbStruct, FmpqStruct, QqbarStruct, acb_from_address,
                       available, backend, c_ulong, fmpz_to_int, qqbar_degree_limit, qqbar_distinct_roots,
                       select_qqbar_root, take_str, truth)
from ..algebra import to_fmpq

__all__ = ["available", "Ca", "real_roots", "COMPACT_DEGREE_LIMIT"]

#: Calcium's degree limit in :meth:`Ca.compact` (120 elsewhere): intermediate degrees exceed the
#: final one (a degree-8 event time of five elastic beads needs 360 from four generators)
COMPACT_DEGREE_LIMIT = 480

# ---- the number ------------------------------------------------------------------------------

def _coerce(x: Any) -> "Ca":
    return x if isinstance(x, Ca) else Ca(x)


class Ca:
    """An exact complex number of Calcium (immutable).  Arithmetic (``+ - * /``, ``**`` with an int
    exponent) mixes with the rationals ``value`` may be.  ``==``, ``<``, ``bool()`` and ``hash()`` are
    refused (TypeError): decide with :meth:`is_zero` / :meth:`sign`, which may answer None (undecided).

    Parameters
    ----------
    value : rational-like or Ca, optional
        An exact rational (default 0): int, ``fmpz``, ``fmpq``, ``Fraction``, a ``"p/q"`` or decimal
        string (anything :func:`lcs_exact.rational.to_fmpq` accepts), or another ``Ca``.

    Raises
    ------
    NotRational
        ``value`` is not an exact rational (e.g. an ``arb``, ``"pi"``).
    RuntimeError
        Calcium is not available (see :func:`available`).

    Examples
    --------
    >>> x = Ca(2).sqrt()
    >>> (x * x - 2).is_zero(), (x - Fraction(14142, 10000)).is_zero()
    (True, False)
    >>> Ca("3/4") + 1
    Ca(1.75000 {7/4})
    """

    __slots__ = ("_buf", "_ptr", "_b")

    def __init__(self, value: Any = 0):
        b = backend()
        self._b = None
        self._buf = (c_ulong * CA_WORDS)()
        self._ptr = ctypes.addressof(self._buf)
        if isinstance(value, Ca):
            with b.lock:
                b.lib.ca_init(self._ptr, b.ctx)
                self._b = b
                b.lib.ca_set(self._ptr, value._ptr, b.ctx)
            return
        q = to_fmpq(value, "Ca value")
        p, d = int(q.p), int(q.q)
        with b.lock:
            b.lib.ca_init(self._ptr, b.ctx)
            self._b = b
            if d == 1 and -(1 << 62) < p < (1 << 62):
                b.lib.ca_set_si(self._ptr, p, b.ctx)
            else:
                fq = FmpqStruct(0, 0)
                try:
                    for field, v in (("num", p), ("den", d)):
                        ok = b.lib.fmpz_set_str(ctypes.addressof(fq) + getattr(FmpqStruct, field).offset,
                                                format(v, "x").encode(), 16)
                        if ok != 0:
                            raise ValueError(f"fmpz_set_str failed on {v!r}")
                    b.lib.ca_set_fmpq(self._ptr, ctypes.byref(fq), b.ctx)   # canonical: gcd 1, den > 0
                finally:
                    b.lib.fmpq_clear(ctypes.byref(fq))

    @classmethod
    def _new(cls) -> "Ca":
        """A fresh wrapper holding 0, to be overwritten by a FLINT call (caller holds the lock)."""
        b = backend()
        self = cls.__new__(cls)
        self._b = None
        self._buf = (c_ulong * CA_WORDS)()
        self._ptr = ctypes.addressof(self._buf)
        b.lib.ca_init(self._ptr, b.ctx)
        self._b = b
        return self

    def __del__(self) -> None:
        b = getattr(self, "_b", None)
        if b is not None and b.alive:
            with b.lock:
                if b.alive:
                    b.lib.ca_clear(self._ptr, b.ctx)
            self._b = None

    def __copy__(self) -> "Ca":
        return self                             # immutable; never copy the ca_t buffer

    def __deepcopy__(self, memo: Any) -> "Ca":
        return self

    def __reduce__(self) -> Any:
        raise TypeError("Ca cannot be pickled (it wraps a FLINT object)")

    @classmethod
    def pi(cls) -> "Ca":
        """The constant pi.

        >>> Ca.pi().enclosure(30).real.overlaps(flint.arb.pi())
        True
        """
        b = backend()
        with b.lock:
            r = cls._new()
            b.lib.ca_pi(r._ptr, b.ctx)
        return r

    @classmethod
    def i(cls) -> "Ca":
        """The imaginary unit.

        >>> (Ca.i() ** 2 + 1).is_zero()
        True
        """
        b = backend()
        with b.lock:
            r = cls._new()
            b.lib.ca_i(r._ptr, b.ctx)
        return r

    @classmethod
    def algebraic(cls, coeffs: Sequence[Any], approx: Any) -> "Ca":
        """The root of ``sum(coeffs[j] * s**j)`` singled out by ``approx``.  The roots' enclosures
        (``qqbar_get_acb``) are refined up to 8192 bits until the choice is proven.  Repeated roots count once.

        Parameters
        ----------
        coeffs : sequence of rationals
            Exact, low degree first, not all zero beyond degree 0.
        approx : acb, arb, complex, float or rational
            An ``acb`` / ``arb`` of nonzero radius selects the unique root inside it (rigorous: exactly
            one distinct root meets the ball); anything else is a point (a ball's midpoint) and selects
            the root certified strictly nearest to it.

        Raises
        ------
        ValueError
            The polynomial is constant, or ``approx`` does not single out one root (a ball
            meeting no root or several distinct roots, a point equidistant from two roots).

        Examples
        --------
        >>> phi = Ca.algebraic([-1, -1, 1], 1.6)            # s^2 - s - 1, golden ratio
        >>> (phi * phi - phi - 1).is_zero(), phi.is_real()
        (True, True)
        >>> Ca.algebraic([1, 0, 1], 0)
        Traceback (most recent call last):
        ...
        ValueError: approx 0 does not single out one root of s^2 + 1 (2 roots are as near)
        """
        ints, qs = _integer_coefficients(coeffs)
        if len(ints) < 2:
            raise ValueError(f"the polynomial {list(coeffs)!r} has no roots (degree < 1)")
        desc = _poly_str(qs)
        if isinstance(approx, (acb, arb)):
            target = acb(approx)
            ball_mode = not (target.real.rad() == 0 and target.imag.rad() == 0)
        else:                                   # a point: complex, float, or an exact rational
            try:
                target = acb(approx) if isinstance(approx, (complex, float, int)) else acb(to_fmpq(approx, "approx"))
            except Exception:                   # noqa: BLE001
                raise TypeError(f"approx {approx!r} is not a number python-flint can read as acb") from None
            target, ball_mode = acb(target.real.mid(), target.imag.mid()), False
        b = backend()
        with b.lock, qqbar_distinct_roots(b.lib, ints) as roots:
            chosen = select_qqbar_root(b.lib, roots, target, ball_mode, approx, desc)
            r = cls._new()
            b.lib.ca_set_qqbar(r._ptr, chosen, b.ctx)
        return r

    def _binary(self, other: Any, fname: str, swap: bool = False) -> "Ca":
        try:
            o = _coerce(other)
        except NotRational:
            return NotImplemented
        x, y = (o, self) if swap else (self, o)
        b = self._b or backend()
        with b.lock:
            r = Ca._new()
            getattr(b.lib, fname)(r._ptr, x._ptr, y._ptr, b.ctx)
            r._check(fname)
        return r

    def __add__(self, other: Any) -> "Ca":
        return self._binary(other, "ca_add")

    def __radd__(self, other: Any) -> "Ca":
        return self._binary(other, "ca_add", swap=True)

    def __sub__(self, other: Any) -> "Ca":
        return self._binary(other, "ca_sub")

    def __rsub__(self, other: Any) -> "Ca":
        return self._binary(other, "ca_sub", swap=True)

    def __mul__(self, other: Any) -> "Ca":
        return self._binary(other, "ca_mul")

    def __rmul__(self, other: Any) -> "Ca":
        return self._binary(other, "ca_mul", swap=True)

    def __truediv__(self, other: Any) -> "Ca":
        try:
            o = _coerce(other)
        except NotRational:
            return NotImplemented
        return self * o._inverse()

    def __rtruediv__(self, other: Any) -> "Ca":
        try:
            o = _coerce(other)
        except NotRational:
            return NotImplemented
        return o * self._inverse()

    def _inverse(self) -> "Ca":
        """1/self; ca_inv answers uinf (proven zero) or Unknown (undecided) instead of aborting."""
        return self._unary("ca_inv")

    def __neg__(self) -> "Ca":
        return self._unary("ca_neg")

    def __pos__(self) -> "Ca":
        return self

    def __abs__(self) -> "Ca":
        return self._unary("ca_abs")

    def __pow__(self, k: Any) -> "Ca":
        if isinstance(k, bool) or not isinstance(k, (Integral, fmpz)):
            return NotImplemented
        k = int(k)
        if not -(1 << 62) < k < (1 << 62):
            raise OverflowError(f"exponent {k} is too large")
        base = self if k >= 0 else self._inverse()
        b = self._b or backend()
        with b.lock:
            r = Ca._new()
            b.lib.ca_pow_si(r._ptr, base._ptr, abs(k), b.ctx)
            r._check("ca_pow_si")
        return r

    def _unary(self, fname: str) -> "Ca":
        b = self._b or backend()
        with b.lock:
            r = Ca._new()
            getattr(b.lib, fname)(r._ptr, self._ptr, b.ctx)
            r._check(fname)
        return r

    def _check(self, fname: str) -> None:
        """Refuse a special value (caller holds the lock); the wrapper is then dropped."""
        field = self._buf[0]
        if not field & 3:
            return
        what = fname[3:] if fname.startswith("ca_") else fname
        if field == CA_UNKNOWN:
            if what == "inv":
                raise UnresolvedSign("division by a number that Calcium cannot prove nonzero")
            raise UnresolvedSign(f"{what}: Calcium cannot decide whether the argument is a singular point")
        if what == "inv":
            raise ZeroDivisionError("division by a number that is exactly zero")
        if field == CA_UNDEFINED:
            raise ValueError(f"{what}: the result is undefined")
        raise ValueError(f"{what}: the result is infinite")

    def exp(self) -> "Ca":
        """e**self.

        >>> (Ca(2).log().exp() - 2).is_zero()
        True
        """
        return self._unary("ca_exp")

    def log(self) -> "Ca":
        """Principal natural logarithm; ``ValueError`` at 0.

        >>> (Ca(2).log() + Ca(3).log() - Ca(6).log()).is_zero()
        True
        """
        return self._unary("ca_log")

    def sqrt(self) -> "Ca":
        """Principal square root.

        >>> Ca(-4).sqrt()
        Ca(2.00000*I {2*a where a = I [a^2+1=0]})
        """
        return self._unary("ca_sqrt")

    def sin(self) -> "Ca":
        """Sine.

        >>> Ca.pi().sin().is_zero()
        True
        """
        return self._unary("ca_sin")

    def cos(self) -> "Ca":
        """Cosine.

        >>> (Ca.pi().cos() + 1).is_zero()
        True
        """
        return self._unary("ca_cos")

    def atan(self) -> "Ca":
        """Principal arctangent; ``ValueError`` at +-i.

        >>> (4 * Ca(1).atan() - Ca.pi()).is_zero()
        True
        """
        return self._unary("ca_atan")

    def acos(self) -> "Ca":
        """Principal arccosine.

        >>> (Ca(-1).acos() - Ca.pi()).is_zero()
        True
        """
        return self._unary("ca_acos")

    def asin(self) -> "Ca":
        """Principal arcsine.

        >>> (2 * Ca(1).asin() - Ca.pi()).is_zero()
        True
        """
        return self._unary("ca_asin")

    def re(self) -> "Ca":
        """Real part.

        >>> (Ca(3) + 4 * Ca.i()).re()
        Ca(3)
        """
        return self._unary("ca_re")

    def im(self) -> "Ca":
        """Imaginary part.

        >>> (Ca(3) + 4 * Ca.i()).im()
        Ca(4)
        """
        return self._unary("ca_im")

    def conj(self) -> "Ca":
        """Complex conjugate.

        >>> (Ca(3) + 4 * Ca.i()).conj()
        Ca(3.00000 - 4.00000*I {-4*a+3 where a = I [a^2+1=0]})
        """
        return self._unary("ca_conj")

    def _predicate(self, fname: str) -> bool | None:
        b = self._b
        check_in_force(" in an exact zero test (Calcium)")  # each test bounded, but not interruptible
        with b.lock:
            return truth(getattr(b.lib, fname)(self._ptr, b.ctx))

    def is_zero(self) -> bool | None:
        """True / False when Calcium proves it; None when it cannot decide (never a guess).

        >>> (Ca.pi() - Fraction(22, 7)).is_zero()
        False
        """
        return self._predicate("ca_check_is_zero")

    def is_rational(self) -> bool | None:
        """True / False when proven; None when undecided.

        >>> (Ca.i() * Ca.pi()).exp().is_rational(), Ca(2).sqrt().is_rational()
        (True, False)
        """
        return self._predicate("ca_check_is_rational")

    def is_real(self) -> bool | None:
        """True / False when proven; None when undecided.

        >>> Ca(2).sqrt().is_real(), Ca(-2).sqrt().is_real()
        (True, False)
        """
        return self._predicate("ca_check_is_real")

    def sign(self, real: bool = False) -> int | None:
        """-1, 0 or 1 for a number proven real; None when Calcium cannot decide; ``ValueError`` for a
        number proven non-real.

        Parameters
        ----------
        real : bool, optional
            True: the caller knows the number is real (built from reals by field operations and square
            roots of positive numbers, as event times and states are); its sign is read off an enclosure
            (128, 512, 2048 bits) whose real part excludes 0 before Calcium proves it real and nonzero
            (ms in a field of many generators, as a column of five beads, vs µs).

        >>> (Ca.pi() - Fraction(22, 7)).sign(), Ca(0).sign(), (Ca(2).sqrt() - 2).sign()
        (-1, 0, -1)
        >>> (Ca(2).sqrt() - Fraction(140, 99)).sign(real=True)
        1
        """
        if real:
            for wp in (128, 512, 2048):  # long expressions cancel hundreds of bits
                e = self._enclosure("ca_get_acb_raw", wp).real
                if not e.contains(0):
                    return 1 if e > 0 else -1
        z = self.is_zero()
        if z is not False:
            return None if z is None else 0
        real = self.is_real()
        if real is False:
            raise ValueError(f"sign of the non-real number {self}")
        if real is None:
            return None
        b = self._b
        with b.lock:
            zero = Ca._new()
            gt = truth(b.lib.ca_check_gt(self._ptr, zero._ptr, b.ctx))
        return None if gt is None else 1 if gt else -1

    def to_fmpq(self) -> fmpq | None:
        """The value as an ``fmpq`` when Calcium proves it rational, else None.

        >>> (Ca.i() * Ca.pi()).exp().to_fmpq(), Ca(2).sqrt().to_fmpq()
        (-1, None)
        """
        b = self._b
        with b.lock:
            q = FmpqStruct(0, 1)
            try:
                if not b.lib.ca_get_fmpq(ctypes.byref(q), self._ptr, b.ctx):
                    return None
                base = ctypes.addressof(q)
                p = fmpz_to_int(b.lib, base + FmpqStruct.num.offset)
                d = fmpz_to_int(b.lib, base + FmpqStruct.den.offset)
            finally:
                b.lib.fmpq_clear(ctypes.byref(q))
        return fmpq(p, d)

    def enclosure(self, prec: int = 53) -> acb:
        """A rigorous ball: the exact value lies in the returned ``flint.acb``.

        ``ca_get_acb`` evaluates with adaptive working precision aiming at ``prec`` accurate bits (it
        stops at Calcium's precision limit, 4096 bits by default, e.g. for an unsimplified exact zero).
        The ball is then transferred exactly: each midpoint as ``man * 2^exp`` (``arf_get_fmpz_2exp``,
        integers through ``fmpz_get_str``), each radius likewise after the exact ``arf_set_mag``;
        python-flint keeps the midpoint exactly and rounds the radius up (both checked), no decimal string.

        Parameters
        ----------
        prec : int, optional
            Accurate bits aimed at (default 53; ``ValueError`` below 2).

        >>> e = Ca.pi().enclosure(64)
        >>> e.imag == 0 and e.real.rad() < 2.0 ** -60 and e.real.overlaps(flint.arb.pi())
        True
        """
        prec = int(prec)
        if prec < 2:
            raise ValueError(f"prec must be >= 2, not {prec}")
        return self._enclosure("ca_get_acb", prec)

    def _enclosure(self, fname: str, prec: int) -> acb:
        """``ca_get_acb`` (refined to ``prec`` accurate bits) or ``ca_get_acb_raw`` (one
        evaluation at ``prec`` bits of working precision), transferred exactly."""
        b = self._b
        with b.lock:
            buf = (c_ulong * (2 * ctypes.sizeof(AcbStruct) // 8))()
            at = ctypes.addressof(buf)
            b.lib.acb_init(at)
            try:
                getattr(b.lib, fname)(at, self._ptr, prec, b.ctx)
                return acb_from_address(b.lib, at)
            finally:
                b.lib.acb_clear(at)

    def minimal_polynomial(self) -> list[int] | None:
        """The integer coefficients (low degree first, content 1, leading coefficient > 0) of the
        minimal polynomial over Q, when Calcium proves the number algebraic; else None.

        >>> (Ca(2).sqrt() + 1).minimal_polynomial()       # (x - 1)^2 = 2
        [-1, -2, 1]
        >>> Ca.pi().minimal_polynomial() is None
        True
        """
        b, lib = self._b, self._b.lib
        with b.lock:
            buf = (c_ulong * (2 * ctypes.sizeof(QqbarStruct) // 8))()
            at = ctypes.addressof(buf)
            lib.qqbar_init(at)
            try:
                if not lib.ca_get_qqbar(at, self._ptr, b.ctx):
                    return None
                poly = QqbarStruct.from_address(at).poly
                return [fmpz_to_int(lib, poly.coeffs + 8 * j) for j in range(poly.length)]
            finally:
                lib.qqbar_clear(at)

    def compact(self, size: int = 200) -> "Ca":
        """An equal number in its smallest exact form when its printed form is longer than ``size``
        characters: an algebraic number re-expressed by its minimal polynomial and an isolating
        enclosure (``ca_get_qqbar``, ``ca_set_qqbar``), else ``self``; the shorter form is returned.

        Arithmetic in Calcium keeps a number as an expression in the generators of a field, and the expression
        grows with every operation even where the number does not: the event times of a column of elastic
        beads stay of degree <= 4 over Q, yet after 13 events their expressions hold 75-digit coefficients
        that cancel to 80 digits, and a few events later a zero test fails at Calcium's precision limit.
        Re-expressed, the same times print in a few dozen characters.

        Parameters
        ----------
        size : int, optional
            The printed length (``str``) above which a shorter form is sought (default 200).

        >>> x = (Ca(2).sqrt() * 10**40 + 1) / (Ca(2).sqrt() * 10**40 - 1)
        >>> y = x.compact(size=50)
        >>> (x - y).is_zero(), len(str(y)) <= len(str(x))
        (True, True)
        """
        text = str(self)
        if len(text) <= size:
            return self
        check_in_force(" in an exact algebraic computation (Calcium)")  # each one bounded, not interruptible
        b, lib = self._b, self._b.lib
        with b.lock:
            buf = (c_ulong * (2 * ctypes.sizeof(QqbarStruct) // 8))()
            at = ctypes.addressof(buf)
            lib.qqbar_init(at)
            try:
                with qqbar_degree_limit(b, COMPACT_DEGREE_LIMIT):
                    found = lib.ca_get_qqbar(at, self._ptr, b.ctx)
                if not found:
                    return self
                r = Ca._new()
                lib.ca_set_qqbar(r._ptr, at, b.ctx)
            finally:
                lib.qqbar_clear(at)
        return r if len(str(r)) < len(text) else self

    def __bool__(self) -> bool:
        raise TypeError("the truth value of a Ca is not decided by bool(): use is_zero() (True/False/None)")

    def __eq__(self, other: Any) -> bool:
        raise TypeError("Ca == is refused: use (x - y).is_zero(), which answers True/False/None")

    def __ne__(self, other: Any) -> bool:
        raise TypeError("Ca != is refused: use (x - y).is_zero(), which answers True/False/None")

    __hash__ = None  # type: ignore[assignment]

    def __str__(self) -> str:
        b = self._b
        with b.lock:
            return take_str(b.lib, b.lib.ca_get_str(self._ptr, b.ctx))

    def __repr__(self) -> str:
        return f"Ca({self})"


# ---- real roots of integer polynomials -------------------------------------------------------

def real_roots(coeffs: Sequence[Any]) -> list[Ca]:
    """The distinct real roots of ``sum(coeffs[j] * s**j)``, each as an exact :class:`Ca` (FLINT's
    ``qqbar_roots_fmpz_poly``; realness decided exactly by ``qqbar_sgn_im``), in no particular order.

    Parameters
    ----------
    coeffs : sequence of rationals
        Exact, low degree first.

    >>> sorted(float(r.enclosure(30).real.mid()) for r in real_roots([-2, 0, 1]))
    [-1.4142135623730951, 1.4142135623730951]
    >>> real_roots([1, 0, 1])
    []
    """
    ints, _ = _integer_coefficients(coeffs)
    if len(ints) < 2:
        return []
    b = backend()
    out: list[Ca] = []
    with b.lock, qqbar_distinct_roots(b.lib, ints) as roots:
        for at in roots:
            if b.lib.qqbar_sgn_im(at) == 0:
                r = Ca._new()
                b.lib.ca_set_qqbar(r._ptr, at, b.ctx)
                out.append(r)
    return out


def _integer_coefficients(coeffs: Sequence[Any]) -> tuple[list[int], list[fmpq]]:
    """(integer coefficients, rational ones) of a polynomial, trailing zeros removed: the
    rationals times the lcm of their denominators."""
    qs = [to_fmpq(c, "polynomial coefficient") for c in coeffs]
    while qs and qs[-1] == 0:
        qs.pop()
    den = 1
    for q in qs:
        den = den * int(q.q) // _gcd(den, int(q.q))
    return [int(q.p) * (den // int(q.q)) for q in qs], qs


def _gcd(a: int, b: int) -> int:
    while b:
        a, b = b, a % b
    return abs(a)


def _poly_str(qs: list[fmpq]) -> str:
    """``[-1, -1, 1]`` -> ``"s^2 - s - 1"`` (for messages)."""
    out = ""
    for j in range(len(qs) - 1, -1, -1):
        q = qs[j]
        if q == 0:
            continue
        sign = "-" if q < 0 else "+"
        a = -q if q < 0 else q
        coef = "" if (a == 1 and j) else f"({a})*" if (j and a.q != 1) else f"{a}*" if j else f"{a}"
        term = coef + ("" if j == 0 else "s" if j == 1 else f"s^{j}")
        out = (f"-{term}" if sign == "-" else term) if not out else f"{out} {sign} {term}"
    return out

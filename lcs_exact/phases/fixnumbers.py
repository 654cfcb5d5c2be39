"""Numbers of the fixture format ``lcs-exact/trajectory/1`` (docs/fixtures.md): writing, reading.

Every real number of a fixture is an object ``{"value": decimal, "error": bound, "exact": closed
form | null}`` with the invariant |value - true| <= error; ``"error": "0"`` means the decimal is
the exact value.  Decimals are exact rationals (read with ``fractions.Fraction``), so a reader
loses nothing: :func:`number_ball` turns a number back into a certified ``flint.arb`` ball.

* writing: :func:`rational_number` (an exact rational), :func:`ball_number` (a certified ball),
  the decimal and bound texts below them (exact integer arithmetic, no float);
* reading: :func:`number_ball`, :func:`number_exact`, :func:`number_rational`, the exact reader
  of decimal strings;
* showing a ball read back: :func:`ball_text` (the digits its radius supports), :func:`short_text`;
* the sample grid of rational times: :func:`sample_grid`.

The names are also importable from :mod:`lcs_exact.fixture`, the module of the whole format.
This module sits just above :mod:`lcs_exact.errors` and :mod:`lcs_exact.rational`.
"""
from __future__ import annotations

import re
from fractions import Fraction
from typing import Any

from flint import arb, ctx, fmpq, fmpz

from ..errors import FormatError, LCSError
from ..algebra import to_fmpq

__all__ = ["rational_number", "ball_number", "number_ball", "number_exact", "number_rational", "to_fraction",
           "ball_text", "short_text", "sample_grid", "MAX_SAMPLES"]

MAX_SAMPLES = 1_000_000  # a grid beyond this is a typo in the step, not a fixture anyone reads


# ---------------------------------------------------------------------------------------------
# numbers: writing
# ---------------------------------------------------------------------------------------------

def _text(m: int) -> str:
    """str(m) without Python's 4300-digit limit on int <-> str conversion (fixtures may hold more)."""
    return str(m) if m.bit_length() < 14000 else str(fmpz(m))  # 14000 bits < 4300 digits


def _ndigits(m: int) -> int:
    return len(_text(abs(m)))


def _format_decimal(m: int, e: int) -> str:
    """The decimal m * 10^e: positional for moderate exponents, else ``d.ddde±k``."""
    if m == 0:
        return "0"
    sign, digits = ("-" if m < 0 else ""), _text(abs(m))
    stripped = digits.rstrip("0")  # 1.50 -> 1.5, 10e20 -> 1e21 (same value; zeros come back below)
    digits, e = stripped, e + len(digits) - len(stripped)
    point = len(digits) + e  # position of the decimal point from the left of ``digits``
    if -5 < point <= 0:
        return f"{sign}0.{'0' * -point}{digits}"
    if 0 < point <= max(len(digits), 21):
        if e >= 0:
            return sign + digits + "0" * e
        return f"{sign}{digits[:point]}.{digits[point:]}"
    mant = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    return f"{sign}{mant}e{point - 1}"


def _ceil_3(c: int, k: int) -> tuple[int, int]:
    """The smallest c' * 10^k' >= c * 10^k whose mantissa c' has at most 3 digits (c > 0): a
    bound rounded up, never down."""
    drop = _ndigits(c) - 3
    if drop > 0:
        c, k = -(-c // 10 ** drop), k + drop
        if c == 1000:
            c, k = 100, k + 1
    return c, k


def _bound_text(err: Fraction) -> str:
    """A decimal with 3 significant digits that is >= err (rounded up: it is a bound)."""
    if err <= 0:
        return "0"
    num, den = err.numerator, err.denominator
    k = _ndigits(num) - _ndigits(den) - 3  # err / 10^k is within a factor 10 of [100, 1000)
    c = -(-num * 10 ** -k // den) if k <= 0 else -(-num // (den * 10 ** k))  # ceil(err / 10^k)
    return _format_decimal(*_ceil_3(c, k))


def _bound_text_int(r: int, e: int) -> str:
    """_bound_text of the error r * 10^e (r >= 0 an integer): integer arithmetic only."""
    return "0" if r <= 0 else _format_decimal(*_ceil_3(r, e))


def rational_number(q: Any, digits: int) -> dict:
    """A fixture number for an exact rational: the decimal when it terminates within ``digits``
    significant digits (error 0), else rounded (half to even) to ``digits`` digits with a bound
    on the rounding; ``exact`` is ``"p/q"``.

    >>> rational_number("1/4", 5)
    {'value': '0.25', 'error': '0', 'exact': '1/4'}
    >>> rational_number("1/3", 5)
    {'value': '0.33333', 'error': '3.34e-6', 'exact': '1/3'}
    """
    f = to_fmpq(q, "number")
    p, d = int(f.p), int(f.q)
    exact = str(f)
    if p == 0:
        return {"value": "0", "error": "0", "exact": "0"}
    a = abs(p)
    # the exponent e with 10^(digits-1) <= |q| / 10^e < 10^digits, in integers: N / M = |q| / 10^e
    e = _ndigits(a) - _ndigits(d) - digits
    while True:
        N, M = (a * 10 ** -e, d) if e <= 0 else (a, d * 10 ** e)
        m, rem = divmod(N, M)
        if m >= 10 ** digits:
            e += 1
        elif m < 10 ** (digits - 1):
            e -= 1
        else:
            break
    if 2 * rem > M or (2 * rem == M and m % 2 == 1):  # half to even
        m, rem = m + 1, rem - M
    err = Fraction(abs(rem), M) * (Fraction(10) ** e)  # |q| - m 10^e, exactly
    return {"value": _format_decimal(m if p > 0 else -m, e), "error": _bound_text(err), "exact": exact}


def ball_number(b: arb, digits: int) -> dict:
    """A fixture number for a certified ball: the midpoint to ``digits`` significant digits and a
    bound on |value - true| that covers both the ball's radius and the rounding of the midpoint.
    An exact ball (radius 0) is an exact dyadic rational and says so in ``exact``.

    Parameters
    ----------
    b : arb
        Certified.
    digits : int
        Significant digits of the midpoint.

    >>> ball_number(arb(fmpq(3, 8)), 10)
    {'value': '0.375', 'error': '0', 'exact': '3/8'}
    >>> ball_number(arb(2).sqrt(), 5)["value"]
    '1.4142'
    """
    if not b.is_finite():
        raise LCSError(f"cannot write the ball {b} as a fixture number: it is not finite")
    if b.is_exact():
        return rational_number(b.fmpq(), digits)
    m, r, e = (int(v) for v in b.mid_rad_10exp(digits + 5))  # b is inside [m +/- r] 10^e
    drop = max(0, _ndigits(m) - digits)
    value = m
    if drop:  # round the midpoint to ``digits`` significant digits; the rounding joins the bound
        scale = 10 ** drop
        value = (abs(m) + scale // 2) // scale * (1 if m >= 0 else -1)
        r += abs(m - value * scale)
    return {"value": _format_decimal(value, e + drop), "error": _bound_text_int(r, e), "exact": None}


# ---------------------------------------------------------------------------------------------
# numbers: reading
# ---------------------------------------------------------------------------------------------

_MAX_EXPONENT = 100_000  # |exponent| of a decimal read exactly (10^(10^9) would not fit in memory)


_DECIMAL = re.compile(r"([+-]?)([0-9]*)(?:\.([0-9]*))?(?:[eE]([+-]?[0-9]{1,7}))?")


def _decimal(text: Any, where: str) -> Fraction:
    """A decimal string read exactly (any number of digits; exponents up to 10^5)."""
    if not isinstance(text, str):
        raise FormatError(f"fixture: {where} must be a decimal string, got {type(text).__name__}")
    m = _DECIMAL.fullmatch(text.strip())
    if m is None or not (m.group(2) or m.group(3)) or abs(int(m.group(4) or 0)) > _MAX_EXPONENT:
        raise FormatError(f"fixture: {where} = {text[:40]!r} is not a decimal number "
                          f"(with |exponent| <= {_MAX_EXPONENT})")
    sign, whole, frac, exp = m.group(1), m.group(2), m.group(3) or "", int(m.group(4) or 0)
    mant = int(fmpz(whole + frac or "0"))
    e = exp - len(frac)
    q = Fraction(mant * 10 ** e) if e >= 0 else Fraction(mant, 10 ** -e)
    return -q if sign == "-" else q


def number_ball(num: dict, prec: int | None = None, *, where: str = "number") -> arb:
    """The certified ball [value - error, value + error] of a fixture number.

    The decimal ``value`` is read exactly (as a rational), so the ball's only widening is
    flint's outward rounding of that rational to ``prec`` bits (default: enough for every digit
    of ``value`` and for a rounding far below ``error``; at least 128 bits).

    Parameters
    ----------
    num : dict
        A fixture number: ``value``, ``error`` and optionally ``exact``.
    prec : int, optional
        Bits of the ball (default above).
    where : str, optional
        Its name in an error message.

    >>> b = number_ball({"value": "0.333", "error": "0.001", "exact": "1/3"})
    >>> b.contains(fmpq(1, 3)), b.contains(fmpq(3331, 10000)), b.contains(fmpq(3341, 10000))
    (True, True, False)
    """
    if not isinstance(num, dict) or "value" not in num or "error" not in num:
        raise FormatError(f"fixture: {where} must be an object with 'value' and 'error'")
    v, e = _decimal(num["value"], f"{where}.value"), _decimal(num["error"], f"{where}.error")
    if e < 0:
        raise FormatError(f"fixture: {where}.error is negative")
    if prec is None:  # every digit of value, and rounding well below the error (a 30-digit
        # sample "0.32" +/- 3e-30 must not come back as 0.32 +/- 1e-17)
        prec = max(128, 48 + int(3.33 * max(_ndigits(v.numerator), _ndigits(v.denominator))))
        if e > 0 and v != 0:
            rel = _ndigits(abs(v.numerator) * e.denominator) - _ndigits(v.denominator * e.numerator)
            prec = max(prec, 48 + int(3.33 * rel))
    with ctx.workprec(prec):
        b = arb(fmpq(v.numerator, v.denominator))  # rounded outward: the ball contains v
        return b if e == 0 else arb(b, arb(fmpq(e.numerator, e.denominator)))


def number_exact(num: dict) -> str | None:
    """The closed form string of a fixture number, or None.

    Parameters
    ----------
    num : dict
        A fixture number: ``value``, ``error`` and optionally ``exact``.

    >>> number_exact({"value": "1.5707963", "error": "2.7e-8", "exact": "pi/2"})
    'pi/2'
    """
    ex = num.get("exact") if isinstance(num, dict) else None
    return ex if isinstance(ex, str) else None


def number_rational(num: dict) -> Fraction | None:
    """The exact rational value of a fixture number, or None when it is not known to be rational.

    Rational when ``exact`` is an integer or ``p/q``, or when ``error`` is 0 (the decimal is then
    the exact value).

    Parameters
    ----------
    num : dict
        A fixture number: ``value``, ``error`` and optionally ``exact``.

    >>> number_rational({"value": "0.333", "error": "0.0004", "exact": "1/3"})
    Fraction(1, 3)
    >>> number_rational({"value": "1.5707963", "error": "2.7e-8", "exact": "pi/2"}) is None
    True
    """
    ex = number_exact(num)
    if ex is not None:
        m = re.fullmatch(r"(-?[0-9]+)(?:/([0-9]+))?", ex.strip())
        if m is not None and (m.group(2) is None or int(fmpz(m.group(2))) != 0):
            return Fraction(int(fmpz(m.group(1))), int(fmpz(m.group(2) or "1")))
    if isinstance(num, dict) and num.get("error") == "0":
        return _decimal(num.get("value"), "value")
    return None


def to_fraction(v: Any, what: str) -> Fraction:
    """An exact rational (anything :func:`lcs_exact.rational.to_fmpq` accepts: a float by its
    shortest repr) as a ``Fraction``.

    Parameters
    ----------
    v : rational-like
    what : str
        Its name in an error message.

    >>> to_fraction("3/4", "t"), to_fraction(0.1, "t")
    (Fraction(3, 4), Fraction(1, 10))
    """
    q = to_fmpq(v, what)
    return Fraction(int(q.p), int(q.q))


# ---------------------------------------------------------------------------------------------
# balls read back, shown
# ---------------------------------------------------------------------------------------------

def ball_text(b: arb, cap: int = 20) -> str:
    """A ball with the digits its radius supports (at most ``cap``), not flint's default 15: a
    30-digit fixture number should not print as [... +/- 1e-15].

    Parameters
    ----------
    b : arb
    cap : int, optional
        The most digits.

    >>> with ctx.workprec(200):
    ...     b = arb(fmpq(1, 3), fmpq(1, 10**25))
    >>> ball_text(b), ball_text(arb(fmpq(3, 4)))
    ('0.33333333333333333333 +/- 3.34e-21', '3/4')
    """
    if b.is_exact():
        return str(b.fmpq())
    digits = max(1, min(cap, int(b.rel_accuracy_bits() * 0.30103)))
    text = b.str(digits, radius=True)
    return text[1:-1] if text.startswith("[") else text


def short_text(b: arb) -> str:
    """A ball in 15 digits without its radius (an integer as such): for tables and reprs.

    Parameters
    ----------
    b : arb

    >>> short_text(arb(3)), short_text(arb(fmpq(1, 3)))
    ('3', '0.333333333333333')
    """
    return b.str(15, radius=False) if not b.is_exact() or not b.mid().is_integer() else str(int(b.unique_fmpz()))


# ---------------------------------------------------------------------------------------------
# the sample grid
# ---------------------------------------------------------------------------------------------

def _as_fraction(r: Any) -> Fraction | None:
    """An exact real as a Fraction when its closed form is rational, else None."""
    cf = r.closed_form
    if cf is not None and getattr(cf, "is_Rational", False):
        return Fraction(int(cf.p), int(cf.q))
    return None


def sample_grid(t_end: Any, h: Any) -> list[Fraction]:
    """The grid 0, h, 2h, ... <= t_end (h rational > 0; t_end rational or an exact real).

    ``h`` accepts what :func:`lcs_exact.rational.to_fmpq` accepts (a float by its shortest
    repr: 0.1 is 1/10).  The count is decided exactly (certified balls when t_end is irrational).

    Parameters
    ----------
    t_end : rational or Real
    h : rational
        The step, > 0.

    >>> [str(t) for t in sample_grid(1, "1/4")]
    ['0', '1/4', '1/2', '3/4', '1']
    """
    step = to_fraction(h, "the sample step")
    if step <= 0:
        raise FormatError(f"the sample step must be > 0, got {step}")
    if hasattr(t_end, "ball"):
        T = _as_fraction(t_end)
    else:
        T = to_fraction(t_end, "t_end")
    if T is not None:
        count = int(T // step)
    else:  # irrational t_end: floor(t_end / h) from a ball that excludes every integer
        count = None
        for digits in (30, 60, 120, 240):
            with ctx.workprec(4 * digits + 64):
                ratio = t_end.ball(digits) / arb(fmpq(step.numerator, step.denominator))
                lo, hi = ratio.lower().floor(), ratio.upper().floor()
            if lo == hi:
                count = int(lo.unique_fmpz())
                break
        if count is None:
            raise FormatError(f"cannot decide how many grid points of step {step} fit before t_end")
    if count < 0:
        return []
    if count + 1 > MAX_SAMPLES:
        raise FormatError(f"the sample step {step} gives {count + 1} grid points on [0, t_end]; "
                          f"at most {MAX_SAMPLES} are written (choose a larger step)")
    return [k * step for k in range(count + 1)]

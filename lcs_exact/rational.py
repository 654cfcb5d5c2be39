"""Exact rationals, rational matrices and rational functions in Q(s).

Representation
--------------
* Scalars are ``flint.fmpq``; matrices are ``flint.fmpq_mat``; vectors are n x 1 ``fmpq_mat``.
  User input is converted once, here (:func:`to_fmpq`, :func:`to_matrix`, :func:`to_vector`).
* A rational function in Q(s) is :class:`RationalFunction`: a pair of ``fmpq_poly`` with the
  denominator monic and coprime to the numerator (the zero function is 0/1).
* :class:`RationalMatrix` is a small dense matrix of :class:`RationalFunction` (G(s), R(s), 5.3).

Signs at s = oo
---------------
Section 5: a rational function is nonnegative for all large real s iff its sequence of Laurent
coefficients at s = oo (5.6) is lexicographically nonnegative (5.7, Lemma 5.1).  In mode
selection those coefficients are *linear forms* in the state x0 (row vectors ell with value
ell . x0).  :func:`sign_of_form` is the one place where such a sign is decided: an identically
zero form is an exact zero; a rational point gives an exact sign; any other point (an exact real
vector) must decide the sign itself through its ``sign_of_form`` method, which certifies it or
raises :class:`~lcs_exact.errors.UnresolvedSign`.
"""
from __future__ import annotations

import math
import re
from collections.abc import Mapping, Set
from decimal import Decimal
from fractions import Fraction
from itertools import islice
from numbers import Integral, Rational, Real
from typing import Any, Iterable, Sequence, Union

import flint
from flint import fmpq, fmpq_mat, fmpq_poly, fmpz

from .errors import InvalidArgument, NotRational, ShapeError, Unsupported

__all__ = [
    "RationalLike", "to_fmpq", "to_matrix", "to_vector", "vector_entries", "to_int", "is_rational_vector",
    "zeros", "identity", "is_zero", "hstack", "vstack", "submatrix", "column", "mat_rows", "mat_equal",
    "RationalFunction", "RationalMatrix", "laurent_coefficients", "sign_of_form", "lex_sign",
    "fmpq_to_sympy", "matrix_to_sympy", "adjugate_coefficients", "poly_at_matrix", "resolvent",
    "MAX_RATIONAL_BITS", "MAX_DIMENSION", "MAX_ENUMERATION_K", "MAX_P_TEST_K", "MAX_MARKOV_INDEX",
    "MAX_KAPPA", "MAX_HORIZON_SLOW", "MAX_HORIZON_FAST", "MAX_PREC_BITS", "check_enumerable",
    "eigenvalue_moduli", "to_short", "pivot_tableau",
]

RationalLike = Union[int, str, Fraction, fmpq, fmpz, Rational, float]

# ---------------------------------------------------------------------------------------------
# limits on user input (one place; docs/limits.md lists them with their reasons)
# ---------------------------------------------------------------------------------------------

#: bits of the numerator and of the denominator of one rational read from user input (about
#: 19,700 decimal digits; ``"1e999999999"`` is refused at once instead of being expanded).
#: ``fmpq``/``fmpz`` values are taken as they are: they are already exact (and the engine's own).
MAX_RATIONAL_BITS = 65_536
#: rows and columns of one matrix, length of one vector (so n, k <= 1024); the exact engine is
#: practical to n ~ 64 (a 16-cart chain, n = 32, runs in seconds).
MAX_DIMENSION = 1024
#: largest k for computations that enumerate the 2^k modes or index sets (RCP for every mode,
#: mode maps, all solutions of an LCP): 2^16 = 65,536 sets.
MAX_ENUMERATION_K = 16
#: largest k for the P-matrix test of a nonsymmetric matrix (Tsatsomeros-Li: 2^k Schur steps,
#: ~3 s at k = 20); a symmetric matrix is tested by its leading minors at any size.
MAX_P_TEST_K = 20
#: largest Markov parameter index i of ``lcs.markov(i)`` (the theory needs i <= n + 1)
MAX_MARKOV_INDEX = 4096
#: largest kappa of ``lcs.ldcp(x0, kappa)`` (Theorem 6.10 needs kappa = n)
MAX_KAPPA = 1024
#: horizon of one phase's search times the smallest nonzero |eigenvalue| of its A_I (slowest rate)
MAX_HORIZON_SLOW = 10**6
#: horizon of one phase's search times the spectral radius of its A_I (fastest rate)
MAX_HORIZON_FAST = 10**12
#: largest ``max_prec`` (bits) a run may refine a sign decision to (2^20 bits ~ 315,000 digits)
MAX_PREC_BITS = 2**20

_LOG2_10 = math.log2(10)


def to_short(x: Any, width: int = 40) -> str:
    """repr of x cut to ``width`` characters (a hostile input must not flood a message).

    >>> to_short("1" * 100), to_short(2**1000)
    ("'1111111111111111111111111111111111...'", '<an integer of 1001 bits>')
    """
    if isinstance(x, int) and x.bit_length() > 4 * width:
        return f"<an integer of {x.bit_length()} bits>"  # repr would be huge (or refused by Python)
    try:
        r = repr(x)
    except ValueError:  # e.g. a numpy or SymPy integer beyond Python's 4300-digit str limit
        return f"<a {type(x).__name__} too large to print>"
    if len(r) <= width:
        return r
    return r[:width - 5] + "...'" if r[:1] in "'\"" else r[:width - 3] + "..."


def _check_bits(p: int, q: int, what: str, shown: Any) -> fmpq:
    """fmpq(p, q) after checking both parts against MAX_RATIONAL_BITS."""
    for part, v in (("numerator", p), ("denominator", q)):
        b = abs(int(v)).bit_length()
        if b > MAX_RATIONAL_BITS:
            raise InvalidArgument(f"{what} {to_short(shown)} is too large: its {part} has {b} bits, more than "
                                  f"the limit MAX_RATIONAL_BITS = {MAX_RATIONAL_BITS} (lcs_exact.rational)")
    return fmpq(p, q)


_NUMBER = re.compile(r"""\A\s*(?P<sign>[-+]?)(?:
        (?P<p>\d+)\s*/\s*(?P<q>\d+)                                    # p/q
      | (?P<int>\d*)(?:\.(?P<frac>\d*))?(?:[eE](?P<exp>[-+]?\d+))?     # decimal, exponent
    )\s*\Z""", re.VERBOSE | re.ASCII)


def _parse_number(text: str, what: str) -> fmpq:
    """An exact rational from ``"p/q"`` or a decimal string (``"-1.25e-3"``), without ever
    expanding a number beyond MAX_RATIONAL_BITS: ``"1e999999999"`` is refused from its exponent."""
    m = _NUMBER.match(text)
    if m is None or (m["p"] is None and not (m["int"] or m["frac"])):
        raise NotRational(f"{what} {to_short(text)} is not a rational number (expected 'p/q' or a decimal "
                          f"such as '-1.25e-3')")
    neg = m["sign"] == "-"
    if m["p"] is not None:
        for part in ("p", "q"):
            if len(m[part].lstrip("0")) > 2 * MAX_RATIONAL_BITS:  # > 4 * 10^5 bits: surely too large
                raise InvalidArgument(f"{what} {to_short(text)} is too large: more than "
                                      f"MAX_RATIONAL_BITS = {MAX_RATIONAL_BITS} bits (lcs_exact.rational)")
        p, q = fmpz(m["p"]), fmpz(m["q"])
        if q == 0:
            raise NotRational(f"{what} {to_short(text)} has a zero denominator")
        return _check_bits(-p if neg else p, q, what, text)
    digits = ((m["int"] or "") + (m["frac"] or "")).lstrip("0")
    stripped = digits.rstrip("0")
    if not stripped:
        return fmpq(0)  # zero, whatever the exponent
    e = m["exp"] or "0"
    if len(e.lstrip("+-").lstrip("0")) > 12:
        raise InvalidArgument(f"{what} {to_short(text)} is too large or too small: its exponent has more than "
                              f"12 digits (limit: MAX_RATIONAL_BITS = {MAX_RATIONAL_BITS} bits, lcs_exact.rational)")
    # value = N * 10^E with N free of factors 10: the reduced denominator of 10^-E is >= 2^|E|
    E = int(e) - len(m["frac"] or "") + (len(digits) - len(stripped))
    if len(stripped) > 2 * MAX_RATIONAL_BITS or abs(E) > MAX_RATIONAL_BITS:
        raise InvalidArgument(f"{what} {to_short(text)} is too large or too small: it would need more than "
                              f"MAX_RATIONAL_BITS = {MAX_RATIONAL_BITS} bits (lcs_exact.rational)")
    N = fmpz(stripped)
    if neg:
        N = -N
    if E >= 0:
        return _check_bits(N * fmpz(10) ** E, 1, what, text)
    q = fmpq(N, fmpz(10) ** (-E))
    return _check_bits(q.p, q.q, what, text)


def to_fmpq(x: Any, what: str = "entry") -> fmpq:
    """Read one exact rational from user input.

    Accepts int, ``"p/q"`` or decimal strings (``"-1.25e-3"``), Fraction, Decimal, sympy
    Rational, fmpq, fmpz, numpy integers, and floats (read as their shortest decimal repr:
    ``0.1 -> 1/10``; a numpy float32 or float16 by its own shortest repr, ``np.float32(0.1)`` is
    also 1/10).  Refuses bools, NaN and infinities, complex numbers, SymPy non-rationals
    (:class:`~lcs_exact.errors.NotRational`, naming ``what``) and numbers whose numerator or
    denominator would exceed :data:`MAX_RATIONAL_BITS` bits
    (:class:`~lcs_exact.errors.InvalidArgument`; checked before a decimal exponent is expanded).

    >>> to_fmpq("3/4"), to_fmpq(0.1), to_fmpq(2), to_fmpq("-1.25e-3")
    (3/4, 1/10, 2, -1/800)
    >>> to_fmpq("1e999999999", "t_end")
    Traceback (most recent call last):
    ...
    lcs_exact.errors.InvalidArgument: t_end '1e999999999' is too large or too small: it would need more than MAX_RATIONAL_BITS = 65536 bits (lcs_exact.rational)
    """
    if isinstance(x, fmpq):
        return x
    if isinstance(x, fmpz):
        return fmpq(x)
    if isinstance(x, bool) or type(x).__name__ == "bool_":
        raise NotRational(f"{what} is a bool ({x!r}), not a number")
    if isinstance(x, int):
        return _check_bits(x, 1, what, x)
    if isinstance(x, Fraction):
        return _check_bits(x.numerator, x.denominator, what, x)
    if isinstance(x, float):
        if not math.isfinite(x):
            raise NotRational(f"{what} is {x!r}, not a finite number")
        return _parse_number(repr(float(x)), what)  # float(): numpy's float64 repr is 'np.float64(...)'
    if isinstance(x, str):
        return _parse_number(x, what)
    if isinstance(x, Decimal):
        if not x.is_finite():
            raise NotRational(f"{what} is {x!r}, not a finite number")
        return _parse_number(str(x), what)
    mod = type(x).__module__
    if mod.startswith("sympy"):
        if getattr(x, "is_Rational", False):
            return _check_bits(int(x.p), int(x.q), what, x)
        raise NotRational(f"{what} {to_short(x)} is a SymPy {type(x).__name__}, not a rational number")
    if mod.startswith("numpy") and hasattr(x, "item") and getattr(x, "ndim", 0) == 0:
        if type(x).__name__ in ("float32", "float16") and math.isfinite(float(x)):
            # a float32 is read by its own shortest repr (np.float32(0.1) is 0.1, as typed), not
            # by the float64 repr of its binary value (0.10000000149011612)
            return _parse_number(str(x), what)
        v = x.item()
        if type(v) is type(x):  # numpy.longdouble: no Python equivalent; its shortest repr is exact enough
            if not math.isfinite(float(v)) and isinstance(x, Real):
                raise NotRational(f"{what} is {x!r}, not a finite number")
            v = str(x) if isinstance(x, Real) else complex(x)
        return to_fmpq(v, what)
    # other numbers.Rational (Integral first: numpy-like ints)
    if isinstance(x, Integral):
        return _check_bits(int(x), 1, what, x)
    if isinstance(x, Rational):
        return _check_bits(int(x.numerator), int(x.denominator), what, x)
    raise NotRational(f"{what} {to_short(x)} of type {type(x).__name__} is not an exact rational number")


def to_int(x: Any, what: str, lo: int | None = None, hi: int | None = None) -> int:
    """An integer argument (a Python or numpy integer, not a bool), checked to lie in [lo, hi];
    :class:`~lcs_exact.errors.InvalidArgument` naming ``what`` otherwise.

    >>> to_int(3, "kappa", 0, 10)
    3
    >>> to_int(1.5, "kappa")
    Traceback (most recent call last):
    ...
    lcs_exact.errors.InvalidArgument: kappa must be an integer, got 1.5 (float)
    """
    if isinstance(x, bool) or type(x).__name__ == "bool_" or not isinstance(x, (Integral, fmpz)):
        raise InvalidArgument(f"{what} must be an integer, got {to_short(x)} ({type(x).__name__})")
    v = int(x)
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        rng = f"in {lo}..{hi}" if lo is not None and hi is not None else f">= {lo}" if lo is not None else f"<= {hi}"
        raise InvalidArgument(f"{what} must be an integer {rng}, got {to_short(v)}")
    return v


def check_enumerable(k: int, what: str, limit: int = MAX_ENUMERATION_K) -> None:
    """Refuse (:class:`~lcs_exact.errors.Unsupported`) an enumeration of 2^k sets beyond ``limit``.

    >>> check_enumerable(16, "RCP for every mode")
    >>> check_enumerable(17, "RCP for every mode")
    Traceback (most recent call last):
    ...
    lcs_exact.errors.Unsupported: RCP for every mode enumerates all 2^17 index sets; k = 17 is above the limit 16 (lcs_exact.rational.MAX_ENUMERATION_K / MAX_P_TEST_K)
    """
    if k > limit:
        raise Unsupported(f"{what} enumerates all 2^{k} index sets; k = {k} is above the limit "
                          f"{limit} (lcs_exact.rational.MAX_ENUMERATION_K / MAX_P_TEST_K)")


def _is_nested(e: Any) -> bool:
    return isinstance(e, (list, tuple, Mapping, Set)) or (
        hasattr(e, "tolist") and getattr(e, "ndim", 0) > 0 and not isinstance(e, fmpq_mat))


def _items(data: Any, name: str, what: str) -> list:
    """The items of a list-like (at most MAX_DIMENSION of them; an endless iterator is cut off)."""
    if isinstance(data, (str, bytes, Mapping, Set)) or not isinstance(data, Iterable):
        raise ShapeError(f"{name} must be {what}, got {type(data).__name__}")
    items = list(islice(iter(data), MAX_DIMENSION + 1))
    if len(items) > MAX_DIMENSION:
        raise ShapeError(f"{name} has more than MAX_DIMENSION = {MAX_DIMENSION} entries along one side "
                         "(lcs_exact.rational)")
    return items


def _rows_of(data: Any, name: str) -> list[list[Any]]:
    if isinstance(data, fmpq_mat) or isinstance(data, flint.fmpz_mat):
        return [[data[i, j] for j in range(data.ncols())] for i in range(data.nrows())]
    if hasattr(data, "tolist"):  # numpy arrays, sympy matrices
        data = data.tolist()
    rows = [r.tolist() if hasattr(r, "tolist") else r for r in _items(data, name, "a matrix (a list of rows)")]
    out = []
    for i, r in enumerate(rows):
        if isinstance(r, (Mapping, Set)):
            raise ShapeError(f"{name} row {i} is a {type(r).__name__}: rows must be lists of numbers")
        row = _items(r, f"{name} row {i}", "a list") if isinstance(r, Iterable) and not isinstance(r, (str, bytes)) else [r]
        for j, e in enumerate(row):
            if _is_nested(e):
                raise ShapeError(f"{name}[{i}, {j}] is a {type(e).__name__}: {name} must be a matrix of "
                                 "numbers (nested too deep)")
        out.append(row)
    return out


def to_matrix(data: Any, name: str = "matrix", shape: tuple[int | None, int | None] | None = None
              ) -> fmpq_mat:
    """Read a matrix (list of rows, sympy/numpy matrix, fmpq_mat) into an ``fmpq_mat``.

    ``shape`` may fix either dimension (``None`` leaves it free).  Raises
    :class:`~lcs_exact.errors.ShapeError` for ragged, wrong-sized, too deeply nested or
    oversized (more than :data:`MAX_DIMENSION` along a side) input, or a mapping or set, and
    :class:`~lcs_exact.errors.NotRational` for an entry that is not an exact rational.

    >>> to_matrix([[1, "1/2"], [0, 0.25]])
    [1, 1/2]
    [0, 1/4]
    """
    if isinstance(data, fmpq_mat):
        m = data
    else:
        rows = _rows_of(data, name)
        widths = {len(r) for r in rows}
        if len(widths) > 1:
            raise ShapeError(f"{name} has rows of different lengths {sorted(widths)}")
        ncols = widths.pop() if widths else 0
        entries = [to_fmpq(e, f"{name}[{i}, {j}]") for i, r in enumerate(rows) for j, e in enumerate(r)]
        m = fmpq_mat(len(rows), ncols, entries)
    if shape is not None:
        want_r, want_c = shape
        if (want_r is not None and m.nrows() != want_r) or (want_c is not None and m.ncols() != want_c):
            exp = f"{'?' if want_r is None else want_r}x{'?' if want_c is None else want_c}"
            raise ShapeError(f"{name} has shape {m.nrows()}x{m.ncols()}, expected {exp}")
    return m


def vector_entries(data: Any, n: int | None, name: str = "x0") -> list:
    """The entries of a vector given flat (``[a, b]``) or as a column (``[[a], [b]]``), not
    converted; :class:`~lcs_exact.errors.ShapeError` for a string, a mapping or set (no order),
    a scalar, deeper nesting or a wrong length.

    >>> vector_entries([[1], ["1/2"]], 2)
    [1, '1/2']
    >>> vector_entries({0: 1, 1: 2}, 2)
    Traceback (most recent call last):
    ...
    lcs_exact.errors.ShapeError: x0 must be a vector of length 2 (a list of numbers), got dict
    """
    want = "a vector" + ("" if n is None else f" of length {n}") + " (a list of numbers)"
    if hasattr(data, "tolist") and not isinstance(data, fmpq_mat):
        data = data.tolist()
    flat: list[Any] = []
    for i, e in enumerate(_items(data, name, want)):
        if hasattr(e, "tolist") and getattr(e, "ndim", 0) > 0:
            e = e.tolist()
        if isinstance(e, (list, tuple)):
            if len(e) != 1:
                raise ShapeError(f"{name} must be {want}: entry {i} is a row of length {len(e)}")
            e = e[0]
        if _is_nested(e):
            raise ShapeError(f"{name}[{i}] is a {type(e).__name__}: {name} must be {want} (nested too deep)")
        flat.append(e)
    if n is not None and len(flat) != n:
        raise ShapeError(f"{name} has length {len(flat)}, expected {n}")
    return flat


def to_vector(data: Any, n: int, name: str = "x0") -> fmpq_mat:
    """Read a rational vector of length n into an n x 1 ``fmpq_mat`` (flat or column input)."""
    if isinstance(data, fmpq_mat):
        if data.ncols() == 1 and data.nrows() == n:
            return data
        if data.nrows() == 1 and data.ncols() == n:
            return data.transpose()
        raise ShapeError(f"{name} has shape {data.nrows()}x{data.ncols()}, expected a vector of length {n}")
    flat = vector_entries(data, n, name)
    return fmpq_mat(n, 1, [to_fmpq(e, f"{name}[{i}]") for i, e in enumerate(flat)])


def is_rational_vector(x: Any) -> bool:
    """True for an ``fmpq_mat`` column (the exact-rational case of a state)."""
    return isinstance(x, fmpq_mat) and x.ncols() == 1


def eigenvalue_moduli(A: fmpq_mat, chi: fmpq_poly | None = None):
    """(smallest nonzero |lambda|, largest |lambda|) over the eigenvalues of A, as certified
    ``arb`` balls, or None when A is nilpotent (every eigenvalue 0).  The zero eigenvalues are
    split off exactly (the power of s dividing det(sI - A)), the others isolated by flint.

    >>> lo, hi = eigenvalue_moduli(fmpq_mat([[0, 1], [-4, 0]]))
    >>> lo.contains(2) and hi.contains(2)
    True
    """
    p = flint.fmpz_poly((chi if chi is not None else A.charpoly()).numer())
    while p.degree() > 0 and p[0] == 0:
        p = flint.fmpz_poly(p.coeffs()[1:])
    if p.degree() <= 0:
        return None
    p = p / p.gcd(p.derivative())  # squarefree part: the roots once each
    mods = [abs(r) for r, _ in flint.fmpz_poly(p).complex_roots()]
    lows, ups = [m.lower() for m in mods], [m.upper() for m in mods]  # exact endpoints
    # min |lambda| lies in [min lower, min upper], max |lambda| in [max lower, max upper]
    return min(lows).union(min(ups)), max(lows).union(max(ups))


# ---------------------------------------------------------------------------------------------
# small fmpq_mat helpers (flint has no slicing or stacking)
# ---------------------------------------------------------------------------------------------


def zeros(r: int, c: int) -> fmpq_mat:
    return fmpq_mat(r, c)


def identity(n: int) -> fmpq_mat:
    m = fmpq_mat(n, n)
    for i in range(n):
        m[i, i] = 1
    return m


def mat_rows(m: fmpq_mat) -> list[list[fmpq]]:
    return [[m[i, j] for j in range(m.ncols())] for i in range(m.nrows())]


def submatrix(m: fmpq_mat, rows: Sequence[int] | None = None, cols: Sequence[int] | None = None) -> fmpq_mat:
    """m[rows, cols] (``None`` keeps all)."""
    r, c = m.nrows(), m.ncols()
    rows = range(r) if rows is None else list(rows)
    cols = range(c) if cols is None else list(cols)
    if 4 * len(rows) * len(cols) < r * c:  # a small part: entry by entry
        return fmpq_mat(len(rows), len(cols), [m[i, j] for i in rows for j in cols])
    e = m.entries()  # row-major, one C call
    return fmpq_mat(len(rows), len(cols), [e[i * c + j] for i in rows for j in cols])


def column(m: fmpq_mat, j: int) -> fmpq_mat:
    return submatrix(m, None, [j])


def hstack(*ms: fmpq_mat, nrows: int | None = None) -> fmpq_mat:
    """[m1 m2 ...]; ``nrows`` is needed only when no block is given."""
    r = ms[0].nrows() if ms else (nrows or 0)
    if any(m.nrows() != r for m in ms):
        raise ShapeError("hstack: blocks have different numbers of rows")
    c = sum(m.ncols() for m in ms)
    blocks = [(m.entries(), m.ncols()) for m in ms]
    return fmpq_mat(r, c, [x for i in range(r) for e, w in blocks for x in e[i * w:(i + 1) * w]])


def vstack(*ms: fmpq_mat, ncols: int | None = None) -> fmpq_mat:
    """[m1; m2; ...]; ``ncols`` is needed only when no block is given."""
    c = ms[0].ncols() if ms else (ncols or 0)
    if any(m.ncols() != c for m in ms):
        raise ShapeError("vstack: blocks have different numbers of columns")
    return fmpq_mat(sum(m.nrows() for m in ms), c, [x for m in ms for x in m.entries()])


def pivot_tableau(T: list, r: int, c: int) -> None:
    """Gauss-Jordan pivot of a tableau of exact rationals (a list of rows), in place: row r is
    divided by T[r][c] and column c is eliminated from every other row (Lemke's method, the
    simplex of :mod:`lcs_exact.polyhedra`)."""
    p = T[r][c]
    T[r] = [e / p for e in T[r]]
    for i in range(len(T)):
        if i != r and T[i][c] != 0:
            f = T[i][c]
            T[i] = [e - f * g for e, g in zip(T[i], T[r])]


def is_zero(m: fmpq_mat) -> bool:
    """All entries zero (fmpq_mat has no is_zero)."""
    return not any(m.entries())


def mat_equal(a: fmpq_mat, b: fmpq_mat) -> bool:
    return a.nrows() == b.nrows() and a.ncols() == b.ncols() and a == b


def fmpq_to_sympy(q: fmpq):
    import sympy
    return sympy.Rational(int(q.p), int(q.q))


def matrix_to_sympy(m: fmpq_mat):
    import sympy
    return sympy.Matrix(m.nrows(), m.ncols(), lambda i, j: fmpq_to_sympy(m[i, j]))


# ---------------------------------------------------------------------------------------------
# Q(s)
# ---------------------------------------------------------------------------------------------

_S = fmpq_poly([0, 1])


def _poly(p: Any) -> fmpq_poly:
    if isinstance(p, fmpq_poly):
        return p
    if isinstance(p, (list, tuple)):
        return fmpq_poly([to_fmpq(c) for c in p])
    return fmpq_poly([to_fmpq(p)])


class RationalFunction:
    """An element p(s)/q(s) of Q(s), normalized: q monic, gcd(p, q) = 1, zero is 0/1.

    ``RationalFunction(num, den)`` takes polynomials (``fmpq_poly``, coefficient lists lowest
    degree first, or scalars); ``RationalFunction(text)`` reads an expression in ``s`` with
    rational numbers, ``+ - * /``, parentheses and integer powers (``^`` or ``**``), which is
    what the repr prints, so the repr pastes back.

    >>> s = RationalFunction.s()
    >>> f = 1 + s / (s**2 + 1)
    >>> f
    RationalFunction('(s^2 + s + 1)/(s^2 + 1)')
    >>> RationalFunction('(s^2 + s + 1)/(s^2 + 1)') == f
    True
    >>> [str(c) for c in f.laurent(4)]
    ['1', '1', '0', '-1']
    """

    __slots__ = ("num", "den")

    def __init__(self, num: Any = 0, den: Any = 1):
        if isinstance(num, str):
            parsed = _parse_rational_function(num)
            if not (isinstance(den, (int, fmpq)) and den == 1):
                parsed = parsed / RationalFunction(den)
            self.num, self.den = parsed.num, parsed.den
            return
        p, q = _poly(num), _poly(den)
        if q.is_zero():
            raise ZeroDivisionError("rational function with zero denominator")
        if p.is_zero():
            self.num, self.den = fmpq_poly([]), fmpq_poly([1])
            return
        g = p.gcd(q)
        if g.degree() > 0:
            p, q = p / g, q / g  # exact division
            p, q = fmpq_poly(p), fmpq_poly(q)
        lc = q.leading_coefficient()
        self.num, self.den = p / lc, q / lc

    @staticmethod
    def s() -> "RationalFunction":
        """The indeterminate s."""
        return RationalFunction(_S)

    @staticmethod
    def _coerce(x: Any) -> "RationalFunction":
        return x if isinstance(x, RationalFunction) else RationalFunction(x)

    # arithmetic ------------------------------------------------------------------------------
    def __add__(self, o):
        o = self._coerce(o)
        if self.den == o.den:
            return RationalFunction(self.num + o.num, self.den)
        return RationalFunction(self.num * o.den + o.num * self.den, self.den * o.den)

    __radd__ = __add__

    def __neg__(self):
        r = RationalFunction.__new__(RationalFunction)
        r.num, r.den = -self.num, self.den
        return r

    def __sub__(self, o):
        return self + (-self._coerce(o))

    def __rsub__(self, o):
        return self._coerce(o) - self

    def __mul__(self, o):
        o = self._coerce(o)
        return RationalFunction(self.num * o.num, self.den * o.den)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = self._coerce(o)
        if o.is_zero():
            raise ZeroDivisionError("division by the zero rational function")
        return RationalFunction(self.num * o.den, self.den * o.num)

    def __rtruediv__(self, o):
        return self._coerce(o) / self

    def __pow__(self, e: int):
        if e < 0:
            return RationalFunction(1) / (self ** (-e))
        return RationalFunction(self.num ** e, self.den ** e)

    def __eq__(self, o):
        if not isinstance(o, RationalFunction):
            try:
                o = RationalFunction(o)
            except Exception:
                return NotImplemented
        return self.num == o.num and self.den == o.den

    def __hash__(self):
        return hash((str(self.num), str(self.den)))

    def __call__(self, s0: Any) -> fmpq:
        """Exact value at a rational point (raises ZeroDivisionError at a pole)."""
        s0 = to_fmpq(s0, "s")
        d = self.den(s0)
        if d == 0:
            raise ZeroDivisionError(f"s = {s0} is a pole of {self}")
        return self.num(s0) / d

    # structure -------------------------------------------------------------------------------
    def is_zero(self) -> bool:
        return self.num.is_zero()

    def is_proper(self) -> bool:
        return self.is_zero() or self.num.degree() <= self.den.degree()

    def is_strictly_proper(self) -> bool:
        return self.is_zero() or self.num.degree() < self.den.degree()

    def relative_degree(self) -> float | int:
        """deg q - deg p (the first Laurent index, 5.6); +oo for the zero function."""
        return float("inf") if self.is_zero() else self.den.degree() - self.num.degree()

    def polynomial_part(self) -> fmpq_poly:
        """The polynomial part (the impulsive part of the time function, section 5.1)."""
        return fmpq_poly(self.num // self.den) if not self.is_zero() else fmpq_poly([])

    def laurent(self, count: int) -> list[fmpq]:
        """The first ``count`` Laurent coefficients at s = oo, starting at s^{-r}, r = relative degree.

        f(s) = sum_{i >= r} f_i s^{-i} (5.6); returns [f_r, f_{r+1}, ...].
        """
        if self.is_zero():
            return [fmpq(0)] * count
        return laurent_coefficients(self.num.coeffs(), self.den.coeffs(), count)

    def sign_at_infinity(self) -> int:
        """Sign of f(sigma) for all large real sigma (Lemma 5.1): -1, 0 or +1."""
        if self.is_zero():
            return 0
        return 1 if self.num.leading_coefficient() > 0 else -1

    # display ---------------------------------------------------------------------------------
    def to_sympy(self):
        import sympy
        s = sympy.Symbol("s")
        num = sum(fmpq_to_sympy(c) * s**i for i, c in enumerate(self.num.coeffs()))
        den = sum(fmpq_to_sympy(c) * s**i for i, c in enumerate(self.den.coeffs()))
        return num / den

    def __str__(self):
        n, d = _poly_str(self.num), _poly_str(self.den)
        if self.den.degree() == 0:
            return n
        if self.num.degree() > 0 and ("+" in n or " - " in n):
            n = f"({n})"
        return f"{n}/({d})" if ("+" in d or " - " in d) else f"{n}/{d}"

    def __repr__(self):
        return f"RationalFunction('{self}')"

    def _repr_latex_(self):
        import sympy
        if len(str(self)) > _LATEX_MAX_CHARS:  # size cap: Jupyter then shows the repr
            return None
        return f"${sympy.latex(self.to_sympy())}$"


#: _repr_latex_ of rational functions and matrices returns None above this many characters
_LATEX_MAX_CHARS = 3000

_TOKEN = re.compile(r"\s*(?:(\d+(?:\.\d*)?|\.\d+)|(\*\*|[-+*/^()])|([A-Za-z_]\w*))")


def _parse_rational_function(text: str) -> "RationalFunction":
    """Read an expression in s (numbers, + - * /, parentheses, integer powers) exactly."""
    tokens: list[tuple[str, str]] = []
    pos, text_ = 0, text.strip()
    while pos < len(text_):
        m = _TOKEN.match(text_, pos)
        if m is None or m.end() == pos:
            raise NotRational(f"cannot read {text!r} as a rational function of s: unexpected "
                              f"{text_[pos:pos + 10]!r} at position {pos}")
        num, op, ident = m.groups()
        if ident is not None and ident != "s":
            raise NotRational(f"cannot read {text!r} as a rational function of s: unknown name {ident!r}")
        tokens.append(("num", num) if num is not None else ("op", "^" if op == "**" else op)
                      if op is not None else ("s", "s"))
        pos = m.end()
        while pos < len(text_) and text_[pos].isspace():
            pos += 1
    if not tokens:
        raise NotRational("cannot read an empty string as a rational function of s")
    i = 0

    def fail(why: str):
        raise NotRational(f"cannot read {text!r} as a rational function of s: {why}")

    def peek():
        return tokens[i] if i < len(tokens) else ("end", "")

    def take():
        nonlocal i
        i += 1
        return tokens[i - 1]

    def expr():
        v = term()
        while peek() in (("op", "+"), ("op", "-")):
            v = v + term() if take()[1] == "+" else v - term()
        return v

    def term():
        v = unary()
        while peek() in (("op", "*"), ("op", "/")):
            if take()[1] == "*":
                v = v * unary()
            else:
                d = unary()
                if d.is_zero():
                    fail("division by zero")
                v = v / d
        return v

    def unary():
        if peek() in (("op", "+"), ("op", "-")):
            return unary() if take()[1] == "+" else -unary()
        return power()

    def power():
        v = atom()
        if peek() == ("op", "^"):
            take()
            sign = 1
            if peek() in (("op", "+"), ("op", "-")):
                sign = -1 if take()[1] == "-" else 1
            kind, tok = take() if i < len(tokens) else ("end", "")
            if kind != "num" or not tok.isdigit():
                fail("an exponent must be an integer")
            if v.is_zero() and sign < 0:
                fail("division by zero")
            v = v ** (sign * int(tok))
        return v

    def atom():
        if i >= len(tokens):
            fail("unexpected end")
        kind, tok = take()
        if kind == "num":
            return RationalFunction(to_fmpq(tok))
        if kind == "s":
            return RationalFunction(_S)
        if tok == "(":
            v = expr()
            if i >= len(tokens) or take() != ("op", ")"):
                fail("missing ')'")
            return v
        fail(f"unexpected {tok!r}")

    v = expr()
    if i != len(tokens):
        fail(f"unexpected {tokens[i][1]!r}")
    return v


def _poly_str(p: fmpq_poly, var: str = "s") -> str:
    """s^2 - s + 1 style (high degree first)."""
    terms = []
    for d, c in reversed(list(enumerate(p.coeffs()))):
        if c == 0:
            continue
        mono = "" if d == 0 else var if d == 1 else f"{var}^{d}"
        a = abs(c)
        body = str(a) if not mono else (mono if a == 1 else f"{a}*{mono}")
        terms.append((c < 0, body))
    if not terms:
        return "0"
    out = ("-" if terms[0][0] else "") + terms[0][1]
    for neg, body in terms[1:]:
        out += (" - " if neg else " + ") + body
    return out


def laurent_coefficients(num: Sequence[Any], den: Sequence[Any], count: int) -> list[Any]:
    """Laurent coefficients at s = oo of N(s)/d(s) (5.6), starting at index deg d - deg N.

    ``num`` are the coefficients N_0, N_1, ..., N_a (low degree first) and may be scalars or
    row vectors (``fmpq_mat``: the numerator of a linear form in x0); ``den`` are the rational
    coefficients of d, d_b != 0.  From N = f d, comparing the coefficients of s^{a-r}:
    f_{b-a+r} = (N_{a-r} - sum_{q<b} d_q f_{q-a+r}) / d_b.
    """
    a, b = len(num) - 1, len(den) - 1
    db = den[b]
    zero = num[0] * 0
    f: list[Any] = []  # f[r] = f_{b-a+r}
    for r in range(count):
        acc = num[a - r] if a - r >= 0 else zero
        for q in range(b):
            idx = q - b + r  # position of f_{q-a+r} in f
            if idx >= 0:
                acc = acc - f[idx] * den[q]
        f.append(acc / db if db != 1 else acc)
    return f


# ---------------------------------------------------------------------------------------------
# sign decisions (the single place)
# ---------------------------------------------------------------------------------------------


def sign_of_form(form: Any, x: Any = None) -> int:
    """Exact sign of the linear form ``form`` at the point ``x``: -1, 0 or +1.

    ``form`` is an ``fmpq`` (then ``x`` is None) or a 1 x n ``fmpq_mat`` row.  A zero form is an
    exact zero by structure; a rational ``x`` (n x 1 ``fmpq_mat``) gives an exact sign; any other
    ``x`` must provide ``x.sign_of_form(form)``, which certifies the sign or raises
    :class:`~lcs_exact.errors.UnresolvedSign`.
    """
    if x is None:
        v = form
    else:
        if form == 0 * form:  # identically zero linear form: exact zero whatever x is
            return 0
        if isinstance(x, fmpq_mat):
            v = (form * x)[0, 0]
        else:
            return int(x.sign_of_form(form))
    return (v > 0) - (v < 0)


def lex_sign(seq: Iterable[Any], x: Any = None) -> int:
    """Lexicographic sign of a sequence of forms at x (5.7): sign of the first nonzero term."""
    for term in seq:
        s = sign_of_form(term, x)
        if s:
            return s
    return 0


# ---------------------------------------------------------------------------------------------
# matrices over Q(s)
# ---------------------------------------------------------------------------------------------


class RationalMatrix:
    """A dense matrix over Q(s) (G(s), R(s), G_II(s)^{-1}, ...), rows of RationalFunction."""

    __slots__ = ("rows",)

    def __init__(self, rows: Sequence[Sequence[Any]]):
        self.rows = [[RationalFunction._coerce(e) for e in r] for r in rows]

    @property
    def shape(self) -> tuple[int, int]:
        return (len(self.rows), len(self.rows[0]) if self.rows else 0)

    def __getitem__(self, ij):
        i, j = ij
        return self.rows[i][j]

    def sub(self, rows: Sequence[int], cols: Sequence[int]) -> "RationalMatrix":
        return RationalMatrix([[self.rows[i][j] for j in cols] for i in rows])

    def __mul__(self, o: "RationalMatrix") -> "RationalMatrix":
        n, m = self.shape
        m2, p = o.shape
        if m != m2:
            raise ShapeError(f"cannot multiply {n}x{m} by {m2}x{p}")
        return RationalMatrix([[sum((self.rows[i][l] * o.rows[l][j] for l in range(m)), RationalFunction(0))
                                for j in range(p)] for i in range(n)])

    def __add__(self, o: "RationalMatrix") -> "RationalMatrix":
        return RationalMatrix([[a + b for a, b in zip(r1, r2)] for r1, r2 in zip(self.rows, o.rows)])

    def __neg__(self):
        return RationalMatrix([[-a for a in r] for r in self.rows])

    def __sub__(self, o):
        return self + (-o)

    def __eq__(self, o):
        return isinstance(o, RationalMatrix) and self.rows == o.rows

    def _eliminate(self, rhs: "RationalMatrix | None"):
        """Gaussian elimination over Q(s); returns (det, solution of self X = rhs or None)."""
        n, m = self.shape
        if n != m:
            raise ShapeError(f"square matrix over Q(s) expected, got {n}x{m}")
        a = [list(self.rows[i]) + (list(rhs.rows[i]) if rhs is not None else []) for i in range(n)]
        det = RationalFunction(1)
        for c in range(n):
            # pivot: nonzero entry of smallest numerator degree (keeps degrees low)
            cand = [i for i in range(c, n) if not a[i][c].is_zero()]
            if not cand:
                return RationalFunction(0), None
            p = min(cand, key=lambda i: (a[i][c].num.degree() + a[i][c].den.degree()))
            if p != c:
                a[c], a[p] = a[p], a[c]
                det = -det
            piv = a[c][c]
            det = det * piv
            inv = 1 / piv
            a[c] = [e * inv for e in a[c]]
            for i in range(n):
                if i != c and not a[i][c].is_zero():
                    f = a[i][c]
                    a[i] = [e - f * g for e, g in zip(a[i], a[c])]
        sol = RationalMatrix([r[n:] for r in a]) if rhs is not None else None
        return det, sol

    def det(self) -> RationalFunction:
        """Determinant over Q(s) (zero iff the matrix is singular as a rational matrix)."""
        if self.shape[0] == 0:
            return RationalFunction(1)
        return self._eliminate(None)[0]

    def solve(self, rhs: "RationalMatrix") -> "RationalMatrix":
        """X with self X = rhs over Q(s); raises ZeroDivisionError when self is singular."""
        if self.shape[0] == 0:
            return RationalMatrix([])
        det, sol = self._eliminate(rhs)
        if sol is None:
            raise ZeroDivisionError("matrix over Q(s) is singular")
        return sol

    def row_forms(self, i: int) -> tuple[list[fmpq_mat], fmpq_poly]:
        """Row i as one rational function whose numerator has row-vector coefficients.

        Returns (numerator coefficients N_0..N_a as 1 x m ``fmpq_mat``, common denominator d):
        row_i(s) . x = (sum_p (N_p . x) s^p) / d(s).
        """
        row = self.rows[i]
        d = fmpq_poly([1])
        for e in row:
            d = d * e.den / d.gcd(e.den)
            d = fmpq_poly(d)
        nums = [fmpq_poly(e.num * fmpq_poly(d / e.den)) for e in row]
        deg = max((p.degree() for p in nums), default=-1)
        m = len(row)
        coeffs = []
        for p in range(max(deg, 0) + 1):
            coeffs.append(fmpq_mat(1, m, [q.coeffs()[p] if p <= q.degree() else 0 for q in nums]))
        return coeffs, d

    def apply(self, x: fmpq_mat) -> list[RationalFunction]:
        """self(s) x for a rational vector x: a list of rational functions."""
        n, m = self.shape
        return [sum((self.rows[i][j] * RationalFunction(x[j, 0]) for j in range(m)), RationalFunction(0))
                for i in range(n)]

    def to_sympy(self):
        import sympy
        return sympy.Matrix([[e.to_sympy() for e in r] for r in self.rows]) if self.rows else sympy.Matrix([])

    def __repr__(self):
        return "RationalMatrix([" + ", ".join("[" + ", ".join(f"'{e}'" for e in r) + "]" for r in self.rows) + "])"

    def __str__(self):
        return "\n".join("[" + ", ".join(str(e) for e in r) + "]" for r in self.rows)

    def _repr_latex_(self):
        import sympy
        n, m = self.shape
        if n * m > 64 or sum(len(str(e)) for r in self.rows for e in r) > _LATEX_MAX_CHARS:
            return None
        return f"${sympy.latex(self.to_sympy())}$"


# ---------------------------------------------------------------------------------------------
# the resolvent (sI - A)^{-1} (5.3)
# ---------------------------------------------------------------------------------------------


def adjugate_coefficients(A: fmpq_mat, chi: fmpq_poly | None = None) -> list[fmpq_mat]:
    """adj(sI - A) = sum_j s^{n-1-j} B_j (Faddeev-LeVerrier: B_0 = I, B_j = A B_{j-1} + c_j I,
    with det(sI - A) = s^n + c_1 s^{n-1} + ... + c_n).

    For any monic ``chi`` of degree d (not only the characteristic polynomial) the same recursion
    gives sum_j s^{d-1-j} B_j = (chi(s) I - chi(A)) (sI - A)^{-1}, a polynomial in s and A.

    >>> [b.entries() for b in adjugate_coefficients(fmpq_mat([[0, 1], [-1, 0]]))]
    [[1, 0, 0, 1], [0, 1, -1, 0]]
    """
    n = A.nrows()
    c = (chi if chi is not None else A.charpoly()).coeffs()[::-1]  # c[j]: coefficient of s^{d-j}
    bs = [identity(n)]
    for j in range(1, len(c) - 1):
        bs.append(A * bs[-1] + identity(n) * c[j])
    return bs


def poly_at_matrix(p: fmpq_poly, S: fmpq_mat) -> fmpq_mat:
    """p(S) for p in Q[s] (Horner), exactly."""
    n = S.nrows()
    out = zeros(n, n)
    for c in reversed(p.coeffs()):
        out = out * S + identity(n) * c
    return out


def resolvent(A: fmpq_mat, left: fmpq_mat, right: fmpq_mat | None = None) -> RationalMatrix:
    """left (sI - A)^{-1} right over Q(s) (right = I when None): R(s), G(s) - D of (5.3).

    >>> resolvent(fmpq_mat([[0, 1], [-1, 0]]), fmpq_mat([[1, 0]]))
    RationalMatrix([['s/(s^2 + 1)', '1/(s^2 + 1)']])
    """
    chi = A.charpoly()
    bs = adjugate_coefficients(A, chi)
    n = A.nrows()
    mats = [left * b * right if right is not None else left * b for b in bs]
    r, c = mats[0].nrows(), mats[0].ncols()
    return RationalMatrix([[RationalFunction(fmpq_poly([mats[n - 1 - d][i, j] for d in range(n)]), chi)
                            for j in range(c)] for i in range(r)])

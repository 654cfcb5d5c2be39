"""Exact rationals and rational matrices: user input converted once, limits, small helpers,
the one place where signs of linear forms are decided.

* Representation: scalars are ``flint.fmpq``, matrices ``flint.fmpq_mat``, vectors n x 1 ``fmpq_mat``;
  user input is converted once, here (:func:`to_fmpq`, :func:`to_matrix`, :func:`to_vector`).  Rational
  functions in Q(s) and matrices of them (G(s), R(s), 5.3) are in :mod:`lcs_exact.ratfunc`.
* Signs at s = oo (section 5): a rational function is nonnegative for all large real s iff its sequence of
  Laurent coefficients at s = oo (5.6) is lexicographically nonnegative (5.7, Lemma 5.1).  In mode selection
  those coefficients are *linear forms* in the state x0 (rows ell with value ell . x0).  :func:`sign_of_form`
  is the one place where such a sign is decided: an identically zero form is an exact zero; a rational point
  gives an exact sign; any other point (an exact real vector) must decide the sign itself through its
  ``sign_of_form`` method, which certifies it or raises :class:`~lcs_exact.errors.UnresolvedSign`.
"""
from __future__ import annotations

import math
import re
from collections.abc import Mapping, Set
from decimal import Decimal
from functools import lru_cache
from fractions import Fraction
from itertools import islice
from numbers import Integral, Rational
from typing import Any, Iterable, Sequence, Union

import flint
from flint import fmpq, fmpq_mat, fmpz

from ..errors import InvalidArgument, NotRational, ShapeError, Unsupported

__all__ = [
    "RationalLike", "to_fmpq", "to_matrix", "to_vector", "vector_entries", "as_list", "to_int", "is_rational_vector",
    "zeros", "identity", "is_zero", "hstack", "vstack", "submatrix", "selection_matrix", "column", "mat_rows", "mat_equal",
    "sign_of_form", "lex_sign", "format_form",
    "fmpq_to_sympy", "matrix_to_sympy",
    "MAX_RATIONAL_BITS", "MAX_DIMENSION", "MAX_ENUMERATION_K", "MAX_P_TEST_K", "MAX_MARKOV_INDEX",
    "MAX_KAPPA", "MAX_HORIZON_SLOW", "MAX_HORIZON_FAST", "MAX_PREC_BITS", "check_enumerable",
    "to_short", "pivot_tableau",
]

RationalLike = Union[int, str, Fraction, fmpq, fmpz, Rational, float]

# ---- limits on user input (one place; docs/limits.md lists them with their reasons) ----------
#: bits of the numerator and of the denominator of one rational read from user input (about 19,700 decimal
#: digits; ``"1e999999999"`` is refused at once instead of being expanded).  ``fmpq``/``fmpz`` values are
#: taken as they are: they are already exact (and the engine's own).
MAX_RATIONAL_BITS = 65_536
#: rows and columns of one matrix, length of one vector (n, k <= 1024); practical to n ~ 64 (16 carts, n = 32: seconds)
MAX_DIMENSION = 1024
#: largest k for enumerations of the 2^k modes or index sets (RCP for every mode, mode maps, all LCP solutions)
MAX_ENUMERATION_K = 16
#: largest k for the P-matrix test of a nonsymmetric matrix (Tsatsomeros-Li: 2^k Schur steps, ~3 s at k = 20);
#: a symmetric matrix is tested by its leading minors at any size.
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

    Parameters
    ----------
    x : object
    width : int, optional

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

    Accepts int, ``"p/q"`` or decimal strings (``"-1.25e-3"``), Fraction, Decimal, sympy Rational, fmpq,
    fmpz, numpy integers, and floats (read as their shortest decimal repr: ``0.1 -> 1/10``; a NumPy float
    of any type, a scalar or a 0-d array, by the shortest repr of its own type: ``np.float32(-0.1)`` and
    ``np.float16(-0.1)`` are -1/10 too).  Refuses bools, NaN and infinities, complex numbers, SymPy
    non-rationals (:class:`~lcs_exact.errors.NotRational`, naming ``what``) and numbers whose numerator
    or denominator would exceed :data:`MAX_RATIONAL_BITS` bits (:class:`~lcs_exact.errors.InvalidArgument`;
    checked before a decimal exponent is expanded).

    Parameters
    ----------
    x : rational-like
        The input (above).
    what : str, optional
        Its name in an error message.

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
        if type(x).__name__ == "ndarray":
            x = x[()]  # a 0-d array: its scalar, of its own type (.item() would make a float32 a float)
        if getattr(getattr(x, "dtype", None), "kind", None) == "f":
            return _numpy_float(x, what)
        v = x.item()
        if type(v) is type(x):  # a numpy type with no Python equivalent (clongdouble)
            v = complex(x)
        return to_fmpq(v, what)
    # other numbers.Rational (Integral first: numpy-like ints)
    if isinstance(x, Integral):
        return _check_bits(int(x), 1, what, x)
    if isinstance(x, Rational):
        return _check_bits(int(x.numerator), int(x.denominator), what, x)
    raise NotRational(f"{what} {to_short(x)} of type {type(x).__name__} is not an exact rational number")


def _numpy_float(x: Any, what: str) -> fmpq:
    """A NumPy float (float16, float32, float64, longdouble) read as the shortest decimal that its own
    type rounds back to it: ``np.float32(-0.1)`` is -1/10, as typed, not the float64 repr of its binary
    value (-0.10000000149011612).  ``format_float_scientific(unique=True)`` is that decimal whatever the
    print options (``str`` is not: under ``legacy='1.13'`` a float32 1/3 prints as 0.333333)."""
    import numpy as np
    if not np.isfinite(x):
        raise NotRational(f"{what} is {x!r}, not a finite number")
    return _parse_number(np.format_float_scientific(x, unique=True, trim="-"), what)


def as_list(data: Any) -> Any:
    """``data.tolist()``, except that a NumPy float array keeps its entries as NumPy scalars (nested lists
    of them): ``tolist`` turns a float32 into the Python float of its binary value, whose repr is not the
    float32's (0.10000000149011612 for ``np.float32(0.1)``); kept, each entry is read by :func:`to_fmpq`
    as its own type's shortest decimal.

    Parameters
    ----------
    data : array-like

    >>> import numpy as np
    >>> [to_fmpq(v) for v in as_list(np.array([0.1, -0.1], dtype=np.float32))]
    [1/10, -1/10]
    >>> as_list(np.array([[1, 2]]))
    [[1, 2]]
    """
    if getattr(getattr(data, "dtype", None), "kind", None) != "f" or \
            not type(data).__module__.startswith("numpy"):
        return data.tolist()
    import numpy as np
    a = np.asarray(data)  # an np.matrix too (its rows would be matrices again)

    def nest(b):
        return b[()] if b.ndim == 0 else list(b) if b.ndim == 1 else [nest(r) for r in b]
    return nest(a)


def to_int(x: Any, what: str, lo: int | None = None, hi: int | None = None) -> int:
    """An integer argument (a Python or numpy integer, not a bool), checked to lie in [lo, hi]
    (:class:`~lcs_exact.errors.InvalidArgument` naming ``what`` otherwise).

    Parameters
    ----------
    x : int
    what : str
        Its name in an error message.
    lo, hi : int or None, optional
        The bounds (None: unbounded).

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

    Parameters
    ----------
    k : int
        2^k sets.
    what : str
        The enumeration, for the message.
    limit : int, optional

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
        data = as_list(data)
    rows = [as_list(r) if hasattr(r, "tolist") else r for r in _items(data, name, "a matrix (a list of rows)")]
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

    ``shape`` may fix either dimension (``None`` leaves it free).  Raises :class:`~lcs_exact.errors.ShapeError`
    for ragged, wrong-sized, too deeply nested or oversized (more than :data:`MAX_DIMENSION` along a side)
    input, or a mapping or set, and :class:`~lcs_exact.errors.NotRational` for an entry that is not an
    exact rational.

    Parameters
    ----------
    data : matrix-like
        Rows, a SymPy or NumPy matrix, or an ``fmpq_mat``.
    name : str, optional
        Its name in an error message.
    shape : (int or None, int or None), optional

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
    """The entries of a vector given flat (``[a, b]``) or as a column (``[[a], [b]]``), not converted;
    :class:`~lcs_exact.errors.ShapeError` for a string, a mapping or set (no order), a scalar, deeper
    nesting or a wrong length.

    Parameters
    ----------
    data : sequence
        Flat or a column.
    n : int or None
        The length required (None: any).
    name : str, optional
        Its name in an error message.

    >>> vector_entries([[1], ["1/2"]], 2)
    [1, '1/2']
    >>> vector_entries({0: 1, 1: 2}, 2)
    Traceback (most recent call last):
    ...
    lcs_exact.errors.ShapeError: x0 must be a vector of length 2 (a list of numbers), got dict
    """
    want = "a vector" + ("" if n is None else f" of length {n}") + " (a list of numbers)"
    if hasattr(data, "tolist") and not isinstance(data, fmpq_mat):
        data = as_list(data)
    flat: list[Any] = []
    for i, e in enumerate(_items(data, name, want)):
        if hasattr(e, "tolist") and getattr(e, "ndim", 0) > 0:
            e = as_list(e)
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
    """Read a rational vector of length n into an n x 1 ``fmpq_mat`` (flat or column input).

    Parameters
    ----------
    data : vector-like
        Flat or a column, or an ``fmpq_mat``.
    n : int
    name : str, optional
        Its name in an error message.
    """
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


# ---- small fmpq_mat helpers (flint has no slicing or stacking) -------------------------------
def zeros(r: int, c: int) -> fmpq_mat:
    """The r x c zero matrix.

    Parameters
    ----------
    r, c : int"""
    return fmpq_mat(r, c)


def identity(n: int) -> fmpq_mat:
    """The n x n identity matrix.

    Parameters
    ----------
    n : int"""
    m = fmpq_mat(n, n)
    for i in range(n):
        m[i, i] = 1
    return m


def mat_rows(m: fmpq_mat) -> list[list[fmpq]]:
    """The entries of m as a list of rows.

    Parameters
    ----------
    m : fmpq_mat"""
    return [[m[i, j] for j in range(m.ncols())] for i in range(m.nrows())]


def submatrix(m: fmpq_mat, rows: Sequence[int] | None = None, cols: Sequence[int] | None = None) -> fmpq_mat:
    """m[rows, cols] (``None`` keeps all).

    A large part is taken by products with 0/1 selection matrices (kept per index set): FLINT
    copies the entries, where reading them into Python objects and back costs ~4x more (a stage
    of the LDCP of a 128-state system takes 40 rows of a 64 x 128 form).  A small part is read
    entry by entry.

    Parameters
    ----------
    m : fmpq_mat
    rows, cols : sequence of int or None, optional
    """
    r, c = m.nrows(), m.ncols()
    rows = None if rows is None else tuple(rows)
    cols = None if cols is None else tuple(cols)
    nr = r if rows is None else len(rows)
    nc = c if cols is None else len(cols)
    if nr * nc < _SELECT_MIN or (rows is not None and cols is not None and 4 * nr * nc < r * c):
        rs = range(r) if rows is None else rows
        cs = range(c) if cols is None else cols
        return fmpq_mat(nr, nc, [m[i, j] for i in rs for j in cs])
    if rows is None and cols is None:
        return fmpq_mat(m)  # a copy, as every other part
    if rows is not None:
        m = _selection(rows, r) * m
    if cols is not None:
        m = m * _selection(cols, c).transpose()
    return m


#: parts with fewer entries are read entry by entry (measured: a selection product costs about
#: as much as 64 entries read from Python)
_SELECT_MIN = 64


def selection_matrix(rows: Sequence[int], r: int) -> fmpq_mat:
    """The len(rows) x r 0/1 matrix S with S m = m[rows, :] (its transpose puts the rows of a
    block at ``rows``).

    Parameters
    ----------
    rows : sequence of int
        Indices in range(r).
    r : int

    >>> selection_matrix((2, 0), 3).tolist()
    [[0, 0, 1], [1, 0, 0]]
    """
    return fmpq_mat(_selection(tuple(rows), r))  # a copy: the kept one is shared


@lru_cache(maxsize=128)
def _selection(rows: tuple, r: int) -> fmpq_mat:
    """:func:`selection_matrix`, kept per (rows, r) (shared: never modified)."""
    if any(not 0 <= i < r for i in rows):
        raise IndexError(f"selection: an index of {rows} is outside range({r})")
    m = fmpq_mat(len(rows), r)  # zeros, then the ones: 60x faster than a list of len(rows) * r
    for a, i in enumerate(rows):
        m[a, i] = 1
    return m


@lru_cache(maxsize=128)
def _placement(top: int, rows: int, r: int) -> fmpq_mat:
    """The r x rows 0/1 matrix that puts a block of ``rows`` rows at rows top, top + 1, ... of r
    (:func:`vstack`; kept, shared: never modified)."""
    m = fmpq_mat(r, rows)
    for a in range(rows):
        m[top + a, a] = 1
    return m


def column(m: fmpq_mat, j: int) -> fmpq_mat:
    return submatrix(m, None, [j])


def hstack(*ms: fmpq_mat, nrows: int | None = None) -> fmpq_mat:
    """[m1 m2 ...]; ``nrows`` is needed only when no block is given.

    Parameters
    ----------
    *ms : fmpq_mat
    nrows : int, optional
    """
    r = ms[0].nrows() if ms else (nrows or 0)
    if any(m.nrows() != r for m in ms):
        raise ShapeError("hstack: blocks have different numbers of rows")
    if len(ms) == 1:
        return fmpq_mat(ms[0])
    return vstack(*[m.transpose() for m in ms], ncols=r).transpose()  # transposes are copies in C


def vstack(*ms: fmpq_mat, ncols: int | None = None) -> fmpq_mat:
    """[m1; m2; ...]; ``ncols`` is needed only when no block is given.

    Parameters
    ----------
    *ms : fmpq_mat
    ncols : int, optional
    """
    c = ms[0].ncols() if ms else (ncols or 0)
    if any(m.ncols() != c for m in ms):
        raise ShapeError("vstack: blocks have different numbers of columns")
    r = sum(m.nrows() for m in ms)
    if len(ms) == 1:
        return fmpq_mat(ms[0])
    if r * c < _SELECT_MIN or c < 2 * r:
        return fmpq_mat(r, c, [x for m in ms for x in m.entries()])
    # wide blocks are placed by products with 0/1 matrices (see submatrix): 1.5-3.5x faster than
    # reading the entries into Python objects and back (the constraint forms of a mode, k x n
    # with k < n / 2); tall results cost more as products (measured on the chains of carts)
    out, top = None, 0
    for m in ms:
        if m.nrows():
            part = _placement(top, m.nrows(), r) * m
            out = part if out is None else out + part
            top += m.nrows()
    return out


def pivot_tableau(T: list, r: int, c: int) -> None:
    """Gauss-Jordan pivot of a tableau of exact rationals (a list of rows), in place: row r is divided by
    T[r][c] and column c is eliminated from every other row (Lemke's method, :mod:`lcs_exact.polyhedra`)."""
    p = T[r][c]
    T[r] = [e / p for e in T[r]]
    for i in range(len(T)):
        if i != r and T[i][c] != 0:
            f = T[i][c]
            T[i] = [e - f * g for e, g in zip(T[i], T[r])]


def is_zero(m: fmpq_mat) -> bool:
    """All entries zero (fmpq_mat has no is_zero; a comparison in C, not a list of entries).

    Parameters
    ----------
    m : fmpq_mat
    """
    return m == fmpq_mat(m.nrows(), m.ncols())


def mat_equal(a: fmpq_mat, b: fmpq_mat) -> bool:
    """a == b, shapes included (False for matrices of different shapes).

    Parameters
    ----------
    a, b : fmpq_mat"""
    return a.nrows() == b.nrows() and a.ncols() == b.ncols() and a == b


def fmpq_to_sympy(q: fmpq):
    import sympy
    return sympy.Rational(int(q.p), int(q.q))


def matrix_to_sympy(m: fmpq_mat):
    """m as a ``sympy.Matrix`` of ``sympy.Rational`` entries (imports SymPy).

    Parameters
    ----------
    m : fmpq_mat"""
    import sympy
    return sympy.Matrix(m.nrows(), m.ncols(), lambda i, j: fmpq_to_sympy(m[i, j]))


# ---- sign decisions (the single place) -------------------------------------------------------
def sign_of_form(form: Any, x: Any = None) -> int:
    """Exact sign of the linear form ``form`` at the point ``x``: -1, 0 or +1.

    ``form`` is an ``fmpq`` (then ``x`` is None) or a 1 x n ``fmpq_mat`` row.  A zero form is an exact
    zero by structure; a rational ``x`` (n x 1 ``fmpq_mat``) gives an exact sign; any other ``x`` must
    provide ``x.sign_of_form(form)``, which certifies the sign or raises :class:`~lcs_exact.errors.UnresolvedSign`.

    Parameters
    ----------
    form : fmpq or fmpq_mat
    x : fmpq_mat or ExactVector, optional
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
    """Lexicographic sign of a sequence of forms at x (5.7): sign of the first nonzero term.

    Parameters
    ----------
    seq : iterable of forms
        As :func:`sign_of_form` takes them.
    x : fmpq_mat or ExactVector, optional
    """
    for term in seq:
        s = sign_of_form(term, x)
        if s:
            return s
    return 0


# ---- polynomials of a matrix (the resolvent's coefficients, spectral data) -------------------
def format_form(form: fmpq_mat) -> str:
    """A row as text: (1, 0, -1/2).

    Parameters
    ----------
    form : fmpq_mat
        A 1 x n row.
    """
    return "(" + ", ".join(str(form[0, j]) for j in range(form.ncols())) + ")"

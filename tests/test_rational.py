"""rational.py: coercion to fmpq / fmpq_mat, Q(s) rational functions, Laurent coefficients at
s = oo (5.6), exact signs of linear forms and the lexicographic sign (5.7), matrices over Q(s).

Every expected value is derived independently: by hand (in a comment), with ``fractions``, or
with SymPy (series expansions, determinants, linear solves).
"""
from __future__ import annotations

from collections import defaultdict
from fractions import Fraction

import numpy as np
import pytest
import sympy
from flint import fmpq, fmpq_mat, fmpq_poly, fmpz
from helpers import F, mat, vec
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from lcs_exact.errors import NotRational, ShapeError, UnresolvedSign
from lcs_exact.algebra.ratfunc import RationalFunction, RationalMatrix, laurent_coefficients, resolvent
from lcs_exact.algebra.matrixfunctions import poly_at_matrix
from lcs_exact.algebra.rational import lex_sign, sign_of_form, to_fmpq, to_matrix, to_vector

from reference.polynomials import peval

s = RationalFunction.s()
S = sympy.Symbol("s")
X = sympy.Symbol("x")
PROP = settings(derandomize=True, deadline=None, max_examples=50)


# ---------------------------------------------------------------------------------------------
# independent helpers
# ---------------------------------------------------------------------------------------------

def sympy_laurent(expr, start: int, count: int) -> list[Fraction]:
    """Coefficients of s^-start, ..., s^-(start+count-1) of expr(s) at s = oo, by SymPy's series
    of expr(1/x) at x = 0 (an independent expansion)."""
    g = sympy.together(expr.subs(S, 1 / X))
    ser = sympy.series(g, X, 0, start + count).removeO()
    ser = sympy.expand(ser)
    return [Fraction(str(ser.coeff(X, i))) for i in range(start, start + count)]


def rf_sympy(num: list, den: list):
    """p(s)/q(s) in SymPy from low-degree-first coefficient lists."""
    return sum(sympy.Rational(str(c)) * S**i for i, c in enumerate(num)) / \
        sum(sympy.Rational(str(c)) * S**i for i, c in enumerate(den))


def fl(xs) -> list[Fraction]:
    return [F(x) for x in xs]


# ---------------------------------------------------------------------------------------------
# to_fmpq
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("value, expected", [
    (3, Fraction(3)),
    (-7, Fraction(-7)),
    ("3/4", Fraction(3, 4)),
    (" -6/8 ", Fraction(-3, 4)),          # reduced: -6/8 = -3/4
    ("0.25", Fraction(1, 4)),
    ("-1.5", Fraction(-3, 2)),
    ("1e-3", Fraction(1, 1000)),
    (Fraction(10, 4), Fraction(5, 2)),
    (sympy.Rational(3, 4), Fraction(3, 4)),
    (sympy.Rational(-22, 7), Fraction(-22, 7)),
    (sympy.Integer(5), Fraction(5)),
    (fmpq(2, 3), Fraction(2, 3)),
    (fmpz(12), Fraction(12)),
    (np.int64(7), Fraction(7)),
    (np.int32(-4), Fraction(-4)),
    (0.1, Fraction(1, 10)),               # shortest repr '0.1', not 3602879701896397/36028797018963968
    (0.25, Fraction(1, 4)),
    (-2.5, Fraction(-5, 2)),
    (1e-7, Fraction(1, 10**7)),
    (3.0, Fraction(3)),
])
def test_to_fmpq_accepts_exact_inputs(value, expected):
    q = to_fmpq(value)
    assert isinstance(q, fmpq)
    assert F(q) == expected


def test_to_fmpq_float_is_shortest_repr_not_binary_value():
    # the binary double nearest 0.1 is 3602879701896397 / 2^55; the design reads repr(0.1) = '0.1'
    assert Fraction(0.1) == Fraction(3602879701896397, 2**55)
    assert F(to_fmpq(0.1)) == Fraction(1, 10) != Fraction(0.1)
    assert F(to_fmpq(1 / 3)) == Fraction("0.3333333333333333")


def test_to_fmpq_numpy_float64_scalar():
    # np.float64 is a subclass of float: it must be read like the float 0.25 (-> 1/4), 0.1 -> 1/10.
    # (repr(np.float64(0.25)) is 'np.float64(0.25)' under numpy 2, so repr(float(x)) is needed.)
    assert F(to_fmpq(np.float64(0.25))) == Fraction(1, 4)
    assert F(to_fmpq(np.float64(0.1))) == Fraction(1, 10)


def test_to_matrix_of_numpy_float_array():
    m = to_matrix(np.array([[0.5, 0.1], [2.0, -0.75]]), "A")
    assert mat(m) == [[Fraction(1, 2), Fraction(1, 10)], [Fraction(2), Fraction(-3, 4)]]


def _shortest_decimal(x) -> Fraction:
    """The shortest decimal that x's own NumPy type reads back as x, found by brute force from
    x's exact value (x is a float64 value exactly: every float16/32/64, and the longdoubles made
    here from float64s): the value rounded to 1, 2, 3, ... significant digits (Decimal,
    half-even), each parsed back by the type itself; the first that gives x back."""
    import decimal
    exact = Fraction(float(x))
    for digits in range(1, 45):
        with decimal.localcontext() as ctx:
            ctx.prec = digits
            text = str(decimal.Decimal(exact.numerator) / decimal.Decimal(exact.denominator))
        if type(x)(text) == x:
            return Fraction(text)
    raise AssertionError(f"no decimal of at most 44 digits reads back as {x!r}")


FLOAT_TYPES = [np.float16, np.float32, np.float64, np.longdouble]
TYPED = ["0.1", "-0.1", "2.5", "-1e-3", "0.3", "-7.77", "1/3", "-2/3", "1e-7", "-123.456"]


def _read_every_way(x, want):
    T = type(x)
    assert F(to_fmpq(x)) == want and F(to_fmpq(-x)) == -want
    assert F(to_fmpq(np.array(x))) == want  # a 0-d array
    assert vec(to_vector(np.array([x, -x], dtype=T), 2)) == [want, -want]
    assert mat(to_matrix(np.array([[x], [-x]], dtype=T))) == [[want], [-want]]
    assert mat(to_matrix(np.matrix([[x, -x]], dtype=T))) == [[want, -want]]
    assert vec(to_vector([x, np.array(-x)], 2)) == [want, -want]
    with np.printoptions(legacy="1.13"):  # str() then differs; the reading must not
        assert F(to_fmpq(x)) == want and F(to_fmpq(np.array(-x))) == -want


@pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")  # np.matrix is read too
@pytest.mark.parametrize("T", FLOAT_TYPES, ids=lambda T: T.__name__)
def test_every_numpy_float_reads_as_its_own_shortest_decimal(T):
    """np.float32(-0.1) is -1/10 like np.float32(0.1) is 1/10: a scalar, a 0-d array, the entries
    of 1-d and 2-d arrays (tolist() made float32 entries Python floats, whose repr is that of
    the float64 value: -0.10000000149011612) and under any print options (str(np.float32(1/3))
    is 0.333333 under legacy='1.13', not the float32 0.33333334)."""
    for text in TYPED:
        x = T(float(Fraction(text)))  # the float64 nearest the text, then rounded to T
        _read_every_way(x, _shortest_decimal(x))
    for text in ("0.1", "-0.1", "0.3", "-1e-3", "1e-7", "-6"):
        # one significant digit, read by T itself: no shorter decimal exists, so it is x's shortest
        _read_every_way(T(text), Fraction(text))


def test_numpy_float_values_derived_by_hand():
    # the float32 nearest 1/3 is 11184811/2^25 = 0.3333333432674407958984375; 0.3333333 reads back
    # as 11184810/2^25 (it is below the midpoint 0.33333332836627960205078125), 0.33333334 as
    # 11184811/2^25: the shortest decimal is 0.33333334
    assert Fraction(float(np.float32(1 / 3))) == Fraction(11184811, 2**25)
    assert F(to_fmpq(np.float32(1 / 3))) == F(to_fmpq(np.array([np.float32(1 / 3)])[0])) == Fraction(33333334, 10**8)
    # float16 has 10 fraction bits: -0.1 is -1638/2^14 = -0.0999755859375, and -0.1 reads back as it
    assert Fraction(float(np.float16(-0.1))) == Fraction(-1638, 2**14)
    assert F(to_fmpq(np.array(np.float16(-0.1)))) == Fraction(-1, 10)
    for bad in (np.float32("nan"), np.array(np.float16("inf")), np.longdouble("-inf")):
        with pytest.raises(NotRational, match="not a finite number"):
            to_fmpq(bad)


@pytest.mark.parametrize("bad", [
    "abc", "1/0", "", None, float("nan"), float("inf"), float("-inf"), sympy.sqrt(2), sympy.pi,
    1 + 2j, complex(1, 0), True, False, [1], object(),
])
def test_to_fmpq_rejects_non_rationals(bad):
    with pytest.raises(NotRational) as ei:
        to_fmpq(bad, "A[0, 1]")
    assert isinstance(ei.value, TypeError)
    assert "A[0, 1]" in str(ei.value)  # the message names the entry


def test_to_fmpq_messages_say_why():
    with pytest.raises(NotRational, match="bool"):
        to_fmpq(True)
    with pytest.raises(NotRational, match="finite"):
        to_fmpq(float("nan"))
    with pytest.raises(NotRational, match="SymPy"):
        to_fmpq(sympy.sqrt(2))


# ---------------------------------------------------------------------------------------------
# to_matrix / to_vector
# ---------------------------------------------------------------------------------------------

def test_to_matrix_reads_mixed_entries():
    m = to_matrix([[1, "1/2", Fraction(1, 3)], [0.25, sympy.Rational(-2, 5), fmpq(7)]])
    assert (m.nrows(), m.ncols()) == (2, 3)
    assert mat(m) == [[1, Fraction(1, 2), Fraction(1, 3)], [Fraction(1, 4), Fraction(-2, 5), 7]]


def test_to_matrix_from_sympy_and_flint():
    m = to_matrix(sympy.Matrix([[1, sympy.Rational(1, 2)], [3, 4]]))
    assert mat(m) == [[1, Fraction(1, 2)], [3, 4]]
    src = fmpq_mat([[1, 2], [3, 4]])
    assert mat(to_matrix(src)) == [[1, 2], [3, 4]]
    assert mat(to_matrix(np.array([[1, 2, 3]], dtype=np.int64))) == [[1, 2, 3]]


def test_to_matrix_shape_constraints():
    m = to_matrix([[1, 2], [3, 4], [5, 6]], "B", (3, None))
    assert (m.nrows(), m.ncols()) == (3, 2)
    assert to_matrix([[1, 2], [3, 4], [5, 6]], "B", (None, 2)).ncols() == 2
    with pytest.raises(ShapeError, match=r"B has shape 3x2, expected 2x\?"):
        to_matrix([[1, 2], [3, 4], [5, 6]], "B", (2, None))
    with pytest.raises(ShapeError, match=r"C has shape 3x2, expected 3x3"):
        to_matrix([[1, 2], [3, 4], [5, 6]], "C", (3, 3))
    with pytest.raises(ShapeError, match=r"has shape 2x2, expected \?x3"):
        to_matrix(fmpq_mat([[1, 2], [3, 4]]), "M", (None, 3))


def test_to_matrix_ragged_rows():
    with pytest.raises(ShapeError) as ei:
        to_matrix([[1, 2], [3]], "A")
    assert isinstance(ei.value, ValueError)
    assert "A" in str(ei.value) and "[1, 2]" in str(ei.value)  # names the row lengths


def test_to_matrix_not_a_matrix():
    with pytest.raises(ShapeError):
        to_matrix("12", "A")
    with pytest.raises(ShapeError):
        to_matrix(5, "A")


def test_to_matrix_entry_position_in_error():
    with pytest.raises(NotRational, match=r"A\[1, 0\]"):
        to_matrix([[1, 2], ["x", 4]], "A")


def test_to_vector_forms():
    for data in ([1, "1/2", 0.25], [[1], ["1/2"], [0.25]], (1, Fraction(1, 2), Fraction(1, 4)),
                 fmpq_mat([[1], [fmpq(1, 2)], [fmpq(1, 4)]]), fmpq_mat([[1, fmpq(1, 2), fmpq(1, 4)]]),
                 np.array([1, 0.5, 0.25])):
        v = to_vector(data, 3)
        assert (v.nrows(), v.ncols()) == (3, 1)
        assert vec(v) == [1, Fraction(1, 2), Fraction(1, 4)]


@pytest.mark.parametrize("data", [[1, 2], [1, 2, 3, 4], [[1, 2], [3, 4], [5, 6]],
                                  fmpq_mat([[1, 2], [3, 4]]), fmpq_mat(1, 2, [1, 2]), "123", 7])
def test_to_vector_wrong_shapes(data):
    with pytest.raises(ShapeError) as ei:
        to_vector(data, 3, "x0")
    assert "x0" in str(ei.value)


# ---------------------------------------------------------------------------------------------
# RationalFunction: normalization, arithmetic, evaluation
# ---------------------------------------------------------------------------------------------

def test_normalization_cancels_gcd_and_makes_denominator_monic():
    # (2 s^2 - 2)/(4 s - 4) = 2 (s-1)(s+1) / (4 (s-1)) = (s + 1)/2 -> numerator 1/2 s + 1/2, den 1
    f = RationalFunction([-2, 0, 2], [-4, 4])
    assert fl(f.num.coeffs()) == [Fraction(1, 2), Fraction(1, 2)]
    assert fl(f.den.coeffs()) == [1]
    # (3 s + 3)/(6 s^2 + 6 s) = 3 (s+1) / (6 s (s+1)) = (1/2)/s
    g = RationalFunction([3, 3], [0, 6, 6])
    assert fl(g.num.coeffs()) == [Fraction(1, 2)] and fl(g.den.coeffs()) == [0, 1]
    # zero is 0/1 whatever the denominator
    z = RationalFunction(0, [5, 7])
    assert z.is_zero() and z.num.is_zero() and fl(z.den.coeffs()) == [1]
    with pytest.raises(ZeroDivisionError):
        RationalFunction(1, 0)


@pytest.mark.slow
@given(st.lists(st.integers(-4, 4), min_size=1, max_size=4),
       st.lists(st.integers(-4, 4), min_size=1, max_size=4),
       st.lists(st.integers(-3, 3), min_size=1, max_size=3))
@PROP
def test_normalization_property(p, q, common):
    """p c / (q c) is stored coprime with a monic denominator, and keeps its values."""
    assume(any(q) and any(common))
    num = sympy.Poly(list(reversed(p)), S) * sympy.Poly(list(reversed(common)), S)
    den = sympy.Poly(list(reversed(q)), S) * sympy.Poly(list(reversed(common)), S)
    f = RationalFunction([int(c) for c in reversed(num.all_coeffs())],
                         [int(c) for c in reversed(den.all_coeffs())])
    assert f.den.leading_coefficient() == 1
    if not f.is_zero():
        fn = sympy.Poly([sympy.Rational(str(c)) for c in reversed(f.num.coeffs())], S)
        fd = sympy.Poly([sympy.Rational(str(c)) for c in reversed(f.den.coeffs())], S)
        assert sympy.gcd(fn, fd).degree() == 0
    # independent: f == p/q as elements of Q(s)
    assert sympy.cancel(f.to_sympy() - rf_sympy(p, q)) == 0


polys = st.lists(st.integers(-3, 3), min_size=1, max_size=4)
points = st.fractions(min_value=-5, max_value=5, max_denominator=7)


@given(polys, polys, polys, polys, points)
@PROP
def test_arithmetic_agrees_with_pointwise_fractions(p1, q1, p2, q2, t):
    assume(any(q1) and any(q2))
    d1, d2 = peval(q1, t), peval(q2, t)
    assume(d1 != 0 and d2 != 0)
    v1, v2 = peval(p1, t) / d1, peval(p2, t) / d2
    f, g = RationalFunction(p1, q1), RationalFunction(p2, q2)
    tq = fmpq(t.numerator, t.denominator)
    assert F((f + g)(tq)) == v1 + v2
    assert F((f - g)(tq)) == v1 - v2
    assert F((f * g)(tq)) == v1 * v2
    assert F((f ** 2)(tq)) == v1 ** 2
    assert F((-f)(tq)) == -v1
    assert F((f + 3)(tq)) == v1 + 3 and F((3 - f)(tq)) == 3 - v1 and F((2 * f)(tq)) == 2 * v1
    if v2 != 0:
        assert F((f / g)(tq)) == v1 / v2
        assert F((1 / g)(tq)) == 1 / v2
        assert F((g ** -1)(tq)) == 1 / v2
    # identities in Q(s) (exact equality of normalized representatives)
    assert (f + g) - g == f
    if not g.is_zero():
        assert (f * g) / g == f
    assert f ** 0 == 1


def test_arithmetic_by_hand():
    # 1/(s+1) + 1/(s-1) = 2 s/(s^2 - 1)
    assert 1 / (s + 1) + 1 / (s - 1) == RationalFunction([0, 2], [-1, 0, 1])
    # (s^2 - 1)/(s - 1) = s + 1
    assert (s**2 - 1) / (s - 1) == s + 1
    # ((s+1)/s)^2 = (s^2 + 2 s + 1)/s^2 ;  ((s+1)/s)^-2 = s^2/(s+1)^2
    assert ((s + 1) / s) ** 2 == RationalFunction([1, 2, 1], [0, 0, 1])
    assert ((s + 1) / s) ** -2 == RationalFunction([0, 0, 1], [1, 2, 1])
    assert s - s == 0 and (s - s).is_zero()
    assert s != s + 1 and s + 1 != 1
    assert RationalFunction(fmpq(3, 2)) == Fraction(3, 2) == RationalFunction("3/2")
    with pytest.raises(ZeroDivisionError):
        s / (s - s)
    with pytest.raises(ZeroDivisionError):
        RationalFunction(0) ** -1


def test_equality_is_on_normalized_forms_and_hash_agrees():
    a = RationalFunction([2, 2], [0, 4, 4])    # 2(s+1)/(4 s (s+1)) = 1/(2 s)
    b = RationalFunction(1, [0, 2])            # 1/(2 s)
    assert a == b and hash(a) == hash(b)
    assert len({a, b, 1 / (2 * s)}) == 1
    assert (a == "not a number") is False


def test_evaluation_at_rationals():
    f = (s**2 - s + 1) / (s**2 + 1)
    # f(1/2) = (1/4 - 1/2 + 1)/(1/4 + 1) = (3/4)/(5/4) = 3/5
    assert F(f(fmpq(1, 2))) == Fraction(3, 5)
    assert F(f("1/2")) == Fraction(3, 5) and F(f(Fraction(1, 2))) == Fraction(3, 5) and F(f(0.5)) == Fraction(3, 5)
    # f(-2) = (4 + 2 + 1)/5 = 7/5
    assert F(f(-2)) == Fraction(7, 5)
    with pytest.raises(ZeroDivisionError):
        (1 / (s - 1))(1)
    with pytest.raises(ZeroDivisionError):
        (1 / (s**2 - fmpq(1, 4)))("-1/2")


# ---------------------------------------------------------------------------------------------
# Laurent coefficients at s = oo (5.6)
# ---------------------------------------------------------------------------------------------

def test_laurent_two_carts_G_by_hand():
    # G(s) = (s^2+1)/(s^4+3s^2+1).  With t = 1/s^2: (1+t) t /(1 + 3t + t^2)
    # = t (1 + t)(1 - 3t + 8t^2 - 21 t^3 + ...) = t - 2 t^2 + 5 t^3 - 13 t^4 + ...
    # (1/(1+3t+t^2) = sum F_{2n+2}(-t)^n with Fibonacci F: 1, 3, 8, 21, 55)
    g = (s**2 + 1) / (s**4 + 3 * s**2 + 1)
    assert g.relative_degree() == 2
    assert fl(g.laurent(9)) == [1, 0, -2, 0, 5, 0, -13, 0, 34]
    assert fl(g.laurent(9)) == sympy_laurent((S**2 + 1) / (S**4 + 3 * S**2 + 1), 2, 9)


@pytest.mark.parametrize("num, den", [
    ([1, 1, 1], [1, 0, 1]),            # (s^2+s+1)/(s^2+1): u(s) of section 7, relative degree 0
    ([0, 1], [1, 0, 3, 0, 1]),         # s/(s^4+3s^2+1)
    ([2, 0, 0, 1], [1, 1]),            # (s^3+2)/(s+1): polynomial part, starts at s^2
    ([5], [0, 0, 0, 2]),               # 5/(2 s^3)
    ([1, -3, 0, 2], [-1, 4, 0, 0, 3]),
    (["1/2", 0, "-2/3"], ["3/4", 1, 0, 5]),
])
def test_laurent_against_sympy_series(num, den):
    f = RationalFunction(num, den)
    r = f.relative_degree()
    expr = rf_sympy(num, den)
    assert r == sympy.degree(sympy.denom(sympy.cancel(expr)), S) - sympy.degree(sympy.numer(sympy.cancel(expr)), S)
    assert fl(f.laurent(7)) == sympy_laurent(expr, r, 7)


def laurent_residual_ok(p, q, start: int, coeffs) -> bool:
    """Independent check that coeffs = [f_start, ..., f_{start+c-1}] are the Laurent coefficients
    at s = oo of N/d (N, d low-degree-first lists, d with nonzero top coefficient): since
    N = d * (L + tail) with L = sum_i f_i s^{-i} and tail = O(s^{-(start+c)}), N - d L has no term
    of degree > deg d - start - c.  Pure Fractions."""
    b, c = len(q) - 1, len(coeffs)
    res: dict[int, Fraction] = defaultdict(Fraction)
    for e, v in enumerate(p):
        res[e] += Fraction(v)
    for i, fi in enumerate(coeffs):
        for e, dq in enumerate(q):
            res[e - (start + i)] -= Fraction(dq) * fi
    return all(v == 0 for e, v in res.items() if e > b - start - c)


@given(st.lists(st.integers(-3, 3), min_size=1, max_size=5),
       st.lists(st.integers(-3, 3), min_size=1, max_size=5), st.integers(1, 8))
@PROP
def test_laurent_property_remainder(p, q, count):
    """laurent() on random (unnormalized) p/q: starts at r = deg q - deg p with f_r = lc(p)/lc(q),
    and passes the remainder identity above."""
    while p and p[-1] == 0:
        p = p[:-1]
    while q and q[-1] == 0:
        q = q[:-1]
    assume(p and q)
    f = RationalFunction(p, q)
    r = (len(q) - 1) - (len(p) - 1)
    assert f.relative_degree() == r
    coeffs = fl(f.laurent(count))
    assert len(coeffs) == count
    assert coeffs[0] == Fraction(p[-1], q[-1]) != 0
    assert laurent_residual_ok(p, q, r, coeffs)
    # a wrong coefficient is detected by the same check (the check is not vacuous)
    bad = list(coeffs)
    bad[-1] += 1
    assert not laurent_residual_ok(p, q, r, bad)
    # the sign for all large s is the sign of the first coefficient (Lemma 5.1)
    assert f.sign_at_infinity() == (1 if coeffs[0] > 0 else -1)


def test_laurent_of_zero_and_constants():
    assert fl(RationalFunction(0).laurent(3)) == [0, 0, 0]
    assert RationalFunction(0).relative_degree() == float("inf")
    assert fl(RationalFunction(4).laurent(3)) == [4, 0, 0]


def test_laurent_coefficients_row_vector_numerators_equal_componentwise():
    # N(s) = [s^2 + 1, s, 1] (row vector numerator) over d = s^4 + 3 s^2 + 1: the two carts' R(s)
    # columns 3, 2, 4 (7.1).  Numerator coefficients as 1 x 3 rows, low degree first.
    N0 = fmpq_mat([[1, 0, 1]])
    N1 = fmpq_mat([[0, 1, 0]])
    N2 = fmpq_mat([[1, 0, 0]])
    d = [1, 0, 3, 0, 1]
    vecs = laurent_coefficients([N0, N1, N2], d, 8)
    assert all(isinstance(v, fmpq_mat) and (v.nrows(), v.ncols()) == (1, 3) for v in vecs)
    # the expansion starts at s^-(4-2) = s^-2 for every component
    for j, expr in enumerate([(S**2 + 1), S, sympy.Integer(1)]):
        expected = sympy_laurent(expr / (S**4 + 3 * S**2 + 1), 2, 8)
        scalar = laurent_coefficients([N0[0, j], N1[0, j], N2[0, j]], d, 8)
        assert [F(v[0, j]) for v in vecs] == fl(scalar) == expected
    # by hand: 1/(s^4+3s^2+1) = s^-4 - 3 s^-6 + ..., i.e. from s^-2: [0, 0, 1, 0, -3, 0, 8, 0]
    assert [F(v[0, 2]) for v in vecs] == [0, 0, 1, 0, -3, 0, 8, 0]


@given(st.integers(1, 3), st.integers(0, 3),
       st.lists(st.lists(st.integers(-3, 3), min_size=3, max_size=3), min_size=4, max_size=4),
       st.lists(st.integers(-3, 3), min_size=1, max_size=4), st.integers(1, 5))
@PROP
def test_laurent_coefficients_vector_equals_scalar(m, deg, table, den_low, lead):
    """Row-vector numerators expand componentwise (with a non-monic denominator)."""
    num = [fmpq_mat(1, m, table[p][:m]) for p in range(deg + 1)]
    den = list(den_low) + [lead]
    vecs = laurent_coefficients(num, den, 6)
    for j in range(m):
        scalar = laurent_coefficients([fmpq(table[p][j]) for p in range(deg + 1)], [fmpq(c) for c in den], 6)
        assert [F(v[0, j]) for v in vecs] == fl(scalar)
        # independent check of the scalar expansion (remainder identity, in Fractions)
        comp = [table[p][j] for p in range(deg + 1)]
        assert laurent_residual_ok(comp, den, len(den) - 1 - deg, fl(scalar))


# ---------------------------------------------------------------------------------------------
# structure: relative degree, polynomial part, sign at infinity, str
# ---------------------------------------------------------------------------------------------

def test_relative_degree():
    assert (1 / s**2).relative_degree() == 2
    assert (s**3 / (s + 1)).relative_degree() == -2
    assert ((s**2 - 1) / (s - 1)).relative_degree() == -1  # = s + 1 after cancellation
    assert ((s**2 + s + 1) / (s**2 + 1)).relative_degree() == 0
    assert (1 / (s**2 + 1)).is_strictly_proper() and not ((s + 1) / (s + 2)).is_strictly_proper()
    assert ((s + 1) / (s + 2)).is_proper() and not (s**2 / (s + 2)).is_proper()


def test_polynomial_part():
    # s^3 + 2 = (s + 1)(s^2 - s + 1) + 1
    pp = ((s**3 + 2) / (s + 1)).polynomial_part()
    assert isinstance(pp, fmpq_poly) and fl(pp.coeffs()) == [1, -1, 1]
    # (s^2 + s + 1)/(s^2 + 1) = 1 + s/(s^2+1): the impulse of section 7 is delta (coefficient 1)
    assert fl(((s**2 + s + 1) / (s**2 + 1)).polynomial_part().coeffs()) == [1]
    assert ((s + 1) / (s**2 + 1)).polynomial_part().is_zero()
    assert RationalFunction(0).polynomial_part().is_zero()
    # (2 s^4 + 1)/(2 s^2 - 2) = (s^4 + 1/2)/(s^2 - 1) = s^2 + 1 + (3/2)/(s^2 - 1)
    assert fl(((2 * s**4 + 1) / (2 * s**2 - 2)).polynomial_part().coeffs()) == [1, 0, 1]


def test_sign_at_infinity():
    assert ((100 - s) / (s**2 + 1)).sign_at_infinity() == -1   # positive at 0, negative for s > 100
    assert ((s - 100) / (s**2 + 1)).sign_at_infinity() == 1
    assert ((-s**2 + 1) / (-(s**3) - 5)).sign_at_infinity() == 1   # -s^2 / -s^3 -> +
    assert (-1 / (s + 1)).sign_at_infinity() == -1
    assert RationalFunction(0).sign_at_infinity() == 0
    assert RationalFunction(-3).sign_at_infinity() == -1


@pytest.mark.parametrize("f, text", [
    ((s**2 - s + 1) / (s**2 + 1), "(s^2 - s + 1)/(s^2 + 1)"),
    ((s**2 + s + 1) / (s**2 + 1), "(s^2 + s + 1)/(s^2 + 1)"),
    (-s / (s**2 + 1), "-s/(s^2 + 1)"),
    (1 / s, "1/s"),
    (1 / s**2, "1/s^2"),
    (s / (s**4 + 3 * s**2 + 1), "s/(s^4 + 3*s^2 + 1)"),
    (RationalFunction(-1), "-1"),
    (RationalFunction(0), "0"),
    (2 * s**2 / 3 - 1, "2/3*s^2 - 1"),
    (s - 1, "s - 1"),
])
def test_str_formatting(f, text):
    assert str(f) == text
    assert repr(f) == f"RationalFunction('{text}')"


def test_to_sympy_roundtrip():
    f = (s**2 - s + 1) / (s**2 + 1)
    assert sympy.cancel(f.to_sympy() - (S**2 - S + 1) / (S**2 + 1)) == 0


# ---------------------------------------------------------------------------------------------
# sign_of_form / lex_sign (5.7)
# ---------------------------------------------------------------------------------------------

class Exploding:
    """A point that must never be consulted."""

    def sign_of_form(self, form):
        raise AssertionError("sign_of_form of the point was consulted for a zero form")


class FakePoint:
    """A non-rational point that decides signs itself and records the forms it was asked about."""

    def __init__(self, value: list[Fraction]):
        self.value = value
        self.asked: list[list[Fraction]] = []

    def sign_of_form(self, form):
        row = [F(form[0, j]) for j in range(form.ncols())]
        self.asked.append(row)
        v = sum(a * b for a, b in zip(row, self.value))
        return (v > 0) - (v < 0)


class Undecidable:
    def sign_of_form(self, form):
        raise UnresolvedSign("cannot decide")


def test_sign_of_scalar_forms():
    assert sign_of_form(fmpq(-3, 7)) == -1
    assert sign_of_form(fmpq(0)) == 0
    assert sign_of_form(fmpq(1, 10**30)) == 1


def test_sign_of_form_at_rational_point():
    form = fmpq_mat([[1, -2, 0]])
    x = lambda *v: fmpq_mat(3, 1, list(v))  # noqa: E731
    assert sign_of_form(form, x(1, 1, 5)) == -1   # 1 - 2 = -1
    assert sign_of_form(form, x(2, 1, -9)) == 0   # 2 - 2 = 0
    assert sign_of_form(form, x(3, 1, 0)) == 1    # 3 - 2 = 1
    assert sign_of_form(form, x(fmpq(1, 3), fmpq(1, 6), 100)) == 0  # 1/3 - 1/3


def test_zero_form_is_zero_without_consulting_the_point():
    zero = fmpq_mat(1, 4)
    assert sign_of_form(zero, Exploding()) == 0
    assert sign_of_form(zero, Undecidable()) == 0
    assert sign_of_form(zero, fmpq_mat([[1], [2], [3], [4]])) == 0
    assert lex_sign([zero, zero, zero], Exploding()) == 0
    assert lex_sign([], Exploding()) == 0


def test_sign_of_form_delegates_to_non_rational_points():
    p = FakePoint([Fraction(1), Fraction(-1), Fraction(1, 2)])
    form = fmpq_mat([[1, 1, 0]])   # 1 - 1 = 0 at p
    assert sign_of_form(form, p) == 0 and p.asked == [[1, 1, 0]]
    assert sign_of_form(fmpq_mat([[0, 0, 4]]), p) == 1          # 4 * 1/2
    assert sign_of_form(fmpq_mat([[0, 1, 0]]), p) == -1
    with pytest.raises(UnresolvedSign):
        sign_of_form(fmpq_mat([[1, 0, 0]]), Undecidable())


def test_lex_sign_first_nonzero_term():
    x = fmpq_mat([[1], [2]])
    forms = [fmpq_mat([[0, 0]]), fmpq_mat([[2, -1]]), fmpq_mat([[-1, 0]]), fmpq_mat([[5, 5]])]
    # values at x: 0, 0, -1, 15 -> first nonzero is -1
    assert lex_sign(forms, x) == -1
    assert lex_sign(forms[:2], x) == 0
    assert lex_sign([forms[1], forms[3], forms[2]], x) == 1
    assert lex_sign([fmpq(0), fmpq(0), fmpq(-2), fmpq(1)]) == -1
    # delegation: zero forms are skipped without asking, the point decides the rest; lex_sign stops
    # at the first nonzero sign
    p = FakePoint([Fraction(1), Fraction(2)])
    assert lex_sign([fmpq_mat(1, 2), forms[1], forms[2], forms[3]], p) == -1
    assert p.asked == [[2, -1], [-1, 0]]


# ---------------------------------------------------------------------------------------------
# RationalMatrix: det / solve against SymPy
# ---------------------------------------------------------------------------------------------

def _sym(m: RationalMatrix):
    return sympy.Matrix([[e.to_sympy() for e in r] for r in m.rows])


def test_det_and_solve_2x2_by_hand():
    G = RationalMatrix([[1 / s, 1], [1, s]])
    # det = 1/s * s - 1 = 0: singular over Q(s)
    assert G.det() == 0
    with pytest.raises(ZeroDivisionError):
        G.solve(RationalMatrix([[1], [1]]))
    H = RationalMatrix([[s, 1], [1, s]])
    # det = s^2 - 1;  H^{-1} (1, 0)^T = (s, -1)/(s^2 - 1)
    assert H.det() == s**2 - 1
    x = H.solve(RationalMatrix([[1], [0]]))
    assert x[0, 0] == s / (s**2 - 1) and x[1, 0] == -1 / (s**2 - 1)


@pytest.mark.parametrize("rows", [
    [[s + 1, 1 / s, 2], [s**2, 1, 1 / (s + 1)], [0, s, 3]],
    [[(s**2 + 1) / (s**4 + 3 * s**2 + 1), s**2 / (s**4 + 3 * s**2 + 1)],
     [s**2 / (s**4 + 3 * s**2 + 1), (2 * s**2 + 1) / (s**4 + 3 * s**2 + 1)]],   # G(s) of section 8
    [[0, 1, s], [1, 0, 1], [s, 1, 0]],     # zero pivot in the first column
    [[RationalFunction(fmpq(1, 2))]],
])
def test_det_and_solve_vs_sympy(rows):
    M = RationalMatrix(rows)
    n = M.shape[0]
    # SymPy's copy of the same entries (built from their coefficients), then SymPy's det / LUsolve
    Ms = sympy.Matrix([[rf_sympy(list(e.num.coeffs()), list(e.den.coeffs())) for e in r] for r in M.rows])
    det_ref = sympy.cancel(Ms.det())
    assert det_ref != 0
    assert sympy.cancel(M.det().to_sympy() - det_ref) == 0
    rhs = RationalMatrix([[s**j + i for j in range(2)] for i in range(n)])
    X = M.solve(rhs)
    X_ref = Ms.LUsolve(_sym(rhs))
    assert X.shape == (n, 2)
    for i in range(n):
        for j in range(2):
            assert sympy.cancel(X[i, j].to_sympy() - X_ref[i, j]) == 0
    assert M * X == rhs


def test_singular_3x3_over_Qs():
    # row 2 = s * row 0 + row 1: singular over Q(s), though no entry is zero
    r0 = [1 / s, s + 1, RationalFunction(2)]
    r1 = [s, 1 / (s + 1), 3 * s]
    r2 = [s * a + b for a, b in zip(r0, r1)]
    M = RationalMatrix([r0, r1, r2])
    assert sympy.cancel(_sym(M).det()) == 0
    assert M.det() == 0 and M.det().is_zero()
    with pytest.raises(ZeroDivisionError):
        M.solve(RationalMatrix([[1], [0], [0]]))


def test_rational_matrix_shapes():
    with pytest.raises(ShapeError):
        RationalMatrix([[1, 2]]).det()
    with pytest.raises(ShapeError):
        RationalMatrix([[1, 2]]) * RationalMatrix([[1, 2]])
    assert RationalMatrix([]).det() == 1


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 5), st.lists(st.fractions(min_value=-9, max_value=9, max_denominator=5).filter(lambda q: abs(q) < 9),
                                   min_size=0, max_size=14),
       st.lists(st.integers(-4, 4), min_size=25, max_size=25))
def test_poly_at_matrix_is_horners_rule(n, coeffs, entries):
    """Paterson-Stockmeyer p(S) equals p(S) by Horner's rule in exact arithmetic, for every degree
    (0 to 13: blocks of every length, a last block shorter than the others)."""
    S = fmpq_mat(n, n, entries[:n * n])
    p = fmpq_poly([fmpq(c.numerator, c.denominator) for c in coeffs])
    want = fmpq_mat(n, n)
    for c in reversed(p.coeffs()):
        want = want * S + fmpq_mat(n, n, [c if i == j else 0 for i in range(n) for j in range(n)])
    assert poly_at_matrix(p, S) == want


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 6), st.lists(st.integers(-3, 3), min_size=36, max_size=36),
       st.lists(st.integers(-2, 2), min_size=12, max_size=12))
def test_scalar_transfer_function_from_markov_parameters(n, entries, vecs):
    """row (sI - A)^{-1} col from the Markov parameters (the O(n^3) path) equals the row of the
    adjugate's resolvent (sI - A)^{-1} (Faddeev-LeVerrier) applied to col, in Q(s)."""
    A = fmpq_mat(n, n, [fmpq(e, 2) for e in entries[:n * n]])
    row, col = fmpq_mat(1, n, vecs[:n]), fmpq_mat(n, 1, vecs[6:6 + n])
    full = resolvent(A, row)  # 1 x n, adjugate path
    want = RationalFunction(0)
    for j in range(n):
        want = want + full[0, j] * RationalFunction(col[j, 0])
    assert resolvent(A, row, col)[0, 0] == want


# ---------------------------------------------------------------------------------------------
# submatrix: entry by entry or by 0/1 selection products (both against the definition)
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("shape", [(3, 4), (16, 32), (40, 70)])
def test_submatrix_is_the_entries_it_names(shape):
    """m[rows, cols] read from a list of lists (the definition), for small parts (entry by entry)
    and large ones (selection products), rows out of order and repeated, with big entries."""
    import random
    from lcs_exact.algebra import selection_matrix, submatrix
    rng = random.Random(7)
    r, c = shape
    table = [[Fraction(rng.randint(-9, 9) * 10 ** rng.choice([0, 30]), rng.randint(1, 5)) for _ in range(c)]
             for _ in range(r)]
    m = fmpq_mat(r, c, [fmpq(x.numerator, x.denominator) for row in table for x in row])
    for rows in (None, [0], list(range(r - 1, -1, -2)), [r - 1, 0, r - 1]):
        for cols in (None, [c - 1], sorted(rng.sample(range(c), c // 2 + 1))):
            rs = range(r) if rows is None else rows
            cs = range(c) if cols is None else cols
            got = submatrix(m, rows, cols)
            assert (got.nrows(), got.ncols()) == (len(rs), len(cs))
            assert [[Fraction(int(e.p), int(e.q)) for e in row] for row in got.tolist()] == \
                [[table[i][j] for j in cs] for i in rs]
    assert selection_matrix((2, 0), 3).tolist() == [[0, 0, 1], [1, 0, 0]]
    with pytest.raises(IndexError):
        selection_matrix((0, 3), 3)
    with pytest.raises(IndexError):
        submatrix(m, [r], None)


def test_norm_inf_is_the_largest_absolute_row_sum():
    """||m||_inf = max_i sum_j |m_ij|, against the definition on Fractions (zeros, signs, big
    entries, empty shapes)."""
    from lcs_exact.algebra import norm_inf
    rows = [[Fraction(-7, 2), 0, Fraction(1, 3)], [1, -1, 10 ** 40], [0, 0, 0]]
    m = fmpq_mat(3, 3, [fmpq(Fraction(x).numerator, Fraction(x).denominator) for r in rows for x in r])
    assert norm_inf(m) == fmpq(2 + 10 ** 40)  # row 1: 1 + 1 + 10^40
    assert norm_inf(fmpq_mat(1, 3, [fmpq(-7, 2), 0, fmpq(1, 3)])) == fmpq(23, 6)
    assert norm_inf(fmpq_mat(0, 0, [])) == 0 and norm_inf(fmpq_mat(2, 0, [])) == 0


def test_submatrix_and_selection_matrix_return_fresh_matrices():
    """The selection matrices are kept per index set: what the caller gets is its own copy (a
    change to it changes neither the kept matrix nor m)."""
    from lcs_exact.algebra import selection_matrix, submatrix
    m = fmpq_mat(10, 10, list(range(100)))
    whole = submatrix(m)
    whole[0, 0] = 99
    assert m[0, 0] == 0 and whole == fmpq_mat(10, 10, [99] + list(range(1, 100)))
    s = selection_matrix([1, 0], 3)
    s[0, 0] = 5
    assert selection_matrix([1, 0], 3).tolist() == [[0, 1, 0], [1, 0, 0]]
    assert submatrix(m, list(range(9, -1, -1)), None) == fmpq_mat(10, 10, [10 * (9 - i) + j for i in range(10) for j in range(10)])


@pytest.mark.parametrize("widths", [(3, 2), (40, 1, 0, 30), (70,), (0, 5), (1, 1, 1)])
def test_vstack_and_hstack_are_the_blocks_they_join(widths):
    """[m1; m2; ...] and [m1 m2 ...] read from lists of lists (the definition): small results
    (entry by entry) and large ones (placement products), empty blocks, big entries; the result
    is a fresh matrix (a change to it changes no block)."""
    import random
    from lcs_exact.algebra import hstack, vstack
    rng = random.Random(len(widths))
    c = 9

    def block(r, cols):
        table = [[Fraction(rng.randint(-9, 9) * 10 ** rng.choice([0, 40]), rng.randint(1, 7)) for _ in range(cols)]
                 for _ in range(r)]
        return table, fmpq_mat(r, cols, [fmpq(x.numerator, x.denominator) for row in table for x in row])

    def rows_of(m):
        return [[Fraction(int(e.p), int(e.q)) for e in row] for row in m.tolist()]

    blocks = [block(w, c) for w in widths]
    got = vstack(*[m for _, m in blocks], ncols=c)
    assert (got.nrows(), got.ncols()) == (sum(widths), c)
    assert rows_of(got) == [row for table, _ in blocks for row in table]
    blocks = [block(c, w) for w in widths]
    got = hstack(*[m for _, m in blocks], nrows=c)
    assert (got.nrows(), got.ncols()) == (c, sum(widths))
    assert rows_of(got) == [[x for table, _ in blocks for x in table[i]] for i in range(c)]
    before = [fmpq_mat(m) for _, m in blocks]
    for i in range(got.nrows()):
        for j in range(got.ncols()):
            got[i, j] = 12345
    assert all(m == b for (_, m), b in zip(blocks, before))
    single = vstack(blocks[0][1])
    if single.nrows() and single.ncols():
        single[0, 0] = 12345
        assert blocks[0][1] == before[0]
    with pytest.raises(ShapeError):
        vstack(fmpq_mat(1, 2), fmpq_mat(1, 3))
    with pytest.raises(ShapeError):
        hstack(fmpq_mat(2, 1), fmpq_mat(3, 1))

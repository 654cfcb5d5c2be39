"""Hostile input to the Python API (issue 8, item 5; the limits of docs/limits.md).

Every user error is a named LCSError subclass, also the matching builtin, whose message names the
argument; inputs that are cheap to write but unbounded to honour (``"1e999999999"``, t_end = 1e18,
k = 40 enumerations, markov(10**9)) are refused at once by a documented limit.  The expected values
of the accepted inputs are derived here independently (Fractions, closed forms).  Fuzzing (hypothesis,
bounded and derandomized): the LCS constructor, to_fmpq and simulate's options never raise anything
but an LCSError.  The last tests reproduce defects this suite found in the engine, now fixed (a dict
read by its keys, unchecked digits, a mode faster than A escaping the horizon limit, a single stiff
exponential searched in 10^6 steps, a closed form lost under a huge horizon).
"""
from __future__ import annotations

import itertools
import math
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from flint import arb, fmpq, fmpq_mat
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from helpers import F, carts, vec
from reference.linalg import det

import lcs_exact
from lcs_exact import (LCS, InvalidArgument, LCSError, LimitExceeded, NotRational, ShapeError, Unsupported,
                       expm_action, simulate)
from lcs_exact.algebra.lcp import all_solutions, is_p_matrix, p_matrix_violation
from lcs_exact.algebra.rational import (MAX_DIMENSION, MAX_ENUMERATION_K, MAX_HORIZON_FAST, MAX_HORIZON_SLOW,
                                MAX_KAPPA, MAX_MARKOV_INDEX, MAX_P_TEST_K, MAX_RATIONAL_BITS, to_fmpq,
                                to_matrix, to_vector)

SETTINGS = dict(derandomize=True, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                       HealthCheck.data_too_large])

X0 = [0, 1, -1, 0]
#: the builtin each error class is also (errors.py)
BUILTIN = {ShapeError: ValueError, NotRational: TypeError, InvalidArgument: ValueError,
           Unsupported: NotImplementedError}


def short_id(v) -> str:
    """A test id for any parameter (huge integers have no repr in Python 3.11)."""
    try:
        r = repr(v)
    except ValueError:
        r = f"int{v.bit_length()}bits" if isinstance(v, int) else type(v).__name__
    return r[:40]


def raises(cls, fn, *names):
    """fn() raises exactly ``cls`` (an LCSError and its builtin) whose message names ``names``."""
    with pytest.raises(cls) as ei:
        fn()
    e = ei.value
    assert type(e) is cls and isinstance(e, LCSError) and isinstance(e, BUILTIN[cls]), repr(e)
    msg = str(e)
    for nm in names:
        assert nm in msg, f"{nm!r} not in {msg!r}"
    assert len(msg) < 600  # a hostile input does not flood the message
    return msg


# ---------------------------------------------------------------------------------------------
# simulate: options, x0, t_end
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kw, cls, names", [
    (dict(t_end=-1), InvalidArgument, ["t_end", ">= 0"]),
    (dict(t_end="-1/3"), InvalidArgument, ["t_end", "-1/3"]),
    (dict(t_end="abc"), NotRational, ["t_end", "'abc'"]),
    (dict(t_end=None), NotRational, ["t_end"]),
    (dict(t_end=float("nan")), NotRational, ["t_end", "nan"]),
    (dict(t_end=float("inf")), NotRational, ["t_end", "inf"]),
    (dict(t_end=True), NotRational, ["t_end", "bool"]),
    (dict(t_end=[1]), NotRational, ["t_end"]),
    (dict(t_end=sp.Float(1.5)), NotRational, ["t_end"]),
    (dict(t_end="1e999999999"), InvalidArgument, ["t_end", "MAX_RATIONAL_BITS"]),
    (dict(digits=0), InvalidArgument, ["digits", "1..10000"]),
    (dict(digits=-3), InvalidArgument, ["digits"]),
    (dict(digits=10**7), InvalidArgument, ["digits", "10000"]),
    (dict(digits="30"), InvalidArgument, ["digits", "'30'"]),
    (dict(digits=30.0), InvalidArgument, ["digits"]),
    (dict(digits=True), InvalidArgument, ["digits"]),
    (dict(digits=np.int64(30)), InvalidArgument, ["digits", "int("]),
    (dict(digits=None), InvalidArgument, ["digits"]),
    (dict(max_events=-1), InvalidArgument, ["max_events"]),
    (dict(max_events=2.5), InvalidArgument, ["max_events"]),
    (dict(max_events=True), InvalidArgument, ["max_events"]),
    (dict(max_events="10"), InvalidArgument, ["max_events"]),
    (dict(time_limit=-1), InvalidArgument, ["time_limit"]),
    (dict(time_limit=float("nan")), InvalidArgument, ["time_limit"]),
    (dict(time_limit="5"), InvalidArgument, ["time_limit"]),
    (dict(time_limit=True), InvalidArgument, ["time_limit"]),
    (dict(closed_forms=[]), InvalidArgument, ["closed_forms"]),
    (dict(closed_forms="maybe"), InvalidArgument, ["closed_forms"]),
    (dict(closed_forms=1), InvalidArgument, ["closed_forms"]),
    (dict(max_prec=10**9), InvalidArgument, ["max_prec", "1048576"]),
    (dict(max_prec=32), InvalidArgument, ["max_prec"]),
    (dict(max_prec=True), InvalidArgument, ["max_prec"]),
    (dict(max_prec="4096"), InvalidArgument, ["max_prec"]),
    (dict(zeno="go"), InvalidArgument, ["zeno", "'go'"]),   # a ShapeError before issue 29: an option value
    (dict(zeno=None), InvalidArgument, ["zeno"]),
    (dict(branches="every"), InvalidArgument, ["branches", "'every'"]),
    (dict(branches=["all"]), InvalidArgument, ["branches"]),
    (dict(progress="yes"), InvalidArgument, ["progress"]),
    (dict(x0=None), ShapeError, ["x0"]),
    (dict(x0="0,1,-1,0"), ShapeError, ["x0", "str"]),
    (dict(x0=b"0110"), ShapeError, ["x0"]),
    (dict(x0=5), ShapeError, ["x0", "int"]),
    (dict(x0=[0, 1]), ShapeError, ["x0 has length 2, expected 4"]),
    (dict(x0=[0, 1, -1, 0, 0]), ShapeError, ["x0 has length 5, expected 4"]),
    (dict(x0=[[0, 1], [-1, 0]]), ShapeError, ["x0", "row of length 2"]),
    (dict(x0=[[[0]], [1], [-1], [0]]), ShapeError, ["x0[0]", "nested too deep"]),
    (dict(x0={0: 0, 1: 1, 2: -1, 3: 0}), ShapeError, ["x0", "dict"]),
    (dict(x0={0, 1, -1, 5}), ShapeError, ["x0", "set"]),
    (dict(x0=[0, float("nan"), -1, 0]), NotRational, ["x0[1]", "nan"]),
    (dict(x0=[0, 1, float("-inf"), 0]), NotRational, ["x0[2]", "inf"]),
    (dict(x0=[0, True, -1, 0]), NotRational, ["x0[1]", "bool"]),
    (dict(x0=[0, None, -1, 0]), NotRational, ["x0[1]", "None"]),
    (dict(x0=[0, "one", -1, 0]), NotRational, ["x0[1]", "'one'"]),
    (dict(x0=[0, 1j, -1, 0]), NotRational, ["x0[1]"]),
    (dict(x0=[0, 1, -1, "1e999999999"]), InvalidArgument, ["x0[3]", "MAX_RATIONAL_BITS"]),
    (dict(x0=[0, 1, -1, 2**70000]), InvalidArgument, ["x0[3]", "numerator"]),
    (dict(x0=np.array([0, 1, -1, "x"], dtype=object)), NotRational, ["x0[3]", "'x'"]),
    (dict(x0=np.array([0.0, 1.0, np.nan, 0.0])), NotRational, ["x0[2]"]),
    (dict(lcs="two carts"), InvalidArgument, ["lcs", "str"]),
    (dict(lcs=None), InvalidArgument, ["lcs", "NoneType"]),
], ids=short_id)
def test_simulate_rejects_with_a_named_error(kw, cls, names):
    args = dict(lcs=carts(), x0=X0, t_end=1)
    args.update(kw)
    raises(cls, lambda: simulate(args.pop("lcs"), args.pop("x0"), args.pop("t_end"), **args), *names)


def test_simulate_accepts_the_documented_inputs_exactly():
    # x0 as a column, a numpy object array of strings, a generator, Fraction/Decimal/str entries;
    # t_end as a string, a Fraction, an exact real; time_limit inf; all give the run from
    # (0, 1, -1, 0): the impact at 0 maps it to P_{0} x0 = (0, 1, 0, 0) (section 7), no other event
    # before t = 1 (q_0 = 1 - cos t... stays >= 0: the first return needs t > 1)
    want = [0, 1, 0, 0]
    inputs = [lambda: [[0], [1], [-1], [0]], lambda: np.array(["0", "1", "-1", "0"], dtype=object),
              lambda: (v for v in X0), lambda: [Fraction(0), Decimal("1.0"), "-1", fmpq(0)],
              lambda: fmpq_mat([[0], [1], [-1], [0]])]
    for make in inputs:
        for t_end in ("1", Fraction(1), sp.Rational(1), 1.0):
            tr = simulate(carts(), make(), t_end, time_limit=float("inf"))
            assert len(tr.events) == 1 and [F(q) for q in tr.events[0].state_after.rational().entries()] == want
            assert tr.t_end.rational() == 1 and not tr.partial
    tr = simulate(carts(), X0, sp.pi / 4)   # an exact real horizon, pi/4 to 30 digits
    assert tr.t_end.decimal(30).startswith("0.785398163397448309615660845")


@pytest.mark.slow
def test_a_rate_of_1e200_stops_at_its_horizon_at_once():
    """x'' = 10^400 x (rates +-10^200), y = x >= 0 from (1, 0): x = cosh(10^200 t) never reaches
    0; the phase is searched up to 10^6 / 10^200 (MAX_HORIZON_SLOW: both rates have modulus
    10^200) and the run stops there with HorizonExceeded.  It used to search up to 2^-40 (an
    absolute slack on the horizon) and build a dyadic of e^-(10^188): a hang."""
    from lcs_exact import HorizonExceeded, Status
    big = LCS([[0, 1], [10**400, 0]], [[0], [1]], [[1, 0]], [[0]])
    with pytest.raises(HorizonExceeded, match="MAX_HORIZON_SLOW") as err:
        simulate(big, [1, 0], 1, time_limit=60)
    tr = err.value.trajectory
    end = tr.t_last.rational()
    assert tr.status is Status.HORIZON_LIMIT and fmpq(9, 10**195) < end <= fmpq(1, 10**194)
    assert tr.state(end)[0].ball(20) > 1  # cosh > 1 all the way


def test_horizon_limits_follow_the_spectrum_of_the_phases():
    """Issue 15: the horizon limit applies to the phases evaluated, not to t_end up front.  The
    carts from X0 keep having events: t_end = 10^18 with max_events = 50 runs its 50 events and
    stops with LimitExceeded (the event limit).  A stiff decay (eigenvalues -1 and -10^7) has no
    event: its phase is searched up to 10^12 / 10^7 = 10^5 (MAX_HORIZON_FAST) and the run stops
    there with HorizonExceeded, the trajectory computed up to t = 10^5."""
    from lcs_exact import HorizonExceeded, Status
    for T in (10**18, 1e18, 10**100):
        with pytest.raises(LimitExceeded) as err:
            simulate(carts(), X0, T, max_events=50)
        assert type(err.value) is LimitExceeded and len(err.value.trajectory.events) == 50
        assert err.value.trajectory.status is Status.EVENT_LIMIT
    lo, hi = carts().spectral_scales()
    assert abs(float(hi.mid()) - (math.sqrt(5) + 1) / 2) < 1e-15
    stiff = LCS([[-1, 0], [0, -10**7]], [[1], [0]], [[1, 1]], [[0]])
    assert 2 * 10**5 * 10**7 > MAX_HORIZON_FAST
    with pytest.raises(HorizonExceeded, match=r"t_end = 200000 .* until t = 100000 .*MAX_HORIZON_FAST") as err:
        simulate(stiff, [1, 1], 2 * 10**5)
    tr = err.value.trajectory
    assert tr.status is Status.HORIZON_LIMIT and tr.t_last.rational() == 10**5
    assert tr.state(10**5)[0].ball(20) < arb(10) ** -40000  # e^{-10^5}: decayed, exactly computed
    assert simulate(stiff, [1, 1], 10**5).certified   # 10^5 * 10^7 = 10^12: within the limit
    # the stiff RC-diode benchmark (eigenvalues ~ -2, -1e6, -3e6) over t_end = 5 runs
    rc = LCS([[-2, 1, 0], [1000, -3000, 1000], [0, 10**6, -2 * 10**6]], [[0], [1000], [0]], [[0, 1, 0]], [[0]])
    assert simulate(rc, [-1, 1, 1], 5).certified


def test_nilpotent_A_has_no_horizon_limit():
    # x'' = u, y = x >= 0 from x = 1, x' = -1: free flight x = 1 - t hits the stop at t = 1 exactly,
    # the impact zeroes x' (Moreau), then rest: one event, at 1, whatever the horizon
    integ = LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]])
    assert integ.spectral_scales() is None
    for T in (10**100, 10**1000):
        tr = simulate(integ, [1, -1], T)
        assert len(tr.events) == 1 and tr.events[0].time.ball(30).contains(1)
        assert tr.events[0].time.ball(30).rad() < 1e-29
        assert [F(q) for q in tr.state(T // 2).rational().entries()] == [0, 0]


# ---------------------------------------------------------------------------------------------
# to_fmpq: exact values, limits, no expansion of exponents
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("x, want", [
    ("3/4", Fraction(3, 4)), (" -3 / 6 ", Fraction(-1, 2)), ("-1.25e-3", Fraction(-1, 800)),
    (".5", Fraction(1, 2)), ("5.", Fraction(5)), ("+1.50E2", Fraction(150)),
    ("1e-400", Fraction(1, 10**400)),                    # exact: no underflow to 0
    ("0e999999999999999999999", Fraction(0)),            # zero, whatever the exponent
    ("1" + "0" * 5000 + "e-5000", Fraction(1)),          # trailing zeros cancel the exponent
    ("9" * 5000, Fraction(10**5000 - 1)),                # beyond Python's 4300-digit str->int limit
    (0.1, Fraction(1, 10)), (5e-324, Fraction(5, 10**324)), (1e308, Fraction(10**308)),
    (np.float32(0.5), Fraction(1, 2)), (np.longdouble("0.1"), Fraction(1, 10)), (np.int64(-7), Fraction(-7)),
    (Decimal("0.1"), Fraction(1, 10)), (Decimal("-1E+3"), Fraction(-1000)),
    (sp.Rational(-2, 6), Fraction(-1, 3)), (Fraction(2**65535, 3), Fraction(2**65535, 3)),
    (2**65535, Fraction(2**65535)),                      # 65,536 bits: exactly at the limit
    (fmpq(1, 2**70000), Fraction(1, 2**70000)),          # flint values are taken as they are
], ids=short_id)
def test_to_fmpq_exact_values(x, want):
    got = to_fmpq(x)
    assert isinstance(got, fmpq) and F(got) == want


@pytest.mark.parametrize("x, cls, names", [
    ("1e999999999", InvalidArgument, ["MAX_RATIONAL_BITS"]),
    ("1e-999999999", InvalidArgument, ["MAX_RATIONAL_BITS"]),
    ("1e" + "9" * 30, InvalidArgument, ["exponent"]),
    ("1e70000", InvalidArgument, ["MAX_RATIONAL_BITS"]),
    ("1/" + "1" * 200000, InvalidArgument, ["MAX_RATIONAL_BITS"]),
    (2**65536, InvalidArgument, ["numerator", "65537 bits"]),
    (Fraction(1, 2**65536), InvalidArgument, ["denominator"]),
    (-(10**20000), InvalidArgument, ["numerator"]),
    (sp.Integer(2) ** 70000, InvalidArgument, ["numerator"]),
    (Decimal("1e999999999"), InvalidArgument, ["MAX_RATIONAL_BITS"]),
    ("1_000", NotRational, ["'1_000'"]), ("1/0", NotRational, ["zero denominator"]),
    ("1.5/2", NotRational, []), ("", NotRational, []), (".", NotRational, []), ("e5", NotRational, []),
    ("nan", NotRational, []), ("inf", NotRational, []), ("0x10", NotRational, []), ("½", NotRational, []),
    (float("nan"), NotRational, ["nan"]), (np.float64("inf"), NotRational, ["inf"]),
    (Decimal("nan"), NotRational, []), (True, NotRational, ["bool"]), (np.bool_(False), NotRational, ["bool"]),
    (None, NotRational, ["NoneType"]), (1j, NotRational, ["complex"]), (np.complex128(1), NotRational, []),
    ([1], NotRational, ["list"]), (b"1", NotRational, ["bytes"]),
    (sp.pi, NotRational, ["SymPy"]), (sp.sqrt(2), NotRational, ["SymPy"]), (sp.Float(0.5), NotRational, ["Float"]),
], ids=short_id)
def test_to_fmpq_refuses_with_a_named_error(x, cls, names):
    raises(cls, lambda: to_fmpq(x, "the entry"), "the entry", *names)


def test_rational_limit_is_exact_at_the_boundary():
    # 2^65535 has 65,536 bits (accepted), 2^65536 has 65,537 (refused); the same for a denominator,
    # and for a decimal string whose reduced denominator is 2^65536 (5^65536 cancels nothing)
    assert MAX_RATIONAL_BITS == 65536
    assert F(to_fmpq(Fraction(1, 2**65535))) == Fraction(1, 2**65535)
    raises(InvalidArgument, lambda: to_fmpq(Fraction(1, 2**65536), "q"), "q", "denominator")
    s = "5e-65536"  # = 5 / 10^65536 = 1 / (2^65536 5^65535): denominator of 65536 + 152,170 bits
    raises(InvalidArgument, lambda: to_fmpq(s, "q"), "q")


# ---------------------------------------------------------------------------------------------
# LCS construction, modes, Markov parameters, LDCP, enumerations
# ---------------------------------------------------------------------------------------------

A2 = [[0, 1], [0, 0]]


@pytest.mark.parametrize("args, cls, names", [
    (([], [[1]], [[1]], [[0]]), ShapeError, ["A must be a nonempty square matrix"]),
    (([[]], [[1]], [[1]], [[0]]), ShapeError, ["A"]),
    (([[1, 2], [3]], [[1], [0]], [[1, 0]], [[0]]), ShapeError, ["A has rows of different lengths"]),
    (([[1, 2]], [[1]], [[1, 0]], [[0]]), ShapeError, ["A must be a nonempty square matrix, got shape 1x2"]),
    ((None, [[1]], [[1]], [[0]]), ShapeError, ["A must be a matrix", "NoneType"]),
    (("[[0]]", [[1]], [[1]], [[0]]), ShapeError, ["A must be a matrix", "str"]),
    ((5, [[1]], [[1]], [[0]]), ShapeError, ["A must be a matrix", "int"]),
    (({0: [0]}, [[1]], [[1]], [[0]]), ShapeError, ["A must be a matrix", "dict"]),
    (([{0}], [[1]], [[1]], [[0]]), ShapeError, ["A row 0 is a set"]),
    (([[[1]]], [[1]], [[1]], [[0]]), ShapeError, ["A[0, 0] is a list", "nested too deep"]),
    (([[0]], {"a": 1}, [[1]], [[0]]), ShapeError, ["B", "dict"]),
    (([[0]], [[1]], [[1]], {"D": 0}), ShapeError, ["D[0, 0]", "dict"]),
    (([[0]], [[1]], [[1]], None), NotRational, ["D[0, 0]", "None"]),
    (([[0]], [[1]], [[1]], "x"), NotRational, ["D[0, 0]", "'x'"]),
    ((A2, [[1], [0], [1]], [[1, 0]], [[0]]), ShapeError, ["B has shape 3x1, expected 2x?"]),
    (([[0]], [[]], [[1]], [[0]]), ShapeError, ["B has no columns"]),
    (([[0, "1e999999999"], [0, 0]], [[1], [0]], [[1, 0]], [[0]]), InvalidArgument, ["A[0, 1]", "MAX_RATIONAL_BITS"]),
    (([[0, 2**70000], [0, 0]], [[1], [0]], [[1, 0]], [[0]]), InvalidArgument, ["A[0, 1]"]),
    ((np.array([[1, "x"], [0, 0]], dtype=object), [[1], [0]], [[1, 0]], [[0]]), NotRational, ["A[0, 1]", "'x'"]),
    ((np.array([[1.0, np.nan], [0, 0]]), [[1], [0]], [[1, 0]], [[0]]), NotRational, ["A[0, 1]"]),
    ((A2, [[1], [0]], [[1, sp.pi]], [[0]]), NotRational, ["C[0, 1]", "SymPy"]),
    ((A2, [[1], [0]], [[1, 0]], [[True]]), NotRational, ["D[0, 0]", "bool"]),
    (([[0]], [[1] * (MAX_DIMENSION + 1)], [[1]] * 2, [[0]]), ShapeError, ["B row 0", "MAX_DIMENSION"]),
    (([[0]], [itertools.count()], [[1]], [[0]]), ShapeError, ["B row 0", "MAX_DIMENSION"]),  # endless row
    (([[0]], [[1]], [[1]], [[0]]), None, []),
], ids=short_id)
def test_lcs_constructor(args, cls, names):
    if cls is None:
        lcs = LCS(*args)
        assert (lcs.n, lcs.k) == (1, 1)
        return
    raises(cls, lambda: LCS(*args), *names)


def test_lcs_accepts_numpy_object_arrays_and_huge_exact_entries():
    lcs = LCS(np.array([[0, "1/2"], [Fraction(-1, 3), 0]], dtype=object), np.array([[0], [1]]),
              [[1, 0]], [[0]])
    assert [[F(v) for v in r] for r in (lcs.A.tolist())] == [[0, Fraction(1, 2)], [Fraction(-1, 3), 0]]
    big = LCS([[-(10**10000)]], [[1]], [[1]], [[0]])  # 33,220 bits: within the limit, exact
    assert F(big.A[0, 0]) == -(10**10000)


@pytest.mark.parametrize("I, cls, names", [
    ("10", ShapeError, ["'10'"]), ("a", ShapeError, ["'a'"]), (None, ShapeError, ["None"]),
    (5, ShapeError, ["5"]), ({0: 1}, ShapeError, []), ([0.5], InvalidArgument, ["0.5", "float"]),
    ([True], InvalidArgument, ["True", "bool"]), (["0"], InvalidArgument, ["'0'"]),
    ([1], ShapeError, ["mode {1}", "outside 0..0"]), ([-1], ShapeError, ["[-1]"]),
    (itertools.count(), ShapeError, ["at most k = 1", "more than 1024 items"]),
    ("x" * 10**6, ShapeError, ["'xxxxx"]),
])
def test_mode_index_sets(I, cls, names):
    raises(cls, lambda: carts().mode(I), *names)


def test_mode_accepts_integers_of_any_kind():
    c = carts()
    assert c.mode([np.int64(0)]) is c.mode({0}) is c.mode((0, 0)) is c.mode(frozenset([fmpq(0).p]))


@pytest.mark.parametrize("i", [-1, "a", 1.5, None, True, 10**9, MAX_MARKOV_INDEX + 1])
def test_markov_index(i):
    raises(InvalidArgument, lambda: carts().markov(i), "Markov parameter index i")


def test_markov_values():
    # H_i = C A^{i-1} B for the carts (C = e1, B = e3): A e3 = e1, A e1 = (0, 0, -2, 1), A of that
    # = (-2, 1, 0, 0): H_1..H_4 = 0, 1, 0, -2; and det(sI - A) = s^4 + 3 s^2 + 1 gives the
    # recurrence h_{j+4} = -3 h_{j+2} - h_j (Cayley-Hamilton), run here in integers up to the limit
    h = [0, 1, 0, -2]
    while len(h) < MAX_MARKOV_INDEX:
        h.append(-3 * h[-2] - h[-4])
    c = carts()
    assert [F(c.markov(i)[0, 0]) for i in range(1, 13)] == h[:12]
    assert F(c.markov(np.int64(4))[0, 0]) == -2
    assert F(c.markov(MAX_MARKOV_INDEX)[0, 0]) == h[MAX_MARKOV_INDEX - 1]  # the limit itself works


@pytest.mark.parametrize("kappa", [-4, "a", 1.5, True, 2.0, "4", 10**9, MAX_KAPPA + 1])
def test_ldcp_kappa(kappa):
    raises(InvalidArgument, lambda: carts().ldcp([0, -1, -1, 0], kappa), "kappa")


def test_ldcp_kappa_range_of_the_paper():
    # kappa >= -n + 1 (section 5.2); LDCP_kappa for kappa <= 0 decides nothing for the carts
    # (rho = 2): S^kappa is every mode; LDCP_4 selects {0} at (0, -1, -1, 0) (section 7)
    c = carts()
    assert c.ldcp([0, -1, -1, 0], -3).modes == {frozenset(), frozenset({0})}
    assert c.ldcp([0, -1, -1, 0], np.int64(4)).modes == {frozenset({0})}


def test_expm_action_names_v_not_x0():
    msg = raises(ShapeError, lambda: expm_action(carts().A, -1, [1, 2]), "v has length 2, expected 4")
    assert "x0" not in msg
    raises(ShapeError, lambda: expm_action([[1, 2]], 1, [1, 2]), "M must be square")


def test_trajectory_times_outside_the_range():
    tr = simulate(carts(), X0, 3)
    raises(InvalidArgument, lambda: tr.state(-1), "t = -1", "before the start")
    raises(InvalidArgument, lambda: tr.state(4), "t = 4", "after the last computed time 3")
    raises(InvalidArgument, lambda: tr.state("-1e-30"), "before the start")
    raises(InvalidArgument, lambda: tr.u(4), "after")
    raises(InvalidArgument, lambda: tr.y(-1), "before")
    raises(InvalidArgument, lambda: tr.sample([0, 5]), "t = 5")
    raises(NotRational, lambda: tr.state("abc"), "'abc'")
    raises(NotRational, lambda: tr.state(None), "None")
    raises(NotRational, lambda: tr.state(float("nan")), "nan")
    # the end points themselves are inside: x(0) = x0 after the jump, x(3) from the closed form
    assert [F(q) for q in tr.state(0).rational().entries()] == [0, 1, 0, 0]


def test_fixture_digits_limits():
    """An InvalidArgument, as everywhere digits is taken (a FormatError before issue 29: an
    argument, not a malformed file)."""
    tr = simulate(carts(), X0, 1)
    for d in (0, 10**7, "30", True):
        raises(InvalidArgument, lambda: tr.to_fixture(digits=d), "digits")


def test_enumeration_limits():
    k = MAX_ENUMERATION_K + 1
    # x' = 0 x + I u, y = x + I u: N = I (P-matrix), so "auto" takes LDCP and works at any k;
    # method="rcp" enumerates 2^k modes and is refused
    ident = [[int(i == j) for j in range(k)] for i in range(k)]
    big = LCS(ident, ident, ident, ident)
    x0 = [1] * k
    assert big.select_modes(x0) == {frozenset()}
    raises(Unsupported, lambda: big.select_modes(x0, method="rcp"), f"2^{k}", "MAX_ENUMERATION_K")
    raises(Unsupported, lambda: big.rcp(x0), f"k = {k}")
    raises(Unsupported, lambda: all_solutions([1] * k, ident), "all_solutions")
    raises(ShapeError, lambda: all_solutions([1], [[1, 2]]), "square")


@pytest.mark.slow
def test_p_matrix_test_limits():
    # a nonsymmetric matrix above MAX_P_TEST_K whose symmetric part is positive definite is P
    # (Theorem 3.5): diag 2, superdiagonal 1 has the symmetric part tridiag(1/2, 2, 1/2), whose
    # Gershgorin discs lie in [1, 3] ...
    k = MAX_P_TEST_K + 1
    m = [[Fraction(2) if i == j else Fraction(1) if j == i + 1 else Fraction(0) for j in range(k)] for i in range(k)]
    assert is_p_matrix(m)
    # ... one whose symmetric part is not (diag 1, superdiagonal 3: x = (1, -1, 0, ...) gives
    # x^T M x = 1 + 1 - 3 < 0) would need 2^k Schur complements: refused
    m = [[Fraction(1) if i == j else Fraction(3) if j == i + 1 else Fraction(0) for j in range(k)] for i in range(k)]
    raises(Unsupported, lambda: is_p_matrix(m), "nonsymmetric", f"k = {k}")
    # ... a symmetric one of any size is decided by its leading minors (Sylvester): the tridiagonal
    # (-1, 2, -1) of size 40 is positive definite (leading minors j + 1 > 0); with its last diagonal
    # entry 1/2 the full determinant is (40 + 1) - ... computed here: the violation is the whole set
    n = 40
    t = [[Fraction(2) if i == j else Fraction(-1) if abs(i - j) == 1 else Fraction(0) for j in range(n)] for i in range(n)]
    assert [det([r[:j] for r in t[:j]]) for j in (1, 2, 3, 10)] == [2, 3, 4, 11]
    assert is_p_matrix(t)
    t[n - 1][n - 1] = Fraction(1, 2)
    assert det([r[:n - 1] for r in t[:n - 1]]) == n and det(t) == Fraction(n + 1) - Fraction(3, 2) * n
    bad = p_matrix_violation(t)
    assert bad == tuple(range(n)) and det(t) <= 0
    # a mechanical system with 30 stops: N = E M^-1 E^T symmetric, well-posed (Theorem 8.2)
    from lcs_exact.models import mechanical
    m30 = mechanical([[int(i == j) for j in range(30)] for i in range(30)],
                     [[2 if i == j else -1 if abs(i - j) == 1 else 0 for j in range(30)] for i in range(30)],
                     [[int(i == j) for j in range(30)] for i in range(30)])
    assert m30.well_posedness().well_posed


def test_vectors_and_matrices_refuse_unordered_and_deep_input():
    raises(ShapeError, lambda: to_vector({0: 1, 1: 2}, 2, "q"), "q", "dict")
    raises(ShapeError, lambda: to_vector({1, 2}, 2, "q"), "q", "set")
    raises(ShapeError, lambda: to_vector([[1, 2]], 2, "q"), "q", "row of length 2")
    raises(ShapeError, lambda: to_vector([[[1]], [2]], 2, "q"), "q[0]", "nested")
    raises(ShapeError, lambda: to_matrix([[1, [2]]], "M"), "M[0, 1]", "nested")
    raises(ShapeError, lambda: to_matrix(itertools.repeat([0]), "M"), "M", "MAX_DIMENSION")
    assert vec(to_vector(np.array([[1], [2]]), 2)) == [1, 2] and vec(to_vector((v for v in "12"), 2)) == [1, 2]
    raises(ShapeError, lambda: carts().select_modes({0: 0, 1: -1, 2: -1, 3: 0}), "x0", "dict")


# ---------------------------------------------------------------------------------------------
# fuzzing (bounded, derandomized): only LCSError, never another exception, never a hang
# ---------------------------------------------------------------------------------------------

scalars = st.one_of(st.integers(-10**6, 10**6), st.floats(allow_nan=True, allow_infinity=True),
                    st.text(max_size=12), st.none(), st.booleans(), st.fractions(max_denominator=100),
                    st.sampled_from(["1/2", "-3", "1e-5", "1e999999999", "1/0", "0x1", " 7 ", "1e+3", "nan"]),
                    st.complex_numbers(max_magnitude=10), st.builds(pow, st.just(2), st.just(70000)))
nested = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                       st.dictionaries(st.text(max_size=3), inner, max_size=3),
                                                       st.tuples(inner, inner)), max_leaves=20)
# mostly well-shaped matrices of hostile entries, sometimes arbitrary structure
matrices = st.one_of(nested, st.integers(1, 3).flatmap(
    lambda n: st.lists(st.lists(scalars, min_size=n, max_size=n), min_size=1, max_size=3)))
BUILTINS = (ValueError, TypeError, NotImplementedError, ArithmeticError)


good = st.one_of(st.integers(-5, 5), st.fractions(min_value=-5, max_value=5, max_denominator=7),
                 st.sampled_from(["1/2", "-3", "0.25", "2e-3"]), st.floats(-5, 5, allow_nan=False).map(lambda v: round(v, 3)))


@st.composite
def shaped_systems(draw):
    """A, B, C, D of matching shapes (n, k in 1..3) with numeric entries, and half of the time
    one entry replaced by a hostile scalar: builds often, and refuses the one bad entry by name."""
    n, k = draw(st.integers(1, 3)), draw(st.integers(1, 3))
    mats = [[[draw(good) for _ in range(c)] for _ in range(r)] for r, c in ((n, n), (n, k), (k, n), (k, k))]
    if draw(st.booleans()):
        which = draw(st.integers(0, 3))
        m = mats[which]
        m[draw(st.integers(0, len(m) - 1))][draw(st.integers(0, len(m[0]) - 1))] = draw(scalars)
    return tuple(mats)


@pytest.mark.slow
@settings(max_examples=300, **SETTINGS)
@given(st.one_of(st.tuples(matrices, matrices, matrices, matrices), shaped_systems()))
def test_fuzz_lcs_constructor(abcd):
    A, B, C, D = abcd
    try:
        lcs = LCS(A, B, C, D)
    except LCSError as e:
        event(type(e).__name__)
        assert isinstance(e, BUILTINS) and str(e)
        return
    event("built")
    n, k = lcs.n, lcs.k
    assert (lcs.A.nrows(), lcs.A.ncols(), lcs.B.nrows(), lcs.B.ncols()) == (n, n, n, k)
    assert (lcs.C.nrows(), lcs.C.ncols(), lcs.D.nrows(), lcs.D.ncols()) == (k, n, k, k)
    # the entries are the exact values given (independent reading by Fraction of the same input)
    if isinstance(A, list) and all(isinstance(r, list) for r in A):
        for i, r in enumerate(A):
            for j, v in enumerate(r):
                want = Fraction(repr(v)) if isinstance(v, float) else Fraction(v)
                assert F(lcs.A[i, j]) == want
    # and the system's algebra runs on what was built (no crash beyond LCSError)
    try:
        lcs.well_posedness()
        lcs.markov(n)
    except LCSError as e:
        assert isinstance(e, BUILTINS)


number_text = st.from_regex(r"\A[-+]?(\d{1,30}(\.\d{0,20})?|\.\d{1,20})([eE][-+]?\d{1,7})?\Z")


@pytest.mark.slow
@settings(max_examples=300, **SETTINGS)
@given(st.one_of(number_text, nested))
def test_fuzz_to_fmpq(x):
    try:
        q = to_fmpq(x, "THE_ARG")
    except LCSError as e:
        event(type(e).__name__)
        assert isinstance(e, BUILTINS) and "THE_ARG" in str(e)
        return
    assert isinstance(q, fmpq)
    if isinstance(x, str):
        # an independent reading of the same decimal (Fraction), where it is affordable
        mant, _, ex = x.strip().lower().partition("e")
        if abs(int(ex or 0)) < 400:
            assert F(q) == Fraction(x.strip())
        assert max(int(q.p).bit_length(), int(q.q).bit_length()) <= MAX_RATIONAL_BITS


options = st.fixed_dictionaries({}, optional={
    "digits": st.one_of(st.integers(-3, 40), st.sampled_from([10_000, 10_001, 10**7]), scalars),
    "max_events": st.one_of(st.integers(-3, 50), scalars),
    "closed_forms": st.one_of(st.sampled_from(["lazy", True, False, "eager", "off"]), scalars),
    "max_prec": st.one_of(st.integers(0, 2**21), st.none(), scalars),
})


@pytest.mark.slow
@settings(max_examples=120, **SETTINGS)
@given(options, st.one_of(st.just(X0), nested, st.lists(scalars, min_size=4, max_size=4)),
       st.one_of(st.sampled_from([1, "1/2", 0, "3", 10**7, 10**18]), scalars))
def test_fuzz_simulate_options(opts, x0, t_end):
    # every run is bounded by a time budget (time_limit is the one option not fuzzed here)
    try:
        tr = simulate(carts(), x0, t_end, time_limit=2, **opts)
    except LimitExceeded as e:
        event("LimitExceeded")
        assert e.trajectory is not None and e.trajectory.partial
        return
    except LCSError as e:
        event(type(e).__name__)
        assert isinstance(e, BUILTINS) and str(e)
        return
    event("ran")
    assert tr.certified and not tr.partial


@settings(max_examples=60, **SETTINGS)
@given(st.one_of(st.floats(), st.integers(-5, 10**6), scalars))
def test_fuzz_time_limit(time_limit):
    try:
        tr = simulate(carts(), X0, 2, time_limit=time_limit)
    except LimitExceeded:
        return
    except LCSError as e:
        assert isinstance(e, BUILTINS) and "time_limit" in str(e)
        return
    assert len(tr.events) == 1


# ---------------------------------------------------------------------------------------------
# defects found by this suite in the engine, fixed (they were strict xfails until then)
# ---------------------------------------------------------------------------------------------

def test_allow_unresolved_must_be_a_bool():
    raises(InvalidArgument, lambda: simulate(carts(), X0, 1, allow_unresolved="no"), "allow_unresolved")


@pytest.mark.parametrize("v", [{0: 5, 1: 6}, [[[1]], [0]]])
def test_expm_action_refuses_a_dict_or_deep_nesting(v):
    raises(ShapeError, lambda: expm_action([[0, 1], [-1, 0]], 1, v), "v")


@pytest.mark.parametrize("call, pattern", [
    ("ts_str", r"^ts must be a sequence of rational times, got str$"),
    ("digits0", r"^digits must be an integer in 1\.\.10000, got 0$"),
    ("digits_neg", r"^digits must be an integer in 1\.\.10000, got -5$"),
    ("digits_str", r"^digits must be an integer, got 'a' \(str\)$"),
    ("ts_none", r"^ts must be a sequence of rational times, got NoneType$"),
])
def test_sample_arguments(call, pattern):
    tr = simulate(carts(), X0, 3)
    fn = {"ts_str": lambda: tr.sample("12"), "digits0": lambda: tr.sample([1], digits=0),
          "digits_neg": lambda: tr.sample([1], digits=-5), "digits_str": lambda: tr.sample([1], digits="a"),
          "ts_none": lambda: tr.sample(None)}[call]
    with pytest.raises(LCSError, match=pattern):
        fn()


@pytest.mark.parametrize("call", ["ball_neg", "ball_str", "ball_over", "decimal0"])
def test_real_digits_arguments(call):
    t = simulate(carts(), X0, 3).events[-1].time
    fn = {"ball_neg": lambda: t.ball(-1), "ball_str": lambda: t.ball("a"),
          "ball_over": lambda: t.ball(10_001), "decimal0": lambda: t.decimal(0)}[call]
    with pytest.raises(InvalidArgument):
        fn()


def test_horizon_of_a_mode_faster_than_A():
    # x' = u, y = x + u: A = 0 (no limit from A), but from x0 = -1 the run is in mode {0}:
    # u = -x, x' = -x, whose rate 1 bounds its phase at 10^6 (MAX_HORIZON_SLOW)
    from lcs_exact import HorizonExceeded
    lcs = LCS([[0]], [[1]], [[1]], [[1]])
    with pytest.raises(HorizonExceeded, match=r"t_end = 1e\+100 .* mode \{0\} .* until t = 1000000 .*MAX_HORIZON_SLOW"):
        simulate(lcs, [-1], 10**100, time_limit=30)  # a short t_end in the message, the limit reached


def test_an_exact_equilibrium_has_no_horizon_limit():
    """At a state z with A_I z = 0 (proven) the phase is x(t) = z: u = F_I z and y are constant,
    none negative (the mode was selected at z), so no event ever comes; the run finishes at any
    t_end with the state exactly z.  It used to stop with HorizonExceeded at 10^6 / (slowest rate)
    of A_I, although nothing is ever evaluated at a large t."""
    T = 10**18
    assert T * 1 > MAX_HORIZON_SLOW  # every system below has a rate of modulus 1
    # the oscillator x1' = x2, x2' = -x1 + u, y = x1 from (1, 0): x = (cos t, -sin t) until y = cos t
    # reaches 0 at pi/2 with x = (0, -1); the stop (y = x1: C B = 0, C A B = 1 > 0) resets the
    # velocity (P_I of mode {0} projects onto V_{0} = {x1 = x1' = 0} = {0}): x(pi/2+) = (0, 0), and
    # A 0 = 0: at rest from pi/2 on, mode {} (u = 0), y = 0
    osc = LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    tr = simulate(osc, [1, 0], T)
    assert tr.certified and not tr.partial and len(tr.events) == 1
    assert tr.events[0].time.closed_form == sp.pi / 2
    assert vec(tr.state(T).known_rational()) == [0, 0] and vec(tr.state(T - 1).known_rational()) == [0, 0]
    assert vec(tr.u(T).known_rational()) == [0] and vec(tr.y(T).known_rational()) == [0]
    assert [[b.is_exact() and b == 0 for b in row] for row in tr.sample([T, 10**17 + 1])] == [[True] * 2] * 2
    assert simulate(osc, [0, 0], T).state(T).known_rational() == fmpq_mat([[0], [0]])
    # a cart with friction, p' = v, v' = -v + u, stop y = p: A (p, 0) = 0, a line of equilibria
    # (eigenvalues 0 and -1); at p = 1 no event (y = 1 > 0, u = 0), at p = sqrt 2 neither (a
    # start that is not rational: A z = 0 is proven from the form v = 0 known on it)
    cart = LCS([[0, 1], [0, -1]], [[0], [1]], [[1, 0]], [[0]])
    tr = simulate(cart, [1, 0], T)
    assert not tr.events and vec(tr.state(T).known_rational()) == [1, 0] and vec(tr.y(T).known_rational()) == [1]
    tr = simulate(cart, [sp.sqrt(2), 0], T)
    assert not tr.events and tr.certified and not tr.partial
    x = tr.state(T)
    with lcs_exact.numbers.balls.workprec(256):
        assert abs(x[0].ball(40) - arb(2).sqrt()) < arb(10) ** -39 and x[1].sign() == 0
    # from (1/2, -1): v = -e^-t, p = e^-t - 1/2, which reaches 0 at log 2 with v = -1/2; the stop
    # resets v: (0, 0), an equilibrium again
    tr = simulate(cart, ["1/2", -1], T)
    assert len(tr.events) == 1 and tr.events[0].time.closed_form == sp.log(2)
    assert vec(tr.state(T).known_rational()) == [0, 0]
    # an equilibrium of a closed mode: carts q0, q1 (velocities v0, v1) joined by a spring,
    # cart 1 damped, a constant force -2 (the appended state c = 1) pushing cart 0 onto the stop
    # y = q0: v0' = (q1 - q0) - 2c + u, v1' = (q0 - q1) - v1.  At q = v = 0 the stop holds cart 0
    # with u = 2 (v0' = 0) and nothing moves: mode {0}, whose A_I has the damped oscillator of
    # cart 1 (rates of modulus 1)
    push = LCS([[0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [-1, 1, 0, 0, -2], [1, -1, 0, -1, 0], [0, 0, 0, 0, 0]],
               [[0], [0], [1], [0], [0]], [[1, 0, 0, 0, 0]], [[0]])
    tr = simulate(push, [0, 0, 0, 0, 1], T)
    assert not tr.events and tr.phases[0].mode == frozenset({0}) and not tr.partial
    assert vec(tr.state(T).known_rational()) == [0, 0, 0, 0, 1] and vec(tr.u(T).known_rational()) == [2]


def test_single_stiff_exponential_is_not_slow():
    tr = simulate(LCS([[-10**6]], [[1]], [[1]], [[0]]), [1], 1, time_limit=2)
    assert not tr.events and tr.state(1)[0].ball(20).contains(0) is False


def test_closed_form_of_a_time_under_a_huge_horizon():
    # x'' = u, y = x from (1, -1): x = 1 - t, the impact is at exactly t = 1 (found for t_end = 10^100)
    integ = LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]])
    assert simulate(integ, [1, -1], 10**100).events[0].time.rational() == 1
    assert simulate(integ, [1, -1], 10**300).events[0].time.rational() == 1


def test_exact_reals_and_float32_are_read_exactly():
    """Issue 15: the library's own exact reals are accepted in x0 (a component of traj.state(t)
    keeps its exact definition), and a numpy float32 is read by its own shortest repr."""
    import numpy as np
    c = carts()
    tr = simulate(c, [0, 1, -1, 0], 2)
    x = tr.state(2)
    again = simulate(c, list(x), 1)  # the same state, component by component
    direct = simulate(c, x, 1)
    assert len(again.events) == len(direct.events) == 1
    assert again.events[0].time.ball(30).overlaps(direct.events[0].time.ball(30))
    assert to_fmpq(np.float32(0.1)) == fmpq(1, 10) and to_fmpq(np.float16(0.25)) == fmpq(1, 4)
    assert to_fmpq(np.float32(1e-3)) == fmpq(1, 1000) and to_fmpq(np.float64(0.1)) == fmpq(1, 10)


@pytest.mark.slow
def test_queries_after_a_run_obey_its_time_limit():
    """Issue 15: the run's time_limit bounds every later query too (re-armed per query, checked
    between its steps): 10,000 digits of the four components of x(3) take far longer than
    0.05 s, so the query ends in LimitExceeded, not a hang;
    cheap queries still answer, and a run without time_limit has no limit on its queries."""
    from lcs_exact import LimitExceeded, expm_action
    c = carts()
    x0 = expm_action(c.A, -1, [0, -1, -1, 0])
    tr = simulate(c, x0, 3, time_limit=0.05)
    assert tr.events[1].time.decimal(20).startswith("2.5707963267948966192")  # cheap: answered
    with pytest.raises(LimitExceeded, match="time_limit = 0.05 s"):
        tr.state(3).ball(10000)  # four components of 10,000 digits: checked between them
    fresh = simulate(c, x0, 3, time_limit=0.05)  # (the first query cached its high-precision data)
    with pytest.raises(LimitExceeded, match="time_limit"):
        fresh.sample([fmpq(k, 3) for k in range(1, 9)], 10000)
    free = simulate(c, x0, 3)
    assert free.state(3)[1].decimal(3000).startswith("0.4162661001994821012792")

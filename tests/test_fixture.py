"""fixture.py: the format lcs-exact/trajectory/1 - samples against independent derivations, the
shipped JSON Schema, the certified number encoding and its decoding (DESIGN.md section 5)."""
from __future__ import annotations

import copy
import json
import sys
from fractions import Fraction
from importlib.resources import files

import jsonschema
import mpmath as mp
import pytest
import sympy as sp
from flint import arb, ctx, fmpq
from helpers import A_CARTS, carts, mpmath_digits
from hypothesis import given, settings
from hypothesis import strategies as st

import lcs_exact as L
from lcs_exact.phases.fixture import (ball_number, fixture_dict, number_ball, number_exact, number_rational,
                               rational_number, sample_grid, schema, validate_fixture)

_mp = mpmath_digits(60)
OSC = ([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])  # x'' = -x + u, 0 <= x ⊥ u >= 0


@pytest.fixture(scope="module")
def section7():
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    return L.simulate(carts(), x0, 3, digits=30)


@pytest.fixture(scope="module")
def section7_fixture(section7):
    return section7.to_fixture(30, sample="1/10")


def section7_state(t):
    """x(t) of section 7 derived independently (mpmath, 60 digits): e^{A(t-1)}(0,-1,-1,0) before
    the impact at 1; (0, -cos(t-1), 0, sin(t-1)) on the constrained phase [1, 1 + π/2]; then
    e^{A(t - 1 - π/2)}(0, 0, 0, 1)."""
    A = mp.matrix(A_CARTS)
    t = mp.mpf(t.numerator) / t.denominator if isinstance(t, Fraction) else mp.mpf(t)
    if t < 1:
        return list(mp.expm(A * (t - 1)) * mp.matrix([0, -1, -1, 0]))
    if t <= 1 + mp.pi / 2:
        return [mp.mpf(0), -mp.cos(t - 1), mp.mpf(0), mp.sin(t - 1)]
    return list(mp.expm(A * (t - 1 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1]))


def as_mpf(text: str):
    return mp.mpf(Fraction(text).numerator) / Fraction(text).denominator


def holds(num: dict, true, digits: int) -> bool:
    """|value - true| <= error, and error is at most one unit in the last place of a number with
    ``digits`` significant digits (absolute 10^-digits at 0): every shown digit is right."""
    v, e = as_mpf(num["value"]), as_mpf(num["error"])
    ulp = mp.mpf(10) ** (mp.floor(mp.log10(abs(true))) - digits + 1) if true else mp.mpf(10) ** -digits
    return abs(v - true) <= e and e <= ulp


# ---------------------------------------------------------------------------------------------
# the fixture of section 7
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_section7_fixture_validates_against_the_shipped_schema(section7_fixture):
    shipped = json.loads(files("lcs_exact").joinpath("schemas", "trajectory-1.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(shipped)
    jsonschema.validate(section7_fixture, shipped)  # the file itself, not our wrapper
    validate_fixture(section7_fixture)
    assert schema() == shipped
    assert json.loads(json.dumps(section7_fixture)) == section7_fixture  # plain JSON


def test_section7_samples_against_independent_derivation(section7_fixture):
    fx = section7_fixture
    assert fx["sample_step"] == "1/10" and len(fx["samples"]) == 31
    for k, s in enumerate(fx["samples"]):
        assert s["t"]["exact"] == str(Fraction(k, 10)) and number_rational(s["t"]) == Fraction(k, 10)
        want = section7_state(Fraction(k, 10))
        for i, c in enumerate(s["x"]):
            assert holds(c, want[i], 30), (k, i, c, want[i])
        if 10 < k < 25:  # on the constrained phase x1 = x3 = 0 exactly (and the fixture says so)
            assert [s["x"][i]["exact"] for i in (0, 2)] == ["0", "0"]


def test_section7_events_final_state_and_flags(section7_fixture):
    fx = section7_fixture
    e1, e2 = fx["events"]
    assert e1["time"] == {"value": "1", "error": "0", "exact": "1"}
    assert (e1["mode_before"], e1["modes"], e1["mode_after"], e1["multiplicity"]) == ([], [[0]], [0], 1)
    assert e1["triggers"] == ["y_0"]
    assert [c["exact"] for c in e1["state_after"]] == ["0", "-1", "0", "0"]
    assert e2["time"]["exact"] == "1 + pi/2" and holds(e2["time"], 1 + mp.pi / 2, 30)
    assert fx["final_time"]["exact"] == "3"
    for c, want in zip(fx["final_state"], section7_state(3)):
        assert holds(c, want, 30)
    x0 = section7_state(0)
    for c, want in zip(fx["x0"], x0):
        assert holds(c, want, 30) and c["exact"] is not None  # e^{-A}v in closed form
        assert abs(sp.N(sp.sympify(c["exact"]), 40) - sp.Float(str(want), 40)) < 1e-35
    assert fx["certified"] is True and fx["partial"] is False and fx["stop_reason"] is None
    assert fx["system"]["A"] == [[str(v) for v in row] for row in A_CARTS]


def test_default_digits_and_no_samples(section7):
    fx = section7.to_fixture()
    assert fx["digits"] == 30 and "samples" not in fx and "sample_step" not in fx
    validate_fixture(fx)


def test_partial_run_fixture():
    """A run stopped after one event: the fixture is partial; the phase after the event was
    computed up to the next event time 1 + pi/2 (where the limit stopped the run), so the final
    time is 1 + pi/2, the final state x((1 + pi/2)-) = (0, -cos(pi/2), 0, sin(pi/2)) = (0, 0, 0, 1)
    and the samples stop at 5/2 < 1 + pi/2."""
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(carts(), x0, 3, max_events=1)
    fx = fixture_dict(err.value.trajectory, 20, sample="1/4")
    validate_fixture(fx)
    assert fx["partial"] is True and "max_events" in fx["stop_reason"]
    assert fx["final_time"]["exact"] == "1 + pi/2" and [c["exact"] for c in fx["final_state"]] == ["0", "0", "0", "1"]
    assert [s["t"]["exact"] for s in fx["samples"]] == [str(Fraction(k, 4)) for k in range(11)]


def test_many_digits_past_pythons_int_string_limit():
    """4400 digits (Python refuses int <-> str beyond 4300 digits by default): π/2 to 4400 digits."""
    tr = L.simulate(L.LCS(*OSC), [1, 0], 2, digits=4400)
    fx = tr.to_fixture(sample=1)
    old = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(0)  # for the test's own parsing of the decimals
    with mp.workdps(4420):
        assert holds(fx["events"][0]["time"], mp.pi / 2, 4400)
        assert holds(fx["samples"][1]["x"][0], mp.cos(1), 4400)
    sys.set_int_max_str_digits(old)
    validate_fixture(fx)
    assert number_ball(fx["events"][0]["time"]).rel_accuracy_bits() > 4400 * 3.32


# ---------------------------------------------------------------------------------------------
# the grid
# ---------------------------------------------------------------------------------------------

def test_sample_grid():
    assert sample_grid(1, "1/3") == [Fraction(k, 3) for k in range(4)]
    assert sample_grid("0.3", 0.1) == [Fraction(k, 10) for k in range(4)]  # 0.1 is 1/10, not the double
    assert sample_grid(0, 1) == [0]
    tr = L.simulate(L.LCS(*OSC), [1, 0], sp.pi)  # an irrational t_end: floor(π / (1/2)) = 6
    assert sample_grid(tr.t_end, "1/2")[-1] == 3
    with pytest.raises(L.FormatError, match="must be > 0"):
        sample_grid(1, 0)
    with pytest.raises(L.FormatError, match="grid points"):
        sample_grid(10, "1/1000000")
    with pytest.raises(L.NotRational):
        sample_grid(1, "abc")


# ---------------------------------------------------------------------------------------------
# numbers
# ---------------------------------------------------------------------------------------------

def _significant(text: str) -> int:
    """Significant digits shown (trailing zeros of an integer such as "10" are place holders)."""
    mant = text.lstrip("-").split("e")[0]
    if "." not in mant:
        mant = mant.rstrip("0") or "0"
    return len(mant.replace(".", "").lstrip("0"))


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(st.fractions(max_denominator=10 ** 30).filter(lambda q: q != 0), st.integers(1, 40))
def test_rational_number_bound_holds(q, digits):
    n = rational_number(q, digits)
    v, e = Fraction(n["value"]), Fraction(n["error"])
    assert abs(v - q) <= e and Fraction(n["exact"]) == q
    assert _significant(n["value"]) <= digits
    assert e <= Fraction(1, 10 ** (digits - 1)) * abs(q)  # rounding to `digits` digits
    assert number_rational(n) == q


@settings(max_examples=200, deadline=None)
@given(st.integers(-10 ** 40, 10 ** 40), st.integers(1, 10 ** 30), st.integers(0, 10 ** 20),
       st.integers(-60, 60), st.integers(1, 30))
def test_ball_number_contains_the_ball(p, q, r, e10, digits):
    """The decoded ball [value ± error] contains the whole original ball."""
    with ctx.workprec(200):
        scale = arb(10) ** e10
        b = arb(fmpq(p, q), fmpq(r, 10 ** 25)) * scale
    n = ball_number(b, digits)
    back = number_ball(n)
    with ctx.workprec(200):
        assert back.contains(b), (b, n)
    assert _significant(n["value"]) <= digits


def test_number_decoding():
    b = number_ball({"value": "-2.5e-400", "error": "1e-410", "exact": None})
    with ctx.workprec(300):
        assert b.contains(-fmpq(25, 10 ** 401)) and not b.contains(-fmpq(25, 10 ** 401) + fmpq(2, 10 ** 410))
    with ctx.workprec(300):  # contains() converts fmpq at the ambient precision: work above the ball's
        assert number_ball({"value": "0.1", "error": "0", "exact": "1/10"}).contains(fmpq(1, 10))
    assert number_exact({"value": "1", "error": "0", "exact": "1 + pi/2"}) == "1 + pi/2"
    assert number_rational({"value": "3.14", "error": "0.01", "exact": "pi"}) is None
    assert number_rational({"value": "0.5", "error": "0", "exact": None}) == Fraction(1, 2)
    for bad in ("nan", "1e999999999", "", "1/2", "0x10", "--1"):
        with pytest.raises(L.FormatError):
            number_ball({"value": bad, "error": "0", "exact": None})
    with pytest.raises(L.FormatError, match="must be an object"):
        number_ball(1.5)


# ---------------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------------

def _broken(fx, edit):
    d = copy.deepcopy(fx)
    edit(d)
    return d


@pytest.mark.parametrize("edit, fragment", [
    (lambda d: d.update(schema="lcs-exact/trajectory/2"), "schema"),
    (lambda d: d.pop("events"), "'events' is a required property"),
    (lambda d: d.update(extra=1), "extra"),
    (lambda d: d["events"][0]["time"].update(value="1,0"), "events/0/time/value"),
    (lambda d: d["events"][0]["time"].update(error="-1"), "events/0/time/error"),
    (lambda d: d["events"][0].update(mode_after=[0, 0]), "mode_after"),
    (lambda d: d["x0"].pop(), "x0 has length 3, expected n = 4"),
    (lambda d: d["events"][0].update(mode_after=[3]), "index >= k = 1"),
    (lambda d: d["system"]["B"].append(["1"]), "system.B must be 4x1"),
    (lambda d: d["samples"].reverse(), "does not exceed"),
    (lambda d: d.pop("sample_step"), "sample_step"),
])
def test_validate_rejects(section7_fixture, edit, fragment):
    with pytest.raises(L.FormatError, match="fixture") as err:
        validate_fixture(_broken(section7_fixture, edit))
    assert fragment in str(err.value)


# ---------------------------------------------------------------------------------------------
# the writers in integer arithmetic, against Python's decimal module (correctly rounded)
# ---------------------------------------------------------------------------------------------

def _decimal_reference(q: Fraction, digits: int) -> Fraction:
    """q rounded half-to-even to ``digits`` significant digits by the decimal module (its
    division is correctly rounded in the context's precision)."""
    import decimal
    with decimal.localcontext() as c:
        c.prec, c.rounding, c.Emin, c.Emax = digits, decimal.ROUND_HALF_EVEN, -10 ** 6, 10 ** 6
        d = decimal.Decimal(q.numerator) / decimal.Decimal(q.denominator)
    return Fraction(d)


def _is_tight_bound(text: str, err: Fraction) -> bool:
    """text is a decimal >= err with at most 3 significant digits, and one unit less in its third
    digit would be below err: the smallest such bound (rounded up, never down)."""
    b = Fraction(text)
    if err == 0:
        return text == "0"
    k = 0
    while b / Fraction(10) ** k >= 1000:
        k += 1
    while b / Fraction(10) ** k < 100:
        k -= 1
    three_digits = (b / Fraction(10) ** k).denominator == 1
    return b >= err and three_digits and b - Fraction(10) ** k < err


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(st.integers(-10 ** 45, 10 ** 45).filter(bool), st.integers(1, 10 ** 35), st.integers(1, 40))
def test_rational_number_is_correctly_rounded(p, q, digits):
    want = Fraction(p, q)
    n = rational_number(f"{p}/{q}", digits)
    v = Fraction(n["value"])
    assert v == _decimal_reference(want, digits)
    assert _is_tight_bound(n["error"], abs(v - want)), (n, want)


@settings(max_examples=200, deadline=None)
@given(st.integers(-10 ** 40, 10 ** 40).filter(bool), st.integers(1, 10 ** 30), st.integers(1, 10 ** 20),
       st.integers(-60, 60), st.integers(1, 30))
def test_ball_number_error_is_the_tight_bound(p, q, r, e10, digits):
    """error = (radius + rounding of the midpoint) rounded up to 3 digits, nothing more."""
    with ctx.workprec(300):
        b = arb(fmpq(p, q), fmpq(r, 10 ** 25)) * arb(10) ** e10
        m, rad, e = (int(v) for v in b.mid_rad_10exp(digits + 5))
    n = ball_number(b, digits)
    v = Fraction(n["value"])
    total = Fraction(rad) * Fraction(10) ** e + abs(Fraction(m) * Fraction(10) ** e - v)
    assert _is_tight_bound(n["error"], total), (n, total)


def test_number_ball_keeps_the_fixtures_precision():
    """A 30-digit sample whose value is short ("0.32", error 3e-30) reads back as a ball of
    radius ~3e-30, not widened to the 1e-17 of a 55-bit rounding of 0.32."""
    b = number_ball({"value": "0.32", "error": "3e-30", "exact": None})
    with ctx.workprec(300):
        assert b.contains(fmpq(32, 100) + fmpq(3, 10 ** 30)) and b.contains(fmpq(32, 100) - fmpq(3, 10 ** 30))
        assert b.rad() < arb(fmpq(31, 10 ** 31))
    exact = number_ball({"value": "0.32", "error": "0", "exact": "8/25"})
    with ctx.workprec(300):
        assert exact.contains(fmpq(8, 25)) and exact.rad() < arb(fmpq(1, 10 ** 35))


# ---------------------------------------------------------------------------------------------
# validation of long sample lists (jsonschema runs on two; every sample is still checked)
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("edit, path", [
    (lambda s: s.update(extra=1), "samples/20"),
    (lambda s: s["x"][1].update(value="1,5"), "samples/20/x/1/value"),
    (lambda s: s["x"][2].update(error="-0"), "samples/20/x/2/error"),
    (lambda s: s["x"][0].update(exact=3), "samples/20/x/0/exact"),
    (lambda s: s["x"][0].pop("exact"), "samples/20/x/0"),
    (lambda s: s["t"].update(value=1.5), "samples/20/t/value"),
    (lambda s: s.update(x=[]), "samples/20/x"),
    (lambda s: s.pop("t"), "samples/20"),
])
def test_validate_checks_every_sample(section7_fixture, edit, path):
    assert len(section7_fixture["samples"]) == 31
    d = copy.deepcopy(section7_fixture)
    edit(d["samples"][20])
    with pytest.raises(L.FormatError, match="fixture at " + path):
        validate_fixture(d)
    # the schema file itself agrees (an independent validator of the same draft)
    v = jsonschema.Draft202012Validator(json.loads(files("lcs_exact").joinpath(
        "schemas", "trajectory-1.schema.json").read_text()))
    assert not v.is_valid(d)


# ---------------------------------------------------------------------------------------------
# provenance: optional, free-form JSON, in the schema, covered by the digest, read back
# ---------------------------------------------------------------------------------------------

def test_provenance_is_written_validated_digested_and_read_back(section7):
    prov = {"builder": "lcs_exact.examples.two_carts", "parameters": {}, "x0": "expm_action(A, -1, [0, -1, -1, 0])",
            "t_end": "3", "lcs_exact_version": L.__version__, "mine": [1, "two"]}
    fx = section7.to_fixture(12, provenance=prov)
    prov["builder"] = "changed after writing"           # the fixture holds its own copy
    assert fx["provenance"]["builder"] == "lcs_exact.examples.two_carts" and fx["provenance"]["mine"] == [1, "two"]
    validate_fixture(fx)
    jsonschema.Draft202012Validator(schema()).validate(fx)
    back = L.read_fixture(json.loads(json.dumps(fx)))
    assert back.provenance == fx["provenance"] and len(back.events) == 2
    assert L.read_fixture(section7.to_fixture(12)).provenance is None       # optional
    # the digest covers it: an edited provenance is refused like an edited event
    edited = copy.deepcopy(fx)
    edited["provenance"]["t_end"] = "4"
    with pytest.raises(L.FixtureMismatch):
        L.read_fixture(edited)
    # without provenance the digest is the one written before provenance existed
    plain = section7.to_fixture(12)
    assert {k: v for k, v in fx.items() if k not in ("provenance", "digest")} == \
        {k: v for k, v in plain.items() if k != "digest"}


@pytest.mark.parametrize("prov", [["a list"], {1: "int key"}, {"x": {1, 2}}, {"x": float("nan")}])
def test_provenance_must_be_plain_json(section7, prov):
    with pytest.raises(L.InvalidArgument, match="provenance"):
        section7.to_fixture(12, provenance=prov)


@pytest.mark.parametrize("edit, fragment", [
    (lambda d: d.update(provenance="a string"), "provenance"),
    (lambda d: d.update(provenance={"builder": 3}), "provenance/builder"),
    (lambda d: d.update(provenance={"parameters": []}), "provenance/parameters"),
])
def test_validate_rejects_bad_provenance(section7_fixture, edit, fragment):
    with pytest.raises(L.FormatError, match="fixture") as err:
        validate_fixture(_broken(section7_fixture, edit))
    assert fragment in str(err.value)

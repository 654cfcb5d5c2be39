"""Certified roots of exponential sums (lcs_exact.phases.roots): enclosures, the first-crossing search and
root refinement, on functions whose roots are derived by hand or by mpmath in the test."""
from __future__ import annotations

import mpmath as mp
import pytest
from flint import acb, arb, ctx, fmpq

from lcs_exact.numbers.balls import Policy, workprec
from lcs_exact.errors import UnresolvedSign
from lcs_exact.phases.roots import Bracket, ExpSum, RootReal, first_crossing


class Fn:
    """A RootFunction from terms (lambda, weight, [c_0, c_1, ...]) with exact rational data."""

    def __init__(self, terms, policy=None):
        self.terms, self.policy = terms, policy or Policy()

    def at(self, prec):
        with workprec(prec + 16):
            return ExpSum([(acb(lam), w, [acb(c) for c in cs]) for lam, w, cs in self.terms], prec)

    def deps(self):
        return ()

    def describe(self):
        return "f"


def poly(*coeffs):
    """A polynomial as an exponential sum with the single exponent 0."""
    return Fn([(0, 1, list(coeffs))])


def holds(ball: arb, value, digits: int = 100) -> bool:
    """The ball contains ``value``, an mpf known to ``digits`` significant digits (taken as a ball
    of that relative width): the reference must be more accurate than the ball tested."""
    with ctx.workprec(4 * digits + 64):
        ref = arb(mp.nstr(value, digits + 5), mp.nstr(mp.mpf(10) ** -digits * abs(value), 5))
        return ball.contains(ref)


def test_enclosures_contain_the_function():
    """f(t) = e^{-t} cos(2t) (lambda = -1 + 2i, weight 2, c = 1/2): the Taylor enclosure of f and
    f' on [lo, hi] contains mpmath's values at 30 points inside."""
    f = Fn([(acb(-1, 2), 2, [fmpq(1, 2)])]).at(128)
    lo, hi = fmpq(3, 10), fmpq(7, 10)
    F0, F1 = f.enclose(lo, hi, 0), f.enclose(lo, hi, 1)
    with mp.workdps(50):
        for k in range(31):
            t = mp.mpf(3) / 10 + mp.mpf(k) / 75
            assert holds(F0, mp.exp(-t) * mp.cos(2 * t))
            assert holds(F1, -mp.exp(-t) * (mp.cos(2 * t) + 2 * mp.sin(2 * t)))


def test_stiff_term_decays_in_the_enclosure():
    """f = e^{-10^6 t} + e^{-t} - 1/2: past the stiff transient the enclosure on [1/10, 1/5] is
    as tight as the slow term allows (the stiff term's lambda^4 = 10^24 costs nothing there)."""
    f = Fn([(-10**6, 1, [1]), (-1, 1, [1]), (0, 1, [fmpq(-1, 2)])]).at(128)
    F = f.enclose(fmpq(1, 10), fmpq(1, 5))
    # e^{-t} - 1/2 on [0.1, 0.2] is in [0.318, 0.405]; a bound through |lambda|^4 r^4 / 4! would
    # be ~10^17 wide
    assert F.rad() < 0.05 and F > 0


def test_log2_root_refined_to_many_digits():
    """e^{-t} - 1/2 = 0 at log 2: simple root, interval Newton to 300 digits."""
    fn = Fn([(-1, 1, [1]), (0, 1, [fmpq(-1, 2)])])
    br = first_crossing(fn, fmpq(0), fmpq(5), 128)
    assert br is not None and br.lo < fmpq(7, 10) < br.hi
    r = RootReal(fn, br)
    with mp.workdps(330):
        assert holds(r.ball(300), mp.log(2), 320)
        assert r.ball(300).rad() < mp.mpf(10) ** -299


def test_triple_root_is_a_crossing():
    """(1 - t)^3 changes sign at exactly 1 (a triple root): bracketed, then refined by bisection."""
    fn = poly(1, -3, 3, -1)
    br = first_crossing(fn, fmpq(0), fmpq(3), 128)
    r = RootReal(fn, br)
    assert holds(r.ball(30), 1) and r.ball(30).rad() < 1e-30


def test_near_triple_root_crosses_once():
    """(1 - t)^3 + 10^-30 t crosses once, near 1 + 10^-10 (mpmath's root at 60 digits)."""
    fn = poly(1, fmpq(-3) + fmpq(1, 10**30), 3, -1)
    r = RootReal(fn, first_crossing(fn, fmpq(0), fmpq(3), 128))
    with mp.workdps(60):
        want = mp.findroot(lambda t: (1 - t) ** 3 + mp.mpf(10) ** -30 * t, mp.mpf("1.0000000001"))
    assert holds(r.ball(30), want)


def test_gap_of_1e_minus_30_at_the_start():
    """10^-30 - sin t: the root is 10^-30 (to 1e-90), found without searching at that width."""
    fn = Fn([(acb(0, 1), 2, [acb(0, fmpq(1, 2))]), (0, 1, [fmpq(1, 10**30)])])
    r = RootReal(fn, first_crossing(fn, fmpq(0), fmpq(3), 128))
    b = r.ball(30)
    with mp.workdps(220):
        assert holds(b, mp.asin(mp.mpf(10) ** -30), 200)


def test_positive_function_has_no_crossing():
    """2 + cos(3t) > 0 on [0, 10]: no crossing."""
    assert first_crossing(Fn([(acb(0, 3), 2, [fmpq(1, 2)]), (0, 1, [2])]), fmpq(0), fmpq(10), 128) is None


@pytest.mark.slow
def test_touch_without_proof_is_refused_or_recorded():
    """(1 - t)^2 touches 0 at 1: with no proof of the touch the search refuses (UnresolvedSign);
    allowed, it records the assumption and finds no crossing."""
    with pytest.raises(UnresolvedSign, match="tangential touch"):
        first_crossing(poly(1, -2, 1), fmpq(0), fmpq(3), 128)
    fn = Fn([(0, 1, [1, -2, 1])], Policy(allow_unresolved=True))
    assert first_crossing(fn, fmpq(0), fmpq(3), 128) is None and len(fn.policy.assumptions) == 1


def test_touch_with_proof_is_not_an_event():
    """The same touch with a prover that certifies it: no crossing, nothing assumed."""
    calls = []

    def touch(lo, hi, convex_lo, convex_hi):
        calls.append((lo, hi))
        assert convex_lo <= lo <= hi <= convex_hi
        return lo <= 1 <= hi  # the test knows the touch is at exactly 1

    fn = poly(1, -2, 1)
    assert first_crossing(fn, fmpq(0), fmpq(3), 128, touch=touch) is None and calls
    assert not fn.policy.assumptions


def test_first_of_two_close_roots():
    """(t - 1)(t - 1 - 10^-20): + then - then +: the first crossing is exactly 1."""
    e = fmpq(1, 10**20)
    fn = poly(1 + e, -(2 + e), 1)
    r = RootReal(fn, first_crossing(fn, fmpq(0), fmpq(3), 128))
    assert holds(r.ball(40), 1)


class BlurredFn(Fn):
    """Fn whose constant term is a ball of radius 2^-100 (as a phase start's state gives):
    e^{-t} - (1/2 +- 2^-100), whose root log 2 is known to about 2^-99 only."""

    def at(self, prec):
        f = super().at(prec)
        with workprec(prec + 16):
            lam, w, cs = f.terms[1]
            f.terms[1] = (lam, w, [acb(arb(cs[0].real, arb(2) ** -100))])
        return f


def test_refinement_stops_at_the_resolution_of_the_function():
    """The point Newton's bracket is widened to the resolution of f (radius of f over |f'|), not
    refused: refined at 300 bits, the root gets a ball that holds log 2 and is as narrow as the
    blurred data allow (2^-99 .. 2^-90)."""
    fn = BlurredFn([(-1, 1, [1]), (0, 1, [fmpq(-1, 2)])])
    br = first_crossing(fn, fmpq(0), fmpq(5), 128)
    r = RootReal(fn, br)
    b = r.arb(300)
    with mp.workdps(60):
        assert holds(b, mp.log(2), 50)
    assert arb(2) ** -100 < b.rad() < arb(2) ** -90
    assert r.lo < r.hi and r.simple


def test_root_near_a_double_root_refined_past_the_float_guess():
    """(t - 1)^2 - 10^-40 on the simple bracket (0, 1 - 10^-20 + 10^-30] (f' = 2 (t - 1) < 0
    there): the root 1 - 10^-20 is below the resolution of floats, the float guess is ~1 - 10^-16
    and Newton's points from it only halve their distance to the root, so the certified signs
    at x -+ d fail and the interval Newton refines instead: 180 digits, against the exact root."""
    fn = poly(1 - fmpq(1, 10**40), -2, 1)
    r = RootReal(fn, Bracket(fmpq(0), 1 - fmpq(1, 10**20) + fmpq(1, 10**30), True))
    b = r.arb(640)
    with mp.workdps(260):
        assert holds(b, 1 - mp.mpf(10) ** -20, 240)
        assert b.rad() < mp.mpf(10) ** -180


def test_float_guess_of_a_root():
    """The float guess the refinement starts from (lcs_exact.phases.guesses.float_root): log 2 for
    e^{-t} - 1/2 on (0, 5) and pi/2 for cos t on (1/2, 3), to float accuracy; on (0, 40) Newton's
    first step from the middle leaves the bracket (f'(20) = -2e-9: a step of 2.4e8) and bisection
    takes over."""
    from lcs_exact.phases.guesses import float_root
    f = Fn([(-1, 1, [1]), (0, 1, [fmpq(-1, 2)])]).at(64)
    assert abs(float_root(f, 0.0, 5.0) - 0.6931471805599453) < 1e-15
    cos = Fn([(acb(0, 1), 2, [fmpq(1, 2)])]).at(64)
    assert abs(float_root(cos, 0.5, 3.0) - 1.5707963267948966) < 1e-15
    assert abs(float_root(f, 0.0, 40.0) - 0.6931471805599453) < 1e-15


def test_polish_from_a_bracket_narrower_than_floats():
    """A simple bracket of width 2^-3000 around log 2 (e^{-t} - 1/2): the narrow path reads the
    bits it already has off the exact width (as a float the ratio overflowed: a bare
    OverflowError a fuzz found on a 3-contact mechanical scene) and refines on to 3300 bits."""
    from lcs_exact.numbers.balls import dyadic_lower, dyadic_upper
    with workprec(3100):
        l2 = arb(2).log()
        lo, hi = dyadic_lower(l2), dyadic_upper(l2)
    assert 0 < hi - lo < fmpq(1, 2 ** 3000)
    r = RootReal(Fn([(-1, 1, [1]), (0, 1, [fmpq(-1, 2)])]), Bracket(lo, hi, True))
    b = r.arb(3300)
    with workprec(3500):
        assert b.overlaps(arb(2).log()) and b.rad() < arb(2) ** -3250



@pytest.mark.parametrize("terms, a, b, first", [
    ([(acb(0, 1), 2, [fmpq(1, 2)])], 0.0, 3.0, 1.5707963),                     # cos t
    ([(0, 1, [fmpq(3, 4), -2, 1])], 0.0, 4.0, 0.5),                             # (t - 1)^2 - 1/4
    ([(-1, 1, [1]), (0, 1, [fmpq(-1, 2)])], 0.0, 40.0, 0.6931472),              # e^{-t} - 1/2
    ([(acb(fmpq(-1, 10), 3), 2, [1, fmpq(1, 3)]), (0, 1, [fmpq(1, 5)])], 0.0, 30.0, 0.55339),
    ([(acb(0, 1), 2, [1]), (0, 1, [3])], 0.0, 300.0, None),                    # 3 + 2 cos t: never
    ([(1000, 1, [fmpq(9, 10), -1])], 0.0, 2.0, None),                           # e^{1000 t} (9/10 - t)
])
def test_float_crossing_without_numpy_matches_numpy(monkeypatch, terms, a, b, first):
    """float_crossing's scalar path (small chunks: Python's complex arithmetic, so a small
    system's first simulate does not import numpy) gives the estimate of its numpy path, the
    first grid point past the crossing; a chunk whose floats overflow goes to numpy (inf and nan
    as before: e^{1000 t} (9/10 - t) overflows from t = 0.71 and is -inf past 9/10, no estimate)."""
    from lcs_exact.dynamics import guesses
    f = Fn(terms).at(64)
    monkeypatch.setattr(guesses, "SCALAR_TERM_POINTS", 0)                       # numpy for every chunk
    ref = guesses.float_crossing(f, a, b)
    assert ref is None if first is None else first < ref <= first + (b - a) / 64
    numpy_chunks = []
    numpy_chunk = guesses._numpy_chunk
    monkeypatch.setattr(guesses, "_numpy_chunk", lambda *args: numpy_chunks.append(args) or numpy_chunk(*args))
    monkeypatch.setattr(guesses, "SCALAR_TERM_POINTS", 10 ** 9)                 # Python for every chunk
    assert guesses.float_crossing(f, a, b) == ref
    assert bool(numpy_chunks) == (terms[0][0] == 1000)                          # numpy only after an overflow


class Toucher:
    """A touch prover for the search: ``flat`` records its intervals and proves a touch of even
    order exactly when the interval holds ``at`` (None: never)."""

    def __init__(self, at=None):
        self.at, self.flats = at, []

    def __call__(self, lo, hi, convex_lo, convex_hi):
        return None

    def flat(self, lo, hi, f):
        self.flats.append((lo, hi))
        return self.at is not None and lo <= self.at <= hi


class TinyFn(Fn):
    """10^-60 (2 + cos t) with a radius 2^-(prec - 20) (a phase start's ball): below the balls'
    resolution until about 230 bits, positive all along."""

    def at(self, prec):
        f = super().at(prec)
        with workprec(prec + 16):
            lam, w, cs = f.terms[1]
            f.terms[1] = (lam, w, [acb(arb(cs[0].real, arb(2) ** -(prec - 20)))])
        return f


def test_flat_touches_are_looked_for_on_narrow_intervals_only():
    """A function below the balls' resolution over all of [0, 10] gets more bits (no crossing,
    found at ~256 bits), never a flat-touch proof over the wide interval; the touch of (1 - t)^4
    at 1 is still proven on the narrow interval around it: no ball shows a sign within about
    (2^-128)^(1/4) = 2^-32 of the touch at 128 bits, and the interval asked is a few times that
    (below 2^-20; the search tries flat touches on intervals up to 2^-8 wide at 128 bits)."""
    touch = Toucher()
    fn = TinyFn([(acb(0, 1), 2, [fmpq(1, 2 * 10 ** 60)]), (0, 1, [fmpq(2, 10 ** 60)])])
    assert first_crossing(fn, fmpq(0), fmpq(10), 128, touch=touch) is None
    assert touch.flats == []
    touch = Toucher(at=fmpq(1))
    assert first_crossing(poly(1, -4, 6, -4, 1), fmpq(0), fmpq(3), 128, touch=touch) is None
    assert touch.flats and all(hi - lo <= fmpq(1, 2 ** 20) for lo, hi in touch.flats)

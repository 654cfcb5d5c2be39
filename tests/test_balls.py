"""The precision policy (lcs_exact.numbers.balls): scoped precision, certified signs, unresolved zeros,
deadlines and rigorous evaluation of closed forms."""
from __future__ import annotations

import time

import mpmath as mp
import pytest
import sympy as sp
from flint import arb, ctx

from lcs_exact.numbers.balls import (Deadline, Policy, closed_form_arb, decide_sign, digits_to_bits,
                             workprec)
from lcs_exact.errors import InvalidArgument, LimitExceeded, UnresolvedSign


def test_digits_to_bits_is_enough():
    from fractions import Fraction
    for d in (1, 15, 30, 100, 1000):
        b = digits_to_bits(d)
        assert Fraction(1, 2 ** b) < Fraction(1, 10 ** d) <= Fraction(1, 2 ** (b - 5))


def test_workprec_restores_even_after_an_error():
    with pytest.raises(ZeroDivisionError):
        with workprec(500):
            assert ctx.prec == 500
            raise ZeroDivisionError
    assert ctx.prec == 53


def test_policy_defaults():
    p = Policy(digits=30)
    assert p.target_bits == digits_to_bits(30) + 16 and p.max_prec == 4096
    assert Policy(digits=1000).max_prec == 8 * digits_to_bits(1000)
    assert p.working_prec(100) == p.target_bits + 32 + 100


def test_sign_of_a_tiny_value_is_certified_by_refinement():
    """10^-500 > 0 needs ~1700 bits: decided, not refused."""
    tiny = lambda prec: arb(10) ** -500 + arb(1) - arb(1)  # noqa: E731
    assert decide_sign(tiny, policy=Policy(), what="tiny", start=64) == 1


def test_exact_zero_needs_a_proof():
    zero = lambda prec: arb.pi() - 4 * arb(1).atan()  # noqa: E731
    with pytest.raises(UnresolvedSign, match="pi - 4 atan 1"):
        decide_sign(zero, policy=Policy(max_prec=256), what="pi - 4 atan 1")
    assert decide_sign(zero, policy=Policy(max_prec=256), what="z", prove_zero=lambda: True) == 0
    p = Policy(max_prec=256, allow_unresolved=True)
    assert decide_sign(zero, policy=p, what="pi - 4 atan 1") == 0
    assert p.assumptions == ["pi - 4 atan 1"]


def test_deadline():
    d = Deadline(0.0)
    time.sleep(0.01)
    with pytest.raises(LimitExceeded, match="time_limit = 0.0 s reached while testing"):
        d.check(lambda: " while testing")
    # the message may itself check the deadline (a time shown to 15 digits): it is still built
    with pytest.raises(LimitExceeded, match=r"reached at t = 1\.5$"):
        d.check(lambda: d.check() or " at t = 1.5")
    d.disarm()
    d.check()  # disarmed: no error
    Deadline(None).check()


def test_closed_form_balls_contain_the_value():
    x = sp.sqrt(2) + sp.pi / 3 - sp.log(sp.Rational(5, 2)) + sp.atan(sp.Rational(1, 7)) * sp.exp(1)
    with workprec(300):
        b = closed_form_arb(x)
    with mp.workdps(120):
        want = mp.sqrt(2) + mp.pi / 3 - mp.log(mp.mpf(5) / 2) + mp.atan(mp.mpf(1) / 7) * mp.e
        with ctx.workprec(500):
            assert b.contains(arb(mp.nstr(want, 110))) and b.rad() < 1e-85
    with pytest.raises(InvalidArgument, match="outside the supported set"):
        closed_form_arb(sp.gamma(sp.Rational(1, 3)))

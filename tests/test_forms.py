"""Light closed forms (lcs_exact.numbers.forms): values against mpmath and SymPy, exact zero tests by
Calcium, SymPy's text, and the main job printing 1 + pi/2 without importing SymPy."""
from __future__ import annotations

import subprocess
import sys

import mpmath
import pytest
import sympy
from flint import arb, fmpq

from lcs_exact.numbers.balls import workprec
from lcs_exact.errors import InvalidArgument
from lcs_exact.numbers.forms import Closed

PI = Closed.pi_over_sqrt(1)


def test_values_against_mpmath():
    mpmath.mp.dps = 50
    try:
        cases = [
            (Closed.rational(fmpq(3, 7)), mpmath.mpf(3) / 7),
            (Closed.rational(1) + PI * fmpq(1, 2), 1 + mpmath.pi / 2),
            (Closed.pi_over_sqrt(fmpq(2, 3)) * fmpq(5, 4), mpmath.mpf(5) / 4 * mpmath.pi / mpmath.sqrt(mpmath.mpf(2) / 3)),
            (Closed.log(fmpq(10, 3)) * fmpq(-1, 2), -mpmath.log(mpmath.mpf(10) / 3) / 2),
        ]
        for form, want in cases:
            with workprec(160):
                b = form.arb()
            assert b.contains(arb(mpmath.nstr(want, 45)).mid()) or abs(float(b.mid()) - float(want)) < 1e-40
            assert abs(mpmath.mpf(b.mid().str(45, radius=False)) - want) < mpmath.mpf(10) ** -40
    finally:
        mpmath.mp.dps = 15


def test_structure_and_normal_form():
    # pi / sqrt(9/4) = 2 pi / 3: a square r becomes a rational multiple of pi
    assert Closed.pi_over_sqrt(fmpq(9, 4)) == PI * fmpq(2, 3)
    assert (PI * fmpq(1, 2) + PI * fmpq(1, 2)) == PI
    assert (PI - PI).is_zero and (PI - PI).to_fmpq() == 0
    assert Closed.log(1).is_zero and Closed.rational(fmpq(5, 2)).to_fmpq() == fmpq(5, 2)
    assert PI.has_pi and not Closed.log(2).has_pi
    assert len({Closed.rational(1) + PI, PI + 1}) == 1  # equal forms hash alike
    with pytest.raises(InvalidArgument):
        Closed.pi_over_sqrt(0)
    with pytest.raises(InvalidArgument):
        Closed.log(-1)


def test_exact_zero_tests_by_calcium():
    # log(4)/2 - log(2) = 0 and pi/sqrt(2) - sqrt(2) pi / 2 = 0 are not structural zeros
    z1 = Closed.log(4) * fmpq(1, 2) - Closed.log(2)
    assert not z1.is_zero and z1.to_ca().is_zero() is True
    # pi/sqrt(2) and (1/2) pi/sqrt(1/2) are one number: the normal form pi/sqrt(f), f squarefree,
    # makes them one form; Calcium agrees
    z2 = Closed.pi_over_sqrt(2) - Closed.pi_over_sqrt(fmpq(1, 2)) * fmpq(1, 2)
    assert z2.is_zero
    z3 = Closed.pi_over_sqrt(2) * fmpq(1, 1) - Closed.pi_over_sqrt(fmpq(8, 9)) * fmpq(2, 3)
    assert z3.is_zero  # pi/sqrt(8/9) = 3 pi / (2 sqrt 2)
    assert (Closed.pi_over_sqrt(2) - PI * fmpq(1, 2)).to_ca().is_zero() is False
    assert (PI * fmpq(1, 3) - Closed.rational(1)).to_ca().is_zero() is False


def test_text_and_sympy_agree():
    for form in [Closed.rational(1) + PI * fmpq(1, 2), Closed.rational(-1) + PI * fmpq(1, 2),
                 Closed.rational(1) - PI * fmpq(1, 2), Closed.pi_over_sqrt(2) * fmpq(3, 4),
                 PI * fmpq(-3, 2), Closed.pi_over_sqrt(fmpq(2, 3)) * fmpq(5, 7)]:
        expr = form.to_sympy()
        assert str(form) == str(expr)
        assert sympy.simplify(expr - sympy.sympify(str(form))) == 0
    assert str(Closed.log(fmpq(3, 2)) * -1) == str(-sympy.log(sympy.Rational(3, 2)))
    e = sympy.atan(sympy.Rational(1, 3))
    assert Closed.of_sympy(e).to_sympy() == e and str(Closed.of_sympy(e)) == "atan(1/3)"


@pytest.mark.slow
def test_main_job_prints_closed_forms_without_sympy():
    code = ("import sys\nfrom lcs_exact.cli import two_carts_demo\nlines = []\n"
            "two_carts_demo(out=lines.append)\nprint('sympy' in sys.modules)\n"
            "print([l for l in lines if l.startswith('event')])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    loaded, events = out.strip().splitlines()
    assert loaded == "False"
    assert events.endswith("'event t = 2.57079632679489661923132169164 +/- 2.51e-31 = 1 + pi/2']")
    assert "'event t = 1'" in events


def test_sympys_simplify_as_a_last_resort_prover_is_cut_off_by_its_budget(monkeypatch):
    """f = 2/3 sin t - 1/3 sin 2t + 1/2 at t* = 2 pi - acos(a), a the root of 16a^4 - 32a^3 +
    32a - 7 near -0.92 written by SymPy in nested radicals: f(t*) = 0 (the graze of a forced
    impact oscillator), and SymPy's simplify of it ran for minutes.  Under a budget of work the
    prover answers "unknown"; the ball alone answers a nonzero value."""
    import sympy as sp
    from lcs_exact import forms
    a = sp.Rational(3, 64) * sp.sqrt(6) + sp.Rational(9, 64)
    c = a ** sp.Rational(1, 3)
    r = sp.sqrt(3 / (8 * c) + 1 + 2 * c)
    root = -r / 2 - sp.sqrt(-2 * c - 3 / (8 * c) + 2 / r + 2) / 2 + sp.Rational(1, 2)
    x = sympy.lambdify([], root, "mpmath")()
    assert abs(16 * x**4 - 32 * x**3 + 32 * x - 7) < 1e-12 and abs(x + 0.920601826) < 1e-9
    t = 2 * sp.pi - sp.acos(root)
    expr = sp.expand_trig(2 * sp.sin(t) / 3 - sp.sin(2 * t) / 3 + sp.Rational(1, 2))
    monkeypatch.setattr(forms, "SYMPY_WORK", 200_000)
    assert forms.sympy_proves_zero(expr) is None
    assert forms.sympy_proves_zero(expr + sp.Rational(1, 10**30)) is False
    # Calcium decides the same number: 0 (the radicals by their minimal polynomials)
    assert forms.ca_of_sympy(expr).is_zero() is True

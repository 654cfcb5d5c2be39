"""Limits that hold (issue 28, item 5): ``time_limit`` stops exact algebraic phases between their
Calcium steps, and inputs with 10^400-sized entries print, write their fixture or are refused
at once with a named error - never a hang.  Each scene's values are derived by hand here."""
import pathlib
import subprocess
import sys

import mpmath as mp
import pytest
import sympy
from flint import fmpq

import lcs_exact as L
from lcs_exact import calcium
from lcs_exact.balls import Deadline, check_in_force
from lcs_exact.closedforms import exp_candidates
from lcs_exact.numbers.laplace import t_symbol
from lcs_exact.forms import Closed

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_calcium_steps_stop_at_the_deadline_in_force():
    """A compaction and a zero test look at the run's deadline before they start (each is one
    uninterruptible call into Calcium, bounded; a run is a long chain of them); outside a run
    nothing is checked."""
    x = (calcium.Ca(2).sqrt() * 10**40 + 1) / (calcium.Ca(2).sqrt() * 10**40 - 1)
    assert len(str(x)) > 50
    with Deadline(0.0).in_force():
        with pytest.raises(L.TimeLimitExceeded, match="Calcium"):
            x.compact(size=50)
        with pytest.raises(L.TimeLimitExceeded, match="Calcium"):
            x.is_zero()
    assert (x - x.compact(size=50)).is_zero() is True  # outside: the same work, unchecked
    check_in_force()  # no run in progress


def test_a_run_through_exact_algebraic_phases_stops_inside_them_at_its_time_limit(monkeypatch):
    """A column of three beads falling from rest (g = 981/100, e = 9/10, r = 1/10) runs through
    phases whose event times are algebraic (Calcium): with a deadline that passes at the first
    compaction of an event state, the run stops there with TimeLimitExceeded (status 'time limit',
    its events so far kept), not at the end of the event."""
    from lcs_exact.examples import ball_column
    calls = {"n": 0}
    real = calcium.Ca.compact

    def compact(self, size=200):
        if len(str(self)) > size:
            calls["n"] += 1
            if calls["n"] == 3:  # the clock passes the limit here
                monkeypatch.setattr(Deadline, "expired", lambda d: True)
                monkeypatch.setattr(Deadline, "check", _raise)
        return real(self, size)
    monkeypatch.setattr(calcium.Ca, "compact", compact)
    col = ball_column(3, g="981/100", e="9/10", radius="1/10")
    with pytest.raises(L.TimeLimitExceeded) as info:
        L.simulate(col, col.embed(["1/2", 1, "3/2", 0, 0, 0]), 3, time_limit=10**6)
    assert "Calcium" in str(info.value)
    monkeypatch.undo()  # the clock is back: the queries below run
    tr = info.value.trajectory
    assert tr.status is L.Status.TIME_LIMIT and tr.partial
    # the beads fall alike (their gaps of 3/10 kept) until bead 0 lands at sqrt(2 (1/2 - 1/10) / g)
    t1 = tr.events[0].time
    assert sympy.simplify(t1.closed_form - sympy.sqrt(sympy.Rational(80, 981))) == 0


def _raise(self, where=""):
    raise L.TimeLimitExceeded(f"time_limit = {self.limit} s reached{where() if callable(where) else where}")


def test_a_pi_form_with_a_huge_frequency_prints_as_sympy_does():
    """pi / sqrt(10^400 + 1): its square factors are not searched by trial division (that took
    hours); the text is SymPy's."""
    r = fmpq(10**400 + 1)
    c = Closed.pi_over_sqrt(r) + fmpq(1, 2) * Closed.pi_over_sqrt(1)
    assert str(c) == str(sympy.pi / sympy.sqrt(sympy.Integer(10**400 + 1)) + sympy.pi / 2)


def test_an_oscillator_with_a_compliance_of_1e_minus_400():
    """x'' = -x + u, y = x + 10^-400 u, from (1, 0): free until x = 0 at pi/2 (x' = -1); then in
    mode {0}, u = -10^400 x and x'' = -(1 + 10^400) x, so x = -sin(w s)/w with w = sqrt(1 + 10^400)
    and u = 10^400 sin(w s)/w >= 0 until w s = pi: the second event at pi/2 + pi/sqrt(1 + 10^400),
    printed and written in closed form."""
    eps = fmpq(1, 10**400)
    lcs = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[eps]])
    tr = L.simulate(lcs, [1, 0], 2)
    want = sympy.pi / 2 + sympy.pi / sympy.sqrt(1 + sympy.Integer(10) ** 400)
    e = tr.events[1]
    assert sympy.simplify(e.time.closed_form - want) == 0
    assert str(e.time.closed_form) == str(want)
    with mp.workdps(60):
        assert abs(mp.mpf(e.time.decimal(40).split()[0]) - (mp.pi / 2 + mp.pi / mp.sqrt(1 + mp.mpf(10) ** 400))) \
            < mp.mpf(10) ** -39
    fx = tr.to_fixture(20)
    assert fx["events"][1]["time"]["exact"] == str(want)


def test_exponential_sums_with_rates_10_400_apart_give_no_polynomial_of_huge_degree():
    """-e^{-t/10^400} + 3 e^{-2t}: the exponents' ratio is 2 10^400, a polynomial of that degree in
    e^{gamma t} is not built (it hung, filling memory); no candidate."""
    t = t_symbol()
    assert exp_candidates(-sympy.exp(-t / sympy.Integer(10) ** 400) + 3 * sympy.exp(-2 * t)) == []


def test_a_fixture_that_needs_an_unevaluable_number_is_refused_at_once(tmp_path):
    """A = diag(-1, 10^400) from (1, 1): the run stops at the horizon limit of the rate 10^400
    (t = 999/10^403); x_0 = e^{-t} there is the modal sum whose 10^400-rate term cancels exactly,
    which no affordable ball shows (its radius stays 10^(4 10^11)): the fixture is refused at
    once, in one line on stderr naming -o (it refined for minutes to 6 million bits, twice: the
    refinement now stops at 16 x max_prec bits)."""
    model = tmp_path / "m.json"
    model.write_text('{"A": [[-1, 0], [0, 1e400]], "B": [[1], [1]], "C": [[-1, 3]], "D": [[0]], "x0": [1, 1], '
                     '"t_end": 3}')
    out = tmp_path / "fx.json"
    p = subprocess.run([sys.executable, "-m", "lcs_exact", "simulate", str(model), "-o", str(out)], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in p.stderr
    assert lines[0].startswith(f"lcs-exact: error: -o {out}: the fixture is not written: could not evaluate")
    assert not out.exists()
    assert "PARTIAL (horizon limit" in p.stdout

"""Closed forms of event times and states, each derived by hand in the test.

Candidates are only accepted when proven (inside the isolating interval and an exact zero), so
these tests check both that the closed form is found and that it is the right one.
"""
import mpmath as mp
import sympy as sp
from flint import arb, fmpq

import lcs_exact as L
from lcs_exact.numbers.closedforms import exp_candidates as _exp_candidates, solve_candidates as _solve_candidates
from lcs_exact.numbers.closedforms import prove_flat_touch
from lcs_exact.numbers.laplace import t_symbol

_t = t_symbol()

from helpers import close, num

mp.mp.dps = 60


def test_log_event_of_two_exponentials():
    """y = -e^{-t} + 3 e^{-2t} vanishes at e^t = 3: t = log 3, x = (1/3, 1/9) (rational again)."""
    s = L.LCS([[-1, 0], [0, -2]], [[1], [1]], [[-1, 3]], [[0]])
    tr = L.simulate(s, [1, 1], 3)
    assert tr.certified and len(tr.events) == 1
    e = tr.events[0]
    assert sp.simplify(e.time.closed_form - sp.log(3)) == 0
    assert [str(c.closed_form) for c in e.state_before] == ["1/3", "1/9"]
    assert e.mode_after == frozenset({0}) and e.modes == ()


def test_algebraic_log_event():
    """y = e^{-t} - 5 e^{-2t} + 5 e^{-3t} = u (5u^2 - 5u + 1) with u = e^{-t}: the first root is at
    u = (5 + √5)/10, so t = log(10 / (5 + √5)); x(t) = (u, u^2, u^3)."""
    s = L.LCS([[-1, 0, 0], [0, -2, 0], [0, 0, -3]], [[1], [1], [1]], [[1, -5, 5]], [[0]])
    tr = L.simulate(s, [1, 1, 1], 1)
    assert tr.certified and len(tr.events) == 1
    e = tr.events[0]
    u = (5 + sp.sqrt(5)) / 10
    assert sp.simplify(e.time.closed_form - sp.log(1 / u)) == 0
    cf = e.state_before.closed_form()
    assert cf is not None
    for k in range(3):
        assert sp.simplify(cf[k] - u ** (k + 1)) == 0
    assert close(num(e.time), -mp.log((5 + mp.sqrt(5)) / 10))


def test_exp_candidates_cosh():
    """cosh(√2 t) = 3 at t = log(3 + 2√2)/√2 (u = e^{√2 t}: u^2 - 6u + 1 = 0)."""
    cands = _exp_candidates(sp.cosh(sp.sqrt(2) * _t) - 3)
    want = sp.log(3 + 2 * sp.sqrt(2)) / sp.sqrt(2)
    assert any(sp.simplify(c - want) == 0 for c in cands)


def test_exp_candidates_refuse_polynomial_terms():
    """t e^{-t} terms have no root in radicals of e^{gt}: no candidates (not a wrong one)."""
    assert _exp_candidates(_t * sp.exp(-_t) - sp.Rational(1, 5)) == []


def test_no_symbolic_solve_for_mixed_polynomial_trig():
    """q1 = 1 - t/2 - sin(√2 t)/(2√2) is not one-frequency: no SymPy solve attempt."""
    from flint import arb
    f = 1 - _t / 2 - sp.sin(sp.sqrt(2) * _t) / (2 * sp.sqrt(2))
    assert _solve_candidates(f, arb(1.3)) == []


def test_free_masses_spring_stop():
    """Two unit masses coupled by a unit spring, stop on mass 1 (q1 >= 0), from q = (1, 1),
    v = (-1, 0). Centre c = 1 - t/2, difference d = -sin(√2 t)/√2: q1 = c + d/2 hits 0 first at
    the root of 1 - t/2 - sin(√2 t)/(2√2) (no closed form expected); v1 jumps to 0."""
    A = [[0, 0, 1, 0], [0, 0, 0, 1], [-1, 1, 0, 0], [1, -1, 0, 0]]
    s = L.LCS(A, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])
    tr = L.simulate(s, [1, 1, -1, 0], 2)
    assert tr.certified and len(tr.events) == 1
    r2 = mp.sqrt(2)
    f = lambda t: 1 - t / 2 - mp.sin(r2 * t) / (2 * r2)
    tau = mp.findroot(f, 1.3)
    e = tr.events[0]
    assert close(num(e.time), tau)
    assert e.modes == (frozenset({0}),)
    v2 = -mp.mpf(1) / 2 + mp.cos(r2 * tau) / 2
    q2 = 1 - tau / 2 + mp.sin(r2 * tau) / (2 * r2)
    after = [num(c) for c in e.state_after]
    assert after[0] == 0 and after[2] == 0
    assert close(after[1], q2) and close(after[3], v2)


def test_touch_at_sqrt2_from_a_shifted_start_is_proven():
    """y = q + c with q'' = -q, c' = 0 from x0 = e^{-sqrt2 A}(-1, 0, 1): y(t) = 1 - cos(t - sqrt 2)
    touches 0 at exactly sqrt 2 (y' = 0, y'' = 1 > 0) and is positive elsewhere on [0, 3]: no
    event, certified (the candidate sqrt 2 comes from the orbit of (-1, 0, 1) shifted back)."""
    graze = L.LCS([[0, 1, 0], [-1, 0, 0], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 1]], [[0]])
    tr = L.simulate(graze, L.expm_action(graze.A, -sp.sqrt(2), [-1, 0, 1]), 3)
    assert tr.events == () and tr.certified


def test_atan_forms_and_pi_after_an_irrational_start():
    """q'' = -q with a stop q >= 0 and e = 1/2 (mechanical), from (1, 1/3): q = cos t + sin(t)/3
    reaches the stop where tan t = -3, t1 = pi - atan(3) (the branch SymPy's solve misses);
    the bounce leaves from q = 0, and the next return is half a period later: t1 + pi exactly,
    proven through e^{A pi} = -I and the relation q = 0 on the start (no closed form of it needed)."""
    import sympy
    from lcs_exact import simulate
    from lcs_exact.builders.mechanics import mechanical
    osc = mechanical([[1]], [[1]], [[1]], restitution="1/2")
    tr = simulate(osc, [1, "1/3"], 8)
    t1 = sympy.pi - sympy.atan(3)
    assert sympy.simplify(tr.events[0].time.closed_form - t1) == 0
    assert sympy.simplify(tr.events[1].time.closed_form - (t1 + sympy.pi)) == 0


def test_acos_of_a_quadratic_in_cos_t_two_harmonics():
    """Two oscillators of frequencies 1 and 2 and a stop on q0 + q1 + 8 >= 0 (a gap), from
    q = (-2, 16) at rest: y = -2 cos t + 16 cos 2t + 8 = 32 x^2 - 2x - 8 with x = cos t, so the
    stop is reached at t = acos((1 + sqrt 257)/32), the root of the quadratic in [-1, 1] that
    cos t meets first (by hand)."""
    import sympy
    from lcs_exact import simulate
    from lcs_exact.builders.mechanics import mechanical
    two = mechanical([[1, 0], [0, 1]], [[1, 0], [0, 4]], [[1, 1]], gap=[8])
    tr = simulate(two, two.embed([-2, 16, 0, 0]), 2)
    want = sympy.acos((1 + sympy.sqrt(257)) / 32)
    assert sympy.simplify(sympy.cos(tr.events[0].time.closed_form) - sympy.cos(want)) == 0
    assert abs(float(tr.events[0].time.closed_form) - float(want)) < 1e-15


def test_state_at_a_rational_time_is_rational_only_on_the_generalized_kernel():
    """e^{3A} q for a free mass beside a spring: rational exactly when q has no spring part
    (Lindemann-Weierstrass: e^{3i} and e^{-3i} are independent of 1 over the algebraic numbers),
    decided without Calcium; the spring part's closed form stays cos(3)."""
    A = [[0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]]
    assert L.expm_action(A, 3, [1, 2, 0, 0]).rational().entries() == [7, 2, 0, 0]  # q + 3 q'
    w = L.expm_action(A, 3, [1, 2, 1, 0])
    assert w.rational() is None
    assert str(w[2].closed_form) == "cos(3)" and str(w[0].closed_form) == "7"


def test_state_of_a_ten_dimensional_chain_at_a_rational_time_has_no_rational_form():
    """A 5-cart chain (degree-10 eigenvalues) flowing to t = 3 without events: the state is not
    rational (its parts at eigenvalues != 0 do not vanish), decided exactly; Calcium spent minutes
    and 2 GB on e^{3 M} q to find the same."""
    import lcs_exact as L
    x0 = ["2/5", "-2/5", "2/5", "-1/2", "1/2", "1/5", "0", "1/5", "1/5", "1/5"]
    tr = L.simulate(L.examples.cart_chain(5, stops=[4]), x0, 3, digits=30)
    assert len(tr.events) == 0
    x = tr.state(3)
    assert x.rational() is None and x[0].closed_form is None


def test_repeated_complex_pair_has_no_closed_form_and_no_crash():
    """A = companion of (s^2 + 1)^2 (a repeated pair +-i: t cos t, t sin t terms), D = 1: the
    event times are certified roots; their closed forms are None, not a bare TypeError of the
    harmonic candidates (t cos t is no polynomial in cos t), and the run writes a fixture.
    Checked against mpmath: mode {} is x' = A x, y = x1, the first event where x1 = 0."""
    A = [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [-1, 0, -2, 0]]
    lcs = L.LCS(A, [[0], [0], [0], [1]], [[1, 0, 0, 0]], [[1]])
    tr = L.simulate(lcs, [1, 0, 0, 0], 10, digits=30, closed_forms=True)
    t1 = tr.events[0].time
    assert t1.closed_form is None
    with mp.workdps(50):
        f = lambda t: (mp.expm(mp.matrix(A) * t) * mp.matrix([1, 0, 0, 0]))[0]
        assert close(num(t1), mp.findroot(f, 2.46))
    assert tr.to_fixture(15)["schema"].startswith("lcs-exact/trajectory")


def test_mode_with_chi_s4_plus_1_has_no_closed_form_and_no_crash():
    """A chain of four integrators, y = x1 + u (D = 1), x0 = (99/100, -2, 2, 0): in mode {} x1 =
    (t - 1)^2 - 1/100 reaches 0 at 9/10 (rational, proven); mode {0} (u = -x1: x1'''' = -x1,
    chi = s^4 + 1) ends where x1 turns positive again, 1.09999822227865721654277... (mpmath
    below).  s^4 + 1 is biquadratic over Q(sqrt -4): no real quadratic factors there, so no
    closed form is tried (it raised a bare TypeError comparing I)."""
    A = [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]
    lcs = L.LCS(A, [[0], [0], [0], [1]], [[1, 0, 0, 0]], [[1]])
    tr = L.simulate(lcs, ["99/100", "-2", "2", "0"], 3, digits=30)
    first, second = tr.events[0].time, tr.events[1].time
    assert first.closed_form == sp.Rational(9, 10) and second.closed_form is None
    with mp.workdps(50):
        AI = mp.matrix([[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [-1, 0, 0, 0]])
        x = mp.matrix([0, mp.mpf(-1) / 5, 2, 0])
        want = mp.findroot(lambda t: (mp.expm(AI * (t - mp.mpf(9) / 10)) * x)[0], 1.1)
        assert close(num(second), want)


def test_harmonic_candidate_written_with_i_is_skipped():
    """Two masses, restitution 1, x0 = (3, 6, -1, -4): the first impact at 0.5610619451868779...
    has a harmonic candidate whose root SymPy writes with I (casus irreducibilis); it is not
    tried, so the closed form is None and the fixture is written (a review found InvalidArgument)."""
    lcs = L.models.mechanical([[1, 0], [0, 2]], [[1, -1], [-1, 3]], [[1, 0], [-1, 1]], restitution="1")
    tr = L.simulate(lcs, ["3", "6", "-1", "-4"], "3/5", digits=30)
    t1 = tr.events[0].time
    assert abs(num(t1) - mp.mpf("0.561061945186877943438982369807")) < mp.mpf(10) ** -29
    assert t1.closed_form is None
    assert tr.to_fixture(20)["schema"].startswith("lcs-exact/trajectory")


def test_a_slow_symbolic_candidate_search_is_cut_off_by_the_safety_net_and_marked(monkeypatch):
    """SymPy steps of the closed-form search run under a budget of work (forms.SYMPY_WORK) and a
    wall-clock safety net for work the count cannot see (a harmonic simplification once ran 25 s
    past a run's time_limit).  A search step that would sleep 30 s (a long call into C: no Python
    calls to count) is interrupted by the net; the event (the RL rectifier's turn-off at the first
    root of sin t - cos t + e^{-t}, transcendental) keeps its certified digits and has no closed
    form, reported as "not searched" (the net is a clock), never as "none"."""
    import time
    from lcs_exact import closedforms, forms
    from lcs_exact.models import circuit
    calls = []

    def slow(sym, b):
        calls.append("start")
        time.sleep(30)
        calls.append("end")
        return []

    monkeypatch.setattr(closedforms, "harmonic_candidates", slow)
    monkeypatch.setattr(forms, "SYMPY_SAFETY_NET", 0.2)
    lcs = circuit("V1 1 0 sine(1,1)\nD1 1 2\nR1 2 3 1\nL1 3 0 1")
    tr = L.simulate(lcs, lcs.embed([0]), 5, closed_forms=True)
    assert calls == ["start"]
    t1 = mp.findroot(lambda t: mp.sin(t) - mp.cos(t) + mp.exp(-t), 3.94)
    assert len(tr.events) == 1 and close(num(tr.events[0].time), t1)
    assert tr.events[0].time.closed_form is None
    assert tr.events[0].time.closed_form_status == "not searched"
    assert len(tr.policy.deadline.safety_cuts) == 1 and "search of slow" in tr.policy.deadline.safety_cuts[0]
    # the same search without the net: searched to the end, none found
    monkeypatch.setattr(closedforms, "harmonic_candidates", lambda sym, b: [])
    tr = L.simulate(lcs, lcs.embed([0]), 5, closed_forms=True)
    assert tr.events[0].time.closed_form is None and tr.events[0].time.closed_form_status == "none"


def test_flat_touch_proof_asks_no_candidate_when_no_derivative_has_a_sign():
    """prove_flat_touch needs f^(m) > 0 on the interval for an even m (the first derivative with a
    sign there): a function below the balls' resolution (every enclosure holds 0), or one whose
    first signed derivative is odd, is refused before any candidate is looked at (the spectrum
    here has nothing but its size: a candidate would fail the test)."""
    class Blur:  # f^(d) on [lo, hi]: [+/- 1e-60] for d < signed, then 1 (d even) or -1
        def __init__(self, signed=None, value=1):
            self.signed, self.value = signed, value

        def sign_enclose(self, lo, hi, d):
            return arb(self.value) if self.signed is not None and d >= self.signed else arb(0, 1e-60)

    class SizeOnly:
        n = 8

        def __getattr__(self, name):
            raise AssertionError(f"candidate work: spectrum.{name}")

    lo, hi = fmpq(1), fmpq(1) + fmpq(1, 2 ** 40)
    assert prove_flat_touch(SizeOnly(), None, None, Blur(), lo, hi) is False  # nothing has a sign
    assert prove_flat_touch(SizeOnly(), None, None, Blur(5), lo, hi) is False  # odd order
    assert prove_flat_touch(SizeOnly(), None, None, Blur(4, -1), lo, hi) is False  # f'''' < 0: a maximum

"""Algorithm 7.1 on the paper's section 7 run, exactly; θ (Def. 4.3); limits and partial results."""
from __future__ import annotations

import mpmath as mp
import pytest
import sympy as sp
from helpers import A_CARTS, carts, close, modes, num

import lcs_exact as L
from lcs_exact.phases.flow import theta
from lcs_exact.phases.trajectory import Status

mp.mp.dps = 60


@pytest.fixture(scope="module")
def section7():
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    return L.simulate(carts(), x0, 3, digits=30)


def test_section7_events_closed_forms(section7):
    tr = section7
    assert tr.certified and not tr.partial
    assert len(tr.events) == 2
    e1, e2 = tr.events
    assert sp.simplify(e1.time.closed_form - 1) == 0
    assert sp.simplify(e2.time.closed_form - (1 + sp.pi / 2)) == 0
    # certified digits: 30 significant digits of 1 + pi/2
    assert close(num(e2.time), 1 + mp.pi / 2)
    b = e2.time.ball(30)
    assert b.rad() < mp.mpf(10) ** -30 * 3 and b.contains(b.mid())


def test_section7_states_and_modes(section7):
    e1, e2 = section7.events
    assert e1.mode_before == frozenset() and e1.modes == (frozenset({0}),) and e1.mode_after == {0}
    assert e1.multiplicity == 1 and e1.triggers == ("y_0",)
    # x(1-) = (0,-1,-1,0), x(1+) = (0,-1,0,0): proven rational, not just close
    assert [str(c) for c in e1.state_before.rational().entries()] == ["0", "-1", "-1", "0"]
    assert [str(c) for c in e1.state_after.rational().entries()] == ["0", "-1", "0", "0"]
    # the impulse at the impact: u = delta (u^0 = 1)
    assert [str(c) for c in e1.impulse[0].rational().entries()] == ["1"]
    # release at 1 + pi/2 in state (0,0,0,1), then the free mode
    assert e2.mode_before == {0} and e2.modes == () and e2.mode_after == frozenset()
    assert [str(c) for c in e2.state_after.rational().entries()] == ["0", "0", "0", "1"]


def test_section7_final_state_independent(section7):
    # x(3) = e^{A (2 - pi/2)} (0,0,0,1), computed here with mpmath's expm
    want = mp.expm(mp.matrix(A_CARTS) * (2 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1])
    got = [num(c) for c in section7.state(3)]
    assert all(close(g, want[i]) for i, g in enumerate(got))
    # before the first event the state is e^{At} x0 = e^{A(t-1)} (0,-1,-1,0)
    half = mp.expm(mp.matrix(A_CARTS) * (mp.mpf(1) / 2 - 1)) * mp.matrix([0, -1, -1, 0])
    assert all(close(num(c), half[i]) for i, c in enumerate(section7.state(sp.Rational(1, 2))))


def test_section7_u_and_y(section7):
    # on (1, 1 + pi/2): u(t) = cos(t - 1), y = 0
    t = sp.Rational(3, 2)
    assert close(num(section7.u(t)[0]), mp.cos(mp.mpf(1) / 2))
    assert section7.y(t)[0].ball(30).contains(0)


def test_section7_thousand_digits():
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    tr = L.simulate(carts(), x0, 3, digits=1000)
    mp.mp.dps = 1010
    try:
        want = 1 + mp.pi / 2
        got = mp.mpf(tr.events[1].time.ball(1000).mid().str(1005, radius=False))
        assert abs(got - want) < mp.mpf(10) ** -995
        x3 = L.expm_action(A_CARTS, 3 - (1 + sp.pi / 2), [0, 0, 0, 1])
        for a, b in zip(tr.state(3), x3):
            assert a.ball(1000).overlaps(b.ball(1000))
    finally:
        mp.mp.dps = 60


def test_theta_examples_4_4_and_4_5():
    c = carts()
    assert theta(c, [0, -1, 0, 0], {0}, 10).closed_form == sp.pi / 2  # Example 4.4
    assert theta(c, [0, 1, -1, 0], {0}, 10).closed_form == 0  # Example 4.5
    assert theta(c, [0, -1, 0, 0], {0}, 1) is None  # no event before t = 1


def test_jump_then_free_example_4_5():
    tr = L.simulate(carts(), [0, 1, -1, 0], 1)
    e = tr.events[0]
    assert e.time.closed_form == 0 and e.mode_before is None
    assert e.modes == (frozenset({0}),) and e.mode_after == frozenset()
    assert [str(c) for c in e.state_after.rational().entries()] == ["0", "1", "0", "0"]
    assert tr.certified and len(tr.events) == 1


def test_no_event_at_zero_for_consistent_start():
    tr = L.simulate(carts(), [1, 0, 0, 0], 1)
    assert tr.events == () and tr.certified
    want = mp.expm(mp.matrix(A_CARTS)) * mp.matrix([1, 0, 0, 0])
    assert all(close(num(c), want[i]) for i, c in enumerate(tr.state(1)))


@pytest.mark.parametrize("limit, events, error, status", [
    ({"max_events": 1}, 1, L.LimitExceeded, Status.EVENT_LIMIT),
    ({"time_limit": 0}, None, L.TimeLimitExceeded, Status.TIME_LIMIT)])
def test_limits_return_partial_trajectory(limit, events, error, status):
    """A run stopped by a limit raises LimitExceeded naming it (TimeLimitExceeded for the clock);
    nothing computed is lost, and the trajectory's status says which limit stopped it."""
    (name,) = limit
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    with pytest.raises(L.LimitExceeded, match=name) as err:
        L.simulate(carts(), x0, 3, **limit)
    assert type(err.value) is error
    tr = err.value.trajectory
    assert tr.partial and name in tr.stop_reason and tr.status is status
    if events is not None:  # exactly max_events events are kept
        assert len(tr.events) == events and tr.events[0].time.closed_form == 1


@pytest.mark.slow
def test_fixture_schema(section7):
    fx = section7.to_fixture(30)
    assert fx["schema"] == "lcs-exact/trajectory/1" and fx["certified"] is True
    ev = fx["events"][1]
    assert ev["time"]["exact"] == "1 + pi/2" and ev["time"]["value"].startswith("2.5707963267948966192313216916")
    assert ev["mode_before"] == [0] and ev["mode_after"] == [] and ev["multiplicity"] == 0
    assert [c["exact"] for c in ev["state_after"]] == ["0", "0", "0", "1"]
    assert float(fx["final_state"][3]["error"]) < 1e-30


def test_bad_inputs():
    with pytest.raises(L.ShapeError):
        L.simulate(carts(), [0, 1], 1)
    with pytest.raises(ValueError, match="t_end"):
        L.simulate(carts(), [0, 1, 0, 0], -1)


def test_oscillator_against_stop_closed_form():
    # x'' = -x + u, y = x: from (1, 0) the stop is hit at pi/2 with velocity -1, then rest at 0
    osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    tr = L.simulate(osc, [1, 0], 4)
    (e,) = tr.events
    assert e.time.closed_form == sp.pi / 2
    assert [str(c) for c in e.state_before.rational().entries()] == ["0", "-1"]
    assert [str(c) for c in e.state_after.rational().entries()] == ["0", "0"]
    assert e.mode_after in modes(set(), {0})
    assert [str(c) for c in tr.state(4).rational().entries()] == ["0", "0"]


# --- grazing: y = c - x with x'' = -x (a constant state carries the offset) -----------------
GRAZE = L.LCS([[0, 1, 0], [-1, 0, 0], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 1]], [[0]])


def test_exact_tangential_touch_is_proven_not_an_event():
    # x = -cos(t - phi) with cos phi = 3/5, sin phi = 4/5: y = 1 - cos(t - phi) >= 0 touches 0 at phi
    tr = L.simulate(GRAZE, [sp.Rational(-3, 5), sp.Rational(-4, 5), 1], 7)
    assert tr.events == () and tr.certified


def test_near_graze_dips_below_zero_is_an_event():
    c = 1 + sp.Rational(1, 10**20)  # y = 1 - c cos(t - phi) has min 1 - c < 0
    tr = L.simulate(GRAZE, [-3 * c / 5, -4 * c / 5, 1], 7)
    assert tr.certified and len(tr.events) == 1
    e = tr.events[0]
    # first root: t = phi - acos(1/c), phi = atan2(4, 3)
    want = mp.atan2(4, 3) - mp.acos(1 / (1 + mp.mpf(10) ** -20))
    assert close(num(e.time), want)
    assert e.time.closed_form is not None and close(mp.mpf(str(sp.N(e.time.closed_form, 50))), want)
    assert e.modes == (frozenset({0}),)


def test_clear_miss_is_not_an_event():
    c = 1 - sp.Rational(1, 10**20)  # min of y is 1 - c > 0
    tr = L.simulate(GRAZE, [-3 * c / 5, -4 * c / 5, 1], 7)
    assert tr.events == () and tr.certified


def test_unprovable_touch_is_reported_not_guessed():
    # the same exact touch from a transcendental state e^{M} v: y(t) = 1 - cos(t + 1) touches 0 at
    # 2 pi - 1.  With closed forms the touch is proven (the candidate 2 pi on the orbit of v,
    # shifted back by 1); without them (closed_forms=False) nothing can prove it: it is reported,
    # never guessed, and with allow_unresolved it is recorded and the result is not certified.
    x0 = L.expm_action(GRAZE.A, 1, [-1, 0, 1])
    tr = L.simulate(GRAZE, x0, 6, max_prec=512)
    assert tr.certified and tr.events == ()
    with pytest.raises(L.UnresolvedSign, match="tangential touch") as err:
        L.simulate(GRAZE, x0, 6, max_prec=512, closed_forms=False)
    assert err.value.trajectory.partial
    tr = L.simulate(GRAZE, x0, 6, allow_unresolved=True, max_prec=512, closed_forms=False)
    assert not tr.certified and tr.events == ()
    assert any("tangential touch" in a for a in tr.assumptions)


def test_accumulation_detector_on_geometric_phases():
    # Remark 4.11: phases 2^-i starting at t = 0 accumulate at t = 2 (< t_end = 3)
    from lcs_exact.numbers.reals import RationalReal
    from lcs_exact.accumulations.zeno import check_accumulation as _check_accumulation
    durations, t = [], RationalReal(0)
    with pytest.raises(L.ZenoDetected, match="accumulate"):
        for i in range(40):
            d = RationalReal(sp.Rational(1, 2**i))
            durations.append(d)
            t = t + d
            _check_accumulation(durations, t, RationalReal(3))
    assert len(durations) == 24  # detected as soon as the window is full
    # the same phases with t_end = 3/2 before the limit: no accumulation inside the horizon
    durations, t = [], RationalReal(0)
    for i in range(30):
        durations.append(RationalReal(sp.Rational(1, 2**i)))
        t = t + durations[-1]
        _check_accumulation(durations, t, RationalReal(sp.Rational(3, 2)))
    # constant phases never trigger it
    durations = [RationalReal(1)] * 30
    _check_accumulation(durations, RationalReal(30), RationalReal(100))


@pytest.mark.slow
def test_stiff_chain_first_impact_independent():
    # masses 1, 1; wall spring 1; stiff coupling k = 10^6; stop on mass 1; from q = (1, 1) at rest
    from lcs_exact.models import mechanical
    k = 10**6
    stiff = mechanical([[1, 0], [0, 1]], [[0, 0], [0, 0]], [[1 + k, -k], [-k, k]], [[1, 0]])
    tr = L.simulate(stiff, [1, 1, 0, 0], 3, digits=30)
    assert tr.certified and tr.events
    A = mp.matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-(1 + k), k, 0, 0], [k, -k, 0, 0]])
    with mp.workdps(60):
        # modal solution q1(t) = sum_j c_j e^{lam_j t} from mpmath's eigendecomposition
        lam, V = mp.eig(A)
        c = mp.lu_solve(V, mp.matrix([1, 1, 0, 0]))
        f = lambda t: mp.re(sum(V[0, j] * c[j] * mp.exp(lam[j] * t) for j in range(4)))  # noqa: E731
        t1 = num(tr.events[0].time, 45)
        assert abs(f(t1)) < mp.mpf(10) ** -28  # a root of q1 ...
        # ... and the first one: q1 > 0 on a grid 10x finer than the fast period 2 pi / sqrt(2 k)
        grid = [t1 * j / 5000 for j in range(1, 5000)]
        assert all(f(t) > 0 for t in grid)


def test_deadlock_is_reported_with_partial_trajectory():
    # x' = -2x + 2u, y = -2x: from x0 = 1, mode ∅ has y(s) = -2/(s+2) < 0 and mode {0} has
    # u(s) = -G^{-1} R x0 = -(-4/(s+2))^{-1} (-2/(s+2)) = -1/2 < 0: S(x0) is empty (Remark 7.2)
    lcs = L.LCS([[-2]], [[2]], [[-2]], [[0]])
    assert lcs.select_modes([1], "rcp") == set()
    with pytest.raises(L.Deadlock, match="S\\(z\\) is empty") as err:
        L.simulate(lcs, [1], 1)
    assert err.value.trajectory.partial and err.value.trajectory.events == ()


@pytest.mark.parametrize("eps", [sp.Rational(1, 10), sp.Rational(1, 100), sp.Rational(1, 1000)])
def test_section8_discontinuity_hook_first(eps):
    # x0(eps) = (eps, eps, -2, 1): the hook acts first: jump to (eps, eps, -1/2, -1/2) (P_{hook});
    # in the hook mode x1 = x2 = q with q'' = -q/2 (u2 = q/2), so q = eps cos(w t) - (1/2)/w sin(w t),
    # w = 1/sqrt(2): the stop is hit at t* = sqrt(2) atan(sqrt(2) eps) with velocity
    # v = q'(t*) = -eps w sin(w t*) - (1/2) cos(w t*) -> -1/2; the stop then takes the left cart's
    # velocity: (0, 0, v, v) -> (0, 0, 0, v) (section 8).
    from lcs_exact.models import two_carts_with_hook
    h = two_carts_with_hook()
    tr = L.simulate(h, [eps, eps, -2, 1], sp.Rational(1, 2), digits=30)
    assert tr.certified
    e0, e1 = tr.events[0], tr.events[1]
    assert e0.time.closed_form == 0 and e0.modes == (frozenset({1}),) and e0.mode_after == {1}
    assert [str(c) for c in e0.state_after.rational().entries()] == [str(eps), str(eps), "-1/2", "-1/2"]
    w = 1 / mp.sqrt(2)
    e = mp.mpf(eps.p) / eps.q
    tstar = mp.sqrt(2) * mp.atan(mp.sqrt(2) * e)
    v = -e * w * mp.sin(w * tstar) - mp.cos(w * tstar) / 2
    assert close(num(e1.time), tstar)
    before = [num(c) for c in e1.state_before]
    after = [num(c) for c in e1.state_after]
    assert before[0] == 0 and before[1] == 0 and close(before[2], v) and close(before[3], v)
    assert after[:3] == [0, 0, 0] and close(after[3], v)
    assert e1.modes == (frozenset({0}),) and e1.mode_after == {0}
    assert abs(v + mp.mpf(1) / 2) < e  # g(eps) -> 0


def test_section8_discontinuity_at_eps_zero():
    from lcs_exact.models import two_carts_with_hook
    tr = L.simulate(two_carts_with_hook(), [0, 0, -2, 1], 1)
    (e,) = tr.events
    assert e.time.closed_form == 0 and e.modes == (frozenset({0, 1}),)
    assert [str(c) for c in e.state_after.rational().entries()] == ["0", "0", "0", "0"]
    assert [str(c) for c in tr.state(1).rational().entries()] == ["0", "0", "0", "0"]


def test_cli_simulate_writes_fixture(tmp_path, capsys):
    import json
    from lcs_exact.cli import main
    model = tmp_path / "osc.json"
    model.write_text(json.dumps({"A": [[0, 1], [-1, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]],
                                 "x0": [1, 0], "t_end": "4", "name": "oscillator and stop"}))
    out = tmp_path / "out.json"
    assert main(["simulate", str(model), "--digits", "25", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "= pi/2" in printed and "1 events, certified" in printed
    fx = json.loads(out.read_text())
    assert fx["schema"] == "lcs-exact/trajectory/1" and fx["digits"] == 25
    assert fx["events"][0]["time"]["exact"] == "pi/2"
    assert fx["events"][0]["time"]["value"] == "1.570796326794896619231322"  # pi/2 rounded to 25 digits
    assert [c["exact"] for c in fx["final_state"]] == ["0", "0"]
    assert main(["simulate", str(model), "--x0", "1,2,3"]) == 2  # wrong length: one-line error
    assert "x0" in capsys.readouterr().err


def test_high_index_impulsive_jump():
    # triple integrator, y = x1 (rho = eta = 3, M = N = [1]): G(s) = 1/s^3, R(s) x0 =
    # (x1 s^2 + x2 s + x3)/s^3, so in mode {0}: u(s) = -(x1 s^2 + x2 s + x3).  From (0, -1, 1):
    # u(s) = s - 1 (lexicographically positive): u = delta' - delta, V_{0} = {0}: the jump is to 0;
    # mode ∅ has y(s) = (1 - s)/s^3 < 0 for large s.
    tri = L.LCS([[0, 1, 0], [0, 0, 1], [0, 0, 0]], [[0], [0], [1]], [[1, 0, 0]], [[0]])
    assert tri.select_modes([0, -1, 1]) == modes({0})
    (sol,) = tri.rcp([0, -1, 1])
    assert sol.u[0] == L.RationalFunction([-1, 1])  # s - 1
    tr = L.simulate(tri, [0, -1, 1], 1)
    e = tr.events[0]
    assert e.time.closed_form == 0 and e.modes == (frozenset({0}),) and e.multiplicity == 1
    assert [str(v.rational()[0, 0]) for v in (e.impulse[0], e.impulse[1])] == ["-1", "1"]  # -delta + delta'
    assert [str(c) for c in e.state_after.rational().entries()] == ["0", "0", "0"]
    assert len(tr.events) == 1 and [str(c) for c in tr.state(1).rational().entries()] == ["0", "0", "0"]


def test_time_limit_interrupts_a_root_search():
    """The wall-clock limit is checked inside the root isolation too (not only between events)."""
    with pytest.raises(L.LimitExceeded, match="time_limit = 0 s reached while isolating"):
        theta(carts(), [0, -1, 0, 0], {0}, 10, time_limit=0)
    assert theta(carts(), [0, -1, 0, 0], {0}, 10).closed_form == sp.pi / 2  # no limit outside


def test_section7_final_state_closed_form(section7):
    """x(3) = e^{A(2 - π/2)}(0, 0, 0, 1) in closed form (χ = s^4 + 3s^2 + 1 splits over Q(√5));
    the closed form, evaluated by SymPy, agrees with mpmath's expm to 35 digits, and the fixture
    carries it."""
    x3 = section7.state(3)
    cf = x3.closed_form()
    assert cf is not None
    want = mp.expm(mp.matrix(A_CARTS) * (2 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1])
    with mp.workdps(50):
        for i in range(4):
            assert abs(mp.mpf(str(sp.N(cf[i], 45))) - want[i]) < mp.mpf(10) ** -35
    fx = section7.to_fixture(30)
    assert all(c["exact"] is not None for c in fx["final_state"])
    assert sp.N(sp.sympify(fx["final_state"][3]["exact"]) - cf[3], 40) == 0


def test_event_exactly_at_t_end_is_reported():
    """q'' = -g (g ≡ 1 a constant state) from q = 1/2 at rest: q = 1/2 - t^2/2 hits the stop at
    t = 1 with v = -1. With t_end = 1 the impact is reported and x(t_end) is the state after it
    (as at any event time), consistent with t_end = 3."""
    lcs = L.LCS([[0, 1, 0], [0, 0, -1], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 0]], [[0]])
    for t_end in (1, 3):
        tr = L.simulate(lcs, ["1/2", 0, 1], t_end)
        e = tr.events[0]
        assert e.time.closed_form == 1 and e.modes == (frozenset({0}),)
        assert [str(c) for c in e.state_before.rational().entries()] == ["0", "-1", "1"]
        assert [str(c) for c in tr.state(1).rational().entries()] == ["0", "0", "1"]
    assert len(L.simulate(lcs, ["1/2", 0, 1], 1).events) == 1


def test_decimal_error_bounds_are_upper_bounds():
    """decimal(): a rounded rational carries a bound >= the true error; exact values stand alone."""
    from fractions import Fraction
    from lcs_exact.numbers.reals import as_real
    assert as_real("1/4").decimal(5) == "0.25" and as_real(0).decimal(5) == "0"
    for q in ("1/3", "2/7", 123456789012345):
        text, _, err = as_real(q).decimal(5).partition(" +/- ")
        assert abs(Fraction(text) - Fraction(q)) <= Fraction(err)
    # a transcendental value: |value - true| <= error, the true value from mpmath at 60 digits
    x3 = L.simulate(carts(), L.expm_action(A_CARTS, -1, [0, -1, -1, 0]), 3).state(3)
    with mp.workdps(60):
        want = mp.expm(mp.matrix(A_CARTS) * (2 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1])
        for i in range(4):
            text, _, err = x3[i].decimal(30).partition(" +/- ")
            assert abs(mp.mpf(text) - want[i]) <= mp.mpf(err)


def test_bad_run_arguments_are_named():
    for kw, word in ((dict(digits="30"), "digits"), (dict(digits=0), "digits"), (dict(t_end="abc"), "t_end"),
                     (dict(x0=None), "x0")):
        args = dict(x0=[0, 1, 0, 0], t_end=1)
        args.update(kw)
        with pytest.raises((ValueError, L.LCSError), match=word):
            L.simulate(carts(), args.pop("x0"), args.pop("t_end"), **args)


@pytest.mark.slow
def test_closed_forms_of_a_long_run_are_derived_in_a_loop():
    """Two balls (masses 1 and 2, radii 1/10) stacked over a floor, restitution 19/20: each event
    time's closed form is derived from the state after the event before it, so the derivation
    of the last of 45 events used to recurse through all of them (RecursionError after about 90
    events at Python's default limit; here the limit is lowered to 250).  The earlier closed forms
    are derived first, in a loop."""
    import sys

    import sympy
    from lcs_exact import models, sources
    lcs = models.mechanical([[1, 0], [0, 2]], [[0, 0], [0, 0]], [[1, 0], [-1, 1]],
                            force=[sources.constant("-981/100"), sources.constant("-981/50")],
                            gap=["-1/10", "-1/5"], restitution="19/20")
    tr = L.simulate(lcs, lcs.embed([1, 2, 0, 0]), 6, digits=20)
    assert len(tr.events) > 40
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(250)
    try:
        tr.events[-1].time.closed_form  # noqa: B018 -- derived (or proven absent) without recursing 45 deep
        tr.state(tr.events[-1].time).closed_form()
    finally:
        sys.setrecursionlimit(limit)
    # the first impact, ball 0 from height 1 onto the floor at 1/10: sqrt(2 (9/10) / g)
    first = sympy.sqrt(2 * sympy.Rational(9, 10) / sympy.Rational(981, 100))
    assert sympy.simplify(tr.events[0].time.closed_form - first) == 0
